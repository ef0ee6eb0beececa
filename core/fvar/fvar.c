/* Face-varying UVs at every level (fvar.h).
 *
 * Each level stores a UV and a value label per dart (a face corner).  A
 * level L made by primal quadrisection (core/map/refine.c) keeps every dart
 * of level L-1: an old dart d of a coarse face f runs at L from its corner
 * to the midpoint of its edge, inside the child face of f at that corner
 * (quad n(d_{i-1}), d_i, in_i, out_{i-1}, or triangle n(d_{i-1}), d_i, t_{i-1}).
 * So a fine corner is found from the one old dart of its face: at offset 0
 * the child of the coarse vertex, 1 the child of d's edge, 2 in a quad the
 * child of f, last the child of the previous edge of f; the inner triangle
 * of a triangle split has no old dart and takes its corners from the corner
 * triangles across its edges.  Each child value is written straight to the
 * fine corners that hold it (face children first: the edge and vertex
 * rules of Catmull-Clark read them back from there).
 *
 * The rules are OpenSubdiv's (Far::PrimvarRefiner::InterpolateFaceVarying,
 * the tags of Vtr::FVarLevel), evaluated on each level afresh rather than
 * inherited from level 0 (the same classification for the rules below):
 *   - an edge is a face-varying boundary (discontinuous) when the values at
 *     either end differ between its two faces (value labels, not UV
 *     coordinates: OpenSubdiv compares indices); its child takes the
 *     midpoint on each side, like a mesh boundary edge;
 *   - a vertex all of whose corners share one value and whose edges are
 *     continuous takes the vertex rule of the scheme (smooth, dart, crease,
 *     corner, semi-sharp blends) applied to the face-varying values;
 *   - otherwise each value is a corner (kept) or a crease (3/4 v + 1/8 of the
 *     two ends of its boundary edges) as FVarLinearInterpolation decides:
 *     see docs/SUBDIVISION-RULES.md §7b.
 * Semi-sharp creases inside a face-varying boundary take the plain crease
 * rule (OpenSubdiv blends toward a corner there).
 */
#include "core/fvar/fvar_internal.h"
#include "core/multires/hier.h"
#include "core/schemes/scheme.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SHARP_INF 10.0f

static const char *const interp_names[ST_UV_INTERP_COUNT] = {
    "corners-plus1", "none", "corners-only", "corners-plus2", "boundaries", "all",
};

int st_uv_interp_find(const char *name)
{
    for (int i = 0; name && i < ST_UV_INTERP_COUNT; i++)
        if (strcmp(name, interp_names[i]) == 0) return i;
    return -1;
}

const char *st_uv_interp_name(int interp)
{
    return interp >= 0 && interp < ST_UV_INTERP_COUNT ? interp_names[interp] : "?";
}

const double *st_hier_uv(const st_hier *h, unsigned l)
{
    const st_fvar *f = h->fvar;
    if (!f || l >= f->levels || l > h->map.top) return NULL;
    return f->lv[l].uv;
}

static void level_free(st_fvar_level *lv)
{
    free(lv->uv);
    free(lv->val);
    memset(lv, 0, sizeof *lv);
}

static int level_alloc(st_fvar_level *lv, uint32_t cap)
{
    lv->cap = cap;
    lv->uv = calloc(2 * (size_t)cap + 2, sizeof *lv->uv);
    lv->val = calloc((size_t)cap + 1, sizeof *lv->val);
    if (lv->uv && lv->val) return 0;
    level_free(lv);
    return -1;
}

void st_fvar_free(st_hier *h)
{
    st_fvar *f = h->fvar;
    if (!f) return;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) level_free(&f->lv[l]);
    free(f);
    h->fvar = NULL;
}

/* ---- level 0 ---------------------------------------------------------------- */

/* The dart of level 0 leaving u along the real face whose next vertex is w.
 * In Doo-Sabin's dual encoding a surface face is a β1 orbit and a surface
 * vertex a φ1 orbit (scheme_doosabin.c): the corner is still one dart. */
static uint32_t corner_dart(const st_map *m, uint32_t start, uint32_t w)
{
    int dual = m->face_embedded;
    uint32_t x = start;
    do {
        uint32_t next = dual ? st_beta1(m, x, 0) : st_phi1(m, x, 0);
        if (!st_is_boundary(m, x) && st_vert(m, next, 0) == w) return x;
        x = dual ? st_phi1(m, x, 0) : st_beta1(m, x, 0);
    } while (x != start);
    return ST_NIL;
}

int st_fvar_init(st_hier *h, const st_mesh *mesh, int interp, st_error *err)
{
    if (!mesh->face_uv) return ST_OK;
    st_map *m = &h->map;
    st_fvar *f = calloc(1, sizeof *f);
    uint32_t *vdart = malloc((size_t)(m->verts.end ? m->verts.end : 1) * sizeof *vdart);
    if (!f || !vdart || level_alloc(&f->lv[0], m->darts.end)) {
        free(f ? f->lv[0].uv : NULL);
        free(f ? f->lv[0].val : NULL);
        free(f);
        free(vdart);
        return st_fail(err, ST_ERR_MEMORY, "out of memory for texture coordinates");
    }
    f->interp = interp;
    for (uint32_t v = 0; v < m->verts.end; v++) vdart[v] = ST_NIL;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) vdart[st_vert(m, d, 0)] = d;
    int rc = ST_OK;
    for (uint32_t fi = 0; fi < mesh->nfaces && !rc; fi++) {
        uint32_t a = mesh->face_off[fi], n = mesh->face_off[fi + 1] - a;
        for (uint32_t j = 0; j < n && !rc; j++) {
            uint32_t u = mesh->face_idx[a + j], w = mesh->face_idx[a + (j + 1) % n], t = mesh->face_uv[a + j];
            uint32_t d = u < m->verts.end && vdart[u] != ST_NIL ? corner_dart(m, vdart[u], w) : ST_NIL;
            if (d == ST_NIL || t >= mesh->nuvs) {
                rc = st_fail(err, ST_ERR_INVALID, "face %u corner %u: no such corner in the map, or a bad texture coordinate", fi, j);
                break;
            }
            f->lv[0].uv[2 * (size_t)d] = mesh->uv[2 * (size_t)t];
            f->lv[0].uv[2 * (size_t)d + 1] = mesh->uv[2 * (size_t)t + 1];
            f->lv[0].val[d] = t;
        }
    }
    free(vdart);
    f->levels = 1;
    h->fvar = f;
    if (rc) st_fvar_free(h);
    return rc;
}

/* ---- the children of level l, written into level L ----------------------- */

enum rules { RULES_CATMARK, RULES_LOOP, RULES_LINEAR, RULES_STENCIL };

/* The children are written straight into level L's arrays (no scratch per
 * dart): the vertex child of coarse corner d at d itself, the edge child of
 * d's edge on d's side at φ1(d) and at the last corner of the child face of
 * the next coarse corner, the face child at φ1²(d) of each child quad. */
typedef struct work {
    st_hier *h;
    st_map *m;
    unsigned l, L;
    int interp, rules;
    const double *uv;            /* level l, per dart */
    const uint32_t *val;
    st_fvar_level *out;          /* level L */
    uint32_t *c, *rot;           /* one vertex's corners in β1 order, and scratch */
    uint32_t cap_c, cap_rot;
} work;

static void put2(double *a, uint32_t d, double u, double v)
{
    a[2 * (size_t)d] = u;
    a[2 * (size_t)d + 1] = v;
}

static const double *at2(const double *a, uint32_t d) { return a + 2 * (size_t)d; }

static void put_child(const work *w, uint32_t x, const double p[2], uint32_t label)
{
    put2(w->out->uv, x, p[0], p[1]);
    w->out->val[x] = label;
}

/* The face child of the coarse face of d (Catmull-Clark, quad children). */
static const double *face_child(const work *w, uint32_t d)
{
    return at2(w->out->uv, st_phi1(w->m, st_phi1(w->m, d, w->L), w->L));
}

static int linear_boundaries(int interp) { return interp == ST_UV_BOUNDARIES || interp == ST_UV_ALL; }

static float edge_sharp(const work *w, uint32_t d)
{
    if (st_is_boundary(w->m, st_beta0(w->m, d, w->l))) return SHARP_INF;
    return st_hier_edge_sharpness(w->h, d, w->l);
}

static float decay(float s) { return s >= SHARP_INF ? SHARP_INF : (s > 1.0f ? s - 1.0f : 0.0f); }

/* The edge of corner d is a face-varying boundary: the values at one of
 * its ends differ between its two faces (t = β0(d) real). */
static int discontinuous(const work *w, uint32_t d)
{
    uint32_t t = st_beta0(w->m, d, w->l);
    return w->val[d] != w->val[st_phi1(w->m, t, w->l)] || w->val[st_phi1(w->m, d, w->l)] != w->val[t];
}

/* Centroids of the coarse faces split into quads. */
static void face_children(work *w)
{
    st_map *m = w->m;
    unsigned l = w->l;
    int fbit = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        st_mark_face(m, fbit, d, l);
        if (st_face_degree(m, d, w->L) != 4) continue;  /* a triangle split: no face child */
        double s[2] = {0, 0};
        unsigned n = 0;
        uint32_t x = d;
        do {
            s[0] += w->uv[2 * (size_t)x];
            s[1] += w->uv[2 * (size_t)x + 1];
            n++;
            x = st_phi1(m, x, l);
        } while (x != d);
        double c[2] = { s[0] / n, s[1] / n };
        do {
            put_child(w, st_phi1(m, st_phi1(m, x, w->L), w->L), c, 0);
            x = st_phi1(m, x, l);
        } while (x != d);
    }
    st_marker_release(m, fbit, l);
}

/* The child of the edge of d on d's side (OpenSubdiv's edge masks). */
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
        /* A semi-sharp edge below 1 blends the crease and smooth masks by
         * its sharpness (Sdc::Scheme::ComputeEdgeVertexMask). */
        double wc = s > 0 ? s : 0;
        for (int k = 0; k < 2; k++) p[k] = wc * mid[k] + (1 - wc) * p[k];
    }
    put_child(w, st_phi1(m, d, L), p, label);
    put_child(w, st_phi_1(m, n, L), p, label);
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
static uint32_t prev_corner(const work *w, const vert *v, uint32_t j)
{
    uint32_t p = j ? v->c[j - 1] : (v->hole != ST_NIL ? v->hole : v->c[v->n - 1]);
    return st_beta0(w->m, p, w->l);
}

/* The vertex child's corners are the coarse corners themselves (old
 * darts keep their vertex) and keep their labels. */
static void put_vertex(work *w, uint32_t d, const double p[2])
{
    put_child(w, d, p, w->val[d]);
}

static void set_all(work *w, const vert *v, const double p[2])
{
    for (uint32_t j = 0; j < v->n; j++) put_vertex(w, v->c[j], p);
}

static void keep_all(work *w, const vert *v)
{
    for (uint32_t j = 0; j < v->n; j++) put_vertex(w, v->c[j], at2(w->uv, v->c[j]));
}

enum vrule { RULE_SMOOTH, RULE_CREASE, RULE_CORNER };

/* The vertex rule from its sharpness and its incident edges' (the
 * parent's, or decayed for the child's), and a crease's two far ends. */
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
    double n = v->n, se[2] = {0, 0}, sf[2] = {0, 0};
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

/* Sdc::Crease::ComputeFractionalWeightAtVertex: the mean parent sharpness
 * of the features that become smooth, at most 1. */
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

/* A vertex whose face-varying topology matches the mesh's: the scheme's
 * vertex rule with its semi-sharp blend (Sdc::Scheme::ComputeVertexVertexMask). */
static void matched_vertex(work *w, const vert *v)
{
    float vs = vertex_sharp(w, v);
    const double *pe[2] = {0, 0}, *ce[2] = {0, 0};
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

/* A value of a mismatched vertex: the corners c[j] with that label. */
typedef struct span {
    uint32_t label, size, runs, first, last;  /* first/last: the run's ends (when one run) */
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

/* The spans of a vertex with several values (Vtr::FVarLevel::gatherValueSpans):
 * runs of consecutive corners with one label; a value is disjoint when it
 * has several runs or a discontinuous or infinitely sharp edge inside one. */
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
        /* One value, mismatched by a face-varying boundary ending here (a
         * dart) or by a sharpened corner: a crease across its one
         * discontinuous edge, else a corner. */
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
                if (w->val[v->c[j]] == sp[s].label) {
                    put_vertex(w, v->c[j], at2(w->uv, v->c[j]));
                }
        } else {
            crease_value(w, v, &sp[s]);
        }
    }
}

/* Vtr::FVarLevel::completeTopologyFromFaceValues, for one vertex. */
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

static int gather_vertex(work *w, uint32_t d, vert *v)
{
    st_map *m = w->m;
    unsigned l = w->l;
    uint32_t n = 0, x = d;
    v->hole = ST_NIL;
    do {
        if (n == w->cap_c) {
            uint32_t cap = w->cap_c ? 2 * w->cap_c : 16;
            uint32_t *c = realloc(w->c, cap * sizeof *c);
            if (!c) return -1;
            w->c = c;
            w->cap_c = cap;
        }
        if (st_is_boundary(m, x)) v->hole = x;
        w->c[n++] = x;
        x = st_beta1(m, x, l);
    } while (x != d);
    /* Rotate so that the corners start after the hole, and drop it. */
    if (w->cap_rot < n) {
        uint32_t *r = realloc(w->rot, (size_t)w->cap_c * sizeof *r);
        if (!r) return -1;
        w->rot = r;
        w->cap_rot = w->cap_c;
    }
    uint32_t first = 0, out = 0;
    if (v->hole != ST_NIL) while (w->c[first] != v->hole) first++;
    for (uint32_t i = 1; i <= n; i++) {
        uint32_t y = w->c[(first + i) % n];
        if (!st_is_boundary(m, y)) w->rot[out++] = y;
    }
    memcpy(w->c, w->rot, (size_t)out * sizeof *w->rot);
    v->c = w->c;
    v->n = out;
    return 0;
}

static int vertex_children(work *w)
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
        rc = gather_vertex(w, d, &v);
        if (!rc && v.n) vertex_child(w, &v);
    }
    free(done);
    return rc;
}

/* ---- level L ------------------------------------------------------------------ */

/* The inner triangle of a triangle split has no old dart: each corner is
 * the midpoint that the corner triangle across its edge has at φ1(β0(x)),
 * inside the same coarse face. */
static void inner_triangles(work *w)
{
    const st_map *m = w->m;
    unsigned L = w->L;
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, L, &it); x != ST_NIL; x = st_dart_next(m, L, &it)) {
        if (st_is_boundary(m, x) || m->darts.ins[x] < L) continue;
        uint32_t a = st_phi1(m, x, L), b = st_phi1(m, a, L);
        if (st_phi1(m, b, L) != x || m->darts.ins[a] < L || m->darts.ins[b] < L) continue;
        uint32_t y = st_phi1(m, st_beta0(m, x, L), L);
        put_child(w, x, at2(w->out->uv, y), w->out->val[y]);
    }
}

static int rules_of(const st_hier *h)
{
    switch (h->scheme->id) {
    case ST_SCHEME_CATMARK: return RULES_CATMARK;
    case ST_SCHEME_LOOP: return RULES_LOOP;
    case ST_SCHEME_BUTTERFLY:
    case ST_SCHEME_QUADTRI: return RULES_LINEAR;
    case ST_SCHEME_SQRT3:
    case ST_SCHEME_DOOSABIN: return RULES_STENCIL;
    default: return -1;
    }
}

int st_fvar_continues(const st_hier *h)
{
    return h->fvar && h->fvar->levels == h->map.top + 1 && rules_of(h) >= 0;
}

int st_fvar_refine(st_hier *h, st_error *err)
{
    st_fvar *f = h->fvar;
    unsigned L = h->map.top;
    if (L == 0 || !f || f->levels != L || rules_of(h) < 0) return ST_OK;
    st_map *m = &h->map;
    if (level_alloc(&f->lv[L], m->darts.end))
        return st_fail(err, ST_ERR_MEMORY, "out of memory subdividing texture coordinates to level %u", L);
    if (rules_of(h) == RULES_STENCIL) {
        if (st_fvar_refine_stencil(h, &f->lv[L - 1], &f->lv[L])) {
            level_free(&f->lv[L]);
            return st_fail(err, ST_ERR_MEMORY, "out of memory subdividing texture coordinates to level %u", L);
        }
        f->levels = L + 1;
        return ST_OK;
    }
    work w = { .h = h, .m = m, .l = L - 1, .L = L, .interp = f->interp, .rules = rules_of(h) };
    w.uv = f->lv[L - 1].uv;
    w.val = f->lv[L - 1].val;
    w.out = &f->lv[L];
    face_children(&w);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, L - 1, &it); d != ST_NIL; d = st_dart_next(m, L - 1, &it))
        if (!st_is_boundary(m, d)) edge_child(&w, d);
    int rc = vertex_children(&w);
    if (!rc) inner_triangles(&w);
    free(w.c);
    free(w.rot);
    if (rc) {
        level_free(&f->lv[L]);
        return st_fail(err, ST_ERR_MEMORY, "out of memory subdividing texture coordinates to level %u", L);
    }
    f->levels = L + 1;
    return ST_OK;
}

/* ---- levels removed, copies, soups ---------------------------------------------- */

void st_fvar_remove_top(st_hier *h)
{
    st_fvar *f = h->fvar;
    unsigned top = h->map.top;
    if (!f || top == 0 || f->levels <= top) return;
    level_free(&f->lv[top]);
    f->levels = top;
}

void st_fvar_remove_bottom(st_hier *h)
{
    st_fvar *f = h->fvar;
    if (!f || h->map.top == 0) return;
    level_free(&f->lv[0]);
    memmove(&f->lv[0], &f->lv[1], (ST_MAX_LEVELS - 1) * sizeof f->lv[0]);
    memset(&f->lv[ST_MAX_LEVELS - 1], 0, sizeof f->lv[0]);
    if (f->levels) f->levels--;
    if (!f->levels) st_fvar_free(h);
}

int st_fvar_copy(st_hier *dst, const st_hier *src)
{
    dst->fvar = NULL;
    const st_fvar *f = src->fvar;
    if (!f) return 0;
    st_fvar *g = calloc(1, sizeof *g);
    if (!g) return -1;
    g->interp = f->interp;
    g->levels = f->levels;
    dst->fvar = g;
    for (unsigned l = 0; l < f->levels; l++) {
        if (level_alloc(&g->lv[l], f->lv[l].cap)) { st_fvar_free(dst); return -1; }
        memcpy(g->lv[l].uv, f->lv[l].uv, 2 * (size_t)f->lv[l].cap * sizeof *g->lv[l].uv);
        memcpy(g->lv[l].val, f->lv[l].val, (size_t)f->lv[l].cap * sizeof *g->lv[l].val);
    }
    return 0;
}

int st_hier_uv_copy(st_hier *dst, const st_hier *src, size_t *bytes)
{
    if (st_fvar_copy(dst, src)) return -1;
    for (unsigned l = 0; bytes && dst->fvar && l < dst->fvar->levels; l++) *bytes += 20 * (size_t)dst->fvar->lv[l].cap;
    return 0;
}

void st_hier_uv_free(st_hier *h)
{
    st_fvar_free(h);
}

typedef struct uv_key { uint32_t vert, label, corner; } uv_key;

static int cmp_key(const void *pa, const void *pb)
{
    const uv_key *a = pa, *b = pb;
    if (a->vert != b->vert) return a->vert < b->vert ? -1 : 1;
    if (a->label != b->label) return a->label < b->label ? -1 : 1;
    return (a->corner > b->corner) - (a->corner < b->corner);
}

/* The corners of level l in the face walk of st_map_to_mesh
 * (core/map/map_mesh.c): φ1 orbits, or in the dual encoding β1 orbits,
 * faces with a hole dart or under 3 corners left out. */
static uint32_t level_corners(st_map *m, unsigned l, uint32_t *darts, uint32_t nc)
{
    int dual = m->face_embedded, fbit = st_marker_reserve(m);
    uint32_t c = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL && c < nc; d = st_dart_next(m, l, &it)) {
        if ((!dual && st_is_boundary(m, d)) || st_marked(m, fbit, d)) continue;
        uint32_t x = d, start = c;
        int real = 1;
        do {
            st_mark(m, fbit, x);
            if (st_is_boundary(m, x)) real = 0;
            else if (c < nc) darts[c++] = x;
            x = dual ? st_beta1(m, x, l) : st_phi1(m, x, l);
        } while (x != d);
        if (dual && (!real || c - start < 3)) c = start;
    }
    st_marker_release(m, fbit, l);
    return c;
}

int st_fvar_level_mesh(st_hier *h, unsigned l, st_mesh *out, st_error *err)
{
    const double *uv = st_hier_uv(h, l);
    if (!uv) return ST_OK;
    st_map *m = &h->map;
    const uint32_t *val = h->fvar->lv[l].val;
    uint32_t nc = out->nfaces ? out->face_off[out->nfaces] : 0;
    uv_key *k = malloc(((size_t)nc + 1) * sizeof *k);
    uint32_t *darts = malloc(((size_t)nc + 1) * sizeof *darts);
    out->face_uv = malloc(((size_t)nc + 1) * sizeof *out->face_uv);
    out->uv = malloc(2 * ((size_t)nc + 1) * sizeof *out->uv);
    if (!k || !darts || !out->face_uv || !out->uv) {
        free(k);
        free(darts);
        free(out->face_uv);
        free(out->uv);
        out->face_uv = NULL;
        out->uv = NULL;
        return st_fail(err, ST_ERR_MEMORY, "out of memory extracting the texture coordinates of level %u", l);
    }
    uint32_t c = level_corners(m, l, darts, nc);
    for (uint32_t i = 0; i < c; i++) k[i] = (uv_key){ out->face_idx[i], val[darts[i]], i };
    /* One texture coordinate per (vertex, value): seams stay seams. */
    qsort(k, c, sizeof *k, cmp_key);
    uint32_t nuv = 0;
    for (uint32_t i = 0; i < c; i++) {
        if (i == 0 || k[i].vert != k[i - 1].vert || k[i].label != k[i - 1].label) {
            const double *p = uv + 2 * (size_t)darts[k[i].corner];
            out->uv[2 * (size_t)nuv] = p[0];
            out->uv[2 * (size_t)nuv + 1] = p[1];
            nuv++;
        }
        out->face_uv[k[i].corner] = nuv - 1;
    }
    out->nuvs = nuv;
    free(k);
    free(darts);
    return ST_OK;
}
