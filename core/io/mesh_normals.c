/* Smooth vertex normals for the writers (mesh.h, st_mesh_compute_normals). */
#include "core/io/mesh.h"
#include "core/map/geometry.h"

#include <math.h>
#include <stdlib.h>

/* Each face adds its Newell vector (core/map/geometry.h: twice its area
 * times its unit normal when planar) to each of its vertices, so larger
 * faces weigh more; the sums are normalised.  A vertex whose faces cancel
 * out gets the normal of its first face, or +z when that is degenerate too. */
int st_mesh_vertex_normals(const st_mesh *m, double *n)
{
    double *first = calloc(3 * (size_t)(m->nverts ? m->nverts : 1), sizeof *first);
    if (!first) return -1;
    for (size_t i = 0; i < 3 * (size_t)m->nverts; i++) n[i] = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        if (m->face_hole && m->face_hole[f]) continue; /* no surface */
        uint32_t a = m->face_off[f], b = m->face_off[f + 1];
        double s[3];
        st_newell_indexed(m->pos, m->face_idx + a, b - a, s);
        for (uint32_t c = a; c < b; c++) {
            double *t = n + 3 * (size_t)m->face_idx[c], *u = first + 3 * (size_t)m->face_idx[c];
            for (int k = 0; k < 3; k++) t[k] += s[k];
            if (u[0] == 0 && u[1] == 0 && u[2] == 0)
                for (int k = 0; k < 3; k++) u[k] = s[k];
        }
    }
    for (uint32_t v = 0; v < m->nverts; v++) {
        double *t = n + 3 * (size_t)v;
        double len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        if (!(len > 1e-300) || !isfinite(len)) {
            const double *u = first + 3 * (size_t)v;
            for (int k = 0; k < 3; k++) t[k] = u[k];
            len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        }
        if (!(len > 1e-300) || !isfinite(len)) { t[0] = t[1] = 0; t[2] = 1; continue; }
        for (int k = 0; k < 3; k++) t[k] /= len;
    }
    free(first);
    return 0;
}

int st_mesh_compute_normals(st_mesh *m)
{
    double *n = malloc(3 * (size_t)(m->nverts ? m->nverts : 1) * sizeof *n);
    if (!n || st_mesh_vertex_normals(m, n)) { free(n); return -1; }
    free(m->normals);
    m->normals = n;
    return 0;
}

double st_mesh_diagonal(const st_mesh *m)
{
    double lo[3] = { 0 }, hi[3] = { 0 };
    for (uint32_t v = 0; v < m->nverts; v++)
        for (int k = 0; k < 3; k++) {
            double x = m->pos[3 * (size_t)v + k];
            if (v == 0 || x < lo[k]) lo[k] = x;
            if (v == 0 || x > hi[k]) hi[k] = x;
        }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
}
