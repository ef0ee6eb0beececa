/* Kernel tests: building, levels, queries, enumeration, memory. */
#include "core/map/geometry.h"
#include "core/map/map.h"
#include "core/map/map_mesh.h"
#include "core/map/refine_internal.h"
#include "core/multires/hier.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <string.h>

static void build(st_map *m, void (*make)(st_mesh *))
{
    st_mesh s;
    st_error err;
    make(&s);
    st_map_init(m);
    int rc = st_map_from_mesh(m, &s, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    st_mesh_free(&s);
}

static void grid3(st_mesh *s) { tl_mesh_grid(s, 3); }
static void torus(st_mesh *s) { tl_mesh_torus(s, 12, 8); }

static void valid(st_map *m)
{
    st_error err;
    int rc = st_map_validate(m, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
}

/* Cube: V 8, E 12, F 6; every face a quad, every vertex of degree 3; the two
 * readings agree: φ1 = β1∘β0, φ2 = β0, <φ1> faces, <β1> vertices. */
static void test_cube_readings(void)
{
    st_map m;
    build(&m, tl_mesh_cube);
    valid(&m);
    st_level_stats s;
    st_level_stats_compute(&m, 0, &s);
    CHECK(s.vertices == 8 && s.edges == 12 && s.faces == 6 && s.boundary_loops == 0 && s.euler == 2);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&m, 0, &it); d != ST_NIL; d = st_dart_next(&m, 0, &it)) {
        CHECK(st_face_degree(&m, d, 0) == 4);
        CHECK(st_vertex_degree(&m, d, 0) == 3);
        CHECK(st_phi1(&m, d, 0) == st_beta1(&m, st_beta0(&m, d, 0), 0));
        CHECK(st_phi_1(&m, st_phi1(&m, d, 0), 0) == d);
        /* φ1(d) starts where d ends: at the vertex of its twin. */
        CHECK(st_vert(&m, st_phi1(&m, d, 0), 0) == st_vert(&m, st_phi2(&m, d, 0), 0));
    }
    st_map_free(&m);
}

/* Open 3x3 grid: one hole face of 12 sides, V 16, E 24, F 9, χ = 1. */
static void test_open_grid(void)
{
    st_map m;
    build(&m, grid3);
    valid(&m);
    st_level_stats s;
    st_level_stats_compute(&m, 0, &s);
    CHECK(s.vertices == 16 && s.edges == 24 && s.faces == 9);
    CHECK(s.boundary_loops == 1 && s.boundary_edges == 12 && s.euler == 1);
    st_map_free(&m);
}

/* Catmull-Clark topology: level k of the cube has 6·4^k quads; level 0 is
 * untouched, and a query above the top answers with the top level. */
static void test_refine_levels(void)
{
    st_map m;
    st_error err;
    build(&m, tl_mesh_cube);
    for (unsigned k = 1; k <= 4; k++) {
        CHECKF(st_refine_uniform(&m, ST_SPLIT_POLY, &err) == ST_OK, "%s", err.msg);
        valid(&m);
        st_level_stats s;
        st_level_stats_compute(&m, k, &s);
        uint64_t f = 6ull << (2 * k);
        CHECK(s.faces == f && s.edges == 2 * f && s.vertices == f + 2 && s.euler == 2);
    }
    st_level_stats s0, s9, s4;
    st_level_stats_compute(&m, 0, &s0);
    st_level_stats_compute(&m, 9, &s9);
    st_level_stats_compute(&m, 4, &s4);
    CHECK(s0.darts == 24 && s0.faces == 6 && s0.vertices == 8);
    CHECK(memcmp(&s9, &s4, sizeof s4) == 0);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&m, 1, &it); d != ST_NIL; d = st_dart_next(&m, 1, &it))
        CHECK(st_beta0(&m, d, 17) == st_beta0(&m, d, 4) && st_phi1(&m, d, 20) == st_phi1(&m, d, 4));
    /* Level 0 enumeration visits only level-0 darts. */
    uint32_t n0 = 0;
    for (uint32_t d = st_dart_first(&m, 0, &it); d != ST_NIL; d = st_dart_next(&m, 0, &it)) n0++;
    CHECK(n0 == 24);
    st_map_free(&m);
}

/* Loop topology on the tetrahedron and on an open grid split into
 * triangles by the mixed mode: faces multiply by 4 per level. */
static void test_refine_tri(void)
{
    st_map m;
    st_error err;
    build(&m, tl_mesh_tetra);
    for (unsigned k = 1; k <= 3; k++) {
        CHECKF(st_refine_uniform(&m, ST_SPLIT_TRI, &err) == ST_OK, "%s", err.msg);
        valid(&m);
        st_level_stats s;
        st_level_stats_compute(&m, k, &s);
        CHECK(s.faces == (4ull << (2 * k)) && s.euler == 2);
    }
    st_map_free(&m);
    build(&m, tl_mesh_cube);
    CHECK(st_refine_uniform(&m, ST_SPLIT_TRI, &err) == ST_ERR_TOPOLOGY && m.top == 0);
    st_map_free(&m);
    build(&m, grid3);
    for (unsigned k = 1; k <= 3; k++) {
        CHECKF(st_refine_uniform(&m, ST_SPLIT_MIXED, &err) == ST_OK, "%s", err.msg);
        valid(&m);
    }
    st_level_stats s;
    st_level_stats_compute(&m, 3, &s);
    CHECK(s.faces == 9u * 64 && s.boundary_loops == 1 && s.boundary_edges == 12u * 8 && s.euler == 1);
    st_map_free(&m);
}

/* Topology of a regular hierarchy: at most 16 bytes per finest dart. */
static void test_memory_per_dart(void)
{
    st_map m;
    st_error err;
    build(&m, torus);
    for (unsigned k = 1; k <= 5; k++) CHECK(st_refine_uniform(&m, ST_SPLIT_POLY, &err) == ST_OK);
    st_level_stats s;
    st_level_stats_compute(&m, m.top, &s);
    st_map_bytes b;
    st_map_memory(&m, &b);
    double per = (double)b.topology / (double)s.darts;
    printf("torus 12x8, depth 5: %llu finest darts, topology %.2f bytes per finest dart\n",
           (unsigned long long)s.darts, per);
    CHECKF(per <= 16.0, "%.2f bytes per dart", per);
    st_map_free(&m);
}

/* The validator must catch each kind of corruption, name it and the level. */
static void expect_invalid(st_map *m, const char *needle)
{
    st_error err;
    int rc = st_map_validate(m, &err);
    CHECKF(rc == ST_ERR_INVALID && strstr(err.msg, needle), "expected '%s', got rc %d '%s'", needle, rc, err.msg);
}

static void test_validator_catches(void)
{
    st_map m;
    st_error err;
    build(&m, grid3);
    CHECK(st_refine_uniform(&m, ST_SPLIT_POLY, &err) == ST_OK);
    uint32_t d = 5, e = st_beta0(&m, d, 1), f = st_beta1(&m, d, 1);
    /* β0 not an involution at level 1 only. */
    st_set_beta0(&m, d, 1, st_beta1(&m, e, 1));
    expect_invalid(&m, "level 1, dart 5: beta0");
    st_set_beta0(&m, d, 1, e);
    valid(&m);
    /* β1 not a permutation. */
    st_set_beta1(&m, d, 1, st_beta1(&m, f, 1));
    expect_invalid(&m, "beta1 is not a permutation");
    st_set_beta1(&m, d, 1, f);
    valid(&m);
    /* A vertex orbit carrying two vertices. */
    uint32_t v = st_vert(&m, d, 1);
    st_set_vert(&m, d, 1, st_vert(&m, e, 1));
    expect_invalid(&m, "vertex orbit carries two vertices");
    st_set_vert(&m, d, 1, v);
    valid(&m);
    /* A real face mixed with boundary darts. */
    uint8_t fl = m.flags[d];
    m.flags[d] ^= ST_DART_BOUNDARY;
    expect_invalid(&m, "boundary");
    m.flags[d] = fl;
    valid(&m);
    st_map_free(&m);
}

/* The surface walks (st_face_step, st_vertex_step) on both encodings.
 * Primal cube: they are φ1 and β1.  Doo-Sabin on the unit cube, levels
 * 0..2 (dual encoding: surface faces are β1 orbits, surface vertices φ1
 * orbits): for every face of st_hier_level_mesh, the dart at its first
 * corner followed by st_face_step visits its corners in order and comes
 * back after as many steps; st_vertex_step stays on one surface vertex and
 * goes round it in as many steps as faces hold that vertex; st_face_newell
 * is the Newell sum written out here over the mesh's corners, to the bit
 * (level 0: the cube's faces, 2 x area = 2 along the outward axis).  The
 * view forms answer as the map forms. */
static void check_views(st_map *m, unsigned l)
{
    st_level_view V;
    st_level_view_init(m, l, &V);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        CHECK(st_v_face_step(&V, m->face_embedded, d) == st_face_step(m, d, l));
        CHECK(st_v_vertex_step(&V, m->face_embedded, d) == st_vertex_step(m, d, l));
    }
}

static int same_point(const double *a, const double *b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

static void test_surface_walks(void)
{
    st_map pm;
    build(&pm, tl_mesh_cube);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&pm, 0, &it); d != ST_NIL; d = st_dart_next(&pm, 0, &it))
        CHECK(st_face_step(&pm, d, 0) == st_phi1(&pm, d, 0) && st_vertex_step(&pm, d, 0) == st_beta1(&pm, d, 0));
    check_views(&pm, 0);
    st_map_free(&pm);

    st_mesh cube;
    st_error err;
    tl_mesh_cube(&cube);
    st_hier h;
    CHECKF(st_hier_init(&h, &cube, st_scheme_find("doo-sabin"), NULL, &err) == ST_OK, "%s", err.msg);
    st_mesh_free(&cube);
    CHECKF(st_hier_subdivide_to(&h, 2, &err) == ST_OK, "%s", err.msg);
    st_map *m = &h.map;
    CHECK(m->face_embedded);
    for (unsigned l = 0; l <= 2; l++) {
        st_mesh s;
        st_mesh_init(&s);
        CHECKF(st_hier_level_mesh(&h, l, &s, &err) == ST_OK, "%s", err.msg);
        static const uint32_t faces_at[] = { 6, 26, 98 };   /* F + E + V of the level below */
        CHECKF(s.nfaces == faces_at[l], "level %u: %u faces", l, s.nfaces);
        uint32_t found = 0;
        for (uint32_t f = 0; f < s.nfaces; f++) {
            uint32_t o = s.face_off[f], n = s.face_off[f + 1] - o;
            const double *c0 = s.pos + 3 * (size_t)s.face_idx[o], *c1 = s.pos + 3 * (size_t)s.face_idx[o + 1];
            /* The dart at corner 0 whose next corner is corner 1. */
            uint32_t d = ST_NIL;
            for (uint32_t x = st_dart_first(m, l, &it); x != ST_NIL && d == ST_NIL; x = st_dart_next(m, l, &it))
                if (same_point(st_dart_pos(m, x, l), c0) && same_point(st_dart_pos(m, st_face_step(m, x, l), l), c1)) d = x;
            CHECKF(d != ST_NIL, "level %u face %u: no dart from corner 0 to corner 1", l, f);
            if (d == ST_NIL) continue;
            found++;
            uint32_t x = d;
            for (uint32_t k = 0; k < n; k++, x = st_face_step(m, x, l))
                CHECKF(same_point(st_dart_pos(m, x, l), s.pos + 3 * (size_t)s.face_idx[o + k]) && (k == 0 || x != d),
                       "level %u face %u: corner %u", l, f, k);
            CHECKF(x == d, "level %u face %u: the walk does not close after %u corners", l, f, n);
            /* Around each corner: one surface vertex, once round in as many
             * steps as faces hold it. */
            for (uint32_t k = 0; k < n; k++, x = st_face_step(m, x, l)) {
                uint32_t v = s.face_idx[o + k], holding = 0, steps = 0, y = x;
                for (uint32_t i = 0; i < s.face_off[s.nfaces]; i++) holding += s.face_idx[i] == v;
                do {
                    CHECK(st_vert(m, y, l) == st_vert(m, x, l));
                    steps++;
                    y = st_vertex_step(m, y, l);
                } while (y != x && steps <= holding);
                CHECKF(steps == holding, "level %u face %u corner %u: %u steps round, %u faces", l, f, k, steps, holding);
            }
            double want[3] = { 0, 0, 0 }, got[3];
            for (uint32_t k = 0; k < n; k++) {
                const double *p = s.pos + 3 * (size_t)s.face_idx[o + k], *q = s.pos + 3 * (size_t)s.face_idx[o + (k + 1) % n];
                want[0] += (p[1] - q[1]) * (p[2] + q[2]);
                want[1] += (p[2] - q[2]) * (p[0] + q[0]);
                want[2] += (p[0] - q[0]) * (p[1] + q[1]);
            }
            st_face_newell(m, d, l, got);
            CHECKF(memcmp(got, want, sizeof got) == 0, "level %u face %u: Newell (%g %g %g), by hand (%g %g %g)", l, f,
                   got[0], got[1], got[2], want[0], want[1], want[2]);
            if (l == 0) {
                int axis = got[0] != 0 ? 0 : got[1] != 0 ? 1 : 2;
                CHECKF(fabs(got[axis]) == 2 && got[(axis + 1) % 3] == 0 && got[(axis + 2) % 3] == 0 &&
                           got[axis] * (c0[axis] - 0.5) > 0,
                       "level 0 face %u: (%g %g %g)", f, got[0], got[1], got[2]);
            }
        }
        CHECK(found == s.nfaces);
        check_views(m, l);
        st_mesh_free(&s);
    }
    st_hier_free(&h);
}

int main(void)
{
    test_surface_walks();
    test_validator_catches();
    test_cube_readings();
    test_open_grid();
    test_refine_levels();
    test_refine_tri();
    test_memory_per_dart();
    return TEST_END();
}
