/* Adaptive refinement (the polygon split family, adapt_split.c: Catmull-Clark,
 * Loop, Butterfly; the choice of every scheme's family table): validity
 * after random box moves, watertightness, agreement with the regular
 * hierarchy, the detail round trip and incremental == full updates (the
 * shared drivers of adapt_testlib.c), adaptive access on a regular hierarchy,
 * and synthesis over empty levels. */
#include "core/adapt/access.h"
#include "adapt_testlib.h"
#include "core/adapt/adapt_internal.h"

#include <math.h>
#include <string.h>

/* Adaptive access (§3.3.2) on a regular hierarchy shows the mesh adaptive
 * refinement builds for the same criteria: same faces, same points, no
 * T-junction; with the restriction off it is still watertight. */
static void check_access(const at_case *c)
{
    st_hier r;
    st_error err;
    unsigned max = c->max;
    double extent = c->extent;
    tl_init_hier(&r, c->make, c->id, max);
    uint64_t rng = 211 + c->id;
    for (int step = 0; step < 6; step++) {
        double x[3];
        for (int k = 0; k < 3; k++) x[k] = extent * at_rand_unit(&rng);
        st_adapt_params p = at_box(x[0], x[1], x[2], (0.2 + 0.1 * step) * extent, step % 2, max);
        if (step == 4) p = at_box(0, 0, 0, 100 * extent, 0, max);     /* everything */
        if (step == 5) p = at_box(1000 * extent, 0, 0, 0.1, 1, max);  /* nothing: base level 1 */
        if (step == 2) p.falloff = 0.3 * extent;
        st_hier h;
        st_adapt a;
        tl_init_hier(&h, c->make, c->id, 0);
        CHECK(st_adapt_init(&a, &h, &err) == ST_OK && st_adapt_update(&a, &p, &err) == ST_OK);
        st_mesh want, got;
        st_mesh_init(&want);
        st_mesh_init(&got);
        st_access_stats st;
        CHECK(st_adapt_mesh(&a, &want, &err) == ST_OK);
        CHECKF(st_access_mesh(&r, &p, &got, &st, &err) == ST_OK, "%s", err.msg);
        double dist = at_mesh_dist(&got, &want);
        CHECKF(got.nfaces == want.nfaces && got.nverts == want.nverts && dist < 1e-9 * extent,
               "%s step %d: access %u faces / %u verts, adaptive %u / %u, distance %g", c->name, step,
               got.nfaces, got.nverts, want.nfaces, want.nverts, dist);
        CHECKF(at_watertight(&got, c->closed, c->sides), "%s step %d: access mesh not watertight", c->name, step);
        at_valid(&r.map, "after adaptive access");
        CHECKF(r.map.marks_used == 0, "%s: marker bits leaked (%#x)", c->name, r.map.marks_used);
        p.no_restriction = 1;
        st_mesh_free(&got);
        CHECK(st_access_mesh(&r, &p, &got, NULL, &err) == ST_OK);
        CHECKF(at_watertight(&got, c->closed, c->sides), "%s step %d: access mesh without restriction not watertight",
               c->name, step);
        st_mesh_free(&want);
        st_mesh_free(&got);
        st_adapt_free(&a);
        st_hier_free(&h);
    }
    st_hier_free(&r);
}

/* Synthesis after the box left the finer levels empty (no face subdivided
 * at the first level synthesised) changes nothing. */
static void check_synthesize_empty_levels(const at_case *c)
{
    st_hier h;
    st_adapt a;
    st_error err;
    double extent = c->extent;
    tl_init_hier(&h, c->make, c->id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = at_box(0.5 * extent, 0, 0, 0.4 * extent, 0, c->max);
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    p.max_level = 1;
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    st_mesh before, after;
    st_mesh_init(&before);
    st_mesh_init(&after);
    CHECK(st_adapt_mesh(&a, &before, &err) == ST_OK);
    st_adapt_synthesize(&a, 1);
    CHECK(st_adapt_mesh(&a, &after, &err) == ST_OK);
    double dist = before.nverts == after.nverts ? 0 : INFINITY;
    for (uint32_t k = 0; k < 3 * after.nverts && dist == 0; k++) dist = fmax(dist, fabs(after.pos[k] - before.pos[k]));
    CHECKF(dist < 1e-12 * extent, "%s: synthesis over levels with no subdivided face moved the mesh by %g", c->name,
           dist);
    st_mesh_free(&before);
    st_mesh_free(&after);
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* Each scheme's st_adapt goes through its refinement family's table
 * (adapt_internal.h), and an st_adapt filled in field by field, as a
 * session load does, gets the same table on first use and updates to the
 * same mesh as one made by st_adapt_init. */
static void check_family_tables(void)
{
    static const struct { st_scheme_id id; void (*make)(st_mesh *); const st_adapt_ops *ops; const char *family; } t[] = {
        { ST_SCHEME_CATMARK, tl_mesh_cube, &st_adapt_ops_quads, "polygon split" },
        { ST_SCHEME_LOOP, tl_mesh_octa, &st_adapt_ops_triangles, "polygon split" },
        { ST_SCHEME_BUTTERFLY, tl_mesh_octa, &st_adapt_ops_triangles, "polygon split" },
        { ST_SCHEME_QUADTRI, tl_mesh_cube, &st_adapt_ops_quadtri, "polygon split" },
        { ST_SCHEME_SQRT3, tl_mesh_octa, &st_adapt_ops_sqrt3, "sqrt3" },
        { ST_SCHEME_DOOSABIN, tl_mesh_cube, &st_adapt_ops_doosabin, "doo-sabin" },
    };
    for (size_t k = 0; k < sizeof t / sizeof *t; k++) {
        st_hier h, g;
        st_adapt a, b;
        st_error err;
        tl_init_hier(&h, t[k].make, t[k].id, 0);
        tl_init_hier(&g, t[k].make, t[k].id, 0);
        CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
        CHECKF(a.ops == t[k].ops && !strcmp(a.ops->family, t[k].family), "%s: st_adapt_init chose the %s table",
               h.scheme->name, a.ops ? a.ops->family : "no");
        memset(&b, 0, sizeof b);
        b.h = &g;
        for (uint32_t i = 0; i < a.base_faces.n; i++) st_dart_list_push(&b.base_faces, a.base_faces.d[i]);
        CHECKF(st_adapt_ops_of(&b) == t[k].ops && b.ops == t[k].ops, "%s: no table chosen on first use", h.scheme->name);
        memset(&b.ops, 0, sizeof b.ops);
        st_adapt_params p = at_box(0.9, 0.9, 0.9, 0.3, 0, 3);
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        CHECK(st_adapt_update(&b, &p, &err) == ST_OK);
        uint32_t nf[2], nv[2];
        double dist = at_compare(&a, &b, nf, nv);
        CHECKF(a.touched > 0, "%s: the box refined nothing", h.scheme->name);
        CHECKF(nf[0] == nf[1] && nv[0] == nv[1] && dist == 0, "%s: field-by-field st_adapt: %u/%u faces, distance %g",
               h.scheme->name, nf[1], nf[0], dist);
        st_adapt_free(&a);
        st_adapt_free(&b);
        st_hier_free(&h);
        st_hier_free(&g);
    }
}

int main(void)
{
    check_family_tables();
    static const at_case cases[] = {
        { ST_SCHEME_CATMARK, at_torus, "catmark torus", 1, 0, 3, 2.7 },
        { ST_SCHEME_CATMARK, at_grid, "catmark grid", 0, 0, 3, 4 },
        { ST_SCHEME_CATMARK, tl_mesh_cube, "catmark cube", 1, 0, 3, 1 },
        { ST_SCHEME_LOOP, tl_mesh_octa, "loop octahedron", 1, 0, 3, 1 },
        { ST_SCHEME_BUTTERFLY, tl_mesh_octa, "butterfly octahedron", 1, 0, 3, 1 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        const at_case *c = &cases[i];
        at_check_random_moves(c, 31 + c->id, 12, 0);
        at_check_matches_regular(c, NULL, NULL);
        at_check_detail_round_trip(c);
        at_check_incremental(c, 77 + c->id, 16, 0.3);
        at_check_drag(c, 91 + c->id, 40, 0.1, c->max + 3);
        at_check_drag(c, 191 + c->id, 40, 0.25, c->max + 3);
        check_access(c);
        check_synthesize_empty_levels(c);
    }
    return TEST_END();
}
