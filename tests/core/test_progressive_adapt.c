/* Selective display of progressive hierarchies (core/adapt/adapt.h,
 * "Progressive hierarchies"; core/adapt/adapt_progressive.c): the selected
 * mesh is a valid watertight surface of the input's topology made of faces
 * of levels base..max, the faces touching the box are those of level max
 * at their level-max positions, a box far away gives level base and a box
 * around everything level max, box moves equal from-scratch builds, edits
 * of the hierarchy carry into the display, sessions keep it. */
#include "testlib.h"

#include "core/adapt/adapt_internal.h"
#include "core/progressive/progressive.h"
#include "core/io/session.h"
#include "core/map/map_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int build(const char *name, st_hier *h, uint64_t target, int64_t *euler, uint64_t *loops)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/triangle/%s", STRATA_SHARED_DATA, name);
    st_error err;
    st_mesh m;
    st_mesh_init(&m);
    if (st_mesh_load(path, &m, &err)) {
        tl_skip("%s not loaded (%s)", path, err.msg);
        return -1;
    }
    st_map t;
    st_map_init(&t);
    CHECK(st_map_from_mesh(&t, &m, &err) == ST_OK);
    st_level_stats s;
    st_level_stats_compute(&t, 0, &s);
    *euler = s.euler;
    *loops = s.boundary_loops;
    st_map_free(&t);
    st_progressive_opts o = { .target_faces = target };
    int rc = st_progressive_build(&m, &o, h, NULL, &err);
    CHECKF(rc == ST_OK, "%s: %s", name, err.msg);
    st_mesh_free(&m);
    return rc;
}

/* ---- oriented triangles of a level, as vertex id triples -------------------------- */

typedef struct tri3 { uint32_t v[3]; } tri3;

static int cmp_tri3(const void *x, const void *y) { return memcmp(x, y, sizeof(tri3)); }

static tri3 canon(uint32_t a, uint32_t b, uint32_t c)
{
    tri3 t;
    if (a < b && a < c) t = (tri3){ { a, b, c } };
    else if (b < c) t = (tri3){ { b, c, a } };
    else t = (tri3){ { c, a, b } };
    return t;
}

typedef struct level_tris { tri3 *t; uint32_t n; } level_tris;

static void tris_of_level(st_map *m, unsigned l, level_tris *out)
{
    st_level_stats s;
    st_level_stats_compute(m, l, &s);
    out->t = malloc((size_t)(s.faces ? s.faces : 1) * sizeof *out->t);
    out->n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t x, y;
        if (!st_tri_first_dart(m, d, l, &x, &y)) continue;
        out->t[out->n++] = canon(st_vert(m, d, l), st_vert(m, x, l), st_vert(m, y, l));
    }
    qsort(out->t, out->n, sizeof *out->t, cmp_tri3);
}

static int has_tri(const level_tris *lt, tri3 t) { return bsearch(&t, lt->t, lt->n, sizeof t, cmp_tri3) != NULL; }

/* Triangles as position triples, each rotated to start at its smallest
 * position, sorted: the same triangles at the same positions compare equal. */
typedef struct ptri { double p[9]; } ptri;

static int cmp_ptri(const void *x, const void *y) { return memcmp(x, y, sizeof(ptri)); }

static ptri *soup_tris(const st_mesh *s)
{
    ptri *t = calloc(s->nfaces ? s->nfaces : 1, sizeof *t);
    for (uint32_t f = 0; f < s->nfaces; f++) {
        const uint32_t *idx = s->face_idx + s->face_off[f];
        const double *q[3] = { s->pos + 3 * (size_t)idx[0], s->pos + 3 * (size_t)idx[1], s->pos + 3 * (size_t)idx[2] };
        int r = 0;
        for (int j = 1; j < 3; j++) if (memcmp(q[j], q[r], 3 * sizeof(double)) < 0) r = j;
        for (int j = 0; j < 3; j++) memcpy(t[f].p + 3 * j, q[(r + j) % 3], 3 * sizeof(double));
    }
    qsort(t, s->nfaces, sizeof *t, cmp_ptri);
    return t;
}

static int same_triangles(const st_mesh *a, const st_mesh *b)
{
    if (a->nfaces != b->nfaces) return 0;
    ptri *ta = soup_tris(a), *tb = soup_tris(b);
    int same = !memcmp(ta, tb, a->nfaces * sizeof *ta);
    free(ta);
    free(tb);
    return same;
}

/* ---- the checks ------------------------------------------------------------------------ */

static int same_mesh(const st_mesh *a, const st_mesh *b)
{
    if (a->nverts != b->nverts || a->nfaces != b->nfaces) return 0;
    if (memcmp(a->pos, b->pos, 3 * (size_t)a->nverts * sizeof *a->pos)) return 0;
    if (memcmp(a->face_off, b->face_off, ((size_t)a->nfaces + 1) * sizeof *a->face_off)) return 0;
    return !memcmp(a->face_idx, b->face_idx, (size_t)a->face_off[a->nfaces] * sizeof *a->face_idx);
}

static int bbox_meets(const double lo[3], const double hi[3], const st_adapt_params *p)
{
    for (int k = 0; k < 3; k++)
        if (hi[k] < p->box_lo[k] || lo[k] > p->box_hi[k]) return 0;
    return 1;
}

/* Everything the design promises for one box (no falloff), with the
 * selection a made; returns the number of faces of C. */
static uint32_t check_selection(const char *what, st_hier *h, st_adapt *a, const st_adapt_params *p, int64_t euler,
                                uint64_t loops)
{
    st_map *m = &h->map;
    const st_pm_select *s = a->pm;
    unsigned M = p->max_level < m->top ? p->max_level : m->top, B = p->base_level < M ? p->base_level : M;
    st_error err;
    st_mesh c;
    st_mesh_init(&c);
    CHECK(st_adapt_mesh(a, &c, &err) == ST_OK);
    /* a valid map of the input's topology (watertight: the holes are the
     * input's boundary loops, Euler characteristic kept) */
    st_map cm;
    st_map_init(&cm);
    int rc = st_map_from_mesh(&cm, &c, &err);
    CHECKF(rc == ST_OK, "%s: the selected mesh is not a surface: %s", what, rc ? err.msg : "");
    if (!rc) {
        CHECKF(st_map_validate(&cm, &err) == ST_OK, "%s: %s", what, err.msg);
        st_level_stats cs;
        st_level_stats_compute(&cm, 0, &cs);
        CHECKF(cs.euler == euler && cs.boundary_loops == loops, "%s: Euler %lld (input %lld), %llu loops (input %llu)", what,
               (long long)cs.euler, (long long)euler, (unsigned long long)cs.boundary_loops, (unsigned long long)loops);
        /* every border edge of C joins two vertices of the input's borders */
        uint8_t *onb = calloc(m->verts.end ? m->verts.end : 1, 1);
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, M, &it); d != ST_NIL; d = st_dart_next(m, M, &it))
            if (st_is_boundary(m, d)) onb[st_vert(m, d, M)] = 1;
        uint64_t bad = 0;
        for (uint32_t d = st_dart_first(&cm, 0, &it); d != ST_NIL; d = st_dart_next(&cm, 0, &it))
            if (st_is_boundary(&cm, d)) bad += !onb[s->vid[st_vert(&cm, d, 0)]];
        CHECKF(bad == 0, "%s: %llu border darts of C leave a vertex inside the input", what, (unsigned long long)bad);
        free(onb);
        /* the display map is that mesh */
        unsigned lv = 9;
        const st_map *dm = st_adapt_display_map(a, &lv);
        st_level_stats ds;
        CHECK(dm && lv == 0);
        if (dm) {
            st_level_stats_compute((st_map *)dm, 0, &ds);
            CHECK(ds.faces == c.nfaces && ds.vertices == c.nverts);
            int same = 1;
            for (uint32_t i = 0; i < c.nverts; i++) same &= !memcmp(st_pos(dm, i, 0), c.pos + 3 * (size_t)i, 3 * sizeof(double));
            CHECKF(same, "%s: the display map's positions are not the mesh's", what);
        }
    }
    st_map_free(&cm);
    /* every face of C is a face of a level in B..M; every vertex sits at
     * its position of a level in B..M where it exists */
    level_tris lt[ST_MAX_LEVELS];
    for (unsigned l = B; l <= M; l++) tris_of_level(m, l, &lt[l]);
    uint64_t foreign = 0, coarse = 0;
    for (uint32_t f = 0; f < c.nfaces; f++) {
        const uint32_t *t = c.face_idx + 3 * (size_t)f;
        tri3 x = canon(s->vid[t[0]], s->vid[t[1]], s->vid[t[2]]);
        int found = 0;
        for (unsigned l = B; l <= M && !found; l++) found = has_tri(&lt[l], x);
        foreign += !found;
        int atB = has_tri(&lt[B], x);
        for (int k = 0; k < 3 && atB; k++) atB = !memcmp(c.pos + 3 * (size_t)t[k], st_pos(m, s->vid[t[k]], B), 3 * sizeof(double));
        coarse += atB;
    }
    CHECKF(foreign == 0, "%s: %llu faces of C are faces of no level %u..%u", what, (unsigned long long)foreign, B, M);
    uint64_t badlam = 0;
    for (uint32_t i = 0; i < s->nverts; i++) {
        unsigned l = s->lam[i];
        badlam += l < B || l > M || m->verts.ins[s->vid[i]] > l || memcmp(c.pos + 3 * (size_t)i, st_pos(m, s->vid[i], l), 3 * sizeof(double));
    }
    CHECKF(badlam == 0, "%s: %llu vertices not at a position of theirs of levels %u..%u", what, (unsigned long long)badlam, B, M);
    /* inside the box: every face of level M touching it, at level-M positions */
    uint32_t *disp = malloc((size_t)(m->verts.end ? m->verts.end : 1) * sizeof *disp);
    for (uint32_t v = 0; v < m->verts.end; v++) disp[v] = ST_NIL;
    for (uint32_t i = 0; i < s->nverts; i++) disp[s->vid[i]] = i;
    tri3 *ct = malloc((size_t)(c.nfaces ? c.nfaces : 1) * sizeof *ct);
    for (uint32_t f = 0; f < c.nfaces; f++) {
        const uint32_t *t = c.face_idx + 3 * (size_t)f;
        ct[f] = canon(s->vid[t[0]], s->vid[t[1]], s->vid[t[2]]);
    }
    qsort(ct, c.nfaces, sizeof *ct, cmp_tri3);
    level_tris cl = { ct, c.nfaces };
    uint64_t inside = 0, missing = 0, moved = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, M, &it); d != ST_NIL; d = st_dart_next(m, M, &it)) {
        uint32_t x, y;
        if (!st_tri_first_dart(m, d, M, &x, &y)) continue;
        double lo[3], hi[3];
        st_adapt_face_bbox(m, d, M, lo, hi);
        if (!p->has_box || !bbox_meets(lo, hi, p)) continue;
        inside++;
        uint32_t v[3] = { st_vert(m, d, M), st_vert(m, x, M), st_vert(m, y, M) };
        if (!has_tri(&cl, canon(v[0], v[1], v[2]))) { missing++; continue; }
        for (int k = 0; k < 3; k++)
            moved += memcmp(c.pos + 3 * (size_t)disp[v[k]], st_pos(m, v[k], M), 3 * sizeof(double)) != 0;
    }
    CHECKF(missing == 0 && moved == 0, "%s: of %llu faces of level %u touching the box, %llu missing, %llu corners moved", what,
           (unsigned long long)inside, M, (unsigned long long)missing, (unsigned long long)moved);
    printf("%s: levels %u..%u: %u faces (level %u: %u, level %u: %u), %llu touch the box, %llu coarse faces at level-%u positions\n",
           what, B, M, c.nfaces, B, lt[B].n, M, lt[M].n, (unsigned long long)inside, (unsigned long long)coarse, B);
    free(disp);
    free(ct);
    for (unsigned l = B; l <= M; l++) free(lt[l].t);
    uint32_t n = c.nfaces;
    st_mesh_free(&c);
    return n;
}

/* A box of half-size r * diagonal around the level-top position of a vertex. */
static void box_around(st_hier *h, uint32_t v, double r, st_adapt_params *p)
{
    st_map *m = &h->map;
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    st_dart_iter it;
    for (uint32_t u = st_vertex_first(m, m->top, &it); u != ST_NIL; u = st_vertex_next(m, m->top, &it))
        for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], st_pos(m, u, m->top)[k]); hi[k] = fmax(hi[k], st_pos(m, u, m->top)[k]); }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double *c = st_pos(m, v, m->top);
    for (int k = 0; k < 3; k++) { p->box_lo[k] = c[k] - r * diag; p->box_hi[k] = c[k] + r * diag; }
    p->has_box = 1;
}

static uint32_t some_vertex(st_hier *h, uint64_t *rng)
{
    st_map *m = &h->map;
    for (;;) {
        uint32_t v = tl_rand(rng) % m->verts.end;
        if (m->verts.ins[v] != ST_FREE_LEVEL && m->verts.ins[v] <= m->top) return v;
    }
}

static void fresh_mesh(st_hier *h, const st_adapt_params *p, st_mesh *out)
{
    st_adapt b;
    st_error err;
    CHECK(st_adapt_init(&b, h, &err) == ST_OK);
    CHECK(st_adapt_update(&b, p, &err) == ST_OK);
    CHECK(st_adapt_mesh(&b, out, &err) == ST_OK);
    st_adapt_free(&b);
}

static void test_mesh(const char *name, uint64_t target)
{
    st_hier h;
    int64_t euler;
    uint64_t loops;
    if (build(name, &h, target, &euler, &loops)) return;
    st_map *m = &h.map;
    unsigned top = m->top;
    CHECKF(top >= 4, "%s: %u levels", name, top + 1);
    st_adapt a;
    st_error err;
    CHECKF(st_adapt_init(&a, &h, &err) == ST_OK, "%s: %s", name, err.msg);
    uint64_t rng = 0x5eed0000u + top;
    char what[256];
    /* far away: level B exactly; around everything: level M exactly */
    for (unsigned B = 0; B <= 2; B += 2) {
        st_adapt_params far = { .base_level = B, .max_level = top, .has_box = 1,
                                .box_lo = { 1e9, 1e9, 1e9 }, .box_hi = { 2e9, 2e9, 2e9 } };
        CHECK(st_adapt_update(&a, &far, &err) == ST_OK);
        st_mesh c, l;
        st_mesh_init(&c);
        st_mesh_init(&l);
        CHECK(st_adapt_mesh(&a, &c, &err) == ST_OK && st_hier_level_mesh(&h, B, &l, &err) == ST_OK);
        CHECKF(c.nverts == l.nverts && same_triangles(&c, &l), "%s: box far away: %u faces, level %u has %u", name, c.nfaces, B, l.nfaces);
        snprintf(what, sizeof what, "%s far", name);
        check_selection(what, &h, &a, &far, euler, loops);
        CHECK(a.pm->kept == 0);
        st_mesh_free(&c);
        st_mesh_free(&l);
        st_adapt_params all = far;
        for (int k = 0; k < 3; k++) { all.box_lo[k] = -1e9; all.box_hi[k] = 1e9; }
        CHECK(st_adapt_update(&a, &all, &err) == ST_OK);
        st_mesh_init(&c);
        st_mesh_init(&l);
        CHECK(st_adapt_mesh(&a, &c, &err) == ST_OK && st_hier_level_mesh(&h, top, &l, &err) == ST_OK);
        CHECKF(c.nverts == l.nverts && same_triangles(&c, &l), "%s: box around all: %u faces, the top level has %u", name, c.nfaces, l.nfaces);
        CHECK(a.pm->applied == 0);
        st_mesh_free(&c);
        st_mesh_free(&l);
    }
    /* boxes of several sizes, at several levels; then the same boxes again
     * on the same state, each equal to a from-scratch build */
    st_adapt_params boxes[8];
    for (int i = 0; i < 8; i++) {
        st_adapt_params p = { .base_level = (unsigned)(i % 3), .max_level = i % 4 == 3 ? top - 1 : top };
        box_around(&h, some_vertex(&h, &rng), i < 4 ? 0.03 : 0.12, &p);
        boxes[i] = p;
        CHECKF(st_adapt_update(&a, &p, &err) == ST_OK, "%s: %s", name, err.msg);
        snprintf(what, sizeof what, "%s box %d", name, i);
        uint32_t n = check_selection(what, &h, &a, &p, euler, loops);
        st_level_stats sb, st;
        st_level_stats_compute(m, p.base_level, &sb);
        st_level_stats_compute(m, p.max_level, &st);
        CHECKF(n > sb.faces && n < st.faces, "%s: %u faces, not between levels %u and %u (%llu, %llu)", what, n, p.base_level,
               p.max_level, (unsigned long long)sb.faces, (unsigned long long)st.faces);
    }
    for (int i = 7; i >= 0; i--) {
        CHECK(st_adapt_update(&a, &boxes[i], &err) == ST_OK);
        st_mesh x, y;
        st_mesh_init(&x);
        st_mesh_init(&y);
        CHECK(st_adapt_mesh(&a, &x, &err) == ST_OK);
        fresh_mesh(&h, &boxes[i], &y);
        CHECKF(same_mesh(&x, &y), "%s: box %d again differs from a fresh build", name, i);
        st_mesh_free(&x);
        st_mesh_free(&y);
    }
    /* a falloff: still valid, and in between */
    st_adapt_params fo = boxes[0];
    fo.falloff = (fo.box_hi[0] - fo.box_lo[0]) * 0.5;
    CHECK(st_adapt_update(&a, &fo, &err) == ST_OK);
    snprintf(what, sizeof what, "%s falloff", name);
    check_selection(what, &h, &a, &fo, euler, loops);
    /* an edit of level 0 carries into the display: as a fresh build on the
     * edited hierarchy */
    CHECK(st_adapt_update(&a, &boxes[4], &err) == ST_OK);
    st_dart_iter it;
    uint32_t d = st_dart_first(m, 0, &it);
    const double *p0 = st_dart_pos(m, d, 0);
    double q[1][3] = { { p0[0] + 0.05, p0[1] - 0.02, p0[2] + 0.01 } };
    st_hier_move(&h, 0, &d, q, 1);
    st_adapt_synthesize(&a, 0);
    st_mesh x, y;
    st_mesh_init(&x);
    st_mesh_init(&y);
    /* the same selection, its vertices at their new positions */
    CHECK(st_adapt_mesh(&a, &x, &err) == ST_OK);
    int same = 1;
    for (uint32_t i = 0; i < x.nverts; i++) same &= !memcmp(x.pos + 3 * (size_t)i, st_pos(m, a.pm->vid[i], a.pm->lam[i]), 3 * sizeof(double));
    unsigned lv;
    const st_map *dm = st_adapt_display_map(&a, &lv);
    same &= dm != NULL;
    for (uint32_t i = 0; same && i < x.nverts; i++) same &= !memcmp(st_pos(dm, i, 0), x.pos + 3 * (size_t)i, 3 * sizeof(double));
    CHECKF(same, "%s: after an edit the display does not follow", name);
    st_mesh_free(&x);
    st_mesh_init(&x);
    /* the next update is a fresh build on the edited hierarchy */
    CHECK(st_adapt_update(&a, &boxes[4], &err) == ST_OK);
    CHECK(st_adapt_mesh(&a, &x, &err) == ST_OK);
    fresh_mesh(&h, &boxes[4], &y);
    CHECKF(same_mesh(&x, &y), "%s: after an edit the display is not a fresh build", name);
    snprintf(what, sizeof what, "%s edited", name);
    check_selection(what, &h, &a, &boxes[4], euler, loops);
    /* now that levels differ in positions: far away is level B to the bit,
     * around everything level M */
    for (int wide = 0; wide < 2; wide++) {
        st_adapt_params e = { .base_level = 1, .max_level = top, .has_box = 1 };
        for (int k = 0; k < 3; k++) { e.box_lo[k] = wide ? -1e9 : 1e9; e.box_hi[k] = wide ? 1e9 : 2e9; }
        st_mesh c, l;
        st_mesh_init(&c);
        st_mesh_init(&l);
        fresh_mesh(&h, &e, &c);
        CHECK(st_hier_level_mesh(&h, wide ? top : 1, &l, &err) == ST_OK);
        CHECKF(same_triangles(&c, &l), "%s: edited, box %s: not level %u", name, wide ? "around all" : "far away", wide ? top : 1);
        st_mesh_free(&c);
        st_mesh_free(&l);
    }
    /* sessions: the criteria are kept, the display comes back the same,
     * save -> load -> save is byte-identical */
    st_session_ref r = { .h = &h, .adapt = &a, .edit_level = 0, .display_level = top };
    st_session s;
    if (tl_session_roundtrip(&r, name, &s) == 0) {
        CHECK(s.has_adapt);
        st_mesh z;
        st_mesh_init(&z);
        CHECK(st_adapt_mesh(&s.adapt, &z, &err) == ST_OK);
        CHECKF(same_mesh(&x, &z), "%s: the loaded session shows another mesh", name);
        st_mesh_free(&z);
        st_session_free(&s);
    }
    st_mesh_free(&x);
    st_mesh_free(&y);
    /* nothing of face refinement applies */
    CHECK(st_adapt_subdivide_face(&a, d, 0, 1, &err) != ST_OK && strstr(err.msg, "progressive"));
    CHECK(st_adapt_simplify_face(&a, d, 0, &err) != ST_OK);
    CHECK(st_adapt_can_simplify(&a, d, 0, 1) == 0);
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* A session whose progressive adaptive state carries details is refused
 * with a message (they cannot come from this build). */
static void test_session_refusal(void)
{
    st_hier h;
    int64_t euler;
    uint64_t loops;
    if (build("sphere_ico.obj", &h, 40, &euler, &loops)) return;
    st_adapt a;
    st_error err;
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = { .base_level = 0, .max_level = h.map.top };
    box_around(&h, 0, 0.1, &p);
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    st_adapt_saved e = { .path = 1, .meta = 2, .d = { 0, 0, 0 } };
    a.saved = &e;
    a.nsaved = 1;
    st_session_ref r = { .h = &h, .adapt = &a };
    void *b = NULL;
    size_t n = 0;
    CHECK(st_session_write_mem(&r, &b, &n, &err) == ST_OK);
    a.saved = NULL;
    a.nsaved = 0;
    st_session s;
    CHECK(st_session_parse("bad.strata", b, n, &s, &err) != ST_OK && strstr(err.msg, "bad.strata") && strstr(err.msg, "keeps no details"));
    free(b);
    st_adapt_free(&a);
    st_hier_free(&h);
}

int main(void)
{
    test_mesh("spot_low_resolution.obj", 60);
    test_mesh("blub_open.obj", 100);
    test_mesh("plane_holes.obj", 40);
    test_mesh("boot.obj", 400);
    test_mesh("hand_lowres.obj", 60);
    test_session_refusal();
    return TEST_END();
}
