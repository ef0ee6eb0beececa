/* Newell's method for the normal of a polygon (Sutherland, Sproull and
 * Schumacker 1974, "A characterization of ten hidden-surface algorithms",
 * who credit it to M. E. Newell): over the edges p -> q of the polygon,
 *
 *   n.x += (p.y - q.y)(p.z + q.z)
 *   n.y += (p.z - q.z)(p.x + q.x)
 *   n.z += (p.x - q.x)(p.y + q.y)
 *
 * For a planar polygon n is twice its area times its unit normal (so sums
 * of face vectors are area-weighted); for a non-planar one it is the normal
 * of the plane that the polygon projects onto with the largest area.  It is
 * never normalised here: callers decide what a zero vector means.
 *
 * Everyone who computes a face normal uses these, in this edge order, so
 * that equal faces give bit-equal normals (images and positions are compared
 * to the bit across paths). */
#ifndef ST_GEOMETRY_H
#define ST_GEOMETRY_H

#include <stddef.h>
#include <stdint.h>

#include "core/map/map.h"

/* Adds the term of the edge p -> q to n. */
static inline void st_newell_add(double n[3], const double *p, const double *q)
{
    n[0] += (p[1] - q[1]) * (p[2] + q[2]);
    n[1] += (p[2] - q[2]) * (p[0] + q[0]);
    n[2] += (p[0] - q[0]) * (p[1] + q[1]);
}

/* The same for float points, summed in double. */
static inline void st_newell_add_f(double n[3], const float *p, const float *q)
{
    n[0] += ((double)p[1] - q[1]) * ((double)p[2] + q[2]);
    n[1] += ((double)p[2] - q[2]) * ((double)p[0] + q[0]);
    n[2] += ((double)p[0] - q[0]) * ((double)p[1] + q[1]);
}

/* Newell vector of the polygon of count points at pts (3 floats each, in
 * order, closed by the edge from the last to the first). */
static inline void st_newell_points_f(const float *pts, unsigned count, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    for (unsigned i = 0; i < count; i++) st_newell_add_f(n, pts + 3 * i, pts + 3 * ((i + 1) % count));
}

/* Newell vector of the polygon whose corners are the vertices idx[0..count)
 * of the position table pos (3 doubles per vertex). */
static inline void st_newell_indexed(const double *pos, const uint32_t *idx, uint32_t count, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    for (uint32_t c = 0; c < count; c++)
        st_newell_add(n, pos + 3 * (size_t)idx[c], pos + 3 * (size_t)idx[c + 1 < count ? c + 1 : 0]);
}

/* Newell vector of the surface face of dart d at level l: the positions of
 * its corners along st_face_step from d (core/map/map.h), that is its
 * φ1 = β1∘β0 orbit (a face is that orbit, Kraemer 2008 §1.2.2), or its β1
 * orbit in Doo-Sabin's dual encoding (§3.2.1, figs 3.19-3.20).  Boundary
 * faces are polygons too: callers that want no normal for them test
 * st_is_boundary first. */
void st_face_newell(const st_map *m, uint32_t d, unsigned l, double n[3]);

/* Newell vector of the polygon through the positions of the darts of d's β1
 * orbit at level l, starting at d, whatever the encoding (zero on a primal
 * map: the orbit is one vertex).  A surface face is st_face_newell's. */
void st_vertex_newell(const st_map *m, uint32_t d, unsigned l, double n[3]);

#endif
