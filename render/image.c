#include "render/image.h"
#include "core/base/membudget.h"
#include "core/io/atomic_file.h"
#include "core/io/file_open.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* stb, private to this file (static functions: no clash with another unit
 * that compiles its own stb implementation, e.g. for tinygltf). */
#if defined(__GNUC__)
/* Unused static stb functions are reported at the end of the file: this
 * one stays off for the whole file. */
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#endif
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

typedef struct sink { unsigned char *p; size_t n, cap; int oom; } sink;

static void sink_write(void *ctx, void *data, int size)
{
    sink *s = ctx;
    if (s->oom || size <= 0) return;
    if (s->n + (size_t)size > s->cap) {
        size_t c = s->cap ? s->cap : 4096;
        while (c < s->n + (size_t)size) c *= 2;
        unsigned char *q = realloc(s->p, c);
        if (!q) { s->oom = 1; return; }
        s->p = q;
        s->cap = c;
    }
    memcpy(s->p + s->n, data, (size_t)size);
    s->n += (size_t)size;
}

int st_png_write(const char *path, int w, int h, const unsigned char *rgba, st_error *err)
{
    if (w <= 0 || h <= 0) return st_fail(err, ST_ERR_RANGE, "%s: empty image", path);
    unsigned char *rgb = malloc((size_t)w * (size_t)h * 3);
    if (!rgb) return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", path);
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) memcpy(rgb + 3 * i, rgba + 4 * i, 3);
    sink s = { 0 };
    int ok = stbi_write_png_to_func(sink_write, &s, w, h, 3, rgb, w * 3);
    free(rgb);
    if (!ok || s.oom) { free(s.p); return st_fail(err, ST_ERR_MEMORY, "%s: cannot encode the PNG", path); }
    /* Through a temporary renamed over path (core/io/atomic_file.h): a
     * failed write (a full disk) keeps the old file and says why. */
    st_afile af;
    int rc = st_afile_open(&af, path, err);
    if (!rc) {
        st_afile_write(&af, s.p, s.n);
        rc = st_afile_commit(&af, err);
    }
    free(s.p);
    return rc;
}

size_t st_png_write_bytes(int w, int h)
{
    /* RGB copy 3, filtered rows 3 (+1 per row), the deflate stream of at
     * most about the filtered size held in a sink up to twice that: 6. */
    return (size_t)w * (size_t)h * 12 + (size_t)h;
}

int st_png_read(const char *path, int *w, int *h, unsigned char **rgba, st_error *err)
{
    FILE *f = st_open_input(path, err);
    if (!f) return err ? err->code : ST_ERR_IO;
    unsigned char *buf = NULL;
    size_t n = 0, cap = 0;
    for (;;) {
        if (n == cap) {
            cap = cap ? 2 * cap : 65536;
            unsigned char *q = realloc(buf, cap);
            if (!q) { free(buf); fclose(f); return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", path); }
            buf = q;
        }
        size_t r = fread(buf + n, 1, cap - n, f);
        n += r;
        if (r == 0) break;
    }
    fclose(f);
    int rc = st_png_decode(path, buf, n, w, h, rgba, err);
    free(buf);
    return rc;
}

/* stb's reason, printable: for an unknown chunk it copies the chunk's type
 * bytes from the file into the message, newlines and escapes included
 * (fuzz_nmap). */
static const char *png_reason(char *buf, size_t n)
{
    const char *r = stbi_failure_reason();
    snprintf(buf, n, "%s", r ? r : "unknown");
    for (char *c = buf; *c; c++)
        if ((unsigned char)*c < 0x20 || (unsigned char)*c > 0x7e) *c = '?';
    return buf;
}

/* Whether the first IDAT chunk is empty: stb then adds 0 to its NULL
 * buffer and copies 0 bytes to it, undefined behaviour that UBSan stops on
 * (fuzz_nmap), so such a file is refused before stb sees it.  Encoders
 * write no empty IDAT. */
static int first_idat_empty(const unsigned char *d, size_t n)
{
    size_t at = 8;
    /* A chunk's length and type (8 bytes) suffice: stb reads a chunk whose
     * CRC is cut off too (fuzz_nmap's seed idat_empty_truncated.png). */
    while (n >= 8 && at <= n - 8) {
        uint32_t len = (uint32_t)d[at] << 24 | (uint32_t)d[at + 1] << 16 | (uint32_t)d[at + 2] << 8 | d[at + 3];
        if (!memcmp(d + at + 4, "IDAT", 4)) return len == 0;
        if (len > n - at - 8) return 0; /* truncated: stb says so */
        at += 12 + (size_t)len;
    }
    return 0;
}

int st_png_decode(const char *name, const void *data, size_t n, int *w, int *h, unsigned char **rgba, st_error *err)
{
    if (n > 0x7fffffff) return st_fail(err, ST_ERR_RANGE, "%s: file too large", name);
    /* The size the header claims, checked before stb allocates for it. */
    int iw = 0, ih = 0, comp = 0;
    char why[64];
    if (!stbi_info_from_memory(data, (int)n, &iw, &ih, &comp))
        return st_fail(err, ST_ERR_PARSE, "%s: not a PNG this reader understands (%s)", name, png_reason(why, sizeof why));
    if (first_idat_empty(data, n)) return st_fail(err, ST_ERR_PARSE, "%s: an empty IDAT chunk before the image data", name);
    if (iw > ST_PNG_MAX_SIDE || ih > ST_PNG_MAX_SIDE)
        return st_fail(err, ST_ERR_RANGE, "%s: %dx%d pixels, more than %d a side", name, iw, ih, ST_PNG_MAX_SIDE);
    /* stb holds the inflated rows (up to 16 bits a channel) and the RGBA result. */
    size_t bytes = (size_t)iw * (size_t)ih * 4;
    st_error e;
    if (3 * bytes >= ST_MEM_CHECK_MIN_BYTES && st_mem_check(3 * bytes, "decoding it", &e))
        return st_fail(err, ST_ERR_MEMORY, "%s: %s", name, e.msg);
    unsigned char *px = stbi_load_from_memory(data, (int)n, w, h, &comp, 4);
    if (!px) return st_fail(err, ST_ERR_PARSE, "%s: not a PNG this reader understands (%s)", name, png_reason(why, sizeof why));
    /* Hand back memory from malloc (stb's allocator is malloc too, but the
     * caller should not need to know). */
    bytes = (size_t)*w * (size_t)*h * 4;
    unsigned char *out = malloc(bytes ? bytes : 1);
    if (!out) { stbi_image_free(px); return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", name); }
    memcpy(out, px, bytes);
    stbi_image_free(px);
    *rgba = out;
    return ST_OK;
}

void st_image_compare(const unsigned char *a, const unsigned char *b, int w, int h, int tol,
                      st_image_diff *out, unsigned char *diff)
{
    memset(out, 0, sizeof *out);
    out->pixels = (uint64_t)w * (uint64_t)h;
    for (size_t i = 0; i < (size_t)out->pixels; i++) {
        int m = 0;
        for (int c = 0; c < 3; c++) {
            int d = abs((int)a[4 * i + c] - (int)b[4 * i + c]);
            if (d > m) m = d;
        }
        if (m > out->max_delta) out->max_delta = m;
        if (m > tol) out->differing++;
        if (diff) {
            unsigned char *o = diff + 4 * i;
            if (m > tol) {
                o[0] = (unsigned char)(128 + (m > 127 ? 127 : m));
                o[1] = 0;
                o[2] = 0;
            } else {
                unsigned g = (b[4 * i] + b[4 * i + 1] + b[4 * i + 2]) / 3;
                o[0] = o[1] = o[2] = (unsigned char)(191 + g / 4);
            }
            o[3] = 255;
        }
    }
    out->fraction = out->pixels ? (double)out->differing / (double)out->pixels : 0;
}

int st_image_match(const st_image_diff *d, double max_fraction)
{
    return d->fraction <= max_fraction;
}
