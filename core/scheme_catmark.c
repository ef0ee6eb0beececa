/* Catmull-Clark (1978) on any polygon mesh, with OpenSubdiv's boundary and
 * crease rules (crease.h).  Masks (digest §4, thesis fig. 3.14):
 *   face point   = average of the face's vertices;
 *   edge point   = (v0 + v1 + f0 + f1) / 4, f = adjacent face points;
 *   vertex point = ((n-2) v + Σe/n + Σf/n) / n  (= (Q + 2R + (n-3)S)/n).
 * Topology: polygon quadrisection (refine.c). */
#include "crease.h"
#include "hier_internal.h"

#include <stdlib.h>

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

const st_scheme st_scheme_catmark = {
    .name = "catmull-clark",
    .id = ST_SCHEME_CATMARK,
    .interpolating = 0,
    .support_rings = 1,
    .check = NULL,
    .refine = catmark_refine,
    .emit = catmark_emit,
};
