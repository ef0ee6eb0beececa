/* strata render IN [--scheme S --levels N --level L] [--boundary B]
 *                  [--view front|back|left|right|top|iso | --orbit AZ,EL,DIST]
 *                  [--mode smooth|flat|wire|cage|uv] [--size WxH] -o OUT.png
 *                  [--normal-map N.png [--normal-space tangent|object]] [--auto-uv]
 *
 * Renders level L (default N) of IN's hierarchy headless (OSMesa: no
 * display, no GPU) into a PNG.  Same inputs, same machine: same bytes.
 * --mode uv draws a checker through the level's face-varying UVs, or with
 * --auto-uv through the atlas strata bake --auto-uv lays out for a 1024²
 * map with the default padding (st_bake_chart_uvs).  With --normal-map,
 * --auto-uv reads the map on that atlas (made for the map's size) even
 * where the level has UVs of its own: a map baked with --auto-uv. */
#include "cli.h"
#include "core/bake/bake.h"
#include "core/adapt/adapt_estimate.h"
#include "core/base/membudget.h"
#include "cli_common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/image.h"
#include "core/adapt/adapt.h"
#include "core/fvar/fvar.h"
#include "core/io/session.h"
#include "render/offscreen.h"
#include "render_nmap.h"

#define DEFAULT_W 800
#define DEFAULT_H 600

typedef struct render_opts {
    st_render_spec spec;
    int width, height;
    int view_given, orbit_given;
    int adaptive;               /* --box / --base-level / --max-level given */
    st_adapt_params adapt;
    const char *normal_map;     /* --normal-map N.png (app/render_nmap.h) */
    int normal_object;          /* --normal-space object */
    int mode_given;
    int auto_uv;                /* --auto-uv: --mode uv through st_bake_chart_uvs */
} render_opts;

/* ---- render-only options ---------------------------------------------------- */

static int parse_view(render_opts *r, const char *v)
{
    int p = st_view_parse(v);
    if (p < 0) { fprintf(stderr, "strata render: --view wants front, back, left, right, top or iso, got '%s'\n", v); return -1; }
    r->spec.view = p;
    r->view_given = 1;
    return 0;
}

static int parse_orbit(render_opts *r, const char *v)
{
    char *end;
    float x[3];
    const char *s = v;
    for (int i = 0; i < 3; i++) {
        x[i] = strtof(s, &end);
        if (end == s || !isfinite(x[i]) || (i < 2 ? *end != ',' : *end != 0)) {
            fprintf(stderr, "strata render: --orbit wants AZ,EL,DIST (degrees, degrees, model units; DIST 0 frames the model), got '%s'\n", v);
            return -1;
        }
        s = end + 1;
    }
    if (x[2] < 0) { fprintf(stderr, "strata render: --orbit distance must be >= 0, got %g\n", x[2]); return -1; }
    r->spec.view = -1;
    r->spec.az = x[0];
    r->spec.el = x[1];
    r->spec.dist = x[2];
    r->orbit_given = 1;
    return 0;
}

static int parse_mode(render_opts *r, const char *v)
{
    int m = st_render_mode_parse(v);
    if (m < 0) { fprintf(stderr, "strata render: --mode wants smooth, flat, wire, cage or uv, got '%s'\n", v); return -1; }
    r->spec.mode = m;
    r->mode_given = 1;
    return 0;
}

static int parse_normal_map(render_opts *r, const char *v)
{
    r->normal_map = v;
    return 0;
}

static int parse_normal_space(render_opts *r, const char *v)
{
    if (strcmp(v, "tangent") && strcmp(v, "object")) {
        fprintf(stderr, "strata render: --normal-space wants tangent or object, got '%s'\n", v);
        return -1;
    }
    r->normal_object = !strcmp(v, "object");
    return 0;
}

static int parse_size(render_opts *r, const char *v)
{
    char *end;
    long w = strtol(v, &end, 10), h = 0;
    if (end != v && (*end == 'x' || *end == 'X')) {
        const char *s = end + 1;
        h = strtol(s, &end, 10);
        if (end == s || *end) h = 0;
    }
    if (w < 1 || h < 1 || w > ST_HEADLESS_MAX_SIZE || h > ST_HEADLESS_MAX_SIZE) {
        fprintf(stderr, "strata render: --size wants WxH with 1..%d pixels each, got '%s'\n", ST_HEADLESS_MAX_SIZE, v);
        return -1;
    }
    r->width = (int)w;
    r->height = (int)h;
    return 0;
}

/* Adaptive display: an interest-box refinement (core/adapt/adapt.h) drawn at its
 * top level, with the box shown. */
static int parse_box(render_opts *r, const char *v)
{
    if (st_cli_parse_box(v, r->adapt.box_lo, r->adapt.box_hi)) {
        fprintf(stderr, "strata render: --box wants x0,y0,z0,x1,y1,z1, got '%s'\n", v);
        return -1;
    }
    r->adapt.has_box = 1;
    r->adaptive = 1;
    for (int k = 0; k < 3; k++) {
        r->spec.box[k] = (float)r->adapt.box_lo[k];
        r->spec.box[k + 3] = (float)r->adapt.box_hi[k];
    }
    r->spec.has_box = 1;
    return 0;
}

static int parse_level_option(const char *name, const char *v, unsigned *out)
{
    char *end;
    long l = strtol(v, &end, 10);
    if (end == v || *end || l < 0 || l >= ST_MAX_LEVELS) {
        fprintf(stderr, "strata render: %s wants a level 0..%d, got '%s'\n", name, ST_MAX_LEVELS - 1, v);
        return -1;
    }
    *out = (unsigned)l;
    return 0;
}

static int parse_base_level(render_opts *r, const char *v)
{
    r->adaptive = 1;
    return parse_level_option("--base-level", v, &r->adapt.base_level);
}

static int parse_max_level(render_opts *r, const char *v)
{
    r->adaptive = 1;
    return parse_level_option("--max-level", v, &r->adapt.max_level);
}

static const struct {
    const char *name;
    int (*parse)(render_opts *, const char *);
} render_options[] = {
    { "--view", parse_view },
    { "--orbit", parse_orbit },
    { "--mode", parse_mode },
    { "--size", parse_size },
    { "--box", parse_box },
    { "--base-level", parse_base_level },
    { "--max-level", parse_max_level },
    { "--normal-map", parse_normal_map },
    { "--normal-space", parse_normal_space },
};

/* Options of st_cli_parse that take a value: copied through untouched so
 * that their values are never read as render options. */
static int common_takes_value(const char *a)
{
    static const char *const names[] = { "--scheme", "--levels", "--level", "--boundary", "--uv-interp", "-o" };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(a, names[i])) return 1;
    return 0;
}

/* Takes the render-only options out of argv (into r) and leaves the common
 * ones in rest[] for st_cli_parse. */
static int split_args(int argc, char **argv, render_opts *r, char **rest, int *nrest)
{
    *nrest = 0;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        int handled = 0;
        if (!strcmp(a, "--auto-uv")) { r->auto_uv = 1; continue; }
        for (size_t k = 0; k < sizeof render_options / sizeof render_options[0]; k++) {
            if (strcmp(a, render_options[k].name)) continue;
            if (i + 1 >= argc) { fprintf(stderr, "strata render: %s needs a value\n", a); return -1; }
            if (render_options[k].parse(r, argv[++i])) return -1;
            handled = 1;
            break;
        }
        if (handled) continue;
        rest[(*nrest)++] = argv[i];
        if (common_takes_value(a) && i + 1 < argc) rest[(*nrest)++] = argv[++i];
    }
    if (r->view_given && r->orbit_given) {
        fprintf(stderr, "strata render: give either --view or --orbit, not both\n");
        return -1;
    }
    return 0;
}

/* The image's memory against --mem-budget before it is allocated: the
 * offscreen framebuffers, the pixels read back, the PNG encoder's. */
static int check_image_budget(const render_opts *r, const char *out)
{
    size_t px = (size_t)r->width * (size_t)r->height;
    size_t need = st_offscreen_bytes(r->width, r->height) + px * 4 + st_png_write_bytes(r->width, r->height);
    char what[96];
    snprintf(what, sizeof what, "a %dx%d image", r->width, r->height);
    st_error err;
    if (!st_mem_check(need, what, &err)) return 0;
    fprintf(stderr, "strata render: %s: %s\n", out, err.msg);
    return -1;
}

int st_cmd_render(int argc, char **argv)
{
    render_opts r;
    memset(&r, 0, sizeof r);
    r.spec = st_render_spec_default();
    r.adapt.max_level = 3; /* as strata adapt */
    r.width = DEFAULT_W;
    r.height = DEFAULT_H;
    char **rest = malloc((size_t)(argc > 0 ? argc : 1) * sizeof *rest);
    if (!rest) { fprintf(stderr, "strata render: out of memory\n"); return 1; }
    int nrest = 0;
    st_cli_opts o;
    if (split_args(argc, argv, &r, rest, &nrest) || st_cli_parse(nrest, rest, &o, "render")) { free(rest); return 2; }
    free(rest);
    if (!o.out) { fprintf(stderr, "strata render: -o OUT.png is required\n"); return 2; }
    if (!st_path_has_ext(o.out, ".png")) { fprintf(stderr, "strata render: the output must be a .png file, got '%s'\n", o.out); return 2; }
    if (o.level > (int)o.levels && !st_session_is_path(o.in)) {
        fprintf(stderr, "strata render: --level %d is above --levels %u\n", o.level, o.levels);
        return 2;
    }
    /* At once, before the model is read; again once it is in memory. */
    if (check_image_budget(&r, o.out)) return 1;
    r.spec.cage_level = 0;
    if (r.adaptive) {
        if (o.levels || o.level >= 0) { fprintf(stderr, "strata render: --levels/--level do not go with --box (the box decides the levels)\n"); return 2; }
        if (r.adapt.base_level > r.adapt.max_level) { fprintf(stderr, "strata render: --base-level is above --max-level\n"); return 2; }
    }
    if (r.normal_map && (r.adaptive || (r.mode_given && r.spec.mode != ST_MODE_SMOOTH))) {
        fprintf(stderr, "strata render: --normal-map draws a level in smooth mode; it does not go with --box or --mode %s\n",
                st_render_mode_name(r.spec.mode));
        return 2;
    }

    st_hier h;
    int rc = st_cli_load(&o, &h, "render");
    if (rc) return rc;
    unsigned level = 0;
    if (!r.adaptive && st_cli_level(&o, &h, "render", &level)) { st_hier_free(&h); return 2; }
    r.spec.level = level;
    double *auto_uv = NULL;
    if (r.auto_uv && ((r.spec.mode != ST_MODE_UV && !r.normal_map) || r.adaptive)) {
        fprintf(stderr, "strata render: --auto-uv applies to --mode uv or --normal-map of a level (not adaptive)\n");
        st_hier_free(&h);
        return 2;
    }
    if (r.auto_uv && !r.normal_map) {
        st_error e;
        st_bake_layout lay;
        int arc = st_bake_chart_uvs(&h, level, 1024, ST_BAKE_AUTO_PADDING, &lay, NULL, &e);
        if (!arc) {
            st_bake_uvs u = st_bake_layout_uvs(&lay);
            arc = st_bake_layout_dart_uvs(&h, level, &u, &auto_uv, &e);
            st_bake_layout_free(&lay);
        }
        if (arc) { fprintf(stderr, "strata render: %s: %s\n", o.in, e.msg); st_hier_free(&h); return 1; }
        r.spec.uv = (st_uv_map){ auto_uv, NULL, h.map.darts.end };
    } else if (r.spec.mode == ST_MODE_UV && !r.adaptive && !(r.spec.uv = st_hier_uv(&h, level)).uv) {
        if (level && st_hier_has_uv(&h, 0))
            fprintf(stderr, "strata render: %s: level %u has no UVs for --mode uv (this scheme keeps those of level 0 only: try --level 0)\n",
                    o.in, level);
        else
            fprintf(stderr, "strata render: %s: no UVs for --mode uv (the file gives no texture coordinates, or the scheme keeps none; "
                            "--auto-uv draws the checker through an atlas of charts)\n",
                    o.in);
        st_hier_free(&h);
        return 1;
    }
    st_error err;
    st_adapt a;
    st_adapt_uv auv;
    memset(&a, 0, sizeof a);
    memset(&auv, 0, sizeof auv);
    const st_map *shown = &h.map; /* the adaptive result: h's top level, or a progressive hierarchy's own map */
    if (r.adaptive) {
        rc = st_mem_check(st_adapt_estimate_bytes(&h, &r.adapt), "the adaptive refinement", &err);
        if (!rc) rc = st_adapt_init(&a, &h, &err);
        if (!rc) rc = st_adapt_update(&a, &r.adapt, &err);
        if (rc) { fprintf(stderr, "strata render: %s: %s\n", o.in, err.msg); st_adapt_free(&a); st_hier_free(&h); return 1; }
        shown = st_adapt_display_map(&a, &level);
        if (!shown) { fprintf(stderr, "strata render: %s: out of memory for the adaptive mesh\n", o.in); st_adapt_free(&a); st_hier_free(&h); return 1; }
        r.spec.level = level;
        /* --mode uv: the adaptive mesh's own UVs (core/adapt/adapt.h) */
        const char *no_uv = r.spec.mode == ST_MODE_UV ? st_adapt_uv_absent(&a) : NULL;
        if (no_uv) { fprintf(stderr, "strata render: %s: no UVs for --mode uv: %s\n", o.in, no_uv); st_adapt_free(&a); st_hier_free(&h); return 1; }
        if (r.spec.mode == ST_MODE_UV && st_adapt_uv_build(&a, &auv, &err)) {
            fprintf(stderr, "strata render: %s: %s\n", o.in, err.msg);
            st_adapt_free(&a);
            st_hier_free(&h);
            return 1;
        }
        if (auv.uv) r.spec.uv = (st_uv_map){ auv.uv, NULL, auv.cap };
        if (shown == &h.map) st_adapt_free(&a);
    }
    st_offscreen off;
    unsigned char *rgba = NULL;
    if (check_image_budget(&r, o.out)) {
        free(auto_uv);
        st_adapt_uv_free(&auv);
        st_adapt_free(&a);
        st_hier_free(&h);
        return 1;
    }
    rc = st_offscreen_init(&off, r.width, r.height, &err);
    if (rc) {
        fprintf(stderr, "strata render: cannot render headless: %s\n", err.msg);
        free(auto_uv);
        st_adapt_uv_free(&auv);
        st_adapt_free(&a);
        st_hier_free(&h);
        return 1;
    }
    rgba = malloc((size_t)r.width * (size_t)r.height * 4);
    if (!rgba) rc = st_fail(&err, ST_ERR_MEMORY, "out of memory for a %dx%d image", r.width, r.height);
    uint32_t faces = 0;
    if (r.normal_map) {
        if (!rc) rc = st_render_normal_mapped(&off, &h, &r.spec, r.normal_map, r.normal_object, r.auto_uv, rgba, &faces, &err);
    } else {
        if (!rc) rc = st_offscreen_prepare(&off, shown, &r.spec, &err);
        faces = off.r.surf.nfaces;
        if (!rc) rc = st_offscreen_draw(&off, &r.spec, rgba, &err);
    }
    if (!rc) rc = st_png_write(o.out, r.width, r.height, rgba, &err);
    st_offscreen_free(&off);
    free(rgba);
    free(auto_uv);
    st_adapt_uv_free(&auv);
    st_adapt_free(&a);
    st_hier_free(&h);
    if (rc) { fprintf(stderr, "strata render: %s\n", err.msg); return 1; }
    if (r.spec.view >= 0)
        printf("wrote %s (%dx%d, %s, level %u, %u faces, %s view)\n", o.out, r.width, r.height,
               st_render_mode_name(r.spec.mode), level, faces, st_view_name(r.spec.view));
    else
        printf("wrote %s (%dx%d, %s, level %u, %u faces, orbit %g,%g,%g)\n", o.out, r.width, r.height,
               st_render_mode_name(r.spec.mode), level, faces, r.spec.az, r.spec.el, r.spec.dist);
    return 0;
}
