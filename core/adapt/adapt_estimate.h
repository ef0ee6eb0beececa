/* What an adaptive update will cost, for the memory guard
 * (core/base/membudget.h): estimated from level 0 before anything is built.
 *
 * Every face is refined to the base level, so that part is the regular
 * hierarchy's (core/multires/estimate.h).  Above it, level k holds the
 * faces inside the box grown by the falloff bands of the levels above k
 * and by about two faces of level k (the one-level restriction's and the
 * stencils' rings): a face of level 0 whose bounding box overlaps that
 * region by a fraction f of its extent contributes f times its children
 * at level k (g^k of them, g the scheme's face growth per level: 4; 3 for
 * √3).  Bytes per dart, with their share of vertices and scratch, are
 * measured per scheme; tests/core/test_membudget.c holds the estimate to within
 * 25 % of the measured peak. */
#ifndef ST_ADAPT_ESTIMATE_H
#define ST_ADAPT_ESTIMATE_H

#include <stddef.h>

#include "core/adapt/adapt.h"

/* Bytes st_adapt_update(p) may add to the process, from level 0 of h. */
size_t st_adapt_estimate_bytes(st_hier *h, const st_adapt_params *p);

/* Bytes st_adapt_mesh(a) and writing its result may add, from the adaptive
 * map's counts after the update (a second check, before extraction: the
 * first, from level 0, cannot know how many faces the box really holds). */
size_t st_adapt_estimate_mesh_bytes(st_adapt *a);

#endif
