/* Mesh import and export: every OBJ face form, negative indices, CRLF,
 * OpenSubdiv tags, OFF variants, PLY in all three encodings with every
 * scalar type and unknown elements/properties, and import -> export ->
 * import round trips through OBJ and binary PLY.  Also the project's base
 * meshes in assets/: each loads with no repair and faces outwards. */
#include "core/io/mesh.h"
#include "core/map/geometry.h"
#include "core/map/map_mesh.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *tmp_path(const char *name)
{
    static char buf[4][1024];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", STRATA_TMP, name);
    return buf[k];
}

/* Loads text written to STRATA_TMP/name; returns rc, notes counted. */
static int load_text(const char *name, const char *text, st_mesh *m, uint32_t *nnotes)
{
    st_error e = {0};
    st_notes n = {0};
    const char *path = tmp_path(name);
    tl_write_file(path, text, strlen(text));
    st_mesh_init(m);
    int rc = st_mesh_load_notes(path, m, &n, &e);
    CHECKF(rc == 0, "%s: %s", name, e.msg);
    for (uint32_t i = 0; i < n.count; i++) fprintf(stderr, "note: %s\n", n.lines[i]);
    if (nnotes) *nnotes = n.count;
    st_notes_free(&n);
    return rc;
}

static int faces_are(const st_mesh *m, const uint32_t *off, const uint32_t *idx, uint32_t nf)
{
    return m->nfaces == nf && memcmp(m->face_off, off, (nf + 1) * sizeof *off) == 0 &&
           memcmp(m->face_idx, idx, off[nf] * sizeof *idx) == 0;
}

static int same_faces(const st_mesh *a, const st_mesh *b)
{
    return faces_are(a, b->face_off, b->face_idx, b->nfaces);
}

/* Positions equal within rel (0: bit-exact). */
static int same_positions(const st_mesh *a, const st_mesh *b, double rel)
{
    if (a->nverts != b->nverts) return 0;
    for (size_t i = 0; i < 3 * (size_t)a->nverts; i++)
        if (fabs(a->pos[i] - b->pos[i]) > rel * fabs(b->pos[i])) return 0;
    return 1;
}

static int same_tags(const st_mesh *a, const st_mesh *b)
{
    return a->ncreases == b->ncreases && a->ncorners == b->ncorners && a->boundary_interp == b->boundary_interp &&
           (!a->ncreases || (memcmp(a->crease_v, b->crease_v, 2 * a->ncreases * sizeof *a->crease_v) == 0 &&
                             memcmp(a->crease_s, b->crease_s, a->ncreases * sizeof *a->crease_s) == 0)) &&
           (!a->ncorners || (memcmp(a->corner_v, b->corner_v, a->ncorners * sizeof *a->corner_v) == 0 &&
                             memcmp(a->corner_s, b->corner_s, a->ncorners * sizeof *a->corner_s) == 0));
}

/* ---- OBJ ------------------------------------------------------------------------ */

/* A cube (vertex i at x = i&1, y = i&2, z = i&4, as -1/+1) using every face
 * form, a relative face, CRLF, skipped records and OpenSubdiv tags.
 *      6----7
 *     /|   /|      faces, 1-based: bottom 1 3 4 2, top 5 6 8 7,
 *    4----5 |      front 1 2 6 5, back 3 7 8 4,
 *    | 2--|-3      left 1 5 7 3, right 2 4 8 6
 *    0----1                                                        */
static const char cube_obj[] =
    "# a cube\r\nmtllib cube.mtl\r\no Cube\r\n"
    "v -1 -1 -1\r\nv 1 -1 -1\r\nv -1 1 -1\r\nv 1 1 -1\r\n"
    "v -1 -1 1\r\nv 1 -1 1\r\nv -1 1 1\r\nv 1 1 1 1.0\r\n"
    "vt 0 0\r\nvt 1 0\r\nvn 0 0 1\r\ng side\r\ns off\r\nusemtl red\r\n"
    "f 1 3 4 2\r\n"
    "f 5/1 6/2 8/1 7/2\r\n"
    "f 1//1 2//1 6//1 5//1\r\n"
    "f 3/1/1 7/2/1 8/1/1 4/2/1\r\n"
    "f -8 -4 -2 -6\r\n"
    "\tf 2 4 8 6   # right\r\n"
    "l 1 2\r\n"
    "t crease 4/1/0 0 1 1 3 2.5\r\n"
    "t corner 2/2/0 6 7 1.5 4\r\n"
    "t interpolateboundary 1/0/0 1\r\n"
    "t facevaryingpropagatecorners 1/0/0 0\r\n";

static const uint32_t cube_off[] = {0, 4, 8, 12, 16, 20, 24};
static const uint32_t cube_idx[] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};

static void test_obj_forms(void)
{
    st_mesh m;
    uint32_t notes = 9;
    if (load_text("io_cube.obj", cube_obj, &m, &notes)) return;
    CHECK(notes == 0);
    CHECK(m.nverts == 8 && faces_are(&m, cube_off, cube_idx, 6));
    CHECK(m.pos[0] == -1 && m.pos[3 * 7 + 2] == 1 && m.normals == NULL);
    CHECK(m.ncreases == 2 && m.crease_v[0] == 0 && m.crease_v[1] == 1 && m.crease_v[2] == 1 && m.crease_v[3] == 3);
    CHECK(m.crease_s[0] == 2.5f && m.crease_s[1] == 2.5f);
    CHECK(m.ncorners == 2 && m.corner_v[0] == 6 && m.corner_v[1] == 7 && m.corner_s[0] == 1.5f && m.corner_s[1] == 4.0f);
    CHECK(m.boundary_interp == ST_BOUNDARY_EDGE_AND_CORNER);
    st_error e;
    CHECK(st_mesh_check("cube", &m, &e) == 0);
    st_mesh_free(&m);
}

/* Relative indices count back from the vertices defined so far; positive
 * ones may name a vertex defined further down.  One crease per edge. */
static void test_obj_relative(void)
{
    static const char text[] =
        "f 1 2 3\n"                 /* forward references */
        "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
        "v 1 1 0\n"
        "f -3 -1 -2\n"              /* 2 4 3 */
        "t crease 4/2/0 0 1 1 2 1 2\n";
    st_mesh m;
    if (load_text("io_relative.obj", text, &m, NULL)) return;
    static const uint32_t off[] = {0, 3, 6}, idx[] = {0, 1, 2, 1, 3, 2};
    CHECK(faces_are(&m, off, idx, 2));
    CHECK(m.ncreases == 2 && m.crease_s[0] == 1.0f && m.crease_s[1] == 2.0f);
    CHECK(m.boundary_interp == ST_BOUNDARY_UNSET);
    st_mesh_free(&m);
}

/* Two 100-gons glued along their boundary (a pillow): faces long enough to
 * take the sorting path of the repeated-vertex check. */
/* OpenSubdiv's tag convention (regression/common/far_utils.h): a crease
 * tag's integers are vertex pairs, one edge per pair, not a chain; one
 * sharpness for all pairs or one per pair.  creasemethod normal and
 * smoothtriangles catmark name what Strata does and are accepted. */
static void test_obj_tag_pairs(void)
{
    static const char text[] =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
        "f 1 2 3 4\nf 2 5 6 3\n"
        "t crease 4/1/0 0 1 1 4 0.7\n"          /* edges 0-1 and 1-4, both 0.7 */
        "t crease 6/3/0 3 0 2 5 4 5 1 2 3.5\n"  /* edges 3-0 (1), 2-5 (2), 4-5 (3.5) */
        "t corner 2/1/0 2 3 4\n"
        "t creasemethod 0/0/1 normal\n"
        "t smoothtriangles 0/0/1 catmark\n"
        "t interpolateboundary 1/0/0 2\n";
    st_mesh m;
    if (load_text("io_tag_pairs.obj", text, &m, NULL)) return;
    static const uint32_t v[] = {0, 1, 1, 4, 3, 0, 2, 5, 4, 5};
    static const float s[] = {0.7f, 0.7f, 1.0f, 2.0f, 3.5f};
    CHECK(m.ncreases == 5);
    for (uint32_t i = 0; i < 5 && m.ncreases == 5; i++) {
        CHECKF(m.crease_v[2 * i] == v[2 * i] && m.crease_v[2 * i + 1] == v[2 * i + 1],
               "crease %u is %u-%u, expected %u-%u", i, m.crease_v[2 * i], m.crease_v[2 * i + 1], v[2 * i], v[2 * i + 1]);
        CHECKF(m.crease_s[i] == s[i], "crease %u sharpness %g, expected %g", i, (double)m.crease_s[i], (double)s[i]);
    }
    CHECK(m.ncorners == 2 && m.corner_v[0] == 2 && m.corner_v[1] == 3 && m.corner_s[1] == 4.0f);
    CHECK(m.boundary_interp == ST_BOUNDARY_EDGE_ONLY);
    CHECK(m.crease_method == 0);
    st_mesh_free(&m);
}

/* `t creasemethod 0/0/1 chaikin` selects Chaikin's sharpness rule; the last
 * creasemethod tag wins, as in OpenSubdiv's harness; an OBJ written back
 * keeps it. */
static void test_obj_creasemethod(void)
{
    static const char text[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                               "t crease 2/1/0 0 1 0.7\nt creasemethod 0/0/1 chaikin\n";
    st_mesh m;
    if (load_text("io_chaikin.obj", text, &m, NULL)) return;
    CHECK(m.crease_method == 1);
    const char *path = tmp_path("io_chaikin_out.obj");
    st_error e;
    CHECK(st_mesh_save_obj(path, &m, &e) == 0);
    st_mesh back;
    st_mesh_init(&back);
    CHECK(st_mesh_load_obj(path, &back, &e) == 0 && back.crease_method == 1 && back.ncreases == 1);
    st_mesh_free(&back);
    st_mesh_free(&m);
    static const char text2[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                                "t creasemethod 0/0/1 chaikin\nt creasemethod 0/0/1 normal\n"
                                "t smoothtriangles 0/0/1 smooth\n";
    if (load_text("io_normal.obj", text2, &m, NULL)) return;
    CHECK(m.crease_method == 0 && m.tri_sub == 1);
    st_mesh_free(&m);
}

/* `t hole` names faces (0-based, a face may come after the tag); several
 * tags add up. */
static void test_obj_holes(void)
{
    static const char text[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                               "t hole 1/0/0 1\nf 1 2 3 4\nf 2 5 6 3\nf 4 3 6\nt hole 2/0/0 2 1\n";
    st_mesh m;
    if (load_text("io_holes.obj", text, &m, NULL)) return;
    CHECK(m.nfaces == 3 && m.face_hole && !m.face_hole[0] && m.face_hole[1] && m.face_hole[2]);
    st_mesh_free(&m);
}

static void test_obj_big_faces(void)
{
    char *text = malloc(20000);
    size_t n = 0;
    for (int i = 0; i < 100; i++)
        n += (size_t)sprintf(text + n, "v %g %g 0\n", cos(i * 0.0628), sin(i * 0.0628));
    n += (size_t)sprintf(text + n, "f");
    for (int i = 1; i <= 100; i++) n += (size_t)sprintf(text + n, " %d", i);
    n += (size_t)sprintf(text + n, "\nf");
    for (int i = 100; i >= 1; i--) n += (size_t)sprintf(text + n, " %d", i);
    sprintf(text + n, "\n");
    st_mesh m;
    if (!load_text("io_pillow.obj", text, &m, NULL)) {
        st_error e;
        CHECK(m.nfaces == 2 && m.face_off[2] == 200 && st_mesh_check("pillow", &m, &e) == 0);
        st_mesh_free(&m);
    }
    text[n - 3] = '5';      /* the second face now lists vertex 5 twice (", 5" for ", 2") */
    text[n - 2] = ' ';
    st_error e;
    st_mesh_init(&m);
    CHECK(st_mesh_parse_obj("pillow.obj", text, strlen(text), &m, &e) == ST_ERR_TOPOLOGY);
    CHECKF(strstr(e.msg, "pillow.obj:102: face uses vertex 5 more than once") != NULL, "%s", e.msg);
    free(text);
}

/* ---- OFF ------------------------------------------------------------------------ */

static void test_off_variants(void)
{
    static const uint32_t off[] = {0, 3, 6, 9, 12}, idx[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    static const char *texts[] = {
        "OFF\n# tetrahedron\n\n4 4 6\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n"
        "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n",
        /* counts on the keyword line, CRLF, comments after data, no edge count */
        "OFF 4 4\r\n1 1 1 # a\r\n1 -1 -1\r\n-1 1 -1\r\n-1 -1 1\r\n"
        "3 0 1 2\r\n3 0 3 1\r\n3 0 2 3\r\n3 1 3 2",
        /* no keyword; per-vertex colours and per-face colours */
        "4 4 0\n1 1 1 255 0 0\n1 -1 -1 0 255 0\n-1 1 -1 0 0 255\n-1 -1 1 9 9 9\n"
        "3 0 1 2 1 0 0\n3 0 3 1 0 1 0\n3 0 2 3 0 0 1\n3 1 3 2 1 1 1\n",
        "COFF\n4 4 6\n1 1 1 0.5 0.5 0.5 1\n1 -1 -1 0 0 0 1\n-1 1 -1 0 0 0 1\n-1 -1 1 0 0 0 1\n"
        "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n",
    };
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        char name[32];
        st_mesh m;
        snprintf(name, sizeof name, "io_tet%zu.off", i);
        if (load_text(name, texts[i], &m, NULL)) continue;
        CHECKF(m.nverts == 4 && faces_are(&m, off, idx, 4), "%s", name);
        CHECKF(m.pos[0] == 1 && m.pos[11] == 1 && m.pos[10] == -1, "%s", name);
        st_mesh_free(&m);
    }
}

/* ---- PLY ------------------------------------------------------------------------ */

enum { ASCII, LE, BE };
static const char *const type_names[16] = {"char", "int8", "uchar", "uint8", "short", "int16", "ushort", "uint16",
                                           "int", "int32", "uint", "uint32", "float", "float32", "double", "float64"};

static int type_size(int t) { return t < 4 ? 1 : t < 8 ? 2 : t < 12 ? 4 : t < 14 ? 4 : 8; }
static int type_signed(int t) { return t < 12 ? ((t / 2) % 2 == 0) : 1; }

typedef struct buf {
    unsigned char *b;
    size_t n;
} buf;

static void put(buf *b, const void *p, size_t n)
{
    memcpy(b->b + b->n, p, n);
    b->n += n;
}

/* Appends value as type t in the given encoding (ascii: text + sep). */
static void put_value(buf *b, int enc, int t, double v, char sep)
{
    if (enc == ASCII) {
        char s[64];
        int k = t >= 12 ? snprintf(s, sizeof s, "%.17g%c", v, sep) : snprintf(s, sizeof s, "%lld%c", (long long)v, sep);
        put(b, s, (size_t)k);
        return;
    }
    unsigned char raw[8];
    int n = type_size(t);
    if (t >= 14) memcpy(raw, &v, 8);
    else if (t >= 12) { float f = (float)v; memcpy(raw, &f, 4); }
    else { int64_t i = (int64_t)v; memcpy(raw, &i, 8); }   /* little-endian host: low bytes first */
    for (int k = 0; k < n; k++) b->b[b->n + (size_t)k] = raw[enc == BE ? n - 1 - k : k];
    b->n += (size_t)n;
}

static const char *const enc_names[3] = {"ascii", "binary_little_endian", "binary_big_endian"};

/* A tetrahedron whose x, y, z are of type xt, face lists of count type ct
 * and index type it, surrounded by unknown elements and properties
 * (scalars and lists) that the reader must skip. */
static void build_ply(buf *b, int enc, int xt, int ct, int it, const char *list_name)
{
    static const int xyz[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    static const int faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    int sgn = type_signed(xt) ? 1 : 0;     /* unsigned: coordinates 0/2 instead of -1/+1 */
    char hdr[1024];
    int k = snprintf(hdr, sizeof hdr, "ply\nformat %s 1.0\ncomment skip me\nobj_info also me\n"
                     "element material 2\nproperty list uchar float rgb\nproperty int id\n"
                     "element vertex 4\nproperty %s x\nproperty list ushort double junk\nproperty %s y\n"
                     "property %s z\nproperty uchar red\n"
                     "element face 4\nproperty uchar flags\nproperty list %s %s %s\n"
                     "property list uchar float texcoord\n"
                     "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n",
                     enc_names[enc], type_names[xt], type_names[xt], type_names[xt],
                     type_names[ct], type_names[it], list_name);
    b->n = 0;
    put(b, hdr, (size_t)k);
    for (int i = 0; i < 2; i++) {   /* material */
        put_value(b, enc, 2, 3, ' ');
        for (int j = 0; j < 3; j++) put_value(b, enc, 12, 0.25 * j, ' ');
        put_value(b, enc, 8, -i, '\n');
    }
    for (int v = 0; v < 4; v++) {
        put_value(b, enc, xt, sgn ? xyz[v][0] : xyz[v][0] + 1, ' ');
        put_value(b, enc, 6, v, ' ');      /* junk list of v doubles */
        for (int j = 0; j < v; j++) put_value(b, enc, 14, 1e300, ' ');
        put_value(b, enc, xt, sgn ? xyz[v][1] : xyz[v][1] + 1, ' ');
        put_value(b, enc, xt, sgn ? xyz[v][2] : xyz[v][2] + 1, ' ');
        put_value(b, enc, 2, 200, '\n');
    }
    for (int f = 0; f < 4; f++) {
        put_value(b, enc, 2, 9, ' ');
        put_value(b, enc, ct, 3, ' ');
        for (int j = 0; j < 3; j++) put_value(b, enc, it, faces[f][j], ' ');
        put_value(b, enc, 2, 2, ' ');
        put_value(b, enc, 12, 0.5, ' ');
        put_value(b, enc, 12, 0.75, '\n');
    }
    put_value(b, enc, 8, 0, ' ');
    put_value(b, enc, 8, 1, '\n');
}

static void test_ply_types(void)
{
    static const uint32_t off[] = {0, 3, 6, 9, 12}, idx[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    buf b = {malloc(8192), 0};
    int bad = 0, runs = 0;
    for (int enc = 0; enc < 3; enc++)
        for (int xt = 0; xt < 16; xt++)
            for (int ct = 0; ct < 12; ct++) {
                int it = (ct * 5 + xt) % 12;   /* every index type meets every count type over xt */
                build_ply(&b, enc, xt, ct, it, (ct + xt) % 2 ? "vertex_indices" : "vertex_index");
                st_mesh m;
                st_error e;
                st_mesh_init(&m);
                int rc = st_mesh_parse_ply("types.ply", (const char *)b.b, b.n, &m, &e);
                double lo = type_signed(xt) ? -1 : 0, hi = type_signed(xt) ? 1 : 2;
                int ok = rc == 0 && m.nverts == 4 && faces_are(&m, off, idx, 4) &&
                         m.pos[0] == hi && m.pos[3] == hi && m.pos[4] == lo && m.pos[11] == hi;
                if (!ok && bad++ < 5)
                    fprintf(stderr, "ply %s x:%s count:%s index:%s: rc %d %s\n", enc_names[enc],
                            type_names[xt], type_names[ct], type_names[it], rc, rc ? e.msg : "wrong values");
                runs++;
                st_mesh_free(&m);
            }
    CHECKF(bad == 0, "%d of %d PLY type combinations failed", bad, runs);
    free(b.b);
}

/* ---- round trips ---------------------------------------------------------------- */

/* A triangular bipyramid with awkward coordinates, creases, corners. */
static void awkward_mesh(st_mesh *m)
{
    static const double p[5][3] = {{0.1, 1.0 / 3.0, -2.5e17}, {1e-300, -0.7, 3.141592653589793},
                                   {-1.0, 2.0 / 7.0, 1e-5}, {0.0, 0.0, 123456789.123456789},
                                   {-0.0, 5e-324, -1e300}};
    static const uint32_t off[] = {0, 3, 6, 9, 12, 15, 18};
    static const uint32_t idx[] = {0, 1, 3, 1, 2, 3, 2, 0, 3, 1, 0, 4, 2, 1, 4, 0, 2, 4};
    st_mesh_init(m);
    m->nverts = 5;
    m->nfaces = 6;
    m->pos = malloc(sizeof p);
    memcpy(m->pos, p, sizeof p);
    m->face_off = malloc(sizeof off);
    memcpy(m->face_off, off, sizeof off);
    m->face_idx = malloc(sizeof idx);
    memcpy(m->face_idx, idx, sizeof idx);
    m->ncreases = 2;
    m->crease_v = malloc(4 * sizeof *m->crease_v);
    m->crease_s = malloc(2 * sizeof *m->crease_s);
    memcpy(m->crease_v, (uint32_t[]){0, 1, 1, 2}, 4 * sizeof *m->crease_v);
    memcpy(m->crease_s, (float[]){0.1f, 10.0f}, 2 * sizeof *m->crease_s);
    m->ncorners = 1;
    m->corner_v = malloc(sizeof *m->corner_v);
    m->corner_s = malloc(sizeof *m->corner_s);
    m->corner_v[0] = 4;
    m->corner_s[0] = 1.0f / 3.0f;
    m->boundary_interp = ST_BOUNDARY_NONE;
}

static void test_round_trips(void)
{
    st_mesh a, b, c;
    st_error e;
    awkward_mesh(&a);
    CHECK(st_mesh_check("awkward", &a, &e) == 0);
    const char *obj = tmp_path("io_round.obj"), *ply = tmp_path("io_round.ply");
    CHECK(st_mesh_save(obj, &a, &e) == 0);
    st_mesh_init(&b);
    CHECKF(st_mesh_load(obj, &b, &e) == 0, "%s", e.msg);
    CHECK(same_positions(&b, &a, 1e-9) && same_faces(&b, &a) && same_tags(&b, &a));
    CHECK(st_mesh_save(ply, &b, &e) == 0);
    st_mesh_init(&c);
    CHECKF(st_mesh_load(ply, &c, &e) == 0, "%s", e.msg);
    CHECK(same_positions(&c, &b, 0) && same_faces(&c, &b) && c.ncreases == 0);
    /* A second PLY trip is bit-exact too, file included. */
    const char *ply2 = tmp_path("io_round2.ply");
    CHECK(st_mesh_save(ply2, &c, &e) == 0);
    size_t n1, n2;
    char *f1 = tl_read_file(ply, &n1), *f2 = tl_read_file(ply2, &n2);
    CHECK(f1 && f2 && n1 == n2 && memcmp(f1, f2, n1) == 0);
    free(f1);
    free(f2);
    st_mesh_free(&a);
    st_mesh_free(&b);
    st_mesh_free(&c);
}

/* Shared meshes through both writers keep every vertex and face. */
static void test_round_trip_file(const char *path)
{
    st_mesh a, b;
    st_error e;
    st_mesh_init(&a);
    st_mesh_init(&b);
    if (st_mesh_load(path, &a, &e)) {
        tl_skip("round trip of %s: %s", path, e.msg);
        return;
    }
    CHECK(st_mesh_save(tmp_path("io_trip.obj"), &a, &e) == 0);
    CHECK(st_mesh_load(tmp_path("io_trip.obj"), &b, &e) == 0);
    CHECKF(same_positions(&b, &a, 1e-9) && same_faces(&b, &a), "%s via OBJ", path);
    CHECK(st_mesh_save(tmp_path("io_trip.ply"), &a, &e) == 0);
    CHECK(st_mesh_load(tmp_path("io_trip.ply"), &b, &e) == 0);
    CHECKF(same_positions(&b, &a, 0) && same_faces(&b, &a), "%s via PLY", path);
    st_mesh_free(&a);
    st_mesh_free(&b);
}

static void test_normals_export(void)
{
    st_mesh a, b;
    st_error e;
    awkward_mesh(&a);
    a.normals = malloc(3 * a.nverts * sizeof *a.normals);
    for (uint32_t i = 0; i < 3 * a.nverts; i++) a.normals[i] = i % 3 == 2 ? 1.0 : 0.0;
    CHECK(st_mesh_save(tmp_path("io_normals.obj"), &a, &e) == 0);
    CHECK(st_mesh_save(tmp_path("io_normals.ply"), &a, &e) == 0);
    char *text = tl_read_file(tmp_path("io_normals.obj"), NULL);
    CHECK(text && strstr(text, "\nvn 0 0 1\n") && strstr(text, "\nf 1//1 2//2 4//4\n"));
    free(text);
    text = tl_read_file(tmp_path("io_normals.ply"), NULL);
    CHECK(text && strstr(text, "property double nx\nproperty double ny\nproperty double nz\n") &&
          strstr(text, "format binary_little_endian 1.0\n") && strstr(text, "property list uchar uint vertex_indices\n"));
    free(text);
    st_mesh_init(&b);
    CHECK(st_mesh_load(tmp_path("io_normals.obj"), &b, &e) == 0 && same_positions(&b, &a, 1e-9) && same_faces(&b, &a));
    CHECK(st_mesh_load(tmp_path("io_normals.ply"), &b, &e) == 0 && same_positions(&b, &a, 0) && same_faces(&b, &a));
    st_mesh_free(&a);
    st_mesh_free(&b);
}

/* Newell vectors (core/map/geometry.h) and the vertex normals every writer
 * uses (st_mesh_vertex_normals), degenerate cases included. */
static void test_newell_and_normals(void)
{
    static const double sq[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    static const float sqf[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    static const uint32_t ccw[] = {0, 1, 2, 3};
    double n[3], nf[3];
    st_newell_indexed(sq, ccw, 4, n);
    CHECKF(n[0] == 0 && n[1] == 0 && n[2] == 2, "unit square: (%g %g %g), want (0 0 2)", n[0], n[1], n[2]);
    st_newell_points_f(sqf, 4, nf);
    CHECK(nf[0] == n[0] && nf[1] == n[1] && nf[2] == n[2]);

    st_mesh m;
    if (load_text("io_newell_cube.obj", cube_obj, &m, NULL)) return;
    double *vn = malloc(3 * (size_t)m.nverts * sizeof *vn);
    CHECK(vn && st_mesh_vertex_normals(&m, vn) == 0);
    for (uint32_t v = 0; vn && v < m.nverts; v++)
        for (int k = 0; k < 3; k++)   /* corners of a cube centred at 0: along the diagonal, outwards */
            CHECKF(fabs(vn[3 * v + k] - m.pos[3 * v + k] / sqrt(3.0)) < 1e-15, "vertex %u normal %d: %g", v, k,
                   vn[3 * v + k]);
    free(vn);
    /* Each face of the map: 2 x its area (4) along its outward axis. */
    st_map map;
    st_error e;
    st_map_init(&map);
    CHECKF(st_map_from_mesh(&map, &m, &e) == 0, "%s", e.msg);
    st_dart_iter it;
    unsigned faces = 0;
    for (uint32_t d = st_dart_first(&map, 0, &it); d != ST_NIL; d = st_dart_next(&map, 0, &it)) {
        if (st_is_boundary(&map, d)) continue;
        st_face_newell(&map, d, 0, n);
        const double *p = st_dart_pos(&map, d, 0);
        int axis = fabs(n[0]) > 0 ? 0 : fabs(n[1]) > 0 ? 1 : 2;
        CHECKF(fabs(n[axis]) == 8 && n[(axis + 1) % 3] == 0 && n[(axis + 2) % 3] == 0 && n[axis] * p[axis] > 0,
               "face of dart %u: (%g %g %g)", d, n[0], n[1], n[2]);
        st_vertex_newell(&map, d, 0, nf);   /* a primal map: one point, no area */
        CHECK(nf[0] == 0 && nf[1] == 0 && nf[2] == 0);
        faces++;
    }
    CHECK(faces == 24);
    st_map_free(&map);
    st_mesh_free(&m);

    /* A vertex whose faces cancel out takes its first face's normal; one
     * with only a degenerate face, and one in no face, take +z. */
    static double pos[] = {0, 0, 0, 0, 1, 0, 0, 0, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4, 9, 9, 9};
    static uint32_t off[] = {0, 3, 6, 9}, idx[] = {0, 1, 2, 0, 2, 1, 3, 4, 5};
    st_mesh t;
    st_mesh_init(&t);
    t.nverts = 7; t.pos = pos; t.nfaces = 3; t.face_off = off; t.face_idx = idx;
    double out[21];
    CHECK(st_mesh_vertex_normals(&t, out) == 0);
    for (int v = 0; v < 7; v++) {
        int axis = v < 3 ? 0 : 2;   /* +x: the first face (0 1 2) of 0-2; +z for 3-6 */
        CHECKF(out[3 * v + axis] == 1 && out[3 * v + (axis + 1) % 3] == 0 && out[3 * v + (axis + 2) % 3] == 0,
               "vertex %d: (%g %g %g)", v, out[3 * v], out[3 * v + 1], out[3 * v + 2]);
    }
}

static void test_writer_errors(void)
{
    st_mesh a;
    st_error e = {0};
    awkward_mesh(&a);
    CHECK(st_mesh_save(STRATA_TMP "/no/such/dir/x.obj", &a, &e) == ST_ERR_IO && strstr(e.msg, "no/such/dir/x.obj"));
    CHECK(st_mesh_save(tmp_path("io_x.stl"), &a, &e) == ST_ERR_INVALID);
    a.face_idx[4] = 77;
    const char *path = tmp_path("io_bad_write.ply");
    remove(path);
    CHECK(st_mesh_save(path, &a, &e) == ST_ERR_INVALID && strstr(e.msg, "vertex 77"));
    CHECK(tl_read_file(path, NULL) == NULL);
    a.face_idx[4] = 2;
    a.pos[3] = NAN;
    CHECK(st_mesh_save_obj(path, &a, &e) == ST_ERR_GEOMETRY);
    st_mesh_free(&a);
}

static void test_lifetime(void)
{
    st_mesh a, b;
    awkward_mesh(&a);
    st_mesh_init(&b);
    double *pos = a.pos;
    st_mesh_move(&b, &a);
    CHECK(b.pos == pos && b.nverts == 5 && a.pos == NULL && a.nverts == 0 && a.boundary_interp == ST_BOUNDARY_UNSET);
    st_mesh_move(&b, &b);
    CHECK(b.pos == pos);
    awkward_mesh(&a);
    st_mesh_move(&b, &a);   /* frees b's old arrays first (ASan would see a leak) */
    st_mesh_free(&b);
    st_mesh_free(&b);
    CHECK(b.pos == NULL && b.nfaces == 0);
    st_notes n = {0};
    st_notes_add(&n, "%s %d", "x", 1);
    CHECK(n.count == 1 && strcmp(n.lines[0], "x 1") == 0);
    st_notes_free(&n);
    st_notes_free(&n);
    CHECK(st_notes_add(NULL, "ignored") == 0);
}

/* ---- assets ------------------------------------------------------------------------ */

static double signed_volume(const st_mesh *m)
{
    double vol = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        const double *a = m->pos + 3 * m->face_idx[m->face_off[f]];
        for (uint32_t c = m->face_off[f] + 1; c + 1 < m->face_off[f + 1]; c++) {
            const double *b = m->pos + 3 * m->face_idx[c], *d = m->pos + 3 * m->face_idx[c + 1];
            vol += (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
                    a[2] * (b[0] * d[1] - b[1] * d[0])) / 6;
        }
    }
    return vol;
}

static void test_assets(void)
{
    static const struct { const char *name; uint32_t v, f, maxdeg; int closed; } assets[] = {
        {"cube.obj", 8, 6, 4, 1},      {"tetrahedron.obj", 4, 4, 3, 1}, {"octahedron.obj", 6, 8, 3, 1},
        {"torus.obj", 96, 96, 4, 1},   {"mixed.obj", 9, 9, 4, 1},       {"open.obj", 25, 16, 4, 0},
        {"ngon.obj", 12, 8, 6, 1},
    };
    for (size_t i = 0; i < sizeof assets / sizeof assets[0]; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", STRATA_ASSETS, assets[i].name);
        st_mesh m;
        st_error e;
        st_notes n = {0};
        st_mesh_init(&m);
        int rc = st_mesh_load_notes(path, &m, &n, &e);
        CHECKF(rc == 0 && n.count == 0, "%s: rc %d, %u notes: %s", assets[i].name, rc, n.count, rc ? e.msg : "");
        st_notes_free(&n);
        if (rc) continue;
        uint32_t maxdeg = 0, mindeg = 99;
        for (uint32_t f = 0; f < m.nfaces; f++) {
            uint32_t d = m.face_off[f + 1] - m.face_off[f];
            maxdeg = d > maxdeg ? d : maxdeg;
            mindeg = d < mindeg ? d : mindeg;
        }
        CHECKF(m.nverts == assets[i].v && m.nfaces == assets[i].f && maxdeg == assets[i].maxdeg,
               "%s: %u vertices, %u faces, max degree %u", assets[i].name, m.nverts, m.nfaces, maxdeg);
        CHECKF(st_mesh_check(assets[i].name, &m, &e) == 0, "%s", e.msg);
        if (assets[i].closed) {
            CHECKF(signed_volume(&m) > 0, "%s faces inwards", assets[i].name);
        } else {
            /* the open grid lies in z = 0 and faces +z: its first face turns counter-clockwise */
            const double *p0 = m.pos + 3 * m.face_idx[0], *p1 = m.pos + 3 * m.face_idx[1], *p2 = m.pos + 3 * m.face_idx[2];
            CHECK((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]) > 0);
        }
        if (!strcmp(assets[i].name, "mixed.obj")) CHECK(mindeg == 3);
        st_mesh_free(&m);
    }
}

int main(void)
{
    test_obj_forms();
    test_obj_relative();
    test_obj_tag_pairs();
    test_obj_creasemethod();
    test_obj_holes();
    test_obj_big_faces();
    test_off_variants();
    test_ply_types();
    test_round_trips();
    test_round_trip_file(STRATA_SHARED_DATA "/catmull_clark/hexa_sphere.off");
    test_round_trip_file(STRATA_SHARED_DATA "/triangle/bob_small.ply");
    test_round_trip_file(STRATA_SHARED_DATA "/catmull_clark/newell_teapot_cage.obj");
    test_normals_export();
    test_newell_and_normals();
    test_writer_errors();
    test_lifetime();
    test_assets();
    return TEST_END();
}
