/* UV layouts and tangent frames of a level (core/bake/bake.h). */
#include "core/bake/bake_internal.h"
#include "core/fvar/fvar.h"
#include "core/map/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void st_bake_layout_free(st_bake_layout *l)
{
    free(l->corner_off);
    free(l->uv);
    memset(l, 0, sizeof *l);
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static int normalize3(double *v)
{
    double len = sqrt(dot3(v, v));
    if (!(len > 1e-300) || !isfinite(len)) return 0;
    for (int k = 0; k < 3; k++) v[k] /= len;
    return 1;
}

/* Any unit vector orthogonal to unit n. */
static void any_orthogonal(const double *n, double *t)
{
    double axis[3] = { 0, 0, 0 };
    int k = fabs(n[0]) <= fabs(n[1]) ? (fabs(n[0]) <= fabs(n[2]) ? 0 : 2) : (fabs(n[1]) <= fabs(n[2]) ? 1 : 2);
    axis[k] = 1;
    double d = dot3(axis, n);
    for (int i = 0; i < 3; i++) t[i] = axis[i] - d * n[i];
    normalize3(t);
}

/* ---- the per-face atlas ---------------------------------------------------- */

/* Corner coordinates of the face of d in its own plane: x along the first
 * edge, y = normal × x; returns the degree. */
static unsigned face_plane_coords(const st_map *m, uint32_t d, unsigned l, double *xy)
{
    double n[3], a[3];
    st_face_newell(m, d, l, n);
    if (!normalize3(n)) { n[0] = n[1] = 0; n[2] = 1; }
    const double *p0 = st_dart_pos(m, d, l), *p1 = st_dart_pos(m, st_face_step(m, d, l), l);
    for (int k = 0; k < 3; k++) a[k] = p1[k] - p0[k];
    double dn = dot3(a, n);
    for (int k = 0; k < 3; k++) a[k] -= dn * n[k];
    if (!normalize3(a)) any_orthogonal(n, a);
    double b[3];
    cross3(n, a, b);
    unsigned k = 0;
    uint32_t x = d;
    do {
        const double *p = st_dart_pos(m, x, l);
        double r[3] = { p[0] - p0[0], p[1] - p0[1], p[2] - p0[2] };
        xy[2 * k] = dot3(r, a);
        xy[2 * k + 1] = dot3(r, b);
        k++;
        x = st_face_step(m, x, l);
    } while (x != d);
    return k;
}

int st_bake_auto_uvs(st_hier *h, unsigned l, st_bake_layout *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    st_map *m = &h->map;
    if (l > m->top) return st_fail(err, ST_ERR_RANGE, "level %u does not exist (top level %u)", l, m->top);
    uint32_t *darts, nf;
    int rc = st_bake_level_faces(m, l, &darts, &nf, err);
    if (rc) return rc;
    out->corner_off = malloc(((size_t)nf + 1) * sizeof *out->corner_off);
    out->nfaces = nf;
    if (!out->corner_off) { free(darts); return st_fail(err, ST_ERR_MEMORY, "out of memory making UVs of level %u", l); }
    out->corner_off[0] = 0;
    for (uint32_t f = 0; f < nf; f++) out->corner_off[f + 1] = out->corner_off[f] + st_bake_face_degree(m, darts[f], l);
    out->uv = malloc(((size_t)out->corner_off[nf] ? out->corner_off[nf] : 1) * 2 * sizeof *out->uv);
    if (!out->uv) { free(darts); st_bake_layout_free(out); return st_fail(err, ST_ERR_MEMORY, "out of memory making UVs of level %u", l); }
    /* Plane coordinates first, then one scale for every face: the largest
     * face fills the inner 3/4 of its cell. */
    double extent = 0;
    for (uint32_t f = 0; f < nf; f++) {
        double *xy = out->uv + 2 * (size_t)out->corner_off[f];
        unsigned n = face_plane_coords(m, darts[f], l, xy);
        double lo[2] = { xy[0], xy[1] }, hi[2] = { xy[0], xy[1] };
        for (unsigned c = 1; c < n; c++)
            for (int k = 0; k < 2; k++) { lo[k] = fmin(lo[k], xy[2 * c + k]); hi[k] = fmax(hi[k], xy[2 * c + k]); }
        extent = fmax(extent, fmax(hi[0] - lo[0], hi[1] - lo[1]));
    }
    uint32_t grid = 1;
    while ((uint64_t)grid * grid < nf) grid++;
    double cell = 1.0 / grid, inner = 0.75 * cell;
    double scale = extent > 0 ? inner / extent : 0;
    for (uint32_t f = 0; f < nf; f++) {
        double *xy = out->uv + 2 * (size_t)out->corner_off[f];
        unsigned n = out->corner_off[f + 1] - out->corner_off[f];
        double lo[2] = { xy[0], xy[1] }, hi[2] = { xy[0], xy[1] };
        for (unsigned c = 1; c < n; c++)
            for (int k = 0; k < 2; k++) { lo[k] = fmin(lo[k], xy[2 * c + k]); hi[k] = fmax(hi[k], xy[2 * c + k]); }
        double centre[2] = { ((f % grid) + 0.5) * cell, ((f / grid) + 0.5) * cell };
        for (unsigned c = 0; c < n; c++)
            for (int k = 0; k < 2; k++)
                xy[2 * c + k] = centre[k] + (xy[2 * c + k] - 0.5 * (lo[k] + hi[k])) * scale;
    }
    free(darts);
    return ST_OK;
}

/* ---- the chart atlas (core/uv) ------------------------------------------------ */

int st_bake_chart_uvs(st_hier *h, unsigned l, uint32_t size, uint32_t padding, st_bake_layout *out, st_uv_stats *stats,
                      st_error *err)
{
    memset(out, 0, sizeof *out);
    st_map *m = &h->map;
    if (l > m->top) return st_fail(err, ST_ERR_RANGE, "level %u does not exist (top level %u)", l, m->top);
    st_mesh mesh;
    st_mesh_init(&mesh);
    int rc = st_hier_level_mesh(h, l, &mesh, err);
    if (rc) return rc;
    uint32_t *darts = NULL, nf = 0;
    rc = st_bake_level_faces(m, l, &darts, &nf, err);
    free(darts);
    if (!rc && nf != mesh.nfaces)
        rc = st_fail(err, ST_ERR_INVALID, "level %u: %u faces to bake but %u in its mesh", l, nf, mesh.nfaces);
    st_uv_atlas atlas = { 0 };
    if (!rc) {
        st_uv_mesh um = { mesh.nverts, mesh.pos, mesh.nfaces, mesh.face_off, mesh.face_idx };
        st_uv_opts uo = { .size = size, .padding = padding };
        rc = st_uv_make_atlas(&um, &uo, &atlas, err);
    }
    if (!rc) {
        out->nfaces = mesh.nfaces;
        out->corner_off = mesh.face_off; /* taken over */
        mesh.face_off = NULL;
        out->uv = atlas.uv;
        atlas.uv = NULL;
        if (stats) *stats = atlas.stats;
    }
    st_uv_atlas_free(&atlas);
    st_mesh_free(&mesh);
    return rc;
}

int st_bake_layout_dart_uvs(st_hier *h, unsigned l, const st_bake_uvs *uvs, double **out, st_error *err)
{
    *out = NULL;
    st_map *m = &h->map;
    if (l > m->top) return st_fail(err, ST_ERR_RANGE, "level %u does not exist (top level %u)", l, m->top);
    uint32_t *darts, nf;
    int rc = st_bake_level_faces(m, l, &darts, &nf, err);
    if (!rc) rc = st_bake_check_uvs(m, l, darts, nf, uvs, err);
    if (rc) { free(darts); return rc; }
    double *uv = calloc(2 * (size_t)(m->darts.end ? m->darts.end : 1), sizeof *uv);
    if (!uv) { free(darts); return st_fail(err, ST_ERR_MEMORY, "out of memory for the UVs of level %u", l); }
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t d = darts[f], k = uvs->corner_off[f];
        do {
            uv[2 * (size_t)d] = uvs->uv[2 * (size_t)k];
            uv[2 * (size_t)d + 1] = uvs->uv[2 * (size_t)k + 1];
            k++;
            d = st_face_step(m, d, l);
        } while (d != darts[f]);
    }
    free(darts);
    *out = uv;
    return ST_OK;
}

/* ---- the mesh's own UVs ----------------------------------------------------- */

int st_bake_level_uvs(st_hier *h, unsigned l, st_bake_layout *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    st_map *m = &h->map;
    if (l > m->top) return st_fail(err, ST_ERR_RANGE, "level %u does not exist (top level %u)", l, m->top);
    st_uv_map uv = st_hier_uv(h, l);
    if (!uv.uv) return st_fail(err, ST_ERR_INVALID, "level %u has no UVs", l);
    uint32_t *darts, nf;
    int rc = st_bake_level_faces(m, l, &darts, &nf, err);
    if (rc) return rc;
    out->nfaces = nf;
    out->corner_off = malloc(((size_t)nf + 1) * sizeof *out->corner_off);
    if (!out->corner_off) { free(darts); return st_fail(err, ST_ERR_MEMORY, "out of memory reading the UVs of level %u", l); }
    out->corner_off[0] = 0;
    for (uint32_t f = 0; f < nf; f++) out->corner_off[f + 1] = out->corner_off[f] + st_bake_face_degree(m, darts[f], l);
    out->uv = malloc(((size_t)out->corner_off[nf] ? out->corner_off[nf] : 1) * 2 * sizeof *out->uv);
    if (!out->uv) { free(darts); st_bake_layout_free(out); return st_fail(err, ST_ERR_MEMORY, "out of memory reading the UVs of level %u", l); }
    /* Corners from each face's first dart along the face: st_hier_uv's order. */
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t d = darts[f], k = out->corner_off[f];
        do {
            const double *p = st_uv_map_at(&uv, d);
            out->uv[2 * (size_t)k] = p[0];
            out->uv[2 * (size_t)k + 1] = p[1];
            k++;
            d = st_face_step(m, d, l);
        } while (d != darts[f]);
    }
    free(darts);
    return ST_OK;
}

/* ---- tangents -------------------------------------------------------------- */

typedef struct corner_key {
    uint32_t vert;
    int32_t side;                 /* orientation of the face in UV: ±1 */
    double u, v;
    uint32_t corner;
} corner_key;

static int key_cmp(const void *pa, const void *pb)
{
    const corner_key *a = pa, *b = pb;
    if (a->vert != b->vert) return a->vert < b->vert ? -1 : 1;
    if (a->side != b->side) return a->side < b->side ? -1 : 1;
    if (a->u != b->u) return a->u < b->u ? -1 : 1;
    if (a->v != b->v) return a->v < b->v ? -1 : 1;
    return a->corner < b->corner ? -1 : a->corner > b->corner;
}

static double corner_angle(const double *p, const double *a, const double *b)
{
    double e[3], g[3], c[3];
    for (int k = 0; k < 3; k++) { e[k] = a[k] - p[k]; g[k] = b[k] - p[k]; }
    cross3(e, g, c);
    return atan2(sqrt(dot3(c, c)), dot3(e, g));
}

/* Adds the UV-derivative tangent and bitangent of triangle (i0, i1, i2) of
 * face-corner indices (Lengyel's formula, MikkTSpace's per-triangle step),
 * weighted by each corner's angle, to the sums of the corners' groups. */
static void add_triangle_frame(const st_map *m, unsigned l, const uint32_t *vert, const double *uv,
                               const uint32_t *group, double *sum, const uint32_t i[3])
{
    const double *p[3];
    for (int k = 0; k < 3; k++) p[k] = st_pos(m, vert[i[k]], l);
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) { e1[k] = p[1][k] - p[0][k]; e2[k] = p[2][k] - p[0][k]; }
    const double *t0 = uv + 2 * (size_t)i[0], *t1 = uv + 2 * (size_t)i[1], *t2 = uv + 2 * (size_t)i[2];
    double du1 = t1[0] - t0[0], dv1 = t1[1] - t0[1], du2 = t2[0] - t0[0], dv2 = t2[1] - t0[1];
    double r = du1 * dv2 - du2 * dv1;
    if (!(fabs(r) > 1e-300)) return;
    double T[3], Bt[3];
    for (int k = 0; k < 3; k++) {
        T[k] = (e1[k] * dv2 - e2[k] * dv1) / r;
        Bt[k] = (e2[k] * du1 - e1[k] * du2) / r;
    }
    if (!normalize3(T) || !normalize3(Bt)) return;
    for (int k = 0; k < 3; k++) {
        double w = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        double *s = sum + 6 * (size_t)group[i[k]];
        for (int c = 0; c < 3; c++) { s[c] += w * T[c]; s[3 + c] += w * Bt[c]; }
    }
}

static int uv_side(const double *uv, uint32_t n)
{
    double a = 0;
    for (uint32_t c = 0; c < n; c++) {
        const double *p = uv + 2 * c, *q = uv + 2 * ((c + 1) % n);
        a += p[0] * q[1] - q[0] * p[1];
    }
    return a < 0 ? -1 : 1;
}

int st_bake_tangents(st_hier *h, unsigned l, const st_bake_uvs *uvs, double *tangents, double *normals, st_error *err)
{
    st_map *m = &h->map;
    if (l > m->top) return st_fail(err, ST_ERR_RANGE, "level %u does not exist (top level %u)", l, m->top);
    uint32_t *darts = NULL, nf = 0;
    double *vn = NULL, *sum = NULL;
    uint32_t *vert = NULL, *group = NULL;
    corner_key *keys = NULL;
    int rc = st_bake_level_faces(m, l, &darts, &nf, err);
    if (!rc) rc = st_bake_check_uvs(m, l, darts, nf, uvs, err);
    if (!rc) rc = st_bake_vertex_normals(m, l, &vn, err);
    if (rc) goto done;
    size_t nc = uvs->corner_off[nf];
    vert = malloc((nc ? nc : 1) * sizeof *vert);
    group = malloc((nc ? nc : 1) * sizeof *group);
    keys = malloc((nc ? nc : 1) * sizeof *keys);
    sum = calloc(6 * (nc ? nc : 1), sizeof *sum);
    if (!vert || !group || !keys || !sum) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory computing tangents of level %u", l); goto done; }
    /* Smoothing groups: corners with one vertex, one UV, one orientation. */
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t a = uvs->corner_off[f], n = uvs->corner_off[f + 1] - a;
        int side = uv_side(uvs->uv + 2 * (size_t)a, n);
        uint32_t x = darts[f];
        for (uint32_t c = 0; c < n; c++, x = st_face_step(m, x, l)) {
            vert[a + c] = st_vert(m, x, l);
            corner_key k = { vert[a + c], side, uvs->uv[2 * ((size_t)a + c)], uvs->uv[2 * ((size_t)a + c) + 1], a + c };
            keys[a + c] = k;
        }
    }
    qsort(keys, nc, sizeof *keys, key_cmp);
    uint32_t g = 0;
    for (size_t i = 0; i < nc; i++) {
        if (i > 0 && (keys[i].vert != keys[i - 1].vert || keys[i].side != keys[i - 1].side ||
                      keys[i].u != keys[i - 1].u || keys[i].v != keys[i - 1].v)) g++;
        group[keys[i].corner] = g;
    }
    /* The triangles of each face as the bake rasterises it: the fan from
     * corner 0 (as the renderer of the level triangulates a polygon for a
     * game engine) unless that fan folds over in UV (st_bake_split_polygon). */
    for (uint32_t f = 0; f < nf && !rc; f++) {
        uint32_t a = uvs->corner_off[f], n = uvs->corner_off[f + 1] - a;
        uint32_t local[16][3], (*tris)[3] = n <= 18 ? local : malloc((size_t)n * sizeof *tris);
        if (!tris) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory computing tangents of level %u", l); break; }
        unsigned nt = st_bake_split_polygon(uvs->uv + 2 * (size_t)a, n, tris);
        for (unsigned t = 0; t < nt; t++) {
            uint32_t tri[3] = { a + tris[t][0], a + tris[t][1], a + tris[t][2] };
            add_triangle_frame(m, l, vert, uvs->uv, group, sum, tri);
        }
        if (tris != local) free(tris);
    }
    if (rc) goto done;
    for (size_t c = 0; c < nc; c++) {
        const double *n = vn + 3 * (size_t)vert[c], *s = sum + 6 * (size_t)group[c];
        double *t = tangents + 4 * c;
        double d = dot3(s, n);
        for (int k = 0; k < 3; k++) t[k] = s[k] - d * n[k];
        if (!normalize3(t)) any_orthogonal(n, t);
        double b[3];
        cross3(n, t, b);
        t[3] = dot3(b, s + 3) < 0 ? -1.0 : 1.0;
        if (normals) memcpy(normals + 3 * c, n, 3 * sizeof *n);
    }
done:
    free(darts);
    free(vn);
    free(sum);
    free(vert);
    free(group);
    free(keys);
    return rc;
}

int st_bake_check_scheme(const st_hier *h, st_error *err)
{
    if (h->scheme->id != ST_SCHEME_PROGRESSIVE) return ST_OK;
    return st_fail(err, ST_ERR_INVALID,
                   "baking needs a subdivision hierarchy; %s levels come from edge collapses and carry no UVs above level 0",
                   h->scheme->name);
}
