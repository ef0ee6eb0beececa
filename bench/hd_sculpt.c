/* bench_hd: HD levels (ui/doc/editor_hd.c) on spot's cage, headless
 * through the document, as the HD sculpting issue measures them:
 *
 *   bench_hd [--level L] [--share S] [--regions K] [--out DIR] [--profile-moves N]
 *            [--profile-step S] [--heap-mapped]
 *
 * spot_quadrangulated.obj rebuilt to its 180-face cage (Mesh > Rebuild
 * levels: unsubdivide), one uniform level added (levels 0..3), then K
 * regions (default 3), each holding a share S (default 0.01) of the
 * level-3 vertices, sculpted at HD level L (default 10) with the interest
 * box over each in turn (draw strokes).  Prints:
 *   - memory: the process's resident size after each region and at the
 *     end, against core's estimate of a uniform hierarchy to level L;
 *   - dab time at level L against a dab at level 3 with about the same
 *     number of vertices under the brush (7 alternating rounds of a 9-dab
 *     stroke at each, the median of the strokes' medians);
 *   - a small box move over a sculpted region (5 % of the box's width,
 *     there and back) against building the adaptive display anew for the
 *     same box (medians of 5), and moves of 2.5 % and 10 % against it;
 *   - the session: bytes and save time after 1 region and after K, per
 *     face stored;
 *   - exactness: the display after every stroke equals a full adaptive
 *     re-synthesis bit for bit.
 * --profile-moves N: after the regions, N box moves alone (for profilers),
 * and their median time; --profile-step S: each a move by S times the
 * box's half-size (default 0.1: 5 % of its width).
 * --heap-mapped: every block of 4 MiB or more in a mapping of its own
 * (glibc's mmap threshold fixed, where by default it rises to 32 MiB once
 * a large block is freed), for the comparison in bench/RESULTS.md: the
 * window keeps glibc's default.
 * Figures, not pass/fail: bench/RESULTS.md keeps them. */
#include "editor.h"
#include "bench_common.h"
#include "core/adapt/adapt.h"
#include "core/multires/estimate.h"

#include <math.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef STRATA_SHARED_DATA
#define STRATA_SHARED_DATA "../shared/data/meshes"
#endif

int ed_hier_clone(st_hier *dst, const st_hier *src, size_t *bytes); /* ui/doc/editor_clone.c */

/* Resident size, after handing freed heap pages back (glibc keeps the
 * pages of freed blocks mapped: the box-move figure's fresh displays and
 * the exactness check's clone would otherwise count as the model's). */
static double rss_mib(void)
{
#ifdef __GLIBC__
    malloc_trim(0);
#endif
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = 0, res = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &pages, &res) != 2) res = 0;
        fclose(f);
    }
    return (double)res * (double)sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0);
}

static void die(const char *what, const st_error *e)
{
    fprintf(stderr, "bench_hd: %s: %s\n", what, e ? e->msg : "failed");
    exit(1);
}

/* Level-l vertices of h within distance r of c. */
static uint32_t count_within(st_map *m, unsigned l, const double c[3], double r)
{
    uint32_t n = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
        const double *p = st_pos(m, v, l);
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += (p[k] - c[k]) * (p[k] - c[k]);
        if (d2 < r * r) n++;
    }
    return n;
}

/* The radius around c holding about `want` level-l vertices of m. */
static double radius_for(st_map *m, unsigned l, const double c[3], uint32_t want, double hi)
{
    double lo = 0;
    for (int it = 0; it < 40; it++) {
        double mid = 0.5 * (lo + hi);
        if (count_within(m, l, c, mid) < want) lo = mid;
        else hi = mid;
    }
    return hi;
}

static void box_at(st_doc *d, const double c[3], double half, unsigned max_level, int on)
{
    st_adapt_params p = d->box;
    for (int k = 0; k < 3; k++) { p.box_lo[k] = c[k] - half; p.box_hi[k] = c[k] + half; }
    p.has_box = 1;
    p.max_level = max_level;
    p.falloff = 0;
    st_error err;
    if (st_doc_set_box(d, &p, on, &err)) die("interest box", &err);
}

/* Median time (s) of 9 dabs at the sculpt level around c (normal nrm). */
static double dab_median(st_doc *d, const double c[3], const double nrm[3], double radius)
{
    double t[9];
    st_brush_set_tool(&d->brush, ST_BRUSH_DRAW);
    d->brush.radius = radius;
    d->brush.strength = 0.3;
    if (st_doc_stroke_begin(d)) { fprintf(stderr, "bench_hd: stroke refused: %s\n", d->refusal); exit(1); }
    for (int i = 0; i < 9; i++) {
        double p[3] = { c[0] + 0.02 * radius * i, c[1], c[2] };
        double t0 = bench_now();
        st_doc_stroke_dab(d, p, nrm, NULL);
        t[i] = bench_now() - t0;
    }
    st_doc_stroke_end(d);
    return bench_median(t, 9);
}

/* One box move of --profile-moves, in a function of its own so that
 * callgrind can count it alone (--toggle-collect=profile_move). */
__attribute__((noinline)) static void profile_move(st_doc *d, const double c[3], double half, unsigned max_level)
{
    box_at(d, c, half, max_level, 1);
}

static int display_is_synthesis(st_doc *d)
{
    st_hier c;
    if (ed_hier_clone(&c, &d->display.hier, NULL)) return -1;
    st_adapt a = d->display.adapt;
    a.h = &c;
    st_adapt_synthesize(&a, d->h.map.top);
    int same = 1;
    st_map *m1 = &d->display.hier.map, *m2 = &c.map;
    for (unsigned L = 0; L <= m1->top && same; L++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(m1, L, &it); v != ST_NIL && same; v = st_vertex_next(m1, L, &it))
            same = !memcmp(st_pos(m1, v, L), st_pos(m2, v, L), 3 * sizeof(double));
    }
    st_hier_free(&c);
    return same;
}

static long file_size(const char *p)
{
    struct stat st;
    return stat(p, &st) ? -1 : (long)st.st_size;
}

int main(int argc, char **argv)
{
    unsigned L = 10, K = 3;
    int profile_moves = 0, heap_mapped = 0;
    double profile_step = 0.1;
    double share = 0.01;
    const char *dir = "/tmp";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--level") && i + 1 < argc) L = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--share") && i + 1 < argc) share = atof(argv[++i]);
        else if (!strcmp(argv[i], "--regions") && i + 1 < argc) K = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--out") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "--profile-moves") && i + 1 < argc) profile_moves = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--heap-mapped")) heap_mapped = 1;
        else if (!strcmp(argv[i], "--profile-step") && i + 1 < argc) profile_step = atof(argv[++i]);
        else { fprintf(stderr, "usage: bench_hd [--level L] [--share S] [--regions K] [--out DIR] [--profile-moves N] [--profile-step S] [--heap-mapped]\n"); return 2; }
    }
#if defined(__GLIBC__) && defined(M_MMAP_THRESHOLD)
    if (heap_mapped) (void)mallopt(M_MMAP_THRESHOLD, 4 << 20);
#endif
    if (heap_mapped) printf("heap: blocks of 4 MiB or more mapped on their own (--heap-mapped; the window keeps glibc's default)\n");
    st_doc d;
    st_error err;
    st_doc_init(&d);
    d.mem_budget = (size_t)20 << 30;
    const char *path = STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj";
    if (st_doc_open(&d, path, "catmull-clark", 0, &err)) die(path, &err);
    char msg[256];
    if (st_doc_rebuild_levels(&d, NULL, NULL, msg, sizeof msg, &err)) die("rebuild levels", &err);
    while (d.h.map.top < 3)
        if (st_doc_add_level(&d, &err)) die("add level", &err);
    st_level_stats s0;
    st_level_stats_compute(&d.h.map, 0, &s0);
    st_level_stats fin;
    size_t uniform = st_hier_estimate_subdivide(&d.h, L, &fin);
    printf("spot cage: %llu faces, uniform levels 0..%u; uniform level %u would be %llu faces, %.1f GiB (core's estimate)\n",
           (unsigned long long)s0.faces, d.h.map.top, L, (unsigned long long)fin.faces, uniform / 1073741824.0);
    printf("memory after opening: %.1f MiB resident\n", rss_mib());

    /* Region centres: level-3 vertices far apart (farthest-point picks). */
    st_map *mm = &d.h.map;
    unsigned N = mm->top;
    uint32_t nv3 = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(mm, N, &it); v != ST_NIL; v = st_vertex_next(mm, N, &it)) nv3++;
    double centre[8][3], half[8];
    uint32_t first = st_vertex_first(mm, N, &it);
    memcpy(centre[0], st_pos(mm, first, N), sizeof centre[0]);
    for (unsigned k = 1; k < K && k < 8; k++) {
        double best = -1;
        for (uint32_t v = st_vertex_first(mm, N, &it); v != ST_NIL; v = st_vertex_next(mm, N, &it)) {
            const double *p = st_pos(mm, v, N);
            double dmin = INFINITY;
            for (unsigned j = 0; j < k; j++) {
                double d2 = 0;
                for (int q = 0; q < 3; q++) d2 += (p[q] - centre[j][q]) * (p[q] - centre[j][q]);
                dmin = fmin(dmin, d2);
            }
            if (dmin > best) { best = dmin; memcpy(centre[k], p, sizeof centre[k]); }
        }
    }
    uint32_t want = (uint32_t)ceil(share * nv3);
    const double view[3] = { 0, 0, 0 };
    memcpy(d.brush.view_dir, view, sizeof view);
    d.brush.front_only = 0;
    long ses1 = 0;
    double save1 = 0;
    uint64_t faces1 = 0;
    char ses[4096];
    snprintf(ses, sizeof ses, "%s/bench_hd.strata", dir);
    double dab_hd = 0, move_t = 0, build_t = 0, rd_last = 0;
    uint32_t under_hd = 0;
    for (unsigned k = 0; k < K && k < 8; k++) {
        double r = radius_for(mm, N, centre[k], want, 2.0);
        half[k] = r / sqrt(3.0);
        double t0 = bench_now();
        box_at(&d, centre[k], half[k], L, 1);
        double tb = bench_now() - t0;
        if (!k) st_doc_set_edit_level(&d, L);
        if (st_doc_sculpt_level(&d) != L) { fprintf(stderr, "bench_hd: HD level %u refused: %s\n", L, d.note); return 1; }
        double len = sqrt(centre[k][0] * centre[k][0] + centre[k][1] * centre[k][1] + centre[k][2] * centre[k][2]);
        double nrm[3] = { centre[k][0] / len, centre[k][1] / len, centre[k][2] / len };
        /* the dab: about 2000 vertices of level L under it */
        double rd = radius_for(&d.display.hier.map, L, centre[k], 2000, half[k]);
        dab_median(&d, centre[k], nrm, rd);
        if (k == K - 1 || k == 7) {
            rd_last = rd;
            under_hd = count_within(&d.display.hier.map, L, centre[k], rd);
        }
        uint64_t hf = st_doc_hd_faces(&d);
        printf("region %u: box half-size %.4f around %u level-%u vertices (%.2f %%), refined in %.2f s; "
               "HD faces stored %llu; %.1f MiB resident\n",
               k + 1, half[k], want, N, 100.0 * want / nv3, tb, (unsigned long long)hf, rss_mib());
        if (k == 0) {
            t0 = bench_now();
            if (st_doc_save_session(&d, ses, NULL, NULL, NULL, NULL, &err)) die("save", &err);
            save1 = bench_now() - t0;
            ses1 = file_size(ses);
            faces1 = hf;
        }
    }
    unsigned last = (K < 8 ? K : 8) - 1;
    /* Box move over the last sculpted region: a tenth of its size, there
     * and back, against a display built anew for the same box. */
    if (profile_moves > 0) {
        /* For profilers: the box moves alone, there and back. */
        double *tm = malloc((size_t)profile_moves * sizeof *tm);
        for (int i = 0; i < profile_moves; i++) {
            double c[3] = { centre[last][0] + (i % 2 ? 0 : profile_step * half[last]), centre[last][1], centre[last][2] };
            double t0 = bench_now();
            profile_move(&d, c, half[last], L);
            if (tm) tm[i] = bench_now() - t0;
        }
        if (tm) printf("  %d box moves alone: median %.2f ms\n", profile_moves, 1e3 * bench_median(tm, profile_moves));
        free(tm);
        return 0;
    }
    double tmv[5], tbd[5];
    for (int i = 0; i < 5; i++) {
        double c[3] = { centre[last][0] + (i % 2 ? 0 : 0.1 * half[last]), centre[last][1], centre[last][2] };
        double t0 = bench_now();
        box_at(&d, c, half[last], L, 1);
        tmv[i] = bench_now() - t0;
        st_box_display fresh;
        memset(&fresh, 0, sizeof fresh);
        t0 = bench_now();
        if (st_box_display_build(&fresh, &d.h, &d.box, &err)) die("display build", &err);
        tbd[i] = bench_now() - t0;
        st_box_display_free(&fresh);
    }
    move_t = bench_median(tmv, 5);
    build_t = bench_median(tbd, 5);
    /* The same move by half and by twice the step: a move refines the
     * slice the box enters and coarsens the one it leaves, so its cost
     * follows the distance (the step above, 0.1 of the half-size, is 5 %
     * of the box's width). */
    static const double steps[2] = { 0.05, 0.2 };
    double step_t[2];
    for (int j = 0; j < 2; j++) {
        double t[5];
        for (int i = 0; i < 5; i++) {
            double c[3] = { centre[last][0] + (i % 2 ? 0 : steps[j] * half[last]), centre[last][1], centre[last][2] };
            double t0 = bench_now();
            box_at(&d, c, half[last], L, 1);
            t[i] = bench_now() - t0;
        }
        step_t[j] = bench_median(t, 5);
    }
    {   /* back where the figures below were measured */
        double c[3] = { centre[last][0] + 0.1 * half[last], centre[last][1], centre[last][2] };
        box_at(&d, c, half[last], L, 1);
    }

    /* A dab at level 3 with about as many vertices under it, away from the
     * HD regions (the farthest level-3 vertex from them). */
    double far[3] = { 0, 0, 0 }, best = -1;
    for (uint32_t v = st_vertex_first(mm, N, &it); v != ST_NIL; v = st_vertex_next(mm, N, &it)) {
        const double *p = st_pos(mm, v, N);
        double dmin = INFINITY;
        for (unsigned j = 0; j <= last; j++) {
            double d2 = 0;
            for (int q = 0; q < 3; q++) d2 += (p[q] - centre[j][q]) * (p[q] - centre[j][q]);
            dmin = fmin(dmin, d2);
        }
        if (dmin > best) { best = dmin; memcpy(far, p, sizeof far); }
    }
    double r3 = radius_for(mm, N, far, under_hd, 2.0);
    uint32_t under3 = count_within(mm, N, far, r3);
    double len = sqrt(far[0] * far[0] + far[1] * far[1] + far[2] * far[2]);
    double nrm3[3] = { far[0] / len, far[1] / len, far[2] / len };
    const double *cl = centre[last];
    double ll = sqrt(cl[0] * cl[0] + cl[1] * cl[1] + cl[2] * cl[2]);
    double nrml[3] = { cl[0] / ll, cl[1] / ll, cl[2] / ll };
    /* Alternating rounds, the median of each side's medians. */
    double tl[7], t3[7];
    for (int i = 0; i < 7; i++) {
        st_doc_set_edit_level(&d, L);
        tl[i] = dab_median(&d, cl, nrml, rd_last);
        st_doc_set_edit_level(&d, N);
        t3[i] = dab_median(&d, far, nrm3, r3);
    }
    dab_hd = bench_median(tl, 7);
    double dab3 = bench_median(t3, 7);

    /* Exactness of an HD edit: one more stroke in the last region, from a
     * full synthesis (the window's box updates place new vertices with the
     * stencil of the face that made them, last bits apart: editor_hd.c). */
    st_adapt_synthesize(&d.display.adapt, N);
    st_doc_set_edit_level(&d, L);
    {
        const double *c = centre[last];
        double l2 = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        double nrm[3] = { c[0] / l2, c[1] / l2, c[2] / l2 };
        dab_median(&d, c, nrm, 0.3 * half[last]);
    }
    /* The model's memory, before the exactness check's clone (which
     * touches the whole capacity of the display's arrays and leaves part
     * of it resident after it is freed). */
    double rss = rss_mib();
    int exact = display_is_synthesis(&d);

    double t0 = bench_now();
    if (st_doc_save_session(&d, ses, NULL, NULL, NULL, NULL, &err)) die("save", &err);
    double saveK = bench_now() - t0;
    long sesK = file_size(ses);
    uint64_t facesK = st_doc_hd_faces(&d);
    uint64_t faces = 0, verts = 0;
    st_doc_display_counts(&d, &faces, &verts);

    printf("\nHD level %u, %u regions of %.2f %% of the surface each:\n", L, last + 1, 100.0 * want / nv3);
    printf("  memory: %.1f MiB resident for the whole model (displayed %llu faces, %llu stored at HD levels); "
           "uniform level %u: %.1f GiB estimated; ratio %.4f\n",
           rss, (unsigned long long)faces, (unsigned long long)facesK, L, uniform / 1073741824.0,
           rss * 1048576.0 / (double)uniform);
    printf("  dab: level %u %.3f ms (%u vertices within the radius), level %u %.3f ms (%u vertices): ratio %.2f\n", L,
           1e3 * dab_hd, under_hd, N, 1e3 * dab3, under3, dab_hd / dab3);
    printf("  box move over a sculpted region: %.2f ms, display built anew: %.2f ms: ratio %.4f\n", 1e3 * move_t,
           1e3 * build_t, move_t / build_t);
    printf("  box move by 2.5 %% / 5 %% / 10 %% of the box's width: %.2f / %.2f / %.2f ms: ratios %.4f / %.4f / %.4f\n",
           1e3 * step_t[0], 1e3 * move_t, 1e3 * step_t[1], step_t[0] / build_t, move_t / build_t, step_t[1] / build_t);
    printf("  session: 1 region %ld bytes, %.3f s (%llu HD faces, %.1f bytes/face); %u regions %ld bytes, %.3f s "
           "(%llu HD faces, %.1f bytes/face)\n",
           ses1, save1, (unsigned long long)faces1, faces1 ? (double)ses1 / faces1 : 0, last + 1, sesK, saveK,
           (unsigned long long)facesK, facesK ? (double)sesK / facesK : 0);
    printf("  exactness: the display %s a full adaptive re-synthesis bit for bit\n",
           exact == 1 ? "equals" : exact == 0 ? "DIFFERS FROM" : "(out of memory to compare with)");
    unlink(ses);
    st_doc_free(&d);
    return exact == 0;
}
