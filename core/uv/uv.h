/* st_uv: an automatic texture atlas for a polygon mesh that carries no UVs.
 *
 * The pipeline (st_uv_atlas), one file per step:
 *
 *   1. charts (uv_charts.c): faces grouped into regions of similar normal by
 *      greedy region growing over edge adjacency, a normal cone per chart as
 *      in D-Charts (Julius, Kraevoy, Sheffer 2005, §3) and xatlas; growth
 *      stops at creases (dihedral angle above a threshold).  Every chart is
 *      made a topological disk: one boundary loop, no pinched vertex, Euler
 *      characteristic V − E + F = 1 (Lévy et al. 2002 §5 need the same for
 *      LSCM); a chart that is not is split in two across its principal axis
 *      until it is.
 *   2. flattening (uv_lscm.c): least squares conformal maps (Lévy, Petitjean,
 *      Ray, Maillot, "Least Squares Conformal Maps for Automatic Texture
 *      Atlas Generation", SIGGRAPH 2002, §3), two pinned vertices, solved as
 *      sparse least squares by conjugate gradients on the normal equations
 *      (CGLS, Björck 1996 §7.4).  A chart whose map flips a triangle or
 *      whose border crosses itself falls back to the projection on its mean
 *      plane; when that fails too, the chart is split and both halves
 *      flattened again.
 *   3. packing (uv_pack.c): each chart turned to its minimal-area bounding
 *      box (Freeman and Shapira 1975: one side lies along a hull edge), then
 *      the charts themselves rasterised conservatively into a grid of cells
 *      and put at the first free place in row order (xatlas's brute-force
 *      raster packing), each dilated by `padding` texels of a size×size map
 *      so that any two charts are at least that far apart (half of it at
 *      the square's border, so that the repeat wrap keeps it too), at the
 *      largest scale that fits the unit square, found by bisection.
 *   4. figures (uv_stats.c): texel coverage, overlap between charts,
 *      distortion (L2 stretch of Sander et al. 2001, angle and area errors).
 *
 * One scale for every chart: the UVs have the same texel density over the
 * whole surface (charts are scaled to their 3D area before packing).
 * GL-free; flat arrays of 32-bit indices; scratch arrays sized by the mesh,
 * none per vertex or per face. */
#ifndef ST_UV_H
#define ST_UV_H

#include <stddef.h>
#include <stdint.h>

#include "core/base/st_error.h"

/* The input: polygons (counts and offsets, core/io/mesh.h's layout),
 * consistently oriented (counter-clockwise seen from outside). */
typedef struct st_uv_mesh {
    uint32_t nverts;
    const double *pos;            /* 3 * nverts */
    uint32_t nfaces;
    const uint32_t *face_off;     /* nfaces + 1 offsets into face_idx */
    const uint32_t *face_idx;     /* face_off[nfaces] vertex indices */
} st_uv_mesh;

/* Zero means the default. */
typedef struct st_uv_opts {
    uint32_t size;                /* texels per side of the map the atlas is for; default 1024 */
    uint32_t padding;             /* texels between charts; default 0 (pass the bake's padding) */
    double cone_deg;              /* largest angle between a face's normal and its chart's; default 60 */
    double crease_deg;            /* dihedral angle at which growth stops; default 80 */
} st_uv_opts;

/* Figures of an atlas (st_uv_atlas fills them; st_uv_measure recomputes). */
typedef struct st_uv_stats {
    uint32_t ncharts;
    uint32_t fallback_charts;     /* charts flattened by projection instead of LSCM */
    uint32_t splits;              /* charts split (not a disk, or flipped both ways) */
    double uv_area;               /* total UV area of the charts, in the unit square */
    double l2_stretch;            /* Sander et al. 2001 L2 stretch, scale removed: 1 = isometric */
    double angle_err_deg;         /* mean |UV angle − 3D angle| over triangle corners */
    double area_p5, area_p95;     /* 5th and 95th percentiles (by area) of the triangles'
                                     UV/3D area ratio over the whole atlas' ratio; 1 = equiareal */
    uint32_t flipped;             /* triangles with UV area <= 0 */
} st_uv_stats;

/* An owned atlas. */
typedef struct st_uv_atlas {
    uint32_t nfaces, ncharts;
    uint32_t *face_chart;         /* nfaces: the chart of each face */
    double *uv;                   /* 2 per corner, parallel to face_idx, in [0,1]² */
    st_uv_stats stats;
} st_uv_atlas;

/* The atlas of m.  On failure nothing is returned (ST_ERR_MEMORY, or
 * ST_ERR_GEOMETRY for non-finite positions). */
int st_uv_make_atlas(const st_uv_mesh *m, const st_uv_opts *o, st_uv_atlas *out, st_error *err);
void st_uv_atlas_free(st_uv_atlas *a);

/* The triangles the atlas flattens face f into (corner indices from
 * face_off[f]): a fan from the first corner whose fan has every triangle
 * turning the face's way in 3D (Newell normal), else from corner 0.  Writes
 * n − 2 triangles into tris; returns their count. */
unsigned st_uv_face_triangles(const st_uv_mesh *m, uint32_t f, uint32_t (*tris)[3]);

/* Distortion and flips of the UVs uv (2 per corner) of m, by the
 * triangles above.  Fills every field but ncharts, fallback_charts, splits. */
int st_uv_measure(const st_uv_mesh *m, const double *uv, st_uv_stats *s, st_error *err);

/* Texel figures at size × size, texel centres ((x + ½)/size, (y + ½)/size)
 * inside a triangle (half-open on edges, as a rasteriser): texels covered
 * by some chart, texels covered by two different charts, and (folded,
 * optional) texels covered twice inside one chart (by two of its faces). */
int st_uv_texels(const st_uv_mesh *m, const double *uv, const uint32_t *face_chart, uint32_t size,
                 uint64_t *covered, uint64_t *overlap, uint64_t *folded, st_error *err);

#endif
