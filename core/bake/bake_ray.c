/* The bounding volume hierarchy and the rays of the bake
 * (core/bake/bake_ray_internal.h). */
#include "core/bake/bake_ray_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- counts ---------------------------------------------------------------- */

/* The first dart of its face along the face (the smallest id): counts each
 * face once without marker bits, so the estimate can take a const map. */
static int face_leader(const st_map *m, uint32_t d, unsigned l, unsigned *deg)
{
    unsigned k = 0;
    uint32_t x = d;
    int lead = 1;
    do {
        lead &= x >= d;
        k++;
        x = st_face_step(m, x, l);
    } while (x != d && k < 1u << 20);
    *deg = k;
    return lead;
}

uint64_t st_bake_level_triangles(const st_map *m, unsigned l)
{
    uint64_t tris = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d)) continue;
        unsigned deg;
        if (face_leader(m, d, l, &deg) && deg >= 3) tris += deg - 2;
    }
    return tris;
}

/* f(n) = 1 + f(⌊n/2⌋) + f(⌈n/2⌉) above the leaf size, 1 at or below it; the
 * pair (f(m), f(m+1)) follows from (f(k), f(k+1)) with k = ⌊m/2⌋, so the
 * count takes log n steps. */
static void node_pair(uint64_t m, uint64_t *fm, uint64_t *fm1)
{
    if (m + 1 <= ST_BAKE_BVH_LEAF) {
        *fm = 1;
        *fm1 = 1;
        return;
    }
    uint64_t k = m / 2, fk, fk1;
    node_pair(k, &fk, &fk1);
    /* m even: halves k, k; m + 1: k, k + 1.  m odd: k, k + 1; m + 1: k + 1, k + 1. */
    uint64_t f_m = m <= ST_BAKE_BVH_LEAF ? 1 : (m % 2 == 0 ? 1 + 2 * fk : 1 + fk + fk1);
    uint64_t f_m1 = m % 2 == 0 ? 1 + fk + fk1 : 1 + 2 * fk1;
    *fm = f_m;
    *fm1 = f_m1;
}

uint64_t st_bake_bvh_nodes(uint64_t n)
{
    uint64_t f, f1;
    node_pair(n, &f, &f1);
    return f;
}

size_t st_bake_bvh_bytes(uint64_t n)
{
    size_t per_tri = 4 * sizeof(uint32_t) + 3 * sizeof(double);      /* vertices, leaf order; centroids (build) */
    size_t per_node = 2 * sizeof(uint32_t) + 6 * sizeof(double);
    return (size_t)n * per_tri + (size_t)st_bake_bvh_nodes(n) * per_node;
}

/* ---- build ----------------------------------------------------------------- */

typedef struct build_ctx {
    st_bake_bvh *b;
    double *centroid;       /* 3 per triangle */
    uint32_t next;          /* next free node */
} build_ctx;

void st_bake_bvh_free(st_bake_bvh *b)
{
    free(b->tri_vert);
    free(b->leaf_tri);
    free(b->node_first);
    free(b->node_count);
    free(b->node_box);
    memset(b, 0, sizeof *b);
}

static const double *tri_corner(const st_bake_bvh *b, uint32_t t, int k)
{
    return st_pos(b->m, b->tri_vert[3 * (size_t)t + k], b->level);
}

/* Key order of triangles a, b along an axis: centroid, then id. */
static int key_less(const double *c, unsigned axis, uint32_t a, uint32_t b)
{
    double x = c[3 * (size_t)a + axis], y = c[3 * (size_t)b + axis];
    return x < y || (x == y && a < b);
}

static void swap_u32(uint32_t *a, uint32_t *b)
{
    uint32_t t = *a;
    *a = *b;
    *b = t;
}

/* Rearranges idx[0..n) so that idx[k] holds the element of rank k in the key
 * order and no element before it ranks above it (Hoare's selection with a
 * median-of-three pivot).  The key order is total, so which triangles end in
 * each half does not depend on the pivots. */
static void select_rank(uint32_t *idx, uint32_t n, uint32_t k, const double *c, unsigned axis)
{
    uint32_t lo = 0, hi = n - 1;
    while (hi > lo) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (key_less(c, axis, idx[mid], idx[lo])) swap_u32(&idx[mid], &idx[lo]);
        if (key_less(c, axis, idx[hi], idx[lo])) swap_u32(&idx[hi], &idx[lo]);
        if (key_less(c, axis, idx[hi], idx[mid])) swap_u32(&idx[hi], &idx[mid]);
        uint32_t pivot = idx[mid];
        uint32_t i = lo, j = hi;
        while (i <= j) {
            while (key_less(c, axis, idx[i], pivot)) i++;
            while (key_less(c, axis, pivot, idx[j])) j--;
            if (i <= j) {
                swap_u32(&idx[i], &idx[j]);
                i++;
                if (j == 0) break;
                j--;
            }
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else return;
    }
}

/* The node's box over its triangles' corners, widened by a margin far above
 * the rounding of the slab test, so a hit on a triangle is never lost to
 * its box. */
static void node_bounds(build_ctx *c, uint32_t node, uint32_t begin, uint32_t end)
{
    st_bake_bvh *b = c->b;
    double *box = b->node_box + 6 * (size_t)node;
    for (int k = 0; k < 3; k++) { box[k] = INFINITY; box[3 + k] = -INFINITY; }
    for (uint32_t i = begin; i < end; i++)
        for (int j = 0; j < 3; j++) {
            const double *p = tri_corner(b, b->leaf_tri[i], j);
            for (int k = 0; k < 3; k++) {
                box[k] = fmin(box[k], p[k]);
                box[3 + k] = fmax(box[3 + k], p[k]);
            }
        }
    double ext = 0;
    for (int k = 0; k < 3; k++) ext = fmax(ext, fmax(fabs(box[k]), fabs(box[3 + k])));
    double margin = 1e-9 * ext + 1e-300;
    for (int k = 0; k < 3; k++) { box[k] -= margin; box[3 + k] += margin; }
}

static void build_node(build_ctx *c, uint32_t node, uint32_t begin, uint32_t end)
{
    st_bake_bvh *b = c->b;
    node_bounds(c, node, begin, end);
    uint32_t n = end - begin;
    if (n <= ST_BAKE_BVH_LEAF) {
        b->node_first[node] = begin;
        b->node_count[node] = n;
        return;
    }
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t i = begin; i < end; i++) {
        const double *p = c->centroid + 3 * (size_t)b->leaf_tri[i];
        for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], p[k]); hi[k] = fmax(hi[k], p[k]); }
    }
    unsigned axis = 0;
    for (unsigned k = 1; k < 3; k++)
        if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    uint32_t half = n / 2;
    select_rank(b->leaf_tri + begin, n, half, c->centroid, axis);
    uint32_t child = c->next;
    c->next += 2;
    b->node_first[node] = child;
    b->node_count[node] = 0;
    build_node(c, child, begin, begin + half);
    build_node(c, child + 1, begin + half, end);
}

/* Fans of the level's surface faces from their first dart (hole faces have
 * no surface). */
static uint32_t fill_triangles(st_bake_bvh *b, st_map *m, unsigned l, const uint32_t *darts, uint32_t nf)
{
    uint32_t t = 0;
    for (uint32_t f = 0; f < nf; f++) {
        if (!m->face_embedded && st_is_hole(m, darts[f])) continue;
        uint32_t d = darts[f], v0 = st_vert(m, d, l);
        uint32_t x = st_face_step(m, d, l), y = st_face_step(m, x, l);
        while (y != d) {
            uint32_t *tv = b->tri_vert + 3 * (size_t)t++;
            tv[0] = v0;
            tv[1] = st_vert(m, x, l);
            tv[2] = st_vert(m, y, l);
            x = y;
            y = st_face_step(m, y, l);
        }
    }
    return t;
}

int st_bake_bvh_build(st_map *m, unsigned l, st_bake_bvh *b, st_error *err)
{
    memset(b, 0, sizeof *b);
    b->m = m;
    b->level = l;
    uint32_t *darts = NULL, nf = 0;
    int rc = st_bake_level_faces(m, l, &darts, &nf, err);
    if (rc) return rc;
    uint64_t want = 0;
    for (uint32_t f = 0; f < nf; f++) {
        unsigned deg = st_bake_face_degree(m, darts[f], l);
        if (deg >= 3 && (m->face_embedded || !st_is_hole(m, darts[f]))) want += deg - 2;
    }
    if (want == 0 || want >= ST_NIL / 3) {
        free(darts);
        return st_fail(err, ST_ERR_INVALID, "level %u has %s triangles to cast rays at", l, want ? "too many" : "no");
    }
    uint64_t nodes = st_bake_bvh_nodes(want);
    b->tri_vert = malloc(3 * (size_t)want * sizeof *b->tri_vert);
    b->leaf_tri = malloc((size_t)want * sizeof *b->leaf_tri);
    b->node_first = malloc((size_t)nodes * sizeof *b->node_first);
    b->node_count = malloc((size_t)nodes * sizeof *b->node_count);
    b->node_box = malloc(6 * (size_t)nodes * sizeof *b->node_box);
    double *centroid = malloc(3 * (size_t)want * sizeof *centroid);
    if (!b->tri_vert || !b->leaf_tri || !b->node_first || !b->node_count || !b->node_box || !centroid) {
        free(darts);
        free(centroid);
        st_bake_bvh_free(b);
        return st_fail(err, ST_ERR_MEMORY, "out of memory building the ray hierarchy over %llu triangles of level %u",
                       (unsigned long long)want, l);
    }
    b->ntris = fill_triangles(b, m, l, darts, nf);
    free(darts);
    b->nnodes = (uint32_t)nodes;
    for (uint32_t t = 0; t < b->ntris; t++) {
        b->leaf_tri[t] = t;
        for (int k = 0; k < 3; k++)
            centroid[3 * (size_t)t + k] = (tri_corner(b, t, 0)[k] + tri_corner(b, t, 1)[k] + tri_corner(b, t, 2)[k]) / 3;
    }
    build_ctx c = { b, centroid, 1 };
    build_node(&c, 0, 0, b->ntris);
    free(centroid);
    return ST_OK;
}

/* ---- traversal ------------------------------------------------------------- */

/* The interval [*t0, *t1] of the line inside the node's box, clipped to
 * [-reach, reach]; 0 when empty. */
static int box_span(const double *box, const double o[3], const double d[3], double reach, double *t0, double *t1)
{
    double a = -reach, z = reach;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < box[k] || o[k] > box[3 + k]) return 0;
            continue;
        }
        double s = (box[k] - o[k]) / d[k], e = (box[3 + k] - o[k]) / d[k];
        if (s > e) { double x = s; s = e; e = x; }
        if (s > a) a = s;
        if (e < z) z = e;
        if (a > z) return 0;
    }
    *t0 = a;
    *t1 = z;
    return 1;
}

/* The smallest |t| of a span (0 when it holds t = 0). */
static double span_near(double t0, double t1)
{
    if (t0 <= 0 && t1 >= 0) return 0;
    return t0 > 0 ? t0 : -t1;
}

static void sub3(const double *a, const double *b, double *o)
{
    for (int k = 0; k < 3; k++) o[k] = a[k] - b[k];
}

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Möller and Trumbore 1997, for triangles facing d's way (det < 0 when
 * (e1 × e2) · d > 0); weights within a relative 1e-9 of the triangle
 * accepted, so a line through a shared edge is not lost between the two. */
static int hit_triangle(const st_bake_bvh *b, uint32_t t, const double o[3], const double d[3], double *tt, double w[3])
{
    const double *p0 = tri_corner(b, t, 0), *p1 = tri_corner(b, t, 1), *p2 = tri_corner(b, t, 2);
    double e1[3], e2[3], pv[3], tv[3], qv[3];
    sub3(p1, p0, e1);
    sub3(p2, p0, e2);
    cross3(d, e2, pv);
    double det = dot3(e1, pv);
    if (!(det < 0) || !isfinite(det)) return 0;
    double inv = 1.0 / det;
    sub3(o, p0, tv);
    double u = dot3(tv, pv) * inv;
    const double eps = 1e-9;
    if (u < -eps || u > 1 + eps) return 0;
    cross3(tv, e1, qv);
    double v = dot3(d, qv) * inv;
    if (v < -eps || u + v > 1 + eps) return 0;
    *tt = dot3(e2, qv) * inv;
    w[0] = 1 - u - v;
    w[1] = u;
    w[2] = v;
    return isfinite(*tt);
}

int st_bake_bvh_nearest(const st_bake_bvh *b, const double o[3], const double d[3], double reach, st_bake_hit *hit)
{
    hit->tri = ST_NIL;
    hit->t = 0;
    double best = reach;
    /* Depth is at most ⌈log2 n⌉ + 1 (halves), so 64 entries suffice. */
    uint32_t stack[64];
    unsigned top = 0;
    stack[top++] = 0;
    while (top) {
        uint32_t node = stack[--top];
        double t0, t1;
        if (!box_span(b->node_box + 6 * (size_t)node, o, d, best, &t0, &t1)) continue;
        if (b->node_count[node]) {
            for (uint32_t i = b->node_first[node]; i < b->node_first[node] + b->node_count[node]; i++) {
                uint32_t t = b->leaf_tri[i];
                double tt, w[3];
                if (!hit_triangle(b, t, o, d, &tt, w)) continue;
                double a = fabs(tt);
                if (a > best || (a == best && hit->tri != ST_NIL && t > hit->tri)) continue;
                best = a;
                hit->tri = t;
                hit->t = tt;
                memcpy(hit->w, w, sizeof hit->w);
            }
            continue;
        }
        /* The child nearer to t = 0 is popped first (pushed last). */
        uint32_t c = b->node_first[node];
        double a0, a1, b0, b1;
        int in0 = box_span(b->node_box + 6 * (size_t)c, o, d, best, &a0, &a1);
        int in1 = box_span(b->node_box + 6 * (size_t)(c + 1), o, d, best, &b0, &b1);
        if (in0 && in1) {
            int first = span_near(b0, b1) < span_near(a0, a1);
            stack[top++] = first ? c : c + 1;
            stack[top++] = first ? c + 1 : c;
        } else if (in0) {
            stack[top++] = c;
        } else if (in1) {
            stack[top++] = c + 1;
        }
    }
    return hit->tri != ST_NIL;
}

/* ---- reach ----------------------------------------------------------------- */

static void level_box(const st_map *m, unsigned l, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) { lo[k] = INFINITY; hi[k] = -INFINITY; }
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
        const double *p = st_pos(m, v, l);
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
}

void st_bake_level_boxes(const st_map *m, unsigned B, unsigned L, double *diag, double *gap)
{
    double lb[3], hb[3], ll[3], hl[3], d2 = 0, g = 0;
    level_box(m, B, lb, hb);
    level_box(m, L, ll, hl);
    for (int k = 0; k < 3; k++) {
        double e = fmax(hb[k], hl[k]) - fmin(lb[k], ll[k]);
        d2 += e * e;
        g = fmax(g, fmax(fabs(lb[k] - ll[k]), fabs(hb[k] - hl[k])));
    }
    *diag = isfinite(d2) ? sqrt(d2) : 0;
    *gap = isfinite(g) ? g : 0;
}
