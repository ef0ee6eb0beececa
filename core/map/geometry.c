/* Newell vectors of map faces (core/map/geometry.h). */
#include "core/map/geometry.h"

/* Σ over an orbit of darts of level l, from d, of the Newell terms of
 * each dart's edge: the face orbit (st_face_step, the dual encoding
 * aware) or the β1 orbit.  Inline, so each caller's step is constant. */
static inline void newell_orbit(const st_map *m, uint32_t d, unsigned l, int face_orbit, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    uint32_t x = d;
    do {
        uint32_t y = face_orbit ? st_face_step(m, x, l) : st_beta1(m, x, l);
        st_newell_add(n, st_dart_pos(m, x, l), st_dart_pos(m, y, l));
        x = y;
    } while (x != d);
}

void st_face_newell(const st_map *m, uint32_t d, unsigned l, double n[3]) { newell_orbit(m, d, l, 1, n); }

void st_vertex_newell(const st_map *m, uint32_t d, unsigned l, double n[3]) { newell_orbit(m, d, l, 0, n); }
