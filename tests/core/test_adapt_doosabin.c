/* Adaptive Doo-Sabin through the dual encoding (adapt_doosabin.c): validity
 * after random box moves, a closed polygonal display, agreement with the
 * regular Doo-Sabin hierarchy (box over everything) and with the base level
 * (box over nothing), the detail round trip, resynthesis, incremental ==
 * full updates, the flatness criterion (the drivers shared with the other
 * adaptive schemes, adapt_testlib.c), and the no_restriction flag ignored. */
#include "adapt_testlib.h"

/* A cube with one corner cut off: a triangle, three pentagons, three quads. */
static void cut_cube(st_mesh *s)
{
    static const double p[] = { -1,-1,-1, 1,-1,-1, 1,1,-1, -1,1,-1, -1,-1,1, 1,-1,0.3, 1,1,1, -1,1,1, 0.3,-1,1, 1,-0.3,1 };
    static const uint32_t off[] = { 0, 4, 8, 12, 17, 22, 27, 30 };
    static const uint32_t idx[] = { 0,3,2,1, 0,4,7,3, 3,7,6,2, 0,1,5,8,4, 4,8,9,6,7, 1,2,6,9,5, 8,5,9 };
    tl_mesh_make(s, p, 10, off, idx, 7);
}

/* Border polygons (surface faces whose corners are of two levels) sit at
 * the depth borders of every level. */
static int border_polygon(st_map *m, uint32_t d, unsigned k)
{
    return st_face_level(m, d, k) == k && st_face_level(m, st_beta1(m, d, k), k) == k - 1;
}

/* The one-level restriction is always applied for Doo-Sabin: with
 * no_restriction set, the same mesh as with it. */
static void check_restriction_flag_ignored(const at_case *c)
{
    at_pair q;
    st_error err;
    double extent = c->extent;
    at_pair_init(&q, c, 0);
    st_adapt_params p = at_box(0.6 * extent, 0.1 * extent, 0, 0.2 * extent, 0, c->max), r = p;
    r.no_restriction = 1;
    CHECK(st_adapt_update(&q.a, &p, &err) == ST_OK && st_adapt_update(&q.b, &r, &err) == ST_OK);
    at_valid(&q.g.map, c->name);
    CHECKF(at_restriction_holds(&q.g.map), "%s: no_restriction was not ignored", c->name);
    uint32_t nf[2], nv[2];
    double worst = at_compare(&q.a, &q.b, nf, nv);
    CHECKF(nf[0] == nf[1] && worst < 1e-12 * extent, "%s: no_restriction %u faces vs %u, distance %g", c->name,
           nf[1], nf[0], worst);
    at_pair_free(&q);
}

static at_case doosabin(void (*make)(st_mesh *), const char *name, unsigned max, double extent)
{
    return (at_case){ ST_SCHEME_DOOSABIN, make, name, 1, 0, max, extent };
}

int main(void)
{
    const at_case cases[] = {
        doosabin(tl_mesh_octa, "octahedron", 4, 1),
        doosabin(tl_mesh_cube, "cube", 4, 1),
        doosabin(tl_mesh_tetra, "tetrahedron", 4, 1),
        doosabin(cut_cube, "cut cube", 4, 2),
        doosabin(at_torus, "torus", 4, 2.7),
    };
    at_run_cases(cases, sizeof cases / sizeof *cases, border_polygon, "border polygon", check_restriction_flag_ignored);
    const at_case flat = doosabin(at_torus, "torus", 3, 2.7), cut1 = doosabin(cut_cube, "cut cube", 4, 1);
    at_check_flatness(&flat);
    const at_inc inc[] = {
        { doosabin(at_torus, "torus", 4, 2.7), 0.3 },
        { doosabin(at_torus, "torus small box", 5, 2.7), 0.08 },
        { doosabin(tl_mesh_octa, "octahedron", 5, 1), 0.2 },
        { cut1, 0.15 },
    };
    at_run_incremental(inc, sizeof inc / sizeof *inc);
    at_check_history_free(&cut1, 1234);      /* extent 1, max 4 */
    at_check_history_free(&cases[4], 1235);  /* torus, max 4 */
    return TEST_END();
}
