/* Shared between the files of ui/doc/ (the document: editor*.c, brush*.c,
 * undo.c); not part of the window's API. */
#ifndef ST_EDITOR_INTERNAL_H
#define ST_EDITOR_INTERNAL_H

#include "editor.h"
#include "core/map/dart_list.h"
#include "core/multires/edit.h"
#include "core/multires/layers.h"
#include "core/multires/mask.h"
#include "core/base/membudget.h"

/* ---- editor_clone.c ---- */
/* Bit-exact deep copy (ids and allocation state included); -1 when out of
 * memory (dst left empty).  *bytes: what the copy allocated. */
int ed_hier_clone(st_hier *dst, const st_hier *src, size_t *bytes);
/* Re-points the attached sharpness attributes after the struct moved. */
void ed_hier_fix(st_hier *h);
void ed_hier_swap(st_hier *a, st_hier *b);
size_t ed_hier_bytes(const st_hier *h);

/* ---- undo.c ---- */
enum ed_step_kind { ED_STEP_EDIT, ED_STEP_HIER, ED_STEP_BOX, ED_STEP_ADD, ED_STEP_RMTOP };

struct st_undo_step {
    int kind;
    int hd;                    /* ED_STEP_EDIT of an HD level: the keys are the box display's (editor_hd.c) */
    const char *name;          /* what the step was, for menus: "move", "brush stroke", ... (static) */
    size_t bytes;
    uint64_t serial;           /* the st_doc.revision of the state this step leads to (ed_push_step) */
    /* ED_STEP_EDIT: values before and after, keyed by (level, kind, vid)
     * as core's footprints (core/map/footprint.h: st_fp_key): positions
     * of every vertex st_hier_edit rewrote (every level >= the edit level)
     * and the edit level's details of the moved vertices. */
    unsigned level;
    uint32_t n, cap;
    uint64_t *key;
    double (*oldv)[3], (*newv)[3];
    struct ed_rec_plane *planes; /* while recording: which keys are in (undo.c) */
    uint32_t nplanes, capplanes, nindexed, lastplane;
    uint32_t *moved;           /* darts (edit level) of the moved vertices, deduplicated */
    uint32_t nmoved, capmoved;
    /* ED_STEP_HIER: the whole other state (swapped in and out). */
    st_hier snap;
    const st_scheme *scheme;
    unsigned edit_level, display_level;
    int rebased;
    /* ED_STEP_ADD (a level added by regular refinement): undo removes it,
     * redo refines again with the pool's spare blocks in their first order,
     * which gives the same ids; `idsum` checks it. */
    uint64_t idsum;
    unsigned display_after, edit_after;
    /* ED_STEP_RMTOP (the finest level removed): undo refines again the same
     * way (same ids, idsum) and writes back the level's positions and
     * details kept here. */
    uint32_t *vids, nvids;
    double (*vpos)[3];
    double *det;
    uint32_t detcap;
    /* ED_STEP_BOX */
    st_adapt_params box_old, box_new;
    int on_old, on_new;
    /* Sculpt layers and masks (editor_layers.c, editor_mask.c).
     * ED_STEP_EDIT into a level with layers: `lay` holds the layer values
     * the edit changed (keys ed_layer_key) before and after.
     * has_layers: the whole layer stack before (layers_old) and after
     * (layers_new) a layer operation; ED_STEP_HIER: the other hierarchy's
     * stack in layers_old.  has_mask: the mask before and after (ED_STEP_HIER:
     * the other hierarchy's mask in mask_old). */
    st_undo_step *lay;
    int has_layers, has_mask;
    st_layers layers_old, layers_new;
    st_mask mask_old, mask_new;
};

st_undo_step *ed_step_new(int kind);
/* Installs *h as the document's hierarchy; the old one goes into the
 * returned hierarchy step, which the caller finishes and pushes. */
st_undo_step *ed_swap_hier(st_doc *d, st_hier *h);
void ed_step_free(st_undo_step *s);
/* Records the current value of (level, kind, vid) as "old" unless present
 * (touch_pos returns 1 when it was not). */
int ed_step_touch_pos(st_undo_step *s, const st_hier *h, unsigned level, uint32_t vid);
void ed_step_touch_detail(st_undo_step *s, const st_hier *h, unsigned level, uint32_t vid);
void ed_step_add_moved(st_undo_step *s, const st_map *m, unsigned level, uint32_t dart);
/* Every value st_hier_edit(h, l, darts, ., n, .) is going to write, as
 * "old" (core's st_hier_edit_footprint; scratch: its footprint, reused). */
void ed_step_touch_move(st_undo_step *s, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n,
                        st_footprint *scratch);
/* Reads the current values as "new" (end of the step). */
void ed_step_capture_new(st_undo_step *s, const st_hier *h);
/* Writes the old (which = 0) or new (1) values back (st_hier_restore),
 * appending what it wrote to fp. */
void ed_step_apply(const st_undo_step *s, st_hier *h, int which, st_footprint *fp);
void ed_step_finish(st_undo_step *s);   /* drops the index, computes bytes */
/* Bounded history of the document (st_doc_undo / st_doc_redo): pushes a
 * finished step, dropping the redo tail and, beyond undo_budget, the oldest
 * steps (d->note says so). */
void ed_push_step(st_doc *d, st_undo_step *s);
void ed_undo_clear(st_doc *d);

/* ---- editor.c ---- */
double ed_now_ms(void);
/* Ends a drag or a stroke in progress (another operation comes). */
void ed_finish_active(st_doc *d);
/* The memory budget before a drag or stroke at level l: the edit
 * re-synthesises the levels above, which may create their position
 * columns and, on a progressive hierarchy, the ring tables
 * (st_hier_synth_estimate).  -1, with d->refusal saying why, when the
 * model plus that estimate is over d->mem_budget. */
int ed_edit_budget(st_doc *d, unsigned l);
/* After any change of h's levels or scheme: selection cleared, levels
 * clamped, the box's display rebuilt, everything redrawn; _done also times
 * the change begun at t0. */
void ed_topology_changed(st_doc *d);
void ed_topology_done(st_doc *d, double t0);
/* Adding a level without a copy: removing the top level puts its id blocks
 * on the pools' spare stacks in reverse, so refining again gives the same
 * ids; the sum over the top level's ids checks it (editor.c). */
uint64_t ed_top_ids_sum(const st_map *m);
void ed_remove_top_keep_order(st_hier *h);
/* After a local change of h's geometry at level l with the given moved
 * darts: change bits, display sync, timing.  Core appended what it wrote
 * (st_hier_edit, st_hier_restore) to d->fp_model from index `from` on: the
 * box's display copies exactly that, and the renderer refreshes it
 * (st_doc_take_change); from > d->fp_model.n: no footprint, the display is
 * synced in full. */
void ed_geometry_changed(st_doc *d, unsigned l, const uint32_t *darts, uint32_t n, double t0, uint32_t from);
uint32_t ed_vertex_dart(st_doc *d, uint32_t vid);
/* The table behind ed_vertex_dart: one dart per vertex id of the editing
 * level (ST_NIL: none), *n entries, built on demand and kept while the
 * topology holds (d->vdart_level). */
const uint32_t *ed_vertex_darts(st_doc *d, uint32_t *n);
/* The pending step of the drag (active 1) or stroke (2) in progress, taken
 * (the document is left idle); NULL when no such operation is active or it
 * has no step. */
st_undo_step *ed_take_pending(st_doc *d, int active);
/* Ends an edit step: pushed on the undo stack unless nothing changed. */
void ed_push_edit(st_doc *d, st_undo_step *s);

/* ---- brush.c ---- */
struct st_brush_state;
void ed_brush_state_free(struct st_brush_state *bs);
/* Vertices of the editing level strictly inside the sphere (c, R) and their
 * falloff, from the stroke's grid (between st_doc_stroke_begin and end);
 * valid until the next query. */
uint32_t ed_brush_query(st_doc *d, const double c[3], double R, const uint32_t **vids, const double **w);

/* ---- editor_layers.c ---- */
/* Key of a layer value in an undo step: slot (core/multires/layers.h:
 * st_layers_get), level, vertex id. */
static inline uint64_t ed_layer_key(int slot, unsigned level, uint32_t vid)
{
    return (uint64_t)(uint32_t)(slot + 2) << 40 | (uint64_t)level << 33 | vid;
}
/* The edit of a drag or a stroke: records the old values of everything it
 * will write in s (h's footprint and the layer values), then edits h at
 * level l into the active layer when it is on l (else the level's own
 * details; st_layers_edit). */
void ed_model_edit(st_doc *d, st_undo_step *s, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n);
/* The slot a stroke or drag at level l goes into: the active layer when it
 * is on l, visible and at a strength != 0, else -1 (the level's own
 * details; d->note says why when the active layer could not take it). */
int ed_layer_target(st_doc *d, unsigned l);
/* Records the layer value (slot, level, vid) as "old" in s unless present. */
void ed_step_touch_layer(st_undo_step *s, const st_layers *ls, int slot, unsigned level, uint32_t vid);
/* ed_model_edit's recording part alone for the layers (a drag records
 * once at begin, then edits with s NULL). */
void ed_model_touch_layers(st_doc *d, st_undo_step *s, unsigned l, const uint32_t *darts, uint32_t n);
/* Layer values of s->lay: read as "new", written back (which 0 old, 1 new). */
void ed_layer_values_capture(st_undo_step *s, const st_layers *ls);
void ed_layer_values_apply(const st_undo_step *s, st_layers *ls, int which);
/* Whole-stack and mask parts of a step (has_layers / has_mask). */
void ed_step_apply_extra(st_doc *d, const st_undo_step *s, int which);

/* ---- brush.c ---- */
/* st_doc_stroke_begin; a mask stroke (moves_geometry 0) skips the memory
 * budget's check, as it re-synthesises nothing. */
int ed_stroke_begin(st_doc *d, int moves_geometry);

/* Recounts the displayed mesh's faces and vertices (st_doc_display_counts). */
void ed_count_display(st_doc *d);

/* ---- editor_hd.c ---- */
/* The display is shown instead of h: box on, or HD levels kept. */
int ed_display_on(const st_doc *d);
/* Non-zero detail at a level above the model's top in the display, or a
 * sculpt layer there. */
int ed_hd_detail_present(const st_doc *d);
/* Operations that rebuild the model's levels call this first: refused
 * (err says why) while the HD levels hold sculpted detail. */
int ed_hd_blocks(st_doc *d, const char *what, st_error *err);
/* The display was dropped or rebuilt: the HD state goes with it, and the
 * HD steps of the history, which name its ids. */
void ed_hd_forget(st_doc *d);
/* Stroke parts at hd_level (brush.c calls them): the map, vertex darts and
 * mask the kernel reads, the write of a dab's result with its undo
 * record, and undo / redo of an HD step. */
int ed_hd_stroke_begin(st_doc *d);
/* hd_level's vertex -> dart table and the kernel's mask (1 where a vertex
 * cannot move at hd_level), built again after the display changed. */
void ed_hd_tables(st_doc *d);
/* v is a display vertex that hd_level's selection and drags may move. */
int ed_hd_vertex_ok(const st_doc *d, uint32_t v);
/* Records the old level values of the darts' vertices in s (an HD step,
 * level s->level), and with _values alone not the values of the layers
 * a stroke or drag there writes (s->lay). */
void ed_hd_record(st_doc *d, st_undo_step *s, const uint32_t *darts, uint32_t n);
void ed_hd_record_values(st_doc *d, st_undo_step *s, const uint32_t *darts, uint32_t n);
/* HD mode on for what comes (a stroke, a layer): the box's display kept
 * with the box off, sculpted faces and layers kept refined.  -1 with
 * d->refusal saying why when HD levels are not possible now. */
int ed_hd_enter(st_doc *d);
/* Recomposes the layers of HD level l over the darts' vertices
 * (st_adapt_edit_layered) and tells the display. */
void ed_hd_recompose(st_doc *d, unsigned l, const uint32_t *darts, uint32_t n, double t0);
/* Writes the darts' vertices at hd_level (st_adapt_edit), recording in s
 * first when s is not NULL; the display reports what it wrote. */
void ed_hd_dab_write(st_doc *d, st_undo_step *s, const uint32_t *darts, const double (*pos)[3], uint32_t n, double t0);
void ed_hd_step_apply(st_doc *d, const st_undo_step *s, int redo);

/* ---- editor_mask.c ---- */
/* Vertices of the new top level take the mask's subdivision. */
void ed_mask_extend(st_doc *d);
/* The mask changed at these vertex ids (NULL, n 0: everywhere). */
void ed_mask_changed(st_doc *d, const uint32_t *vids, uint32_t n);

#endif
