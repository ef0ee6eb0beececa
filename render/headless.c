#include "render/headless.h"
#include "render/framebuffer.h"

#include <GL/osmesa.h>
#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

/* OSMesa is opened on first use instead of being linked: it pulls in LLVM,
 * which costs every start of strata about 50 MB of resident memory and a
 * tenth of a second of relocations, also for the commands that never draw
 * (strata info: 58 MB -> 8 MB resident on a cube).  Kept open once opened. */
static struct {
    OSMesaContext (*create)(const int *attribs, OSMesaContext share);
    GLboolean (*make_current)(OSMesaContext ctx, void *buffer, GLenum type, GLsizei w, GLsizei h);
    void (*destroy)(OSMesaContext ctx);
    OSMESAproc (*get_proc)(const char *name);
} osmesa;

#define OSMesaCreateContextAttribs osmesa.create
#define OSMesaMakeCurrent osmesa.make_current
#define OSMesaDestroyContext osmesa.destroy
#define OSMesaGetProcAddress osmesa.get_proc

static int osmesa_open(st_error *err)
{
    if (osmesa.create) return ST_OK;
    static const char *const names[] = { STRATA_OSMESA_PATH, "libOSMesa.so.8", "libOSMesa.so" };
    void *lib = NULL;
    for (size_t i = 0; i < sizeof names / sizeof names[0] && !lib; i++) lib = dlopen(names[i], RTLD_NOW | RTLD_LOCAL);
    if (!lib) return st_fail(err, ST_ERR_INVALID, "headless: cannot open OSMesa (libosmesa6): %s", dlerror());
    /* POSIX guarantees that a dlsym result converts to a function pointer. */
    void *f[4] = { dlsym(lib, "OSMesaCreateContextAttribs"), dlsym(lib, "OSMesaMakeCurrent"),
                   dlsym(lib, "OSMesaDestroyContext"), dlsym(lib, "OSMesaGetProcAddress") };
    for (int i = 0; i < 4; i++)
        if (!f[i]) return st_fail(err, ST_ERR_INVALID, "headless: OSMesa lacks a function: %s", dlerror());
    memcpy(&osmesa.make_current, &f[1], sizeof f[1]);
    memcpy(&osmesa.destroy, &f[2], sizeof f[2]);
    memcpy(&osmesa.get_proc, &f[3], sizeof f[3]);
    memcpy(&osmesa.create, &f[0], sizeof f[0]); /* last: it marks the table complete */
    return ST_OK;
}

static st_gl_proc osmesa_get(const char *name)
{
    /* OSMESAproc is void (*)(); st_gl_proc is the same function pointer
     * with a prototype: only a carrier, each entry is called with its type. */
    return (st_gl_proc)OSMesaGetProcAddress(name);
}

/* (Re)binds the OSMesa buffer of the current size and builds the MSAA
 * target.  hl->buffer must hold width*height*4 bytes. */
static int make_target(st_headless *hl, st_error *err)
{
    if (!OSMesaMakeCurrent((OSMesaContext)hl->ctx, hl->buffer, GL_UNSIGNED_BYTE, hl->width, hl->height))
        return st_fail(err, ST_ERR_INVALID, "headless: OSMesaMakeCurrent failed for %dx%d", hl->width, hl->height);
    st_gl *gl = &hl->gl;
    if (!gl->GetError && st_gl_load(gl, osmesa_get, err)) return err ? err->code : ST_ERR_INVALID;
    st_framebuffer_destroy(&hl->target, gl);
    if (hl->samples > 1) {
        int rc = st_framebuffer_create(&hl->target, gl, hl->width, hl->height, hl->samples,
                                       "headless: multisampled", err);
        if (rc) return rc;
    }
    while (gl->GetError() != GL_NO_ERROR) {}
    return ST_OK;
}

static int check_size(int w, int h, st_error *err)
{
    if (w < 1 || h < 1 || w > ST_HEADLESS_MAX_SIZE || h > ST_HEADLESS_MAX_SIZE)
        return st_fail(err, ST_ERR_RANGE, "headless: image size %dx%d outside 1..%d", w, h, ST_HEADLESS_MAX_SIZE);
    return ST_OK;
}

int st_headless_init(st_headless *hl, int width, int height, int samples, st_error *err)
{
    memset(hl, 0, sizeof *hl);
    int rc = check_size(width, height, err);
    if (!rc) rc = osmesa_open(err);
    if (rc) return rc;
    const int attribs[] = {
        OSMESA_FORMAT, OSMESA_RGBA,
        OSMESA_DEPTH_BITS, 24,
        OSMESA_STENCIL_BITS, 0,
        OSMESA_ACCUM_BITS, 0,
        OSMESA_PROFILE, OSMESA_CORE_PROFILE,
        OSMESA_CONTEXT_MAJOR_VERSION, 3,
        OSMESA_CONTEXT_MINOR_VERSION, 3,
        0
    };
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!ctx) return st_fail(err, ST_ERR_INVALID, "headless: OSMesaCreateContextAttribs failed (no OpenGL 3.3 core profile from OSMesa)");
    hl->ctx = ctx;
    hl->width = width;
    hl->height = height;
    hl->samples = samples;
    hl->buffer = malloc((size_t)width * (size_t)height * 4);
    if (!hl->buffer) { st_headless_free(hl); return st_fail(err, ST_ERR_MEMORY, "headless: out of memory for a %dx%d image", width, height); }
    rc = make_target(hl, err);
    if (rc) { st_headless_free(hl); return rc; }
    return ST_OK;
}

int st_headless_resize(st_headless *hl, int width, int height, st_error *err)
{
    int rc = check_size(width, height, err);
    if (rc) return rc;
    if (width == hl->width && height == hl->height) return ST_OK;
    unsigned char *b = malloc((size_t)width * (size_t)height * 4);
    if (!b) return st_fail(err, ST_ERR_MEMORY, "headless: out of memory for a %dx%d image", width, height);
    free(hl->buffer);
    hl->buffer = b;
    hl->width = width;
    hl->height = height;
    return make_target(hl, err);
}

void st_headless_begin(st_headless *hl)
{
    OSMesaMakeCurrent((OSMesaContext)hl->ctx, hl->buffer, GL_UNSIGNED_BYTE, hl->width, hl->height);
    hl->gl.BindFramebuffer(GL_FRAMEBUFFER, hl->target.fbo);
    hl->gl.Viewport(0, 0, hl->width, hl->height);
}

int st_headless_read(st_headless *hl, unsigned char *rgba, st_error *err)
{
    st_gl *gl = &hl->gl;
    if (hl->target.fbo) {
        gl->BindFramebuffer(GL_READ_FRAMEBUFFER, hl->target.fbo);
        gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        gl->BlitFramebuffer(0, 0, hl->width, hl->height, 0, 0, hl->width, hl->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    gl->Finish();
    GLenum e = gl->GetError();
    /* OSMesa's buffer is bottom-up: copy rows in reverse. */
    size_t row = (size_t)hl->width * 4;
    for (int y = 0; y < hl->height; y++)
        memcpy(rgba + (size_t)y * row, hl->buffer + (size_t)(hl->height - 1 - y) * row, row);
    if (e != GL_NO_ERROR) return st_fail(err, ST_ERR_INVALID, "headless: OpenGL error %s while rendering", st_gl_error_name(e));
    return ST_OK;
}

void st_headless_free(st_headless *hl)
{
    if (hl->ctx) {
        if (hl->gl.GetError) {
            OSMesaMakeCurrent((OSMesaContext)hl->ctx, hl->buffer, GL_UNSIGNED_BYTE, hl->width, hl->height);
            st_framebuffer_destroy(&hl->target, &hl->gl);
        }
        /* Unbind first: a context destroyed while current keeps its
         * framebuffer referenced (and leaks it). */
        OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
        OSMesaDestroyContext((OSMesaContext)hl->ctx);
    }
    free(hl->buffer);
    memset(hl, 0, sizeof *hl);
}
