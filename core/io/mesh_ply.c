/* PLY reader: ascii, binary_little_endian and binary_big_endian.
 *
 * The header is parsed into a table of elements and their properties; the
 * body is then read element by element in header order.  Only two things
 * are kept: the x, y, z properties of the "vertex" element (any numeric
 * type, converted to double) and the "vertex_indices" (or "vertex_index")
 * list of the "face" element (any integer count and index types).  Every
 * other element and property, lists included, is skipped by type, so that
 * the reader stays in step with the data.
 *
 * Safety rules: element counts are checked against the limits and against
 * the bytes left (each record has a minimum size known from the header)
 * before anything is allocated; every read is bounds-checked and a short
 * file names the byte offset (binary) or line (ascii) where it ends; the
 * body must end exactly where the header says it does.
 */
#include "core/io/mesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ELEMS 64        /* elements in one header */
#define MAX_PROPS 1024      /* properties in one header, all elements */

enum ply_type { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 };
static const uint8_t type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
enum ply_format { F_ASCII, F_LE, F_BE };
enum ply_role { R_OTHER, R_VERTEX, R_FACE };

typedef struct ply_prop {
    const char *name;       /* points into the header, nlen bytes */
    size_t nlen;
    uint8_t type;           /* scalar type, or the item type of a list */
    uint8_t count_type;     /* T_NONE for a scalar, else the list count type */
} ply_prop;

typedef struct ply_elem {
    const char *name;
    size_t nlen;
    uint64_t count;         /* records announced by the header */
    uint32_t first, nprops; /* its properties: props[first .. first+nprops) */
    int role;               /* enum ply_role */
    int xyz[3];             /* vertex: property numbers of x, y, z (-1: absent) */
    int list;               /* face: property number of vertex_indices (-1: absent) */
    int uv[2];              /* vertex: property numbers of u v / s t / texture_u texture_v (-1: absent) */
} ply_elem;

typedef struct ply_reader {
    const char *name;
    st_error *err;
    const unsigned char *data;
    size_t size, pos;       /* the file and the read cursor */
    uint64_t line;          /* ascii: line of the cursor (header lines included) */
    int format;             /* enum ply_format */
    ply_elem elems[MAX_ELEMS];
    ply_prop props[MAX_PROPS];
    uint32_t nelems, nprops;
    int in_body;            /* 0 while reading the (text) header */
    uint64_t mark;          /* binary body: offset of the value being read */
    const ply_elem *ctx;    /* element being read and record number, for messages */
    uint64_t ctx_index;
    st_mesh_build b;        /* result under construction; face_loc: line or byte offset of each face */
} ply_reader;

/* Problems name the line in the header and in an ascii body, and the byte
 * offset of the value being read in a binary body. */
static int binary_body(const ply_reader *r)
{
    return r->in_body && r->format != F_ASCII;
}
#define FAIL(r, code, ...) st_mesh_fail_at((r)->err, (code), (r)->name, binary_body(r), \
                                           binary_body(r) ? (r)->mark : (r)->line, __VA_ARGS__)

static int name_is(const char *s, size_t n, const char *word)
{
    return strlen(word) == n && memcmp(s, word, n) == 0;
}

/* ---- header ---------------------------------------------------------------- */

typedef struct hdr_line {
    const char *tok[6];     /* first tokens of the line */
    size_t len[6];
    int n;                  /* tokens found (at most 6 kept) */
} hdr_line;

/* Splits the next header line (the cursor moves past it).  0 at the end. */
static int header_line(ply_reader *r, hdr_line *h)
{
    if (r->pos >= r->size) return 0;
    const char *s = (const char *)r->data + r->pos;
    const char *nl = memchr(s, '\n', r->size - r->pos);
    const char *le = nl ? nl : (const char *)r->data + r->size;
    r->pos = (size_t)(le - (const char *)r->data) + (nl ? 1 : 0);
    r->line++;
    h->n = 0;
    const char *q = s;
    while (q < le && h->n < 6) {
        while (q < le && (*q == ' ' || *q == '\t' || *q == '\r')) q++;
        if (q == le) break;
        const char *t = q;
        while (q < le && *q != ' ' && *q != '\t' && *q != '\r') q++;
        h->tok[h->n] = t;
        h->len[h->n++] = (size_t)(q - t);
    }
    return 1;
}

static int parse_type(const char *s, size_t n)
{
    static const struct { const char *a, *b; int t; } names[] = {
        {"char", "int8", T_I8},     {"uchar", "uint8", T_U8},
        {"short", "int16", T_I16},  {"ushort", "uint16", T_U16},
        {"int", "int32", T_I32},    {"uint", "uint32", T_U32},
        {"float", "float32", T_F32}, {"double", "float64", T_F64},
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (name_is(s, n, names[i].a) || name_is(s, n, names[i].b)) return names[i].t;
    return T_NONE;
}

static int header_format(ply_reader *r, const hdr_line *h)
{
    char q[48];
    if (h->n != 3 || !name_is(h->tok[2], h->len[2], "1.0"))
        return FAIL(r, ST_ERR_PARSE, "bad format line (expected 'format <type> 1.0')");
    if (name_is(h->tok[1], h->len[1], "ascii")) r->format = F_ASCII;
    else if (name_is(h->tok[1], h->len[1], "binary_little_endian")) r->format = F_LE;
    else if (name_is(h->tok[1], h->len[1], "binary_big_endian")) r->format = F_BE;
    else return FAIL(r, ST_ERR_PARSE, "unknown PLY format '%s'", st_text_quote(q, sizeof q, h->tok[1], h->len[1]));
    return 0;
}

static int header_element(ply_reader *r, const hdr_line *h)
{
    int64_t count;
    if (h->n != 3 || st_mesh_parse_int(h->tok[2], h->len[2], &count) || count < 0)
        return FAIL(r, ST_ERR_PARSE, "bad element line (expected 'element <name> <count>')");
    if (r->nelems == MAX_ELEMS) return FAIL(r, ST_ERR_RANGE, "more than %d elements", MAX_ELEMS);
    ply_elem *e = &r->elems[r->nelems++];
    memset(e, 0, sizeof *e);
    e->name = h->tok[1];
    e->nlen = h->len[1];
    e->count = (uint64_t)count;
    e->first = r->nprops;
    e->xyz[0] = e->xyz[1] = e->xyz[2] = e->list = -1;
    e->uv[0] = e->uv[1] = -1;
    return 0;
}

static int header_property(ply_reader *r, const hdr_line *h)
{
    char q[48];
    if (r->nelems == 0) return FAIL(r, ST_ERR_PARSE, "property before any element");
    if (r->nprops == MAX_PROPS) return FAIL(r, ST_ERR_RANGE, "more than %d properties", MAX_PROPS);
    ply_prop p = {0};
    int is_list = h->n >= 2 && name_is(h->tok[1], h->len[1], "list");
    if (is_list ? h->n != 5 : h->n != 3)
        return FAIL(r, ST_ERR_PARSE, "bad property line (expected 'property <type> <name>' "
                    "or 'property list <count type> <item type> <name>')");
    int ti = is_list ? 3 : 1;
    p.type = (uint8_t)parse_type(h->tok[ti], h->len[ti]);
    if (p.type == T_NONE)
        return FAIL(r, ST_ERR_PARSE, "unknown property type '%s'", st_text_quote(q, sizeof q, h->tok[ti], h->len[ti]));
    if (is_list) {
        p.count_type = (uint8_t)parse_type(h->tok[2], h->len[2]);
        if (p.count_type == T_NONE || p.count_type >= T_F32)
            return FAIL(r, ST_ERR_PARSE, "list count type '%s' is not an integer type",
                        st_text_quote(q, sizeof q, h->tok[2], h->len[2]));
    }
    p.name = h->tok[ti + 1];
    p.nlen = h->len[ti + 1];
    r->props[r->nprops++] = p;
    r->elems[r->nelems - 1].nprops++;
    return 0;
}

static int header_lines(ply_reader *r)
{
    hdr_line h;
    char q[48];
    int have_format = 0;
    while (header_line(r, &h)) {
        if (h.n == 0) continue;
        int rc = 0;
        if (name_is(h.tok[0], h.len[0], "end_header")) {
            if (!have_format) return FAIL(r, ST_ERR_PARSE, "header has no format line");
            return 0;
        } else if (name_is(h.tok[0], h.len[0], "format")) {
            rc = header_format(r, &h);
            have_format = 1;
        } else if (name_is(h.tok[0], h.len[0], "element")) {
            rc = header_element(r, &h);
        } else if (name_is(h.tok[0], h.len[0], "property")) {
            rc = header_property(r, &h);
        } else if (!name_is(h.tok[0], h.len[0], "comment") && !name_is(h.tok[0], h.len[0], "obj_info")) {
            rc = FAIL(r, ST_ERR_PARSE, "unknown header line '%s'", st_text_quote(q, sizeof q, h.tok[0], h.len[0]));
        }
        if (rc) return rc;
    }
    return st_fail(r->err, ST_ERR_PARSE, "%s: header has no end_header line", r->name);
}

/* Per-vertex texture coordinates under the names exporters use (u v:
 * Blender, s t: VCGlib/MeshLab, texture_u texture_v: others); the first
 * pair present in full is read. */
static void find_uv(ply_reader *r, ply_elem *e)
{
    static const char *const names[3][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}};
    for (int n = 0; n < 3 && e->uv[1] < 0; n++) {
        int at[2] = {-1, -1};
        for (uint32_t k = 0; k < e->nprops; k++) {
            const ply_prop *p = &r->props[e->first + k];
            for (int a = 0; a < 2; a++)
                if (p->count_type == T_NONE && at[a] < 0 && name_is(p->name, p->nlen, names[n][a])) at[a] = (int)k;
        }
        if (at[0] >= 0 && at[1] >= 0) { e->uv[0] = at[0]; e->uv[1] = at[1]; }
    }
}

/* Finds the vertex and face elements and the properties the mesh needs. */
static int header_roles(ply_reader *r)
{
    static const char *const axis[3] = {"x", "y", "z"};
    ply_elem *ev = NULL, *ef = NULL;
    for (uint32_t i = 0; i < r->nelems; i++) {
        ply_elem *e = &r->elems[i];
        if (!ev && name_is(e->name, e->nlen, "vertex")) { ev = e; e->role = R_VERTEX; }
        else if (!ef && name_is(e->name, e->nlen, "face")) { ef = e; e->role = R_FACE; }
        for (uint32_t k = 0; k < e->nprops; k++) {
            const ply_prop *p = &r->props[e->first + k];
            for (int a = 0; a < 3; a++)
                if (e == ev && p->count_type == T_NONE && e->xyz[a] < 0 && name_is(p->name, p->nlen, axis[a]))
                    e->xyz[a] = (int)k;
            if (e == ef && e->list < 0 && p->count_type != T_NONE &&
                (name_is(p->name, p->nlen, "vertex_indices") || name_is(p->name, p->nlen, "vertex_index")))
                e->list = (int)k;
        }
    }
    if (!ev || ev->xyz[0] < 0 || ev->xyz[1] < 0 || ev->xyz[2] < 0)
        return st_fail(r->err, ST_ERR_PARSE, "%s: header has no vertex element with x, y and z", r->name);
    find_uv(r, ev);
    if (!ef || ef->list < 0)
        return st_fail(r->err, ST_ERR_PARSE, "%s: header has no face element with a vertex_indices list", r->name);
    if (r->props[ef->first + (uint32_t)ef->list].type >= T_F32)
        return st_fail(r->err, ST_ERR_PARSE, "%s: vertex_indices are not of an integer type", r->name);
    if (ev->count > ST_MESH_MAX_VERTS || ef->count > ST_MESH_MAX_FACES)
        return st_fail(r->err, ST_ERR_RANGE, "%s: %llu vertices and %llu faces exceed the limits (%u, %u)",
                       r->name, (unsigned long long)ev->count, (unsigned long long)ef->count,
                       ST_MESH_MAX_VERTS, ST_MESH_MAX_FACES);
    if (ef->count == 0) return st_fail(r->err, ST_ERR_TOPOLOGY, "%s: no faces", r->name);
    r->b.m.nverts = (uint32_t)ev->count;
    r->b.m.nfaces = (uint32_t)ef->count;
    return 0;
}

/* The fewest bytes one record of e can take: binary, its scalars and list
 * counts; ascii, one character and one separator per value. */
static uint64_t min_record(const ply_reader *r, const ply_elem *e)
{
    uint64_t n = 0;
    for (uint32_t k = 0; k < e->nprops; k++) {
        const ply_prop *p = &r->props[e->first + k];
        if (r->format == F_ASCII) n += 2;
        else n += type_size[p->count_type != T_NONE ? p->count_type : p->type];
    }
    return n;
}

/* Announced records against the bytes after the header, before allocating.
 * Problems are located at the start of the body. */
static int check_counts(ply_reader *r)
{
    uint64_t left = r->size - r->pos, need = 0;
    int bin = r->format != F_ASCII;
    uint64_t at = bin ? (uint64_t)r->pos : r->line;
    char q[48];
    for (uint32_t i = 0; i < r->nelems; i++) {
        const ply_elem *e = &r->elems[i];
        uint64_t rec = min_record(r, e);
        if (rec && e->count > (left + 1) / rec)
            return st_mesh_fail_at(r->err, ST_ERR_RANGE, r->name, bin, at, "header announces %llu '%s' "
                                   "records of at least %llu bytes but only %llu bytes follow the header",
                                   (unsigned long long)e->count, st_text_quote(q, sizeof q, e->name, e->nlen),
                                   (unsigned long long)rec, (unsigned long long)left);
        need += rec * e->count;     /* no overflow: each term is at most left + 1 */
    }
    if (!bin && need > 0) need--;   /* no separator after the last value */
    if (need > left)
        return st_mesh_fail_at(r->err, ST_ERR_RANGE, r->name, bin, at, "header announces more data "
                               "than the file holds (at least %llu bytes needed, %llu follow the header)",
                               (unsigned long long)need, (unsigned long long)left);
    return 0;
}

/* ---- body ------------------------------------------------------------------ */

static int truncated(ply_reader *r)
{
    char q[48];
    const ply_elem *e = r->ctx;
    return FAIL(r, ST_ERR_PARSE, "file ends inside %s record %llu of %llu (truncated, or the "
                "header announces more records than the file holds)", st_text_quote(q, sizeof q, e->name, e->nlen),
                (unsigned long long)r->ctx_index + 1, (unsigned long long)e->count);
}

static int is_space(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == '\n';
}

/* Next ascii token, counting the lines it skips. */
static int ascii_token(ply_reader *r, const char **tok, size_t *len)
{
    while (r->pos < r->size && is_space(r->data[r->pos])) {
        if (r->data[r->pos] == '\n') r->line++;
        r->pos++;
    }
    if (r->pos == r->size) return truncated(r);
    size_t start = r->pos;
    while (r->pos < r->size && !is_space(r->data[r->pos])) r->pos++;
    *tok = (const char *)r->data + start;
    *len = r->pos - start;
    return 0;
}

/* Little- or big-endian unsigned integer of n bytes at the cursor. */
static int binary_raw(ply_reader *r, int type, uint64_t *raw)
{
    size_t n = type_size[type];
    r->mark = r->pos;
    if (r->size - r->pos < n) return truncated(r);
    const unsigned char *b = r->data + r->pos;
    uint64_t v = 0;
    for (size_t k = 0; k < n; k++) v = (v << 8) | b[r->format == F_BE ? k : n - 1 - k];
    r->pos += n;
    *raw = v;
    return 0;
}

/* Converts raw bits of the given type: integers exactly into *i, every
 * type into *d. */
static void convert(int type, uint64_t raw, int64_t *i, double *d)
{
    int64_t v = 0;
    switch (type) {
    case T_I8:  v = raw >= 0x80 ? (int64_t)raw - 0x100 : (int64_t)raw; break;
    case T_I16: v = raw >= 0x8000 ? (int64_t)raw - 0x10000 : (int64_t)raw; break;
    case T_I32: v = raw >= 0x80000000u ? (int64_t)raw - 0x100000000 : (int64_t)raw; break;
    case T_F32: {
        uint32_t u = (uint32_t)raw;
        float f;
        memcpy(&f, &u, sizeof f);
        *i = 0;
        *d = f;
        return;
    }
    case T_F64:
        memcpy(d, &raw, sizeof *d);
        *i = 0;
        return;
    default: v = (int64_t)raw; break;   /* unsigned types */
    }
    *i = v;
    *d = (double)v;
}

static int read_value(ply_reader *r, int type, int64_t *i, double *d)
{
    if (r->format != F_ASCII) {
        uint64_t raw = 0;
        int rc = binary_raw(r, type, &raw);
        if (!rc) convert(type, raw, i, d);
        return rc;
    }
    const char *tok;
    size_t len;
    char q[48];
    int rc = ascii_token(r, &tok, &len);
    if (rc) return rc;
    if (type >= T_F32) {
        *i = 0;
        if (st_mesh_parse_double(tok, len, d))
            return FAIL(r, ST_ERR_PARSE, "bad number '%s'", st_text_quote(q, sizeof q, tok, len));
        return 0;
    }
    if (st_mesh_parse_int(tok, len, i))
        return FAIL(r, ST_ERR_PARSE, "bad integer '%s'", st_text_quote(q, sizeof q, tok, len));
    *d = (double)*i;
    return 0;
}

/* Skips n values of one type (one scalar, or the items of a list). */
static int skip_values(ply_reader *r, int type, uint64_t n)
{
    if (r->format != F_ASCII) {
        r->mark = r->pos;
        if (n > (r->size - r->pos) / type_size[type]) return truncated(r);
        r->pos += (size_t)n * type_size[type];
        return 0;
    }
    for (uint64_t k = 0; k < n; k++) {
        const char *tok;
        size_t len;
        int rc = ascii_token(r, &tok, &len);
        if (rc) return rc;
    }
    return 0;
}

static int read_list_length(ply_reader *r, const ply_prop *p, int64_t *n)
{
    double d;
    int rc = read_value(r, p->count_type, n, &d);
    if (!rc && *n < 0) rc = FAIL(r, ST_ERR_PARSE, "negative list length %lld", (long long)*n);
    return rc;
}

static int skip_property(ply_reader *r, const ply_prop *p)
{
    if (p->count_type == T_NONE) return skip_values(r, p->type, 1);
    int64_t n;
    int rc = read_list_length(r, p, &n);
    return rc ? rc : skip_values(r, p->type, (uint64_t)n);
}

static int read_vertex(ply_reader *r, const ply_elem *e, uint32_t v)
{
    for (uint32_t k = 0; k < e->nprops; k++) {
        const ply_prop *p = &r->props[e->first + k];
        int a = (int)k == e->xyz[0] ? 0 : (int)k == e->xyz[1] ? 1 : (int)k == e->xyz[2] ? 2 : -1;
        int t = (int)k == e->uv[0] ? 0 : (int)k == e->uv[1] ? 1 : -1;
        if (t >= 0) {
            int64_t i;
            double x;
            int rc = read_value(r, p->type, &i, &x);
            if (rc) return rc;
            if (!isfinite(x))
                return FAIL(r, ST_ERR_GEOMETRY, "vertex %u has a non-finite texture coordinate", v);
            r->b.m.uv[2 * (size_t)v + (size_t)t] = x;
            continue;
        }
        if (a < 0) {
            int rc = skip_property(r, p);
            if (rc) return rc;
            continue;
        }
        int64_t i;
        double x;
        int rc = read_value(r, p->type, &i, &x);
        if (rc) return rc;
        if (!isfinite(x))
            return FAIL(r, ST_ERR_GEOMETRY, "vertex %u has a non-finite coordinate (nan, inf or overflow)", v);
        r->b.m.pos[3 * (size_t)v + (size_t)a] = x;
    }
    return 0;
}

static int ensure_tmp(ply_reader *r, size_t n)
{
    return st_mesh_build_reserve(&r->b, n) ? FAIL(r, ST_ERR_MEMORY, "out of memory") : 0;
}

/* Reads n vertex indices into r->b.tmp, each checked against the vertex count. */
static int read_indices(ply_reader *r, const ply_prop *p, uint32_t n)
{
    if (r->format != F_ASCII && n > (r->size - r->pos) / type_size[p->type]) {
        r->mark = r->pos;
        return truncated(r);
    }
    int rc = ensure_tmp(r, n);
    if (rc) return rc;
    for (uint32_t k = 0; k < n; k++) {
        int64_t v;
        double d;
        rc = read_value(r, p->type, &v, &d);
        if (rc) return rc;
        if (v < 0 || v >= (int64_t)r->b.m.nverts)
            return FAIL(r, ST_ERR_RANGE, "face %llu references vertex %lld but the file has %u vertices",
                        (unsigned long long)r->ctx_index, (long long)v, r->b.m.nverts);
        r->b.tmp[k] = (uint32_t)v;
    }
    return 0;
}

static int read_face_list(ply_reader *r, const ply_prop *p, uint32_t f)
{
    int64_t n;
    int rc = read_list_length(r, p, &n);
    if (rc) return rc;
    uint64_t loc = binary_body(r) ? r->mark : r->line;
    if (n < 3) return FAIL(r, ST_ERR_TOPOLOGY, "face %u has %lld vertices; a face needs at least 3", f, (long long)n);
    if (n > ST_MESH_MAX_DEGREE)
        return FAIL(r, ST_ERR_RANGE, "face %u has %lld vertices (limit %u)", f, (long long)n, ST_MESH_MAX_DEGREE);
    rc = read_indices(r, p, (uint32_t)n);
    if (rc) return rc;
    uint32_t dup = st_mesh_face_repeat(r->b.tmp, (uint32_t)n, r->b.scratch);
    if (dup != UINT32_MAX)
        return st_mesh_fail_at(r->err, ST_ERR_TOPOLOGY, r->name, binary_body(r), loc,
                               "face %u uses vertex %u more than once", f, dup);
    rc = st_mesh_build_face(&r->b, f, (uint32_t)n, loc);
    if (rc == ST_ERR_RANGE) return FAIL(r, ST_ERR_RANGE, "too many face corners");
    if (rc) return FAIL(r, ST_ERR_MEMORY, "out of memory for face corners");
    return 0;
}

static int read_face(ply_reader *r, const ply_elem *e, uint32_t f)
{
    for (uint32_t k = 0; k < e->nprops; k++) {
        const ply_prop *p = &r->props[e->first + k];
        int rc = (int)k == e->list ? read_face_list(r, p, f) : skip_property(r, p);
        if (rc) return rc;
    }
    return 0;
}

static int read_record(ply_reader *r, const ply_elem *e, uint64_t i)
{
    if (e->role == R_VERTEX) return read_vertex(r, e, (uint32_t)i);
    if (e->role == R_FACE) return read_face(r, e, (uint32_t)i);
    for (uint32_t k = 0; k < e->nprops; k++) {
        int rc = skip_property(r, &r->props[e->first + k]);
        if (rc) return rc;
    }
    return 0;
}

static int read_body(ply_reader *r)
{
    r->in_body = 1;
    for (uint32_t j = 0; j < r->nelems; j++) {
        const ply_elem *e = &r->elems[j];
        r->ctx = e;
        if (e->nprops == 0) continue;   /* records of no bytes: nothing to read */
        for (uint64_t i = 0; i < e->count; i++) {
            r->ctx_index = i;
            int rc = read_record(r, e, i);
            if (rc) return rc;
        }
    }
    if (r->format == F_ASCII)
        while (r->pos < r->size && is_space(r->data[r->pos])) r->line += r->data[r->pos++] == '\n';
    r->mark = r->pos;
    if (r->pos < r->size)
        return FAIL(r, ST_ERR_PARSE, "%llu bytes of data after the last element (the header "
                    "announces fewer records than the file holds)", (unsigned long long)(r->size - r->pos));
    return 0;
}

static int read_magic(ply_reader *r)
{
    hdr_line h;
    if (!header_line(r, &h) || h.n != 1 || !name_is(h.tok[0], h.len[0], "ply"))
        return st_fail(r->err, ST_ERR_PARSE, "%s:1: not a PLY file (no 'ply' first line)", r->name);
    return 0;
}

static int alloc_mesh(ply_reader *r)
{
    st_mesh *m = &r->b.m;
    m->pos = malloc(3 * (size_t)m->nverts * sizeof *m->pos + 1);
    m->face_off = malloc(((size_t)m->nfaces + 1) * sizeof *m->face_off);
    r->b.face_loc = malloc((size_t)m->nfaces * sizeof *r->b.face_loc);
    if (!m->pos || !m->face_off || !r->b.face_loc)
        return st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory for %u vertices and %u faces",
                       r->name, m->nverts, m->nfaces);
    m->face_off[0] = 0;
    const ply_elem *ev = NULL;
    for (uint32_t i = 0; i < r->nelems && !ev; i++)
        if (r->elems[i].role == R_VERTEX) ev = &r->elems[i];
    if (ev && ev->uv[1] >= 0) {
        m->nuvs = m->nverts;
        m->uv = malloc(2 * (size_t)m->nverts * sizeof *m->uv + 1);
        if (!m->uv) return st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory for texture coordinates", r->name);
    }
    return 0;
}

/* Per-vertex UVs as a face-varying channel: each corner names its vertex's
 * value (no seams: PLY has none). */
static int uv_corners(ply_reader *r)
{
    st_mesh *m = &r->b.m;
    if (!m->uv || m->nverts == 0) {
        free(m->uv);
        m->uv = NULL;
        m->nuvs = 0;
        return 0;
    }
    size_t nc = m->face_off[m->nfaces];
    m->face_uv = malloc(nc * sizeof *m->face_uv + 1);
    if (!m->face_uv) return st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory for texture coordinates", r->name);
    memcpy(m->face_uv, m->face_idx, nc * sizeof *m->face_uv);
    return 0;
}

int st_mesh_parse_ply_src(const char *name, const char *data, size_t size,
                          st_mesh *out, st_mesh_src *src, st_error *err)
{
    if (size == 0) return st_fail(err, ST_ERR_PARSE, "%s: empty file", name);
    ply_reader *r = calloc(1, sizeof *r);
    if (!r) return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", name);
    r->name = name;
    r->err = err;
    r->data = (const unsigned char *)data;
    r->size = size;
    st_mesh_init(&r->b.m);
    int rc = read_magic(r);
    if (!rc) rc = header_lines(r);
    r->line++;      /* an ascii body starts on the line after end_header */
    if (!rc) rc = header_roles(r);
    if (!rc) rc = check_counts(r);
    if (!rc) rc = alloc_mesh(r);
    if (!rc) rc = read_body(r);
    if (!rc) rc = uv_corners(r);
    rc = st_mesh_build_end(&r->b, rc, out, src, r->format != F_ASCII, 0);
    free(r);
    return rc;
}
