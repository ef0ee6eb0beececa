/* Adaptive refinement: validity after random box moves, watertightness,
 * agreement with the regular hierarchy, and the detail round trip. */
#include "access.h"
#include "adapt.h"
#include "hier_internal.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void torus(st_mesh *s) { tl_mesh_torus(s, 8, 6); }
static void grid(st_mesh *s) { tl_mesh_grid(s, 4); }
static void octa(st_mesh *s)
{
    static const double p[] = { 1,0,0, -1,0,0, 0,1,0, 0,-1,0, 0,0,1, 0,0,-1 };
    static const uint32_t off[] = { 0, 3, 6, 9, 12, 15, 18, 21, 24 };
    static const uint32_t idx[] = { 0,2,4, 2,1,4, 1,3,4, 3,0,4, 2,0,5, 1,2,5, 3,1,5, 0,3,5 };
    tl_mesh_make(s, p, 6, off, idx, 8);
}

static void valid(st_map *m, const char *what)
{
    st_error err;
    int rc = st_map_validate(m, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
}

/* Every undirected edge of the displayed mesh in exactly two faces with
 * opposite directions (closed inputs), or one (open inputs, boundary). */
static int watertight(const st_mesh *s, int closed)
{
    uint32_t n = s->face_off[s->nfaces];
    uint64_t *key = malloc((size_t)n * sizeof *key);
    for (uint32_t f = 0, k = 0; f < s->nfaces; f++)
        for (uint32_t j = s->face_off[f]; j < s->face_off[f + 1]; j++, k++) {
            uint32_t a = s->face_idx[j], b = s->face_idx[j + 1 < s->face_off[f + 1] ? j + 1 : s->face_off[f]];
            key[k] = (uint64_t)a << 32 | b;
        }
    int ok = 1;
    for (uint32_t k = 0; k < n && ok; k++) {
        uint64_t rev = (key[k] & 0xffffffffu) << 32 | key[k] >> 32;
        unsigned same = 0, opp = 0;
        for (uint32_t j = 0; j < n; j++) { same += key[j] == key[k]; opp += key[j] == rev; }
        if (same != 1 || opp > 1 || (closed && opp != 1)) ok = 0;
    }
    free(key);
    return ok;
}

/* The one-level restriction: faces of the displayed (top) level that share
 * a vertex differ by at most one subdivision level. */
static int restriction_holds(st_map *m)
{
    unsigned T = m->top;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, T, &it); d != ST_NIL; d = st_dart_next(m, T, &it)) {
        if (st_is_boundary(m, d)) continue;
        unsigned fl = st_face_level(m, d, T);
        uint32_t y = d;
        do {
            if (!st_is_boundary(m, y) && fl > st_face_level(m, y, T) + 1) return 0;
            y = st_beta1(m, y, T);
        } while (y != d);
    }
    return 1;
}

static void check_display(st_adapt *a, int closed, const char *what)
{
    st_mesh s;
    st_error err;
    st_mesh_init(&s);
    CHECK(st_adapt_mesh(a, &s, &err) == ST_OK);
    CHECKF(watertight(&s, closed), "%s: displayed mesh not watertight", what);
    st_mesh_free(&s);
}

static st_adapt_params box_params(double cx, double cy, double cz, double r, unsigned base, unsigned max)
{
    st_adapt_params p = { .base_level = base, .max_level = max, .has_box = 1 };
    p.box_lo[0] = cx - r; p.box_lo[1] = cy - r; p.box_lo[2] = cz - r;
    p.box_hi[0] = cx + r; p.box_hi[1] = cy + r; p.box_hi[2] = cz + r;
    return p;
}

/* Largest distance from a point of a to the nearest point of b. */
static double pointset_dist(const st_mesh *a, const st_mesh *b)
{
    double worst = 0;
    for (uint32_t v = 0; v < a->nverts; v++) {
        double best = INFINITY;
        for (uint32_t w = 0; w < b->nverts; w++) {
            double d = 0;
            for (int k = 0; k < 3; k++) d += (a->pos[3 * v + k] - b->pos[3 * w + k]) * (a->pos[3 * v + k] - b->pos[3 * w + k]);
            best = fmin(best, d);
        }
        worst = fmax(worst, sqrt(best));
    }
    return worst;
}

/* Random box moves with fixed seeds: every level valid, display watertight. */
static void check_random_moves(st_scheme_id id, void (*make)(st_mesh *), int closed, unsigned max, double extent)
{
    st_hier h;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, make, id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    uint64_t rng = 31 + id;
    for (int step = 0; step < 12; step++) {
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = extent * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        st_adapt_params p = box_params(c[0], c[1], c[2], 0.3 * extent, tl_rand(&rng) % 2, max);
        int rc = st_adapt_update(&a, &p, &err);
        CHECKF(rc == ST_OK, "%s step %d: %s", h.scheme->name, step, err.msg);
        valid(&h.map, h.scheme->name);
        check_display(&a, closed, h.scheme->name);
        CHECKF(restriction_holds(&h.map), "%s step %d: faces sharing a vertex differ by more than one level",
               h.scheme->name, step);
    }
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* Nearest squared distance from p to the level-l points of a regular hierarchy. */
static double nearest(const st_hier *r, unsigned l, const double *p)
{
    double best = INFINITY;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&r->map, l, &it); v != ST_NIL; v = st_vertex_next(&r->map, l, &it)) {
        const double *q = st_pos(&r->map, v, l);
        double d = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
        if (d < best) best = d;
    }
    return sqrt(best);
}

/* With the restriction, every vertex of every face of level k has the
 * position it has at level k of the regular hierarchy. */
static void check_matches_regular(st_scheme_id id, void (*make)(st_mesh *), unsigned max, double extent)
{
    st_hier h, r;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, make, id, 0);
    tl_init_hier(&r, make, id, max);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = box_params(0.5 * extent, 0.2 * extent, 0, 0.35 * extent, 0, max);
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    double worst = 0;
    unsigned checked = 0;
    for (unsigned k = 1; k <= h.map.top; k++) {
        st_dart_iter it;
        int fb = st_marker_reserve(&h.map);
        for (uint32_t d = st_dart_first(&h.map, k, &it); d != ST_NIL; d = st_dart_next(&h.map, k, &it)) {
            if (st_is_boundary(&h.map, d) || st_marked(&h.map, fb, d)) continue;
            st_mark_face(&h.map, fb, d, k);
            if (st_face_level(&h.map, d, k) != k) continue;
            uint32_t x = d;
            do {
                worst = fmax(worst, nearest(&r, k, st_dart_pos(&h.map, x, k)));
                checked++;
                x = st_phi1(&h.map, x, k);
            } while (x != d);
        }
        st_marker_release(&h.map, fb, k);
    }
    CHECKF(worst < 1e-9 * extent && checked > 0, "%s: adaptive vs regular %g over %u corners", h.scheme->name, worst, checked);
    /* A box covering everything gives the regular finest level; one covering
     * nothing gives the base level. */
    st_adapt_params all = box_params(0, 0, 0, 100 * extent, 0, max);
    CHECK(st_adapt_update(&a, &all, &err) == ST_OK);
    st_mesh s, t;
    st_mesh_init(&s);
    st_mesh_init(&t);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    CHECK(st_hier_level_mesh(&r, max, &t, &err) == ST_OK);
    CHECKF(s.nfaces == t.nfaces && s.nverts == t.nverts, "%s: all-in %u/%u faces vs regular %u/%u", h.scheme->name, s.nfaces, s.nverts, t.nfaces, t.nverts);
    double dmax = 0;
    for (uint32_t v = 0; v < s.nverts; v++) dmax = fmax(dmax, nearest(&r, max, s.pos + 3 * v));
    CHECKF(dmax < 1e-9 * extent, "%s: all-in differs from regular by %g", h.scheme->name, dmax);
    st_adapt_params none = box_params(1000 * extent, 0, 0, 0.1, 0, max);
    CHECK(st_adapt_update(&a, &none, &err) == ST_OK);
    st_mesh_free(&s);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    st_mesh_free(&t);
    CHECK(st_hier_level_mesh(&r, 0, &t, &err) == ST_OK);
    CHECKF(s.nfaces == t.nfaces, "%s: none-in %u faces vs base %u", h.scheme->name, s.nfaces, t.nfaces);
    dmax = 0;
    for (uint32_t v = 0; v < s.nverts; v++) dmax = fmax(dmax, nearest(&r, 0, s.pos + 3 * v));
    CHECKF(dmax < 1e-12, "%s: none-in differs from base by %g", h.scheme->name, dmax);
    valid(&h.map, "after all-in / none-in");
    st_mesh_free(&s);
    st_mesh_free(&t);
    st_adapt_free(&a);
    st_hier_free(&h);
    st_hier_free(&r);
}

/* Refine, put details on the fine vertices at every level, move the box
 * away and back (then half away and back): the same geometry.  Details of
 * removed vertices are kept by refinement-tree address, in world space, and
 * turned back into the frames of the recreated cells (adapt.c). */
static void check_detail_round_trip(st_scheme_id id, void (*make)(st_mesh *), unsigned max, double extent)
{
    st_hier h;
    st_adapt a;
    st_error err;
    uint64_t rng = 5;
    tl_init_hier(&h, make, id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params in = box_params(0.4 * extent, 0, 0, 0.4 * extent, 0, max);
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    for (unsigned l = 1; l <= h.map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            double d[3];
            for (int k = 0; k < 3; k++) d[k] = 0.02 * extent * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
            st_hier_set_detail(&h, l, v, d);
        }
    }
    st_adapt_synthesize(&a, 0);
    /* The edit moved the surface: let the criterion settle on it first. */
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    st_mesh before, after;
    st_mesh_init(&before);
    st_mesh_init(&after);
    CHECK(st_adapt_mesh(&a, &before, &err) == ST_OK);
    st_adapt_params away = box_params(-10 * extent, 0, 0, 0.1, 0, max);
    CHECK(st_adapt_update(&a, &away, &err) == ST_OK);
    valid(&h.map, "box away");
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    valid(&h.map, "box back");
    /* Then a partial coarsening (the box half away) and back once more. */
    st_adapt_params half = box_params(0.8 * extent, 0.2 * extent, 0, 0.4 * extent, 0, max);
    CHECK(st_adapt_update(&a, &half, &err) == ST_OK);
    valid(&h.map, "box half away");
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    CHECK(st_adapt_mesh(&a, &after, &err) == ST_OK);
    CHECKF(before.nverts == after.nverts && before.nfaces == after.nfaces, "%s: %u/%u vs %u/%u", h.scheme->name,
           before.nverts, before.nfaces, after.nverts, after.nfaces);
    /* Compare as point sets (vertex ids may be reassigned). */
    double worst = pointset_dist(&after, &before);
    CHECKF(worst < 1e-6 * extent, "%s: away and back moved the surface by %g", h.scheme->name, worst);
    st_mesh_free(&before);
    st_mesh_free(&after);
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* The incremental update (box moved, nothing else changed) gives the same
 * mesh as a full update, along a random walk of the box. */
static void check_incremental(st_scheme_id id, void (*make)(st_mesh *), unsigned max, double extent)
{
    st_hier h, g;
    st_adapt a, b;
    st_error err;
    tl_init_hier(&h, make, id, 0);
    tl_init_hier(&g, make, id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK && st_adapt_init(&b, &g, &err) == ST_OK);
    uint64_t rng = 77 + id;
    double c[3] = { 0.5 * extent, 0, 0 };
    for (int step = 0; step < 16; step++) {
        for (int k = 0; k < 3; k++) c[k] += 0.15 * extent * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        st_adapt_params p = box_params(c[0], c[1], c[2], 0.3 * extent, 0, max);
        p.falloff = step % 3 ? 0 : 0.2 * extent;
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        b.has_prev = 0; /* force the full update */
        CHECK(st_adapt_update(&b, &p, &err) == ST_OK);
        st_mesh s, t;
        st_mesh_init(&s);
        st_mesh_init(&t);
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK && st_adapt_mesh(&b, &t, &err) == ST_OK);
        double worst = pointset_dist(&s, &t);
        CHECKF(s.nfaces == t.nfaces && s.nverts == t.nverts && worst < 1e-12,
               "%s step %d: incremental %u faces / %u verts, full %u / %u, max distance %g", h.scheme->name, step,
               s.nfaces, s.nverts, t.nfaces, t.nverts, worst);
        valid(&h.map, "incremental update");
        st_mesh_free(&s);
        st_mesh_free(&t);
    }
    st_adapt_free(&a);
    st_adapt_free(&b);
    st_hier_free(&h);
    st_hier_free(&g);
}

/* Adaptive access (§3.3.2) on a regular hierarchy shows the mesh adaptive
 * refinement builds for the same criteria: same faces, same points, no
 * T-junction; with the restriction off it is still watertight. */
static void check_access(st_scheme_id id, void (*make)(st_mesh *), int closed, unsigned max, double extent)
{
    st_hier r;
    st_error err;
    tl_init_hier(&r, make, id, max);
    uint64_t rng = 211 + id;
    for (int step = 0; step < 6; step++) {
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = extent * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        st_adapt_params p = box_params(c[0], c[1], c[2], (0.2 + 0.1 * step) * extent, step % 2, max);
        if (step == 4) p = box_params(0, 0, 0, 100 * extent, 0, max);     /* everything */
        if (step == 5) p = box_params(1000 * extent, 0, 0, 0.1, 1, max);  /* nothing: base level 1 */
        if (step == 2) p.falloff = 0.3 * extent;
        st_hier h;
        st_adapt a;
        tl_init_hier(&h, make, id, 0);
        CHECK(st_adapt_init(&a, &h, &err) == ST_OK && st_adapt_update(&a, &p, &err) == ST_OK);
        st_mesh want, got;
        st_mesh_init(&want);
        st_mesh_init(&got);
        st_access_stats st;
        CHECK(st_adapt_mesh(&a, &want, &err) == ST_OK);
        CHECKF(st_access_mesh(&r, &p, &got, &st, &err) == ST_OK, "%s", err.msg);
        double dist = fmax(pointset_dist(&got, &want), pointset_dist(&want, &got));
        CHECKF(got.nfaces == want.nfaces && got.nverts == want.nverts && dist < 1e-9 * extent,
               "%s step %d: access %u faces / %u verts, adaptive %u / %u, distance %g", r.scheme->name, step,
               got.nfaces, got.nverts, want.nfaces, want.nverts, dist);
        CHECKF(watertight(&got, closed), "%s step %d: access mesh not watertight", r.scheme->name, step);
        valid(&r.map, "after adaptive access");
        CHECKF(r.map.marks_used == 0, "%s: marker bits leaked (%#x)", r.scheme->name, r.map.marks_used);
        p.no_restriction = 1;
        st_mesh_free(&got);
        CHECK(st_access_mesh(&r, &p, &got, NULL, &err) == ST_OK);
        CHECKF(watertight(&got, closed), "%s step %d: access mesh without restriction not watertight", r.scheme->name, step);
        st_mesh_free(&want);
        st_mesh_free(&got);
        st_adapt_free(&a);
        st_hier_free(&h);
    }
    st_hier_free(&r);
}

/* Synthesis after the box left the finer levels empty (no face subdivided
 * at the first level synthesised) changes nothing. */
static void check_synthesize_empty_levels(st_scheme_id id, void (*make)(st_mesh *), unsigned max, double extent)
{
    st_hier h;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, make, id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = box_params(0.5 * extent, 0, 0, 0.4 * extent, 0, max);
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
    CHECKF(dist < 1e-12 * extent, "%s: synthesis over levels with no subdivided face moved the mesh by %g", h.scheme->name, dist);
    st_mesh_free(&before);
    st_mesh_free(&after);
    st_adapt_free(&a);
    st_hier_free(&h);
}

int main(void)
{
    struct { st_scheme_id id; void (*make)(st_mesh *); int closed; unsigned max; double extent; } cases[] = {
        { ST_SCHEME_CATMARK, torus, 1, 3, 2.7 },
        { ST_SCHEME_CATMARK, grid, 0, 3, 4 },
        { ST_SCHEME_CATMARK, tl_mesh_cube, 1, 3, 1 },
        { ST_SCHEME_LOOP, octa, 1, 3, 1 },
        { ST_SCHEME_BUTTERFLY, octa, 1, 3, 1 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        check_random_moves(cases[i].id, cases[i].make, cases[i].closed, cases[i].max, cases[i].extent);
        check_matches_regular(cases[i].id, cases[i].make, cases[i].max, cases[i].extent);
        check_detail_round_trip(cases[i].id, cases[i].make, cases[i].max, cases[i].extent);
        check_incremental(cases[i].id, cases[i].make, cases[i].max, cases[i].extent);
        check_access(cases[i].id, cases[i].make, cases[i].closed, cases[i].max, cases[i].extent);
        check_synthesize_empty_levels(cases[i].id, cases[i].make, cases[i].max, cases[i].extent);
    }
    return TEST_END();
}
