/* Internals of core/bake: level faces, vertex normals, UV checks, the nested
 * walk from a level-B face down to its level-L faces, the UV rasteriser. */
#ifndef ST_BAKE_INTERNAL_H
#define ST_BAKE_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "core/bake/bake_internal.h is internal to core"
#endif

#include "core/bake/bake.h"

/* The bake walks the surface's faces whichever the encoding (st_face_step,
 * core/map/map.h), so that layouts and tangents follow st_hier_level_mesh's
 * faces; their Newell vectors are st_face_newell's. */
unsigned st_bake_face_degree(const st_map *m, uint32_t d, unsigned l);

/* First dart of every real face of level l, in st_map_to_mesh's order. */
int st_bake_level_faces(st_map *m, unsigned l, uint32_t **darts, uint32_t *n, st_error *err);

/* Area-weighted smooth unit normals of level l (the sum of the incident
 * faces' Newell vectors, as the renderer and the mesh writers smooth),
 * indexed by vertex id (m->verts.end entries of 3). */
int st_bake_vertex_normals(const st_map *m, unsigned l, double **out, st_error *err);

/* ST_OK when uvs describe the faces (darts, n) of level l: same face count,
 * same corner counts, finite UVs within ±2^20 (ST_BAKE_UV_MAX; any tile). */
#define ST_BAKE_UV_MAX 1048576.0
int st_bake_check_uvs(const st_map *m, unsigned l, const uint32_t *darts, uint32_t n, const st_bake_uvs *uvs, st_error *err);

/* A level-L face inside a level-B face: vertex ids and UVs of its corners. */
typedef int (*st_bake_face_fn)(void *ctx, const uint32_t *verts, const double *uv, unsigned n);

/* Calls fn for every level-L face inside the level-B face of dart d, whose
 * corner UVs are uv (2 per corner, corners from d along φ1).  Fails with a
 * message when the faces do not nest.  In an adaptive map (HD levels) a
 * face not subdivided toward the next level is a leaf: fn gets it as the
 * map of level L holds it, its corners and the vertices finer neighbours
 * put on its sides (UVs at the middles of the halved sides), so every
 * point of the level-B face is baked from the finest face there. */
int st_bake_walk(st_map *m, uint32_t d, unsigned B, unsigned L, const double *uv, unsigned n,
                 st_bake_face_fn fn, void *ctx, st_error *err);

/* Calls fn(ctx, x, y, w) for the texel centres of a size × size map inside
 * the UV triangle t (either orientation); w are the barycentric weights of
 * t's corners.  Centres on an edge shared by two triangles go to exactly
 * one of them (top-left rule on edges in a canonical order). */
typedef void (*st_bake_texel_fn)(void *ctx, uint32_t x, uint32_t y, const double w[3]);
void st_bake_raster_tri(const double t[3][2], uint32_t size, st_bake_texel_fn fn, void *ctx);

/* Triangles of the UV polygon uv (n corners, 2 doubles each) that do not
 * overlap in UV: corner indices in the polygon's orientation, n-2 of them
 * written to tri (returned).  The fan from corner 0 when it is valid (every
 * convex polygon, and a concave quad whose reflex corner is 0 or 2), else
 * ear clipping (a quad: the diagonal through its reflex corner).  Each
 * triangle joins three corners of the face, so UV and surface still match. */
unsigned st_bake_split_polygon(const double *uv, unsigned n, uint32_t (*tri)[3]);

/* Barycentric weights of point p in UV triangle t; 0 if degenerate. */
int st_bake_barycentric(const double t[3][2], const double p[2], double w[3]);

#endif
