/* The ID buffer of picking; see idbuffer.h. */
#include "render/idbuffer.h"
#include "render/framebuffer.h"
#include "render/gl_program.h"

#include <string.h>

static const char *const pick_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "uniform float u_size;\n"
    "uniform float u_bias;\n"
    "flat out uint v_id;\n"
    "void main() {\n"
    "    vec4 p = u_proj * (u_view * vec4(a_pos, 1.0));\n"
    "    p.z -= u_bias * p.w;\n"
    "    gl_Position = p;\n"
    "    gl_PointSize = u_size;\n"
    "    v_id = uint(gl_VertexID) + 1u;\n"
    "}\n";
static const char *const pick_fs =
    "#version 330 core\n"
    "flat in uint v_id;\n"
    "uniform int u_mode;\n"
    "out vec4 o_id;\n"
    "void main() {\n"
    "    uint v = u_mode == 0 ? 0u : v_id;\n"
    "    o_id = vec4(float(v & 255u), float((v >> 8) & 255u), float((v >> 16) & 255u), float(v >> 24)) / 255.0;\n"
    "}\n";

#define PICK_POINT_SIZE 7.0f
#define PICK_POINT_BIAS 1e-3f

int st_idbuffer_init(st_idbuffer *b, const st_gl *gl, st_error *err)
{
    memset(b, 0, sizeof *b);
    b->gl = gl;
    b->prog = st_gl_program(gl, pick_vs, pick_fs, "pick: shader", "pick: program", err);
    if (!b->prog) { st_idbuffer_free(b); return ST_ERR_INVALID; }
    b->u_view = gl->GetUniformLocation(b->prog, "u_view");
    b->u_proj = gl->GetUniformLocation(b->prog, "u_proj");
    b->u_size = gl->GetUniformLocation(b->prog, "u_size");
    b->u_bias = gl->GetUniformLocation(b->prog, "u_bias");
    b->u_mode = gl->GetUniformLocation(b->prog, "u_mode");
    return ST_OK;
}

static void destroy_target(st_idbuffer *b)
{
    st_framebuffer_destroy(&b->target, b->gl);
    b->w = b->h = 0;
}

void st_idbuffer_free(st_idbuffer *b)
{
    if (b->gl) {
        destroy_target(b);
        if (b->prog) b->gl->DeleteProgram(b->prog);
    }
    memset(b, 0, sizeof *b);
}

static int make_target(st_idbuffer *b, int w, int h, st_error *err)
{
    destroy_target(b);
    int rc = st_framebuffer_create(&b->target, b->gl, w, h, 1, "pick: ID", err);
    if (rc) return rc;
    b->w = w;
    b->h = h;
    return ST_OK;
}

int st_idbuffer_draw(st_idbuffer *b, const st_renderer *r, const st_camera *cam, int w, int h, st_error *err)
{
    const st_gl *gl = b->gl;
    if (b->w != w || b->h != h || !b->target.fbo) {
        int rc = make_target(b, w, h, err);
        if (rc) return rc;
    }
    float view[16], proj[16];
    st_camera_view(cam, view);
    st_camera_proj(cam, (float)w / (float)h, proj);
    gl->BindFramebuffer(GL_FRAMEBUFFER, b->target.fbo);
    gl->Viewport(0, 0, w, h);
    gl->Disable(GL_BLEND);
    gl->Enable(GL_DEPTH_TEST);
    gl->DepthFunc(GL_LEQUAL);
    gl->DepthMask(GL_TRUE);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->ClearColor(0, 0, 0, 0);
    gl->ClearDepth(1);
    gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl->UseProgram(b->prog);
    gl->UniformMatrix4fv(b->u_view, 1, GL_FALSE, view);
    gl->UniformMatrix4fv(b->u_proj, 1, GL_FALSE, proj);
    if (r->has_surf && r->gsurf.ntris) {
        gl->Uniform1i(b->u_mode, 0);
        gl->Uniform1f(b->u_bias, 0);
        gl->Uniform1f(b->u_size, 1);
        st_gl_draw_surface_offset(gl, r->gsurf.vao, r->gsurf.ibo_tris, r->gsurf.ntris);
    }
    if (r->has_cage && r->gcage.nverts) {
        gl->Enable(GL_PROGRAM_POINT_SIZE);
        gl->DepthMask(GL_FALSE);
        gl->Uniform1i(b->u_mode, 1);
        gl->Uniform1f(b->u_bias, PICK_POINT_BIAS);
        gl->Uniform1f(b->u_size, PICK_POINT_SIZE);
        gl->BindVertexArray(r->gcage.vao);
        gl->DrawArrays(GL_POINTS, 0, (GLsizei)r->gcage.nverts);
        gl->DepthMask(GL_TRUE);
    }
    gl->BindVertexArray(0);
    gl->UseProgram(0);
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    return ST_OK;
}

void st_idbuffer_read_ids(const st_idbuffer *b, int x, int y, int rw, int rh, unsigned char *px)
{
    const st_gl *gl = b->gl;
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, b->target.fbo);
    gl->ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(x, y, rw, rh, GL_RGBA, GL_UNSIGNED_BYTE, px);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

float st_idbuffer_read_depth(const st_idbuffer *b, int x, int y)
{
    const st_gl *gl = b->gl;
    float z = 1;
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, b->target.fbo);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(x, y, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &z);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return z;
}
