/* Estimate of an adaptive update's memory (adapt_estimate.h). */
#include "core/adapt/adapt_estimate.h"
#include "core/adapt/adapt_internal.h"
#include "core/multires/estimate.h"

#include <math.h>
#include <stdint.h>

/* Overlap of [lo, hi] with the box grown by r on each side, as a fraction
 * of the face's extent on each axis (an axis where the face is flat counts
 * 1 when it lies within the grown box). */
static double overlap_fraction(const double lo[3], const double hi[3], const st_adapt_params *p, double r)
{
    double f = 1.0;
    for (int k = 0; k < 3; k++) {
        double a = fmax(lo[k], p->box_lo[k] - r), b = fmin(hi[k], p->box_hi[k] + r);
        if (b < a) return 0.0;
        double ext = hi[k] - lo[k];
        f *= ext > 0 ? (b - a) / ext : 1.0;
    }
    return f;
}

size_t st_adapt_estimate_bytes(st_hier *h, const st_adapt_params *p)
{
    /* A progressive hierarchy has every level: the selection's arrays (about
     * 16 bytes per vertex), the selected mesh and its one-level map (at most
     * the finest level's darts, about 40 bytes each with the mesh). */
    if (h->scheme->id == ST_SCHEME_PROGRESSIVE)
        return (size_t)h->map.verts.end * 16u + (size_t)h->map.darts.end * 40u;
    /* the regular part: every face to the base level */
    size_t regular = st_hier_estimate_subdivide(h, p->base_level, NULL);
    if (!p->has_box || p->max_level <= p->base_level) return regular;
    st_map *m = &h->map;
    st_scheme_id id = h->scheme->id;
    double g = id == ST_SCHEME_SQRT3 ? 3.0 : 4.0;
    double darts = 0; /* darts of the levels above the base, all levels together */
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
        if (st_is_boundary(m, d)) continue;
        double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
        uint32_t x = d, min = d, n = 0;
        do {
            const double *q = st_dart_pos(m, x, 0);
            for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], q[k]); hi[k] = fmax(hi[k], q[k]); }
            if (x < min) min = x;
            n++;
            x = st_phi1(m, x, 0);
        } while (x != d && n < 1u << 20);
        if (min != d) continue; /* each face once, at its smallest dart */
        double ext = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
        /* Level k holds the faces within the box grown by the falloff bands
         * of the levels above k, and by the rings the one-level restriction
         * and the stencils add around the finer levels' faces: about two
         * faces of level k, each ext / 2^k (√3: ext / 3^(k/2)) wide. */
        /* children of the face at level 1: a quad per side (polygon split;
         * quad/triangle splits a triangle into 3 quads, about as many),
         * 4 triangles (quadrisection), 3 (√3), 4 cells (Doo-Sabin: one of
         * each kind per face); then g times as many per level */
        int polysplit = id == ST_SCHEME_CATMARK || id == ST_SCHEME_QUADTRI;
        double faces_k = 1, sides = polysplit || id == ST_SCHEME_DOOSABIN ? 4.0 : 3.0;
        for (unsigned k = 1; k <= p->max_level; k++) {
            faces_k *= k == 1 && polysplit ? (double)n : g;
            if (k <= p->base_level) continue;
            double width = ext / pow(id == ST_SCHEME_SQRT3 ? sqrt(3.0) : 2.0, (double)k);
            double r = (double)(p->max_level - k) * p->falloff + 2.0 * width;
            darts += overlap_fraction(lo, hi, p, r) * faces_k * sides;
        }
    }
    /* bytes per dart with its share of the vertices (a quad mesh has a
     * vertex per 4 darts, a triangle mesh one per 6) and of the passes'
     * scratch, measured on the shared meshes (tests/core/test_membudget.c) */
    double per_dart = id == ST_SCHEME_CATMARK || id == ST_SCHEME_QUADTRI ? 26.0 : id == ST_SCHEME_DOOSABIN ? 22.0 : 24.0;
    double total = (double)regular + darts * per_dart;
    return total >= (double)SIZE_MAX ? SIZE_MAX : (size_t)total;
}

size_t st_adapt_estimate_mesh_bytes(st_adapt *a)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    if (st_adapt_is_progressive(a)) /* the selection's mesh: at most the finest level's */
        return st_estimate_mesh_bytes(m->verts.end, m->darts.end / 3u, m->darts.end);
    st_level_stats s;
    st_level_stats_compute(m, m->top, &s);
    /* extraction (st_map_to_mesh): a vertex index per vertex id and the
     * marker bits if the map has none yet, then the mesh's positions, face
     * offsets and corner indices (the writers stream them) */
    double b = 4.0 * (double)m->verts.end + (m->marks ? 0.0 : 4.0 * (double)m->darts.cap);
    b += 24.0 * (double)s.vertices + 4.0 * (double)s.faces + 4.0 * (double)(s.darts - s.boundary_edges);
    /* UVs (adapt_uv.c): per dart id below the pool's end, the value, its
     * chart, level and rank, and the passes' buffers (62 bytes allocated, about 55 touched); then per
     * corner of the mesh the sort keys, the texture coordinates and their
     * indices (40 bytes) */
    if (!st_adapt_uv_absent(a)) b += 55.0 * (double)m->darts.end + 40.0 * (double)(s.darts - s.boundary_edges);
    return b >= (double)SIZE_MAX ? SIZE_MAX : (size_t)b;
}
