/* st_overlay: flat 2D triangles drawn over whatever the bound framebuffer
 * shows, blended, without depth: what the window's HUD (ui/hud.c: text,
 * rectangles, the brush circle) lays out, drawn here so that ui/ needs no
 * shader of its own.  Coordinates are framebuffer pixels, origin at the top
 * left.
 *
 *     st_overlay ov;
 *     if (st_overlay_init(&ov, &gl, &err)) ...        // context current
 *     st_overlay_draw(&ov, verts, nverts, w, h);     // 3 vertices per triangle
 *     st_overlay_free(&ov);
 */
#ifndef ST_OVERLAY_H
#define ST_OVERLAY_H

#include "render/gl_loader.h"

#define ST_OVERLAY_VFLOATS 6           /* floats per vertex: x y r g b a */

typedef struct st_overlay {
    const st_gl *gl;
    GLuint prog, vao, vbo;
    GLint u_viewport;
} st_overlay;

/* Compiles the program; errors name it "hud: shader" / "hud: program". */
int st_overlay_init(st_overlay *o, const st_gl *gl, st_error *err);
void st_overlay_free(st_overlay *o);
/* Draws the nv vertices v (ST_OVERLAY_VFLOATS each, 3 per triangle) into
 * the viewport w x h of the bound framebuffer, blended (source alpha), no
 * depth test; leaves depth testing on and blending off, as it found them
 * in the window. */
void st_overlay_draw(const st_overlay *o, const float *v, unsigned nv, int w, int h);

#endif
