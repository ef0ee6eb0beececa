/* Writers of baked maps (formats/bake_images.h). */
#include "bake_images.h"
#include "exr_io.h"
#include "core/io/mesh.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* libpng's output and errors: bytes go through st_afile_write (which keeps
 * a failed write's errno); an error jumps back without printing, and the
 * caller says what failed. */
static void png_out(png_structp png, png_bytep data, size_t n)
{
    if (st_afile_write(png_get_io_ptr(png), data, n)) png_error(png, "write failed");
}
static void png_flush_none(png_structp png) { (void)png; }
static void png_fail(png_structp png, png_const_charp msg)
{
    snprintf(png_get_error_ptr(png), 128, "%s", msg);
    png_longjmp(png, 1);
}
static void png_warn_none(png_structp png, png_const_charp msg) { (void)png; (void)msg; }

/* Rows of 8- or 16-bit samples (16-bit big-endian, as PNG stores them),
 * `channels` per pixel (1 grey, 3 RGB), row 0 first. */
static int write_png_rows(st_afile *af, uint32_t w, uint32_t h, int channels, int bits, const unsigned char *data, st_error *err)
{
    char why[128] = "";
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, why, png_fail, png_warn_none);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        return st_fail(err, ST_ERR_MEMORY, "%s: out of memory starting a PNG", af->path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        if (af->werr) return st_fail(err, ST_ERR_IO, "%s: write error: %s", af->path, strerror(af->werr));
        return st_fail(err, ST_ERR_IO, "%s: error encoding the PNG: %s", af->path, why);
    }
    png_set_write_fn(png, af, png_out, png_flush_none);
    png_set_IHDR(png, info, w, h, bits, channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    size_t stride = (size_t)w * (size_t)channels * (size_t)(bits / 8);
    for (uint32_t y = 0; y < h; y++) png_write_row(png, (png_const_bytep)(data + stride * y));
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return ST_OK;
}

/* x in [0,1] to an 8- or 16-bit sample at q. */
static void put_sample(unsigned char *q, int bits, double x)
{
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    if (bits == 8) { q[0] = (unsigned char)lround(x * 255); return; }
    long v = lround(x * 65535);
    q[0] = (unsigned char)(v >> 8);
    q[1] = (unsigned char)(v & 0xff);
}

static int write_samples(st_afile *af, const st_bake_maps *m, const float *src, int channels, int bits,
                         double offset, double scale, st_error *err)
{
    size_t texels = (size_t)m->size * m->size, bytes = (size_t)(bits / 8);
    unsigned char *data = malloc(texels * (size_t)channels * bytes);
    if (!data) return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", af->path);
    for (size_t i = 0; i < texels * (size_t)channels; i++) put_sample(data + i * bytes, bits, (src[i] - offset) / scale);
    int rc = write_png_rows(af, m->size, m->size, channels, bits, data, err);
    free(data);
    return rc;
}

int st_bake_write_normal_png(st_afile *af, const st_bake_maps *m, int bits, st_error *err)
{
    if (!m->normal) return st_fail(err, ST_ERR_INVALID, "%s: no normal map was baked", af->path);
    /* n in [-1,1] to [0,1]: (n - (-1)) / 2. */
    return write_samples(af, m, m->normal, 3, bits, -1.0, 2.0, err);
}

/* The EXR encoded in memory, then written like every other file. */
static int write_exr(st_afile *af, const st_bake_maps *m, int ch, st_error *err)
{
    char msg[256];
    unsigned char *mem = NULL;
    size_t n = 0;
    if (st_exr_encode(m->disp, (int)m->size, (int)m->size, ch, &mem, &n, msg, sizeof msg))
        return st_fail(err, ST_ERR_IO, "%s: %s", af->path, msg);
    int bad = st_afile_write(af, mem, n);
    free(mem);
    if (bad) return st_fail(err, ST_ERR_IO, "%s: write error: %s", af->path, strerror(af->werr));
    return ST_OK;
}

int st_bake_write_disp(st_afile *af, const st_bake_maps *m, double *offset, double *scale, st_error *err)
{
    const char *path = af->path;
    if (!m->disp) return st_fail(err, ST_ERR_INVALID, "%s: no displacement map was baked", path);
    int ch = (int)m->disp_channels;
    if (st_path_has_ext(path, ".exr")) {
        *offset = 0;
        *scale = 1;
        return write_exr(af, m, ch, err);
    }
    if (!st_path_has_ext(path, ".png"))
        return st_fail(err, ST_ERR_INVALID, "%s: a displacement map is written as .exr or .png", path);
    /* The baked range (padding only averages it) maps onto 0..65535. */
    double lo = m->disp_min, hi = m->disp_max;
    if (!(hi > lo)) { hi = lo + 1; }
    *offset = lo;
    *scale = hi - lo;
    return write_samples(af, m, m->disp, ch, 16, lo, hi - lo, err);
}

int st_bake_write_sidecar(st_afile *af, const char *image, const st_bake_maps *m, const char *meaning,
                          double offset, double scale, st_error *err)
{
    /* Write errors show at the commit (stdio's error flag). */
    (void)err;
    FILE *f = af->f;
    const char *base = strrchr(image, '/');
    base = base ? base + 1 : image;
    fputs("{\n  \"image\": \"", f);
    for (const char *c = base; *c; c++) {
        if (*c == '"' || *c == '\\') fputc('\\', f);
        if ((unsigned char)*c >= 0x20) fputc(*c, f);
    }
    fprintf(f, "\",\n  \"channels\": %u,\n  \"bits\": 16,\n"
               "  \"meaning\": \"%s\",\n  \"decode\": \"value = offset + scale * sample / 65535\",\n"
               "  \"offset\": %.17g,\n  \"scale\": %.17g\n}\n",
            m->disp_channels, meaning, offset, scale);
    return ST_OK;
}
