/* Rebuild levels: a dense mesh made into a hierarchy with coarse editing
 * levels, by one of two methods, the same for `strata rebuild`
 * (app/cmd_rebuild.c) and the window's "rebuild levels" (ui/doc/editor_rebuild.c):
 *   - unsubdivide (core/rebuild/unsubdivide.h): the mesh has subdivision
 *     connectivity; the cage and the depth are recovered, positions by the
 *     analysis; OBJ tags (creases, corners, holes) and UVs are carried to
 *     the cage so that refinement gives them back;
 *   - progressive (core/progressive/progressive.h; Kraemer 2008 §4.4):
 *     any manifold mesh, by grouped independent edge collapses; edge
 *     collapses have no rule for tags or UVs, so they are dropped and a
 *     note names what was dropped;
 *   - auto: unsubdivide, and when it refuses, progressive (the refusal is
 *     reported).
 * The finest level reproduces the input exactly either way. */
#ifndef ST_REBUILD_H
#define ST_REBUILD_H

#include <stdint.h>

#include "core/io/mesh.h"
#include "core/multires/hier.h"

enum st_rebuild_method { ST_REBUILD_AUTO, ST_REBUILD_UNSUBDIVIDE, ST_REBUILD_PROGRESSIVE };

typedef struct st_rebuild_opts {
    int method;                /* enum st_rebuild_method */
    const char *scheme;        /* unsubdivide's scheme; NULL: by the pattern (Catmull-Clark for the
                                  polygon split, Loop for quadrisection) */
    int uv_interp;             /* enum st_uv_interp: how unsubdivide's cage UVs are refined */
    unsigned max_levels;       /* at most this many levels removed; 0: no limit */
    uint32_t target_faces;     /* 0: unsubdivide none, progressive 1 % of the input's faces (at least 4) */
    /* Called with the fraction done (progressive: after each level;
     * unsubdivide: once, at the end); a non-zero return cancels
     * (ST_ERR_INVALID, "cancelled"), nothing built.  May be NULL. */
    int (*progress)(void *ctx, double fraction);
    void *progress_ctx;
} st_rebuild_opts;

typedef struct st_rebuild_report {
    int method;                /* ST_REBUILD_UNSUBDIVIDE or _PROGRESSIVE: the one that built */
    int wrong_scheme;          /* failed because opts.scheme refines otherwise than the pattern found */
    char refusal[1024];        /* auto fell back to progressive: unsubdivide's refusal; else "" */
    char warning[256];         /* an option that did not apply (a scheme for progressive); else "" */
    char summary[512];         /* one line: method, levels, faces (the CLI's first line) */
    char brief[256];           /* the same, short (the window's message) */
    char stop[1024];           /* unsubdivide: why no further step was taken; else "" */
    /* What else to know, one line each: the tags and UVs unsubdivide kept,
     * what progressive triangulated or dropped, why it stopped early. */
    st_notes notes;
    unsigned levels;           /* levels built: 0..levels-1 */
    uint32_t cage_faces;       /* faces of level 0 */
} st_rebuild_report;

void st_rebuild_report_free(st_rebuild_report *rep);

/* Builds the hierarchy of `in` (a repaired mesh, st_mesh_repair) into *h
 * (left empty on failure; rep filled either way as far as it got).  `name`
 * (the file) prefixes refusals. */
int st_rebuild(const char *name, const st_mesh *in, const st_rebuild_opts *o, st_hier *h,
               st_rebuild_report *rep, st_error *err);

/* Level l of h as the input of a rebuild: its faces, positions and UVs
 * (st_hier_level_mesh), hole faces, and its edge and vertex sharpness as
 * crease and corner tags, with h's boundary, crease and triangle options,
 * so that rebuilding a hierarchy's finest level (the window) sees what
 * `strata rebuild` sees in a file holding that level with its tags. */
int st_rebuild_level_input(st_hier *h, unsigned l, st_mesh *out, st_error *err);

#endif
