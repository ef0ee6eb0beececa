/* HUD: 2D overlay of the modeller window (text from stb_easy_font, filled
 * rectangles, lines: the brush circle and the selection rectangle), laid
 * out here as triangles and drawn by render's overlay (render/overlay.h).
 * Coordinates are framebuffer pixels, origin at the top left.  Calls
 * between begin and flush only queue triangles; flush draws them all at
 * once, blended, without depth. */
#ifndef ST_HUD_H
#define ST_HUD_H

#include "render/overlay.h"

typedef struct st_hud {
    st_overlay ov;
    float *v;                  /* x y r g b a per vertex (ST_OVERLAY_VFLOATS), 3 per triangle */
    unsigned nv, capv;
    int w, h;
} st_hud;

int st_hud_init(st_hud *u, const st_gl *gl, st_error *err);
void st_hud_free(st_hud *u);
void st_hud_begin(st_hud *u, int w, int h);
/* Text at (x, y) (top left of the first line), scale times the font's
 * native size (about 7 pixels per line); '\n' starts a new line.  Returns
 * the text's width in pixels. */
float st_hud_text(st_hud *u, float x, float y, float scale, const float rgba[4], const char *text);
float st_hud_text_width(const char *text, float scale);
void st_hud_rect(st_hud *u, float x0, float y0, float x1, float y1, const float rgba[4]);
void st_hud_line(st_hud *u, float x0, float y0, float x1, float y1, float width, const float rgba[4]);
void st_hud_circle(st_hud *u, float cx, float cy, float r, float width, const float rgba[4]);
void st_hud_flush(st_hud *u);

#endif
