/* ID-buffer picking; see pick.h. */
#include "pick.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/gl_program.h"

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

int st_pick_init(st_pick *p, const st_gl *gl, st_error *err)
{
    memset(p, 0, sizeof *p);
    p->gl = gl;
    p->prog = st_gl_program(gl, pick_vs, pick_fs, "pick: shader", "pick: program", err);
    if (!p->prog) { st_pick_free(p); return ST_ERR_INVALID; }
    p->u_view = gl->GetUniformLocation(p->prog, "u_view");
    p->u_proj = gl->GetUniformLocation(p->prog, "u_proj");
    p->u_size = gl->GetUniformLocation(p->prog, "u_size");
    p->u_bias = gl->GetUniformLocation(p->prog, "u_bias");
    p->u_mode = gl->GetUniformLocation(p->prog, "u_mode");
    return ST_OK;
}

static void destroy_target(st_pick *p)
{
    st_framebuffer_destroy(&p->target, p->gl);
    p->w = p->h = 0;
}

void st_pick_free(st_pick *p)
{
    if (p->gl) {
        destroy_target(p);
        if (p->prog) p->gl->DeleteProgram(p->prog);
    }
    free(p->scratch);
    memset(p, 0, sizeof *p);
}

static int make_target(st_pick *p, int w, int h, st_error *err)
{
    destroy_target(p);
    int rc = st_framebuffer_create(&p->target, p->gl, w, h, 1, "pick: ID", err);
    if (rc) return rc;
    p->w = w;
    p->h = h;
    return ST_OK;
}

int st_pick_render(st_pick *p, const st_renderer *r, const st_camctl *c, int w, int h, st_error *err)
{
    if (w < 1 || h < 1) return ST_OK;
    if (p->valid && p->w == w && p->h == h) return ST_OK;
    const st_gl *gl = p->gl;
    if (p->w != w || p->h != h || !p->target.fbo) {
        int rc = make_target(p, w, h, err);
        if (rc) return rc;
    }
    float view[16], proj[16];
    st_camera_view(&c->cam, view);
    st_camera_proj(&c->cam, (float)w / (float)h, proj);
    gl->BindFramebuffer(GL_FRAMEBUFFER, p->target.fbo);
    gl->Viewport(0, 0, w, h);
    gl->Disable(GL_BLEND);
    gl->Enable(GL_DEPTH_TEST);
    gl->DepthFunc(GL_LEQUAL);
    gl->DepthMask(GL_TRUE);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->ClearColor(0, 0, 0, 0);
    gl->ClearDepth(1);
    gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl->UseProgram(p->prog);
    gl->UniformMatrix4fv(p->u_view, 1, GL_FALSE, view);
    gl->UniformMatrix4fv(p->u_proj, 1, GL_FALSE, proj);
    if (r->has_surf && r->gsurf.ntris) {
        gl->Uniform1i(p->u_mode, 0);
        gl->Uniform1f(p->u_bias, 0);
        gl->Uniform1f(p->u_size, 1);
        st_gl_draw_surface_offset(gl, r->gsurf.vao, r->gsurf.ibo_tris, r->gsurf.ntris);
    }
    if (r->has_cage && r->gcage.nverts) {
        gl->Enable(GL_PROGRAM_POINT_SIZE);
        gl->DepthMask(GL_FALSE);
        gl->Uniform1i(p->u_mode, 1);
        gl->Uniform1f(p->u_bias, PICK_POINT_BIAS);
        gl->Uniform1f(p->u_size, PICK_POINT_SIZE);
        gl->BindVertexArray(r->gcage.vao);
        gl->DrawArrays(GL_POINTS, 0, (GLsizei)r->gcage.nverts);
        gl->DepthMask(GL_TRUE);
    }
    gl->BindVertexArray(0);
    gl->UseProgram(0);
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    p->valid = 1;
    p->renders++;
    return ST_OK;
}

static unsigned char *scratch(st_pick *p, size_t bytes)
{
    if (bytes > p->scratch_cap) {
        unsigned char *s = realloc(p->scratch, bytes);
        if (!s) return NULL;
        p->scratch = s;
        p->scratch_cap = bytes;
    }
    return p->scratch;
}

/* Reads the ID pixels of the rectangle [x0, x1) x [y0, y1) (top-left
 * origin, clipped); returns the pixels bottom-up with their GL rectangle. */
static unsigned char *read_ids(st_pick *p, int *x0, int *y0, int *x1, int *y1)
{
    if (*x0 < 0) *x0 = 0;
    if (*y0 < 0) *y0 = 0;
    if (*x1 > p->w) *x1 = p->w;
    if (*y1 > p->h) *y1 = p->h;
    if (*x1 <= *x0 || *y1 <= *y0 || !p->target.fbo) return NULL;
    int rw = *x1 - *x0, rh = *y1 - *y0;
    unsigned char *px = scratch(p, (size_t)rw * rh * 4);
    if (!px) return NULL;
    const st_gl *gl = p->gl;
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, p->target.fbo);
    gl->ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(*x0, p->h - *y1, rw, rh, GL_RGBA, GL_UNSIGNED_BYTE, px);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return px;
}

static uint32_t decode(const unsigned char *q)
{
    return (uint32_t)q[0] | (uint32_t)q[1] << 8 | (uint32_t)q[2] << 16 | (uint32_t)q[3] << 24;
}

uint32_t st_pick_at(st_pick *p, int x, int y)
{
    int x0 = x - ST_PICK_RADIUS, y0 = y - ST_PICK_RADIUS, x1 = x + ST_PICK_RADIUS + 1, y1 = y + ST_PICK_RADIUS + 1;
    unsigned char *px = read_ids(p, &x0, &y0, &x1, &y1);
    if (!px) return ST_NIL;
    int rw = x1 - x0, rh = y1 - y0;
    uint32_t best = ST_NIL;
    long bestd = (long)ST_PICK_RADIUS * ST_PICK_RADIUS + 1;
    for (int j = 0; j < rh; j++) {
        int sy = y1 - 1 - j;             /* row j of the read is screen row sy */
        for (int i = 0; i < rw; i++) {
            uint32_t id = decode(px + 4 * ((size_t)j * rw + i));
            if (!id) continue;
            long dx = x0 + i - x, dy = sy - y, d = dx * dx + dy * dy;
            if (d < bestd) { bestd = d; best = id - 1; }
        }
    }
    return best;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

int64_t st_pick_rect(st_pick *p, int ax, int ay, int bx, int by, uint32_t **out)
{
    *out = NULL;
    int x0 = ax < bx ? ax : bx, x1 = (ax < bx ? bx : ax) + 1;
    int y0 = ay < by ? ay : by, y1 = (ay < by ? by : ay) + 1;
    unsigned char *px = read_ids(p, &x0, &y0, &x1, &y1);
    if (!px) return 0;
    size_t n = (size_t)(x1 - x0) * (size_t)(y1 - y0), k = 0;
    uint32_t *ids = malloc((n ? n : 1) * sizeof *ids);
    if (!ids) return -1;
    for (size_t i = 0; i < n; i++) {
        uint32_t id = decode(px + 4 * i);
        if (id && (!k || ids[k - 1] != id - 1)) ids[k++] = id - 1;
    }
    qsort(ids, k, sizeof *ids, cmp_u32);
    size_t u = 0;
    for (size_t i = 0; i < k; i++)
        if (!u || ids[u - 1] != ids[i]) ids[u++] = ids[i];
    *out = ids;
    return (int64_t)u;
}

static int read_depth(st_pick *p, int x, int y, float *z)
{
    if (x < 0 || y < 0 || x >= p->w || y >= p->h) return 0;
    const st_gl *gl = p->gl;
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, p->target.fbo);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(x, p->h - 1 - y, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, z);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return *z < 1.0f;
}

int st_pick_surface(st_pick *p, const st_camctl *c, int x, int y, double pos[3], double nrm[3])
{
    if (!p->target.fbo) return 0;
    float z = 1;
    if (!read_depth(p, x, y, &z)) return 0;
    st_camctl_unproject(c, p->w, p->h, x + 0.5, y + 0.5, z, pos);
    double r[3], u[3], b[3];
    st_camctl_axes(c, r, u, b);
    /* Normal from the depths of two neighbours (central differences where
     * both sides hit the surface). */
    const int k = 2;
    double q[4][3];
    int ok[4];
    const int off[4][2] = { { k, 0 }, { -k, 0 }, { 0, k }, { 0, -k } };
    for (int i = 0; i < 4; i++) {
        float zi = 1;
        ok[i] = read_depth(p, x + off[i][0], y + off[i][1], &zi);
        if (ok[i]) st_camctl_unproject(c, p->w, p->h, x + off[i][0] + 0.5, y + off[i][1] + 0.5, zi, q[i]);
    }
    double dx[3], dy[3];
    for (int i = 0; i < 3; i++) {
        dx[i] = ok[0] && ok[1] ? q[0][i] - q[1][i] : ok[0] ? q[0][i] - pos[i] : ok[1] ? pos[i] - q[1][i] : r[i];
        dy[i] = ok[2] && ok[3] ? q[2][i] - q[3][i] : ok[2] ? q[2][i] - pos[i] : ok[3] ? pos[i] - q[3][i] : -u[i];
    }
    double n[3] = { dy[1] * dx[2] - dy[2] * dx[1], dy[2] * dx[0] - dy[0] * dx[2], dy[0] * dx[1] - dy[1] * dx[0] };
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0)) { for (int i = 0; i < 3; i++) nrm[i] = b[i]; return 1; }
    double s = (n[0] * b[0] + n[1] * b[1] + n[2] * b[2]) < 0 ? -1 : 1;
    for (int i = 0; i < 3; i++) nrm[i] = s * n[i] / len;
    return 1;
}
