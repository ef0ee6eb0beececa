/* Face-varying UVs of an adaptive mesh (adapt.h: "UVs").
 *
 * The level-0 UVs of the hierarchy (core/fvar) are carried up the adaptive
 * map level by level with the rules of docs/SUBDIVISION-RULES.md §7b, the
 * ones core/fvar/fvar.c applies to a whole level, here applied to the
 * faces subdivided toward the next level only:
 *   - a face subdivided toward L = l+1 gets its face child (centroid of its
 *     corners' level-l values), written at φ1²(d) of each child quad;
 *   - an edge split toward L gets its edge child on each side, written at
 *     the corners of the split point in the faces on that side - on the side
 *     of a face not subdivided (a transition face) that is the one dart the
 *     split inserted there, so the transition face holds the fine point's
 *     value in its own chart;
 *   - a vertex that is a corner of a subdivided face gets its vertex child,
 *     written at every corner around it, so faces not subdivided that share
 *     the vertex show it at its finest value, as they show it at its finest
 *     position (st_adapt_mesh).
 * Every corner of the top level thus holds the value of the finest level at
 * which its vertex was computed, in the chart of its face.  With the
 * one-level restriction every stencil reads complete level-l faces (Kraemer
 * 2008 §3.2.2), the same neighbourhood as a regular level; the arithmetic
 * is fvar.c's, term for term, and its sums start where fvar.c's start on a
 * regular level (order_children), so the values are the regular level's
 * bit for bit.  Without the restriction a stencil reads whatever the
 * neighbourhood is, as the positions do.
 *
 * The rules below are copies of fvar.c's (which keeps them to itself); a
 * change there must be made here too - tests/test_adapt_uv.c compares the
 * two bit for bit.
 *
 * Catmull-Clark and Loop follow OpenSubdiv's face-varying rules (the
 * hierarchy's --uv-interp), Butterfly and quad/triangle are linear.  √3's
 * flips and Doo-Sabin's dual encoding have no corner of the level below to
 * interpolate from (as in fvar.c), and progressive hierarchies keep level
 * 0's UVs only: their adaptive meshes carry none above level 0
 * (st_adapt_uv_absent says why). */
#include "core/adapt/adapt_internal.h"
#include "core/fvar/fvar_internal.h"
#include "core/map/map_mesh.h"
#include "core/multires/hier_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SHARP_INF 10.0f

enum rules { RULES_CATMARK, RULES_LOOP, RULES_LINEAR };

static int rules_of(const st_hier *h)
{
    switch (h->scheme->id) {
    case ST_SCHEME_CATMARK: return RULES_CATMARK;
    case ST_SCHEME_LOOP: return RULES_LOOP;
    case ST_SCHEME_BUTTERFLY:
    case ST_SCHEME_QUADTRI: return RULES_LINEAR;
    default: return -1;
    }
}

const char *st_adapt_uv_absent(const st_adapt *a)
{
    const st_hier *h = a->h;
    if (h->map.face_embedded) return "Doo-Sabin carries no UVs";
    if (!st_hier_uv(h, 0)) return "the mesh has no texture coordinates";
    if (st_adapt_is_progressive(a)) return "a progressive hierarchy's adaptive mesh carries no UVs";
    if (rules_of(h) < 0 && h->map.top > 0)
        return "this scheme keeps the UVs of level 0 only, and adaptive meshes above level 0 carry none";
    return NULL;
}

void st_adapt_uv_free(st_adapt_uv *u)
{
    free(u->uv);
    free(u->val);
    free(u->level);
    free(u->rank);
    memset(u, 0, sizeof *u);
}

/* ---- one step l -> L = l+1 ------------------------------------------------------ */

typedef struct work {
    st_hier *h;
    st_map *m;
    unsigned l, L;
    int interp, rules;
    const double *uv;       /* the values so far (level l at every corner of a level-l face) */
    const uint32_t *val;
    double *ouv;            /* the values after the step (starts as a copy of uv) */
    uint32_t *oval;
    uint8_t *olevel;        /* the level each corner's value comes from */
    double *cent;           /* per dart of map l: the centroid of its face (the face child) */
    uint8_t *sub;           /* per dart of map l: its face is subdivided toward L */
    uint32_t *rank;         /* per dart: its place among the darts of its level in a regular
                               level's numbering (order_children), ST_NIL: none */
    uint32_t *c, *rot;      /* one vertex's corners in β1 order, and scratch */
    uint32_t cap_c, cap_rot;
} work;

static const double *at2(const double *a, uint32_t d) { return a + 2 * (size_t)d; }

static void put_child(const work *w, uint32_t x, const double p[2], uint32_t label)
{
    w->ouv[2 * (size_t)x] = p[0];
    w->ouv[2 * (size_t)x + 1] = p[1];
    w->oval[x] = label;
    w->olevel[x] = (uint8_t)w->L;
}

static const double *face_child(const work *w, uint32_t d) { return at2(w->cent, d); }

static int linear_boundaries(int interp) { return interp == ST_UV_BOUNDARIES || interp == ST_UV_ALL; }

static float edge_sharp(const work *w, uint32_t d)
{
    if (st_is_boundary(w->m, st_beta0(w->m, d, w->l))) return SHARP_INF;
    return st_hier_edge_sharpness(w->h, d, w->l);
}

static float decay(float s) { return s >= SHARP_INF ? SHARP_INF : (s > 1.0f ? s - 1.0f : 0.0f); }

static int discontinuous(const work *w, uint32_t d)
{
    uint32_t t = st_beta0(w->m, d, w->l);
    return w->val[d] != w->val[st_phi1(w->m, t, w->l)] || w->val[st_phi1(w->m, d, w->l)] != w->val[t];
}

/* The dart a regular level's scan meets first on the face of d: its oldest
 * (a regular level makes all its darts after those of the level below; an
 * adaptive map interleaves levels), then the first in that level's
 * numbering. */
static int regular_before(const work *w, uint32_t x, uint32_t y);

static uint32_t oldest_dart(const work *w, uint32_t d, unsigned l)
{
    const st_map *m = w->m;
    uint32_t b = d, x = st_phi1(m, d, l);
    while (x != d) {
        if (regular_before(w, x, b)) b = x;
        x = st_phi1(m, x, l);
    }
    return b;
}

/* Centroids of every face of map l (the edge and vertex rules of
 * Catmull-Clark read those of faces not subdivided too), face children of
 * the subdivided ones.  The sum starts where fvar.c's starts on a regular
 * level: at the face's oldest dart. */
static void face_pass(work *w)
{
    st_map *m = w->m;
    unsigned l = w->l;
    int fbit = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        st_mark_face(m, fbit, d, l);
        d = oldest_dart(w, d, l);
        double s[2] = { 0, 0 };
        unsigned n = 0;
        uint32_t x = d;
        do {
            s[0] += w->uv[2 * (size_t)x];
            s[1] += w->uv[2 * (size_t)x + 1];
            n++;
            x = st_phi1(m, x, l);
        } while (x != d);
        double c[2] = { s[0] / n, s[1] / n };
        int sub = st_adapt_split_toward(m, d, l);
        do {
            w->cent[2 * (size_t)x] = c[0];
            w->cent[2 * (size_t)x + 1] = c[1];
            w->sub[x] = (uint8_t)sub;
            x = st_phi1(m, x, l);
        } while (x != d);
        if (!sub || st_face_degree(m, d, w->L) != 4) continue; /* a triangle split: no face child */
        do {
            put_child(w, st_phi1(m, st_phi1(m, x, w->L), w->L), c, 0);
            x = st_phi1(m, x, l);
        } while (x != d);
    }
    st_marker_release(m, fbit, l);
}

/* The child of the split edge of d on d's side (fvar.c's edge_child). */
static void edge_child(work *w, uint32_t d)
{
    st_map *m = w->m;
    unsigned l = w->l, L = w->L;
    uint32_t t = st_beta0(m, d, l), n = st_phi1(m, d, l);
    const double *a = at2(w->uv, d), *b = at2(w->uv, n);
    double mid[2] = { (a[0] + b[0]) / 2, (a[1] + b[1]) / 2 }, p[2];
    int hole = st_is_boundary(m, t);
    int disc = !hole && discontinuous(w, d);
    uint32_t label = disc ? d : (hole || d < t ? d : t);
    float s = hole ? SHARP_INF : st_hier_edge_sharpness(w->h, d, l);
    if (w->rules == RULES_LINEAR || w->interp == ST_UV_ALL || hole || disc || s >= 1.0f) {
        p[0] = mid[0];
        p[1] = mid[1];
    } else {
        if (w->rules == RULES_CATMARK) {
            const double *f0 = face_child(w, d), *f1 = face_child(w, t);
            for (int k = 0; k < 2; k++) p[k] = (a[k] + b[k] + f0[k] + f1[k]) / 4;
        } else {
            const double *o0 = at2(w->uv, st_phi1(m, n, l)), *o1 = at2(w->uv, st_phi1(m, st_phi1(m, t, l), l));
            for (int k = 0; k < 2; k++) p[k] = 0.375 * (a[k] + b[k]) + 0.125 * (o0[k] + o1[k]);
        }
        double wc = s > 0 ? s : 0;
        for (int k = 0; k < 2; k++) p[k] = wc * mid[k] + (1 - wc) * p[k];
    }
    put_child(w, st_phi1(m, d, L), p, label);
    put_child(w, st_phi_1(m, n, L), p, label);
}

/* ---- vertex children (fvar.c's rules, on the corners of one vertex) --------- */

typedef struct vert {
    uint32_t *c, n;
    uint32_t hole;
} vert;

static uint32_t prev_corner(const work *w, const vert *v, uint32_t j)
{
    uint32_t p = j ? v->c[j - 1] : (v->hole != ST_NIL ? v->hole : v->c[v->n - 1]);
    return st_beta0(w->m, p, w->l);
}

static void put_vertex(work *w, uint32_t d, const double p[2]) { put_child(w, d, p, w->val[d]); }

static void set_all(work *w, const vert *v, const double p[2])
{
    for (uint32_t j = 0; j < v->n; j++) put_vertex(w, v->c[j], p);
}

static void keep_all(work *w, const vert *v)
{
    for (uint32_t j = 0; j < v->n; j++) put_vertex(w, v->c[j], at2(w->uv, v->c[j]));
}

enum vrule { RULE_SMOOTH, RULE_CREASE, RULE_CORNER };

static enum vrule rule_of(const work *w, const vert *v, float vs, int child, const double **ends)
{
    uint32_t nsharp = 0;
    uint32_t ne = v->n + (v->hole != ST_NIL);
    for (uint32_t j = 0; j < ne; j++) {
        float s = j < v->n ? edge_sharp(w, v->c[j]) : SHARP_INF;
        if (child) s = decay(s);
        if (s <= 0) continue;
        if (nsharp < 2) ends[nsharp] = j < v->n ? at2(w->uv, st_phi1(w->m, v->c[j], w->l)) : at2(w->uv, prev_corner(w, v, 0));
        nsharp++;
    }
    if (child) vs = decay(vs);
    if (vs > 0 || nsharp > 2) return RULE_CORNER;
    return nsharp == 2 ? RULE_CREASE : RULE_SMOOTH;
}

static void smooth_mask(const work *w, const vert *v, double out[2])
{
    const double *p = at2(w->uv, v->c[0]);
    double n = v->n, se[2] = { 0, 0 }, sf[2] = { 0, 0 };
    for (uint32_t j = 0; j < v->n; j++) {
        const double *e = at2(w->uv, st_phi1(w->m, v->c[j], w->l));
        const double *f = w->rules == RULES_CATMARK ? face_child(w, v->c[j]) : e;
        for (int k = 0; k < 2; k++) { se[k] += e[k]; sf[k] += f[k]; }
    }
    if (w->rules == RULES_CATMARK) {
        for (int k = 0; k < 2; k++) out[k] = (n - 2) / n * p[k] + (se[k] + sf[k]) / (n * n);
    } else {
        double c = cos(M_PI * 2.0 / n), b = 0.25 * c + 0.375, ew = (0.625 - b * b) / n;
        for (int k = 0; k < 2; k++) out[k] = (1 - n * ew) * p[k] + ew * se[k];
    }
}

static void rule_mask(const work *w, const vert *v, enum vrule r, const double **ends, double out[2])
{
    const double *p = at2(w->uv, v->c[0]);
    if (r == RULE_CORNER) { out[0] = p[0]; out[1] = p[1]; return; }
    if (r == RULE_CREASE) {
        for (int k = 0; k < 2; k++) out[k] = 0.75 * p[k] + 0.125 * (ends[0][k] + ends[1][k]);
        return;
    }
    smooth_mask(w, v, out);
}

static double fractional_weight(const work *w, const vert *v, float vs)
{
    double sum = 0;
    unsigned count = 0;
    if (vs > 0 && decay(vs) <= 0) { sum += vs; count++; }
    for (uint32_t j = 0; j < v->n; j++) {
        float s = edge_sharp(w, v->c[j]);
        if (s > 0 && decay(s) <= 0) { sum += s; count++; }
    }
    if (!count) return 0;
    sum /= count;
    return sum > 1 ? 1 : sum;
}

static float vertex_sharp(const work *w, const vert *v)
{
    if (v->hole != ST_NIL && v->n == 1 && w->h->opts.boundary == ST_BOUNDARY_EDGE_AND_CORNER) return SHARP_INF;
    return st_hier_vertex_sharpness(w->h, st_vert(w->m, v->c[0], w->l), w->l);
}

static void matched_vertex(work *w, const vert *v)
{
    float vs = vertex_sharp(w, v);
    const double *pe[2] = { 0, 0 }, *ce[2] = { 0, 0 };
    enum vrule pr = rule_of(w, v, vs, 0, pe), cr = rule_of(w, v, vs, 1, ce);
    double out[2];
    rule_mask(w, v, pr, pe, out);
    if (pr != cr) {
        double c[2], wp = fractional_weight(w, v, vs);
        rule_mask(w, v, cr, ce, c);
        for (int k = 0; k < 2; k++) out[k] = wp * out[k] + (1 - wp) * c[k];
    }
    set_all(w, v, out);
}

typedef struct span {
    uint32_t label, size, runs, first, last;
    int disjoint;
} span;

static int interior_edge_breaks(const work *w, const vert *v, uint32_t j)
{
    return discontinuous(w, v->c[j]) || st_hier_edge_sharpness(w->h, v->c[j], w->l) >= SHARP_INF;
}

static void crease_value(work *w, const vert *v, const span *s)
{
    const double *p = at2(w->uv, v->c[s->first]);
    const double *e0 = at2(w->uv, prev_corner(w, v, s->first));
    const double *e1 = at2(w->uv, st_phi1(w->m, v->c[s->last], w->l));
    double out[2];
    for (int k = 0; k < 2; k++) out[k] = 0.75 * p[k] + 0.125 * (e0[k] + e1[k]);
    uint32_t j = s->first;
    for (;;) {
        put_vertex(w, v->c[j], out);
        if (j == s->last) break;
        j = (j + 1) % v->n;
    }
}

static uint32_t gather_spans(const work *w, const vert *v, span *sp, uint32_t cap)
{
    uint32_t n = v->n, start = 0, ns = 0;
    int boundary = v->hole != ST_NIL;
    if (!boundary)
        while (start < n && w->val[v->c[start]] == w->val[v->c[(start + n - 1) % n]]) start++;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = (start + i) % n;
        uint32_t lab = w->val[v->c[j]];
        int cont = i > 0 && lab == w->val[v->c[(j + n - 1) % n]];
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

static void mismatched_vertex(work *w, const vert *v, uint32_t nvalues, int dependent)
{
    int boundary = v->hole != ST_NIL, fvar_corners_sharp = w->interp != ST_UV_NONE;
    if (nvalues == 1) {
        uint32_t ndisc = 0, at = 0;
        int broken = boundary;
        for (uint32_t j = 0; j < v->n && !boundary; j++) {
            if (discontinuous(w, v->c[j])) { ndisc++; at = j; }
            else if (st_hier_edge_sharpness(w->h, v->c[j], w->l) >= SHARP_INF) broken = 1;
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
                if (w->val[v->c[j]] == sp[s].label) put_vertex(w, v->c[j], at2(w->uv, v->c[j]));
        } else {
            crease_value(w, v, &sp[s]);
        }
    }
}

static void vertex_child(work *w, const vert *v)
{
    if (w->rules == RULES_LINEAR || w->interp == ST_UV_ALL) { keep_all(w, v); return; }
    int boundary = v->hole != ST_NIL;
    int mismatch = 0;
    for (uint32_t j = 0; j < v->n && !mismatch; j++)
        if (!st_is_boundary(w->m, st_beta0(w->m, v->c[j], w->l))) mismatch = discontinuous(w, v->c[j]);
    if (boundary && !mismatch) {
        int smooth_corners = w->h->opts.boundary != ST_BOUNDARY_EDGE_AND_CORNER && w->interp != ST_UV_NONE;
        if (linear_boundaries(w->interp) || (v->n == 1 && smooth_corners)) mismatch = 1;
    }
    if (!mismatch) { matched_vertex(w, v); return; }
    uint32_t nvalues = 0;
    for (uint32_t j = 0; j < v->n; j++) {
        uint32_t i = 0;
        while (i < j && w->val[v->c[i]] != w->val[v->c[j]]) i++;
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

/* x comes before y in the scan of a regular level (st_dart_first/next:
 * level by level, each in the order the level was made). */
static int regular_before(const work *w, uint32_t x, uint32_t y)
{
    const uint8_t *ins = w->m->darts.ins;
    if (ins[x] != ins[y]) return ins[x] < ins[y];
    if (ins[x] == 0 || w->rank[x] == w->rank[y]) return x < y;
    return w->rank[x] < w->rank[y];
}

/* The corners of the vertex of d at level l in β1 order, starting after
 * the hole when there is one, else at the corner a regular level meets
 * first (fvar.c's gather_vertex); *touches: one of them is a corner of a
 * face subdivided toward L. */
static int gather_vertex(work *w, uint32_t d, vert *v, int *touches)
{
    st_map *m = w->m;
    unsigned l = w->l;
    uint32_t n = 0, x = d;
    v->hole = ST_NIL;
    *touches = 0;
    do {
        if (n == w->cap_c) {
            uint32_t cap = w->cap_c ? 2 * w->cap_c : 16;
            uint32_t *c = realloc(w->c, cap * sizeof *c);
            if (!c) return -1;
            w->c = c;
            w->cap_c = cap;
        }
        if (st_is_boundary(m, x)) v->hole = x;
        else *touches |= w->sub[x];
        w->c[n++] = x;
        x = st_beta1(m, x, l);
    } while (x != d);
    if (w->cap_rot < w->cap_c) {
        uint32_t *r = realloc(w->rot, (size_t)w->cap_c * sizeof *r);
        if (!r) return -1;
        w->rot = r;
        w->cap_rot = w->cap_c;
    }
    uint32_t first = 0, out = 0;
    if (v->hole != ST_NIL) while (w->c[first] != v->hole) first++;
    else {
        /* Closed around: from where fvar.c starts on a regular level, the
         * corner after the one its scan meets first (the sums of the masks
         * run from there). */
        for (uint32_t i = 1; i < n; i++)
            if (regular_before(w, w->c[i], w->c[first])) first = i;
    }
    for (uint32_t i = 1; i <= n; i++) {
        uint32_t y = w->c[(first + i) % n];
        if (!st_is_boundary(m, y)) w->rot[out++] = y;
    }
    memcpy(w->c, w->rot, (size_t)out * sizeof *w->rot);
    v->c = w->c;
    v->n = out;
    return 0;
}

static int vertex_pass(work *w)
{
    st_map *m = w->m;
    unsigned l = w->l;
    uint8_t *done = calloc((size_t)m->verts.end + 1, 1);
    if (!done) return -1;
    st_dart_iter it;
    int rc = 0;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL && !rc; d = st_dart_next(m, l, &it)) {
        uint32_t u = st_vert(m, d, l);
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

/* The inner triangles of the triangle splits toward L (all three darts new
 * at L): each corner is the edge child the corner triangle across has. */
static void inner_triangles(work *w)
{
    const st_map *m = w->m;
    unsigned L = w->L;
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, L, &it); x != ST_NIL; x = st_dart_next(m, L, &it)) {
        if (st_is_boundary(m, x) || m->darts.ins[x] != L) continue;
        uint32_t a = st_phi1(m, x, L), b = st_phi1(m, a, L);
        if (st_phi1(m, b, L) != x || m->darts.ins[a] != L || m->darts.ins[b] != L) continue;
        uint32_t y = st_phi1(m, st_beta0(m, x, L), L);
        put_child(w, x, at2(w->ouv, y), w->oval[y]);
    }
}

/* ---- a regular level's numbering ------------------------------------------------ */

/* The bulk refinement (core/map/refine.c) numbers the darts of level L face
 * by face of level l, each face from the first of its darts of level l met
 * (level 0: its smallest id), corner i giving n(d_i), then first(d_i) =
 * φ1(d_i) at L, then out_i = β0(in_i) (a triangle split: u_i =
 * β0(first(d_{i+1}))).  Ranking the adaptive map's darts of level L by
 * (rank of the face, 3 i + role) gives their order there, which the
 * vertex rules need to sum as fvar.c does on a regular level. */
typedef struct rank_key { uint32_t face, pos, dart; } rank_key;

static int cmp_rank(const void *pa, const void *pb)
{
    const rank_key *a = pa, *b = pb;
    if (a->face != b->face) return a->face < b->face ? -1 : 1;
    if (a->pos != b->pos) return a->pos < b->pos ? -1 : 1;
    return (a->dart > b->dart) - (a->dart < b->dart);
}

static int order_children(work *w)
{
    st_map *m = w->m;
    unsigned l = w->l, L = w->L;
    const uint8_t *ins = m->darts.ins;
    size_t cap = 64, n = 0;
    rank_key *k = malloc(cap * sizeof *k);
    if (!k) return -1;
    int fbit = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        st_mark_face(m, fbit, d, l);
        if (!w->sub[d]) continue;
        /* the face's first dart: its newest darts' first in the scan */
        uint32_t f0 = d, x = st_phi1(m, d, l);
        while (x != d) {
            if (ins[x] > ins[f0] || (ins[x] == ins[f0] && regular_before(w, x, f0))) f0 = x;
            x = st_phi1(m, x, l);
        }
        uint32_t face = l ? w->rank[f0] : f0;
        int tri = st_face_degree(m, f0, L) == 3;
        uint32_t i = 0;
        x = f0;
        do {
            if (n + 3 > cap) {
                rank_key *g = realloc(k, 2 * cap * sizeof *k);
                if (!g) { free(k); st_marker_release(m, fbit, l); return -1; }
                k = g;
                cap *= 2;
            }
            uint32_t in = st_phi1(m, x, L);
            uint32_t out = tri ? st_beta0(m, st_phi1(m, st_phi1(m, x, l), L), L) : st_beta0(m, in, L);
            k[n++] = (rank_key){ face, 3 * i, st_beta0(m, st_beta0(m, x, l), L) };
            k[n++] = (rank_key){ face, 3 * i + 1, in };
            k[n++] = (rank_key){ face, 3 * i + 2, out };
            i++;
            x = st_phi1(m, x, l);
        } while (x != f0);
    }
    st_marker_release(m, fbit, l);
    qsort(k, n, sizeof *k, cmp_rank);
    for (size_t j = 0; j < n; j++)
        if (ins[k[j].dart] == L) w->rank[k[j].dart] = (uint32_t)j;
    free(k);
    return 0;
}

static int step(work *w)
{
    st_map *m = w->m;
    size_t cap = m->darts.end;
    memcpy(w->ouv, w->uv, 2 * cap * sizeof *w->ouv);
    memcpy(w->oval, w->val, cap * sizeof *w->oval);
    memset(w->sub, 0, cap);
    face_pass(w);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, w->l, &it); d != ST_NIL; d = st_dart_next(m, w->l, &it))
        if (!st_is_boundary(m, d) && st_adapt_edge_split(m, d, w->l)) edge_child(w, d);
    if (vertex_pass(w) || order_children(w)) return -1;
    inner_triangles(w);
    return 0;
}

/* ---- the whole map --------------------------------------------------------------- */

int st_adapt_uv_build(st_adapt *a, st_adapt_uv *u, st_error *err)
{
    memset(u, 0, sizeof *u);
    if (st_adapt_uv_absent(a)) return ST_OK;
    st_hier *h = a->h;
    st_map *m = &h->map;
    const st_fvar *f = h->fvar;
    uint32_t cap = m->darts.end;
    size_t n = (size_t)cap + 1;
    double *buf = malloc(2 * n * sizeof *buf), *cent = malloc(2 * n * sizeof *cent);
    uint32_t *vbuf = malloc(n * sizeof *vbuf);
    uint8_t *sub = malloc(n);
    uint32_t *rank = malloc(n * sizeof *rank);
    u->uv = calloc(2 * n, sizeof *u->uv);
    u->val = calloc(n, sizeof *u->val);
    u->level = calloc(n, 1);
    int rc = !buf || !cent || !vbuf || !sub || !rank || !u->uv || !u->val || !u->level;
    for (size_t i = 0; !rc && i < n; i++) rank[i] = ST_NIL;
    if (!rc) {
        /* level 0: the hierarchy's own (level-0 darts never change while adapting) */
        uint32_t n0 = f->lv[0].cap < cap ? f->lv[0].cap : cap;
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
            if (d >= n0) continue;
            u->uv[2 * (size_t)d] = f->lv[0].uv[2 * (size_t)d];
            u->uv[2 * (size_t)d + 1] = f->lv[0].uv[2 * (size_t)d + 1];
            u->val[d] = f->lv[0].val[d];
        }
        u->cap = cap;
    }
    work w = { .h = h, .m = m, .interp = f->interp, .rules = rules_of(h), .cent = cent, .sub = sub, .rank = rank, .olevel = u->level };
    for (unsigned L = 1; !rc && L <= m->top; L++) {
        /* the values so far go to buf/vbuf, the step writes back into u */
        memcpy(buf, u->uv, 2 * (size_t)cap * sizeof *buf);
        memcpy(vbuf, u->val, (size_t)cap * sizeof *vbuf);
        w.l = L - 1;
        w.L = L;
        w.uv = buf;
        w.val = vbuf;
        w.ouv = u->uv;
        w.oval = u->val;
        rc = step(&w);
    }
    free(w.c);
    free(w.rot);
    free(buf);
    free(cent);
    free(vbuf);
    free(sub);
    u->rank = rank;
    if (rc) {
        st_adapt_uv_free(u);
        return st_fail(err, ST_ERR_MEMORY, "out of memory for the adaptive mesh's texture coordinates");
    }
    return ST_OK;
}

/* ---- the displayed mesh's texture coordinates ------------------------------------ */

typedef struct uv_key { uint32_t vert, level, label, corner; uint64_t face; } uv_key;

static int cmp_key(const void *pa, const void *pb)
{
    const uv_key *a = pa, *b = pb;
    if (a->vert != b->vert) return a->vert < b->vert ? -1 : 1;
    if (a->level != b->level) return a->level < b->level ? -1 : 1;
    if (a->label != b->label) return a->label < b->label ? -1 : 1;
    if (a->face != b->face) return a->face < b->face ? -1 : 1;
    return (a->corner > b->corner) - (a->corner < b->corner);
}

/* A dart's place in a regular level's scan (level, then numbering). */
static uint64_t scan_key(const st_map *m, const st_adapt_uv *u, uint32_t x)
{
    uint8_t ins = m->darts.ins[x];
    uint32_t r = ins == 0 ? x : (x < u->cap && u->rank ? u->rank[x] : ST_NIL);
    return (uint64_t)ins << 32 | r;
}

int st_adapt_uv_mesh(st_adapt *a, const st_adapt_uv *u, st_mesh *out, st_error *err)
{
    if (!u->uv) return ST_OK;
    st_map *m = &a->h->map;
    unsigned top = m->top;
    uint32_t nc = out->nfaces ? out->face_off[out->nfaces] : 0;
    uv_key *k = malloc(((size_t)nc + 1) * sizeof *k);
    uint32_t *darts = malloc(((size_t)nc + 1) * sizeof *darts);
    uint32_t *face_uv = malloc(((size_t)nc + 1) * sizeof *face_uv);
    double *uv = malloc(2 * ((size_t)nc + 1) * sizeof *uv);
    if (!k || !darts || !face_uv || !uv) {
        free(k);
        free(darts);
        free(face_uv);
        free(uv);
        return st_fail(err, ST_ERR_MEMORY, "out of memory for the adaptive mesh's texture coordinates");
    }
    /* The face walk of st_map_to_mesh (core/map/map_mesh.c). */
    int fbit = st_marker_reserve(m);
    uint32_t c = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, top, &it); d != ST_NIL && c < nc; d = st_dart_next(m, top, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        uint64_t face = UINT64_MAX;
        uint32_t x = d;
        do {
            uint64_t s = scan_key(m, u, x);
            face = s < face ? s : face;
            x = st_phi1(m, x, top);
        } while (x != d);
        do {
            st_mark(m, fbit, x);
            darts[c] = x;
            k[c] = (uv_key){ out->face_idx[c], x < u->cap ? u->level[x] : 0, x < u->cap ? u->val[x] : 0, c, face };
            c++;
            x = st_phi1(m, x, top);
        } while (x != d && c < nc);
    }
    st_marker_release(m, fbit, top);
    /* One texture coordinate per (vertex, level, value): seams stay seams,
     * and corners holding one value share one coordinate - that of the
     * face a regular level's walk meets first, as st_hier_level_mesh takes
     * it (the two sides of a smooth edge may differ in the last bit). */
    qsort(k, c, sizeof *k, cmp_key);
    uint32_t nuv = 0;
    for (uint32_t i = 0; i < c; i++) {
        if (i == 0 || k[i].vert != k[i - 1].vert || k[i].level != k[i - 1].level || k[i].label != k[i - 1].label) {
            uint32_t x = darts[k[i].corner];
            uv[2 * (size_t)nuv] = x < u->cap ? u->uv[2 * (size_t)x] : 0;
            uv[2 * (size_t)nuv + 1] = x < u->cap ? u->uv[2 * (size_t)x + 1] : 0;
            nuv++;
        }
        face_uv[k[i].corner] = nuv - 1;
    }
    free(k);
    free(darts);
    free(out->face_uv);
    free(out->uv);
    out->face_uv = face_uv;
    out->uv = uv;
    out->nuvs = nuv;
    return ST_OK;
}
