/* The renderer's side of a model change: the window hands over what the
 * document shows and what changed since the last frame (st_scene,
 * st_scene_change), and the renderer picks its own refresh.
 *
 * The choices, cheapest that is exact first:
 *   - rebuild everything (st_renderer_set_level + set_cage) when nothing is
 *     shown yet, the topology changed, or what is shown changed (the
 *     displayed or editing level, the levels, the box on or off);
 *   - a box move that updated the adaptive map in place: re-tessellate
 *     only the faces its log names (st_renderer_patch), else rebuild;
 *   - every position changed (undo, analysis), or the model moved under
 *     the box without the display following: refresh all positions;
 *   - box on: the surface from what core wrote in the display's map, the
 *     cage from what it wrote in the model (their footprints);
 *   - box off: both from the model's footprint (st_renderer_refresh).
 * The document (ui/doc) states the change once; this file is the only one
 * that reads it for the meshes. */
#ifndef ST_SCENE_SYNC_H
#define ST_SCENE_SYNC_H

#include "render/renderer.h"

/* What is shown now. */
typedef struct st_scene {
    const st_map *model;      /* the model: the cage (and the surface with the box off) */
    const st_map *display;    /* the surface's map: model, or the interest box's adaptive map */
    unsigned display_level;   /* the surface's level in display */
    unsigned edit_level;      /* the cage's level in model */
    int box_on;               /* the interest box drives the display */
} st_scene;

/* What changed since the last st_renderer_show (the document's words). */
enum st_scene_change_bits {
    ST_SCENE_TOPOLOGY = 1,       /* levels, scheme, adaptive refinement */
    ST_SCENE_POSITIONS = 2,      /* vertices of the model moved: footprint */
    ST_SCENE_ALL_POSITIONS = 4,  /* everything moved */
    ST_SCENE_DISPLAY = 8,        /* box on: the display's map moved too: disp_footprint (the cage too when it is the display's, an HD level) */
    ST_SCENE_PATCH = 16          /* the box moved, the display's map changed in place: patch */
};
typedef struct st_scene_change {
    unsigned bits;                      /* enum st_scene_change_bits */
    uint32_t nmoved;                    /* model vertices moved */
    const st_footprint *footprint;      /* what core wrote in the model */
    const st_footprint *disp_footprint; /* what core wrote in the display's map */
    const st_map_log *patch;            /* the display map's changes of a box move */
} st_scene_change;

/* What the buffers were last built from; all zero: nothing. */
typedef struct st_scene_shown {
    unsigned display_level, edit_level, top;
    int box_on;
    int valid;
} st_scene_shown;

/* What st_renderer_show did. */
enum st_scene_done_bits {
    ST_SCENE_REBUILT = 1,    /* every buffer was built again */
    ST_SCENE_PATCHED = 2,    /* a box move was drawn by re-tessellating its faces */
    ST_SCENE_TOUCHED = 4,    /* some buffer changed */
    ST_SCENE_FAILED = 8      /* the model could not be drawn: err says why */
};

/* Brings the meshes up to s after change c; shown is the renderer's record
 * of what it holds (kept by the caller between frames, zeroed to force a
 * rebuild).  Returns enum st_scene_done_bits. */
unsigned st_renderer_show(st_renderer *r, st_scene_shown *shown, const st_scene *s, const st_scene_change *c,
                          st_error *err);

#endif
