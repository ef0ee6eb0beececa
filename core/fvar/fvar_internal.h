/* The face-varying UV channel of a hierarchy, for core/multires/hier*.c,
 * sessions and tests (core/fvar/fvar.h is the public side). */
#ifndef ST_FVAR_INTERNAL_H
#define ST_FVAR_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/fvar/fvar.h"
#include "core/base/st_error.h"
#include "core/io/mesh.h"
#include "core/map/map.h"

/* One level: per dart id below cap, the corner's UV and a value label.
 * Labels say which corners of one vertex share a face-varying value
 * (OpenSubdiv's "siblings"); they compare only between corners of the
 * same vertex.  At level 0 they are the file's UV indices. */
typedef struct st_fvar_level {
    uint32_t cap;
    double *uv;       /* 2 * cap */
    uint32_t *val;    /* cap */
} st_fvar_level;

typedef struct st_fvar {
    int interp;                       /* enum st_uv_interp */
    unsigned levels;                  /* levels 0..levels-1 carry UVs */
    st_fvar_level lv[ST_MAX_LEVELS];
} st_fvar;

struct st_hier;

/* Level 0's UVs from the soup the hierarchy was built from (h->map level 0
 * made by st_map_from_mesh from mesh); nothing when mesh has none. */
int st_fvar_init(struct st_hier *h, const st_mesh *mesh, int interp, st_error *err);
void st_fvar_free(struct st_hier *h);
/* After level L = top was added by the scheme's refine(): its UVs from
 * level L-1 (primal quadrisection schemes; others leave level L without). */
int st_fvar_refine(struct st_hier *h, st_error *err);
/* Level top's UVs and labels for √3 and Doo-Sabin (fvar_stencil.c), from
 * level top-1's; -1 when out of memory. */
int st_fvar_refine_stencil(struct st_hier *h, const st_fvar_level *coarse, st_fvar_level *fine);
/* Whether the next level will get UVs (the estimate of its memory counts
 * ST_FVAR_BYTES_PER_DART per dart of that level then). */
int st_fvar_continues(const struct st_hier *h);
#define ST_FVAR_BYTES_PER_DART 20.0
/* Level bookkeeping mirroring st_hier_remove_top / st_hier_remove_bottom. */
void st_fvar_remove_top(struct st_hier *h);
void st_fvar_remove_bottom(struct st_hier *h);
/* Fills out->nuvs, uv, face_uv for the soup st_map_to_mesh made of level
 * l (same face walk): one texture coordinate per (vertex, value label). */
int st_fvar_level_mesh(struct st_hier *h, unsigned l, st_mesh *out, st_error *err);
/* A deep copy of src's channel into dst (dst's map has the same dart ids). */
int st_fvar_copy(struct st_hier *dst, const struct st_hier *src);

#endif
