/* Packing (core/uv/uv.h step 3).
 *
 * Each chart is turned so that its bounding box has the least area: that
 * box has a side along an edge of the chart's convex hull (Freeman and
 * Shapira, "Determining the minimum-area encasing rectangle for an
 * arbitrary closed curve", CACM 1975), so every hull edge (Andrew's monotone
 * chain) is tried; then laid flat (width >= height).  The charts, longest
 * first, are then packed by their shapes (below), at the largest scale that
 * fits the square, found by bisection; one scale for every chart. */
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
    int32_t x, y;                 /* cell position of the chart's mask */
    int rot;                      /* quarter turns the packer gave it */
} box;

/* Longest box side first, then the other side, then the chart. */
static int box_cmp(const void *pa, const void *pb)
{
    const box *a = pa, *b = pb;
    if (a->w != b->w) return a->w > b->w ? -1 : 1;
    if (a->h != b->h) return a->h > b->h ? -1 : 1;
    return a->chart < b->chart ? -1 : a->chart > b->chart;
}

/* ---- packing by shape ----------------------------------------------------------
 *
 * Boxes waste the room between irregular charts, so the charts themselves
 * are packed, as xatlas does (its "bruteforce" raster packer): each chart
 * rasterised conservatively (every cell its triangles touch: the edge
 * functions offset by half a cell's L1 extent) into a grid of cells of
 * `cell` texels, put at the first free place in row order (bottom-left
 * first fit), in whichever of its four quarter turns lands lowest; the grid
 * then holds the chart dilated by the padding in cells, so another chart's
 * cells are at least padding + 1 cells away on some axis, i.e. its points
 * at least `padding` texels away. */

typedef struct raster_ctx {
    const st_uv_mesh *m;
    const uint32_t *chart_off, *chart_faces;
    const double *uv;
    uint32_t (*tris)[3];
    int32_t G, cell, pad;         /* grid side in cells, texels per cell, padding in cells */
    uint8_t *grid;                /* G * G: 1 taken (charts dilated, border) */
    int32_t *run;                 /* G * G: free cells from this one rightwards in its row (0: taken) */
    uint8_t *mask;                /* scratch: one chart's cells */
    int32_t *span;                /* 3 * G scratch: per mask row its first and last cell (-1: none), 1 when solid between */
    size_t mask_cap;
} raster_ctx;

/* A chart turned by rot quarter turns counter-clockwise inside its box
 * (a rotation: orientation kept), its corner back at the origin. */
static void turn_uv(const box *b, int rot, double *u, double *v)
{
    double x = *u, y = *v;
    switch (rot) {
    case 1: *u = b->h - y; *v = x; break;
    case 2: *u = b->w - x; *v = b->h - y; break;
    case 3: *u = y; *v = b->w - x; break;
    default: break;
    }
}

/* The chart's cells at scale sc (cells per model unit), turned or not;
 * returns 0 when the mask does not fit the scratch. */
static int chart_mask(raster_ctx *r, const box *b, double sc, int rot, int32_t *W, int32_t *H)
{
    double w = rot & 1 ? b->h : b->w, h = rot & 1 ? b->w : b->h;
    *W = (int32_t)ceil(w * sc) + 1;
    *H = (int32_t)ceil(h * sc) + 1;
    if (*W > r->G || *H > r->G || (size_t)*W * (size_t)*H > r->mask_cap) return 0;
    memset(r->mask, 0, (size_t)*W * (size_t)*H);
    const st_uv_mesh *m = r->m;
    for (uint32_t i = r->chart_off[b->chart]; i < r->chart_off[b->chart + 1]; i++) {
        uint32_t f = r->chart_faces[i];
        unsigned nt = st_uv_face_triangles(m, f, r->tris);
        for (unsigned t = 0; t < nt; t++) {
            double P[3][2];
            for (int j = 0; j < 3; j++) {
                double u = r->uv[2 * (size_t)r->tris[t][j]], v = r->uv[2 * (size_t)r->tris[t][j] + 1];
                turn_uv(b, rot, &u, &v);
                P[j][0] = u * sc;
                P[j][1] = v * sc;
            }
            double area = (P[1][0] - P[0][0]) * (P[2][1] - P[0][1]) - (P[2][0] - P[0][0]) * (P[1][1] - P[0][1]);
            if (area < 0) for (int k = 0; k < 2; k++) { double tmp = P[1][k]; P[1][k] = P[2][k]; P[2][k] = tmp; }
            int32_t x0 = (int32_t)floor(fmin(P[0][0], fmin(P[1][0], P[2][0]))), x1 = (int32_t)floor(fmax(P[0][0], fmax(P[1][0], P[2][0])));
            int32_t y0 = (int32_t)floor(fmin(P[0][1], fmin(P[1][1], P[2][1]))), y1 = (int32_t)floor(fmax(P[0][1], fmax(P[1][1], P[2][1])));
            if (x0 < 0) x0 = 0;
            if (y0 < 0) y0 = 0;
            if (x1 > *W - 1) x1 = *W - 1;
            if (y1 > *H - 1) y1 = *H - 1;
            for (int32_t y = y0; y <= y1; y++)
                for (int32_t x = x0; x <= x1; x++) {
                    double cx = x + 0.5, cy = y + 0.5;
                    int in = 1;
                    for (int e = 0; e < 3 && in; e++) {
                        const double *a = P[e], *q = P[(e + 1) % 3];
                        double nx = -(q[1] - a[1]), ny = q[0] - a[0];
                        double ev = nx * (cx - a[0]) + ny * (cy - a[1]);
                        in = ev + 0.5 * (fabs(nx) + fabs(ny)) >= 0;
                    }
                    if (in) r->mask[(size_t)y * (size_t)*W + (size_t)x] = 1;
                }
        }
    }
    return 1;
}

/* The free runs of rows y0..y1 of the grid. */
static void update_runs(raster_ctx *r, int32_t y0, int32_t y1)
{
    if (y0 < 0) y0 = 0;
    if (y1 > r->G - 1) y1 = r->G - 1;
    for (int32_t y = y0; y <= y1; y++) {
        const uint8_t *g = r->grid + (size_t)y * (size_t)r->G;
        int32_t *run = r->run + (size_t)y * (size_t)r->G, n = 0;
        for (int32_t x = r->G - 1; x >= 0; x--) run[x] = n = g[x] ? 0 : n + 1;
    }
}

/* The first place in row order where the mask's cells are all free.  A
 * mask row that is solid between its first and last cell is checked by
 * the free run at its first cell; other rows cell by cell (the same
 * answer as testing every cell). */
static int first_fit(raster_ctx *r, int32_t W, int32_t H, int32_t *X, int32_t *Y)
{
    int32_t *sp = r->span;
    for (int32_t j = 0; j < H; j++) {
        const uint8_t *mr = r->mask + (size_t)j * (size_t)W;
        int32_t lo = -1, hi = -1, solid = 1;
        for (int32_t i = 0; i < W; i++)
            if (mr[i]) { if (lo < 0) lo = i; hi = i; }
        for (int32_t i = lo; lo >= 0 && i <= hi; i++) solid &= mr[i] != 0;
        sp[3 * j] = lo; sp[3 * j + 1] = hi; sp[3 * j + 2] = solid;
    }
    for (int32_t y = 0; y + H <= r->G; y++)
        for (int32_t x = 0; x + W <= r->G; x++) {
            int ok = 1;
            for (int32_t j = 0; j < H && ok; j++) {
                int32_t lo = sp[3 * j], hi = sp[3 * j + 1];
                if (lo < 0) continue;
                const int32_t *run = r->run + (size_t)(y + j) * (size_t)r->G + (size_t)x;
                if (sp[3 * j + 2]) { ok = run[lo] > hi - lo; continue; }
                const uint8_t *mr = r->mask + (size_t)j * (size_t)W, *gr = r->grid + (size_t)(y + j) * (size_t)r->G + (size_t)x;
                for (int32_t i = lo; i <= hi; i++)
                    if (mr[i] && gr[i]) { ok = 0; break; }
            }
            if (ok) { *X = x; *Y = y; return 1; }
        }
    return 0;
}

static int try_raster(raster_ctx *r, box *b, uint32_t nb, double sc)
{
    int32_t G = r->G, ph = r->pad / 2;
    memset(r->grid, 0, (size_t)G * (size_t)G);
    for (int32_t y = 0; y < G; y++)
        for (int32_t x = 0; x < G; x++)
            if (x < ph || y < ph || x >= G - (r->pad - ph) || y >= G - (r->pad - ph)) r->grid[(size_t)y * (size_t)G + (size_t)x] = 1;
    update_runs(r, 0, G - 1);
    for (uint32_t k = 0; k < nb; k++) {
        int32_t best_top = INT32_MAX, bx = 0, by = 0, bw = 0, bh = 0;
        int brot = -1;
        for (int rot = 0; rot < 4; rot++) {
            int32_t W, H, X, Y;
            if (!chart_mask(r, &b[k], sc, rot, &W, &H)) continue;
            if (!first_fit(r, W, H, &X, &Y)) continue;
            if (Y + H < best_top || (Y + H == best_top && X < bx)) { best_top = Y + H; bx = X; by = Y; bw = W; bh = H; brot = rot; }
        }
        if (brot < 0) return 0;
        int32_t W, H;
        chart_mask(r, &b[k], sc, brot, &W, &H);
        (void)bw; (void)bh;
        b[k].x = bx;
        b[k].y = by;
        b[k].rot = brot;
        /* The chart dilated by the padding (a square of cells). */
        for (int32_t j = 0; j < H; j++)
            for (int32_t i = 0; i < W; i++) {
                if (!r->mask[(size_t)j * (size_t)W + (size_t)i]) continue;
                for (int32_t dy = -r->pad; dy <= r->pad; dy++) {
                    int32_t y = by + j + dy;
                    if (y < 0 || y >= G) continue;
                    for (int32_t dx = -r->pad; dx <= r->pad; dx++) {
                        int32_t x = bx + i + dx;
                        if (x >= 0 && x < G) r->grid[(size_t)y * (size_t)G + (size_t)x] = 1;
                    }
                }
            }
        update_runs(r, by - r->pad, by + H + r->pad);
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
    int rc = ST_OK;
    if (!pts || !hl || !b) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory packing %u UV charts", nch); goto done; }
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
    /* Longest first: the small charts then fill the room round the big ones. */
    qsort(b, nch, sizeof *b, box_cmp);
    /* The largest scale that packs, by bisection between one that fits
     * and one that does not (the charts' area bounds it above). */
    int32_t N = (int32_t)c->o.size, cell = N >= 512 ? N / 256 : 1;
    uint32_t pad = c->o.padding;
    raster_ctx r = { m, chart_off, chart_faces, uv, c->ftris, N / cell, cell, (int32_t)((pad + (uint32_t)cell - 1) / (uint32_t)cell), NULL, NULL, NULL, NULL, 0 };
    r.grid = malloc((size_t)r.G * (size_t)r.G);
    r.run = malloc((size_t)r.G * (size_t)r.G * sizeof *r.run);
    r.mask_cap = (size_t)r.G * (size_t)r.G;
    r.mask = malloc(r.mask_cap);
    r.span = malloc(3 * (size_t)r.G * sizeof *r.span);
    if (!r.grid || !r.run || !r.mask || !r.span) { free(r.grid); free(r.run); free(r.mask); free(r.span); rc = st_fail(err, ST_ERR_MEMORY, "out of memory packing %u UV charts", nch); goto done; }
    double area = 0;
    for (uint32_t i = 0; i < chart_off[nch]; i++) {
        uint32_t f = chart_faces[i], a0 = m->face_off[f], a1 = m->face_off[f + 1];
        for (uint32_t q = a0; q < a1; q++) {
            const double *p = uv + 2 * (size_t)q, *p2 = uv + 2 * (size_t)(q + 1 < a1 ? q + 1 : a0);
            area += 0.5 * (p[0] * p2[1] - p2[0] * p[1]);
        }
    }
    /* sc: cells per model unit. */
    double hi_s = area > 0 ? (double)r.G / sqrt(area) : 1, lo_s = hi_s / 2;
    int fits = 0;
    for (int it = 0; it < 60 && !(fits = try_raster(&r, b, nch, lo_s)); it++) { hi_s = lo_s; lo_s /= 2; }
    for (int it = 0; it < 14 && fits && hi_s > lo_s * (1 + 1e-3); it++) {
        double mid = 0.5 * (lo_s + hi_s);
        if (try_raster(&r, b, nch, mid)) lo_s = mid; else hi_s = mid;
    }
    if (fits) fits = try_raster(&r, b, nch, lo_s);
    free(r.grid);
    free(r.run);
    free(r.mask);
    free(r.span);
    if (!fits) {
        /* More charts with padding than cells: the charts overlap rather
         * than fail (a map too small for the mesh). */
        for (uint32_t k = 0; k < nch; k++) { b[k].x = b[k].y = 0; b[k].rot = 0; }
    }
    double sc = lo_s;
    for (uint32_t k = 0; k < nch; k++) {
        uint32_t ch = b[k].chart;
        for (uint32_t i = chart_off[ch]; i < chart_off[ch + 1]; i++) {
            uint32_t f = chart_faces[i];
            for (uint32_t q = m->face_off[f]; q < m->face_off[f + 1]; q++) {
                double *p = uv + 2 * (size_t)q, u = p[0], v = p[1];
                turn_uv(&b[k], b[k].rot, &u, &v);
                p[0] = (b[k].x + u * sc) * cell / N;
                p[1] = (b[k].y + v * sc) * cell / N;
            }
        }
    }
done:
    free(pts); free(hl); free(b);
    return rc;
}
