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
#include "primal_emit.h"
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

static const st_primal_rules loop_rules = { smooth_vertex, smooth_edge, 1, ST_FACE_POINTS_NONE };

static void loop_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    st_primal_emit(h, L, faces, n, sink, ctx, &loop_rules);
}

static int loop_check(st_hier *h, st_error *err) { return st_check_triangles(h, err); }

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
