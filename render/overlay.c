/* Flat 2D overlay triangles; see overlay.h. */
#include "render/overlay.h"
#include "render/gl_program.h"

#include <stddef.h>
#include <string.h>

static const char *const overlay_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec2 a_pos;\n"
    "layout(location = 1) in vec4 a_color;\n"
    "uniform vec2 u_viewport;\n"
    "out vec4 v_color;\n"
    "void main() {\n"
    "    gl_Position = vec4(a_pos.x / u_viewport.x * 2.0 - 1.0, 1.0 - a_pos.y / u_viewport.y * 2.0, 0.0, 1.0);\n"
    "    v_color = a_color;\n"
    "}\n";
static const char *const overlay_fs =
    "#version 330 core\n"
    "in vec4 v_color;\n"
    "out vec4 o_color;\n"
    "void main() { o_color = v_color; }\n";

int st_overlay_init(st_overlay *o, const st_gl *gl, st_error *err)
{
    memset(o, 0, sizeof *o);
    o->gl = gl;
    o->prog = st_gl_program(gl, overlay_vs, overlay_fs, "hud: shader", "hud: program", err);
    if (!o->prog) { st_overlay_free(o); return ST_ERR_INVALID; }
    o->u_viewport = gl->GetUniformLocation(o->prog, "u_viewport");
    gl->GenVertexArrays(1, &o->vao);
    gl->GenBuffers(1, &o->vbo);
    gl->BindVertexArray(o->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, o->vbo);
    const GLsizei stride = ST_OVERLAY_VFLOATS * sizeof(float);
    gl->VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, stride, (const void *)0);
    gl->VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride, (const void *)(2 * sizeof(float)));
    gl->EnableVertexAttribArray(0);
    gl->EnableVertexAttribArray(1);
    gl->BindVertexArray(0);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    return ST_OK;
}

void st_overlay_free(st_overlay *o)
{
    if (o->gl) {
        if (o->vbo) o->gl->DeleteBuffers(1, &o->vbo);
        if (o->vao) o->gl->DeleteVertexArrays(1, &o->vao);
        if (o->prog) o->gl->DeleteProgram(o->prog);
    }
    memset(o, 0, sizeof *o);
}

void st_overlay_draw(const st_overlay *o, const float *v, unsigned nv, int w, int h)
{
    const st_gl *gl = o->gl;
    if (!nv) return;
    gl->Viewport(0, 0, w, h);
    gl->Disable(GL_DEPTH_TEST);
    gl->Enable(GL_BLEND);
    gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl->UseProgram(o->prog);
    gl->Uniform2f(o->u_viewport, (float)w, (float)h);
    gl->BindVertexArray(o->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, o->vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)nv * ST_OVERLAY_VFLOATS * sizeof(float)), v, GL_STREAM_DRAW);
    gl->DrawArrays(GL_TRIANGLES, 0, (GLsizei)nv);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    gl->BindVertexArray(0);
    gl->UseProgram(0);
    gl->Disable(GL_BLEND);
    gl->Enable(GL_DEPTH_TEST);
}
