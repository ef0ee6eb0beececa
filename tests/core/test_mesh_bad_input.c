/* Bad input for the mesh loaders: every refusal names the file, the line (or
 * byte offset) and the problem, returns non-zero, and leaves the caller's
 * mesh exactly as it was; every repair is announced by a note.  Also: every
 * truncated prefix and every single-bit flip of a small binary PLY (loads
 * cleanly or fails cleanly, never crashes). */
#include "core/io/mesh.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- helpers ---------------------------------------------------------------- */

static const char *tmp_path(const char *name)
{
    static char buf[1024];
    snprintf(buf, sizeof buf, "%s/%s", STRATA_TMP, name);
    return buf;
}

/* A deep copy, to prove a failed load changed nothing. */
typedef struct snapshot {
    st_mesh m;              /* the arrays' addresses as they were */
    double *pos;
    uint32_t *off, *idx;
} snapshot;

static void take(snapshot *s, const st_mesh *m)
{
    s->m = *m;
    s->pos = malloc(3 * m->nverts * sizeof *s->pos);
    s->off = malloc((m->nfaces + 1) * sizeof *s->off);
    s->idx = malloc(m->face_off[m->nfaces] * sizeof *s->idx);
    memcpy(s->pos, m->pos, 3 * m->nverts * sizeof *s->pos);
    memcpy(s->off, m->face_off, (m->nfaces + 1) * sizeof *s->off);
    memcpy(s->idx, m->face_idx, m->face_off[m->nfaces] * sizeof *s->idx);
}

static int unchanged(const snapshot *s, const st_mesh *m)
{
    return memcmp(&s->m, m, sizeof *m) == 0 &&
           memcmp(s->pos, m->pos, 3 * m->nverts * sizeof *s->pos) == 0 &&
           memcmp(s->off, m->face_off, (m->nfaces + 1) * sizeof *s->off) == 0 &&
           memcmp(s->idx, m->face_idx, m->face_off[m->nfaces] * sizeof *s->idx) == 0;
}

static void drop(snapshot *s)
{
    free(s->pos);
    free(s->off);
    free(s->idx);
}

/* The mesh every refused load is given as *out: a tetrahedron. */
static void load_good(st_mesh *m)
{
    static const char tet[] = "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\n"
                              "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
    const char *path = tmp_path("bad_good_tet.obj");
    st_error e;
    tl_write_file(path, tet, sizeof tet - 1);
    st_mesh_init(m);
    CHECK(st_mesh_load(path, m, &e) == 0 && m->nverts == 4 && m->nfaces == 4);
}

/* Writes data to file name, loads it over a good mesh, expects refusal with
 * the name, loc (":4:" or "byte 12") and what in the message. */
static void refused_bytes_flags(const char *name, const void *data, size_t size, unsigned flags,
                                const char *loc, const char *what)
{
    st_mesh m;
    snapshot s;
    st_error e = {0};
    load_good(&m);
    take(&s, &m);
    const char *path = tmp_path(name);
    if (data) tl_write_file(path, data, size);
    int rc = st_mesh_load_flags(path, &m, flags, NULL, &e);
    CHECKF(rc != 0, "%s loaded but should be refused", name);
    CHECKF(strstr(e.msg, name) != NULL, "%s: message lacks the file name: %s", name, e.msg);
    CHECKF(!loc || strstr(e.msg, loc) != NULL, "%s: message lacks '%s': %s", name, loc, e.msg);
    CHECKF(strstr(e.msg, what) != NULL, "%s: message lacks '%s': %s", name, what, e.msg);
    CHECKF(unchanged(&s, &m), "%s: the previous mesh was changed", name);
    drop(&s);
    st_mesh_free(&m);
}

static void refused_bytes(const char *name, const void *data, size_t size, const char *loc, const char *what)
{
    refused_bytes_flags(name, data, size, 0, loc, what);
}

static void refused(const char *name, const char *text, const char *loc, const char *what)
{
    refused_bytes(name, text, text ? strlen(text) : 0, loc, what);
}

/* Loads text that needs a repair; expects success and a note with what. */
static void repaired(const char *name, const char *text, const char *what, st_mesh *m)
{
    st_error e = {0};
    st_notes n = {0};
    const char *path = tmp_path(name);
    tl_write_file(path, text, strlen(text));
    st_mesh_init(m);
    int rc = st_mesh_load_notes(path, m, &n, &e);
    CHECKF(rc == 0, "%s: %s", name, e.msg);
    int found = 0;
    for (uint32_t i = 0; i < n.count; i++) {
        found |= strstr(n.lines[i], what) != NULL;
        CHECKF(strstr(n.lines[i], name) && strstr(n.lines[i], ": repaired: "), "%s: note '%s'", name, n.lines[i]);
    }
    CHECKF(found, "%s: no note says '%s' (%u notes)", name, what, n.count);
    CHECKF(rc || st_mesh_check(name, m, &e) == 0, "%s: repaired mesh fails the check: %s", name, e.msg);
    st_notes_free(&n);
}

/* ---- binary PLY building -------------------------------------------------------- */

typedef struct buf {
    unsigned char b[4096];
    size_t n;
} buf;

static void put(buf *b, const void *p, size_t n)
{
    memcpy(b->b + b->n, p, n);
    b->n += n;
}
static void put_str(buf *b, const char *s) { put(b, s, strlen(s)); }
static void put_f32(buf *b, float f) { put(b, &f, 4); }        /* tests run on little-endian hosts */
static void put_i32(buf *b, int32_t v) { put(b, &v, 4); }
static void put_u8(buf *b, uint8_t v) { put(b, &v, 1); }

static const float tet_xyz[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
static const int tet_faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};

/* A tetrahedron as binary little-endian PLY: float xyz plus an ignored
 * uchar, uchar/int face lists, and (unless no_extra) an unknown element
 * with a list. */
static void tet_ply_x(buf *b, int nv_claim, int nf_claim, int nv_data, int nf_data, int no_extra)
{
    char hdr[512];
    snprintf(hdr, sizeof hdr, "ply\nformat binary_little_endian 1.0\ncomment tetrahedron\n"
             "element vertex %d\nproperty float x\nproperty float y\nproperty float z\nproperty uchar flags\n"
             "element face %d\nproperty list uchar int vertex_indices\n%s"
             "end_header\n", nv_claim, nf_claim, no_extra ? "" : "element extra 1\nproperty list uchar short junk\n");
    b->n = 0;
    put_str(b, hdr);
    for (int v = 0; v < nv_data; v++) {
        for (int k = 0; k < 3; k++) put_f32(b, tet_xyz[v % 4][k]);
        put_u8(b, 7);
    }
    for (int f = 0; f < nf_data; f++) {
        put_u8(b, 3);
        for (int k = 0; k < 3; k++) put_i32(b, tet_faces[f % 4][k]);
    }
    if (no_extra) return;
    put_u8(b, 2);
    put_u8(b, 1); put_u8(b, 0); put_u8(b, 2); put_u8(b, 0);
}

static void tet_ply(buf *b, int nv_claim, int nf_claim, int nv_data, int nf_data)
{
    tet_ply_x(b, nv_claim, nf_claim, nv_data, nf_data, 0);
}

static size_t header_size(const buf *b)
{
    const char *end = strstr((const char *)b->b, "end_header\n");
    return (size_t)(end - (const char *)b->b) + strlen("end_header\n");
}

/* Parses exactly n bytes (a fresh allocation, so ASan sees any overread),
 * repairs on success, and checks the promise of the repair. */
static int parse_exact(const char *fmt, const unsigned char *data, size_t n, st_mesh *m, st_error *e)
{
    char *copy = malloc(n ? n : 1);
    memcpy(copy, data, n);
    int rc = fmt[0] == 'p' ? st_mesh_parse_ply("t.ply", copy, n, m, e)
           : fmt[0] == 'o' && fmt[1] == 'b' ? st_mesh_parse_obj("t.obj", copy, n, m, e)
           : st_mesh_parse_off("t.off", copy, n, m, e);
    free(copy);
    if (rc) return rc;
    rc = st_mesh_repair("t", m, NULL, e);
    if (!rc) CHECKF(st_mesh_check("t", m, e) == 0, "repaired mesh fails the check: %s", e->msg);
    return rc;
}

/* ---- cases ------------------------------------------------------------------------ */

static const char tri3[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";     /* three vertices, lines 1-3 */

static void test_missing_and_empty(void)
{
    refused("bad_missing_file.obj", NULL, NULL, "cannot open");
    refused("bad_empty.obj", "", NULL, "empty file");
    refused("bad_empty.off", "", NULL, "empty file");
    refused("bad_empty.ply", "", NULL, "empty file");
    refused("bad_only_comments.obj", "# nothing\n\n", NULL, "no faces");
    refused("bad_unknown_format.stl", "solid x\n", NULL, "unknown mesh format");
}

static void test_index_range(void)
{
    char t[256];
    snprintf(t, sizeof t, "%sf 1 2 9\n", tri3);
    refused("bad_index_range.obj", t, ":4:", "face references vertex 9 but the file has 3 vertices");
    snprintf(t, sizeof t, "%sf 1 0 2\n", tri3);
    refused("bad_index_zero.obj", t, ":4:", "vertex index 0");
    snprintf(t, sizeof t, "%sf -1 -2 -4\n", tri3);
    refused("bad_index_relative.obj", t, ":4:", "relative index -4 reaches before the first vertex");
    snprintf(t, sizeof t, "%sf 1 2 3x\n", tri3);
    refused("bad_index_token.obj", t, ":4:", "bad face corner '3x'");
    refused("bad_index_range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", ":6:",
            "face references vertex 3 but the file has 3 vertices");
    refused("bad_index_negative.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", ":6:", "vertex -1");
    refused("bad_index_range.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n", ":13:", "references vertex 5");
}

static void test_degenerate_faces(void)
{
    char t[256];
    snprintf(t, sizeof t, "%s\nf 1 2\n", tri3);
    refused("bad_face_two.obj", t, ":5:", "face has 2 vertices");
    snprintf(t, sizeof t, "%sf 1 2 1\n", tri3);
    refused("bad_face_repeat.obj", t, ":4:", "face uses vertex 1 more than once");
    refused("bad_face_two.off", "OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n# comment\n2 0 1\n", ":7:", "face has 2 vertices");
    refused("bad_face_repeat.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", ":5:", "more than once");
    buf b;
    tet_ply(&b, 4, 4, 4, 4);
    size_t f0 = header_size(&b) + 4 * 13;          /* first face record */
    memcpy(b.b + f0 + 1 + 4, b.b + f0 + 1, 4);     /* face 0 = 0 0 2 */
    char loc[32];
    snprintf(loc, sizeof loc, "byte %zu", f0);
    refused_bytes("bad_face_repeat.ply", b.b, b.n, loc, "uses vertex 0 more than once");
}

static void test_non_finite(void)
{
    refused("bad_nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", ":2:", "non-finite");
    refused("bad_inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n", ":3:", "non-finite");
    refused("bad_overflow.obj", "v 1e999 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1:", "non-finite");
    refused("bad_nan.off", "OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n", ":4:", "non-finite");
    buf b;
    tet_ply(&b, 4, 4, 4, 4);
    size_t at = header_size(&b) + 2 * 13 + 4;      /* vertex 2, y */
    float nan = NAN;
    memcpy(b.b + at, &nan, 4);
    char loc[32];
    snprintf(loc, sizeof loc, "byte %zu", at);
    refused_bytes("bad_nan.ply", b.b, b.n, loc, "vertex 2 has a non-finite coordinate");
}

static void test_truncated_and_lying_counts(void)
{
    buf b;
    tet_ply(&b, 4, 4, 4, 4);
    char loc[32];
    snprintf(loc, sizeof loc, "byte %zu", header_size(&b));
    refused_bytes("bad_truncated.ply", b.b, header_size(&b) + 10, loc, "header announces 4 'vertex' records");
    snprintf(loc, sizeof loc, "byte %zu", b.n - 4);    /* cut inside the last list */
    refused_bytes("bad_truncated_tail.ply", b.b, b.n - 2, loc, "file ends inside extra record 1 of 1");
    tet_ply_x(&b, 4, 5, 4, 4, 1);   /* header: 5 faces, data: 4 */
    snprintf(loc, sizeof loc, "byte %zu", b.n);
    refused_bytes("bad_lies_more.ply", b.b, b.n, loc, "file ends inside face record 5 of 5");
    /* A lying vertex count shifts every later record: the first impossible
     * value is what gets reported (here face 3's list length). */
    tet_ply(&b, 5, 4, 4, 4);
    refused_bytes("bad_lies_more_verts.ply", b.b, b.n, "byte", "face 3 has 2 vertices");
    tet_ply(&b, 4, 4, 4, 5);    /* header: 4 faces, data: 5 */
    /* the extra element reads 7 bytes of face 5 as its list; 6 + 5 remain */
    snprintf(loc, sizeof loc, "byte %zu", b.n - 11);
    refused_bytes("bad_lies_fewer.ply", b.b, b.n, loc, "11 bytes of data after the last element");
    refused("bad_lies_more.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ":2:",
            "header announces 3 vertices and 2 faces but only 26 bytes follow");
    refused("bad_lies_more_long.off", "OFF\n3 2 0\n0.000000 0.000000 0.000000\n1.000000 0.000000 0.000000\n"
            "0.000000 1.000000 0.000000\n3 0 1 2\n", ":6:", "file ends after 1 of 2 faces");
    refused("bad_lies_fewer.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", ":7:",
            "more data than the header announced");
    refused("bad_lies_more_verts.off", "OFF\n4 1 0\n0.000000 0.000000 0.000000\n1.000000 0.000000 0.000000\n"
            "0.000000 1.000000 0.000000\n3 0 1 2\n", ":6:", "file ends after 0 of 1 faces");
    const char *ply_head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    char t[512];
    snprintf(t, sizeof t, "%s0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", ply_head);
    refused("bad_lies_fewer.ply", t, ":14:", "after the last element");
    snprintf(t, sizeof t, "%s0 0 0\n1 0 0\n0 1 0\n", ply_head);
    refused("bad_lies_more_ascii.ply", t, NULL, "announces more");
}

static void test_absurd_counts(void)
{
    refused("bad_absurd.off", "OFF\n2000000000 1 0\n0 0 0\n", ":2:", "exceed the limits");
    refused("bad_absurd_size.off", "OFF\n100000000 100000000 0\n0 0 0\n", ":2:", "only 6 bytes follow");
    refused("bad_absurd.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
            "property float x\nproperty float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n", NULL, "exceed the limits");
    refused("bad_absurd_size.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 100000000\n"
            "property float x\nproperty float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n0123456789", NULL, "announces 100000000 'vertex' records");
    refused("bad_absurd_other.ply", "ply\nformat binary_big_endian 1.0\nelement junk 9000000000000000000\n"
            "property double w\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n", NULL, "'junk' records");
    refused("bad_absurd_list.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0\n1 0 0\n0 1 0\n99999999 0 1 2\n", ":13:", "face 0 has 99999999 vertices");
    char t[256];
    snprintf(t, sizeof t, "%st crease 99999999/1/0 0 1 2\nf 1 2 3\n", tri3);
    refused("bad_absurd_tag.obj", t, ":4:", "bad tag counts");
}

static void test_header_syntax(void)
{
    refused("bad_magic.ply", "PLY\nformat ascii 1.0\n", ":1:", "not a PLY file");
    refused("bad_format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", ":2:", "unknown PLY format");
    refused("bad_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", ":4:",
            "unknown property type 'quad'");
    refused("bad_list_type.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\n"
            "end_header\n", ":4:", "not an integer type");
    refused("bad_no_end.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", NULL, "no end_header");
    refused("bad_no_xyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
            NULL, "no vertex element with x, y and z");
    refused("bad_keyword.off", "4OFF\n3 1 0\n", ":1:", "unsupported OFF variant");
    refused("bad_binary.off", "OFF BINARY\n", ":1:", "binary OFF");
    refused("bad_coordinate.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", ":2:", "bad vertex coordinate 'zero'");
    refused("bad_short_vertex.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", ":2:", "vertex has 2 coordinates");
}

static void test_tags(void)
{
    char t[256];
    snprintf(t, sizeof t, "%sf 1 2 3\nt crease 2/1/0 0 7 1.0\n", tri3);
    refused("bad_tag_range.obj", t, ":5:", "tag references vertex 7");
    snprintf(t, sizeof t, "%sf 1 2 3\nt corner 1/1/0 0\n", tri3);
    refused("bad_tag_short.obj", t, ":5:", "fewer floats");
    snprintf(t, sizeof t, "%sf 1 2 3\nt crease 2/1/0 0 1 -2\n", tri3);
    refused("bad_tag_sharpness.obj", t, ":5:", "bad sharpness");
    snprintf(t, sizeof t, "%sf 1 2 3\nt interpolateboundary 1/0/0 7\n", tri3);
    refused("bad_tag_interp.obj", t, ":5:", "interpolateboundary 7");
    snprintf(t, sizeof t, "%sf 1 2 3\nt crease 2/1/0 0 1 1.0 5\n", tri3);
    refused("bad_tag_extra.obj", t, ":5:", "more values than announced");
    /* Crease integers are vertex pairs (OpenSubdiv): an odd count, a pair
     * of one vertex, or a float count that is neither 1 nor one per pair. */
    snprintf(t, sizeof t, "%sf 1 2 3\nt crease 3/1/0 0 1 2 1.0\n", tri3);
    refused("bad_tag_odd.obj", t, ":5:", "crease tag has 3 integers: they are vertex pairs");
    snprintf(t, sizeof t, "%sf 1 2 3\nt crease 4/1/0 0 1 2 2 1.0\n", tri3);
    refused("bad_tag_self.obj", t, ":5:", "pairs vertex 2 with itself (pair 2)");
    snprintf(t, sizeof t, "%sf 1 2 3\nt crease 4/3/0 0 1 1 2 1 2 3\n", tri3);
    refused("bad_tag_floats.obj", t, ":5:", "1 sharpness or one per pair (4 integers, 3 floats)");
    /* Hole tags name faces that exist, and nothing else. */
    snprintf(t, sizeof t, "%sf 1 2 3\nt hole 1/0/0 1\n", tri3);
    refused("bad_tag_hole_range.obj", t, ":5:", "hole tag references face 1 but the file has 1 faces");
    snprintf(t, sizeof t, "%sf 1 2 3\nt hole 1/0/0 -1\n", tri3);
    refused("bad_tag_hole_negative.obj", t, ":5:", "hole tag references face -1");
    snprintf(t, sizeof t, "%sf 1 2 3\nt hole 0/0/0\n", tri3);
    refused("bad_tag_hole_empty.obj", t, ":5:", "hole needs 1+ face indices and no floats");
    snprintf(t, sizeof t, "%sf 1 2 3\nt hole 1/1/0 0 0.5\n", tri3);
    refused("bad_tag_hole_float.obj", t, ":5:", "hole needs 1+ face indices and no floats");
    /* What Strata does not model is refused, not ignored. */
    snprintf(t, sizeof t, "%sf 1 2 3\nt smoothtriangles 0/0/1 loop\n", tri3);
    refused("bad_tag_smoothtri.obj", t, ":5:", "smoothtriangles 'loop' is not 'catmark' or 'smooth'");
    snprintf(t, sizeof t, "%sf 1 2 3\nt creasemethod 0/0/1 sharp\n", tri3);
    refused("bad_tag_method.obj", t, ":5:", "creasemethod 'sharp' is not 'normal' or 'chaikin'");
    snprintf(t, sizeof t, "%sf 1 2 3\nt creasemethod 1/0/0 1\n", tri3);
    refused("bad_tag_method_form.obj", t, ":5:", "creasemethod needs exactly one string");
}

/* Three triangles on the edge 1-2 (a fan of fins).
 *        3
 *   4 -- 1 -- 5      every face contains edge 1-2
 *        2                                              */
static const char fins[] = "v 0 0 0\nv 0 0 1\nv 1 0 0\nv -1 0 0\nv 0 1 0\n"
                           "f 1 2 3\nf 2 1 4\nf 1 2 5\n";

/* A Moebius strip of three quads (a0 a1 a2 top, b0 b1 b2 bottom), the
 * third one glued back to the first with a half twist. */
static const char moebius[] = "v 0 0 1\nv 1 0 1\nv 2 0 1\nv 0 0 0\nv 1 0 0\nv 2 0 0\n"
                              "f 1 2 5 4\nf 2 3 6 5\nf 3 4 1 6\n";

/* An edge with 3+ faces is split on reading (core/io/mesh_repair.c: the
 * third fin gets its own copies of 1 and 2, the face count is kept) and
 * refused, as before the split existed, with ST_MESH_STRICT (--strict). */
static void test_non_manifold_edge(void)
{
    static const char fins_off[] = "OFF\n5 3 0\n0 0 0\n0 0 1\n1 0 0\n-1 0 0\n0 1 0\n3 0 1 2\n3 1 0 3\n3 0 1 4\n";
    st_mesh m;
    repaired("fins.obj", fins, "edge between vertices 1 and 2 split into 2 (lines 6, 7, 8; line 6 and line 7 keep it)", &m);
    CHECK(m.nfaces == 3 && m.nverts == 7);
    st_mesh_free(&m);
    repaired("fins.off", fins_off, "edge between vertices 0 and 1 split into 2 (lines 8, 9, 10; line 8 and line 9 keep it)", &m);
    CHECK(m.nfaces == 3 && m.nverts == 7);
    st_mesh_free(&m);
    refused_bytes_flags("bad_fins.obj", fins, strlen(fins), ST_MESH_STRICT, ":8:",
                        "non-manifold edge between vertices 1 and 2: 3 faces share it (lines 6, 7, 8)");
    refused_bytes_flags("bad_fins.off", fins_off, strlen(fins_off), ST_MESH_STRICT,
                        ":10:", "non-manifold edge between vertices 0 and 1");
    buf b;   /* the tetrahedron's faces plus a fourth triangle on edge 0-1 */
    tet_ply(&b, 4, 5, 4, 5);
    size_t last = b.n - 5 - 13;
    memcpy(b.b + last + 1, (int32_t[]){0, 1, 3}, 12);
    char loc[32];
    snprintf(loc, sizeof loc, "byte %zu", last);
    refused_bytes_flags("bad_fins.ply", b.b, b.n, ST_MESH_STRICT, loc, "3 faces share it");
    /* The same file without the flag opens: the fifth face repeats a face
     * of the tetrahedron (every triple of its vertices is one), so it is
     * the third face on its three edges and gets copies of all three. */
    st_error e = {0};
    st_mesh_init(&m);
    CHECKF(st_mesh_load(tmp_path("bad_fins.ply"), &m, &e) == 0, "%s", e.msg);
    CHECKF(m.nfaces == 5 && m.nverts == 7, "bad_fins.ply: V %u F %u", m.nverts, m.nfaces);
    CHECKF(st_mesh_check("bad_fins.ply", &m, &e) == 0, "%s", e.msg);
    st_mesh_free(&m);
}

static void test_non_orientable(void)
{
    refused("bad_moebius.obj", moebius, NULL, "non-orientable surface: cannot orient consistently");
    st_error e;
    st_mesh m;
    st_mesh_init(&m);
    CHECK(st_mesh_load(tmp_path("bad_moebius.obj"), &m, &e) == ST_ERR_TOPOLOGY);
    CHECKF(strstr(e.msg, "bad_moebius.obj:9:") != NULL, "%s", e.msg);   /* the last quad's line */
}

static void test_repairs(void)
{
    st_mesh m;
    /* Two triangles sharing edge 1-2 with the same winding: the second flips. */
    repaired("fix_orientation.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 3 4\n",
             "flipped 1 of 2 faces to orient the surface consistently (first: line 6)", &m);
    CHECK(m.nfaces == 2 && m.face_idx[3] == 1 && m.face_idx[4] == 3 && m.face_idx[5] == 2);
    st_mesh_free(&m);
    /* Vertices 3 and 6 are not used by any face. */
    repaired("fix_isolated.obj", "v 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\nv 1 1 0\nv 8 8 8\nf 1 2 4\nf 2 5 4\n",
             "dropped 2 unreferenced vertices (3, 6)", &m);
    CHECK(m.nverts == 4 && m.pos[3 * 2] == 0 && m.pos[3 * 2 + 1] == 1);
    CHECK(m.face_idx[0] == 0 && m.face_idx[1] == 1 && m.face_idx[2] == 2 && m.face_idx[4] == 3);
    st_mesh_free(&m);
    /* Bow-tie: two triangles meeting only at vertex 3, with a crease and a
     * corner on it.   1   4
     *                  \ /
     *                   3      (0-based tags: vertex 2)
     *                  / \
     *                 2   5                                          */
    repaired("fix_bowtie.obj", "v -1 1 0\nv -1 -1 0\nv 0 0 0\nv 1 1 0\nv 1 -1 0\nf 1 2 3\nf 3 5 4\n"
             "t crease 2/1/0 2 4 2.5\nt corner 1/1/0 2 3.0\n", "split 1 non-manifold vertex", &m);
    CHECK(m.nverts == 6 && m.pos[3 * 5] == 0 && m.pos[3 * 5 + 1] == 0);
    CHECK(m.ncreases == 1 && m.ncorners == 2 && m.corner_s[1] == 3.0f);
    CHECK(m.crease_v[0] == 5 && m.crease_v[1] == 4 && m.crease_s[0] == 2.5f);   /* the copy of 2 */
    st_mesh_free(&m);
    repaired("fix_bowtie_named.obj", "v -1 1 0\nv -1 -1 0\nv 0 0 0\nv 1 1 0\nv 1 -1 0\nf 1 2 3\nf 3 5 4\n",
             "vertex 3 split into 2", &m);
    st_mesh_free(&m);
    /* A crease tag on two vertices that share no edge is dropped. */
    repaired("fix_crease.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\nt crease 2/1/0 0 3 1\n",
             "dropped 1 crease tags that name no edge", &m);
    CHECK(m.ncreases == 0);
    st_mesh_free(&m);
}

/* Every prefix of a valid binary PLY fails cleanly (with the file's name
 * and, past the header, a byte offset) and leaves out untouched. */
static void test_prefixes(void)
{
    buf b;
    tet_ply(&b, 4, 4, 4, 4);
    size_t hs = header_size(&b);
    st_mesh m;
    load_good(&m);
    snapshot s;
    take(&s, &m);
    int bad = 0;
    for (size_t n = 0; n < b.n; n++) {
        st_error e = {0};
        char *copy = malloc(n ? n : 1);
        memcpy(copy, b.b, n);
        int rc = st_mesh_parse_ply("prefix.ply", copy, n, &m, &e);
        free(copy);
        if (rc == 0 || !strstr(e.msg, "prefix.ply") || (n > hs && !strstr(e.msg, "byte")) || !unchanged(&s, &m)) {
            if (!bad++) fprintf(stderr, "prefix %zu: rc %d: %s\n", n, rc, e.msg);
        }
    }
    CHECKF(bad == 0, "%d prefixes misbehaved", bad);
    st_error e;
    CHECK(parse_exact("ply", b.b, b.n, &m, &e) == 0 && m.nverts == 4 && m.nfaces == 4);
    drop(&s);
    st_mesh_free(&m);
    /* Text formats: any prefix either loads (cut at a record boundary) or not. */
    static const char off[] = "OFF\n# tet\n4 4 6\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n"
                              "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n";
    static const char obj[] = "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\r\nf 1 2 3\nf 1/1 4/2 2/3\nf 1//1 3//2 4//3\nf -3 -1 -2\n";
    int loaded = 0;
    for (size_t n = 0; n <= sizeof off - 1; n++) {
        st_mesh_init(&m);
        loaded += parse_exact("off", (const unsigned char *)off, n, &m, &e) == 0;
        st_mesh_free(&m);
    }
    CHECKF(loaded == 2, "OFF: %d prefixes loaded, expected 2 (the whole file, with or without the last newline)", loaded);
    for (size_t n = 0; n <= sizeof obj - 1; n++) {
        st_mesh_init(&m);
        parse_exact("obj", (const unsigned char *)obj, n, &m, &e);
        st_mesh_free(&m);
    }
}

/* Every single-bit flip of the binary PLY: no crash, no leak, and whatever
 * loads passes the check. */
static void test_bit_flips(void)
{
    buf b;
    tet_ply(&b, 4, 4, 4, 4);
    int loaded = 0, total = 0;
    for (size_t i = 0; i < b.n; i++)
        for (int bit = 0; bit < 8; bit++) {
            st_mesh m;
            st_error e;
            st_mesh_init(&m);
            b.b[i] ^= (unsigned char)(1u << bit);
            loaded += parse_exact("ply", b.b, b.n, &m, &e) == 0;
            b.b[i] ^= (unsigned char)(1u << bit);
            st_mesh_free(&m);
            total++;
        }
    printf("bit flips: %d of %d variants loaded\n", loaded, total);
    CHECK(loaded > 0 && loaded < total);
}

int main(void)
{
    test_missing_and_empty();
    test_index_range();
    test_degenerate_faces();
    test_non_finite();
    test_truncated_and_lying_counts();
    test_absurd_counts();
    test_header_syntax();
    test_tags();
    test_non_manifold_edge();
    test_non_orientable();
    test_repairs();
    test_prefixes();
    test_bit_flips();
    return TEST_END();
}
