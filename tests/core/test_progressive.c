/* Progressive multiresolution meshes (core/progressive/progressive.h):
 * topology kept at every level, the independence rule, the hierarchy's
 * geometry (finest == input, rigid motion, local edits, sessions) and
 * multiresolution filtering. */
#include "testlib.h"

#include "core/progressive/progressive_internal.h"
#include "core/base/parallel.h"
#include "core/multires/hier_internal.h"
#include "core/io/session.h"
#include "core/io/map_io_internal.h"
#include "core/map/map_mesh.h"
#include "core/map/pool_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- fixtures ------------------------------------------------------------------ */

static int load_shared(const char *name, st_mesh *m) { return tl_load_shared("triangle", name, m); }

/* Euler characteristic and boundary loops of a soup, through a map. */
static void soup_topology(const st_mesh *s, int64_t *euler, uint64_t *loops)
{
    st_map m;
    st_map_init(&m);
    st_error err;
    CHECK(st_map_from_mesh(&m, s, &err) == ST_OK);
    st_level_stats st;
    st_level_stats_compute(&m, 0, &st);
    *euler = st.euler;
    *loops = st.boundary_loops;
    st_map_free(&m);
}

/* Triangles as position triples, each rotated to start at its smallest
 * position and sorted: two meshes with the same triangles at the same
 * positions, whatever their numbering, compare equal. */
typedef struct ptri { double p[9]; } ptri;

static int cmp_pos(const double *a, const double *b) { return memcmp(a, b, 3 * sizeof(double)); }
static int cmp_ptri(const void *x, const void *y) { return memcmp(x, y, sizeof(ptri)); }

static ptri *soup_tris(const st_mesh *s, uint32_t *n)
{
    uint32_t k = 0;
    for (uint32_t f = 0; f < s->nfaces; f++) k += s->face_off[f + 1] - s->face_off[f] - 2;
    ptri *t = calloc(k ? k : 1, sizeof *t);
    k = 0;
    for (uint32_t f = 0; f < s->nfaces; f++) {
        const uint32_t *idx = s->face_idx + s->face_off[f];
        uint32_t deg = s->face_off[f + 1] - s->face_off[f];
        for (uint32_t i = 1; i + 1 < deg; i++, k++) {
            const double *q[3] = { s->pos + 3 * (size_t)idx[0], s->pos + 3 * (size_t)idx[i], s->pos + 3 * (size_t)idx[i + 1] };
            int r = 0;
            for (int j = 1; j < 3; j++) if (cmp_pos(q[j], q[r]) < 0) r = j;
            for (int j = 0; j < 3; j++) memcpy(t[k].p + 3 * j, q[(r + j) % 3], 3 * sizeof(double));
        }
    }
    qsort(t, k, sizeof *t, cmp_ptri);
    *n = k;
    return t;
}

static int same_triangles(const st_mesh *a, const st_mesh *b)
{
    uint32_t na, nb;
    ptri *ta = soup_tris(a, &na), *tb = soup_tris(b, &nb);
    int same = na == nb && !memcmp(ta, tb, na * sizeof *ta);
    free(ta);
    free(tb);
    return same;
}

/* ---- the independence rule, checked on the map ---------------------------------- */

/* At every level L (progressive.h, point 3): the vertices inserted at L
 * are pairwise not neighbours at L, each is the end a of exactly one edge
 * a -> b whose two darts are new (its split), and the partners b are
 * distinct vertices of level L-1. */
static int check_independence(st_map *m, const char *what)
{
    int ok = 1;
    uint32_t nv = m->verts.end;
    uint32_t *partner_of = calloc(nv ? nv : 1, sizeof *partner_of), *splits = calloc(nv ? nv : 1, sizeof *splits);
    for (unsigned L = 1; L <= m->top && ok; L++) {
        memset(partner_of, 0, nv * sizeof *partner_of);
        memset(splits, 0, nv * sizeof *splits);
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
            uint32_t e = st_beta0(m, d, L), a = st_vert(m, d, L), b = st_vert(m, e, L);
            if (m->verts.ins[a] == L && m->verts.ins[b] == L) {
                fprintf(stderr, "%s: level %u: split vertices %u and %u are neighbours\n", what, L, a, b);
                ok = 0;
            }
            if (m->darts.ins[d] != L || m->darts.ins[e] != L || st_is_boundary(m, d) || m->verts.ins[a] != L) continue;
            splits[a]++;
            partner_of[b]++;
        }
        for (uint32_t v = st_vertex_first(m, L, &it); v != ST_NIL; v = st_vertex_next(m, L, &it)) {
            if (m->verts.ins[v] == L && splits[v] != 1) {
                fprintf(stderr, "%s: level %u: vertex %u is split %u times\n", what, L, v, splits[v]);
                ok = 0;
            }
            if (partner_of[v] > 1) {
                fprintf(stderr, "%s: level %u: vertex %u is the partner of %u splits\n", what, L, v, partner_of[v]);
                ok = 0;
            }
        }
    }
    free(partner_of);
    free(splits);
    return ok;
}

/* ---- topology at every level ------------------------------------------------------ */

static void check_mesh(const char *what, const st_mesh *in, uint64_t target, int expect_levels)
{
    st_hier h;
    st_progressive_report rep;
    st_error err;
    st_progressive_opts o = { .target_faces = target };
    int rc = st_progressive_build(in, &o, &h, &rep, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
    if (rc) return;
    int64_t euler;
    uint64_t loops;
    soup_topology(in, &euler, &loops);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s: %s", what, err.msg);
    CHECK(rep.levels == h.map.top + 1 && rep.levels <= ST_MAX_LEVELS);
    int polygons = 0;
    for (uint32_t f = 0; f < in->nfaces; f++) polygons |= in->face_off[f + 1] - in->face_off[f] > 3;
    CHECK(rep.triangulated == polygons);
    if (expect_levels) CHECKF(rep.levels >= 3, "%s: only %u levels (%s)", what, rep.levels, rep.note);
    for (unsigned l = 0; l <= h.map.top; l++) {
        st_level_stats s;
        st_level_stats_compute(&h.map, l, &s);
        CHECKF(s.euler == euler && s.boundary_loops == loops, "%s: level %u: Euler %lld (input %lld), %llu loops (input %llu)",
               what, l, (long long)s.euler, (long long)euler, (unsigned long long)s.boundary_loops, (unsigned long long)loops);
        /* the report counts on the working copy: the map's walked counts */
        CHECKF(s.faces == rep.faces[l] && s.vertices == rep.vertices[l], "%s: level %u: report %llu faces %llu vertices, map %llu %llu",
               what, l, (unsigned long long)rep.faces[l], (unsigned long long)rep.vertices[l], (unsigned long long)s.faces,
               (unsigned long long)s.vertices);
        if (l) CHECKF(rep.faces[l] > rep.faces[l - 1] && rep.kept[l] < 1.0, "%s: level %u", what, l);
    }
    CHECKF(rep.faces[0] <= target || !rep.target_reached, "%s", what);
    CHECKF(check_independence(&h.map, what), "%s: independence", what);
    /* Built to size: no spare pool capacity, and each level's detail array
     * ends at its last non-zero detail (reads past it give zero). */
    CHECKF(h.map.darts.cap == h.map.darts.end && h.map.verts.cap == h.map.verts.end, "%s: darts %u of %u, vertices %u of %u",
           what, h.map.darts.end, h.map.darts.cap, h.map.verts.end, h.map.verts.cap);
    for (unsigned l = 1; l <= h.map.top; l++) {
        const double *last = h.detail[l] ? h.detail[l] + 3 * (size_t)(h.detail_cap[l] - 1) : NULL;
        CHECKF(!last || h.detail_cap[l] == 1 || last[0] != 0 || last[1] != 0 || last[2] != 0 || signbit(last[0]) ||
               signbit(last[1]) || signbit(last[2]), "%s: level %u's details end with a zero", what, l);
        CHECKF(!h.detail[l] || h.detail_cap[l] <= h.map.verts.end, "%s: level %u", what, l);
    }
    /* The finest level is the input, position for position. */
    st_mesh top;
    st_mesh_init(&top);
    CHECK(st_hier_level_mesh(&h, h.map.top, &top, &err) == ST_OK);
    CHECKF(same_triangles(in, &top), "%s: the finest level is not the input", what);
    st_mesh_free(&top);
    /* and so is a full synthesis of it: to the bit but for the vertices
     * counted in rep.inexact, which move by an ulp or so */
    tl_posnap a, b;
    tl_snap_pos(&h, &a);
    st_hier_synthesize(&h, 0);
    tl_snap_pos(&h, &b);
    double extent = 0;
    for (uint32_t i = 0; i < 3 * in->nverts; i++) extent = fmax(extent, fabs(in->pos[i]));
    CHECKF(tl_snap_maxdiff(&a, &b) <= 1e-12 * extent, "%s: a full synthesis moves the input by %g", what, tl_snap_maxdiff(&a, &b));
    if (rep.inexact == 0) CHECK(tl_snap_maxdiff(&a, &b) == 0);
    free(a.p);
    free(b.p);
    printf("%s: %u levels, faces %llu -> %llu, t at the finest level %.3f, %.1f topology bytes per finest dart%s, %llu "
           "inexact; %s\n", what, rep.levels, (unsigned long long)rep.faces[rep.levels - 1], (unsigned long long)rep.faces[0],
           rep.levels > 1 ? rep.kept[rep.levels - 1] : 1.0, rep.bytes_per_dart, rep.triangulated ? " (triangulated)" : "",
           (unsigned long long)rep.inexact, rep.note);
    st_hier_free(&h);
}

static const char *const shared[] = {
    "sphere_ico.obj", "spot_low_resolution.obj", "hemisphere.obj", "cube_no_bottom.obj",
    "plane_holes.obj", "blub_open.obj", "hand_lowres.obj", "boot.obj",
};

static void test_topology(void)
{
    for (size_t i = 0; i < sizeof shared / sizeof *shared; i++) {
        st_mesh m;
        if (load_shared(shared[i], &m)) continue;
        check_mesh(shared[i], &m, m.nfaces / 20, 1);
        check_mesh(shared[i], &m, 0, 1);           /* as far as the rules allow */
        st_mesh_free(&m);
    }
    st_mesh t;
    st_mesh_init(&t);
    tl_mesh_torus(&t, 24, 16);                      /* genus 1, quads: fanned */
    check_mesh("torus 24x16", &t, 40, 1);
    st_mesh_free(&t);
}

/* A tetrahedron has no allowed collapse: one level and a note, no error. */
static void test_tetrahedron(void)
{
    st_mesh t;
    st_mesh_init(&t);
    tl_mesh_tetra(&t);
    st_hier h;
    st_progressive_report rep;
    st_error err;
    st_progressive_opts o = { .target_faces = 1 };
    CHECK(st_progressive_build(&t, &o, &h, &rep, &err) == ST_OK);
    CHECK(rep.levels == 1 && h.map.top == 0 && rep.faces[0] == 4 && !rep.target_reached && strstr(rep.note, "no collapse"));
    st_hier_free(&h);
    /* The octahedron: each collapse would leave a valence-3 ... it may go one level. */
    st_mesh_free(&t);
    tl_mesh_octa(&t);
    CHECK(st_progressive_build(&t, &o, &h, &rep, &err) == ST_OK);
    CHECK(st_map_validate(&h.map, &err) == ST_OK);
    st_hier_free(&h);
    st_mesh_free(&t);
}

typedef struct cancel_at { double at; int calls; } cancel_at;

static int cancel_when(void *ctx, double f)
{
    cancel_at *c = ctx;
    c->calls++;
    return f >= c->at;
}

static void test_progress_and_bad_input(void)
{
    st_mesh m;
    if (load_shared("spot_low_resolution.obj", &m)) return;
    st_hier h;
    st_error err;
    /* cancelled while simplifying (fractions up to 0.8), then while laying
     * out the map (0.8 to 0.95) */
    for (int k = 0; k < 2; k++) {
        cancel_at c = { k ? 0.85 : 0.5, 0 };
        st_progressive_opts o = { .target_faces = 10, .progress = cancel_when, .progress_ctx = &c };
        CHECK(st_progressive_build(&m, &o, &h, NULL, &err) == ST_ERR_INVALID && strstr(err.msg, "cancelled") && c.calls >= 1);
        CHECK(h.map.top == 0 && h.scheme == NULL); /* left empty */
    }
    /* max_levels caps the levels */
    st_progressive_opts o2 = { .target_faces = 10, .max_levels = 3 };
    st_progressive_report rep;
    CHECK(st_progressive_build(&m, &o2, &h, &rep, &err) == ST_OK && rep.levels == 3 && strstr(rep.note, "limit"));
    st_hier_free(&h);
    /* an edge used twice in one direction (not a manifold) is refused */
    {
        static const double pos[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0 };
        static const uint32_t off[3] = { 0, 3, 6 }, idx[6] = { 0, 1, 2, 0, 1, 3 };
        st_mesh bad;
        st_mesh_init(&bad);
        tl_mesh_make(&bad, pos, 4, off, idx, 2);
        CHECK(st_progressive_build(&bad, NULL, &h, NULL, &err) == ST_ERR_TOPOLOGY && strstr(err.msg, "edge 0-1"));
        st_mesh_free(&bad);
    }
    /* a non-finite coordinate is refused with a message */
    m.pos[4] = NAN;
    CHECK(st_progressive_build(&m, NULL, &h, NULL, &err) == ST_ERR_GEOMETRY && strstr(err.msg, "vertex 1"));
    st_mesh_free(&m);
}

/* ---- geometry ------------------------------------------------------------------------ */

/* The predictor the builds below use (progressive.h, enum st_pm_predictor):
 * the exactness tests run under each. */
static int g_predictor = ST_PM_RELAXED;
static int g_fit = 0; /* st_progressive_opts.fit_coarse of build() */

static int build(const char *name, st_hier *h, uint64_t target)
{
    st_mesh m;
    if (load_shared(name, &m)) return -1;
    st_error err;
    st_progressive_opts o = { .target_faces = target, .predictor = g_predictor, .fit_coarse = g_fit };
    int rc = st_progressive_build(&m, &o, h, NULL, &err);
    CHECKF(rc == ST_OK, "%s: %s", name, err.msg);
    st_mesh_free(&m);
    return rc;
}

/* One dart per vertex of level l, in vertex id order. */
static uint32_t *vertex_darts(st_map *m, unsigned l, uint32_t *n)
{
    uint32_t *vd = malloc(m->verts.end * sizeof *vd), k = 0;
    for (uint32_t v = 0; v < m->verts.end; v++) vd[v] = ST_NIL;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) vd[st_vert(m, d, l)] = d;
    for (uint32_t v = 0; v < m->verts.end; v++) if (vd[v] != ST_NIL) vd[k++] = vd[v];
    *n = k;
    return vd;
}

static void rotate(const double p[3], double q[3])
{
    const double c = cos(0.7), s = sin(0.7);
    q[0] = c * p[0] - s * p[1] + 1.5;
    q[1] = s * p[0] + c * p[1] - 2.0;
    q[2] = p[2] + 0.25;
}

static void test_rigid_motion(const char *name)
{
    st_hier h;
    if (build(name, &h, 40)) return;
    st_map *m = &h.map;
    unsigned top = m->top;
    uint32_t n;
    uint32_t *vd = vertex_darts(m, 0, &n);
    double (*np)[3] = malloc(n * sizeof *np);
    for (uint32_t i = 0; i < n; i++) rotate(st_dart_pos(m, vd[i], 0), np[i]);
    tl_posnap before;
    tl_snap_pos(&h, &before);
    st_hier_move(&h, 0, vd, (const double (*)[3])np, n);
    double worst = 0, size = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, top, &it); v != ST_NIL; v = st_vertex_next(m, top, &it)) {
        double q[3];
        const double *p0 = before.p + 3 * ((size_t)top * before.n + v);
        rotate(p0, q);
        const double *p = st_pos(m, v, top);
        for (int k = 0; k < 3; k++) {
            worst = fmax(worst, fabs(p[k] - q[k]));
            size = fmax(size, fabs(p0[k]));
        }
    }
    CHECKF(worst <= 1e-9 * (1 + size), "%s: rigid motion of level 0 moves the finest level by %g off", name, worst);
    free(before.p);
    free(np);
    free(vd);
    st_hier_free(&h);
}

/* An edit at level top-k (k = 0: level 0): local re-synthesis == full
 * synthesis to the bit, and a vertex moves at level L only if a vertex
 * its stencil or its frame reads (the frame vertex's 1-ring) moved at L-1.
 * With few levels above the edit, few vertices move. */
static void test_local_edit(const char *name, unsigned k)
{
    st_hier h;
    if (build(name, &h, 30)) return;
    st_map *m = &h.map;
    unsigned l = k && k <= m->top ? m->top - k : 0;
    uint32_t n;
    uint32_t *vd = vertex_darts(m, l, &n);
    uint32_t d = vd[n / 3];
    const double *p = st_dart_pos(m, d, l);
    double q[1][3] = { { p[0] + 0.05, p[1] - 0.03, p[2] + 0.04 } };
    tl_posnap before, local, full;
    /* From a synthesised state (as after any first edit): the few split
     * vertices whose input bits no detail reproduces (rep.inexact) have
     * taken their synthesised position. */
    st_hier_synthesize(&h, 0);
    tl_snap_pos(&h, &before);
    uint64_t count = st_hier_move(&h, l, &d, q, 1);
    tl_snap_pos(&h, &local);
    st_hier_synthesize(&h, l);
    tl_snap_pos(&h, &full);
    CHECKF(tl_snap_maxdiff(&local, &full) == 0, "%s: local edit at level %u differs from full synthesis by %g", name, l,
           tl_snap_maxdiff(&local, &full));
    uint8_t *moved = calloc(m->verts.end, 1), *prev = calloc(m->verts.end, 1);
    prev[st_vert(m, d, l)] = 1;
    uint64_t changed = 0, total = 0;
    int ok = 1;
    st_stencil_buf buf = { 0 };
    for (unsigned L = l + 1; L <= m->top; L++) {
        memset(moved, 0, m->verts.end);
        uint32_t nv;
        uint32_t *vl = vertex_darts(m, L, &nv);
        total += nv;
        for (uint32_t i = 0; i < nv; i++) {
            uint32_t v = st_vert(m, vl[i], L);
            size_t at = 3 * ((size_t)L * before.n + v);
            if (!memcmp(before.p + at, full.p + at, 3 * sizeof(double))) continue;
            moved[v] = 1;
            changed++;
            st_stencil s;
            if (!st_progressive_stencil(&h, L, vl[i], &buf, &s)) { ok = 0; continue; }
            int near = 0;
            for (uint32_t j = 0; j < s.n; j++) near |= prev[s.src[j]];
            uint32_t x = s.frame_dart;
            near |= prev[st_vert(m, x, L - 1)];
            do { near |= prev[st_vert(m, st_beta0(m, x, L - 1), L - 1)]; x = st_beta1(m, x, L - 1); } while (x != s.frame_dart);
            ok &= near;
        }
        free(vl);
        uint8_t *t = prev; prev = moved; moved = t;
    }
    CHECKF(ok, "%s: a vertex outside the edit's support moved", name);
    /* Written exactly where a position changed (progressive_synth.c). */
    CHECKF(count == changed && changed > 0, "%s: %llu moved, %llu written", name, (unsigned long long)changed, (unsigned long long)count);
    if (k) CHECKF(changed * 10 < total, "%s: %llu of %llu vertices moved above level %u", name, (unsigned long long)changed,
                  (unsigned long long)total, l);
    st_stencil_buf_free(&buf);
    free(moved); free(prev); free(vd);
    free(before.p); free(local.p); free(full.p);
    st_hier_free(&h);
}

/* Full synthesis of every level through the stencils (emit + st_synth_sink),
 * not the scheme's ring tables. */
static void synthesize_by_stencils(st_hier *h)
{
    for (unsigned L = 1; L <= h->map.top; L++) {
        st_synth_ctx c = st_hier_synth_ctx(h, L);
        st_hier_emit(h, L, NULL, 0, st_synth_sink, &c);
    }
}

/* Where the edits of the table tests move the k-th vertex listed at the
 * i-th of their three levels (from p): varied per vertex and per level. */
static void spread_edit(const double p[3], uint32_t k, int i, double q[3])
{
    q[0] = p[0] + 0.01 * (k % 3);
    q[1] = p[1] - 0.02;
    q[2] = p[2] + 0.005 * (i + 1);
}

/* The ring tables (core/progressive/progressive_synth.c) give the bits of
 * the stencils and st_hier_frame: after edits at three levels, which leave
 * details on vertices predicted by their own position (frames of every
 * kind of vertex), and on the border of open meshes, a full synthesis by
 * the tables and one by the stencils agree to the bit. */
static void test_tables_match_stencils(const char *name, uint64_t target)
{
    st_hier h;
    if (build(name, &h, target)) return;
    st_map *m = &h.map;
    unsigned levels[3] = { 1, m->top / 2, m->top - 1 };
    for (int i = 0; i < 3; i++) {
        unsigned l = levels[i];
        uint32_t n;
        uint32_t *vd = vertex_darts(m, l, &n);
        for (uint32_t k = 0; k < n; k += n / 7 + 1) {
            double q[1][3];
            spread_edit(st_dart_pos(m, vd[k], l), k, i, q[0]);
            st_hier_move(&h, l, &vd[k], q, 1);
        }
        free(vd);
    }
    uint64_t self_with_detail = 0;
    st_stencil_buf buf = { 0 };
    for (unsigned L = 1; L <= m->top; L++) {
        uint32_t n;
        uint32_t *vd = vertex_darts(m, L, &n);
        for (uint32_t k = 0; k < n; k++) {
            st_stencil s;
            if (!st_progressive_stencil(&h, L, vd[k], &buf, &s)) continue;
            const double *d = st_hier_detail(&h, L, s.fine);
            self_with_detail += s.n == 1 && s.src[0] == s.fine && (d[0] != 0 || d[1] != 0 || d[2] != 0);
        }
        free(vd);
    }
    st_stencil_buf_free(&buf);
    CHECKF(self_with_detail > 0, "%s: no detail on a vertex predicted by itself", name);
    tl_posnap tables, stencils;
    st_hier_synthesize(&h, 0);
    tl_snap_pos(&h, &tables);
    synthesize_by_stencils(&h);
    tl_snap_pos(&h, &stencils);
    CHECKF(tl_snap_maxdiff(&tables, &stencils) == 0, "%s: the tables' synthesis differs from the stencils' by %g", name,
           tl_snap_maxdiff(&tables, &stencils));
    free(tables.p);
    free(stencils.p);
    st_hier_free(&h);
}

/* An edit's own level takes S(P_{l-1}) and the frame from the ring tables
 * when they are cached (the scheme's predict_vertex), else from the
 * stencils: the same edits on two copies, one with every table dropped
 * before each edit, leave the same details and positions to the bit, at
 * three levels, on vertices of every kind and on borders. */
static void test_edit_level_with_and_without_tables(const char *name, uint64_t target)
{
    st_hier a, b;
    if (build(name, &a, target)) return;
    if (build(name, &b, target)) { st_hier_free(&a); return; }
    st_map *m = &a.map;
    st_hier_synthesize(&a, 0); /* (the same positions in both before the edits) */
    st_hier_synthesize(&b, 0);
    unsigned levels[3] = { 1, m->top / 2, m->top - 1 };
    uint64_t edits = 0;
    for (int i = 0; i < 3; i++) {
        unsigned l = levels[i];
        uint32_t n;
        uint32_t *vd = vertex_darts(m, l, &n);
        for (uint32_t k = 0; k < n; k += n / 9 + 1) {
            double q[1][3];
            spread_edit(st_dart_pos(m, vd[k], l), k, i, q[0]);
            CHECKF(st_progressive_table_bytes(&a) > 0, "%s: no ring table cached before an edit", name);
            for (unsigned t = 0; t <= b.map.top; t++) st_progressive_drop_table(&b, t);
            CHECKF(st_progressive_table_bytes(&b) == 0, "%s: a ring table left after dropping them", name);
            st_hier_move(&a, l, &vd[k], q, 1);
            st_hier_move(&b, l, &vd[k], q, 1);
            uint32_t v = st_vert(m, vd[k], l);
            CHECKF(!memcmp(st_hier_detail(&a, l, v), st_hier_detail(&b, l, v), 3 * sizeof(double)),
                   "%s: level %u, vertex %u: the detail differs with and without the tables", name, l, v);
            edits++;
        }
        free(vd);
    }
    CHECKF(edits >= 9, "%s: only %llu edits", name, (unsigned long long)edits);
    tl_posnap pa, pb;
    tl_snap_pos(&a, &pa);
    tl_snap_pos(&b, &pb);
    CHECKF(tl_snap_maxdiff(&pa, &pb) == 0, "%s: positions differ by %g with and without the tables", name,
           tl_snap_maxdiff(&pa, &pb));
    free(pa.p);
    free(pb.p);
    st_hier_free(&a);
    st_hier_free(&b);
}

/* Signed volume of level l's faces (fans of their vertex cycles). */
static double level_volume(st_map *m, unsigned l)
{
    st_mesh o;
    st_error err;
    st_mesh_init(&o);
    if (st_map_to_mesh(m, l, &o, &err)) return NAN;
    double vol = 0;
    for (uint32_t f = 0; f < o.nfaces; f++) {
        const double *a = o.pos + 3 * (size_t)o.face_idx[o.face_off[f]];
        for (uint32_t k = o.face_off[f] + 1; k + 1 < o.face_off[f + 1]; k++) {
            const double *b = o.pos + 3 * (size_t)o.face_idx[k], *c = o.pos + 3 * (size_t)o.face_idx[k + 1];
            double bc[3];
            st_cross3(b, c, bc);
            vol += st_dot3(a, bc) / 6;
        }
    }
    st_mesh_free(&o);
    return vol;
}

/* Level 0 placed at its quadrics' optima (progressive.h, point 8): the
 * same map as without, every level above 0 at the input positions to the
 * bit (so the finest level is the input), level 0's vertices moved, and a
 * closed coarse level nearer the input's volume (half-edge collapses onto
 * input points cut corners off a convex shape; the planes' optimum puts
 * them back). */
static void test_fit_coarse(const char *name, uint64_t target, int closed)
{
    st_hier a, b;
    int saved = g_fit;
    g_fit = 1;
    int rc = build(name, &a, target);
    g_fit = 0;
    if (!rc && build(name, &b, target)) { st_hier_free(&a); rc = -1; }
    g_fit = saved;
    if (rc) return;
    st_map *ma = &a.map, *mb = &b.map;
    CHECKF(ma->top == mb->top && ma->verts.end == mb->verts.end && ma->darts.end == mb->darts.end,
           "%s: the placement changed the map", name);
    uint64_t moved = 0, above_differ = 0;
    for (unsigned l = 0; l <= ma->top && l <= mb->top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(ma, l, &it); v != ST_NIL; v = st_vertex_next(ma, l, &it)) {
            int same = !memcmp(st_pos(ma, v, l), st_pos(mb, v, l), 3 * sizeof(double));
            if (l == 0) moved += !same;
            else above_differ += !same;
        }
    }
    CHECKF(above_differ == 0, "%s: %llu positions above level 0 differ from the input", name,
           (unsigned long long)above_differ);
    CHECKF(moved > 0, "%s: no vertex of level 0 was placed", name);
    if (closed) {
        double vin = level_volume(ma, ma->top), vfit = level_volume(ma, 0), vsub = level_volume(mb, 0);
        CHECKF(fabs(vfit - vin) < fabs(vsub - vin), "%s: level 0's volume %g placed, %g on input points, input %g", name,
               vfit, vsub, vin);
        printf("%s: level 0's volume %.5g placed, %.5g on input points, input %.5g (%llu vertices placed)\n", name, vfit,
                 vsub, vin, (unsigned long long)moved);
    }
    /* Synthesis gives the input back at every level above 0 (as without the
     * placement, but for the details whose bits cannot be reached). */
    tl_posnap before, after;
    tl_snap_pos(&a, &before);
    st_hier_synthesize(&a, 0);
    tl_snap_pos(&a, &after);
    double worst = tl_snap_maxdiff(&before, &after);
    CHECKF(worst < 1e-12, "%s: synthesis moves the placed hierarchy by %g", name, worst);
    free(before.p);
    free(after.p);
    st_hier_free(&a);
    st_hier_free(&b);
}

static void test_session(const char *name)
{
    st_hier h;
    if (build(name, &h, 30)) return;
    /* an edit first, so that positions carry columns too */
    uint32_t n;
    uint32_t *vd = vertex_darts(&h.map, 1, &n);
    const double *p = st_dart_pos(&h.map, vd[0], 1);
    double q[1][3] = { { p[0] + 0.01, p[1], p[2] - 0.02 } };
    st_hier_move(&h, 1, vd, q, 1);
    free(vd);
    st_session_ref r = { .h = &h, .edit_level = 1, .display_level = h.map.top };
    st_error err;
    st_session s;
    if (tl_session_roundtrip(&r, name, &s) == 0) {
        CHECK(s.h.scheme == &st_scheme_progressive && s.h.map.top == h.map.top);
        /* the same later edit on both gives the same bits */
        vd = vertex_darts(&h.map, 0, &n);
        uint32_t d = vd[n / 2];
        free(vd);
        const double *p0 = st_dart_pos(&h.map, d, 0);
        double q0[1][3] = { { p0[0] - 0.02, p0[1] + 0.03, p0[2] } };
        st_hier_move(&h, 0, &d, q0, 1);
        st_hier_move(&s.h, 0, &d, q0, 1);
        tl_posnap a, b;
        tl_snap_pos(&h, &a);
        tl_snap_pos(&s.h, &b);
        CHECK(a.n == b.n && tl_snap_maxdiff(&a, &b) == 0);
        free(a.p);
        free(b.p);
        /* and refining is refused with a message */
        CHECK(st_hier_subdivide_to(&s.h, s.h.map.top + 1, &err) != ST_OK && strstr(err.msg, "simplification"));
        st_session_free(&s);
    }
    st_hier_free(&h);
}

/* The HIER chunk's third word (crease method | triangle rule << 8 |
 * predictor << 16) in a session's bytes: its offset, 0 if not found. */
static size_t hier_word_at(const unsigned char *c, size_t n)
{
    for (size_t i = 0; i + 16 < n; i++)
        if (!memcmp(c + i, "HIER", 4)) {
            uint32_t len = (uint32_t)c[i + 12] | (uint32_t)c[i + 13] << 8 | (uint32_t)c[i + 14] << 16 | (uint32_t)c[i + 15] << 24;
            size_t at = i + 12 + 4 + len + 4; /* tag, payload length, name length, name, boundary */
            return at + 4 <= n ? at : 0;
        }
    return 0;
}

/* Sessions in the format from before the predictor tag (bits 16-23 of the
 * HIER word zero) open with the relaxation and synthesise as before: a
 * relaxed build (a zero st_progressive_opts) writes exactly that format,
 * byte for byte, and a light or graded build tags itself, loads with its
 * predictor and saves back the same bytes.  An unknown predictor is
 * refused. */
static void test_session_predictor(const char *name)
{
    for (int pred = ST_PM_RELAXED; pred <= ST_PM_GRADED; pred++) {
        g_predictor = pred;
        st_hier h;
        if (build(name, &h, 30)) { g_predictor = ST_PM_RELAXED; return; }
        st_session_ref r = { .h = &h, .edit_level = 0, .display_level = h.map.top };
        st_error err;
        void *f1 = NULL, *f2 = NULL;
        size_t n1 = 0, n2 = 0;
        CHECK(st_session_write_mem(&r, &f1, &n1, &err) == 0);
        size_t at = hier_word_at(f1, n1);
        CHECKF(at != 0, "%s: no HIER chunk", name);
        unsigned tag = at ? ((unsigned char *)f1)[at + 2] : 99;
        CHECKF(tag == (unsigned)pred, "%s: predictor %d written as %u", name, pred, tag);
        st_session s;
        if (st_session_parse(name, f1, n1, &s, &err) == 0) {
            CHECKF(s.h.opts.pm_predictor == pred, "%s: predictor %d loaded as %d", name, pred, s.h.opts.pm_predictor);
            /* the same synthesis, from level 0, on both */
            tl_posnap a, b;
            st_hier_synthesize(&h, 0);
            st_hier_synthesize(&s.h, 0);
            tl_snap_pos(&h, &a);
            tl_snap_pos(&s.h, &b);
            CHECKF(a.n == b.n && tl_snap_maxdiff(&a, &b) == 0, "%s, predictor %d: the loaded session synthesises otherwise",
                   name, pred);
            free(a.p);
            free(b.p);
            st_hier_synthesize(&s.h, 0);
            r.h = &h;
            st_session_ref r2 = { .h = &s.h, .edit_level = 0, .display_level = s.h.map.top };
            free(f1);
            CHECK(st_session_write_mem(&r, &f1, &n1, &err) == 0);
            CHECK(st_session_write_mem(&r2, &f2, &n2, &err) == 0);
            CHECKF(n1 == n2 && memcmp(f1, f2, n1) == 0, "%s, predictor %d: save, load, save differ", name, pred);
            free(f2);
            st_session_free(&s);
        } else {
            CHECKF(0, "%s: %s", name, err.msg);
        }
        /* an unknown predictor: refused, with a message that says so */
        if (at) {
            unsigned char *c = f1;
            c[at + 2] = 7;
            tl_session_fix_crc(c, n1);
            CHECK(st_session_parse(name, c, n1, &s, &err) != 0 && strstr(err.msg, "predictor"));
        }
        free(f1);
        st_hier_free(&h);
    }
    g_predictor = ST_PM_RELAXED;
}

/* ---- filtering ------------------------------------------------------------------------ */

/* Mean dihedral angle (radians between the normals of the two faces of
 * each interior edge) of level l: zero on a plane, small on a smooth
 * surface, large on a bumpy one. */
static void face_normal_at(st_map *m, uint32_t d, unsigned l, double n[3])
{
    const double *p = st_dart_pos(m, d, l), *q = st_dart_pos(m, st_phi1(m, d, l), l),
                 *r = st_dart_pos(m, st_phi1(m, st_phi1(m, d, l), l), l);
    double u[3] = { q[0] - p[0], q[1] - p[1], q[2] - p[2] }, v[3] = { r[0] - p[0], r[1] - p[1], r[2] - p[2] };
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0) for (int k = 0; k < 3; k++) n[k] /= len;
}

static double roughness(st_map *m, unsigned l)
{
    double sum = 0;
    uint64_t cnt = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t e = st_beta0(m, d, l);
        if (d > e || st_is_boundary(m, d) || st_is_boundary(m, e)) continue;
        double a[3], b[3];
        face_normal_at(m, d, l, a);
        face_normal_at(m, e, l, b);
        double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        sum += acos(c > 1 ? 1 : c < -1 ? -1 : c);
        cnt++;
    }
    return cnt ? sum / (double)cnt : 0;
}

static void test_filter(const char *name)
{
    st_hier h;
    if (build(name, &h, 40)) return;
    st_error err;
    unsigned top = h.map.top;
    tl_posnap a, b;
    tl_snap_pos(&h, &a);
    double ones[ST_MAX_LEVELS];
    for (unsigned k = 0; k < ST_MAX_LEVELS; k++) ones[k] = 1.0;
    CHECK(st_progressive_filter(&h, ones, top, &err) == ST_OK);
    tl_snap_pos(&h, &b);
    CHECKF(tl_snap_maxdiff(&a, &b) == 0, "%s: gains 1 changed positions", name);
    free(b.p);
    /* g then 1/g gives the details back (to rounding) */
    double g[ST_MAX_LEVELS];
    for (unsigned k = 0; k < ST_MAX_LEVELS; k++) g[k] = k % 2 ? 2.0 : 1.0;
    CHECK(st_progressive_filter(&h, g, top, &err) == ST_OK);
    for (unsigned k = 0; k < ST_MAX_LEVELS; k++) g[k] = 1.0 / g[k];
    CHECK(st_progressive_filter(&h, g, top, &err) == ST_OK);
    tl_snap_pos(&h, &b);
    CHECKF(tl_snap_maxdiff(&a, &b) < 1e-9, "%s: gains 2 then 1/2 differ by %g", name, tl_snap_maxdiff(&a, &b));
    free(b.p);
    /* Gain 0 on the finest bands: a smoother surface, coarse levels kept. */
    double before = roughness(&h.map, top);
    unsigned bands = top >= 3 ? 3 : top;
    double z[ST_MAX_LEVELS];
    for (unsigned k = 0; k < top; k++) z[k] = k + bands >= top ? 0.0 : 1.0;
    tl_posnap c0;
    tl_snap_pos(&h, &c0);
    CHECK(st_progressive_filter(&h, z, top, &err) == ST_OK);
    double after = roughness(&h.map, top);
    tl_snap_pos(&h, &b);
    double coarse_diff = 0;
    for (unsigned l = 0; l + bands < top; l++)
        for (uint32_t v = 0; v < b.n; v++)
            for (int k = 0; k < 3; k++) {
                size_t at = 3 * ((size_t)l * b.n + v) + (size_t)k;
                coarse_diff = fmax(coarse_diff, fabs(b.p[at] - c0.p[at]));
            }
    CHECKF(after < 0.95 * before, "%s: roughness %.4f -> %.4f after removing %u bands", name, before, after, bands);
    CHECK(coarse_diff == 0);
    printf("%s: mean dihedral angle %.4f -> %.4f rad with the %u finest bands removed\n", name,
           before, after, bands);
    /* Enhancing: gains 2 on those bands make it rougher than the input. */
    free(b.p);
    free(c0.p);
    st_hier_free(&h);
    if (build(name, &h, 40)) { free(a.p); return; }
    for (unsigned k = 0; k < top; k++) z[k] = k + bands >= top ? 2.0 : 1.0;
    CHECK(st_progressive_filter(&h, z, top, &err) == ST_OK);
    CHECKF(roughness(&h.map, top) > before, "%s: gains 2 did not enhance", name);
    CHECK(st_progressive_filter(&h, (const double[]){ NAN }, 1, &err) != ST_OK);
    free(a.p);
    st_hier_free(&h);
}

/* The generic passes on a progressive hierarchy: least-squares analysis
 * then synthesis gives the finest level back; deleting the coarsest level
 * leaves a valid hierarchy whose synthesis still gives it back. */
static void test_analysis_and_remove_bottom(const char *name, uint64_t target)
{
    st_hier h;
    if (build(name, &h, target)) return;
    st_error err;
    unsigned top = h.map.top;
    tl_posnap a, b;
    tl_snap_pos(&h, &a);
    double res = st_hier_analyze(&h, 0);
    st_hier_synthesize(&h, 0);
    tl_snap_pos(&h, &b);
    double worst = 0, extent = 0;
    for (uint32_t v = 0; v < a.n; v++)
        for (int k = 0; k < 3; k++) {
            size_t at = 3 * ((size_t)top * a.n + v) + (size_t)k;
            worst = fmax(worst, fabs(a.p[at] - b.p[at]));
            extent = fmax(extent, fabs(a.p[at]));
        }
    CHECKF(worst <= 1e-9 * extent, "%s: analysis then synthesis moves the finest level by %g (residual %g)", name, worst, res);
    free(b.p);
    st_hier_remove_bottom(&h);
    CHECK(h.map.top == top - 1);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s: %s", name, err.msg);
    CHECK(check_independence(&h.map, name));
    st_hier_synthesize(&h, 0);
    worst = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, h.map.top, &it); v != ST_NIL; v = st_vertex_next(&h.map, h.map.top, &it)) {
        const double *p = st_pos(&h.map, v, h.map.top);
        for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(p[k] - a.p[3 * ((size_t)top * a.n + v) + (size_t)k]));
    }
    CHECKF(worst <= 1e-9 * extent, "%s: after deleting level 0, synthesis moves the finest level by %g", name, worst);
    free(a.p);
    st_hier_free(&h);
}

/* A map the scheme did not build (a crafted session could name it for a
 * Loop hierarchy): every pass runs without a fault, and the vertices it
 * cannot predict (no dart of the level below) keep their positions. */
static void test_foreign_map(void)
{
    st_hier h;
    tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, 2);
    uint64_t rng = 5;
    tl_random_details(&h, &rng, 0.01);
    h.scheme = &st_scheme_progressive;
    tl_posnap a, b;
    tl_snap_pos(&h, &a);
    st_hier_synthesize(&h, 0);
    uint32_t n;
    uint32_t *vd = vertex_darts(&h.map, 0, &n);
    double q[1][3] = { { 0.1, 0.2, 0.3 } };
    st_hier_move(&h, 0, vd, q, 1);
    st_hier_analyze(&h, 0);
    tl_snap_pos(&h, &b);
    CHECK(a.n == b.n && b.levels == 3);
    st_error err;
    CHECK(st_map_validate(&h.map, &err) == ST_OK);
    free(vd);
    free(a.p);
    free(b.p);
    h.scheme = &st_scheme_loop;
    st_hier_free(&h);
}

/* ---- sparse form of the relations (map.h, "Sparse form") ------------------------------ */

/* β0, β1 and vert of every dart at every level, through the getters and
 * through level views, the walks built on them (map.h: inline, so they take
 * this file's path, the one that answers both forms), and the cell counts
 * of every level (st_level_stats_compute has one copy per form). */
typedef struct rel_snap { uint32_t n; uint32_t *v; } rel_snap;

static void snap_relations(const st_map *m, rel_snap *s)
{
    s->n = 0;
    s->v = malloc(((size_t)m->darts.end * 10 + 6) * (m->top + 1) * sizeof *s->v + 1);
    for (unsigned l = 0; l <= m->top; l++) {
        st_level_view v;
        st_level_view_init(m, l, &v);
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
            uint32_t *o = s->v + s->n;
            o[0] = st_beta0(m, d, l);
            o[1] = st_beta1(m, d, l);
            o[2] = st_vert(m, d, l);
            o[3] = st_v_beta0(&v, d);
            o[4] = st_v_beta1(&v, d);
            o[5] = st_v_vert(&v, d);
            o[6] = st_face_degree(m, d, l);
            o[7] = st_vertex_degree(m, d, l);
            o[8] = st_phi_1(m, d, l);
            o[9] = st_beta1_inv(m, d, l);
            s->n += 10;
        }
        st_level_stats ls;
        st_level_stats_compute((st_map *)m, l, &ls);
        uint32_t *o = s->v + s->n;
        o[0] = (uint32_t)ls.darts;
        o[1] = (uint32_t)ls.vertices;
        o[2] = (uint32_t)ls.edges;
        o[3] = (uint32_t)ls.faces;
        o[4] = (uint32_t)ls.boundary_loops;
        o[5] = (uint32_t)ls.boundary_edges;
        s->n += 6;
    }
}

static int same_snap(const rel_snap *a, const rel_snap *b)
{
    return a->n == b->n && memcmp(a->v, b->v, (size_t)a->n * sizeof *a->v) == 0;
}

static void test_sparse_form(const char *name, uint64_t target)
{
    st_hier h;
    if (build(name, &h, target)) return;
    st_map *m = &h.map;
    st_map_sparse_stats st;
    st_map_sparse_stats_compute(m, &st);
    /* The build leaves all three relations sparse, and a dart's list holds
     * at most one pair per level above its insertion level. */
    CHECKF(st.relations_sparse == 3 && st.pairs > 0 && st.longest >= 1 && st.longest <= m->top,
           "%s: %u sparse relations, %llu pairs, longest %u, top %u", name, st.relations_sparse, (unsigned long long)st.pairs,
           st.longest, m->top);
    st_map_bytes sparse_bytes, dense_bytes;
    st_map_memory(m, &sparse_bytes);
    rel_snap a, b, c;
    snap_relations(m, &a);
    void *f1 = NULL, *f2 = NULL;
    size_t n1 = 0, n2 = 0;
    st_error err;
    st_session_ref r = { .h = &h, .edit_level = 0, .display_level = m->top };
    CHECK(st_session_write_mem(&r, &f1, &n1, &err) == 0);
    /* Thawed: the same relations at every level, the same session bytes,
     * a valid map, and at least twice the memory in columns. */
    st_mla_thaw(&m->beta0, &m->darts);
    st_mla_thaw(&m->beta1, &m->darts);
    st_mla_thaw(&m->vert, &m->darts);
    st_map_sparse_stats_compute(m, &st);
    CHECK(st.relations_sparse == 0 && !m->beta0.sp);
    snap_relations(m, &b);
    CHECKF(same_snap(&a, &b), "%s: the sparse form answers differently from the dense columns", name);
    CHECK(st_session_write_mem(&r, &f2, &n2, &err) == 0);
    CHECKF(n1 == n2 && memcmp(f1, f2, n1) == 0, "%s: sessions differ between the sparse and the dense form", name);
    CHECKF(st_map_validate(m, &err) == ST_OK, "%s: %s", name, err.msg);
    st_map_memory(m, &dense_bytes);
    CHECKF(dense_bytes.topology > sparse_bytes.topology, "%s: topology %zu bytes dense, %zu sparse", name, dense_bytes.topology,
           sparse_bytes.topology);
    /* Frozen again, then a setter: it turns the map dense first, and the
     * write lands as on the dense map. */
    st_map_compact(m);
    st_map_sparse_stats_compute(m, &st);
    CHECK(st.relations_sparse == 3);
    snap_relations(m, &c);
    CHECK(same_snap(&a, &c));
    st_dart_iter it;
    uint32_t d = st_dart_first(m, 0, &it);
    uint32_t e = st_beta0(m, d, m->top);
    st_set_beta0(m, d, m->top, e);
    CHECK(!m->beta0.sp && m->beta1.sp && st_beta0(m, d, m->top) == e);
    free(c.v);
    snap_relations(m, &c);
    CHECK(same_snap(&a, &c));
    CHECKF(st_map_validate(m, &err) == ST_OK, "%s: %s", name, err.msg);
    free(a.v);
    free(b.v);
    free(c.v);
    free(f1);
    free(f2);
    st_hier_free(&h);
}

/* A subdivision hierarchy changes β0 of every old dart at every level:
 * compacting it keeps the dense columns. */
static void test_sparse_form_not_for_subdivision(void)
{
    st_mesh m;
    if (load_shared("spot_low_resolution.obj", &m)) return;
    st_hier h;
    st_error err;
    CHECK(st_hier_init(&h, &m, &st_scheme_loop, NULL, &err) == ST_OK);
    CHECK(st_hier_subdivide_to(&h, 3, &err) == ST_OK);
    st_map_compact(&h.map);
    st_map_sparse_stats st;
    st_map_sparse_stats_compute(&h.map, &st);
    CHECK(st.relations_sparse == 0 && h.map.beta0.col[1] && h.map.beta0.col[3]);
    CHECK(st_map_validate(&h.map, &err) == ST_OK);
    st_hier_free(&h);
    st_mesh_free(&m);
}

/* The grouped collapses are the same on one thread and on three (the
 * changed cost keys are computed in pieces on the worker threads,
 * core/base/parallel.h): the same collapses, in the same groups. */
static void test_threads(const char *name, uint64_t target)
{
    st_mesh m;
    if (load_shared(name, &m)) return;
    CHECK(m.face_off[m.nfaces] == 3 * m.nfaces); /* a triangle mesh: pm_work_init takes it as it is */
    pm_work w[2];
    st_error err;
    char note[256];
    for (int k = 0; k < 2; k++) {
        st_parallel_set_threads(k ? 3 : 1);
        CHECK(pm_work_init(&w[k], m.pos, m.nverts, m.face_idx, m.nfaces, &err) == ST_OK);
        CHECK(pm_simplify(&w[k], target, ST_MAX_LEVELS - 1, NULL, NULL, note, sizeof note, &err) == ST_OK);
    }
    st_parallel_set_threads(0);
    CHECK(w[0].ncol > 1000 && w[0].ncol == w[1].ncol && w[0].ngroups == w[1].ngroups);
    CHECK(memcmp(w[0].col, w[1].col, (size_t)w[0].ncol * sizeof *w[0].col) == 0);
    CHECK(memcmp(w[0].group_beg, w[1].group_beg, ((size_t)w[0].ngroups + 1) * sizeof *w[0].group_beg) == 0);
    pm_work_free(&w[0]);
    pm_work_free(&w[1]);
    st_mesh_free(&m);
}

int main(void)
{
    test_topology();
    test_tetrahedron();
    test_progress_and_bad_input();
    test_rigid_motion("spot_low_resolution.obj");
    test_rigid_motion("hemisphere.obj");
    test_local_edit("spot_low_resolution.obj", 0);
    test_local_edit("blub_open.obj", 3);
    test_local_edit("plane_holes.obj", 4);
    test_local_edit("boot.obj", 2);
    test_tables_match_stencils("spot_low_resolution.obj", 30);
    test_tables_match_stencils("blub_open.obj", 30);
    test_tables_match_stencils("plane_holes.obj", 20);
    test_edit_level_with_and_without_tables("spot_low_resolution.obj", 30);
    test_edit_level_with_and_without_tables("blub_open.obj", 30);
    test_edit_level_with_and_without_tables("plane_holes.obj", 20);
    test_session("spot_low_resolution.obj");
    test_session("cube_no_bottom.obj");
    test_session_predictor("spot_low_resolution.obj");
    test_session_predictor("cube_no_bottom.obj");
    /* The light predictor keeps every exactness property (progressive.h,
     * point 5). */
    g_predictor = ST_PM_LIGHT;
    test_rigid_motion("spot_low_resolution.obj");
    test_local_edit("spot_low_resolution.obj", 0);
    test_local_edit("blub_open.obj", 3);
    test_tables_match_stencils("plane_holes.obj", 20);
    test_session("spot_low_resolution.obj");
    test_threads("plane_holes.obj", 20);
    /* So does the graded one, new builds' default (ST_PM_DEFAULT), and
     * removing its finest bands still smooths (its weight there is 1/2). */
    g_predictor = ST_PM_GRADED;
    test_rigid_motion("spot_low_resolution.obj");
    test_rigid_motion("hemisphere.obj");
    test_local_edit("spot_low_resolution.obj", 0);
    test_local_edit("blub_open.obj", 3);
    test_local_edit("boot.obj", 2);
    test_tables_match_stencils("spot_low_resolution.obj", 30);
    test_tables_match_stencils("plane_holes.obj", 20);
    test_session("spot_low_resolution.obj");
    test_threads("plane_holes.obj", 20);
    test_filter("spot_low_resolution.obj");
    test_filter("boot.obj");
    /* Level 0 placed at its quadrics' optima (point 8; st_rebuild's
     * builds: graded and placed) keeps every exactness property. */
    test_fit_coarse("spot_low_resolution.obj", 30, 1);
    test_fit_coarse("sphere_ico.obj", 20, 1);
    test_fit_coarse("blub_open.obj", 30, 0);
    test_fit_coarse("plane_holes.obj", 20, 0);
    g_fit = 1;
    test_rigid_motion("spot_low_resolution.obj");
    test_local_edit("spot_low_resolution.obj", 0);
    test_local_edit("blub_open.obj", 3);
    test_local_edit("boot.obj", 2);
    test_tables_match_stencils("spot_low_resolution.obj", 30);
    test_tables_match_stencils("plane_holes.obj", 20);
    test_edit_level_with_and_without_tables("spot_low_resolution.obj", 30);
    test_session("spot_low_resolution.obj");
    test_session("cube_no_bottom.obj");
    test_threads("plane_holes.obj", 20);
    test_sparse_form("spot_low_resolution.obj", 30);
    g_fit = 0;
    g_predictor = ST_PM_RELAXED;
    test_filter("spot_low_resolution.obj");
    test_filter("boot.obj");
    test_foreign_map();
    test_sparse_form("spot_low_resolution.obj", 30);
    test_sparse_form("plane_holes.obj", 20);
    test_sparse_form_not_for_subdivision();
    test_analysis_and_remove_bottom("hand_lowres.obj", 60);
    test_analysis_and_remove_bottom("cube_no_bottom.obj", 4);
    test_threads("plane_holes.obj", 20);
    return TEST_END();
}
