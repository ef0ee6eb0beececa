/* HUD drawing; see hud.h. */
#include "hud.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wconversion"
#endif
#include <stb/stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

int st_hud_init(st_hud *u, const st_gl *gl, st_error *err)
{
    memset(u, 0, sizeof *u);
    return st_overlay_init(&u->ov, gl, err);
}

void st_hud_free(st_hud *u)
{
    st_overlay_free(&u->ov);
    free(u->v);
    memset(u, 0, sizeof *u);
}

void st_hud_begin(st_hud *u, int w, int h)
{
    u->nv = 0;
    u->w = w;
    u->h = h;
}

static void vert(st_hud *u, float x, float y, const float c[4])
{
    if (u->nv == u->capv) {
        unsigned cap = u->capv ? 2 * u->capv : 4096;
        float *nvp = realloc(u->v, (size_t)cap * ST_OVERLAY_VFLOATS * sizeof *nvp);
        if (!nvp) return;
        u->v = nvp;
        u->capv = cap;
    }
    float *p = u->v + ST_OVERLAY_VFLOATS * (size_t)u->nv++;
    p[0] = x; p[1] = y;
    p[2] = c[0]; p[3] = c[1]; p[4] = c[2]; p[5] = c[3];
}

static void quad(st_hud *u, const float p[4][2], const float c[4])
{
    vert(u, p[0][0], p[0][1], c); vert(u, p[1][0], p[1][1], c); vert(u, p[2][0], p[2][1], c);
    vert(u, p[0][0], p[0][1], c); vert(u, p[2][0], p[2][1], c); vert(u, p[3][0], p[3][1], c);
}

void st_hud_rect(st_hud *u, float x0, float y0, float x1, float y1, const float c[4])
{
    const float p[4][2] = { { x0, y0 }, { x1, y0 }, { x1, y1 }, { x0, y1 } };
    quad(u, p, c);
}

void st_hud_line(st_hud *u, float x0, float y0, float x1, float y1, float width, const float c[4])
{
    float dx = x1 - x0, dy = y1 - y0, len = sqrtf(dx * dx + dy * dy);
    if (len <= 0) return;
    float nx = -dy / len * 0.5f * width, ny = dx / len * 0.5f * width;
    const float p[4][2] = { { x0 + nx, y0 + ny }, { x1 + nx, y1 + ny }, { x1 - nx, y1 - ny }, { x0 - nx, y0 - ny } };
    quad(u, p, c);
}

void st_hud_circle(st_hud *u, float cx, float cy, float r, float width, const float c[4])
{
    const int n = 64;
    for (int i = 0; i < n; i++) {
        float a0 = 6.2831853f * i / n, a1 = 6.2831853f * (i + 1) / n;
        float ri = r - 0.5f * width, ro = r + 0.5f * width;
        const float p[4][2] = { { cx + ri * cosf(a0), cy + ri * sinf(a0) }, { cx + ro * cosf(a0), cy + ro * sinf(a0) },
                                { cx + ro * cosf(a1), cy + ro * sinf(a1) }, { cx + ri * cosf(a1), cy + ri * sinf(a1) } };
        quad(u, p, c);
    }
}

float st_hud_text_width(const char *text, float scale)
{
    return (float)stb_easy_font_width((char *)text) * scale;
}

float st_hud_text(st_hud *u, float x, float y, float scale, const float c[4], const char *text)
{
    /* stb_easy_font writes quads: 4 vertices of x, y, z, colour (16 bytes). */
    static char buf[16 * 4 * 3000];
    unsigned char col[4] = { 255, 255, 255, 255 };
    int nq = stb_easy_font_print(0, 0, (char *)text, col, buf, sizeof buf);
    for (int q = 0; q < nq; q++) {
        float p[4][2];
        for (int k = 0; k < 4; k++) {
            const float *f = (const float *)(buf + 16 * (4 * q + k));
            p[k][0] = x + f[0] * scale;
            p[k][1] = y + f[1] * scale;
        }
        quad(u, p, c);
    }
    return st_hud_text_width(text, scale);
}

void st_hud_flush(st_hud *u)
{
    st_overlay_draw(&u->ov, u->v, u->nv, u->w, u->h);
    u->nv = 0;
}
