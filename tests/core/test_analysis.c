/* Analysis and synthesis: round trips, zero details for exact
 * subdivisions, and level switches that change nothing. */
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/base/parallel.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void torus(st_mesh *s) { tl_mesh_torus(s, 8, 5); }
static void grid(st_mesh *s) { tl_mesh_grid(s, 4); }

static double bbox_diag(const st_hier *h, unsigned l)
{
    double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
        const double *p = st_pos(&h->map, v, l);
        for (int i = 0; i < 3; i++) { lo[i] = fmin(lo[i], p[i]); hi[i] = fmax(hi[i], p[i]); }
    }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/* Copies the positions of level l, indexed by vertex id. */
static double *copy_level(const st_hier *h, unsigned l)
{
    double *p = calloc(3 * (size_t)h->map.verts.end + 1, sizeof *p);
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
        memcpy(p + 3 * (size_t)v, st_pos(&h->map, v, l), 3 * sizeof *p);
    return p;
}

static double max_diff_level(const st_hier *h, unsigned l, const double *ref)
{
    double m = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
        const double *p = st_pos(&h->map, v, l);
        for (int i = 0; i < 3; i++) m = fmax(m, fabs(p[i] - ref[3 * (size_t)v + i]));
    }
    return m;
}

/* Analysis to level 0 then synthesis gives back the finest positions. */
static void check_round_trip(st_scheme_id id, void (*make)(st_mesh *), unsigned depth)
{
    st_hier h;
    uint64_t rng = 4242 + id;
    tl_init_hier(&h, make, id, depth);
    tl_random_details(&h, &rng, 0.01);
    double diag = bbox_diag(&h, depth);
    double *fine = copy_level(&h, depth);
    double res = st_hier_analyze(&h, 0);
    st_hier_synthesize(&h, 0);
    double err = max_diff_level(&h, depth, fine) / diag;
    printf("%s depth %u: analysis+synthesis round trip %.3g of the bbox diagonal (solver residual %.2g)\n",
           h.scheme->name, depth, err, res);
    CHECKF(err < 1e-6, "%s: round trip error %g", h.scheme->name, err);
    free(fine);
    st_hier_free(&h);
}

/* A mesh that is exactly a subdivision analyses to zero details and gives
 * back its control mesh. */
static void check_exact_subdivision(st_scheme_id id, void (*make)(st_mesh *), unsigned depth)
{
    st_hier h;
    tl_init_hier(&h, make, id, depth);
    double *coarse = copy_level(&h, 0);
    double diag = bbox_diag(&h, 0);
    /* Scramble the coarse levels so that analysis has to find them. */
    st_dart_iter it;
    for (unsigned l = 0; l < depth; l++)
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it))
            if (st_vertex_level(&h.map, v) == l) {
                double p[3];
                memcpy(p, st_pos(&h.map, v, l), sizeof p);
                p[0] += 0.1; p[2] -= 0.05;
                st_hier_write_pos(&h, v, l, p);
            }
    double *fine = copy_level(&h, depth);
    st_hier_analyze(&h, 0);
    double worst = 0;
    for (unsigned l = 1; l <= depth; l++)
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            const double *d = st_hier_detail(&h, l, v);
            worst = fmax(worst, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
    double back = max_diff_level(&h, 0, coarse) / diag;
    CHECKF(worst / diag < 1e-9, "%s: details of an exact subdivision %g", h.scheme->name, worst / diag);
    CHECKF(back < 1e-9, "%s: control mesh recovered to %g", h.scheme->name, back);
    CHECK(max_diff_level(&h, depth, fine) / diag < 1e-12);
    free(coarse);
    free(fine);
    st_hier_free(&h);
}

/* Going to any level and back up (re-synthesis from it) changes nothing. */
static void check_level_switch(st_scheme_id id, void (*make)(st_mesh *), unsigned depth)
{
    st_hier h;
    uint64_t rng = 99;
    tl_init_hier(&h, make, id, depth);
    tl_random_details(&h, &rng, 0.02);
    double *before[ST_MAX_LEVELS];
    for (unsigned l = 0; l <= depth; l++) before[l] = copy_level(&h, l);
    for (unsigned l = 0; l <= depth; l++) {
        st_hier_synthesize(&h, l);
        for (unsigned k = 0; k <= depth; k++) {
            double e = max_diff_level(&h, k, before[k]);
            CHECKF(e < 1e-12, "%s: switching to level %u changed level %u by %g", h.scheme->name, l, k, e);
        }
    }
    for (unsigned l = 0; l <= depth; l++) free(before[l]);
    st_hier_free(&h);
}

/* Precision: the same round trip with positions and details stored as
 * float (quantised after analysis) instead of double.  Printed so that the
 * storage choice is justified by a measurement; double must stay far below
 * the 1e-6 tolerance. */
static void report_precision(void)
{
    st_hier h;
    uint64_t rng = 7;
    tl_init_hier(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 6);
    tl_random_details(&h, &rng, 0.01);
    double diag = bbox_diag(&h, 6);
    double *fine = copy_level(&h, 6);
    st_hier_analyze(&h, 0);
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, 0, &it); v != ST_NIL; v = st_vertex_next(&h.map, 0, &it)) {
        const double *p = st_pos(&h.map, v, 0);
        double q[3] = { (float)p[0], (float)p[1], (float)p[2] };
        st_hier_write_pos(&h, v, 0, q);
    }
    for (unsigned l = 1; l <= 6; l++)
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            const double *d = st_hier_detail(&h, l, v);
            double q[3] = { (float)d[0], (float)d[1], (float)d[2] };
            st_hier_set_detail(&h, l, v, q);
        }
    st_hier_synthesize(&h, 0);
    double err = max_diff_level(&h, 6, fine) / diag;
    printf("precision: depth-6 round trip with float storage %.3g of the bbox diagonal (double: see above)\n", err);
    CHECK(err > 1e-12); /* float quantisation is visible: the measurement is real */
    free(fine);
    st_hier_free(&h);
}

/* Delete lower: level 1 becomes the control mesh; every finer level keeps
 * its positions and topology, and re-synthesis changes nothing. */
static void check_remove_bottom(st_scheme_id id, void (*make)(st_mesh *), unsigned depth)
{
    st_hier h;
    st_error err;
    uint64_t rng = 5;
    tl_init_hier(&h, make, id, depth);
    tl_random_details(&h, &rng, 0.02);
    double *before[ST_MAX_LEVELS];
    st_level_stats sb[ST_MAX_LEVELS];
    for (unsigned l = 1; l <= depth; l++) { before[l] = copy_level(&h, l); st_level_stats_compute(&h.map, l, &sb[l]); }
    st_hier_remove_bottom(&h);
    CHECK(h.map.top == depth - 1);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s", err.msg);
    for (unsigned l = 0; l < depth; l++) {
        st_level_stats s;
        st_level_stats_compute(&h.map, l, &s);
        CHECK(memcmp(&s, &sb[l + 1], sizeof s) == 0);
        CHECK(max_diff_level(&h, l, before[l + 1]) == 0);
    }
    st_hier_synthesize(&h, 0);
    for (unsigned l = 0; l < depth; l++) CHECK(max_diff_level(&h, l, before[l + 1]) < 1e-12);
    CHECK(st_hier_subdivide_to(&h, depth + 1, &err) == ST_OK);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s", err.msg);
    for (unsigned l = 1; l <= depth; l++) free(before[l]);
    st_hier_free(&h);
}

/* Levels whose position or detail differs by a bit somewhere. */
static unsigned levels_differing(const st_hier *a, const st_hier *b)
{
    unsigned n = 0;
    for (unsigned l = 0; l <= a->map.top; l++) {
        int differ = 0;
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&a->map, l, &it); v != ST_NIL && !differ; v = st_vertex_next(&a->map, l, &it))
            differ = memcmp(st_pos(&a->map, v, l), st_pos(&b->map, v, l), 3 * sizeof(double)) ||
                     memcmp(st_hier_detail(a, l, v), st_hier_detail(b, l, v), 3 * sizeof(double));
        n += differ;
    }
    return n;
}

/* Catmull-Clark's streamed pass (hier_analysis.c): on an exact subdivision
 * every level is accepted without stored stencils and gives the bits of
 * the stored rows and the solve; with details (noise above the rounding)
 * every level falls back to the solve, the same bits again.  One, two and
 * four threads agree. */
static void check_streamed(void (*make)(st_mesh *), unsigned depth, double details)
{
    st_hier ref;
    uint64_t rng = 11;
    tl_init_hier(&ref, make, ST_SCHEME_CATMARK, depth);
    if (details > 0) tl_random_details(&ref, &rng, details);
    st_analysis_report rep;
    st_hier_analyze_ex(&ref, 0, 1, &rep);
    for (unsigned l = 1; l <= depth; l++) CHECK(!rep.streamed[l]);
    static const unsigned threads[3] = { 1, 2, 4 };
    for (unsigned t = 0; t < 3; t++) {
        st_hier h;
        st_parallel_set_threads(threads[t]);
        rng = 11;
        tl_init_hier(&h, make, ST_SCHEME_CATMARK, depth);
        if (details > 0) tl_random_details(&h, &rng, details);
        st_hier_analyze_ex(&h, 0, 0, &rep);
        unsigned streamed = 0;
        for (unsigned l = 1; l <= depth; l++) streamed += rep.streamed[l];
        CHECKF(streamed == (details > 0 ? 0 : depth), "depth %u, details %g, %u thread(s): %u of %u levels streamed",
               depth, details, threads[t], streamed, depth);
        unsigned differ = levels_differing(&ref, &h);
        CHECKF(differ == 0, "depth %u, details %g, %u thread(s): %u levels differ from the stored rows' analysis",
               depth, details, threads[t], differ);
        st_hier_free(&h);
    }
    st_parallel_set_threads(0);
    st_hier_free(&ref);
}

int main(void)
{
    report_precision();
    struct { st_scheme_id id; void (*make)(st_mesh *); unsigned depth; } cases[] = {
        { ST_SCHEME_CATMARK, torus, 4 },
        { ST_SCHEME_CATMARK, grid, 3 },
        { ST_SCHEME_CATMARK, tl_mesh_cube, 6 },
        { ST_SCHEME_DOOSABIN, torus, 4 },
        { ST_SCHEME_DOOSABIN, tl_mesh_cube, 6 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        check_round_trip(cases[i].id, cases[i].make, cases[i].depth);
        check_exact_subdivision(cases[i].id, cases[i].make, cases[i].depth < 4 ? cases[i].depth : 4);
        check_remove_bottom(cases[i].id, cases[i].make, 3);
        check_level_switch(cases[i].id, cases[i].make, cases[i].depth < 4 ? cases[i].depth : 4);
    }
    check_streamed(grid, 4, 0);          /* boundary rules */
    check_streamed(grid, 4, 0.01);
    check_streamed(torus, 4, 0);
    check_streamed(tl_mesh_cube, 7, 0);  /* 98k quads: level 6's pass on several threads */
    check_streamed(tl_mesh_cube, 7, 0.01);
    return TEST_END();
}
