/* The GL side of the renderer, on a headless OSMesa context: the loader
 * table (and its failure), the context (3.3+ core), the embedded shaders,
 * and incremental buffer updates: after st_hier_edit + st_renderer_refresh the
 * GPU's vertex and face-normal buffers equal a full rebuild, with only a
 * part of the vertices re-uploaded. */
#include "testlib.h"

#include <stdlib.h>
#include <string.h>

#include "core/adapt/adapt.h"
#include "core/multires/edit.h"
#include "render/headless.h"
#include "render/renderer.h"
#include "render/shaders.h"

static st_gl_proc null_get(const char *name) { (void)name; return NULL; }

static void test_loader_failures(void)
{
    st_gl gl;
    st_error err;
    memset(&gl, 0xff, sizeof gl);
    CHECK(st_gl_load(&gl, null_get, &err) != ST_OK);
    CHECKF(strstr(err.msg, "glGetError") != NULL, "message: %s", err.msg);
    CHECK(gl.GetError == NULL && gl.DrawElements == NULL);
    CHECK(st_gl_load(&gl, NULL, &err) != ST_OK);
    st_headless hl;
    CHECK(st_headless_init(&hl, 0, 10, 1, &err) == ST_ERR_RANGE);
    CHECK(st_headless_init(&hl, 10, ST_HEADLESS_MAX_SIZE + 1, 1, &err) == ST_ERR_RANGE);
}

static void test_shaders_embedded(void)
{
    CHECK(st_shader_count() == 11);
    static const char *names[] = { "surface.vert", "surface.frag", "line.vert", "line.geom", "line.frag", "point.vert", "point.frag",
                                   "surface_nmap.vert", "surface_nmap.frag", "surface_uv.vert", "surface_uv.geom" };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        const char *s = st_shader_source(names[i]);
        CHECKF(s && !strncmp(s, "#version 330 core\n", 18), "shader %s", names[i]);
    }
    CHECK(st_shader_source("nope.frag") == NULL);
}

static void test_context(st_headless *hl)
{
    st_gl *gl = &hl->gl;
    CHECKF(gl->major > 3 || (gl->major == 3 && gl->minor >= 3), "OpenGL %d.%d", gl->major, gl->minor);
    GLint mask = 0;
    gl->GetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
    CHECKF(mask & GL_CONTEXT_CORE_PROFILE_BIT, "profile mask 0x%x is not core", (unsigned)mask);
    printf("headless context: %s, %s\n", (const char *)gl->GetString(GL_VERSION), (const char *)gl->GetString(GL_RENDERER));
    /* A cleared image reads back top-down: clear the top half red by a
     * scissor-free trick (viewport + draw nothing is not enough): clear all
     * blue, then read; then resize and read again. */
    st_error err;
    unsigned char px[16 * 8 * 4];
    st_headless_begin(hl);
    gl->ClearColor(0, 0, 1, 1);
    gl->Clear(GL_COLOR_BUFFER_BIT);
    CHECK(st_headless_read(hl, px, &err) == ST_OK);
    CHECK(px[0] == 0 && px[2] == 255 && px[3] == 255);
    CHECK(st_headless_resize(hl, 32, 16, &err) == ST_OK);
    CHECK(hl->width == 32 && hl->height == 16);
}

static int buffer_equals(const st_gl *gl, GLenum target, GLuint buf, const void *data, size_t bytes)
{
    unsigned char *b = malloc(bytes ? bytes : 1);
    gl->BindBuffer(target, buf);
    gl->GetBufferSubData(target, 0, (GLsizeiptr)bytes, b);
    gl->BindBuffer(target, 0);
    int eq = !memcmp(b, data, bytes);
    free(b);
    return eq;
}

static void torus(st_mesh *m) { tl_mesh_torus(m, 12, 8); }

static void test_incremental_upload(st_headless *hl)
{
    st_gl *gl = &hl->gl;
    st_error err;
    st_renderer r;
    CHECKF(st_renderer_init(&r, gl, &err) == ST_OK, "%s", err.msg);
    static const st_scheme_id ids[] = { ST_SCHEME_CATMARK, ST_SCHEME_DOOSABIN };
    for (size_t s = 0; s < sizeof ids / sizeof ids[0]; s++) {
        st_hier h;
        uint64_t rng = 99;
        tl_init_hier(&h, torus, ids[s], 4);
        tl_random_details(&h, &rng, 0.01);
        st_headless_begin(hl);
        CHECK(st_renderer_set_level(&r, &h.map, 4, &err) == ST_OK);
        CHECK(st_renderer_set_cage(&r, &h.map, 1, &err) == ST_OK);
        uint32_t full_verts = r.surf.nverts;
        uint32_t dart = tl_random_dart_at(&h.map, 1, &rng);
        const double *p = st_dart_pos(&h.map, dart, 1);
        double pos[1][3] = { { p[0] + 0.2, p[1] - 0.1, p[2] + 0.05 } };
        st_footprint fp = { 0 };
        st_hier_edit(&h, 1, &dart, (const double (*)[3])pos, 1, &fp);
        CHECK(st_renderer_refresh(&r, ST_TARGET_MESHES, &h.map, &fp) == 0);
        st_footprint_free(&fp);
        CHECKF(r.last.vertices > 0 && r.last.vertices < full_verts / 2,
               "%u vertices re-uploaded of %u", r.last.vertices, full_verts);
        printf("%s: edit at level 1 shown at level 4: %u of %u vertices re-uploaded in %u ranges\n",
               h.scheme->name, r.last.vertices, full_verts, r.last.ranges);
        st_rgeom fresh, fcage;
        st_rgeom_init(&fresh);
        st_rgeom_init(&fcage);
        CHECK(st_rgeom_build(&fresh, &h.map, 4, &err) == ST_OK);
        CHECK(st_rgeom_build(&fcage, &h.map, 1, &err) == ST_OK);
        CHECK(buffer_equals(gl, GL_ARRAY_BUFFER, r.gsurf.vbo, fresh.vdata, (size_t)fresh.nverts * ST_RGEOM_VSTRIDE * sizeof(float)));
        CHECK(buffer_equals(gl, GL_TEXTURE_BUFFER, r.gsurf.tbo_face_normal, fresh.fnormal, (size_t)fresh.nfaces * 4 * sizeof(float)));
        CHECK(buffer_equals(gl, GL_ARRAY_BUFFER, r.gcage.vbo, fcage.vdata, (size_t)fcage.nverts * ST_RGEOM_VSTRIDE * sizeof(float)));
        /* Index buffers are untouched by an edit and hold the triangles. */
        gl->BindVertexArray(r.gsurf.vao);
        CHECK(buffer_equals(gl, GL_ELEMENT_ARRAY_BUFFER, r.gsurf.ibo_tris, fresh.tris, (size_t)fresh.ntris * 3 * sizeof(uint32_t)));
        gl->BindVertexArray(0);
        /* Whole-position refresh (after an analysis, say). */
        tl_random_details(&h, &rng, 0.01);
        st_renderer_refresh_all(&r, ST_TARGET_MESHES, &h.map);
        CHECK(st_rgeom_build(&fresh, &h.map, 4, &err) == ST_OK);
        CHECK(buffer_equals(gl, GL_ARRAY_BUFFER, r.gsurf.vbo, fresh.vdata, (size_t)fresh.nverts * ST_RGEOM_VSTRIDE * sizeof(float)));
        /* Selection ignores ids not on the cage. */
        uint32_t sel[3] = { r.cage.vid[0], r.cage.vid[1], 0xfffffff0u };
        CHECK(st_renderer_set_selection(&r, sel, 3) == 0 && r.nsel == 2);
        st_renderer_set_hover(&r, ST_NIL);
        CHECK(r.hover == ST_NIL);
        CHECK(gl->GetError() == GL_NO_ERROR);
        st_rgeom_free(&fresh);
        st_rgeom_free(&fcage);
        st_hier_free(&h);
    }
    st_renderer_free(&r);
}

/* Box moves over an adaptive display: st_renderer_patch leaves the GPU
 * buffers holding exactly the patched CPU arrays (every range it uploaded,
 * or a full upload when the room ran out), with no GL error. */
static void torus_fine(st_mesh *m) { tl_mesh_torus(m, 32, 24); }

static void test_patch_upload(st_headless *hl, st_scheme_id id)
{
    st_gl *gl = &hl->gl;
    st_error err;
    st_renderer r;
    CHECKF(st_renderer_init(&r, gl, &err) == ST_OK, "%s", err.msg);
    st_hier h;
    st_adapt a;
    tl_init_hier(&h, torus_fine, id, 0);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = { .base_level = 2, .max_level = 4, .has_box = 1 };
    double lo[3] = { 2.3, -0.3, -0.3 }, hi[3] = { 2.9, 0.3, 0.3 }; /* (on the outer equator) */
    memcpy(p.box_lo, lo, sizeof lo);
    memcpy(p.box_hi, hi, sizeof hi);
    CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    st_headless_begin(hl);
    CHECK(st_renderer_set_level(&r, &h.map, h.map.top, &err) == ST_OK);
    st_map_log log = { 0 };
    int patched = 0;
    for (int k = 0; k < 8; k++) {
        double shift = (k % 3 == 2 ? -0.05 : 0.05) * (p.box_hi[1] - p.box_lo[1]);
        p.box_lo[1] += shift;
        p.box_hi[1] += shift;
        st_map_log_clear(&log);
        unsigned top = h.map.top;
        h.map.log = &log;
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
        h.map.log = NULL;
        if (h.map.top == top && st_renderer_patch(&r, &h.map, &log) == 0) patched++;
        else CHECK(st_renderer_set_level(&r, &h.map, h.map.top, &err) == ST_OK);
        const st_rgeom *g = &r.surf;
        CHECK(r.gsurf.nverts == g->nverts && r.gsurf.ntris == g->ntris && r.gsurf.nlines == g->nlines);
        CHECK(buffer_equals(gl, GL_ARRAY_BUFFER, r.gsurf.vbo, g->vdata, (size_t)g->nverts * ST_RGEOM_VSTRIDE * sizeof(float)));
        CHECK(buffer_equals(gl, GL_TEXTURE_BUFFER, r.gsurf.tbo_face_normal, g->fnormal, (size_t)g->nfaces * 4 * sizeof(float)));
        CHECK(buffer_equals(gl, GL_TEXTURE_BUFFER, r.gsurf.tbo_tri_face, g->tri_face, (size_t)g->ntris * sizeof(uint32_t)));
        gl->BindVertexArray(r.gsurf.vao);
        CHECK(buffer_equals(gl, GL_ELEMENT_ARRAY_BUFFER, r.gsurf.ibo_tris, g->tris, (size_t)g->ntris * 3 * sizeof(uint32_t)));
        CHECK(buffer_equals(gl, GL_ELEMENT_ARRAY_BUFFER, r.gsurf.ibo_lines, g->lines, (size_t)g->nlines * 2 * sizeof(uint32_t)));
        gl->BindVertexArray(0);
        CHECK(gl->GetError() == GL_NO_ERROR);
    }
    printf("%s: adaptive box moves: %d of 8 patched in place (%u faces drawn, %u removed slots)\n", h.scheme->name,
           patched, r.surf.nfaces - r.surf.ndead, r.surf.ndead);
    CHECKF(patched >= 4, "only %d of 8 box moves patched", patched);
    st_map_log_free(&log);
    st_adapt_free(&a);
    st_hier_free(&h);
    st_renderer_free(&r);
}

int main(void)
{
    test_loader_failures();
    test_shaders_embedded();
    st_headless hl;
    st_error err;
    int rc = st_headless_init(&hl, 16, 8, 4, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (!rc) {
        test_context(&hl);
        test_incremental_upload(&hl);
        test_patch_upload(&hl, ST_SCHEME_CATMARK);
        test_patch_upload(&hl, ST_SCHEME_DOOSABIN);
        st_headless_free(&hl);
    }
    return TEST_END();
}
