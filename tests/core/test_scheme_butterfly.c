/* Modified Butterfly: interpolation (even vertices bit-identical), exact
 * values of the regular, extraordinary (k = 3, 4, 12) and boundary rules,
 * reproduction of planes and of the regular lattice, refusal of
 * non-triangles, and the multiresolution checks.  The comparison with
 * OpenMesh on real meshes is cli_oracle_butterfly.sh. */
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Open grid of unit squares cut by the diagonal (i,j)-(i+1,j+1): interior
 * vertices have valence 6.  z(i, j) given by fz. */
static void tri_grid_fz(st_mesh *s, unsigned n, double (*fz)(double, double))
{
    uint32_t nv = (n + 1) * (n + 1), nf = 2 * n * n;
    double *p = malloc(3 * (size_t)nv * sizeof *p);
    uint32_t *off = malloc(((size_t)nf + 1) * sizeof *off), *idx = malloc(3 * (size_t)nf * sizeof *idx);
    for (unsigned j = 0; j <= n; j++)
        for (unsigned i = 0; i <= n; i++) {
            double *q = p + 3 * (j * (n + 1) + i);
            q[0] = i; q[1] = j; q[2] = fz(i, j);
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
static double z_bumpy(double x, double y) { return 0.1 * (((int)x * 7 + (int)y * 3) % 5); }
static double z_plane(double x, double y) { return 0.3 * x - 0.2 * y + 1.0; }
static double z_cubic(double x, double y) { (void)y; return x * x * x; }
static void tri_grid(st_mesh *s) { tri_grid_fz(s, 5, z_bumpy); }
static void plane_grid(st_mesh *s) { tri_grid_fz(s, 4, z_plane); }
static void cubic_grid(st_mesh *s) { tri_grid_fz(s, 4, z_cubic); }

/* Closed bipyramid: equator of n vertices (valence 4) on the unit circle
 * with a wave in z, poles (valence n) at z = ±1.5. */
static unsigned bipyramid_n = 12;
static void bipyramid(st_mesh *s)
{
    unsigned n = bipyramid_n;
    double *p = malloc(3 * (size_t)(n + 2) * sizeof *p);
    uint32_t *off = malloc((2 * (size_t)n + 1) * sizeof *off), *idx = malloc(6 * (size_t)n * sizeof *idx);
    for (unsigned k = 0; k < n; k++) {
        p[3 * k] = cos(2 * M_PI * k / n);
        p[3 * k + 1] = sin(2 * M_PI * k / n);
        p[3 * k + 2] = 0.2 * (k % 3);
    }
    p[3 * n] = 0; p[3 * n + 1] = 0; p[3 * n + 2] = 1.5;
    p[3 * n + 3] = 0; p[3 * n + 4] = 0; p[3 * n + 5] = -1.5;
    for (unsigned k = 0; k < n; k++) {
        uint32_t a = k, b = (k + 1) % n;
        uint32_t *t = idx + 6 * k;
        t[0] = a; t[1] = b; t[2] = n;          /* upper, counter-clockwise seen from above */
        t[3] = b; t[4] = a; t[5] = n + 1;
    }
    for (unsigned k = 0; k <= 2 * n; k++) off[k] = 3 * k;
    tl_mesh_make(s, p, n + 2, off, idx, 2 * n);
    free(p); free(off); free(idx);
}

static int near3(const double *p, double x, double y, double z, double tol)
{
    return fabs(p[0] - x) <= tol && fabs(p[1] - y) <= tol && fabs(p[2] - z) <= tol;
}

static uint32_t dart_between(const st_map *m, unsigned l, uint32_t u, uint32_t w)
{
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it))
        if (st_vert(m, d, l) == u && st_vert(m, st_beta0(m, d, l), l) == w) return d;
    return ST_NIL;
}

/* Level-1 point of the level-0 edge u-w. */
static const double *edge_point(const st_hier *h, uint32_t u, uint32_t w)
{
    uint32_t d = dart_between(&h->map, 0, u, w);
    if (d == ST_NIL) return NULL;
    return st_pos(&h->map, st_vert(&h->map, st_beta0(&h->map, d, 1), 1), 1);
}

/* Every vertex keeps its position bit for bit at every finer level. */
static void check_interpolating(st_hier *h)
{
    unsigned bad = 0;
    for (unsigned l = 0; l < h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
            for (unsigned L = l + 1; L <= h->map.top; L++)
                bad += memcmp(st_pos(&h->map, v, l), st_pos(&h->map, v, L), 3 * sizeof(double)) != 0;
    }
    CHECKF(bad == 0, "%u positions changed", bad);
}

static void test_interpolating(void)
{
    void (*makes[])(st_mesh *) = { tl_mesh_tetra, tl_mesh_icosa, tri_grid, bipyramid };
    for (size_t i = 0; i < sizeof makes / sizeof *makes; i++) {
        st_hier h;
        tl_init_hier(&h, makes[i], ST_SCHEME_BUTTERFLY, 3);
        check_interpolating(&h);
        st_hier_free(&h);
    }
}

/* Tetrahedron: both ends have valence 3, so the point is the average of
 * the two k = 3 stencils: 7/12 (a0 + a1) - 1/12 (c + d).  Edge
 * (1,1,1)-(-1,-1,1): 7/12 (0,0,2) - 1/12 (0,0,-2) = (0, 0, 4/3). */
static void test_valence3(void)
{
    st_hier h;
    tl_init_hier(&h, tl_mesh_tetra, ST_SCHEME_BUTTERFLY, 1);
    const double *e = edge_point(&h, 0, 1);
    CHECK(e && near3(e, 0, 0, 4.0 / 3, 1e-15));
    st_hier_free(&h);
}

/* Octahedron: valence 4 at both ends: 3/4 a0 + 3/8 a1 - 1/8 (the vertex
 * opposite a1 around a0) averaged with the mirror stencil.  Edge
 * (1,0,0)-(0,1,0): (3/4 x + 3/8 y + 1/8 y + mirror)/2 = (5/8, 5/8, 0). */
static void test_valence4(void)
{
    st_hier h;
    tl_init_hier(&h, tl_mesh_octa, ST_SCHEME_BUTTERFLY, 1);
    const double *e = edge_point(&h, 0, 2);
    CHECK(e && near3(e, 0.625, 0.625, 0, 1e-15));
    st_hier_free(&h);
}

/* Bipyramid, n = 12: the edge pole-equator0 has ends of valence 12 and 4,
 * both extraordinary: the average of
 *   pole:   3/4 N + Σ_j s_j E_j, s_j = (1/4 + cos(2πj/12) + cos(4πj/12)/2)/12,
 *           E_j the equator vertex j steps from E_0 (either direction);
 *   E_0:    3/4 E_0 + 3/8 N - 1/8 S (ring N, E_1, S, E_11; s = 3/8, 0, -1/8, 0). */
static void test_high_valence(void)
{
    st_hier h;
    bipyramid_n = 12;
    tl_init_hier(&h, bipyramid, ST_SCHEME_BUTTERFLY, 1);
    const st_map *m = &h.map;
    const unsigned n = 12, N = n, S = n + 1;
    double x[3] = { 0, 0, 0 };
    for (int i = 0; i < 3; i++) {
        double sum = 0;
        for (unsigned j = 0; j < n; j++) {
            double s = (0.25 + cos(2 * M_PI * j / n) + 0.5 * cos(4 * M_PI * j / n)) / n;
            sum += s;
            x[i] += 0.5 * s * st_pos(m, j, 0)[i];
        }
        x[i] += 0.5 * (1 - sum) * st_pos(m, N, 0)[i];
        x[i] += 0.5 * (0.75 * st_pos(m, 0, 0)[i] + 0.375 * st_pos(m, N, 0)[i] - 0.125 * st_pos(m, S, 0)[i]);
    }
    const double *e = edge_point(&h, N, 0);
    CHECKF(e && near3(e, x[0], x[1], x[2], 1e-14), "(%g %g %g) vs (%g %g %g)", e ? e[0] : 0, e ? e[1] : 0, e ? e[2] : 0, x[0], x[1], x[2]);
    st_hier_free(&h);
}

/* Planar data stays planar, exactly up to rounding (every stencil is an
 * affine combination, ghost points included), on an open grid whose corners
 * make the boundary 4-point rule leave the lattice. */
static void test_plane(void)
{
    st_hier h;
    tl_init_hier(&h, plane_grid, ST_SCHEME_BUTTERFLY, 3);
    double worst = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, 3, &it); v != ST_NIL; v = st_vertex_next(&h.map, 3, &it)) {
        const double *p = st_pos(&h.map, v, 3);
        worst = fmax(worst, fabs(p[2] - z_plane(p[0], p[1])));
    }
    CHECKF(worst < 1e-13, "plane error %g", worst);
    st_hier_free(&h);
}

/* The boundary 4-point rule reproduces cubics: on the edge (1,0)-(2,0) of
 * the grid with z = x³, 9/16 (1 + 8) - 1/16 (0 + 27) = 27/8 = 1.5³.  The
 * interior regular edge (1,1)-(2,2) (its wings (2,1) side and (1,2) side)
 * also reproduces the cubic along x: z(1.5) = 27/8. */
static void test_boundary_and_regular(void)
{
    st_hier h;
    tl_init_hier(&h, cubic_grid, ST_SCHEME_BUTTERFLY, 1);
    const double *e = edge_point(&h, 1, 2);
    CHECK(e && near3(e, 1.5, 0, 3.375, 1e-14));
    e = edge_point(&h, 6, 12); /* (1,1)-(2,2) */
    CHECK(e && near3(e, 1.5, 1.5, 3.375, 1e-14));
    st_hier_free(&h);
}

static void test_refuses_quads(void)
{
    st_mesh s;
    st_error err;
    st_hier h;
    tl_mesh_cube(&s);
    int rc = st_hier_init(&h, &s, &st_scheme_butterfly, NULL, &err);
    CHECKF(rc != ST_OK && strstr(err.msg, "4 sides") != NULL, "%s", rc ? err.msg : "accepted");
    st_mesh_free(&s);
    CHECK(st_scheme_find("butterfly") == &st_scheme_butterfly);
    CHECK(st_scheme_butterfly.interpolating);
}

static void bipyramid14(st_mesh *s) { bipyramid_n = 14; bipyramid(s); }

/* Closed torus of triangles: tl_mesh_torus(12, 8) quads cut by alternating
 * diagonals, so vertices have valence 4 or 8 (all extraordinary). */
static void tri_torus(st_mesh *s)
{
    st_mesh q;
    tl_mesh_torus(&q, 12, 8);
    uint32_t nf = 2 * q.nfaces;
    uint32_t *off = malloc(((size_t)nf + 1) * sizeof *off), *idx = malloc(3 * (size_t)nf * sizeof *idx);
    for (uint32_t f = 0; f < q.nfaces; f++) {
        const uint32_t *v = q.face_idx + q.face_off[f];
        unsigned i = f % 12, j = f / 12, r = (i + j) % 2;
        uint32_t t[6] = { v[r], v[r + 1], v[(r + 2) % 4], v[r], v[(r + 2) % 4], v[(r + 3) % 4] };
        memcpy(idx + 6 * f, t, sizeof t);
    }
    for (uint32_t k = 0; k <= nf; k++) off[k] = 3 * k;
    tl_mesh_make(s, q.pos, q.nverts, off, idx, nf);
    st_mesh_free(&q);
    free(off); free(idx);
}


int main(void)
{
    test_refuses_quads();
    test_interpolating();
    test_valence3();
    test_valence4();
    test_high_valence();
    test_plane();
    test_boundary_and_regular();
    /* local == full also checks that an edit recomputes less than
     * everything: only on meshes larger than the two-ring support. */
    struct { void (*make)(st_mesh *); unsigned levels; int local; } cases[] = {
        { tl_mesh_tetra, 4, 0 }, { tl_mesh_octa, 3, 0 }, { tl_mesh_icosa, 3, 0 }, { bipyramid14, 3, 0 },
        { tri_grid, 3, 1 }, { tri_torus, 3, 1 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        if (cases[i].local) tl_check_local_equals_full(ST_SCHEME_BUTTERFLY, cases[i].make, cases[i].levels);
        tl_check_rigid_motion(ST_SCHEME_BUTTERFLY, cases[i].make, cases[i].levels);
        tl_check_details_kept(ST_SCHEME_BUTTERFLY, cases[i].make, cases[i].levels);
    }
    tl_check_analysis(ST_SCHEME_BUTTERFLY, tl_mesh_icosa, 3);
    tl_check_analysis(ST_SCHEME_BUTTERFLY, tri_grid, 3);
    return TEST_END();
}
