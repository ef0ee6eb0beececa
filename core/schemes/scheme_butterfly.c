/* Modified Butterfly (Zorin, Schröder, Sweldens 1996), interpolating, on
 * triangle meshes, with the boundary and valence rules of OpenMesh 9's
 * Subdivider::Uniform::ModifiedButterflyT (compute_midpoint), which is the
 * oracle of the tests.  Topology: triangle quadrisection (ST_SPLIT_TRI).
 *
 * Even vertices keep their position (stencil: the vertex, weight 1).
 * The point of an edge (a0, a1), valence = number of incident edges:
 *
 *   boundary edge: the 4-point rule along the boundary,
 *       9/16 (a0 + a1) - 1/16 (p0 + p1), p = the other boundary neighbours;
 *   interior edge, when both ends have valence 6, or one end is on the
 *   boundary and the other has valence 6, or both ends are on the boundary:
 *       the 10-point stencil with w = 0 (8 points):
 *       1/2 (a0 + a1) + 1/8 (b0 + b1) - 1/16 (c0 + c1 + c2 + c3),
 *       b = the apexes of the two triangles, c = the vertices across the
 *       four "wing" edges (b, a); a wing edge on the boundary has no vertex
 *       across, and c is the ghost a' + b - a'' (the apex reflected through
 *       the wing edge's midpoint: a' the wing's end on the edge, a'' the
 *       other end of the edge);
 *   otherwise each end that is interior with valence k != 6 contributes
 *       Zorin's stencil  3/4 a + Σ_j s_j v_j  (v_0 = the other end, then
 *       around the vertex; s symmetric so the direction does not matter):
 *       k = 3: 5/12, -1/12, -1/12;  k = 4: 3/8, 0, -1/8, 0;
 *       k >= 5: s_j = (1/4 + cos(2πj/k) + 1/2 cos(4πj/k)) / k,
 *       (the weight of a is 1 - Σ s_j, as OpenMesh computes it: 3/4 up to
 *       rounding), and the point is the average of the contributions.
 *
 * Differences from the paper (kept on purpose, to match OpenMesh):
 *   - the paper (SIGGRAPH 96) gives no boundary rules; Zorin's later
 *     boundary masks (thesis 1998) treat interior edges next to the boundary
 *     with special stencils, OpenMesh uses the regular 8-point stencil with
 *     ghost points there, and the extraordinary stencil only for interior
 *     ends;
 *   - an interior edge with one boundary end of any valence and one interior
 *     end of valence 6 uses the regular stencil;
 *   - an interior edge whose interior end has valence != 6 and whose other
 *     end is on the boundary uses the interior end's stencil alone.
 * Creases, corners and the boundary option (edge-only / edge-and-corner)
 * do not apply to this scheme: OpenMesh has one boundary rule, and there is
 * no sharpness in the butterfly rules.  Tags are kept (refine propagates
 * them) but ignored by the masks. */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/crease_internal.h"
#include "core/schemes/synth_internal.h"
#include "core/schemes/primal_emit_internal.h"

#include <math.h>
#include <stdlib.h>

static int vertex_on_boundary(const st_map *m, uint32_t d, unsigned l)
{
    uint32_t x = d;
    do {
        if (st_is_boundary(m, x)) return 1;
        x = st_beta1(m, x, l);
    } while (x != d);
    return 0;
}

/* Vertex across the wing edge of dart w (level l) from w's triangle, whose
 * apex is y: that vertex, or the ghost vert(w) + vert(β0 w) - y when the
 * wing lies on the boundary.  Adds it with weight g. */
static void add_wing(const st_map *m, unsigned l, uint32_t w, uint32_t y, double g, st_stencil_buf *out)
{
    uint32_t t = st_beta0(m, w, l);
    if (!st_is_boundary(m, t)) {
        st_stencil_buf_add(out, st_vert(m, st_phi1(m, st_phi1(m, t, l), l), l), g);
        return;
    }
    st_stencil_buf_add(out, st_vert(m, w, l), g);
    st_stencil_buf_add(out, st_vert(m, t, l), g);
    st_stencil_buf_add(out, y, -g);
}

/* Regular (8-point) stencil of the interior edge of d. */
static void regular_edge(const st_map *m, unsigned l, uint32_t d, st_stencil_buf *out)
{
    uint32_t e = st_beta0(m, d, l);
    uint32_t a0 = st_vert(m, d, l), a1 = st_vert(m, e, l);
    uint32_t d1 = st_phi1(m, d, l), d2 = st_phi1(m, d1, l);   /* at a1, at the apex of d's face */
    uint32_t e1 = st_phi1(m, e, l), e2 = st_phi1(m, e1, l);   /* at a0, at the apex of e's face */
    st_stencil_buf_add(out, a0, 0.5);
    st_stencil_buf_add(out, a1, 0.5);
    st_stencil_buf_add(out, st_vert(m, d2, l), 0.125);
    st_stencil_buf_add(out, st_vert(m, e2, l), 0.125);
    add_wing(m, l, d1, a0, -0.0625, out);   /* wing (a1, b_d) */
    add_wing(m, l, d2, a1, -0.0625, out);   /* wing (b_d, a0) */
    add_wing(m, l, e1, a1, -0.0625, out);   /* wing (a0, b_e) */
    add_wing(m, l, e2, a0, -0.0625, out);   /* wing (b_e, a1) */
}

/* Zorin's stencil of the interior vertex of d with valence k != 6, scaled
 * by s, the ring starting at the other end of d's edge. */
static void extraordinary(const st_map *m, unsigned l, uint32_t d, unsigned k, double s, st_stencil_buf *out)
{
    double sum = 0;
    uint32_t x = d;
    for (unsigned j = 0; j < k; j++, x = st_beta1(m, x, l)) {
        double w;
        if (k == 3) w = j == 0 ? 5.0 / 12 : -1.0 / 12;
        else if (k == 4) w = j == 0 ? 3.0 / 8 : j == 2 ? -1.0 / 8 : 0.0;
        else {
            double inv = 1.0 / (double)k;
            w = (0.25 + cos(2.0 * M_PI * (double)j * inv) + 0.5 * cos(4.0 * M_PI * (double)j * inv)) * inv;
        }
        sum += w;
        st_stencil_buf_add(out, st_vert(m, st_beta0(m, x, l), l), s * w);
    }
    double wa = k == 3 || k == 4 ? 0.75 : 1.0 - sum;
    st_stencil_buf_add(out, st_vert(m, d, l), s * wa);
}

/* 4-point rule on the boundary edge of the real dart r (β0(r) boundary). */
static void boundary_edge(const st_map *m, unsigned l, uint32_t r, st_stencil_buf *out)
{
    uint32_t b = st_beta0(m, r, l);                /* hole dart from w = end of r to u = vert(r) */
    uint32_t u = st_vert(m, r, l), w = st_vert(m, b, l);
    uint32_t p = st_vert(m, st_beta0(m, st_phi1(m, b, l), l), l);       /* after u along the hole */
    uint32_t q = st_vert(m, st_beta0(m, st_beta1_inv(m, b, l), l), l);  /* before w along the hole */
    st_stencil_buf_add(out, u, 0.5625);
    st_stencil_buf_add(out, w, 0.5625);
    st_stencil_buf_add(out, p, -0.0625);
    st_stencil_buf_add(out, q, -0.0625);
}

static void edge_point(const st_map *m, unsigned l, uint32_t d, st_stencil_buf *out)
{
    uint32_t e = st_beta0(m, d, l);
    st_stencil_buf_clear(out);
    if (st_is_boundary(m, e)) { boundary_edge(m, l, d, out); return; }
    if (st_is_boundary(m, d)) { boundary_edge(m, l, e, out); return; }
    unsigned k0 = st_vertex_degree(m, d, l), k1 = st_vertex_degree(m, e, l);
    int b0 = vertex_on_boundary(m, d, l), b1 = vertex_on_boundary(m, e, l);
    if ((k0 == 6 && k1 == 6) || (b0 && k1 == 6) || (b1 && k0 == 6) || (b0 && b1)) {
        regular_edge(m, l, d, out);
        return;
    }
    int x0 = k0 != 6 && !b0, x1 = k1 != 6 && !b1;
    double s = x0 && x1 ? 0.5 : 1.0;
    if (x0) extraordinary(m, l, d, k0, s, out);
    if (x1) extraordinary(m, l, e, k1, s, out);
}

static void butterfly_edge(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out)
{
    edge_point(sv->map, l, d, out);
}

/* Interpolating: even vertices keep their position (vertex mask NULL);
 * crease tags are carried but not used, as in OpenMesh. */
static const st_primal_rules butterfly_rules = { NULL, butterfly_edge, 0, ST_FACE_POINTS_NONE };

static void butterfly_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    st_primal_emit(sv, L, faces, n, sink, ctx, &butterfly_rules);
}

static int butterfly_check(const st_subdiv_view *sv, st_error *err) { return st_check_triangles(sv, "butterfly", err); }

static int butterfly_refine(const st_subdiv_view *sv, st_error *err) { return st_subdiv_refine_primal(sv, ST_SPLIT_TRI, err); }

const st_scheme st_scheme_butterfly = {
    .name = "butterfly",
    .id = ST_SCHEME_BUTTERFLY,
    .interpolating = 1,
    .support_rings = 2,
    .check = butterfly_check,
    .refine = butterfly_refine,
    .emit = butterfly_emit,
};
