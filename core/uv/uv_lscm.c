/* Flattening a chart (core/uv/uv.h step 2): least squares conformal maps,
 * Lévy, Petitjean, Ray, Maillot 2002, §3.
 *
 * Each triangle T, in coordinates (x_j, y_j) of its own plane, asks that
 * the map U = u + i v be conformal on it (Cauchy-Riemann, §3.2), which
 * §3.3 writes as one complex equation Σ_j W_j U_j = 0 with
 * W_1 = (x_3 − x_2) + i (y_3 − y_2) and cyclically, weighted by 1/√d_T
 * (d_T twice the area of T).  With two vertices pinned the system
 * M U = 0 has a unique least-squares solution (§3.4, Theorem 2).  It is
 * solved in real form (two rows per triangle, two unknowns per vertex) by
 * conjugate gradients on the normal equations, CGLS (Björck, "Numerical
 * Methods for Least Squares Problems", 1996, §7.4.1), started from the
 * projection on the chart's mean plane, whose two pins (the ends of a 3D
 * diameter, found by two farthest-point sweeps; §5 pins the extremes of
 * the chart's principal axis) keep their projected positions.
 *
 * A map that flips a triangle or whose border crosses itself is not used: the projection is tried, and
 * when that flips too the caller splits the chart. */
#include "core/uv/uv_internal.h"

#include <math.h>
#include <string.h>

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* r = A x: two rows per triangle. */
static void apply(const uv_ctx *c, uint32_t nt, const double *x, double *r)
{
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *v = c->tv + 3 * (size_t)t;
        const double *w = c->tw + 6 * (size_t)t;
        double re = 0, im = 0;
        for (int j = 0; j < 3; j++) {
            double u = x[2 * (size_t)v[j]], vv = x[2 * (size_t)v[j] + 1], a = w[2 * j], b = w[2 * j + 1];
            re += a * u - b * vv;
            im += b * u + a * vv;
        }
        r[2 * (size_t)t] = re;
        r[2 * (size_t)t + 1] = im;
    }
}

/* s = Aᵀ r, zero on the pinned unknowns. */
static void apply_t(const uv_ctx *c, uint32_t nt, uint32_t nv, const double *r, double *s, const uint32_t pin[2])
{
    memset(s, 0, 2 * (size_t)nv * sizeof *s);
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *v = c->tv + 3 * (size_t)t;
        const double *w = c->tw + 6 * (size_t)t;
        double r0 = r[2 * (size_t)t], r1 = r[2 * (size_t)t + 1];
        for (int j = 0; j < 3; j++) {
            double a = w[2 * j], b = w[2 * j + 1];
            s[2 * (size_t)v[j]] += a * r0 + b * r1;
            s[2 * (size_t)v[j] + 1] += -b * r0 + a * r1;
        }
    }
    for (int k = 0; k < 2; k++) s[2 * (size_t)pin[k]] = s[2 * (size_t)pin[k] + 1] = 0;
}

static double dotn(const double *a, const double *b, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

/* Triangles whose UV area is not positive (among those with a 3D area). */
static uint32_t flips(const uv_ctx *c, uint32_t nt, const double *x)
{
    uint32_t bad = 0;
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *v = c->tv + 3 * (size_t)t;
        if (c->tw[6 * (size_t)t] == 0 && c->tw[6 * (size_t)t + 1] == 0 && c->tw[6 * (size_t)t + 2] == 0 &&
            c->tw[6 * (size_t)t + 3] == 0) continue; /* degenerate in 3D */
        const double *p = x + 2 * (size_t)v[0], *q = x + 2 * (size_t)v[1], *r = x + 2 * (size_t)v[2];
        double a = (q[0] - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (q[1] - p[1]);
        if (!(a > 0)) bad++;
    }
    return bad;
}

static int cross_proper(const double *a, const double *b, const double *c, const double *d)
{
    double d1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    double d2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
    double d3 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
    double d4 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

/* 1 when the chart's border crosses itself in x.  A map of a disk with no
 * flipped triangle is one-to-one exactly when its border is a simple curve
 * (a border that winds twice, around an interior vertex whose UV angles add
 * up to 4π, must cross itself: Hopf's Umlaufsatz); border edges that share
 * a vertex are not compared.  The chart's faces carry fmark == stamp. */
static int border_crosses(const uv_ctx *c, const uint32_t *faces, uint32_t n, const double *x)
{
    const st_uv_mesh *m = c->m;
    uint32_t nb = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = faces[i];
        for (uint32_t k = m->face_off[f]; k < m->face_off[f + 1]; k++) {
            uint32_t t = c->twin[k];
            if (t != UV_NIL && c->fmark[c->corner_face[t]] == c->stamp) continue;
            c->border[nb++] = k;
        }
    }
    for (uint32_t i = 0; i < nb; i++) {
        uint32_t ki = c->border[i], ai = c->vloc[m->face_idx[ki]], bi = c->vloc[m->face_idx[uv_next(m, c->corner_face, ki)]];
        const double *p = x + 2 * (size_t)ai, *q = x + 2 * (size_t)bi;
        double lo0 = fmin(p[0], q[0]), hi0 = fmax(p[0], q[0]), lo1 = fmin(p[1], q[1]), hi1 = fmax(p[1], q[1]);
        for (uint32_t j = i + 1; j < nb; j++) {
            uint32_t kj = c->border[j], aj = c->vloc[m->face_idx[kj]], bj = c->vloc[m->face_idx[uv_next(m, c->corner_face, kj)]];
            if (ai == aj || ai == bj || bi == aj || bi == bj) continue;
            const double *r = x + 2 * (size_t)aj, *s = x + 2 * (size_t)bj;
            if (fmax(r[0], s[0]) < lo0 || fmin(r[0], s[0]) > hi0 || fmax(r[1], s[1]) < lo1 || fmin(r[1], s[1]) > hi1) continue;
            if (cross_proper(p, q, r, s)) return 1;
        }
    }
    return 0;
}

/* The chart vertex farthest from vertex `from` (local indices). */
static uint32_t farthest(const uv_ctx *c, uint32_t nv, uint32_t from)
{
    const double *o = c->m->pos + 3 * (size_t)c->vlist[from];
    double best = -1;
    uint32_t arg = from;
    for (uint32_t i = 0; i < nv; i++) {
        const double *p = c->m->pos + 3 * (size_t)c->vlist[i];
        double dd = (p[0] - o[0]) * (p[0] - o[0]) + (p[1] - o[1]) * (p[1] - o[1]) + (p[2] - o[2]) * (p[2] - o[2]);
        if (dd > best) { best = dd; arg = i; }
    }
    return arg;
}

int uv_flatten(uv_ctx *c, const uint32_t *faces, uint32_t n, double *uv)
{
    const st_uv_mesh *m = c->m;
    uv_new_stamp(c);
    uint32_t st = c->stamp, nv = 0, nt = 0;
    double nrm[3] = { 0, 0, 0 }, area3 = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = faces[i];
        c->fmark[f] = st;
        for (int k = 0; k < 3; k++) nrm[k] += c->fn[3 * (size_t)f + k] * c->farea[f];
        area3 += c->farea[f];
        for (uint32_t k = m->face_off[f]; k < m->face_off[f + 1]; k++) {
            uint32_t v = m->face_idx[k];
            if (c->vmark[v] != st) { c->vmark[v] = st; c->vloc[v] = nv; c->vlist[nv++] = v; }
        }
    }
    /* The chart's frame: e1, e2 = n × e1 (so counter-clockwise faces stay so). */
    double len = sqrt(dot3(nrm, nrm));
    if (len > 0) for (int k = 0; k < 3; k++) nrm[k] /= len;
    else { nrm[0] = nrm[1] = 0; nrm[2] = 1; }
    double e1[3] = { 0, 0, 0 }, e2[3];
    int ax = fabs(nrm[0]) <= fabs(nrm[1]) ? (fabs(nrm[0]) <= fabs(nrm[2]) ? 0 : 2) : (fabs(nrm[1]) <= fabs(nrm[2]) ? 1 : 2);
    e1[ax] = 1;
    double d = dot3(e1, nrm);
    for (int k = 0; k < 3; k++) e1[k] -= d * nrm[k];
    len = sqrt(dot3(e1, e1));
    for (int k = 0; k < 3; k++) e1[k] /= len;
    cross3(nrm, e1, e2);
    for (uint32_t i = 0; i < nv; i++) {
        const double *p = m->pos + 3 * (size_t)c->vlist[i];
        c->x[2 * (size_t)i] = dot3(p, e1);
        c->x[2 * (size_t)i + 1] = dot3(p, e2);
    }
    /* Triangles and their coefficients W_j / √d_T (§3.3). */
    uint32_t (*tris)[3] = c->ftris;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = faces[i];
        unsigned k = st_uv_face_triangles(m, f, tris);
        for (unsigned t = 0; t < k; t++, nt++) {
            const double *p[3];
            uint32_t *tv = c->tv + 3 * (size_t)nt;
            double *w = c->tw + 6 * (size_t)nt;
            for (int j = 0; j < 3; j++) {
                uint32_t v = m->face_idx[tris[t][j]];
                tv[j] = c->vloc[v];
                p[j] = m->pos + 3 * (size_t)v;
            }
            double a[3] = { p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2] };
            double b[3] = { p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2] };
            double cr[3];
            cross3(a, b, cr);
            double d2 = sqrt(dot3(cr, cr)), la = sqrt(dot3(a, a));
            if (!(d2 > 1e-300) || !(la > 0)) { memset(w, 0, 6 * sizeof *w); continue; }
            double X[3] = { a[0] / la, a[1] / la, a[2] / la }, N[3] = { cr[0] / d2, cr[1] / d2, cr[2] / d2 }, Y[3];
            cross3(N, X, Y);
            double q[3][2] = { { 0, 0 }, { la, 0 }, { dot3(b, X), dot3(b, Y) } };
            double sc = 1 / sqrt(d2);
            for (int j = 0; j < 3; j++) {
                const double *q1 = q[(j + 1) % 3], *q2 = q[(j + 2) % 3];
                w[2 * j] = (q2[0] - q1[0]) * sc;
                w[2 * j + 1] = (q2[1] - q1[1]) * sc;
            }
        }
    }
    int how = 0;
    if (nv >= 3 && nt > 0) {
        /* Pins: the ends of a diameter (two farthest-point sweeps). */
        uint32_t pin[2];
        pin[0] = farthest(c, nv, 0);
        pin[1] = farthest(c, nv, pin[0]);
        size_t n2 = 2 * (size_t)nv, m2 = 2 * (size_t)nt;
        double *x = c->x, *r = c->r, *s = c->s, *p = c->p, *q = c->q;
        apply(c, nt, x, r);
        for (size_t i = 0; i < m2; i++) r[i] = -r[i];
        apply_t(c, nt, nv, r, s, pin);
        memcpy(p, s, n2 * sizeof *p);
        double gamma = dotn(s, s, n2), gamma0 = gamma;
        uint32_t maxit = 200 + 4 * nv;
        if (maxit > 6000) maxit = 6000;
        for (uint32_t it = 0; it < maxit && gamma > 1e-24 * gamma0 && gamma > 0; it++) {
            apply(c, nt, p, q);
            double qq = dotn(q, q, m2);
            if (!(qq > 0)) break;
            double alpha = gamma / qq;
            for (size_t i = 0; i < n2; i++) x[i] += alpha * p[i];
            for (size_t i = 0; i < m2; i++) r[i] -= alpha * q[i];
            apply_t(c, nt, nv, r, s, pin);
            double g2 = dotn(s, s, n2);
            double beta = g2 / gamma;
            gamma = g2;
            for (size_t i = 0; i < n2; i++) p[i] = s[i] + beta * p[i];
        }
        int finite = 1;
        for (size_t i = 0; i < n2 && finite; i++) finite = isfinite(x[i]);
        if (!finite || flips(c, nt, x) || border_crosses(c, faces, n, x)) {
            how = 1;
            for (uint32_t i = 0; i < nv; i++) {
                const double *pp = m->pos + 3 * (size_t)c->vlist[i];
                x[2 * (size_t)i] = dot3(pp, e1);
                x[2 * (size_t)i + 1] = dot3(pp, e2);
            }
            if (flips(c, nt, x) || border_crosses(c, faces, n, x)) how = -1;
        }
    } else if (nt > 0 && (flips(c, nt, c->x) || border_crosses(c, faces, n, c->x))) how = -1;
    /* UV area made the 3D area (one texel density for every chart). */
    double area_uv = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = faces[i], a = m->face_off[f], b = m->face_off[f + 1];
        for (uint32_t k = a; k < b; k++) {
            const double *p = c->x + 2 * (size_t)c->vloc[m->face_idx[k]];
            const double *q = c->x + 2 * (size_t)c->vloc[m->face_idx[k + 1 < b ? k + 1 : a]];
            area_uv += 0.5 * (p[0] * q[1] - q[0] * p[1]);
        }
    }
    double scale = area_uv > 0 && area3 > 0 ? sqrt(area3 / area_uv) : 1;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = faces[i];
        for (uint32_t k = m->face_off[f]; k < m->face_off[f + 1]; k++) {
            const double *p = c->x + 2 * (size_t)c->vloc[m->face_idx[k]];
            uv[2 * (size_t)k] = p[0] * scale;
            uv[2 * (size_t)k + 1] = p[1] * scale;
        }
    }
    return how;
}
