/* bench_render [MESH] [--levels N] [--edit-level L] [--scheme S] [--reps R]
 *
 * Buffer update after a one-vertex edit vs a full rebuild of the buffers
 * (bench/RESULTS.md): a hierarchy of depth N (default 6) is displayed at its finest
 * level on a headless (OSMesa) context; one vertex of level L (default 2) is
 * moved with st_hier_edit, which reports what it wrote (its footprint), then
 *
 *   incremental: st_renderer_refresh with that footprint - the vertices of
 *                the finest level the edit wrote, their positions and the
 *                normals around them, re-uploaded range by range with
 *                glBufferSubData;
 *   full:        st_renderer_set_level - walk and triangulate the level,
 *                all positions and normals, all buffers uploaded again.
 *
 * Both end with glFinish.  Target: incremental <= 0.05 x full.  The time of
 * st_hier_edit itself (geometry, not buffers) is printed apart.  Medians of
 * R repetitions (default 15).
 *
 * Then the same for an adaptive change, in bench_adapt's case: the shared
 * spot_quadrangulated.obj refined by Catmull-Clark to depth 5 inside an
 * interest box (a tenth of the model's extent, around the vertex of largest
 * x), base level 0 (then most of the small displayed mesh changes with the
 * box) and 3 (the box's changes are a small part of what is shown), the box
 * moved by 5 % of its size (st_adapt_update, with the map's change log on;
 * not timed), then
 *
 *   patch: st_renderer_patch - only the faces the move touched are
 *          re-tessellated, only changed ranges uploaded;
 *   full:  st_renderer_set_level on the adaptive level.
 *
 * (No target is set for this one; its ratio is printed.) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/io/mesh.h"
#include "core/adapt/adapt.h"
#include "core/multires/edit.h"
#include "bench_common.h"
#include "render/headless.h"
#include "core/map/map_mesh.h"
#include "core/progressive/scheme_registry.h"
#include "render/renderer.h"

#ifndef STRATA_ASSETS
#define STRATA_ASSETS "assets"
#endif
#ifndef STRATA_SHARED_DATA
#define STRATA_SHARED_DATA "../shared/data/meshes"
#endif

/* The interest box of bench_adapt: a tenth of the extent around the vertex
 * of largest x of level 0, shifted along x by `shift` times its size. */
static void box_at(const st_map *m, double shift, st_adapt_params *p)
{
    double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 }, at[3] = { 0, 0, 0 };
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, 0, &it); v != ST_NIL; v = st_vertex_next(m, 0, &it)) {
        const double *q = st_pos(m, v, 0);
        if (q[0] > hi[0]) memcpy(at, q, sizeof at);
        for (int k = 0; k < 3; k++) { if (q[k] < lo[k]) lo[k] = q[k]; if (q[k] > hi[k]) hi[k] = q[k]; }
    }
    for (int k = 0; k < 3; k++) {
        double r = 0.05 * (hi[k] - lo[k]), c = at[k] + (k == 0 ? shift * 2 * r : 0);
        p->box_lo[k] = c - r;
        p->box_hi[k] = c + r;
    }
    p->has_box = 1;
}

/* The faces of the display (level l of m) that a move re-made: those
 * holding a dart the move logged (new, or with a changed relation) --
 * what any patch must re-tessellate, whatever else it keeps. */
static uint32_t faces_remade(const st_map *m, unsigned l, const st_map_log *log)
{
    uint8_t *seen = calloc(m->darts.end ? m->darts.end : 1, 1);
    uint32_t n = 0;
    for (uint32_t i = 0; seen && i < log->ndarts; i++) {
        uint32_t d = log->darts[i];
        if (d >= m->darts.end || seen[d] || !st_dart_in_level(m, d, l) || st_is_void(m, d)) continue;
        n++;
        uint32_t x = d, k = 0;
        do {
            seen[x] = 1;
            x = st_beta1(m, st_beta0(m, x, l), l);
        } while (x != d && ++k < m->darts.end);
    }
    free(seen);
    return n;
}

/* Adaptive part (see the header) on `path` with Catmull-Clark to `depth`. */
static void bench_adaptive(st_renderer *r, st_headless *hl, const char *path, unsigned base_level, unsigned depth,
                           int reps)
{
    st_error err;
    st_hier h;
    st_adapt a;
    st_mesh base;
    st_mesh_init(&base);
    if (st_mesh_load(path, &base, &err) || st_hier_init(&h, &base, &st_scheme_catmark, NULL, &err) ||
        st_adapt_init(&a, &h, &err)) {
        fprintf(stderr, "bench_render: adaptive: %s\n", err.msg);
        return;
    }
    st_mesh_free(&base);
    st_adapt_params p = { .base_level = base_level, .max_level = depth };
    box_at(&h.map, 0, &p);
    st_map_log log = { 0 };
    double *tp = malloc((size_t)reps * sizeof *tp), *tf = malloc((size_t)reps * sizeof *tf);
    double *share = malloc((size_t)reps * sizeof *share); /* per move: faces re-made / shown */
    if (st_adapt_update(&a, &p, &err) || st_renderer_set_level(r, &h.map, h.map.top, &err)) {
        fprintf(stderr, "bench_render: adaptive: %s\n", err.msg);
        return;
    }
    int rebuilt = 0;
    uint32_t touched = 0, remade = 0;
    st_upload_stats last = { 0 };
    for (int k = 0; k < reps; k++) {
        box_at(&h.map, (k % 2) ? 0.0 : 0.05, &p);
        st_map_log_clear(&log);
        h.map.log = &log;
        unsigned top = h.map.top;
        if (st_adapt_update(&a, &p, &err)) { fprintf(stderr, "bench_render: adaptive: %s\n", err.msg); return; }
        h.map.log = NULL;
        remade = faces_remade(&h.map, h.map.top, &log);
        double t0 = bench_now();
        if (h.map.top != top || st_renderer_patch(r, &h.map, &log)) {
            rebuilt++;
            st_renderer_set_level(r, &h.map, h.map.top, &err);
        }
        hl->gl.Finish();
        tp[k] = bench_now() - t0;
        touched = (uint32_t)a.touched;
        last = r->last;
        {
            uint32_t shown_k = r->surf.nfaces - r->surf.ndead;
            share[k] = (double)remade / (shown_k ? shown_k : 1);
        }
    }
    for (int k = 0; k < reps; k++) {
        double t0 = bench_now();
        st_renderer_set_level(r, &h.map, h.map.top, &err);
        hl->gl.Finish();
        tf[k] = bench_now() - t0;
    }
    double mp = bench_median(tp, reps), mf = bench_median(tf, reps);
    printf("adaptive: %s, catmull-clark, base level %u, depth %u in a box of a tenth of the extent, %u faces shown; box "
           "moved by 5%% of its size (%u faces subdivided or simplified)\n", path, p.base_level, p.max_level,
           r->surf.nfaces - r->surf.ndead, touched);
    printf("full rebuild of the buffers:  %8.3f ms\n", 1e3 * mf);
    printf("touched faces re-tessellated: %8.3f ms  (%u glBufferSubData ranges, %.1f KB; %d of %d moves rebuilt "
           "instead: a large change, or compaction)\n", 1e3 * mp, last.ranges, last.bytes / 1024.0, rebuilt, reps);
    printf("ratio patch / full:           %8.4f\n", mp / mf);
    uint32_t shown = r->surf.nfaces - r->surf.ndead;
    printf("faces the move re-made:       %u of %u shown (%.1f%%): a patch re-tessellates at least these, so at the\n"
           "                              cost per face of a rebuild it cannot go below %.3f of one\n",
           remade, shown, 100.0 * remade / (shown ? shown : 1), (double)remade / (shown ? shown : 1));
    /* The moves alternate there and back: one kind refines the slice the
     * box enters, the other coarsens it, and they re-make different counts
     * of faces; the median ratio above is one kind's. */
    double lo = 1, hi = 0;
    for (int k = 0; k < reps; k++) { if (share[k] < lo) lo = share[k]; if (share[k] > hi) hi = share[k]; }
    printf("                              over the %d moves: %.3f to %.3f of the faces shown, median %.3f\n", reps, lo,
           hi, bench_median(share, reps));
    free(tp);
    free(tf);
    free(share);
    st_map_log_free(&log);
    st_adapt_free(&a);
    st_hier_free(&h);
}

int main(int argc, char **argv)
{
    const char *path = STRATA_ASSETS "/torus.obj", *scheme = "catmull-clark";
    unsigned levels = 6, edit_level = 2;
    int reps = 15;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--edit-level") && i + 1 < argc) edit_level = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--scheme") && i + 1 < argc) scheme = argv[++i];
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]);
        else if (argv[i][0] != '-') path = argv[i];
        else { fprintf(stderr, "usage: bench_render [MESH] [--levels N] [--edit-level L] [--scheme S] [--reps R]\n"); return 2; }
    }
    if (reps < 1) reps = 1;
    if (reps > 200) reps = 200;
    if (edit_level > levels) edit_level = levels;
    st_error err;
    st_mesh mesh;
    st_mesh_init(&mesh);
    if (st_mesh_load(path, &mesh, &err)) { fprintf(stderr, "bench_render: %s\n", err.msg); return 1; }
    const st_scheme *sc = st_scheme_find(scheme);
    if (!sc) { fprintf(stderr, "bench_render: unknown scheme %s\n", scheme); return 1; }
    st_hier h;
    double t0 = bench_now();
    if (st_hier_init(&h, &mesh, sc, NULL, &err) || st_hier_subdivide_to(&h, levels, &err)) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        return 1;
    }
    st_mesh_free(&mesh);
    double t_build = bench_now() - t0;

    st_headless hl;
    if (st_headless_init(&hl, 64, 64, 0, &err)) { fprintf(stderr, "bench_render: %s\n", err.msg); return 1; }
    st_renderer r;
    if (st_renderer_init(&r, &hl.gl, &err)) { fprintf(stderr, "bench_render: %s\n", err.msg); return 1; }
    st_headless_begin(&hl);
    unsigned D = levels;

    /* Full rebuilds. */
    double *full = malloc((size_t)reps * sizeof *full), *inc = malloc((size_t)reps * sizeof *inc);
    double *mv = malloc((size_t)reps * sizeof *mv);
    uint64_t full_bytes = 0;
    for (int k = 0; k < reps; k++) {
        t0 = bench_now();
        if (st_renderer_set_level(&r, &h.map, D, &err)) { fprintf(stderr, "bench_render: %s\n", err.msg); return 1; }
        hl.gl.Finish();
        full[k] = bench_now() - t0;
        full_bytes = r.last.bytes;
    }

    /* One vertex of the edit level: the first dart of that level. */
    st_dart_iter it;
    uint32_t dart = st_dart_first(&h.map, edit_level, &it);
    const double *p0 = st_dart_pos(&h.map, dart, edit_level);
    double base[3] = { p0[0], p0[1], p0[2] };
    uint64_t moved = 0;
    st_upload_stats last = { 0 };
    st_footprint fp = { 0 };
    for (int k = 0; k < reps; k++) {
        double pos[1][3] = { { base[0] + 0.01 * (k + 1), base[1] - 0.005 * (k + 1), base[2] + 0.008 * (k + 1) } };
        t0 = bench_now();
        fp.n = 0;
        moved = st_hier_edit(&h, edit_level, &dart, (const double (*)[3])pos, 1, &fp);
        mv[k] = bench_now() - t0;
        t0 = bench_now();
        if (st_renderer_refresh(&r, ST_TARGET_MESHES, &h.map, &fp)) { fprintf(stderr, "bench_render: out of memory\n"); return 1; }
        hl.gl.Finish();
        inc[k] = bench_now() - t0;
        last = r.last;
    }
    double tf = bench_median(full, reps), ti = bench_median(inc, reps), tm = bench_median(mv, reps);
    printf("mesh %s, %s, depth %u (hierarchy built in %.3f s)\n", path, sc->name, levels, t_build);
    printf("level %u shown: %u vertices, %u faces, %u triangles, %u polygon edges\n",
           D, r.surf.nverts, r.surf.nfaces, r.surf.ntris, r.surf.nlines);
    printf("edit: one vertex of level %u moved; st_hier_edit recomputed %llu positions in %.3f ms (median of %d)\n",
           edit_level, (unsigned long long)moved, 1e3 * tm, reps);
    printf("full rebuild of the buffers:  %8.3f ms  (%.1f MB uploaded)\n", 1e3 * tf, full_bytes / 1048576.0);
    printf("incremental buffer update:    %8.3f ms  (%u vertices = %.2f%% of the level, %u glBufferSubData ranges, %.1f KB)\n",
           1e3 * ti, last.vertices, 100.0 * last.vertices / (r.surf.nverts ? r.surf.nverts : 1), last.ranges, last.bytes / 1024.0);
    printf("ratio incremental / full:     %8.4f  (target <= 0.05: %s)\n", ti / tf, ti / tf <= 0.05 ? "met" : "NOT met");
    bench_adaptive(&r, &hl, STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", 0, 5, reps);
    bench_adaptive(&r, &hl, STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", 3, 5, reps);
    st_renderer_free(&r);
    st_headless_free(&hl);
    st_hier_free(&h);
    st_footprint_free(&fp);
    free(full);
    free(inc);
    free(mv);
    return 0;
}
