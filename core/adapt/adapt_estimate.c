/* Estimate of an adaptive update's memory (adapt_estimate.h). */
#include "core/adapt/adapt_estimate.h"
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
    double g = h->scheme->id == ST_SCHEME_SQRT3 ? 3.0 : 4.0;
    unsigned bands = p->falloff > 0 ? p->max_level - p->base_level : 0;
    double faces = 0;
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
        double inner = 0;
        for (unsigned k = 0; k <= bands; k++) {
            double f = overlap_fraction(lo, hi, p, (double)k * p->falloff);
            faces += (f - inner) * pow(g, (double)(p->max_level - k));
            inner = f;
        }
    }
    /* a face of the finest level: 2 darts per edge, about 2 edges per face
     * for quads and 1.5 for triangles; about 1 vertex per quad, 1/2 per
     * triangle; every coarser level adds a third more (1/(1 - 1/g)). */
    double per_face = 4.0 * 11.8 + 1.0 * 24.8;
    double bytes = faces * per_face * (g / (g - 1.0)) * 3.2; /* 3.2: measured on blub, max levels 8-12 */
    double total = (double)regular + bytes;
    return total >= (double)SIZE_MAX ? SIZE_MAX : (size_t)total;
}
