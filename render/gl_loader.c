#include "render/gl_loader.h"

#include <string.h>

int st_gl_load(st_gl *gl, st_gl_get_proc get, st_error *err)
{
    memset(gl, 0, sizeof *gl);
    if (!get) return st_fail(err, ST_ERR_INVALID, "GL loader: no getProcAddress function");
    /* Converting through st_gl_proc (void (*)(void)) is the generic
     * function-pointer carrier; each entry is called with its real type. */
#define ST_GL_LOAD(type, name) \
    gl->name = (type)get("gl" #name); \
    if (!gl->name) { memset(gl, 0, sizeof *gl); \
        return st_fail(err, ST_ERR_INVALID, "GL loader: the context has no gl" #name " (OpenGL 3.3 core needed)"); }
    ST_GL_FUNCTIONS(ST_GL_LOAD)
#undef ST_GL_LOAD
    GLint major = 0, minor = 0;
    gl->GetIntegerv(GL_MAJOR_VERSION, &major);
    gl->GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < 3 || (major == 3 && minor < 3)) {
        memset(gl, 0, sizeof *gl);
        return st_fail(err, ST_ERR_INVALID, "GL loader: context version %d.%d, OpenGL 3.3 core needed", major, minor);
    }
    gl->major = major;
    gl->minor = minor;
    return ST_OK;
}

const char *st_gl_error_name(GLenum e)
{
    switch (e) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "GL error";
    }
}
