/* Picking through an ID buffer (no scan of the vertices per mouse move).
 *
 * st_pick_render() draws, through render's ID buffer (render/idbuffer.h)
 * the size of the window: the displayed surface (depth only) and then the
 * editing level's control vertices as small square points whose colour
 * encodes their index in the renderer's cage table + 1, depth-tested
 * against the surface (a vertex behind the surface is not pickable, as it
 * is not visible) without writing depth.  The buffer is redrawn only when
 * the view or the geometry changed (st_pick_invalidate); a mouse move then
 * reads back only the pixels around the cursor (st_pick_at), a dragged
 * rectangle the pixels of the rectangle (st_pick_rect), and brushes the
 * surface depth around the cursor (st_pick_surface).  Coordinates:
 * framebuffer pixels, origin top left. */
#ifndef ST_PICK_H
#define ST_PICK_H

#include <stdint.h>

#include "camera_ctl.h"
#include "render/idbuffer.h"
#include "render/renderer.h"

#define ST_PICK_RADIUS 10      /* pixels around the cursor searched for a vertex */

typedef struct st_pick {
    st_idbuffer ids;           /* the ID buffer, its size ids.w x ids.h */
    int valid;                 /* the buffer shows the current view and geometry */
    unsigned char *scratch;
    size_t scratch_cap;
    uint64_t renders;          /* times the ID buffer was drawn (statistics) */
} st_pick;

int st_pick_init(st_pick *p, const st_gl *gl, st_error *err);
void st_pick_free(st_pick *p);
static inline void st_pick_invalidate(st_pick *p) { p->valid = 0; }
/* Redraws the ID buffer when invalid (or the size changed). */
int st_pick_render(st_pick *p, const st_renderer *r, const st_camctl *c, int w, int h, st_error *err);
/* Cage vertex index (renderer cage table) nearest to (x, y) within
 * ST_PICK_RADIUS pixels, ST_NIL when none. */
uint32_t st_pick_at(st_pick *p, int x, int y);
/* Cage vertex indices visible inside the rectangle (any corner order),
 * each once, into *out (malloc'ed, caller frees).  Returns the count, or
 * -1 when out of memory. */
int64_t st_pick_rect(st_pick *p, int x0, int y0, int x1, int y1, uint32_t **out);
/* The surface point under (x, y) and its normal (towards the viewer);
 * 0 when the cursor is not over the surface. */
int st_pick_surface(st_pick *p, const st_camctl *c, int x, int y, double pos[3], double nrm[3]);

#endif
