/* Packing (core/uv/uv.h step 3).
 *
 * Each chart is turned so that its bounding box has the least area: that
 * box has a side along an edge of the chart's convex hull (Freeman and
 * Shapira, "Determining the minimum-area encasing rectangle for an
 * arbitrary closed curve", CACM 1975), so every hull edge (Andrew's monotone
 * chain) is tried; then laid flat (width >= height).
 *
 * The boxes, tallest first, go into a size × size grid of texels by the
 * skyline bottom-left rule (Jylänki 2010, "A Thousand Ways to Pack the Bin",
 * §4: each box where its top is lowest, upright or turned a quarter), each
 * box widened by `padding` texels so that any two charts are at least that
 * far apart, half of it on each side so that the square's border keeps it
 * across the repeat wrap.  The scale (texels per model unit, the same for
 * every chart) is the largest that fits, by bisection. */
#include "core/uv/uv_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct pt { double x, y; } pt;

static int pt_cmp(const void *pa, const void *pb)
{
    const pt *a = pa, *b = pb;
    if (a->x != b->x) return a->x < b->x ? -1 : 1;
    return (a->y > b->y) - (a->y < b->y);
}

static double turn(pt o, pt a, pt b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

/* Andrew's monotone chain; p sorted in place; the hull written to h, returns its size. */
static uint32_t hull(pt *p, uint32_t n, pt *h)
{
    qsort(p, n, sizeof *p, pt_cmp);
    if (n < 3) { memcpy(h, p, n * sizeof *p); return n; }
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) {
        while (k >= 2 && turn(h[k - 2], h[k - 1], p[i]) <= 0) k--;
        h[k++] = p[i];
    }
    for (uint32_t i = n - 1, t = k + 1; i-- > 0;) {
        while (k >= t && turn(h[k - 2], h[k - 1], p[i]) <= 0) k--;
        h[k++] = p[i];
    }
    return k - 1;
}

typedef struct box {
    double w, h;                  /* model units, after turning */
    uint32_t chart;
    int32_t x, y;                 /* texel position of the padded box */
    int rot;                      /* turned a quarter by the packer */
} box;

static int box_cmp(const void *pa, const void *pb)
{
    const box *a = pa, *b = pb;
    if (a->h != b->h) return a->h > b->h ? -1 : 1;
    if (a->w != b->w) return a->w > b->w ? -1 : 1;
    return a->chart < b->chart ? -1 : a->chart > b->chart;
}

typedef struct skyline {
    int32_t *x, *y, *w;
    uint32_t n;
} skyline;

/* The lowest top for a W × H box at segment i, or INT32_MAX. */
static int32_t fit_at(const skyline *s, uint32_t i, int32_t W, int32_t H, int32_t N, int32_t *yout)
{
    int32_t x = s->x[i];
    if (x + W > N) return INT32_MAX;
    int32_t y = 0, left = W;
    for (uint32_t j = i; left > 0; j++) {
        if (j >= s->n) return INT32_MAX;
        if (s->y[j] > y) y = s->y[j];
        left -= s->w[j];
    }
    if (y + H > N) return INT32_MAX;
    *yout = y;
    return y + H;
}

static void place(skyline *s, uint32_t i, int32_t W, int32_t H, int32_t y)
{
    int32_t x = s->x[i];
    /* Insert the new segment at i, then trim what it covers. */
    memmove(s->x + i + 1, s->x + i, (s->n - i) * sizeof *s->x);
    memmove(s->y + i + 1, s->y + i, (s->n - i) * sizeof *s->y);
    memmove(s->w + i + 1, s->w + i, (s->n - i) * sizeof *s->w);
    s->n++;
    s->x[i] = x; s->y[i] = y + H; s->w[i] = W;
    for (uint32_t j = i + 1; j < s->n;) {
        int32_t end = x + W;
        if (s->x[j] >= end) break;
        int32_t cut = end - s->x[j];
        if (cut >= s->w[j]) {
            memmove(s->x + j, s->x + j + 1, (s->n - j - 1) * sizeof *s->x);
            memmove(s->y + j, s->y + j + 1, (s->n - j - 1) * sizeof *s->y);
            memmove(s->w + j, s->w + j + 1, (s->n - j - 1) * sizeof *s->w);
            s->n--;
        } else {
            s->x[j] += cut;
            s->w[j] -= cut;
            break;
        }
    }
    /* Merge equal heights. */
    for (uint32_t j = 0; j + 1 < s->n;) {
        if (s->y[j] == s->y[j + 1]) {
            s->w[j] += s->w[j + 1];
            memmove(s->x + j + 1, s->x + j + 2, (s->n - j - 2) * sizeof *s->x);
            memmove(s->y + j + 1, s->y + j + 2, (s->n - j - 2) * sizeof *s->y);
            memmove(s->w + j + 1, s->w + j + 2, (s->n - j - 2) * sizeof *s->w);
            s->n--;
        } else j++;
    }
}

/* Texels of a box side at scale sc, padding included. */
static int32_t side(double len, double sc, uint32_t pad)
{
    double t = ceil(len * sc - 1e-9);
    return (int32_t)(t < 1 ? 1 : t) + (int32_t)pad;
}

/* Packs every box at scale sc; 1 when all fit. */
static int try_pack(box *b, uint32_t nb, double sc, uint32_t pad, int32_t N, skyline *s)
{
    s->n = 1;
    s->x[0] = 0; s->y[0] = 0; s->w[0] = N;
    for (uint32_t k = 0; k < nb; k++) {
        int32_t W = side(b[k].w, sc, pad), H = side(b[k].h, sc, pad);
        if (W > N && H > N) return 0;
        int32_t best = INT32_MAX, by = 0, bx = 0;
        uint32_t bi = 0;
        int brot = 0;
        for (int rot = 0; rot < 2; rot++) {
            int32_t w = rot ? H : W, h = rot ? W : H;
            for (uint32_t i = 0; i < s->n; i++) {
                int32_t y = 0, top = fit_at(s, i, w, h, N, &y);
                if (top < best || (top == best && s->x[i] < bx)) { best = top; by = y; bx = s->x[i]; bi = i; brot = rot; }
            }
        }
        if (best == INT32_MAX) return 0;
        b[k].x = bx;
        b[k].y = by;
        b[k].rot = brot;
        place(s, bi, brot ? H : W, brot ? W : H, by);
    }
    return 1;
}

int uv_pack(uv_ctx *c, uint32_t nch, const uint32_t *chart_off, const uint32_t *chart_faces, double *uv, st_error *err)
{
    const st_uv_mesh *m = c->m;
    if (!nch) return ST_OK;
    size_t nc1 = c->nc ? c->nc : 1;
    pt *pts = malloc(nc1 * sizeof *pts), *hl = malloc(2 * (nc1 + 1) * sizeof *hl);
    box *b = malloc((size_t)nch * sizeof *b);
    skyline s = { malloc((2 * (size_t)nch + 2) * sizeof(int32_t)), malloc((2 * (size_t)nch + 2) * sizeof(int32_t)),
                  malloc((2 * (size_t)nch + 2) * sizeof(int32_t)), 0 };
    int rc = ST_OK;
    if (!pts || !hl || !b || !s.x || !s.y || !s.w) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory packing %u UV charts", nch); goto done; }
    /* Turn each chart to its least-area box, flat, its corner at the origin. */
    for (uint32_t k = 0; k < nch; k++) {
        uint32_t np = 0;
        for (uint32_t i = chart_off[k]; i < chart_off[k + 1]; i++) {
            uint32_t f = chart_faces[i];
            for (uint32_t q = m->face_off[f]; q < m->face_off[f + 1]; q++) pts[np++] = (pt){ uv[2 * (size_t)q], uv[2 * (size_t)q + 1] };
        }
        uint32_t nh = hull(pts, np, hl);
        double best = INFINITY, bc = 1, bs = 0;
        for (uint32_t e = 0; e < nh; e++) {
            pt a = hl[e], d = hl[(e + 1) % nh];
            double dx = d.x - a.x, dy = d.y - a.y, len = sqrt(dx * dx + dy * dy);
            if (!(len > 0)) continue;
            double cs = dx / len, sn = dy / len, lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
            for (uint32_t i = 0; i < nh; i++) {
                double u = cs * hl[i].x + sn * hl[i].y, v = -sn * hl[i].x + cs * hl[i].y;
                lo[0] = fmin(lo[0], u); hi[0] = fmax(hi[0], u); lo[1] = fmin(lo[1], v); hi[1] = fmax(hi[1], v);
            }
            double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
            if (area < best) { best = area; bc = cs; bs = sn; }
        }
        double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
        for (uint32_t i = chart_off[k]; i < chart_off[k + 1]; i++) {
            uint32_t f = chart_faces[i];
            for (uint32_t q = m->face_off[f]; q < m->face_off[f + 1]; q++) {
                double *p = uv + 2 * (size_t)q, u = bc * p[0] + bs * p[1], v = -bs * p[0] + bc * p[1];
                p[0] = u; p[1] = v;
                lo[0] = fmin(lo[0], u); hi[0] = fmax(hi[0], u); lo[1] = fmin(lo[1], v); hi[1] = fmax(hi[1], v);
            }
        }
        int flat = hi[1] - lo[1] > hi[0] - lo[0]; /* taller than wide: a quarter turn, (u, v) → (h − v, u) */
        for (uint32_t i = chart_off[k]; i < chart_off[k + 1]; i++) {
            uint32_t f = chart_faces[i];
            for (uint32_t q = m->face_off[f]; q < m->face_off[f + 1]; q++) {
                double *p = uv + 2 * (size_t)q, u = p[0] - lo[0], v = p[1] - lo[1];
                if (flat) { p[0] = (hi[1] - lo[1]) - v; p[1] = u; }
                else { p[0] = u; p[1] = v; }
            }
        }
        b[k].w = flat ? hi[1] - lo[1] : hi[0] - lo[0];
        b[k].h = flat ? hi[0] - lo[0] : hi[1] - lo[1];
        b[k].chart = k;
    }
    qsort(b, nch, sizeof *b, box_cmp);
    /* The largest scale that packs, by bisection between one that fits
     * and one that does not (the boxes' area bounds it above). */
    int32_t N = (int32_t)c->o.size;
    uint32_t pad = c->o.padding;
    double area = 0;
    for (uint32_t k = 0; k < nch; k++) area += b[k].w * b[k].h;
    double hi_s = area > 0 ? (double)N / sqrt(area) : 1, lo_s = hi_s / 2;
    for (int it = 0; it < 60 && !try_pack(b, nch, lo_s, pad, N, &s); it++) { hi_s = lo_s; lo_s /= 2; }
    if (try_pack(b, nch, hi_s, pad, N, &s)) lo_s = hi_s;
    for (int it = 0; it < 24 && hi_s > lo_s * (1 + 1e-4); it++) {
        double mid = 0.5 * (lo_s + hi_s);
        if (try_pack(b, nch, mid, pad, N, &s)) lo_s = mid; else hi_s = mid;
    }
    if (!try_pack(b, nch, lo_s, pad, N, &s)) {
        /* More charts with padding than texels: the boxes overlap rather
         * than fail (a map too small for the mesh). */
        for (uint32_t k = 0; k < nch; k++) { b[k].x = b[k].y = 0; b[k].rot = 0; }
    }
    double sc = lo_s, half = (double)(pad / 2);
    for (uint32_t k = 0; k < nch; k++) {
        uint32_t ch = b[k].chart;
        for (uint32_t i = chart_off[ch]; i < chart_off[ch + 1]; i++) {
            uint32_t f = chart_faces[i];
            for (uint32_t q = m->face_off[f]; q < m->face_off[f + 1]; q++) {
                double *p = uv + 2 * (size_t)q, u = p[0], v = p[1];
                if (b[k].rot) { double t = u; u = b[k].h - v; v = t; }
                p[0] = (b[k].x + half + u * sc) / N;
                p[1] = (b[k].y + half + v * sc) / N;
            }
        }
    }
done:
    free(pts); free(hl); free(b); free(s.x); free(s.y); free(s.w);
    return rc;
}
