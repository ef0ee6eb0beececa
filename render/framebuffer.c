/* Offscreen framebuffer objects; see framebuffer.h. */
#include "render/framebuffer.h"

/* Storage for the bound renderbuffer, multisampled or not. */
static void storage(const st_gl *gl, int samples, GLenum format, int w, int h)
{
    if (samples > 1) gl->RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, w, h);
    else gl->RenderbufferStorage(GL_RENDERBUFFER, format, w, h);
}

int st_framebuffer_create(st_framebuffer *fb, const st_gl *gl, int width, int height, int samples,
                          const char *what, st_error *err)
{
    if (samples > 1) {
        GLint maxs = 0;
        gl->GetIntegerv(GL_MAX_SAMPLES, &maxs);
        if (samples > maxs) samples = maxs;
    }
    gl->GenFramebuffers(1, &fb->fbo);
    gl->GenRenderbuffers(1, &fb->color_rb);
    gl->GenRenderbuffers(1, &fb->depth_rb);
    gl->BindRenderbuffer(GL_RENDERBUFFER, fb->color_rb);
    storage(gl, samples, GL_RGBA8, width, height);
    gl->BindRenderbuffer(GL_RENDERBUFFER, fb->depth_rb);
    storage(gl, samples, GL_DEPTH_COMPONENT24, width, height);
    gl->BindRenderbuffer(GL_RENDERBUFFER, 0);
    gl->BindFramebuffer(GL_FRAMEBUFFER, fb->fbo);
    gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, fb->color_rb);
    gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, fb->depth_rb);
    GLenum st = gl->CheckFramebufferStatus(GL_FRAMEBUFFER);
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (st != GL_FRAMEBUFFER_COMPLETE) {
        st_framebuffer_destroy(fb, gl);
        return st_fail(err, ST_ERR_INVALID, "%s framebuffer incomplete (0x%x)", what, (unsigned)st);
    }
    return ST_OK;
}

void st_framebuffer_destroy(st_framebuffer *fb, const st_gl *gl)
{
    if (fb->fbo) gl->DeleteFramebuffers(1, &fb->fbo);
    if (fb->color_rb) gl->DeleteRenderbuffers(1, &fb->color_rb);
    if (fb->depth_rb) gl->DeleteRenderbuffers(1, &fb->depth_rb);
    fb->fbo = fb->color_rb = fb->depth_rb = 0;
}
