/* Shared checks for the adaptive-refinement tests (adapt_testlib.h). */
#include "adapt_testlib.h"
#include "core/adapt/adapt_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void at_torus(st_mesh *s) { tl_mesh_torus(s, 8, 6); }
void at_grid(st_mesh *s) { tl_mesh_grid(s, 4); }

void at_valid(st_map *m, const char *what)
{
    st_error err;
    int rc = st_map_validate(m, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
}

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

int at_watertight(const st_mesh *s, int closed, unsigned sides)
{
    uint32_t n = s->face_off[s->nfaces];
    for (uint32_t f = 0; f < s->nfaces; f++) {
        uint32_t len = s->face_off[f + 1] - s->face_off[f];
        if (len < 3 || (sides && len != sides)) return 0;
    }
    uint64_t *key = malloc(((size_t)n + 1) * sizeof *key), *sorted = malloc(((size_t)n + 1) * sizeof *sorted);
    for (uint32_t f = 0, k = 0; f < s->nfaces; f++)
        for (uint32_t j = s->face_off[f]; j < s->face_off[f + 1]; j++, k++) {
            uint32_t a = s->face_idx[j], b = s->face_idx[j + 1 < s->face_off[f + 1] ? j + 1 : s->face_off[f]];
            key[k] = (uint64_t)a << 32 | b;
        }
    memcpy(sorted, key, (size_t)n * sizeof *key);
    qsort(sorted, n, sizeof *sorted, cmp_u64);
    int ok = 1;
    for (uint32_t k = 0; k + 1 < n && ok; k++)
        if (sorted[k] == sorted[k + 1]) ok = 0; /* a directed edge twice */
    for (uint32_t k = 0; k < n && ok && closed; k++) {
        uint64_t rev = (key[k] & 0xffffffffu) << 32 | key[k] >> 32;
        if (!bsearch(&rev, sorted, n, sizeof *sorted, cmp_u64)) ok = 0;
    }
    free(key);
    free(sorted);
    return ok;
}

/* The O(1) readings of the Algorithm-1 maps ("subdivided toward i+1", "of
 * level i") agree with the definitions (st_face_is_subdivided,
 * st_face_level) on every dart of every level. */
static void check_split_toward(st_map *m, const at_case *c, int step)
{
    unsigned bad = 0, seen = 0;
    for (unsigned i = 0; i <= m->top; i++) {
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, i, &it); d != ST_NIL; d = st_dart_next(m, i, &it)) {
            if (st_is_boundary(m, d)) continue;
            seen++;
            bad += st_adapt_split_toward(m, d, i) != st_face_is_subdivided(m, d, i);
            bad += st_adapt_face_of_level(m, d, i) != (st_face_level(m, d, i) == i);
        }
    }
    CHECKF(bad == 0 && seen > 0, "%s step %d: O(1) face readings differ from st_face_is_subdivided / st_face_level %u times on %u darts",
           c->name, step, bad, seen);
}

void at_check_display(st_adapt *a, const at_case *c, int step)
{
    st_mesh s;
    st_error err;
    st_mesh_init(&s);
    CHECK(st_adapt_mesh(a, &s, &err) == ST_OK);
    CHECKF(at_watertight(&s, c->closed, c->sides), "%s step %d: displayed mesh not watertight%s", c->name, step,
           c->sides == 3 ? " (or not all triangles)" : "");
    st_mesh_free(&s);
    if (c->id != ST_SCHEME_SQRT3) check_split_toward(&a->h->map, c, step);
}

int at_restriction_holds(st_map *m)
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

st_adapt_params at_box(double cx, double cy, double cz, double r, unsigned base, unsigned max)
{
    st_adapt_params p = { .base_level = base, .max_level = max, .has_box = 1 };
    p.box_lo[0] = cx - r; p.box_lo[1] = cy - r; p.box_lo[2] = cz - r;
    p.box_hi[0] = cx + r; p.box_hi[1] = cy + r; p.box_hi[2] = cz + r;
    return p;
}

double at_rand_unit(uint64_t *rng) { return (double)(tl_rand(rng) % 2001) / 1000.0 - 1.0; }

static int cmp_x(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* Points of a mesh sorted by x (3 doubles each), for nearest-point queries. */
typedef struct sorted_pts { double *p; uint32_t n; } sorted_pts;

static sorted_pts sort_pts(const st_mesh *b)
{
    sorted_pts s = { malloc(((size_t)b->nverts * 3 + 1) * sizeof(double)), b->nverts };
    if (b->nverts) memcpy(s.p, b->pos, (size_t)b->nverts * 3 * sizeof(double));
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

double at_pointset_dist(const st_mesh *a, const st_mesh *b)
{
    sorted_pts s = sort_pts(b);
    double worst = 0;
    for (uint32_t v = 0; v < a->nverts; v++) worst = fmax(worst, nearest_sorted(&s, a->pos + 3 * v));
    free(s.p);
    return worst;
}

double at_mesh_dist(const st_mesh *a, const st_mesh *b) { return fmax(at_pointset_dist(a, b), at_pointset_dist(b, a)); }

void at_pair_init(at_pair *p, const at_case *c, unsigned hlevels)
{
    st_error err;
    tl_init_hier(&p->h, c->make, c->id, hlevels);
    tl_init_hier(&p->g, c->make, c->id, 0);
    CHECK(st_adapt_init(&p->a, &p->h, &err) == ST_OK && st_adapt_init(&p->b, &p->g, &err) == ST_OK);
}

void at_pair_free(at_pair *p)
{
    st_adapt_free(&p->a);
    st_adapt_free(&p->b);
    st_hier_free(&p->h);
    st_hier_free(&p->g);
}

double at_compare(st_adapt *a, st_adapt *b, uint32_t nf[2], uint32_t nv[2])
{
    st_mesh s, t;
    st_error err;
    st_mesh_init(&s);
    st_mesh_init(&t);
    CHECK(st_adapt_mesh(a, &s, &err) == ST_OK && st_adapt_mesh(b, &t, &err) == ST_OK);
    nf[0] = s.nfaces, nf[1] = t.nfaces, nv[0] = s.nverts, nv[1] = t.nverts;
    double d = at_mesh_dist(&s, &t);
    st_mesh_free(&s);
    st_mesh_free(&t);
    return d;
}

void at_check_random_moves(const at_case *c, uint64_t seed, int steps, int vary)
{
    st_hier h;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, c->make, c->id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    uint64_t rng = seed;
    for (int step = 0; step < steps; step++) {
        double x[3];
        for (int k = 0; k < 3; k++) x[k] = c->extent * at_rand_unit(&rng);
        double r = vary ? 0.15 + 0.05 * (step % 4) : 0.3;
        st_adapt_params p = at_box(x[0], x[1], x[2], r * c->extent, tl_rand(&rng) % 2, c->max);
        if (vary && step % 5 == 2) p.falloff = 0.2 * c->extent;
        if (vary && step % 7 == 3) p.no_restriction = 1; /* ignored by the scheme: still restricted */
        int rc = st_adapt_update(&a, &p, &err);
        CHECKF(rc == ST_OK, "%s step %d: %s", c->name, step, err.msg);
        at_valid(&h.map, c->name);
        at_check_display(&a, c, step);
        CHECKF(at_restriction_holds(&h.map), "%s step %d: faces sharing a vertex differ by more than one level",
               c->name, step);
    }
    st_adapt_free(&a);
    st_hier_free(&h);
}

void at_check_matches_regular(const at_case *c, at_border_face border, const char *border_name)
{
    st_hier h, r;
    st_adapt a;
    st_error err;
    const char *name = c->name;
    unsigned max = c->max;
    double extent = c->extent;
    if (max >= 8) { CHECKF(0, "%s: max %u too deep for this check", name, max); return; }
    tl_init_hier(&h, c->make, c->id, 0);
    tl_init_hier(&r, c->make, c->id, max);
    st_mesh lev[8];
    sorted_pts sl[8];
    for (unsigned k = 0; k <= max; k++) {
        st_mesh_init(&lev[k]);
        CHECK(st_hier_level_mesh(&r, k, &lev[k], &err) == ST_OK);
        sl[k] = sort_pts(&lev[k]);
    }
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = at_box(0.5 * extent, 0.2 * extent, 0, 0.35 * extent, 0, max);
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    double worst = 0;
    unsigned checked = 0, per_level[8] = { 0 };
    for (unsigned k = 1; k <= h.map.top; k++) {
        st_dart_iter it;
        int fb = st_marker_reserve(&h.map);
        for (uint32_t d = st_dart_first(&h.map, k, &it); d != ST_NIL; d = st_dart_next(&h.map, k, &it)) {
            if (st_is_boundary(&h.map, d) || st_marked(&h.map, fb, d)) continue;
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
    if (border) {
        unsigned n = 0;
        for (unsigned k = 1; k <= h.map.top; k++) {
            st_dart_iter it;
            for (uint32_t d = st_dart_first(&h.map, k, &it); d != ST_NIL; d = st_dart_next(&h.map, k, &it))
                n += border(&h.map, d, k) != 0;
        }
        CHECKF(n > 0, "%s: no %s at the depth borders", name, border_name);
    }
    /* The partial mesh is smaller than the regular one. */
    st_mesh s;
    st_mesh_init(&s);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    CHECKF(s.nfaces < lev[max].nfaces && s.nfaces > lev[0].nfaces, "%s: partial %u faces (base %u, regular %u)", name,
           s.nfaces, lev[0].nfaces, lev[max].nfaces);
    st_mesh_free(&s);

    st_adapt_params all = at_box(0, 0, 0, 100 * extent, 0, max);
    CHECK(st_adapt_update(&a, &all, &err) == ST_OK);
    at_valid(&h.map, "all-in");
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    double dmax = at_mesh_dist(&s, &lev[max]);
    CHECKF(s.nfaces == lev[max].nfaces && s.nverts == lev[max].nverts && dmax < 1e-9 * extent,
           "%s: all-in %u faces / %u verts vs regular %u / %u, distance %g", name, s.nfaces, s.nverts, lev[max].nfaces,
           lev[max].nverts, dmax);
    st_mesh_free(&s);

    for (unsigned base = 0; base <= 1; base++) {
        st_adapt_params none = at_box(1000 * extent, 0, 0, 0.1, base, max);
        CHECK(st_adapt_update(&a, &none, &err) == ST_OK);
        at_valid(&h.map, "none-in");
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
        dmax = at_mesh_dist(&s, &lev[base]);
        CHECKF(s.nfaces == lev[base].nfaces && s.nverts == lev[base].nverts && dmax < 1e-12 * fmin(extent, 1),
               "%s: none-in (base %u) %u faces / %u verts vs %u / %u, distance %g", name, base, s.nfaces, s.nverts,
               lev[base].nfaces, lev[base].nverts, dmax);
        at_check_display(&a, c, -1);
        st_mesh_free(&s);
    }
    /* And back up: the same partial mesh as the first time. */
    CHECK(st_adapt_update(&a, &all, &err) == ST_OK);
    CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
    dmax = at_mesh_dist(&s, &lev[max]);
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

/* Details of removed vertices are kept by refinement-tree address, in world
 * space, and turned back into the frames of the recreated cells (adapt_details.c). */
void at_check_detail_round_trip(const at_case *c)
{
    st_hier h;
    st_adapt a;
    st_error err;
    const char *name = c->name;
    unsigned max = c->max;
    double extent = c->extent;
    uint64_t rng = 5;
    tl_init_hier(&h, c->make, c->id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params in = at_box(0.4 * extent, 0, 0, 0.4 * extent, 0, max);
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    for (unsigned l = 1; l <= h.map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            double d[3];
            for (int k = 0; k < 3; k++) d[k] = 0.02 * extent * at_rand_unit(&rng);
            st_hier_set_detail(&h, l, v, d);
        }
    }
    st_adapt_synthesize(&a, 0);
    /* The edit moved the surface: let the criterion settle on it first. */
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    /* Settled: the same criteria again change nothing (no refine/simplify
     * cycle; for √3 an odd triangle and the even ones replacing it get the
     * same answer, adapt_sqrt3.c). */
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    CHECKF(a.touched == 0, "%s: settled update touched %llu faces", name, (unsigned long long)a.touched);
    st_mesh before, after;
    st_mesh_init(&before);
    st_mesh_init(&after);
    CHECK(st_adapt_mesh(&a, &before, &err) == ST_OK);
    st_adapt_params away = at_box(-10 * extent, 0, 0, 0.1, 0, max);
    CHECK(st_adapt_update(&a, &away, &err) == ST_OK);
    at_valid(&h.map, "box away");
    CHECKF(a.nsaved > 0, "%s: no detail saved", name);
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    at_valid(&h.map, "box back");
    /* Then a partial coarsening (the box half away) and back once more. */
    st_adapt_params half = at_box(0.8 * extent, 0.2 * extent, 0, 0.4 * extent, 0, max);
    CHECK(st_adapt_update(&a, &half, &err) == ST_OK);
    at_valid(&h.map, "box half away");
    CHECK(st_adapt_update(&a, &in, &err) == ST_OK);
    CHECK(st_adapt_mesh(&a, &after, &err) == ST_OK);
    CHECKF(before.nverts == after.nverts && before.nfaces == after.nfaces, "%s: %u/%u vs %u/%u", name, before.nverts,
           before.nfaces, after.nverts, after.nfaces);
    /* Compare as point sets (vertex ids may be reassigned). */
    double worst = at_mesh_dist(&after, &before);
    CHECKF(worst < 1e-6 * extent, "%s: away and back moved the surface by %g", name, worst);
    st_mesh_free(&before);
    st_mesh_free(&after);
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* p applied to q.a incrementally and to q.b as a full update: the same
 * mesh (faces, vertices, positions); returns the faces q.a's update
 * touched. */
static uint64_t update_both(at_pair *q, const st_adapt_params *p, const at_case *c, const char *what, int step)
{
    st_error err;
    CHECK(st_adapt_update(&q->a, p, &err) == ST_OK);
    q->b.has_prev = 0; /* force the full update */
    CHECK(st_adapt_update(&q->b, p, &err) == ST_OK);
    uint32_t nf[2], nv[2];
    double worst = at_compare(&q->a, &q->b, nf, nv);
    CHECKF(nf[0] == nf[1] && nv[0] == nv[1] && worst < 1e-12 * fmin(c->extent, 1),
           "%s %s %d: incremental %u faces / %u verts, full %u / %u, max distance %g", c->name, what, step, nf[0],
           nv[0], nf[1], nv[1], worst);
    at_valid(&q->h.map, "incremental update");
    return q->a.touched;
}

void at_check_incremental(const at_case *c, uint64_t seed, int steps, double r)
{
    at_pair q;
    double extent = c->extent;
    at_pair_init(&q, c, 0);
    uint64_t rng = seed;
    double x[3] = { 0.5 * extent, 0, 0 };
    uint64_t touched_inc = 0;
    for (int step = 0; step < steps; step++) {
        for (int k = 0; k < 3; k++) x[k] += 0.15 * extent * at_rand_unit(&rng);
        st_adapt_params p = at_box(x[0], x[1], x[2], r * extent, 0, c->max);
        p.falloff = step % 3 ? 0 : 0.2 * extent;
        touched_inc += update_both(&q, &p, c, "step", step);
    }
    CHECK(touched_inc > 0);
    at_pair_free(&q);
}

void at_check_drag(const at_case *c, uint64_t seed, int steps, double r, unsigned max)
{
    at_pair q;
    double extent = c->extent;
    at_pair_init(&q, c, 0);
    uint64_t rng = seed;
    /* from a vertex of the surface (the box starts on it) */
    double x[3];
    uint32_t v0 = (uint32_t)(tl_rand(&rng) % (q.h.map.verts.end ? q.h.map.verts.end : 1));
    while (v0 > 0 && q.h.map.verts.ins[v0] != 0) v0--;
    memcpy(x, st_pos(&q.h.map, v0, 0), sizeof x);
    uint64_t touched_inc = 0;
    for (int step = 0; step < steps; step++) {
        /* 1 to 6 % of the box's width along one axis, as a drag moves it */
        int axis = (int)(tl_rand(&rng) % 3);
        double frac = 0.01 * (double)(1 + tl_rand(&rng) % 6);
        x[axis] += (tl_rand(&rng) % 2 ? 1 : -1) * frac * 2 * r * extent;
        st_adapt_params p = at_box(x[0], x[1], x[2], r * extent, 0, max);
        touched_inc += update_both(&q, &p, c, "drag step", step);
    }
    CHECKF(touched_inc > 0, "%s: the drag changed nothing", c->name);
    at_pair_free(&q);
}

/* (The emitted stencils agree with the placement, odd triangles and border
 * polygons included.) */
void at_check_resynth_and_repeat(const at_case *c)
{
    at_pair q;
    st_error err;
    const char *name = c->name;
    double extent = c->extent;
    at_pair_init(&q, c, 0);
    uint64_t rng = 99;
    double x[3] = { 0.5 * extent, 0, 0 };
    for (int step = 0; step < 8; step++) {
        for (int k = 0; k < 3; k++) x[k] += 0.15 * extent * at_rand_unit(&rng);
        st_adapt_params p = at_box(x[0], x[1], x[2], 0.3 * extent, 0, c->max);
        CHECK(st_adapt_update(&q.a, &p, &err) == ST_OK);
        st_mesh s, t;
        st_mesh_init(&s);
        st_mesh_init(&t);
        CHECK(st_adapt_mesh(&q.a, &s, &err) == ST_OK);
        tl_posnap s0, s1;
        tl_snap_pos(&q.h, &s0);
        st_adapt_synthesize(&q.a, 0);
        tl_snap_pos(&q.h, &s1);
        CHECKF(tl_snap_maxdiff(&s0, &s1) < 1e-12 * extent, "%s step %d: resynthesis moved a vertex by %g", name, step,
               tl_snap_maxdiff(&s0, &s1));
        free(s0.p);
        free(s1.p);
        CHECK(st_adapt_update(&q.a, &p, &err) == ST_OK);
        CHECKF(q.a.touched == 0, "%s step %d: the same criteria again touched %llu faces", name, step,
               (unsigned long long)q.a.touched);
        /* A fresh hierarchy brought to the same criteria in one update. */
        st_adapt_free(&q.b);
        st_hier_free(&q.g);
        tl_init_hier(&q.g, c->make, c->id, 0);
        CHECK(st_adapt_init(&q.b, &q.g, &err) == ST_OK);
        CHECK(st_adapt_update(&q.b, &p, &err) == ST_OK);
        CHECK(st_adapt_mesh(&q.b, &t, &err) == ST_OK);
        double worst = at_mesh_dist(&s, &t);
        CHECKF(s.nfaces == t.nfaces && s.nverts == t.nverts && worst < 1e-9 * extent,
               "%s step %d: after moves %u faces / %u verts, fresh %u / %u, distance %g", name, step, s.nfaces, s.nverts,
               t.nfaces, t.nverts, worst);
        st_mesh_free(&s);
        st_mesh_free(&t);
    }
    at_pair_free(&q);
}

void at_check_on_regular_levels(const at_case *c)
{
    at_pair q;
    st_error err;
    double extent = c->extent;
    at_pair_init(&q, c, 1);
    st_adapt_params p = at_box(0.3 * extent, -0.2 * extent, 0.1 * extent, 0.3 * extent, 1, c->max);
    CHECK(st_adapt_update(&q.a, &p, &err) == ST_OK && st_adapt_update(&q.b, &p, &err) == ST_OK);
    at_valid(&q.h.map, c->name);
    uint32_t nf[2], nv[2];
    double worst = at_compare(&q.a, &q.b, nf, nv);
    CHECKF(nf[0] == nf[1] && worst < 1e-9 * extent, "%s: on regular level 1: %u faces vs %u, distance %g", c->name,
           nf[0], nf[1], worst);
    at_pair_free(&q);
}

void at_check_flatness(const at_case *c)
{
    st_hier h, r;
    st_adapt a;
    st_error err;
    const char *name = c->name;
    tl_init_hier(&h, c->make, c->id, 0);
    tl_init_hier(&r, c->make, c->id, c->max);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = { .max_level = c->max, .flatness = 0.5 };
    for (int step = 0; step < 2; step++) {
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        at_valid(&h.map, name);
        at_check_display(&a, c, 100 + step);
        st_mesh s, t, b;
        st_mesh_init(&s);
        st_mesh_init(&t);
        st_mesh_init(&b);
        CHECK(st_adapt_mesh(&a, &s, &err) == ST_OK);
        CHECK(st_hier_level_mesh(&r, c->max, &t, &err) == ST_OK && st_hier_level_mesh(&r, 0, &b, &err) == ST_OK);
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

void at_check_history_free(const at_case *c, uint64_t seed)
{
    st_hier h;
    st_adapt a;
    st_error err;
    const char *name = c->name;
    double e = c->extent;
    tl_init_hier(&h, c->make, c->id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    uint64_t rng = seed;
    for (int step = 0; step < 12; step++) {
        double x[3];
        for (int k = 0; k < 3; k++) x[k] = e * at_rand_unit(&rng);
        /* Base level drawn before the box size: the order GCC drew them in
         * when both were arguments of one call (the cases run so far). */
        unsigned base = tl_rand(&rng) % 3;
        double r = (0.1 + 0.1 * (tl_rand(&rng) % 4)) * e;
        st_adapt_params p = at_box(x[0], x[1], x[2], r, base, c->max);
        if (tl_rand(&rng) % 2) p.falloff = 0.15 * e;
        if (tl_rand(&rng) % 3 == 0) p.flatness = 0.3;
        if (tl_rand(&rng) % 4 == 0) p.has_box = 0;
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        at_valid(&h.map, name);
        at_check_display(&a, c, step);
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        CHECKF(a.touched == 0, "%s step %d: the same criteria again touched %llu faces", name, step,
               (unsigned long long)a.touched);
        st_hier g;
        st_adapt b;
        tl_init_hier(&g, c->make, c->id, 0);
        CHECK(st_adapt_init(&b, &g, &err) == ST_OK && st_adapt_update(&b, &p, &err) == ST_OK);
        uint32_t nf[2], nv[2];
        double w = at_compare(&a, &b, nf, nv);
        CHECKF(nf[0] == nf[1] && nv[0] == nv[1] && w < 1e-9 * e, "%s step %d: %u faces after moves, %u fresh, distance %g",
               name, step, nf[0], nf[1], w);
        st_adapt_free(&b);
        st_hier_free(&g);
    }
    st_adapt_free(&a);
    st_hier_free(&h);
}

void at_run_cases(const at_case *cases, size_t n, at_border_face border, const char *border_name,
                  void (*extra)(const at_case *))
{
    for (size_t i = 0; i < n; i++) {
        const at_case *c = &cases[i];
        at_case coarser = *c;
        coarser.max--;
        at_check_random_moves(c, 31 + i, 14, 1);
        at_check_matches_regular(c, border, border_name);
        at_check_detail_round_trip(c);
        at_check_resynth_and_repeat(&coarser);
        at_check_on_regular_levels(c);
        if (extra) extra(c);
    }
}

void at_run_incremental(const at_inc *inc, size_t n)
{
    for (size_t i = 0; i < n; i++) at_check_incremental(&inc[i].c, 77, 24, inc[i].r);
}
