/* Headless OpenGL through Mesa's OSMesa (no display, no GPU needed).
 *
 * Debian 12's OSMesa (Mesa 22.3, llvmpipe) gives an OpenGL
 * 4.5 core context for OSMesaCreateContextAttribs with OSMESA_CORE_PROFILE
 * and a 3.3 request.  It renders into a caller-owned RGBA buffer whose first
 * row is the *bottom* of the image; st_headless_read() returns rows top-down.
 *
 * Drawing goes into a multisampled framebuffer object when samples > 1
 * (smoother edges; llvmpipe's MSAA is deterministic), resolved into the
 * OSMesa buffer by st_headless_read().  With samples <= 1 the OSMesa buffer
 * itself (with a 24-bit depth buffer) is the target.
 *
 *     st_headless hl;
 *     if (st_headless_init(&hl, 640, 480, 4, &err)) ...
 *     st_headless_begin(&hl);           // binds the target, sets the viewport
 *     ... draw with hl.gl ...
 *     st_headless_read(&hl, rgba);       // 640*480*4 bytes, top row first
 *     st_headless_free(&hl);
 */
#ifndef ST_HEADLESS_H
#define ST_HEADLESS_H

#include "render/gl_loader.h"

#define ST_HEADLESS_MAX_SIZE 8192

typedef struct st_headless {
    void *ctx;                 /* OSMesaContext */
    unsigned char *buffer;     /* width*height*4, bottom-up RGBA, OSMesa's colour buffer */
    int width, height;
    int samples;               /* requested MSAA samples (<= 1: none) */
    st_framebuffer target;     /* multisampled target, empty when samples <= 1 */
    st_gl gl;                  /* entry points of this context */
} st_headless;

/* Creates the context (current on this thread) and its target.  On failure
 * hl is left empty and err says why (e.g. OSMesa missing, size too big). */
int st_headless_init(st_headless *hl, int width, int height, int samples, st_error *err);
/* Changes the image size (the context is kept). */
int st_headless_resize(st_headless *hl, int width, int height, st_error *err);
/* Makes the context current and binds the draw target and viewport. */
void st_headless_begin(st_headless *hl);
/* Resolves, waits for rendering (glFinish) and copies the image into rgba
 * (width*height*4 bytes), top row first.  Returns the first GL error seen
 * (ST_ERR_INVALID with its name) or ST_OK. */
int st_headless_read(st_headless *hl, unsigned char *rgba, st_error *err);
void st_headless_free(st_headless *hl);

#endif
