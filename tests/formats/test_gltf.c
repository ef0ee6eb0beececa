/* glTF import/export (formats/gltf_io.h): export -> import round trips (files
 * and memory, .gltf and .glb, u8/u16/u32 indices), hand-made files for what
 * the exporter never writes (non-indexed primitives, several primitives and
 * meshes, node transforms, mirroring, strips and fans), and bad input: each
 * refusal returns non-zero, names the file, is one line, and leaves the
 * output mesh exactly as it was.  Also every prefix and many bit flips of a
 * small GLB: a clean load or a clean refusal, never a crash. */
#include "formats/gltf_io.h"
#include "testlib.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char *tmp_path(const char *name)
{
    static char buf[1024];
    snprintf(buf, sizeof buf, "%s/%s", STRATA_TMP, name);
    return buf;
}

/* ---- comparing soups ------------------------------------------------------ */

static uint32_t tri_count(const st_mesh *m)
{
    uint32_t n = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) n += m->face_off[f + 1] - m->face_off[f] - 2;
    return n;
}

/* b (triangles) is a's polygons fanned from their first corner, corner by
 * corner, within tol: the exporter's triangulation, read back in order. */
static int same_fanned(const st_mesh *a, const st_mesh *b, double tol)
{
    if (b->nfaces != tri_count(a)) return 0;
    uint32_t t = 0;
    for (uint32_t f = 0; f < a->nfaces; f++) {
        uint32_t o = a->face_off[f], e = a->face_off[f + 1];
        for (uint32_t k = o + 1; k + 1 < e; k++, t++) {
            if (b->face_off[t + 1] - b->face_off[t] != 3) return 0;
            uint32_t ca[3] = { a->face_idx[o], a->face_idx[k], a->face_idx[k + 1] };
            for (int c = 0; c < 3; c++) {
                const double *p = a->pos + 3 * ca[c], *q = b->pos + 3 * b->face_idx[b->face_off[t] + (uint32_t)c];
                for (int d = 0; d < 3; d++)
                    if (fabs(p[d] - q[d]) > tol) return 0;
            }
        }
    }
    return 1;
}

/* Six times the signed volume: positive for a closed, outward mesh. */
static double volume6(const st_mesh *m)
{
    double v = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t o = m->face_off[f], e = m->face_off[f + 1];
        const double *p0 = m->pos + 3 * m->face_idx[o];
        for (uint32_t k = o + 1; k + 1 < e; k++) {
            const double *p1 = m->pos + 3 * m->face_idx[k], *p2 = m->pos + 3 * m->face_idx[k + 1];
            v += p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
                 p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]);
        }
    }
    return v;
}

/* ---- round trips ---------------------------------------------------------- */

static void offset_scale(st_mesh *m, double s, double dx)
{
    for (uint32_t i = 0; i < 3 * m->nverts; i++) m->pos[i] = m->pos[i] * s + dx;
}

static void check_round_trip(const char *label, const st_mesh *a)
{
    double tol = 1e-6 * st_mesh_diagonal(a);
    st_error err;
    for (int binary = 0; binary <= 1; binary++) {
        int sizes[] = { 0, 1, 2, 4 };
        for (int s = 0; s < 4; s++) {
            if (sizes[s] == 1 && a->nverts >= 255) continue;
            void *data = NULL;
            size_t size = 0;
            st_mesh b;
            st_mesh_init(&b);
            int rc = st_gltf_write_mem(a, binary, sizes[s], &data, &size, &err);
            CHECKF(rc == 0, "%s: write: %s", label, err.msg);
            if (rc) continue;
            rc = st_gltf_parse(label, data, size, &b, &err);
            CHECKF(rc == 0, "%s (%s, %d-byte indices): %s", label, binary ? "glb" : "gltf", sizes[s], err.msg);
            CHECKF(!rc && same_fanned(a, &b, tol), "%s (%s, %d-byte indices): soup differs", label,
                   binary ? "glb" : "gltf", sizes[s]);
            CHECK(!rc && b.nverts == a->nverts);  /* welded back to the shared vertices */
            st_mesh_free(&b);
            free(data);
        }
    }
    /* Files: .gltf + .bin and .glb, loaded with repair. */
    const char *ext[] = { "gltf", "glb" };
    for (int e = 0; e < 2; e++) {
        char name[256];
        snprintf(name, sizeof name, "gltf_rt_%s.%s", label, ext[e]);
        const char *path = tmp_path(name);
        int rc = st_gltf_save(path, a, &err);
        CHECKF(rc == 0, "%s: %s", path, err.msg);
        st_mesh b;
        st_mesh_init(&b);
        rc = rc ? rc : st_gltf_load(path, &b, &err);
        CHECKF(rc == 0, "%s: %s", path, err.msg);
        CHECKF(!rc && same_fanned(a, &b, tol), "%s: loaded soup differs", path);
        st_mesh_free(&b);
    }
}

static void test_round_trips(void)
{
    st_mesh m;
    tl_mesh_cube(&m);
    check_round_trip("cube", &m);
    offset_scale(&m, 1000.0, 12345.0);  /* tolerance follows the size */
    check_round_trip("cube_far", &m);
    st_mesh_free(&m);
    tl_mesh_tetra(&m);
    check_round_trip("tetra", &m);
    st_mesh_free(&m);
    tl_mesh_grid(&m, 5);
    check_round_trip("grid", &m);
    st_mesh_free(&m);
    tl_mesh_torus(&m, 24, 16);
    check_round_trip("torus", &m);
    st_mesh_free(&m);
    /* A pentagon prism: polygons are fanned. */
    double pos[30];
    uint32_t idx[20], off[8] = { 0, 5, 10, 14, 18, 22, 26, 30 };
    uint32_t sides[30];
    for (int i = 0; i < 5; i++) {
        double a = 2 * M_PI * i / 5;
        pos[3 * i] = cos(a), pos[3 * i + 1] = sin(a), pos[3 * i + 2] = 0;
        pos[15 + 3 * i] = cos(a), pos[15 + 3 * i + 1] = sin(a), pos[15 + 3 * i + 2] = 1;
        idx[i] = (uint32_t)(4 - i);       /* bottom, facing down */
        idx[5 + i] = (uint32_t)(5 + i);   /* top */
    }
    uint32_t all[30];
    memcpy(all, idx, sizeof idx);
    for (uint32_t i = 0; i < 5; i++) {
        uint32_t j = (i + 1) % 5;
        sides[4 * i] = i, sides[4 * i + 1] = j, sides[4 * i + 2] = 5 + j, sides[4 * i + 3] = 5 + i;
    }
    memcpy(all + 10, sides, 20 * sizeof(uint32_t));
    tl_mesh_make(&m, pos, 10, off, all, 7);
    check_round_trip("prism", &m);
    CHECK(volume6(&m) > 0);
    st_mesh_free(&m);
}

/* ---- hand-made files ------------------------------------------------------ */

static void base64(const unsigned char *in, size_t n, char *out)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = tab[v >> 18 & 63];
        out[o++] = tab[v >> 12 & 63];
        out[o++] = i + 1 < n ? tab[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? tab[v & 63] : '=';
    }
    out[o] = 0;
}

/* A .gltf text: one buffer (bin, as a data: URI) plus the JSON members in
 * rest ("\"accessors\": [...], ..."). */
static char *make_gltf(const void *bin, size_t n, const char *rest)
{
    char *b64 = malloc(4 * (n / 3 + 1) + 1);
    base64(bin, n, b64);
    size_t cap = strlen(b64) + strlen(rest) + 256;
    char *s = malloc(cap);
    snprintf(s, cap,
             "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": %zu, "
             "\"uri\": \"data:application/octet-stream;base64,%s\"}], %s}",
             n, b64, rest);
    free(b64);
    return s;
}

/* A GLB of JSON members rest and a BIN chunk. */
static unsigned char *make_glb(const void *bin, size_t n, const char *rest, size_t *size)
{
    char json[8192];
    snprintf(json, sizeof json, "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": %zu}], %s}", n, rest);
    size_t jn = strlen(json), jp = (jn + 3) & ~(size_t)3, bp = (n + 3) & ~(size_t)3;
    *size = 12 + 8 + jp + 8 + bp;
    unsigned char *g = calloc(1, *size);
    uint32_t h[5] = { 0x46546C67u, 2, (uint32_t)*size, (uint32_t)jp, 0x4E4F534Au };
    memcpy(g, h, 20);
    memcpy(g + 20, json, jn);
    memset(g + 20 + jn, ' ', jp - jn);
    uint32_t c[2] = { (uint32_t)bp, 0x004E4942u };
    memcpy(g + 20 + jp, c, 8);
    memcpy(g + 28 + jp, bin, n);
    return g;
}

/* Tetrahedron positions (4 x float3) at byte 0, outward faces. */
static const float tet_pos[12] = { 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1 };
static const uint32_t tet_faces[12] = { 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2 };

static int parse_str(const char *name, const char *text, st_mesh *out, st_error *err)
{
    return st_gltf_parse(name, text, strlen(text), out, err);
}

static void test_index_types(void)
{
    /* Buffer: positions, then the same 12 indices as u8, u16 and u32. */
    unsigned char buf[48 + 12 + 24 + 48];
    memcpy(buf, tet_pos, 48);
    for (int i = 0; i < 12; i++) {
        buf[48 + i] = (unsigned char)tet_faces[i];
        uint16_t s = (uint16_t)tet_faces[i];
        memcpy(buf + 60 + 2 * i, &s, 2);
        memcpy(buf + 84 + 4 * i, &tet_faces[i], 4);
    }
    const char *types[3] = { "5121", "5123", "5125" };
    const int offs[3] = { 48, 60, 84 }, lens[3] = { 12, 24, 48 };
    for (int t = 0; t < 3; t++) {
        char rest[2048];
        snprintf(rest, sizeof rest,
                 "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": %d, \"byteLength\": %d}],"
                 "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},"
                 "{\"bufferView\": 1, \"componentType\": %s, \"count\": 12, \"type\": \"SCALAR\"}],"
                 "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}]",
                 offs[t], lens[t], types[t]);
        char *text = make_gltf(buf, sizeof buf, rest);
        st_mesh m;
        st_error err;
        st_mesh_init(&m);
        int rc = parse_str("idx.gltf", text, &m, &err);
        CHECKF(rc == 0, "index type %s: %s", types[t], err.msg);
        CHECK(!rc && m.nverts == 4 && m.nfaces == 4 && volume6(&m) > 0);
        CHECK(!rc && memcmp(m.face_idx, tet_faces, sizeof tet_faces) == 0);
        st_mesh_free(&m);
        free(text);
    }
}

static void test_non_indexed_and_merged(void)
{
    /* Non-indexed: 12 corners, duplicated positions, welded to 4 vertices. */
    float soup[36];
    for (int i = 0; i < 12; i++) memcpy(soup + 3 * i, tet_pos + 3 * tet_faces[i], 12);
    const char *rest =
        "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 144}],"
        "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 12, \"type\": \"VEC3\"}],"
        "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}]";
    char *text = make_gltf(soup, sizeof soup, rest);
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    int rc = parse_str("soup.gltf", text, &m, &err);
    CHECKF(rc == 0, "%s", err.msg);
    CHECK(!rc && m.nverts == 4 && m.nfaces == 4 && volume6(&m) > 0);
    CHECK(!rc && st_mesh_repair("soup.gltf", &m, NULL, &err) == 0 && st_mesh_check("soup.gltf", &m, &err) == 0);
    st_mesh_free(&m);
    free(text);

    /* Mesh 0: two primitives (faces 0-1, faces 2-3) on shared positions;
     * mesh 1: the tetrahedron again, placed by node 1 (translation +5 in x),
     * and node 2 (child of 1) mirrors it (scale -1 in x) and moves it up:
     * mirrored winding must be flipped back to outward. */
    unsigned char buf[48 + 48];
    memcpy(buf, tet_pos, 48);
    memcpy(buf + 48, tet_faces, 48);
    const char *rest2 =
        "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48}],"
        "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},"
        "{\"bufferView\": 1, \"componentType\": 5125, \"count\": 6, \"type\": \"SCALAR\"},"
        "{\"bufferView\": 1, \"byteOffset\": 24, \"componentType\": 5125, \"count\": 6, \"type\": \"SCALAR\"},"
        "{\"bufferView\": 1, \"componentType\": 5125, \"count\": 12, \"type\": \"SCALAR\"}],"
        "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1},"
        "{\"attributes\": {\"POSITION\": 0}, \"indices\": 2}]},"
        "{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 3}]}],"
        "\"nodes\": [{\"mesh\": 0}, {\"mesh\": 1, \"translation\": [5, 0, 0], \"children\": [2]},"
        "{\"mesh\": 1, \"scale\": [-1, 1, 1], \"translation\": [0, 10, 0]}],"
        "\"scenes\": [{\"nodes\": [0, 1]}], \"scene\": 0";
    text = make_gltf(buf, sizeof buf, rest2);
    st_mesh_init(&m);
    rc = parse_str("merged.gltf", text, &m, &err);
    CHECKF(rc == 0, "%s", err.msg);
    CHECKF(!rc && m.nverts == 12 && m.nfaces == 12, "%u vertices %u faces", m.nverts, m.nfaces);
    if (!rc && m.nverts == 12) {
        CHECK(m.pos[3 * 4] == 6.0 && m.pos[3 * 4 + 1] == 1.0);      /* first vertex of mesh 1 at +5 */
        CHECK(m.pos[3 * 8] == 4.0 && m.pos[3 * 8 + 1] == 11.0);     /* mirrored: x -> 5 - 1, y + 10 */
        CHECK(volume6(&m) > 0);                                     /* all three outward */
        CHECK(st_mesh_repair("merged.gltf", &m, NULL, &err) == 0 && st_mesh_check("merged.gltf", &m, &err) == 0);
    }
    st_mesh_free(&m);
    free(text);

    /* The same in a GLB. */
    size_t gsize;
    unsigned char *glb = make_glb(buf, sizeof buf, rest2, &gsize);
    st_mesh_init(&m);
    rc = st_gltf_parse("merged.glb", glb, gsize, &m, &err);
    CHECKF(rc == 0 && m.nfaces == 12 && volume6(&m) > 0, "%s", rc ? err.msg : "wrong mesh");
    st_mesh_free(&m);
    free(glb);
}

static void test_strip_fan(void)
{
    float sq[12] = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
    unsigned char buf[48 + 8];
    memcpy(buf, sq, 48);
    uint16_t strip[4] = { 0, 1, 3, 2 };
    memcpy(buf + 48, strip, 8);
    for (int mode = 5; mode <= 6; mode++) {
        char rest[1024];
        snprintf(rest, sizeof rest,
                 "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 8}],"
                 "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},"
                 "{\"bufferView\": 1, \"componentType\": 5123, \"count\": 4, \"type\": \"SCALAR\"}],"
                 "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": %s, \"mode\": %d}]}]",
                 mode == 5 ? "1" : "-1", mode);
        if (mode == 6) {
            /* non-indexed fan 0 1 2 3: drop the indices member */
            char *p = strstr(rest, ", \"indices\": -1");
            memmove(p, p + strlen(", \"indices\": -1"), strlen(p + strlen(", \"indices\": -1")) + 1);
        }
        char *text = make_gltf(buf, sizeof buf, rest);
        st_mesh m;
        st_error err;
        st_mesh_init(&m);
        int rc = parse_str("strip.gltf", text, &m, &err);
        CHECKF(rc == 0, "mode %d: %s", mode, err.msg);
        int ccw = 1;
        for (uint32_t f = 0; !rc && f < m.nfaces; f++) {
            const double *a = m.pos + 3 * m.face_idx[3 * f], *b = m.pos + 3 * m.face_idx[3 * f + 1],
                         *c = m.pos + 3 * m.face_idx[3 * f + 2];
            ccw &= (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0;
        }
        CHECKF(!rc && m.nfaces == 2 && m.nverts == 4 && ccw, "mode %d: %u faces, ccw %d", mode, m.nfaces, ccw);
        st_mesh_free(&m);
        free(text);
    }
}

/* ---- bad input ------------------------------------------------------------ */

/* out holds a cube; a refusal must keep it bit for bit. */
static void expect_refusal(const char *name, const void *data, size_t size, const char *what)
{
    st_mesh m, copy;
    tl_mesh_cube(&m);
    copy = m;
    double pos0 = m.pos[0];
    st_error err = { 0 };
    int rc = st_gltf_parse(name, data, size, &m, &err);
    CHECKF(rc != 0, "%s: accepted", what);
    CHECKF(rc == 0 || (strstr(err.msg, name) && !strchr(err.msg, '\n')), "%s: message '%s'", what, err.msg);
    CHECKF(memcmp(&m, &copy, sizeof m) == 0 && m.pos[0] == pos0, "%s: output changed", what);
    if (rc) printf("refused as expected (%s): %s\n", what, err.msg);
    st_mesh_free(&m);
}

static void expect_text_refusal(const char *name, const char *text, const char *what, const char *needle)
{
    expect_refusal(name, text, strlen(text), what);
    st_mesh m;
    st_error err = { 0 };
    st_mesh_init(&m);
    if (st_gltf_parse(name, text, strlen(text), &m, &err) != 0 && needle)
        CHECKF(strstr(err.msg, needle) != NULL, "%s: message '%s' lacks '%s'", what, err.msg, needle);
    st_mesh_free(&m);
}

static char *tet_file(const char *pos_acc, const char *idx_acc, const char *prim_extra, const float *pos)
{
    unsigned char buf[96];
    memcpy(buf, pos ? pos : tet_pos, 48);
    memcpy(buf + 48, tet_faces, 48);
    char rest[2048];
    snprintf(rest, sizeof rest,
             "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48}],"
             "\"accessors\": [%s, %s],"
             "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1%s}]}]",
             pos_acc, idx_acc, prim_extra);
    return make_gltf(buf, sizeof buf, rest);
}

#define POS_OK "{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"}"
#define IDX_OK "{\"bufferView\": 1, \"componentType\": 5125, \"count\": 12, \"type\": \"SCALAR\"}"

static void test_bad_input(void)
{
    char *t;
    t = tet_file(POS_OK, IDX_OK, "", NULL);
    {   /* the good one parses */
        st_mesh m;
        st_error err;
        st_mesh_init(&m);
        CHECK(parse_str("good.gltf", t, &m, &err) == 0 && m.nfaces == 4);
        st_mesh_free(&m);
    }
    free(t);

    /* index out of range: 3 positions declared, index 3 used */
    t = tet_file("{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"}", IDX_OK, "", NULL);
    expect_text_refusal("range.gltf", t, "index out of range", "index");
    free(t);
    /* accessor beyond its buffer view */
    t = tet_file(POS_OK, "{\"bufferView\": 1, \"componentType\": 5125, \"count\": 13, \"type\": \"SCALAR\"}", "", NULL);
    expect_text_refusal("beyond.gltf", t, "accessor beyond buffer view", "accessor 1");
    free(t);
    t = tet_file(POS_OK, "{\"bufferView\": 1, \"byteOffset\": 40, \"componentType\": 5125, \"count\": 3, \"type\": \"SCALAR\"}", "", NULL);
    expect_text_refusal("offset.gltf", t, "accessor offset beyond view", "accessor 1");
    free(t);
    /* NaN position */
    float nanpos[12];
    memcpy(nanpos, tet_pos, sizeof nanpos);
    nanpos[7] = NAN;
    t = tet_file(POS_OK, IDX_OK, "", nanpos);
    expect_text_refusal("nan.gltf", t, "NaN position", "not finite");
    free(t);
    /* lines and points */
    t = tet_file(POS_OK, IDX_OK, ", \"mode\": 1", NULL);
    expect_text_refusal("lines.gltf", t, "lines mode", "LINES");
    free(t);
    t = tet_file(POS_OK, IDX_OK, ", \"mode\": 0", NULL);
    expect_text_refusal("points.gltf", t, "points mode", "POINTS");
    free(t);
    /* wrong types, sparse, missing bits */
    t = tet_file("{\"bufferView\": 0, \"componentType\": 5121, \"count\": 4, \"type\": \"VEC3\"}", IDX_OK, "", NULL);
    expect_text_refusal("type.gltf", t, "byte positions", "POSITION");
    free(t);
    t = tet_file(POS_OK, "{\"bufferView\": 1, \"componentType\": 5126, \"count\": 12, \"type\": \"SCALAR\"}", "", NULL);
    expect_text_refusal("ftype.gltf", t, "float indices", "indices");
    free(t);
    t = tet_file(POS_OK, "{\"componentType\": 5125, \"count\": 12, \"type\": \"SCALAR\"}", "", NULL);
    expect_text_refusal("noview.gltf", t, "accessor without bufferView", "bufferView");
    free(t);
    t = tet_file(POS_OK, "{\"bufferView\": 7, \"componentType\": 5125, \"count\": 12, \"type\": \"SCALAR\"}", "", NULL);
    expect_text_refusal("view7.gltf", t, "bufferView does not exist", "bufferView");
    free(t);

    /* external buffer: refused from memory */
    const char *ext = "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": 96, \"uri\": \"tet.bin\"}],"
                      "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}],"
                      "\"accessors\": [" POS_OK "],"
                      "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}]}";
    expect_text_refusal("external.gltf", ext, "external URI in memory", "data:");
    /* buffer view beyond the buffer */
    const char *bv = "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": 4, \"uri\": \"data:application/octet-stream;base64,AAAAAA==\"}],"
                     "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}],"
                     "\"accessors\": [" POS_OK "],"
                     "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}]}";
    expect_text_refusal("view.gltf", bv, "bufferView beyond buffer", "bufferView 0");

    /* node cycle, and a shared child */
    unsigned char buf[96];
    memcpy(buf, tet_pos, 48);
    memcpy(buf + 48, tet_faces, 48);
    const char *cyc =
        "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48}],"
        "\"accessors\": [" POS_OK ", " IDX_OK "],"
        "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],"
        "\"nodes\": [{\"mesh\": 0, \"children\": [1]}, {\"children\": [0]}], \"scenes\": [{\"nodes\": [0]}]";
    t = make_gltf(buf, sizeof buf, cyc);
    expect_text_refusal("cycle.gltf", t, "node cycle", "node");
    free(t);
    /* Declared counts that would place too many triangles: refused before
     * anything is read or allocated for them. */
    const char *many =
        "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}],"
        "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 150000000, \"type\": \"VEC3\"}],"
        "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}],"
        "\"nodes\": [{\"mesh\": 0}, {\"mesh\": 0}, {\"mesh\": 0}], \"scenes\": [{\"nodes\": [0, 1, 2]}]";
    t = make_gltf(buf, sizeof buf, many);
    expect_text_refusal("many.gltf", t, "too many triangles placed", "more than");
    free(t);
    const char *nomesh = "\"nodes\": [{}], \"scenes\": [{\"nodes\": [0]}]";
    t = make_gltf(buf, sizeof buf, nomesh);
    expect_text_refusal("empty.gltf", t, "no triangles", "no triangles");
    free(t);

    /* not JSON, wrong magic, truncated GLB, too deep */
    expect_text_refusal("garbage.gltf", "this is not glTF", "garbage", NULL);
    expect_refusal("empty.glb", "", 0, "empty input");
    size_t gsize;
    const char *rest =
        "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48}],"
        "\"accessors\": [" POS_OK ", " IDX_OK "],"
        "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}]";
    unsigned char *glb = make_glb(buf, sizeof buf, rest, &gsize);
    {
        st_mesh m;
        st_error err;
        st_mesh_init(&m);
        CHECKF(st_gltf_parse("ok.glb", glb, gsize, &m, &err) == 0 && m.nfaces == 4, "good glb: %s", err.msg);
        st_mesh_free(&m);
    }
    expect_refusal("trunc.glb", glb, gsize - 10, "truncated glb");
    expect_refusal("head.glb", glb, 30, "glb header only");
    glb[3] = 'X';
    expect_refusal("magic.glb", glb, gsize, "wrong magic");
    glb[3] = 'F';
    uint32_t huge = 0x7ffffff0u;
    memcpy(glb + 12, &huge, 4);
    expect_refusal("chunk.glb", glb, gsize, "JSON chunk longer than the file");
    free(glb);
    char deep[4000];
    size_t k = 0;
    k += (size_t)snprintf(deep, sizeof deep, "{\"asset\": {\"version\": \"2.0\"}, \"extras\": ");
    for (int i = 0; i < 1000; i++) deep[k++] = '[';
    for (int i = 0; i < 1000; i++) deep[k++] = ']';
    deep[k++] = '}';
    deep[k] = 0;
    expect_text_refusal("deep.gltf", deep, "deep JSON", "deeper");

    /* From files: the message names the path. */
    const char *path = tmp_path("gltf_lines.gltf");
    t = tet_file(POS_OK, IDX_OK, ", \"mode\": 3", NULL);
    tl_write_file(path, t, strlen(t));
    free(t);
    st_mesh m;
    tl_mesh_cube(&m);
    st_mesh copy = m;
    st_error err;
    CHECK(st_gltf_load(path, &m, &err) != 0 && strstr(err.msg, path) && memcmp(&m, &copy, sizeof m) == 0);
    CHECK(st_gltf_load(tmp_path("gltf_missing.glb"), &m, &err) != 0 && strstr(err.msg, "gltf_missing.glb"));
    st_mesh_free(&m);

    /* The writer refuses what it cannot write. */
    st_mesh bad;
    st_mesh_init(&bad);
    CHECK(st_gltf_save(tmp_path("gltf_empty.glb"), &bad, &err) != 0);
    tl_mesh_cube(&bad);
    bad.pos[4] = NAN;
    CHECK(st_gltf_save(tmp_path("gltf_nan.glb"), &bad, &err) != 0 && strstr(err.msg, "gltf_nan.glb"));
    bad.pos[4] = 1;
    CHECK(st_gltf_save(tmp_path("gltf_cube.obj"), &bad, &err) != 0);
    void *data;
    size_t size;
    CHECK(st_gltf_write_mem(&bad, 1, 3, &data, &size, &err) != 0);
    st_mesh_free(&bad);
}

/* Every prefix and many single-bit flips of a small GLB: clean either way. */
static void test_mutations(void)
{
    st_mesh m;
    tl_mesh_cube(&m);
    void *data;
    size_t size;
    st_error err;
    if (st_gltf_write_mem(&m, 1, 0, &data, &size, &err)) {
        CHECKF(0, "%s", err.msg);
        return;
    }
    st_mesh_free(&m);
    unsigned char *bytes = data;
    int clean = 1, ok_prefix = 0;
    for (size_t n = 0; n < size; n++) {
        st_mesh out;
        st_mesh_init(&out);
        out.nverts = 7;
        int rc = st_gltf_parse("prefix.glb", bytes, n, &out, &err);
        if (rc) clean &= out.nverts == 7 && !out.pos && strstr(err.msg, "prefix.glb") != NULL;
        else ok_prefix++, st_mesh_free(&out);
    }
    CHECKF(clean, "a prefix failed uncleanly");
    CHECK(ok_prefix == 0);
    uint64_t rng = 12345;
    int loaded = 0, refused = 0;
    for (int i = 0; i < 4000; i++) {
        size_t bit = tl_rand(&rng) % (size * 8);
        bytes[bit / 8] ^= (unsigned char)(1u << (bit % 8));
        st_mesh out;
        st_mesh_init(&out);
        int rc = st_gltf_parse("flip.glb", bytes, size, &out, &err);
        if (rc) refused++;
        else {
            loaded++;
            st_notes notes = { 0 };
            if (st_mesh_repair("flip.glb", &out, &notes, &err) == 0)
                CHECKF(st_mesh_check("flip.glb", &out, &err) == 0, "repair broke its promise: %s", err.msg);
            st_notes_free(&notes);
        }
        st_mesh_free(&out);
        bytes[bit / 8] ^= (unsigned char)(1u << (bit % 8));
    }
    printf("bit flips: %d loaded, %d refused\n", loaded, refused);
    free(data);
}

int main(void)
{
    test_round_trips();
    test_index_types();
    test_non_indexed_and_merged();
    test_strip_fan();
    test_bad_input();
    test_mutations();
    return TEST_END();
}
