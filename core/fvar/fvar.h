/* Face-varying texture coordinates (UVs) at every level of a hierarchy.
 *
 * A mesh read with UVs (st_mesh.face_uv) gives its hierarchy a UV per face
 * corner at level 0; every level added by a primal quadrisection scheme
 * (Catmull-Clark, Loop, Butterfly, quad/triangle) gets its corners' UVs by
 * the rules of docs/SUBDIVISION-RULES.md ("Face-varying UVs"): OpenSubdiv's
 * face-varying rules and FVarLinearInterpolation options for Catmull-Clark
 * and Loop, linear interpolation for Butterfly and quad/triangle.  UV seams
 * (two corners of a vertex naming different texture coordinates) behave as
 * face-varying boundaries.  √3 and Doo-Sabin apply their own stencils to
 * the UVs, with seams as boundaries (core/fvar/fvar_stencil.c);
 * progressive hierarchies keep the UVs of level 0 only.  Sculpting never
 * changes UVs.
 */
#ifndef ST_FVAR_H
#define ST_FVAR_H

#include <stddef.h>
#include <stdint.h>

/* OpenSubdiv's Sdc::Options::FVarLinearInterpolation, in Strata's order:
 * the zero value is OpenSubdiv's default (FVAR_LINEAR_CORNERS_PLUS1). */
enum st_uv_interp {
    ST_UV_CORNERS_PLUS1 = 0, /* corners-only, plus junctions of 3+ UV regions sharpened */
    ST_UV_NONE,              /* smooth everywhere the mesh is smooth */
    ST_UV_CORNERS_ONLY,      /* UV corners (a region's one face at a vertex) kept */
    ST_UV_CORNERS_PLUS2,     /* corners-plus1, plus darts and concave corners sharpened */
    ST_UV_BOUNDARIES,        /* linear along every UV boundary and seam */
    ST_UV_ALL,               /* linear everywhere (bilinear UVs) */
    ST_UV_INTERP_COUNT
};

/* CLI names: "none", "corners-only", "corners-plus1", "corners-plus2",
 * "boundaries", "all"; -1 when unknown. */
int st_uv_interp_find(const char *name);
const char *st_uv_interp_name(int interp);

struct st_hier;

/* The UVs of level l: 2 doubles per dart id, uv[2 d], uv[2 d + 1] being the
 * texture coordinate of the face corner of dart d (the real face on d's
 * left, at d's vertex), for every dart of a real face of level l.  Walking
 * a level's faces as st_hier_level_mesh does (darts in st_dart_first/next
 * order, each unvisited real face along φ1) and reading uv at each dart
 * gives the corners in the order of that mesh's face_idx.  NULL when the
 * hierarchy has no UVs at level l. */
const double *st_hier_uv(const struct st_hier *h, unsigned l);

/* For code that copies an st_hier field by field (the editor's undo
 * snapshots): dst->fvar becomes a deep copy of src's UVs (NULL when none),
 * *bytes (may be NULL) grows by what it allocated; -1 when out of memory
 * (dst->fvar NULL then).  st_hier_uv_free releases dst's. */
int st_hier_uv_copy(struct st_hier *dst, const struct st_hier *src, size_t *bytes);
void st_hier_uv_free(struct st_hier *h);

#endif
