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
 * file could not be read or written, 2 bad usage. */
#include "bake_images.h"
#include "cli.h"
#include "cli_common.h"
#include "core/bake/bake.h"
#include "core/base/membudget.h"
#include "core/fvar/fvar.h"
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

/* NAME.json beside a displacement PNG: NAME.png with its extension replaced. */
static char *sidecar_path(const char *png)
{
    size_t n = strlen(png);
    char *s = malloc(n + 6);
    if (!s) return NULL;
    memcpy(s, png, n - 4);
    strcpy(s + n - 4, ".json");
    return s;
}

/* The path of one tile's map: a literal <UDIM> replaced by the tile's
 * number, else the number put before the extension (NAME.1001.png);
 * udim 0 (one image): the path as given, <UDIM> read as 1001. */
static char *tile_path(const char *path, unsigned udim)
{
    size_t n = strlen(path);
    char *s = malloc(n + 16);
    if (!s) return NULL;
    const char *tok = strstr(path, "<UDIM>");
    if (tok) {
        snprintf(s, n + 16, "%.*s%u%s", (int)(tok - path), path, udim ? udim : 1001u, tok + 6);
    } else if (udim) {
        const char *dot = strrchr(path, '.');
        snprintf(s, n + 16, "%.*s.%u%s", (int)(dot - path), path, udim, dot);
    } else {
        memcpy(s, path, n + 1);
    }
    return s;
}

/* Writes every map to its temporary and finishes them all (every write
 * that can fail is then done); the caller places them once every tile is
 * written, so the maps appear together (core/io/atomic_file.h
 * st_afile_finish).  On any failure every temporary of this call is
 * removed; the caller aborts those of earlier tiles, and the old files stay. */
static int write_outputs(const bake_args *b, const char *const final[3], const st_bake_maps *maps, st_afile af[3], st_error *err)
{
    const char *side = final[2];
    memset(af, 0, 3 * sizeof *af);
    int rc = ST_OK;
    for (int k = 0; k < 3 && !rc; k++)
        if (final[k]) rc = st_afile_open(&af[k], final[k], err);
    double offset = 0, scale = 1;
    if (!rc && b->normal_path) rc = st_bake_write_normal_png(&af[0], maps, b->bits, err);
    if (!rc && b->disp_path) rc = st_bake_write_disp(&af[1], maps, &offset, &scale, err);
    if (!rc && side) {
        const char *meaning = !b->vector ? "displacement along the base level's interpolated normal"
                            : b->space == ST_BAKE_TANGENT ? "displacement vector in tangent space (tangent, bitangent, normal)"
                                                         : "displacement vector in object space (x, y, z)";
        rc = st_bake_write_sidecar(&af[2], final[1], maps, meaning, offset, scale, err);
    }
    for (int k = 0; k < 3 && !rc; k++)
        if (af[k].f) rc = st_afile_finish(&af[k], err);
    if (rc)
        for (int k = 0; k < 3; k++) st_afile_abort(&af[k]);
    return rc;
}

/* Bytes the writers add while the maps are held: the PNG rows (8/16-bit
 * samples), the EXR planes and tinyexr's own copy (about as much again,
 * measured: 2048², 3 channels, 84 MiB over the maps). */
static size_t writer_bytes(const bake_args *b, const st_bake_opts *o)
{
    size_t texels = (size_t)o->size * o->size, ch = b->vector ? 3 : 1, w = 0, d = 0;
    if (b->normal_path) w = texels * 3 * (size_t)(b->bits / 8);
    if (b->disp_path) d = st_path_has_ext(b->disp_path, ".exr") ? 2 * texels * ch * sizeof(float) : texels * ch * 2;
    return w > d ? w : d;
}

static void report(const bake_args *b, const char *const final[3], const st_bake_opts *o, const st_bake_maps *maps)
{
    const char *side = final[2];
    if (b->normal_path)
        printf("wrote %s (%ux%u, %s-space normals, %d-bit RGB)\n", final[0], o->size, o->size,
               o->space == ST_BAKE_TANGENT ? "tangent" : "object", b->bits);
    if (b->disp_path)
        printf("wrote %s (%ux%u, %s displacement, %s)%s%s\n", final[1], o->size, o->size,
               b->vector ? "vector" : "scalar", st_path_has_ext(b->disp_path, ".exr") ? "32-bit float EXR" : "16-bit PNG",
               side ? ", scale and offset in " : "", side ? side : "");
    if (o->udim) printf("tile %u (%u faces): ", st_bake_udim(o->tile), maps->faces);
    printf("level %u onto level %u: %llu texels baked, %llu padded", o->level, o->base,
           (unsigned long long)maps->baked, (unsigned long long)maps->padded);
    if (maps->disp) printf(", displacement %.6g .. %.6g", maps->disp_min, maps->disp_max);
    printf("\n");
    printf("coverage: %llu of %llu texels baked (%.1f %%)\n", (unsigned long long)maps->baked,
           (unsigned long long)o->size * o->size, 100.0 * (double)maps->baked / ((double)o->size * o->size));
    if (maps->by_rays)
        printf("correspondence: by rays along level %u's normals: %llu texels, %llu misses (filled flat), reach %.6g\n",
               o->base, (unsigned long long)maps->baked,
               (unsigned long long)maps->ray_misses, maps->ray_reach);
    else
        printf("correspondence: exact (the faces of level %u nest in those of level %u)\n", o->level, o->base);
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
    st_hier h;
    int rc = st_cli_load(&o, &h, "bake");
    if (rc) return rc;
    unsigned level = o.level >= 0 ? (unsigned)o.level : h.map.top;
    st_error err;
    st_bake_layout lay = { 0 };
    st_bake_maps maps = { 0 };
    st_bake_tiles tiles = { 0 };
    st_afile *af = NULL;
    char **names = NULL;
    uint32_t nt = 0;              /* maps written: tiles, or 1 */
    st_bake_opts bo = { .base = (unsigned)b.base, .level = level, .size = b.size, .space = b.space,
                        .normal = b.normal_path != NULL, .displacement = b.disp_path ? (b.vector ? 3 : 1) : 0,
                        .padding = b.padding, .ray_reach = b.ray_reach };
    if ((unsigned)b.base > h.map.top || level > h.map.top || (unsigned)b.base > level) {
        fprintf(stderr, "strata bake: %s: cannot bake level %u onto level %d: levels are 0..%u and the base must not be finer\n",
                o.in, level, b.base, h.map.top);
        rc = 1;
        goto done;
    }
    if (st_bake_check_scheme(&h, &err)) { fprintf(stderr, "strata bake: %s: %s\n", o.in, err.msg); rc = 1; goto done; }
    if (!b.auto_uv && !st_hier_uv(&h, (unsigned)b.base)) {
        fprintf(stderr, "strata bake: %s: level %d has no UVs (the mesh it was made from had none); "
                        "--auto-uv lays out an atlas of charts\n", o.in, b.base);
        rc = 1;
        goto done;
    }
    st_uv_stats us;
    rc = b.auto_uv ? st_bake_chart_uvs(&h, (unsigned)b.base, b.size, b.padding, &lay, &us, &err)
                   : st_bake_level_uvs(&h, (unsigned)b.base, &lay, &err);
    if (rc) { fprintf(stderr, "strata bake: %s: %s\n", o.in, err.msg); rc = 1; goto done; }
    if (b.auto_uv)
        printf("note: auto UVs of level %d: %u charts (%u flattened by projection, %u splits), L2 stretch %.4f, "
               "angle error %.2f deg, area ratio %.3f..%.3f (5th..95th percentile), %.1f %% of the square\n",
               b.base, us.ncharts, us.fallback_charts, us.splits, us.l2_stretch, us.angle_err_deg, us.area_p5, us.area_p95,
               100 * us.uv_area);
    st_bake_uvs uvs = st_bake_layout_uvs(&lay);
    if (st_mem_check(st_bake_estimate(&h, &uvs, &bo) + writer_bytes(&b, &bo), "baking and writing the maps", &err)) {
        fprintf(stderr, "strata bake: %s: %s\n", o.in, err.msg);
        rc = 1;
        goto done;
    }
    if (st_bake_uv_tiles(&uvs, bo.size, &tiles, &err)) { fprintf(stderr, "strata bake: %s: %s\n", o.in, err.msg); rc = 1; goto done; }
    int udim = b.udim;
    if (udim == 1 && tiles.first_non_udim != UINT32_MAX) {
        uint32_t f = tiles.first_non_udim, a = uvs.corner_off[f];
        int32_t t[2];
        st_bake_face_tile(uvs.uv + 2 * (size_t)a, uvs.corner_off[f + 1] - a, t);
        fprintf(stderr, "strata bake: %s: face %u of level %d lies in UV tile (%d, %d), which has no UDIM number "
                        "(u tiles 0..9, v tiles 0..99); --udim off wraps every face into one map\n",
                o.in, f + 1, b.base, t[0], t[1]);
        rc = 1;
        goto done;
    }
    if (udim < 0)
        udim = tiles.first_non_udim == UINT32_MAX && !(tiles.ntiles == 1 && tiles.tile[0][0] == 0 && tiles.tile[0][1] == 0);
    if (tiles.corners_outside)
        printf("note: %llu of %u corners of level %d lie outside their face's UV tile: baked with wrap-around (texture repeat)\n",
               (unsigned long long)tiles.corners_outside, uvs.corner_off[uvs.nfaces], b.base);
    if (tiles.faces_crossing)
        printf("note: %u faces cross their tile's border by more than a texel and a quarter of the face (first: face %u): "
               "wrapped as well\n", tiles.faces_crossing, tiles.first_crossing + 1);
    if (!udim && tiles.ntiles > 1) printf("note: faces at home in %u UV tiles wrapped into one map (--udim off)\n", tiles.ntiles);
    nt = udim ? tiles.ntiles : 1;
    af = calloc(3 * (size_t)nt, sizeof *af);
    names = calloc(3 * (size_t)nt, sizeof *names);
    if (!af || !names) { rc = 1; goto done; }
    /* Each tile baked and written to its temporaries in turn (one tile's
     * maps held at a time); all placed together at the end. */
    for (uint32_t t = 0; t < nt && !rc; t++) {
        unsigned number = 0;
        if (udim) {
            bo.udim = 1;
            bo.tile[0] = tiles.tile[t][0];
            bo.tile[1] = tiles.tile[t][1];
            number = st_bake_udim(bo.tile);
        }
        char **fin = names + 3 * (size_t)t;
        if (b.normal_path && !(fin[0] = tile_path(b.normal_path, number))) rc = 1;
        if (!rc && b.disp_path && !(fin[1] = tile_path(b.disp_path, number))) rc = 1;
        if (!rc && fin[1] && st_path_has_ext(fin[1], ".png") && !(fin[2] = sidecar_path(fin[1]))) rc = 1;
        if (rc) { fprintf(stderr, "strata bake: out of memory\n"); break; }
        if (st_bake(&h, &uvs, &bo, &maps, &err)) {
            if (udim) fprintf(stderr, "strata bake: %s: tile %u: %s\n", o.in, number, err.msg);
            else fprintf(stderr, "strata bake: %s: %s\n", o.in, err.msg);
            rc = 1;
            break;
        }
        if (write_outputs(&b, (const char *const *)fin, &maps, af + 3 * (size_t)t, &err)) { fprintf(stderr, "strata: %s\n", err.msg); rc = 1; }
        else report(&b, (const char *const *)fin, &bo, &maps);
        st_bake_maps_free(&maps);
    }
    for (size_t k = 0; af && k < 3 * (size_t)nt; k++) {
        if (rc) { st_afile_abort(&af[k]); continue; }
        if (af[k].tmp && st_afile_place(&af[k], &err)) { fprintf(stderr, "strata: %s\n", err.msg); rc = 1; }
    }
    if (!rc && udim) printf("UDIM: %u tiles written\n", nt);
done:
    for (size_t k = 0; names && k < 3 * (size_t)nt; k++) free(names[k]);
    free(names);
    free(af);
    st_bake_tiles_free(&tiles);
    st_bake_maps_free(&maps);
    st_bake_layout_free(&lay);
    st_hier_free(&h);
    return rc;
}
