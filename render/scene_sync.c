/* The renderer's choice of refresh after a model change (scene_sync.h). */
#include "render/scene_sync.h"

/* Every position again: the surface from the display's map, the cage from
 * the model. */
static void refresh_all(st_renderer *r, const st_scene *s)
{
    if (s->display == s->model) { st_renderer_refresh_all(r, ST_TARGET_MESHES, s->model); return; }
    st_renderer_refresh_all(r, ST_TARGET_SURFACE, s->display);
    st_renderer_refresh_all(r, ST_TARGET_CAGE, s->model);
}

static int build(st_renderer *r, const st_scene *s, st_error *err)
{
    return st_renderer_set_level(r, s->display, s->display_level, err) ||
           st_renderer_set_cage(r, s->model, s->edit_level, err);
}

static int needs_rebuild(const st_scene_shown *shown, const st_scene *s, const st_scene_change *c)
{
    return !shown->valid || (c->bits & ST_SCENE_TOPOLOGY) || s->display_level != shown->display_level ||
           s->edit_level != shown->edit_level || s->model->top != shown->top || s->box_on != shown->box_on;
}

/* Positions only: which footprint refreshes which target. */
static unsigned refresh_positions(st_renderer *r, const st_scene *s, const st_scene_change *c)
{
    int boxed = s->display != s->model;
    if ((c->bits & ST_SCENE_ALL_POSITIONS) ||
        ((c->bits & ST_SCENE_POSITIONS) && boxed && !(c->bits & ST_SCENE_DISPLAY))) {
        refresh_all(r, s);
        return ST_SCENE_TOUCHED;
    }
    if (boxed && (c->bits & (ST_SCENE_POSITIONS | ST_SCENE_DISPLAY))) {
        int rc = 0;
        if (c->bits & ST_SCENE_DISPLAY) rc |= st_renderer_refresh(r, ST_TARGET_SURFACE, s->display, c->disp_footprint);
        if (c->bits & ST_SCENE_POSITIONS) rc |= st_renderer_refresh(r, ST_TARGET_CAGE, s->model, c->footprint);
        if (rc) refresh_all(r, s);
        return ST_SCENE_TOUCHED;
    }
    if (!boxed && (c->bits & ST_SCENE_DISPLAY)) {
        /* The cage is the display's own map (an HD level, ui/doc/editor_hd.c):
         * what the display wrote refreshes both. */
        if (st_renderer_refresh(r, ST_TARGET_MESHES, s->display, c->disp_footprint)) refresh_all(r, s);
        return ST_SCENE_TOUCHED;
    }
    if ((c->bits & ST_SCENE_POSITIONS) && c->nmoved) {
        if (st_renderer_refresh(r, ST_TARGET_MESHES, s->model, c->footprint)) {
            /* Out of memory for the incremental path: rebuild. */
            st_error ignored;
            build(r, s, &ignored);
            return ST_SCENE_TOUCHED | ST_SCENE_REBUILT;
        }
        return ST_SCENE_TOUCHED;
    }
    return 0;
}

unsigned st_renderer_show(st_renderer *r, st_scene_shown *shown, const st_scene *s, const st_scene_change *c,
                          st_error *err)
{
    if (needs_rebuild(shown, s, c)) {
        unsigned done = ST_SCENE_REBUILT | ST_SCENE_TOUCHED;
        if (build(r, s, err)) done |= ST_SCENE_FAILED;
        *shown = (st_scene_shown){ s->display_level, s->edit_level, s->model->top, s->box_on, 1 };
        return done;   /* the buffers were just built from the current positions */
    }
    unsigned done = 0;
    if (c->bits & ST_SCENE_PATCH) {
        /* A box move: only the touched faces are re-tessellated. */
        if (!st_renderer_patch(r, s->display, c->patch)) done |= ST_SCENE_PATCHED;
        else if (st_renderer_set_level(r, s->display, s->display_level, err)) done |= ST_SCENE_FAILED;
        done |= ST_SCENE_TOUCHED;
    }
    return done | refresh_positions(r, s, c);
}
