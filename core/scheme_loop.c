/* Loop (1987) on triangle meshes, with OpenSubdiv 3.5's boundary, corner
 * and semi-sharp crease rules (crease.h; Sdc::Scheme<SCHEME_LOOP>,
 * sdc/loopScheme.h).  Masks (digest §4, thesis fig. 3.14, listing 3.2.1):
 *   edge point   = 3/8 (a + b) + 1/8 (c + d), c and d opposite the edge;
 *   vertex point = (1 - nβ) v + β Σ neighbours, Loop's original
 *                  β = (1/n) (5/8 - (3/8 + cos(2π/n) / 4)²),
 *                  exactly 1/16 (and 5/8 for v) at valence 6.
 * The weights are computed with OpenSubdiv's own expression order
 * (assignSmoothMaskForVertex) so that both agree to the last bits.
 * Boundaries: boundary edges are infinitely sharp (midpoints, B-spline
 * boundary curves); with edge-and-corner a boundary vertex with one face is
 * a corner.  Topology: triangle quadrisection (refine.c, ST_SPLIT_TRI). */
#include "crease.h"
#include "hier_internal.h"

#include <math.h>
#include <stdlib.h>

/* Vertex opposite the edge of d in d's triangle (level l). */
static uint32_t opposite(const st_map *m, uint32_t d, unsigned l)
{
    return st_vert(m, st_phi1(m, st_phi1(m, d, l), l), l);
}

/* Only called for edges with two real faces (boundary edges are sharp). */
static void smooth_edge(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = &h->map;
    uint32_t e = st_beta0(m, d, l);
    st_stencil_buf_add(out, st_vert(m, d, l), 0.375);
    st_stencil_buf_add(out, st_vert(m, e, l), 0.375);
    st_stencil_buf_add(out, opposite(m, d, l), 0.125);
    st_stencil_buf_add(out, opposite(m, e, l), 0.125);
}

/* Loop's original weights, in OpenSubdiv's arithmetic (double). */
static void loop_weights(unsigned n, double *vw, double *ew)
{
    if (n == 6) { *vw = 0.625; *ew = 0.0625; return; }
    double dn = (double)n, inv = 1.0 / dn;
    double c = cos(M_PI * 2.0 * inv);
    double beta = 0.25 * c + 0.375;
    *ew = (0.625 - beta * beta) * inv;
    *vw = 1.0 - *ew * dn;
}

/* Smooth (and dart) vertices are interior: every face around is real. */
static void smooth_vertex(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = &h->map;
    unsigned n = st_vertex_degree(m, d, l);
    double vw, ew;
    loop_weights(n, &vw, &ew);
    st_stencil_buf_add(out, st_vert(m, d, l), vw);
    uint32_t x = d;
    do {
        st_stencil_buf_add(out, st_vert(m, st_beta0(m, x, l), l), ew);
        x = st_beta1(m, x, l);
    } while (x != d);
}

typedef struct emitter {
    st_stencil_buf buf, tmp;
} emitter;

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

/* Every fine vertex once: vertices by marker, edges by d < β0(d). */
static void emit_all(st_hier *h, unsigned L, emitter *e, st_stencil_sink sink, void *ctx)
{
    st_map *m = &h->map;
    unsigned l = L - 1;
    int vb = st_marker_reserve(m);
    if (vb < 0) abort();
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (!st_marked(m, vb, d)) { st_mark_vertex(m, vb, d, l); emit_vertex(h, L, d, e, sink, ctx); }
        if (d < st_beta0(m, d, l)) emit_edge(h, L, d, e, sink, ctx);
    }
    st_marker_release(m, vb, l);
}

/* Fine vertices of the given coarse triangles: corners and edge points. */
static void emit_faces(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t c = faces[i], x = c;
        do {
            emit_edge(h, L, x, e, sink, ctx);
            emit_vertex(h, L, x, e, sink, ctx);
            x = st_phi1(m, x, L - 1);
        } while (x != c);
    }
}

static void loop_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    emitter e = { 0 };
    if (faces) emit_faces(h, L, faces, n, &e, sink, ctx);
    else emit_all(h, L, &e, sink, ctx);
    st_stencil_buf_free(&e.buf);
    st_stencil_buf_free(&e.tmp);
}

/* Triangles only: names the side count of the first other face. */
static int loop_check(st_hier *h, st_error *err)
{
    const st_map *m = &h->map;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
        if (st_is_boundary(m, d)) continue;
        unsigned n = st_face_degree(m, d, 0);
        if (n != 3)
            return st_fail(err, ST_ERR_TOPOLOGY, "the loop scheme needs a triangle mesh, but the mesh has a face with %u sides", n);
    }
    return ST_OK;
}

static int loop_refine(st_hier *h, st_error *err) { return st_hier_refine_primal(h, ST_SPLIT_TRI, err); }

const st_scheme st_scheme_loop = {
    .name = "loop",
    .id = ST_SCHEME_LOOP,
    .interpolating = 0,
    .support_rings = 1,
    .check = loop_check,
    .refine = loop_refine,
    .emit = loop_emit,
};
