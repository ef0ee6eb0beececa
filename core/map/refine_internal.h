/* Topological refinement: builds level top+1 from level top by primal
 * quadrisection (Kraemer 2008 §3.2.1).  Positions of new vertices are
 * set to the linear (midpoint / centroid) rule; the schemes overwrite them. */
#ifndef ST_REFINE_H
#define ST_REFINE_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/map/map.h"

enum st_split_mode {
    ST_SPLIT_POLY,      /* every face -> quads around a centre (Catmull-Clark) */
    ST_SPLIT_TRI,       /* triangles -> 4 triangles (Loop, Butterfly); other faces refused */
    ST_SPLIT_MIXED,     /* triangles -> 4 triangles, other faces -> quads (quad/triangle) */
};

/* Adds level top+1.  Its new darts and vertices are numbered face by face,
 * in an order that keeps neighbourhoods close in memory (refine.c), not in
 * the order the operators below would number them. */
int st_refine_uniform(st_map *m, enum st_split_mode mode, st_error *err);
/* The same step through the generic operators (st_split_edge, st_cut_face):
 * the reference the bulk writer of st_refine_uniform reproduces (the same
 * relations at every level and the same positions, up to the numbering of
 * the new darts and vertices), used by it for maps it does not handle (a
 * column above the top, a face with fewer than 3 sides or along itself). */
int st_refine_uniform_ops(st_map *m, enum st_split_mode mode, st_error *err);

/* Face-level pieces, usable by adaptive refinement (Algorithm 1).  d is a
 * dart of a real face of level l whose edges are all split at level l+1
 * (so its darts alternate corner, midpoint at level l+1) and which starts
 * at an old corner. */
void st_split_face_tri(st_map *m, uint32_t d, unsigned l);
void st_split_face_poly(st_map *m, uint32_t d, unsigned l, const double centre[3]);

#endif
