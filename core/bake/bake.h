/* st_bake: normal and displacement maps of a fine level baked onto the UV
 * layout of a coarse one (the low mesh a game engine renders).
 *
 * Correspondence.  For the primal schemes whose faces nest (Catmull-Clark,
 * Loop, Butterfly, quad/triangle) every face of level L lies inside one face
 * of level B: refinement splits a face at its corners (old darts keep their
 * vertex, Kraemer 2008 §3.2.1), edge points and, for the polygon split, a
 * face point.  Following those splits from each face of B gives every
 * level-L vertex inside it a parametric position, which B's UVs map to the
 * texture: edge points at the middle of their edge, face points at the
 * centroid of the corners (face-varying "linear" interpolation, OpenSubdiv's
 * default).  The level-L faces are then rasterised in B's UV layout; no ray
 * is cast, and the result is exact.  An adaptive hierarchy (HD levels,
 * core/adapt/adapt.h) is walked the same way: where a face was not
 * subdivided, the face as level L's map holds it (its corners and the
 * points finer neighbours put on its sides) is rasterised, so each texel
 * takes the finest existing face there.
 *
 * √3 and Doo-Sabin faces do not nest (√3 flips the old edges, Kobbelt 2000;
 * Doo-Sabin makes faces of vertices, edges and faces, §3.2.1's dual
 * encoding), so there the bake falls back on what every baker does without
 * a correspondence: from B's point at each texel a line along B's
 * interpolated normal, level L's nearest hit on it in either direction
 * within a reach (st_bake_opts.ray_reach; by default 5 % of the joint
 * bounding-box diagonal plus the largest gap between the two levels'
 * boxes), and
 * L's normal interpolated at the hit (core/bake/bake_ray.c: a flat bounding
 * volume hierarchy over L's triangles).  A texel whose line meets nothing
 * takes B's own point and normal (flat) and is counted in
 * st_bake_maps.ray_misses.  Progressive hierarchies (levels by edge
 * collapses, no UVs above level 0) are refused.
 *
 * Tangent frames (MikkTSpace's construction, Mikkelsen 2008): per triangle of
 * B's fan triangulation, the tangent and bitangent from the UV derivatives;
 * summed per corner over its smoothing group (corners that share a vertex, a
 * UV and the UV orientation), weighted by the corner angle; the tangent is
 * made orthogonal to the corner's normal (Gram-Schmidt) and the bitangent's
 * side is kept as a sign w.  A shader (and glTF, whose TANGENT attribute is
 * exactly these four numbers) rebuilds bitangent = w · cross(n, t).
 *
 * Texel (x, y) of a size × size map has its centre at UV ((x + ½)/size,
 * (y + ½)/size); maps are stored row y = 0 first, so written as images the
 * first row is v = 0 (glTF's convention: UV (0,0) is the image's first pixel).
 *
 * Tiles and wrap-around.  UVs need not lie in [0,1].  Every face has a home
 * tile, the integer square that holds the mean of its corner UVs
 * (st_bake_face_tile).  The map is sampled with repeat (GL_REPEAT, glTF's
 * default sampler wrap 10497), so a texel serves UV q + (i, j) for every
 * integer (i, j): a face is rasterised once per tile it touches, shifted
 * into the map, and the part of it that overshoots its home tile lands on
 * the opposite side of the map (wrap-around).  The home parts claim their
 * texels first and are the only ones checked for overlaps; an overshoot
 * takes only the texels no home part holds, so UV tools' small overshoots
 * (spot's u = −0.052) never read as overlapping islands.  UDIM layouts
 * (Mari's and Blender's numbering: tile (u, v) is 1001 + u + 10 v) are
 * baked one tile at a time (st_bake_opts.udim): only the faces at home in
 * that tile, overshoots wrapped inside it.
 */
#ifndef ST_BAKE_H
#define ST_BAKE_H

#include <stddef.h>
#include <stdint.h>

#include "core/multires/hier.h"
#include "core/uv/uv.h"

/* UVs of the faces of a level, in the order st_hier_level_mesh lists them,
 * each face's corners from its first dart along φ1 (the same order). */
typedef struct st_bake_uvs {
    uint32_t nfaces;
    const uint32_t *corner_off;   /* nfaces + 1 offsets */
    const double *uv;             /* 2 per corner */
} st_bake_uvs;

/* An owned layout (st_bake_auto_uvs, st_bake_level_uvs). */
typedef struct st_bake_layout {
    uint32_t nfaces;
    uint32_t *corner_off;
    double *uv;
} st_bake_layout;
void st_bake_layout_free(st_bake_layout *l);
static inline st_bake_uvs st_bake_layout_uvs(const st_bake_layout *l)
{
    st_bake_uvs u = { l->nfaces, l->corner_off, l->uv };
    return u;
}

/* A per-face atlas of level l: each face projected on its own plane (shape
 * kept, one scale for all faces so texel density is uniform), in its own
 * cell of a square grid with a margin of 1/8 cell around it.  Islands never
 * overlap.  Simple and predictable (one island per face, in face order), it
 * is the tests' fixture; it uses about 5 % of a map's texels, so strata
 * bake --auto-uv lays out st_bake_chart_uvs instead. */
int st_bake_auto_uvs(st_hier *h, unsigned l, st_bake_layout *out, st_error *err);

/* An atlas of charts of level l (core/uv/uv.h: charts of similar normal,
 * each a disk flattened by LSCM, packed into [0,1]² at one texel density)
 * for a size × size map with at least `padding` texels between charts:
 * what strata bake --auto-uv bakes on.  The layout is a function of the
 * level, size and padding alone (same inputs, same bits), so strata render
 * and convert --normal-map make it again from the map's size and bake's
 * default padding (ST_BAKE_AUTO_PADDING).  `stats` (optional) receives its
 * figures. */
#define ST_BAKE_AUTO_PADDING 8
int st_bake_chart_uvs(st_hier *h, unsigned l, uint32_t size, uint32_t padding, st_bake_layout *out, st_uv_stats *stats,
                      st_error *err);

/* A layout of level l as st_hier_uv gives UVs: 2 doubles per dart,
 * indexed by dart (m->darts.end of them, 0 for darts of no face of level
 * l), each face's corners in the layout's order; what the renderer's UV
 * checker (--mode uv) reads.  *out is the caller's to free. */
int st_bake_layout_dart_uvs(st_hier *h, unsigned l, const st_bake_uvs *uvs, double **out, st_error *err);

/* The mesh's own UVs of level l (core/fvar/fvar.h: st_hier_uv) as a layout
 * in the order above.  ST_ERR_INVALID with "level l has no UVs" when the
 * hierarchy carries none at that level. */
int st_bake_level_uvs(st_hier *h, unsigned l, st_bake_layout *out, st_error *err);

/* ST_OK when h can be baked: every subdivision scheme (by its nesting
 * faces or by rays, see above); progressive hierarchies are refused. */
int st_bake_check_scheme(const st_hier *h, st_error *err);
/* 1 when the faces of h nest level to level (the exact correspondence). */
int st_bake_faces_nest(const st_hier *h);

/* Face-corner tangents of level l for uvs: 4 doubles per corner (unit
 * tangent xyz, orthogonal to the corner normal, and the bitangent sign w =
 * ±1), in the order of uvs.  `normals` (optional, 3 per corner) receives the
 * corner normals they were made orthogonal to: the area-weighted smooth
 * vertex normals of the level. */
int st_bake_tangents(st_hier *h, unsigned l, const st_bake_uvs *uvs, double *tangents, double *normals, st_error *err);

/* The home tile of a face (corners uv, 2 per corner): the floor of the mean
 * of its corner UVs. */
void st_bake_face_tile(const double *uv, unsigned n, int32_t tile[2]);

/* The UDIM number of tile (u, v), 1001 + u + 10 v, or 0 when the tile has
 * none (u outside 0..9, v outside 0..99). */
unsigned st_bake_udim(const int32_t tile[2]);

/* How a layout sits on the tiles, for a map of `size` texels per side. */
typedef struct st_bake_tiles {
    uint32_t ntiles;              /* home tiles in use */
    int32_t (*tile)[2];           /* ntiles, by UDIM order (v, then u) */
    uint32_t *faces;              /* ntiles: faces at home in each */
    uint64_t corners_outside;     /* corners outside their face's home tile */
    uint32_t faces_crossing;      /* faces overshooting their home tile by more than a
                                     texel and more than a quarter of their UV extent */
    uint32_t first_crossing;      /* the first such face (from 0), or UINT32_MAX */
    uint32_t first_non_udim;      /* the first face whose home tile has no UDIM number, or UINT32_MAX */
} st_bake_tiles;
int st_bake_uv_tiles(const st_bake_uvs *uvs, uint32_t size, st_bake_tiles *out, st_error *err);
void st_bake_tiles_free(st_bake_tiles *t);

enum st_bake_space { ST_BAKE_TANGENT, ST_BAKE_OBJECT };

typedef struct st_bake_opts {
    unsigned base, level;         /* B and L, B <= L <= top */
    uint32_t size;                /* texels per side */
    int space;                    /* enum st_bake_space, of the normal map and of --vector */
    int normal;                   /* bake the normal map */
    int displacement;             /* 0: none, 1: scalar along B's normal, 3: vector */
    uint32_t padding;             /* texels of dilation around the islands */
    double ray_reach;             /* by rays: how far from B the line looks for L; 0: the default above */
    int rays;                     /* 1: by rays even where the faces nest (to compare the two) */
    int udim;                     /* 0: every face, wrapped into one map; 1: the faces at home in `tile` */
    int32_t tile[2];              /* with udim: the tile baked (u, v) */
    /* Optional, on the calling thread: the fraction of the faces (or of the
     * rows, by rays) done; non-zero cancels (st_bake fails with "cancelled"). */
    int (*progress)(void *ctx, double fraction);
    void *progress_ctx;
} st_bake_opts;

/* 1 when st_bake will cast rays: the faces do not nest, or o->rays. */
int st_bake_by_rays(const st_hier *h, const st_bake_opts *o);

typedef struct st_bake_maps {
    uint32_t size;
    float *normal;                /* 3 per texel, unit vector (background: 0,0,1), or NULL */
    float *disp;                  /* 1 or 3 per texel (background 0), or NULL */
    unsigned disp_channels;
    uint8_t *mask;                /* per texel: 0 background, 1 baked, 2 padded */
    uint64_t baked, padded;       /* texel counts */
    double disp_min, disp_max;    /* over every channel of baked texels */
    int by_rays;                  /* the correspondence: 0 nesting faces, 1 rays along B's normals */
    uint64_t ray_misses;          /* by rays: baked texels whose line met no face of L (flat) */
    double ray_reach;             /* by rays: the reach used */
    uint64_t corners_outside;     /* corners of the faces baked outside the map's tile ([0,1]² or opts.tile), wrapped */
    uint32_t faces;               /* faces of level B baked (all, or those at home in the tile) */
} st_bake_maps;
void st_bake_maps_free(st_bake_maps *m);

/* Bytes a bake needs beyond the hierarchy (the maps and the scratch, and
 * by rays the bounding volume hierarchy with its build scratch). */
size_t st_bake_estimate(const st_hier *h, const st_bake_uvs *uvs, const st_bake_opts *o);

/* The bake.  Refuses (ST_ERR_INVALID, a message naming faces and UVs) UVs
 * that do not match level B, that are not finite or lie beyond ±2^20, a face
 * spanning more than 4 tiles, islands whose home parts overlap, progressive
 * hierarchies; checks the memory budget with
 * st_bake_estimate first.  Nothing is returned on failure.  Same inputs,
 * same bits, on any number of threads (the rays are shared out by rows). */
int st_bake(st_hier *h, const st_bake_uvs *uvs, const st_bake_opts *o, st_bake_maps *out, st_error *err);

#endif
