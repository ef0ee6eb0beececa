/* bench_adapt: interest-box update after moving the box by 5 % of its size,
 * against rebuilding the adaptive mesh from scratch.
 *
 *   bench_adapt
 *
 * Cases: spot_quadrangulated.obj, Catmull-Clark, base 0, max 5; koala.obj,
 * Loop, base 0, max 3.  The box (a tenth of the model's extent, around the
 * vertex of largest x) is moved by 5 % of its size along x.  Medians of 9. */
#include "core/io/mesh.h"
#include "core/adapt/adapt.h"
#include "bench_common.h"
#include "core/multires/hier.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define RUNS 9

static int load(st_hier *h, const char *path, const char *scheme)
{
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    if (st_mesh_load(path, &m, &err)) { fprintf(stderr, "bench_adapt: %s\n", err.msg); return -1; }
    int rc = st_hier_init(h, &m, st_scheme_find(scheme), NULL, &err);
    st_mesh_free(&m);
    if (rc) fprintf(stderr, "bench_adapt: %s\n", err.msg);
    return rc;
}

/* A box of a tenth of the model's extent around the vertex of largest x
 * (on the surface), shifted along x by `shift` times its size. */
static double anchor[3];

static void box_at(const double lo[3], const double hi[3], double shift, st_adapt_params *p)
{
    double c[3], r[3];
    for (int k = 0; k < 3; k++) { c[k] = anchor[k]; r[k] = 0.05 * (hi[k] - lo[k]); }
    c[0] += shift * 2 * r[0];
    for (int k = 0; k < 3; k++) { p->box_lo[k] = c[k] - r[k]; p->box_hi[k] = c[k] + r[k]; }
    p->has_box = 1;
}

static void run_case(const char *path, const char *scheme, unsigned max)
{
    st_hier h;
    st_adapt a;
    st_error err;
    if (load(&h, path, scheme)) return;
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, 0, &it); v != ST_NIL; v = st_vertex_next(&h.map, 0, &it))
        for (int k = 0; k < 3; k++) {
            const double *q = st_pos(&h.map, v, 0);
            if (k == 0 && q[0] > hi[0]) memcpy(anchor, q, sizeof anchor);
            lo[k] = fmin(lo[k], q[k]);
            hi[k] = fmax(hi[k], q[k]);
        }
    st_adapt_params p = { .base_level = 0, .max_level = max };
    double t_move[RUNS], t_build[RUNS];
    st_adapt_init(&a, &h, &err);
    box_at(lo, hi, 0, &p);
    st_adapt_update(&a, &p, &err);
    for (int r = 0; r < RUNS; r++) {
        box_at(lo, hi, (r % 2) ? 0.0 : 0.05, &p);
        double t0 = bench_now();
        st_adapt_update(&a, &p, &err);
        t_move[r] = bench_now() - t0;
    }
    st_mesh out;
    st_mesh_init(&out);
    st_adapt_mesh(&a, &out, &err);
    uint32_t faces = out.nfaces;
    st_mesh_free(&out);
    st_adapt_free(&a);
    st_hier_free(&h);
    for (int r = 0; r < RUNS; r++) {
        st_hier g;
        st_adapt b;
        if (load(&g, path, scheme)) return;
        box_at(lo, hi, 0.05, &p);
        double t0 = bench_now();
        st_adapt_init(&b, &g, &err);
        st_adapt_update(&b, &p, &err);
        t_build[r] = bench_now() - t0;
        st_adapt_free(&b);
        st_hier_free(&g);
    }
    double m = bench_median(t_move, RUNS), b = bench_median(t_build, RUNS);
    printf("%s, %s, max level %u, %u faces displayed: box moved by 5%% %.1f ms, rebuild %.1f ms, ratio %.3f (target <= 0.1)\n",
           path, scheme, max, faces, 1e3 * m, 1e3 * b, m / b);
}

int main(void)
{
    run_case(STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", "catmull-clark", 5);
    run_case(STRATA_SHARED_DATA "/large/koala.obj", "loop", 3);
    return 0;
}
