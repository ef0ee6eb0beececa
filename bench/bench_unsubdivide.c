/* bench_unsubdivide [MESH] [--levels N] [--repeat R]: unsubdivide of a
 * Catmull-Clark mesh (default: spot's quad cage, 2928 faces, subdivided 4
 * times = 749,568 quads; in Strata's vertex order, then shuffled) against Strata subdividing the
 * cage to the same depth.  Prints medians of R runs (default 5) of
 *   - st_unsubdivide limited to N levels (labelling, checks, cage),
 *   - st_unsubdivide with no limit (spot's cage is itself twice split),
 *   - st_unsub_build_hier (cage hierarchy, correspondence, analysis),
 *   - st_hier_init + st_hier_subdivide_to(N) of the cage,
 * and the ratio of the first to the last.  --no-hier leaves out the
 * hierarchy (for callgrind's instruction counts). */
#include "bench_common.h"
#include "core/rebuild/unsubdivide.h"

#include <stdio.h>
#include <string.h>

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint32_t rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 32);
}

/* Vertex order shuffled (faces follow), as another program would number. */
static void shuffle_vertices(st_mesh *m)
{
    uint32_t n = m->nverts, *perm = malloc(n * sizeof *perm);
    double *pos = malloc(3 * (size_t)n * sizeof *pos);
    if (!perm || !pos) abort();
    for (uint32_t i = 0; i < n; i++) perm[i] = i;
    for (uint32_t i = n; i > 1; i--) { uint32_t j = rnd() % i, t = perm[i - 1]; perm[i - 1] = perm[j]; perm[j] = t; }
    for (uint32_t v = 0; v < n; v++) memcpy(pos + 3 * (size_t)perm[v], m->pos + 3 * (size_t)v, 3 * sizeof *pos);
    for (uint32_t c = 0; c < m->face_off[m->nfaces]; c++) m->face_idx[c] = perm[m->face_idx[c]];
    free(m->pos);
    m->pos = pos;
    free(perm);
}

int main(int argc, char **argv)
{
    const char *path = STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj";
    unsigned levels = 4;
    int repeat = 5, hier = 1;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--no-hier")) hier = 0;   /* for callgrind: unsubdivide and subdivide only */
        else path = argv[i];
    }
    if (repeat < 1 || repeat > 99 || levels < 1 || levels > 8) { fprintf(stderr, "bad arguments\n"); return 2; }
    const st_scheme *sc = st_scheme_find("catmull-clark");
    st_error err;
    st_mesh cage, fine;
    st_mesh_init(&cage);
    st_mesh_init(&fine);
    if (st_mesh_load(path, &cage, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    double t_sub[99], t_unsub[99], t_all[99], t_hier[99], c_sub[99], c_unsub[99];
    for (int r = 0; r < repeat; r++) {
        st_hier h;
        double t0 = bench_now(), c0 = cpu_now();
        if (st_hier_init(&h, &cage, sc, NULL, &err) || st_hier_subdivide_to(&h, levels, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
        t_sub[r] = bench_now() - t0;
        c_sub[r] = cpu_now() - c0;
        if (r == 0 && st_hier_level_mesh(&h, levels, &fine, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
        st_hier_free(&h);
    }
    st_unsub u;
    double t_plain[99];
    for (int r = 0; r < repeat; r++) {
        st_unsub_opts o = { .max_levels = levels };
        double t0 = bench_now();
        if (st_unsubdivide("bench", &fine, &o, &u, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
        t_plain[r] = bench_now() - t0;
        st_unsub_free(&u);
    }
    shuffle_vertices(&fine);
    unsigned found = 0, found_all = 0;
    uint32_t cage_faces = 0, cage_all = 0;
    for (int r = 0; r < repeat; r++) {
        st_unsub_opts o = { .max_levels = levels };
        double t0 = bench_now(), c0 = cpu_now();
        if (st_unsubdivide("bench", &fine, &o, &u, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
        t_unsub[r] = bench_now() - t0;
        c_unsub[r] = cpu_now() - c0;
        found = u.levels;
        cage_faces = u.step[0].coarse.nfaces;
        st_unsub_free(&u);
        o.max_levels = 0;
        t0 = bench_now();
        if (st_unsubdivide("bench", &fine, &o, &u, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
        t_all[r] = bench_now() - t0;
        found_all = u.levels;
        cage_all = u.step[0].coarse.nfaces;
        st_unsub_free(&u);
    }
    st_unsub_opts o = { .max_levels = levels };
    if (st_unsubdivide("bench", &fine, &o, &u, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    int hr = !hier ? 0 : repeat < 3 ? repeat : 3;
    double detail = 0;
    for (int r = 0; r < hr; r++) {
        st_hier h;
        double t0 = bench_now();
        if (st_unsub_build_hier(&fine, &u, sc, NULL, &h, NULL, NULL, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
        t_hier[r] = bench_now() - t0;
        detail = st_unsub_max_detail(&h);
        st_hier_free(&h);
    }
    st_unsub_free(&u);
    double ms_sub = 1e3 * bench_median(t_sub, repeat), ms_unsub = 1e3 * bench_median(t_unsub, repeat);
    double ms_all = 1e3 * bench_median(t_all, repeat), ms_hier = hr ? 1e3 * bench_median(t_hier, hr) : 0;
    printf("input: %s (%u faces) x%u = %u faces, %u vertices, vertex order shuffled\n", path, cage.nfaces, levels, fine.nfaces, fine.nverts);
    printf("unsubdivide, %u levels, Strata's vertex order: %8.1f ms  (median of %d)\n", found, 1e3 * bench_median(t_plain, repeat), repeat);
    printf("unsubdivide, %u levels:        %8.1f ms  (median of %d; cage %u faces)\n", found, ms_unsub, repeat, cage_faces);
    printf("unsubdivide, no limit (%u):     %8.1f ms  (cage %u faces)\n", found_all, ms_all, cage_all);
    printf("hierarchy + analysis:          %8.1f ms  (median of %d; longest detail %.3g)\n", ms_hier, hr, detail);
    printf("subdivide the cage %u levels:   %8.1f ms  (median of %d)\n", levels, ms_sub, repeat);
    /* The least CPU time too: on a loaded machine the median moves with
     * the other processes' cache and memory traffic; the minimum less so. */
    double min_unsub = c_unsub[0];
    for (int r = 1; r < repeat; r++) if (c_unsub[r] < min_unsub) min_unsub = c_unsub[r];
    printf("ratio unsubdivide / subdivide: %.2f wall clock, %.2f CPU time (%.1f ms / %.1f ms; unsubdivide's least CPU time %.1f ms)\n",
           ms_unsub / ms_sub, bench_median(c_unsub, repeat) / bench_median(c_sub, repeat), 1e3 * bench_median(c_unsub, repeat),
           1e3 * bench_median(c_sub, repeat), 1e3 * min_unsub);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
    return 0;
}
