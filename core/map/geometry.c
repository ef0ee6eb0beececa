/* Newell vectors of map faces (core/map/geometry.h). */
#include "core/map/geometry.h"

void st_face_newell(const st_map *m, uint32_t d, unsigned l, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    uint32_t x = d;
    do {
        uint32_t y = st_face_step(m, x, l);
        st_newell_add(n, st_dart_pos(m, x, l), st_dart_pos(m, y, l));
        x = y;
    } while (x != d);
}

void st_vertex_newell(const st_map *m, uint32_t d, unsigned l, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    uint32_t x = d;
    do {
        uint32_t y = st_beta1(m, x, l);
        st_newell_add(n, st_dart_pos(m, x, l), st_dart_pos(m, y, l));
        x = y;
    } while (x != d);
}
