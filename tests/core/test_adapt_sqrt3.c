/* Adaptive √3 (adapt_sqrt3.c, thesis Algorithm 8): validity after random box
 * moves, watertight triangle display, agreement with the regular √3
 * hierarchy, the base level when the box covers nothing, the detail round
 * trip, resynthesis, and the refusal of open meshes.  The drivers are shared
 * with the other adaptive schemes (adapt_testlib.c); the odd triangles and
 * the refusal of open meshes are √3's own. */
#include "adapt_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Quads split along a diagonal. */
static void triangulate(st_mesh *s)
{
    uint32_t nf = 0;
    for (uint32_t f = 0; f < s->nfaces; f++) nf += s->face_off[f + 1] - s->face_off[f] - 2;
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(3 * (size_t)nf * sizeof *idx), k = 0;
    for (uint32_t f = 0; f < s->nfaces; f++) {
        const uint32_t *v = s->face_idx + s->face_off[f];
        for (uint32_t j = 1; j + 1 < s->face_off[f + 1] - s->face_off[f]; j++) {
            off[k] = 3 * k;
            idx[3 * k] = v[0]; idx[3 * k + 1] = v[j]; idx[3 * k + 2] = v[j + 1];
            k++;
        }
    }
    off[k] = 3 * k;
    st_mesh t;
    tl_mesh_make(&t, s->pos, s->nverts, off, idx, nf);
    free(off);
    free(idx);
    st_mesh_free(s);
    *s = t;
}

/* Icosahedron with every edge split twice (midpoints pushed to the unit
 * sphere): 320 triangles, like the shared sphere_ico.obj. */
static void icosphere(st_mesh *s)
{
    const double t = (1 + sqrt(5.0)) / 2;
    double p[642 * 3] = { -1,t,0, 1,t,0, -1,-t,0, 1,-t,0, 0,-1,t, 0,1,t, 0,-1,-t, 0,1,-t, t,0,-1, t,0,1, -t,0,-1, -t,0,1 };
    uint32_t f[320 * 3] = { 0,11,5, 0,5,1, 0,1,7, 0,7,10, 0,10,11, 1,5,9, 5,11,4, 11,10,2, 10,7,6, 7,1,8,
                            3,9,4, 3,4,2, 3,2,6, 3,6,8, 3,8,9, 4,9,5, 2,4,11, 6,2,10, 8,6,7, 9,8,1 };
    uint32_t nv = 12, nf = 20;
    for (int round = 0; round < 2; round++) {
        uint32_t g[320 * 3], ng = 0;
        uint64_t keys[960];
        uint32_t mids[960], nk = 0;
        for (uint32_t k = 0; k < nf; k++) {
            uint32_t m3[3];
            for (int e = 0; e < 3; e++) {
                uint32_t a = f[3 * k + e], b = f[3 * k + (e + 1) % 3];
                uint64_t key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
                uint32_t j = 0;
                while (j < nk && keys[j] != key) j++;
                if (j == nk) {
                    for (int c = 0; c < 3; c++) p[3 * nv + c] = (p[3 * a + c] + p[3 * b + c]) / 2;
                    keys[nk] = key;
                    mids[nk++] = nv++;
                }
                m3[e] = mids[j];
            }
            uint32_t v0 = f[3 * k], v1 = f[3 * k + 1], v2 = f[3 * k + 2];
            uint32_t tri[12] = { v0, m3[0], m3[2], v1, m3[1], m3[0], v2, m3[2], m3[1], m3[0], m3[1], m3[2] };
            memcpy(g + 3 * ng, tri, sizeof tri);
            ng += 4;
        }
        memcpy(f, g, 3 * ng * sizeof *g);
        nf = ng;
    }
    for (uint32_t v = 0; v < nv; v++) {
        double r = sqrt(p[3 * v] * p[3 * v] + p[3 * v + 1] * p[3 * v + 1] + p[3 * v + 2] * p[3 * v + 2]);
        for (int c = 0; c < 3; c++) p[3 * v + c] /= r;
    }
    uint32_t off[321];
    for (uint32_t k = 0; k <= nf; k++) off[k] = 3 * k;
    tl_mesh_make(s, p, nv, off, f, nf);
}

static void tri_torus(st_mesh *s) { tl_mesh_torus(s, 8, 6); triangulate(s); }
static void tri_cube(st_mesh *s) { tl_mesh_cube(s); triangulate(s); }
static void tri_grid(st_mesh *s) { tl_mesh_grid(s, 3); triangulate(s); }

/* Odd triangles (Algorithm 8: a neighbour of lower level across an
 * unflipped edge) sit at the depth borders of every level. */
static int odd_triangle(st_map *m, uint32_t d, unsigned k)
{
    return st_face_level(m, d, k) == k && st_face_level(m, st_beta0(m, d, k), k) < k;
}

static void check_open_refused(void)
{
    st_hier h;
    st_adapt a;
    st_error err;
    tl_init_hier(&h, tri_grid, ST_SCHEME_SQRT3, 0);
    CHECK(st_adapt_init(&a, &h, &err) != ST_OK);
    CHECK(strstr(err.msg, "closed") != NULL);
    st_adapt_free(&a);
    st_hier_free(&h);
}

static at_case sqrt3(void (*make)(st_mesh *), const char *name, unsigned max, double extent)
{
    return (at_case){ ST_SCHEME_SQRT3, make, name, 1, 3, max, extent };
}

int main(void)
{
    const at_case cases[] = {
        sqrt3(tl_mesh_octa, "octahedron", 4, 1),
        sqrt3(tri_cube, "cube", 3, 1),
        sqrt3(tri_torus, "torus", 4, 2.7),
        sqrt3(icosphere, "icosphere", 4, 1),
    };
    at_run_cases(cases, sizeof cases / sizeof *cases, odd_triangle, "odd triangle", NULL);
    const at_case flat = sqrt3(tri_torus, "torus", 3, 2.7);
    at_check_flatness(&flat);
    const at_inc inc[] = {
        { sqrt3(tri_torus, "torus", 4, 2.7), 0.3 },
        { sqrt3(tri_torus, "torus small box", 5, 2.7), 0.08 },
        { sqrt3(tl_mesh_octa, "octahedron", 5, 1), 0.2 },
        { sqrt3(icosphere, "icosphere", 4, 1), 0.15 },
    };
    at_run_incremental(inc, sizeof inc / sizeof *inc);
    at_check_history_free(&cases[3], 1234); /* icosphere, max 4 */
    at_check_history_free(&cases[2], 1235); /* torus, max 4 */
    check_open_refused();
    return TEST_END();
}
