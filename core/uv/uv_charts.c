/* Charts (core/uv/uv.h step 1): greedy region growing under a normal cone,
 * the disk test, and the splits that make a chart a disk.
 *
 * Growing follows D-Charts (Julius, Kraevoy, Sheffer 2005, §3.1: a face
 * joins the chart whose proxy normal it deviates least from) without its
 * Lloyd iterations: seeds are taken largest face first, and a chart grows
 * from its seed through edges, the face nearest in normal first (a
 * priority queue), as long as the face stays within cone_deg of the
 * chart's area-weighted mean normal and the edge it is reached through is
 * no crease (dihedral angle above crease_deg; Lévy et al. 2002 §5 also cut
 * at sharp features). */
#include "core/uv/uv_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct heap {
    double *cost;
    uint32_t *face;
    uint32_t n;
} heap;

static void heap_push(heap *h, double cost, uint32_t f)
{
    uint32_t i = h->n++;
    while (i > 0) {
        uint32_t p = (i - 1) / 2;
        if (h->cost[p] < cost || (h->cost[p] == cost && h->face[p] <= f)) break;
        h->cost[i] = h->cost[p];
        h->face[i] = h->face[p];
        i = p;
    }
    h->cost[i] = cost;
    h->face[i] = f;
}

static uint32_t heap_pop(heap *h)
{
    uint32_t top = h->face[0];
    double c = h->cost[--h->n];
    uint32_t f = h->face[h->n], i = 0;
    for (;;) {
        uint32_t l = 2 * i + 1, r = l + 1, m = i;
        double mc = c;
        uint32_t mf = f;
        if (l < h->n && (h->cost[l] < mc || (h->cost[l] == mc && h->face[l] < mf))) { m = l; mc = h->cost[l]; mf = h->face[l]; }
        if (r < h->n && (h->cost[r] < mc || (h->cost[r] == mc && h->face[r] < mf))) m = r;
        if (m == i) break;
        h->cost[i] = h->cost[m];
        h->face[i] = h->face[m];
        i = m;
    }
    if (h->n) { h->cost[i] = c; h->face[i] = f; }
    return top;
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

typedef struct area_key { double area; uint32_t face; } area_key;

static int area_cmp(const void *pa, const void *pb)
{
    const area_key *a = pa, *b = pb;
    if (a->area != b->area) return a->area > b->area ? -1 : 1;
    return a->face < b->face ? -1 : a->face > b->face;
}

uint32_t uv_grow_charts(uv_ctx *c, uint32_t *face_chart)
{
    const st_uv_mesh *m = c->m;
    uint32_t nf = m->nfaces;
    double cos_cone = cos(c->o.cone_deg * M_PI / 180), cos_crease = cos(c->o.crease_deg * M_PI / 180);
    area_key *seeds = malloc((size_t)(nf ? nf : 1) * sizeof *seeds);
    heap h = { malloc((size_t)(c->nc ? c->nc : 1) * sizeof(double)), malloc((size_t)(c->nc ? c->nc : 1) * sizeof(uint32_t)), 0 };
    for (uint32_t f = 0; f < nf; f++) face_chart[f] = UV_NIL;
    if (!seeds || !h.cost || !h.face) {
        /* No scratch: one chart per face (every face is a disk). */
        for (uint32_t f = 0; f < nf; f++) face_chart[f] = f;
        free(seeds); free(h.cost); free(h.face);
        return nf;
    }
    for (uint32_t f = 0; f < nf; f++) seeds[f] = (area_key){ c->farea[f], f };
    qsort(seeds, nf, sizeof *seeds, area_cmp);
    uint32_t k = 0;
    for (uint32_t s = 0; s < nf; s++) {
        uint32_t seed = seeds[s].face;
        if (face_chart[seed] != UV_NIL) continue;
        double sum[3], nrm[3];
        for (int i = 0; i < 3; i++) sum[i] = nrm[i] = c->fn[3 * (size_t)seed + i] * c->farea[seed];
        face_chart[seed] = k;
        h.n = 0;
        uint32_t f = seed;
        for (;;) {
            double len = sqrt(dot3(sum, sum));
            for (int i = 0; i < 3; i++) nrm[i] = len > 0 ? sum[i] / len : 0;
            /* The neighbours of f across edges that are no crease. */
            for (uint32_t i = m->face_off[f]; i < m->face_off[f + 1]; i++) {
                uint32_t t = c->twin[i];
                if (t == UV_NIL) continue;
                uint32_t g = c->corner_face[t];
                if (face_chart[g] != UV_NIL) continue;
                if (c->farea[f] > 0 && c->farea[g] > 0 && dot3(c->fn + 3 * (size_t)f, c->fn + 3 * (size_t)g) < cos_crease) continue;
                heap_push(&h, 1 - dot3(c->fn + 3 * (size_t)g, nrm), g);
            }
            f = UV_NIL;
            while (h.n) {
                uint32_t g = heap_pop(&h);
                if (face_chart[g] != UV_NIL) continue;
                if (c->farea[g] > 0 && dot3(c->fn + 3 * (size_t)g, nrm) < cos_cone) continue;
                f = g;
                break;
            }
            if (f == UV_NIL) break;
            face_chart[f] = k;
            for (int i = 0; i < 3; i++) sum[i] += c->fn[3 * (size_t)f + i] * c->farea[f];
        }
        k++;
    }
    free(seeds); free(h.cost); free(h.face);
    return k;
}

/* The disk test (Euler characteristic and border loops, as Lévy et al. 2002
 * §5 require of a chart).  A border half-edge is a corner whose opposite
 * half-edge is missing or in another chart.  With at most one border
 * half-edge leaving each vertex, the border is a set of disjoint loops,
 * counted by following them. */
int uv_is_disk(uv_ctx *c, const uint32_t *faces, uint32_t n)
{
    const st_uv_mesh *m = c->m;
    uv_new_stamp(c);
    uint32_t st = c->stamp;
    for (uint32_t i = 0; i < n; i++) c->fmark[faces[i]] = st;
    uint32_t nv = 0, half_in = 0, border = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = faces[i];
        for (uint32_t k = m->face_off[f]; k < m->face_off[f + 1]; k++) {
            uint32_t v = m->face_idx[k];
            if (c->vmark[v] != st) { c->vmark[v] = st; c->vloc[v] = nv; c->vout[nv] = UV_NIL; nv++; }
            uint32_t t = c->twin[k];
            if (t != UV_NIL && c->fmark[c->corner_face[t]] == st) { half_in++; continue; }
            border++;
            if (c->vout[c->vloc[v]] != UV_NIL) return 0; /* pinched: two border edges leave v */
            c->vout[c->vloc[v]] = k;
        }
    }
    if ((int64_t)nv - (int64_t)(half_in / 2 + border) + (int64_t)n != 1) return 0;
    if (!border) return 0;
    /* Follow the loop from one border corner; it must hold every border edge. */
    uint32_t first = UV_NIL;
    for (uint32_t i = 0; i < nv && first == UV_NIL; i++) first = c->vout[i];
    uint32_t k = first, len = 0;
    do {
        uint32_t b = m->face_idx[uv_next(m, c->corner_face, k)];
        k = c->vout[c->vloc[b]];
        len++;
    } while (k != UV_NIL && k != first && len <= border);
    return k == first && len == border;
}

uint32_t uv_components(uv_ctx *c, uint32_t *faces, uint32_t n, uint32_t *sizes)
{
    const st_uv_mesh *m = c->m;
    uv_new_stamp(c);
    uv_new_stamp(c);
    uint32_t in = c->stamp - 1, seen = c->stamp;
    for (uint32_t i = 0; i < n; i++) c->fmark[faces[i]] = in;
    uint32_t out = 0, ncomp = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (c->fmark[faces[i]] != in) continue;
        uint32_t head = out;
        c->fqueue[out++] = faces[i];
        c->fmark[faces[i]] = seen;
        while (head < out) {
            uint32_t f = c->fqueue[head++];
            for (uint32_t k = m->face_off[f]; k < m->face_off[f + 1]; k++) {
                uint32_t t = c->twin[k];
                if (t == UV_NIL) continue;
                uint32_t g = c->corner_face[t];
                if (c->fmark[g] != in) continue;
                c->fmark[g] = seen;
                c->fqueue[out++] = g;
            }
        }
        sizes[ncomp++] = out; /* the component's end; made a size below */
    }
    uint32_t prev = 0;
    for (uint32_t b = 0; b < ncomp; b++) { uint32_t end = sizes[b]; sizes[b] = end - prev; prev = end; }
    memcpy(faces, c->fqueue, (size_t)n * sizeof *faces);
    return ncomp;
}

typedef struct proj_key { double t; uint32_t face; } proj_key;

static int proj_cmp(const void *pa, const void *pb)
{
    const proj_key *a = pa, *b = pb;
    if (a->t != b->t) return a->t < b->t ? -1 : 1;
    return a->face < b->face ? -1 : a->face > b->face;
}

/* Halves by the median along the principal axis of the face centres (the
 * dominant eigenvector of their covariance, by power iteration). */
void uv_bisect(uv_ctx *c, uint32_t *faces, uint32_t n)
{
    double mean[3] = { 0, 0, 0 }, cov[9] = { 0 };
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) mean[k] += c->fcent[3 * (size_t)faces[i] + k] / n;
    for (uint32_t i = 0; i < n; i++) {
        const double *p = c->fcent + 3 * (size_t)faces[i];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) cov[3 * a + b] += (p[a] - mean[a]) * (p[b] - mean[b]);
    }
    double ax[3] = { 0.577, 0.577, 0.577 };
    for (int it = 0; it < 50; it++) {
        double y[3];
        for (int a = 0; a < 3; a++) y[a] = cov[3 * a] * ax[0] + cov[3 * a + 1] * ax[1] + cov[3 * a + 2] * ax[2];
        double len = sqrt(dot3(y, y));
        if (!(len > 0)) break;
        for (int a = 0; a < 3; a++) ax[a] = y[a] / len;
    }
    proj_key *k = malloc((size_t)n * sizeof *k);
    if (!k) return; /* any order halves the range */
    for (uint32_t i = 0; i < n; i++) {
        const double *p = c->fcent + 3 * (size_t)faces[i];
        k[i] = (proj_key){ (p[0] - mean[0]) * ax[0] + (p[1] - mean[1]) * ax[1] + (p[2] - mean[2]) * ax[2], faces[i] };
    }
    qsort(k, n, sizeof *k, proj_cmp);
    for (uint32_t i = 0; i < n; i++) faces[i] = k[i].face;
    free(k);
}
