/* The memory guard (core/base/membudget.h, core/multires/estimate.h):
 *   - the predicted cell counts of every new level equal the counts the
 *     refinement really makes, for every scheme (closed and open meshes);
 *   - the estimated peak of st_hier_subdivide_to is within 25 % of the
 *     measured peak resident size, on several meshes, schemes and depths
 *     (each case in a child process of its own, so that peaks don't mix);
 *     likewise the adaptive refinement's two estimates (the update, from
 *     level 0; the output mesh and its UVs, from the adaptive map), on five
 *     schemes, boxes large and thin, with and without falloff;
 *   - the synthesis of strata filter on a progressive session (its ring
 *     tables, core/progressive/progressive_synth.c): the estimate within
 *     10 % of the peak's growth above the loaded session, and of the bytes
 *     the tables then hold;
 *   - over the budget, st_hier_subdivide_to and st_progressive_filter
 *     refuse at once with ST_ERR_MEMORY, the estimate and the limit in the
 *     message, and leave the hierarchy as it was. */
#include "testlib.h"
#include "core/base/membudget.h"
#include "core/multires/estimate.h"
#include "core/adapt/adapt.h"
#include "core/adapt/adapt_estimate.h"
#include "core/io/session.h"
#include "core/multires/hier_internal.h"
#include "core/progressive/progressive_internal.h"
#include "core/progressive/scheme_registry.h"

#include <malloc.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static int load(st_hier *h, const char *rel, st_scheme_id id)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", STRATA_SHARED_DATA, rel);
    st_mesh mesh;
    st_error err;
    st_mesh_init(&mesh);
    if (st_mesh_load(path, &mesh, &err)) { fprintf(stderr, "%s\n", err.msg); return -1; }
    int rc = st_hier_init(h, &mesh, st_scheme_get(id), NULL, &err);
    st_mesh_free(&mesh);
    if (rc) fprintf(stderr, "%s: %s\n", path, err.msg);
    return rc;
}

/* Predicted counts of each level == counts measured after refinement. */
static void check_counts(const char *rel, st_scheme_id id, unsigned levels)
{
    st_hier h;
    if (load(&h, rel, id)) { CHECK(!"load"); return; }
    st_error err;
    for (unsigned l = 1; l <= levels; l++) {
        st_level_stats before, predicted, got;
        st_level_stats_compute(&h.map, l - 1, &before);
        uint64_t triangles = st_level_triangles(&h.map, l - 1);
        st_estimate_next_level(id, l, &before, &triangles, &predicted);
        CHECK(st_hier_subdivide_to(&h, l, &err) == ST_OK);
        st_level_stats_compute(&h.map, l, &got);
        CHECKF(predicted.vertices == got.vertices && predicted.edges == got.edges && predicted.faces == got.faces &&
               predicted.darts == got.darts && predicted.boundary_edges == got.boundary_edges &&
               predicted.boundary_loops == got.boundary_loops && predicted.euler == got.euler,
               "%s %s level %u: predicted V %llu E %llu F %llu D %llu B %llu, got V %llu E %llu F %llu D %llu B %llu",
               rel, h.scheme->name, l, (unsigned long long)predicted.vertices, (unsigned long long)predicted.edges,
               (unsigned long long)predicted.faces, (unsigned long long)predicted.darts,
               (unsigned long long)predicted.boundary_edges, (unsigned long long)got.vertices,
               (unsigned long long)got.edges, (unsigned long long)got.faces, (unsigned long long)got.darts,
               (unsigned long long)got.boundary_edges);
    }
    st_hier_free(&h);
}

/* One peak case: `prepare` loads what the operation starts from, `estimate`
 * says what it will add, `run` does it; each in a child process of its own,
 * so that peaks don't mix and a child starts with only its own pages. */
typedef struct peak_case {
    const char *rel;
    st_scheme_id id;
    unsigned levels;              /* subdivide: the depth; adapt: the maximum level */
    const st_adapt_params *box;   /* adapt only */
} peak_case;
typedef size_t (*estimate_fn)(st_hier *h, const peak_case *c);
typedef int (*run_fn)(st_hier *h, const peak_case *c);   /* also for `prepare` */

/* Runs body(arg, r) in a child process of its own and returns the n
 * numbers it wrote to r (0 when the child sent none), so that peaks don't
 * mix and a child starts with only its parent's pages. */
static int in_child(void (*body)(const void *arg, double *r), const void *arg, double *r, size_t n)
{
    int fd[2];
    memset(r, 0, n * sizeof *r);
    if (pipe(fd)) return 0;
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        body(arg, r);
        ssize_t w = write(fd[1], r, n * sizeof *r);
        _exit(w == (ssize_t)(n * sizeof *r) ? 0 : 1);
    }
    close(fd[1]);
    ssize_t got = read(fd[0], r, n * sizeof *r);
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return got == (ssize_t)(n * sizeof *r);
}

typedef struct peak_run { const peak_case *c; run_fn prepare; estimate_fn estimate_of; run_fn run; } peak_run;

/* In the child: resident size before, the estimate, the peak after. */
static void peak_body(const void *arg, double *r)
{
    const peak_run *pr = arg;
    const peak_case *c = pr->c;
    st_hier h;
    if (load(&h, c->rel, c->id) || (pr->prepare && pr->prepare(&h, c) != ST_OK)) return;
    r[0] = (double)st_mem_resident();
    r[1] = (double)pr->estimate_of(&h, c);
    if (pr->run(&h, c) == ST_OK) {
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        r[2] = (double)ru.ru_maxrss * 1024.0;
    }
    st_hier_free(&h);
}

static void check_peak_of(const char *what, const peak_case *c, run_fn prepare, estimate_fn estimate_of, run_fn run)
{
    peak_run pr = { c, prepare, estimate_of, run };
    double r[3];
    CHECK(in_child(peak_body, &pr, r, 3) && r[2] > 0);
    double estimate = r[0] + r[1], peak = r[2], ratio = estimate / peak;
    printf("%-9s %-40s %-14s levels %u: resident before %.1f MiB, estimated peak %.1f MiB, measured %.1f MiB (%.2f)\n",
           what, c->rel, st_scheme_get(c->id)->name, c->levels, r[0] / 1048576, estimate / 1048576, peak / 1048576,
           ratio);
#if defined(__SANITIZE_ADDRESS__)
    (void)ratio; /* the sanitizer's shadow memory and quarantine are not the program's */
#else
    CHECKF(ratio > 0.75 && ratio < 1.25, "%s %s %u levels: estimate %.1f MiB against a peak of %.1f MiB", what, c->rel,
           c->levels, estimate / 1048576, peak / 1048576);
#endif
}

/* Under ASan the peak's ratio is not checked (the sanitizer's memory is not
 * the program's), so the peak cases run two levels shallower there: the
 * same code under the sanitizers at about a sixteenth of the work (it was
 * the slowest test of the sanitizer stage, 138 s). */
#if defined(__SANITIZE_ADDRESS__)
enum { PEAK_LEVELS_CUT = 2 };
#else
enum { PEAK_LEVELS_CUT = 0 };
#endif
static unsigned peak_levels(unsigned levels, unsigned floor)
{
    return levels >= floor + PEAK_LEVELS_CUT ? levels - PEAK_LEVELS_CUT : floor;
}

static size_t subdivide_estimate(st_hier *h, const peak_case *c) { return st_hier_estimate_subdivide(h, c->levels, NULL); }
static int subdivide_run(st_hier *h, const peak_case *c)
{
    st_error err;
    return st_hier_subdivide_to(h, c->levels, &err);
}
static void check_peak(const char *rel, st_scheme_id id, unsigned levels)
{
    peak_case c = { rel, id, peak_levels(levels, 1), NULL };
    check_peak_of("subdivide", &c, NULL, subdivide_estimate, subdivide_run);
}

/* The adaptive refinement as strata adapt runs it, in two steps, each
 * with its own check (core/adapt/adapt_estimate.h): the update, estimated
 * from level 0; then the output mesh (with its UVs), estimated from the
 * adaptive map's counts.  The child's adaptive state lives here. */
static st_adapt child_adapt;
static size_t adapt_estimate(st_hier *h, const peak_case *c) { return st_adapt_estimate_bytes(h, c->box); }
static int adapt_run(st_hier *h, const peak_case *c)
{
    st_error err;
    memset(&child_adapt, 0, sizeof child_adapt);
    int rc = st_adapt_init(&child_adapt, h, &err);
    if (!rc) rc = st_adapt_update(&child_adapt, c->box, &err);
    if (rc) fprintf(stderr, "%s: %s\n", c->rel, err.msg);
    return rc;
}
static size_t adapt_mesh_estimate(st_hier *h, const peak_case *c)
{
    (void)h, (void)c;
    return st_adapt_estimate_mesh_bytes(&child_adapt);
}
static int adapt_mesh_run(st_hier *h, const peak_case *c)
{
    (void)h;
    st_error err;
    st_mesh out;
    st_mesh_init(&out);
    int rc = st_adapt_mesh(&child_adapt, &out, &err);
    char path[64];
    snprintf(path, sizeof path, "/tmp/test_membudget_%d.obj", (int)getpid());
    if (!rc) rc = st_mesh_save(path, &out, &err); /* as strata adapt writes it */
    remove(path);
    if (rc) fprintf(stderr, "%s: %s\n", c->rel, err.msg);
    st_mesh_free(&out);
    return rc;
}
/* box: fractions of the mesh's bounding box (lo x, y, z, hi x, y, z) */
static void check_adapt_peak(const char *rel, st_scheme_id id, unsigned base, unsigned max, const double box[6],
                             double falloff)
{
    st_mesh mesh;
    st_error err;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", STRATA_SHARED_DATA, rel);
    st_mesh_init(&mesh);
    if (st_mesh_load(path, &mesh, &err)) { CHECKF(0, "%s", err.msg); return; }
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t v = 0; v < mesh.nverts; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], mesh.pos[3 * v + k]);
            hi[k] = fmax(hi[k], mesh.pos[3 * v + k]);
        }
    st_mesh_free(&mesh);
    st_adapt_params p;
    memset(&p, 0, sizeof p);
    max = peak_levels(max, base + 1);
    p.base_level = base;
    p.max_level = max;
    p.has_box = 1;
    for (int k = 0; k < 3; k++) {
        p.box_lo[k] = lo[k] + box[k] * (hi[k] - lo[k]);
        p.box_hi[k] = lo[k] + box[k + 3] * (hi[k] - lo[k]);
    }
    p.falloff = falloff * (hi[1] - lo[1]);
    peak_case c = { rel, id, max, &p };
    check_peak_of("adapt", &c, NULL, adapt_estimate, adapt_run);
    check_peak_of("adapt out", &c, adapt_run, adapt_mesh_estimate, adapt_mesh_run);
}

/* ---- the progressive filter's synthesis ------------------------------------ */

/* Koala's progressive hierarchy as strata rebuild makes it (1 % of the
 * faces), saved as a session: built in a child, so that this process stays
 * small for the peaks. */
static char session_path[64];
static void save_session_body(const void *arg, double *r)
{
    (void)arg;
    st_mesh mesh;
    st_error err;
    char path[1024];
    snprintf(path, sizeof path, "%s/large/koala.obj", STRATA_SHARED_DATA);
    st_mesh_init(&mesh);
    if (st_mesh_load(path, &mesh, &err)) return;
    st_progressive_opts o = { .target_faces = mesh.nfaces / 100 };
    st_hier h;
    if (st_progressive_build(&mesh, &o, &h, NULL, &err) == ST_OK) {
        st_session_ref ref = { .h = &h, .display_level = h.map.top };
        r[0] = st_session_save_ref(session_path, &ref, &err) == ST_OK;
        st_hier_free(&h);
    }
    st_mesh_free(&mesh);
}

typedef struct filter_case { const double *gains; unsigned n; } filter_case;

static unsigned first_filtered(const filter_case *f)
{
    for (unsigned k = 0; k < f->n; k++)
        if (f->gains[k] != 1.0) return k + 1;
    return 0;
}

/* The peak since the last write of 5 to /proc/self/clear_refs (VmHWM). */
static double resident_peak(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kib = 0;
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "VmHWM:", 6)) kib = atof(line + 6);
    if (f) fclose(f);
    return kib * 1024.0;
}

static double position_column_bytes(const st_map *m)
{
    double n = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) n += (double)m->pos.colcap[l] * (double)m->pos.elem;
    return n;
}

/* In the child: the session loaded, its peak reset; resident size, the
 * estimate, the peak after the filter, the bytes of the ring tables and of
 * the new position columns then. */
static void filter_body(const void *arg, double *r)
{
    const filter_case *f = arg;
    st_session s;
    st_error err;
    if (st_session_load(session_path, &s, &err)) { fprintf(stderr, "%s\n", err.msg); return; }
    malloc_trim(0); /* the file's buffer: freed pages are not the filter's */
    FILE *cr = fopen("/proc/self/clear_refs", "w");
    if (cr) { fputs("5", cr); fclose(cr); }
    r[0] = (double)st_mem_resident();
    r[1] = (double)st_progressive_synth_estimate(&s.h, first_filtered(f) - 1);
    double columns = position_column_bytes(&s.h.map);
    if (st_progressive_filter(&s.h, f->gains, f->n, &err) == ST_OK) {
        r[2] = resident_peak();
        r[3] = (double)st_progressive_table_bytes(&s.h);
        r[4] = position_column_bytes(&s.h.map) - columns;
    }
    st_session_free(&s);
}

static void check_filter_peak(const double *gains, unsigned n)
{
    filter_case f = { gains, n };
    double r[5];
    CHECK(in_child(filter_body, &f, r, 5) && r[2] > 0 && r[3] > 0);
    double growth = r[2] - r[0], made = r[3] + r[4], ratio = (r[0] + r[1]) / r[2];
    printf("filter    koala progressive session, from level %u: resident before %.1f MiB, estimated growth %.2f MiB, "
           "measured %.2f MiB (%.2f; ring tables %.2f MiB, position columns %.2f MiB); estimated peak %.1f MiB, "
           "measured %.1f MiB (%.3f)\n",
           first_filtered(&f) - 1, r[0] / 1048576, r[1] / 1048576, growth / 1048576, r[1] / growth, r[3] / 1048576,
           r[4] / 1048576, (r[0] + r[1]) / 1048576, r[2] / 1048576, ratio);
    CHECKF(r[1] > 0.9 * made && r[1] < 1.1 * made, "estimate %.2f MiB against %.2f MiB of tables and columns",
           r[1] / 1048576, made / 1048576);
#if !defined(__SANITIZE_ADDRESS__) /* the sanitizer's shadow memory and quarantine are not the program's */
    CHECKF(r[1] > 0.9 * growth && r[1] < 1.1 * growth, "estimate %.2f MiB against a growth of %.2f MiB",
           r[1] / 1048576, growth / 1048576);
    CHECKF(ratio > 0.9 && ratio < 1.1, "estimated peak %.1f MiB against %.1f MiB", (r[0] + r[1]) / 1048576,
           r[2] / 1048576);
#endif
}

/* Over the budget the filter is refused before it scales a detail. */
static void check_filter_refusal(void)
{
    st_session s;
    st_error err;
    if (st_session_load(session_path, &s, &err)) { CHECKF(0, "%s", err.msg); return; }
    static const double gains[2] = { 1, 0 };
    size_t need = st_progressive_synth_estimate(&s.h, 1);
    double before = st_hier_detail(&s.h, 2, 0)[0] + st_hier_detail(&s.h, s.h.map.top, 0)[0];
    st_mem_budget_set(st_mem_resident() + need / 2);
    int rc = st_progressive_filter(&s.h, gains, 2, &err);
    CHECK(rc == ST_ERR_MEMORY);
    CHECKF(strstr(err.msg, "synthesis") && strstr(err.msg, "MiB more") && strstr(err.msg, "memory budget"), "message: %s",
           err.msg);
    CHECK(st_progressive_table_bytes(&s.h) == 0);   /* no table was built */
    CHECK(st_hier_detail(&s.h, 2, 0)[0] + st_hier_detail(&s.h, s.h.map.top, 0)[0] == before);
    st_mem_budget_set(st_mem_resident() + 2 * need);
    CHECK(st_progressive_filter(&s.h, gains, 2, &err) == ST_OK);
    st_mem_budget_set(0);
    st_session_free(&s);
}

static void check_refusal(void)
{
    st_hier h;
    if (load(&h, "catmull_clark/spot_quadrangulated.obj", ST_SCHEME_CATMARK)) { CHECK(!"load"); return; }
    size_t before = st_mem_resident();
    st_mem_budget_set(before + ((size_t)64 << 20)); /* 64 MiB more: level 4 needs ~80 */
    st_error err;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int rc = st_hier_subdivide_to(&h, 6, &err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double secs = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    CHECK(rc == ST_ERR_MEMORY);
    CHECKF(strstr(err.msg, "subdividing to level 6") && strstr(err.msg, "MiB more") && strstr(err.msg, "memory budget"),
           "message: %s", err.msg);
    CHECK(h.map.top == 0);        /* nothing was built */
    CHECK(secs < 1.0);
    /* Within the budget the same call goes through. */
    CHECK(st_hier_subdivide_to(&h, 2, &err) == ST_OK && h.map.top == 2);
    st_mem_budget_set(0);
    CHECK(st_mem_budget() > 0);
    size_t b;
    CHECK(st_mem_parse_mib("1.5", &b) == 0 && b == (size_t)(1.5 * 1048576));
    CHECK(st_mem_parse_mib("0", &b) != 0 && st_mem_parse_mib("-3", &b) != 0 && st_mem_parse_mib("12x", &b) != 0);
    st_hier_free(&h);
}

int main(void)
{
    /* peaks first, while this process is small: a child starts with its pages */
    check_peak("catmull_clark/spot_quadrangulated.obj", ST_SCHEME_CATMARK, 4);
    check_peak("catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, 6);
    check_peak("triangle/spot_low_resolution.obj", ST_SCHEME_LOOP, 5);
    check_peak("triangle/sphere_ico.obj", ST_SCHEME_SQRT3, 7);
    check_peak("catmull_clark/blub_control_mesh.obj", ST_SCHEME_DOOSABIN, 6);
    check_peak("triangle/hand_lowres.obj", ST_SCHEME_BUTTERFLY, 5);
    check_peak("catmull_clark/mixed_faring.off", ST_SCHEME_QUADTRI, 4);
    /* the adaptive refinement (strata adapt, render/convert --box, the window's box) */
    static const double box[6] = { 0.5, 0.6, 0.3, 0.8, 0.9, 0.7 };
    check_adapt_peak("catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, 0, 8, box, 0);
    check_adapt_peak("catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, 2, 7, box, 0.05);
    check_adapt_peak("catmull_clark/spot_quadrangulated.obj", ST_SCHEME_CATMARK, 1, 6, box, 0);
    check_adapt_peak("triangle/spot_low_resolution.obj", ST_SCHEME_LOOP, 0, 7, box, 0);
    check_adapt_peak("triangle/spot_low_resolution.obj", ST_SCHEME_BUTTERFLY, 1, 6, box, 0);
    check_adapt_peak("triangle/spot_low_resolution.obj", ST_SCHEME_SQRT3, 0, 9, box, 0);
    check_adapt_peak("catmull_clark/blub_control_mesh.obj", ST_SCHEME_DOOSABIN, 0, 7, box, 0);
    static const double slab[6] = { 0.45, 0, 0, 0.5, 1, 1 }; /* thin: the rings matter */
    check_adapt_peak("catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, 0, 8, slab, 0);
    check_adapt_peak("triangle/spot_low_resolution.obj", ST_SCHEME_LOOP, 1, 7, slab, 0.02);
    check_adapt_peak("catmull_clark/spot_quadrangulated.obj", ST_SCHEME_DOOSABIN, 0, 6, slab, 0);

    /* strata filter's synthesis on koala's progressive session */
    snprintf(session_path, sizeof session_path, "/tmp/test_membudget_%d.strata", (int)getpid());
    double saved = 0;
    CHECK(in_child(save_session_body, NULL, &saved, 1) && saved == 1);
    static const double from_two[2] = { 1, 0 }, from_zero[1] = { 0.5 };
    check_filter_peak(from_two, 2);
    check_filter_peak(from_zero, 1);

    check_counts("catmull_clark/dodecahedron_poly.obj", ST_SCHEME_CATMARK, 3);
    check_counts("triangle/cube_no_bottom.obj", ST_SCHEME_CATMARK, 3);
    check_counts("triangle/hemisphere.obj", ST_SCHEME_LOOP, 3);
    check_counts("triangle/sphere_ico.obj", ST_SCHEME_BUTTERFLY, 3);
    check_counts("catmull_clark/mixed_faring.off", ST_SCHEME_QUADTRI, 3);
    check_counts("triangle/sphere_ico.obj", ST_SCHEME_SQRT3, 4);
    check_counts("catmull_clark/blub_control_mesh.obj", ST_SCHEME_DOOSABIN, 3);
    check_counts("triangle/hemisphere.obj", ST_SCHEME_DOOSABIN, 3);
    check_counts("triangle/plane_holes.obj", ST_SCHEME_LOOP, 3);
    check_counts("triangle/plane_holes.obj", ST_SCHEME_BUTTERFLY, 2);
    check_counts("triangle/hemisphere.obj", ST_SCHEME_SQRT3, 4);
    check_counts("triangle/cube_no_bottom.obj", ST_SCHEME_QUADTRI, 3);
    check_counts("catmull_clark/hole_capsule.off", ST_SCHEME_CATMARK, 3);
    check_counts("catmull_clark/newell_teapot_cage.obj", ST_SCHEME_CATMARK, 2);
    check_counts("edge_cases/grid_holes.obj", ST_SCHEME_DOOSABIN, 2);

    check_refusal();
    check_filter_refusal();
    remove(session_path);
    return TEST_END();
}
