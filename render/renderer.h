/* st_renderer: the one OpenGL 3.3 core renderer, used by the window (GLFW)
 * and by headless rendering (OSMesa).  It draws into whatever framebuffer is
 * bound, with the st_gl table it was given (gl_loader.h).
 *
 * What it draws (st_draw_opts):
 *   - the surface of the displayed level: smooth shading (vertex normals) or
 *     flat shading (one normal per polygon, not per triangle); faces are the
 *     map's real faces, so boundary faces are never drawn; non-triangles are
 *     split by the case tables (triangulate.h);
 *   - the wireframe of the displayed level's polygon edges;
 *   - the control mesh of the editing level as an overlay, its vertices as
 *     points, selected vertices and the hovered vertex highlighted;
 *   - the interest box, a wire box given by two corners;
 *   - optionally a UV checker on the surface through its face-varying UVs
 *     (st_renderer_set_uvs, st_draw_opts.checker).
 *
 * Data path: map -> st_rgeom (CPU) -> buffers.  st_renderer_set_level()
 * builds and uploads everything for a level; after an edit that moved
 * vertices, st_renderer_refresh() with the footprint core reported for it
 * (core/map/footprint.h) recomputes only those positions and the
 * normals around them and re-uploads only their ranges with
 * glBufferSubData.  Updates name their targets (enum st_render_target): the
 * surface and the cage may come from different maps (the interest box's
 * display and the model).
 *
 *     st_renderer r;
 *     st_renderer_init(&r, &gl, &err);
 *     st_renderer_set_level(&r, &h.map, 3, &err);
 *     st_renderer_set_cage(&r, &h.map, 0, &err);
 *     st_renderer_draw(&r, &cam, width, height, &opts);
 *     ...
 *     st_footprint fp = { 0 };
 *     st_hier_edit(&h, 2, darts, pos, n, &fp);          (core/multires/edit.h)
 *     st_renderer_refresh(&r, ST_TARGET_MESHES, &h.map, &fp);
 */
#ifndef ST_RENDERER_H
#define ST_RENDERER_H

#include "render/camera.h"
#include "render/geom.h"
#include "render/gl_loader.h"
#include "core/map/footprint.h"

/* What an update applies to: the displayed surface, the control-mesh
 * overlay (the cage, with its selection and hover), or both. */
enum st_render_target { ST_TARGET_SURFACE = 1, ST_TARGET_CAGE = 2, ST_TARGET_MESHES = 3 };

enum st_shading { ST_SHADE_NONE, ST_SHADE_SMOOTH, ST_SHADE_FLAT };

typedef struct st_draw_opts {
    int shading;              /* enum st_shading */
    int wire;                 /* polygon edges of the displayed level */
    int cage;                 /* control mesh of the editing level, with its vertices */
    int box;                  /* the interest box (st_renderer_set_box) */
    int clear;                /* clear colour and depth first */
    float line_width;         /* pixels, 0: 1 */
    float point_size;         /* pixels, 0: 6 */
    int checker;              /* UV checker instead of the plain colours (needs st_renderer_set_uvs) */
} st_draw_opts;

/* Display modes of `strata render --mode`, as draw options. */
enum st_render_mode { ST_MODE_SMOOTH, ST_MODE_FLAT, ST_MODE_WIRE, ST_MODE_CAGE, ST_MODE_UV, ST_MODE_COUNT };
int st_render_mode_parse(const char *name);             /* -1 if unknown */
const char *st_render_mode_name(int mode);
void st_render_mode_opts(int mode, st_draw_opts *o);

/* One drawable mesh on the GPU. */
typedef struct st_gpu_mesh {
    GLuint vao, vbo, ibo_tris, ibo_lines;
    GLuint tbo_face_normal, tex_face_normal;  /* RGBA32F per face */
    GLuint tbo_tri_face, tex_tri_face;        /* R32UI per triangle */
    uint32_t nverts, ntris, nlines, nfaces;
    size_t cap[5];                            /* bytes allocated: vbo, ibo_tris, ibo_lines, face normals, tri faces */
} st_gpu_mesh;

typedef struct st_upload_stats {
    uint64_t bytes;           /* bytes sent by the last update */
    uint32_t ranges;          /* glBufferSubData calls of the last update */
    uint32_t vertices;        /* vertices re-uploaded */
} st_upload_stats;

typedef struct st_surface_uniforms {
    GLint view, proj, flat, tri_face, face_normal, front, back, masked, checker, tri_uv;
} st_surface_uniforms;

typedef struct st_renderer {
    const st_gl *gl;
    GLuint prog_surface, prog_line, prog_point;
    GLuint prog_uv;           /* the surface program with surface_uv.geom: the UV checker */
    st_surface_uniforms us;   /* surface program uniforms */
    st_surface_uniforms uu;   /* the same, of prog_uv */
    struct {
        GLint view, proj, depth_bias, viewport, width, color;
    } ul;                     /* line program uniforms */
    struct {
        GLint view, proj, size, depth_bias, color;
    } up;                     /* point program uniforms */

    st_rgeom surf;            /* displayed level */
    st_gpu_mesh gsurf;
    int has_surf;
    st_rgeom cage;            /* editing level (control mesh overlay) */
    st_gpu_mesh gcage;
    int has_cage;

    GLuint ibo_sel;           /* selected cage vertices (indices into the cage's vertices) */
    uint32_t nsel;
    uint32_t hover;           /* cage vertex index of the hovered vertex, ST_NIL if none */
    GLuint vao_box, vbo_box;
    int has_box;

    float background[3];
    st_upload_stats last;     /* of the last set_level / refresh */
    uint32_t *scratch;        /* vertex ids a footprint moves on one mesh */
    uint32_t scratch_n, scratch_cap;
    /* Sculpting mask on the surface (st_renderer_set_mask): a shade per
     * surface vertex (1 - 0.6 mask), attribute 2 of the surface. */
    GLuint vbo_shade;
    float *shade;
    uint32_t nshade;
    int has_shade;
    /* UVs per triangle corner of the surface (st_renderer_set_uvs), a
     * texture buffer of 3 RG32F texels per triangle. */
    GLuint tbo_uv, tex_uv;
    int has_uv;
} st_renderer;

/* The sculpting mask drawn as darkening of the surface: mask[vid] in [0, 1]
 * per vertex id of the map the surface was built from (cap entries; NULL
 * or cap 0: no mask).  vids (n of them) are the ids whose value changed,
 * re-uploaded alone; NULL: every vertex.  A rebuild of the surface
 * (st_renderer_set_level) drops the mask: set it again. */
void st_renderer_set_mask(st_renderer *r, const float *mask, uint32_t cap, const uint32_t *vids, uint32_t n);

/* Compiles the embedded shaders.  gl stays owned by the caller and must
 * outlive the renderer; its context must be current for every call. */
int st_renderer_init(st_renderer *r, const st_gl *gl, st_error *err);
void st_renderer_free(st_renderer *r);

/* Builds and uploads level l of m as the displayed surface. */
int st_renderer_set_level(st_renderer *r, const st_map *m, unsigned l, st_error *err);
/* Uploads the texture coordinates of the displayed surface for the UV
 * checker: uv gives one per dart id of the surface's map level
 * (core/fvar/fvar.h: st_uv_map, st_hier_uv); NULL or uv->uv NULL drops
 * them.  Set them again after st_renderer_set_level or st_renderer_patch
 * (both drop them: the triangles change); position refreshes keep them. */
int st_renderer_set_uvs(st_renderer *r, const st_map *m, const st_uv_map *uv, st_error *err);

/* Builds and uploads level l of m as the control-mesh overlay; clears the
 * selection and the hover. */
int st_renderer_set_cage(st_renderer *r, const st_map *m, unsigned l, st_error *err);
/* Drops the targets' meshes (nothing is drawn for them until they are set
 * again); the cage's selection and hover go with it. */
void st_renderer_clear(st_renderer *r, unsigned targets);
void st_renderer_clear_cage(st_renderer *r);   /* st_renderer_clear(r, ST_TARGET_CAGE) */

/* Incremental update of the targets (enum st_render_target) whose mesh was
 * built from map m, after a local edit that wrote the values `change`
 * reports (core/multires/edit.h: st_hier_edit, st_hier_restore,
 * st_hier_resynth_around): re-reads exactly the drawn vertices whose
 * position at the mesh's level the footprint wrote
 * (st_rgeom_footprint_vids), recomputes the dependent normals and
 * re-uploads only the touched ranges.  Returns 0 or -1 (out of memory:
 * nothing uploaded; build the level again). */
int st_renderer_refresh(st_renderer *r, unsigned targets, const st_map *m, const st_footprint *change);
/* Every position of the targets' map changed (e.g. after analysis),
 * topology not: re-reads and re-uploads their vertex data. */
void st_renderer_refresh_all(st_renderer *r, unsigned targets, const st_map *m);
/* After a local change of the displayed map's topology recorded in log (an
 * interest-box update): re-tessellates only the touched faces
 * (st_rgeom_patch) and re-uploads only the changed ranges; GPU buffers are
 * allocated with room to grow, and re-created when that runs out.  Returns
 * 0, or non-zero when the caller must st_renderer_set_level instead (out
 * of memory, overflowed log, too many removed faces to keep, or a change
 * so large against what is shown that a build is cheaper). */
int st_renderer_patch(st_renderer *r, const st_map *m, const st_map_log *log);

/* Uploads the CPU-side meshes (surf, cage) again in full, e.g. after a test
 * changed them by hand. */
void st_renderer_reupload(st_renderer *r);

/* Selection and hover, as vertex ids of the cage level (ids not on the cage
 * are ignored; ST_NIL: no hover). */
int st_renderer_set_selection(st_renderer *r, const uint32_t *vids, uint32_t n);
void st_renderer_set_hover(st_renderer *r, uint32_t vid);
/* Interest box from two opposite corners (any order); show = 0 hides it. */
void st_renderer_set_box(st_renderer *r, const float a[3], const float b[3], int show);

/* Draws into the bound framebuffer, viewport width x height. */
void st_renderer_draw(st_renderer *r, const st_camera *cam, int width, int height, const st_draw_opts *o);

#endif
