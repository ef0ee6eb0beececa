/* A uniform grid over the base faces, so that an incremental box update
 * (Kraemer 2008 §3.2.5: a moved interest box triggers Algorithms 5 and 6)
 * finds the base faces near the boxes at a cost proportional to what it
 * finds, not to the size of the base mesh: moving the box a little touches
 * only faces near its old and new positions.
 *
 * Each base face is filed under the cell of its bounding-box centre; its box
 * is kept for the exact test (st_adapt_box_near).  The grid is a
 * cache of level-0 geometry: st_adapt_update rebuilds it on every full
 * update (which the editor forces after any edit, has_prev = 0) and builds it
 * when missing (a new or reloaded st_adapt); it is never saved. */
#include "core/adapt/adapt_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct st_adapt_grid {
    uint32_t nfaces;
    double *box;          /* 6 per base face: lo xyz, hi xyz */
    double maxsize;       /* largest size */
    double lo[3], cell[3];
    unsigned res[3];
    uint32_t *start;      /* res[0]*res[1]*res[2] + 1 offsets into face[] */
    uint32_t *face;       /* base-face indices, by cell */
};

void st_adapt_grid_free(st_adapt_grid *g)
{
    if (!g) return;
    free(g->box);
    free(g->start);
    free(g->face);
    free(g);
}

int st_adapt_box_near(const double box[6], const double lo[3], const double hi[3])
{
    double s = 0;
    for (int k = 0; k < 3; k++) s = fmax(s, box[3 + k] - box[k]);
    int hit = 1;
    for (int k = 0; k < 3; k++) hit &= box[k] - s <= hi[k] && box[3 + k] + s >= lo[k];
    return hit;
}

static unsigned cell_of(const st_adapt_grid *g, int k, double x)
{
    double t = (x - g->lo[k]) / g->cell[k];
    if (!(t > 0)) return 0; /* (also NaN) */
    return t >= g->res[k] ? g->res[k] - 1 : (unsigned)t;
}

static uint32_t cell_index(const st_adapt_grid *g, const double c[3])
{
    return (cell_of(g, 2, c[2]) * g->res[1] + cell_of(g, 1, c[1])) * g->res[0] + cell_of(g, 0, c[0]);
}

static void centre(const double *box, double c[3])
{
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (box[k] + box[3 + k]);
}

/* Lays the grid out: about two faces per cell, cells cubic-ish. */
static void layout(st_adapt_grid *g)
{
    double hi[3];
    for (int k = 0; k < 3; k++) { g->lo[k] = INFINITY; hi[k] = -INFINITY; }
    for (uint32_t f = 0; f < g->nfaces; f++) {
        double c[3];
        centre(g->box + 6 * f, c);
        for (int k = 0; k < 3; k++) {
            if (c[k] < g->lo[k]) g->lo[k] = c[k];
            if (c[k] > hi[k]) hi[k] = c[k];
        }
    }
    double ext[3], vol = 1;
    int dims = 0;
    for (int k = 0; k < 3; k++) {
        ext[k] = g->nfaces && hi[k] > g->lo[k] ? hi[k] - g->lo[k] : 0;
        if (ext[k] > 0) { vol *= ext[k]; dims++; }
    }
    double want = g->nfaces / 2.0 + 1, side = dims ? pow(vol / want, 1.0 / dims) : 1;
    for (int k = 0; k < 3; k++) {
        double r = ext[k] > 0 ? ceil(ext[k] / side) : 1;
        /* NaN (an infinite extent over an infinite side) counts as 1 */
        g->res[k] = !(r >= 1) ? 1 : !(r <= 1024) ? 1024 : (unsigned)r;
    }
    /* At most about four cells a face whatever the extents: extents of
     * 1e300 overflow the volume and the side, and the clamps above alone
     * allowed 1024^3 cells (4 GiB of counts, found by fuzz_session).  A
     * mesh of ordinary size has about one cell for two faces, untouched. */
    while ((uint64_t)g->res[0] * g->res[1] * g->res[2] > 4 * (uint64_t)g->nfaces + 1024) {
        int k = g->res[0] >= g->res[1] && g->res[0] >= g->res[2] ? 0 : g->res[1] >= g->res[2] ? 1 : 2;
        g->res[k] = (g->res[k] + 1) / 2;
    }
    for (int k = 0; k < 3; k++) g->cell[k] = ext[k] > 0 && isfinite(ext[k]) ? ext[k] / g->res[k] : 1;
}

st_adapt_grid *st_adapt_grid_build(const st_map *m, const st_dart_list *base,
                                   void (*bbox)(const st_map *, uint32_t, unsigned, double *, double *))
{
    st_adapt_grid *g = calloc(1, sizeof *g);
    if (!g) return NULL;
    g->nfaces = base->n;
    g->box = malloc(((size_t)base->n + 1) * 6 * sizeof *g->box);
    if (!g->box) { st_adapt_grid_free(g); return NULL; }
    for (uint32_t f = 0; f < base->n; f++) {
        double *b = g->box + 6 * f, s = 0;
        bbox(m, base->d[f], 0, b, b + 3);
        for (int k = 0; k < 3; k++) s = fmax(s, b[3 + k] - b[k]);
        if (s > g->maxsize) g->maxsize = s;
    }
    layout(g);
    size_t ncell = (size_t)g->res[0] * g->res[1] * g->res[2];
    g->start = calloc(ncell + 1, sizeof *g->start);
    g->face = malloc(((size_t)base->n + 1) * sizeof *g->face);
    if (!g->start || !g->face) { st_adapt_grid_free(g); return NULL; }
    /* Counting sort by cell (faces in increasing index within a cell). */
    for (uint32_t f = 0; f < base->n; f++) {
        double c[3];
        centre(g->box + 6 * f, c);
        g->start[cell_index(g, c) + 1]++;
    }
    for (size_t i = 0; i < ncell; i++) g->start[i + 1] += g->start[i];
    for (uint32_t f = 0; f < base->n; f++) {
        double c[3];
        centre(g->box + 6 * f, c);
        uint32_t i = cell_index(g, c);
        g->face[g->start[i]++] = f;
    }
    for (size_t i = ncell; i > 0; i--) g->start[i] = g->start[i - 1];
    g->start[0] = 0;
    return g;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* A face is near [lo, hi] when its box grown by its size meets it.  Its
 * centre is then within 1.5 maxsize of [lo, hi]: those cells are read. */
void st_adapt_grid_near(const st_adapt_grid *g, const double lo[3], const double hi[3], st_dart_list *out_index)
{
    unsigned c0[3], c1[3];
    for (int k = 0; k < 3; k++) {
        c0[k] = cell_of(g, k, lo[k] - 1.5 * g->maxsize);
        c1[k] = cell_of(g, k, hi[k] + 1.5 * g->maxsize);
    }
    out_index->n = 0;
    for (unsigned z = c0[2]; z <= c1[2]; z++)
        for (unsigned y = c0[1]; y <= c1[1]; y++)
            for (unsigned x = c0[0]; x <= c1[0]; x++) {
                uint32_t i = (z * g->res[1] + y) * g->res[0] + x;
                for (uint32_t j = g->start[i]; j < g->start[i + 1]; j++) {
                    uint32_t f = g->face[j];
                    if (st_adapt_box_near(g->box + 6 * f, lo, hi)) st_dart_list_push(out_index, f);
                }
            }
    /* In base-face order, as a scan would list them. */
    if (out_index->n > 1) qsort(out_index->d, out_index->n, sizeof *out_index->d, cmp_u32);
}
