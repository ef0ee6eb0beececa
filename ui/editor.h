/* st_doc: the modeller's document and every editing operation on it, with no
 * GL and no window (issue 6).  The window (ui/window.c) turns events into
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
 * Conventions (Blender multires / ZBrush, chosen where the issue is silent):
 *   - editing at level i moves P_i; every finer level follows with its
 *     details (st_hier_move); coarser levels never move;
 *   - the displayed level is >= the editing level and <= top; adding a level
 *     shows it; with the interest box on, the display is the adaptive mesh
 *     (the top level of the map, refined between base and max levels);
 *   - every operation that changes the model is one undo step; a drag or a
 *     brush stroke (begin .. end) is one step however many updates it had.
 *
 * Errors: operations return 0, or non-zero with err filled and the document
 * unchanged (a failed open keeps the current model). */
#ifndef ST_EDITOR_H
#define ST_EDITOR_H

#include <stddef.h>
#include <stdint.h>

#include "adapt.h"
#include "hier.h"
#include "mesh.h"

enum st_brush_tool { ST_BRUSH_GRAB, ST_BRUSH_DRAW, ST_BRUSH_SMOOTH, ST_BRUSH_FLATTEN, ST_BRUSH_COUNT };
const char *st_brush_name(int tool);

typedef struct st_brush {
    int tool;                  /* enum st_brush_tool */
    double radius;             /* object units */
    double strength;           /* 0..1 */
    int mirror_x;              /* X-mirror symmetry (plane x = 0 of object space) */
    int invert;                /* draw: push in instead of out */
} st_brush;

/* What the last operations changed, for the renderer (accumulated until
 * st_doc_take_change()). */
enum st_change_bits {
    ST_CHANGE_TOPOLOGY = 1,    /* levels, scheme, adaptive refinement: rebuild buffers */
    ST_CHANGE_POSITIONS = 2,   /* vertices moved: see moved_level / moved_darts */
    ST_CHANGE_SELECTION = 4,
    ST_CHANGE_BOX = 8,
    ST_CHANGE_ALL_POSITIONS = 16, /* everything moved (undo, analysis): refresh all */
};

typedef struct st_doc_change {
    unsigned bits;             /* enum st_change_bits */
    unsigned moved_level;      /* the level the moved darts are on */
    uint32_t *moved_darts;     /* one dart per moved vertex (owned by the doc) */
    uint32_t nmoved;
} st_doc_change;

typedef struct st_undo_step st_undo_step;   /* editor.c */

typedef struct st_doc {
    char path[4096];           /* file the model came from ("" for none) */
    st_mesh base;              /* as loaded and repaired */
    const st_scheme *scheme;
    st_hier_opts opts;
    st_hier h;
    int loaded;

    st_adapt adapt;
    st_adapt_params box;       /* box corners, base and max levels, falloff */
    int box_on;                /* the interest box drives the display */

    unsigned edit_level, display_level;

    uint32_t *sel;             /* selected vertex ids of the editing level, sorted */
    uint32_t nsel, capsel;

    st_brush brush;

    st_undo_step **undo;       /* oldest first */
    uint32_t nundo, capundo, undo_pos;  /* undo_pos steps are done; the rest can be redone */
    size_t undo_bytes, undo_budget;     /* oldest steps dropped beyond the budget */

    size_t mem_budget;         /* refuse operations that would need more (bytes) */

    st_doc_change change;

    /* In-progress drag or stroke (between begin and end). */
    int active;                /* 0, 1 drag, 2 stroke */
    st_undo_step *pending;
    double last_update_ms;     /* time of the last geometry update */
} st_doc;

void st_doc_init(st_doc *d);
void st_doc_free(st_doc *d);

/* Opens a mesh file with a scheme and a depth (levels >= 0).  On failure d
 * is unchanged.  Clears the undo history. */
int st_doc_open(st_doc *d, const char *path, const char *scheme, unsigned levels, st_error *err);
/* Rebuilds the hierarchy with another scheme (same depth, details dropped;
 * the caller asks for confirmation first).  Undoable. */
int st_doc_set_scheme(st_doc *d, const char *scheme, st_error *err);

/* Levels.  Add: regular refinement of the top (refused with a message giving
 * the bytes needed when over mem_budget).  Remove top / bottom: delete the
 * finest / coarsest level (bottom = "rebase": level 1 becomes the control
 * mesh).  All undoable. */
int st_doc_add_level(st_doc *d, st_error *err);
int st_doc_remove_top(st_doc *d, st_error *err);
int st_doc_remove_bottom(st_doc *d, st_error *err);
/* Bytes a new top level would need (estimate from the current top). */
size_t st_doc_add_level_bytes(const st_doc *d);
void st_doc_set_edit_level(st_doc *d, unsigned l);     /* clamped; clears the selection */
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
 * cursor's translation since the last dab), end (one undo step). */
int st_doc_stroke_begin(st_doc *d);
int st_doc_stroke_dab(st_doc *d, const double center[3], const double normal[3], const double grab_delta[3]);
void st_doc_stroke_end(st_doc *d);

/* Interest box: corners, levels, on/off.  Refines or coarsens the display
 * incrementally (st_adapt_update).  Undoable (a box drag is one step when
 * bracketed by st_doc_box_begin / st_doc_box_end). */
int st_doc_set_box(st_doc *d, const st_adapt_params *box, int on, st_error *err);
void st_doc_box_begin(st_doc *d);
void st_doc_box_end(st_doc *d);

/* Undo and redo; 0 when done, -1 when there is nothing to undo/redo. */
int st_doc_undo(st_doc *d, st_error *err);
int st_doc_redo(st_doc *d, st_error *err);

/* Returns the accumulated change and resets it (moved_darts stays valid
 * until the next operation). */
st_doc_change st_doc_take_change(st_doc *d);

/* Counts of the displayed mesh, for the HUD. */
void st_doc_display_counts(const st_doc *d, uint64_t *faces, uint64_t *verts);

#endif
