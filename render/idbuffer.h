/* st_idbuffer: the ID buffer that the window picks from (ui/pick.c): an
 * offscreen framebuffer where the renderer's displayed surface is drawn
 * (depth only, with the renderer's own depth offset, so that it hides what
 * the renderer's picture hides) and then the cage's vertices as small
 * square points whose colour encodes their index in the renderer's cage
 * table + 1, depth-tested against the surface without writing depth.  The
 * GL side of picking lives here; which pixels to read and what to make of
 * them is the window's.
 *
 * Pixels are read in GL's convention: (x, y) from the bottom left.
 *
 *     st_idbuffer b;
 *     st_idbuffer_init(&b, &gl, &err);
 *     st_idbuffer_draw(&b, &r, &cam, w, h, &err);
 *     st_idbuffer_read_ids(&b, x, y, rw, rh, rgba);   // id = r | g << 8 | ...
 *     st_idbuffer_free(&b);
 */
#ifndef ST_IDBUFFER_H
#define ST_IDBUFFER_H

#include "render/camera.h"
#include "render/gl_loader.h"
#include "render/renderer.h"

typedef struct st_idbuffer {
    const st_gl *gl;
    GLuint prog;
    st_framebuffer target;     /* RGBA8 colour (the ids), 24-bit depth */
    GLint u_view, u_proj, u_size, u_bias, u_mode;
    int w, h;                  /* size of target, 0 x 0 when there is none */
} st_idbuffer;

/* Compiles the program; errors name it "pick: shader" / "pick: program". */
int st_idbuffer_init(st_idbuffer *b, const st_gl *gl, st_error *err);
void st_idbuffer_free(st_idbuffer *b);
/* Draws what r shows through cam into a w x h buffer (re-created when the
 * size changed or there is none); leaves the window's framebuffer bound. */
int st_idbuffer_draw(st_idbuffer *b, const st_renderer *r, const st_camera *cam, int w, int h, st_error *err);
/* RGBA8 pixels of the rectangle (x, y) .. (x + rw, y + rh), rows bottom
 * up, into px (rw * rh * 4 bytes).  The rectangle must lie in the buffer. */
void st_idbuffer_read_ids(const st_idbuffer *b, int x, int y, int rw, int rh, unsigned char *px);
/* Depth (0 near .. 1 far, 1 where nothing was drawn) of pixel (x, y). */
float st_idbuffer_read_depth(const st_idbuffer *b, int x, int y);

#endif
