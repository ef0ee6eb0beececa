/* strata bake IN --base-level B [--level L] --normal-map N.png
 *             [--displacement-map D.exr|D.png] [--size 2048] [--space tangent|object]
 *             [--vector] [--padding 8] [--bits 8|16] [--auto-uv] [--ray-reach D]
 *             [--udim auto|on|off]
 *
 * Bakes the surface of level L (default: the finest) onto the UV layout of
 * level B (core/bake/bake.h): B's own UVs (core/fvar/fvar.h), or with
 * --auto-uv a generated atlas of charts (st_bake_chart_uvs, core/uv/uv.h:
 * charts of similar normal flattened by LSCM, packed for --size with
 * --padding texels between them; a note gives its charts and distortion),
 * which a level without UVs needs; without either the command says level B
 * has no UVs.  Every bake prints the texels it wrote as a share of the map.
 * √3 and Doo-Sabin levels are baked by rays along B's normals (--ray-reach:
 * how far, in model units; default from the bounding boxes), and the
 * output says which correspondence was used and how many texels missed.
 * UVs may lie in any tile (core/bake/bake.h: tiles and wrap-around): with
 * --udim auto (the default) a layout whose faces are at home in tiles other
 * than 1001 alone, all with UDIM numbers, is baked one image per tile,
 * NAME.1001.png, NAME.1002.png ... (1001 + u + 10 v, Mari's and Blender's
 * numbering; a literal <UDIM> in the name is replaced instead); --udim off
 * wraps every face into the one image; --udim on insists on tiles.  Corners
 * outside their tile are counted in a note and baked with wrap-around.
 * Islands that overlap are refused by st_bake.  Every file is
 * written to its temporary (core/io/atomic_file.h) and the temporaries are
 * renamed only once all are written and synced, so a refusal or a failed
 * write leaves the old files, and a kill leaves the old maps or the new
 * ones, except in the few microseconds between the renames.  Exit status: 0 done, 1 refused or a
 * file could not be read or written, 2 bad usage.
 *
 * HD levels (core/io/session.h): a session holding them is baked from its
 * HD hierarchy when no --level is given (its top: the finest existing face
 * at each texel) or when --level is above the model's top N (an HD level,
 * refused above the HD top).  Its levels 0..N are copies of the model's,
 * same ids and UVs, so level B there is the model's level B and the whole
 * bake runs on the HD hierarchy: the nested walk takes each face where it
 * stopped being subdivided (core/bake/bake.h), so HD detail leaves as
 * normal and displacement maps and everything else bakes as from level N. */
#include "formats/bake_run.h"
#include "cli.h"
#include "cli_common.h"
#include "core/bake/bake.h"
#include "core/io/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int usage(void)
{
    fprintf(stderr,
            "usage: strata bake IN --base-level B [--level L] --normal-map N.png [--displacement-map D.exr|D.png]\n"
            "                   [--size 2048] [--space tangent|object] [--vector] [--padding 8] [--bits 8|16] [--auto-uv]\n"
            "                   [--ray-reach D] [--udim auto|on|off]\n");
    return 2;
}

typedef struct bake_args {
    const char *normal_path, *disp_path;
    int base;                 /* -1: not given */
    unsigned size, padding;
    int bits, space, vector, auto_uv;
    int udim;                 /* -1 auto, 0 off, 1 on */
    double ray_reach;         /* 0: the default */
} bake_args;

static int parse_unsigned(const char *s, unsigned lo, unsigned hi, unsigned *out)
{
    char *end;
    unsigned long v = strtoul(s, &end, 10);
    if (!*s || *end || s[0] == '-' || v < lo || v > hi) return -1;
    *out = (unsigned)v;
    return 0;
}

/* Takes bake's own options out of argv; the rest (IN, --level, --scheme,
 * --levels, --boundary) goes to st_cli_parse. */
static int split_args(int argc, char **argv, bake_args *b, char **rest, int *nrest)
{
    *nrest = 0;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        unsigned u;
        if (!strcmp(a, "--normal-map") && v) { b->normal_path = v; i++; }
        else if (!strcmp(a, "--displacement-map") && v) { b->disp_path = v; i++; }
        else if (!strcmp(a, "--base-level") && v) {
            if (parse_unsigned(v, 0, ST_MAX_LEVELS - 1, &u)) { fprintf(stderr, "strata bake: --base-level wants a level number, got '%s'\n", v); return -1; }
            b->base = (int)u;
            i++;
        } else if (!strcmp(a, "--size") && v) {
            if (parse_unsigned(v, 1, 16384, &b->size)) { fprintf(stderr, "strata bake: --size wants 1..16384 texels, got '%s'\n", v); return -1; }
            i++;
        } else if (!strcmp(a, "--padding") && v) {
            if (parse_unsigned(v, 0, 254, &b->padding)) { fprintf(stderr, "strata bake: --padding wants 0..254 texels, got '%s'\n", v); return -1; }
            i++;
        } else if (!strcmp(a, "--bits") && v) {
            if (parse_unsigned(v, 8, 16, &u) || (u != 8 && u != 16)) { fprintf(stderr, "strata bake: --bits wants 8 or 16, got '%s'\n", v); return -1; }
            b->bits = (int)u;
            i++;
        } else if (!strcmp(a, "--space") && v) {
            if (!strcmp(v, "tangent")) b->space = ST_BAKE_TANGENT;
            else if (!strcmp(v, "object")) b->space = ST_BAKE_OBJECT;
            else { fprintf(stderr, "strata bake: --space wants tangent or object, got '%s'\n", v); return -1; }
            i++;
        } else if (!strcmp(a, "--ray-reach") && v) {
            char *end;
            double r = strtod(v, &end);
            if (!*v || *end || !(r > 0) || !isfinite(r)) { fprintf(stderr, "strata bake: --ray-reach wants a distance > 0, got '%s'\n", v); return -1; }
            b->ray_reach = r;
            i++;
        } else if (!strcmp(a, "--udim") && v) {
            if (!strcmp(v, "auto")) b->udim = -1;
            else if (!strcmp(v, "on")) b->udim = 1;
            else if (!strcmp(v, "off")) b->udim = 0;
            else { fprintf(stderr, "strata bake: --udim wants auto, on or off, got '%s'\n", v); return -1; }
            i++;
        } else if (!strcmp(a, "--vector")) b->vector = 1;
        else if (!strcmp(a, "--auto-uv")) b->auto_uv = 1;
        else rest[(*nrest)++] = argv[i];
    }
    return 0;
}

static int check_paths(const bake_args *b)
{
    if (!b->normal_path && !b->disp_path) { fprintf(stderr, "strata bake: nothing to bake: give --normal-map and/or --displacement-map\n"); return -1; }
    if (b->base < 0) { fprintf(stderr, "strata bake: --base-level B is required (the level whose UVs receive the maps)\n"); return -1; }
    if (b->normal_path && !st_path_has_ext(b->normal_path, ".png")) { fprintf(stderr, "strata bake: %s: the normal map is written as .png\n", b->normal_path); return -1; }
    if (b->disp_path && !st_path_has_ext(b->disp_path, ".png") && !st_path_has_ext(b->disp_path, ".exr")) {
        fprintf(stderr, "strata bake: %s: the displacement map is written as .exr or .png\n", b->disp_path);
        return -1;
    }
    if (b->vector && !b->disp_path) { fprintf(stderr, "strata bake: --vector applies to --displacement-map\n"); return -1; }
    return 0;
}

/* The hierarchy and level baked from s (see above), or NULL after a
 * message. */
static st_hier *bake_source(const st_cli_opts *o, st_session *s, unsigned *level)
{
    unsigned N = s->h.map.top;
    int hd = s->has_hd && (o->level < 0 || (unsigned)o->level > N);
    if (hd && s->hd_from != N) {
        /* --levels refined the model past the level the HD levels grew from. */
        fprintf(stderr, "strata bake: note: %s's HD levels grow from level %u, the model is now refined to %u: baked without them\n",
                o->in, s->hd_from, N);
        hd = 0;
    }
    if (!hd) {
        *level = o->level >= 0 ? (unsigned)o->level : N;
        return &s->h;
    }
    unsigned top = s->hd.map.top;
    if (o->level >= 0 && (unsigned)o->level > top) {
        fprintf(stderr, "strata bake: --level %d does not exist in %s: its model has levels 0..%u and its HD levels go up to %u\n",
                o->level, o->in, N, top);
        return NULL;
    }
    *level = o->level >= 0 ? (unsigned)o->level : top;
    printf("%s: baking from the HD levels (%u..%u above the model's 0..%u): level %u, each texel from the finest face there\n",
           o->in, N + 1, top, N, *level);
    return &s->hd;
}

static void print_line(void *ctx, const char *line)
{
    (void)ctx;
    printf("%s\n", line);
}

int st_cmd_bake(int argc, char **argv)
{
    bake_args b = { .base = -1, .size = 2048, .padding = 8, .bits = 8, .space = ST_BAKE_TANGENT, .udim = -1 };
    char **rest = malloc((size_t)(argc ? argc : 1) * sizeof *rest);
    int nrest = 0;
    st_cli_opts o;
    if (!rest) return 1;
    if (split_args(argc, argv, &b, rest, &nrest) || st_cli_parse(nrest, rest, &o, "bake") || check_paths(&b)) {
        free(rest);
        return usage();
    }
    free(rest);
    if (o.out) { fprintf(stderr, "strata bake: -o does not apply: name the maps with --normal-map and --displacement-map\n"); return usage(); }
    st_session s;
    int rc = st_cli_load_session(&o, &s, "bake");
    if (rc) return rc;
    unsigned level = 0;
    st_hier *h = bake_source(&o, &s, &level);
    if (!h) { st_session_free(&s); return 1; }
    st_bake_request r = { .normal_path = b.normal_path, .disp_path = b.disp_path, .base = (unsigned)b.base,
                          .level = level, .size = b.size, .padding = b.padding,
                          .bits = b.bits, .space = b.space, .vector = b.vector, .auto_uv = b.auto_uv, .udim = b.udim,
                          .ray_reach = b.ray_reach, .say = print_line };
    st_bake_result res;
    st_error err;
    rc = st_bake_run(h, &r, &res, &err);
    if (rc && res.file_error) fprintf(stderr, "strata: %s\n", err.msg);
    else if (rc) fprintf(stderr, "strata bake: %s: %s\n", o.in, err.msg);
    st_session_free(&s);
    return rc ? 1 : 0;
}
