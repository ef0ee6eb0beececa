/* √3 topology (Kobbelt 2000; Kraemer 2008 §3.4.2, fig. 3.46) and the
 * cell lookups the √3 rules need (scheme_sqrt3.c).
 *
 * Level L = l+1 is built from level l by
 *   1. every real triangle of level l gets a centre vertex: cut an edge
 *      between two corners (a 2-gon and a triangle), split that new edge by
 *      the centre, connect the centre to the third corner (st_cut_face,
 *      st_split_edge, st_cut_face at level L);
 *      on boundary steps (st_sqrt3_boundary_step(L)) a triangle with a
 *      boundary edge gets no centre: its boundary edge is split twice and
 *      the opposite corner is connected to both new points (a fan of 3);
 *   2. every interior edge of level l is flipped at level L (st_flip_edge).
 * Boundary edges are never flipped.  Each level has 3x the faces of the
 * level below.  Flips change β1 and vert of old darts at level L (the map
 * keeps per-level columns for them); β0 of old interior darts never changes.
 */
#ifndef ST_REFINE_SQRT3_H
#define ST_REFINE_SQRT3_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/map/map.h"

/* Builds level top+1.  Refuses (ST_ERR_TOPOLOGY) real faces that are not
 * triangles; the map is unchanged on failure. */
int st_refine_sqrt3(st_map *m, st_error *err);

/* True when the step that builds level L trisects boundary edges: every
 * second step, L = 2, 4, 6, ... (CGAL's and OpenMesh's parity for one call
 * that makes all the levels). */
static inline int st_sqrt3_boundary_step(unsigned L) { return L >= 2 && L % 2 == 0; }

/* Real dart of the face of f at level l whose edge is a boundary edge
 * (its twin is a hole dart), or ST_NIL. */
uint32_t st_sqrt3_face_boundary_dart(const st_map *m, uint32_t f, unsigned l);

/* Centre vertex (at level L) of the level L-1 face of f, or ST_NIL when the
 * face was split as a boundary fan (no centre).  Also for the faces of an
 * adaptive hierarchy (adapt_sqrt3.c), some of whose edges stay unflipped. */
uint32_t st_sqrt3_centre(const st_map *m, uint32_t f, unsigned L);

/* Boundary darts at the vertex of d, level l: *hole = the hole dart that
 * starts at the vertex, *real = the real dart that starts there and whose
 * twin is a hole dart.  Returns 0 (both ST_NIL) for an interior vertex.
 * Along the boundary the vertex's neighbours are vert(β0(*hole)) and
 * vert(β0(*real)). */
int st_sqrt3_vertex_boundary(const st_map *m, uint32_t d, unsigned l, uint32_t *hole, uint32_t *real);

/* Vertex (at level L) inserted on a boundary edge of level L-1 next to the
 * start of y, y being either dart of that edge (boundary steps only). */
static inline uint32_t st_sqrt3_edge_point(const st_map *m, uint32_t y, unsigned L)
{
    return st_vert(m, st_beta0(m, y, L), L);
}

#endif
