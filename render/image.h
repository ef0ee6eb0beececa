/* PNG files and image comparison (for `strata render` and the image tests).
 *
 * Images are RGBA, 8 bits per channel, top row first.
 *
 * Comparison metric (the convention of established render test suites):
 * a pixel differs when one of its R, G, B channels differs by
 * more than `tol` (out of 255); the images match when at most `max_fraction`
 * of the pixels differ.  Blender's render tests fail above 1 % of pixels
 * differing by more than 1.6 % (idiff -fail 0.016 -failpercent 1); three.js
 * allows 0.3 % of differing pixels.  Strata's tests use ST_IMAGE_TOL = 4
 * (1.6 % of 255) and ST_IMAGE_MAX_FRACTION = 0.003 (three.js's 0.3 %), the
 * stricter of the two.
 */
#ifndef ST_IMAGE_H
#define ST_IMAGE_H

#include <stdint.h>

#include "core/base/st_error.h"

#include <stddef.h>

#define ST_IMAGE_TOL 4
#define ST_IMAGE_MAX_FRACTION 0.003

/* Writes an RGB PNG (alpha dropped).  Deterministic: the same pixels give
 * the same bytes.  Atomic (core/io/atomic_file.h): on failure the old file
 * stays and the message names path and the reason. */
int st_png_write(const char *path, int w, int h, const unsigned char *rgba, st_error *err);
/* Bytes st_png_write takes beside the pixels it is given, at most: the RGB
 * copy, stb's filtered rows, the compressed stream in a buffer that grows
 * by doubling. */
size_t st_png_write_bytes(int w, int h);
/* Reads a PNG into a malloc'ed RGBA buffer (caller frees). */
int st_png_read(const char *path, int *w, int *h, unsigned char **rgba, st_error *err);
/* The same from n bytes in memory (fuzz_nmap); name stands for the file in
 * messages.  Images over ST_PNG_MAX_SIDE pixels a side, or over the memory
 * budget (core/base/membudget.h), are refused before they are decoded. */
#define ST_PNG_MAX_SIDE 16384
int st_png_decode(const char *name, const void *data, size_t n, int *w, int *h, unsigned char **rgba, st_error *err);

typedef struct st_image_diff {
    uint64_t differing;       /* pixels with a channel off by more than tol */
    uint64_t pixels;
    int max_delta;            /* largest channel difference */
    double fraction;          /* differing / pixels */
} st_image_diff;

/* Compares two images of the same size.  diff (w*h*4, may be NULL)
 * receives a picture of the differences: differing pixels in red (brighter
 * for larger differences) over a faded copy of b. */
void st_image_compare(const unsigned char *a, const unsigned char *b, int w, int h, int tol,
                      st_image_diff *out, unsigned char *diff);
/* True when out says the images match under max_fraction. */
int st_image_match(const st_image_diff *d, double max_fraction);

#endif
