/* strata filter IN.strata --gains g0,g1,... -o OUT
 *
 * Multiresolution filtering of a progressive hierarchy (strata rebuild
 * --method progressive; Kraemer 2008 §4.4.6, GSS99 §5): the details of
 * level k+1 are multiplied by gain k; levels past the list keep gain 1.
 * Gain 0 removes that band of detail (smoothing), 1 keeps it bit for bit,
 * > 1 enhances it.  OUT is a session (.strata) or a mesh of the finest
 * level (.obj .ply .gltf .glb).  Exit status: 0 done, 1 a file could not be
 * read or written or the hierarchy cannot be filtered, 2 bad usage. */
#include "cli.h"
#include "formats/mesh_any.h"
#include "core/io/session.h"
#include "core/progressive/progressive.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int usage(void)
{
    fprintf(stderr, "usage: strata filter IN.strata --gains g0,g1,... -o OUT(.strata|.obj|.ply|.gltf|.glb)\n");
    return 2;
}

/* "1,0.5,0": at most ST_MAX_LEVELS finite numbers; -1 when malformed. */
static int parse_gains(const char *s, double *g, unsigned *n)
{
    *n = 0;
    for (;;) {
        char *end;
        double v = strtod(s, &end);
        if (end == s || !isfinite(v) || *n >= ST_MAX_LEVELS) return -1;
        g[(*n)++] = v;
        if (!*end) return 0;
        if (*end != ',') return -1;
        s = end + 1;
    }
}

int st_cmd_filter(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    double gains[ST_MAX_LEVELS];
    unsigned ngains = 0;
    int have_gains = 0;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--gains") && v) {
            if (parse_gains(v, gains, &ngains)) {
                fprintf(stderr, "strata filter: --gains wants finite numbers separated by commas, got '%s'\n", v);
                return 2;
            }
            have_gains = 1;
            i++;
        } else if (!strcmp(a, "-o") && v) { out = v; i++; }
        else if (a[0] == '-') { fprintf(stderr, "strata filter: unknown or incomplete option '%s'\n", a); return usage(); }
        else if (!in) in = a;
        else { fprintf(stderr, "strata filter: unexpected argument '%s'\n", a); return usage(); }
    }
    if (!in || !out || !have_gains) return usage();
    if (!st_session_is_path(in)) {
        fprintf(stderr, "strata filter: %s is not a session: filter a hierarchy made by strata rebuild (.strata)\n", in);
        return 2;
    }
    st_session s;
    st_error err;
    if (st_session_load(in, &s, &err)) { fprintf(stderr, "strata: %s\n", err.msg); return 1; }
    int rc = st_progressive_filter(&s.h, gains, ngains, &err);
    if (rc) {
        fprintf(stderr, "strata filter: %s: %s\n", in, err.msg);
        st_session_free(&s);
        return 1;
    }
    if (st_session_is_path(out)) {
        rc = st_session_save(out, &s, &err);
    } else {
        st_mesh m;
        st_mesh_init(&m);
        rc = st_hier_level_mesh(&s.h, s.h.map.top, &m, &err);
        if (!rc) rc = st_any_mesh_save(out, &m, &err);
        st_mesh_free(&m);
    }
    if (rc) fprintf(stderr, "strata: %s\n", err.msg);
    else {
        char lv[48];
        printf("%s: %u gain%s applied to %s (%s)\n", out, ngains, ngains == 1 ? "" : "s", in,
               st_levels_phrase(s.h.map.top, lv, sizeof lv));
    }
    st_session_free(&s);
    return rc ? 1 : 0;
}
