/* Wavefront OBJ reader: `v` and `f` records plus OpenSubdiv's `t` tags.
 *
 * Two passes over the text.  The first counts `v` and `f` lines so that the
 * position and face-offset arrays are allocated once, from counts the file
 * actually contains, and so that positive face indices can be checked
 * against the final vertex count (a face may name a vertex defined further
 * down).  The second pass parses.  Texture coordinates (`vt u v [w]`, w
 * ignored) become the face-varying UV channel (mesh.h); everything else
 * that OBJ can hold (vn, vp, o, g, s, usemtl, mtllib, l, p, free-form
 * geometry) is skipped: the subdivision cage needs only positions and
 * polygons.
 *
 * Faces are `f a b c ...` where each corner is `v`, `v/t`, `v//n` or
 * `v/t/n`; v and t are used.  Indices count from 1; negative ones count
 * back from the last vertex (texture coordinate) defined so far (-1 is the
 * latest).  A face gives t on every corner or on none; when some faces have
 * none, the file has no UV channel (it is dropped, as a UV layout with
 * holes in it cannot be subdivided).
 *
 * Tags follow OpenSubdiv's regression shapes (regression/common/
 * shape_utils.cpp reads them, far_utils.h applies them): `t name
 * nint/nfloat/nstring` then the values.  Tag vertex indices are 0-based
 * (unlike faces).
 *   t crease 4/1/0 a b c d s          vertex pairs, one crease edge per pair
 *                                      (a-b, c-d); one sharpness for all or
 *                                      one per pair; an odd count is refused
 *   t corner 1/1/0 v s                one sharpness for all or one per vertex
 *   t interpolateboundary 1/0/0 b     0 none, 1 edge-and-corner, 2 edge-only
 *   t creasemethod 0/0/1 normal       uniform sharpness decay (the default),
 *                       ... chaikin      or Chaikin's rule (Sdc::Options::CREASE_CHAIKIN)
 *   t smoothtriangles 0/0/1 catmark   Catmull-Clark's own rule on triangles,
 *                          ... smooth    or TRI_SUB_SMOOTH's edge weights
 *   t hole 2/0/0 f g                  faces (0-based, in file order) that are
 *                                      holes: in the rules, with no surface
 * Other tags are read (their counts must hold) and ignored.
 */
#include "core/io/mesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct obj_reader {
    const char *name;
    st_error *err;
    uint64_t line;          /* 1-based number of the line being parsed */
    const char *q, *le;     /* token cursor and end of the current line */
    uint32_t nv_total;      /* `v` lines in the whole file (first pass) */
    uint32_t nf_total;      /* `f` lines in the whole file (first pass) */
    uint32_t nvt_total;     /* `vt` lines in the whole file (first pass) */
    int faces_without_uv;   /* some face gave no t index: the channel is dropped */
    size_t cap_uv, cap_face_uv;
    st_mesh_build b;        /* result under construction; face_loc: line of each face */
    size_t cap_crease, cap_corner;
} obj_reader;

/* Fails naming the current line. */
#define FAIL(r, code, ...) st_mesh_fail_at((r)->err, (code), (r)->name, 0, (r)->line, __VA_ARGS__)

/* ---- tokens --------------------------------------------------------------- */


/* Next whitespace-separated token of the current line; 0 at the end of the
 * line or at a '#' comment. */
static int next_token(obj_reader *r, const char **tok, size_t *len)
{
    return st_text_token(&r->q, r->le, tok, len);
}

static int token_is(const char *tok, size_t len, const char *word)
{
    return strlen(word) == len && memcmp(tok, word, len) == 0;
}

static int ensure_tmp(obj_reader *r, size_t need)
{
    return st_mesh_build_reserve(&r->b, need) ? FAIL(r, ST_ERR_MEMORY, "out of memory") : 0;
}

/* ---- first pass ------------------------------------------------------------ */

/* The keyword of a line starting at p: returns 'v' for "v", 'f' for "f",
 * 't' for "vt". */
static char line_kind(const char *p, const char *le)
{
    while (p < le && st_text_is_blank(*p)) p++;
    if (p < le && (*p == 'v' || *p == 'f') && (p + 1 == le || st_text_is_blank(p[1]))) return *p;
    if (p + 1 < le && p[0] == 'v' && p[1] == 't' && (p + 2 == le || st_text_is_blank(p[2]))) return 't';
    return 0;
}

static int count_records(obj_reader *r, const char *data, size_t size)
{
    uint64_t nv = 0, nf = 0, nvt = 0;
    const char *p = data, *end = data + size;
    while (p < end) {
        const char *le = memchr(p, '\n', (size_t)(end - p));
        if (!le) le = end;
        char k = line_kind(p, le);
        nv += k == 'v';
        nf += k == 'f';
        nvt += k == 't';
        p = le + 1;
    }
    if (nvt > ST_MESH_MAX_VERTS)
        return st_fail(r->err, ST_ERR_RANGE, "%s: %llu texture coordinates exceed the limit of %u",
                       r->name, (unsigned long long)nvt, ST_MESH_MAX_VERTS);
    r->nvt_total = (uint32_t)nvt;
    if (nv > ST_MESH_MAX_VERTS)
        return st_fail(r->err, ST_ERR_RANGE, "%s: %llu vertices exceed the limit of %u",
                       r->name, (unsigned long long)nv, ST_MESH_MAX_VERTS);
    if (nf > ST_MESH_MAX_FACES)
        return st_fail(r->err, ST_ERR_RANGE, "%s: %llu faces exceed the limit of %u",
                       r->name, (unsigned long long)nf, ST_MESH_MAX_FACES);
    r->nv_total = (uint32_t)nv;
    r->nf_total = (uint32_t)nf;
    return 0;
}

/* ---- records --------------------------------------------------------------- */

static int parse_vertex(obj_reader *r)
{
    double *xyz = r->b.m.pos + 3 * (size_t)r->b.m.nverts;
    for (int k = 0; k < 3; k++) {
        const char *tok;
        size_t len;
        char q[48];
        if (!next_token(r, &tok, &len))
            return FAIL(r, ST_ERR_PARSE, "vertex has %d coordinates, 3 needed", k);
        if (st_mesh_parse_double(tok, len, &xyz[k]))
            return FAIL(r, ST_ERR_PARSE, "bad vertex coordinate '%s'", st_text_quote(q, sizeof q, tok, len));
        if (!isfinite(xyz[k]))
            return FAIL(r, ST_ERR_GEOMETRY, "non-finite vertex coordinate '%s' (nan, inf or overflow)",
                        st_text_quote(q, sizeof q, tok, len));
    }
    /* Further values (w, or the r g b of some exporters) are ignored. */
    r->b.m.nverts++;
    return 0;
}

/* `vt u v [w]`: the first two numbers. */
static int parse_texcoord(obj_reader *r)
{
    if (r->b.m.nuvs >= r->nvt_total) return FAIL(r, ST_ERR_RANGE, "too many texture coordinates");
    double *uv = st_mesh_grow(r->b.m.uv, &r->cap_uv, 2 * ((size_t)r->b.m.nuvs + 1), sizeof *uv);
    if (!uv) return FAIL(r, ST_ERR_MEMORY, "out of memory for texture coordinates");
    r->b.m.uv = uv;
    uv += 2 * (size_t)r->b.m.nuvs;
    for (int k = 0; k < 2; k++) {
        const char *tok;
        size_t len;
        char q[48];
        if (!next_token(r, &tok, &len)) {
            if (k == 1) { uv[1] = 0; break; }  /* `vt u`: v defaults to 0 (OBJ spec) */
            return FAIL(r, ST_ERR_PARSE, "texture coordinate has no value");
        }
        if (st_mesh_parse_double(tok, len, &uv[k]))
            return FAIL(r, ST_ERR_PARSE, "bad texture coordinate '%s'", st_text_quote(q, sizeof q, tok, len));
        if (!isfinite(uv[k]))
            return FAIL(r, ST_ERR_GEOMETRY, "non-finite texture coordinate '%s'", st_text_quote(q, sizeof q, tok, len));
    }
    r->b.m.nuvs++;
    return 0;
}

/* The words of a face corner's index in messages: vertex or texture
 * coordinate. */
typedef struct obj_index_kind {
    const char *noun, *count_unit, *relative_noun, *first;
} obj_index_kind;

/* An OBJ index i into 0-based: i > 0 counts from the file's first element
 * (total in the file, counted beforehand), i < 0 back from the last one
 * defined so far (OBJ's relative indices); 0 is invalid. */
static int resolve_index(obj_reader *r, const obj_index_kind *k, int64_t i, uint32_t total, uint32_t so_far,
                         uint32_t *out)
{
    if (i == 0)
        return FAIL(r, ST_ERR_RANGE, "%s index 0 in a face (OBJ indices start at 1)", k->noun);
    if (i > 0 && (uint64_t)i > total)
        return FAIL(r, ST_ERR_RANGE, "face references %s %lld but the file has %u%s", k->noun, (long long)i, total,
                    k->count_unit);
    if (i < 0 && -i > (int64_t)so_far)
        return FAIL(r, ST_ERR_RANGE, "relative %sindex %lld reaches before the first %s (%u%s defined so far)",
                    k->relative_noun, (long long)i, k->first, so_far, k->count_unit);
    *out = i > 0 ? (uint32_t)(i - 1) : (uint32_t)((int64_t)so_far + i);
    return 0;
}

/* The t of a corner "v/t" or "v/t/n" ([tok, tok+len) is "t"): 0-based. */
static int parse_corner_uv(obj_reader *r, const char *tok, size_t len, const char *corner, size_t clen, uint32_t *t)
{
    char q[48];
    int64_t i;
    if (st_mesh_parse_int(tok, len, &i))
        return FAIL(r, ST_ERR_PARSE, "bad face corner '%s'", st_text_quote(q, sizeof q, corner, clen));
    static const obj_index_kind uv = { "texture coordinate", "", "texture coordinate ", "one" };
    return resolve_index(r, &uv, i, r->nvt_total, r->b.m.nuvs, t);
}

/* One face corner "v", "v/t", "v//n" or "v/t/n": the 0-based vertex, and
 * the 0-based texture coordinate or UINT32_MAX when the corner has none. */
static int parse_corner(obj_reader *r, const char *tok, size_t len, uint32_t *v, uint32_t *t)
{
    char q[48];
    size_t vlen = 0;
    while (vlen < len && tok[vlen] != '/') vlen++;
    int slashes = 0;
    for (size_t i = vlen; i < len; i++) {
        char c = tok[i];
        slashes += c == '/';
        if (c != '/' && c != '-' && (c < '0' || c > '9')) slashes = 3;
    }
    int64_t i;
    if (slashes > 2 || st_mesh_parse_int(tok, vlen, &i))
        return FAIL(r, ST_ERR_PARSE, "bad face corner '%s'", st_text_quote(q, sizeof q, tok, len));
    *t = UINT32_MAX;
    size_t tlen = 0;
    while (vlen + 1 + tlen < len && tok[vlen + 1 + tlen] != '/') tlen++;
    if (slashes >= 1 && tlen > 0) {
        int rc = parse_corner_uv(r, tok + vlen + 1, tlen, tok, len, t);
        if (rc) return rc;
    }
    static const obj_index_kind vertex = { "vertex", " vertices", "", "vertex" };
    return resolve_index(r, &vertex, i, r->nv_total, r->b.m.nverts, v);
}

/* The face's texture coordinate indices (r->b.scratch[0..n)) into m.face_uv,
 * parallel to face_idx; a face without them drops the channel. */
static int store_face_uv(obj_reader *r, uint32_t nc, uint32_t n, int with_uv)
{
    if (!with_uv) r->faces_without_uv = 1;
    if (r->faces_without_uv || r->nvt_total == 0) return 0;
    uint32_t *fu = st_mesh_grow(r->b.m.face_uv, &r->cap_face_uv, (size_t)nc + n, sizeof *fu);
    if (!fu) return FAIL(r, ST_ERR_MEMORY, "out of memory for %u face corners", nc + n);
    r->b.m.face_uv = fu;
    memcpy(fu + nc, r->b.scratch, (size_t)n * sizeof *fu);
    return 0;
}

static int parse_face(obj_reader *r)
{
    st_mesh *m = &r->b.m;
    const char *tok;
    size_t len;
    uint32_t n = 0, with_uv = 0;
    while (next_token(r, &tok, &len)) {
        if (n == ST_MESH_MAX_DEGREE)
            return FAIL(r, ST_ERR_RANGE, "face has more than %u vertices", ST_MESH_MAX_DEGREE);
        int rc = ensure_tmp(r, (size_t)n + 1);
        uint32_t t = UINT32_MAX;
        if (!rc) rc = parse_corner(r, tok, len, &r->b.tmp[n], &t);
        if (rc) return rc;
        r->b.scratch[n] = t;  /* kept until the repeat check below reuses scratch */
        with_uv += t != UINT32_MAX;
        n++;
    }
    if (with_uv && with_uv != n)
        return FAIL(r, ST_ERR_PARSE, "face gives texture coordinates on %u of its %u corners", with_uv, n);
    int urc = store_face_uv(r, m->face_off[m->nfaces], n, with_uv != 0);
    if (urc) return urc;
    if (n < 3) return FAIL(r, ST_ERR_TOPOLOGY, "face has %u vertices; a face needs at least 3", n);
    uint32_t dup = st_mesh_face_repeat(r->b.tmp, n, r->b.scratch);
    if (dup != UINT32_MAX)
        return FAIL(r, ST_ERR_TOPOLOGY, "face uses vertex %u more than once", dup + 1);
    int frc = m->nfaces >= r->nf_total ? ST_ERR_RANGE : st_mesh_build_face(&r->b, m->nfaces, n, r->line);
    if (frc == ST_ERR_RANGE) return FAIL(r, ST_ERR_RANGE, "too many face corners");
    if (frc) return FAIL(r, ST_ERR_MEMORY, "out of memory for %u face corners", m->face_off[m->nfaces] + n);
    m->nfaces++;
    return 0;
}

/* ---- tags ------------------------------------------------------------------ */

/* The tags OpenSubdiv's regression harness applies (regression/common/
 * far_utils.h: GetSdcOptions and assignComponentTags); any other name is
 * read (its counts must hold) and ignored. */
enum tag_kind { TAG_OTHER, TAG_CREASE, TAG_CORNER, TAG_INTERP, TAG_HOLE, TAG_CREASEMETHOD, TAG_SMOOTHTRI };

typedef struct tag_head {
    enum tag_kind kind;
    int64_t nint, nfloat, nstring;
} tag_head;

static enum tag_kind tag_kind_of(const char *name, size_t len)
{
    static const struct { const char *name; enum tag_kind kind; } known[] = {
        {"crease", TAG_CREASE}, {"corner", TAG_CORNER}, {"interpolateboundary", TAG_INTERP},
        {"hole", TAG_HOLE}, {"creasemethod", TAG_CREASEMETHOD}, {"smoothtriangles", TAG_SMOOTHTRI},
    };
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        if (token_is(name, len, known[i].name)) return known[i].kind;
    return TAG_OTHER;
}

/* "nint/nfloat/nstring", each a small non-negative count. */
static int parse_tag_counts(obj_reader *r, const char *tok, size_t len, tag_head *h)
{
    int64_t v[3];
    size_t a = 0;
    for (int k = 0; k < 3; k++) {
        size_t b = a;
        while (b < len && tok[b] != '/') b++;
        if ((k < 2) != (b < len) || st_mesh_parse_int(tok + a, b - a, &v[k]) ||
            v[k] < 0 || v[k] > ST_MESH_MAX_DEGREE) {
            char q[48];
            return FAIL(r, ST_ERR_PARSE, "bad tag counts '%s' (expected nint/nfloat/nstring)",
                        st_text_quote(q, sizeof q, tok, len));
        }
        a = b + 1;
    }
    h->nint = v[0];
    h->nfloat = v[1];
    h->nstring = v[2];
    return 0;
}

/* Checks the counts of a known tag against what its kind needs.  A crease
 * tag's integers are vertex pairs, one edge per pair, as OpenSubdiv reads
 * them (`t crease 4/1/0 0 1 1 3 0.7` is the edges 0-1 and 1-3), with one
 * sharpness for all edges or one per edge. */
static int check_tag_shape(obj_reader *r, const tag_head *h)
{
    if (h->kind == TAG_CREASE && h->nint % 2)
        return FAIL(r, ST_ERR_PARSE, "crease tag has %lld integers: they are vertex pairs, one edge per "
                    "pair (OpenSubdiv's convention), so their count must be even", (long long)h->nint);
    if (h->kind == TAG_CREASE && (h->nint < 2 || (h->nfloat != 1 && h->nfloat != h->nint / 2)))
        return FAIL(r, ST_ERR_PARSE, "bad tag: crease needs 1+ vertex pairs and 1 sharpness or one per "
                    "pair (%lld integers, %lld floats)", (long long)h->nint, (long long)h->nfloat);
    if (h->kind == TAG_CORNER && (h->nint < 1 || (h->nfloat != 1 && h->nfloat != h->nint)))
        return FAIL(r, ST_ERR_PARSE, "bad tag: corner needs 1+ vertices and 1 sharpness or one per vertex");
    if (h->kind == TAG_INTERP && (h->nint != 1 || h->nfloat != 0))
        return FAIL(r, ST_ERR_PARSE, "bad tag: interpolateboundary needs exactly one integer");
    if ((h->kind == TAG_CREASEMETHOD || h->kind == TAG_SMOOTHTRI) && h->nstring != 1)
        return FAIL(r, ST_ERR_PARSE, "bad tag: %s needs exactly one string",
                    h->kind == TAG_CREASEMETHOD ? "creasemethod" : "smoothtriangles");
    if (h->kind == TAG_HOLE && (h->nint < 1 || h->nfloat != 0))
        return FAIL(r, ST_ERR_PARSE, "bad tag: hole needs 1+ face indices and no floats");
    return 0;
}

/* Reads the integers of a tag into r->b.tmp, range-checked for its kind. */
static int read_tag_ints(obj_reader *r, const tag_head *h)
{
    int rc = ensure_tmp(r, (size_t)h->nint);
    if (rc) return rc;
    for (int64_t i = 0; i < h->nint; i++) {
        const char *tok;
        size_t len;
        int64_t v;
        char q[48];
        if (!next_token(r, &tok, &len))
            return FAIL(r, ST_ERR_PARSE, "tag announces %lld integers but has %lld",
                        (long long)h->nint, (long long)i);
        if (h->kind == TAG_OTHER) continue;
        if (st_mesh_parse_int(tok, len, &v))
            return FAIL(r, ST_ERR_PARSE, "bad tag integer '%s'", st_text_quote(q, sizeof q, tok, len));
        if (h->kind == TAG_INTERP) {
            if (v < 0 || v > 2)
                return FAIL(r, ST_ERR_RANGE, "interpolateboundary %lld is not 0, 1 or 2", (long long)v);
        } else if (h->kind == TAG_HOLE) {
            if (v < 0 || v >= (int64_t)r->nf_total)
                return FAIL(r, ST_ERR_RANGE, "hole tag references face %lld but the file has %u faces "
                            "(tag indices start at 0)", (long long)v, r->nf_total);
        } else if (v < 0 || v >= (int64_t)r->nv_total) {
            return FAIL(r, ST_ERR_RANGE, "tag references vertex %lld but the file has %u vertices "
                        "(tag indices start at 0)", (long long)v, r->nv_total);
        }
        if (h->kind == TAG_CREASE && i % 2 && r->b.tmp[i - 1] == (uint32_t)v)
            return FAIL(r, ST_ERR_TOPOLOGY, "crease tag pairs vertex %lld with itself (pair %lld)",
                        (long long)v, (long long)(i / 2 + 1));
        r->b.tmp[i] = (uint32_t)v;
    }
    return 0;
}

static int read_sharpness(obj_reader *r, float *s)
{
    const char *tok;
    size_t len;
    double v;
    char q[48];
    if (!next_token(r, &tok, &len)) return FAIL(r, ST_ERR_PARSE, "tag has fewer floats than announced");
    if (st_mesh_parse_double(tok, len, &v) || !isfinite(v) || v < 0 || v > 3.0e38)
        return FAIL(r, ST_ERR_PARSE, "bad sharpness '%s' (a finite number >= 0)",
                    st_text_quote(q, sizeof q, tok, len));
    *s = (float)v;
    return 0;
}

static int push_crease(obj_reader *r, uint32_t a, uint32_t b, float s)
{
    st_mesh *m = &r->b.m;
    size_t cap_s = r->cap_crease, cap_v = r->cap_crease * 2;
    float *cs = st_mesh_grow(m->crease_s, &cap_s, (size_t)m->ncreases + 1, sizeof *cs);
    if (cs) m->crease_s = cs;
    uint32_t *cv = cs ? st_mesh_grow(m->crease_v, &cap_v, 2 * ((size_t)m->ncreases + 1), sizeof *cv) : NULL;
    if (!cs || !cv) return FAIL(r, ST_ERR_MEMORY, "out of memory for crease tags");
    m->crease_v = cv;
    r->cap_crease = cap_s < cap_v / 2 ? cap_s : cap_v / 2;
    cv[2 * m->ncreases] = a;
    cv[2 * m->ncreases + 1] = b;
    cs[m->ncreases++] = s;
    return 0;
}

static int push_corner(obj_reader *r, uint32_t v, float s)
{
    st_mesh *m = &r->b.m;
    size_t cap_s = r->cap_corner, cap_v = r->cap_corner;
    float *cs = st_mesh_grow(m->corner_s, &cap_s, (size_t)m->ncorners + 1, sizeof *cs);
    if (cs) m->corner_s = cs;
    uint32_t *cv = cs ? st_mesh_grow(m->corner_v, &cap_v, (size_t)m->ncorners + 1, sizeof *cv) : NULL;
    if (!cs || !cv) return FAIL(r, ST_ERR_MEMORY, "out of memory for corner tags");
    m->corner_v = cv;
    r->cap_corner = cap_s < cap_v ? cap_s : cap_v;
    cv[m->ncorners] = v;
    cs[m->ncorners++] = s;
    return 0;
}

/* The floats of a tag: sharpness values applied as they are read, one for
 * all items or one per item (crease pair or corner vertex).  Pair k takes
 * float k; OpenSubdiv's harness indexes them by the pair's first integer
 * (floatargs[2k]), which runs past the list, so its regression shapes use one
 * float per tag, and its oracle here (tests/oracles/mesh_io.h) reads k too. */
static int apply_tag_floats(obj_reader *r, const tag_head *h)
{
    int64_t items = h->kind == TAG_CREASE ? h->nint / 2 : h->nint;
    float s = 0;
    for (int64_t j = 0; j < items; j++) {
        int rc = 0;
        if (j == 0 || h->nfloat > 1) rc = read_sharpness(r, &s);
        if (!rc && h->kind == TAG_CREASE) rc = push_crease(r, r->b.tmp[2 * j], r->b.tmp[2 * j + 1], s);
        if (!rc && h->kind == TAG_CORNER) rc = push_corner(r, r->b.tmp[j], s);
        if (rc) return rc;
    }
    return 0;
}

/* The string of `creasemethod` (normal or chaikin) or `smoothtriangles`
 * (catmark or smooth); the last tag of a kind wins. */
static int check_tag_string(obj_reader *r, const tag_head *h, const char *tok, size_t len)
{
    char q[48];
    int creasing = h->kind == TAG_CREASEMETHOD;
    const char *ours = creasing ? "normal" : "catmark", *other = creasing ? "chaikin" : "smooth";
    int *field = creasing ? &r->b.m.crease_method : &r->b.m.tri_sub;
    if (token_is(tok, len, ours)) {
        *field = 0;
        return 0;
    }
    if (token_is(tok, len, other)) {
        *field = 1;
        return 0;
    }
    return FAIL(r, ST_ERR_PARSE, "%s '%s' is not '%s' or '%s'", creasing ? "creasemethod" : "smoothtriangles",
                st_text_quote(q, sizeof q, tok, len), ours, other);
}

static int parse_tag(obj_reader *r)
{
    const char *name, *tok;
    size_t nlen, len;
    tag_head h = {TAG_OTHER, 0, 0, 0};
    if (!next_token(r, &name, &nlen) || !next_token(r, &tok, &len))
        return FAIL(r, ST_ERR_PARSE, "tag needs a name and nint/nfloat/nstring counts");
    h.kind = tag_kind_of(name, nlen);
    int rc = parse_tag_counts(r, tok, len, &h);
    if (!rc) rc = check_tag_shape(r, &h);
    if (!rc) rc = read_tag_ints(r, &h);
    if (rc) return rc;
    if (h.kind == TAG_INTERP) r->b.m.boundary_interp = (int)r->b.tmp[0];
    if (h.kind == TAG_HOLE) {
        /* Flags for the faces of the whole file (a tag may name a face
         * defined further down). */
        if (!r->b.m.face_hole) r->b.m.face_hole = calloc(r->nf_total ? r->nf_total : 1, 1);
        if (!r->b.m.face_hole) return FAIL(r, ST_ERR_MEMORY, "out of memory for hole tags");
        for (int64_t j = 0; j < h.nint; j++) r->b.m.face_hole[r->b.tmp[j]] = 1;
    }
    if (h.kind == TAG_CREASE || h.kind == TAG_CORNER) {
        rc = apply_tag_floats(r, &h);
        if (rc) return rc;
    } else {
        for (int64_t j = 0; j < h.nfloat; j++)
            if (!next_token(r, &tok, &len)) return FAIL(r, ST_ERR_PARSE, "tag has fewer floats than announced");
    }
    for (int64_t j = 0; j < h.nstring; j++) {
        if (!next_token(r, &tok, &len)) return FAIL(r, ST_ERR_PARSE, "tag has fewer strings than announced");
        if (j == 0 && (h.kind == TAG_CREASEMETHOD || h.kind == TAG_SMOOTHTRI)) {
            rc = check_tag_string(r, &h, tok, len);
            if (rc) return rc;
        }
    }
    if (next_token(r, &tok, &len)) return FAIL(r, ST_ERR_PARSE, "tag has more values than announced");
    return 0;
}

/* ---- driver ---------------------------------------------------------------- */

static int grow_vertex(obj_reader *r, size_t *cap)
{
    double *p = st_mesh_grow(r->b.m.pos, cap, 3 * ((size_t)r->b.m.nverts + 1), sizeof *p);
    if (!p) return FAIL(r, ST_ERR_MEMORY, "out of memory for vertices");
    r->b.m.pos = p;
    return 0;
}

static int grow_face(obj_reader *r, size_t *cap, size_t *cap_loc)
{
    uint32_t *off = st_mesh_grow(r->b.m.face_off, cap, (size_t)r->b.m.nfaces + 2, sizeof *off);
    if (!off) return FAIL(r, ST_ERR_MEMORY, "out of memory for faces");
    r->b.m.face_off = off;
    if (!cap_loc) return 0;
    uint64_t *loc = st_mesh_grow(r->b.face_loc, cap_loc, (size_t)r->b.m.nfaces + 1, sizeof *loc);
    if (!loc) return FAIL(r, ST_ERR_MEMORY, "out of memory for faces");
    r->b.face_loc = loc;
    return 0;
}

static int parse_line(obj_reader *r, size_t *cap_pos, size_t *cap_off, size_t *cap_loc)
{
    const char *tok;
    size_t len;
    if (!next_token(r, &tok, &len)) return 0;
    if (token_is(tok, len, "v")) {
        if (r->b.m.nverts >= r->nv_total) return FAIL(r, ST_ERR_RANGE, "too many vertices");
        int rc = grow_vertex(r, cap_pos);
        return rc ? rc : parse_vertex(r);
    }
    if (token_is(tok, len, "f")) {
        int rc = grow_face(r, cap_off, cap_loc);
        return rc ? rc : parse_face(r);
    }
    if (token_is(tok, len, "t")) return parse_tag(r);
    if (token_is(tok, len, "vt")) return parse_texcoord(r);
    return 0;   /* vn, o, g, s, usemtl, mtllib, l, p, ...: not needed */
}

static int parse_lines(obj_reader *r, const char *data, size_t size, int want_loc)
{
    size_t cap_pos = 0, cap_off = 0, cap_loc = 0;
    int rc = grow_face(r, &cap_off, want_loc ? &cap_loc : NULL);
    if (rc) return rc;
    r->b.m.face_off[0] = 0;
    const char *p = data, *end = data + size;
    while (p < end && !rc) {
        const char *le = memchr(p, '\n', (size_t)(end - p));
        if (!le) le = end;
        r->line++;
        r->q = p;
        r->le = le;
        rc = parse_line(r, &cap_pos, &cap_off, want_loc ? &cap_loc : NULL);
        p = le < end ? le + 1 : end;
    }
    return rc;
}

int st_mesh_parse_obj_src(const char *name, const char *data, size_t size,
                          st_mesh *out, st_mesh_src *src, st_error *err)
{
    obj_reader r = { .name = name, .err = err };
    st_mesh_init(&r.b.m);
    if (size == 0) return st_fail(err, ST_ERR_PARSE, "%s: empty file", name);
    int rc = count_records(&r, data, size);
    if (!rc && r.nf_total == 0) rc = st_fail(err, ST_ERR_TOPOLOGY, "%s: no faces (no 'f' lines)", name);
    if (!rc) rc = parse_lines(&r, data, size, src != NULL);
    if (!rc && (r.faces_without_uv || !r.b.m.face_uv)) {
        /* No face, or not every face, names texture coordinates: no channel. */
        free(r.b.m.uv);
        free(r.b.m.face_uv);
        r.b.m.uv = NULL;
        r.b.m.face_uv = NULL;
        r.b.m.nuvs = 0;
    }
    return st_mesh_build_end(&r.b, rc, out, src, 0, 1);
}
