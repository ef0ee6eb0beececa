/* OpenSubdiv's sharpness rules shared by Catmull-Clark and Loop
 * (DeRose, Kass, Truong 1998; Sdc::Crease):
 *   - boundary edges are infinitely sharp;
 *   - a vertex is a corner when its sharpness is > 0, else smooth, dart,
 *     crease or corner for 0, 1, 2, > 2 incident sharp edges;
 *     with edge-and-corner boundaries a boundary vertex with one face is an
 *     infinitely sharp corner;
 *   - crease vertex: (e_a + 6 v + e_b) / 8 over its two sharp edges; corner:
 *     v; smooth and dart: the scheme's smooth mask;
 *   - edge point: smooth mask when the edge is smooth, midpoint when sharp;
 *   - when a rule changes between a parent and its child (a sharpness decays
 *     to 0), both masks are blended by the average parent sharpness of the
 *     features that decay (ComputeFractionalWeightAtVertex), clamped to 1.
 * Sharpness decreases by 1 per level (uniform method, OpenSubdiv's default),
 * or by Chaikin's rule (Sdc::Options::CREASE_CHAIKIN, OBJ `t creasemethod
 * chaikin`): the child edge at a vertex takes 3/4 of its parent's sharpness
 * plus 1/4 of the mean of the other semi-sharp edges there, less one; the
 * two halves of an edge may then differ, and an edge point takes the crease
 * mask only when both stay sharp, else the masks blend by the parent
 * sharpness (Sdc::Scheme::ComputeEdgeVertexMask). */
#ifndef ST_CREASE_H
#define ST_CREASE_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/schemes/scheme.h"
#include "core/map/refine_internal.h"

#define ST_SHARP_INFINITE 10.0f

/* Sharpness of the edge of d at level l, infinite on boundaries. */
float st_crease_edge_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l);
/* Sharpness of the vertex of d at level l, with the edge-and-corner rule. */
float st_crease_vertex_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l);
float st_crease_decay(float s);
/* Sharpness of the child at the vertex of d of the edge of d (level l), by
 * the view's crease method: what refinement stores at level l + 1. */
float st_crease_child_edge_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l);

typedef void (*st_vertex_mask_fn)(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out);
typedef void (*st_edge_mask_fn)(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out);

/* Stencil of the child of the vertex of d (level l) into out. */
void st_crease_vertex_point(const st_subdiv_view *sv, unsigned l, uint32_t d, st_vertex_mask_fn smooth,
                            st_stencil_buf *out, st_stencil_buf *tmp);
/* Stencil of the point splitting the edge of d (level l) into out. */
void st_crease_edge_point(const st_subdiv_view *sv, unsigned l, uint32_t d, st_edge_mask_fn smooth,
                          st_stencil_buf *out, st_stencil_buf *tmp);

/* Stores sharpness s at level l on the edge of d (both its darts) / on
 * vertex v, this level only; the attributes must exist (has_sharpness). */
void st_subdiv_store_edge_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l, float s);
void st_subdiv_store_vertex_sharpness(const st_subdiv_view *sv, uint32_t v, unsigned l, float s);
/* Adds level top+1 by a primal split of the map (refine_internal.h) and
 * gives its child edges and vertices their sharpness (refine_primal.c). */
int st_subdiv_refine_primal(const st_subdiv_view *sv, enum st_split_mode mode, st_error *err);

#endif
