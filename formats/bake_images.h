/* Writers of baked maps (core/bake/bake.h): PNG through libpng (8- or
 * 16-bit, RGB or grey) and 32-bit float OpenEXR through tinyexr
 * (formats/exr_io.cc, the one C++ translation unit behind formats/exr_io.h). */
#ifndef ST_BAKE_IMAGES_H
#define ST_BAKE_IMAGES_H

#include <stdint.h>

#include "core/bake/bake.h"
#include "core/io/atomic_file.h"

/* Each writer writes into an open atomic file (core/io/atomic_file.h: the
 * caller commits it, or finishes several and places them together) and
 * names af->path, the output, in its messages; a failed write's reason
 * comes from st_afile_write. */

/* Normal map as RGB = 0.5 · n + 0.5, 8 or 16 bits per channel. */
int st_bake_write_normal_png(st_afile *af, const st_bake_maps *m, int bits, st_error *err);

/* Displacement map: .exr (32-bit float, 1 channel Y or 3 channels RGB) or
 * .png (16 bits per channel, grey or RGB: value = offset + scale · sample /
 * 65535, offset and scale written by st_bake_write_sidecar), chosen by
 * af->path's extension. */
int st_bake_write_disp(st_afile *af, const st_bake_maps *m, double *offset, double *scale, st_error *err);

/* The JSON file beside a 16-bit displacement PNG that says how to read it. */
int st_bake_write_sidecar(st_afile *af, const char *image, const st_bake_maps *m, const char *meaning,
                          double offset, double scale, st_error *err);

#endif
