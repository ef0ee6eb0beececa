/* The OpenGL 3.3 core renderer; see renderer.h. */
#include "render/renderer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/gl_program.h"
#include "render/shaders.h"

/* ---- display modes ------------------------------------------------------------ */

static const char *const mode_names[ST_MODE_COUNT] = { "smooth", "flat", "wire", "cage", "uv" };

int st_render_mode_parse(const char *name)
{
    for (int i = 0; i < ST_MODE_COUNT; i++)
        if (!strcmp(name, mode_names[i])) return i;
    return -1;
}

const char *st_render_mode_name(int mode) { return mode >= 0 && mode < ST_MODE_COUNT ? mode_names[mode] : "?"; }

void st_render_mode_opts(int mode, st_draw_opts *o)
{
    memset(o, 0, sizeof *o);
    o->clear = 1;
    o->box = 1;
    o->shading = mode == ST_MODE_FLAT ? ST_SHADE_FLAT : ST_SHADE_SMOOTH;
    o->wire = mode == ST_MODE_WIRE;
    o->cage = mode == ST_MODE_CAGE;
    o->checker = mode == ST_MODE_UV;
}

/* ---- shaders ------------------------------------------------------------------ */

static GLuint compile(const st_gl *gl, GLenum type, const char *name, st_error *err)
{
    const char *src = st_shader_source(name);
    if (!src) { st_fail(err, ST_ERR_INVALID, "render: shader %s.glsl is not embedded", name); return 0; }
    char what[256];
    snprintf(what, sizeof what, "render: shaders/%s.glsl", name);
    return st_gl_shader(gl, type, src, what, err);
}

static GLuint program(const st_gl *gl, const char *vs, const char *gs, const char *fs, st_error *err)
{
    GLuint sh[3] = { 0, 0, 0 };
    sh[0] = compile(gl, GL_VERTEX_SHADER, vs, err);
    if (sh[0] && gs) sh[1] = compile(gl, GL_GEOMETRY_SHADER, gs, err);
    if (sh[0] && (!gs || sh[1])) sh[2] = compile(gl, GL_FRAGMENT_SHADER, fs, err);
    if (sh[0] && (!gs || sh[1]) && sh[2]) {
        char what[256];
        snprintf(what, sizeof what, "render: program %s + %s", vs, fs);
        return st_gl_link(gl, sh, 3, what, err);
    }
    for (int i = 0; i < 3; i++) if (sh[i]) gl->DeleteShader(sh[i]);
    return 0;
}

static void surface_uniforms(const st_gl *gl, GLuint p, st_surface_uniforms *u)
{
    u->view = gl->GetUniformLocation(p, "u_view");
    u->proj = gl->GetUniformLocation(p, "u_proj");
    u->flat = gl->GetUniformLocation(p, "u_flat");
    u->tri_face = gl->GetUniformLocation(p, "u_tri_face");
    u->face_normal = gl->GetUniformLocation(p, "u_face_normal");
    u->front = gl->GetUniformLocation(p, "u_front");
    u->back = gl->GetUniformLocation(p, "u_back");
    u->masked = gl->GetUniformLocation(p, "u_masked");
    u->checker = gl->GetUniformLocation(p, "u_checker");
    u->tri_uv = gl->GetUniformLocation(p, "u_tri_uv");
    gl->UseProgram(p);
    gl->Uniform1i(u->tri_face, 0);
    gl->Uniform1i(u->face_normal, 1);
    if (u->tri_uv >= 0) gl->Uniform1i(u->tri_uv, 2);
}

int st_renderer_init(st_renderer *r, const st_gl *gl, st_error *err)
{
    memset(r, 0, sizeof *r);
    r->gl = gl;
    r->hover = ST_NIL;
    memcpy(r->background, st_gl_background, sizeof r->background);
    st_rgeom_init(&r->surf);
    st_rgeom_init(&r->cage);
    r->prog_surface = program(gl, "surface.vert", NULL, "surface.frag", err);
    if (r->prog_surface) r->prog_line = program(gl, "line.vert", "line.geom", "line.frag", err);
    if (r->prog_line) r->prog_point = program(gl, "point.vert", NULL, "point.frag", err);
    if (r->prog_point) r->prog_uv = program(gl, "surface_uv.vert", "surface_uv.geom", "surface.frag", err);
    if (!r->prog_uv) { st_renderer_free(r); return err ? err->code : ST_ERR_INVALID; }
    surface_uniforms(gl, r->prog_surface, &r->us);
    surface_uniforms(gl, r->prog_uv, &r->uu);
    GLuint p = r->prog_line;
    r->ul.view = gl->GetUniformLocation(p, "u_view");
    r->ul.proj = gl->GetUniformLocation(p, "u_proj");
    r->ul.depth_bias = gl->GetUniformLocation(p, "u_depth_bias");
    r->ul.viewport = gl->GetUniformLocation(p, "u_viewport");
    r->ul.width = gl->GetUniformLocation(p, "u_width");
    r->ul.color = gl->GetUniformLocation(p, "u_color");
    p = r->prog_point;
    r->up.view = gl->GetUniformLocation(p, "u_view");
    r->up.proj = gl->GetUniformLocation(p, "u_proj");
    r->up.size = gl->GetUniformLocation(p, "u_size");
    r->up.depth_bias = gl->GetUniformLocation(p, "u_depth_bias");
    r->up.color = gl->GetUniformLocation(p, "u_color");
    gl->UseProgram(0);
    GLenum e = gl->GetError();
    if (e != GL_NO_ERROR) {
        st_renderer_free(r);
        return st_fail(err, ST_ERR_INVALID, "render: OpenGL error %s while setting up", st_gl_error_name(e));
    }
    return ST_OK;
}

/* ---- buffers ------------------------------------------------------------------ */

static void gpu_mesh_free(const st_gl *gl, st_gpu_mesh *g)
{
    if (g->vao) gl->DeleteVertexArrays(1, &g->vao);
    GLuint bufs[5] = { g->vbo, g->ibo_tris, g->ibo_lines, g->tbo_face_normal, g->tbo_tri_face };
    for (int i = 0; i < 5; i++) if (bufs[i]) gl->DeleteBuffers(1, &bufs[i]);
    if (g->tex_face_normal) gl->DeleteTextures(1, &g->tex_face_normal);
    if (g->tex_tri_face) gl->DeleteTextures(1, &g->tex_tri_face);
    memset(g, 0, sizeof *g);
}

/* Sizes of zero are rounded up to one element: some drivers dislike empty
 * texture buffers. */
/* Allocates the bound buffer with a quarter more room than `bytes` (so
 * that st_renderer_patch can append in place) and fills its start. */
static size_t buffer_data(const st_gl *gl, GLenum target, size_t bytes, const void *data, size_t min)
{
    size_t cap = bytes + bytes / 4 + min;
    gl->BufferData(target, (GLsizeiptr)cap, NULL, GL_DYNAMIC_DRAW);
    if (bytes) gl->BufferSubData(target, 0, (GLsizeiptr)bytes, data);
    return cap;
}

/* Refills the bound buffer of `cap` bytes when the data fits in it and the
 * buffer is not more than twice the room buffer_data would give: no new
 * storage (which the driver clears before the copy: llvmpipe's memset of a
 * fresh buffer costs as much as the copy), e.g. when the same level is
 * built again.  Draws read only the counts, never past them. */
static size_t buffer_refill(const st_gl *gl, GLenum target, size_t cap, size_t bytes, const void *data, size_t min)
{
    size_t want = bytes + bytes / 4 + min;
    if (cap < bytes + min || cap > 2 * want) return buffer_data(gl, target, bytes, data, min);
    if (bytes) gl->BufferSubData(target, 0, (GLsizeiptr)bytes, data);
    return cap;
}

static uint64_t gpu_mesh_upload(const st_gl *gl, st_gpu_mesh *g, const st_rgeom *geo)
{
    if (!g->vao) {
        gl->GenVertexArrays(1, &g->vao);
        gl->GenBuffers(1, &g->vbo);
        gl->GenBuffers(1, &g->ibo_tris);
        gl->GenBuffers(1, &g->ibo_lines);
        gl->GenBuffers(1, &g->tbo_face_normal);
        gl->GenBuffers(1, &g->tbo_tri_face);
        gl->GenTextures(1, &g->tex_face_normal);
        gl->GenTextures(1, &g->tex_tri_face);
    }
    size_t vb = (size_t)geo->nverts * ST_RGEOM_VSTRIDE * sizeof(float);
    size_t tb = (size_t)geo->ntris * 3 * sizeof(uint32_t);
    size_t lb = (size_t)geo->nlines * 2 * sizeof(uint32_t);
    size_t fb = (size_t)geo->nfaces * 4 * sizeof(float);
    size_t ob = (size_t)geo->ntris * sizeof(uint32_t);
    gl->BindVertexArray(g->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, g->vbo);
    g->cap[0] = buffer_refill(gl, GL_ARRAY_BUFFER, g->cap[0], vb, geo->vdata, 16);
    gl->VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, ST_RGEOM_VSTRIDE * sizeof(float), (const void *)0);
    gl->VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, ST_RGEOM_VSTRIDE * sizeof(float), (const void *)(3 * sizeof(float)));
    gl->EnableVertexAttribArray(0);
    gl->EnableVertexAttribArray(1);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo_lines);
    g->cap[2] = buffer_refill(gl, GL_ELEMENT_ARRAY_BUFFER, g->cap[2], lb, geo->lines, 16);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo_tris);
    g->cap[1] = buffer_refill(gl, GL_ELEMENT_ARRAY_BUFFER, g->cap[1], tb, geo->tris, 16);
    gl->BindVertexArray(0);
    gl->BindBuffer(GL_TEXTURE_BUFFER, g->tbo_face_normal);
    g->cap[3] = buffer_refill(gl, GL_TEXTURE_BUFFER, g->cap[3], fb, geo->fnormal, 16);
    gl->BindBuffer(GL_TEXTURE_BUFFER, g->tbo_tri_face);
    g->cap[4] = buffer_refill(gl, GL_TEXTURE_BUFFER, g->cap[4], ob, geo->tri_face, 16);
    gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
    gl->BindTexture(GL_TEXTURE_BUFFER, g->tex_face_normal);
    gl->TexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, g->tbo_face_normal);
    gl->BindTexture(GL_TEXTURE_BUFFER, g->tex_tri_face);
    gl->TexBuffer(GL_TEXTURE_BUFFER, GL_R32UI, g->tbo_tri_face);
    gl->BindTexture(GL_TEXTURE_BUFFER, 0);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    g->nverts = geo->nverts;
    g->ntris = geo->ntris;
    g->nlines = geo->nlines;
    g->nfaces = geo->nfaces;
    return vb + tb + lb + fb + ob;
}

int st_renderer_set_level(st_renderer *r, const st_map *m, unsigned l, st_error *err)
{
    int rc = st_rgeom_build(&r->surf, m, l, err);
    if (rc) { r->has_surf = 0; return rc; }
    memset(&r->last, 0, sizeof r->last);
    r->last.bytes = gpu_mesh_upload(r->gl, &r->gsurf, &r->surf);
    r->last.ranges = 5;
    r->last.vertices = r->surf.nverts;
    r->has_surf = 1;
    r->has_uv = 0;
    if (r->has_shade) {
        r->gl->BindVertexArray(r->gsurf.vao);
        r->gl->DisableVertexAttribArray(2);
        r->gl->BindVertexArray(0);
        r->has_shade = 0;
    }
    return ST_OK;
}

/* ---- UV checker ------------------------------------------------------------------- */

int st_renderer_set_uvs(st_renderer *r, const st_map *m, const st_uv_map *uv, st_error *err)
{
    const st_gl *gl = r->gl;
    r->has_uv = 0;
    if (!uv || !uv->uv || !r->has_surf) return ST_OK;
    const st_rgeom *g = &r->surf;
    size_t n = 6 * (size_t)(g->ntris ? g->ntris : 1);
    float *t = malloc(n * sizeof *t);
    if (!t) return st_fail(err, ST_ERR_MEMORY, "render: out of memory for the UVs of %u triangles", g->ntris);
    st_rgeom_corner_uvs(g, m, uv, t);
    if (!r->tbo_uv) {
        gl->GenBuffers(1, &r->tbo_uv);
        gl->GenTextures(1, &r->tex_uv);
    }
    gl->BindBuffer(GL_TEXTURE_BUFFER, r->tbo_uv);
    gl->BufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(n * sizeof *t), t, GL_STATIC_DRAW);
    gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
    gl->BindTexture(GL_TEXTURE_BUFFER, r->tex_uv);
    gl->TexBuffer(GL_TEXTURE_BUFFER, GL_RG32F, r->tbo_uv);
    gl->BindTexture(GL_TEXTURE_BUFFER, 0);
    free(t);
    r->has_uv = 1;
    return ST_OK;
}

/* ---- mask shading ---------------------------------------------------------------- */

static float shade_of(const float *mask, uint32_t cap, uint32_t vid)
{
    float m = mask && vid < cap ? mask[vid] : 0.0f;
    return 1.0f - 0.6f * m;
}

void st_renderer_set_mask(st_renderer *r, const float *mask, uint32_t cap, const uint32_t *vids, uint32_t n)
{
    const st_gl *gl = r->gl;
    if (!r->has_surf) return;
    const st_rgeom *g = &r->surf;
    if (!mask || !cap) {
        if (r->has_shade) {
            gl->BindVertexArray(r->gsurf.vao);
            gl->DisableVertexAttribArray(2);
            gl->BindVertexArray(0);
        }
        r->has_shade = 0;
        return;
    }
    if (!r->has_shade || r->nshade != g->nverts) vids = NULL; /* first time on this surface: all */
    if (!vids) {
        float *p = realloc(r->shade, (size_t)(g->nverts ? g->nverts : 1) * sizeof *p);
        if (!p) return;
        r->shade = p;
        r->nshade = g->nverts;
        for (uint32_t i = 0; i < g->nverts; i++) p[i] = shade_of(mask, cap, g->vid[i]);
        if (!r->vbo_shade) gl->GenBuffers(1, &r->vbo_shade);
        gl->BindVertexArray(r->gsurf.vao);
        gl->BindBuffer(GL_ARRAY_BUFFER, r->vbo_shade);
        gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)g->nverts * sizeof *p), p, GL_DYNAMIC_DRAW);
        gl->VertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, sizeof(float), (const void *)0);
        gl->EnableVertexAttribArray(2);
        gl->BindVertexArray(0);
        r->has_shade = 1;
        return;
    }
    /* The changed vertices only: one range from the lowest to the highest
     * slot (the vertex table is in id order, so a region's ids are close). */
    uint32_t lo = UINT32_MAX, hi = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = vids[i];
        if (v >= g->nvids || g->slot[v] == ST_NIL) continue;
        uint32_t s = g->slot[v];
        r->shade[s] = shade_of(mask, cap, v);
        if (s < lo) lo = s;
        if (s > hi) hi = s;
    }
    if (lo > hi) return;
    gl->BindBuffer(GL_ARRAY_BUFFER, r->vbo_shade);
    gl->BufferSubData(GL_ARRAY_BUFFER, (GLintptr)((size_t)lo * sizeof(float)), (GLsizeiptr)((size_t)(hi - lo + 1) * sizeof(float)),
                      r->shade + lo);
}

int st_renderer_set_cage(st_renderer *r, const st_map *m, unsigned l, st_error *err)
{
    int rc = st_rgeom_build(&r->cage, m, l, err);
    r->nsel = 0;
    r->hover = ST_NIL;
    if (rc) { r->has_cage = 0; return rc; }
    gpu_mesh_upload(r->gl, &r->gcage, &r->cage);
    r->has_cage = 1;
    return ST_OK;
}

void st_renderer_clear(st_renderer *r, unsigned targets)
{
    if (targets & ST_TARGET_SURFACE) r->has_surf = 0;
    if (targets & ST_TARGET_CAGE) {
        r->has_cage = 0;
        r->nsel = 0;
        r->hover = ST_NIL;
    }
}

void st_renderer_clear_cage(st_renderer *r) { st_renderer_clear(r, ST_TARGET_CAGE); }

/* Re-uploads the dirty ranges of one mesh. */
static void upload_ranges(st_renderer *r, st_gpu_mesh *g, const st_rgeom *geo,
                          const st_range_list *vr, const st_range_list *fr)
{
    const st_gl *gl = r->gl;
    const size_t vs = ST_RGEOM_VSTRIDE * sizeof(float);
    if (vr->n) {
        gl->BindBuffer(GL_ARRAY_BUFFER, g->vbo);
        for (uint32_t i = 0; i < vr->n; i++) {
            gl->BufferSubData(GL_ARRAY_BUFFER, (GLintptr)(vr->r[i].first * vs), (GLsizeiptr)(vr->r[i].count * vs),
                              geo->vdata + (size_t)vr->r[i].first * ST_RGEOM_VSTRIDE);
            r->last.bytes += vr->r[i].count * vs;
            r->last.vertices += vr->r[i].count;
        }
        gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    }
    if (fr->n) {
        gl->BindBuffer(GL_TEXTURE_BUFFER, g->tbo_face_normal);
        for (uint32_t i = 0; i < fr->n; i++) {
            gl->BufferSubData(GL_TEXTURE_BUFFER, (GLintptr)(fr->r[i].first * 4 * sizeof(float)),
                              (GLsizeiptr)(fr->r[i].count * 4 * sizeof(float)),
                              geo->fnormal + 4 * (size_t)fr->r[i].first);
            r->last.bytes += fr->r[i].count * 4 * sizeof(float);
        }
        gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
    }
    r->last.ranges += vr->n + fr->n;
}

static int refresh_mesh(st_renderer *r, st_rgeom *geo, st_gpu_mesh *g, const st_map *m,
                        const uint32_t *vids, uint32_t n)
{
    st_range_list vr = { 0 }, fr = { 0 };
    int rc = st_rgeom_refresh(geo, m, vids, n, &vr, &fr);
    if (!rc) upload_ranges(r, g, geo, &vr, &fr);
    st_range_list_free(&vr);
    st_range_list_free(&fr);
    return rc;
}

/* The meshes a target mask names that are built. */
static int target_mesh(st_renderer *r, unsigned targets, int k, st_rgeom **geo, st_gpu_mesh **g)
{
    if (!(targets & (k ? ST_TARGET_CAGE : ST_TARGET_SURFACE)) || !(k ? r->has_cage : r->has_surf)) return 0;
    *geo = k ? &r->cage : &r->surf;
    *g = k ? &r->gcage : &r->gsurf;
    return 1;
}

int st_renderer_refresh(st_renderer *r, unsigned targets, const st_map *m, const st_footprint *change)
{
    memset(&r->last, 0, sizeof r->last);
    int rc = 0;
    for (int k = 0; k < 2; k++) {
        st_rgeom *geo;
        st_gpu_mesh *g;
        if (!target_mesh(r, targets, k, &geo, &g)) continue;
        r->scratch_n = 0;
        if (st_rgeom_footprint_vids(geo, m, change, &r->scratch, &r->scratch_n, &r->scratch_cap)) { rc = -1; continue; }
        rc |= refresh_mesh(r, geo, g, m, r->scratch, r->scratch_n);
    }
    return rc ? -1 : 0;
}

void st_renderer_refresh_all(st_renderer *r, unsigned targets, const st_map *m)
{
    const st_gl *gl = r->gl;
    memset(&r->last, 0, sizeof r->last);
    for (int k = 0; k < 2; k++) {
        st_rgeom *geo;
        st_gpu_mesh *g;
        if (!target_mesh(r, targets, k, &geo, &g)) continue;
        st_rgeom_refresh_all(geo, m);
        size_t vb = (size_t)geo->nverts * ST_RGEOM_VSTRIDE * sizeof(float);
        size_t fb = (size_t)geo->nfaces * 4 * sizeof(float);
        gl->BindBuffer(GL_ARRAY_BUFFER, g->vbo);
        if (vb) gl->BufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)vb, geo->vdata);
        gl->BindBuffer(GL_ARRAY_BUFFER, 0);
        gl->BindBuffer(GL_TEXTURE_BUFFER, g->tbo_face_normal);
        if (fb) gl->BufferSubData(GL_TEXTURE_BUFFER, 0, (GLsizeiptr)fb, geo->fnormal);
        gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
        r->last.bytes += vb + fb;
        r->last.ranges += 2;
        r->last.vertices += geo->nverts;
    }
}

/* Uploads ranges of elements of `size` bytes from data into buffer buf
 * (through the copy-write target, which no VAO or texture state holds). */
static void upload_elems(st_renderer *r, GLuint buf, const st_range_list *l, const void *data, size_t size)
{
    const st_gl *gl = r->gl;
    if (!l->n) return;
    gl->BindBuffer(GL_COPY_WRITE_BUFFER, buf);
    for (uint32_t i = 0; i < l->n; i++) {
        size_t off = (size_t)l->r[i].first * size, len = (size_t)l->r[i].count * size;
        gl->BufferSubData(GL_COPY_WRITE_BUFFER, (GLintptr)off, (GLsizeiptr)len, (const unsigned char *)data + off);
        r->last.bytes += len;
    }
    gl->BindBuffer(GL_COPY_WRITE_BUFFER, 0);
    r->last.ranges += l->n;
}

int st_renderer_patch(st_renderer *r, const st_map *m, const st_map_log *log)
{
    memset(&r->last, 0, sizeof r->last);
    if (!r->has_surf) return -1;
    st_rgeom *geo = &r->surf;
    st_gpu_mesh *g = &r->gsurf;
    /* A change that touched a tenth of the darts shown costs more to patch
     * than to build (bench_render: a box move over a display at base level
     * 0 touches 9k distinct darts of 60k, and patching took 1.3 times a
     * build there; at base level 3, 8k of 800k, it takes 0.05). */
    r->has_uv = 0; /* UVs are per triangle: set them again */
    int64_t touched = st_rgeom_log_darts(geo, m, log);
    if (touched < 0 || (uint64_t)touched > 4 * (uint64_t)(geo->nfaces - geo->ndead) / 10) return 1;
    st_rgeom_dirty dirty = { 0 };
    int rc = st_rgeom_patch(geo, m, log, &dirty);
    if (!rc) {
        size_t need[5] = { (size_t)geo->nverts * ST_RGEOM_VSTRIDE * sizeof(float), (size_t)geo->ntris * 3 * sizeof(uint32_t),
                           (size_t)geo->nlines * 2 * sizeof(uint32_t), (size_t)geo->nfaces * 4 * sizeof(float),
                           (size_t)geo->ntris * sizeof(uint32_t) };
        int fits = 1;
        for (int i = 0; i < 5; i++) fits &= need[i] <= g->cap[i];
        if (!fits) {
            r->last.bytes = gpu_mesh_upload(r->gl, g, geo);
            r->last.ranges = 5;
            r->last.vertices = geo->nverts;
        } else {
            st_range_list none = { 0 };
            upload_ranges(r, g, geo, &dirty.verts, &none);
            upload_elems(r, g->tbo_face_normal, &dirty.faces, geo->fnormal, 4 * sizeof(float));
            upload_elems(r, g->ibo_tris, &dirty.tris, geo->tris, 3 * sizeof(uint32_t));
            upload_elems(r, g->tbo_tri_face, &dirty.tris, geo->tri_face, sizeof(uint32_t));
            upload_elems(r, g->ibo_lines, &dirty.lines, geo->lines, 2 * sizeof(uint32_t));
            g->nverts = geo->nverts;
            g->ntris = geo->ntris;
            g->nlines = geo->nlines;
            g->nfaces = geo->nfaces;
        }
    }
    st_rgeom_dirty_free(&dirty);
    return rc;
}

void st_renderer_reupload(st_renderer *r)
{
    if (r->has_surf) gpu_mesh_upload(r->gl, &r->gsurf, &r->surf);
    if (r->has_cage) gpu_mesh_upload(r->gl, &r->gcage, &r->cage);
}

int st_renderer_set_selection(st_renderer *r, const uint32_t *vids, uint32_t n)
{
    r->nsel = 0;
    if (!r->has_cage) return 0;
    uint32_t *idx = malloc((size_t)(n ? n : 1) * sizeof *idx);
    if (!idx) return -1;
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++)
        if (vids[i] < r->cage.nvids && r->cage.slot[vids[i]] != ST_NIL) idx[k++] = r->cage.slot[vids[i]];
    const st_gl *gl = r->gl;
    if (!r->ibo_sel) gl->GenBuffers(1, &r->ibo_sel);
    gl->BindVertexArray(0);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_sel);
    buffer_data(gl, GL_ELEMENT_ARRAY_BUFFER, (size_t)k * sizeof *idx, idx, 16);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    free(idx);
    r->nsel = k;
    return 0;
}

void st_renderer_set_hover(st_renderer *r, uint32_t vid)
{
    r->hover = (r->has_cage && vid < r->cage.nvids) ? r->cage.slot[vid] : ST_NIL;
}

void st_renderer_set_box(st_renderer *r, const float a[3], const float b[3], int show)
{
    const st_gl *gl = r->gl;
    r->has_box = show != 0;
    if (!show) return;
    float lo[3], hi[3];
    for (int i = 0; i < 3; i++) { lo[i] = a[i] < b[i] ? a[i] : b[i]; hi[i] = a[i] < b[i] ? b[i] : a[i]; }
    /* 12 edges: corner k has bit i set when its coordinate i is hi[i]; an
     * edge joins two corners differing in one bit. */
    float v[24 * 3];
    int n = 0;
    for (int k = 0; k < 8; k++)
        for (int i = 0; i < 3; i++) {
            if (k & (1 << i)) continue;
            int k2 = k | (1 << i);
            for (int c = 0; c < 3; c++) v[3 * n + c] = (k & (1 << c)) ? hi[c] : lo[c];
            n++;
            for (int c = 0; c < 3; c++) v[3 * n + c] = (k2 & (1 << c)) ? hi[c] : lo[c];
            n++;
        }
    if (!r->vao_box) {
        gl->GenVertexArrays(1, &r->vao_box);
        gl->GenBuffers(1, &r->vbo_box);
    }
    gl->BindVertexArray(r->vao_box);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->vbo_box);
    gl->BufferData(GL_ARRAY_BUFFER, sizeof v, v, GL_DYNAMIC_DRAW);
    gl->VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), (const void *)0);
    gl->EnableVertexAttribArray(0);
    gl->BindVertexArray(0);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
}

/* ---- drawing ------------------------------------------------------------------ */

static void line_pass(st_renderer *r, const float view[16], const float proj[16], int w, int h,
                      float width, float bias, const float color[4])
{
    const st_gl *gl = r->gl;
    gl->UseProgram(r->prog_line);
    gl->UniformMatrix4fv(r->ul.view, 1, GL_FALSE, view);
    gl->UniformMatrix4fv(r->ul.proj, 1, GL_FALSE, proj);
    gl->Uniform2f(r->ul.viewport, (float)w, (float)h);
    gl->Uniform1f(r->ul.width, width);
    gl->Uniform1f(r->ul.depth_bias, bias);
    gl->Uniform4fv(r->ul.color, 1, color);
}

static void point_pass(st_renderer *r, const float view[16], const float proj[16], float size, float bias,
                       const float color[4])
{
    const st_gl *gl = r->gl;
    gl->UseProgram(r->prog_point);
    gl->UniformMatrix4fv(r->up.view, 1, GL_FALSE, view);
    gl->UniformMatrix4fv(r->up.proj, 1, GL_FALSE, proj);
    gl->Uniform1f(r->up.size, size);
    gl->Uniform1f(r->up.depth_bias, bias);
    gl->Uniform4fv(r->up.color, 1, color);
}

void st_renderer_draw(st_renderer *r, const st_camera *cam, int w, int h, const st_draw_opts *o)
{
    const st_gl *gl = r->gl;
    static const float wire_color[4] = { 0.10f, 0.11f, 0.14f, 1 };
    static const float cage_color[4] = { 0.85f, 0.42f, 0.05f, 1 };
    static const float sel_color[4] = { 1.00f, 0.80f, 0.10f, 1 };
    static const float hover_color[4] = { 0.35f, 0.95f, 1.00f, 1 };
    static const float box_color[4] = { 0.10f, 0.45f, 0.90f, 1 };
    float view[16], proj[16];
    float aspect = h > 0 ? (float)w / (float)h : 1;
    st_camera_view(cam, view);
    st_camera_proj(cam, aspect, proj);
    float lw = o->line_width > 0 ? o->line_width : 1.0f;
    float ps = o->point_size > 0 ? o->point_size : 6.0f;

    st_gl_scene_state(gl, w, h);
    gl->Enable(GL_PROGRAM_POINT_SIZE);
    if (o->clear) st_gl_clear(gl, r->background[0], r->background[1], r->background[2], 1);
    if (r->has_surf && o->shading != ST_SHADE_NONE && r->gsurf.ntris) {
        int checker = o->checker && r->has_uv;
        const st_surface_uniforms *u = checker ? &r->uu : &r->us;
        gl->UseProgram(checker ? r->prog_uv : r->prog_surface);
        gl->UniformMatrix4fv(u->view, 1, GL_FALSE, view);
        gl->UniformMatrix4fv(u->proj, 1, GL_FALSE, proj);
        gl->Uniform1i(u->flat, o->shading == ST_SHADE_FLAT);
        gl->Uniform3fv(u->front, 1, st_gl_surface_front);
        gl->Uniform3fv(u->back, 1, st_gl_surface_back);
        gl->Uniform1i(u->masked, r->has_shade);
        gl->Uniform1i(u->checker, checker);
        if (checker) {
            gl->ActiveTexture(GL_TEXTURE2);
            gl->BindTexture(GL_TEXTURE_BUFFER, r->tex_uv);
        }
        gl->ActiveTexture(GL_TEXTURE0);
        gl->BindTexture(GL_TEXTURE_BUFFER, r->gsurf.tex_tri_face);
        gl->ActiveTexture(GL_TEXTURE1);
        gl->BindTexture(GL_TEXTURE_BUFFER, r->gsurf.tex_face_normal);
        gl->ActiveTexture(GL_TEXTURE0);
        /* Push the surface back by a constant (no slope factor: a slope term
         * pushes steep front faces behind the back faces at silhouettes) so
         * that edges drawn on it win. */
        st_gl_draw_surface_offset(gl, r->gsurf.vao, r->gsurf.ibo_tris, r->gsurf.ntris);
        gl->BindTexture(GL_TEXTURE_BUFFER, 0);
        gl->ActiveTexture(GL_TEXTURE1);
        gl->BindTexture(GL_TEXTURE_BUFFER, 0);
        gl->ActiveTexture(GL_TEXTURE2);
        gl->BindTexture(GL_TEXTURE_BUFFER, 0);
        gl->ActiveTexture(GL_TEXTURE0);
    }
    if (r->has_surf && o->wire && r->gsurf.nlines) {
        line_pass(r, view, proj, w, h, lw, 5e-4f, wire_color);
        gl->BindVertexArray(r->gsurf.vao);
        gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->gsurf.ibo_lines);
        gl->DrawElements(GL_LINES, (GLsizei)(2 * r->gsurf.nlines), GL_UNSIGNED_INT, (const void *)0);
    }
    if (r->has_cage && o->cage) {
        line_pass(r, view, proj, w, h, lw * 1.5f, 1e-4f, cage_color);
        gl->BindVertexArray(r->gcage.vao);
        gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->gcage.ibo_lines);
        gl->DrawElements(GL_LINES, (GLsizei)(2 * r->gcage.nlines), GL_UNSIGNED_INT, (const void *)0);
        point_pass(r, view, proj, ps, 2e-4f, cage_color);
        gl->DrawArrays(GL_POINTS, 0, (GLsizei)r->gcage.nverts);
        if (r->nsel) {
            point_pass(r, view, proj, ps * 1.6f, 4e-4f, sel_color);
            gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_sel);
            gl->DrawElements(GL_POINTS, (GLsizei)r->nsel, GL_UNSIGNED_INT, (const void *)0);
        }
        if (r->hover != ST_NIL) {
            point_pass(r, view, proj, ps * 2.0f, 6e-4f, hover_color);
            gl->DrawArrays(GL_POINTS, (GLint)r->hover, 1);
        }
    }
    if (r->has_box && o->box) {
        line_pass(r, view, proj, w, h, lw * 1.5f, 0, box_color);
        gl->BindVertexArray(r->vao_box);
        gl->DrawArrays(GL_LINES, 0, 24);
    }
    gl->BindVertexArray(0);
    gl->UseProgram(0);
}

void st_renderer_free(st_renderer *r)
{
    const st_gl *gl = r->gl;
    if (gl) {
        gpu_mesh_free(gl, &r->gsurf);
        gpu_mesh_free(gl, &r->gcage);
        if (r->vbo_shade) gl->DeleteBuffers(1, &r->vbo_shade);
        if (r->tbo_uv) gl->DeleteBuffers(1, &r->tbo_uv);
        if (r->tex_uv) gl->DeleteTextures(1, &r->tex_uv);
        if (r->prog_uv) gl->DeleteProgram(r->prog_uv);
        if (r->ibo_sel) gl->DeleteBuffers(1, &r->ibo_sel);
        if (r->vbo_box) gl->DeleteBuffers(1, &r->vbo_box);
        if (r->vao_box) gl->DeleteVertexArrays(1, &r->vao_box);
        if (r->prog_surface) gl->DeleteProgram(r->prog_surface);
        if (r->prog_line) gl->DeleteProgram(r->prog_line);
        if (r->prog_point) gl->DeleteProgram(r->prog_point);
    }
    st_rgeom_free(&r->surf);
    st_rgeom_free(&r->cage);
    free(r->scratch);
    free(r->shade);
    memset(r, 0, sizeof *r);
}
