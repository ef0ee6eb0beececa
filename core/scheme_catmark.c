/* Catmull-Clark (1978) on any polygon mesh, with OpenSubdiv's boundary and
 * crease rules (crease.h).  Masks (digest §4, thesis fig. 3.14):
 *   face point   = average of the face's vertices;
 *   edge point   = (v0 + v1 + f0 + f1) / 4, f = adjacent face points;
 *   vertex point = ((n-2) v + Σe/n + Σf/n) / n  (= (Q + 2R + (n-3)S)/n).
 * Topology: polygon quadrisection (refine.c). */
#include "crease.h"
#include "hier_internal.h"

#include <stdlib.h>
#include <string.h>

#include "pool.h"

/* Adds w · (face centroid of d's face) as vertex weights. */
static void add_face_centroid(const st_map *m, unsigned l, uint32_t d, double w, st_stencil_buf *out)
{
    unsigned n = st_face_degree(m, d, l);
    uint32_t x = d;
    do { st_stencil_buf_add(out, st_vert(m, x, l), w / n); x = st_phi1(m, x, l); } while (x != d);
}

static void smooth_edge(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = &h->map;
    uint32_t e = st_beta0(m, d, l);
    st_stencil_buf_add(out, st_vert(m, d, l), 0.25);
    st_stencil_buf_add(out, st_vert(m, e, l), 0.25);
    add_face_centroid(m, l, d, 0.25, out);
    add_face_centroid(m, l, e, 0.25, out);
}

static void smooth_vertex(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = &h->map;
    unsigned n = st_vertex_degree(m, d, l);
    double inv = 1.0 / ((double)n * n);
    st_stencil_buf_add(out, st_vert(m, d, l), (double)(n - 2) / n);
    uint32_t x = d;
    do {
        st_stencil_buf_add(out, st_vert(m, st_beta0(m, x, l), l), inv);
        add_face_centroid(m, l, x, inv, out);
        x = st_beta1(m, x, l);
    } while (x != d);
}

typedef struct emitter {
    st_stencil_buf buf, tmp;
} emitter;

static void emit_face(const st_hier *h, unsigned L, uint32_t c, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
    unsigned l = L - 1;
    uint32_t centre = st_vert(m, st_phi1(m, st_phi1(m, c, L), L), L);
    st_stencil_buf_clear(&e->buf);
    add_face_centroid(m, l, c, 1.0, &e->buf);
    st_stencil s = { centre, e->buf.n, e->buf.src, e->buf.w, c, ST_CELL_FACE };
    sink(ctx, &s);
}

static void emit_edge(const st_hier *h, unsigned L, uint32_t d, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
    uint32_t mid = st_vert(m, st_beta0(m, d, L), L);
    st_crease_edge_point(h, L - 1, d, smooth_edge, &e->buf, &e->tmp);
    st_stencil s = { mid, e->buf.n, e->buf.src, e->buf.w, d, ST_CELL_EDGE };
    sink(ctx, &s);
}

static void emit_vertex(const st_hier *h, unsigned L, uint32_t d, emitter *e, st_stencil_sink sink, void *ctx)
{
    st_crease_vertex_point(h, L - 1, d, smooth_vertex, &e->buf, &e->tmp);
    st_stencil s = { st_vert(&h->map, d, L - 1), e->buf.n, e->buf.src, e->buf.w, d, ST_CELL_VERTEX };
    sink(ctx, &s);
}

/* Every fine vertex once: faces and vertices by marker, edges by d < β0(d). */
static void emit_all(st_hier *h, unsigned L, emitter *e, st_stencil_sink sink, void *ctx)
{
    st_map *m = &h->map;
    unsigned l = L - 1;
    int fb = st_marker_reserve(m), vb = st_marker_reserve(m);
    if (fb < 0 || vb < 0) abort();
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (!st_marked(m, vb, d)) { st_mark_vertex(m, vb, d, l); emit_vertex(h, L, d, e, sink, ctx); }
        if (d < st_beta0(m, d, l)) emit_edge(h, L, d, e, sink, ctx);
        if (!st_is_boundary(m, d) && !st_marked(m, fb, d)) { st_mark_face(m, fb, d, l); emit_face(h, L, d, e, sink, ctx); }
    }
    st_marker_release(m, fb, l);
    st_marker_release(m, vb, l);
}

/* Fine vertices of the given faces: centre, edge points, corners. */
static void emit_faces(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t c = faces[i], x = c;
        emit_face(h, L, c, e, sink, ctx);
        do {
            emit_edge(h, L, x, e, sink, ctx);
            emit_vertex(h, L, x, e, sink, ctx);
            x = st_phi1(m, x, L - 1);
        } while (x != c);
    }
}

static void catmark_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    emitter e = { 0 };
    if (faces) emit_faces(h, L, faces, n, &e, sink, ctx);
    else emit_all(h, L, &e, sink, ctx);
    st_stencil_buf_free(&e.buf);
    st_stencil_buf_free(&e.tmp);
}

static int catmark_refine(st_hier *h, st_error *err) { return st_hier_refine_primal(h, ST_SPLIT_POLY, err); }


/* ---- fast full-level synthesis ------------------------------------------------
 * Same arithmetic as the stencils above, organised like OpenSubdiv's
 * PrimvarRefiner: face points first (each face walked once, found through
 * its centre vertex), then edge and vertex points reading the face points
 * back from level L.  Cells touching a boundary or a sharp feature take the
 * stencil path.  The weights are applied in the same order as the stencils
 * so that both paths give the same bits. */

typedef struct fast_ctx {
    st_hier *h;
    unsigned L;
    st_level_view c, f;        /* coarse level L-1, fine level L */
    double *pnew, *pold;       /* level-L positions: base (new vertices), column (old vertices) */
    emitter e;
} fast_ctx;

static double *fine_slot(fast_ctx *x, uint32_t v)
{
    return (x->c.vins[v] == x->L ? x->pnew : x->pold) + 3 * (size_t)v;
}

static uint32_t centre_of(const fast_ctx *x, uint32_t d)
{
    return st_v_vert(&x->f, st_v_phi1(&x->f, st_v_phi1(&x->f, d)));
}

static void sink_write(void *ctx, const st_stencil *s)
{
    fast_ctx *x = ctx;
    st_stencil_eval(x->h, x->L, s, fine_slot(x, s->fine));
}

static void fast_face(fast_ctx *x, uint32_t d, uint32_t centre)
{
    double acc[3] = { 0, 0, 0 };
    unsigned n = 0;
    uint32_t y = d;
    do { n++; y = st_v_phi1(&x->c, y); } while (y != d);
    double w = 1.0 / n;
    do {
        const double *p = st_v_pos(&x->c, st_v_vert(&x->c, y));
        acc[0] += w * p[0]; acc[1] += w * p[1]; acc[2] += w * p[2];
        y = st_v_phi1(&x->c, y);
    } while (y != d);
    memcpy(fine_slot(x, centre), acc, sizeof acc);
}

static int smooth_edge_ok(const fast_ctx *x, uint32_t d, uint32_t e)
{
    const st_map *m = &x->h->map;
    (void)0;
    if (st_is_boundary(m, d) || st_is_boundary(m, e)) return 0;
    return !x->h->has_sharpness || st_hier_edge_sharpness(x->h, d, x->L - 1) <= 0;
}

static void fast_edge(fast_ctx *x, uint32_t d, uint32_t e)
{
    if (!smooth_edge_ok(x, d, e)) { emit_edge(x->h, x->L, d, &x->e, sink_write, x); return; }
    const double *a = st_v_pos(&x->c, st_v_vert(&x->c, d)), *b = st_v_pos(&x->c, st_v_vert(&x->c, e));
    const double *f0 = fine_slot(x, centre_of(x, d)), *f1 = fine_slot(x, centre_of(x, e));
    double *out = fine_slot(x, st_v_vert(&x->f, st_v_beta0(&x->f, d)));
    for (int i = 0; i < 3; i++) out[i] = 0.25 * a[i] + 0.25 * b[i] + 0.25 * f0[i] + 0.25 * f1[i];
}

static void fast_vertex(fast_ctx *x, uint32_t d)
{
    uint32_t v = st_v_vert(&x->c, d);
    unsigned n = 0;
    uint32_t y = d;
    int smooth = !x->h->has_sharpness || st_hier_vertex_sharpness(x->h, v, x->L - 1) <= 0;
    do {
        uint32_t e = st_v_beta0(&x->c, y);
        if (!smooth_edge_ok(x, y, e)) smooth = 0;
        n++;
        y = st_v_beta1(&x->c, y);
    } while (y != d);
    if (!smooth) { emit_vertex(x->h, x->L, d, &x->e, sink_write, x); return; }
    double inv = 1.0 / ((double)n * n), acc[3];
    const double *p = st_v_pos(&x->c, v);
    for (int i = 0; i < 3; i++) acc[i] = (double)(n - 2) / n * p[i];
    do {
        const double *q = st_v_pos(&x->c, st_v_vert(&x->c, st_v_beta0(&x->c, y)));
        const double *f = fine_slot(x, centre_of(x, y));
        for (int i = 0; i < 3; i++) acc[i] += inv * q[i] + inv * f[i];
        y = st_v_beta1(&x->c, y);
    } while (y != d);
    memcpy(fine_slot(x, v), acc, sizeof acc);
}

static void catmark_predict_level(st_hier *h, unsigned L)
{
    st_map *m = &h->map;
    fast_ctx x = { .h = h, .L = L };
    x.pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    x.pnew = (double *)m->pos.base;
    if (!x.pold) abort(); /* out of memory for a level's positions */
    st_level_view_init(m, L - 1, &x.c);
    st_level_view_init(m, L, &x.f);
    uint32_t fgen = st_hier_stamp_begin(h);
    uint32_t vgen = st_hier_stamp_begin(h);
    uint32_t *stamp = h->stamp;
    const st_pool *p = &m->darts;
    for (unsigned pass = 0; pass < 2; pass++)
        for (unsigned lv = 0; lv < L; lv++)
            for (uint32_t b = 0; b < p->nblocks[lv]; b++) {
                uint32_t first = p->blocks[lv][b] << ST_POOL_BLOCK_SHIFT;
                for (uint32_t d = first; d < first + ST_POOL_BLOCK; d++) {
                    if (p->ins[d] == ST_FREE_LEVEL) continue;
                    if (pass == 0) {
                        if (st_is_boundary(m, d)) continue;
                        uint32_t c = centre_of(&x, d);
                        if (stamp[c] != fgen) { stamp[c] = fgen; fast_face(&x, d, c); }
                        continue;
                    }
                    uint32_t e = st_v_beta0(&x.c, d);
                    if (d < e) fast_edge(&x, d, e);
                    uint32_t v = st_v_vert(&x.c, d);
                    if (stamp[v] != vgen) { stamp[v] = vgen; fast_vertex(&x, d); }
                }
            }
    st_stencil_buf_free(&x.e.buf);
    st_stencil_buf_free(&x.e.tmp);
}

const st_scheme st_scheme_catmark = {
    .name = "catmull-clark",
    .id = ST_SCHEME_CATMARK,
    .interpolating = 0,
    .support_rings = 1,
    .check = NULL,
    .refine = catmark_refine,
    .emit = catmark_emit,
    .predict_level = catmark_predict_level,
};
