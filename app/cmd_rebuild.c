/* strata rebuild IN [--method auto|unsubdivide|progressive] [--scheme S]
 *                   [--target-faces N] [--max-levels L] [--uv-interp I] [--strict] -o OUT.strata
 *
 * Makes a dense mesh into a hierarchy with coarse editing levels and saves
 * it as a session (core/io/session.h).
 *   - unsubdivide: IN has subdivision connectivity (a subdivided cage, in
 *     any vertex order); the cage and the depth are recovered
 *     (core/rebuild/unsubdivide.h), positions by the analysis.  The finest
 *     level reproduces IN exactly.
 *   - progressive: any manifold mesh (core/progressive/progressive.h).
 *   - auto (default): unsubdivide, and when it refuses, progressive; says
 *     which it used and why.
 * The methods are core's (core/rebuild/rebuild.h), which the window's
 * "rebuild levels" calls too.  Unsubdivide keeps the OBJ tags and UVs
 * (core/rebuild/unsubdivide.h); progressive says which it drops.  --uv-interp: the face-varying option
 * the UVs are refined by (unsubdivide).
 * --max-levels L: at most L levels removed.  --target-faces N: no step that
 * would leave a cage of fewer than N faces (the cage is the coarsest level
 * the pattern allows with at least N faces).
 * Exit status: 0 done, 1 unreadable input, refusal or unwritable output
 * (nothing written), 2 bad usage. */
#include "cli.h"
#include "formats/mesh_any.h"
#include "core/base/hugepage.h"
#include "core/io/session.h"
#include "core/rebuild/rebuild.h"
#include "core/progressive/scheme_registry.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct rebuild_opts {
    const char *in, *out, *scheme;
    int method;
    int uv_interp;             /* enum st_uv_interp */
    unsigned read_flags;       /* ST_MESH_STRICT with --strict */
    unsigned max_levels;       /* 0: no limit */
    uint32_t target_faces;     /* 0: none */
} rebuild_opts;

static int usage(void)
{
    fprintf(stderr, "usage: strata rebuild IN [--method auto|unsubdivide|progressive] [--scheme S]\n"
                    "                     [--target-faces N] [--max-levels L] [--uv-interp I] [--strict] -o OUT.strata\n");
    return 2;
}

static int parse_count(const char *s, unsigned long max, unsigned long *out)
{
    char *end;
    unsigned long v = strtoul(s, &end, 10);
    if (!*s || *end || s[0] == '-' || v > max) return -1;
    *out = v;
    return 0;
}

static int parse(int argc, char **argv, rebuild_opts *o)
{
    memset(o, 0, sizeof *o);
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        unsigned long n;
        if (!strcmp(a, "-o") && v) { o->out = v; i++; }
        else if (!strcmp(a, "--scheme") && v) { o->scheme = v; i++; }
        else if (!strcmp(a, "--strict")) o->read_flags |= ST_MESH_STRICT;
        else if (!strcmp(a, "--uv-interp") && v) {
            if ((o->uv_interp = st_uv_interp_find(v)) < 0) {
                fprintf(stderr, "strata rebuild: --uv-interp wants none, corners-only, corners-plus1, corners-plus2, boundaries or all, got '%s'\n", v);
                return -1;
            }
            i++;
        }
        else if (!strcmp(a, "--method") && v) {
            if (!strcmp(v, "auto")) o->method = ST_REBUILD_AUTO;
            else if (!strcmp(v, "unsubdivide")) o->method = ST_REBUILD_UNSUBDIVIDE;
            else if (!strcmp(v, "progressive")) o->method = ST_REBUILD_PROGRESSIVE;
            else { fprintf(stderr, "strata rebuild: --method wants auto, unsubdivide or progressive, got '%s'\n", v); return -1; }
            i++;
        } else if (!strcmp(a, "--max-levels") && v) {
            if (parse_count(v, ST_MAX_LEVELS - 1, &n) || n == 0) { fprintf(stderr, "strata rebuild: --max-levels wants 1..%d, got '%s'\n", ST_MAX_LEVELS - 1, v); return -1; }
            o->max_levels = (unsigned)n;
            i++;
        } else if (!strcmp(a, "--target-faces") && v) {
            if (parse_count(v, ST_MESH_MAX_FACES, &n) || n == 0) { fprintf(stderr, "strata rebuild: --target-faces wants a positive face count, got '%s'\n", v); return -1; }
            o->target_faces = (uint32_t)n;
            i++;
        } else if (a[0] == '-' && a[1]) { fprintf(stderr, "strata rebuild: unknown or incomplete option '%s'\n", a); return -1; }
        else if (!o->in) o->in = a;
        else { fprintf(stderr, "strata rebuild: unexpected argument '%s'\n", a); return -1; }
    }
    if (!o->in || !o->out) { fprintf(stderr, "strata rebuild: needs an input mesh and -o OUT.strata\n"); return -1; }
    if (!st_session_is_path(o->out)) { fprintf(stderr, "strata rebuild: %s: the output is a session (.strata)\n", o->out); return -1; }
    if (o->scheme && !st_scheme_find(o->scheme)) {
        fprintf(stderr, "strata rebuild: unknown scheme '%s' (catmull-clark, loop, butterfly, quad-triangle, sqrt3, doo-sabin)\n", o->scheme);
        return -1;
    }
    return 0;
}

static int save_hier(const rebuild_opts *o, st_hier *h)
{
    st_error err;
    st_mesh cage;
    st_mesh_init(&cage);
    if (st_hier_level_mesh(h, 0, &cage, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        return 1;
    }
    st_session_ref r = { .h = h, .edit_level = 0, .display_level = h->map.top, .base = &cage };
    int rc = st_session_save_ref(o->out, &r, &err);
    if (rc) fprintf(stderr, "strata: %s\n", err.msg);
    st_mesh_free(&cage);
    return rc ? 1 : 0;
}

/* The report's lines, each behind the file it is about: the input for the
 * progressive method (printed before saving), the output for unsubdivide
 * (after). */
static void print_report(const char *file, const st_rebuild_report *rep)
{
    printf("%s: %s\n", file, rep->summary);
    if (rep->stop[0]) printf("%s: %s\n", file, rep->stop);
    for (uint32_t i = 0; i < rep->notes.count; i++) printf("%s: %s\n", file, rep->notes.lines[i]);
}

int st_cmd_rebuild(int argc, char **argv)
{
    rebuild_opts o;
    if (parse(argc, argv, &o)) return usage();
    /* Read, rebuild, save: each stage reuses what the one before freed
     * (spot x4 shuffled with UVs: 73k page faults instead of 119k,
     * hugepage.h). */
    st_malloc_keep_freed();
    st_error err;
    st_notes notes = { 0 };
    st_mesh mesh;
    st_mesh_init(&mesh);
    if (st_any_mesh_load(o.in, &mesh, o.read_flags, &notes, &err)) {
        fprintf(stderr, "strata: %s\n", err.msg);
        st_notes_free(&notes);
        return 1;
    }
    for (uint32_t i = 0; i < notes.count; i++) fprintf(stderr, "strata: %s\n", notes.lines[i]);
    st_notes_free(&notes);
    st_rebuild_opts ro = { .method = o.method, .scheme = o.scheme, .uv_interp = o.uv_interp,
                           .max_levels = o.max_levels, .target_faces = o.target_faces };
    st_rebuild_report rep;
    st_hier h;
    int rc = st_rebuild(o.in, &mesh, &ro, &h, &rep, &err), built = !rc;
    if (rep.refusal[0]) {
        fprintf(stderr, "strata rebuild: unsubdivide refused: %s\n", rep.refusal);
        fprintf(stderr, "strata rebuild: %s: using the progressive method\n", o.in);
    }
    if (rep.warning[0]) fprintf(stderr, "strata rebuild: %s\n", rep.warning);
    if (rc) {
        fprintf(stderr, "strata rebuild: %s\n", err.msg);
        rc = rep.wrong_scheme ? 2 : 1;
    } else if (rep.method == ST_REBUILD_PROGRESSIVE) {
        print_report(o.in, &rep);
        rc = save_hier(&o, &h);
        { char lv[48]; if (!rc) printf("%s: session, %s\n", o.out, st_levels_phrase(h.map.top, lv, sizeof lv)); }
    } else {
        rc = save_hier(&o, &h);
        if (!rc) print_report(o.out, &rep);
    }
    if (built) st_hier_free(&h);
    st_rebuild_report_free(&rep);
    st_mesh_free(&mesh);
    return rc;
}
