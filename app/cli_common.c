/* Shared option parsing and loading for the subcommands. */
#include "cli_common.h"
#include "formats/mesh_any.h"
#include "core/io/session.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int parse_uint(const char *s, unsigned max, unsigned *out)
{
    char *end;
    unsigned long v = strtoul(s, &end, 10);
    if (!*s || *end || v > max) return -1;
    *out = (unsigned)v;
    return 0;
}

int st_cli_parse_uv_interp(const char *v, int *out, const char *cmd)
{
    int i = st_uv_interp_find(v);
    if (i < 0) {
        fprintf(stderr, "strata %s: --uv-interp wants none, corners-only, corners-plus1, corners-plus2, "
                "boundaries or all, got '%s'\n", cmd, v);
        return -1;
    }
    *out = i;
    return 0;
}

int st_cli_parse(int argc, char **argv, st_cli_opts *o, const char *cmd)
{
    memset(o, 0, sizeof *o);
    o->level = -1;
    o->boundary = ST_BOUNDARY_UNSET;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--scheme") && v) { o->scheme = v; i++; }
        else if (!strcmp(a, "--levels") && v) {
            if (parse_uint(v, ST_MAX_LEVELS - 1, &o->levels)) { fprintf(stderr, "strata %s: --levels wants 0..%d, got '%s'\n", cmd, ST_MAX_LEVELS - 1, v); return -1; }
            i++;
        } else if (!strcmp(a, "--level") && v) {
            unsigned l;
            if (parse_uint(v, ST_MAX_LEVELS - 1, &l)) { fprintf(stderr, "strata %s: --level wants a level number, got '%s'\n", cmd, v); return -1; }
            o->level = (int)l;
            i++;
        } else if (!strcmp(a, "--boundary") && v) {
            if (!strcmp(v, "edge-only")) o->boundary = ST_BOUNDARY_EDGE_ONLY;
            else if (!strcmp(v, "edge-and-corner")) o->boundary = ST_BOUNDARY_EDGE_AND_CORNER;
            else { fprintf(stderr, "strata %s: --boundary wants edge-only or edge-and-corner, got '%s'\n", cmd, v); return -1; }
            i++;
        } else if (!strcmp(a, "--uv-interp") && v) {
            if (st_cli_parse_uv_interp(v, &o->uv_interp, cmd)) return -1;
            i++;
        } else if (!strcmp(a, "--strict")) o->read_flags |= ST_MESH_STRICT;
        else if (!strcmp(a, "-o") && v) { o->out = v; i++; }
        else if (a[0] == '-' && a[1]) { fprintf(stderr, "strata %s: unknown or incomplete option '%s'\n", cmd, a); return -1; }
        else if (!o->in) o->in = a;
        else { fprintf(stderr, "strata %s: unexpected argument '%s'\n", cmd, a); return -1; }
    }
    if (!o->in) { fprintf(stderr, "strata %s: no input file\n", cmd); return -1; }
    return 0;
}

/* A session file (.strata) as input: every chunk as saved (details, edits,
 * levels, layers, view), refined further when --levels asks for more. */
static int load_session(const st_cli_opts *o, st_session *s, const char *cmd)
{
    st_error err;
    if (st_session_load(o->in, s, &err)) { fprintf(stderr, "strata: %s\n", err.msg); return 1; }
    if (o->scheme && st_scheme_find(o->scheme) != s->h.scheme) {
        fprintf(stderr, "strata %s: %s is a %s session; --scheme %s does not apply (strata convert rebuilds with another scheme from a mesh)\n",
                cmd, o->in, s->h.scheme->name, o->scheme);
        st_session_free(s);
        return 2;
    }
    if (o->levels > s->h.map.top && s->has_adapt && s->box_on) {
        fprintf(stderr, "strata %s: %s shows an adaptive mesh (interest box on); --levels cannot refine it further\n", cmd, o->in);
        st_session_free(s);
        return 2;
    }
    if (o->levels > s->h.map.top && st_hier_subdivide_to(&s->h, o->levels, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        st_session_free(s);
        return 1;
    }
    return 0;
}

/* A mesh as input: the hierarchy built with --scheme to --levels.  With
 * keep_base the control mesh as loaded stays in s->base (a session written
 * from it stores it, as strata convert's does); without, it is freed before
 * the levels are refined, so it does not add to their peak. */
static int load_mesh(const st_cli_opts *o, st_session *s, const char *cmd, int keep_base)
{
    const char *name = o->scheme ? o->scheme : "catmull-clark";
    const st_scheme *sc = st_scheme_find(name);
    if (!sc) { fprintf(stderr, "strata %s: unknown scheme '%s' (catmull-clark, loop, butterfly, quad-triangle, sqrt3, doo-sabin)\n", cmd, name); return 2; }
    st_mesh mesh;
    st_error err;
    st_notes notes = { 0 };
    st_mesh_init(&mesh);
    if (st_any_mesh_load(o->in, &mesh, o->read_flags, &notes, &err)) { fprintf(stderr, "strata: %s\n", err.msg); st_notes_free(&notes); return 1; }
    /* Repairs are made, and said. */
    for (uint32_t i = 0; i < notes.count; i++) fprintf(stderr, "strata: %s\n", notes.lines[i]);
    st_notes_free(&notes);
    st_hier_opts ho = { .boundary = o->boundary, .crease_method = ST_CREASE_UNIFORM, .uv_interp = o->uv_interp };
    st_session_init(s);
    int rc = st_hier_init(&s->h, &mesh, sc, &ho, &err);
    if (rc) {
        st_mesh_free(&mesh);
        st_session_init(s);
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        return 1;
    }
    if (keep_base) {
        st_mesh_move(&s->base, &mesh);
        s->has_base = 1;
    } else st_mesh_free(&mesh);
    if (st_hier_subdivide_to(&s->h, o->levels, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        st_session_free(s);
        return 1;
    }
    s->display_level = s->h.map.top;
    return 0;
}

int st_cli_load_session(const st_cli_opts *o, st_session *s, const char *cmd)
{
    return st_session_is_path(o->in) ? load_session(o, s, cmd) : load_mesh(o, s, cmd, 1);
}

int st_cli_load(const st_cli_opts *o, st_hier *h, const char *cmd)
{
    st_session s;
    int rc = st_session_is_path(o->in) ? load_session(o, &s, cmd) : load_mesh(o, &s, cmd, 0);
    if (rc) return rc;
    st_session_move_hier(h, &s.h);
    st_session_free(&s);
    return 0;
}

int st_cli_level(const st_cli_opts *o, const st_hier *h, const char *cmd, unsigned *level)
{
    *level = o->level >= 0 ? (unsigned)o->level : o->levels;
    if (o->level < 0 && !o->levels && st_session_is_path(o->in)) *level = h->map.top;
    if (*level > h->map.top) {
        fprintf(stderr, "strata %s: level %u does not exist (the finest is %u)\n", cmd, *level, h->map.top);
        return -1;
    }
    return 0;
}

int st_cli_parse_box(const char *s, double lo[3], double hi[3])
{
    double v[6];
    char *end;
    for (int k = 0; k < 6; k++) {
        v[k] = strtod(s, &end);
        if (end == s || !isfinite(v[k]) || (k < 5 && *end != ',') || (k == 5 && *end)) return -1;
        s = end + 1;
    }
    for (int k = 0; k < 3; k++) {
        lo[k] = v[k] < v[k + 3] ? v[k] : v[k + 3];
        hi[k] = v[k] < v[k + 3] ? v[k + 3] : v[k];
    }
    return 0;
}
