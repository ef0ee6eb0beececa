/* Session files (.strata): everything needed to continue work exactly.
 * The format is documented in docs/SESSION-FORMAT.md.
 *
 * What is stored: the hierarchy as it is in memory (the map's pools and
 * every multilevel attribute: β0, β1, vertex relation, positions of every
 * level, sharpness; the detail vectors of every level), the scheme by name
 * and its options, the adaptive state (saved details of coarsened regions,
 * base faces, last criteria) when present, the interest box and whether it
 * is on, the editing and displayed levels, the camera (st_session_view),
 * and optionally the base mesh as loaded.  Nothing is regenerated on load:
 * dart and vertex ids, hence local frames and every later operation, are
 * those of the session that was saved, and load -> save gives the same
 * bytes.
 *
 * Reading is bounded and checked: magic, version, header checksum, total
 * size, CRC-32 of the whole file, then every count against the bytes left,
 * every structure (pools, relations at every level, st_map_validate, finite
 * positions and details).  A failed load leaves *out untouched and returns
 * a one-line message naming the file.
 *
 * Saving is crash-safe (core/io/atomic_file.h): a temporary next to the file,
 * fsync, rename over the old file, fsync of the directory.
 *
 * Typical use by the window (ui/):
 *     st_session_ref r = { .h = &doc->h, .adapt = doc->box_on ? &doc->adapt : NULL,
 *                          .box = &doc->box, .box_on = doc->box_on,
 *                          .edit_level = doc->edit_level, .display_level = doc->display_level,
 *                          .view = &view, .base = &doc->base };
 *     st_session_save_ref(path, &r, &err);          // Save
 *     char rec[4096];
 *     if (st_session_recovery_path(rec, sizeof rec) == 0)
 *         st_session_save_ref(rec, &r, &err);       // autosave after edits
 *     st_session s;
 *     if (st_session_load(path, &s, &err) == 0) {   // Open
 *         st_session_move_hier(&doc->h, &s.h);      // re-points attributes
 *         if (s.has_adapt) st_session_move_adapt(&doc->adapt, &s.adapt, &doc->h);
 *         ... copy box, levels, view; st_mesh_move(&doc->base, &s.base) ...
 *         (s.has_hd: the HD hierarchy, moved the same way with
 *          st_session_move_hier(&doc->hd, &s.hd) and
 *          st_session_move_adapt(&doc->hd_adapt, &s.hd_adapt, &doc->hd))
 *         st_session_free(&s);
 *     }
 * An st_hier or st_adapt must not be copied with memcpy/assignment: the map
 * points at the hierarchy's sharpness attributes and the adaptive state at
 * its hierarchy; the move functions fix those pointers.
 */
#ifndef ST_SESSION_H
#define ST_SESSION_H

#include <stddef.h>
#include <stdint.h>

#include "core/adapt/adapt.h"
#include "core/multires/hier.h"
#include "core/multires/layers.h"
#include "core/multires/mask.h"
#include "core/io/mesh.h"

/* The version written, and the newest read: 1 the first; 2 added
 * face-varying UVs; 3 stores attribute arrays only up to the last live id;
 * 4 regenerates subdivision levels from level 0 (LVL0), 5 progressive
 * levels from their splits (PMRC) (docs/SESSION-FORMAT.md).  Versions 1
 * to 4 are still read. */
#define ST_SESSION_VERSION 5u
#define ST_SESSION_MAGIC "STRATASN"

/* The camera, as the window's render camera describes it (orbit around
 * target: azimuth and elevation in radians, distance; vertical field of
 * view in radians; orthographic with a view height when ortho != 0). */
typedef struct st_session_view {
    float target[3], az, el, dist, fovy;
    int ortho;
    float ortho_height;
} st_session_view;

/* The window's settings a user expects back with the model (as Blender
 * keeps a file's tool settings and overlays): the brush tool (an index,
 * ST_SESSION_NO_TOOL for selection), its radius in object units, strength
 * and falloff, the mirror axes (bits 1 x, 2 y, 4 z) and the display toggles
 * (bits ST_SESSION_SHOW_*).  Core stores the numbers; ui gives them
 * meaning.  Ancillary chunk `tool`: older readers skip it. */
#define ST_SESSION_NO_TOOL 0xffffffffu
enum { ST_SESSION_SHOW_CAGE = 1, ST_SESSION_SHOW_WIRE = 2, ST_SESSION_SHOW_FLAT = 4, ST_SESSION_SHOW_CHECKER = 8 };
typedef struct st_session_tool {
    uint32_t tool;                 /* < 256, or ST_SESSION_NO_TOOL */
    double radius;                 /* finite, > 0 */
    double strength;               /* finite, 0..1 */
    uint32_t falloff;              /* < 256 */
    uint32_t mirror;               /* bits 1 x, 2 y, 4 z */
    uint32_t show;                 /* ST_SESSION_SHOW_* bits */
} st_session_tool;

/* A loaded session; owns everything in it. */
typedef struct st_session {
    st_hier h;                     /* always valid after a successful load */
    int has_adapt;
    st_adapt adapt;                /* adapt.h == &h (st_session_move keeps it so) */
    st_adapt_params box;           /* the interest box and its levels */
    int box_on;
    unsigned edit_level, display_level;
    int has_view;
    st_session_view view;
    int has_base;
    st_mesh base;                  /* the control mesh as loaded, if stored */
    st_layers layers;              /* sculpt layers (empty when none were stored) */
    st_mask mask;                  /* sculpting mask (zero when none was stored) */
    int has_tool;
    st_session_tool tool;          /* the window's settings (has_tool: stored) */
    /* The HD hierarchy (ancillary chunk `hdlv`, docs/SESSION-FORMAT.md): an
     * adaptive hierarchy whose levels 0..hd_from are copies of h's (same
     * dart and vertex ids, same positions) and whose levels above are
     * refined only where the user sculpted.  The ids of the levels above
     * are those of the file, packed (the writer renumbers them,
     * core/map/renumber_internal.h), not those of the document that saved it.
     * has_hd 0: none (hd is then an empty hierarchy and hd_adapt zero). */
    int has_hd;
    unsigned hd_from;              /* h's top level when the HD hierarchy was made */
    st_hier hd;
    st_adapt hd_adapt;             /* hd_adapt.h == &hd (st_session_move keeps it so) */
    st_layers hd_layers;           /* sculpt layers of the HD levels (each above hd_from; offsets by hd's
                                      vertex ids), stored in the hdlv image; empty when none */
} st_session;

/* What to save, by reference (nothing is copied). */
typedef struct st_session_ref {
    const st_hier *h;              /* required */
    const st_adapt *adapt;         /* NULL: no adaptive state (must belong to h) */
    const st_adapt_params *box;    /* NULL: none (stored as zeros, off) */
    int box_on;
    unsigned edit_level, display_level;   /* clamped to 0..top when written */
    const st_session_view *view;   /* NULL: none */
    const st_mesh *base;           /* NULL: none */
    const st_layers *layers;       /* NULL or empty: none (must belong to h) */
    const st_mask *mask;           /* NULL or all zero: none */
    const st_session_tool *tool;   /* NULL: none */
    /* Non-zero: every level's topology and UVs written out (MAP), even when
     * the reader could regenerate them from level 0 (LVL0, POSN): for
     * tests that compare what a load gives, level by level. */
    int whole_map;
    /* The HD hierarchy (see st_session): NULL, no `hdlv` chunk.  hd_adapt
     * must belong to hd, hd must have h's scheme and hd_from be h's top. */
    const st_hier *hd;
    const st_adapt *hd_adapt;
    unsigned hd_from;
    const st_layers *hd_layers;    /* NULL or empty: none; else layers of hd's levels above hd_from only */
} st_session_ref;

void st_session_init(st_session *s);
void st_session_free(st_session *s);
/* Moves src into dst (dst freed first), fixing internal pointers. */
void st_session_move(st_session *dst, st_session *src);
/* Moves a hierarchy / adaptive state (dst overwritten without being freed;
 * src left empty).  The adaptive state is re-pointed at h. */
void st_session_move_hier(st_hier *dst, st_hier *src);
void st_session_move_adapt(st_adapt *dst, st_adapt *src, st_hier *h);
/* The reference form of a loaded session. */
st_session_ref st_session_ref_of(const st_session *s);

/* Crash-safe save (see above).  Refused: hierarchies with attributes this
 * format does not know (a map attribute other than the sharpness). */
int st_session_save_ref(const char *path, const st_session_ref *r, st_error *err);
/* The same, calling progress(ctx, fraction of the bytes written) after
 * each buffer written (64 KiB); a non-zero return stops the save
 * (ST_ERR_INVALID, "cancelled"): the temporary is removed and the file at
 * path is as it was, or absent if it was.  progress NULL: as above. */
int st_session_save_ref_progress(const char *path, const st_session_ref *r, int (*progress)(void *ctx, double fraction),
                                 void *ctx, st_error *err);
int st_session_save(const char *path, const st_session *s, st_error *err);
/* The same bytes into a malloc'ed buffer (*data freed by the caller). */
int st_session_write_mem(const st_session_ref *r, void **data, size_t *size, st_error *err);

/* Loads path into *out (initialised here).  On failure *out is left as it
 * was (not even initialised) and err names the file. */
int st_session_load(const char *path, st_session *out, st_error *err);
/* Parses a session from memory; name is used in messages. */
int st_session_parse(const char *name, const void *data, size_t size, st_session *out, st_error *err);

/* Recovery file for autosave: $STRATA_RECOVERY if set, else
 * $XDG_STATE_HOME/strata/recovery.strata, else
 * $HOME/.local/state/strata/recovery.strata.  Creates the parent
 * directories.  0, or -1 when no path can be made (buf too small, no HOME,
 * directories cannot be created). */
int st_session_recovery_path(char *buf, size_t n);

/* Whether path ends in ".strata" (case-insensitive). */
int st_session_is_path(const char *path);

#endif
