/* Level faces, normals, UV checks, the nested walk and the UV rasteriser of
 * the bake (core/bake/bake.h). */
#include "core/bake/bake_internal.h"
#include "core/adapt/adapt.h"
#include "core/map/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

unsigned st_bake_face_degree(const st_map *m, uint32_t d, unsigned l)
{
    unsigned k = 0;
    uint32_t x = d;
    do { k++; x = st_face_step(m, x, l); } while (x != d);
    return k;
}

/* The dual encoding's faces as core/map/map_mesh.c lists them: every β1
 * orbit, those with a hole dart or under 3 corners left out. */
static int dual_faces(st_map *m, unsigned l, uint32_t **darts, uint32_t *n, st_error *err)
{
    uint32_t cap = 64, k = 0;
    uint32_t *out = malloc(cap * sizeof *out);
    int bit = out ? st_marker_reserve(m) : -1;
    if (bit < 0) { free(out); return st_fail(err, ST_ERR_MEMORY, "out of memory listing the faces of level %u", l); }
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_marked(m, bit, d)) continue;
        st_mark_vertex(m, bit, d, l);
        uint32_t x = d, deg = 0;
        int real = 1;
        do { real &= !st_is_boundary(m, x); deg++; x = st_beta1(m, x, l); } while (x != d);
        if (!real || deg < 3) continue;
        if (k == cap) {
            uint32_t *g = realloc(out, 2 * (size_t)cap * sizeof *g);
            if (!g) { st_marker_release(m, bit, l); free(out); return st_fail(err, ST_ERR_MEMORY, "out of memory listing the faces of level %u", l); }
            out = g;
            cap *= 2;
        }
        out[k++] = d;
    }
    st_marker_release(m, bit, l);
    *darts = out;
    *n = k;
    return ST_OK;
}

int st_bake_level_faces(st_map *m, unsigned l, uint32_t **darts, uint32_t *n, st_error *err)
{
    if (m->face_embedded) return dual_faces(m, l, darts, n, err);
    st_level_stats s;
    st_level_stats_compute(m, l, &s);
    uint32_t *out = malloc((size_t)(s.faces ? s.faces : 1) * sizeof *out);
    if (!out) return st_fail(err, ST_ERR_MEMORY, "out of memory listing the faces of level %u", l);
    int bit = st_marker_reserve(m);
    if (bit < 0) { free(out); return st_fail(err, ST_ERR_INVALID, "no marker bit left to list the faces of level %u", l); }
    uint32_t k = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, bit, d)) continue;
        st_mark_face(m, bit, d, l);
        if (k < s.faces) out[k] = d;
        k++;
    }
    st_marker_release(m, bit, l);
    *darts = out;
    *n = k < s.faces ? k : (uint32_t)s.faces;
    return ST_OK;
}

int st_bake_vertex_normals(const st_map *m, unsigned l, double **out, st_error *err)
{
    size_t nv = m->verts.end ? m->verts.end : 1;
    double *n = calloc(3 * nv, sizeof *n);
    if (!n) return st_fail(err, ST_ERR_MEMORY, "out of memory computing the normals of level %u", l);
    st_dart_iter it;
    /* Each dart adds its face's Newell vector (twice the area times the
     * normal) to its vertex: every face once per corner. */
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d)) continue;
        double f[3];
        st_face_newell(m, d, l, f);
        double *t = n + 3 * (size_t)st_vert(m, d, l);
        for (int k = 0; k < 3; k++) t[k] += f[k];
    }
    for (size_t v = 0; v < nv; v++) {
        double *t = n + 3 * v;
        double len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        if (!(len > 1e-300) || !isfinite(len)) { t[0] = t[1] = 0; t[2] = 1; continue; }
        for (int k = 0; k < 3; k++) t[k] /= len;
    }
    *out = n;
    return ST_OK;
}

int st_bake_check_uvs(const st_map *m, unsigned l, const uint32_t *darts, uint32_t n, const st_bake_uvs *uvs, st_error *err)
{
    if (!uvs || !uvs->corner_off || !uvs->uv)
        return st_fail(err, ST_ERR_INVALID, "level %u has no UVs", l);
    if (uvs->nfaces != n)
        return st_fail(err, ST_ERR_INVALID, "the UVs describe %u faces but level %u has %u", uvs->nfaces, l, n);
    if (uvs->corner_off[0] != 0)
        return st_fail(err, ST_ERR_INVALID, "the UVs' corner offsets do not start at 0");
    for (uint32_t f = 0; f < n; f++) {
        uint32_t deg = st_bake_face_degree(m, darts[f], l);
        if (uvs->corner_off[f + 1] < uvs->corner_off[f] || uvs->corner_off[f + 1] - uvs->corner_off[f] != deg)
            return st_fail(err, ST_ERR_INVALID, "face %u of level %u has %u corners but %d UVs",
                           f + 1, l, deg, (int)(uvs->corner_off[f + 1] - uvs->corner_off[f]));
        for (uint32_t c = 0; c < deg; c++) {
            const double *uv = uvs->uv + 2 * ((size_t)uvs->corner_off[f] + c);
            if (!isfinite(uv[0]) || !isfinite(uv[1]))
                return st_fail(err, ST_ERR_INVALID, "face %u of level %u: corner %u has no UV", f + 1, l, c + 1);
            /* Any tile is baked (bake.h: tiles and wrap-around); the bound
             * only keeps tile numbers exact in 32-bit integers. */
            if (fabs(uv[0]) > ST_BAKE_UV_MAX || fabs(uv[1]) > ST_BAKE_UV_MAX)
                return st_fail(err, ST_ERR_INVALID, "face %u of level %u: corner %u has UV (%g, %g) beyond ±%g",
                               f + 1, l, c + 1, uv[0], uv[1], ST_BAKE_UV_MAX);
        }
    }
    return ST_OK;
}

/* ---- tiles ----------------------------------------------------------------- */

void st_bake_face_tile(const double *uv, unsigned n, int32_t tile[2])
{
    double s[2] = { 0, 0 };
    for (unsigned c = 0; c < n; c++) { s[0] += uv[2 * c]; s[1] += uv[2 * c + 1]; }
    for (int k = 0; k < 2; k++) {
        double t = n ? floor(s[k] / n) : 0;
        tile[k] = isfinite(t) && fabs(t) <= ST_BAKE_UV_MAX ? (int32_t)t : 0;
    }
}

unsigned st_bake_udim(const int32_t tile[2])
{
    if (tile[0] < 0 || tile[0] > 9 || tile[1] < 0 || tile[1] > 99) return 0;
    return 1001u + (unsigned)tile[0] + 10u * (unsigned)tile[1];
}

void st_bake_tiles_free(st_bake_tiles *t)
{
    free(t->tile);
    free(t->faces);
    memset(t, 0, sizeof *t);
}

/* Tiles in UDIM order: v, then u (1001, 1002, ..., 1011, ...). */
static int tile_before(const int32_t a[2], const int32_t b[2])
{
    return a[1] != b[1] ? a[1] < b[1] : a[0] < b[0];
}

int st_bake_uv_tiles(const st_bake_uvs *uvs, uint32_t size, st_bake_tiles *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    out->first_crossing = out->first_non_udim = UINT32_MAX;
    uint32_t cap = 0;
    for (uint32_t f = 0; f < uvs->nfaces; f++) {
        uint32_t a = uvs->corner_off[f], n = uvs->corner_off[f + 1] - a;
        const double *uv = uvs->uv + 2 * (size_t)a;
        int32_t t[2];
        st_bake_face_tile(uv, n, t);
        uint32_t i = 0;
        while (i < out->ntiles && (out->tile[i][0] != t[0] || out->tile[i][1] != t[1])) i++;
        if (i == out->ntiles) {
            if (i == cap) {
                uint32_t nc = cap ? 2 * cap : 8;
                int32_t (*g)[2] = realloc(out->tile, nc * sizeof *g);
                if (g) out->tile = g;
                uint32_t *h = g ? realloc(out->faces, nc * sizeof *h) : NULL;
                if (!h) { st_bake_tiles_free(out); return st_fail(err, ST_ERR_MEMORY, "out of memory listing UV tiles"); }
                out->faces = h;
                cap = nc;
            }
            /* Insertion in UDIM order. */
            while (i > 0 && tile_before(t, out->tile[i - 1])) {
                memcpy(out->tile[i], out->tile[i - 1], sizeof *out->tile);
                out->faces[i] = out->faces[i - 1];
                i--;
            }
            out->tile[i][0] = t[0];
            out->tile[i][1] = t[1];
            out->faces[i] = 0;
            out->ntiles++;
        }
        out->faces[i]++;
        if (!st_bake_udim(t) && out->first_non_udim == UINT32_MAX) out->first_non_udim = f;
        /* How far the face leaves its tile, against its own UV extent: an
         * overshoot under a texel or a quarter of the face is a UV tool's
         * slack, more is a face laid across the border. */
        double over = 0, lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
        for (uint32_t c = 0; c < n; c++) {
            int outside = 0;
            for (int k = 0; k < 2; k++) {
                double x = uv[2 * c + k];
                lo[k] = fmin(lo[k], x);
                hi[k] = fmax(hi[k], x);
                double o = fmax(t[k] - x, x - (t[k] + 1.0));
                if (o > 0) { outside = 1; over = fmax(over, o); }
            }
            out->corners_outside += (uint64_t)outside;
        }
        double extent = fmax(hi[0] - lo[0], hi[1] - lo[1]);
        if (over > 1.0 / size && over > 0.25 * extent) {
            if (!out->faces_crossing) out->first_crossing = f;
            out->faces_crossing++;
        }
    }
    return ST_OK;
}

/* ---- the nested walk ------------------------------------------------------ */

/* Vertex ids and UVs of the vertices of one refined face at level l+1: its
 * corners, its edge points, its face point (polygon split). */
typedef struct uv_table {
    uint32_t *id;
    double *uv;
    uint32_t n;
} uv_table;

static const double *table_find(const uv_table *t, uint32_t id)
{
    for (uint32_t i = 0; i < t->n; i++)
        if (t->id[i] == id) return t->uv + 2 * (size_t)i;
    return NULL;
}

static void table_add(uv_table *t, uint32_t id, double u, double v)
{
    t->id[t->n] = id;
    t->uv[2 * (size_t)t->n] = u;
    t->uv[2 * (size_t)t->n + 1] = v;
    t->n++;
}

/* Corners of the face of dart c at level l (at most 4: a child of a split)
 * looked up in t; -1 when a vertex is not one of the parent's. */
static int child_face(const st_map *m, uint32_t c, unsigned l, const uv_table *t, uint32_t ids[4], double uv[8])
{
    unsigned k = 0;
    uint32_t x = c;
    do {
        if (k == 4) return -1;
        uint32_t v = st_vert(m, x, l);
        const double *p = table_find(t, v);
        if (!p) return -1;
        ids[k] = v;
        uv[2 * k] = p[0];
        uv[2 * k + 1] = p[1];
        k++;
        x = st_phi1(m, x, l);
    } while (x != c);
    return (int)k;
}

typedef struct walk_ctx {
    st_map *m;
    unsigned L;
    st_bake_face_fn fn;
    void *ctx;
    st_error *err;
} walk_ctx;

static int walk_face(walk_ctx *w, uint32_t d, unsigned l, const uint32_t *ids, const double *uv, unsigned n);

static int not_nested(walk_ctx *w, unsigned l)
{
    return st_fail(w->err, ST_ERR_INVALID,
                   "the faces of level %u do not nest in those of level %u (a face is not split at its corners and edges)",
                   l + 1, l);
}

/* Splits the face of d at level l into its children at level l+1 (thesis
 * §3.2.1: an old dart keeps its vertex, so at level l+1 dart d_i runs along
 * the child at corner i) and walks each. */
static int walk_children(walk_ctx *w, uint32_t d, unsigned l, const uint32_t *ids, const double *uv, unsigned n, uv_table *t)
{
    st_map *m = w->m;
    unsigned f = l + 1;
    double cu = 0, cv = 0;
    t->n = 0;
    for (unsigned i = 0; i < n; i++) {
        table_add(t, ids[i], uv[2 * i], uv[2 * i + 1]);
        cu += uv[2 * i];
        cv += uv[2 * i + 1];
    }
    /* Edge points at the middle of their edge (linear face-varying rule). */
    uint32_t x = d;
    for (unsigned i = 0; i < n; i++) {
        unsigned j = i + 1 < n ? i + 1 : 0;
        uint32_t e = st_vert(m, st_phi1(m, x, f), f);
        if (table_find(t, e)) return not_nested(w, l);
        table_add(t, e, 0.5 * (uv[2 * i] + uv[2 * j]), 0.5 * (uv[2 * i + 1] + uv[2 * j + 1]));
        x = st_phi1(m, x, l);
    }
    unsigned child_deg = st_face_degree(m, d, f);
    if (child_deg == 4) {
        /* Polygon split: the face point at the centroid of the corners. */
        uint32_t c = st_vert(m, st_phi1(m, st_phi1(m, d, f), f), f);
        if (table_find(t, c)) return not_nested(w, l);
        table_add(t, c, cu / n, cv / n);
    } else if (child_deg != 3 || n != 3) {
        return not_nested(w, l);
    }
    uint32_t cids[4];
    double cuv[8];
    x = d;
    for (unsigned i = 0; i < n; i++) {
        int k = child_face(m, x, f, t, cids, cuv);
        if (k != (int)child_deg || cids[0] != ids[i]) return not_nested(w, l);
        int rc = walk_face(w, x, f, cids, cuv, (unsigned)k);
        if (rc) return rc;
        x = st_phi1(m, x, l);
    }
    if (child_deg == 3) {
        /* Triangle quadrisection: the middle triangle of the edge points,
         * across the inner edge of the corner-0 child. */
        uint32_t c = st_phi2(m, st_phi1(m, d, f), f);
        int k = child_face(m, c, f, t, cids, cuv);
        if (k != 3) return not_nested(w, l);
        int rc = walk_face(w, c, f, cids, cuv, 3);
        if (rc) return rc;
    }
    return ST_OK;
}

/* ---- leaves of an adaptive map (HD levels, core/adapt/adapt.h) ---------- */

/* A face of an adaptive map that is not subdivided below level L, as the
 * map of level L holds it: its corners and, on its sides, the vertices that
 * finer neighbours inserted there. */
typedef struct leaf_poly {
    uint32_t *id;
    double *uv;
    unsigned n, cap;
} leaf_poly;

static int leaf_push(walk_ctx *w, leaf_poly *p, uint32_t id, const double *uv)
{
    if (p->n == p->cap) {
        unsigned cap = p->cap ? 2 * p->cap : 16;
        uint32_t *i = realloc(p->id, cap * sizeof *i);
        if (i) p->id = i;
        double *u = i ? realloc(p->uv, 2 * (size_t)cap * sizeof *u) : NULL;
        if (!u) return st_fail(w->err, ST_ERR_MEMORY, "out of memory listing the sides of an adaptive face");
        p->uv = u;
        p->cap = cap;
    }
    p->id[p->n] = id;
    p->uv[2 * (size_t)p->n] = uv[0];
    p->uv[2 * (size_t)p->n + 1] = uv[1];
    p->n++;
    return ST_OK;
}

/* The points inside the side of dart x (level j) from UV a to UV b, in
 * order along φ1.  A split at j+1 puts the midpoint's dart (inserted at
 * j+1) after x; an edge not split at j+1 never is later (faces of level
 * j+1 have only split or new sides), so the recursion stops there.  Each
 * point takes the middle of its half-side in UV, as walk_children does. */
static int leaf_side(walk_ctx *w, leaf_poly *p, uint32_t x, unsigned j, const double *a, const double *b)
{
    if (j >= w->L) return ST_OK;
    uint32_t y = st_phi1(w->m, x, j + 1);
    if (w->m->darts.ins[y] != j + 1) return ST_OK;
    double mid[2] = { 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]) };
    int rc = leaf_side(w, p, x, j + 1, a, mid);
    if (!rc) rc = leaf_push(w, p, st_vert(w->m, y, j + 1), mid);
    if (!rc) rc = leaf_side(w, p, y, j + 1, mid, b);
    return rc;
}

/* Bakes the leaf face of d (level l < L) as the level-L map shows it. */
static int walk_leaf(walk_ctx *w, uint32_t d, unsigned l, const uint32_t *ids, const double *uv, unsigned n)
{
    leaf_poly p = { NULL, NULL, 0, 0 };
    int rc = ST_OK;
    uint32_t x = d;
    for (unsigned i = 0; i < n && !rc; i++) {
        unsigned j = i + 1 < n ? i + 1 : 0;
        rc = leaf_push(w, &p, ids[i], uv + 2 * i);
        if (!rc) rc = leaf_side(w, &p, x, l, uv + 2 * i, uv + 2 * j);
        x = st_phi1(w->m, x, l);
    }
    if (!rc) rc = w->fn(w->ctx, p.id, p.uv, p.n);
    free(p.id);
    free(p.uv);
    return rc;
}

/* Whether the face of d (level l < L) is subdivided toward l+1.  In a
 * uniform hierarchy always; the quick test reads it from the two darts
 * after d at l+1 (a split side, then an inner edge: both inserted at l+1;
 * a face left alone has an old dart there), and the adaptive reading of
 * the face's level (st_face_is_subdivided) confirms a "no", so a uniform
 * walk never pays for it. */
static int is_subdivided(st_map *m, uint32_t d, unsigned l)
{
    unsigned f = l + 1;
    uint32_t y = st_phi1(m, d, f);
    if (m->darts.ins[y] == f && m->darts.ins[st_phi1(m, y, f)] == f) return 1;
    return st_face_is_subdivided(m, d, l);
}

static int walk_face(walk_ctx *w, uint32_t d, unsigned l, const uint32_t *ids, const double *uv, unsigned n)
{
    if (l == w->L) return w->fn(w->ctx, ids, uv, n);
    if (!is_subdivided(w->m, d, l)) return walk_leaf(w, d, l, ids, uv, n);
    if (n <= 4) {
        uint32_t tid[9];
        double tuv[18];
        uv_table t = { tid, tuv, 0 };
        return walk_children(w, d, l, ids, uv, n, &t);
    }
    uv_table t = { malloc((2 * (size_t)n + 1) * sizeof *t.id), malloc((2 * (size_t)n + 1) * 2 * sizeof *t.uv), 0 };
    int rc = (t.id && t.uv) ? walk_children(w, d, l, ids, uv, n, &t)
                            : st_fail(w->err, ST_ERR_MEMORY, "out of memory splitting a %u-gon", n);
    free(t.id);
    free(t.uv);
    return rc;
}

int st_bake_walk(st_map *m, uint32_t d, unsigned B, unsigned L, const double *uv, unsigned n,
                 st_bake_face_fn fn, void *ctx, st_error *err)
{
    uint32_t *ids = malloc((size_t)(n ? n : 1) * sizeof *ids);
    if (!ids) return st_fail(err, ST_ERR_MEMORY, "out of memory walking a %u-gon", n);
    uint32_t x = d;
    for (unsigned i = 0; i < n; i++) {
        ids[i] = st_vert(m, x, B);
        x = st_phi1(m, x, B);
    }
    walk_ctx w = { m, L, fn, ctx, err };
    int rc = walk_face(&w, d, B, ids, uv, n);
    free(ids);
    return rc;
}

/* ---- the rasteriser ------------------------------------------------------ */

static double cross2(const double *a, const double *b, const double *p)
{
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

/* ---- splitting a UV polygon into triangles ------------------------------- */

static const double *corner_uv(const double *uv, uint32_t i) { return uv + 2 * (size_t)i; }

/* Twice the signed area of the polygon (shoelace). */
static double polygon_area2(const double *uv, unsigned n)
{
    double a = 0;
    for (unsigned i = 0; i < n; i++) {
        const double *p = corner_uv(uv, i), *q = corner_uv(uv, i + 1 < n ? i + 1 : 0);
        a += p[0] * q[1] - q[0] * p[1];
    }
    return a;
}

static unsigned fan(unsigned n, uint32_t (*tri)[3])
{
    for (unsigned t = 0; t + 2 < n; t++) {
        tri[t][0] = 0;
        tri[t][1] = t + 1;
        tri[t][2] = t + 2;
    }
    return n >= 2 ? n - 2 : 0;
}

/* The fan from corner 0 covers the polygon once when no fan triangle turns
 * against the polygon's orientation. */
static int fan_valid(const double *uv, unsigned n, double orient)
{
    for (unsigned t = 0; t + 2 < n; t++)
        if (cross2(corner_uv(uv, 0), corner_uv(uv, t + 1), corner_uv(uv, t + 2)) * orient < 0) return 0;
    return 1;
}

/* Point p inside or on triangle (a, b, c) of orientation orient. */
static int in_triangle(const double *a, const double *b, const double *c, const double *p, double orient)
{
    return cross2(a, b, p) * orient >= 0 && cross2(b, c, p) * orient >= 0 && cross2(c, a, p) * orient >= 0;
}

/* Corner i of the remaining polygon rest[0..m) is an ear: convex, and no
 * other remaining corner (at another position) inside its triangle. */
static int is_ear(const double *uv, const uint32_t *rest, unsigned m, unsigned i, double orient)
{
    const double *a = corner_uv(uv, rest[(i + m - 1) % m]), *b = corner_uv(uv, rest[i]), *c = corner_uv(uv, rest[(i + 1) % m]);
    if (cross2(a, b, c) * orient <= 0) return 0;
    for (unsigned j = 0; j < m; j++) {
        const double *p = corner_uv(uv, rest[j]);
        if (p == a || p == b || p == c) continue;
        if ((p[0] == a[0] && p[1] == a[1]) || (p[0] == c[0] && p[1] == c[1])) continue;
        if (in_triangle(a, b, c, p, orient)) return 0;
    }
    return 1;
}

/* Ear clipping (Meisters 1975); rest holds n corner indices.  A polygon
 * with no ear left (self-intersecting in UV) ends as a fan of the rest. */
static unsigned ear_clip(const double *uv, unsigned n, double orient, uint32_t *rest, uint32_t (*tri)[3])
{
    unsigned m = n, k = 0;
    for (unsigned i = 0; i < n; i++) rest[i] = i;
    while (m > 3) {
        unsigned i = 0;
        while (i < m && !is_ear(uv, rest, m, i, orient)) i++;
        if (i == m) break;
        tri[k][0] = rest[(i + m - 1) % m];
        tri[k][1] = rest[i];
        tri[k][2] = rest[(i + 1) % m];
        k++;
        memmove(rest + i, rest + i + 1, (m - i - 1) * sizeof *rest);
        m--;
    }
    for (unsigned t = 0; t + 2 < m; t++, k++) {
        tri[k][0] = rest[0];
        tri[k][1] = rest[t + 1];
        tri[k][2] = rest[t + 2];
    }
    return k;
}

unsigned st_bake_split_polygon(const double *uv, unsigned n, uint32_t (*tri)[3])
{
    double orient = polygon_area2(uv, n);
    if (n <= 3 || orient == 0 || !isfinite(orient) || fan_valid(uv, n, orient)) return fan(n, tri);
    uint32_t local[64];
    uint32_t *rest = n <= 64 ? local : malloc(n * sizeof *rest);
    if (!rest) return fan(n, tri);
    unsigned k = ear_clip(uv, n, orient, rest, tri);
    if (rest != local) free(rest);
    return k;
}

/* The edge function of a→b at p computed with the endpoints in a canonical
 * order, so the two triangles of a shared edge get exactly opposite values
 * and the tie rule below gives a centre on the edge to exactly one. */
static double edge_fn(const double *a, const double *b, const double *p)
{
    if (a[0] > b[0] || (a[0] == b[0] && a[1] > b[1])) return -cross2(b, a, p);
    return cross2(a, b, p);
}

/* On a counter-clockwise triangle, the edge a→b owns the centres on it when
 * it points this way (the opposite direction never does). */
static int owns_edge(const double *a, const double *b)
{
    double dx = b[0] - a[0], dy = b[1] - a[1];
    return dy > 0 || (dy == 0 && dx < 0);
}

int st_bake_barycentric(const double t[3][2], const double p[2], double w[3])
{
    double area = cross2(t[0], t[1], t[2]);
    if (area == 0 || !isfinite(area)) return 0;
    w[0] = edge_fn(t[1], t[2], p) / area;
    w[1] = edge_fn(t[2], t[0], p) / area;
    w[2] = 1.0 - w[0] - w[1];
    return 1;
}

static int clamp_texel(double x, uint32_t size)
{
    if (x < 0) return 0;
    if (x > (double)size - 1) return (int)size - 1;
    return (int)x;
}

void st_bake_raster_tri(const double t[3][2], uint32_t size, st_bake_texel_fn fn, void *ctx)
{
    double area = cross2(t[0], t[1], t[2]);
    if (area == 0 || !isfinite(area)) return;
    /* Counter-clockwise order o[] of the corners. */
    int o[3] = { 0, 1, 2 };
    if (area < 0) { o[1] = 2; o[2] = 1; area = -area; }
    const double *a = t[o[0]], *b = t[o[1]], *c = t[o[2]];
    double lo[2], hi[2];
    for (int k = 0; k < 2; k++) {
        lo[k] = fmin(a[k], fmin(b[k], c[k])) * size - 0.5;
        hi[k] = fmax(a[k], fmax(b[k], c[k])) * size - 0.5;
    }
    if (hi[0] < 0 || hi[1] < 0 || lo[0] > (double)size - 1 || lo[1] > (double)size - 1) return;
    int x0 = clamp_texel(ceil(lo[0]), size), x1 = clamp_texel(floor(hi[0]), size);
    int y0 = clamp_texel(ceil(lo[1]), size), y1 = clamp_texel(floor(hi[1]), size);
    int own_ab = owns_edge(a, b), own_bc = owns_edge(b, c), own_ca = owns_edge(c, a);
    for (int y = y0; y <= y1; y++) {
        double p[2] = { 0, (y + 0.5) / size };
        for (int x = x0; x <= x1; x++) {
            p[0] = (x + 0.5) / size;
            double eab = edge_fn(a, b, p), ebc = edge_fn(b, c, p), eca = edge_fn(c, a, p);
            if (eab < 0 || ebc < 0 || eca < 0) continue;
            if ((eab == 0 && !own_ab) || (ebc == 0 && !own_bc) || (eca == 0 && !own_ca)) continue;
            double wo[3] = { ebc / area, eca / area, eab / area }, w[3];
            for (int k = 0; k < 3; k++) w[o[k]] = wo[k];
            fn(ctx, (uint32_t)x, (uint32_t)y, w);
        }
    }
}
