/* strata rebuild IN [--method auto|unsubdivide|progressive] [--scheme S]
 *                   [--target-faces N] [--max-levels L] [--uv-interp I] -o OUT.strata
 *
 * Makes a dense mesh into a hierarchy with coarse editing levels and saves
 * it as a session (core/io/session.h).
 *   - unsubdivide: IN has subdivision connectivity (a subdivided cage, in
 *     any vertex order); the cage and the depth are recovered
 *     (core/rebuild/unsubdivide.h), positions by the analysis.  The finest
 *     level reproduces IN exactly.
 *   - progressive: arbitrary meshes (not in this build yet).
 *   - auto (default): unsubdivide, and when it refuses, progressive; says
 *     which it used and why.
 * Unsubdivide keeps the OBJ tags and UVs (core/rebuild/unsubdivide.h);
 * progressive says which it drops.  --uv-interp: the face-varying option
 * the UVs are refined by (unsubdivide).
 * --max-levels L: at most L levels removed.  --target-faces N: no step that
 * would leave a cage of fewer than N faces (the cage is the coarsest level
 * the pattern allows with at least N faces).
 * Exit status: 0 done, 1 unreadable input, refusal or unwritable output
 * (nothing written), 2 bad usage. */
#include "cli.h"
#include "mesh_any.h"
#include "core/progressive/progressive.h"
#include "core/base/membudget.h"
#include "core/io/session.h"
#include "core/rebuild/unsubdivide.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum rebuild_method { METHOD_AUTO, METHOD_UNSUBDIVIDE, METHOD_PROGRESSIVE };

typedef struct rebuild_opts {
    const char *in, *out, *scheme;
    int method;
    int uv_interp;             /* enum st_uv_interp */
    unsigned max_levels;       /* 0: no limit */
    uint32_t target_faces;     /* 0: none */
} rebuild_opts;

static int usage(void)
{
    fprintf(stderr, "usage: strata rebuild IN [--method auto|unsubdivide|progressive] [--scheme S]\n"
                    "                     [--target-faces N] [--max-levels L] [--uv-interp I] -o OUT.strata\n");
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
        else if (!strcmp(a, "--uv-interp") && v) {
            if ((o->uv_interp = st_uv_interp_find(v)) < 0) {
                fprintf(stderr, "strata rebuild: --uv-interp wants none, corners-only, corners-plus1, corners-plus2, boundaries or all, got '%s'\n", v);
                return -1;
            }
            i++;
        }
        else if (!strcmp(a, "--method") && v) {
            if (!strcmp(v, "auto")) o->method = METHOD_AUTO;
            else if (!strcmp(v, "unsubdivide")) o->method = METHOD_UNSUBDIVIDE;
            else if (!strcmp(v, "progressive")) o->method = METHOD_PROGRESSIVE;
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

static int save_hier(const rebuild_opts *o, st_hier *h);

/* The progressive method builds levels by edge collapses, which have no
 * rule for OBJ tags or UVs (a collapse merges a crease or a seam with its
 * neighbours): what the input had and the hierarchy lacks, one line. */
static void progressive_dropped(const rebuild_opts *o, const st_mesh *mesh)
{
    char buf[512];
    size_t n = 0;
    uint32_t holes = st_mesh_hole_faces(mesh);
    if (mesh->ncreases) n += (size_t)snprintf(buf + n, sizeof buf - n, "%s%u crease tag%s", n ? ", " : "", mesh->ncreases, mesh->ncreases == 1 ? "" : "s");
    if (mesh->ncorners && n < sizeof buf) n += (size_t)snprintf(buf + n, sizeof buf - n, "%s%u corner tag%s", n ? ", " : "", mesh->ncorners, mesh->ncorners == 1 ? "" : "s");
    if (holes && n < sizeof buf) n += (size_t)snprintf(buf + n, sizeof buf - n, "%s%u hole face%s (they are ordinary faces now)", n ? ", " : "", holes, holes == 1 ? "" : "s");
    if (mesh->face_uv && n < sizeof buf) n += (size_t)snprintf(buf + n, sizeof buf - n, "%sthe UVs", n ? ", " : "");
    if (n) printf("%s: note: the progressive method keeps no tags or UVs; dropped %s\n", o->in, buf);
}

/* The progressive method for any manifold mesh (core/progressive/: grouped
 * independent edge collapses, Kraemer 2008 §4.4).  Default target: 1 % of
 * the input's faces (at least 4), as far as the collapses allow. */
static int rebuild_progressive(const rebuild_opts *o, const st_mesh *mesh)
{
    if (o->scheme && strcmp(o->scheme, "progressive"))
        fprintf(stderr, "strata rebuild: --scheme %s applies to unsubdivide; the progressive method has its own "
                        "prediction (scheme progressive)\n", o->scheme);
    uint64_t corners = mesh->nfaces ? mesh->face_off[mesh->nfaces] : 0;
    st_error err;
    /* about 160 bytes per finest dart at the peak (koala: 47 MiB for 300k darts) */
    if (st_mem_check((size_t)corners * 200u, "the progressive rebuild", &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        return 1;
    }
    st_progressive_opts po = { .target_faces = o->target_faces, .max_levels = o->max_levels ? o->max_levels + 1 : 0 };
    if (!po.target_faces) po.target_faces = mesh->nfaces / 100 > 4 ? mesh->nfaces / 100 : 4;
    st_progressive_report rep;
    st_hier h;
    if (st_progressive_build(mesh, &po, &h, &rep, &err)) {
        fprintf(stderr, "strata rebuild: %s: %s\n", o->in, err.msg);
        return 1;
    }
    printf("%s: progressive, %u levels (faces", o->in, rep.levels);
    for (unsigned l = 0; l < rep.levels; l++) printf(" %llu", (unsigned long long)rep.faces[l]);
    printf("), kept per level t =");
    for (unsigned l = 1; l < rep.levels; l++) printf(" %.2f", rep.kept[l]);
    printf(", %.1f topology bytes per finest dart\n", rep.bytes_per_dart);
    if (rep.triangulated) printf("%s: polygons were split into triangles (fans) first\n", o->in);
    if (rep.note[0]) printf("%s: %s\n", o->in, rep.note);
    progressive_dropped(o, mesh);
    int rc = save_hier(o, &h);
    if (!rc) printf("%s: session, levels 0..%u\n", o->out, h.map.top);
    st_hier_free(&h);
    return rc;
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

static int rebuild_unsubdivide(const rebuild_opts *o, const st_mesh *mesh, const st_unsub *u)
{
    const char *name = o->scheme ? o->scheme : u->pattern == ST_UNSUB_POLY_SPLIT ? "catmull-clark" : "loop";
    const st_scheme *sc = st_scheme_find(name);
    if (!st_unsub_scheme_fits(u, sc)) {
        fprintf(stderr, "strata rebuild: %s is a %s; --scheme %s refines differently (use %s)\n", o->in,
                u->pattern == ST_UNSUB_POLY_SPLIT ? "polygon split (Catmull-Clark)" : "triangle quadrisection",
                name, u->pattern == ST_UNSUB_POLY_SPLIT ? "catmull-clark, or quad-triangle on a cage without triangles" : "loop, butterfly or quad-triangle");
        return 2;
    }
    st_hier h;
    st_error err;
    st_hier_opts ho = { .boundary = ST_BOUNDARY_UNSET, .crease_method = ST_CREASE_UNIFORM, .uv_interp = o->uv_interp };
    uint32_t *fine_of = NULL;
    if (st_unsub_build_hier(mesh, u, sc, &ho, &h, &fine_of, NULL, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        return 1;
    }
    int rc = save_hier(o, &h);
    if (!rc) {
        const st_mesh *cage = &u->step[0].coarse;
        printf("%s: unsubdivide, %s, scheme %s: levels 0..%u, cage %u faces and %u vertices, finest %u faces, longest detail %.3g\n",
               o->out, u->pattern == ST_UNSUB_POLY_SPLIT ? "polygon split" : "triangle quadrisection", sc->name,
               h.map.top, cage->nfaces, cage->nverts, mesh->nfaces, st_unsub_max_detail(&h));
        printf("%s: %s\n", o->out, u->stop);
        const st_mesh *c = &u->step[0].coarse;
        if (mesh->ncreases || mesh->ncorners || mesh->face_hole)
            printf("%s: tags kept: cage %u crease edge%s, %u corner%s, %u hole face%s; finest level as the input's\n", o->out,
                   c->ncreases, c->ncreases == 1 ? "" : "s", c->ncorners, c->ncorners == 1 ? "" : "s",
                   st_mesh_hole_faces(c), st_mesh_hole_faces(c) == 1 ? "" : "s");
        if (mesh->face_uv)
            printf("%s: UVs: cage corners from the input's; refined with --uv-interp %s, the finest level's UVs differ from "
                   "the input's by at most %.3g (UVs have no details)\n",
                   o->out, st_uv_interp_name(o->uv_interp), st_unsub_uv_residual(&h, mesh, fine_of));
    }
    free(fine_of);
    st_hier_free(&h);
    return rc;
}

int st_cmd_rebuild(int argc, char **argv)
{
    rebuild_opts o;
    if (parse(argc, argv, &o)) return usage();
    st_error err;
    st_notes notes = { 0 };
    st_mesh mesh;
    st_mesh_init(&mesh);
    if (st_any_mesh_load(o.in, &mesh, &notes, &err)) {
        fprintf(stderr, "strata: %s\n", err.msg);
        st_notes_free(&notes);
        return 1;
    }
    for (uint32_t i = 0; i < notes.count; i++) fprintf(stderr, "strata: %s\n", notes.lines[i]);
    st_notes_free(&notes);
    int rc;
    if (o.method == METHOD_PROGRESSIVE) {
        rc = rebuild_progressive(&o, &mesh);
    } else {
        st_unsub u;
        st_unsub_opts uo = { .max_levels = o.max_levels, .target_faces = o.target_faces };
        if (st_unsubdivide(o.in, &mesh, &uo, &u, &err) == ST_OK) {
            rc = rebuild_unsubdivide(&o, &mesh, &u);
            st_unsub_free(&u);
        } else if (o.method == METHOD_UNSUBDIVIDE) {
            fprintf(stderr, "strata rebuild: %s\n", err.msg);
            rc = 1;
        } else {
            fprintf(stderr, "strata rebuild: unsubdivide refused: %s\n", err.msg);
            fprintf(stderr, "strata rebuild: %s: using the progressive method\n", o.in);
            rc = rebuild_progressive(&o, &mesh);
        }
    }
    st_mesh_free(&mesh);
    return rc;
}
