/* Drawing a level with a normal map (strata render --normal-map): the
 * level's triangles (each polygon fanned from its first corner, as the
 * bake's tangents and glTF assume) with per-corner positions, smooth vertex
 * normals, tangents (xyz + bitangent sign, st_bake_tangents) and UVs, shaded
 * as the renderer's smooth mode (shaders/surface_nmap.*.glsl) with the
 * normal read from the map.  Headless through st_offscreen's context.
 *
 *     st_nmap_mesh mesh;
 *     st_nmap_mesh_build(&h, B, &uvs, &mesh, &err);
 *     st_nmap nm;
 *     st_nmap_init(&nm, &off.hl.gl, &err);
 *     st_nmap_set_mesh(&nm, &mesh);
 *     st_nmap_set_map(&nm, rgba, w, h);          (RGBA8, row 0 = v = 0)
 *     st_nmap_draw(&nm, &cam, width, height, ST_NMAP_TANGENT);
 */
#ifndef ST_NMAP_H
#define ST_NMAP_H

#include "render/camera.h"
#include "render/gl_loader.h"
#include "core/bake/bake.h"

#define ST_NMAP_FLOATS 12     /* per corner: pos 3, normal 3, tangent 4, uv 2 */

/* The triangles are grouped by their face's home UV tile (core/bake/bake.h:
 * st_bake_face_tile), tiles in UDIM order, and each face's UVs are moved
 * by its home tile into [0,1] (give or take its overshoot, read with
 * repeat), so that a UDIM set draws one texture per group and a single map
 * reads the same texels as before the move. */
typedef struct st_nmap_mesh {
    uint32_t ncorners;        /* 3 per triangle */
    float *attr;              /* ST_NMAP_FLOATS per corner */
    float bbox[6];
    uint32_t ntiles;          /* home tiles of the faces */
    int32_t (*tile)[2];       /* ntiles, UDIM order */
    uint32_t *tile_off;       /* ntiles + 1: the corners of tile i are tile_off[i] .. tile_off[i+1] */
} st_nmap_mesh;

int st_nmap_mesh_build(st_hier *h, unsigned level, const st_bake_uvs *uvs, st_nmap_mesh *out, st_error *err);
void st_nmap_mesh_free(st_nmap_mesh *m);

/* How the map is read: tangent-space, object-space, or not at all (the
 * same mesh with its vertex normals, for comparisons). */
enum st_nmap_mode { ST_NMAP_TANGENT, ST_NMAP_OBJECT, ST_NMAP_NONE };

typedef struct st_nmap {
    const st_gl *gl;
    GLuint prog, vao, vbo, tex;
    GLuint tiles_tex[64];     /* st_nmap_set_tile_map: one texture per tile of the mesh, 0: none */
    uint32_t ntiles;          /* the mesh's tiles */
    uint32_t *tile_off;       /* the mesh's tile ranges (ntiles + 1, copied) */
    GLint u_view, u_proj, u_map, u_use_map, u_object, u_front, u_back;
    uint32_t ncorners;
    int has_map;
} st_nmap;

int st_nmap_init(st_nmap *n, const st_gl *gl, st_error *err);
void st_nmap_set_mesh(st_nmap *n, const st_nmap_mesh *m);
/* RGBA8 pixels, row 0 first (v = 0), mip-mapped with trilinear filtering. */
void st_nmap_set_map(st_nmap *n, const unsigned char *rgba, int w, int h);
/* The texture of the mesh's tile i (a UDIM set; at most 64 tiles); tiles
 * without one are drawn with st_nmap_set_map's, or without a map. */
void st_nmap_set_tile_map(st_nmap *n, uint32_t i, const unsigned char *rgba, int w, int h);
/* The map in the PNG at path (st_nmap_set_map), or with a literal <UDIM>
 * in path one PNG per tile of the mesh (NAME.1001.png ...,
 * st_nmap_set_tile_map; at most 64).  A missing or unreadable file, or a
 * used tile without a UDIM number, is an error naming it. */
int st_nmap_load_map(st_nmap *n, const st_nmap_mesh *mesh, const char *path, st_error *err);
/* Clears to the renderer's background and draws. */
void st_nmap_draw(st_nmap *n, const st_camera *cam, int w, int h, int mode);
void st_nmap_free(st_nmap *n);

#endif
