/* st_gl: the OpenGL 3.3 core entry points Strata uses, as one table of
 * function pointers.
 *
 * Why a table: libOSMesa and glvnd's
 * libGL both export the core gl* symbols, and GLFW opens libGL at run time,
 * so an executable that links OSMesa and calls gl* directly would send the
 * window's calls to OSMesa.  Every GL call in render/ goes through an st_gl
 * filled from the current context's own getProcAddress: glfwGetProcAddress
 * for the window, OSMesaGetProcAddress for headless rendering.  No glad or
 * epoxy (epoxy cannot see OSMesa contexts).
 *
 * Usage:
 *     st_gl gl;
 *     if (st_gl_load(&gl, glfwGetProcAddress, &err)) ...   // context current
 *     gl.ClearColor(0, 0, 0, 1);
 */
#ifndef ST_GL_LOADER_H
#define ST_GL_LOADER_H

#include <GL/glcorearb.h>

#include "core/base/st_error.h"

/* The generic function pointer type of glfwGetProcAddress (GLFWglproc). */
typedef void (*st_gl_proc)(void);
typedef st_gl_proc (*st_gl_get_proc)(const char *name);

/* X(type, member): member is the GL name without its "gl" prefix. */
#define ST_GL_FUNCTIONS(X) \
    X(PFNGLGETERRORPROC, GetError) \
    X(PFNGLGETSTRINGPROC, GetString) \
    X(PFNGLGETINTEGERVPROC, GetIntegerv) \
    X(PFNGLENABLEPROC, Enable) \
    X(PFNGLDISABLEPROC, Disable) \
    X(PFNGLVIEWPORTPROC, Viewport) \
    X(PFNGLCLEARPROC, Clear) \
    X(PFNGLCLEARCOLORPROC, ClearColor) \
    X(PFNGLCLEARDEPTHPROC, ClearDepth) \
    X(PFNGLDEPTHFUNCPROC, DepthFunc) \
    X(PFNGLDEPTHMASKPROC, DepthMask) \
    X(PFNGLCOLORMASKPROC, ColorMask) \
    X(PFNGLPOLYGONOFFSETPROC, PolygonOffset) \
    X(PFNGLBLENDFUNCPROC, BlendFunc) \
    X(PFNGLFINISHPROC, Finish) \
    X(PFNGLFLUSHPROC, Flush) \
    X(PFNGLPIXELSTOREIPROC, PixelStorei) \
    X(PFNGLREADPIXELSPROC, ReadPixels) \
    X(PFNGLREADBUFFERPROC, ReadBuffer) \
    X(PFNGLDRAWBUFFERPROC, DrawBuffer) \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray) \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) \
    X(PFNGLGENBUFFERSPROC, GenBuffers) \
    X(PFNGLBINDBUFFERPROC, BindBuffer) \
    X(PFNGLBUFFERDATAPROC, BufferData) \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData) \
    X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData) \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers) \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer) \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
    X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, DisableVertexAttribArray) \
    X(PFNGLDRAWELEMENTSPROC, DrawElements) \
    X(PFNGLDRAWARRAYSPROC, DrawArrays) \
    X(PFNGLCREATESHADERPROC, CreateShader) \
    X(PFNGLSHADERSOURCEPROC, ShaderSource) \
    X(PFNGLCOMPILESHADERPROC, CompileShader) \
    X(PFNGLGETSHADERIVPROC, GetShaderiv) \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog) \
    X(PFNGLDELETESHADERPROC, DeleteShader) \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram) \
    X(PFNGLATTACHSHADERPROC, AttachShader) \
    X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation) \
    X(PFNGLLINKPROGRAMPROC, LinkProgram) \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv) \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog) \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram) \
    X(PFNGLUSEPROGRAMPROC, UseProgram) \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation) \
    X(PFNGLUNIFORM1IPROC, Uniform1i) \
    X(PFNGLUNIFORM1FPROC, Uniform1f) \
    X(PFNGLUNIFORM2FPROC, Uniform2f) \
    X(PFNGLUNIFORM3FVPROC, Uniform3fv) \
    X(PFNGLUNIFORM4FVPROC, Uniform4fv) \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv) \
    X(PFNGLGENTEXTURESPROC, GenTextures) \
    X(PFNGLBINDTEXTUREPROC, BindTexture) \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture) \
    X(PFNGLTEXBUFFERPROC, TexBuffer) \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures) \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D) \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri) \
    X(PFNGLGENERATEMIPMAPPROC, GenerateMipmap) \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers) \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer) \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer) \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus) \
    X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer) \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers) \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers) \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer) \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage) \
    X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample) \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)

typedef struct st_gl {
#define ST_GL_MEMBER(type, name) type name;
    ST_GL_FUNCTIONS(ST_GL_MEMBER)
#undef ST_GL_MEMBER
    int major, minor;          /* context version, read after loading */
} st_gl;

/* An offscreen framebuffer object, as public structs hold one (st_headless,
 * st_idbuffer); only render creates and deletes them (its private
 * framebuffer.h), so the type lives here. */
typedef struct st_framebuffer {
    GLuint fbo, color_rb, depth_rb;    /* all 0 when there is none */
} st_framebuffer;

/* Fills every entry from get(name) for the context current on this thread.
 * Fails (ST_ERR_INVALID, naming the first missing function) if one is
 * missing or the context is older than 3.3; gl is zeroed then. */
int st_gl_load(st_gl *gl, st_gl_get_proc get, st_error *err);

/* Name of a GL error code ("GL_INVALID_OPERATION", ...). */
const char *st_gl_error_name(GLenum e);

#endif
