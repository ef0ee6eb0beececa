/* HD levels (core/adapt/adapt_hd.c, adapt.h "HD levels"): a Catmull-Clark
 * cube, uniform to N = 2, refined adaptively to N+4 in a box over the
 * corner (1, 1, 1).  An edit at an HD level equals a full adaptive
 * synthesis bit for bit and changes only the edited vertices at its level
 * and below; a coarse edit carries the HD detail; keep_above keeps the
 * sculpted faces refined when the box leaves; which vertices are editable;
 * the per-level counts; box updates (incremental, simplifying, forced by
 * the restriction) equal a full synthesis from the base bit for bit, for
 * Catmull-Clark, Loop and Butterfly. */
#include "adapt_testlib.h"
#include "core/adapt/adapt_internal.h" /* st_adapt_faces_of_level */
#include "core/io/session.h"
#include "core/multires/edit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { N = 2, HD = N + 3, TOP = N + 4, NSEL = 6 };

static const double disp[3] = { 0.011, -0.007, 0.019 };

typedef struct fixture {
    st_hier h;
    st_adapt a;
    st_adapt_params box;
} fixture;

static void fixture_init(fixture *f)
{
    st_error err;
    tl_init_hier(&f->h, tl_mesh_cube, ST_SCHEME_CATMARK, N);
    CHECK(st_adapt_init(&f->a, &f->h, &err) == ST_OK);
    f->a.exact = 1; /* HD hierarchies keep every update a full synthesis (adapt.h) */
    st_adapt_synthesize(&f->a, 0);
    f->box = at_box(1, 1, 1, 0.35, N, TOP);
    CHECKF(st_adapt_update(&f->a, &f->box, &err) == ST_OK, "%s", err.msg);
    CHECK(f->h.map.top == TOP);
    /* (the update leaves every position as a full synthesis gives it: the
     * checks below compare edits against full syntheses) */
}

static void fixture_free(fixture *f)
{
    st_adapt_free(&f->a);
    st_hier_free(&f->h);
}

/* A deep copy through a session in memory (every level's map written). */
static int copy_session(fixture *f, st_session *s)
{
    st_session_ref r = { .h = &f->h, .adapt = &f->a, .box = &f->box, .box_on = 1, .whole_map = 1,
                         .display_level = f->h.map.top };
    void *bytes;
    size_t n;
    st_error err;
    if (st_session_write_mem(&r, &bytes, &n, &err) != ST_OK) { CHECKF(0, "%s", err.msg); return -1; }
    st_session_init(s);
    int rc = st_session_parse("hd.strata", bytes, n, s, &err);
    free(bytes);
    CHECKF(rc == ST_OK && s->has_adapt, "%s", rc ? err.msg : "no adaptive state");
    return rc == ST_OK && s->has_adapt ? 0 : -1;
}

/* Every position of every level, bit for bit. */
static int same_positions(const st_hier *a, const st_hier *b)
{
    tl_posnap x, y;
    tl_snap_pos(a, &x);
    tl_snap_pos(b, &y);
    int eq = x.levels == y.levels && x.n == y.n && !memcmp(x.p, y.p, (size_t)x.levels * x.n * 3 * sizeof *x.p);
    if (!eq && x.levels == y.levels && x.n == y.n) {
        unsigned shown = 0;
        for (unsigned l = 0; l < x.levels; l++)
            for (uint32_t v = 0; v < x.n; v++) {
                const double *p = x.p + ((size_t)l * x.n + v) * 3, *q = y.p + ((size_t)l * x.n + v) * 3;
                if (memcmp(p, q, 3 * sizeof *p) && shown++ < 12)
                    fprintf(stderr, "  level %u vertex %u (ins %u): %.17g %.17g %.17g vs %.17g %.17g %.17g\n", l, v,
                            a->map.verts.ins[v], p[0], p[1], p[2], q[0], q[1], q[2]);
            }
        fprintf(stderr, "  %u positions differ\n", shown);
    }
    free(x.p);
    free(y.p);
    return eq;
}

/* Faces of subdivision level l (the map's own reading, face by face). */
static uint32_t faces_of_level(st_map *m, unsigned l)
{
    st_dart_list faces = { 0 };
    st_adapt_faces_of_level(m, l, &faces);
    uint32_t n = faces.n;
    st_dart_list_free(&faces);
    return n;
}

static uint32_t hd_faces(st_map *m)
{
    uint32_t n = 0;
    for (unsigned l = N + 1; l <= m->top; l++) n += faces_of_level(m, l);
    return n;
}

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/* The NSEL editable vertices of level HD nearest to the cube's corner
 * (distinct vertices: one dart each, nearest first). */
static uint32_t pick_editable(st_map *m, uint32_t *darts, uint32_t *verts)
{
    static const double corner[3] = { 1, 1, 1 };
    double dist[NSEL];
    uint32_t n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, HD, &it); d != ST_NIL; d = st_dart_next(m, HD, &it)) {
        uint32_t v = st_vert(m, d, HD), k;
        double e = dist3(st_pos(m, v, HD), corner);
        if ((n == NSEL && e >= dist[NSEL - 1]) || !st_adapt_vertex_editable(m, d, HD)) continue;
        for (k = 0; k < n && verts[k] != v; k++) {}
        if (k < n) continue;
        if (n < NSEL) n++;
        for (k = n - 1; k > 0 && dist[k - 1] > e; k--) { dist[k] = dist[k - 1]; darts[k] = darts[k - 1]; verts[k] = verts[k - 1]; }
        dist[k] = e;
        darts[k] = d;
        verts[k] = v;
    }
    return n;
}

/* a, b: the HD edit against a full synthesis, and what it changed. */
static void check_hd_edit(fixture *f, uint32_t *darts, uint32_t *verts, uint32_t *nsel)
{
    st_map *m = &f->h.map;
    uint32_t n = pick_editable(m, darts, verts);
    *nsel = n;
    CHECKF(n == NSEL, "only %u editable vertices of level %d near the corner", n, HD);
    if (!n) return;
    double(*pos)[3] = malloc(n * sizeof *pos);
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) pos[i][k] = st_pos(m, verts[i], HD)[k] + disp[k];
    tl_posnap before, after;
    tl_snap_pos(&f->h, &before);
    st_footprint fp = { 0 };
    uint64_t above = st_adapt_edit(&f->h, HD, darts, (const double(*)[3])pos, n, &fp, NULL);
    tl_snap_pos(&f->h, &after);
    CHECKF(above > 0, "the edit wrote nothing above level %d", HD);
    at_valid(m, "after the HD edit");
    /* b: only the edited vertices at levels <= HD; something above. */
    uint64_t changed_low = 0, changed_high = 0, edited_moved = 0;
    for (unsigned l = 0; l < before.levels; l++)
        for (uint32_t v = 0; v < before.n; v++) {
            const double *p = before.p + ((size_t)l * before.n + v) * 3, *q = after.p + ((size_t)l * after.n + v) * 3;
            if (!memcmp(p, q, 3 * sizeof *p)) continue;
            int edited = 0;
            for (uint32_t i = 0; i < n; i++) edited |= verts[i] == v;
            if (l > HD) changed_high++;
            else if (l == HD && edited) edited_moved++;
            else changed_low++;
        }
    CHECKF(changed_low == 0, "%llu positions at levels <= %d changed besides the edited vertices",
           (unsigned long long)changed_low, HD);
    CHECKF(edited_moved == n, "%llu of %u edited vertices moved at level %d", (unsigned long long)edited_moved, n, HD);
    CHECKF(changed_high > n, "only %llu positions changed above level %d", (unsigned long long)changed_high, HD);
    /* The edited vertices are where the edit asked (up to the rounding of
     * pred + F^T D), and the footprint names every written value. */
    for (uint32_t i = 0; i < n; i++)
        CHECKF(dist3(st_pos(m, verts[i], HD), pos[i]) < 1e-12, "edited vertex %u is %g off", verts[i],
               dist3(st_pos(m, verts[i], HD), pos[i]));
    CHECKF(fp.n >= 2 * n + changed_high, "footprint of %u keys for %llu values written", fp.n,
           (unsigned long long)(2 * n + changed_high));
    /* a: a full adaptive synthesis of a copy from N gives the same bits. */
    st_session s;
    if (!copy_session(f, &s)) {
        CHECKF(same_positions(&f->h, &s.h), "the session copy differs");
        st_adapt_synthesize(&s.adapt, N);
        CHECKF(same_positions(&f->h, &s.h), "full synthesis from level %d differs from the HD edit", N);
        st_session_free(&s);
    }
    st_footprint_free(&fp);
    free(before.p);
    free(after.p);
    free(pos);
}

/* c: a level-N edit under the sculpt carries the HD detail. */
static void check_coarse_edit(fixture *f, const uint32_t *verts, uint32_t nsel)
{
    st_map *m = &f->h.map;
    if (!nsel) return;
    /* The level-N vertex nearest to the first sculpted vertex. */
    uint32_t best = ST_NIL;
    double bd = INFINITY;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, N, &it); d != ST_NIL; d = st_dart_next(m, N, &it)) {
        double e = dist3(st_pos(m, st_vert(m, d, N), N), st_pos(m, verts[0], HD));
        if (e < bd) { bd = e; best = d; }
    }
    double was[3], p[3];
    memcpy(was, st_pos(m, verts[0], HD), sizeof was);
    for (int k = 0; k < 3; k++) p[k] = st_pos(m, st_vert(m, best, N), N)[k] + 0.05 * (k + 1);
    const double(*pos)[3] = (const double(*)[3])p;
    CHECK(st_adapt_edit(&f->h, N, &best, pos, 1, NULL, NULL) > 0);
    CHECKF(dist3(st_pos(m, verts[0], HD), was) > 0.01, "the coarse edit left the sculpted vertex in place");
    st_session s, z;
    if (copy_session(f, &s)) return;
    st_adapt_synthesize(&s.adapt, N);
    CHECKF(same_positions(&f->h, &s.h), "full synthesis after the coarse edit differs from the local one");
    st_session_free(&s);
    /* The HD offset: against the same hierarchy with the sculpt's details
     * zeroed, the sculpted vertices sit |disp| away at level HD (a detail
     * is a local-frame vector: its length is kept). */
    if (copy_session(f, &z)) return;
    static const double zero[3];
    for (uint32_t i = 0; i < nsel; i++) st_hier_set_detail(&z.h, HD, verts[i], zero);
    st_adapt_synthesize(&z.adapt, N);
    double len = sqrt(disp[0] * disp[0] + disp[1] * disp[1] + disp[2] * disp[2]);
    for (uint32_t i = 0; i < nsel; i++) {
        double off = dist3(st_pos(m, verts[i], HD), st_pos(&z.h.map, verts[i], HD));
        CHECKF(fabs(off - len) < 1e-9, "vertex %u: HD offset %g after the coarse edit, sculpted %g", verts[i], off, len);
    }
    st_session_free(&z);
}

/* d: keep_above keeps the sculpted faces when the box leaves; without it
 * everything above N coarsens. */
static void check_keep(fixture *f, const uint32_t *verts, uint32_t nsel)
{
    st_map *m = &f->h.map;
    st_error err;
    st_session s;
    int have_copy = !copy_session(f, &s);
    uint32_t hd_before = hd_faces(m);
    double was[NSEL][3];
    for (uint32_t i = 0; i < nsel; i++) memcpy(was[i], st_pos(m, verts[i], HD), sizeof was[i]);
    st_adapt_params away = at_box(100, 100, 100, 0.35, N, TOP);
    f->a.keep_above = N;
    CHECKF(st_adapt_update(&f->a, &away, &err) == ST_OK, "%s", err.msg);
    at_valid(m, "after the box left (keep)");
    CHECK(at_restriction_holds(m));
    uint32_t hd_after = hd_faces(m), at_hd = faces_of_level(m, HD);
    printf("HD faces: %u in the box, %u kept after it left (%u of level %d)\n", hd_before, hd_after, at_hd, HD);
    CHECKF(at_hd > 0, "no face of level %d kept", HD);
    CHECKF(hd_after > 0 && 4 * hd_after < hd_before, "%u HD faces kept of %u", hd_after, hd_before);
    for (uint32_t i = 0; i < nsel; i++) {
        CHECKF(!memcmp(st_pos(m, verts[i], HD), was[i], sizeof was[i]), "sculpted vertex %u moved", verts[i]);
        /* Still on faces of level HD only, so still shown at the top. */
        uint32_t d = ST_NIL;
        st_dart_iter it;
        for (uint32_t x = st_dart_first(m, HD, &it); x != ST_NIL && d == ST_NIL; x = st_dart_next(m, HD, &it))
            if (st_vert(m, x, HD) == verts[i]) d = x;
        CHECKF(d != ST_NIL && st_adapt_vertex_editable(m, d, HD), "sculpted vertex %u no longer editable", verts[i]);
    }
    /* The same move without keep_above (a session copy starts with it 0). */
    if (have_copy) {
        CHECK(s.adapt.keep_above == 0);
        CHECKF(st_adapt_update(&s.adapt, &away, &err) == ST_OK, "%s", err.msg);
        CHECKF(hd_faces(&s.h.map) == 0, "%u HD faces left without keep_above", hd_faces(&s.h.map));
        st_session_free(&s);
    }
}

/* e: at the border of the refined region a vertex is not editable at HD;
 * inside it is (check_hd_edit picked those). */
static void check_editable(fixture *f)
{
    st_map *m = &f->h.map;
    uint32_t border = 0, inside = 0, mixed_ok = 1;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, HD, &it); d != ST_NIL; d = st_dart_next(m, HD, &it)) {
        if (st_is_boundary(m, d)) continue;
        /* A vertex with faces of level HD and coarser faces around it. */
        unsigned fine = 0, coarse = 0;
        uint32_t x = d;
        do {
            if (st_face_level(m, x, HD) == HD) fine++;
            else coarse++;
            x = st_beta1(m, x, HD);
        } while (x != d);
        int e = st_adapt_vertex_editable(m, d, HD);
        if (fine && coarse) { border++; if (e) mixed_ok = 0; }
        if (!coarse) { inside++; if (!e) mixed_ok = 0; }
    }
    CHECKF(border > 0 && inside > 0, "%u border and %u inside darts", border, inside);
    CHECKF(mixed_ok, "st_adapt_vertex_editable disagrees with the faces around a vertex");
    uint32_t d0 = st_dart_first(m, 0, &it);
    CHECK(!st_adapt_vertex_editable(m, d0, 0));
    CHECK(st_adapt_vertex_editable(m, d0, N)); /* uniform levels: every vertex */
}

/* e, holes: on an open grid the vertices of the boundary are editable
 * where their real faces are of the level. */
static void check_editable_open(void)
{
    st_hier h;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, at_grid, ST_SCHEME_CATMARK, 1);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = at_box(0, 0, 0, 100, 1, 2); /* everything to level 2 */
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    st_map *m = &h.map;
    uint32_t on_hole = 0, ok = 1;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 2, &it); d != ST_NIL; d = st_dart_next(m, 2, &it)) {
        if (!st_is_boundary(m, d)) continue;
        on_hole++;
        if (!st_adapt_vertex_editable(m, d, 2)) ok = 0;
    }
    CHECKF(on_hole > 0 && ok, "%u boundary darts, some boundary vertex not editable", on_hole);
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* f: st_adapt_hd_levels against the faces of each level. */
static void check_hd_levels(fixture *f)
{
    st_map *m = &f->h.map;
    uint64_t faces[ST_MAX_LEVELS], bytes[ST_MAX_LEVELS];
    st_adapt_hd_levels(m, N, faces, bytes);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (l <= N || l > m->top) {
            CHECKF(faces[l] == 0 && bytes[l] == 0, "level %u counted", l);
            continue;
        }
        uint32_t want = faces_of_level(m, l);
        CHECKF(faces[l] == want, "level %u: %llu faces, direct count %u", l, (unsigned long long)faces[l], want);
        /* At least the inserted vertices' position and detail. */
        CHECKF(bytes[l] >= (uint64_t)m->verts.live[l] * 48 && bytes[l] > 0, "level %u: %llu bytes for %u vertices", l,
               (unsigned long long)bytes[l], m->verts.live[l]);
        printf("level %u: %llu faces, %llu bytes\n", l, (unsigned long long)faces[l], (unsigned long long)bytes[l]);
    }
}


/* g: positions after st_adapt_update equal a full adaptive synthesis from
 * the base level bit for bit (adapt_resynth.c, "updates"): a hierarchy of
 * UNI uniform levels with random details, made canonical once (the
 * uniform synthesis is not the adaptive one), then a box update, random
 * details at every level (made canonical again), box moves (incremental
 * updates: regions refined, re-refined with their kept details,
 * simplified), a small far box where the restriction forces coarser
 * neighbours, and the first box again.  After each, a session copy is
 * synthesised from base and compared, every position of every level. */
typedef struct canon_case {
    const char *name;
    st_scheme_id id;
    void (*make)(st_mesh *);
    unsigned base, max;
    double c[3], r, far[3];
    int no_restriction;       /* the one-level restriction off (the pass then counts every vertex of a
                                 face the update touched as moved) */
} canon_case;

enum { UNI = 2 };

static void set_random_details(st_hier *h, unsigned from, uint64_t *rng, double scale)
{
    for (unsigned l = from + 1; l <= h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            double d[3];
            for (int i = 0; i < 3; i++) d[i] = scale * ((double)(tl_rand(rng) % 2001) / 1000.0 - 1.0);
            st_hier_set_detail(h, l, v, d);
        }
    }
}

/* Faces the restriction subdivided: subdivided faces of level l whose own
 * criteria want no more than l. */
static uint32_t forced_faces(st_map *m, const st_adapt_params *p)
{
    uint32_t n = 0;
    st_dart_list faces = { 0 };
    for (unsigned l = p->base_level; l < m->top; l++) {
        st_adapt_faces_of_level(m, l, &faces);
        for (uint32_t k = 0; k < faces.n; k++)
            if (st_face_is_subdivided(m, faces.d[k], l) && st_adapt_wanted_level(m, faces.d[k], l, p) <= l) n++;
    }
    st_dart_list_free(&faces);
    return n;
}

static int canon_same(const canon_case *cc, st_hier *h, st_adapt *a, const st_adapt_params *box, const char *step)
{
    st_session_ref r = { .h = h, .adapt = a, .box = box, .box_on = 1, .whole_map = 1, .display_level = h->map.top };
    void *bytes;
    size_t n;
    st_error err;
    if (st_session_write_mem(&r, &bytes, &n, &err) != ST_OK) { CHECKF(0, "%s", err.msg); return 0; }
    st_session s;
    st_session_init(&s);
    int rc = st_session_parse("canon.strata", bytes, n, &s, &err);
    free(bytes);
    CHECKF(rc == ST_OK && s.has_adapt, "%s", rc ? err.msg : "no adaptive state");
    if (rc || !s.has_adapt) return 0;
    int same = same_positions(h, &s.h);
    CHECKF(same, "%s, %s: the session copy differs", cc->name, step);
    st_adapt_synthesize(&s.adapt, cc->base);
    same = same && same_positions(h, &s.h);
    CHECKF(same, "%s, %s: the update differs from a full synthesis from level %u", cc->name, step, cc->base);
    st_session_free(&s);
    return same;
}

/* The position at level l of the vertex nearest to c (the boxes sit on
 * the surface whatever the scheme's shrinkage); mid: the midpoint of the
 * two nearest (off every vertex: a small box there is not symmetric about
 * a vertex, so the restriction has work). */
static void on_surface(st_map *m, unsigned l, const double c[3], int mid, double out[3])
{
    double best[2] = { INFINITY, INFINITY }, p[2][3] = { { 0 } };
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
        double e = dist3(st_pos(m, v, l), c);
        if (e < best[0]) {
            best[1] = best[0];
            memcpy(p[1], p[0], sizeof p[1]);
            best[0] = e;
            memcpy(p[0], st_pos(m, v, l), sizeof p[0]);
        } else if (e < best[1]) {
            best[1] = e;
            memcpy(p[1], st_pos(m, v, l), sizeof p[1]);
        }
    }
    for (int k = 0; k < 3; k++) out[k] = mid ? 0.5 * (p[0][k] + p[1][k]) : p[0][k];
}

static void check_update_canonical(const canon_case *cc)
{
    st_hier h;
    st_adapt a;
    st_error err;
    uint64_t rng = 0x5eed0001u + cc->id;
    tl_init_hier(&h, cc->make, cc->id, UNI);
    set_random_details(&h, 0, &rng, 0.02);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    a.exact = 1;
    st_adapt_synthesize(&a, 0);
    double c[3], fc[3];
    on_surface(&h.map, UNI, cc->c, 0, c);
    on_surface(&h.map, UNI, cc->far, 1, fc);
    st_adapt_params box = at_box(c[0], c[1], c[2], cc->r, cc->base, cc->max);
    box.no_restriction = cc->no_restriction;
    CHECKF(st_adapt_update(&a, &box, &err) == ST_OK, "%s", err.msg);
    CHECKF(h.map.top == cc->max, "%s: top %u", cc->name, h.map.top);
    canon_same(cc, &h, &a, &box, "first update");
    /* Details at every level, then the moves start from a canonical state. */
    set_random_details(&h, cc->base, &rng, 0.01);
    st_adapt_synthesize(&a, cc->base);
    CHECKF(st_adapt_update(&a, &box, &err) == ST_OK, "%s", err.msg);
    unsigned moves = 0;
    for (int i = 0; i < 6; i++) {
        st_adapt_params p = box;
        double step = (i % 3 == 2 ? -0.15 : 0.2) * cc->r;
        for (int k = 0; k < 3; k++) {
            p.box_lo[k] += step * (k + 1) * (i + 1) / 4;
            p.box_hi[k] += step * (k + 1) * (i + 1) / 4;
        }
        CHECKF(st_adapt_update(&a, &p, &err) == ST_OK, "%s", err.msg);
        at_valid(&h.map, cc->name);
        char what[64];
        snprintf(what, sizeof what, "box move %d (%llu faces touched)", i, (unsigned long long)a.touched);
        moves += a.touched > 0;
        canon_same(cc, &h, &a, &p, what);
    }
    CHECKF(moves >= 4, "%s: only %u box moves changed the map", cc->name, moves);
    st_adapt_params far = at_box(fc[0], fc[1], fc[2], 0.1 * cc->r, cc->base, cc->max);
    far.no_restriction = cc->no_restriction;
    CHECKF(st_adapt_update(&a, &far, &err) == ST_OK, "%s", err.msg);
    uint32_t forced = forced_faces(&h.map, &far);
    CHECKF(forced > 0 || cc->no_restriction, "%s: the restriction forced no face", cc->name);
    CHECK(cc->no_restriction || at_restriction_holds(&h.map));
    canon_same(cc, &h, &a, &far, "far box (restriction)");
    CHECKF(st_adapt_update(&a, &box, &err) == ST_OK, "%s", err.msg);
    canon_same(cc, &h, &a, &box, "first box again");
    printf("%s: base %u, max %u: %u faces forced by the far box\n", cc->name, cc->base,
           cc->max, forced);
    st_adapt_free(&a);
    st_hier_free(&h);
}

static void check_updates_canonical(void)
{
    static const canon_case cases[] = {
        { "catmull-clark cube", ST_SCHEME_CATMARK, tl_mesh_cube, UNI, UNI + 3, { 1, 1, 1 }, 0.35, { -1, -0.3, 0.2 }, 0 },
        { "catmull-clark cube, base 0", ST_SCHEME_CATMARK, tl_mesh_cube, 0, 4, { 1, 0.5, 1 }, 0.4, { -1, -0.3, 0.2 }, 0 },
        { "catmull-clark cube, no restriction", ST_SCHEME_CATMARK, tl_mesh_cube, UNI, UNI + 3, { 1, 1, 1 }, 0.35,
          { -1, -0.3, 0.2 }, 1 },
        { "loop octahedron, no restriction", ST_SCHEME_LOOP, tl_mesh_octa, 0, 4, { 0.4, 0.4, 0.3 }, 0.3,
          { -0.4, -0.3, -0.3 }, 1 },
        { "loop octahedron", ST_SCHEME_LOOP, tl_mesh_octa, UNI, UNI + 3, { 0.4, 0.4, 0.3 }, 0.3, { -0.4, -0.3, -0.3 }, 0 },
        { "loop icosahedron, base 0", ST_SCHEME_LOOP, tl_mesh_icosa, 0, 4, { -0.9, 0.9, 0.9 }, 0.5, { 0.9, -0.9, -0.9 }, 0 },
        { "butterfly icosahedron", ST_SCHEME_BUTTERFLY, tl_mesh_icosa, UNI, UNI + 3, { -0.9, 0.9, 0.9 }, 0.5, { 1.0, -1.3, -0.4 }, 0 },
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) check_update_canonical(&cases[k]);
}

int main(void)
{
    check_updates_canonical();
    fixture f;
    fixture_init(&f);
    check_editable(&f);
    check_editable_open();
    check_hd_levels(&f);
    uint32_t darts[NSEL], verts[NSEL], nsel = 0;
    check_hd_edit(&f, darts, verts, &nsel);
    check_coarse_edit(&f, verts, nsel);
    check_keep(&f, verts, nsel);
    fixture_free(&f);
    return TEST_END();
}
