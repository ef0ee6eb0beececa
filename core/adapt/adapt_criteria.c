/* The criteria of adaptive refinement (Kraemer 2008 §3.2.2, §3.2.5: a moved
 * interest box or a curvature criterion drives Algorithms 5 and 6): the
 * level a cell wants for an interest box with its falloff, and the
 * flatness reading of a polygon face.
 *
 * Invariant: a face's wanted level depends only on its own geometry at its
 * level and on the criteria - never on what was refined before - so an
 * update's result does not depend on earlier updates, and the incremental
 * update may skip the faces far from both boxes (adapt_update.c).  The √3
 * and Doo-Sabin families read their cells differently (adapt_sqrt3.c,
 * adapt_doosabin.c) on top of st_adapt_box_want. */
#include "core/map/geometry.h"
#include "core/adapt/adapt_internal.h"

#include <math.h>

void st_adapt_face_bbox(const st_map *m, uint32_t d, unsigned l, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) { lo[k] = INFINITY; hi[k] = -INFINITY; }
    uint32_t x = d;
    do {
        const double *p = st_dart_pos(m, x, l);
        /* (Comparisons, not fmin/fmax: positions are finite, and these are
         * calls in a hot loop.) */
        for (int k = 0; k < 3; k++) {
            if (p[k] < lo[k]) lo[k] = p[k];
            if (p[k] > hi[k]) hi[k] = p[k];
        }
        x = st_phi1(m, x, l);
    } while (x != d);
}

/* max_level inside the box, one level less per falloff band around it (none
 * without a falloff), and never below base_level. */
unsigned st_adapt_box_want(const double lo[3], const double hi[3], const st_adapt_params *p)
{
    unsigned want = p->base_level;
    if (p->has_box) {
        double gap = 0;
        for (int k = 0; k < 3; k++) {
            double g0 = p->box_lo[k] - hi[k], g1 = lo[k] - p->box_hi[k], g = g0 > g1 ? g0 : g1;
            if (g > gap) gap = g;
        }
        unsigned w = p->max_level;
        if (gap > 0) {
            /* Compared in double: a box far away (or a tiny falloff, as a
             * damaged session may hold) gives more steps than an unsigned
             * holds, and converting those would be undefined. */
            double steps = p->falloff > 0 ? ceil(gap / p->falloff) : (double)p->max_level;
            w = steps >= (double)p->max_level ? 0 : p->max_level - (unsigned)steps;
        }
        if (w > want) want = w;
    }
    return want;
}


/* The largest angle between the normal of the face of d and the normals of
 * its edge-neighbours, at level l. */
static double face_bend(const st_map *m, uint32_t d, unsigned l)
{
    double n0[3], worst = 0;
    st_face_newell(m, d, l, n0);
    uint32_t x = d;
    do {
        uint32_t e = st_beta0(m, x, l);
        if (!st_is_boundary(m, e)) {
            double n1[3];
            st_face_newell(m, e, l, n1);
            double dn = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]) * sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
            if (dn > 0) {
                double c = (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2]) / dn;
                worst = fmax(worst, acos(fmax(-1.0, fmin(1.0, c))));
            }
        }
        x = st_phi1(m, x, l);
    } while (x != d);
    return worst;
}

unsigned st_adapt_wanted_level(const st_map *m, uint32_t d, unsigned l, const st_adapt_params *p)
{
    double lo[3], hi[3];
    st_adapt_face_bbox(m, d, l, lo, hi);
    unsigned want = st_adapt_box_want(lo, hi, p);
    if (p->flatness > 0 && l < p->max_level && face_bend(m, d, l) > p->flatness) want = p->max_level;
    return want > p->max_level ? p->max_level : want;
}
