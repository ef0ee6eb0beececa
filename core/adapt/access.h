/* Adaptive access (Kraemer 2008 §3.3.2, figs 3.36-3.37): show chosen
 * depths per region of a REGULARLY built hierarchy without changing it.
 *
 * One marker bit per level j (bit B_j): a dart carries B_j when its face of
 * level j is "opened", i.e. shown through its sub-faces of level j+1.  For
 * each face, level by level from 0, the criteria of st_adapt_params decide
 * (the same test as adaptive refinement, st_adapt_wanted_level); with the
 * one-level restriction, opening a face first opens the parents of the
 * faces that share a vertex with it.  The displayed faces are the faces of
 * level j that are present (parent opened) and not opened; a side whose
 * neighbour is opened shows the midpoint of level j+1, so the mesh has no
 * T-junction; a vertex takes the position of the finest displayed face
 * around it, and each corner the UV of that level in its face's chart
 * (core/fvar: the corner's dart stays in the child face at that corner).
 * Under the restriction, this is the mesh adaptive refinement (adapt.h)
 * builds for the same criteria, read off the regular levels.
 *
 * Several accesses can coexist: the marks are scratch bits, released at the
 * end.  Primal quadrisection schemes only (Catmull-Clark, Loop, Butterfly,
 * quad/triangle). */
#ifndef ST_ACCESS_H
#define ST_ACCESS_H

#include "core/adapt/adapt.h"

typedef struct st_access_stats {
    uint64_t faces_per_level[ST_MAX_LEVELS];  /* displayed faces by level */
    uint64_t forced;                          /* faces opened by the restriction only */
} st_access_stats;

/* The displayed polygon mesh of the regular hierarchy h (levels 0..top) for
 * the criteria of p (max_level is clamped to top).  stats may be NULL. */
int st_access_mesh(st_hier *h, const st_adapt_params *p, st_mesh *out, st_access_stats *stats, st_error *err);

#endif
