/* Compiling and linking GLSL programs through the st_gl table, shared by the
 * renderer (render/renderer.c), the normal-map pass (render/nmap.c) and
 * the window's overlays (render/overlay.c, render/idbuffer.c); also the
 * surface draw that the ID buffer (render/idbuffer.c) must repeat exactly
 * (same depth offset) to see what the renderer shows.
 *
 * Errors: a failing call returns 0, deletes what it created and fills err
 * with "<what> does not compile: <info log>" or "<what> does not link:
 * <info log>", where `what` names the shader or program for the user
 * (e.g. "hud: shader", "render: shaders/line.geom.glsl").
 *
 * Usage:
 *     GLuint prog = st_gl_program(gl, vs_src, fs_src, "hud: shader", "hud: program", &err);
 *     if (!prog) return err.code;
 */
#ifndef ST_GL_PROGRAM_H
#define ST_GL_PROGRAM_H
#ifndef STRATA_RENDER_INTERNAL
#error "internal to render: ui/, app/ and bench/ use render's public headers (docs/ARCHITECTURE.md)"
#endif

#include <stdint.h>

#include "render/gl_loader.h"

/* One shader stage of the given type (GL_VERTEX_SHADER, ...) from src. */
GLuint st_gl_shader(const st_gl *gl, GLenum type, const char *src, const char *what, st_error *err);

/* Attaches the n shaders (zeros are skipped) to a new program and links it.
 * The shaders are deleted in every case. */
GLuint st_gl_link(const st_gl *gl, const GLuint *shaders, int n, const char *what, st_error *err);

/* A vertex + fragment program from sources: shader_what names both stages
 * in a compile error, program_what the program in a link error. */
GLuint st_gl_program(const st_gl *gl, const char *vs_src, const char *fs_src, const char *shader_what,
                     const char *program_what, st_error *err);

/* Draws ntris triangles (vao, element buffer ibo_tris) pushed back by a
 * constant polygon offset (units 2, no slope factor), so that edges and
 * points drawn on the surface win.  The program and uniforms are the
 * caller's. */
void st_gl_draw_surface_offset(const st_gl *gl, GLuint vao, GLuint ibo_tris, uint32_t ntris);

/* What the passes that draw a scene share (render/renderer.c, render/nmap.c):
 * the surface's front and back colours and the background; the state a
 * pass starts from (viewport w x h, depth test LEQUAL with depth writes, no
 * culling, no blending); clearing colour (r, g, b, a) and depth (to 1). */
extern const float st_gl_surface_front[3], st_gl_surface_back[3], st_gl_background[3];
void st_gl_scene_state(const st_gl *gl, int w, int h);
void st_gl_clear(const st_gl *gl, float r, float g, float b, float a);

#endif
