/* HUD drawing; see hud.h. */
#include "hud.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/gl_program.h"

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

static const char *const hud_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec2 a_pos;\n"
    "layout(location = 1) in vec4 a_color;\n"
    "uniform vec2 u_viewport;\n"
    "out vec4 v_color;\n"
    "void main() {\n"
    "    gl_Position = vec4(a_pos.x / u_viewport.x * 2.0 - 1.0, 1.0 - a_pos.y / u_viewport.y * 2.0, 0.0, 1.0);\n"
    "    v_color = a_color;\n"
    "}\n";
static const char *const hud_fs =
    "#version 330 core\n"
    "in vec4 v_color;\n"
    "out vec4 o_color;\n"
    "void main() { o_color = v_color; }\n";

int st_hud_init(st_hud *u, const st_gl *gl, st_error *err)
{
    memset(u, 0, sizeof *u);
    u->gl = gl;
    u->prog = st_gl_program(gl, hud_vs, hud_fs, "hud: shader", "hud: program", err);
    if (!u->prog) { st_hud_free(u); return ST_ERR_INVALID; }
    u->u_viewport = gl->GetUniformLocation(u->prog, "u_viewport");
    gl->GenVertexArrays(1, &u->vao);
    gl->GenBuffers(1, &u->vbo);
    gl->BindVertexArray(u->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, u->vbo);
    gl->VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (const void *)0);
    gl->VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (const void *)(2 * sizeof(float)));
    gl->EnableVertexAttribArray(0);
    gl->EnableVertexAttribArray(1);
    gl->BindVertexArray(0);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    return ST_OK;
}

void st_hud_free(st_hud *u)
{
    if (u->gl) {
        if (u->vbo) u->gl->DeleteBuffers(1, &u->vbo);
        if (u->vao) u->gl->DeleteVertexArrays(1, &u->vao);
        if (u->prog) u->gl->DeleteProgram(u->prog);
    }
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
        float *nvp = realloc(u->v, (size_t)cap * 6 * sizeof *nvp);
        if (!nvp) return;
        u->v = nvp;
        u->capv = cap;
    }
    float *p = u->v + 6 * (size_t)u->nv++;
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
    const st_gl *gl = u->gl;
    if (!u->nv) return;
    gl->Viewport(0, 0, u->w, u->h);
    gl->Disable(GL_DEPTH_TEST);
    gl->Enable(GL_BLEND);
    gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl->UseProgram(u->prog);
    gl->Uniform2f(u->u_viewport, (float)u->w, (float)u->h);
    gl->BindVertexArray(u->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, u->vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)u->nv * 6 * sizeof(float)), u->v, GL_STREAM_DRAW);
    gl->DrawArrays(GL_TRIANGLES, 0, (GLsizei)u->nv);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    gl->BindVertexArray(0);
    gl->UseProgram(0);
    gl->Disable(GL_BLEND);
    gl->Enable(GL_DEPTH_TEST);
    u->nv = 0;
}
