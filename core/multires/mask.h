/* A sculpting mask over a multiresolution hierarchy: one value in [0, 1]
 * per vertex id (0: free, 1: protected).
 *
 * Correspondence between levels: a vertex id is the same vertex at every
 * level from the one it was inserted at upwards (core/map/map.h), so one
 * value per id serves every level.  A mask is painted at a level l (the
 * editing level): that sets the values of level l's vertices; the vertices
 * inserted above l then take the scheme's subdivision of the mask, the
 * stencil of each new vertex applied to the values of level L-1 (the same
 * weights as its position, Kraemer 2008 §3.1), clamped to [0, 1].  Seen
 * from a coarser level m < l, a vertex has the value of the coinciding
 * vertex.  So a mask painted at level 3 protects the same region at level
 * 5, and constant regions stay constant. */
#ifndef ST_MASK_H
#define ST_MASK_H

#include <stddef.h>
#include <stdint.h>

#include "core/multires/hier.h"

typedef struct st_mask {
    float *v;                  /* per vertex id below cap; NULL: zero everywhere */
    uint32_t cap;
} st_mask;

static inline float st_mask_get(const st_mask *mk, uint32_t vid)
{
    return mk->v && vid < mk->cap ? mk->v[vid] : 0.0f;
}
void st_mask_set(st_mask *mk, uint32_t vid, float x);   /* grows (zeros) */
void st_mask_free(st_mask *mk);
int st_mask_copy(st_mask *dst, const st_mask *src);     /* -1 when out of memory (dst empty) */
/* Whether any value is non-zero. */
int st_mask_any(const st_mask *mk);

/* Re-derives the vertices inserted above level l from level l's values:
 * around the vertices of the given darts of level l (the region a local
 * edit's re-synthesis reaches), or everywhere when darts is NULL. */
void st_mask_propagate(st_mask *mk, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n);
/* The same, local only, appending the ids it wrote to *out (grown; *cap its
 * capacity, *nout its length). */
void st_mask_propagate_list(st_mask *mk, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n, uint32_t **out,
                            uint32_t *nout, uint32_t *cap);

#endif
