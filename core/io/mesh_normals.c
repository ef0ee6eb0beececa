/* Smooth vertex normals for the writers (mesh.h, st_mesh_compute_normals). */
#include "core/io/mesh.h"

#include <math.h>
#include <stdlib.h>

/* Each face adds its area vector (Newell's method: for a planar polygon,
 * twice its area times its unit normal; for a non-planar one the normal of
 * its best projection) to each of its vertices, so larger faces weigh more;
 * the sums are normalised.  A vertex whose faces cancel out gets the normal
 * of its first face, or +z when that is degenerate too. */
int st_mesh_compute_normals(st_mesh *m)
{
    double *n = calloc(3 * (size_t)(m->nverts ? m->nverts : 1), sizeof *n);
    double *first = calloc(3 * (size_t)(m->nverts ? m->nverts : 1), sizeof *first);
    if (!n || !first) { free(n); free(first); return -1; }
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t a = m->face_off[f], b = m->face_off[f + 1];
        double s[3] = { 0, 0, 0 };
        for (uint32_t c = a; c < b; c++) {
            const double *p = m->pos + 3 * (size_t)m->face_idx[c];
            const double *q = m->pos + 3 * (size_t)m->face_idx[c + 1 < b ? c + 1 : a];
            s[0] += (p[1] - q[1]) * (p[2] + q[2]);
            s[1] += (p[2] - q[2]) * (p[0] + q[0]);
            s[2] += (p[0] - q[0]) * (p[1] + q[1]);
        }
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
    free(m->normals);
    m->normals = n;
    return 0;
}
