/* The interest box's display (editor_display.c): the adaptive mesh the
 * window shows instead of the regular hierarchy when the box is on.
 *
 * It is a copy of the model's levels 0..copied_top (same ids), refined
 * adaptively inside the box by st_adapt (Kraemer 2008 §3.2.2-3.2.6), with
 * every vertex of a level <= the model's top at the position of the same
 * vertex of the model (found by a walk of both refinement structures: the
 * pairs below), and levels beyond the model's top synthesised from there.  The
 * model (the document's regular hierarchy) is never changed here: after
 * every edit of the model the document asks the display to follow.
 *
 * Part of strata_editor (no GL); the document (editor.c) is its only user. */
#ifndef ST_EDITOR_DISPLAY_H
#define ST_EDITOR_DISPLAY_H

#include <stdint.h>

#include "core/adapt/adapt.h"
#include "core/multires/edit.h"

typedef struct st_box_display {
    st_hier hier;              /* the adaptive display hierarchy (valid when built) */
    st_adapt adapt;            /* st_adapt's state on hier */
    int built;                 /* hier and adapt are built */
    int64_t euler0;            /* V - E + F of the model's level 0 when built (not for a progressive model):
                                  the display's counts without a walk (editor.c) */
    unsigned copied_top;       /* levels 0..copied_top of hier are copies of the model's (same ids) */

    /* Display vertex id -> model vertex id at the levels both have
     * (ST_NIL: no model vertex); identity up to copied_top.  Length
     * ndisp_to_model = hier.map.verts.end when the pairs were built. */
    uint32_t *disp_to_model_vertex;
    uint32_t ndisp_to_model;
    /* Model vertex id -> display vertex id, for vertices inserted above
     * copied_top and shown (ST_NIL: not shown); below, the ids are equal.
     * Length nmodel_to_disp = the model's verts.end. */
    uint32_t *model_to_disp_vertex;
    uint32_t nmodel_to_disp;
    /* Display vertex id -> bit L set when the vertex is paired at level L
     * (L > copied_top), and display vertex id -> one of its darts at level
     * min(model top, hier top), preferring an inner dart (ST_NIL: none);
     * both of length ndisp_vertices = hier.map.verts.end. */
    uint32_t *levels_of_disp_vertex;
    uint32_t *dart_of_disp_vertex;
    uint32_t ndisp_vertices;
    /* Every pairing above copied_top as (level, display vertex, model
     * vertex) triples, in the order of the walk: npairs entries (3 per
     * pair). */
    uint32_t *pairs;
    uint32_t npairs, cappairs;

    /* Per level L beyond the model's top: a dart of each of the display's
     * faces of level L-1 subdivided toward L, at
     * subdivided_faces[subdivided_faces_at[L] .. subdivided_faces_at[L+1]);
     * valid while subdivided_faces_ok (until the topology changes). */
    uint32_t *subdivided_faces;
    uint32_t nsubdivided_faces, capsubdivided_faces;
    uint32_t subdivided_faces_at[ST_MAX_LEVELS + 1];
    int subdivided_faces_ok;

    /* Since the document last took them (st_doc_take_change): */
    st_map_log patch_log;      /* changes of hier's map by box moves (ST_CHANGE_PATCH) */
    st_footprint written;      /* values of hier written by following local edits */
    uint32_t *moved;           /* display vertex ids whose positions changed (repeats possible) */
    uint32_t nmoved, capmoved;
} st_box_display;

/* Drops the display hierarchy and st_adapt's state (built = 0); the
 * arrays stay allocated for the next build. */
void st_box_display_drop(st_box_display *bd);
/* Frees everything (the struct may be zeroed and reused). */
void st_box_display_free(st_box_display *bd);

/* Builds the display of `model` for the box parameters p: a copy of the
 * model cut to p's base level, refined by st_adapt_update, paired and
 * synced.  On failure nothing is built. */
int st_box_display_build(st_box_display *bd, const st_hier *model, const st_adapt_params *p, st_error *err);

/* The box moved, base level unchanged: updates the display in place
 * (st_adapt_update), logging the map's changes in patch_log (cleared first
 * unless keep_log), then pairs and syncs the new vertices.  On failure the
 * display must be rebuilt. */
int st_box_display_move(st_box_display *bd, const st_hier *model, const st_adapt_params *p, int keep_log,
                        st_error *err);

/* The model's values of `keys` changed (core's footprint of an edit): the
 * display copies those positions and re-synthesises its levels beyond the
 * model around them only, reporting what it wrote in `written` and
 * `moved`. */
void st_box_display_follow_edit(st_box_display *bd, const st_hier *model, const uint64_t *keys, uint32_t nkeys);
/* The model changed at levels >= from without a footprint: every paired
 * position again, and a full synthesis beyond the model. */
void st_box_display_follow_model(st_box_display *bd, const st_hier *model, unsigned from);

/* The display wrote written.keys[from..] itself (an HD edit, its undo):
 * their vertices are reported as moved. */
void st_box_display_written(st_box_display *bd, uint32_t from);
/* Takes hier and adapt (a session's HD levels: an adaptive hierarchy whose
 * levels 0..model top are the model's, same ids) as the display, paired
 * with the model and synced to it.  Refused (nothing taken) when its
 * scheme or its levels up to the model's top do not match. */
int st_box_display_adopt(st_box_display *bd, const st_hier *model, st_hier *hier, st_adapt *adapt, st_error *err);

/* The model vertex shown as display vertex dv (ST_NIL: none). */
uint32_t st_box_display_model_vertex(const st_box_display *bd, uint32_t dv);

#endif
