/* Writers: OBJ (text) and PLY (binary little-endian).
 *
 * Both write to a temporary next to path and rename it over path when
 * everything has been written, flushed and fsynced (core/io/atomic_file.h), so
 * a failed or killed save (full disk, bad mesh, crash) never leaves a
 * truncated file in place of a good one.
 *
 * OBJ positions use %.17g, which reads back to the same double; tags are
 * written in OpenSubdiv's `t` syntax (0-based indices), normals as `vn`
 * with `f a//a` corners, texture coordinates as `vt` with `f a/t` or
 * `f a/t/a` corners (the UV indices as the mesh holds them, so seams
 * survive a round trip).  PLY stores double x y z (and nx ny nz), and
 * vertex_indices as a uchar-counted list when every face has at most 255
 * vertices, uint-counted otherwise.  PLY has one texture coordinate per
 * vertex (u v): a mesh with UVs is written with its vertices split along
 * UV seams (one PLY vertex per vertex and UV index; tags then name the
 * first copy).  PLY has no standard place for tags; they are not written.
 * Hole faces (st_mesh.face_hole) have no surface and are not written;
 * every vertex is, so vertex numbers stay those of the level (as
 * OpenSubdiv's harness writes a refined level with holes).
 */
#include "core/io/atomic_file.h"
#include "core/io/mesh.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Refuses meshes the readers could not read back. */
static int check_writable(const char *path, const st_mesh *m, st_error *err)
{
    if (m->nverts && !m->pos) return st_fail(err, ST_ERR_INVALID, "%s: mesh has no positions", path);
    if (!m->face_off || (m->nfaces && !m->face_idx))
        return st_fail(err, ST_ERR_INVALID, "%s: mesh has no face arrays", path);
    for (size_t i = 0; i < 3 * (size_t)m->nverts; i++)
        if (!isfinite(m->pos[i]) || (m->normals && !isfinite(m->normals[i])))
            return st_fail(err, ST_ERR_GEOMETRY, "%s: vertex %zu is not finite", path, i / 3);
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t a = m->face_off[f], b = m->face_off[f + 1];
        if (b < a || b - a < 3) return st_fail(err, ST_ERR_INVALID, "%s: face %u has fewer than 3 vertices", path, f);
        for (uint32_t c = a; c < b; c++)
            if (m->face_idx[c] >= m->nverts)
                return st_fail(err, ST_ERR_INVALID, "%s: face %u references vertex %u of %u",
                               path, f, m->face_idx[c], m->nverts);
    }
    for (uint32_t i = 0; i < 2 * m->ncreases; i++)
        if (m->crease_v[i] >= m->nverts) return st_fail(err, ST_ERR_INVALID, "%s: bad crease tag", path);
    for (uint32_t i = 0; i < m->ncorners; i++)
        if (m->corner_v[i] >= m->nverts) return st_fail(err, ST_ERR_INVALID, "%s: bad corner tag", path);
    if (!m->face_uv) return 0;
    for (size_t i = 0; i < 2 * (size_t)m->nuvs; i++)
        if (!m->uv || !isfinite(m->uv[i]))
            return st_fail(err, ST_ERR_GEOMETRY, "%s: texture coordinate %zu is not finite", path, i / 2);
    uint32_t nc = m->nfaces ? m->face_off[m->nfaces] : 0;
    for (uint32_t c = 0; c < nc; c++)
        if (m->face_uv[c] >= m->nuvs)
            return st_fail(err, ST_ERR_INVALID, "%s: a face corner references texture coordinate %u of %u",
                           path, m->face_uv[c], m->nuvs);
    return 0;
}

/* m without its hole faces: a view sharing everything but the face arrays
 * (v->face_off == m->face_off when m has no holes).  Freed by
 * surface_done. */
static int surface_view(const char *path, const st_mesh *m, st_mesh *v, st_error *err)
{
    *v = *m;
    v->face_hole = NULL;
    if (!m->face_hole) return 0;
    v->face_off = malloc(((size_t)m->nfaces + 1) * sizeof *v->face_off);
    v->face_idx = malloc(((size_t)m->face_off[m->nfaces] + 1) * sizeof *v->face_idx);
    v->face_uv = m->face_uv ? malloc(((size_t)m->face_off[m->nfaces] + 1) * sizeof *v->face_uv) : NULL;
    if (!v->face_off || !v->face_idx || (m->face_uv && !v->face_uv)) {
        free(v->face_off);
        free(v->face_idx);
        free(v->face_uv);
        return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", path);
    }
    uint32_t nf = 0, k = 0;
    v->face_off[0] = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        if (m->face_hole[f]) continue;
        for (uint32_t c = m->face_off[f]; c < m->face_off[f + 1]; c++) {
            if (v->face_uv) v->face_uv[k] = m->face_uv[c];
            v->face_idx[k++] = m->face_idx[c];
        }
        v->face_off[++nf] = k;
    }
    v->nfaces = nf;
    return 0;
}

static void surface_done(const st_mesh *m, st_mesh *v)
{
    if (v->face_off != m->face_off) {
        free(v->face_off);
        free(v->face_idx);
        if (v->face_uv != m->face_uv) free(v->face_uv);
    }
}

/* ---- temporary file, renamed into place on success (atomic_file.h) ------------ */

typedef struct out_file {
    FILE *f;
    st_afile af;
} out_file;

static int out_open(out_file *o, const char *path, st_error *err)
{
    int rc = st_afile_open(&o->af, path, err);
    o->f = o->af.f;
    return rc;
}

/* Flushes, fsyncs and renames into place; removes the temporary on any error. */
static int out_close(out_file *o, const char *path, st_error *err)
{
    (void)path;
    return st_afile_commit(&o->af, err);
}

/* ---- OBJ ------------------------------------------------------------------------ */

static void obj_body(FILE *f, const st_mesh *m)
{
    fprintf(f, "# Strata mesh: %u vertices, %u faces\n", m->nverts, m->nfaces);
    for (uint32_t v = 0; v < m->nverts; v++) {
        const double *p = m->pos + 3 * (size_t)v;
        fprintf(f, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    for (uint32_t v = 0; m->normals && v < m->nverts; v++) {
        const double *n = m->normals + 3 * (size_t)v;
        fprintf(f, "vn %.17g %.17g %.17g\n", n[0], n[1], n[2]);
    }
    for (uint32_t t = 0; m->face_uv && t < m->nuvs; t++)
        fprintf(f, "vt %.17g %.17g\n", m->uv[2 * (size_t)t], m->uv[2 * (size_t)t + 1]);
    for (uint32_t fi = 0; fi < m->nfaces; fi++) {
        fputc('f', f);
        for (uint32_t c = m->face_off[fi]; c < m->face_off[fi + 1]; c++) {
            uint32_t v = m->face_idx[c] + 1;
            if (m->face_uv && m->normals) fprintf(f, " %u/%u/%u", v, m->face_uv[c] + 1, v);
            else if (m->face_uv) fprintf(f, " %u/%u", v, m->face_uv[c] + 1);
            else if (m->normals) fprintf(f, " %u//%u", v, v);
            else fprintf(f, " %u", v);
        }
        fputc('\n', f);
    }
    for (uint32_t i = 0; i < m->ncreases; i++)
        fprintf(f, "t crease 2/1/0 %u %u %.9g\n", m->crease_v[2 * i], m->crease_v[2 * i + 1],
                (double)m->crease_s[i]);
    for (uint32_t i = 0; i < m->ncorners; i++)
        fprintf(f, "t corner 1/1/0 %u %.9g\n", m->corner_v[i], (double)m->corner_s[i]);
    if (m->boundary_interp >= ST_BOUNDARY_NONE && m->boundary_interp <= ST_BOUNDARY_EDGE_ONLY)
        fprintf(f, "t interpolateboundary 1/0/0 %d\n", m->boundary_interp);
    if (m->crease_method == 1) fputs("t creasemethod 0/0/1 chaikin\n", f);
    if (m->tri_sub == 1) fputs("t smoothtriangles 0/0/1 smooth\n", f);
}

/* Writes the surface faces of m (surface_view) with body, atomically. */
static int write_surface(const char *path, const st_mesh *m, void (*body)(FILE *f, const st_mesh *v), st_error *err)
{
    st_mesh v;
    int rc = surface_view(path, m, &v, err);
    if (rc) return rc;
    out_file o;
    rc = out_open(&o, path, err);
    if (!rc) {
        body(o.f, &v);
        rc = out_close(&o, path, err);
    }
    surface_done(m, &v);
    return rc;
}

int st_mesh_save_obj(const char *path, const st_mesh *m, st_error *err)
{
    int rc = check_writable(path, m, err);
    return rc ? rc : write_surface(path, m, obj_body, err);
}

/* ---- PLY ------------------------------------------------------------------------ */

static void put_u32(unsigned char *b, uint32_t v)
{
    for (int k = 0; k < 4; k++) b[k] = (unsigned char)(v >> (8 * k));
}

static void put_f64(unsigned char *b, double d)
{
    uint64_t v;
    memcpy(&v, &d, sizeof v);
    for (int k = 0; k < 8; k++) b[k] = (unsigned char)(v >> (8 * k));
}

static void ply_header(FILE *f, const st_mesh *m, int wide)
{
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment written by Strata\n"
               "element vertex %u\nproperty double x\nproperty double y\nproperty double z\n", m->nverts);
    if (m->normals) fprintf(f, "property double nx\nproperty double ny\nproperty double nz\n");
    if (m->uv && m->nuvs == m->nverts && !m->face_uv) fprintf(f, "property double u\nproperty double v\n");
    fprintf(f, "element face %u\nproperty list %s uint vertex_indices\nend_header\n",
            m->nfaces, wide ? "uint" : "uchar");
}

static void ply_vertices(FILE *f, const st_mesh *m)
{
    unsigned char b[64];
    int uv = m->uv && m->nuvs == m->nverts && !m->face_uv;
    for (uint32_t v = 0; v < m->nverts; v++) {
        size_t n = 0;
        for (int k = 0; k < 3; k++, n += 8) put_f64(b + n, m->pos[3 * (size_t)v + (size_t)k]);
        for (int k = 0; m->normals && k < 3; k++, n += 8) put_f64(b + n, m->normals[3 * (size_t)v + (size_t)k]);
        for (int k = 0; uv && k < 2; k++, n += 8) put_f64(b + n, m->uv[2 * (size_t)v + (size_t)k]);
        fwrite(b, 1, n, f);
    }
}

static void ply_faces(FILE *f, const st_mesh *m, int wide)
{
    unsigned char b[4];
    for (uint32_t fi = 0; fi < m->nfaces; fi++) {
        uint32_t n = m->face_off[fi + 1] - m->face_off[fi];
        if (wide) {
            put_u32(b, n);
            fwrite(b, 1, 4, f);
        } else {
            fputc((int)n, f);
        }
        for (uint32_t c = m->face_off[fi]; c < m->face_off[fi + 1]; c++) {
            put_u32(b, m->face_idx[c]);
            fwrite(b, 1, 4, f);
        }
    }
}

/* The mesh with one vertex per (vertex, UV index) pair: corners sorted by
 * pair, a new vertex per distinct pair.  Positions and normals are copied;
 * uv becomes per vertex (face_uv = face_idx). */
typedef struct uv_pair { uint32_t v, t, c; } uv_pair;

static int cmp_pair(const void *a, const void *b)
{
    const uv_pair *x = a, *y = b;
    if (x->v != y->v) return x->v < y->v ? -1 : 1;
    if (x->t != y->t) return x->t < y->t ? -1 : 1;
    return (x->c > y->c) - (x->c < y->c);
}

static int split_uv_seams(const st_mesh *m, st_mesh *e)
{
    uint32_t nc = m->face_off[m->nfaces];
    uv_pair *p = malloc(((size_t)nc + 1) * sizeof *p);
    st_mesh_init(e);
    e->face_off = malloc(((size_t)m->nfaces + 1) * sizeof *e->face_off);
    e->face_idx = malloc(((size_t)nc + 1) * sizeof *e->face_idx);
    e->pos = malloc(3 * ((size_t)nc + 1) * sizeof *e->pos);
    e->uv = malloc(2 * ((size_t)nc + 1) * sizeof *e->uv);
    if (m->normals) e->normals = malloc(3 * ((size_t)nc + 1) * sizeof *e->normals);
    if (!p || !e->face_off || !e->face_idx || !e->pos || !e->uv || (m->normals && !e->normals)) {
        free(p);
        st_mesh_free(e);
        return -1;
    }
    memcpy(e->face_off, m->face_off, ((size_t)m->nfaces + 1) * sizeof *e->face_off);
    e->nfaces = m->nfaces;
    if (m->face_hole) {
        /* The same faces in the same order: the same hole flags. */
        e->face_hole = malloc((size_t)m->nfaces + 1);
        if (!e->face_hole) {
            free(p);
            st_mesh_free(e);
            return -1;
        }
        memcpy(e->face_hole, m->face_hole, m->nfaces);
    }
    for (uint32_t c = 0; c < nc; c++) p[c] = (uv_pair){ m->face_idx[c], m->face_uv[c], c };
    qsort(p, nc, sizeof *p, cmp_pair);
    uint32_t n = 0;
    for (uint32_t i = 0; i < nc; i++) {
        if (i == 0 || p[i].v != p[i - 1].v || p[i].t != p[i - 1].t) {
            memcpy(e->pos + 3 * (size_t)n, m->pos + 3 * (size_t)p[i].v, 3 * sizeof *e->pos);
            if (m->normals) memcpy(e->normals + 3 * (size_t)n, m->normals + 3 * (size_t)p[i].v, 3 * sizeof *e->normals);
            memcpy(e->uv + 2 * (size_t)n, m->uv + 2 * (size_t)p[i].t, 2 * sizeof *e->uv);
            n++;
        }
        e->face_idx[p[i].c] = n - 1;
    }
    e->nverts = e->nuvs = n;
    free(p);
    return 0;
}

/* Binary little-endian PLY; faces of more than 255 corners widen the list
 * count to uint. */
static void ply_body(FILE *f, const st_mesh *v)
{
    int wide = 0;
    for (uint32_t fi = 0; fi < v->nfaces; fi++)
        wide |= v->face_off[fi + 1] - v->face_off[fi] > 255;
    ply_header(f, v, wide);
    ply_vertices(f, v);
    ply_faces(f, v, wide);
}

int st_mesh_save_ply(const char *path, const st_mesh *m, st_error *err)
{
    int rc = check_writable(path, m, err);
    st_mesh split;
    if (!rc && m->face_uv) {
        if (split_uv_seams(m, &split)) return st_fail(err, ST_ERR_MEMORY, "%s: out of memory splitting UV seams", path);
        rc = st_mesh_save_ply(path, &split, err);  /* split.face_uv is NULL: written with per-vertex u v */
        st_mesh_free(&split);
        return rc;
    }
    return rc ? rc : write_surface(path, m, ply_body, err);
}

/* ---- dispatch ------------------------------------------------------------------- */

int st_mesh_save(const char *path, const st_mesh *m, st_error *err)
{
    if (st_path_has_ext(path, ".obj")) return st_mesh_save_obj(path, m, err);
    if (st_path_has_ext(path, ".ply")) return st_mesh_save_ply(path, m, err);
    return st_fail(err, ST_ERR_INVALID, "%s: unknown mesh format for writing (expected .obj or .ply)", path);
}
