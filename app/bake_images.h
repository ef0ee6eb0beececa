/* Writers of baked maps (core/bake/bake.h): PNG through libpng (8- or
 * 16-bit, RGB or grey) and 32-bit float OpenEXR through tinyexr
 * (app/exr_io.cc, the one C++ translation unit behind app/exr_io.h). */
#ifndef ST_BAKE_IMAGES_H
#define ST_BAKE_IMAGES_H

#include <stdint.h>

#include "core/bake/bake.h"

/* Normal map as RGB = 0.5 · n + 0.5, 8 or 16 bits per channel. */
int st_bake_write_normal_png(const char *path, const st_bake_maps *m, int bits, st_error *err);

/* Displacement map: .exr (32-bit float, 1 channel Y or 3 channels RGB) or
 * .png (16 bits per channel, grey or RGB: value = offset + scale · sample /
 * 65535, offset and scale written by st_bake_write_sidecar). */
int st_bake_write_disp(const char *path, const st_bake_maps *m, double *offset, double *scale, st_error *err);

/* The JSON file beside a 16-bit displacement PNG that says how to read it. */
int st_bake_write_sidecar(const char *path, const char *image, const st_bake_maps *m, const char *meaning,
                          double offset, double scale, st_error *err);

#endif
