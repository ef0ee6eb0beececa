/* bench_unsubdivide [MESH] [--levels N] [--repeat R] [--no-hier] [--rebuild-only] [--noise F]:
 * rebuilding the levels of a Catmull-Clark mesh (default: spot's quad cage,
 * 2928 faces, subdivided 4 times = 749,568 quads, vertex order shuffled as
 * another program would number) against Strata subdividing the cage to the
 * same depth.  The operation timed first is the user-visible one, what
 * `strata rebuild --method unsubdivide --max-levels N` does between loading
 * the mesh and saving the session: st_rebuild, i.e. recovering the cage
 * (st_unsubdivide) and building the hierarchy with its levels and details
 * (st_unsub_build_hier: the cage refined, the input's positions written at
 * the finest level, the analysis) and the report.  Then its two parts
 * alone, the same in Strata's vertex order and without a level limit.
 * Medians of R runs (default 5) of wall-clock and CPU time (CPU time counts
 * every thread).  --no-hier: unsubdivide and subdivide only (for
 * callgrind); --rebuild-only: the rebuild alone, R times (for perf);
 * --noise F: every vertex of the shuffled input moved by up to F times the bounding-box
 * diagonal per coordinate (no exact subdivision: the analysis' solver
 * iterates). */
#include "bench_common.h"
#include "core/base/hugepage.h"
#include "core/rebuild/rebuild.h"
#include "core/rebuild/unsubdivide.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

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

/* Each coordinate moved by up to f times the bounding-box diagonal. */
static void add_noise(st_mesh *m, double f)
{
    double diag = st_mesh_diagonal(m);
    for (size_t i = 0; i < 3 * (size_t)m->nverts; i++) m->pos[i] += f * diag * ((double)rnd() / 4294967295.0 * 2 - 1);
}

/* Wall-clock and CPU time of repeated runs. */
/* Minor page faults of the process so far (every thread's). */
static long minor_faults(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) ? 0 : ru.ru_minflt;
}

/* Wall-clock and CPU time of repeated runs, and their page faults (a fault
 * costs microseconds on a virtual machine: they are most of what a cold
 * run adds to a warm one). */
typedef struct timing { double wall[99], cpu[99], faults[99]; int n; double w0, c0; long f0; } timing;
static void tic(timing *t) { t->w0 = bench_now(); t->c0 = cpu_now(); t->f0 = minor_faults(); }
static void toc(timing *t)
{
    t->wall[t->n] = bench_now() - t->w0;
    t->cpu[t->n] = cpu_now() - t->c0;
    t->faults[t->n++] = (double)(minor_faults() - t->f0);
}
static double med_wall(timing *t) { return t->n ? 1e3 * bench_median(t->wall, t->n) : 0; }
static double med_cpu(timing *t) { return t->n ? 1e3 * bench_median(t->cpu, t->n) : 0; }

static void die(const st_error *err) { fprintf(stderr, "bench_unsubdivide: %s\n", err->msg); exit(1); }

/* st_rebuild by unsubdivide, as the CLI calls it. */
static void rebuild(const st_mesh *fine, unsigned levels, timing *t, st_rebuild_report *rep)
{
    st_rebuild_opts o = { .method = ST_REBUILD_UNSUBDIVIDE, .max_levels = levels };
    st_hier h;
    st_error err;
    tic(t);
    if (st_rebuild("bench", fine, &o, &h, rep, &err)) die(&err);
    toc(t);
    st_hier_free(&h);   /* after the clock: the command saves the session first */
}

int main(int argc, char **argv)
{
    const char *path = STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj";
    unsigned levels = 4;
    int repeat = 5, hier = 1, only_rebuild = 0;
    double noise = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--no-hier")) hier = 0;   /* for callgrind: unsubdivide and subdivide only */
        else if (!strcmp(argv[i], "--rebuild-only")) only_rebuild = 1;
        else if (!strcmp(argv[i], "--noise") && i + 1 < argc) noise = atof(argv[++i]);
        else path = argv[i];
    }
    if (repeat < 1 || repeat > 99 || levels < 1 || levels > 8 || !(noise >= 0 && noise < 1)) { fprintf(stderr, "bad arguments\n"); return 2; }
    st_malloc_keep_freed();   /* as `strata rebuild` does */
    const st_scheme *sc = st_scheme_find("catmull-clark");
    st_error err;
    st_mesh cage, fine;
    st_mesh_init(&cage);
    st_mesh_init(&fine);
    if (st_mesh_load(path, &cage, &err)) die(&err);
    timing t_sub = { 0 }, t_reb = { 0 }, t_reb_all = { 0 }, t_reb_plain = { 0 }, t_unsub = { 0 }, t_hier = { 0 };
    {
        st_hier h;
        if (st_hier_init(&h, &cage, sc, NULL, &err) || st_hier_subdivide_to(&h, levels, &err)) die(&err);
        if (st_hier_level_mesh(&h, levels, &fine, &err)) die(&err);
        st_hier_free(&h);
    }
    if (noise > 0) add_noise(&fine, noise);
    st_rebuild_report rep;
    memset(&rep, 0, sizeof rep);
    if (only_rebuild) {
        shuffle_vertices(&fine);
        for (int r = 0; r < repeat; r++) {
            st_rebuild_report_free(&rep);
            rebuild(&fine, levels, &t_reb, &rep);
        }
        /* The first run's figures before the medians sort the arrays. */
        double wall0 = 1e3 * t_reb.wall[0], cpu0 = 1e3 * t_reb.cpu[0], faults0 = t_reb.faults[0];
        double wall = med_wall(&t_reb), cpu = med_cpu(&t_reb), faults = bench_median(t_reb.faults, t_reb.n);
        printf("rebuild, %u levels: %8.1f ms wall, %8.1f ms CPU, %.0f page faults (median of %d; the first, "
               "cold as in a command's process: %.1f ms wall, %.1f ms CPU, %.0f page faults): %s\n", levels, wall, cpu, faults,
               repeat, wall0, cpu0, faults0, rep.summary);
        st_rebuild_report_free(&rep);
        st_mesh_free(&fine);
        st_mesh_free(&cage);
        return 0;
    }
    /* Interleaved, so that the load of the machine weighs on each alike. */
    st_mesh plain;
    st_mesh_init(&plain);
    for (int r = 0; r < repeat; r++) {
        st_hier h;
        tic(&t_sub);
        if (st_hier_init(&h, &cage, sc, NULL, &err) || st_hier_subdivide_to(&h, levels, &err)) die(&err);
        toc(&t_sub);
        if (r == 0) {
            if (st_hier_level_mesh(&h, levels, &plain, &err)) die(&err);
            shuffle_vertices(&fine);
        }
        st_hier_free(&h);
        st_unsub u;
        st_unsub_opts o = { .max_levels = levels };
        tic(&t_unsub);
        if (st_unsubdivide("bench", &fine, &o, &u, &err)) die(&err);
        toc(&t_unsub);
        if (hier) {
            tic(&t_hier);
            if (st_unsub_build_hier(&fine, &u, sc, NULL, &h, NULL, NULL, &err)) die(&err);
            toc(&t_hier);
            st_hier_free(&h);
        }
        st_unsub_free(&u);
        if (!hier) continue;
        st_rebuild_report_free(&rep);
        rebuild(&fine, levels, &t_reb, &rep);
        if (r < 3) {
            st_rebuild_report_free(&rep);
            rebuild(&plain, levels, &t_reb_plain, &rep);
            st_rebuild_report_free(&rep);
            rebuild(&fine, 0, &t_reb_all, &rep);
        }
    }
    printf("input: %s (%u faces) x%u = %u faces, %u vertices\n", path, cage.nfaces, levels, fine.nfaces, fine.nverts);
    printf("                                           wall ms   CPU ms  (medians)\n");
    if (hier) {
        printf("rebuild, %u levels, shuffled order:     %9.1f %8.1f  (%d runs)\n", levels, med_wall(&t_reb), med_cpu(&t_reb), t_reb.n);
        printf("  of which unsubdivide (cage):         %9.1f %8.1f\n", med_wall(&t_unsub), med_cpu(&t_unsub));
        printf("  of which hierarchy + analysis:       %9.1f %8.1f\n", med_wall(&t_hier), med_cpu(&t_hier));
        printf("rebuild, %u levels, Strata's order:     %9.1f %8.1f  (%d runs)\n", levels, med_wall(&t_reb_plain), med_cpu(&t_reb_plain), t_reb_plain.n);
        printf("rebuild, no limit, shuffled order:     %9.1f %8.1f  (%d runs: %s)\n", med_wall(&t_reb_all), med_cpu(&t_reb_all), t_reb_all.n, rep.summary);
    } else {
        printf("unsubdivide, %u levels, shuffled order: %9.1f %8.1f  (%d runs)\n", levels, med_wall(&t_unsub), med_cpu(&t_unsub), t_unsub.n);
    }
    printf("subdivide the cage %u levels:           %9.1f %8.1f  (%d runs)\n", levels, med_wall(&t_sub), med_cpu(&t_sub), t_sub.n);
    timing *num = hier ? &t_reb : &t_unsub;
    printf("ratio %s / subdivide: %.2f wall clock, %.2f CPU time\n", hier ? "rebuild" : "unsubdivide",
           med_wall(num) / med_wall(&t_sub), med_cpu(num) / med_cpu(&t_sub));
    st_rebuild_report_free(&rep);
    st_mesh_free(&plain);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
    return 0;
}
