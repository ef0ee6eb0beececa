/* Quad/triangle scheme: reductions to Catmull-Clark (meshes without
 * triangles, and pure-quad regions of mixed meshes) and to Loop (meshes of
 * triangles, and pure-triangle regions), hand-computed values on a
 * triangular prism, the house asset (mixed.obj) and the chamfered cube,
 * and the multiresolution checks.  cli_oracle_quadtri.sh compares the
 * reductions with OpenSubdiv on real meshes. */
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Open 4 x 4 grid of squares cut by diagonals, bumpy z. */
static void tri_grid(st_mesh *s)
{
    const unsigned n = 4;
    uint32_t nv = (n + 1) * (n + 1), nf = 2 * n * n;
    double p[3 * 25];
    uint32_t off[33], idx[96];
    for (unsigned j = 0; j <= n; j++)
        for (unsigned i = 0; i <= n; i++) {
            double *q = p + 3 * (j * (n + 1) + i);
            q[0] = i; q[1] = j; q[2] = 0.1 * ((i * 7 + j * 3) % 5);
        }
    uint32_t f = 0;
    for (unsigned j = 0; j < n; j++)
        for (unsigned i = 0; i < n; i++) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            uint32_t t[6] = { a, b, c, a, c, d };
            memcpy(idx + 3 * f, t, sizeof t);
            f += 2;
        }
    for (uint32_t k = 0; k <= nf; k++) off[k] = 3 * k;
    tl_mesh_make(s, p, nv, off, idx, nf);
}

/* Triangular prism: bottom A(0,0,0) B(1,0,0) C(0,1,0), top D E F = +z.
 * 2 triangles, 3 quads; every vertex: 2 quads + 1 triangle. */
static void prism(st_mesh *s)
{
    static const double p[] = { 0,0,0, 1,0,0, 0,1,0, 0,0,1, 1,0,1, 0,1,1 };
    static const uint32_t off[] = { 0, 3, 6, 10, 14, 18 };
    static const uint32_t idx[] = { 0,2,1, 3,4,5, 0,1,4,3, 1,2,5,4, 2,0,3,5 };
    tl_mesh_make(s, p, 6, off, idx, 5);
}

/* Open mixed strip: a 4 x 3 grid whose left half is quads and right half
 * triangles (boundary, seams, mixed vertices). */
static void mixed_grid(st_mesh *s)
{
    const unsigned nx = 4, ny = 3;
    double p[3 * 20];
    uint32_t off[32], idx[96], nf = 0, k = 0;
    for (unsigned j = 0; j <= ny; j++)
        for (unsigned i = 0; i <= nx; i++) {
            double *q = p + 3 * (j * (nx + 1) + i);
            q[0] = i; q[1] = j; q[2] = 0.2 * ((i * 5 + j * 2) % 3);
        }
    for (unsigned j = 0; j < ny; j++)
        for (unsigned i = 0; i < nx; i++) {
            uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
            if (i < nx / 2) {
                off[nf++] = k;
                idx[k++] = a; idx[k++] = b; idx[k++] = c; idx[k++] = d;
            } else {
                off[nf++] = k;
                idx[k++] = a; idx[k++] = b; idx[k++] = c;
                off[nf++] = k;
                idx[k++] = a; idx[k++] = c; idx[k++] = d;
            }
        }
    off[nf] = k;
    tl_mesh_make(s, p, 20, off, idx, nf);
}

static void cube(st_mesh *s) { tl_mesh_cube(s); }
static void torus(st_mesh *s) { tl_mesh_torus(s, 8, 6); }
static void grid(st_mesh *s) { tl_mesh_grid(s, 4); }

static int load_file(st_mesh *s, const char *path)
{
    st_error err;
    st_mesh_init(s);
    int rc = st_mesh_load(path, s, &err);
    if (rc) fprintf(stderr, "note: %s\n", err.msg);
    return rc;
}
static void house(st_mesh *s) { CHECK(load_file(s, STRATA_ASSETS "/mixed.obj") == 0); }
static void ngon(st_mesh *s) { CHECK(load_file(s, STRATA_ASSETS "/ngon.obj") == 0); }

static int near3(const double *p, double x, double y, double z, double tol)
{
    return fabs(p[0] - x) <= tol && fabs(p[1] - y) <= tol && fabs(p[2] - z) <= tol;
}

static int count_at(const st_hier *h, unsigned l, double x, double y, double z)
{
    int n = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
        n += near3(st_pos(&h->map, v, l), x, y, z, 1e-14);
    return n;
}

static void build(st_hier *h, void (*make)(st_mesh *), const st_scheme *sc, int boundary, unsigned levels)
{
    st_mesh s;
    st_error err;
    make(&s);
    st_hier_opts o = { .boundary = boundary, .crease_method = ST_CREASE_UNIFORM };
    int rc = st_hier_init(h, &s, sc, &o, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    st_mesh_free(&s);
    rc = st_hier_subdivide_to(h, levels, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
}

/* Same topology (same split code for quads and for triangles), so vertex
 * ids agree: compare every position of every level. */
static void check_same_as(void (*make)(st_mesh *), const st_scheme *ref, int boundary, unsigned levels, const char *what)
{
    st_hier a, b;
    build(&a, make, &st_scheme_quadtri, boundary, levels);
    build(&b, make, ref, boundary, levels);
    CHECK(a.map.verts.end == b.map.verts.end);
    double worst = 0;
    for (unsigned l = 0; l <= levels; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&a.map, l, &it); v != ST_NIL; v = st_vertex_next(&a.map, l, &it)) {
            const double *p = st_pos(&a.map, v, l), *q = st_pos(&b.map, v, l);
            for (int i = 0; i < 3; i++) worst = fmax(worst, fabs(p[i] - q[i]));
        }
    }
    CHECKF(worst < 1e-13, "%s: quad-triangle differs from %s by %g", what, ref->name, worst);
    st_hier_free(&a);
    st_hier_free(&b);
}

static void test_reductions(void)
{
    check_same_as(cube, &st_scheme_catmark, ST_BOUNDARY_EDGE_ONLY, 3, "cube");
    check_same_as(torus, &st_scheme_catmark, ST_BOUNDARY_EDGE_ONLY, 3, "torus");
    check_same_as(grid, &st_scheme_catmark, ST_BOUNDARY_EDGE_ONLY, 3, "grid");
    check_same_as(grid, &st_scheme_catmark, ST_BOUNDARY_EDGE_AND_CORNER, 3, "grid corners");
    check_same_as(ngon, &st_scheme_catmark, ST_BOUNDARY_EDGE_ONLY, 3, "ngon.obj");
    check_same_as(tl_mesh_tetra, &st_scheme_loop, ST_BOUNDARY_EDGE_ONLY, 3, "tetra");
    check_same_as(tl_mesh_icosa, &st_scheme_loop, ST_BOUNDARY_EDGE_ONLY, 3, "icosahedron");
    check_same_as(tri_grid, &st_scheme_loop, ST_BOUNDARY_EDGE_ONLY, 3, "tri grid");
    check_same_as(tri_grid, &st_scheme_loop, ST_BOUNDARY_EDGE_AND_CORNER, 3, "tri grid corners");
}

/* Prism, level 1, by hand (A = origin; q1 = centroid of ABED = (1/2,0,1/2),
 * q3 = centroid of CADF = (0,1/2,1/2)):
 *   vertex A: nq = 2, nt = 1, ω = 12/8 = 3/2; n·c̄ = [5/8 A + 3/16 (B+C)]
 *     + [1/2 A + 1/8 (B+D) + 1/4 q1] + [1/2 A + 1/8 (C+D) + 1/4 q3]
 *     = (7/16, 7/16, 1/2); A' = ω c̄ = (7/32, 7/32, 1/4);
 *   edge AB (triangle ACB, quad ABED): regular seam (ω = 1):
 *     13/40 (A+B) + 3/20 C + 1/5 q1 = (17/40, 3/20, 1/10);
 *   edge AD (two quads): Catmull-Clark (A + D + q1 + q3)/4 = (1/8, 1/8, 1/2);
 *   face point of ABED: its centroid (1/2, 0, 1/2). */
static void test_prism_values(void)
{
    st_hier h;
    tl_init_hier(&h, prism, ST_SCHEME_QUADTRI, 1);
    CHECK(near3(st_pos(&h.map, 0, 1), 7.0 / 32, 7.0 / 32, 0.25, 1e-15));
    CHECK(count_at(&h, 1, 17.0 / 40, 3.0 / 20, 0.1) == 1);
    CHECK(count_at(&h, 1, 0.125, 0.125, 0.5) == 1);
    CHECK(count_at(&h, 1, 0.5, 0, 0.5) == 1);
    st_level_stats s;
    st_level_stats_compute(&h.map, 1, &s);
    CHECK(s.faces == 20 && s.vertices == 6 + 9 + 3);
    st_hier_free(&h);
}

/* Dart of level l from u to w, ST_NIL if none. */
static uint32_t dart_between(const st_map *m, unsigned l, uint32_t u, uint32_t w)
{
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it))
        if (st_vert(m, d, l) == u && st_vert(m, st_beta0(m, d, l), l) == w) return d;
    return ST_NIL;
}

/* House (mixed.obj: 5 quads of a cube without its top, 4 roof triangles):
 *   - pure-quad region: the floor corners (vertices 0-3: floor + 2 walls)
 *     and the edges between two quads move exactly as Catmull-Clark;
 *   - pure-triangle region: the apex (valence 4, Loop β = 31/256):
 *     (1 - 124/256) (0,0,2) + 31/256 · 4 · (0,0,1) = (0, 0, 97/64); the roof
 *     edge apex-(1,1,1) (both faces triangles): 3/8 ((0,0,2) + (1,1,1))
 *     + 1/8 ((-1,1,1) + (1,-1,1)) = (3/8, 3/8, 11/8). */
static void test_house_regions(void)
{
    st_hier q, c;
    build(&q, house, &st_scheme_quadtri, ST_BOUNDARY_EDGE_ONLY, 1);
    build(&c, house, &st_scheme_catmark, ST_BOUNDARY_EDGE_ONLY, 1);
    for (uint32_t v = 0; v < 4; v++) {
        const double *a = st_pos(&q.map, v, 1), *b = st_pos(&c.map, v, 1);
        CHECKF(near3(a, b[0], b[1], b[2], 1e-15), "floor corner %u", v);
    }
    /* Edges of level 0 between two quads: the edge point ids agree
     * (edges are split before faces in both). */
    unsigned quad_edges = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&q.map, 0, &it); d != ST_NIL; d = st_dart_next(&q.map, 0, &it)) {
        uint32_t e = st_beta0(&q.map, d, 0);
        if (d > e || st_face_degree(&q.map, d, 0) != 4 || st_face_degree(&q.map, e, 0) != 4) continue;
        uint32_t mq = st_vert(&q.map, st_beta0(&q.map, d, 1), 1), mc = st_vert(&c.map, st_beta0(&c.map, d, 1), 1);
        const double *a = st_pos(&q.map, mq, 1), *b = st_pos(&c.map, mc, 1);
        CHECK(near3(a, b[0], b[1], b[2], 1e-15));
        quad_edges++;
    }
    CHECK(quad_edges == 8);
    CHECK(near3(st_pos(&q.map, 8, 1), 0, 0, 97.0 / 64, 1e-15));
    uint32_t d = dart_between(&q.map, 0, 8, 7);
    CHECK(d != ST_NIL && near3(st_pos(&q.map, st_vert(&q.map, st_beta0(&q.map, d, 1), 1), 1), 0.375, 0.375, 11.0 / 8, 1e-15));
    st_hier_free(&q);
    st_hier_free(&c);
}

/* Chamfered cube (8 triangles, 18 quads, all valence 4, cube symmetric):
 * face counts per level, and the result keeps the cube's symmetry. */
static void test_chamfer_cube(void)
{
    st_mesh s;
    st_error err;
    if (load_file(&s, STRATA_SHARED_DATA "/catmull_clark/chamfer_cube.off")) {
        tl_skip("chamfer_cube.off missing");
        return;
    }
    st_hier h;
    int rc = st_hier_init(&h, &s, &st_scheme_quadtri, NULL, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    st_mesh_free(&s);
    rc = st_hier_subdivide_to(&h, 3, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    unsigned expect_tri = 8, expect_quad = 18;
    for (unsigned l = 1; l <= 3; l++) {
        expect_tri *= 4;
        expect_quad *= 4;
        st_mesh out;
        st_mesh_init(&out);
        CHECK(st_hier_level_mesh(&h, l, &out, &err) == ST_OK);
        unsigned nt = 0, nq = 0;
        for (uint32_t f = 0; f < out.nfaces; f++) {
            unsigned k = out.face_off[f + 1] - out.face_off[f];
            nt += k == 3;
            nq += k == 4;
        }
        CHECKF(nt == expect_tri && nq == expect_quad && nt + nq == out.nfaces, "level %u: %u tris, %u quads", l, nt, nq);
        /* Symmetry: the bounding box is centred and a cube. */
        double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
        for (uint32_t v = 0; v < out.nverts; v++)
            for (int i = 0; i < 3; i++) { lo[i] = fmin(lo[i], out.pos[3 * v + i]); hi[i] = fmax(hi[i], out.pos[3 * v + i]); }
        for (int i = 0; i < 3; i++) CHECK(fabs(lo[i] + hi[i]) < 1e-12 && fabs(hi[i] - hi[0]) < 1e-12 && hi[i] <= 1 + 1e-12);
        st_mesh_free(&out);
    }
    st_hier_free(&h);
}


int main(void)
{
    CHECK(st_scheme_find("quad-triangle") == &st_scheme_quadtri);
    test_reductions();
    test_prism_values();
    test_house_regions();
    test_chamfer_cube();
    struct { void (*make)(st_mesh *); unsigned levels; int local; } cases[] = {
        { prism, 3, 0 }, { house, 3, 1 }, { mixed_grid, 3, 1 }, { ngon, 3, 1 }, { tl_mesh_tetra, 3, 0 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        if (cases[i].local) tl_check_local_equals_full(ST_SCHEME_QUADTRI, cases[i].make, cases[i].levels);
        tl_check_rigid_motion(ST_SCHEME_QUADTRI, cases[i].make, cases[i].levels);
        tl_check_details_kept(ST_SCHEME_QUADTRI, cases[i].make, cases[i].levels);
    }
    tl_check_analysis(ST_SCHEME_QUADTRI, house, 3);
    tl_check_analysis(ST_SCHEME_QUADTRI, mixed_grid, 3);
    return TEST_END();
}
