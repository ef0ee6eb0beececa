/* Creating and deleting offscreen framebuffer objects (st_framebuffer,
 * render/gl_loader.h): one RGBA8 colour and one 24-bit depth
 * renderbuffer, multisampled when samples > 1.  The headless context draws
 * into one (MSAA, resolved into OSMesa's buffer) and picking into another
 * (the ID buffer, render/idbuffer.h, read back pixel by pixel). */
#ifndef ST_FRAMEBUFFER_H
#define ST_FRAMEBUFFER_H
#ifndef STRATA_RENDER_INTERNAL
#error "internal to render: ui/, app/ and bench/ use render's public headers (docs/ARCHITECTURE.md)"
#endif

#include "render/gl_loader.h"

/* Creates fb (width x height; samples <= 1: single-sampled, else at most
 * GL_MAX_SAMPLES) in the current context and leaves no framebuffer or
 * renderbuffer bound.  fb must be empty.  On failure fb stays empty and err
 * says "WHAT framebuffer incomplete (0x...)" (WHAT: e.g. "pick: ID"). */
int st_framebuffer_create(st_framebuffer *fb, const st_gl *gl, int width, int height, int samples,
                          const char *what, st_error *err);
/* Deletes what fb holds (nothing when empty) and empties it. */
void st_framebuffer_destroy(st_framebuffer *fb, const st_gl *gl);

#endif
