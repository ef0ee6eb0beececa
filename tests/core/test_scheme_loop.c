/* Loop scheme: exact values on literal meshes (smooth, boundary, corner and
 * crease rules), refusal of non-triangles, and the multiresolution checks.
 * The comparison with OpenSubdiv on real meshes is cli_oracle_loop.sh. */
#include "core/schemes/crease_internal.h"
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Open n x n grid of squares cut by the diagonal (i,j)-(i+1,j+1): interior
 * vertices have valence 6; corners (0,0) and (n,n) have 2 faces, the other
 * two corners 1 face. z is a bumpy function so that nothing is planar. */
static void tri_grid_n(st_mesh *s, unsigned n)
{
    uint32_t nv = (n + 1) * (n + 1), nf = 2 * n * n;
    double *p = malloc(3 * (size_t)nv * sizeof *p);
    uint32_t *off = malloc(((size_t)nf + 1) * sizeof *off), *idx = malloc(3 * (size_t)nf * sizeof *idx);
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
            for (int k = 0; k < 6; k++) idx[3 * f + k] = t[k];
            f += 2;
        }
    for (uint32_t k = 0; k <= nf; k++) off[k] = 3 * k;
    tl_mesh_make(s, p, nv, off, idx, nf);
    free(p); free(off); free(idx);
}
static void tri_grid(st_mesh *s) { tri_grid_n(s, 4); }

/* Regular valence-6 fan: centre 0 at z = 1, ring k at angle 60k°, z = k. */
static void hex_fan(st_mesh *s)
{
    double p[21];
    p[0] = 0; p[1] = 0; p[2] = 1;
    for (int k = 0; k < 6; k++) {
        p[3 * (k + 1)] = cos(M_PI * k / 3);
        p[3 * (k + 1) + 1] = sin(M_PI * k / 3);
        p[3 * (k + 1) + 2] = k;
    }
    uint32_t off[7], idx[18];
    for (int k = 0; k < 6; k++) {
        off[k] = 3 * k;
        idx[3 * k] = 0; idx[3 * k + 1] = 1 + k; idx[3 * k + 2] = 1 + (k + 1) % 6;
    }
    off[6] = 18;
    tl_mesh_make(s, p, 7, off, idx, 6);
}

static int near3(const double *p, double x, double y, double z, double tol)
{
    return fabs(p[0] - x) <= tol && fabs(p[1] - y) <= tol && fabs(p[2] - z) <= tol;
}

/* Number of vertices of level l at (x, y, z). */
static int count_at(const st_hier *h, unsigned l, double x, double y, double z)
{
    int n = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
        n += near3(st_pos(&h->map, v, l), x, y, z, 1e-14);
    return n;
}

/* Dart of level l from vertex u to vertex w, ST_NIL if none. */
static uint32_t dart_between(const st_map *m, unsigned l, uint32_t u, uint32_t w)
{
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it))
        if (st_vert(m, d, l) == u && st_vert(m, st_beta0(m, d, l), l) == w) return d;
    return ST_NIL;
}

static void init_opts(st_hier *h, void (*make)(st_mesh *), int boundary, unsigned levels)
{
    st_mesh s;
    st_error err;
    make(&s);
    st_hier_opts o = { .boundary = boundary, .crease_method = ST_CREASE_UNIFORM };
    int rc = st_hier_init(h, &s, &st_scheme_loop, &o, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    st_mesh_free(&s);
    rc = st_hier_subdivide_to(h, levels, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
}

/* Tetrahedron (valence 3, β = 3/16): vertex (1,1,1) -> 7/16 v + 3/16 Σ =
 * (1/4,1/4,1/4); edge (1,1,1)-(-1,-1,1) with opposite (-1,1,-1), (1,-1,-1)
 * -> 3/8 (0,0,2) + 1/8 (0,0,-2) = (0,0,1/2). */
static void test_tetra_values(void)
{
    st_hier h;
    tl_init_hier(&h, tl_mesh_tetra, ST_SCHEME_LOOP, 1);
    CHECK(near3(st_pos(&h.map, 0, 1), 0.25, 0.25, 0.25, 1e-15));
    CHECK(count_at(&h, 1, 0, 0, 0.5) == 1);
    CHECK(count_at(&h, 1, 0, 0, -0.5) == 1);
    st_level_stats s;
    st_level_stats_compute(&h.map, 1, &s);
    CHECK(s.vertices == 10 && s.faces == 16 && s.edges == 24);
    st_hier_free(&h);
}

/* Octahedron (valence 4, β = (5/8 - 9/64)/4 = 31/256): vertex (1,0,0) ->
 * (1 - 124/256) (1,0,0) + 31/256 Σ(neighbours = 0) = (33/64, 0, 0); edge
 * (1,0,0)-(0,1,0), opposite (0,0,±1): (3/8, 3/8, 0). */
static void test_octahedron_values(void)
{
    st_hier h;
    tl_init_hier(&h, tl_mesh_octa, ST_SCHEME_LOOP, 1);
    CHECK(near3(st_pos(&h.map, 0, 1), 33.0 / 64, 0, 0, 1e-15));
    CHECK(count_at(&h, 1, 0.375, 0.375, 0) == 1);
    st_hier_free(&h);
}

/* Regular valence-6 centre of the fan: 5/8 (0,0,1) + 1/16 Σ ring = (0,0,25/16)
 * (Σ of the ring: 0 in x and y, 15 in z).  Interior edge centre-ring0:
 * 3/8 (c + r0) + 1/8 (r5 + r1).  Boundary edge r0-r1: midpoint.  Boundary
 * vertex r0: (6 r0 + r1 + r5) / 8 with both boundary options (2 faces). */
static void test_regular_and_boundary(void)
{
    st_hier h;
    init_opts(&h, hex_fan, ST_BOUNDARY_EDGE_ONLY, 1);
    const st_map *m = &h.map;
    CHECK(near3(st_pos(m, 0, 1), 0, 0, 25.0 / 16, 1e-15));
    const double *c = st_pos(m, 0, 0), *r0 = st_pos(m, 1, 0), *r1 = st_pos(m, 2, 0), *r5 = st_pos(m, 6, 0);
    uint32_t d = dart_between(m, 0, 0, 1);
    CHECK(d != ST_NIL);
    const double *e = st_pos(m, st_vert(m, st_beta0(m, d, 1), 1), 1);
    double x[3];
    for (int i = 0; i < 3; i++) x[i] = 0.375 * (c[i] + r0[i]) + 0.125 * (r5[i] + r1[i]);
    CHECK(near3(e, x[0], x[1], x[2], 1e-15));
    d = dart_between(m, 0, 1, 2);
    e = st_pos(m, st_vert(m, st_beta0(m, d, 1), 1), 1);
    CHECK(near3(e, 0.5 * (r0[0] + r1[0]), 0.5 * (r0[1] + r1[1]), 0.5 * (r0[2] + r1[2]), 1e-15));
    for (int i = 0; i < 3; i++) x[i] = (6 * r0[i] + r1[i] + r5[i]) / 8;
    CHECK(near3(st_pos(m, 1, 1), x[0], x[1], x[2], 1e-15));
    st_hier_free(&h);
}

/* Corner rule: in tri_grid, vertex (n,0) has a single face.  Edge-and-corner
 * keeps it; edge-only moves it along the boundary to (6v + a + b)/8. */
static void test_corner_rule(void)
{
    for (int k = 0; k < 2; k++) {
        st_hier h;
        init_opts(&h, tri_grid, k ? ST_BOUNDARY_EDGE_AND_CORNER : ST_BOUNDARY_EDGE_ONLY, 1);
        const st_map *m = &h.map;
        uint32_t v = 4, a = 3, b = 9; /* (4,0); neighbours (3,0) and (4,1) */
        const double *p = st_pos(m, v, 0), *pa = st_pos(m, a, 0), *pb = st_pos(m, b, 0), *q = st_pos(m, v, 1);
        if (k) CHECK(memcmp(p, q, 3 * sizeof *p) == 0);
        else CHECK(near3(q, (6 * p[0] + pa[0] + pb[0]) / 8, (6 * p[1] + pa[1] + pb[1]) / 8, (6 * p[2] + pa[2] + pb[2]) / 8, 1e-15));
        /* (0,0) has two faces: crease rule with both options. */
        p = st_pos(m, 0, 0); pa = st_pos(m, 1, 0); pb = st_pos(m, 5, 0); q = st_pos(m, 0, 1);
        CHECK(near3(q, (6 * p[0] + pa[0] + pb[0]) / 8, (6 * p[1] + pa[1] + pb[1]) / 8, (6 * p[2] + pa[2] + pb[2]) / 8, 1e-15));
        st_hier_free(&h);
    }
}

/* Creases on the octahedron: the equator (±x, ±y) infinitely sharp makes
 * its vertices creases, (a + 6v + b)/8 = (3/4, 0, 0) for (1,0,0), and its
 * edges' points midpoints (1/2, 1/2, 0).  A semi-sharp edge of sharpness
 * 0.5 from (0,0,1) to (1,0,0) (with the equator smooth) blends the edge's
 * smooth point and midpoint half and half. */
static void test_creases(void)
{
    st_mesh s;
    st_error err;
    tl_mesh_octa(&s);
    s.ncreases = 4;
    s.crease_v = malloc(8 * sizeof *s.crease_v);
    s.crease_s = malloc(4 * sizeof *s.crease_s);
    uint32_t eq[8] = { 0, 2, 2, 1, 1, 3, 3, 0 };
    memcpy(s.crease_v, eq, sizeof eq);
    for (int i = 0; i < 4; i++) s.crease_s[i] = 10.0f;
    st_hier h;
    int rc = st_hier_init(&h, &s, &st_scheme_loop, NULL, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    rc = st_hier_subdivide_to(&h, 2, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    CHECK(near3(st_pos(&h.map, 0, 1), 0.75, 0, 0, 1e-15));
    CHECK(count_at(&h, 1, 0.5, 0.5, 0) == 1);
    /* The equator stays a planar closed curve (z = 0) at level 2. */
    int on_plane = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, 2, &it); v != ST_NIL; v = st_vertex_next(&h.map, 2, &it))
        on_plane += fabs(st_pos(&h.map, v, 2)[2]) < 1e-15;
    CHECK(on_plane == 16);
    st_hier_free(&h);

    s.ncreases = 1;
    s.crease_v[0] = 4; s.crease_v[1] = 0; s.crease_s[0] = 0.5f;
    rc = st_hier_init(&h, &s, &st_scheme_loop, NULL, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    rc = st_hier_subdivide_to(&h, 1, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    /* smooth: 3/8 ((0,0,1) + (1,0,0)) + 1/8 ((0,1,0) + (0,-1,0)); midpoint (1/2, 0, 1/2). */
    CHECK(count_at(&h, 1, 0.4375, 0, 0.4375) == 1);
    st_hier_free(&h);
    st_mesh_free(&s);
}

static void test_refuses_quads(void)
{
    st_mesh s;
    st_error err;
    st_hier h;
    tl_mesh_cube(&s);
    int rc = st_hier_init(&h, &s, &st_scheme_loop, NULL, &err);
    CHECK(rc != ST_OK);
    CHECKF(rc != ST_OK && strstr(err.msg, "4 sides") != NULL, "%s", err.msg);
    st_mesh_free(&s);
}

/* The scheme table is found by id and by CLI name. */
static void test_registry(void)
{
    CHECK(st_scheme_find("loop") == &st_scheme_loop);
    CHECK(st_scheme_get(ST_SCHEME_LOOP) == &st_scheme_loop);
    CHECK(!st_scheme_loop.interpolating);
}


int main(void)
{
    test_registry();
    test_tetra_values();
    test_octahedron_values();
    test_regular_and_boundary();
    test_corner_rule();
    test_creases();
    test_refuses_quads();
    /* local == full also checks that an edit recomputes less than
     * everything, which needs meshes larger than the support (not the
     * tetrahedron or the octahedron, whose every face is within reach). */
    struct { void (*make)(st_mesh *); unsigned levels; int local; } cases[] = {
        { tl_mesh_tetra, 4, 0 }, { tl_mesh_octa, 3, 0 }, { tl_mesh_icosa, 3, 1 }, { tri_grid, 3, 1 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        if (cases[i].local) tl_check_local_equals_full(ST_SCHEME_LOOP, cases[i].make, cases[i].levels);
        tl_check_rigid_motion(ST_SCHEME_LOOP, cases[i].make, cases[i].levels);
        tl_check_details_kept(ST_SCHEME_LOOP, cases[i].make, cases[i].levels);
    }
    tl_check_analysis(ST_SCHEME_LOOP, tl_mesh_icosa, 3);
    tl_check_analysis(ST_SCHEME_LOOP, tri_grid, 3);
    return TEST_END();
}
