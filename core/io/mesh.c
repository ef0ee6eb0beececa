/* st_mesh lifetime, notes, file reading and st_mesh_load() dispatch.
 *
 * Loading is three steps, each of which can refuse: read the whole file,
 * parse it into a scratch st_mesh (mesh_obj.c, mesh_off.c, mesh_ply.c), and
 * repair/check it (mesh_repair.c).  Only when all three succeed is the result
 * moved into *out, so a failed load leaves the caller's model untouched.
 */
#include "core/io/mesh_internal.h"
#include "core/base/hugepage.h"
#include "core/base/membudget.h"
#include "core/io/file_open.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Files above this are refused before reading: the largest mesh the limits
 * allow (2^27 vertices as text) stays well below it. */
#define MAX_FILE_BYTES ((size_t)1 << 32)

void st_mesh_src_free(st_mesh_src *src)
{
    if (!src) return;
    free(src->face_loc);
    src->face_loc = NULL;
}


/* ---- face and number helpers shared by the parsers ---------------------- */

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

uint32_t st_mesh_face_repeat(const uint32_t *idx, uint32_t n, uint32_t *scratch)
{
    /* Pairwise for short faces (the common case, no copy); sorting for long
     * ones so that a file of huge faces cannot make this quadratic. */
    if (n <= 16) {
        for (uint32_t i = 1; i < n; i++)
            for (uint32_t j = 0; j < i; j++)
                if (idx[i] == idx[j]) return idx[i];
        return UINT32_MAX;
    }
    memcpy(scratch, idx, (size_t)n * sizeof *idx);
    qsort(scratch, n, sizeof *scratch, cmp_u32);
    for (uint32_t i = 1; i < n; i++)
        if (scratch[i] == scratch[i - 1]) return scratch[i];
    return UINT32_MAX;
}

int st_mesh_parse_double(const char *s, size_t len, double *out)
{
    /* strtod needs a terminated string; tokens are copied to a bounded buffer
     * so the parser never reads past the caller's data. */
    char buf[128];
    if (len == 0 || len >= sizeof buf) return -1;
    memcpy(buf, s, len);
    buf[len] = 0;
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    if (end != buf + len) return -1;
    *out = v;   /* overflow gives +-HUGE_VAL: the caller's finiteness check names it */
    return 0;
}

int st_text_is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

const char *st_text_quote(char *buf, size_t size, const char *tok, size_t len)
{
    size_t n = len < size - 1 ? len : size - 1;
    for (size_t i = 0; i < n; i++) buf[i] = (tok[i] >= 32 && tok[i] < 127) ? tok[i] : '?';
    buf[n] = 0;
    return buf;
}

int st_text_token(const char **q, const char *le, const char **tok, size_t *len)
{
    const char *p = *q;
    while (p < le && st_text_is_blank(*p)) p++;
    if (p == le || *p == '#') { *q = p; return 0; }
    const char *s = p;
    while (p < le && !st_text_is_blank(*p) && *p != '#') p++;
    *tok = s;
    *len = (size_t)(p - s);
    *q = p;
    return 1;
}

int st_mesh_parse_int(const char *s, size_t len, int64_t *out)
{
    size_t i = 0;
    int neg = 0;
    if (len > 0 && (s[0] == '-' || s[0] == '+')) { neg = s[0] == '-'; i = 1; }
    if (i == len) return -1;
    int64_t v = 0;
    for (; i < len; i++) {
        if (s[i] < '0' || s[i] > '9') return -1;
        if (v > (INT64_MAX - 9) / 10) return -1;   /* far beyond any limit */
        v = v * 10 + (s[i] - '0');
    }
    *out = neg ? -v : v;
    return 0;
}

/* ---- reading files and dispatching -------------------------------------- */

#define LOAD_BYTES_PER_FILE_BYTE 6u

/* Reads path into a malloc'ed buffer (NUL-terminated for convenience). */
static int read_whole_file(const char *path, char **data, size_t *size, st_error *err)
{
    FILE *f = st_open_input(path, err);
    if (!f) return err ? err->code : ST_ERR_IO;
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return st_fail(err, ST_ERR_IO, "%s: not a regular file", path);
    }
    if ((uint64_t)st.st_size > MAX_FILE_BYTES) {
        fclose(f);
        return st_fail(err, ST_ERR_RANGE, "%s: file of %lld bytes is too large (limit %zu)",
                       path, (long long)st.st_size, MAX_FILE_BYTES);
    }
    size_t n = (size_t)st.st_size;
    /* The memory guard (core/base/membudget.h): the file, then the mesh
     * parsed from it and repaired.  The mesh's size follows the counts, not
     * the bytes (digits per number vary), so this is a bound rather than an
     * estimate: LOAD_BYTES_PER_FILE_BYTE times the file, measured at 2 to 6
     * on the shared meshes (koala.obj 5.7, a 30 MB OBJ with UVs 2.1). */
    int rc = st_mem_check_read(path, "file", n, n + 1 + LOAD_BYTES_PER_FILE_BYTE * n, err);
    if (rc) {
        fclose(f);
        return rc;
    }
    /* Written in full by the read: huge pages, one fault per 2 MiB
     * (hugepage.h; a 120 MB OBJ took 30 thousand faults in 4 KiB pages). */
    char *buf = st_malloc_huge(n + 1);
    if (!buf) {
        fclose(f);
        return st_fail(err, ST_ERR_MEMORY, "%s: out of memory reading %zu bytes", path, n);
    }
    size_t got = fread(buf, 1, n, f);
    int bad = ferror(f);
    fclose(f);
    if (bad || got != n) {
        free(buf);
        return st_fail(err, ST_ERR_IO, "%s: read error after %zu of %zu bytes", path, got, n);
    }
    buf[n] = 0;
    *data = buf;
    *size = n;
    return 0;
}

enum mesh_format { FMT_UNKNOWN, FMT_OBJ, FMT_OFF, FMT_PLY };

int st_path_has_ext(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    if (n < k) return 0;
    for (size_t i = 0; i < k; i++) {
        char c = s[n - k + i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != suffix[i]) return 0;
    }
    return 1;
}

static enum mesh_format format_of(const char *path)
{
    if (st_path_has_ext(path, ".obj")) return FMT_OBJ;
    if (st_path_has_ext(path, ".off")) return FMT_OFF;
    if (st_path_has_ext(path, ".ply")) return FMT_PLY;
    return FMT_UNKNOWN;
}

static int parse_as(enum mesh_format fmt, const char *name, const char *data, size_t size,
                    st_mesh *out, st_mesh_src *src, st_error *err)
{
    switch (fmt) {
    case FMT_OBJ: return st_mesh_parse_obj_src(name, data, size, out, src, err);
    case FMT_OFF: return st_mesh_parse_off_src(name, data, size, out, src, err);
    case FMT_PLY: return st_mesh_parse_ply_src(name, data, size, out, src, err);
    default: break;
    }
    return st_fail(err, ST_ERR_PARSE, "%s: unknown mesh format (expected .obj, .off or .ply)", name);
}

/* Read, parse, repair into scratch; move into *out only on full success.
 * Notes are collected separately and appended only on success too. */
static int load_as(enum mesh_format fmt, const char *path, st_mesh *out, unsigned flags,
                   st_notes *notes, st_error *err)
{
    if (fmt == FMT_UNKNOWN) return parse_as(fmt, path, NULL, 0, NULL, NULL, err);
    char *data = NULL;
    size_t size = 0;
    int rc = read_whole_file(path, &data, &size, err);
    if (rc) return rc;
    st_mesh m;
    st_mesh_init(&m);
    st_mesh_src src = {0};
    rc = parse_as(fmt, path, data, size, &m, &src, err);
    free(data);
    if (rc) st_mesh_free(&m);
    else rc = st_mesh_finish_load(path, &m, &src, flags, out, notes, err);
    st_mesh_src_free(&src);
    return rc;
}

int st_mesh_finish_load(const char *name, st_mesh *parsed, const st_mesh_src *src, unsigned flags,
                        st_mesh *out, st_notes *notes, st_error *err)
{
    st_notes local = {0};
    int rc = st_mesh_repair_src(name, parsed, src, flags, notes ? &local : NULL, err);
    if (rc) {
        st_mesh_free(parsed);
        st_notes_free(&local);
        return rc;
    }
    st_mesh_move(out, parsed);
    for (uint32_t i = 0; i < local.count; i++) st_notes_add(notes, "%s", local.lines[i]);
    st_notes_free(&local);
    return 0;
}

int st_mesh_load_notes(const char *path, st_mesh *out, st_notes *notes, st_error *err)
{
    return load_as(format_of(path), path, out, 0, notes, err);
}

int st_mesh_load_flags(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err)
{
    return load_as(format_of(path), path, out, flags, notes, err);
}

int st_mesh_load(const char *path, st_mesh *out, st_error *err)
{
    return load_as(format_of(path), path, out, 0, NULL, err);
}

int st_mesh_load_obj(const char *path, st_mesh *out, st_error *err)
{
    return load_as(FMT_OBJ, path, out, 0, NULL, err);
}

int st_mesh_load_off(const char *path, st_mesh *out, st_error *err)
{
    return load_as(FMT_OFF, path, out, 0, NULL, err);
}

int st_mesh_load_ply(const char *path, st_mesh *out, st_error *err)
{
    return load_as(FMT_PLY, path, out, 0, NULL, err);
}

int st_mesh_parse_obj(const char *name, const char *data, size_t size, st_mesh *out, st_error *err)
{
    return st_mesh_parse_obj_src(name, data, size, out, NULL, err);
}

int st_mesh_parse_off(const char *name, const char *data, size_t size, st_mesh *out, st_error *err)
{
    return st_mesh_parse_off_src(name, data, size, out, NULL, err);
}

int st_mesh_parse_ply(const char *name, const char *data, size_t size, st_mesh *out, st_error *err)
{
    return st_mesh_parse_ply_src(name, data, size, out, NULL, err);
}

int st_mesh_repair(const char *name, st_mesh *m, st_notes *notes, st_error *err)
{
    return st_mesh_repair_src(name, m, NULL, 0, notes, err);
}

int st_mesh_repair_flags(const char *name, st_mesh *m, unsigned flags, st_notes *notes, st_error *err)
{
    return st_mesh_repair_src(name, m, NULL, flags, notes, err);
}

int st_mesh_fail_at(st_error *err, int code, const char *name, int binary, uint64_t loc,
                    const char *fmt, ...)
{
    if (!err) return code;
    char what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (binary)
        return st_fail(err, code, "%s: byte %llu: %s", name, (unsigned long long)loc, what);
    return st_fail(err, code, "%s:%llu: %s", name, (unsigned long long)loc, what);
}

void *st_mesh_grow(void *p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return p;
    size_t n = *cap ? *cap : 64;
    while (n < need) {
        if (n > SIZE_MAX / 2) return NULL;
        n *= 2;
    }
    if (n > SIZE_MAX / elem) return NULL;
    void *q = realloc(p, n * elem);
    if (q) *cap = n;
    return q;
}

int st_mesh_build_reserve(st_mesh_build *b, size_t need)
{
    if (need <= b->cap_tmp) return ST_OK;
    size_t cap = b->cap_tmp, cap2 = b->cap_tmp;
    uint32_t *t = st_mesh_grow(b->tmp, &cap, need, sizeof *t);
    if (!t) return ST_ERR_MEMORY;
    b->tmp = t;
    uint32_t *s = st_mesh_grow(b->scratch, &cap2, need, sizeof *s);
    if (!s) return ST_ERR_MEMORY;
    b->scratch = s;
    b->cap_tmp = cap < cap2 ? cap : cap2;
    return ST_OK;
}

int st_mesh_build_face(st_mesh_build *b, uint32_t f, uint32_t n, uint64_t loc)
{
    uint32_t nc = b->m.face_off[f];
    if ((uint64_t)nc + n > UINT32_MAX) return ST_ERR_RANGE;
    uint32_t *idx = st_mesh_grow(b->m.face_idx, &b->cap_idx, (size_t)nc + n, sizeof *idx);
    if (!idx) return ST_ERR_MEMORY;
    b->m.face_idx = idx;
    memcpy(idx + nc, b->tmp, (size_t)n * sizeof *idx);
    b->m.face_off[f + 1] = nc + n;
    if (b->face_loc) b->face_loc[f] = loc;
    return ST_OK;
}

int st_mesh_build_end(st_mesh_build *b, int rc, st_mesh *out, st_mesh_src *src, int binary, int index_base)
{
    if (!rc) {
        if (src) {
            src->face_loc = b->face_loc;
            src->binary = binary;
            src->index_base = index_base;
            b->face_loc = NULL;
        }
        st_mesh_move(out, &b->m);
    }
    free(b->face_loc);
    free(b->tmp);
    free(b->scratch);
    st_mesh_free(&b->m);
    return rc;
}
