/* The bake from a hierarchy to files (formats/bake_run.h). */
#include "bake_run.h"
#include "bake_images.h"
#include "core/base/membudget.h"
#include "core/fvar/fvar.h"
#include "core/io/atomic_file.h"
#include "core/io/mesh.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int st_bake_request_check(const st_bake_request *r, st_error *err)
{
    if (!r->normal_path && !r->disp_path) return st_fail(err, ST_ERR_INVALID, "nothing to bake: no normal map and no displacement map named");
    if (r->normal_path && !st_path_has_ext(r->normal_path, ".png"))
        return st_fail(err, ST_ERR_INVALID, "%s: the normal map is written as .png", r->normal_path);
    if (r->disp_path && !st_path_has_ext(r->disp_path, ".png") && !st_path_has_ext(r->disp_path, ".exr"))
        return st_fail(err, ST_ERR_INVALID, "%s: the displacement map is written as .exr or .png", r->disp_path);
    if (r->vector && !r->disp_path) return st_fail(err, ST_ERR_INVALID, "a vector displacement needs a displacement map");
    if (r->size < 1 || r->size > 16384) return st_fail(err, ST_ERR_INVALID, "a map is 1..16384 texels wide, not %u", r->size);
    if (r->padding > 254) return st_fail(err, ST_ERR_INVALID, "padding is 0..254 texels, not %u", r->padding);
    if (r->bits != 8 && r->bits != 16) return st_fail(err, ST_ERR_INVALID, "a normal map has 8 or 16 bits, not %d", r->bits);
    if (r->udim < -1 || r->udim > 1) return st_fail(err, ST_ERR_INVALID, "UDIM is auto, on or off");
    if (!(r->ray_reach >= 0) || !isfinite(r->ray_reach)) return st_fail(err, ST_ERR_INVALID, "the ray reach is a distance > 0");
    return ST_OK;
}

static void say(const st_bake_request *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void say(const st_bake_request *r, const char *fmt, ...)
{
    if (!r->say) return;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    r->say(r->say_ctx, line);
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

char *st_bake_tile_path(const char *path, unsigned udim)
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
static int write_outputs(const st_bake_request *b, const char *const final[3], const st_bake_maps *maps, st_afile af[3], st_error *err)
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
static size_t writer_bytes(const st_bake_request *b, const st_bake_opts *o)
{
    size_t texels = (size_t)o->size * o->size, ch = b->vector ? 3 : 1, w = 0, d = 0;
    if (b->normal_path) w = texels * 3 * (size_t)(b->bits / 8);
    if (b->disp_path) d = st_path_has_ext(b->disp_path, ".exr") ? 2 * texels * ch * sizeof(float) : texels * ch * 2;
    return w > d ? w : d;
}

static void report(const st_bake_request *b, const char *const final[3], const st_bake_opts *o, const st_bake_maps *maps)
{
    const char *side = final[2];
    char line[1024];
    int n;
    if (b->normal_path)
        say(b, "wrote %s (%ux%u, %s-space normals, %d-bit RGB)", final[0], o->size, o->size,
            o->space == ST_BAKE_TANGENT ? "tangent" : "object", b->bits);
    if (b->disp_path)
        say(b, "wrote %s (%ux%u, %s displacement, %s)%s%s", final[1], o->size, o->size,
            b->vector ? "vector" : "scalar", st_path_has_ext(b->disp_path, ".exr") ? "32-bit float EXR" : "16-bit PNG",
            side ? ", scale and offset in " : "", side ? side : "");
    n = 0;
    if (o->udim) n = snprintf(line, sizeof line, "tile %u (%u faces): ", st_bake_udim(o->tile), maps->faces);
    n += snprintf(line + n, sizeof line - (size_t)n, "level %u onto level %u: %llu texels baked, %llu padded", o->level, o->base,
                  (unsigned long long)maps->baked, (unsigned long long)maps->padded);
    if (maps->disp && n < (int)sizeof line)
        snprintf(line + n, sizeof line - (size_t)n, ", displacement %.6g .. %.6g", maps->disp_min, maps->disp_max);
    say(b, "%s", line);
    say(b, "coverage: %llu of %llu texels baked (%.1f %%)", (unsigned long long)maps->baked,
        (unsigned long long)o->size * o->size, 100.0 * (double)maps->baked / ((double)o->size * o->size));
    if (maps->by_rays)
        say(b, "correspondence: by rays along level %u's normals: %llu texels, %llu misses (filled flat), reach %.6g",
            o->base, (unsigned long long)maps->baked, (unsigned long long)maps->ray_misses, maps->ray_reach);
    else
        say(b, "correspondence: exact (the faces of level %u nest in those of level %u)", o->level, o->base);
}

/* The progress of one tile's bake as a fraction of the whole run. */
typedef struct tile_progress {
    const st_bake_request *r;
    uint32_t tile, ntiles;
    int cancelled;
} tile_progress;

static int tile_fraction(void *ctx, double f)
{
    tile_progress *p = ctx;
    if (p->r->progress(p->r->progress_ctx, (p->tile + f) / p->ntiles)) p->cancelled = 1;
    return p->cancelled;
}

int st_bake_run(st_hier *h, const st_bake_request *b, st_bake_result *res, st_error *err)
{
    memset(res, 0, sizeof *res);
    int rc = st_bake_request_check(b, err);
    if (rc) return rc;
    unsigned level = b->level;
    st_bake_layout lay = { 0 };
    st_bake_maps maps = { 0 };
    st_bake_tiles tiles = { 0 };
    st_afile *af = NULL;
    char **names = NULL;
    uint32_t nt = 0;              /* maps written: tiles, or 1 */
    tile_progress tp = { .r = b };
    st_bake_opts bo = { .base = b->base, .level = level, .size = b->size, .space = b->space,
                        .normal = b->normal_path != NULL, .displacement = b->disp_path ? (b->vector ? 3 : 1) : 0,
                        .padding = b->padding, .ray_reach = b->ray_reach };
    if (b->progress) { bo.progress = tile_fraction; bo.progress_ctx = &tp; }
    if (b->base > h->map.top || level > h->map.top || b->base > level) {
        rc = st_fail(err, ST_ERR_INVALID, "cannot bake level %u onto level %u: levels are 0..%u and the base must not be finer",
                     level, b->base, h->map.top);
        goto done;
    }
    if ((rc = st_bake_check_scheme(h, err))) goto done;
    if (!b->auto_uv && !st_hier_has_uv(h, b->base)) {
        rc = st_fail(err, ST_ERR_INVALID, "level %u has no UVs (the mesh it was made from had none); "
                                          "--auto-uv lays out an atlas of charts", b->base);
        goto done;
    }
    st_uv_stats us;
    rc = b->auto_uv ? st_bake_chart_uvs(h, b->base, b->size, b->padding, &lay, &us, err)
                    : st_bake_level_uvs(h, b->base, &lay, err);
    if (rc) goto done;
    if (b->auto_uv)
        say(b, "note: auto UVs of level %u: %u charts (%u flattened by projection, %u splits), L2 stretch %.4f, "
               "angle error %.2f deg, area ratio %.3f..%.3f (5th..95th percentile), %.1f %% of the square",
            b->base, us.ncharts, us.fallback_charts, us.splits, us.l2_stretch, us.angle_err_deg, us.area_p5, us.area_p95,
            100 * us.uv_area);
    st_bake_uvs uvs = st_bake_layout_uvs(&lay);
    if ((rc = st_mem_check(st_bake_estimate(h, &uvs, &bo) + writer_bytes(b, &bo), "baking and writing the maps", err))) goto done;
    if ((rc = st_bake_uv_tiles(&uvs, bo.size, &tiles, err))) goto done;
    int udim = b->udim;
    if (udim == 1 && tiles.first_non_udim != UINT32_MAX) {
        uint32_t f = tiles.first_non_udim, a = uvs.corner_off[f];
        int32_t t[2];
        st_bake_face_tile(uvs.uv + 2 * (size_t)a, uvs.corner_off[f + 1] - a, t);
        rc = st_fail(err, ST_ERR_INVALID, "face %u of level %u lies in UV tile (%d, %d), which has no UDIM number "
                                          "(u tiles 0..9, v tiles 0..99); --udim off wraps every face into one map",
                     f + 1, b->base, t[0], t[1]);
        goto done;
    }
    if (udim < 0)
        udim = tiles.first_non_udim == UINT32_MAX && !(tiles.ntiles == 1 && tiles.tile[0][0] == 0 && tiles.tile[0][1] == 0);
    if (tiles.corners_outside)
        say(b, "note: %llu of %u corners of level %u lie outside their face's UV tile: baked with wrap-around (texture repeat)",
            (unsigned long long)tiles.corners_outside, uvs.corner_off[uvs.nfaces], b->base);
    if (tiles.faces_crossing)
        say(b, "note: %u faces cross their tile's border by more than a texel and a quarter of the face (first: face %u): "
               "wrapped as well", tiles.faces_crossing, tiles.first_crossing + 1);
    if (!udim && tiles.ntiles > 1) say(b, "note: faces at home in %u UV tiles wrapped into one map (--udim off)", tiles.ntiles);
    nt = udim ? tiles.ntiles : 1;
    tp.ntiles = nt;
    af = calloc(3 * (size_t)nt, sizeof *af);
    names = calloc(3 * (size_t)nt, sizeof *names);
    if (!af || !names) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory"); goto done; }
    /* Each tile baked and written to its temporaries in turn (one tile's
     * maps held at a time); all placed together at the end. */
    for (uint32_t t = 0; t < nt && !rc; t++) {
        unsigned number = 0;
        tp.tile = t;
        if (udim) {
            bo.udim = 1;
            bo.tile[0] = tiles.tile[t][0];
            bo.tile[1] = tiles.tile[t][1];
            number = st_bake_udim(bo.tile);
        }
        char **fin = names + 3 * (size_t)t;
        if (b->normal_path && !(fin[0] = st_bake_tile_path(b->normal_path, number))) rc = 1;
        if (!rc && b->disp_path && !(fin[1] = st_bake_tile_path(b->disp_path, number))) rc = 1;
        if (!rc && fin[1] && st_path_has_ext(fin[1], ".png") && !(fin[2] = sidecar_path(fin[1]))) rc = 1;
        if (rc) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory"); break; }
        if ((rc = st_bake(h, &uvs, &bo, &maps, err))) {
            if (tp.cancelled) res->cancelled = 1;
            else if (udim) {
                st_error e = *err;
                st_fail(err, e.code, "tile %u: %s", number, e.msg);
            }
            break;
        }
        if ((rc = write_outputs(b, (const char *const *)fin, &maps, af + 3 * (size_t)t, err))) res->file_error = 1;
        else {
            report(b, (const char *const *)fin, &bo, &maps);
            res->baked += maps.baked;
            res->ray_misses += maps.ray_misses;
            res->by_rays = maps.by_rays;
        }
        st_bake_maps_free(&maps);
        if (!rc && b->progress && tile_fraction(&tp, 1)) { res->cancelled = 1; rc = st_fail(err, ST_ERR_INVALID, "cancelled"); }
    }
    for (size_t k = 0; af && k < 3 * (size_t)nt; k++) {
        if (rc) { st_afile_abort(&af[k]); continue; }
        if (af[k].tmp && (rc = st_afile_place(&af[k], err))) res->file_error = 1;
    }
    if (!rc) {
        res->maps = nt;
        res->udim = udim;
        if (udim) say(b, "UDIM: %u tiles written", nt);
    }
done:
    for (size_t k = 0; names && k < 3 * (size_t)nt; k++) free(names[k]);
    free(names);
    free(af);
    st_bake_tiles_free(&tiles);
    st_bake_maps_free(&maps);
    st_bake_layout_free(&lay);
    return rc;
}
