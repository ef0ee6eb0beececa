/* Figures of an atlas (core/uv/uv.h step 4): distortion and texels.
 *
 * Stretch is Sander, Snyder, Gortler, Hoppe, "Texture Mapping Progressive
 * Meshes", SIGGRAPH 2001, §3: for the map from UV to the surface with
 * Jacobian singular values Γ ≥ γ, L2 = √(Σ A_t (Γ² + γ²)/2 / Σ A_t) over
 * triangles t with 3D areas A_t, after scaling the UVs to the surface's
 * total area (their normalisation), so 1 is isometric and every stretch
 * is ≥ 1.  Angle error: the mean |UV angle − 3D angle| of the triangle
 * corners (0 for a conformal map).  Area: each triangle's UV/3D area ratio
 * over the whole atlas' ratio; its 5th and 95th percentiles, weighted by
 * 3D area (both 1 for an equiareal map). */
#include "core/uv/uv_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ratio { double r, a; } ratio;

static int ratio_cmp(const void *pa, const void *pb)
{
    const ratio *x = pa, *y = pb;
    return (x->r > y->r) - (x->r < y->r);
}

static double angle3(const double *o, const double *a, const double *b)
{
    double e[3] = { a[0] - o[0], a[1] - o[1], a[2] - o[2] }, g[3] = { b[0] - o[0], b[1] - o[1], b[2] - o[2] };
    double c[3] = { e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2], e[0] * g[1] - e[1] * g[0] };
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), e[0] * g[0] + e[1] * g[1] + e[2] * g[2]);
}

static double angle2(const double *o, const double *a, const double *b)
{
    double e[2] = { a[0] - o[0], a[1] - o[1] }, g[2] = { b[0] - o[0], b[1] - o[1] };
    return atan2(fabs(e[0] * g[1] - e[1] * g[0]), e[0] * g[0] + e[1] * g[1]);
}

int st_uv_measure(const st_uv_mesh *m, const double *uv, st_uv_stats *s, st_error *err)
{
    size_t nt = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t d = m->face_off[f + 1] - m->face_off[f];
        nt += d >= 3 ? d - 2 : 0;
    }
    ratio *rs = malloc((nt ? nt : 1) * sizeof *rs);
    uint32_t (*tris)[3] = malloc((size_t)uv_max_degree(m) * sizeof *tris);
    if (!rs || !tris) { free(rs); free(tris); return st_fail(err, ST_ERR_MEMORY, "out of memory measuring a UV layout"); }
    double a3 = 0, auv = 0, stretch = 0, angle = 0;
    uint64_t ncorners = 0;
    uint32_t flipped = 0;
    size_t k = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        unsigned n = st_uv_face_triangles(m, f, tris);
        for (unsigned t = 0; t < n; t++) {
            const double *q[3], *p[3];
            for (int j = 0; j < 3; j++) {
                q[j] = m->pos + 3 * (size_t)m->face_idx[tris[t][j]];
                p[j] = uv + 2 * (size_t)tris[t][j];
            }
            double e1[3], e2[3], cr[3];
            for (int j = 0; j < 3; j++) { e1[j] = q[1][j] - q[0][j]; e2[j] = q[2][j] - q[0][j]; }
            cr[0] = e1[1] * e2[2] - e1[2] * e2[1]; cr[1] = e1[2] * e2[0] - e1[0] * e2[2]; cr[2] = e1[0] * e2[1] - e1[1] * e2[0];
            double A = 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
            double U = 0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
            if (!(A > 0)) continue;
            if (!(U > 0)) { flipped++; continue; }
            a3 += A;
            auv += U;
            double Ss[3], St[3];
            for (int j = 0; j < 3; j++) {
                Ss[j] = (q[0][j] * (p[1][1] - p[2][1]) + q[1][j] * (p[2][1] - p[0][1]) + q[2][j] * (p[0][1] - p[1][1])) / (2 * U);
                St[j] = (q[0][j] * (p[2][0] - p[1][0]) + q[1][j] * (p[0][0] - p[2][0]) + q[2][j] * (p[1][0] - p[0][0])) / (2 * U);
            }
            double a = Ss[0] * Ss[0] + Ss[1] * Ss[1] + Ss[2] * Ss[2], c = St[0] * St[0] + St[1] * St[1] + St[2] * St[2];
            stretch += A * 0.5 * (a + c);
            for (int j = 0; j < 3; j++) {
                angle += fabs(angle3(q[j], q[(j + 1) % 3], q[(j + 2) % 3]) - angle2(p[j], p[(j + 1) % 3], p[(j + 2) % 3]));
                ncorners++;
            }
            rs[k++] = (ratio){ U / A, A };
        }
    }
    s->flipped = flipped;
    s->uv_area = auv;
    s->l2_stretch = a3 > 0 ? sqrt(stretch / a3 * auv / a3) : 0;
    s->angle_err_deg = ncorners ? angle / (double)ncorners * 180 / M_PI : 0;
    qsort(rs, k, sizeof *rs, ratio_cmp);
    double whole = a3 > 0 ? auv / a3 : 1, acc = 0;
    s->area_p5 = s->area_p95 = 1;
    int got5 = 0;
    for (size_t i = 0; i < k; i++) {
        acc += rs[i].a;
        if (!got5 && acc >= 0.05 * a3) { s->area_p5 = rs[i].r / whole; got5 = 1; }
        if (acc >= 0.95 * a3) { s->area_p95 = rs[i].r / whole; break; }
    }
    free(rs);
    free(tris);
    return ST_OK;
}

/* Texel centre (x + ½, y + ½)/size inside a counter-clockwise triangle:
 * every edge function positive, or zero on a top or left edge (D3D's
 * rule), so two triangles sharing an edge never both take a texel. */
static int edge_in(double ax, double ay, double bx, double by, double px, double py)
{
    double e = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
    if (e != 0) return e > 0;
    double dx = bx - ax, dy = by - ay;
    return dy < 0 || (dy == 0 && dx > 0);
}

int st_uv_texels(const st_uv_mesh *m, const double *uv, const uint32_t *face_chart, uint32_t size,
                 uint64_t *covered, uint64_t *overlap, uint64_t *folded, st_error *err)
{
    size_t texels = (size_t)size * size;
    uint32_t *owner = malloc((texels ? texels : 1) * sizeof *owner), *oface = malloc((texels ? texels : 1) * sizeof *oface);
    uint8_t *twice = calloc(texels ? texels : 1, 1);
    uint32_t (*tris)[3] = malloc((size_t)uv_max_degree(m) * sizeof *tris);
    if (!owner || !oface || !twice || !tris) {
        free(owner); free(oface); free(twice); free(tris);
        return st_fail(err, ST_ERR_MEMORY, "out of memory counting the texels of a %ux%u UV layout", size, size);
    }
    for (size_t i = 0; i < texels; i++) owner[i] = UV_NIL;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t ch = face_chart ? face_chart[f] : f;
        unsigned n = st_uv_face_triangles(m, f, tris);
        for (unsigned t = 0; t < n; t++) {
            double P[3][2];
            for (int j = 0; j < 3; j++) {
                P[j][0] = uv[2 * (size_t)tris[t][j]] * size;
                P[j][1] = uv[2 * (size_t)tris[t][j] + 1] * size;
            }
            double a = (P[1][0] - P[0][0]) * (P[2][1] - P[0][1]) - (P[2][0] - P[0][0]) * (P[1][1] - P[0][1]);
            if (a == 0 || !isfinite(a)) continue;
            if (a < 0) for (int j = 0; j < 2; j++) { double tmp = P[1][j]; P[1][j] = P[2][j]; P[2][j] = tmp; }
            double lo[2] = { fmin(P[0][0], fmin(P[1][0], P[2][0])), fmin(P[0][1], fmin(P[1][1], P[2][1])) };
            double hi[2] = { fmax(P[0][0], fmax(P[1][0], P[2][0])), fmax(P[0][1], fmax(P[1][1], P[2][1])) };
            long x0 = (long)floor(lo[0] - 0.5), x1 = (long)ceil(hi[0] - 0.5), y0 = (long)floor(lo[1] - 0.5), y1 = (long)ceil(hi[1] - 0.5);
            if (x0 < 0) x0 = 0;
            if (y0 < 0) y0 = 0;
            if (x1 > (long)size - 1) x1 = (long)size - 1;
            if (y1 > (long)size - 1) y1 = (long)size - 1;
            for (long y = y0; y <= y1; y++)
                for (long x = x0; x <= x1; x++) {
                    double px = x + 0.5, py = y + 0.5;
                    if (!edge_in(P[0][0], P[0][1], P[1][0], P[1][1], px, py) || !edge_in(P[1][0], P[1][1], P[2][0], P[2][1], px, py) ||
                        !edge_in(P[2][0], P[2][1], P[0][0], P[0][1], px, py)) continue;
                    size_t i = (size_t)y * size + (size_t)x;
                    if (owner[i] == UV_NIL) { owner[i] = ch; oface[i] = f; }
                    else if (owner[i] != ch) twice[i] |= 1;
                    else if (oface[i] != f) twice[i] |= 2;
                }
        }
    }
    uint64_t cov = 0, ov = 0, fo = 0;
    for (size_t i = 0; i < texels; i++) { cov += owner[i] != UV_NIL; ov += twice[i] & 1; fo += (twice[i] & 2) >> 1; }
    *covered = cov;
    *overlap = ov;
    if (folded) *folded = fo;
    free(owner); free(oface); free(twice); free(tris);
    return ST_OK;
}
