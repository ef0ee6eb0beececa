/* ASCII OFF reader (Geomview Object File Format).
 *
 *   [ST][C][N]OFF            header keyword, optional
 *   nv nf [ne]               counts (ne, the edge count, is ignored)
 *   x y z [extra...]         nv vertex lines; normals/colours/uv ignored
 *   n i0 ... i(n-1) [rgb]    nf face lines, 0-based indices; colours ignored
 *
 * The file is read line by line ('#' starts a comment anywhere, blank lines
 * are skipped), one record per line as every writer we know produces: that
 * is what lets optional per-vertex and per-face extras be skipped without
 * knowing their count.  The counts are checked against the limits and the
 * bytes left in the file before anything is allocated, and the file must
 * hold exactly the announced records: fewer or more is an error.
 * 4OFF/nOFF (other dimensions) and binary OFF are refused.
 */
#include "core/io/mesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct off_reader {
    const char *name;
    st_error *err;
    const char *p, *end;    /* unread part of the file */
    uint64_t line;          /* line of the current record */
    const char *q, *le;     /* token cursor and end of the current line */
    st_mesh_build b;        /* result under construction; face_loc: line of each face */
} off_reader;

#define FAIL(r, code, ...) st_mesh_fail_at((r)->err, (code), (r)->name, 0, (r)->line, __VA_ARGS__)


static int next_token(off_reader *r, const char **tok, size_t *len)
{
    return st_text_token(&r->q, r->le, tok, len);
}

/* Moves to the next line holding a token; 0 at the end of the file. */
static int next_record(off_reader *r)
{
    while (r->p < r->end) {
        const char *le = memchr(r->p, '\n', (size_t)(r->end - r->p));
        if (!le) le = r->end;
        r->line++;
        r->q = r->p;
        r->le = le;
        r->p = le < r->end ? le + 1 : r->end;
        const char *save = r->q, *tok;
        size_t len;
        if (next_token(r, &tok, &len)) {
            r->q = save;
            return 1;
        }
    }
    return 0;
}

static int read_count(off_reader *r, const char *what, int64_t *v)
{
    const char *tok;
    size_t len;
    char q[48];
    if (!next_token(r, &tok, &len)) return FAIL(r, ST_ERR_PARSE, "missing %s count", what);
    if (st_mesh_parse_int(tok, len, v) || *v < 0)
        return FAIL(r, ST_ERR_PARSE, "bad %s count '%s'", what, st_text_quote(q, sizeof q, tok, len));
    return 0;
}

/* The keyword line, if any.  Leaves the cursor on the counts. */
static int parse_keyword(off_reader *r)
{
    const char *tok;
    size_t len;
    char q[48];
    if (!next_record(r)) return st_fail(r->err, ST_ERR_PARSE, "%s: empty file", r->name);
    const char *save = r->q;
    next_token(r, &tok, &len);
    if (len >= 3 && memcmp(tok + len - 3, "OFF", 3) == 0) {
        for (size_t i = 0; i + 3 < len; i++)
            if (!strchr("STCN", tok[i]))
                return FAIL(r, ST_ERR_PARSE, "unsupported OFF variant '%s' (only 3D ASCII OFF)",
                            st_text_quote(q, sizeof q, tok, len));
        save = r->q;
        int more = next_token(r, &tok, &len);
        if (more && len == 6 && memcmp(tok, "BINARY", 6) == 0)
            return FAIL(r, ST_ERR_PARSE, "binary OFF is not supported");
        r->q = save;
        if (!more && !next_record(r))
            return FAIL(r, ST_ERR_PARSE, "file ends before the vertex and face counts");
        return 0;
    }
    r->q = save;
    if (tok[0] == '-' || tok[0] == '+' || (tok[0] >= '0' && tok[0] <= '9')) return 0;
    return FAIL(r, ST_ERR_PARSE, "not an OFF file (starts with '%s')", st_text_quote(q, sizeof q, tok, len));
}

/* Counts line: checked against the limits and the bytes that follow (a
 * vertex line takes at least 6 bytes, "0 0 0\n", a face at least 8). */
static int parse_counts(off_reader *r)
{
    int64_t nv, nf, ne;
    int rc = read_count(r, "vertex", &nv);
    if (!rc) rc = read_count(r, "face", &nf);
    if (rc) return rc;
    const char *tok;
    size_t len;
    if (next_token(r, &tok, &len) && (st_mesh_parse_int(tok, len, &ne) || ne < 0))
        return FAIL(r, ST_ERR_PARSE, "bad edge count");
    if (next_token(r, &tok, &len)) return FAIL(r, ST_ERR_PARSE, "extra values after the counts");
    if (nv > ST_MESH_MAX_VERTS || nf > ST_MESH_MAX_FACES)
        return FAIL(r, ST_ERR_RANGE, "%lld vertices and %lld faces exceed the limits (%u, %u)",
                    (long long)nv, (long long)nf, ST_MESH_MAX_VERTS, ST_MESH_MAX_FACES);
    if (nf == 0) return FAIL(r, ST_ERR_TOPOLOGY, "no faces");
    uint64_t need = 6 * (uint64_t)nv + 8 * (uint64_t)nf - 1;
    if (need > (uint64_t)(r->end - r->p))
        return FAIL(r, ST_ERR_RANGE, "header announces %lld vertices and %lld faces but only "
                    "%zu bytes follow", (long long)nv, (long long)nf, (size_t)(r->end - r->p));
    r->b.m.pos = malloc(3 * (size_t)nv * sizeof *r->b.m.pos + 1);
    r->b.m.face_off = malloc(((size_t)nf + 1) * sizeof *r->b.m.face_off);
    r->b.face_loc = malloc((size_t)nf * sizeof *r->b.face_loc);
    if (!r->b.m.pos || !r->b.m.face_off || !r->b.face_loc)
        return FAIL(r, ST_ERR_MEMORY, "out of memory for %lld vertices", (long long)nv);
    r->b.m.nverts = (uint32_t)nv;
    r->b.m.nfaces = (uint32_t)nf;
    r->b.m.face_off[0] = 0;
    return 0;
}

static int parse_vertices(off_reader *r)
{
    for (uint32_t v = 0; v < r->b.m.nverts; v++) {
        if (!next_record(r))
            return FAIL(r, ST_ERR_PARSE, "file ends after %u of %u vertices", v, r->b.m.nverts);
        for (int k = 0; k < 3; k++) {
            const char *tok;
            size_t len;
            char q[48];
            double x;
            if (!next_token(r, &tok, &len))
                return FAIL(r, ST_ERR_PARSE, "vertex %u has %d coordinates, 3 needed", v, k);
            if (st_mesh_parse_double(tok, len, &x))
                return FAIL(r, ST_ERR_PARSE, "bad vertex coordinate '%s'", st_text_quote(q, sizeof q, tok, len));
            if (!isfinite(x))
                return FAIL(r, ST_ERR_GEOMETRY, "non-finite vertex coordinate '%s' (nan, inf or overflow)",
                            st_text_quote(q, sizeof q, tok, len));
            r->b.m.pos[3 * (size_t)v + (size_t)k] = x;
        }
    }
    return 0;
}

static int read_face_size(off_reader *r, uint32_t *n)
{
    const char *tok = "";
    size_t len = 0;
    int64_t v;
    char q[48];
    next_token(r, &tok, &len);
    if (st_mesh_parse_int(tok, len, &v))
        return FAIL(r, ST_ERR_PARSE, "bad face size '%s'", st_text_quote(q, sizeof q, tok, len));
    if (v < 3) return FAIL(r, ST_ERR_TOPOLOGY, "face has %lld vertices; a face needs at least 3", (long long)v);
    if (v > ST_MESH_MAX_DEGREE)
        return FAIL(r, ST_ERR_RANGE, "face has %lld vertices (limit %u)", (long long)v, ST_MESH_MAX_DEGREE);
    if (st_mesh_build_reserve(&r->b, (size_t)v)) return FAIL(r, ST_ERR_MEMORY, "out of memory");
    *n = (uint32_t)v;
    return 0;
}

static int parse_face(off_reader *r, uint32_t f)
{
    uint32_t n = 0;
    int rc = read_face_size(r, &n);
    if (rc) return rc;
    for (uint32_t k = 0; k < n; k++) {
        const char *tok;
        size_t len;
        int64_t v;
        char q[48];
        if (!next_token(r, &tok, &len))
            return FAIL(r, ST_ERR_PARSE, "face announces %u vertices but lists %u", n, k);
        if (st_mesh_parse_int(tok, len, &v))
            return FAIL(r, ST_ERR_PARSE, "bad vertex index '%s'", st_text_quote(q, sizeof q, tok, len));
        if (v < 0 || v >= (int64_t)r->b.m.nverts)
            return FAIL(r, ST_ERR_RANGE, "face references vertex %lld but the file has %u vertices "
                        "(OFF indices start at 0)", (long long)v, r->b.m.nverts);
        r->b.tmp[k] = (uint32_t)v;
    }
    uint32_t dup = st_mesh_face_repeat(r->b.tmp, n, r->b.scratch);
    if (dup != UINT32_MAX) return FAIL(r, ST_ERR_TOPOLOGY, "face uses vertex %u more than once", dup);
    int frc = st_mesh_build_face(&r->b, f, n, r->line);
    if (frc == ST_ERR_RANGE) return FAIL(r, ST_ERR_RANGE, "too many face corners");
    if (frc) return FAIL(r, ST_ERR_MEMORY, "out of memory for face corners");
    return 0;
}

static int parse_faces(off_reader *r)
{
    for (uint32_t f = 0; f < r->b.m.nfaces; f++) {
        if (!next_record(r))
            return FAIL(r, ST_ERR_PARSE, "file ends after %u of %u faces", f, r->b.m.nfaces);
        int rc = parse_face(r, f);
        if (rc) return rc;
    }
    if (next_record(r))
        return FAIL(r, ST_ERR_PARSE, "more data than the header announced (%u vertices, %u faces)",
                    r->b.m.nverts, r->b.m.nfaces);
    return 0;
}

int st_mesh_parse_off_src(const char *name, const char *data, size_t size,
                          st_mesh *out, st_mesh_src *src, st_error *err)
{
    off_reader r = { .name = name, .err = err, .p = data, .end = data + size };
    st_mesh_init(&r.b.m);
    int rc = size == 0 ? st_fail(err, ST_ERR_PARSE, "%s: empty file", name) : parse_keyword(&r);
    if (!rc) rc = parse_counts(&r);
    if (!rc) rc = parse_vertices(&r);
    if (!rc) rc = parse_faces(&r);
    return st_mesh_build_end(&r.b, rc, out, src, 0, 0);
}
