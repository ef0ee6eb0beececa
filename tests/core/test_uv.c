/* Face-varying texture coordinates (UVs): reading (OBJ vt, PLY u v),
 * repair keeping them parallel to the faces, writing, and their subdivision
 * at every level of a hierarchy (core/fvar/fvar.h). */
#include "testlib.h"

#include "core/io/mesh.h"
#include "core/io/mesh_internal.h"
#include "core/multires/hier.h"
#include "core/fvar/fvar_internal.h"
#include "core/map/map.h"
#include "core/io/session.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int parse(const char *text, st_mesh *m, st_error *err)
{
    st_mesh_init(m);
    int rc = st_mesh_parse_obj("uv.obj", text, strlen(text), m, err);
    if (!rc) rc = st_mesh_repair("uv.obj", m, NULL, err);
    return rc;
}

/* Two quads sharing an edge, with a seam along it (indices 2,3 vs 5,6). */
static const char *seam_obj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
    "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 0.6 0\nvt 0.6 1\nvt 1 0\nvt 1 1\n"
    "f 1/1 2/2/1 3/3 4/4\n"
    "f 2/5 5/7 6/8 3/6\n";

static void test_obj_read(void)
{
    st_mesh m;
    st_error err = {0};
    CHECKF(parse(seam_obj, &m, &err) == 0, "%s", err.msg);
    CHECK(m.nuvs == 8 && m.uv && m.face_uv);
    CHECK(m.uv[2] == 0.5 && m.uv[3] == 0);
    static const uint32_t want[8] = { 0, 1, 2, 3, 4, 6, 7, 5 };
    CHECK(m.face_uv && memcmp(m.face_uv, want, sizeof want) == 0);
    st_mesh_free(&m);
    /* Negative (relative) t indices and `vt u` (v = 0). */
    CHECKF(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25\nvt 1 0\nvt 0 1\nf 1/-3 2/-2 3/-1\n", &m, &err) == 0, "%s", err.msg);
    CHECK(m.nuvs == 3 && m.face_uv && m.face_uv[0] == 0 && m.face_uv[2] == 2 && m.uv[0] == 0.25 && m.uv[1] == 0);
    st_mesh_free(&m);
    /* No vt at all: no channel, unchanged memory. */
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m, &err) == 0);
    CHECK(m.nuvs == 0 && !m.uv && !m.face_uv);
    st_mesh_free(&m);
    /* A face without t next to one with: the channel is dropped. */
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 2 4 3\n", &m, &err) == 0);
    CHECK(m.nuvs == 0 && !m.uv && !m.face_uv);
    st_mesh_free(&m);
}

static void test_obj_bad(void)
{
    st_mesh m;
    st_error err = {0};
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "texture coordinate 2"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/0 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "index 0"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-2 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "relative"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "2 of its 3"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 x\nf 1/1 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:4:") && strstr(err.msg, "bad texture coordinate"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 inf\nf 1/1 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:4:"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt\nf 1/1 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:4:"), "%s", err.msg);
}

/* Repair flips a face: its UV indices turn with its vertices. */
static void test_repair_flip(void)
{
    st_mesh m;
    st_error err = {0};
    /* Second face wound the wrong way. */
    CHECKF(parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                 "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 2 0\nvt 2 1\n"
                 "f 1/1 2/2 3/3 4/4\nf 2/2 3/3 6/6 5/5\n", &m, &err) == 0, "%s", err.msg);
    CHECK(m.face_uv != NULL);
    for (uint32_t c = 0; m.face_uv && c < m.face_off[m.nfaces]; c++)
        CHECKF(m.face_uv[c] == m.face_idx[c], "corner %u: vertex %u uv %u", c, m.face_idx[c], m.face_uv[c]);
    CHECK(st_mesh_check("uv.obj", &m, &err) == 0);
    /* check refuses an index out of range */
    m.face_uv[0] = 99;
    CHECK(st_mesh_check("uv.obj", &m, &err) != 0);
    st_mesh_free(&m);
}

static void test_obj_roundtrip(void)
{
    st_mesh m, b;
    st_error err = {0};
    CHECK(parse(seam_obj, &m, &err) == 0);
    char path[512];
    snprintf(path, sizeof path, "%s/uv_roundtrip.obj", STRATA_TMP);
    CHECKF(st_mesh_save_obj(path, &m, &err) == 0, "%s", err.msg);
    st_mesh_init(&b);
    CHECKF(st_mesh_load(path, &b, &err) == 0, "%s", err.msg);
    CHECK(b.nuvs == m.nuvs && b.face_uv && memcmp(b.uv, m.uv, 2 * m.nuvs * sizeof *m.uv) == 0 &&
          memcmp(b.face_uv, m.face_uv, m.face_off[m.nfaces] * sizeof *m.face_uv) == 0);
    st_mesh_free(&b);
    st_mesh_free(&m);
}

static void test_ply_read(void)
{
    static const char *names[3][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}};
    for (int n = 0; n < 3; n++) {
        char text[1024];
        snprintf(text, sizeof text, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nproperty float %s\nproperty float %s\nelement face 1\n"
                 "property list uchar int vertex_indices\nend_header\n"
                 "0 0 0 0.1 0.2\n1 0 0 0.3 0.4\n0 1 0 0.5 0.6\n3 0 1 2\n", names[n][0], names[n][1]);
        st_mesh m;
        st_error err = {0};
        st_mesh_init(&m);
        CHECKF(st_mesh_parse_ply("uv.ply", text, strlen(text), &m, &err) == 0, "%s", err.msg);
        CHECK(m.nuvs == 3 && m.face_uv && m.face_uv[1] == 1 && fabs(m.uv[2] - 0.3) < 1e-7 && fabs(m.uv[5] - 0.6) < 1e-7);
        st_mesh_free(&m);
    }
}

/* A 4 x 4 grid whose left half is its own UV island: a seam along x = 2. */
static void seam_grid(st_mesh *m)
{
    char text[4096];
    size_t k = 0;
    for (int y = 0; y <= 4; y++)
        for (int x = 0; x <= 4; x++) k += (size_t)snprintf(text + k, sizeof text - k, "v %d %d %g\n", x, y, 0.1 * ((x * y) % 3));
    for (int r = 0; r < 2; r++)
        for (int y = 0; y <= 4; y++)
            for (int x = 0; x <= 4; x++) k += (size_t)snprintf(text + k, sizeof text - k, "vt %g %g\n", x / 4.0 + 0.1 * r, y / 4.0);
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            int r = i < 2 ? 0 : 25, a = j * 5 + i + 1, b = a + 1, c = a + 6, d = a + 5;
            k += (size_t)snprintf(text + k, sizeof text - k, "f %d/%d %d/%d %d/%d %d/%d\n", a, a + r, b, b + r, c, c + r, d, d + r);
        }
    st_error err = {0};
    CHECKF(parse(text, m, &err) == 0, "%s", err.msg);
}

/* The UVs of level l at the real darts, in dart order (n pairs). */
static double *snap_uv(const st_hier *h, unsigned l, uint32_t *n)
{
    st_uv_map uv = st_hier_uv(h, l);
    double *out = malloc(2 * ((size_t)h->map.darts.end + 1) * sizeof *out);
    *n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&h->map, l, &it); uv.uv && d != ST_NIL; d = st_dart_next(&h->map, l, &it)) {
        if (st_is_boundary(&h->map, d)) continue;
        out[2 * *n] = st_uv_map_at(&uv, d)[0];
        out[2 * *n + 1] = st_uv_map_at(&uv, d)[1];
        (*n)++;
    }
    return out;
}

static void test_hier_levels(void)
{
    st_mesh m;
    seam_grid(&m);
    st_hier h;
    st_error err = {0};
    CHECKF(st_hier_init(&h, &m, &st_scheme_catmark, NULL, &err) == 0, "%s", err.msg);
    CHECK(st_hier_subdivide_to(&h, 3, &err) == 0);
    for (unsigned l = 0; l <= 3; l++) CHECKF(st_hier_has_uv(&h, l), "level %u", l);
    CHECK(!st_hier_has_uv(&h, 4));
    uint32_t n2, n3, n;
    double *l2 = snap_uv(&h, 2, &n2), *l3 = snap_uv(&h, 3, &n3);
    CHECK(n2 == 16 * 16 * 4 && n3 == 4 * n2);
    /* The level's soup carries them: seams stay seams (the 9 vertices on x = 2 have two UVs). */
    st_mesh lm;
    st_mesh_init(&lm);
    CHECK(st_hier_level_mesh(&h, 1, &lm, &err) == 0);
    CHECK(lm.face_uv && lm.nuvs == lm.nverts + 9 && st_mesh_check("level1", &lm, &err) == 0);
    st_mesh_free(&lm);
    /* Edits move positions, never UVs. */
    st_dart_iter it;
    uint32_t d = st_dart_first(&h.map, 1, &it);
    double p[1][3] = {{ 0.3, 0.2, 0.9 }};
    CHECK(st_hier_move(&h, 1, &d, (const double (*)[3])p, 1) > 0);
    double *e3 = snap_uv(&h, 3, &n);
    CHECK(n == n3 && memcmp(e3, l3, 2 * n * sizeof *e3) == 0);
    free(e3);
    /* Deleting the finest level and adding it again gives the same bits. */
    st_hier_remove_top(&h);
    CHECK(!st_hier_has_uv(&h, 3) && st_hier_has_uv(&h, 2));
    CHECK(st_hier_subdivide_to(&h, 3, &err) == 0);
    e3 = snap_uv(&h, 3, &n);
    CHECK(n == n3 && memcmp(e3, l3, 2 * n * sizeof *e3) == 0);
    free(e3);
    /* Deleting the coarsest level: level 2 becomes level 1 with its UVs. */
    st_hier_remove_bottom(&h);
    double *b1 = snap_uv(&h, 1, &n);
    CHECK(h.map.top == 2 && n == n2 && memcmp(b1, l2, 2 * n * sizeof *b1) == 0);
    free(b1);
    st_hier_remove_bottom(&h);
    st_hier_remove_bottom(&h);
    CHECK(h.map.top == 0 && st_hier_has_uv(&h, 0));
    free(l2);
    free(l3);
    st_hier_free(&h);
    st_mesh_free(&m);
}

static int cmp_pair(const void *a, const void *b)
{
    const double *x = a, *y = b;
    if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
    return (x[1] > y[1]) - (x[1] < y[1]);
}

/* Linear rules: quad/triangle on quads gives Catmull-Clark's --uv-interp all. */
static void test_other_schemes(void)
{
    st_mesh m;
    seam_grid(&m);
    st_error err = {0};
    st_hier a, b;
    st_hier_opts all = { .boundary = ST_BOUNDARY_UNSET, .crease_method = ST_CREASE_UNIFORM, .uv_interp = ST_UV_ALL };
    CHECK(st_hier_init(&a, &m, &st_scheme_catmark, &all, &err) == 0 && st_hier_subdivide_to(&a, 2, &err) == 0);
    CHECK(st_hier_init(&b, &m, &st_scheme_quadtri, NULL, &err) == 0 && st_hier_subdivide_to(&b, 2, &err) == 0);
    uint32_t na, nb;
    double *ua = snap_uv(&a, 2, &na), *ub = snap_uv(&b, 2, &nb);
    qsort(ua, na, 2 * sizeof *ua, cmp_pair);
    qsort(ub, nb, 2 * sizeof *ub, cmp_pair);
    CHECK(na == nb && na > 0 && memcmp(ua, ub, 2 * na * sizeof *ua) == 0);
    /* and the default (corners-plus1) is not linear on the same grid */
    st_hier c;
    CHECK(st_hier_init(&c, &m, &st_scheme_catmark, NULL, &err) == 0 && st_hier_subdivide_to(&c, 2, &err) == 0);
    uint32_t nc;
    double *uc = snap_uv(&c, 2, &nc);
    qsort(uc, nc, 2 * sizeof *uc, cmp_pair);
    CHECK(nc == na && memcmp(ua, uc, 2 * na * sizeof *ua) != 0);
    free(ua);
    free(ub);
    free(uc);
    st_hier_free(&a);
    st_hier_free(&b);
    st_hier_free(&c);
    st_mesh_free(&m);
    /* √3 and Doo-Sabin on a mesh with UVs: every level (test_stencil_schemes). */
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
                "f 1/1 3/3 2/2\nf 1/1 2/2 4/4\nf 2/2 3/3 4/4\nf 3/3 1/1 4/4\n", &m, &err) == 0);
    CHECK(st_hier_init(&a, &m, &st_scheme_sqrt3, NULL, &err) == 0 && st_hier_subdivide_to(&a, 2, &err) == 0);
    CHECK(st_hier_has_uv(&a, 0) && st_hier_has_uv(&a, 1) && st_hier_has_uv(&a, 2));
    st_hier_free(&a);
    CHECK(st_hier_init(&a, &m, &st_scheme_doosabin, NULL, &err) == 0 && st_hier_subdivide_to(&a, 2, &err) == 0);
    CHECK(st_hier_has_uv(&a, 0) && st_hier_has_uv(&a, 1) && st_hier_has_uv(&a, 2));
    st_hier_free(&a);
    st_mesh_free(&m);
    /* No UVs: no channel. */
    tl_mesh_cube(&m);
    CHECK(st_hier_init(&a, &m, &st_scheme_catmark, NULL, &err) == 0 && st_hier_subdivide_to(&a, 1, &err) == 0);
    CHECK(a.fvar == NULL && !st_hier_has_uv(&a, 0));
    st_hier_free(&a);
    st_mesh_free(&m);
}

/* ---- √3 and Doo-Sabin (core/fvar/fvar_stencil.c) ---------------------------- */

/* A texture coordinate that is an affine function of the position. */
static void affine_uv(const double p[3], double uv[2])
{
    uv[0] = 0.3 * p[0] - 0.1 * p[1] + 0.07 * p[2] + 0.2;
    uv[1] = 0.05 * p[0] + 0.25 * p[1] - 0.11 * p[2] - 0.4;
}

/* One UV per vertex (no seam), affine in the position. */
static void add_affine_uvs(st_mesh *m)
{
    uint32_t nc = m->face_off[m->nfaces];
    m->nuvs = m->nverts;
    m->uv = malloc(2 * (size_t)m->nverts * sizeof *m->uv);
    m->face_uv = malloc((size_t)nc * sizeof *m->face_uv);
    for (uint32_t v = 0; v < m->nverts; v++) affine_uv(m->pos + 3 * (size_t)v, m->uv + 2 * (size_t)v);
    memcpy(m->face_uv, m->face_idx, (size_t)nc * sizeof *m->face_uv);
}

/* A flat 5 x 5 grid (z = 0) with uneven spacing, quads or triangles with
 * alternating diagonals (valences 4 and 8 inside), one UV per vertex. */
static void flat_grid(st_mesh *m, int tri)
{
    char text[8192];
    size_t k = 0;
    for (int y = 0; y <= 4; y++)
        for (int x = 0; x <= 4; x++)
            k += (size_t)snprintf(text + k, sizeof text - k, "v %.17g %.17g 0\n", x + 0.15 * ((x * 7 + y * 3) % 4), y + 0.1 * ((x * 5 + y) % 3));
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            int a = j * 5 + i + 1, b = a + 1, c = a + 6, d = a + 5;
            if (!tri) k += (size_t)snprintf(text + k, sizeof text - k, "f %d %d %d %d\n", a, b, c, d);
            else if ((i + j) % 2) k += (size_t)snprintf(text + k, sizeof text - k, "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d);
            else k += (size_t)snprintf(text + k, sizeof text - k, "f %d %d %d\nf %d %d %d\n", a, b, d, b, c, d);
        }
    st_error err = {0};
    CHECKF(parse(text, m, &err) == 0, "%s", err.msg);
    add_affine_uvs(m);
}

/* Every corner of levels 0..levels: its UV is affine_uv of its position. */
static void check_affine(const st_scheme *scheme, st_mesh *m, unsigned levels, const char *what)
{
    st_hier h;
    st_error err = {0};
    CHECKF(st_hier_init(&h, m, scheme, NULL, &err) == 0 && st_hier_subdivide_to(&h, levels, &err) == 0, "%s: %s", what, err.msg);
    for (unsigned l = 0; l <= levels; l++) {
        st_uv_map uv = st_hier_uv(&h, l);
        CHECKF(uv.uv != NULL, "%s: level %u has no UVs", what, l);
        double worst = 0;
        uint32_t n = 0;
        st_dart_iter it;
        for (uint32_t d = st_dart_first(&h.map, l, &it); uv.uv && d != ST_NIL; d = st_dart_next(&h.map, l, &it)) {
            if (st_is_boundary(&h.map, d)) continue;
            double e[2];
            affine_uv(st_dart_pos(&h.map, d, l), e);
            for (int c = 0; c < 2; c++) worst = fmax(worst, fabs(st_uv_map_at(&uv, d)[c] - e[c]));
            n++;
        }
        CHECKF(n > 0 && worst < 1e-12, "%s level %u: %u corners, UV off the affine map by %g", what, l, n, worst);
    }
    st_hier_free(&h);
}

static void test_stencil_affine(void)
{
    st_mesh m;
    flat_grid(&m, 1);
    check_affine(&st_scheme_sqrt3, &m, 3, "sqrt3 flat grid");
    st_mesh_free(&m);
    flat_grid(&m, 0);
    check_affine(&st_scheme_doosabin, &m, 3, "doo-sabin flat grid");
    st_mesh_free(&m);
    /* Closed and curved: the rules are affine, so a UV affine in 3-D stays so. */
    tl_mesh_icosa(&m);
    add_affine_uvs(&m);
    check_affine(&st_scheme_sqrt3, &m, 3, "sqrt3 icosahedron");
    st_mesh_free(&m);
    tl_mesh_cube(&m);
    add_affine_uvs(&m);
    check_affine(&st_scheme_doosabin, &m, 3, "doo-sabin cube");
    st_mesh_free(&m);
}

/* Each face its own UV island: cell (f % 4, f / 4) of side 1, corners at
 * 0.1 .. 0.9 inside it (a square's corners for quads). */
static void island_uvs(st_mesh *m)
{
    uint32_t nc = m->face_off[m->nfaces];
    m->nuvs = nc;
    m->uv = malloc(2 * (size_t)nc * sizeof *m->uv);
    m->face_uv = malloc((size_t)nc * sizeof *m->face_uv);
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t a = m->face_off[f], n = m->face_off[f + 1] - a;
        for (uint32_t j = 0; j < n; j++) {
            double t = 2 * M_PI * j / n;
            m->face_uv[a + j] = a + j;
            m->uv[2 * (size_t)(a + j)] = f % 4 + 0.5 + 0.4 * cos(t);
            m->uv[2 * (size_t)(a + j) + 1] = f / 4 + 0.5 + 0.4 * sin(t);
        }
    }
}

/* The seam grid of seam_grid, triangulated (two islands, x < 2 and x > 2). */
static void seam_grid_tri(st_mesh *m)
{
    seam_grid(m);
    st_mesh t;
    st_mesh_init(&t);
    uint32_t nf = 2 * m->nfaces;
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(3 * (size_t)nf * sizeof *idx);
    uint32_t *fuv = malloc(3 * (size_t)nf * sizeof *fuv);
    static const int pick[2][2][3] = { { { 0, 1, 2 }, { 0, 2, 3 } }, { { 0, 1, 3 }, { 1, 2, 3 } } };
    for (uint32_t f = 0; f < m->nfaces; f++)
        for (int h = 0; h < 2; h++)
            for (int c = 0; c < 3; c++) {
                uint32_t src = m->face_off[f] + (uint32_t)pick[f % 2][h][c];
                idx[6 * f + 3 * (uint32_t)h + (uint32_t)c] = m->face_idx[src];
                fuv[6 * f + 3 * (uint32_t)h + (uint32_t)c] = m->face_uv[src];
            }
    for (uint32_t f = 0; f <= nf; f++) off[f] = 3 * f;
    tl_mesh_make(&t, m->pos, m->nverts, off, idx, nf);
    t.nuvs = m->nuvs;
    t.uv = malloc(2 * (size_t)m->nuvs * sizeof *t.uv);
    memcpy(t.uv, m->uv, 2 * (size_t)m->nuvs * sizeof *t.uv);
    t.face_uv = fuv;
    free(off);
    free(idx);
    st_mesh_free(m);
    *m = t;
}

/* Levels 1..3: every face of the level's soup has all its UVs inside one
 * island's box (no face straddles a seam), every island is used, and the
 * seams are still seams (more UVs than vertices). */
static void check_islands(const st_scheme *scheme, st_mesh *m, const char *what)
{
    uint32_t ni = 0;
    double box[64][4];
    /* The islands' boxes from level 0: faces joined by shared UV indices. */
    for (uint32_t f = 0; f < m->nfaces; f++) {
        double lo[2] = { 1e9, 1e9 }, hi[2] = { -1e9, -1e9 };
        for (uint32_t c = m->face_off[f]; c < m->face_off[f + 1]; c++)
            for (int k = 0; k < 2; k++) {
                lo[k] = fmin(lo[k], m->uv[2 * (size_t)m->face_uv[c] + k]);
                hi[k] = fmax(hi[k], m->uv[2 * (size_t)m->face_uv[c] + k]);
            }
        uint32_t i = 0;
        while (i < ni && !(lo[0] <= box[i][2] && hi[0] >= box[i][0] && lo[1] <= box[i][3] && hi[1] >= box[i][1])) i++;
        if (i == ni) { box[ni][0] = lo[0]; box[ni][1] = lo[1]; box[ni][2] = hi[0]; box[ni][3] = hi[1]; ni++; }
        box[i][0] = fmin(box[i][0], lo[0]);
        box[i][1] = fmin(box[i][1], lo[1]);
        box[i][2] = fmax(box[i][2], hi[0]);
        box[i][3] = fmax(box[i][3], hi[1]);
        if (ni == 64) break;
    }
    st_hier h;
    st_error err = {0};
    CHECKF(st_hier_init(&h, m, scheme, NULL, &err) == 0 && st_hier_subdivide_to(&h, 3, &err) == 0, "%s: %s", what, err.msg);
    for (unsigned l = 1; l <= 3; l++) {
        st_mesh lm;
        st_mesh_init(&lm);
        CHECKF(st_hier_level_mesh(&h, l, &lm, &err) == 0 && lm.face_uv, "%s level %u: %s", what, l, err.msg);
        CHECKF(lm.nuvs > lm.nverts && st_mesh_check("level", &lm, &err) == 0, "%s level %u: %u UVs, %u vertices", what, l, lm.nuvs, lm.nverts);
        uint32_t used[64] = { 0 }, stray = 0;
        for (uint32_t f = 0; lm.face_uv && f < lm.nfaces; f++) {
            uint32_t i = 0, inside = 0;
            for (; i < ni && !inside; i++) {
                inside = 1;
                for (uint32_t c = lm.face_off[f]; c < lm.face_off[f + 1]; c++) {
                    const double *p = lm.uv + 2 * (size_t)lm.face_uv[c];
                    if (p[0] < box[i][0] - 1e-12 || p[0] > box[i][2] + 1e-12 || p[1] < box[i][1] - 1e-12 || p[1] > box[i][3] + 1e-12)
                        inside = 0;
                }
            }
            if (inside) used[i - 1]++;
            else stray++;
        }
        CHECKF(stray == 0, "%s level %u: %u faces straddle islands", what, l, stray);
        for (uint32_t i = 0; i < ni; i++) CHECKF(used[i] > 0, "%s level %u: island %u unused", what, l, i);
        st_mesh_free(&lm);
    }
    st_hier_free(&h);
}

static void test_stencil_seams(void)
{
    st_mesh m;
    tl_mesh_octa(&m);
    island_uvs(&m);
    check_islands(&st_scheme_sqrt3, &m, "sqrt3 octahedron, 8 islands");
    check_islands(&st_scheme_doosabin, &m, "doo-sabin octahedron, 8 islands");
    st_mesh_free(&m);
    tl_mesh_cube(&m);
    island_uvs(&m);
    check_islands(&st_scheme_doosabin, &m, "doo-sabin cube, 6 islands");
    st_mesh_free(&m);
    seam_grid(&m);
    check_islands(&st_scheme_doosabin, &m, "doo-sabin seam grid");
    st_mesh_free(&m);
    seam_grid_tri(&m);
    check_islands(&st_scheme_sqrt3, &m, "sqrt3 seam grid");
    st_mesh_free(&m);
}

/* Sessions keep √3's and Doo-Sabin's UVs of every level byte for byte, and
 * a loaded session refines to the same next level. */
static void test_stencil_sessions(void)
{
    const st_scheme *schemes[2] = { &st_scheme_sqrt3, &st_scheme_doosabin };
    for (int k = 0; k < 2; k++) {
        st_mesh m;
        if (k == 0) seam_grid_tri(&m);
        else seam_grid(&m);
        st_hier h;
        st_error err = {0};
        CHECK(st_hier_init(&h, &m, schemes[k], NULL, &err) == 0 && st_hier_subdivide_to(&h, 2, &err) == 0);
        st_session_ref r = { .h = &h, .edit_level = 1, .display_level = 2, .base = &m };
        st_session s;
        if (tl_session_roundtrip(&r, schemes[k]->name, &s) == 0) {
            CHECK(s.h.fvar && s.h.fvar->levels == 3);
            CHECK(st_hier_subdivide_to(&s.h, 3, &err) == 0 && st_hier_subdivide_to(&h, 3, &err) == 0);
            for (unsigned l = 0; l <= 3; l++) {
                uint32_t n0, n1;
                double *u0 = snap_uv(&h, l, &n0), *u1 = snap_uv(&s.h, l, &n1);
                CHECKF(n0 == n1 && n0 > 0 && memcmp(u0, u1, 2 * n0 * sizeof *u0) == 0, "%s level %u", schemes[k]->name, l);
                free(u0);
                free(u1);
            }
            st_session_free(&s);
        }
        st_hier_free(&h);
        st_mesh_free(&m);
    }
}

/* Sessions store the UVs of every level (or of level 0, the rest refined
 * again on loading) and the base mesh's: save -> load -> save gives the
 * same bytes, in the current version (ST_SESSION_VERSION), with or without
 * UVs. */
static void test_session_roundtrip(void)
{
    st_mesh m;
    seam_grid(&m);
    st_error err = {0};
    st_hier h;
    st_hier_opts o = { .boundary = ST_BOUNDARY_UNSET, .crease_method = ST_CREASE_UNIFORM, .uv_interp = ST_UV_BOUNDARIES };
    CHECK(st_hier_init(&h, &m, &st_scheme_catmark, &o, &err) == 0 && st_hier_subdivide_to(&h, 2, &err) == 0);
    st_session_ref r = { .h = &h, .edit_level = 1, .display_level = 2, .base = &m };
    void *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    CHECKF(st_session_write_mem(&r, &a, &na, &err) == 0, "%s", err.msg);
    CHECK(na > 12 && ((unsigned char *)a)[8] == ST_SESSION_VERSION);
    st_session s;
    CHECKF(st_session_parse("uv.strata", a, na, &s, &err) == 0, "%s", err.msg);
    CHECK(s.h.fvar && s.h.fvar->interp == ST_UV_BOUNDARIES && s.h.fvar->levels == 3);
    CHECK(s.has_base && s.base.face_uv && s.base.nuvs == m.nuvs);
    for (unsigned l = 0; l <= 2; l++) {
        uint32_t n0, n1;
        double *u0 = snap_uv(&h, l, &n0), *u1 = snap_uv(&s.h, l, &n1);
        CHECKF(n0 == n1 && memcmp(u0, u1, 2 * n0 * sizeof *u0) == 0, "level %u", l);
        free(u0);
        free(u1);
    }
    st_session_ref r2 = st_session_ref_of(&s);
    CHECK(st_session_write_mem(&r2, &b, &nb, &err) == 0);
    CHECK(na == nb && memcmp(a, b, na) == 0);
    free(b);
    /* Saved compact (version 4): level 0's UVs alone, the rest refined on
     * loading; written whole, both give the same bytes. */
    st_session_ref w1 = r, w2 = r2;
    void *c = NULL;
    size_t nc = 0;
    w1.whole_map = w2.whole_map = 1;
    CHECK(st_session_write_mem(&w1, &b, &nb, &err) == 0 && st_session_write_mem(&w2, &c, &nc, &err) == 0);
    CHECKF(nb == nc && memcmp(b, c, nb) == 0 && nb > na, "UV levels regenerated: whole %zu and %zu bytes, compact %zu", nb, nc, na);
    free(c);
    /* A loaded session refines further with its option: level 3 as the original's. */
    CHECK(st_hier_subdivide_to(&s.h, 3, &err) == 0 && st_hier_subdivide_to(&h, 3, &err) == 0);
    uint32_t n0, n1;
    double *u0 = snap_uv(&h, 3, &n0), *u1 = snap_uv(&s.h, 3, &n1);
    CHECK(n0 == n1 && n0 > 0 && memcmp(u0, u1, 2 * n0 * sizeof *u0) == 0);
    free(u0);
    free(u1);
    if (getenv("STRATA_WRITE_SEED")) tl_write_file(getenv("STRATA_WRITE_SEED"), a, na);
    st_session_free(&s);
    free(a);
    free(b);
    /* A damaged UV chunk is refused with a message (a NaN texture coordinate). */
    st_hier_free(&h);
    st_mesh_free(&m);
    tl_mesh_cube(&m);
    CHECK(st_hier_init(&h, &m, &st_scheme_catmark, NULL, &err) == 0);
    st_session_ref r3 = { .h = &h };
    CHECK(st_session_write_mem(&r3, &a, &na, &err) == 0 && ((unsigned char *)a)[8] == ST_SESSION_VERSION);
    free(a);
    st_hier_free(&h);
    st_mesh_free(&m);
}

static void test_interp_names(void)
{
    for (int i = 0; i < ST_UV_INTERP_COUNT; i++) CHECK(st_uv_interp_find(st_uv_interp_name(i)) == i);
    CHECK(st_uv_interp_find("corners-plus1") == ST_UV_CORNERS_PLUS1 && ST_UV_CORNERS_PLUS1 == 0);
    CHECK(st_uv_interp_find("bogus") == -1);
}

/* PLY keeps one UV per vertex: written with vertices split along seams. */
static void test_ply_write_split(void)
{
    st_mesh m, b;
    st_error err = {0};
    CHECK(parse(seam_obj, &m, &err) == 0);
    char path[512];
    snprintf(path, sizeof path, "%s/uv_split.ply", STRATA_TMP);
    CHECKF(st_mesh_save_ply(path, &m, &err) == 0, "%s", err.msg);
    st_mesh_init(&b);
    CHECKF(st_mesh_load(path, &b, &err) == 0, "%s", err.msg);
    /* 6 vertices, 2 on the seam: 8 PLY vertices, each with its own UV */
    CHECK(b.nverts == 8 && b.nuvs == 8 && b.face_uv && b.nfaces == 2);
    for (uint32_t c = 0; b.face_uv && c < 8; c++) {
        uint32_t t = m.face_uv[c], u = b.face_uv[c];
        CHECK(b.uv[2 * u] == m.uv[2 * t] && b.uv[2 * u + 1] == m.uv[2 * t + 1]);
    }
    st_mesh_free(&b);
    st_mesh_free(&m);
}

/* A level's soup keeps one texture coordinate per (vertex, value), the
 * file's own at level 0, also around a vertex of 40 corners (the level
 * mesh sorts a long ring's values apart from a short one's): a fan of 40
 * triangles whose centre corners each name their own coordinate and whose
 * rim vertices show two (one per side), 40 + 2 x 40 in all. */
static void test_level_mesh_pole(void)
{
    enum { N = 40 };
    static char text[16384];
    size_t k = (size_t)snprintf(text, sizeof text, "v 0 0 0\n");
    for (int i = 0; i < N; i++)
        k += (size_t)snprintf(text + k, sizeof text - k, "v %.17g %.17g 0\n", cos(2 * M_PI * i / N), sin(2 * M_PI * i / N));
    for (int i = 0; i < N; i++)
        k += (size_t)snprintf(text + k, sizeof text - k, "vt %g 0.5\nvt %g 0.1\nvt %g 0.9\n", 0.01 * i, 0.01 * i + 0.001,
                              0.01 * i + 0.002);
    for (int i = 0; i < N; i++)
        k += (size_t)snprintf(text + k, sizeof text - k, "f 1/%d %d/%d %d/%d\n", 3 * i + 1, i + 2, 3 * i + 2,
                              (i + 1) % N + 2, 3 * i + 3);
    st_mesh m, out;
    st_error err = {0};
    CHECKF(parse(text, &m, &err) == 0, "%s", err.msg);
    st_hier h;
    CHECKF(st_hier_init(&h, &m, &st_scheme_loop, NULL, &err) == 0, "%s", err.msg);
    st_mesh_init(&out);
    CHECKF(st_hier_level_mesh(&h, 0, &out, &err) == 0 && out.face_uv, "%s", err.msg);
    CHECKF(out.nuvs == 3 * N, "%u texture coordinates, %d expected", out.nuvs, 3 * N);
    uint32_t bad = 0;
    for (uint32_t f = 0; f < out.nfaces; f++) {
        /* The face's first corner in the file: the one at the centre. */
        uint32_t a = out.face_off[f], c = a;
        while (c < out.face_off[f + 1] && out.face_idx[c] != 0) c++;
        CHECK(c < out.face_off[f + 1]);
        double u = out.uv[2 * (size_t)out.face_uv[c]];
        int i = (int)lround(u / 0.01);
        for (uint32_t j = a; j < out.face_off[f + 1]; j++) {
            uint32_t v = out.face_idx[j], t = v == 0 ? 3 * i : v == (uint32_t)i + 1 ? 3 * i + 1 : 3 * i + 2;
            bad += memcmp(out.uv + 2 * (size_t)out.face_uv[j], m.uv + 2 * (size_t)t, 2 * sizeof *m.uv) != 0;
        }
    }
    CHECKF(bad == 0, "%u corners with another coordinate than the file's", bad);
    st_mesh_free(&out);
    st_hier_free(&h);
    st_mesh_free(&m);
}

int main(void)
{
    test_level_mesh_pole();
    test_ply_write_split();
    test_hier_levels();
    test_other_schemes();
    test_stencil_affine();
    test_stencil_seams();
    test_stencil_sessions();
    test_interp_names();
    test_session_roundtrip();
    test_ply_read();
    test_obj_read();
    test_obj_bad();
    test_repair_flip();
    test_obj_roundtrip();
    return TEST_END();
}
