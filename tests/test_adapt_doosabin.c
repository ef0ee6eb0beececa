/* Adaptive Doo-Sabin through the dual encoding (adapt_doosabin.c): validity
 * after random box moves, a closed polygonal display, agreement with the
 * regular Doo-Sabin hierarchy (box over everything) and with the base level
 * (box over nothing), the detail round trip, resynthesis, incremental ==
 * full updates, the flatness criterion, and the refusal of open meshes. */
#include "adapt.h"
#include "hier_internal.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void octa(st_mesh *s)
{
    static const double p[] = { 1,0,0, -1,0,0, 0,1,0, 0,-1,0, 0,0,1, 0,0,-1 };
    static const uint32_t off[] = { 0, 3, 6, 9, 12, 15, 18, 21, 24 };
    static const uint32_t idx[] = { 0,2,4, 2,1,4, 1,3,4, 3,0,4, 2,0,5, 1,2,5, 3,1,5, 0,3,5 };
    tl_mesh_make(s, p, 6, off, idx, 8);
}

static void cube(st_mesh *s) { tl_mesh_cube(s); }
static void torus(st_mesh *s) { tl_mesh_torus(s, 8, 6); }
static void tetra(st_mesh *s) { tl_mesh_tetra(s); }


/* A cube with one corner cut off: a triangle, three pentagons, three quads. */
static void cut_cube(st_mesh *s)
{
    static const double p[] = { -1,-1,-1, 1,-1,-1, 1,1,-1, -1,1,-1, -1,-1,1, 1,-1,0.3, 1,1,1, -1,1,1, 0.3,-1,1, 1,-0.3,1 };
    static const uint32_t off[] = { 0, 4, 8, 12, 17, 22, 27, 30 };
    static const uint32_t idx[] = { 0,3,2,1, 0,4,7,3, 3,7,6,2, 0,1,5,8,4, 4,8,9,6,7, 1,2,6,9,5, 8,5,9 };
    tl_mesh_make(s, p, 10, off, idx, 7);
}

static void valid(st_map *m, const char *what)
{
    st_error err;
    int rc = st_map_validate(m, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
}

static int cmp(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* Every undirected edge of the displayed mesh in exactly two faces, with
 * opposite directions; every face has at least 3 sides. */
static int watertight(const st_mesh *s)
{
    uint32_t n = s->face_off[s->nfaces];
    for (uint32_t f = 0; f < s->nfaces; f++)
        if (s->face_off[f + 1] - s->face_off[f] < 3) return 0;
    uint64_t *key = malloc((size_t)n * sizeof *key), *sorted = malloc((size_t)n * sizeof *sorted);
    for (uint32_t f = 0, k = 0; f < s->nfaces; f++)
        for (uint32_t j = s->face_off[f]; j < s->face_off[f + 1]; j++, k++) {
            uint32_t a = s->face_idx[j], b = s->face_idx[j + 1 < s->face_off[f + 1] ? j + 1 : s->face_off[f]];
            key[k] = (uint64_t)a << 32 | b;
        }
    memcpy(sorted, key, (size_t)n * sizeof *key);
    qsort(sorted, n, sizeof *sorted, cmp);
    int ok = 1;
    for (uint32_t k = 0; k + 1 < n && ok; k++)
        if (sorted[k] == sorted[k + 1]) ok = 0; /* a directed edge twice */
    for (uint32_t k = 0; k < n && ok; k++) {
        uint64_t rev = (key[k] & 0xffffffffu) << 32 | key[k] >> 32;
        if (!bsearch(&rev, sorted, n, sizeof *sorted, cmp)) ok = 0;
    }
    free(key);
    free(sorted);
    return ok;
}

/* Faces of the top level sharing a vertex differ by at most one level. */
static int restriction_holds(st_map *m)
{
    unsigned T = m->top;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, T, &it); d != ST_NIL; d = st_dart_next(m, T, &it)) {
        unsigned fl = st_face_level(m, d, T);
        uint32_t y = d;
        do {
            if (fl > st_face_level(m, y, T) + 1) return 0;
            y = st_beta1(m, y, T);
        } while (y != d);
    }
    return 1;
}

static void check_display(st_adapt *a, const char *what, int step)
{
    st_mesh s;
    st_error err;
    st_mesh_init(&s);
    CHECK(st_adapt_mesh(a, &s, &err) == ST_OK);
    CHECKF(watertight(&s), "%s step %d: displayed mesh not closed", what, step);
    st_mesh_free(&s);
}

static st_adapt_params box_params(double cx, double cy, double cz, double r, unsigned base, unsigned max)
{
    st_adapt_params p = { .base_level = base, .max_level = max, .has_box = 1 };
    p.box_lo[0] = cx - r; p.box_lo[1] = cy - r; p.box_lo[2] = cz - r;
    p.box_hi[0] = cx + r; p.box_hi[1] = cy + r; p.box_hi[2] = cz + r;
    return p;
}

static int cmp_x(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* Points of b sorted by x (3 doubles each), for nearest-point queries. */
typedef struct sorted_pts { double *p; uint32_t n; } sorted_pts;

static sorted_pts sort_pts(const st_mesh *b)
{
    sorted_pts s = { malloc(((size_t)b->nverts * 3 + 1) * sizeof(double)), b->nverts };
    memcpy(s.p, b->pos, (size_t)b->nverts * 3 * sizeof(double));
    qsort(s.p, s.n, 3 * sizeof(double), cmp_x);
    return s;
}

static double nearest_sorted(const sorted_pts *s, const double *p)
{
    uint32_t lo = 0, hi = s->n;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (s->p[3 * mid] < p[0]) lo = mid + 1; else hi = mid;
    }
    double best = INFINITY;
    for (uint32_t k = lo; k < s->n; k++) {
        double dx = s->p[3 * k] - p[0];
        if (dx * dx > best) break;
        double d = dx * dx + (s->p[3 * k + 1] - p[1]) * (s->p[3 * k + 1] - p[1]) + (s->p[3 * k + 2] - p[2]) * (s->p[3 * k + 2] - p[2]);
        best = fmin(best, d);
    }
    for (uint32_t k = lo; k-- > 0;) {
        double dx = s->p[3 * k] - p[0];
        if (dx * dx > best) break;
        double d = dx * dx + (s->p[3 * k + 1] - p[1]) * (s->p[3 * k + 1] - p[1]) + (s->p[3 * k + 2] - p[2]) * (s->p[3 * k + 2] - p[2]);
        best = fmin(best, d);
    }
    return sqrt(best);
}

/* Largest distance from a point of a to the nearest point of b. */
static double pointset_dist(const st_mesh *a, const st_mesh *b)
{
    sorted_pts s = sort_pts(b);
    double worst = 0;
    for (uint32_t v = 0; v < a->nverts; v++) worst = fmax(worst, nearest_sorted(&s, a->pos + 3 * v));
    free(s.p);
    return worst;
}

/* Random box moves with fixed seeds: every level valid, display watertight,
 * restriction kept. */
static void check_random_moves(void (*make)(st_mesh *), const char *name, unsigned max, double extent, uint64_t seed)
{
    st_hier h;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    uint64_t rng = seed;
    for (int step = 0; step < 14; step++) {
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = extent * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        st_adapt_params p = box_params(c[0], c[1], c[2], (0.15 + 0.05 * (step % 4)) * extent, tl_rand(&rng) % 2, max);
        if (step % 5 == 2) p.falloff = 0.2 * extent;
        if (step % 7 == 3) p.no_restriction = 1; /* ignored by √3: still valid */
        int rc = st_adapt_update(&a, &p, &err);
        CHECKF(rc == ST_OK, "%s step %d: %s", name, step, err.msg);
        valid(&h.map, name);
        check_display(&a, name, step);
        CHECKF(restriction_holds(&h.map), "%s step %d: faces sharing a vertex differ by more than one level", name, step);
    }
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* Every corner of every face of level k has its level-k position in the
 * regular hierarchy; the box over everything gives the regular top level,
 * over nothing the base level. */
static void check_matches_regular(void (*make)(st_mesh *), const char *name, unsigned max, double extent)
{
    st_hier h, r;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
    tl_init_hier(&r, make, ST_SCHEME_DOOSABIN, max);
    st_mesh lev[8];
    sorted_pts sl[8];
    for (unsigned k = 0; k <= max; k++) {
        st_mesh_init(&lev[k]);
        CHECK(st_hier_level_mesh(&r, k, &lev[k], &err) == ST_OK);
        sl[k] = sort_pts(&lev[k]);
    }
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = box_params(0.5 * extent, 0.2 * extent, 0, 0.35 * extent, 0, max);
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    double worst = 0;
    unsigned checked = 0, per_level[8] = { 0 };
    for (unsigned k = 1; k <= h.map.top; k++) {
        st_dart_iter it;
        int fb = st_marker_reserve(&h.map);
        for (uint32_t d = st_dart_first(&h.map, k, &it); d != ST_NIL; d = st_dart_next(&h.map, k, &it)) {
            if (st_marked(&h.map, fb, d)) continue;
            st_mark_face(&h.map, fb, d, k);
            if (st_face_level(&h.map, d, k) != k) continue;
            per_level[k]++;
            uint32_t x = d;
            do {
                worst = fmax(worst, nearest_sorted(&sl[k], st_dart_pos(&h.map, x, k)));
                checked++;
                x = st_phi1(&h.map, x, k);
            } while (x != d);
        }
        st_marker_release(&h.map, fb, k);
    }
    CHECKF(h.map.top == max, "%s: top %u, max %u", name, h.map.top, max);
    for (unsigned k = 1; k <= max; k++) CHECKF(per_level[k] > 0, "%s: no face of level %u", name, k);
    CHECKF(worst < 1e-9 * extent && checked > 0, "%s: adaptive vs regular %g over %u corners", name, worst, checked);
    /* Border polygons (surface faces whose corners are of two levels) at
     * the depth borders of every level. */
    unsigned border = 0;
    for (unsigned k = 1; k <= h.map.top; k++) {
        st_dart_iter it;
        for (uint32_t d = st_dart_first(&h.map, k, &it); d != ST_NIL; d = st_dart_next(&h.map, k, &it))
            if (st_face_level(&h.map, d, k) == k && st_face_level(&h.map, st_beta1(&h.map, d, k), k) == k - 1) border++;
    }
    CHECKF(border > 0, "%s: no border polygon", name);
    /* The partial mesh is smaller than the regular one. */
    st_mesh s;
    st_mesh_init(&s);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    CHECKF(s.nfaces < lev[max].nfaces && s.nfaces > lev[0].nfaces, "%s: partial %u faces (base %u, regular %u)", name,
           s.nfaces, lev[0].nfaces, lev[max].nfaces);
    st_mesh_free(&s);

    st_adapt_params all = box_params(0, 0, 0, 100 * extent, 0, max);
    CHECK(st_adapt_update(&a, &all, &err) == ST_OK);
    valid(&h.map, "all-in");
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    double dmax = fmax(pointset_dist(&s, &lev[max]), pointset_dist(&lev[max], &s));
    CHECKF(s.nfaces == lev[max].nfaces && s.nverts == lev[max].nverts && dmax < 1e-9 * extent,
           "%s: all-in %u faces / %u verts vs regular %u / %u, distance %g", name, s.nfaces, s.nverts, lev[max].nfaces,
           lev[max].nverts, dmax);
    st_mesh_free(&s);

    for (unsigned base = 0; base <= 1; base++) {
        st_adapt_params none = box_params(1000 * extent, 0, 0, 0.1, base, max);
        CHECK(st_adapt_update(&a, &none, &err) == ST_OK);
        valid(&h.map, "none-in");
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
        dmax = fmax(pointset_dist(&s, &lev[base]), pointset_dist(&lev[base], &s));
        CHECKF(s.nfaces == lev[base].nfaces && s.nverts == lev[base].nverts && dmax < 1e-12 * extent,
               "%s: none-in (base %u) %u faces / %u verts vs %u / %u, distance %g", name, base, s.nfaces, s.nverts,
               lev[base].nfaces, lev[base].nverts, dmax);
        check_display(&a, name, -1);
        st_mesh_free(&s);
    }
    /* And back up: the same partial mesh as the first time. */
    CHECK(st_adapt_update(&a, &all, &err) == ST_OK);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    dmax = fmax(pointset_dist(&s, &lev[max]), pointset_dist(&lev[max], &s));
    CHECKF(s.nfaces == lev[max].nfaces && dmax < 1e-9 * extent, "%s: all-in again: %u faces, distance %g", name, s.nfaces, dmax);
    st_mesh_free(&s);
    for (unsigned k = 0; k <= max; k++) {
        st_mesh_free(&lev[k]);
        free(sl[k].p);
    }
    st_adapt_free(&a);
    st_hier_free(&h);
    st_hier_free(&r);
}

/* Refine, put details on every vertex at every level, move the box away and
 * back, then half away and back: the same geometry (1e-6 of the extent). */
static void check_detail_round_trip(void (*make)(st_mesh *), const char *name, unsigned max, double extent)
{
    st_hier h;
    st_adapt a;
    st_error err;
    uint64_t rng = 5;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
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
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    /* Settled: the same criteria again change nothing (an odd triangle and
     * the even ones replacing it get the same answer: no refine/simplify
     * cycle, adapt_sqrt3.c). */
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    CHECKF(a.touched == 0, "%s: settled update touched %llu faces", name, (unsigned long long)a.touched);
    st_mesh before, after;
    st_mesh_init(&before);
    st_mesh_init(&after);
    CHECK(st_adapt_mesh(&a, &before, &err) == ST_OK);
    st_adapt_params away = box_params(-10 * extent, 0, 0, 0.1, 0, max);
    CHECK(st_adapt_update(&a, &away, &err) == ST_OK);
    valid(&h.map, "box away");
    CHECKF(a.nsaved > 0, "%s: no detail saved", name);
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    valid(&h.map, "box back");
    st_adapt_params half = box_params(0.8 * extent, 0.2 * extent, 0, 0.4 * extent, 0, max);
    CHECK(st_adapt_update(&a, &half, &err) == ST_OK);
    valid(&h.map, "box half away");
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    CHECK(st_adapt_mesh(&a, &after, &err) == ST_OK);
    CHECKF(before.nverts == after.nverts && before.nfaces == after.nfaces, "%s: %u/%u vs %u/%u", name, before.nverts,
           before.nfaces, after.nverts, after.nfaces);
    double worst = fmax(pointset_dist(&after, &before), pointset_dist(&before, &after));
    CHECKF(worst < 1e-6 * extent, "%s: away and back moved the surface by %g", name, worst);
    st_mesh_free(&before);
    st_mesh_free(&after);
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* Resynthesis from level 0 of an unedited adaptive hierarchy changes no
 * position (the emitted stencils agree with the placement, odd triangles
 * included); repeated updates with the same criteria touch nothing; the
 * update after a box move equals a fresh full update. */
static void check_resynth_and_repeat(void (*make)(st_mesh *), const char *name, unsigned max, double extent)
{
    st_hier h, g;
    st_adapt a, b;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
    tl_init_hier(&g, make, ST_SCHEME_DOOSABIN, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK && st_adapt_init(&b, &g, &err) == ST_OK);
    uint64_t rng = 99;
    double c[3] = { 0.5 * extent, 0, 0 };
    for (int step = 0; step < 8; step++) {
        for (int k = 0; k < 3; k++) c[k] += 0.15 * extent * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        st_adapt_params p = box_params(c[0], c[1], c[2], 0.3 * extent, 0, max);
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        st_mesh s, t;
        st_mesh_init(&s);
        st_mesh_init(&t);
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
        tl_posnap s0, s1;
        tl_snap_pos(&h, &s0);
        st_adapt_synthesize(&a, 0);
        tl_snap_pos(&h, &s1);
        CHECKF(tl_snap_maxdiff(&s0, &s1) < 1e-12 * extent, "%s step %d: resynthesis moved a vertex by %g", name, step,
               tl_snap_maxdiff(&s0, &s1));
        free(s0.p);
        free(s1.p);
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        CHECKF(a.touched == 0, "%s step %d: the same criteria again touched %llu faces", name, step, (unsigned long long)a.touched);
        /* A fresh hierarchy brought to the same criteria in one update. */
        st_adapt_free(&b);
        st_hier_free(&g);
        tl_init_hier(&g, make, ST_SCHEME_DOOSABIN, 0);
        CHECK(st_adapt_init(&b, &g, &err) == ST_OK);
        CHECK(st_adapt_update(&b, &p, &err) == ST_OK);
        CHECK(st_adapt_mesh(&b, &t, &err) == ST_OK);
        double worst = fmax(pointset_dist(&s, &t), pointset_dist(&t, &s));
        CHECKF(s.nfaces == t.nfaces && s.nverts == t.nverts && worst < 1e-9 * extent,
               "%s step %d: after moves %u faces / %u verts, fresh %u / %u, distance %g", name, step, s.nfaces, s.nverts,
               t.nfaces, t.nverts, worst);
        st_mesh_free(&s);
        st_mesh_free(&t);
    }
    st_adapt_free(&a);
    st_adapt_free(&b);
    st_hier_free(&h);
    st_hier_free(&g);
}

/* Regular levels already built below the adaptive ones: adapting on top of
 * a hierarchy of depth 1 gives the same as from level 0 with base level 1. */
static void check_on_regular_levels(void (*make)(st_mesh *), const char *name, unsigned max, double extent)
{
    st_hier h, g;
    st_adapt a, b;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 1);
    tl_init_hier(&g, make, ST_SCHEME_DOOSABIN, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK && st_adapt_init(&b, &g, &err) == ST_OK);
    st_adapt_params p = box_params(0.3 * extent, -0.2 * extent, 0.1 * extent, 0.3 * extent, 1, max);
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK && st_adapt_update(&b, &p, &err) == ST_OK);
    valid(&h.map, name);
    st_mesh s, t;
    st_mesh_init(&s);
    st_mesh_init(&t);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK && st_adapt_mesh(&b, &t, &err) == ST_OK);
    double worst = fmax(pointset_dist(&s, &t), pointset_dist(&t, &s));
    CHECKF(s.nfaces == t.nfaces && worst < 1e-9 * extent, "%s: on regular level 1: %u faces vs %u, distance %g", name,
           s.nfaces, t.nfaces, worst);
    st_mesh_free(&s);
    st_mesh_free(&t);
    st_adapt_free(&a);
    st_adapt_free(&b);
    st_hier_free(&h);
    st_hier_free(&g);
}

/* The flatness criterion alone, then with a box: valid, watertight, and
 * refined somewhere but not everywhere. */
static void check_flatness(void (*make)(st_mesh *), const char *name, unsigned max)
{
    st_hier h, r;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
    tl_init_hier(&r, make, ST_SCHEME_DOOSABIN, max);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = { .max_level = max, .flatness = 0.5 };
    for (int step = 0; step < 2; step++) {
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        valid(&h.map, name);
        check_display(&a, name, 100 + step);
        st_mesh s, t, b;
        st_mesh_init(&s);
        st_mesh_init(&t);
        st_mesh_init(&b);
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
        CHECK(st_hier_level_mesh(&r, max, &t, &err) == ST_OK && st_hier_level_mesh(&r, 0, &b, &err) == ST_OK);
        CHECKF(s.nfaces > b.nfaces && s.nfaces < t.nfaces, "%s flatness: %u faces (base %u, regular %u)", name, s.nfaces,
               b.nfaces, t.nfaces);
        st_mesh_free(&s);
        st_mesh_free(&t);
        st_mesh_free(&b);
        p.has_box = 1;
        for (int k = 0; k < 3; k++) { p.box_lo[k] = -0.2; p.box_hi[k] = 0.2; }
        p.box_lo[0] = 2;
        p.box_hi[0] = 3;
    }
    st_adapt_free(&a);
    st_hier_free(&h);
    st_hier_free(&r);
}

/* The incremental update (only the box moved: the faces near the old and
 * new boxes are visited) gives the same mesh as a full update, along a
 * random walk of the box. */
static void check_incremental(void (*make)(st_mesh *), const char *name, unsigned max, double extent, double r)
{
    st_hier h, g;
    st_adapt a, b;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
    tl_init_hier(&g, make, ST_SCHEME_DOOSABIN, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK && st_adapt_init(&b, &g, &err) == ST_OK);
    uint64_t rng = 77;
    double c[3] = { 0.5 * extent, 0, 0 };
    uint64_t touched_inc = 0;
    for (int step = 0; step < 24; step++) {
        for (int k = 0; k < 3; k++) c[k] += 0.15 * extent * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        st_adapt_params p = box_params(c[0], c[1], c[2], r * extent, 0, max);
        p.falloff = step % 3 ? 0 : 0.2 * extent;
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        touched_inc += a.touched;
        b.has_prev = 0; /* force the full update */
        CHECK(st_adapt_update(&b, &p, &err) == ST_OK);
        st_mesh s, t;
        st_mesh_init(&s);
        st_mesh_init(&t);
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK && st_adapt_mesh(&b, &t, &err) == ST_OK);
        double worst = fmax(pointset_dist(&s, &t), pointset_dist(&t, &s));
        CHECKF(s.nfaces == t.nfaces && s.nverts == t.nverts && worst < 1e-12 * extent,
               "%s step %d: incremental %u faces / %u verts, full %u / %u, max distance %g", name, step, s.nfaces,
               s.nverts, t.nfaces, t.nverts, worst);
        valid(&h.map, "incremental update");
        st_mesh_free(&s);
        st_mesh_free(&t);
    }
    CHECK(touched_inc > 0);
    st_adapt_free(&a);
    st_adapt_free(&b);
    st_hier_free(&h);
    st_hier_free(&g);
}

/* Random criteria (box sizes, base levels, falloff, flatness, no box):
 * after every update the same criteria again change nothing, and the mesh
 * equals the one a fresh hierarchy gets in one update (the result does not
 * depend on earlier updates). */
static void check_history_free(void (*make)(st_mesh *), const char *name, double e, uint64_t seed)
{
    st_hier h;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    uint64_t rng = seed;
    for (int step = 0; step < 12; step++) {
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = e * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        st_adapt_params p = box_params(c[0], c[1], c[2], (0.1 + 0.1 * (tl_rand(&rng) % 4)) * e, tl_rand(&rng) % 3, 4);
        if (tl_rand(&rng) % 2) p.falloff = 0.15 * e;
        if (tl_rand(&rng) % 3 == 0) p.flatness = 0.3;
        if (tl_rand(&rng) % 4 == 0) p.has_box = 0;
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        valid(&h.map, name);
        check_display(&a, name, step);
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        CHECKF(a.touched == 0, "%s step %d: the same criteria again touched %llu faces", name, step, (unsigned long long)a.touched);
        st_hier g;
        st_adapt b;
        tl_init_hier(&g, make, ST_SCHEME_DOOSABIN, 0);
        CHECK(st_adapt_init(&b, &g, &err) == ST_OK && st_adapt_update(&b, &p, &err) == ST_OK);
        st_mesh s, t;
        st_mesh_init(&s);
        st_mesh_init(&t);
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK && st_adapt_mesh(&b, &t, &err) == ST_OK);
        double w = fmax(pointset_dist(&s, &t), pointset_dist(&t, &s));
        CHECKF(s.nfaces == t.nfaces && s.nverts == t.nverts && w < 1e-9 * e, "%s step %d: %u faces after moves, %u fresh, distance %g",
               name, step, s.nfaces, t.nfaces, w);
        st_mesh_free(&s);
        st_mesh_free(&t);
        st_adapt_free(&b);
        st_hier_free(&g);
    }
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* The one-level restriction is always applied for Doo-Sabin: with
 * no_restriction set, the same mesh as with it. */
static void check_restriction_flag_ignored(void (*make)(st_mesh *), const char *name, unsigned max, double extent)
{
    st_hier h, g;
    st_adapt a, b;
    st_error err;
    tl_init_hier(&h, make, ST_SCHEME_DOOSABIN, 0);
    tl_init_hier(&g, make, ST_SCHEME_DOOSABIN, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK && st_adapt_init(&b, &g, &err) == ST_OK);
    st_adapt_params p = box_params(0.6 * extent, 0.1 * extent, 0, 0.2 * extent, 0, max), q = p;
    q.no_restriction = 1;
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK && st_adapt_update(&b, &q, &err) == ST_OK);
    valid(&g.map, name);
    CHECKF(restriction_holds(&g.map), "%s: no_restriction was not ignored", name);
    st_mesh s, t;
    st_mesh_init(&s);
    st_mesh_init(&t);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK && st_adapt_mesh(&b, &t, &err) == ST_OK);
    double worst = fmax(pointset_dist(&s, &t), pointset_dist(&t, &s));
    CHECKF(s.nfaces == t.nfaces && worst < 1e-12 * extent, "%s: no_restriction %u faces vs %u, distance %g", name,
           t.nfaces, s.nfaces, worst);
    st_mesh_free(&s);
    st_mesh_free(&t);
    st_adapt_free(&a);
    st_adapt_free(&b);
    st_hier_free(&h);
    st_hier_free(&g);
}

int main(void)
{
    struct { void (*make)(st_mesh *); const char *name; unsigned max; double extent; } cases[] = {
        { octa, "octahedron", 4, 1 },
        { cube, "cube", 4, 1 },
        { tetra, "tetrahedron", 4, 1 },
        { cut_cube, "cut cube", 4, 2 },
        { torus, "torus", 4, 2.7 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        check_random_moves(cases[i].make, cases[i].name, cases[i].max, cases[i].extent, 31 + i);
        check_matches_regular(cases[i].make, cases[i].name, cases[i].max, cases[i].extent);
        check_detail_round_trip(cases[i].make, cases[i].name, cases[i].max, cases[i].extent);
        check_resynth_and_repeat(cases[i].make, cases[i].name, cases[i].max - 1, cases[i].extent);
        check_on_regular_levels(cases[i].make, cases[i].name, cases[i].max, cases[i].extent);
        check_restriction_flag_ignored(cases[i].make, cases[i].name, cases[i].max, cases[i].extent);
    }
    check_flatness(torus, "torus", 3);
    check_incremental(torus, "torus", 4, 2.7, 0.3);
    check_incremental(torus, "torus small box", 5, 2.7, 0.08);
    check_incremental(octa, "octahedron", 5, 1, 0.2);
    check_incremental(cut_cube, "cut cube", 4, 1, 0.15);
    check_history_free(cut_cube, "cut cube", 1, 1234);
    check_history_free(torus, "torus", 2.7, 1235);
    return TEST_END();
}
