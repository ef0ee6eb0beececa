/* bench_session [MESH] [--scheme S] [--levels N] [--reps R] [--progressive]
 *
 * Saving and loading a session in one process, the whole form (MAP: every
 * level's topology, what every session held before version 4) against the
 * compact one (LVL0 + POSN: level 0, every level's positions; the reader
 * regenerates the levels), on the same hierarchy: MESH (default the shared
 * spot_quadrangulated.obj) subdivided N times (default 4) by S (default
 * catmull-clark).  Each repetition writes both files into memory
 * (st_session_write_mem, the writer of st_session_save without the disk)
 * and parses both (st_session_parse, the loader after reading the file),
 * alternating; prints the sizes, the medians of R repetitions (default 7)
 * and the ratios compact / whole.
 *
 * --progressive: the same for the progressive hierarchy of MESH (default
 * the shared koala.obj) down to 1 % of its faces, as `strata rebuild
 * --method progressive` builds and saves it (level 0 as the base mesh); its
 * compact form is PMRC + POSN (level 0
 * and the vertex splits; the reader replays them).  --profile-load: the
 * compact form's load alone, R times, for profilers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "core/io/mesh.h"
#include "core/io/session.h"
#include "core/multires/hier.h"
#include "core/progressive/progressive.h"
#include "core/progressive/scheme_registry.h"

#ifndef STRATA_SHARED_DATA
#define STRATA_SHARED_DATA "../shared/data/meshes"
#endif

static double time_write(const st_session_ref *r, void **data, size_t *n)
{
    st_error err;
    free(*data);
    *data = NULL;
    double t0 = bench_now();
    if (st_session_write_mem(r, data, n, &err)) { fprintf(stderr, "bench_session: %s\n", err.msg); exit(1); }
    return bench_now() - t0;
}

static double time_parse(const void *data, size_t n)
{
    st_session s;
    st_error err;
    double t0 = bench_now();
    if (st_session_parse("bench.strata", data, n, &s, &err)) { fprintf(stderr, "bench_session: %s\n", err.msg); exit(1); }
    double t = bench_now() - t0;
    st_session_free(&s);
    return t;
}

int main(int argc, char **argv)
{
    const char *path = STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", *scheme = "catmull-clark";
    unsigned levels = 4;
    int reps = 7, progressive = 0, have_path = 0, profile_load = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--scheme") && i + 1 < argc) scheme = argv[++i];
        else if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--progressive")) progressive = 1;
        else if (!strcmp(argv[i], "--profile-load")) profile_load = 1;
        else if (argv[i][0] != '-') path = argv[i], have_path = 1;
        else { fprintf(stderr, "usage: bench_session [MESH] [--scheme S] [--levels N] [--reps R] [--progressive] [--profile-load]\n"); return 2; }
    }
    if (progressive && !have_path) path = STRATA_SHARED_DATA "/large/koala.obj";
    if (reps < 1) reps = 1;
    st_mesh m;
    st_hier h;
    st_error err;
    st_mesh_init(&m);
    const st_scheme *sc = st_scheme_find(progressive ? "progressive" : scheme);
    if (progressive) {
        st_progressive_opts po = { .predictor = ST_PM_DEFAULT, .fit_coarse = 1 };
        if (st_mesh_load(path, &m, &err) || (po.target_faces = m.nfaces / 100, 0) ||
            st_progressive_build(&m, &po, &h, NULL, &err)) {
            fprintf(stderr, "bench_session: %s\n", err.msg);
            return 1;
        }
        levels = h.map.top;
        /* What `strata rebuild` stores as the base mesh: level 0 (app/cmd_rebuild.c). */
        st_mesh_free(&m);
        st_mesh_init(&m);
        if (st_hier_level_mesh(&h, 0, &m, &err)) { fprintf(stderr, "bench_session: %s\n", err.msg); return 1; }
    } else if (!sc || st_mesh_load(path, &m, &err) || st_hier_init(&h, &m, sc, NULL, &err) || st_hier_subdivide_to(&h, levels, &err)) {
        fprintf(stderr, "bench_session: %s\n", sc ? err.msg : "unknown scheme");
        return 1;
    }
    st_session_ref whole = { .h = &h, .base = &m, .display_level = levels, .whole_map = 1 }, compact = whole;
    compact.whole_map = 0;
    void *bw = NULL, *bc = NULL;
    size_t nw = 0, nc = 0;
    double *sw = malloc((size_t)reps * sizeof *sw), *sc_ = malloc((size_t)reps * sizeof *sc_);
    double *lw = malloc((size_t)reps * sizeof *lw), *lc = malloc((size_t)reps * sizeof *lc);
    if (profile_load) {
        /* For profilers: the compact load alone, R times. */
        time_write(&compact, &bc, &nc);
        for (int k = 0; k < reps; k++) time_parse(bc, nc);
        free(bc);
        return 0;
    }
    for (int k = 0; k < reps; k++) {
        sw[k] = time_write(&whole, &bw, &nw);
        sc_[k] = time_write(&compact, &bc, &nc);
        lw[k] = time_parse(bw, nw);
        lc[k] = time_parse(bc, nc);
    }
    double msw = bench_median(sw, reps), msc = bench_median(sc_, reps), mlw = bench_median(lw, reps), mlc = bench_median(lc, reps);
    printf("session of %s, %s, %u levels: whole (MAP) %zu bytes, compact (%s + POSN) %zu bytes: %.3fx\n", path, sc->name,
           levels, nw, progressive ? "PMRC" : "LVL0", nc, (double)nc / (double)nw);
    printf("save (to memory):       whole %8.1f ms, compact %8.1f ms: %.3fx  (medians of %d)\n", 1e3 * msw, 1e3 * msc,
           msc / msw, reps);
    printf("load (parse, regenerate): whole %8.1f ms, compact %8.1f ms: %.3fx\n", 1e3 * mlw, 1e3 * mlc, mlc / mlw);
    free(bw);
    free(bc);
    free(sw);
    free(sc_);
    free(lw);
    free(lc);
    st_hier_free(&h);
    st_mesh_free(&m);
    return 0;
}
