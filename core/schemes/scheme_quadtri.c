/* Quad/triangle subdivision (Stam, Loop 2003) on meshes mixing triangles
 * and quads, in the paper's two-step form (docs/SUBDIVISION-RULES.md §7):
 * a linear subdivision step followed by one smoothing (averaging) step.
 *
 * Topology (ST_SPLIT_MIXED, Kraemer 2008 §3.4.1): every edge is split at its
 * midpoint; a triangle becomes 4 triangles; any other face becomes quads
 * around its centroid.  After the first level every face is a triangle or
 * a quad.
 *
 * Smoothing: every vertex u of the linearly subdivided mesh (positions:
 * old vertices, edge midpoints, face centroids) moves to
 *     u' = u + ω (c̄ - u),   c̄ = (1/n) Σ_f c_f
 * over its n incident fine faces, with the per-face "centroids"
 *     quad:     (u + x + y + z) / 4,
 *     triangle: 1/4 u + 3/8 (x + y)   (Loop-weighted, u's own weight 1/4),
 * and ω from the numbers nq of quads and nt of triangles around u:
 *     nt = 0:  ω = 4/n                                   (Catmull-Clark)
 *     nq = 0:  ω = 8/3 (5/8 - (3/8 + cos(2π/n)/4)²)      (Loop's β = 3ω/(8n));
 *              ω = 1 exactly at n = 6
 *     mixed:   ω = 12 / (3 nq + 2 nt)                    (our choice, see below).
 * ω = 1 in every regular configuration (4 quads, 6 triangles, or 2 quads
 * and 3 triangles: 3 nq + 2 nt = 12, a full turn of quarter and sixth
 * turns), so regular vertices and the regular quad/triangle seam use plain
 * averaging.  The paper tunes the masks of mixed vertices (bounded
 * curvature at the regular seam, minimal curvature divergence elsewhere);
 * those tuned values were not available to us (SUBDIVISION-RULES.md §7
 * lists them as an open item), so mixed vertices use the weight above: the
 * same "regular iff 3 nq + 2 nt = 12" measure that gives 4/n on quads.
 * Replacing omega() for mixed vertices is all it takes to adopt the
 * paper's table.
 *
 * Expanded over the coarse vertices, this gives (l = coarse level):
 *   face point of a non-triangle: its centroid (ω cancels out);
 *   edge point of (a, b): each adjacent triangle (a, b, r) adds 3 fine
 *     triangles, contributing 9/8 (a + b) + 3/4 r to n·c̄; each adjacent
 *     quad (centroid c) adds 2 fine quads, contributing (a + b)/2 + c; then
 *     e' = (1 - ω)(a + b)/2 + ω c̄.  Triangle/triangle: Loop's 3/8, 1/8;
 *     quad/quad: Catmull-Clark's (a + b + c0 + c1)/4; triangle/quad:
 *     13/40 (a + b) + 3/20 r + 1/5 c;
 *   vertex point of v: each triangle (v, x, y) adds 5/8 v + 3/16 (x + y),
 *     each other face (v, x, ..., y) with centroid c adds
 *     1/2 v + 1/8 (x + y) + 1/4 c, then v' = (1 - ω) v + ω c̄.  Pure
 *     triangles: exactly Loop's mask; pure polygons: exactly
 *     Catmull-Clark's ((n-3) v + 2R + Q)/n.
 *
 * n-gons (n > 4, level 0 only): they are split as Catmull-Clark splits them
 * (quads around the centroid), and their fine quads contribute as quads;
 * at their edges the two fine quads' midpoints (x+p)/2 + (y+q)/2 are
 * replaced by twice the centroid (equal for a quad), which is exactly
 * Catmull-Clark's edge rule.  So a mesh without triangles subdivides
 * exactly as Catmull-Clark (OpenSubdiv), n-gons included, and a mesh
 * without quads exactly as Loop.
 *
 * Boundaries, creases and corners: OpenSubdiv's rules through crease.h
 * (boundary curves are cubic B-splines, the crease mask (a + 6v + b)/8 and
 * the edge midpoint are common to Loop and Catmull-Clark); the smoothing
 * above is the smooth mask. */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/crease_internal.h"
#include "core/schemes/synth_internal.h"
#include "core/schemes/primal_emit_internal.h"

#include <math.h>
#include <stdlib.h>

static double omega(unsigned nq, unsigned nt)
{
    unsigned n = nq + nt;
    if (n == 0) return 0;
    if (nt == 0) return 4.0 / n;
    if (nq == 0) {
        if (n == 6) return 1.0;
        double b = 0.375 + 0.25 * cos(2.0 * M_PI / n);
        return (8.0 / 3.0) * (0.625 - b * b);
    }
    return 12.0 / (3.0 * nq + 2.0 * nt);
}

/* Edge point of the interior edge of d (both faces real: boundary edges are
 * sharp and never reach the smooth mask). */
static void smooth_edge(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = sv->map;
    uint32_t side[2] = { d, st_beta0(m, d, l) };
    uint32_t a = st_vert(m, side[0], l), b = st_vert(m, side[1], l);
    unsigned nq = 0, nt = 0;
    for (int i = 0; i < 2; i++) {
        if (st_is_boundary(m, side[i])) continue;
        if (st_face_degree(m, side[i], l) == 3) nt += 3; else nq += 2;
    }
    unsigned n = nq + nt;
    if (!n) { st_stencil_buf_add(out, a, 0.5); st_stencil_buf_add(out, b, 0.5); return; }
    double w = omega(nq, nt), k = w / n;
    /* (1 - ω) · midpoint, then ω/n · Σ of the face contributions. */
    double ab = 0.5 * (1.0 - w);
    for (int i = 0; i < 2; i++) {
        uint32_t x = side[i];
        if (st_is_boundary(m, x)) continue;
        if (st_face_degree(m, x, l) == 3) {
            ab += 9.0 / 8.0 * k;
            st_stencil_buf_add(out, st_vert(m, st_phi1(m, st_phi1(m, x, l), l), l), 0.75 * k);
        } else {
            ab += 0.5 * k;
            st_add_face_centroid(m, l, x, k, out);
        }
    }
    st_stencil_buf_add(out, a, ab);
    st_stencil_buf_add(out, b, ab);
}

/* Vertex point of the interior vertex of d. */
static void smooth_vertex(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = sv->map;
    unsigned nq = 0, nt = 0;
    uint32_t x = d;
    do {
        if (!st_is_boundary(m, x)) { if (st_face_degree(m, x, l) == 3) nt++; else nq++; }
        x = st_beta1(m, x, l);
    } while (x != d);
    unsigned n = nq + nt;
    uint32_t v = st_vert(m, d, l);
    if (!n) { st_stencil_buf_add(out, v, 1.0); return; }
    double w = omega(nq, nt), k = w / n, vw = 1.0 - w;
    x = d;
    do {
        if (!st_is_boundary(m, x)) {
            uint32_t next = st_phi1(m, x, l);
            if (st_face_degree(m, x, l) == 3) {
                vw += 0.625 * k;
                st_stencil_buf_add(out, st_vert(m, next, l), 0.1875 * k);
                st_stencil_buf_add(out, st_vert(m, st_phi1(m, next, l), l), 0.1875 * k);
            } else {
                vw += 0.5 * k;
                st_stencil_buf_add(out, st_vert(m, next, l), 0.125 * k);
                st_stencil_buf_add(out, st_vert(m, st_phi_1(m, x, l), l), 0.125 * k);
                st_add_face_centroid(m, l, x, 0.25 * k, out);
            }
        }
        x = st_beta1(m, x, l);
    } while (x != d);
    st_stencil_buf_add(out, v, vw);
}

static const st_primal_rules quadtri_rules = { smooth_vertex, smooth_edge, 1, ST_FACE_POINTS_NON_TRIANGLES };

static void quadtri_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    st_primal_emit(sv, L, faces, n, sink, ctx, &quadtri_rules);
}

static int quadtri_refine(const st_subdiv_view *sv, st_error *err) { return st_subdiv_refine_primal(sv, ST_SPLIT_MIXED, err); }

const st_scheme st_scheme_quadtri = {
    .name = "quad-triangle",
    .id = ST_SCHEME_QUADTRI,
    .interpolating = 0,
    .support_rings = 1,
    .check = NULL,
    .refine = quadtri_refine,
    .emit = quadtri_emit,
};
