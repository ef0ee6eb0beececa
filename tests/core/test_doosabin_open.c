/* Doo-Sabin on open meshes (scheme_doosabin.c, "Boundaries"): checked
 * against the formulas, level by level, on the extracted meshes:
 *   - every corner point of a real face of level l is Doo and Sabin's mask
 *     of that face (the points CGAL computes: it drops the rest);
 *   - every boundary loop of level l+1 is Chaikin's refinement of the
 *     matching loop of level l (points at 3/4, 1/4 of each boundary edge);
 *   - the surface has one face per face, edge and vertex of level l and
 *     twice as many boundary edges; the map stays valid;
 * and the multiresolution checks shared by the schemes (local edits, rigid
 * motions, details) on an open grid. */
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void grid(st_mesh *s) { tl_mesh_grid(s, 4); }

/* Half-edges of m on a boundary (no twin), as (from, to). */
typedef struct hedges { uint32_t *from, *to, n; } hedges;

static void boundary_hedges(const st_mesh *m, hedges *b)
{
    uint32_t total = m->face_off[m->nfaces];
    b->from = malloc((total + 1) * sizeof *b->from);
    b->to = malloc((total + 1) * sizeof *b->to);
    b->n = 0;
    for (uint32_t f = 0; f < m->nfaces; f++)
        for (uint32_t i = m->face_off[f]; i < m->face_off[f + 1]; i++) {
            uint32_t a = m->face_idx[i], c = m->face_idx[i + 1 < m->face_off[f + 1] ? i + 1 : m->face_off[f]];
            int twin = 0;
            for (uint32_t g = 0; g < m->nfaces && !twin; g++)
                for (uint32_t j = m->face_off[g]; j < m->face_off[g + 1]; j++) {
                    uint32_t p = m->face_idx[j], q = m->face_idx[j + 1 < m->face_off[g + 1] ? j + 1 : m->face_off[g]];
                    if (p == c && q == a) { twin = 1; break; }
                }
            if (!twin) { b->from[b->n] = a; b->to[b->n] = c; b->n++; }
        }
}

/* Distance from p to the nearest point of m. */
static double nearest(const st_mesh *m, const double *p)
{
    double best = INFINITY;
    for (uint32_t v = 0; v < m->nverts; v++) {
        const double *q = m->pos + 3 * (size_t)v;
        double d = fmax(fabs(p[0] - q[0]), fmax(fabs(p[1] - q[1]), fabs(p[2] - q[2])));
        best = fmin(best, d);
    }
    return best;
}

static void check_levels(const char *name, void (*make)(st_mesh *), const char *path, unsigned levels)
{
    st_mesh base;
    st_error err;
    st_mesh_init(&base);
    if (make) make(&base);
    else CHECKF(st_mesh_load(path, &base, &err) == ST_OK, "%s", err.msg);
    st_hier h;
    CHECKF(st_hier_init(&h, &base, st_scheme_find("doo-sabin"), NULL, &err) == ST_OK, "%s: %s", name, err.msg);
    CHECKF(st_hier_subdivide_to(&h, levels, &err) == ST_OK, "%s: %s", name, err.msg);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s: %s", name, err.msg);
    for (unsigned l = 0; l < levels; l++) {
        st_mesh a, b;
        st_mesh_init(&a);
        st_mesh_init(&b);
        CHECK(st_hier_level_mesh(&h, l, &a, &err) == ST_OK && st_hier_level_mesh(&h, l + 1, &b, &err) == ST_OK);
        st_level_stats sa, sb;
        st_level_stats_compute(&h.map, l, &sa);
        st_level_stats_compute(&h.map, l + 1, &sb);
        CHECKF(sb.faces == sa.faces + sa.edges + sa.vertices && sb.boundary_edges == 2 * sa.boundary_edges &&
                   sb.boundary_loops == sa.boundary_loops && b.nfaces == sb.faces && sa.boundary_edges > 0,
               "%s level %u: %llu faces, %llu boundary edges", name, l + 1, (unsigned long long)sb.faces,
               (unsigned long long)sb.boundary_edges);
        /* Corner points: Doo and Sabin's mask of each face of level l. */
        double worst = 0;
        for (uint32_t f = 0; f < a.nfaces; f++) {
            uint32_t o = a.face_off[f], n = a.face_off[f + 1] - o;
            for (uint32_t g = 0; g < n; g++) {
                double p[3] = { 0, 0, 0 };
                for (uint32_t j = 0; j < n; j++) {
                    double w = j == 0 ? 0.25 + 5.0 / (4.0 * n) : (3.0 + 2.0 * cos(2.0 * M_PI * j / n)) / (4.0 * n);
                    const double *q = a.pos + 3 * (size_t)a.face_idx[o + (g + j) % n];
                    for (int k = 0; k < 3; k++) p[k] += w * q[k];
                }
                worst = fmax(worst, nearest(&b, p));
            }
        }
        CHECKF(worst < 1e-12, "%s level %u: a corner point is %g from the mask", name, l + 1, worst);
        /* Boundary: Chaikin's points of every boundary edge of level l lie on
         * level l+1's boundary, and there are as many as its boundary edges. */
        hedges ha, hb;
        boundary_hedges(&a, &ha);
        boundary_hedges(&b, &hb);
        st_mesh onb;
        st_mesh_init(&onb);
        onb.nverts = hb.n;
        onb.pos = malloc((hb.n + 1) * 3 * sizeof *onb.pos);
        for (uint32_t i = 0; i < hb.n; i++) memcpy(onb.pos + 3 * (size_t)i, b.pos + 3 * (size_t)hb.from[i], 3 * sizeof(double));
        worst = 0;
        for (uint32_t i = 0; i < ha.n; i++) {
            const double *p = a.pos + 3 * (size_t)ha.from[i], *q = a.pos + 3 * (size_t)ha.to[i];
            double c1[3], c2[3];
            for (int k = 0; k < 3; k++) { c1[k] = 0.75 * p[k] + 0.25 * q[k]; c2[k] = 0.25 * p[k] + 0.75 * q[k]; }
            worst = fmax(worst, fmax(nearest(&onb, c1), nearest(&onb, c2)));
        }
        CHECKF(worst < 1e-12 && hb.n == 2 * ha.n, "%s level %u: boundary %u edges, %g from Chaikin's points", name, l + 1, hb.n, worst);
        free(onb.pos);
        onb.pos = NULL;
        onb.nverts = 0;
        st_mesh_free(&onb);
        free(ha.from); free(ha.to); free(hb.from); free(hb.to);
        st_mesh_free(&a);
        st_mesh_free(&b);
    }
    st_hier_free(&h);
    st_mesh_free(&base);
}

int main(void)
{
    check_levels("grid", grid, NULL, 3);
    check_levels("open.obj", NULL, STRATA_ASSETS "/open.obj", 3);
    check_levels("cube_no_bottom", NULL, STRATA_SHARED_DATA "/triangle/cube_no_bottom.obj", 3);
    check_levels("hole_capsule", NULL, STRATA_SHARED_DATA "/catmull_clark/hole_capsule.off", 2);
    tl_check_local_equals_full(ST_SCHEME_DOOSABIN, grid, 3);
    tl_check_rigid_motion(ST_SCHEME_DOOSABIN, grid, 3);
    tl_check_details_kept(ST_SCHEME_DOOSABIN, grid, 3);
    tl_check_analysis(ST_SCHEME_DOOSABIN, grid, 6); /* the round trip at depth 6 */
    return TEST_END();
}
