/* A level drawn with a normal map (render/nmap.h). */
#include "render/nmap.h"
#include "render/gl_program.h"
#include "render/image.h"
#include "render/shaders.h"
#include "core/io/mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void st_nmap_mesh_free(st_nmap_mesh *m)
{
    free(m->attr);
    free(m->tile);
    free(m->tile_off);
    memset(m, 0, sizeof *m);
}

static void put_corner(float *a, const double *p, const double *n, const double *t, const double *uv, const int32_t tile[2])
{
    for (int k = 0; k < 3; k++) { a[k] = (float)p[k]; a[3 + k] = (float)n[k]; }
    for (int k = 0; k < 4; k++) a[6 + k] = (float)t[k];
    a[10] = (float)(uv[0] - tile[0]);
    a[11] = (float)(uv[1] - tile[1]);
}

int st_nmap_mesh_build(st_hier *h, unsigned level, const st_bake_uvs *uvs, st_nmap_mesh *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    st_mesh mesh;
    st_mesh_init(&mesh);
    int rc = st_hier_level_mesh(h, level, &mesh, err);
    if (rc) return rc;
    size_t nc = mesh.face_off[mesh.nfaces], ntri = 0;
    double *tan = malloc((nc ? nc : 1) * 4 * sizeof *tan), *nrm = malloc((nc ? nc : 1) * 3 * sizeof *nrm);
    if (!tan || !nrm) rc = st_fail(err, ST_ERR_MEMORY, "out of memory building the normal-mapped mesh");
    if (!rc) rc = st_bake_tangents(h, level, uvs, tan, nrm, err);
    for (uint32_t f = 0; !rc && f < mesh.nfaces; f++) ntri += mesh.face_off[f + 1] - mesh.face_off[f] - 2;
    if (!rc && !(out->attr = malloc((ntri ? ntri : 1) * 3 * ST_NMAP_FLOATS * sizeof *out->attr)))
        rc = st_fail(err, ST_ERR_MEMORY, "out of memory building the normal-mapped mesh");
    st_bake_tiles tiles = { 0 };
    if (!rc) rc = st_bake_uv_tiles(uvs, 1, &tiles, err);
    if (!rc && !(out->tile_off = calloc((size_t)tiles.ntiles + 1, sizeof *out->tile_off)))
        rc = st_fail(err, ST_ERR_MEMORY, "out of memory building the normal-mapped mesh");
    if (!rc) {
        float *a = out->attr;
        /* One pass per tile, faces in order within it: a mesh in one tile
         * keeps its triangle order. */
        for (uint32_t ti = 0; ti < tiles.ntiles; ti++) {
            out->tile_off[ti] = (uint32_t)((a - out->attr) / ST_NMAP_FLOATS);
            for (uint32_t f = 0; f < mesh.nfaces; f++) {
                uint32_t s = mesh.face_off[f], n = mesh.face_off[f + 1] - s;
                int32_t home[2];
                st_bake_face_tile(uvs->uv + 2 * (size_t)s, n, home);
                if (home[0] != tiles.tile[ti][0] || home[1] != tiles.tile[ti][1]) continue;
                for (uint32_t t = 0; t + 2 < n; t++) {
                    uint32_t c[3] = { s, s + t + 1, s + t + 2 };
                    for (int k = 0; k < 3; k++, a += ST_NMAP_FLOATS)
                        put_corner(a, mesh.pos + 3 * (size_t)mesh.face_idx[c[k]], nrm + 3 * (size_t)c[k],
                                   tan + 4 * (size_t)c[k], uvs->uv + 2 * (size_t)c[k], home);
                }
            }
        }
        out->ncorners = (uint32_t)(3 * ntri);
        out->tile_off[tiles.ntiles] = out->ncorners;
        out->ntiles = tiles.ntiles;
        out->tile = tiles.tile;
        tiles.tile = NULL;
        for (int k = 0; k < 3; k++) { out->bbox[k] = 3e38f; out->bbox[k + 3] = -3e38f; }
        for (uint32_t v = 0; v < mesh.nverts; v++)
            for (int k = 0; k < 3; k++) {
                float x = (float)mesh.pos[3 * (size_t)v + k];
                if (x < out->bbox[k]) out->bbox[k] = x;
                if (x > out->bbox[k + 3]) out->bbox[k + 3] = x;
            }
    }
    st_bake_tiles_free(&tiles);
    free(tan);
    free(nrm);
    st_mesh_free(&mesh);
    if (rc) st_nmap_mesh_free(out);
    return rc;
}

int st_nmap_init(st_nmap *n, const st_gl *gl, st_error *err)
{
    memset(n, 0, sizeof *n);
    n->gl = gl;
    n->prog = st_gl_program(gl, st_shader_source("surface_nmap.vert"), st_shader_source("surface_nmap.frag"),
                            "surface_nmap", "normal-mapped surface program", err);
    if (!n->prog) return err->code ? err->code : ST_ERR_INVALID;
    n->u_view = gl->GetUniformLocation(n->prog, "u_view");
    n->u_proj = gl->GetUniformLocation(n->prog, "u_proj");
    n->u_map = gl->GetUniformLocation(n->prog, "u_map");
    n->u_use_map = gl->GetUniformLocation(n->prog, "u_use_map");
    n->u_object = gl->GetUniformLocation(n->prog, "u_object_space");
    n->u_front = gl->GetUniformLocation(n->prog, "u_front");
    n->u_back = gl->GetUniformLocation(n->prog, "u_back");
    gl->GenVertexArrays(1, &n->vao);
    gl->GenBuffers(1, &n->vbo);
    gl->GenTextures(1, &n->tex);
    return ST_OK;
}

void st_nmap_set_mesh(st_nmap *n, const st_nmap_mesh *m)
{
    const st_gl *gl = n->gl;
    gl->BindVertexArray(n->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, n->vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)m->ncorners * ST_NMAP_FLOATS * sizeof(float)), m->attr, GL_STATIC_DRAW);
    static const int offs[4] = { 0, 3, 6, 10 }, sizes[4] = { 3, 3, 4, 2 };
    for (GLuint i = 0; i < 4; i++) {
        gl->VertexAttribPointer(i, sizes[i], GL_FLOAT, GL_FALSE, ST_NMAP_FLOATS * sizeof(float),
                                (const void *)(offs[i] * sizeof(float)));
        gl->EnableVertexAttribArray(i);
    }
    gl->BindVertexArray(0);
    n->ncorners = m->ncorners;
    free(n->tile_off);
    n->ntiles = 0;
    n->tile_off = malloc(((size_t)m->ntiles + 1) * sizeof *n->tile_off);
    if (n->tile_off) {
        memcpy(n->tile_off, m->tile_off, ((size_t)m->ntiles + 1) * sizeof *n->tile_off);
        n->ntiles = m->ntiles;
    }
}

static void upload(const st_gl *gl, GLuint tex, const unsigned char *rgba, int w, int h)
{
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, tex);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    gl->GenerateMipmap(GL_TEXTURE_2D);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    /* Repeat: strata bake wraps the faces that overshoot their UV tile
     * (core/bake/bake.h: tiles and wrap-around), as glTF's default sampler
     * reads them. */
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    gl->BindTexture(GL_TEXTURE_2D, 0);
}

void st_nmap_set_map(st_nmap *n, const unsigned char *rgba, int w, int h)
{
    upload(n->gl, n->tex, rgba, w, h);
    n->has_map = 1;
}

void st_nmap_set_tile_map(st_nmap *n, uint32_t i, const unsigned char *rgba, int w, int h)
{
    if (i >= 64) return;
    if (!n->tiles_tex[i]) n->gl->GenTextures(1, &n->tiles_tex[i]);
    upload(n->gl, n->tiles_tex[i], rgba, w, h);
}

void st_nmap_draw(st_nmap *n, const st_camera *cam, int w, int h, int mode)
{
    const st_gl *gl = n->gl;
    float view[16], proj[16];
    st_camera_view(cam, view);
    st_camera_proj(cam, h > 0 ? (float)w / (float)h : 1, proj);
    /* The renderer's state, surface colours and background (gl_program.h). */
    st_gl_scene_state(gl, w, h);
    st_gl_clear(gl, st_gl_background[0], st_gl_background[1], st_gl_background[2], 1);
    gl->UseProgram(n->prog);
    gl->UniformMatrix4fv(n->u_view, 1, GL_FALSE, view);
    gl->UniformMatrix4fv(n->u_proj, 1, GL_FALSE, proj);
    gl->Uniform3fv(n->u_front, 1, st_gl_surface_front);
    gl->Uniform3fv(n->u_back, 1, st_gl_surface_back);
    int use = mode != ST_NMAP_NONE;
    gl->Uniform1i(n->u_use_map, use);
    gl->Uniform1i(n->u_object, mode == ST_NMAP_OBJECT);
    gl->Uniform1i(n->u_map, 0);
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindVertexArray(n->vao);
    /* Each tile's triangles with its texture (a UDIM set), else the map. */
    uint32_t nt = n->tile_off && n->ntiles ? n->ntiles : 1;
    for (uint32_t i = 0; i < nt; i++) {
        int ranged = n->tile_off && n->ntiles;
        uint32_t c0 = ranged ? n->tile_off[i] : 0, c1 = ranged ? n->tile_off[i + 1] : n->ncorners;
        GLuint tex = i < 64 && n->tiles_tex[i] ? n->tiles_tex[i] : n->tex;
        int has = i < 64 && n->tiles_tex[i] ? 1 : n->has_map;
        gl->Uniform1i(n->u_use_map, use && has);
        gl->BindTexture(GL_TEXTURE_2D, tex);
        if (c1 > c0) gl->DrawArrays(GL_TRIANGLES, (GLint)c0, (GLsizei)(c1 - c0));
    }
    gl->BindVertexArray(0);
    gl->BindTexture(GL_TEXTURE_2D, 0);
    gl->UseProgram(0);
}

void st_nmap_free(st_nmap *n)
{
    const st_gl *gl = n->gl;
    if (!gl) return;
    if (n->tex) gl->DeleteTextures(1, &n->tex);
    for (int i = 0; i < 64; i++)
        if (n->tiles_tex[i]) gl->DeleteTextures(1, &n->tiles_tex[i]);
    free(n->tile_off);
    if (n->vbo) gl->DeleteBuffers(1, &n->vbo);
    if (n->vao) gl->DeleteVertexArrays(1, &n->vao);
    if (n->prog) gl->DeleteProgram(n->prog);
    memset(n, 0, sizeof *n);
}

/* A UDIM set's tile path: the literal <UDIM> in path replaced by number. */
static int tile_path(const char *path, const char *tok, unsigned number, char *out, size_t n)
{
    int k = snprintf(out, n, "%.*s%u%s", (int)(tok - path), path, number, tok + 6);
    return k > 0 && (size_t)k < n;
}

/* Every tile of a UDIM set NAME.<UDIM>.png that the mesh's faces use, read
 * and given to n; a used tile without a UDIM number or without its file is
 * an error naming it. */
static int load_udim(st_nmap *nm, const st_nmap_mesh *mesh, const char *path, const char *tok, st_error *err)
{
    if (mesh->ntiles > 64)
        return st_fail(err, ST_ERR_INVALID, "%s: the level's faces use %u UV tiles; at most 64 are drawn", path, mesh->ntiles);
    for (uint32_t i = 0; i < mesh->ntiles; i++) {
        unsigned number = st_bake_udim(mesh->tile[i]);
        if (!number)
            return st_fail(err, ST_ERR_INVALID, "%s: the level has faces in UV tile (%d, %d), which has no UDIM number",
                           path, mesh->tile[i][0], mesh->tile[i][1]);
        char one[4096];
        if (!tile_path(path, tok, number, one, sizeof one)) return st_fail(err, ST_ERR_INVALID, "%s: path too long", path);
        int tw = 0, th = 0;
        unsigned char *tex = NULL;
        int rc = st_png_read(one, &tw, &th, &tex, err);
        if (rc) return rc;
        st_nmap_set_tile_map(nm, i, tex, tw, th);
        free(tex);
    }
    return ST_OK;
}

int st_nmap_load_map(st_nmap *n, const st_nmap_mesh *mesh, const char *path, st_error *err)
{
    const char *tok = strstr(path, "<UDIM>");
    if (tok) return load_udim(n, mesh, path, tok, err);
    int tw = 0, th = 0;
    unsigned char *tex = NULL;
    int rc = st_png_read(path, &tw, &th, &tex, err);
    if (rc) return rc;
    st_nmap_set_map(n, tex, tw, th);
    free(tex);
    return ST_OK;
}
