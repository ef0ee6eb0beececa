/* Multiresolution geometry: synthesis, details in local frames, local
 * re-synthesis after edits, for every registered scheme that applies. */
#include "hier.h"
#include "hier_internal.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void cube_scaled(st_mesh *s) { tl_mesh_cube(s); }
static void torus(st_mesh *s) { tl_mesh_torus(s, 10, 6); }
static void grid(st_mesh *s) { tl_mesh_grid(s, 5); }

/* Catmull-Clark on the unit cube: the corner (0,0,0) goes to (2/9,2/9,2/9)
 * (F = (1/3)³, R = (1/6)³, n = 3), a face centre stays, an edge point of
 * the edge (0,0,0)-(1,0,0) is (1/2, 1/8, 1/8). */
static void test_catmark_cube_values(void)
{
    st_hier h;
    tl_init_hier(&h, cube_scaled, ST_SCHEME_CATMARK, 1);
    const double *c = st_pos(&h.map, 0, 1);
    CHECKF(fabs(c[0] - 2.0 / 9) < 1e-15 && fabs(c[1] - 2.0 / 9) < 1e-15 && fabs(c[2] - 2.0 / 9) < 1e-15,
           "(%g %g %g)", c[0], c[1], c[2]);
    int found_edge = 0, found_face = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, 1, &it); v != ST_NIL; v = st_vertex_next(&h.map, 1, &it)) {
        const double *p = st_pos(&h.map, v, 1);
        if (fabs(p[0] - 0.5) < 1e-15 && fabs(p[1] - 0.125) < 1e-15 && fabs(p[2] - 0.125) < 1e-15) found_edge++;
        if (fabs(p[0] - 0.5) < 1e-15 && fabs(p[1] - 0.5) < 1e-15 && fabs(p[2]) < 1e-15) found_face++;
    }
    CHECK(found_edge == 1 && found_face == 1);
    st_hier_free(&h);
}

int main(void)
{
    test_catmark_cube_values();
    struct { st_scheme_id id; void (*make)(st_mesh *); unsigned levels; } cases[] = {
        { ST_SCHEME_CATMARK, torus, 4 },
        { ST_SCHEME_CATMARK, grid, 3 },
        { ST_SCHEME_CATMARK, cube_scaled, 4 },
        { ST_SCHEME_DOOSABIN, torus, 3 },
        { ST_SCHEME_DOOSABIN, cube_scaled, 3 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        tl_check_local_equals_full(cases[i].id, cases[i].make, cases[i].levels);
        tl_check_rigid_motion(cases[i].id, cases[i].make, cases[i].levels);
        tl_check_details_kept(cases[i].id, cases[i].make, cases[i].levels);
    }
    return TEST_END();
}
