/* Face-varying UVs for the schemes that are not primal quadrisections:
 * √3 (Kobbelt 2000; Kraemer 2008 §3.4.2) and Doo-Sabin through its dual
 * encoding (Kraemer 2008 §3.2.1).  Rules: docs/SUBDIVISION-RULES.md §7b.
 *
 * Both schemes describe every vertex of level L by a stencil over level L-1
 * (st_scheme.emit).  The UVs follow the positions' own stencils wherever
 * that is well defined, and the surface's charts elsewhere:
 *   - a fine vertex whose stencil reads only coarse vertices that have one
 *     face-varying value each takes the stencil applied to those values, on
 *     all its corners (so UVs that are an affine function of the positions
 *     stay one at every level, seams or not further away);
 *   - otherwise each fine face is assigned a home: one coarse face whose
 *     chart it uses (faces_of_level).  A corner at a kept vertex (√3) takes the home face's UV
 *     at that vertex.  A corner at a new vertex with source face S (the
 *     coarse face its stencil's frame names: √3's face centre and boundary
 *     points, Doo-Sabin's corner (F, g)) takes the stencil restricted to the
 *     corners of S, renormalised, with S's UVs, when S is the home or meets
 *     it with equal values at every shared vertex; across a seam it takes
 *     the stencil restricted to the home's corners instead (the seam acts as
 *     a boundary: the part of the fine face beyond it is pressed onto it).
 * Value labels of level L: corners of one vertex with bitwise equal UVs
 * share one (the smallest of their dart ids).
 */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/fvar/fvar_internal.h"
#include "core/schemes/scheme.h"

#include <stdlib.h>
#include <string.h>

/* V_UNSEEN: not computed by this step (an adaptive step computes the
 * vertices of the faces it subdivides only). */
enum { V_UNSEEN = 0, V_NONE, V_KEPT, V_SOURCED };
enum { VALUE_NONE = 0, VALUE_ONE, VALUE_MANY };

typedef struct stencil_uv {
    st_map *m;
    unsigned l, L;
    const double *uv;          /* level l: per dart, or per value through idx */
    const uint32_t *val;
    const uint32_t *idx;       /* level l compact (st_fvar_level): per dart its value; NULL: dense */
    double *out;               /* level L, per dart */
    /* level l, per vertex id: whether its corners share one value, and it */
    uint8_t *values;
    double *vuv;
    uint32_t *vdart;           /* a real corner of the vertex */
    uint32_t *face;            /* level l, per dart: its face's id (a dart of it) */
    /* level L, per vertex id */
    uint8_t *kind, *smooth;
    double *suv;
    uint32_t *src_face, *off, *cnt;
    /* the stencils of V_SOURCED vertices that are not smooth, flat */
    uint32_t *src;
    double *w;
    size_t n, cap;
    /* scratch: (weight, u, v) terms of one sum, summed in sorted order */
    double *t;
    size_t tcap;
    int adaptive;              /* write only the corners of vertices computed */
    uint8_t *out_level;        /* when not NULL: L at every corner written */
    uint32_t *out_val;         /* level L's labels, per dart */
    /* Adaptive Doo-Sabin: per dart, its place among its level's darts in a
     * regular level's numbering (core/adapt/adapt_uv.c's order_children);
     * NULL: the map is one regular level, whose scan is that order. */
    const uint32_t *rank;
    int failed;
} stencil_uv;

/* Level l's UV and label at dart d. */
static inline const double *in_uv(const stencil_uv *s, uint32_t d)
{
    return s->uv + 2 * (size_t)(s->idx ? s->idx[d] : d);
}
static inline uint32_t in_val(const stencil_uv *s, uint32_t d)
{
    return s->val[s->idx ? s->idx[d] : d];
}

/* The corner of face f (a dart of level l) at vertex v, or ST_NIL. */
static uint32_t corner_at(const stencil_uv *s, uint32_t f, uint32_t v)
{
    uint32_t x = f;
    do {
        if (st_vert(s->m, x, s->l) == v) return x;
        x = st_face_step(s->m, x, s->l);
    } while (x != f);
    return ST_NIL;
}

/* Dart x comes before dart y in a regular level's scan (level by level,
 * each in the order the level was made: fvar_rules.c's
 * st_fvar_regular_before); on a regular level that is id order. */
static int dart_before(const stencil_uv *s, uint32_t x, uint32_t y)
{
    if (!s->rank) return x < y;
    const uint8_t *ins = s->m->darts.ins;
    if (ins[x] != ins[y]) return ins[x] < ins[y];
    if (ins[x] == 0 || s->rank[x] == s->rank[y]) return x < y;
    return s->rank[x] < s->rank[y];
}

static int push_entry(stencil_uv *s, uint32_t v, double w)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 1024;
        uint32_t *src = realloc(s->src, cap * sizeof *src);
        if (src) s->src = src;
        double *ww = realloc(s->w, cap * sizeof *ww);
        if (ww) s->w = ww;
        if (!src || !ww) return -1;
        s->cap = cap;
    }
    s->src[s->n] = v;
    s->w[s->n++] = w;
    return 0;
}

static int reserve_terms(stencil_uv *s, size_t n)
{
    if (n <= s->tcap) return 0;
    double *t = realloc(s->t, 3 * n * sizeof *t);
    if (!t) return -1;
    s->t = t;
    s->tcap = n;
    return 0;
}

static int cmp_term(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* Σ w (u, v) over the n terms in s->t, and Σ w, summed in the order of
 * the terms sorted by (w, u, v): a stencil lists its terms from whichever
 * dart it was reached by, and the dart ids of an adaptive map are not a
 * regular level's, so the sum is taken in an order that depends on the
 * terms alone - an adaptive step then gives a regular level's values bit
 * for bit (equal terms are interchangeable). */
static double sorted_sum(stencil_uv *s, size_t n, double out[2])
{
    qsort(s->t, n, 3 * sizeof *s->t, cmp_term);
    double acc[2] = { 0, 0 }, sum = 0;
    for (size_t i = 0; i < n; i++) {
        const double *t = s->t + 3 * i;
        acc[0] += t[0] * t[1];
        acc[1] += t[0] * t[2];
        sum += t[0];
    }
    out[0] = acc[0];
    out[1] = acc[1];
    return sum;
}

static void sink(void *ctx, const st_stencil *st)
{
    stencil_uv *s = ctx;
    const st_map *m = s->m;
    uint32_t v = st->fine;
    double u[2] = { 0, 0 };
    int smooth = st->n > 0;
    if (reserve_terms(s, st->n)) { s->failed = 1; return; }
    size_t nt = 0;
    for (uint32_t i = 0; i < st->n; i++) {
        uint32_t a = st->src[i];
        if (s->values[a] != VALUE_ONE) { smooth = 0; continue; }
        s->t[3 * nt] = st->w[i];
        s->t[3 * nt + 1] = s->vuv[2 * (size_t)a];
        s->t[3 * nt + 2] = s->vuv[2 * (size_t)a + 1];
        nt++;
    }
    sorted_sum(s, nt, u);
    s->smooth[v] = (uint8_t)smooth;
    s->suv[2 * (size_t)v] = u[0];
    s->suv[2 * (size_t)v + 1] = u[1];
    if (st->frame_cell == ST_CELL_VERTEX) { s->kind[v] = V_KEPT; return; }
    uint32_t f = st->frame_dart;
    if (st_is_boundary(m, f)) f = st_beta0(m, f, s->l);
    if (st_is_boundary(m, f)) { s->kind[v] = V_NONE; return; }
    s->kind[v] = V_SOURCED;
    s->src_face[v] = s->face[f];
    if (smooth) return; /* its corners never read the stencil again */
    s->off[v] = (uint32_t)s->n;
    s->cnt[v] = st->n;
    for (uint32_t i = 0; i < st->n && !s->failed; i++)
        if (push_entry(s, st->src[i], st->w[i])) s->failed = 1;
}

/* Vertex v's stencil restricted to the corners of face f, renormalised,
 * with f's UVs; 0 when no source lies on f. */
static int restricted(stencil_uv *s, uint32_t v, uint32_t f, double out[2])
{
    double acc[2];
    size_t n = 0;
    if (reserve_terms(s, s->cnt[v])) { s->failed = 1; return 0; }
    for (uint32_t i = 0; i < s->cnt[v]; i++) {
        uint32_t c = corner_at(s, f, s->src[s->off[v] + i]);
        if (c == ST_NIL) continue;
        s->t[3 * n] = s->w[s->off[v] + i];
        s->t[3 * n + 1] = in_uv(s, c)[0];
        s->t[3 * n + 2] = in_uv(s, c)[1];
        n++;
    }
    double sum = sorted_sum(s, n, acc);
    if (sum <= 0) return 0;
    out[0] = acc[0] / sum;
    out[1] = acc[1] / sum;
    return 1;
}

/* Faces a and b of level l share a vertex and hold equal values at every
 * vertex they share (no seam between them). */
static int continuous(const stencil_uv *s, uint32_t a, uint32_t b)
{
    uint32_t x = a, shared = 0;
    do {
        uint32_t y = corner_at(s, b, st_vert(s->m, x, s->l));
        if (y != ST_NIL) {
            if (in_val(s, x) != in_val(s, y)) return 0;
            shared++;
        }
        x = st_face_step(s->m, x, s->l);
    } while (x != a);
    return shared > 0;
}

static void corner_uv(stencil_uv *s, uint32_t x, uint32_t home, double out[2])
{
    uint32_t v = st_vert(s->m, x, s->L);
    const double *p = NULL;
    if (s->smooth[v] || s->kind[v] <= V_NONE) {
        p = s->suv + 2 * (size_t)v;
    } else if (s->kind[v] == V_KEPT) {
        uint32_t c = home != ST_NIL ? corner_at(s, home, v) : ST_NIL;
        p = in_uv(s, c != ST_NIL ? c : s->vdart[v]);
    } else {
        uint32_t S = s->src_face[v];
        if (home == ST_NIL || S == home || continuous(s, S, home) || !restricted(s, v, home, out))
            if (!restricted(s, v, S, out)) p = s->suv + 2 * (size_t)v;
    }
    if (p) { out[0] = p[0]; out[1] = p[1]; }
}

/* Adaptive Doo-Sabin: the corner x, inserted toward L by the split of an
 * edge of M* whose other side stays at level l (adapt_doosabin.c), of a
 * vertex v this step does not compute, in a border triangle (two new
 * vertices and v).  It shows v as v's other corners do (their value, label
 * and level), in the chart of the triangle's home, one of the two faces
 * along the coarse edge, both of which have a corner at v. */
static void border_corner(stencil_uv *s, uint32_t x, uint32_t home)
{
    uint32_t v = st_vert(s->m, x, s->L);
    uint32_t c = home != ST_NIL ? corner_at(s, home, v) : ST_NIL;
    if (c == ST_NIL) c = s->values[v] != VALUE_NONE ? s->vdart[v] : ST_NIL;
    if (c == ST_NIL) return;
    s->out[2 * (size_t)x] = in_uv(s, c)[0];
    s->out[2 * (size_t)x + 1] = in_uv(s, c)[1];
    s->out_val[x] = in_val(s, c);
    if (s->out_level) s->out_level[x] = s->out_level[c];
}

/* Every real face of level L: its home, then its corners.  The home is the
 * coarse face of an old dart that the fine face keeps (√3: each fine
 * triangle keeps one, so the two triangles across a flipped seam edge go
 * one to each side; Doo-Sabin: the F-faces), else the source face among
 * its corners whose first dart a regular level's scan meets first
 * (Doo-Sabin's E- and V-faces; dart_before). */
static void faces_of_level(stencil_uv *s)
{
    st_map *m = s->m;
    unsigned L = s->L;
    int fb = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        uint32_t home = ST_NIL, source = ST_NIL, x = d;
        do {
            st_mark(m, fb, x);
            uint32_t v = st_vert(m, x, L);
            if (m->darts.ins[x] < L && (home == ST_NIL || dart_before(s, s->face[x], home))) home = s->face[x];
            if (s->kind[v] == V_SOURCED && (source == ST_NIL || dart_before(s, s->src_face[v], source)))
                source = s->src_face[v];
            x = st_face_step(m, x, L);
        } while (x != d);
        if (home == ST_NIL) home = source;
        do {
            if (!s->adaptive || s->kind[st_vert(m, x, L)] != V_UNSEEN) {
                corner_uv(s, x, home, s->out + 2 * (size_t)x);
                if (s->out_level) s->out_level[x] = (uint8_t)L;
            } else if (m->face_embedded && m->darts.ins[x] == L) {
                border_corner(s, x, home);
            }
            x = st_face_step(m, x, L);
        } while (x != d);
    }
    st_marker_release(m, fb, L);
}

/* Labels of level L: per vertex, corners with bitwise equal UVs share the
 * smallest of their dart ids. */
static void label_level(stencil_uv *s, uint32_t *label)
{
    st_map *m = s->m;
    unsigned L = s->L;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
        if (st_is_boundary(m, d)) continue;
        if (s->adaptive && s->kind[st_vert(m, d, L)] == V_UNSEEN) continue;
        const double *p = s->out + 2 * (size_t)d;
        uint32_t best = d, y = st_vertex_step(m, d, L);
        while (y != d) {
            const double *q = s->out + 2 * (size_t)y;
            if (!st_is_boundary(m, y) && y < best && !memcmp(p, q, 2 * sizeof *p)) best = y;
            y = st_vertex_step(m, y, L);
        }
        label[d] = best;
    }
}

/* Per vertex of level l: one value or several; per dart: its face's id. */
static void classify_level(stencil_uv *s)
{
    st_map *m = s->m;
    unsigned l = s->l;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d)) continue;
        uint32_t v = st_vert(m, d, l);
        if (s->values[v] == VALUE_NONE) {
            s->values[v] = VALUE_ONE;
            s->vdart[v] = d;
            s->vuv[2 * (size_t)v] = in_uv(s, d)[0];
            s->vuv[2 * (size_t)v + 1] = in_uv(s, d)[1];
        } else if (in_val(s, s->vdart[v]) != in_val(s, d)) {
            s->values[v] = VALUE_MANY;
        }
    }
    int fb = st_marker_reserve(m);
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        /* the face's id: the dart a regular level's scan meets first */
        uint32_t id = d, x = st_face_step(m, d, l);
        for (; s->rank && x != d; x = st_face_step(m, x, l))
            if (dart_before(s, x, id)) id = x;
        x = d;
        do { st_mark(m, fb, x); s->face[x] = id; x = st_face_step(m, x, l); } while (x != d);
    }
    st_marker_release(m, fb, l);
}

static void stencil_free(stencil_uv *s)
{
    free(s->values);
    free(s->vuv);
    free(s->vdart);
    free(s->face);
    free(s->kind);
    free(s->smooth);
    free(s->suv);
    free(s->src_face);
    free(s->off);
    free(s->cnt);
    free(s->src);
    free(s->w);
    free(s->t);
}

/* Level L = l+1's values from level l's: every face of level l when faces
 * is NULL (a regular level), else the n faces of level l that an adaptive
 * map subdivides toward L. */
static int run(const st_subdiv_view *sv, const st_scheme *scheme, unsigned l, const double *uv, const uint32_t *val,
               const uint32_t *idx, const uint32_t *faces, uint32_t n, const uint32_t *rank, double *out_uv, uint32_t *out_val,
               uint8_t *out_level)
{
    st_map *m = sv->map;
    size_t nv = (size_t)m->verts.end + 1, nd = (size_t)m->darts.end + 1;
    stencil_uv s = { .m = m, .L = l + 1, .l = l, .uv = uv, .val = val, .idx = idx, .out = out_uv, .adaptive = faces != NULL,
                     .out_level = out_level, .out_val = out_val, .rank = rank };
    s.values = calloc(nv, 1);
    s.vuv = calloc(2 * nv, sizeof *s.vuv);
    s.vdart = calloc(nv, sizeof *s.vdart);
    s.face = calloc(nd, sizeof *s.face);
    s.kind = calloc(nv, 1);
    s.smooth = calloc(nv, 1);
    s.suv = calloc(2 * nv, sizeof *s.suv);
    s.src_face = calloc(nv, sizeof *s.src_face);
    s.off = calloc(nv, sizeof *s.off);
    s.cnt = calloc(nv, sizeof *s.cnt);
    int rc = -1;
    if (s.values && s.vuv && s.vdart && s.face && s.kind && s.smooth && s.suv && s.src_face && s.off && s.cnt) {
        classify_level(&s);
        if (faces) {
            if (n) scheme->emit(sv, s.L, faces, n, sink, &s);
        } else {
            scheme->emit(sv, s.L, NULL, 0, sink, &s);
        }
        if (!s.failed) faces_of_level(&s);
        if (!s.failed) {
            label_level(&s, out_val);
            rc = 0;
        }
    }
    stencil_free(&s);
    return rc;
}

int st_fvar_refine_stencil(const st_subdiv_view *sv, const st_scheme *scheme, const st_fvar_level *coarse,
                           st_fvar_level *fine)
{
    return run(sv, scheme, sv->map->top - 1, coarse->uv, coarse->val, coarse->idx, NULL, 0, NULL, fine->uv, fine->val, NULL);
}

int st_fvar_stencil_step(const st_subdiv_view *sv, const st_scheme *scheme, unsigned l, const double *uv,
                         const uint32_t *val, const uint32_t *faces, uint32_t n, const uint32_t *rank, double *out_uv,
                         uint32_t *out_val, uint8_t *out_level)
{
    return run(sv, scheme, l, uv, val, NULL, faces, n, rank, out_uv, out_val, out_level);
}
