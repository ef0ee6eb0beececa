/* Topological refinement: builds level top+1 from level top by primal
 * quadrisection (thesis §3.2.1, digest §4).  Positions of new vertices are
 * set to the linear (midpoint / centroid) rule; the schemes overwrite them. */
#ifndef ST_REFINE_H
#define ST_REFINE_H

#include "map.h"

enum st_split_mode {
    ST_SPLIT_POLY,      /* every face -> quads around a centre (Catmull-Clark) */
    ST_SPLIT_TRI,       /* triangles -> 4 triangles (Loop, Butterfly); other faces refused */
    ST_SPLIT_MIXED,     /* triangles -> 4 triangles, other faces -> quads (quad/triangle) */
};

int st_refine_uniform(st_map *m, enum st_split_mode mode, st_error *err);

/* Face-level pieces, usable by adaptive refinement (Algorithm 1).  d is a
 * dart of a real face of level l whose edges are all split at level l+1
 * (so its darts alternate corner, midpoint at level l+1) and which starts
 * at an old corner. */
void st_split_face_tri(st_map *m, uint32_t d, unsigned l);
void st_split_face_poly(st_map *m, uint32_t d, unsigned l, const double centre[3]);

#endif
