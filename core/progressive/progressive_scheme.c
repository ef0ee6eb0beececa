/* "progressive": the prediction of a progressive multiresolution mesh
 * (progressive.h, point 5; thesis §4.4.6, GSS99 §3).
 *
 * Its table lives here, above core/multires, not with the subdivision
 * schemes of core/schemes: its fast paths are the progressive hierarchy's
 * own (ring tables cached in the st_hier, details applied with the
 * prediction, the pm_predictor option), so it reads the hierarchy through
 * the view's owner, where the rules of core/schemes read the view alone.
 *
 * The levels come from simplification, so refine() refuses.  At level L:
 *   - a vertex that exists at L-1 is predicted by its own level-(L-1)
 *     position (the half-edge collapse left it in place), unless it is a
 *     neighbour of a split vertex: then by half its own position and half
 *     the average of its neighbours, the split ones at their prediction
 *     (GSS99 §3: the neighbours of a split are relaxed too);
 *   - a vertex inserted at L (a split vertex) by the average of the
 *     level-(L-1) positions of its level-L neighbours, or of its two
 *     boundary neighbours on a border (a boundary vertex only moves along
 *     its boundary).  The independence rule of the build makes every such
 *     neighbour a vertex of level L-1.
 * The detail frame is the vertex cell, at L-1, of a dart of level L-1 that
 * starts at the vertex at level L: for a split vertex a that dart started
 * at b, the vertex a was merged into, at L-1.
 *
 * Everything is read from the map alone (a loaded session has nothing
 * else), and a vertex's stencil is built from the smallest dart of its
 * level-L orbit, so that its order of summation, hence its rounding, is the
 * same whichever dart reached it: local re-synthesis == full synthesis.
 * Synthesis itself, full and local, evaluates the same stencils from flat
 * ring tables (progressive_synth.c), to the same bits;
 * emit() serves the analysis, the edits' predictions and maps the tables
 * do not describe. */
#include "core/multires/hier_internal.h"
#include "core/progressive/progressive_internal.h"

#include <stdlib.h>

static uint32_t orbit_min(const st_map *m, uint32_t d, unsigned L)
{
    uint32_t best = d, x = d;
    do {
        if (x < best) best = x;
        x = st_beta1(m, x, L);
    } while (x != d);
    return best;
}

static int on_border(const st_map *m, uint32_t x, unsigned L)
{
    return st_is_boundary(m, x) || st_is_boundary(m, st_beta0(m, x, L));
}

/* Average of the level-(L-1) positions of the level-L neighbours of the
 * orbit of c (its border neighbours on a border), into buf with total
 * weight `scale`; the neighbours inserted at L are left out (none for a
 * split vertex of a map this scheme built). */
static void ring_average(const st_map *m, uint32_t c, unsigned L, int border, double scale, st_stencil_buf *buf)
{
    uint32_t first = buf->n, x = c;
    do {
        uint32_t u = st_vert(m, st_beta0(m, x, L), L);
        if ((!border || on_border(m, x, L)) && m->verts.ins[u] < L) st_stencil_buf_add(buf, u, 1.0);
        x = st_beta1(m, x, L);
    } while (x != c);
    if (buf->n == first) return; /* the caller falls back on a vertex of level L-1 */
    double w = scale / (buf->n - first);
    for (uint32_t i = first; i < buf->n; i++) buf->w[i] = w;
}

int st_progressive_stencil(const st_hier *h, unsigned L, uint32_t d, st_stencil_buf *buf, st_stencil *s)
{
    const st_map *m = &h->map;
    uint32_t v = st_vert(m, d, L), c = orbit_min(m, d, L), frame = ST_NIL, x = c;
    int border = 0, near_split = 0;
    do {
        if (frame == ST_NIL && m->darts.ins[x] < L) frame = x;
        border |= on_border(m, x, L);
        near_split |= m->verts.ins[st_vert(m, st_beta0(m, x, L), L)] == L;
        x = st_beta1(m, x, L);
    } while (x != c);
    if (frame == ST_NIL) return 0; /* no dart of level L-1 here: not a map this scheme built */
    double mu = pm_relax_weight(h, L);
    st_stencil_buf_clear(buf);
    if (m->verts.ins[v] == L) {
        ring_average(m, c, L, border, 1.0, buf);
        if (buf->n == 0) st_stencil_buf_add(buf, st_vert(m, frame, L - 1), 1.0);
    } else if (!near_split) {
        st_stencil_buf_add(buf, v, 1.0);
    } else {
        /* A neighbour of a split vertex: half its own position, half the
         * average of its neighbours, a split one at its own prediction
         * (GSS99 §3: the neighbours are relaxed too). */
        st_stencil_buf_add(buf, v, 1.0 - mu);
        unsigned k = 0;
        x = c;
        do {
            k += !border || on_border(m, x, L);
            x = st_beta1(m, x, L);
        } while (x != c);
        st_stencil_buf sub = { 0 };
        x = c;
        do {
            uint32_t e = st_beta0(m, x, L), u = st_vert(m, e, L);
            if (!border || on_border(m, x, L)) {
                if (m->verts.ins[u] < L) {
                    st_stencil_buf_add(buf, u, mu / k);
                } else {
                    uint32_t ce = orbit_min(m, e, L), y = ce;
                    int ub = 0;
                    do { ub |= on_border(m, y, L); y = st_beta1(m, y, L); } while (y != ce);
                    st_stencil_buf_clear(&sub);
                    ring_average(m, ce, L, ub, 1.0, &sub);
                    if (sub.n == 0) st_stencil_buf_add(&sub, v, 1.0);
                    st_stencil_buf_add_scaled(buf, &sub, mu / k);
                }
            }
            x = st_beta1(m, x, L);
        } while (x != c);
        st_stencil_buf_free(&sub);
    }
    *s = (st_stencil){ v, buf->n, buf->src, buf->w, frame, ST_CELL_VERTEX };
    return 1;
}

static void emit_one(st_hier *h, unsigned L, uint32_t d, st_stencil_buf *buf, st_stencil_sink sink, void *ctx)
{
    st_stencil s;
    if (st_progressive_stencil(h, L, d, buf, &s)) sink(ctx, &s);
}

static void emit_all(st_hier *h, unsigned L, st_stencil_sink sink, void *ctx)
{
    st_map *m = &h->map;
    uint32_t n = m->verts.end ? m->verts.end : 1;
    uint32_t *vmin = malloc(n * sizeof *vmin);
    if (!vmin) abort(); /* one word per vertex: out of memory here is fatal, as for stencils */
    for (uint32_t v = 0; v < n; v++) vmin[v] = ST_NIL;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
        uint32_t v = st_vert(m, d, L);
        if (v < n && d < vmin[v]) vmin[v] = d;
    }
    st_stencil_buf buf = { 0 };
    for (uint32_t v = 0; v < n; v++)
        if (vmin[v] != ST_NIL) emit_one(h, L, vmin[v], &buf, sink, ctx);
    st_stencil_buf_free(&buf);
    free(vmin);
}

/* For each vertex w (at level L) of the darts of the given coarse faces:
 * w and all its neighbours at L.  A stencil of level L reads the level-
 * (L-1) positions within two rings (at L-1) of its vertex, and the vertex
 * is itself a face vertex or a neighbour of one of the faces within
 * support_rings = 2 of any vertex it reads. */
static void emit_faces(st_hier *h, unsigned L, const uint32_t *faces, uint32_t nfaces, st_stencil_sink sink, void *ctx)
{
    st_map *m = &h->map;
    st_stencil_buf buf = { 0 };
    /* Each vertex once: it is reached from every face and ring around it,
     * some forty times, and its stencil is the costly part (the sinks'
     * stamps only drop the repeats once built).  The stencil does not
     * depend on the dart that reached the vertex (orbit_min above). */
    uint8_t *seen = calloc(m->verts.end ? m->verts.end : 1, 1);
    if (!seen) abort(); /* one byte per vertex: out of memory here is fatal, as for stencils */
    for (uint32_t i = 0; i < nfaces; i++) {
        uint32_t f = faces[i], x = f;
        do {
            uint32_t v = st_vert(m, x, L);
            if (!seen[v]) { seen[v] = 1; emit_one(h, L, x, &buf, sink, ctx); }
            uint32_t z = x;
            do {
                uint32_t e = st_beta0(m, z, L), u = st_vert(m, e, L);
                if (!seen[u]) { seen[u] = 1; emit_one(h, L, e, &buf, sink, ctx); }
                z = st_beta1(m, z, L);
            } while (z != x);
            x = st_phi1(m, x, L - 1);
        } while (x != f);
    }
    free(seen);
    st_stencil_buf_free(&buf);
}

static void progressive_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t nfaces,
                             st_stencil_sink sink, void *ctx)
{
    st_hier *h = sv->owner;
    if (L == 0 || L > h->map.top) return;
    if (!faces) emit_all(h, L, sink, ctx);
    else emit_faces(h, L, faces, nfaces, sink, ctx);
}

/* Full synthesis of level L: the ring tables, or the stencils on a map
 * they do not describe. */
static void progressive_synth_level(const st_subdiv_view *sv, unsigned L)
{
    st_hier *h = sv->owner;
    if (st_progressive_synth_level(h, L)) return;
    st_synth_ctx c = st_hier_synth_ctx(h, L);
    emit_all(h, L, st_synth_sink, &c);
}

static int progressive_predict_around(const st_subdiv_view *sv, unsigned L, const uint32_t *seeds, uint32_t nseeds,
                                      st_synth_ctx *out)
{
    return st_progressive_resynth_around(sv->owner, L, seeds, nseeds, out);
}

static int progressive_predict_vertex(const st_subdiv_view *sv, unsigned L, uint32_t v, double pred[3], double f[3][3])
{
    return st_progressive_predict_vertex(sv->owner, L, v, pred, f);
}

static size_t progressive_synth_estimate(const st_subdiv_view *sv, unsigned from)
{
    return st_progressive_synth_estimate(sv->owner, from);
}

static int progressive_check(const st_subdiv_view *sv, st_error *err)
{
    const st_map *m = sv->map;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it))
        if (!st_is_boundary(m, d) && st_face_degree(m, d, 0) != 3)
            return st_fail(err, ST_ERR_INVALID, "the progressive scheme needs a triangle mesh");
    return ST_OK;
}

static int progressive_refine(const st_subdiv_view *sv, st_error *err)
{
    (void)sv;
    return st_fail(err, ST_ERR_INVALID,
                   "a progressive hierarchy is built by simplification (st_progressive_build) and cannot be refined");
}

const st_scheme st_scheme_progressive = {
    .name = "progressive",
    .id = ST_SCHEME_PROGRESSIVE,
    .interpolating = 0,               /* the neighbours of a split are relaxed */
    .support_rings = 2,               /* a stencil reads two rings (emit_faces) */
    /* Triangles in; levels come from simplification, never from refine(). */
    .check = progressive_check, .refine = progressive_refine,
    .emit = progressive_emit,         /* the analysis, the edits' predictions, maps without tables */
    /* The hierarchy's own fast paths: ring tables, details applied with
     * the prediction (progressive_synth.c), and what their tables cost. */
    .predict_level = progressive_synth_level, .predict_around = progressive_predict_around,
    .fast_paths_apply_details = 1, .synth_estimate = progressive_synth_estimate,
    .predict_vertex = progressive_predict_vertex,
};
