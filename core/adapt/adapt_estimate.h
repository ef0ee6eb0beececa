/* What an adaptive update will cost, for the memory guard
 * (core/base/membudget.h): estimated from level 0 before anything is built.
 *
 * Every face is refined to the base level, so that part is the regular
 * hierarchy's (core/multires/estimate.h).  Inside the interest box faces go
 * to the maximum level, and in each falloff band around it to one level
 * less: a face of level 0 whose bounding box overlaps the box (grown by k
 * band widths) by a fraction f of its extent contributes about
 * f · g^(level - 0) faces at that level, g the scheme's face growth per
 * level (4; 3 for √3).  The restriction's transition rings are a boundary
 * term, small beside the area term, and left out.  Bytes per face come from
 * the same per-dart and per-vertex costs as the regular estimate. */
#ifndef ST_ADAPT_ESTIMATE_H
#define ST_ADAPT_ESTIMATE_H

#include <stddef.h>

#include "core/adapt/adapt.h"

/* Bytes st_adapt_update(p) may add to the process, from level 0 of h. */
size_t st_adapt_estimate_bytes(st_hier *h, const st_adapt_params *p);

#endif
