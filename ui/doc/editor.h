/* st_doc: the modeller's document and every editing operation on it, with no
 * GL and no window.  The window (ui/window.c) turns events into
 * calls here and then asks what changed (st_doc_change) to update the
 * renderer; tests and the interaction benchmark drive the same calls
 * headless.
 *
 * State: the loaded base mesh (kept so the scheme can be changed), the
 * hierarchy, the adaptive state when the interest box is on, the editing
 * level (whose vertices are picked, dragged and brushed: Blender multires'
 * "sculpt level") and the displayed level ("viewport level"), the selection
 * (vertex ids of the editing level), the brush, and the undo history.
 *
 * Conventions (Blender multires / ZBrush, chosen where the requirements are silent):
 *   - editing at level i moves P_i; every finer level follows with its
 *     details (st_hier_move); coarser levels never move;
 *   - the displayed level is >= the editing level and <= top; adding a level
 *     shows it; with the interest box on, the display is the adaptive mesh
 *     st_doc_display_hier() at st_doc_display_map_level() (its top level,
 *     refined between the box's base and max levels);
 *   - the model is always the regular hierarchy h: drags, brushes, levels
 *     and undo act on h at the editing level, also with the box on; the
 *     box's display is derived from h (same positions for every level h
 *     has, synthesised beyond h's top) and follows every edit, so box on,
 *     edit, box off, box on never loses or rotates a detail (editor_display.c);
 *   - every operation that changes the model is one undo step; a drag or a
 *     brush stroke (begin .. end) is one step however many updates it had;
 *     undo and redo restore positions and details bit for bit (undo.c);
 *     adding a level keeps nothing (undo removes it, redo refines again
 *     with the same ids), removing the finest keeps that level's positions
 *     and details, rebase and scheme changes keep a whole copy of the other
 *     hierarchy; the history is bounded by undo_budget (oldest steps
 *     dropped first, `note` says so).
 *
 * Errors: operations return 0, or non-zero with err filled and the document
 * unchanged (a failed open keeps the current model).  Non-fatal messages
 * (repairs made while loading, history dropped, box switched off) are left
 * in `note`. */
#ifndef ST_EDITOR_H
#define ST_EDITOR_H

#include <stddef.h>
#include <stdint.h>

#include "core/adapt/adapt.h"
#include "core/multires/edit.h"
#include "core/multires/layers.h"
#include "core/multires/mask.h"
#include "core/io/mesh.h"
#include "core/io/session.h"
#include "core/sculpt/sculpt.h"
#include "editor_display.h"

/* Brushes: the tools (enum st_brush_tool) and falloff presets (enum
 * st_falloff, st_falloff_eval) are the sculpting kernel's
 * (core/sculpt/sculpt.h); the document keeps the settings (st_brush) and
 * the stroke (brush.c). */
const char *st_brush_name(int tool);

typedef struct st_brush {
    int tool;                  /* enum st_brush_tool */
    double radius;             /* object units (one radius for every brush, as Blender's unified size) */
    double strength;           /* 0..1, of the current tool */
    int falloff;               /* enum st_falloff, of the current tool */
    int mirror_x;              /* symmetry across the plane x = 0 of object space */
    int mirror_y;              /* ... y = 0 */
    int mirror_z;              /* ... z = 0 */
    int invert;                /* the stroke's opposite direction (Ctrl held): in instead of out */
    int front_only;            /* front faces only: vertices whose normal faces away from the viewer
                                  (view_dir) are not touched (on by default, as in Blender) */
    double view_dir[3];        /* direction the view looks in object space, set by the window at
                                  stroke begin; zero: unknown (no front-face test) */
    double spacing;            /* dabs every spacing * radius along the path (window strokes) */
    int space_atten;           /* Blender's "Adjust Strength for Spacing" (BRUSH_SPACE_ATTEN, on by
                                  default): each dab's strength is divided by how many dabs overlap
                                  at `spacing`, so a stroke deposits the same whatever the spacing */
    double fade;               /* strength fades in over the first fade * radius of a stroke's path
                                  (0: none), so a stroke does not start with a full-strength dab;
                                  with it crease and pinch pull across the stroke only, so its end
                                  is not a star (core/sculpt/sculpt_tools.c) */
    double reach_edges;        /* a dab takes in at least this many mean edge lengths of the editing
                                  level (st_doc_brush_reach; 0: the radius only) */
    int area_plane;            /* draw, crease, pinch, flatten and clay strips work in the plane of the
                                  area under the dab (Blender's default Sculpt Plane "Area Plane"); 0:
                                  along the normal given with the dab, flatten in the plain mean */
    int hold;                  /* damp each dab so that no face turns more than 44 degrees or shrinks
                                  below 10 % of its area within a stroke (core/sculpt/sculpt_hold.c) */
    double autosmooth;         /* of the current tool, 0..1: after each dab the vertices under it
                                  are smoothed by autosmooth * weight (Blender's Auto-Smooth) */
    int stabilize;             /* lazy mouse: the brush trails the cursor by stabilize_dist * radius */
    double stabilize_dist;
    /* Each tool's own strength and falloff, kept while another tool is
     * active (st_brush_set_tool). */
    double tool_strength[ST_BRUSH_COUNT];
    int tool_falloff[ST_BRUSH_COUNT];
    double tool_autosmooth[ST_BRUSH_COUNT];
} st_brush;

/* Default settings of every brush (radius r). */
void st_brush_defaults(st_brush *b, double radius);
/* Makes `tool` current: keeps the current tool's strength, falloff and
 * auto-smooth and takes the new one's. */
void st_brush_set_tool(st_brush *b, int tool);
/* The raw dab of every tool: no auto-smooth, no spacing attenuation, no
 * fade, no coarse-level reach, no area plane, no hold (what the brush formulas of core/sculpt/sculpt_tools.c
 * give for one dab; the document tests written for them pin it). */
void st_brush_raw(st_brush *b);

/* What the last operations changed, for the renderer (accumulated until
 * st_doc_take_change()). */
enum st_change_bits {
    ST_CHANGE_TOPOLOGY = 1,    /* levels, scheme, adaptive refinement: rebuild buffers */
    ST_CHANGE_POSITIONS = 2,   /* vertices of h moved: `footprint` holds what core wrote, e.g.
                                  st_renderer_refresh(r, targets, &d->h.map, footprint); moved_level /
                                  nmoved: the level and the count of the vertices moved there;
                                  with the box on the display moved too: ST_CHANGE_DISPLAY */
    ST_CHANGE_SELECTION = 4,
    ST_CHANGE_BOX = 8,
    ST_CHANGE_ALL_POSITIONS = 16, /* everything moved (undo, analysis): refresh all */
    ST_CHANGE_DISPLAY = 32,    /* box on, topology unchanged: the display hierarchy
                                  (st_doc_display_hier) wrote `disp_footprint` (its vertices disp_vids,
                                  at some level): e.g. st_renderer_refresh(r, ST_TARGET_SURFACE,
                                  &st_doc_display_hier(d)->map, disp_footprint) */
    ST_CHANGE_MASK = 128,      /* the mask changed (st_doc.mask): at mask_vids of h (ids), or everywhere
                                  when nmask_vids is 0; positions did not move for it */
    ST_CHANGE_PATCH = 64,      /* the box moved and the display was updated in place: what its map's
                                  update touched is in `patch` (st_renderer_patch(r, map, patch));
                                  never set together with ST_CHANGE_TOPOLOGY */
};

typedef struct st_doc_change {
    unsigned bits;             /* enum st_change_bits */
    unsigned moved_level;      /* the level the moved vertices are on */
    uint32_t nmoved;           /* vertices moved there (which ones: the footprint) */
    uint32_t *disp_vids;       /* ST_CHANGE_DISPLAY: vertex ids of the display hierarchy (owned by the doc) */
    uint32_t ndisp;
    const st_map_log *patch;   /* ST_CHANGE_PATCH: the display map's changes (owned by the doc) */
    const st_footprint *footprint;      /* ST_CHANGE_POSITIONS: values of h core wrote (owned by the doc) */
    const st_footprint *disp_footprint; /* ST_CHANGE_DISPLAY: values of the display core wrote (owned by the doc) */
    uint32_t *mask_vids;       /* ST_CHANGE_MASK: vertex ids of h whose mask changed (owned by the doc) */
    uint32_t nmask_vids;       /* 0: all of them */
} st_doc_change;

typedef struct st_undo_step st_undo_step;   /* editor.c */

typedef struct st_doc {
    char path[4096];           /* file the model came from ("" for none) */
    st_mesh base;              /* as loaded and repaired */
    const st_scheme *scheme;
    st_hier_opts opts;
    st_hier h;
    int loaded;

    st_adapt_params box;       /* box corners, base and max levels, falloff */
    int box_on;                /* the interest box drives the display */
    /* The interest box's display (editor_display.h): when box_on, the
     * adaptive mesh shown instead of the regular hierarchy, derived from h.
     * h always stays the regular hierarchy (the model): edits, levels and
     * undo act on h, then the display follows. */
    st_box_display display;

    unsigned edit_level, display_level;
    /* HD levels (editor_hd.c): hd_level > 0 when strokes go to that level
     * of the box's display, above the model's top (edit_level then stays
     * the model's top, so that everything reading edit_level on h holds);
     * hd: the display holds HD levels (its base is the model's top and
     * faces carrying sculpted detail are never coarsened,
     * display.adapt.keep_above), so it stays shown with the box off. */
    unsigned hd_level;
    int hd;
    uint32_t *hd_vdart, nhd_vdart;   /* hd_level: one dart per display vertex id (st_sculpt_vertex_darts) */
    st_mask hd_mask;           /* hd_level: 1 where a vertex cannot move at hd_level, else the display mask */
    int hd_tables_ok;          /* hd_vdart and hd_mask are those of the display now (ed_hd_tables) */
    st_edit_cache *hd_cache;   /* predictions of the HD stroke in progress */

    uint32_t *sel;             /* selected vertex ids of the editing level, sorted */
    uint32_t nsel, capsel;

    st_brush brush;

    st_undo_step **undo;       /* oldest first */
    uint32_t nundo, capundo, undo_pos;  /* undo_pos steps are done; the rest can be redone */
    /* Names the model's state in the undo history: a new serial for every
     * step pushed, and after an undo or a redo the serial of the state it
     * returns to (base_revision at the history's start), so that undoing
     * back to the saved state is clean again, as Qt's QUndoStack clean
     * index is (0 after opening).  The window compares it with the
     * revision it last saved ("unsaved changes?") and last wrote to the
     * recovery file (a step ended: write it now); caches of what a state
     * gives (the normal map, the scheme menu's refusals) key on it. */
    uint64_t revision;
    uint64_t base_revision;    /* the state before undo[0] (older steps dropped, or the history forgotten) */
    uint64_t last_serial;      /* the last serial given: serials never repeat */
    size_t undo_bytes, undo_budget;     /* oldest steps dropped beyond the budget */

    size_t mem_budget;         /* refuse operations that would need more (bytes) */
    unsigned read_flags;       /* st_mesh_load_flags flags of st_doc_open: ST_MESH_STRICT (the window's --strict) */
    /* Reads a mesh file for st_doc_open; NULL: core's OBJ/OFF/PLY readers
     * (st_mesh_load_flags).  The program gives one that reads glTF too
     * (app/cmd_window.c: st_any_mesh_load), so that this library needs no
     * glTF reader of its own.  Same contract as st_mesh_load_flags. */
    int (*load_mesh)(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err);

    st_doc_change change;

    /* In-progress drag or stroke (between begin and end). */
    int active;                /* 0, 1 drag, 2 stroke */
    st_undo_step *pending;
    double last_update_ms;     /* how long the last geometry update took (edit, undo, level, box), ms,
                                  monotonic clock; its time stamp is last_update_at_ms */
    double last_update_at_ms;  /* monotonic time stamp of the last geometry update */
    st_footprint fp_model;     /* values of h written since the last st_doc_take_change (core appends) */
    st_footprint fp_query;     /* scratch: an edit's footprint asked before it (undo) */
    st_footprint fp_taken[2];  /* model and display footprints handed out by st_doc_take_change */
    int rebased;               /* remove_bottom happened since open: set_scheme then cannot take the file's tags */
    int box_recording;         /* inside st_doc_box_begin .. end */
    st_adapt_params box_rec_params;
    int box_rec_on;
    uint64_t disp_faces, disp_verts;  /* cached st_doc_display_counts */
    uint32_t *vdart;           /* edit level: vertex id -> dart (built on demand) */
    uint32_t nvdart;
    int vdart_level;           /* level vdart was built for, -1 none */
    struct st_brush_state *bs; /* stroke scratch (spatial grid, ...) */
    /* Mask (core/multires/mask.h): per vertex id of h, painted at the
     * editing level, subdivided above it; protects vertices from brushes,
     * drags and grabs in proportion (displacement times 1 - mask). */
    st_mask mask;
    int mask_all;              /* the pending change covers every vertex */
    int mask_erase;            /* the mask stroke in progress erases */
    uint32_t capmaskv;         /* capacity of change.mask_vids */
    st_mask display_mask;      /* the mask over the box display's ids (st_doc_display_mask) */
    /* Sculpt layers (core/multires/layers.h); strokes and drags at the
     * active layer's level go into it. */
    st_layers layers;
    /* Predictions of the vertices the drag or stroke in progress touched
     * (core/multires/edit.h); valid while edit_serial == ecache_serial,
     * which every end of a drag or stroke breaks. */
    st_edit_cache *ecache;
    uint64_t edit_serial, ecache_serial;
    char note[256];            /* last non-fatal message (undo history dropped, ...) */
    char refusal[320];         /* why the last drag or stroke begin was refused by the
                                  memory budget ("" otherwise: ed_edit_budget) */
    /* Long operations (opening at a depth, adding a level, a scheme
     * change, switching the box on) call this, when set, before each
     * stage, e.g. "building level 5", 5, 6: the window can redraw a
     * message.  NULL: nothing is called. */
    void (*progress)(void *ctx, const char *what, unsigned step, unsigned steps);
    void *progress_ctx;
} st_doc;

void st_doc_init(st_doc *d);
void st_doc_free(st_doc *d);

/* Opens a mesh file with a scheme and a depth (levels >= 0).  On failure d
 * is unchanged.  Clears the undo history.  levels ST_DOC_LEVELS_AUTO: a
 * dense mesh (more than ST_DOC_DENSE_FACES faces, a scan) opens as it is,
 * at level 0 alone (its coarse levels come from Mesh > Rebuild levels);
 * a smaller cage gets ST_DOC_DEFAULT_LEVELS levels above it. */
#define ST_DOC_LEVELS_AUTO 0xffffffffu
#define ST_DOC_DENSE_FACES 20000u
#define ST_DOC_DEFAULT_LEVELS 2u
int st_doc_open(st_doc *d, const char *path, const char *scheme, unsigned levels, st_error *err);
/* Rebuilds the hierarchy with another scheme (same depth, details dropped;
 * the caller asks for confirmation first) from the current control mesh
 * (level 0 as edited, with the file's crease tags while level 0 is still
 * the loaded one).  Undoable. */
int st_doc_set_scheme(st_doc *d, const char *scheme, st_error *err);
/* Whether st_doc_set_scheme(scheme) can rebuild the control mesh as it is
 * (level 0 as edited): ST_OK, or why not in err (core's
 * st_scheme_accepts: loop on quads, sqrt3 with holes, ...). */
int st_doc_scheme_accepts(st_doc *d, const char *scheme, st_error *err);
/* The same for n schemes at once, level 0 read once: rc[i] and errs[i]
 * for schemes[i]; returns how many it takes. */
unsigned st_doc_schemes_accepted(st_doc *d, const char *const *schemes, unsigned n, int *rc, st_error *errs);

/* The long operations with progress and cancellation: progress (may be
 * NULL) is called with the fraction done (0 first, 1 last, increasing), a
 * non-zero return cancels (ST_ERR_INVALID, "cancelled") and the document
 * stays as it was to the bit: model, levels, ids, undo history.  Open:
 * reading and level 0, then each level; add a level: its refinement, then
 * its synthesis (core's st_hier_subdivide_to_progress); scheme change:
 * level 0, then each level; save: every 64 KiB written (the file at path
 * stays as it was, or absent: core/io/atomic_file.h).  A cancel takes
 * effect at the next report: reading a file and one level's refinement or
 * synthesis are not cut short. */
int st_doc_open_progress(st_doc *d, const char *path, const char *scheme, unsigned levels,
                         int (*progress)(void *ctx, double fraction), void *ctx, st_error *err);
int st_doc_set_scheme_progress(st_doc *d, const char *scheme, int (*progress)(void *ctx, double fraction), void *ctx,
                               st_error *err);
int st_doc_add_level_progress(st_doc *d, int (*progress)(void *ctx, double fraction), void *ctx, st_error *err);
/* Saves the document as a session (core/io/session.h: hierarchy, box,
 * levels, base mesh, layers, mask; view may be NULL); editor_session.c. */
int st_doc_save_session(const st_doc *d, const char *path, const st_session_view *view, const st_session_tool *tool,
                        int (*progress)(void *ctx, double fraction), void *ctx, st_error *err);

/* Rebuild levels: the finest level (the loaded mesh when there is one
 * level) made into a hierarchy with coarse levels, as `strata rebuild
 * --method auto` does: unsubdivide when it has subdivision connectivity
 * (scheme Catmull-Clark or Loop by its pattern), else the progressive
 * method (to 1 % of the faces).  The result replaces the hierarchy
 * (editing level 0, displayed level top); undoable like a scheme change.
 * progress (may be NULL) is called with the fraction done; a non-zero
 * return cancels (ST_ERR_INVALID, "cancelled"), the document unchanged.
 * msg receives which method made how many levels. */
int st_doc_rebuild_levels(st_doc *d, int (*progress)(void *ctx, double fraction), void *ctx, char *msg,
                          size_t msgcap, st_error *err);

/* Levels.  Add: regular refinement of the top (refused with a message giving
 * the bytes needed when over mem_budget).  Remove top / bottom: delete the
 * finest / coarsest level (bottom = "rebase": level 1 becomes the control
 * mesh).  All undoable. */
/* Multiresolution filtering of a progressive model (ui/doc/editor_filter.c;
 * core's st_progressive_filter, GSS99 §5): the details of level k+1
 * scaled by gains[k] (k < n; the levels past the list keep theirs: 0
 * removes that band, 1 keeps it to the bit, above 1 enhances it), the
 * levels above re-synthesised.  One undo step ("filter"), exact both ways;
 * all gains 1 change nothing and make no step.  Refused on a model that is
 * not progressive, with sculpt layers (merge or delete them first), or
 * over the memory budget. */
int st_doc_filter(st_doc *d, const double *gains, unsigned n, st_error *err);
/* The Filter panel's presets (GSS99 §5's band gains, as an audio
 * equaliser's presets): the gains of levels 1..top in gains[0..top-1].
 * Bands are split in thirds by level: smooth removes the finest third and
 * halves the middle one; sharpen enhances the finest half (x1.5); keep
 * coarse shape removes every band above the coarsest third; keep fine
 * detail removes the coarsest third (large bumps go, texture stays). */
enum st_filter_preset {
    ST_FILTER_SMOOTH, ST_FILTER_SHARPEN, ST_FILTER_KEEP_COARSE, ST_FILTER_KEEP_FINE, ST_FILTER_NPRESETS
};
const char *st_filter_preset_name(int preset);
void st_filter_preset_gains(int preset, unsigned top, double *gains);
int st_doc_add_level(st_doc *d, st_error *err);
int st_doc_remove_top(st_doc *d, st_error *err);
int st_doc_remove_bottom(st_doc *d, st_error *err);
/* Bytes a new top level would need (estimate from the current top). */
size_t st_doc_add_level_bytes(const st_doc *d);
/* Clamped; clears the selection.  Above the model's top: an HD level
 * (editor_hd.c, st_doc_hd_refusal), where brushes sculpt the box's display
 * itself; when HD levels are not available, the top. */
void st_doc_set_edit_level(st_doc *d, unsigned l);
void st_doc_set_display_level(st_doc *d, unsigned l);  /* clamped to edit..top */

/* Selection of editing-level vertices (ids).  mode: 0 replace, 1 add,
 * 2 remove. */
enum st_select_mode { ST_SELECT_REPLACE, ST_SELECT_ADD, ST_SELECT_REMOVE };
void st_doc_select(st_doc *d, const uint32_t *vids, uint32_t n, int mode);
/* Position of an editing-level vertex. */
void st_doc_vertex_pos(const st_doc *d, uint32_t vid, double p[3]);

/* Drag of the selection: begin, then any number of updates giving the total
 * translation from the start (object units), then end (one undo step).
 * Cancel puts the selection back and records nothing. */
int st_doc_drag_begin(st_doc *d);
int st_doc_drag_update(st_doc *d, const double delta[3]);
void st_doc_drag_end(st_doc *d);
void st_doc_drag_cancel(st_doc *d);

/* Brush stroke at the editing level: begin, one dab per cursor sample
 * (centre on the surface, the surface normal there, and for grab the
 * cursor's translation since the last dab), end (one undo step).
 * Every brush weighs a vertex under a dab by the falloff preset at its
 * distance times the strength times the front-face test (front_only with
 * view_dir set: a vertex whose normal faces away from the viewer is not
 * touched).
 * Grab captures the vertices under its first dab and moves them by weight *
 * delta at every dab; the other brushes (core/sculpt/sculpt_tools.c: draw, smooth,
 * flatten, crease, pinch, inflate, clay strips, layer, relax) displace
 * from the positions before the dab, proportionally to weight and R/10,
 * in the plane of the area under the dab, then auto-smooth and the hold
 * (st_brush's settings; st_brush_raw turns them off).  R is the dab's
 * reach (st_doc_brush_reach).
 * Symmetry (mirror_x, _y, _z, any combination) repeats the dab reflected
 * across the enabled planes of object space (up to 8 dabs, displacements
 * all from the same positions, added), so a symmetric mesh stays
 * symmetric.  Vertices under a dab come from a uniform grid of
 * the editing level built at stroke begin (cell = radius), kept exact by
 * re-inserting every moved vertex (core/sculpt/sculpt.c).  Normal may be NULL (+z);
 * grab_delta may be NULL (zero). */
int st_doc_stroke_begin(st_doc *d);
/* The radius brushes take in at the editing level: the brush radius, or
 * brush.reach_edges (default ST_BRUSH_REACH_EDGES) times the mean edge
 * length of the editing level when that is larger, so that at a coarse level a dab takes in at least the
 * vertices of the faces under the cursor (issue 30: a coarse level barely
 * responded when few coarse vertices lay inside the radius).  The window's
 * panel shows it when it differs from the radius. */
#define ST_BRUSH_REACH_EDGES 3.0
double st_doc_brush_reach(st_doc *d);
int st_doc_stroke_dab(st_doc *d, const double center[3], const double normal[3], const double grab_delta[3]);
/* The fade-out of the stroke's end: the next dabs' strength times k (0..1;
 * 1 again at the next stroke).  The window's stroke trails the cursor by
 * the fade length and, when the button comes up, lays the trailing part
 * with k falling to 0.1 (st_stroke_path_end), as the fade-in rises. */
void st_doc_stroke_fade_out(st_doc *d, double k);
void st_doc_stroke_end(st_doc *d);

/* Where the dabs of a stroke go (brush_stroke.c), in any space of up to
 * three coordinates (the window uses pixels, z = 0).  The brush point
 * follows the cursor: directly, or with the stabiliser ("lazy mouse") it
 * stays `lazy` behind it and moves only when the cursor pulls it further.
 * Along the brush point's path a dab is placed every `spacing` (path
 * length), wherever the events fell: fast and slow cursor motion along the
 * same path give the same dabs.  spacing <= 0: one dab at the brush point
 * per event (no spacing). */
typedef struct st_stroke_path {
    double brush[3];           /* the brush point */
    double since;              /* path length since the last dab */
} st_stroke_path;
/* Starts at the cursor; the caller puts the first dab there. */
void st_stroke_path_begin(st_stroke_path *sp, const double cursor[3]);
/* The cursor moved: calls dab(ctx, p) for every dab due, in order, and
 * returns how many. */
unsigned st_stroke_path_move(st_stroke_path *sp, const double cursor[3], double spacing, double lazy,
                             void (*dab)(void *ctx, const double p[3]), void *ctx);
/* The end of a stroke that trailed the cursor: the dabs still due between
 * the brush point and the cursor, each called with the factor k of its
 * place, from 1 near the brush point down to 0.1 at the cursor (smoothstep,
 * the fade-in's curve mirrored).  Returns how many. */
unsigned st_stroke_path_end(st_stroke_path *sp, const double cursor[3], double spacing,
                            void (*dab)(void *ctx, const double p[3], double k), void *ctx);

/* Interest box: corners, levels, on/off.  Refines or coarsens the display
 * incrementally (st_adapt_update).  Undoable (a box drag is one step when
 * bracketed by st_doc_box_begin / st_doc_box_end). */
int st_doc_set_box(st_doc *d, const st_adapt_params *box, int on, st_error *err);
void st_doc_box_begin(st_doc *d);
void st_doc_box_end(st_doc *d);

/* The highest maximum level the box p can have within the memory budget
 * (its display estimated as st_doc_set_box checks it), at most the top +
 * 3, or with p's base level at the top (HD levels) at most the map's level
 * limit, the estimate doubled past the top + 3; the box panel's slider
 * stops there. */
unsigned st_doc_box_max_level_allowed(st_doc *d, const st_adapt_params *p);
/* Empties the undo history (what opening a file leaves). */
void st_doc_forget_history(st_doc *d);
/* Undo and redo; 0 when done, -1 when there is nothing to undo/redo. */
int st_doc_undo(st_doc *d, st_error *err);
int st_doc_redo(st_doc *d, st_error *err);
/* What the step undo / redo would act on was, for menus ("move", "brush
 * stroke", "add level", "delete the finest level", "delete the coarsest
 * level", "scheme change", "rebuild levels", "interest box"); NULL when
 * there is none. */
const char *st_doc_undo_name(const st_doc *d);
const char *st_doc_redo_name(const st_doc *d);

/* Returns the accumulated change and resets it (disp_vids stays valid
 * until the next operation, the footprints until the next take). */
st_doc_change st_doc_take_change(st_doc *d);

/* Counts of the displayed mesh, for the HUD. */
void st_doc_display_counts(const st_doc *d, uint64_t *faces, uint64_t *verts);

/* ---- what is displayed ----------------------------------------------------- */

/* What the window draws: the regular hierarchy at display_level, or with the
 * interest box on the adaptive display hierarchy at its top level. */
const st_hier *st_doc_display_hier(const st_doc *d);
unsigned st_doc_display_map_level(const st_doc *d);
/* Picking on the displayed mesh gives vertex ids of st_doc_display_hier();
 * this maps one to the editing-level vertex id used by st_doc_select
 * (identity when the box is off; ST_NIL when the vertex is not a vertex of
 * the editing level). */
uint32_t st_doc_display_to_edit_vertex(const st_doc *d, uint32_t display_vid);
/* A dart of the editing level for an editing-level vertex id (ST_NIL if
 * none), e.g. to call st_hier_edit. */
uint32_t st_doc_vertex_dart(st_doc *d, uint32_t vid);

/* Bytes the model uses now (map + details); the memory budget compares
 * this plus what an operation adds to mem_budget. */
size_t st_doc_model_bytes(const st_doc *d);

/* Interaction benchmark (strata --bench-interaction): on the loaded model,
 * drags one vertex of `level` (a vertex near the middle of the level's id
 * range) through `steps` updates, and reports the median time per update
 * (geometry only: st_hier_edit plus the display sync; the window adds its
 * buffer updates), then puts the model back exactly (nothing is recorded
 * in the undo history), and the time of a full synthesis
 * st_hier_synthesize(h, 0) (ms).  Returns 0, or -1 when no model is loaded
 * or level > top. */
int st_doc_bench_drag(st_doc *d, unsigned level, unsigned steps, double *step_ms_median, double *full_synth_ms);

/* ---- masks (editor_mask.c) ------------------------------------------------------
 * The mask is painted and edited at the editing level; every operation is
 * one undo step ("mask ...") and ends with the finer levels' subdivision
 * of it (core/multires/mask.h).  Operations return 0, or -1 when no model
 * is loaded. */
float st_doc_mask(const st_doc *d, uint32_t vid);
int st_doc_mask_clear(st_doc *d);
int st_doc_mask_invert(st_doc *d);
/* Grow / shrink: each vertex takes the largest / smallest value of its
 * one-ring and itself (morphological dilation / erosion). */
int st_doc_mask_grow(st_doc *d);
int st_doc_mask_shrink(st_doc *d);
/* Smooth: each vertex moves halfway to its one-ring average. */
int st_doc_mask_smooth(st_doc *d);
/* Mask by cavity: 1 where the vertex lies below the mean of its one-ring
 * (a crevice), by the depth relative to the ring's mean edge length:
 * clamp(4 * depth / edge, 0, 1); 0 on flat and convex parts. */
int st_doc_mask_cavity(st_doc *d);
/* Mask brush: a stroke (begin, dabs, end: one undo step) that brushes the
 * mask in (erase 0: m += s f (1 - m)) or out (erase 1: m -= s f m), s the
 * brush strength, f its falloff, over the vertices of the editing level
 * within the brush radius. */
int st_doc_mask_stroke_begin(st_doc *d, int erase);
int st_doc_mask_stroke_dab(st_doc *d, const double center[3]);
void st_doc_mask_stroke_end(st_doc *d);
/* The mask over the vertex ids of st_doc_display_hier(d), for drawing:
 * the document's own with the box off; with the box on, each display
 * vertex paired with a model vertex takes that vertex's value and the
 * vertices of the display's levels beyond the model's top take the
 * scheme's subdivision of them (as the model's finer levels do).  Valid
 * until the next change of the document. */
const st_mask *st_doc_display_mask(st_doc *d);

/* ---- sculpt layers (editor_layers.c) --------------------------------------------
 * Every operation is one undo step; 0, or non-zero with err filled and the
 * document unchanged.  k is a layer index (bottom 0). */
int st_doc_layer_add(st_doc *d, const char *name, st_error *err);   /* at the editing level, made active */
int st_doc_layer_set_active(st_doc *d, int k, st_error *err);        /* -1: none (the level's own details); sets the editing level */
int st_doc_layer_set_strength(st_doc *d, int k, double strength, st_error *err);   /* clamped to 0..2 */
int st_doc_layer_set_hidden(st_doc *d, int k, int hidden, st_error *err);
int st_doc_layer_rename(st_doc *d, int k, const char *name, st_error *err);
int st_doc_layer_move(st_doc *d, int k, int to, st_error *err);
int st_doc_layer_merge_down(st_doc *d, int k, st_error *err);
int st_doc_layer_delete(st_doc *d, int k, st_error *err);

/* ---- HD levels (editor_hd.c) -----------------------------------------------------
 * With the interest box on, brushes can sculpt above the model's top, up to
 * the box's maximum level (ZBrush's HD geometry): the adaptive display
 * becomes part of the model there.  Its base is the model's top; strokes
 * write detail vectors at the HD level of its vertices (core's
 * st_adapt_edit, local frames, levels above re-synthesised), edits of the
 * uniform levels carry them along (the display follows the model), and
 * faces that carry HD detail never coarsen when the box moves or goes off
 * (st_adapt.keep_above): memory grows with what is sculpted.  Undo and redo
 * restore the HD level's values bit for bit.  Sessions keep them (chunk
 * hdlv).  The selection holds the display's vertex ids of the HD level and
 * drags move them.  The mask brush paints the model's top level, which the
 * HD levels take subdivided.  Sculpt layers added at an HD level live on
 * the display's level (editor_layers.c) and keep their faces refined
 * (st_adapt.keep_layers).  Operations that would rebuild the model's
 * levels (add or delete a level, scheme change, rebuild levels, filter)
 * are refused while HD detail or an HD layer exists. */
/* Why HD levels cannot be used now (NULL: they can). */
const char *st_doc_hd_refusal(const st_doc *d);
/* The level strokes sculpt: hd_level when set, else edit_level. */
unsigned st_doc_sculpt_level(const st_doc *d);
/* The highest level st_doc_set_edit_level accepts now. */
unsigned st_doc_level_limit(const st_doc *d);
/* The display is the adaptive hierarchy (box on, or HD levels kept). */
int st_doc_display_adaptive(const st_doc *d);
/* The map and level whose vertices the cage shows and picking and the
 * selection use: the model's editing level, or at an HD level the
 * display's vertices of that level. */
const st_map *st_doc_cage_map(const st_doc *d, unsigned *level);
/* Faces stored at the HD levels (above the model's top) of the display,
 * 0 when it has none. */
uint64_t st_doc_hd_faces(const st_doc *d);
/* What a bake of `*level` reads: the HD levels at their top when *level is
 * the model's top and HD detail exists (*level set to their top; their
 * levels 0..top are the model's, same ids and UVs), else NULL (the
 * model). */
st_hier *st_doc_hd_bake_source(st_doc *d, unsigned *level);
/* A session's HD levels (its chunk hdlv: hd, hd_adapt and the HD levels'
 * sculpt layers, taken; hd_layers may be NULL) become the display, kept
 * like sculpted HD levels, and the layers join the document's stack; the
 * model must be the session's.  Refused, nothing taken, when they do not
 * match it. */
int st_doc_adopt_hd(st_doc *d, st_hier *hd, st_adapt *hd_adapt, st_layers *hd_layers, st_error *err);

/* Brush falloff of the smooth preset: (1 - (r/R)^2)^2 for r < R, else 0. */
double st_brush_falloff(double r, double radius);

#endif
