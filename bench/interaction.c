/* strata --bench-interaction FILE: the cost of one drag step against a full
 * rebuild, on a depth-6 hierarchy (docs/MODELLER.md).
 *
 * Here with the other benchmarks, but not a program of its own as
 * bench/bench_*.c are: it drives the window's document, renderer and GL
 * context, so cmake/ui.cmake compiles it into strata_ui and `strata`
 * keeps the option (app/cmd_window.c: st_window_bench, window.h).  The
 * document's half, st_doc_bench_drag, stays in ui/doc/editor_bench.c,
 * where the headless tests run it (tests/ui/test_editor.c).
 *
 * One vertex of level 2 is selected and dragged in --bench-steps steps
 * through the same calls the window makes (st_doc_drag_update, then
 * st_renderer_refresh with the footprint core reported); each step is timed as geometry
 * (local re-synthesis of levels 3..6) plus buffers (the touched positions
 * and normals recomputed and re-uploaded with glBufferSubData), with
 * glFinish so that the upload is counted.  The reference is a full
 * synthesis from level 0 (st_hier_synthesize) plus a full rebuild and upload
 * of the displayed and editing levels' buffers (st_renderer_set_level +
 * set_cage).  The context is a hidden GLFW window when a display is there,
 * else OSMesa (same Mesa llvmpipe driver either way here). */
#include "window.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "render/headless.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/* Process CPU time: less disturbed than the wall clock on a shared,
 * loaded machine (the synthesis threads count too). */
static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/* One timed step of two phases (the second ends with a gl.Finish): wall
 * clock at the start (a0) and between the phases (a1), CPU time at the
 * start (c0). */
typedef struct lap { double c0, a0, a1; } lap;

static lap lap_start(void)
{
    lap l;
    l.c0 = cpu_ms();
    l.a0 = now_ms();
    l.a1 = l.a0;
    return l;
}

/* Step i done: first phase, second phase, both, CPU time (ms). */
static void lap_end(const lap *l, int i, double *first, double *second, double *total, double *cpu)
{
    double a2 = now_ms();
    first[i] = l->a1 - l->a0;
    second[i] = a2 - l->a1;
    total[i] = a2 - l->a0;
    cpu[i] = cpu_ms() - l->c0;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_d);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* A point of a stroke on the displayed surface: a drawn vertex (index i of
 * the renderer's geometry), its position c and unit normal n, and the
 * direction t the stroke goes in (tangent to the surface). */
typedef struct dab_point { uint32_t i; double c[3], n[3], t[3]; } dab_point;

static void dab_point_at(const st_rgeom *g, uint32_t i, dab_point *p)
{
    const float *q = g->vdata + (size_t)i * ST_RGEOM_VSTRIDE;
    double len = 0;
    p->i = i;
    for (int k = 0; k < 3; k++) {
        p->c[k] = q[k];
        p->n[k] = q[3 + k];
        len += p->n[k] * p->n[k];
    }
    len = sqrt(len);
    for (int k = 0; k < 3; k++) p->n[k] = len > 0 ? p->n[k] / len : k == 2;
}

/* The tangent t made orthogonal to n again, unit length (any tangent when
 * it vanishes). */
static void dab_tangent(dab_point *p)
{
    double d = p->t[0] * p->n[0] + p->t[1] * p->n[1] + p->t[2] * p->n[2], len = 0;
    for (int k = 0; k < 3; k++) { p->t[k] -= d * p->n[k]; len += p->t[k] * p->t[k]; }
    if (!(len > 1e-24)) {
        /* n x (the axis least aligned with n) */
        int a = fabs(p->n[0]) < fabs(p->n[1]) ? (fabs(p->n[0]) < fabs(p->n[2]) ? 0 : 2) : (fabs(p->n[1]) < fabs(p->n[2]) ? 1 : 2);
        double e[3] = { a == 0, a == 1, a == 2 };
        p->t[0] = p->n[1] * e[2] - p->n[2] * e[1];
        p->t[1] = p->n[2] * e[0] - p->n[0] * e[2];
        p->t[2] = p->n[0] * e[1] - p->n[1] * e[0];
        len = p->t[0] * p->t[0] + p->t[1] * p->t[1] + p->t[2] * p->t[2];
    }
    len = sqrt(len);
    for (int k = 0; k < 3; k++) p->t[k] /= len;
}

static void dab_path_start(const st_rgeom *g, dab_point *p)
{
    dab_point_at(g, p->i, p);
    p->t[0] = 1; p->t[1] = 0; p->t[2] = 0;
    dab_tangent(p);
}

/* The next dab: `step` along the tangent, then onto the nearest drawn
 * vertex facing the same side (a linear search, outside the timing), so
 * that the stroke stays on the surface as a picked one does. */
static void dab_path_next(const st_rgeom *g, dab_point *p, double step)
{
    double q[3], best = INFINITY;
    uint32_t bi = p->i;
    for (int k = 0; k < 3; k++) q[k] = p->c[k] + step * p->t[k];
    for (uint32_t i = 0; i < g->nverts; i++) {
        const float *v = g->vdata + (size_t)i * ST_RGEOM_VSTRIDE;
        if (v[3] * p->n[0] + v[4] * p->n[1] + v[5] * p->n[2] <= 0) continue;
        double dx = v[0] - q[0], dy = v[1] - q[1], dz = v[2] - q[2], e = dx * dx + dy * dy + dz * dz;
        if (e < best && i != p->i) { best = e; bi = i; }
    }
    double dir[3];
    for (int k = 0; k < 3; k++) dir[k] = p->t[k];
    dab_point_at(g, bi, p);
    for (int k = 0; k < 3; k++) p->t[k] = dir[k];
    dab_tangent(p);
}

int st_window_bench(const st_win_opts *o)
{
    if (!o->file) { fprintf(stderr, "strata: --bench-interaction needs a FILE\n"); return 2; }
    unsigned levels = o->levels >= 0 ? (unsigned)o->levels : 6;
    unsigned edit = levels >= 2 ? 2 : levels;
    const char *scheme = o->scheme ? o->scheme : "catmull-clark";
    st_doc doc;
    st_doc_init(&doc);
    st_error err;
    double t0 = now_ms();
    if (st_doc_open(&doc, o->file, scheme, levels, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->file, err.msg);
        st_doc_free(&doc);
        return 1;
    }
    double t_open = now_ms() - t0;

    /* A GL context: a hidden window, or OSMesa without a display. */
    GLFWwindow *win = NULL;
    st_headless hl;
    memset(&hl, 0, sizeof hl);
    st_gl gl;
    const char *ctx = NULL;
    if (glfwInit()) {
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        win = glfwCreateWindow(256, 256, "strata bench", NULL, NULL);
        if (win) {
            glfwMakeContextCurrent(win);
            if (st_gl_load(&gl, glfwGetProcAddress, &err)) { glfwDestroyWindow(win); win = NULL; }
            else ctx = "GLFW window";
        }
        if (!win) glfwTerminate();
    }
    if (!win) {
        if (st_headless_init(&hl, 256, 256, 1, &err)) {
            fprintf(stderr, "strata: no OpenGL context for the benchmark: %s\n", err.msg);
            st_doc_free(&doc);
            return 1;
        }
        gl = hl.gl;
        ctx = "OSMesa (no display)";
    }
    const char *renderer = (const char *)gl.GetString(GL_RENDERER);

    st_renderer r;
    int rc = st_renderer_init(&r, &gl, &err);
    unsigned top = doc.h.map.top;
    st_doc_set_edit_level(&doc, edit);
    st_doc_set_display_level(&doc, top);
    /* The first build and upload of the buffers, what the window does
     * before its first frame (fresh GL buffers; the timed rebuilds below
     * refill them). */
    double first_build = -1, first_build_cpu = -1;
    if (!rc) {
        double w0 = now_ms(), c0 = cpu_ms();
        rc = st_renderer_set_level(&r, &doc.h.map, top, &err);
        if (!rc) rc = st_renderer_set_cage(&r, &doc.h.map, edit, &err);
        gl.Finish();
        first_build = now_ms() - w0;
        first_build_cpu = cpu_ms() - c0;
    }
    if (rc || !r.cage.nverts) {
        fprintf(stderr, "strata: bench: %s\n", rc ? err.msg : "empty editing level");
        rc = 1;
        goto done;
    }
    (void)st_doc_take_change(&doc);

    uint32_t v = r.cage.vid[r.cage.nverts / 2];
    st_doc_select(&doc, &v, 1, ST_SELECT_REPLACE);
    (void)st_doc_take_change(&doc);
    double diag = 0;
    for (int k = 0; k < 3; k++) diag += (double)(r.surf.bbox[k + 3] - r.surf.bbox[k]) * (r.surf.bbox[k + 3] - r.surf.bbox[k]);
    diag = sqrt(diag);
    int n = o->bench_steps;
    double *tg = malloc((size_t)n * sizeof *tg), *tb = malloc((size_t)n * sizeof *tb), *tt = malloc((size_t)n * sizeof *tt);
    double *tc = malloc((size_t)n * sizeof *tc);
    if (!tg || !tb || !tt || !tc || st_doc_drag_begin(&doc)) {
        fprintf(stderr, "strata: bench: cannot start the drag\n");
        free(tg); free(tb); free(tt); free(tc);
        rc = 1;
        goto done;
    }
    uint64_t moved_top = 0;
    uint32_t nmoved = 0;
    for (int i = 0; i < n; i++) {
        double delta[3] = { 0.002 * diag * (i + 1), 0.001 * diag * (i + 1), -0.0015 * diag * (i + 1) };
        lap t = lap_start();
        st_doc_drag_update(&doc, delta);
        t.a1 = now_ms();
        st_doc_change ch = st_doc_take_change(&doc);
        st_renderer_refresh(&r, ST_TARGET_MESHES, &doc.h.map, ch.footprint);
        gl.Finish();
        lap_end(&t, i, tg, tb, tt, tc);
        moved_top = r.last.vertices;
        nmoved = ch.nmoved;
    }
    st_doc_drag_end(&doc);
    (void)st_doc_take_change(&doc);
    double mg = median(tg, n), mb = median(tb, n), mt = median(tt, n), mc = median(tc, n);
    free(tg); free(tb); free(tt); free(tc);

    /* Five full rebuilds, three above 8 M faces (each takes tens of
     * seconds there). */
    enum { MAX_REPS = 5 };
    const int REPS = r.surf.nfaces > 8000000u ? 3 : MAX_REPS;
    double fs[MAX_REPS], fb[MAX_REPS], ft[MAX_REPS], fc[MAX_REPS];
    for (int i = 0; i < REPS; i++) {
        lap t = lap_start();
        st_hier_synthesize(&doc.h, 0);
        t.a1 = now_ms();
        st_renderer_set_level(&r, &doc.h.map, top, &err);
        st_renderer_set_cage(&r, &doc.h.map, edit, &err);
        gl.Finish();
        lap_end(&t, i, fs, fb, ft, fc);
    }
    double ms = median(fs, REPS), mbuf = median(fb, REPS), mfull = median(ft, REPS), mfc = median(fc, REPS);
    uint64_t faces = 0, verts = 0;
    st_doc_display_counts(&doc, &faces, &verts);

    /* Sculpting on the top level with a mask and three layers on: a draw
     * dab of radius 5 % of the model (bounding-box diagonal) through the
     * window's path (stroke dab, then st_renderer_refresh of the footprint),
     * timed like a drag step.  The mask is the cavity mask of the level, the
     * strokes go into the third of three layers of the top level.  The dabs
     * follow the surface as the window's picked stroke does (dab_path_next),
     * spaced as the brush spaces them, so each one has the full radius of
     * surface under it. */
    double dab_ms = -1, dab_geo = -1, dab_buf = -1, dab_cpu = -1;
    double dab_verts = 0;
    uint32_t dab_vmin = UINT32_MAX, dab_vmax = 0;
    {
        st_doc_set_edit_level(&doc, top);
        st_doc_mask_cavity(&doc);
        for (int k = 0; k < 3; k++) st_doc_layer_add(&doc, NULL, &err);
        (void)st_doc_take_change(&doc);
        doc.brush.tool = ST_BRUSH_DRAW;
        doc.brush.radius = 0.05 * diag;
        doc.brush.strength = 0.5;
        doc.brush.mirror_x = 0;
        double *dg = malloc((size_t)n * sizeof *dg), *db = malloc((size_t)n * sizeof *db), *dt = malloc((size_t)n * sizeof *dt);
        double *dc = malloc((size_t)n * sizeof *dc), *dv = malloc((size_t)n * sizeof *dv);
        dab_point pt = { r.surf.nverts / 3, { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } };
        dab_path_start(&r.surf, &pt);
        if (dg && db && dt && dc && dv && doc.layers.n == 3 && !st_doc_stroke_begin(&doc)) {
            for (int i = 0; i < n; i++) {
                if (i) dab_path_next(&r.surf, &pt, doc.brush.spacing * doc.brush.radius);
                /* The view looks at the dab (front faces only is on), as
                 * a view turned along the stroke would. */
                for (int k = 0; k < 3; k++) doc.brush.view_dir[k] = -pt.n[k];
                lap t = lap_start();
                st_doc_stroke_dab(&doc, pt.c, pt.n, NULL);
                t.a1 = now_ms();
                st_doc_change ch = st_doc_take_change(&doc);
                st_renderer_refresh(&r, ST_TARGET_SURFACE, &doc.h.map, ch.footprint);
                gl.Finish();
                lap_end(&t, i, dg, db, dt, dc);
                dv[i] = ch.nmoved;
                if (ch.nmoved < dab_vmin) dab_vmin = ch.nmoved;
                if (ch.nmoved > dab_vmax) dab_vmax = ch.nmoved;
            }
            st_doc_stroke_end(&doc);
            dab_geo = median(dg, n);
            dab_buf = median(db, n);
            dab_ms = median(dt, n);
            dab_cpu = median(dc, n);
            dab_verts = median(dv, n);
        }
        free(dg); free(db); free(dt); free(dc); free(dv);
        st_doc_set_edit_level(&doc, edit);
    }

    /* Picking as the window does it: the ID buffer is redrawn after a view
     * or geometry change, then each mouse move reads back 21x21 pixels. */
    enum { PW = 1024, PH = 768, NHOVER = 400 };
    st_camctl cc;
    st_camctl_init(&cc, r.surf.bbox, (float)PW / PH);
    st_pick pk;
    double pick_draw = -1, hover_med = -1, rect_ms = -1;
    int hits = 0;
    int64_t nrect = 0;
    if (!st_pick_init(&pk, &gl, &err)) {
        /* The first draw compiles the program (llvmpipe JIT): time the second. */
        st_pick_render(&pk, &r, &cc, PW, PH, &err);
        gl.Finish();
        st_camctl_orbit(&cc, 20, 5);
        st_pick_invalidate(&pk);
        double a0 = now_ms();
        st_pick_render(&pk, &r, &cc, PW, PH, &err);
        gl.Finish();
        pick_draw = now_ms() - a0;
        double th[NHOVER];
        for (int i = 0; i < NHOVER; i++) {
            int x = (int)((i % 20 + 0.5) * PW / 20), y = (int)((i / 20 + 0.5) * PH / 20);
            double b0 = now_ms();
            uint32_t slot = st_pick_at(&pk, x, y);
            th[i] = now_ms() - b0;
            hits += slot != ST_NIL;
        }
        hover_med = median(th, NHOVER);
        uint32_t *ids = NULL;
        double c0 = now_ms();
        nrect = st_pick_rect(&pk, 0, 0, PW - 1, PH - 1, &ids);
        rect_ms = now_ms() - c0;
        free(ids);
        st_pick_free(&pk);
    }

    printf("bench-interaction: %s, %s, levels 0..%u (opened in %.0f ms)\n", o->file, doc.scheme->name, top, t_open);
    printf("  context: %s, %s\n", ctx, renderer ? renderer : "?");
    printf("  displayed level %u: %llu faces, %llu vertices; editing level %u: %u vertices\n", top,
           (unsigned long long)faces, (unsigned long long)verts, edit, r.cage.nverts);
    printf("  drag of 1 level-%u vertex, %d steps (median): geometry %.3f ms + buffers %.3f ms = %.3f ms per step\n",
           edit, n, mg, mb, mt);
    printf("    (%u moved darts reported, %llu vertices re-uploaded per step)\n", nmoved, (unsigned long long)moved_top);
    printf("  first build and upload of the buffers (before the window's first frame): %.1f ms, in process CPU time %.1f ms\n",
           first_build, first_build_cpu);
    printf("  full synthesis %.1f ms + full buffer rebuild %.1f ms = %.1f ms (median of %d)\n", ms, mbuf, mfull, REPS);
    if (dab_ms >= 0)
        printf("  draw dab on level %u, radius 5%% of the model, cavity mask and 3 layers on, %d dabs (median): geometry %.3f ms\n"
               "    + buffers %.3f ms = %.3f ms (vertices moved per dab: median %.0f, %u..%u); ratio to full = %.4f (target <= 0.02): %s\n",
               top, n, dab_geo, dab_buf, dab_ms, dab_verts, dab_vmin, dab_vmax, dab_ms / mfull, dab_ms / mfull <= 0.02 ? "ok" : "ABOVE TARGET");
    if (dab_cpu >= 0)
        printf("    in process CPU time: dab %.3f ms / full %.1f ms = %.4f\n", dab_cpu, mfc, dab_cpu / mfc);
    printf("  picking (ID buffer %dx%d, level-%u vertices over the level-%u surface): redraw after a view change %.1f ms,\n"
           "    hover lookup %.3f ms (median of %d, %d over a vertex), full-window rectangle %.1f ms (%lld visible vertices)\n",
           PW, PH, edit, top, pick_draw, hover_med, NHOVER, hits, rect_ms, (long long)nrect);
    double ed_step = -1, ed_full = -1;
    if (!st_doc_bench_drag(&doc, edit, (unsigned)n, &ed_step, &ed_full))
        printf("  editor's geometry-only bench (st_doc_bench_drag): %.3f ms per step, full synthesis %.1f ms\n", ed_step, ed_full);
    FILE *la = fopen("/proc/loadavg", "r");
    char load[64] = "?";
    if (la) { if (!fgets(load, sizeof load, la)) load[0] = 0; fclose(la); load[strcspn(load, "\n")] = 0; }
    printf("  (machine load average: %s; the figures are wall-clock medians)\n", load);
    printf("  ratio drag step / full = %.4f wall clock (target <= 0.015): %s\n", mt / mfull, mt / mfull <= 0.015 ? "ok" : "ABOVE TARGET");
    printf("  ratio in process CPU time = %.4f (step %.3f ms / full %.1f ms)\n", mc / mfc, mc, mfc);
    rc = 0;
done:
    st_renderer_free(&r);
    if (win) { glfwDestroyWindow(win); glfwTerminate(); }
    else st_headless_free(&hl);
    st_doc_free(&doc);
    return rc;
}
