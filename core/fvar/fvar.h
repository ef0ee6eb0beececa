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
 * changes UVs.  A hierarchy's UVs are read through core/multires/hier.h
 * (st_hier_uv).
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

/* A level's texture coordinates, read per dart: dart d's (u, v) is at
 * uv + 2 * idx[d], or at uv + 2 * d when idx is NULL (per-dart arrays, an
 * adaptive map's), for d < cap.  A hierarchy keeps one value per vertex
 * and seam and the index per dart (core/fvar/fvar_internal.h). */
typedef struct st_uv_map {
    const double *uv;
    const uint32_t *idx;
    uint32_t cap;
} st_uv_map;

static inline const double *st_uv_map_at(const st_uv_map *u, uint32_t d)
{
    return u->uv + 2 * (size_t)(u->idx ? u->idx[d] : d);
}

/* CLI names: "none", "corners-only", "corners-plus1", "corners-plus2",
 * "boundaries", "all"; -1 when unknown. */
int st_uv_interp_find(const char *name);
const char *st_uv_interp_name(int interp);

#endif
