/* bench_map: kernel figures for a regular hierarchy.
 *
 *   bench_map [MESH.obj] [--levels N] [--split poly|tri]
 *
 * Prints topology bytes per finest dart, cells (faces and vertices)
 * enumerated per second at level 0 and at the finest level, and neighbour
 * queries per second at level 0 and at the finest level.  Equal query rates
 * at both levels (within noise) are the evidence that a relation lookup is
 * O(1) whatever the level.  Medians of 5 runs. */
#include "bench_common.h"
#include "core/map/map.h"
#include "core/map/map_mesh.h"
#include "core/io/mesh.h"
#include "core/map/refine_internal.h"

#include <stdio.h>
#include <string.h>

#define RUNS 5

/* Enumerates faces and vertices of level l with markers; returns cells. */
static uint64_t enumerate_cells(st_map *m, unsigned l)
{
    uint64_t n = 0;
    int fb = st_marker_reserve(m), vb = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (!st_marked(m, fb, d)) { st_mark_face(m, fb, d, l); n++; }
        if (!st_marked(m, vb, d)) { st_mark_vertex(m, vb, d, l); n++; }
    }
    st_marker_release(m, fb, l);
    st_marker_release(m, vb, l);
    return n;
}

static double cells_per_second(st_map *m, unsigned l)
{
    double t[RUNS];
    for (int r = 0; r < RUNS; r++) {
        uint64_t cells = 0;
        int reps = 0;
        double t0 = bench_now(), t1;
        do { cells += enumerate_cells(m, l); reps++; t1 = bench_now(); } while (t1 - t0 < 0.2);
        t[r] = (double)cells / (t1 - t0);
    }
    return bench_median(t, RUNS);
}

/* One neighbour query: the vertices adjacent to the vertex of d (walk the
 * β1 cycle, follow β0 to the other end). */
static uint32_t one_ring(const st_map *m, uint32_t d, unsigned l)
{
    uint32_t acc = 0, x = d;
    do {
        acc += st_vert(m, st_beta0(m, x, l), l);
        x = st_beta1(m, x, l);
    } while (x != d);
    return acc;
}

static volatile uint32_t sink;

/* Queries one-rings of the given darts at level l; returns neighbours/s. */
static double queries_per_second(const st_map *m, const uint32_t *darts, uint32_t n, unsigned l)
{
    double t[RUNS];
    for (int r = 0; r < RUNS; r++) {
        uint64_t q = 0;
        uint32_t acc = 0;
        double t0 = bench_now(), t1;
        do {
            for (uint32_t i = 0; i < n; i++) {
                acc += one_ring(m, darts[i], l);
                q += st_vertex_degree(m, darts[i], l);
            }
            t1 = bench_now();
        } while (t1 - t0 < 0.2);
        sink = acc;
        t[r] = (double)q / (t1 - t0);
    }
    return bench_median(t, RUNS);
}

/* Relation lookups of the same darts at level l, without walking to other
 * darts: the cost of one lookup, separated from where the walk leads. */
static double lookups_per_second(const st_map *m, const uint32_t *darts, uint32_t n, unsigned l)
{
    double t[RUNS];
    for (int r = 0; r < RUNS; r++) {
        uint64_t q = 0;
        uint32_t acc = 0;
        double t0 = bench_now(), t1;
        do {
            for (uint32_t i = 0; i < n; i++) acc += st_beta0(m, darts[i], l) ^ st_beta1(m, darts[i], l);
            q += 2 * (uint64_t)n;
            t1 = bench_now();
        } while (t1 - t0 < 0.2);
        sink = acc;
        t[r] = (double)q / (t1 - t0);
    }
    return bench_median(t, RUNS);
}

static uint32_t *sample_darts(const st_map *m, unsigned l, uint32_t n)
{
    uint32_t *out = malloc((size_t)n * sizeof *out), k = 0;
    uint64_t s = 88172645463325252ull;
    while (k < n) {
        s ^= s << 13; s ^= s >> 7; s ^= s << 17;
        uint32_t d = (uint32_t)(s >> 32) % m->darts.end;
        if (st_dart_in_level(m, d, l)) out[k++] = d;
    }
    return out;
}

int main(int argc, char **argv)
{
    const char *path = STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj";
    unsigned levels = 4;
    enum st_split_mode mode = ST_SPLIT_POLY;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--split") && i + 1 < argc) mode = !strcmp(argv[++i], "tri") ? ST_SPLIT_TRI : ST_SPLIT_POLY;
        else path = argv[i];
    }
    st_mesh mesh;
    st_error err;
    st_map m;
    st_mesh_init(&mesh);
    st_map_init(&m);
    if (st_mesh_load(path, &mesh, &err) || st_map_from_mesh(&m, &mesh, &err)) {
        fprintf(stderr, "bench_map: %s\n", err.msg);
        return 1;
    }
    st_mesh_free(&mesh);
    double t0 = bench_now();
    for (unsigned k = 0; k < levels; k++)
        if (st_refine_uniform(&m, mode, &err)) { fprintf(stderr, "bench_map: %s\n", err.msg); return 1; }
    double t_refine = bench_now() - t0;
    st_level_stats s0, sk;
    st_level_stats_compute(&m, 0, &s0);
    st_level_stats_compute(&m, m.top, &sk);
    st_map_bytes b;
    st_map_memory(&m, &b);
    printf("mesh %s, %s split, depth %u\n", path, mode == ST_SPLIT_TRI ? "triangle" : "polygon", levels);
    printf("darts: level 0 %llu, level %u %llu; refinement %.3f s\n", (unsigned long long)s0.darts, m.top,
           (unsigned long long)sk.darts, t_refine);
    printf("topology bytes per finest dart: %.2f (total %zu bytes; positions %zu bytes)\n",
           (double)b.topology / (double)sk.darts, b.topology, b.positions);
    double c0 = cells_per_second(&m, 0), ck = cells_per_second(&m, m.top);
    printf("cells enumerated per second: level 0 %.3g, level %u %.3g (ratio %.2f)\n", c0, m.top, ck, ck / c0);
    uint32_t n = 100000;
    uint32_t *d0 = sample_darts(&m, 0, n), *dk = sample_darts(&m, m.top, n);
    double q00 = queries_per_second(&m, d0, n, 0);
    double q0k = queries_per_second(&m, d0, n, m.top);
    double qkk = queries_per_second(&m, dk, n, m.top);
    printf("neighbour queries per second: level-0 darts at level 0 %.3g, the same darts at level %u %.3g (ratio %.2f), "
           "random darts at level %u %.3g (ratio %.2f)\n", q00, m.top, q0k, q0k / q00, m.top, qkk, qkk / q00);
    double l00 = lookups_per_second(&m, d0, n, 0), l0k = lookups_per_second(&m, d0, n, m.top);
    printf("relation lookups per second (beta0, beta1 of the same level-0 darts): at level 0 %.3g, at level %u %.3g (ratio %.2f)\n",
           l00, m.top, l0k, l0k / l00);
    free(d0);
    free(dk);
    st_map_free(&m);
    return 0;
}
