/* GLSL compile and link helpers; see gl_program.h. */
#include "render/gl_program.h"

#include <stddef.h>

/* Size of the info log quoted in an error message. */
#define INFO_LOG 768

/* Returns obj when its status (pname: GL_COMPILE_STATUS or GL_LINK_STATUS)
 * is true; otherwise quotes its info log in err, deletes it and returns 0.
 * The shader and program entry points have the same types. */
static GLuint checked(GLuint obj, GLenum pname, PFNGLGETSHADERIVPROC get_iv, PFNGLGETSHADERINFOLOGPROC get_log,
                      PFNGLDELETESHADERPROC del, const char *what, const char *fails, st_error *err)
{
    GLint ok = 0;
    get_iv(obj, pname, &ok);
    if (ok) return obj;
    char log[INFO_LOG] = "";
    get_log(obj, sizeof log, NULL, log);
    del(obj);
    st_fail(err, ST_ERR_INVALID, "%s %s: %s", what, fails, log);
    return 0;
}

GLuint st_gl_shader(const st_gl *gl, GLenum type, const char *src, const char *what, st_error *err)
{
    GLuint s = gl->CreateShader(type);
    gl->ShaderSource(s, 1, &src, NULL);
    gl->CompileShader(s);
    return checked(s, GL_COMPILE_STATUS, gl->GetShaderiv, gl->GetShaderInfoLog, gl->DeleteShader, what,
                   "does not compile", err);
}

GLuint st_gl_link(const st_gl *gl, const GLuint *shaders, int n, const char *what, st_error *err)
{
    GLuint p = gl->CreateProgram();
    for (int i = 0; i < n; i++)
        if (shaders[i]) gl->AttachShader(p, shaders[i]);
    gl->LinkProgram(p);
    for (int i = 0; i < n; i++)
        if (shaders[i]) gl->DeleteShader(shaders[i]);
    return checked(p, GL_LINK_STATUS, gl->GetProgramiv, gl->GetProgramInfoLog, gl->DeleteProgram, what,
                   "does not link", err);
}

GLuint st_gl_program(const st_gl *gl, const char *vs_src, const char *fs_src, const char *shader_what,
                     const char *program_what, st_error *err)
{
    GLuint sh[2] = { 0, 0 };
    sh[0] = st_gl_shader(gl, GL_VERTEX_SHADER, vs_src, shader_what, err);
    if (!sh[0]) return 0;
    sh[1] = st_gl_shader(gl, GL_FRAGMENT_SHADER, fs_src, shader_what, err);
    if (!sh[1]) { gl->DeleteShader(sh[0]); return 0; }
    return st_gl_link(gl, sh, 2, program_what, err);
}

void st_gl_draw_surface_offset(const st_gl *gl, GLuint vao, GLuint ibo_tris, uint32_t ntris)
{
    gl->Enable(GL_POLYGON_OFFSET_FILL);
    gl->PolygonOffset(0.0f, 2.0f);
    gl->BindVertexArray(vao);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_tris);
    gl->DrawElements(GL_TRIANGLES, (GLsizei)(3 * ntris), GL_UNSIGNED_INT, (const void *)0);
    gl->Disable(GL_POLYGON_OFFSET_FILL);
}

const float st_gl_surface_front[3] = { 0.70f, 0.73f, 0.78f }, st_gl_surface_back[3] = { 0.78f, 0.48f, 0.36f };
const float st_gl_background[3] = { 0.93f, 0.94f, 0.96f };

void st_gl_scene_state(const st_gl *gl, int w, int h)
{
    gl->Viewport(0, 0, w, h);
    gl->Enable(GL_DEPTH_TEST);
    gl->DepthFunc(GL_LEQUAL);
    gl->DepthMask(GL_TRUE);
    gl->Disable(GL_CULL_FACE);
    gl->Disable(GL_BLEND);
}

void st_gl_clear(const st_gl *gl, float r, float g, float b, float a)
{
    gl->ClearColor(r, g, b, a);
    gl->ClearDepth(1);
    gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}
