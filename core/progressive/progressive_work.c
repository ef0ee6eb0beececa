/* The working copy of a progressive build: grouped independent half-edge
 * collapses ranked by quadrics (progressive.h, design points 1-3). */
#include "core/progressive/progressive_internal.h"
#include "core/multires/hier_internal.h"
#include "core/base/parallel.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- construction ------------------------------------------------------------ */

static void quad_add_plane(double *q, const double n[3], double dist, double wgt)
{
    double a = n[0], b = n[1], c = n[2], d = dist;
    q[0] += wgt * a * a; q[1] += wgt * a * b; q[2] += wgt * a * c; q[3] += wgt * a * d;
    q[4] += wgt * b * b; q[5] += wgt * b * c; q[6] += wgt * b * d;
    q[7] += wgt * c * c; q[8] += wgt * c * d; q[9] += wgt * d * d;
}

static double quad_eval(const double *q, const double p[3])
{
    double x = p[0], y = p[1], z = p[2];
    return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x
         + q[4] * y * y + 2 * q[5] * y * z + 2 * q[6] * y
         + q[7] * z * z + 2 * q[8] * z + q[9];
}


/* ---- level 0's placement (pm_work_fit_coarse) ---------------------------------- */

/* Whether moving v from pos to x turns a real face around it by more than
 * 60 degrees or shrinks it to under a thousandth of its area. */
static int fit_folds(const pm_work *w, uint32_t v, const double *pos, const double x[3])
{
    uint32_t e0 = w->vhe[v], e = e0;
    do {
        if (!(w->hflags[e] & PM_HE_BOUNDARY)) {
            const double *pv = pos + 3 * (size_t)v, *pb = pos + 3 * (size_t)pm_dest(w, e),
                         *pc = pos + 3 * (size_t)pm_dest(w, w->next[e]);
            double e1[3], e2[3], n0[3], n1[3];
            st_sub3(pb, pv, e1);
            st_sub3(pc, pv, e2);
            st_cross3(e1, e2, n0);
            st_sub3(pb, x, e1);
            st_sub3(pc, x, e2);
            st_cross3(e1, e2, n1);
            double l0 = sqrt(st_dot3(n0, n0)), l1 = sqrt(st_dot3(n1, n1));
            if (!(l1 > 1e-3 * l0) || !(st_dot3(n0, n1) >= 0.5 * l0 * l1)) return 1;
        }
        e = pm_rot(w, e);
    } while (e != e0);
    return 0;
}

/* argmin of quadric q (10 coefficients, quad_add_plane's order) plus
 * lam |x - p|^2, by Cramer's rule on the symmetric 3x3 system; 0 when
 * singular or not finite. */
static int quad_minimum(const double *q, double lam, const double p[3], double x[3])
{
    double a00 = q[0] + lam, a01 = q[1], a02 = q[2], a11 = q[4] + lam, a12 = q[5], a22 = q[7] + lam;
    double b0 = lam * p[0] - q[3], b1 = lam * p[1] - q[6], b2 = lam * p[2] - q[8];
    double c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22, c02 = a01 * a12 - a02 * a11;
    double c11 = a00 * a22 - a02 * a02, c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
    double det = a00 * c00 + a01 * c01 + a02 * c02;
    if (!(fabs(det) > 0)) return 0;
    x[0] = (c00 * b0 + c01 * b1 + c02 * b2) / det;
    x[1] = (c01 * b0 + c11 * b1 + c12 * b2) / det;
    x[2] = (c02 * b0 + c12 * b1 + c22 * b2) / det;
    return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]);
}

void pm_work_fit_coarse(const pm_work *w, double *pos)
{
    for (uint32_t v = 0; v < w->nv; v++) {
        if (w->vdead[v]) continue;
        const double *q = w->quad + 10 * (size_t)v;
        double tr = q[0] + q[4] + q[7], x[3];
        if (!(tr > 0) || !quad_minimum(q, 1e-3 * tr / 3, pos + 3 * (size_t)v, x) || fit_folds(w, v, pos, x)) continue;
        memcpy(pos + 3 * (size_t)v, x, sizeof x);
    }
}

/* Plane quadrics of the input (Garland-Heckbert 97 §5: weighted by area),
 * and for each boundary edge the plane through it perpendicular to its
 * face, weighted by the squared edge length times a penalty, so that a
 * border is simplified along itself (Garland-Heckbert 97 §6.1). */
static void init_quadrics(pm_work *w)
{
    const double boundary_penalty = 100.0;
    for (uint32_t h = 0; h < w->nreal; h += 3) {
        const double *p0 = w->pos + 3 * (size_t)w->org[h], *p1 = w->pos + 3 * (size_t)w->org[h + 1],
                     *p2 = w->pos + 3 * (size_t)w->org[h + 2];
        double e1[3], e2[3], n[3];
        st_sub3(p1, p0, e1);
        st_sub3(p2, p0, e2);
        st_cross3(e1, e2, n);
        double len = sqrt(st_dot3(n, n));
        if (len <= 0) continue;
        for (int i = 0; i < 3; i++) n[i] /= len;
        double area = 0.5 * len, dist = -st_dot3(n, p0);
        for (int k = 0; k < 3; k++) quad_add_plane(w->quad + 10 * (size_t)w->org[h + k], n, dist, area);
        for (int k = 0; k < 3; k++) {
            uint32_t e = h + (uint32_t)k;
            if (!(w->hflags[w->twin[e]] & PM_HE_BOUNDARY)) continue;
            const double *a = w->pos + 3 * (size_t)w->org[e], *b = w->pos + 3 * (size_t)pm_dest(w, e);
            double ed[3], m[3];
            st_sub3(b, a, ed);
            st_cross3(ed, n, m);
            double ml = sqrt(st_dot3(m, m));
            if (ml <= 0) continue;
            for (int i = 0; i < 3; i++) m[i] /= ml;
            double wgt = boundary_penalty * st_dot3(ed, ed);
            quad_add_plane(w->quad + 10 * (size_t)w->org[e], m, -st_dot3(m, a), wgt);
            quad_add_plane(w->quad + 10 * (size_t)pm_dest(w, e), m, -st_dot3(m, a), wgt);
        }
    }
}

void pm_work_free(pm_work *w)
{
    free(w->twin); free(w->next); free(w->prev); free(w->org); free(w->hflags);
    free(w->vhe); free(w->vdead); free(w->quad); free(w->stamp); free(w->indep); free(w->vbound);
    free(w->col); free(w->group_beg); free(w->log);
    memset(w, 0, sizeof *w);
}

void pm_work_drop_topology(pm_work *w)
{
    free(w->twin); free(w->next); free(w->prev); free(w->org); free(w->hflags);
    free(w->vhe); free(w->quad); free(w->stamp); free(w->indep); free(w->vbound); free(w->log);
    w->twin = w->next = w->prev = w->org = w->vhe = w->stamp = NULL;
    w->hflags = w->indep = w->vbound = NULL;
    w->quad = NULL;
    w->log = NULL;
    w->nlog = w->caplog = 0;
}

static uint32_t stamp_next(pm_work *w)
{
    if (++w->stamp_gen == 0) {
        memset(w->stamp, 0, w->nv * sizeof *w->stamp);
        w->stamp_gen = 1;
    }
    return w->stamp_gen;
}

/* Twins of the input's half-edges: u -> v meets the half-edge v -> u among
 * those leaving v, grouped by origin by one counting pass (first[v + 1]
 * holds v's out-degree on entry), instead of a sort of all directed
 * edges.  A directed edge used twice is reported as a sort would find it
 * first: the smallest origin, then the smallest destination. */
static int match_twins(pm_work *w, uint32_t *first, uint32_t *outs, st_error *err)
{
    for (uint32_t v = 0; v < w->nv; v++) first[v + 1] += first[v];
    for (uint32_t h = 0; h < w->nreal; h++) outs[first[w->org[h]]++] = h;
    for (uint32_t v = w->nv; v > 0; v--) first[v] = first[v - 1]; /* the fill advanced each start to the next's */
    first[0] = 0;
    for (uint32_t u = 0; u < w->nv; u++) {
        uint32_t g = stamp_next(w), twice = ST_NIL;
        for (uint32_t i = first[u]; i < first[u + 1]; i++) {
            uint32_t v = pm_dest(w, outs[i]);
            if (w->stamp[v] == g && v < twice) twice = v;
            w->stamp[v] = g;
        }
        if (twice != ST_NIL)
            return st_fail(err, ST_ERR_TOPOLOGY, "progressive: edge %u-%u is used twice in one direction (not a manifold)", u, twice);
    }
    for (uint32_t h = 0; h < w->nreal; h++) {
        if (w->twin[h] != ST_NIL) continue;
        uint32_t u = w->org[h], v = pm_dest(w, h);
        for (uint32_t i = first[v]; i < first[v + 1]; i++)
            if (pm_dest(w, outs[i]) == u) {
                w->twin[h] = outs[i];
                w->twin[outs[i]] = h;
                break;
            }
    }
    return ST_OK;
}

int pm_work_init(pm_work *w, const double *pos, uint32_t nv, const uint32_t *tri, uint32_t nt, st_error *err)
{
    memset(w, 0, sizeof *w);
    if (nt == 0) return st_fail(err, ST_ERR_TOPOLOGY, "progressive: the mesh has no face");
    if ((uint64_t)nt * 6 >= 0xfffffff0u) return st_fail(err, ST_ERR_RANGE, "progressive: %u triangles are too many", nt);
    w->nv = nv;
    w->pos = pos;
    w->nreal = 3 * nt;
    uint32_t cap = 2 * w->nreal; /* at most one boundary half-edge per real one */
    w->twin = malloc(cap * sizeof *w->twin);
    w->next = malloc(cap * sizeof *w->next);
    w->prev = malloc(cap * sizeof *w->prev);
    w->org = malloc(cap * sizeof *w->org);
    w->hflags = calloc(cap, 1);
    w->vhe = malloc((size_t)(nv ? nv : 1) * sizeof *w->vhe);
    w->vdead = calloc(nv ? nv : 1, 1);
    w->quad = calloc(10 * (size_t)(nv ? nv : 1), sizeof *w->quad);
    w->stamp = calloc(nv ? nv : 1, sizeof *w->stamp);
    w->indep = calloc(nv ? nv : 1, 1);
    w->vbound = calloc(nv ? nv : 1, 1);
    /* outs[first[v] .. first[v + 1]): the half-edges leaving v, in id order */
    uint32_t *first = calloc((size_t)nv + 1, sizeof *first);
    uint32_t *outs = malloc(w->nreal * sizeof *outs);
    uint32_t *bout = malloc((size_t)(nv ? nv : 1) * sizeof *bout);
    int rc = ST_OK;
    if (!w->twin || !w->next || !w->prev || !w->org || !w->hflags || !w->vhe || !w->vdead || !w->quad || !w->stamp ||
        !w->indep || !w->vbound || !first || !outs || !bout) {
        rc = st_fail(err, ST_ERR_MEMORY, "progressive: out of memory for %u triangles", nt);
        goto done;
    }
    for (uint32_t v = 0; v < nv; v++) { w->vhe[v] = ST_NIL; bout[v] = ST_NIL; }
    for (uint32_t f = 0; f < nt; f++)
        for (uint32_t k = 0; k < 3; k++) {
            uint32_t h = 3 * f + k, u = tri[h], v = tri[3 * f + (k + 1) % 3];
            if (u >= nv || u == v) { rc = st_fail(err, ST_ERR_TOPOLOGY, "progressive: triangle %u is degenerate", f); goto done; }
            w->org[h] = u;
            w->next[h] = 3 * f + (k + 1) % 3;
            w->prev[h] = 3 * f + (k + 2) % 3;
            w->twin[h] = ST_NIL;
            w->vhe[u] = h;
            first[u + 1]++;
        }
    rc = match_twins(w, first, outs, err);
    if (rc) goto done;
    /* Holes: one boundary half-edge opposite each unmatched one. */
    w->nhe = w->nreal;
    for (uint32_t h = 0; h < w->nreal; h++) {
        if (w->twin[h] != ST_NIL) continue;
        uint32_t b = w->nhe++, u = w->org[w->next[h]];
        w->org[b] = u;
        w->hflags[b] = PM_HE_BOUNDARY;
        w->twin[b] = h;
        w->twin[h] = b;
        if (bout[u] != ST_NIL) {
            rc = st_fail(err, ST_ERR_TOPOLOGY, "progressive: vertex %u touches two holes (not a manifold)", u);
            goto done;
        }
        bout[u] = b;
    }
    for (uint32_t b = w->nreal; b < w->nhe; b++) {
        uint32_t v = w->org[w->twin[b]]; /* b runs from org to v */
        w->next[b] = bout[v];
        w->prev[bout[v]] = b;
    }
    for (uint32_t v = 0; v < nv; v++) {
        if (w->vhe[v] == ST_NIL) { w->vdead[v] = 1; continue; } /* unused vertex */
        w->verts++;
    }
    w->faces = nt;
    init_quadrics(w);
done:
    free(first);
    free(outs);
    free(bout);
    if (rc) pm_work_free(w);
    return rc;
}

/* ---- checks ------------------------------------------------------------------ */

static unsigned valence(const pm_work *w, uint32_t v)
{
    unsigned n = 0;
    uint32_t h = w->vhe[v], x = h;
    do { n++; x = pm_rot(w, x); } while (x != h);
    return n;
}

/* Normal of the triangle of half-edge h with vertex `moved` at q. */
static void tri_normal(const pm_work *w, uint32_t h, uint32_t moved, const double *q, double n[3])
{
    const double *p[3];
    uint32_t x = h;
    for (int k = 0; k < 3; k++, x = w->next[x]) p[k] = w->org[x] == moved ? q : w->pos + 3 * (size_t)w->org[x];
    double e1[3], e2[3];
    st_sub3(p[1], p[0], e1);
    st_sub3(p[2], p[0], e2);
    st_cross3(e1, e2, n);
}

/* The topological and geometric conditions of a collapse h = a -> b
 * (progressive.h, point 2), on the current mesh. */
static int collapse_ok(pm_work *w, uint32_t h)
{
    uint32_t t = w->twin[h], a = w->org[h], b = pm_dest(w, h);
    int bedge = (w->hflags[t] & PM_HE_BOUNDARY) != 0;
    if (w->vbound[a] && !bedge) return 0;
    uint32_t c = w->org[w->prev[h]], d = bedge ? ST_NIL : w->org[w->prev[t]];
    /* link condition and the merged valence */
    uint32_t g = stamp_next(w);
    unsigned na = 0, nb = 0, common = 0;
    uint32_t x = h;
    do { w->stamp[pm_dest(w, x)] = g; na++; x = pm_rot(w, x); } while (x != h);
    x = w->next[h]; /* b -> c leaves b */
    uint32_t start = x;
    do {
        uint32_t n = pm_dest(w, x);
        nb++;
        if (w->stamp[n] == g) {
            if (n != c && n != d) return 0;
            common++;
        }
        x = pm_rot(w, x);
    } while (x != start);
    if (common != (bedge ? 1u : 2u)) return 0;
    unsigned merged = na + nb - (bedge ? 3u : 4u);
    if (merged < (w->vbound[a] || w->vbound[b] ? 2u : 3u)) return 0;
    if (bedge && nb < 3) return 0;               /* b would keep no dart of its own when split back */
    unsigned vc = valence(w, c);
    if (vc < (w->vbound[c] ? 3u : 4u)) return 0;
    if (!bedge) {
        unsigned vd = valence(w, d);
        if (vd < (w->vbound[d] ? 3u : 4u)) return 0;
    }
    /* no face around a flips */
    const double *q = w->pos + 3 * (size_t)b;
    x = h;
    do {
        if (!(w->hflags[x] & PM_HE_BOUNDARY) && x != h && x != w->next[t]) {
            double n0[3], n1[3];
            tri_normal(w, x, a, w->pos + 3 * (size_t)a, n0);
            tri_normal(w, x, a, q, n1);
            if (st_dot3(n0, n1) <= 0) return 0;
        }
        x = pm_rot(w, x);
    } while (x != h);
    return 1;
}

/* ---- collapse and undo ---------------------------------------------------------- */

static int log_he(pm_work *w, uint32_t h)
{
    if (w->nlog == w->caplog) {
        uint32_t cap = w->caplog ? 2 * w->caplog : 1024;
        pm_rec *p = realloc(w->log, cap * sizeof *p);
        if (!p) return -1;
        w->log = p;
        w->caplog = cap;
    }
    w->log[w->nlog++] = (pm_rec){ h, w->twin[h], w->next[h], w->prev[h], w->org[h], w->hflags[h] };
    return 0;
}

static int collapse(pm_work *w, uint32_t h)
{
    if (w->ncol == w->capcol) {
        uint32_t cap = w->capcol ? 2 * w->capcol : 256;
        pm_collapse *p = realloc(w->col, cap * sizeof *p);
        if (!p) return -1;
        w->col = p;
        w->capcol = cap;
    }
    uint32_t t = w->twin[h], a = w->org[h], b = pm_dest(w, h);
    int bedge = (w->hflags[t] & PM_HE_BOUNDARY) != 0;
    uint32_t h1 = w->next[h], h2 = w->next[h1], c = w->org[h2];
    uint32_t t1 = w->next[t], t2 = bedge ? ST_NIL : w->next[t1], d = bedge ? ST_NIL : w->org[t2];
    uint32_t o1 = w->twin[h1], o2 = w->twin[h2];
    pm_collapse *cl = &w->col[w->ncol];
    *cl = (pm_collapse){ h, a, b, c, d, w->nlog, 0, { w->vhe[a], w->vhe[b], w->vhe[c], d != ST_NIL ? w->vhe[d] : ST_NIL } };
    int rc = 0;
    uint32_t x = h;
    do { rc |= log_he(w, x); x = pm_rot(w, x); } while (x != h);
    rc |= log_he(w, h1) | log_he(w, h2) | log_he(w, t) | log_he(w, o1) | log_he(w, o2);
    uint32_t o3 = ST_NIL, o4 = ST_NIL, p = ST_NIL, n = ST_NIL;
    if (!bedge) {
        o3 = w->twin[t1];
        o4 = w->twin[t2];
        rc |= log_he(w, t1) | log_he(w, t2) | log_he(w, o3) | log_he(w, o4);
    } else {
        p = w->prev[t];
        n = w->next[t];
        rc |= log_he(w, p) | log_he(w, n);
    }
    if (rc) return -1;
    cl->rec_end = w->nlog;
    w->ncol++;
    x = h;
    do { w->org[x] = b; x = pm_rot(w, x); } while (x != h);
    w->twin[o1] = o2;
    w->twin[o2] = o1;
    w->hflags[h] |= PM_HE_DEAD;
    w->hflags[h1] |= PM_HE_DEAD;
    w->hflags[h2] |= PM_HE_DEAD;
    w->hflags[t] |= PM_HE_DEAD;
    if (!bedge) {
        w->twin[o3] = o4;
        w->twin[o4] = o3;
        w->hflags[t1] |= PM_HE_DEAD;
        w->hflags[t2] |= PM_HE_DEAD;
        w->vhe[d] = o3;
        w->faces -= 2;
    } else {
        w->next[p] = n;
        w->prev[n] = p;
        w->faces -= 1;
    }
    w->vhe[c] = o1;
    w->vhe[b] = o2;
    w->vdead[a] = 1;
    w->verts--;
    double *qa = w->quad + 10 * (size_t)a, *qb = w->quad + 10 * (size_t)b;
    for (int i = 0; i < 10; i++) qb[i] += qa[i];
    return 0;
}

void pm_undo(pm_work *w, uint32_t i)
{
    const pm_collapse *cl = &w->col[i];
    for (uint32_t r = cl->rec_end; r-- > cl->rec_beg;) {
        const pm_rec *e = &w->log[r];
        w->twin[e->he] = e->twin;
        w->next[e->he] = e->next;
        w->prev[e->he] = e->prev;
        w->org[e->he] = e->org;
        w->hflags[e->he] = e->flags;
    }
    w->vdead[cl->a] = 0;
    w->vhe[cl->a] = cl->vhe[0];
    w->vhe[cl->b] = cl->vhe[1];
    w->vhe[cl->c] = cl->vhe[2];
    if (cl->d != ST_NIL) w->vhe[cl->d] = cl->vhe[3];
    w->verts++;
    w->faces += cl->d != ST_NIL ? 2 : 1;
}

/* ---- grouped simplification ------------------------------------------------------ */

typedef struct cand { uint32_t hi, lo, he; } cand; /* a cost key's halves (cost_key), 12 bytes */

/* The order of costs as unsigned integers: the bits of a non-negative
 * double, with the sign bit set, rank as its value; a negative one (a
 * rounding below zero) has all its bits flipped, so that it ranks below
 * them and by its value too; -0 counts as +0, so that equal costs tie and
 * are ranked by half-edge, as the comparison sort ranked them. */
static uint64_t cost_key(double cost)
{
    uint64_t u;
    if (cost == 0) cost = 0;
    memcpy(&u, &cost, sizeof u);
    return u >> 63 ? ~u : u | UINT64_C(1) << 63;
}

static uint32_t key_half(const cand *c, int low) { return low ? c->lo : c->hi; }

/* Stable least-significant-digit radix sort of a[0, n) by the low or the
 * high half of the key, in `passes` digits of `bits` (passes * bits >= 32,
 * passes << bits <= 3 << 11), skipping the digits every key shares; b
 * holds n more.  Returns a or b: the one that holds the result. */
static cand *radix_sort(cand *a, cand *b, uint32_t n, int low, unsigned bits, unsigned passes)
{
    uint32_t count[3u << 11];
    const uint32_t nb = 1u << bits, mask = nb - 1;
    memset(count, 0, (size_t)passes * nb * sizeof *count);
    for (uint32_t i = 0; i < n; i++)
        for (unsigned p = 0; p < passes; p++) count[p * nb + ((key_half(&a[i], low) >> (p * bits)) & mask)]++;
    for (unsigned p = 0; p < passes && n; p++) {
        unsigned shift = p * bits;
        uint32_t *c = count + p * nb;
        if (c[(key_half(&a[0], low) >> shift) & mask] == n) continue; /* one digit for all: already in order */
        uint32_t sum = 0;
        for (uint32_t d = 0; d < nb; d++) { uint32_t k = c[d]; c[d] = sum; sum += k; }
        for (uint32_t i = 0; i < n; i++) b[c[(key_half(&a[i], low) >> shift) & mask]++] = a[i];
        cand *t = a; a = b; b = t;
    }
    return a;
}

/* Candidates ranked by key, stably (equal keys keep the half-edge order
 * they were gathered in), in place of a comparison sort (qsort took 4/5 of
 * the grouped collapses' instructions): a radix sort by the high 32 bits
 * (sign, exponent, 20 bits of mantissa) at once, and by the low 32 bits
 * run by run as the group reaches them (a group looks at its cheapest
 * 40 % or so only): runs of equal high halves are short (costs that agree
 * to a millionth), or hold equal costs, already in order. */
typedef struct ranking { cand *cs, *tmp; uint32_t n, sorted; } ranking;

static void rank_begin(ranking *r, cand *cs, cand *tmp, uint32_t n)
{
    r->cs = radix_sort(cs, tmp, n, 0, 11, 3);
    r->tmp = r->cs == cs ? tmp : cs;
    r->n = n;
    r->sorted = 0;
}

/* The candidate of rank i, i from 0 up, one at a time. */
static uint32_t rank_get(ranking *r, uint32_t i)
{
    cand *cs = r->cs;
    if (i == r->sorted) { /* the next run of equal high halves: order it by the low half */
        uint32_t j = i + 1;
        while (j < r->n && cs[j].hi == cs[i].hi) j++;
        if (j - i > 16) {
            cand *res = radix_sort(cs + i, r->tmp, j - i, 1, 8, 4);
            if (res != cs + i) memcpy(cs + i, res, (size_t)(j - i) * sizeof *cs);
        } else
            for (uint32_t k = i + 1; k < j; k++) { /* insertion, stable */
                cand c = cs[k];
                uint32_t m = k;
                for (; m > i && cs[m - 1].lo > c.lo; m--) cs[m] = cs[m - 1];
                cs[m] = c;
            }
        r->sorted = j;
    }
    return cs[i].he;
}

/* Marker bits of the independence rule (progressive.h, point 3), per
 * vertex and per group: the removed vertex of an accepted collapse or one
 * of its neighbours at the group's finer level; the target b of one. */
enum { IND_NEAR_REMOVED = 1, IND_TARGET = 2 };

static int independent(const pm_work *w, uint32_t h)
{
    return !(w->hflags[h] & PM_HE_DEAD) && !(w->indep[w->org[h]] & IND_NEAR_REMOVED) && !(w->indep[pm_dest(w, h)] & IND_TARGET);
}

/* Marks before the collapse, so that N(a) is a's ring at the finer level. */
static void claim(pm_work *w, uint32_t h)
{
    uint32_t x = h;
    w->indep[w->org[h]] |= IND_NEAR_REMOVED;
    w->indep[pm_dest(w, h)] |= IND_TARGET;
    do {
        w->indep[pm_dest(w, x)] |= IND_NEAR_REMOVED;
        x = pm_rot(w, x);
    } while (x != h);
}

/* The cost keys of the half-edges live[0, n) whose cost changed (all of
 * them when `all`), on several threads: each key is written by one
 * thread, from state no thread writes, so the keys are the same bits on
 * any number of threads.  A half-edge's cost changes only when its origin
 * or destination is the target b of a collapse of the previous group: b's
 * quadric grew, and the half-edges of the removed vertex now start or end
 * at b.  Those targets still carry IND_TARGET from that group's claims. */
typedef struct cost_job {
    const pm_work *w;
    const uint32_t *live;
    uint32_t n;
    uint64_t *hkey;
    int all;
} cost_job;

enum { COST_CHUNK = 4096 }; /* half-edges per piece; a thread for every 4 pieces at most */

static void update_costs(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    const cost_job *j = ctx;
    const pm_work *w = j->w;
    uint32_t beg, end;
    while (st_team_next(team, 0, j->n, COST_CHUNK, &beg, &end))
        for (uint32_t i = beg; i < end; i++) {
            uint32_t h = j->live[i];
            if (w->hflags[h] & PM_HE_DEAD) continue;
            uint32_t a = w->org[h], b = pm_dest(w, h);
            if (!j->all && !((w->indep[a] | w->indep[b]) & IND_TARGET)) continue;
            const double *pb = w->pos + 3 * (size_t)b;
            j->hkey[h] = cost_key(quad_eval(w->quad + 10 * (size_t)a, pb) + quad_eval(w->quad + 10 * (size_t)b, pb));
        }
}

int pm_simplify(pm_work *w, uint64_t target, unsigned max_groups, int (*progress)(void *, double), void *ctx,
                char *note, size_t notesz, st_error *err)
{
    uint64_t start_faces = w->faces;
    /* One block for the scratch: per real half-edge its cost's key (kept
     * across groups), two candidate buffers, the live list (the real
     * half-edges not dead before the group, in order).  Measured with four
     * separate blocks: after three builds in one process, the sword's
     * simplification took 3.4 k minor page faults (12-36 ms of system
     * time); with one block, none. */
    uint64_t *hkey = malloc((size_t)w->nreal * (sizeof *hkey + 2 * sizeof(cand) + sizeof(uint32_t)));
    cand *cs = hkey ? (cand *)(hkey + w->nreal) : NULL, *tmp = cs ? cs + w->nreal : NULL;
    uint32_t *live = tmp ? (uint32_t *)(tmp + w->nreal) : NULL, nlive = w->nreal;
    w->group_beg = malloc(((size_t)max_groups + 1) * sizeof *w->group_beg);
    if (!hkey || !w->group_beg) {
        free(hkey);
        return st_fail(err, ST_ERR_MEMORY, "progressive: out of memory");
    }
    for (uint32_t h = 0; h < w->nreal; h++) live[h] = h;
    snprintf(note, notesz, "reached the target of %llu faces", (unsigned long long)target);
    int rc = ST_OK;
    w->ngroups = 0;
    w->group_beg[0] = 0;
    while (w->faces > target) {
        if (w->ngroups == max_groups) {
            snprintf(note, notesz, "stopped at the limit of %u levels with %llu faces", max_groups + 1,
                     (unsigned long long)w->faces);
            break;
        }
        memset(w->vbound, 0, w->nv);
        for (uint32_t h = w->nreal; h < w->nhe; h++)
            if (!(w->hflags[h] & PM_HE_DEAD)) w->vbound[w->org[h]] = 1;
        cost_job job = { w, live, nlive, hkey, w->ngroups == 0 };
        unsigned threads = st_parallel_threads(), most = nlive / (4 * COST_CHUNK);
        st_team_run(threads < most ? threads : most ? most : 1, update_costs, &job);
        uint32_t nc = 0, nalive = 0;
        for (uint32_t i = 0; i < nlive; i++) {
            uint32_t h = live[i];
            if (w->hflags[h] & PM_HE_DEAD) continue;
            live[nalive++] = h;
            uint32_t a = w->org[h];
            if (w->vbound[a] && !(w->hflags[w->twin[h]] & PM_HE_BOUNDARY)) continue;
            cs[nc++] = (cand){ (uint32_t)(hkey[h] >> 32), (uint32_t)hkey[h], h };
        }
        nlive = nalive;
        memset(w->indep, 0, w->nv);
        ranking rk;
        rank_begin(&rk, cs, tmp, nc);
        uint32_t before = w->ncol;
        /* Quality: a group takes its collapses among the cheapest 40 % of
         * the candidate half-edges only, so that it does not pay for its
         * size with collapses a sequential simplification would put off.
         * Measured on koala (bench_progressive, 1 % of the faces): all
         * candidates: 16 levels, Hausdorff 1.17x and RMS 1.22x OpenMesh's;
         * 60 %: 17 levels, 1.26x, 1.12x; 40 %: 17 levels, 1.00x, 1.06x;
         * 25 %: 19 levels, 0.95x, 1.04x. */
        uint32_t last = (uint32_t)(0.4 * nc);
        for (uint32_t i = 0; i < nc && w->faces > target; i++) {
            if (i >= last && w->ncol > before) break; /* past the cheapest part, unless it had none allowed */
            uint32_t h = rank_get(&rk, i);
            if (!independent(w, h) || !collapse_ok(w, h)) continue;
            claim(w, h);
            if (collapse(w, h)) { rc = st_fail(err, ST_ERR_MEMORY, "progressive: out of memory"); break; }
        }
        if (rc) break;
        if (w->ncol == before) {
            snprintf(note, notesz, "no collapse is allowed any more at %llu faces (the link condition, valences or "
                     "boundaries forbid every one)", (unsigned long long)w->faces);
            break;
        }
        w->group_beg[++w->ngroups] = w->ncol;
        if (progress) {
            double f = start_faces > target ? (double)(start_faces - w->faces) / (double)(start_faces - target) : 1.0;
            if (progress(ctx, 0.8 * f)) { rc = st_fail(err, ST_ERR_INVALID, "progressive: cancelled"); break; }
        }
    }
    free(hkey);
    return rc;
}
