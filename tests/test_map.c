/* Kernel tests: building, levels, queries, enumeration, memory. */
#include "core/map/map.h"
#include "core/map/map_mesh.h"
#include "core/map/refine_internal.h"
#include "testlib.h"

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

int main(void)
{
    test_validator_catches();
    test_cube_readings();
    test_open_grid();
    test_refine_levels();
    test_refine_tri();
    test_memory_per_dart();
    return TEST_END();
}
