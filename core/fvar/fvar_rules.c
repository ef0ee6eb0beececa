/* The face-varying rules of one refinement step (fvar_internal.h:
 * st_fvar_step), shared by the regular levels (fvar.c) and the adaptive
 * meshes (core/adapt/adapt_uv.c), so that both compute every child with
 * the same arithmetic, term for term and in the same order: an adaptive
 * mesh's values are the regular level's bit for bit (tests/core/test_adapt_uv.c).
 * The rules are OpenSubdiv's; fvar.c's opening comment and
 * docs/SUBDIVISION-RULES.md §7b describe them. */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/fvar/fvar_internal.h"
#include "core/map/pool_internal.h"
#include "core/base/parallel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SHARP_INF 10.0f

static void put2(double *a, uint32_t d, double u, double v)
{
    a[2 * (size_t)d] = u;
    a[2 * (size_t)d + 1] = v;
}

static const double *at2(const double *a, uint32_t d) { return a + 2 * (size_t)d; }

/* ---- level views ---------------------------------------------------------------- */

static float view_float(const st_u32_view *r, const uint8_t *ins, uint32_t i)
{
    uint32_t bits = st_view_get(r, ins, i);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* st_level_view_init without the positions: a step reads connectivity
 * only, so it may run beside a thread that writes positions (whose first
 * write at a level materialises the column a view would read). */
static void connectivity_view(const st_map *m, unsigned l, st_level_view *v)
{
    *v = (st_level_view){ .ins = m->darts.ins, .vins = m->verts.ins };
    v->beta0 = st_u32_view_of(&m->beta0, l);
    v->beta1 = st_u32_view_of(&m->beta1, l);
    v->vert = st_u32_view_of(&m->vert, l);
}

/* Takes the views of levels l and L (fvar_internal.h: st_fvar_step). */
static void take_views(st_fvar_step *w)
{
    connectivity_view(w->m, w->l, &w->vl);
    connectivity_view(w->m, w->L, &w->vL);
    w->has_sharpness = w->sv.has_sharpness;
    if (w->has_sharpness) {
        w->esharp = st_u32_view_of(w->sv.edge_sharp, w->l);
        w->vsharp = st_u32_view_of(w->sv.vertex_sharp, w->l);
    }
    w->viewed = w->l + 1;
}

static uint32_t b0l(const st_fvar_step *w, uint32_t d) { return st_v_beta0(&w->vl, d); }
static uint32_t b1l(const st_fvar_step *w, uint32_t d) { return st_v_beta1(&w->vl, d); }
static uint32_t phi1l(const st_fvar_step *w, uint32_t d) { return st_v_phi1(&w->vl, d); }
static uint32_t phi1L(const st_fvar_step *w, uint32_t d) { return st_v_phi1(&w->vL, d); }

/* st_subdiv_edge_sharpness and st_subdiv_vertex_sharpness at level l. */
static float sharp_of_edge(const st_fvar_step *w, uint32_t d)
{
    return w->has_sharpness ? view_float(&w->esharp, w->vl.ins, d) : 0;
}

static float sharp_of_vertex(const st_fvar_step *w, uint32_t v)
{
    return w->has_sharpness ? view_float(&w->vsharp, w->vl.vins, v) : 0;
}

/* Level l's UV and label at dart d, per value or per dart (st_fvar_step.idx). */
static inline const double *in_uv(const st_fvar_step *w, uint32_t d)
{
    return w->uv + 2 * (size_t)(w->idx ? w->idx[d] : d);
}
static inline uint32_t in_val(const st_fvar_step *w, uint32_t d)
{
    return w->val[w->idx ? w->idx[d] : d];
}

static void put_child(const st_fvar_step *w, uint32_t x, const double p[2], uint32_t label)
{
    put2(w->out_uv, x, p[0], p[1]);
    w->out_val[x] = label;
    if (w->out_level) w->out_level[x] = (uint8_t)w->L;
}

/* The face child of the coarse face of d (Catmull-Clark, quad children);
 * an adaptive map keeps every face's centroid, subdivided or not. */
static inline const double *face_child(const st_fvar_step *w, uint32_t d)
{
    if (w->fc) return at2(w->out_uv, w->fc[d]);  /* all quads: all set */
    if (w->cent) return at2(w->cent, d);
    return at2(w->out_uv, phi1L(w, phi1L(w, d)));
}

static int linear_boundaries(int interp) { return interp == ST_UV_BOUNDARIES || interp == ST_UV_ALL; }

static float edge_sharp(const st_fvar_step *w, uint32_t d)
{
    if (st_is_boundary(w->m, b0l(w, d))) return SHARP_INF;
    return sharp_of_edge(w, d);
}

static float decay(float s) { return s >= SHARP_INF ? SHARP_INF : (s > 1.0f ? s - 1.0f : 0.0f); }

/* The edge of corner d is a face-varying boundary: the values at one of
 * its ends differ between its two faces (t = β0(d) real).  β0 is an
 * involution, so φ1(t) = β1(d) and φ1(d) = β1(t). */
static int discontinuous(const st_fvar_step *w, uint32_t d)
{
    uint32_t t = b0l(w, d);
    return in_val(w, d) != in_val(w, b1l(w, d)) || in_val(w, b1l(w, t)) != in_val(w, t);
}

/* x comes before y in the scan of a regular level (st_dart_first/next:
 * level by level, each in the order the level was made; an adaptive map
 * interleaves levels, and w->rank restores that order). */
int st_fvar_regular_before(const st_fvar_step *w, uint32_t x, uint32_t y)
{
    const uint8_t *ins = w->m->darts.ins;
    if (ins[x] != ins[y]) return ins[x] < ins[y];
    if (ins[x] == 0 || w->rank[x] == w->rank[y]) return x < y;
    return w->rank[x] < w->rank[y];
}

/* The dart a regular level's scan meets first on the face of d at level l
 * (d itself on a regular level, whose scan found d first). */
static uint32_t oldest_dart(const st_fvar_step *w, uint32_t d)
{
    if (!w->rank) return d;
    uint32_t b = d, x = phi1l(w, d);
    while (x != d) {
        if (st_fvar_regular_before(w, x, b)) b = x;
        x = phi1l(w, x);
    }
    return b;
}

/* The child face of corner x at L is a quad: φ1 at L comes back after
 * four steps, not before. */
static int quad_child(const st_fvar_step *w, uint32_t x)
{
    uint32_t b = phi1L(w, phi1L(w, x)), c = phi1L(w, b);
    return b != x && c != x && phi1L(w, c) == x;
}

/* The centroid of the face of f at level l (an adaptive map keeps every
 * face's in w->cent), the face child when it is split into quads.  The sum
 * starts at the corner a regular level's scan meets first. */
static void face_child_of(st_fvar_step *w, uint32_t f)
{
    st_map *m = w->m;
    unsigned l = w->l;
    if (!w->cent && !quad_child(w, f)) { w->tri_splits++; return; }  /* a triangle split: no face child */
    uint32_t d = oldest_dart(w, f);
    double s[2] = {0, 0};
    unsigned n = 0;
    uint32_t x = d;
    do {
        const double *q = in_uv(w, x);
        s[0] += q[0];
        s[1] += q[1];
        n++;
        x = phi1l(w, x);
    } while (x != d);
    double c[2] = { s[0] / n, s[1] / n };
    int sub = w->split_toward ? w->split_toward(m, d, l) : 1;
    if (w->cent || w->sub) {
        do {
            if (w->cent) put2(w->cent, x, c[0], c[1]);
            if (w->sub) w->sub[x] = (uint8_t)sub;
            x = phi1l(w, x);
        } while (x != d);
    }
    if (!sub) return;
    if (w->cent && !quad_child(w, d)) { w->tri_splits++; return; }
    do {
        uint32_t y = phi1L(w, phi1L(w, x));
        put_child(w, y, c, 0);
        if (w->fchild) w->fchild[x] = y;
        x = phi1l(w, x);
    } while (x != d);
}

/* face_child_of on a regular level (every face subdivided, the scan's
 * order its own), in one walk of the face at l that also marks it seen. */
static void regular_face_child(st_fvar_step *w, uint32_t f, uint64_t *seen)
{
    uint32_t cs[16], n = 0, x = f;
    double s[2] = {0, 0};
    do {
        seen[x >> 6] |= 1ull << (x & 63);
        if (n < 16) cs[n] = x;
        const double *q = in_uv(w, x);
        s[0] += q[0];
        s[1] += q[1];
        n++;
        x = phi1l(w, x);
    } while (x != f);
    if (n > 16) { face_child_of(w, f); return; }
    uint32_t y = phi1L(w, phi1L(w, f)), z = phi1L(w, y);
    if (y == f || z == f || phi1L(w, z) != f) { w->tri_splits++; return; }  /* quad_child(w, f) */
    double c[2] = { s[0] / n, s[1] / n };
    /* The child quads meet at the face child: β1 at L turns around it from
     * the quad of corner i to that of corner i-1 (their shared inner edge
     * runs to the midpoint of edge i-1), so one lookup per corner finds
     * φ1²(cs[i]) at L. */
    for (uint32_t k = 0; k < n; k++) {
        uint32_t i = k ? n - k : 0;
        if (k) y = st_v_beta1(&w->vL, y);
        put_child(w, y, c, 0);
        if (w->fchild) w->fchild[cs[i]] = y;
    }
}

/* The dart ids of levels 0..l: the scratch indexed by level l's darts
 * needs no room for those of finer levels the map may already hold
 * (st_fvar_refine_levels). */
static uint32_t darts_of_level(const st_fvar_step *w) { return st_pool_cover(&w->m->darts, w->l + 1); }

/* Faces are met once each: a bit per dart id (no marker to release). */
int st_fvar_face_children(st_fvar_step *w)
{
    take_views(w);
    st_map *m = w->m;
    uint32_t nd = darts_of_level(w);
    uint64_t *seen = calloc((size_t)nd / 64 + 1, sizeof *seen);
    if (!seen) return -1;
    /* Only the Catmull-Clark rules read face children back; an adaptive
     * map's are in w->cent. */
    if (!w->cent && w->rules == ST_FVAR_CATMARK && w->cap_fchild < nd) {
        uint32_t *g = realloc(w->fchild, (size_t)nd * sizeof *g);
        if (!g) { free(seen); return -1; }
        w->fchild = g;
        w->cap_fchild = nd;
    }
    w->faced = w->edged = 0;
    w->tri_splits = 0;
    w->fc = NULL;
    int regular = !w->cent && !w->sub && !w->rank && !w->split_toward;
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, w->l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
        if (regular) { regular_face_child(w, d, seen); continue; }
        uint32_t x = d;
        do {
            seen[x >> 6] |= 1ull << (x & 63);
            x = phi1l(w, x);
        } while (x != d);
        face_child_of(w, d);
    }
    free(seen);
    w->faced = w->l + 1;
    if (!w->cent && !w->tri_splits) w->fc = w->fchild;
    return 0;
}

/* The child of the edge of d on d's side (OpenSubdiv's edge masks); the
 * edge is a face-varying boundary (discontinuous) or not. */
static inline __attribute__((always_inline)) int edge_child(const st_fvar_step *w, uint32_t d)
{
    st_map *m = w->m;
    uint32_t t = b0l(w, d), n = b1l(w, t);
    const double *a = in_uv(w, d), *b = in_uv(w, n);
    double mid[2] = { (a[0] + b[0]) / 2, (a[1] + b[1]) / 2 }, p[2];
    int hole = st_is_boundary(m, t);
    int disc = !hole && (in_val(w, d) != in_val(w, b1l(w, d)) || in_val(w, n) != in_val(w, t));  /* discontinuous(w, d) */
    uint32_t label = disc ? d : (hole || d < t ? d : t);
    float s = hole ? SHARP_INF : sharp_of_edge(w, d);
    if (w->rules == ST_FVAR_LINEAR || w->interp == ST_UV_ALL || hole || disc || s >= 1.0f) {
        p[0] = mid[0];
        p[1] = mid[1];
    } else {
        if (w->rules == ST_FVAR_CATMARK) {
            const double *f0 = face_child(w, d), *f1 = face_child(w, t);
            for (int k = 0; k < 2; k++) p[k] = (a[k] + b[k] + f0[k] + f1[k]) / 4;
        } else {
            const double *o0 = in_uv(w, phi1l(w, n)), *o1 = in_uv(w, phi1l(w, b1l(w, d)));
            for (int k = 0; k < 2; k++) p[k] = 0.375 * (a[k] + b[k]) + 0.125 * (o0[k] + o1[k]);
        }
        /* A semi-sharp edge below 1 blends the crease and smooth masks by
         * its sharpness (Sdc::Scheme::ComputeEdgeVertexMask). */
        double wc = s > 0 ? s : 0;
        for (int k = 0; k < 2; k++) p[k] = wc * mid[k] + (1 - wc) * p[k];
    }
    /* At L, t runs from n's vertex to the midpoint: its β0 there is the
     * half of d's edge that ends at n's vertex, φ1⁻¹(n) at L. */
    put_child(w, phi1L(w, d), p, label);
    put_child(w, st_v_beta0(&w->vL, t), p, label);
    return disc;
}

void st_fvar_edge_child(st_fvar_step *w, uint32_t d)
{
    if (w->viewed != w->l + 1) take_views(w);
    edge_child(w, d);
}

/* The edge pass over the blocks [begin, end) of a list of first ids (the
 * scan's blocks): each real dart's edge child on its side, and its
 * discontinuity. */
static void edge_children_of_blocks(const st_fvar_step *s, const uint32_t *first, uint32_t begin, uint32_t end, uint8_t *disc)
{
    const st_map *m = s->m;
    for (uint32_t b = begin; b < end; b++)
        for (uint32_t d = first[b]; d < first[b] + ST_POOL_BLOCK && d < m->darts.end; d++) {
            if (m->darts.ins[d] == ST_FREE_LEVEL || st_is_boundary(m, d)) continue;
            int dc = edge_child(s, d);
            if (disc) disc[d] = (uint8_t)dc;
        }
}

typedef struct edge_job {
    const st_fvar_step *s;
    const uint32_t *first;
    uint32_t nblocks;
    uint8_t *disc;
} edge_job;

enum { EDGE_CHUNK = 16 };   /* blocks of ST_POOL_BLOCK darts per piece of work */

static void edge_part(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    edge_job *j = ctx;
    uint32_t b, e;
    while (st_team_next(team, 0, j->nblocks, EDGE_CHUNK, &b, &e)) edge_children_of_blocks(j->s, j->first, b, e, j->disc);
}

/* Every real dart's discontinuity is kept for the vertex pass, when the
 * memory for it is there (else that pass works it out again).  Each dart
 * writes its own two children and its own flag from level l's values
 * only, so the pass runs on the threads of a team (core/base/parallel.h)
 * with the same bits on any number of them; a small level stays on one. */
void st_fvar_edge_children(st_fvar_step *w)
{
    take_views(w);
    st_map *m = w->m;
    w->edged = 0;
    uint32_t nd = darts_of_level(w);
    if (w->cap_disc < nd) {
        free(w->disc);
        w->disc = malloc(nd);
        w->cap_disc = w->disc ? nd : 0;
    }
    /* A copy that the children's stores cannot reach: its fields and
     * views stay in registers across the loop. */
    const st_fvar_step s = *w;
    uint8_t *disc = w->disc;
    uint32_t nb = st_pool_block_list(&m->darts, s.l, NULL);
    uint32_t *first = malloc((size_t)(nb ? nb : 1) * sizeof *first);
    unsigned threads = st_parallel_threads(), most = nb / (4 * EDGE_CHUNK);
    if (threads > most) threads = most ? most : 1;
    if (threads > ST_PARALLEL_MAX) threads = ST_PARALLEL_MAX;
    if (first && threads > 1) {
        st_pool_block_list(&m->darts, s.l, first);
        edge_job j = { &s, first, nb, disc };
        st_team_run(threads, edge_part, &j);
    } else {
        st_fvar_scan it;
        st_fvar_scan_init(&it, m, 0, s.l);
        for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
            if (st_is_boundary(m, d)) continue;
            int dc = edge_child(&s, d);
            if (disc) disc[d] = (uint8_t)dc;
        }
    }
    free(first);
    if (disc) w->edged = w->l + 1;
}

/* ---- vertex children --------------------------------------------------------- */

/* One vertex of level l: corners c[0..n) in β1 order (the face across the
 * outgoing edge of c[j] is c[j+1]'s), starting after the hole's dart when
 * the vertex is on the boundary. */
typedef struct vert {
    uint32_t *c, n;
    uint32_t hole;      /* the hole's dart at the vertex, or ST_NIL */
} vert;

/* The corner before c[j] in its face: the far end of c[j]'s incoming edge. */
static uint32_t prev_corner(const st_fvar_step *w, const vert *v, uint32_t j)
{
    uint32_t p = j ? v->c[j - 1] : (v->hole != ST_NIL ? v->hole : v->c[v->n - 1]);
    return b0l(w, p);
}

/* The vertex child's corners are the coarse corners themselves (old
 * darts keep their vertex) and keep their labels. */
static void put_vertex(st_fvar_step *w, uint32_t d, const double p[2])
{
    put_child(w, d, p, in_val(w, d));
}

static void set_all(st_fvar_step *w, const vert *v, const double p[2])
{
    for (uint32_t j = 0; j < v->n; j++) put_vertex(w, v->c[j], p);
}

static void keep_all(st_fvar_step *w, const vert *v)
{
    for (uint32_t j = 0; j < v->n; j++) put_vertex(w, v->c[j], in_uv(w, v->c[j]));
}

enum vrule { RULE_SMOOTH, RULE_CREASE, RULE_CORNER };

/* The vertex rule from its sharpness and its incident edges' (the
 * parent's, or decayed for the child's; w->sharp holds edge_sharp of each
 * corner), and a crease's two far ends. */
static enum vrule rule_of(const st_fvar_step *w, const vert *v, float vs, int child, const double **ends)
{
    uint32_t nsharp = 0;
    uint32_t ne = v->n + (v->hole != ST_NIL);
    for (uint32_t j = 0; j < ne; j++) {
        float s = j < v->n ? w->sharp[j] : SHARP_INF;
        if (child) s = decay(s);
        if (s <= 0) continue;
        if (nsharp < 2) ends[nsharp] = j < v->n ? in_uv(w, phi1l(w, v->c[j])) : in_uv(w, prev_corner(w, v, 0));
        nsharp++;
    }
    if (child) vs = decay(vs);
    if (vs > 0 || nsharp > 2) return RULE_CORNER;
    return nsharp == 2 ? RULE_CREASE : RULE_SMOOTH;
}

static void smooth_mask(const st_fvar_step *w, const vert *v, double out[2])
{
    const double *p = in_uv(w, v->c[0]);
    double n = v->n, se[2] = {0, 0}, sf[2] = {0, 0};
    for (uint32_t j = 0; j < v->n; j++) {
        const double *e = in_uv(w, phi1l(w, v->c[j]));
        const double *f = w->rules == ST_FVAR_CATMARK ? face_child(w, v->c[j]) : e;
        for (int k = 0; k < 2; k++) { se[k] += e[k]; sf[k] += f[k]; }
    }
    if (w->rules == ST_FVAR_CATMARK) {
        for (int k = 0; k < 2; k++) out[k] = (n - 2) / n * p[k] + (se[k] + sf[k]) / (n * n);
    } else {
        double c = cos(M_PI * 2.0 / n), b = 0.25 * c + 0.375, ew = (0.625 - b * b) / n;
        for (int k = 0; k < 2; k++) out[k] = (1 - n * ew) * p[k] + ew * se[k];
    }
}

static void rule_mask(const st_fvar_step *w, const vert *v, enum vrule r, const double **ends, double out[2])
{
    const double *p = in_uv(w, v->c[0]);
    if (r == RULE_CORNER) { out[0] = p[0]; out[1] = p[1]; return; }
    if (r == RULE_CREASE) {
        for (int k = 0; k < 2; k++) out[k] = 0.75 * p[k] + 0.125 * (ends[0][k] + ends[1][k]);
        return;
    }
    smooth_mask(w, v, out);
}

/* Sdc::Crease::ComputeFractionalWeightAtVertex: the mean parent sharpness
 * of the features that become smooth, at most 1. */
static double fractional_weight(const st_fvar_step *w, const vert *v, float vs)
{
    double sum = 0;
    unsigned count = 0;
    if (vs > 0 && decay(vs) <= 0) { sum += vs; count++; }
    for (uint32_t j = 0; j < v->n; j++) {
        float s = w->sharp[j];
        if (s > 0 && decay(s) <= 0) { sum += s; count++; }
    }
    if (!count) return 0;
    sum /= count;
    return sum > 1 ? 1 : sum;
}

static float vertex_sharp(const st_fvar_step *w, const vert *v)
{
    if (v->hole != ST_NIL && v->n == 1 && w->sv.opts.boundary == ST_BOUNDARY_EDGE_AND_CORNER) return SHARP_INF;
    return sharp_of_vertex(w, st_v_vert(&w->vl, v->c[0]));
}

/* A vertex whose face-varying topology matches the mesh's: the scheme's
 * vertex rule with its semi-sharp blend (Sdc::Scheme::ComputeVertexVertexMask). */
static void matched_vertex(st_fvar_step *w, const vert *v)
{
    double out[2];
    if (!w->sv.has_sharpness && v->hole == ST_NIL) {
        /* No sharpness and no boundary edge (it would bring a hole's
         * corner): the smooth rule at parent and child alike. */
        smooth_mask(w, v, out);
        set_all(w, v, out);
        return;
    }
    float vs = vertex_sharp(w, v);
    for (uint32_t j = 0; j < v->n; j++) w->sharp[j] = edge_sharp(w, v->c[j]);
    const double *pe[2] = {0, 0}, *ce[2] = {0, 0};
    enum vrule pr = rule_of(w, v, vs, 0, pe), cr = rule_of(w, v, vs, 1, ce);
    rule_mask(w, v, pr, pe, out);
    if (pr != cr) {
        double c[2], wp = fractional_weight(w, v, vs);
        rule_mask(w, v, cr, ce, c);
        for (int k = 0; k < 2; k++) out[k] = wp * out[k] + (1 - wp) * c[k];
    }
    set_all(w, v, out);
}

/* A value of a mismatched vertex: the corners c[j] with that label. */
typedef struct span {
    uint32_t label, size, runs, first, last;  /* first/last: the run's ends (when one run) */
    int disjoint;
} span;

static int interior_edge_breaks(const st_fvar_step *w, const vert *v, uint32_t j)
{
    return discontinuous(w, v->c[j]) || sharp_of_edge(w, v->c[j]) >= SHARP_INF;
}

static void crease_value(st_fvar_step *w, const vert *v, const span *s)
{
    const double *p = in_uv(w, v->c[s->first]);
    const double *e0 = in_uv(w, prev_corner(w, v, s->first));
    const double *e1 = in_uv(w, phi1l(w, v->c[s->last]));
    double out[2];
    for (int k = 0; k < 2; k++) out[k] = 0.75 * p[k] + 0.125 * (e0[k] + e1[k]);
    uint32_t j = s->first;
    for (;;) {
        put_vertex(w, v->c[j], out);
        if (j == s->last) break;
        j = (j + 1) % v->n;
    }
}

/* The spans of a vertex with several values (Vtr::FVarLevel::gatherValueSpans):
 * runs of consecutive corners with one label; a value is disjoint when it
 * has several runs or a discontinuous or infinitely sharp edge inside one. */
static uint32_t gather_spans(const st_fvar_step *w, const vert *v, span *sp, uint32_t cap)
{
    uint32_t n = v->n, start = 0, ns = 0;
    int boundary = v->hole != ST_NIL;
    if (!boundary)
        while (start < n && in_val(w, v->c[start]) == in_val(w, v->c[(start + n - 1) % n])) start++;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = (start + i) % n;
        uint32_t lab = in_val(w, v->c[j]);
        int cont = i > 0 && lab == in_val(w, v->c[(j + n - 1) % n]);
        uint32_t s = 0;
        while (s < ns && sp[s].label != lab) s++;
        if (s == ns) {
            if (ns == cap) return ns;
            sp[ns++] = (span){ lab, 0, 0, j, j, 0 };
        }
        if (!cont) { sp[s].runs++; sp[s].first = j; }
        else if (interior_edge_breaks(w, v, (j + n - 1) % n)) sp[s].disjoint = 1;
        sp[s].last = j;
        sp[s].size++;
    }
    for (uint32_t s = 0; s < ns; s++) if (sp[s].runs > 1) sp[s].disjoint = 1;
    return ns;
}

static void mismatched_vertex(st_fvar_step *w, const vert *v, uint32_t nvalues, int dependent)
{
    int boundary = v->hole != ST_NIL, fvar_corners_sharp = w->interp != ST_UV_NONE;
    if (nvalues == 1) {
        /* One value, mismatched by a face-varying boundary ending here (a
         * dart) or by a sharpened corner: a crease across its one
         * discontinuous edge, else a corner. */
        uint32_t ndisc = 0, at = 0;
        int broken = boundary;
        for (uint32_t j = 0; j < v->n && !boundary; j++) {
            if (discontinuous(w, v->c[j])) { ndisc++; at = j; }
            else if (sharp_of_edge(w, v->c[j]) >= SHARP_INF) broken = 1;
        }
        if (broken || ndisc != 1) { keep_all(w, v); return; }
        span s = { 0, v->n, 1, (at + 1) % v->n, at, 0 };
        crease_value(w, v, &s);
        return;
    }
    span sp[64];
    uint32_t ns = gather_spans(w, v, sp, 64);
    if (ns != nvalues) { keep_all(w, v); return; }
    if (dependent && ns == 2) {
        int all = sp[0].disjoint || sp[1].disjoint;
        if (w->interp == ST_UV_CORNERS_PLUS2) all |= sp[0].size == 1 || sp[1].size == 1;
        if (all) { keep_all(w, v); return; }
    }
    for (uint32_t s = 0; s < ns; s++) {
        if (sp[s].disjoint || (sp[s].size == 1 && fvar_corners_sharp)) {
            for (uint32_t j = 0; j < v->n; j++)
                if (in_val(w, v->c[j]) == sp[s].label) {
                    put_vertex(w, v->c[j], in_uv(w, v->c[j]));
                }
        } else {
            crease_value(w, v, &sp[s]);
        }
    }
}

/* Vtr::FVarLevel::completeTopologyFromFaceValues, for one vertex. */
static void vertex_child(st_fvar_step *w, const vert *v)
{
    if (w->rules == ST_FVAR_LINEAR || w->interp == ST_UV_ALL) { keep_all(w, v); return; }
    int boundary = v->hole != ST_NIL;
    int mismatch = 0;
    if (w->edged == w->l + 1) {
        for (uint32_t j = 0; j < v->n && !mismatch; j++) mismatch = w->disc[v->c[j]];  /* hole across: 0 */
    } else {
        for (uint32_t j = 0; j < v->n && !mismatch; j++)
            if (!st_is_boundary(w->m, b0l(w, v->c[j]))) mismatch = discontinuous(w, v->c[j]);
    }
    if (boundary && !mismatch) {
        int smooth_corners = w->sv.opts.boundary != ST_BOUNDARY_EDGE_AND_CORNER && w->interp != ST_UV_NONE;
        if (linear_boundaries(w->interp) || (v->n == 1 && smooth_corners)) mismatch = 1;
    }
    if (!mismatch) { matched_vertex(w, v); return; }
    uint32_t nvalues = 0;
    for (uint32_t j = 0; j < v->n; j++) {
        uint32_t i = 0;
        while (i < j && in_val(w, v->c[i]) != in_val(w, v->c[j])) i++;
        nvalues += i == j;
    }
    int dependent = w->interp == ST_UV_CORNERS_PLUS1 || w->interp == ST_UV_CORNERS_PLUS2;
    int darts_sharp = w->interp == ST_UV_CORNERS_PLUS2 || linear_boundaries(w->interp);
    if (linear_boundaries(w->interp) || vertex_sharp(w, v) >= SHARP_INF || (dependent && nvalues > 2) ||
        (darts_sharp && nvalues == 1 && !boundary)) {
        keep_all(w, v);
        return;
    }
    mismatched_vertex(w, v, nvalues, dependent);
}

/* The corners of the vertex of d at level l in β1 order, starting after
 * the hole when there is one, else after the corner a regular level's scan
 * meets first (the sums of the masks run from there); *touches: one of
 * them is a corner of a face subdivided toward L. */
/* Room for n + 1 corners in c, rot and sharp. */
static int corner_room(st_fvar_step *w, uint32_t n)
{
    if (n < w->cap_c) return 0;
    uint32_t cap = w->cap_c ? 2 * w->cap_c : 16;
    uint32_t *c = realloc(w->c, cap * sizeof *c);
    if (!c) return -1;
    w->c = c;
    uint32_t *r = realloc(w->rot, cap * sizeof *r);
    if (!r) return -1;
    w->rot = r;
    float *s = realloc(w->sharp, cap * sizeof *s);
    if (!s) return -1;
    w->sharp = s;
    w->cap_c = w->cap_rot = cap;
    return 0;
}

static int gather_vertex(st_fvar_step *w, uint32_t d, vert *v, int *touches)
{
    st_map *m = w->m;
    uint32_t n = 0, x = d;
    v->hole = ST_NIL;
    *touches = !w->sub;
    /* The walk starts after d and ends at d: the order wanted when there
     * is no hole and d is where the scan begins.  The hole is the last one
     * met from d on (several at a vertex whose faces fan out twice). */
    do {
        x = b1l(w, x);
        if (corner_room(w, n)) return -1;
        if (st_is_boundary(m, x)) {
            if (x != d || v->hole == ST_NIL) v->hole = x;
        } else if (w->sub) {
            *touches |= w->sub[x];
        }
        w->c[n++] = x;
    } while (x != d);
    if (v->hole == ST_NIL && !w->rank) {
        v->c = w->c;
        v->n = n;
        return 0;
    }
    /* Rotate so that the corners start after the hole, and drop it. */
    uint32_t first = 0, out = 0;
    if (v->hole != ST_NIL) while (w->c[first] != v->hole) first++;
    else if (w->rank) {
        for (uint32_t i = 1; i < n; i++)
            if (st_fvar_regular_before(w, w->c[i], w->c[first])) first = i;
    }
    for (uint32_t i = 1, j = first; i <= n; i++) {
        j = j + 1 < n ? j + 1 : 0;
        uint32_t y = w->c[j];
        if (!st_is_boundary(m, y)) w->rot[out++] = y;
    }
    memcpy(w->c, w->rot, (size_t)out * sizeof *w->rot);
    v->c = w->c;
    v->n = out;
    return 0;
}

int st_fvar_vertex_children(st_fvar_step *w)
{
    take_views(w);
    st_map *m = w->m;
    uint8_t *done = calloc((size_t)st_pool_cover(&m->verts, w->l + 1) + 1, 1);  /* level l's vertex ids */
    if (!done) return -1;
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, w->l);
    int rc = 0;
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL && !rc; d = st_fvar_scan_next(&it)) {
        uint32_t u = st_v_vert(&w->vl, d);
        if (done[u]) continue;
        done[u] = 1;
        vert v;
        int touches;
        rc = gather_vertex(w, d, &v, &touches);
        if (!rc && v.n && touches) vertex_child(w, &v);
    }
    free(done);
    return rc;
}

/* ---- level L ------------------------------------------------------------------ */

/* The inner triangle of a triangle split toward L has no old dart (all
 * three darts new at L; an adaptive map may hold finer ones): each corner
 * is the midpoint that the corner triangle across its edge has at
 * φ1(β0(x)), inside the same coarse face. */
void st_fvar_inner_triangles(st_fvar_step *w)
{
    if (w->faced == w->l + 1 && !w->tri_splits) return;  /* every face split into quads (Catmull-Clark) */
    take_views(w);
    const st_map *m = w->m;
    unsigned L = w->L;
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, L, L);   /* the darts new at L: their blocks only */
    for (uint32_t x = st_fvar_scan_next(&it); x != ST_NIL; x = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, x) || m->darts.ins[x] != L) continue;
        uint32_t a = phi1L(w, x), b = phi1L(w, a);
        if (phi1L(w, b) != x || m->darts.ins[a] != L || m->darts.ins[b] != L) continue;
        uint32_t y = phi1L(w, st_v_beta0(&w->vL, x));
        put_child(w, x, at2(w->out_uv, y), w->out_val[y]);
    }
}

void st_fvar_step_free(st_fvar_step *w)
{
    free(w->c);
    free(w->rot);
    free(w->sharp);
    free(w->fchild);
    free(w->disc);
    w->fc = NULL;
    w->fchild = NULL;
    w->disc = NULL;
    w->cap_fchild = w->cap_disc = 0;
    w->c = w->rot = NULL;
    w->sharp = NULL;
    w->cap_c = w->cap_rot = 0;
    w->viewed = w->faced = w->edged = 0;
}
