/* The modeller's actions: the table of everything a key does (actions.h),
 * what each action runs, and when it is enabled.
 *
 * Not in the table: pointer input (orbit, pan, zoom, clicks, rectangles,
 * drags, brush strokes, box handles, dropped files), which is continuous and
 * stays in the window's pointer handlers (window.c); it is listed for F1
 * and the key table in st_gestures below.  Modifier keys pressed alone are
 * state (held modifiers change a drag), not actions (window.c).
 *
 * Adding a key: an id in actions.h, an entry below; F1 follows, and
 * `strata --keys` prints docs/MODELLER.md's key table (tests/ui/test_actions.c fails
 * until docs/MODELLER.md is updated). */
#include "actions.h"
#include "core/adapt/adapt.h"
#include "core/fvar/fvar.h"

#include <math.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "gui.h"
#include "window.h"

/* ---- what the keys run ---------------------------------------------------------- */

static const char *const scheme_cycle[] = { "catmull-clark", "loop", "butterfly", "quad-triangle", "sqrt3", "doo-sabin" };
#define NSCHEMES (sizeof scheme_cycle / sizeof scheme_cycle[0])

/* The scheme after cur in the cycle that the control mesh can take and is
 * not the model's own (Loop, Butterfly and sqrt3 are skipped on quads, as
 * the Scheme menu greys them out); cur itself when there is none. */
static const char *next_scheme(st_app *a, const char *cur)
{
    unsigned at = NSCHEMES - 1;
    for (unsigned i = 0; i < NSCHEMES; i++)
        if (cur && !strcmp(cur, scheme_cycle[i])) at = i;
    const char *own = a->doc.scheme ? a->doc.scheme->name : "";
    int rc[NSCHEMES];
    st_error err[NSCHEMES];
    st_doc_schemes_accepted(&a->doc, scheme_cycle, NSCHEMES, rc, err);
    for (unsigned k = 1; k <= NSCHEMES; k++) {
        unsigned i = (at + k) % NSCHEMES;
        if (strcmp(scheme_cycle[i], own) && rc[i] == ST_OK) return scheme_cycle[i];
    }
    return cur;
}

static void report(st_app *a, int rc, const st_error *err, const char *what)
{
    if (rc) st_app_message(a, 1, "%s: %s", what, err->msg);
    st_app_sync(a);
}

static void move_box(st_app *a, int axis, double dir, int resize)
{
    st_doc *d = &a->doc;
    if (!d->box_on) { st_app_message(a, 0, "the interest box is hidden: I shows it"); return; }
    st_adapt_params b = d->box;
    double step = 0.05 * 2 * a->cc.radius;
    if (resize) {
        double half = 0.5 * (b.box_hi[axis] - b.box_lo[axis]) + 0.5 * dir * step;
        if (half < 0.25 * step) half = 0.25 * step;
        double c = 0.5 * (b.box_hi[axis] + b.box_lo[axis]);
        b.box_lo[axis] = c - half;
        b.box_hi[axis] = c + half;
    } else {
        b.box_lo[axis] += dir * step;
        b.box_hi[axis] += dir * step;
    }
    st_error err;
    double t0 = st_now_ms();
    int rc = st_doc_set_box(d, &b, 1, &err);
    report(a, rc, &err, "cannot move the box");
    if (!rc) {
        char t[32];
        st_app_message(a, 0, "box %s, adaptive mesh updated in %s", resize ? "resized" : "moved",
                       st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t));
    }
}

static void box_levels(st_app *a, int base, int dir)
{
    st_doc *d = &a->doc;
    st_adapt_params b = d->box;
    if (base) {
        if (dir < 0 && b.base_level == 0) return;
        b.base_level += dir;
        if (b.base_level > b.max_level) b.max_level = b.base_level;
    } else {
        if (dir < 0 && b.max_level == 0) return;
        b.max_level += dir;
        if (b.base_level > b.max_level) b.base_level = b.max_level;
    }
    st_error err;
    int rc = st_doc_set_box(d, &b, d->box_on, &err);
    report(a, rc, &err, "cannot change the box levels");
    if (!rc) st_app_message(a, 0, "box levels %u..%u", d->box.base_level, d->box.max_level);
}

/* The first time the box is shown on a model it goes where the user
 * looks: a cube of a fifth of the model's size around the surface point
 * under the cursor, or else the half of the model's bounding box that
 * faces the camera (along the axis closest to the view), so that the
 * visible side is refined, not the inside of the body.  Its levels: from
 * 0 to the displayed level + 1. */
static void place_box(st_app *a, st_adapt_params *b)
{
    const float *bb = a->cc.bbox;
    double p[3];
    if (st_app_surface_at_cursor(a, p)) {
        for (int k = 0; k < 3; k++) {
            double h = 0.1 * (bb[k + 3] - bb[k]);
            b->box_lo[k] = p[k] - h;
            b->box_hi[k] = p[k] + h;
        }
    } else {
        double right[3], up[3], back[3];
        st_camctl_axes(&a->cc, right, up, back);
        int axis = 0;
        for (int k = 1; k < 3; k++)
            if (fabs(back[k]) > fabs(back[axis])) axis = k;
        for (int k = 0; k < 3; k++) {
            b->box_lo[k] = bb[k];
            b->box_hi[k] = bb[k + 3];
        }
        /* A little past the middle, so that the box crosses the surface of
         * a thin model too. */
        double mid = 0.5 * (bb[axis] + bb[axis + 3]), past = 0.05 * (bb[axis + 3] - bb[axis]);
        if (back[axis] > 0) b->box_lo[axis] = mid - past;
        else b->box_hi[axis] = mid + past;
    }
    b->has_box = 1;
    b->base_level = 0;
    unsigned shown = st_doc_display_map_level(&a->doc);
    b->max_level = shown + 1 < ST_MAX_LEVELS ? shown + 1 : shown;
}

static void toggle_box(st_app *a)
{
    st_doc *d = &a->doc;
    st_adapt_params b = d->box;
    if (!d->box_on && !a->box_placed) place_box(a, &b);
    st_error err;
    double t0 = st_now_ms();
    int rc = st_doc_set_box(d, &b, !d->box_on, &err);
    report(a, rc, &err, "cannot change the interest box");
    if (!rc) {
        a->box_placed = 1;
        char t[32];
        st_app_message(a, 0, "interest box %s (%s)", d->box_on ? "on" : "off", st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t));
    }
}

/* When an action may run.  Keys wait for the mouse: while a drag, a
 * stroke, a rectangle or a box drag is under way only Esc, F1, Ctrl+Q and
 * (for a grab) Enter act; orbiting and panning let keys through. */
static int grabbing(const st_app *a) { return a->op == ST_OP_GRAB; }
static int keys_free(const st_app *a) { return a->op == ST_OP_NONE || a->op == ST_OP_ORBIT || a->op == ST_OP_PAN; }
static int model_keys_free(const st_app *a) { return keys_free(a) && a->doc.loaded; }
/* The UV checker needs UVs at the displayed level of the model, or on the
 * interest box's adaptive display (core/adapt/adapt.h: st_adapt_uv_absent);
 * once on, it can always be switched off (another model, or a level
 * without UVs, draws plain). */
/* Show baked map: once something was baked for this model (and can
 * always be switched off). */
static int baked_keys_free(const st_app *a) { return model_keys_free(a) && (a->bake.show || st_app_can_show_baked(a)); }
static int uv_keys_free(const st_app *a)
{
    const st_doc *d = &a->doc;
    int has = d->box_on ? d->display.built && !st_adapt_uv_absent(&d->display.adapt)
                        : st_hier_has_uv(&d->h, st_doc_display_map_level(d));
    return model_keys_free(a) && (a->checker || has);
}

/* File: the dialogs are the GUI's (ui/gui.cc); a key opens them and shows
 * the GUI if it was hidden. */
static void open_file(st_app *a) { st_gui_open_dialog(a, ST_DIALOG_OPEN); }
static void import_file(st_app *a) { st_gui_open_dialog(a, ST_DIALOG_IMPORT); }
static void save(st_app *a) { st_app_request_save(a); }
static void save_as(st_app *a) { st_gui_open_dialog(a, ST_DIALOG_SAVE_AS); }
static void export_mesh(st_app *a) { st_gui_open_dialog(a, ST_DIALOG_EXPORT); }
static void restore_recovery(st_app *a) { st_app_request_recovery(a); }

/* Edit */
static void undo_redo(st_app *a, int redo)
{
    st_doc *d = &a->doc;
    st_error err;
    int rc = redo ? st_doc_redo(d, &err) : st_doc_undo(d, &err);
    if (rc == -1) st_app_message(a, 0, "nothing to %s", redo ? "redo" : "undo");
    else if (rc) st_app_message(a, 1, "%s failed: %s", redo ? "redo" : "undo", err.msg);
    else st_app_message(a, 0, "%s (%u/%u)", redo ? "redone" : "undone", d->undo_pos, d->nundo);
    st_app_sync(a);
}
static void undo(st_app *a) { undo_redo(a, 0); }
static void redo(st_app *a) { undo_redo(a, 1); }
static void select_all(st_app *a) { st_app_select_all(a, 0); }
static void select_none(st_app *a) { st_app_select_all(a, 1); }

/* G: the selection follows the mouse until a click or Enter (Blender's grab). */
static void grab(st_app *a)
{
    if (!a->doc.nsel) { st_app_message(a, 0, "nothing selected to grab"); return; }
    a->op_x0 = a->mx;
    a->op_y0 = a->my;
    a->op_mods = 0;
    st_app_drag_start(a, ST_OP_GRAB);
}
static void grab_confirm(st_app *a) { st_app_drag_finish(a, 0); }

/* Tools */
static void set_tool(st_app *a, int tool)
{
    a->tool = tool;
    if (tool != ST_TOOL_SELECT) st_brush_set_tool(&a->doc.brush, tool);
    st_app_update_hover(a);
}
static void tool_select(st_app *a) { set_tool(a, ST_TOOL_SELECT); }
static void brush_grab(st_app *a) { set_tool(a, ST_BRUSH_GRAB); }
static void brush_draw(st_app *a) { set_tool(a, ST_BRUSH_DRAW); }
static void brush_smooth(st_app *a) { set_tool(a, ST_BRUSH_SMOOTH); }
static void brush_flatten(st_app *a) { set_tool(a, ST_BRUSH_FLATTEN); }
static void brush_crease(st_app *a) { set_tool(a, ST_BRUSH_CREASE); }
static void brush_pinch(st_app *a) { set_tool(a, ST_BRUSH_PINCH); }
static void brush_inflate(st_app *a) { set_tool(a, ST_BRUSH_INFLATE); }
static void brush_clay_strips(st_app *a) { set_tool(a, ST_BRUSH_CLAY_STRIPS); }
static void brush_layer(st_app *a) { set_tool(a, ST_BRUSH_LAYER); }
static void brush_relax(st_app *a) { set_tool(a, ST_BRUSH_RELAX); }
static void radius_down(st_app *a) { a->doc.brush.radius /= 1.15; }
static void radius_up(st_app *a) { a->doc.brush.radius *= 1.15; }
static void strength_down(st_app *a) { a->doc.brush.strength = fmax(0.02, a->doc.brush.strength - 0.05); }
static void strength_up(st_app *a) { a->doc.brush.strength = fmin(1.0, a->doc.brush.strength + 0.05); }
static void falloff_step(st_app *a, int dir)
{
    st_brush *b = &a->doc.brush;
    b->falloff = (b->falloff + dir + ST_FALLOFF_COUNT) % ST_FALLOFF_COUNT;
    st_app_message(a, 0, "falloff %s", st_falloff_name(b->falloff));
}
static void falloff_next(st_app *a) { falloff_step(a, 1); }
static void falloff_prev(st_app *a) { falloff_step(a, -1); }
static void mirror_x(st_app *a) { a->doc.brush.mirror_x = !a->doc.brush.mirror_x; }
static void mirror_y(st_app *a) { a->doc.brush.mirror_y = !a->doc.brush.mirror_y; }
static void mirror_z(st_app *a) { a->doc.brush.mirror_z = !a->doc.brush.mirror_z; }
static void stabilize(st_app *a)
{
    a->doc.brush.stabilize = !a->doc.brush.stabilize;
    st_app_message(a, 0, "stabiliser %s", a->doc.brush.stabilize ? "on" : "off");
}
static void front_only(st_app *a)
{
    a->doc.brush.front_only = !a->doc.brush.front_only;
    st_app_message(a, 0, "front faces only %s", a->doc.brush.front_only ? "on" : "off");
}

/* Mesh: the editing level moves between 0 and the top, the displayed one
 * between the editing level and the top. */
static void step_level(st_app *a, int display, int up)
{
    st_doc *d = &a->doc;
    int down = !up;
    if (display) {
        if (st_doc_display_adaptive(d)) { st_app_message(a, 0, "the interest box decides the display: I hides it"); return; }
        unsigned l = d->display_level;
        if (down && l > d->edit_level) l--;
        if (up && l < d->h.map.top) l++;
        st_doc_set_display_level(d, l);
    } else {
        unsigned l = st_doc_sculpt_level(d);
        if (down && l > 0) l--;
        if (up && l < st_doc_level_limit(d)) l++;
        st_doc_set_edit_level(d, l);
    }
    st_app_sync(a);
    st_app_update_hover(a);
}
static void edit_level_up(st_app *a) { step_level(a, 0, 1); }
static void edit_level_down(st_app *a) { step_level(a, 0, 0); }
static void display_level_up(st_app *a) { step_level(a, 1, 1); }
static void display_level_down(st_app *a) { step_level(a, 1, 0); }
static void add_level(st_app *a) { st_app_request_add_level(a); }
static void delete_finest(st_app *a)
{
    st_error err;
    report(a, st_doc_remove_top(&a->doc, &err), &err, "cannot delete the finest level");
}
static void delete_coarsest(st_app *a)
{
    st_error err;
    report(a, st_doc_remove_bottom(&a->doc, &err), &err, "cannot delete the coarsest level");
}
/* K asks first (the rebuild loses the details): the scheme question. */
static void change_scheme(st_app *a)
{
    const char *own = a->doc.scheme ? a->doc.scheme->name : NULL;
    const char *s = next_scheme(a, own);
    if (s && s != own) a->pending_scheme = s;
    else st_app_message(a, 0, "no other scheme can take this control mesh");
}
static void rebuild_levels(st_app *a) { st_app_request_rebuild(a); }
static void scheme_next(st_app *a) { a->pending_scheme = next_scheme(a, a->pending_scheme); }
static void scheme_confirm(st_app *a)
{
    const char *s = a->pending_scheme;
    a->pending_scheme = NULL;
    st_app_request_scheme(a, s);
}
static void scheme_keep(st_app *a)
{
    a->pending_scheme = NULL;
    st_app_message(a, 0, "scheme unchanged");
}

/* Mask (ui/doc/editor_mask.c) */
static void mask_brush(st_app *a)
{
    a->mask_brush = !a->mask_brush;
    st_app_message(a, 0, a->mask_brush ? "mask brush: a stroke brushes the mask in, Ctrl+stroke erases it" : "mask brush off");
}
static void mask_done(st_app *a, int rc, const char *what)
{
    if (rc) st_app_message(a, 1, "no model");
    else st_app_message(a, 0, "%s", what);
    st_app_sync(a);
}
static void mask_clear(st_app *a) { mask_done(a, st_doc_mask_clear(&a->doc), "mask cleared"); }
static void mask_invert(st_app *a) { mask_done(a, st_doc_mask_invert(&a->doc), "mask inverted"); }
static void mask_grow(st_app *a) { mask_done(a, st_doc_mask_grow(&a->doc), "mask grown"); }
static void mask_shrink(st_app *a) { mask_done(a, st_doc_mask_shrink(&a->doc), "mask shrunk"); }
static void mask_smooth(st_app *a) { mask_done(a, st_doc_mask_smooth(&a->doc), "mask smoothed"); }
static void mask_cavity(st_app *a) { mask_done(a, st_doc_mask_cavity(&a->doc), "mask by cavity"); }

/* Sculpt layers (ui/doc/editor_layers.c): the active one. */
static int active_layer(st_app *a)
{
    int k = a->doc.layers.active;
    if (k < 0 || (uint32_t)k >= a->doc.layers.n) {
        st_app_message(a, 1, "no active layer (Ctrl+L adds one, V picks one)");
        return -1;
    }
    return k;
}
static void layer_add(st_app *a)
{
    st_error err;
    int rc = st_doc_layer_add(&a->doc, NULL, &err);
    if (!rc) {
        const st_layer *y = &a->doc.layers.v[a->doc.layers.active];
        st_app_message(a, 0, "layer '%s' on %slevel %u: strokes go into it", y->name,
                       y->level > a->doc.h.map.top ? "HD " : "", y->level);
    }
    report(a, rc, &err, "cannot add a layer");
}
/* V: the next layer up the stack, then none (the level's own details). */
static void layer_next(st_app *a)
{
    st_layers *ls = &a->doc.layers;
    if (!ls->n) { st_app_message(a, 1, "no layers (Ctrl+L adds one)"); return; }
    int k = ls->active + 1 >= (int)ls->n ? -1 : ls->active + 1;
    st_error err;
    report(a, st_doc_layer_set_active(&a->doc, k, &err), &err, "cannot pick the layer");
    if (k < 0) st_app_message(a, 0, "no active layer: strokes go into the level's own details");
    else st_app_message(a, 0, "active layer '%s' (level %u)", ls->v[k].name, ls->v[k].level);
}
static void layer_hide(st_app *a)
{
    int k = active_layer(a);
    if (k < 0) return;
    st_error err;
    report(a, st_doc_layer_set_hidden(&a->doc, k, !a->doc.layers.v[k].hidden, &err), &err, "cannot hide the layer");
}
static void layer_strength(st_app *a, double step)
{
    int k = active_layer(a);
    if (k < 0) return;
    st_error err;
    double s = a->doc.layers.v[k].strength + step;
    report(a, st_doc_layer_set_strength(&a->doc, k, s, &err), &err, "cannot set the strength");
    st_app_message(a, 0, "layer '%s': strength %.2f", a->doc.layers.v[k].name, a->doc.layers.v[k].strength);
}
static void layer_weaker(st_app *a) { layer_strength(a, -0.25); }
static void layer_stronger(st_app *a) { layer_strength(a, 0.25); }
static void layer_move(st_app *a, int dir)
{
    int k = active_layer(a);
    if (k < 0) return;
    int to = k + dir;
    if (to < 0 || to >= (int)a->doc.layers.n) return;
    st_error err;
    report(a, st_doc_layer_move(&a->doc, k, to, &err), &err, "cannot move the layer");
}
static void layer_up(st_app *a) { layer_move(a, 1); }
static void layer_down(st_app *a) { layer_move(a, -1); }
static void layer_merge(st_app *a)
{
    int k = active_layer(a);
    if (k < 0) return;
    st_error err;
    report(a, st_doc_layer_merge_down(&a->doc, k, &err), &err, "cannot merge");
}
static void layer_delete(st_app *a)
{
    int k = active_layer(a);
    if (k < 0) return;
    st_error err;
    report(a, st_doc_layer_delete(&a->doc, k, &err), &err, "cannot delete the layer");
}

/* Box */
static void box_toggle(st_app *a) { toggle_box(a); }
static void box_move_xn(st_app *a) { move_box(a, 0, -1, 0); }
static void box_move_xp(st_app *a) { move_box(a, 0, 1, 0); }
static void box_move_yn(st_app *a) { move_box(a, 1, -1, 0); }
static void box_move_yp(st_app *a) { move_box(a, 1, 1, 0); }
static void box_move_zn(st_app *a) { move_box(a, 2, -1, 0); }
static void box_move_zp(st_app *a) { move_box(a, 2, 1, 0); }
static void box_shrink_x(st_app *a) { move_box(a, 0, -1, 1); }
static void box_grow_x(st_app *a) { move_box(a, 0, 1, 1); }
static void box_shrink_y(st_app *a) { move_box(a, 1, -1, 1); }
static void box_grow_y(st_app *a) { move_box(a, 1, 1, 1); }
static void box_shrink_z(st_app *a) { move_box(a, 2, -1, 1); }
static void box_grow_z(st_app *a) { move_box(a, 2, 1, 1); }
static void box_max_up(st_app *a) { box_levels(a, 0, 1); }
static void box_max_down(st_app *a) { box_levels(a, 0, -1); }
static void box_base_up(st_app *a) { box_levels(a, 1, 1); }
static void box_base_down(st_app *a) { box_levels(a, 1, -1); }

/* View */
static void frame_all(st_app *a) { st_app_frame_model(a); }
static void view(st_app *a, int v) { st_app_view(a, v); }
static void view_front(st_app *a) { view(a, ST_CV_FRONT); }
static void view_back(st_app *a) { view(a, ST_CV_BACK); }
static void view_right(st_app *a) { view(a, ST_CV_RIGHT); }
static void view_left(st_app *a) { view(a, ST_CV_LEFT); }
static void view_top(st_app *a) { view(a, ST_CV_TOP); }
static void view_bottom(st_app *a) { view(a, ST_CV_BOTTOM); }
static void projection(st_app *a) { st_camctl_toggle_ortho(&a->cc); st_pick_invalidate(&a->pick); }
/* 15 degrees: st_camctl_orbit turns 0.4 degrees per pixel. */
static void orbit(st_app *a, float dx, float dy) { st_camctl_orbit(&a->cc, dx, dy); st_pick_invalidate(&a->pick); }
static void orbit_left(st_app *a) { orbit(a, 15 / 0.4f, 0); }
static void orbit_right(st_app *a) { orbit(a, -15 / 0.4f, 0); }
static void orbit_up(st_app *a) { orbit(a, 0, 15 / 0.4f); }
static void orbit_down(st_app *a) { orbit(a, 0, -15 / 0.4f); }
static void shading(st_app *a) { a->shading = a->shading == ST_SHADE_SMOOTH ? ST_SHADE_FLAT : ST_SHADE_SMOOTH; }
static void wireframe(st_app *a) { a->wire = !a->wire; }
static void cage(st_app *a) { a->cage = !a->cage; st_pick_invalidate(&a->pick); }
static void uv_checker(st_app *a) { a->checker = !a->checker; st_app_sync(a); }
static void bake_maps(st_app *a) { st_gui_show_bake(a); }
static void show_baked(st_app *a)
{
    a->bake.show = !a->bake.show;
    if (a->bake.show) st_app_message(a, 0, "showing level %u with the baked map %s", a->bake.have_base, st_path_base(a->bake.have_map));
}
static void toggle_gui(st_app *a) { (void)a; st_gui_set_shown(!st_gui_shown()); }

/* Help */
static void help(st_app *a) { a->help = !a->help; }
static void about(st_app *a) { (void)a; st_gui_set_shown(1); st_gui_show_about(); }
static void preferences(st_app *a) { (void)a; st_gui_set_shown(1); st_gui_show_prefs(); }
static void quit(st_app *a) { st_app_request_quit(a); }
/* The quit question's answers. */
static void quit_save(st_app *a)
{
    a->quit_asking = 0;
    a->quit_after_save = 1;
    st_app_request_save(a);
}
static void quit_discard(st_app *a)
{
    a->quit_asking = 0;
    a->quit = 1;
}
static void quit_cancel(st_app *a)
{
    a->quit_asking = 0;
    st_app_message(a, 0, "quit cancelled");
}
/* Esc closes the help, else cancels what the mouse is doing. */
static void cancel(st_app *a)
{
    st_doc *d = &a->doc;
    st_error err;
    if (a->help) a->help = 0;
    else if (a->op == ST_OP_DRAG || a->op == ST_OP_GRAB) st_app_drag_finish(a, 1);
    else if (a->op == ST_OP_RECT || a->op == ST_OP_STROKE_WAIT) a->op = ST_OP_NONE;
    else if (a->op == ST_OP_BOX) {
        st_doc_set_box(d, &a->box_start, 1, &err);
        st_doc_box_end(d);
        a->op = ST_OP_NONE;
        st_app_sync(a);
    }
}

/* ---- the table ------------------------------------------------------------------ */

#define C ST_MOD_CTRL
#define S ST_MOD_SHIFT
#define A ST_MOD_ALT
#define ANY ST_MODS
/* KEY(name, needed modifiers, tolerated modifiers) */
#define KEY(k, mods, tolerate) { GLFW_KEY_##k, mods, tolerate }
#define ACT(id, cat, name, help, run, enabled, ...) [id] = { id, name, cat, ST_KEYS_WINDOW, { __VA_ARGS__ }, help, run, enabled }
#define ASK(id, name, help, run, ...) [id] = { id, name, ST_CAT_MESH, ST_KEYS_SCHEME_QUESTION, { __VA_ARGS__ }, help, run, NULL }
#define ASK_QUIT(id, name, help, run, ...) [id] = { id, name, ST_CAT_FILE, ST_KEYS_QUIT_QUESTION, { __VA_ARGS__ }, help, run, NULL }

const st_action st_actions[ST_NACTIONS] = {
    ACT(ST_ACT_OPEN, ST_CAT_FILE, "Open...", "open a mesh or a .strata session (file dialog)", open_file, keys_free,
        KEY(O, C, 0)),
    ACT(ST_ACT_IMPORT, ST_CAT_FILE, "Import...",
        "import a mesh (OBJ, PLY, OFF, glTF/GLB) as a new untitled document (file dialog; Save asks for a name)",
        import_file, keys_free, KEY(I, C | S, 0)),
    ACT(ST_ACT_SAVE, ST_CAT_FILE, "Save session",
        "save the session as NAME.strata (current directory; a .strata saves over itself)",
        save, model_keys_free, KEY(S, C, S | A)),
    ACT(ST_ACT_SAVE_AS, ST_CAT_FILE, "Save session as...", "save the session under a name (file dialog)", save_as,
        model_keys_free, KEY(F12, 0, 0)),
    ACT(ST_ACT_EXPORT, ST_CAT_FILE, "Export...",
        "export the displayed mesh (level, or adaptive mesh with the box on) as OBJ, PLY, glTF or GLB",
        export_mesh, model_keys_free, KEY(E, C, 0)),
    ACT(ST_ACT_RESTORE_RECOVERY, ST_CAT_FILE, "Restore recovery", "restore the autosaved recovery session",
        restore_recovery, model_keys_free, KEY(R, C, S | A)),
    ACT(ST_ACT_QUIT, ST_CAT_FILE, "Quit", "quit", quit, NULL, KEY(Q, C, S | A)),

    ACT(ST_ACT_UNDO, ST_CAT_EDIT, "Undo", "undo / redo", undo, model_keys_free, KEY(Z, C, A)),
    ACT(ST_ACT_REDO, ST_CAT_EDIT, "Redo", "undo / redo", redo, model_keys_free, KEY(Z, C | S, A), KEY(Y, C, S | A)),
    ACT(ST_ACT_SELECT_ALL, ST_CAT_EDIT, "Select all", "select all / none", select_all, model_keys_free, KEY(A, 0, S)),
    ACT(ST_ACT_SELECT_NONE, ST_CAT_EDIT, "Select none", "select all / none", select_none, model_keys_free, KEY(A, A, S)),
    ACT(ST_ACT_PREFERENCES, ST_CAT_EDIT, "Preferences...", "preferences: UI scale, recent files, where they are kept",
        preferences, NULL, KEY(U, C | A, 0)),
    ACT(ST_ACT_GRAB, ST_CAT_EDIT, "Grab",
        "grab the selection: move the mouse, click or Enter confirms, right click or Esc cancels",
        grab, model_keys_free, KEY(G, 0, S | A)),
    ACT(ST_ACT_GRAB_CONFIRM, ST_CAT_EDIT, "Confirm grab", "confirm a grab", grab_confirm, grabbing,
        KEY(ENTER, 0, ANY), KEY(KP_ENTER, 0, ANY)),

    ACT(ST_ACT_TOOL_SELECT, ST_CAT_TOOLS, "Select/move tool", "select/move tool", tool_select, model_keys_free,
        KEY(W, 0, S | A)),
    ACT(ST_ACT_BRUSH_GRAB, ST_CAT_TOOLS, "Grab brush", "brush: grab / draw / smooth / flatten", brush_grab,
        model_keys_free, KEY(B, 0, S | A)),
    ACT(ST_ACT_BRUSH_DRAW, ST_CAT_TOOLS, "Draw brush", "brush: grab / draw / smooth / flatten", brush_draw,
        model_keys_free, KEY(D, 0, S | A)),
    ACT(ST_ACT_BRUSH_SMOOTH, ST_CAT_TOOLS, "Smooth brush", "brush: grab / draw / smooth / flatten",
        brush_smooth, model_keys_free, KEY(S, 0, S | A)),
    ACT(ST_ACT_BRUSH_FLATTEN, ST_CAT_TOOLS, "Flatten brush", "brush: grab / draw / smooth / flatten",
        brush_flatten, model_keys_free, KEY(F, 0, A)),
    ACT(ST_ACT_BRUSH_CREASE, ST_CAT_TOOLS, "Crease brush", "brush: crease / pinch / inflate / clay strips / layer / relax",
        brush_crease, model_keys_free, KEY(C, S, A)),
    ACT(ST_ACT_BRUSH_PINCH, ST_CAT_TOOLS, "Pinch brush", "brush: crease / pinch / inflate / clay strips / layer / relax",
        brush_pinch, model_keys_free, KEY(P, 0, A)),
    ACT(ST_ACT_BRUSH_INFLATE, ST_CAT_TOOLS, "Inflate brush", "brush: crease / pinch / inflate / clay strips / layer / relax",
        brush_inflate, model_keys_free, KEY(I, S, A)),
    ACT(ST_ACT_BRUSH_CLAY_STRIPS, ST_CAT_TOOLS, "Clay strips brush",
        "brush: crease / pinch / inflate / clay strips / layer / relax", brush_clay_strips, model_keys_free,
        KEY(T, 0, A)),
    ACT(ST_ACT_BRUSH_LAYER, ST_CAT_TOOLS, "Layer brush", "brush: crease / pinch / inflate / clay strips / layer / relax",
        brush_layer, model_keys_free, KEY(L, 0, 0)),
    ACT(ST_ACT_BRUSH_RELAX, ST_CAT_TOOLS, "Relax brush", "brush: crease / pinch / inflate / clay strips / layer / relax",
        brush_relax, model_keys_free, KEY(R, S, A)),
    ACT(ST_ACT_RADIUS_DOWN, ST_CAT_TOOLS, "Smaller brush", "brush radius smaller / larger (also Ctrl+Wheel)",
        radius_down, model_keys_free, KEY(LEFT_BRACKET, 0, A)),
    ACT(ST_ACT_RADIUS_UP, ST_CAT_TOOLS, "Larger brush", "brush radius smaller / larger (also Ctrl+Wheel)", radius_up,
        model_keys_free, KEY(RIGHT_BRACKET, 0, A)),
    ACT(ST_ACT_STRENGTH_DOWN, ST_CAT_TOOLS, "Weaker brush", "brush strength down / up", strength_down,
        model_keys_free, KEY(LEFT_BRACKET, S, A)),
    ACT(ST_ACT_STRENGTH_UP, ST_CAT_TOOLS, "Stronger brush", "brush strength down / up", strength_up,
        model_keys_free, KEY(RIGHT_BRACKET, S, A)),
    ACT(ST_ACT_FALLOFF_NEXT, ST_CAT_TOOLS, "Next falloff",
        "brush falloff: next / previous preset (smooth, sphere, root, sharp, linear, constant)", falloff_next,
        model_keys_free, KEY(O, 0, A)),
    ACT(ST_ACT_FALLOFF_PREV, ST_CAT_TOOLS, "Previous falloff",
        "brush falloff: next / previous preset (smooth, sphere, root, sharp, linear, constant)", falloff_prev,
        model_keys_free, KEY(O, S, A)),
    ACT(ST_ACT_MIRROR_X, ST_CAT_TOOLS, "X mirror", "symmetry across x = 0 / y = 0 / z = 0 on / off (any combination)",
        mirror_x, model_keys_free, KEY(X, 0, S | A)),
    ACT(ST_ACT_MIRROR_Y, ST_CAT_TOOLS, "Y mirror", "symmetry across x = 0 / y = 0 / z = 0 on / off (any combination)",
        mirror_y, model_keys_free, KEY(H, 0, A)),
    ACT(ST_ACT_MIRROR_Z, ST_CAT_TOOLS, "Z mirror", "symmetry across x = 0 / y = 0 / z = 0 on / off (any combination)",
        mirror_z, model_keys_free, KEY(J, 0, A)),
    ACT(ST_ACT_STABILIZE, ST_CAT_TOOLS, "Stabiliser", "stroke stabiliser (lazy mouse) on / off", stabilize,
        model_keys_free, KEY(L, S, A)),
    ACT(ST_ACT_FRONT_ONLY, ST_CAT_TOOLS, "Front faces only", "front faces only on / off (on: the brush does not reach the back)",
        front_only, model_keys_free, KEY(F, S, A)),
    ACT(ST_ACT_MASK_BRUSH, ST_CAT_TOOLS, "Mask brush",
        "mask brush on / off: a stroke brushes the mask in, Ctrl+stroke erases it (masked vertices are protected)",
        mask_brush, model_keys_free, KEY(M, 0, 0)),
    ACT(ST_ACT_MASK_CLEAR, ST_CAT_TOOLS, "Clear mask", "clear the mask", mask_clear, model_keys_free, KEY(M, A, 0)),
    ACT(ST_ACT_MASK_INVERT, ST_CAT_TOOLS, "Invert mask", "invert the mask", mask_invert, model_keys_free, KEY(M, C, 0)),
    ACT(ST_ACT_MASK_GROW, ST_CAT_TOOLS, "Grow mask", "grow / shrink the mask by one ring", mask_grow, model_keys_free,
        KEY(KP_ADD, C, 0), KEY(EQUAL, C, 0)),
    ACT(ST_ACT_MASK_SHRINK, ST_CAT_TOOLS, "Shrink mask", "grow / shrink the mask by one ring", mask_shrink,
        model_keys_free, KEY(KP_SUBTRACT, C, 0), KEY(MINUS, C, 0)),
    ACT(ST_ACT_MASK_SMOOTH, ST_CAT_TOOLS, "Smooth mask", "smooth the mask", mask_smooth, model_keys_free, KEY(M, S, 0)),
    ACT(ST_ACT_MASK_CAVITY, ST_CAT_TOOLS, "Mask by cavity", "mask the crevices (mask by cavity)", mask_cavity,
        model_keys_free, KEY(M, A | S, 0)),
    ACT(ST_ACT_LAYER_ADD, ST_CAT_TOOLS, "New layer", "new sculpt layer at the editing level (strokes go into it)",
        layer_add, model_keys_free, KEY(L, C, 0)),
    ACT(ST_ACT_LAYER_NEXT, ST_CAT_TOOLS, "Next layer", "next layer up the stack, then none (the level's own details)",
        layer_next, model_keys_free, KEY(V, 0, 0)),
    ACT(ST_ACT_LAYER_HIDE, ST_CAT_TOOLS, "Hide layer", "hide / show the active layer", layer_hide, model_keys_free,
        KEY(L, A, 0)),
    ACT(ST_ACT_LAYER_WEAKER, ST_CAT_TOOLS, "Weaker layer", "active layer's strength down / up by 0.25 (0..2)",
        layer_weaker, model_keys_free, KEY(PAGE_DOWN, C | A, 0)),
    ACT(ST_ACT_LAYER_STRONGER, ST_CAT_TOOLS, "Stronger layer", "active layer's strength down / up by 0.25 (0..2)",
        layer_stronger, model_keys_free, KEY(PAGE_UP, C | A, 0)),
    ACT(ST_ACT_LAYER_UP, ST_CAT_TOOLS, "Move layer up", "move the active layer up / down the stack", layer_up,
        model_keys_free, KEY(PAGE_UP, A | S, 0)),
    ACT(ST_ACT_LAYER_DOWN, ST_CAT_TOOLS, "Move layer down", "move the active layer up / down the stack", layer_down,
        model_keys_free, KEY(PAGE_DOWN, A | S, 0)),
    ACT(ST_ACT_LAYER_MERGE, ST_CAT_TOOLS, "Merge layer down", "merge the active layer into the one below",
        layer_merge, model_keys_free, KEY(L, C | A, 0)),
    ACT(ST_ACT_LAYER_DELETE, ST_CAT_TOOLS, "Delete layer", "delete the active layer", layer_delete, model_keys_free,
        KEY(L, C | S, 0)),

    ACT(ST_ACT_EDIT_LEVEL_UP, ST_CAT_MESH, "Edit a finer level", "editing level up / down", edit_level_up,
        model_keys_free, KEY(PAGE_UP, 0, 0), KEY(KP_ADD, 0, 0), KEY(EQUAL, 0, 0)),
    ACT(ST_ACT_EDIT_LEVEL_DOWN, ST_CAT_MESH, "Edit a coarser level", "editing level up / down", edit_level_down,
        model_keys_free, KEY(PAGE_DOWN, 0, 0), KEY(KP_SUBTRACT, 0, 0), KEY(MINUS, 0, 0)),
    ACT(ST_ACT_DISPLAY_LEVEL_UP, ST_CAT_MESH, "Display a finer level", "displayed level up / down",
        display_level_up, model_keys_free, KEY(PAGE_UP, S, 0), KEY(KP_ADD, S, 0), KEY(EQUAL, S, 0)),
    ACT(ST_ACT_DISPLAY_LEVEL_DOWN, ST_CAT_MESH, "Display a coarser level", "displayed level up / down",
        display_level_down, model_keys_free, KEY(PAGE_DOWN, S, 0), KEY(KP_SUBTRACT, S, 0), KEY(MINUS, S, 0)),
    ACT(ST_ACT_ADD_LEVEL, ST_CAT_MESH, "Add a level", "add a level (subdivide)", add_level, model_keys_free,
        KEY(D, C, 0)),
    ACT(ST_ACT_DELETE_FINEST, ST_CAT_MESH, "Delete the finest level", "delete the finest level", delete_finest,
        model_keys_free, KEY(D, C | S, A)),
    ACT(ST_ACT_DELETE_COARSEST, ST_CAT_MESH, "Delete the coarsest level", "delete the coarsest level (rebase)",
        delete_coarsest, model_keys_free, KEY(D, C | A, 0)),
    ACT(ST_ACT_CHANGE_SCHEME, ST_CAT_MESH, "Change the scheme...", "change the scheme (asks first, see below)",
        change_scheme, model_keys_free, KEY(K, 0, S | A)),
    ACT(ST_ACT_REBUILD_LEVELS, ST_CAT_MESH, "Rebuild levels",
        "rebuild coarse levels from the finest (unsubdivide, else progressive; Esc cancels)", rebuild_levels,
        model_keys_free, KEY(U, C, 0)),

    ACT(ST_ACT_BOX_TOGGLE, ST_CAT_BOX, "Interest box", "interest box on / off (adaptive display)", box_toggle,
        model_keys_free, KEY(I, 0, A)),
    ACT(ST_ACT_BOX_MOVE_XN, ST_CAT_BOX, "Move the box -X", "move the box in X / Y / Z", box_move_xn, model_keys_free,
        KEY(LEFT, 0, A)),
    ACT(ST_ACT_BOX_MOVE_XP, ST_CAT_BOX, "Move the box +X", "move the box in X / Y / Z", box_move_xp, model_keys_free,
        KEY(RIGHT, 0, A)),
    ACT(ST_ACT_BOX_MOVE_YN, ST_CAT_BOX, "Move the box -Y", "move the box in X / Y / Z", box_move_yn, model_keys_free,
        KEY(DOWN, 0, 0)),
    ACT(ST_ACT_BOX_MOVE_YP, ST_CAT_BOX, "Move the box +Y", "move the box in X / Y / Z", box_move_yp, model_keys_free,
        KEY(UP, 0, 0)),
    ACT(ST_ACT_BOX_MOVE_ZN, ST_CAT_BOX, "Move the box -Z", "move the box in X / Y / Z", box_move_zn, model_keys_free,
        KEY(DOWN, A, 0)),
    ACT(ST_ACT_BOX_MOVE_ZP, ST_CAT_BOX, "Move the box +Z", "move the box in X / Y / Z", box_move_zp, model_keys_free,
        KEY(UP, A, 0)),
    ACT(ST_ACT_BOX_SHRINK_X, ST_CAT_BOX, "Shrink the box in X", "resize the box in X / Y / Z", box_shrink_x,
        model_keys_free, KEY(LEFT, S, A)),
    ACT(ST_ACT_BOX_GROW_X, ST_CAT_BOX, "Grow the box in X", "resize the box in X / Y / Z", box_grow_x,
        model_keys_free, KEY(RIGHT, S, A)),
    ACT(ST_ACT_BOX_SHRINK_Y, ST_CAT_BOX, "Shrink the box in Y", "resize the box in X / Y / Z", box_shrink_y,
        model_keys_free, KEY(DOWN, S, 0)),
    ACT(ST_ACT_BOX_GROW_Y, ST_CAT_BOX, "Grow the box in Y", "resize the box in X / Y / Z", box_grow_y,
        model_keys_free, KEY(UP, S, 0)),
    ACT(ST_ACT_BOX_SHRINK_Z, ST_CAT_BOX, "Shrink the box in Z", "resize the box in X / Y / Z", box_shrink_z,
        model_keys_free, KEY(DOWN, A | S, 0)),
    ACT(ST_ACT_BOX_GROW_Z, ST_CAT_BOX, "Grow the box in Z", "resize the box in X / Y / Z", box_grow_z,
        model_keys_free, KEY(UP, A | S, 0)),
    ACT(ST_ACT_BOX_MAX_UP, ST_CAT_BOX, "Box maximum level up", "box maximum level up / down", box_max_up,
        model_keys_free, KEY(PERIOD, 0, A)),
    ACT(ST_ACT_BOX_MAX_DOWN, ST_CAT_BOX, "Box maximum level down", "box maximum level up / down", box_max_down,
        model_keys_free, KEY(COMMA, 0, A)),
    ACT(ST_ACT_BOX_BASE_UP, ST_CAT_BOX, "Box base level up", "box base level up / down", box_base_up,
        model_keys_free, KEY(PERIOD, S, A)),
    ACT(ST_ACT_BOX_BASE_DOWN, ST_CAT_BOX, "Box base level down", "box base level up / down", box_base_down,
        model_keys_free, KEY(COMMA, S, A)),

    ACT(ST_ACT_BAKE_MAPS, ST_CAT_BAKE, "Bake maps...",
        "bake normal / displacement maps of a fine level onto a coarse one's UVs (Esc cancels)", bake_maps,
        model_keys_free, KEY(B, C, 0)),

    ACT(ST_ACT_FRAME_ALL, ST_CAT_VIEW, "Frame all", "frame all", frame_all, keys_free, KEY(HOME, 0, ANY)),
    ACT(ST_ACT_VIEW_FRONT, ST_CAT_VIEW, "Front view", "front / back view", view_front, keys_free,
        KEY(KP_1, 0, S | A), KEY(1, 0, S | A)),
    ACT(ST_ACT_VIEW_BACK, ST_CAT_VIEW, "Back view", "front / back view", view_back, keys_free,
        KEY(KP_1, C, S | A), KEY(1, C, S | A)),
    ACT(ST_ACT_VIEW_RIGHT, ST_CAT_VIEW, "Right view", "right / left view", view_right, keys_free,
        KEY(KP_3, 0, S | A), KEY(3, 0, S | A)),
    ACT(ST_ACT_VIEW_LEFT, ST_CAT_VIEW, "Left view", "right / left view", view_left, keys_free,
        KEY(KP_3, C, S | A), KEY(3, C, S | A)),
    ACT(ST_ACT_VIEW_TOP, ST_CAT_VIEW, "Top view", "top / bottom view", view_top, keys_free,
        KEY(KP_7, 0, S | A), KEY(7, 0, S | A)),
    ACT(ST_ACT_VIEW_BOTTOM, ST_CAT_VIEW, "Bottom view", "top / bottom view", view_bottom, keys_free,
        KEY(KP_7, C, S | A), KEY(7, C, S | A)),
    ACT(ST_ACT_PROJECTION, ST_CAT_VIEW, "Perspective / orthographic", "perspective / orthographic", projection,
        keys_free, KEY(KP_5, 0, ANY), KEY(5, 0, ANY)),
    ACT(ST_ACT_ORBIT_LEFT, ST_CAT_VIEW, "Orbit left", "orbit by 15 degrees", orbit_left, keys_free, KEY(KP_4, 0, ANY)),
    ACT(ST_ACT_ORBIT_RIGHT, ST_CAT_VIEW, "Orbit right", "orbit by 15 degrees", orbit_right, keys_free,
        KEY(KP_6, 0, ANY)),
    ACT(ST_ACT_ORBIT_UP, ST_CAT_VIEW, "Orbit up", "orbit by 15 degrees", orbit_up, keys_free, KEY(KP_8, 0, ANY)),
    ACT(ST_ACT_ORBIT_DOWN, ST_CAT_VIEW, "Orbit down", "orbit by 15 degrees", orbit_down, keys_free, KEY(KP_2, 0, ANY)),
    ACT(ST_ACT_SHADING, ST_CAT_VIEW, "Smooth / flat shading", "smooth / flat shading", shading, model_keys_free,
        KEY(Z, 0, A)),
    ACT(ST_ACT_WIREFRAME, ST_CAT_VIEW, "Wireframe", "wireframe on / off", wireframe, model_keys_free, KEY(Z, S, A)),
    ACT(ST_ACT_CAGE, ST_CAT_VIEW, "Control mesh", "control mesh overlay on / off", cage, model_keys_free,
        KEY(C, 0, A)),
    ACT(ST_ACT_UV_CHECKER, ST_CAT_VIEW, "UV checker", "UV checker texture on / off (models with UVs)", uv_checker,
        uv_keys_free, KEY(U, 0, 0)),
    ACT(ST_ACT_SHOW_BAKED, ST_CAT_VIEW, "Show baked map", "the bake's base level with its normal map on / off",
        show_baked, baked_keys_free, KEY(B, C | S, 0)),
    ACT(ST_ACT_GUI, ST_CAT_VIEW, "Interface", "menus and side panel on / off", toggle_gui, NULL, KEY(F10, 0, 0)),

    ACT(ST_ACT_HELP, ST_CAT_HELP, "Key bindings", "show / hide the key list", help, NULL, KEY(F1, 0, ANY)),
    ACT(ST_ACT_ABOUT, ST_CAT_HELP, "About Strata", "version and libraries", about, NULL, KEY(F12, S, 0)),
    ACT(ST_ACT_CANCEL, ST_CAT_HELP, "Cancel", "cancel the current operation (or hide the key list)", cancel, NULL,
        KEY(ESCAPE, 0, ANY)),

    ASK(ST_ACT_SCHEME_NEXT, "Next scheme", "propose the next scheme", scheme_next, KEY(K, 0, ANY)),
    ASK(ST_ACT_SCHEME_CONFIRM, "Rebuild", "rebuild the hierarchy with it (its details are lost)", scheme_confirm,
        KEY(Y, 0, ANY), KEY(ENTER, 0, ANY)),
    ASK(ST_ACT_SCHEME_KEEP, "Keep the scheme", "keep the scheme (any other key too)", scheme_keep, KEY(N, 0, ANY)),

    ASK_QUIT(ST_ACT_QUIT_SAVE, "Save and quit", "save the changes, then quit", quit_save, KEY(S, 0, ANY), KEY(ENTER, 0, ANY)),
    ASK_QUIT(ST_ACT_QUIT_DISCARD, "Quit without saving", "quit without saving (the recovery file keeps the changes)",
             quit_discard, KEY(D, 0, ANY)),
    ASK_QUIT(ST_ACT_QUIT_CANCEL, "Keep working", "keep working (any other key too)", quit_cancel, KEY(ESCAPE, 0, ANY),
             KEY(C, 0, ANY)),
};

const st_gesture st_gestures[] = {
    { "Middle drag / Alt+Left drag", "orbit" },
    { "Shift+Middle drag / Alt+Shift+Left drag", "pan" },
    { "Wheel", "zoom" },
    { "Ctrl+Wheel", "brush radius" },
    { "Left click", "select a vertex of the editing level (Shift toggles, Ctrl removes)" },
    { "Left drag on empty space", "rectangle selection (Shift adds, Ctrl removes)" },
    { "Left drag on a vertex", "move the selection in the view plane (Ctrl or Alt: along its normal)" },
    { "Left drag (brush tools)", "stroke, dabs spaced along the path (Ctrl: the other way, e.g. draw pushes in)" },
    { "Left drag a box handle", "square: move that face (resize), circle: move the box" },
    { "Drop a file", "open it, mesh or .strata session (a failed load keeps the model)" },
};
const unsigned st_ngestures = sizeof st_gestures / sizeof st_gestures[0];

/* ---- running ---------------------------------------------------------------------- */

int st_action_enabled(const st_action *act, const st_app *a)
{
    return !act->enabled || act->enabled(a);
}

int st_action_in_menu(const st_action *act)
{
    if (act->context != ST_KEYS_WINDOW) return 0;
    switch (act->id) {
    case ST_ACT_GRAB_CONFIRM: case ST_ACT_CANCEL:
    case ST_ACT_ORBIT_LEFT: case ST_ACT_ORBIT_RIGHT: case ST_ACT_ORBIT_UP: case ST_ACT_ORBIT_DOWN: return 0;
    default: return 1;
    }
}

int st_action_checked(const st_action *act, const st_app *a)
{
    switch (act->id) {
    case ST_ACT_TOOL_SELECT: return a->tool == ST_TOOL_SELECT;
    case ST_ACT_BRUSH_GRAB: return a->tool == ST_BRUSH_GRAB;
    case ST_ACT_BRUSH_DRAW: return a->tool == ST_BRUSH_DRAW;
    case ST_ACT_BRUSH_SMOOTH: return a->tool == ST_BRUSH_SMOOTH;
    case ST_ACT_BRUSH_FLATTEN: return a->tool == ST_BRUSH_FLATTEN;
    case ST_ACT_BRUSH_CREASE: return a->tool == ST_BRUSH_CREASE;
    case ST_ACT_BRUSH_PINCH: return a->tool == ST_BRUSH_PINCH;
    case ST_ACT_BRUSH_INFLATE: return a->tool == ST_BRUSH_INFLATE;
    case ST_ACT_BRUSH_CLAY_STRIPS: return a->tool == ST_BRUSH_CLAY_STRIPS;
    case ST_ACT_BRUSH_LAYER: return a->tool == ST_BRUSH_LAYER;
    case ST_ACT_BRUSH_RELAX: return a->tool == ST_BRUSH_RELAX;
    case ST_ACT_MIRROR_X: return a->doc.brush.mirror_x != 0;
    case ST_ACT_MIRROR_Y: return a->doc.brush.mirror_y != 0;
    case ST_ACT_MIRROR_Z: return a->doc.brush.mirror_z != 0;
    case ST_ACT_STABILIZE: return a->doc.brush.stabilize != 0;
    case ST_ACT_FRONT_ONLY: return a->doc.brush.front_only != 0;
    case ST_ACT_MASK_BRUSH: return a->mask_brush != 0;
    case ST_ACT_BOX_TOGGLE: return a->doc.box_on != 0;
    case ST_ACT_SHADING: return a->shading == ST_SHADE_FLAT ? 0 : 1;
    case ST_ACT_WIREFRAME: return a->wire != 0;
    case ST_ACT_CAGE: return a->cage != 0;
    case ST_ACT_UV_CHECKER: return a->checker != 0;
    case ST_ACT_SHOW_BAKED: return a->bake.show != 0;
    case ST_ACT_PROJECTION: return a->cc.cam.ortho ? 0 : 1;
    case ST_ACT_GUI: return st_gui_shown();
    case ST_ACT_HELP: return a->help != 0;
    default: return -1;
    }
}

const st_action *st_app_key(st_app *a, int key, int mods)
{
    int context = a->quit_asking ? ST_KEYS_QUIT_QUESTION : a->pending_scheme ? ST_KEYS_SCHEME_QUESTION : ST_KEYS_WINDOW;
    const st_action *act = st_action_for_key(context, key, mods);
    /* Any other key answers the scheme question with no, and the quit
     * question with cancel. */
    if (!act && context == ST_KEYS_SCHEME_QUESTION) act = &st_actions[ST_ACT_SCHEME_KEEP];
    if (!act && context == ST_KEYS_QUIT_QUESTION) act = &st_actions[ST_ACT_QUIT_CANCEL];
    if (!act || !st_action_enabled(act, a)) return NULL;
    act->run(a);
    return act;
}
