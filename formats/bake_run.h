/* The bake from a hierarchy to files: what `strata bake` does after parsing
 * its arguments, and what the window's Bake menu runs as a job (ui/jobs.c).
 *
 * st_bake_run lays out level B's UVs (its own, or the atlas of charts of
 * st_bake_chart_uvs for the size and padding), decides the UDIM tiles (core/bake/bake.h: tiles and
 * wrap-around), bakes each tile in turn (one tile's maps held at a time)
 * and writes every map to its temporary (core/io/atomic_file.h); the
 * temporaries are renamed only once all are written and synced, so a
 * refusal, a cancellation or a failed write leaves the old files, and a
 * kill leaves the old maps or the new ones.  Map names: with UDIM tiles a
 * literal <UDIM> in the name is replaced by the tile's number
 * (1001 + u + 10 v), else the number goes before the extension
 * (NAME.1001.png); one image: the name as given, <UDIM> read as 1001.  A
 * 16-bit displacement PNG gets NAME.json beside it (bake_images.h). */
#ifndef ST_BAKE_RUN_H
#define ST_BAKE_RUN_H

#include <stddef.h>
#include <stdint.h>

#include "core/bake/bake.h"

typedef struct st_bake_request {
    const char *normal_path;      /* .png, or NULL */
    const char *disp_path;        /* .exr or .png, or NULL; one of the two is needed */
    unsigned base, level;         /* B <= L <= top */
    uint32_t size;                /* texels per side, 1..16384 */
    uint32_t padding;             /* texels of dilation, 0..254 */
    int bits;                     /* the normal map's 8 or 16 bits per channel */
    int space;                    /* enum st_bake_space */
    int vector;                   /* the displacement as a vector (3 channels) */
    int auto_uv;                  /* bake onto st_bake_chart_uvs instead of B's own UVs */
    int udim;                     /* -1 auto (tiles when every face is at home in a UDIM tile and
                                     not all in 1001), 0 one map, 1 tiles (refused when a face has none) */
    double ray_reach;             /* 0: the default (core/bake/bake.h) */
    /* Optional: the fraction done (0..1) on the calling thread; non-zero
     * cancels (the old files stay, err says "cancelled"). */
    int (*progress)(void *ctx, double fraction);
    void *progress_ctx;
    /* Optional: notes and the per-map report, one line each without '\n'
     * (strata bake prints them). */
    void (*say)(void *ctx, const char *line);
    void *say_ctx;
} st_bake_request;

typedef struct st_bake_result {
    uint32_t maps;                /* images baked: tiles, or 1 */
    int udim;                     /* 1: one image per UDIM tile */
    uint64_t baked, ray_misses;   /* texels, over every tile */
    int by_rays;                  /* the correspondence (core/bake/bake.h) */
    int cancelled;                /* the progress callback asked to stop */
    int file_error;               /* on failure: err names the file that could not be written */
} st_bake_result;

/* Checks the request alone (paths and their extensions, the numbers),
 * without the hierarchy: ST_OK, or ST_ERR_INVALID with a message. */
int st_bake_request_check(const st_bake_request *r, st_error *err);

/* The bake (see above).  ST_OK with *res filled, or an error whose message
 * says what was refused (levels, UVs, tiles, the memory budget) or, with
 * res->file_error, names the file that could not be written. */
int st_bake_run(st_hier *h, const st_bake_request *r, st_bake_result *res, st_error *err);

/* The path of one tile's map (see above; udim 0: one image), malloc'ed. */
char *st_bake_tile_path(const char *path, unsigned udim);

#endif
