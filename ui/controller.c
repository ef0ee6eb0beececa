/* The window's pointer controller (window.h): what a press, a move and a
 * release of the pointer do, by the operation in progress (st_app.op):
 * orbit and pan, a click or a rectangle that selects, the drag of the
 * selection (and G's grab), brush strokes (the dab spacing along the
 * cursor's path, its fade-out, a re-pick of the surface per dab), the
 * interest box's handles; with the picking helpers they use.  The GLFW
 * set-up, keys, renderer sync, screenshots and the frame loop are
 * window.c's. */
#include "window.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/adapt/adapt.h"
#include "gui.h"

#define DRAG_THRESHOLD 4.0           /* pixels before a press becomes a drag */
#define STROKE_REPICK_TRIS 400000    /* brush strokes re-pick the surface per dab below this */

static st_app *app_of(GLFWwindow *w) { return (st_app *)glfwGetWindowUserPointer(w); }

/* ---- picking helpers ---------------------------------------------------------- */

static int ensure_pick(st_app *a)
{
    st_error err;
    if (st_pick_render(&a->pick, &a->r, &a->cc, a->fb_w, a->fb_h, &err)) {
        st_app_message(a, 1, "%s", err.msg);
        return -1;
    }
    return 0;
}

static uint32_t pick_vertex(st_app *a, double x, double y)
{
    if (!a->doc.loaded || !a->r.has_cage || !a->cage || ensure_pick(a)) return ST_NIL;
    uint32_t slot = st_pick_at(&a->pick, (int)floor(x), (int)floor(y));
    return slot != ST_NIL && slot < a->r.cage.nverts ? a->r.cage.vid[slot] : ST_NIL;
}

int st_app_surface_at_cursor(st_app *a, double pos[3])
{
    double n[3];
    return a->doc.loaded && !a->busy && !ensure_pick(a) &&
           st_pick_surface(&a->pick, &a->cc, (int)floor(a->mx), (int)floor(a->my), pos, n);
}

void st_app_update_hover(st_app *a)
{
    if (a->tool == ST_TOOL_SELECT) {
        uint32_t v = pick_vertex(a, a->mx, a->my);
        if (v != a->hover_vid) {
            a->hover_vid = v;
            st_renderer_set_hover(&a->r, v);
        }
    } else {
        if (a->hover_vid != ST_NIL) { a->hover_vid = ST_NIL; st_renderer_set_hover(&a->r, ST_NIL); }
        a->brush_hit = a->doc.loaded && !ensure_pick(a) &&
                       st_pick_surface(&a->pick, &a->cc, (int)floor(a->mx), (int)floor(a->my), a->brush_pos, a->brush_nrm);
    }
}

static int is_selected(const st_doc *d, uint32_t v)
{
    uint32_t lo = 0, hi = d->nsel;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (d->sel[mid] < v) lo = mid + 1; else hi = mid;
    }
    return lo < d->nsel && d->sel[lo] == v;
}

/* Centroid and average normal (from the cage's vertex normals) of the
 * selection. */
static void selection_frame(st_app *a, double c[3], double n[3])
{
    st_doc *d = &a->doc;
    c[0] = c[1] = c[2] = n[0] = n[1] = n[2] = 0;
    for (uint32_t i = 0; i < d->nsel; i++) {
        double p[3];
        st_doc_vertex_pos(d, d->sel[i], p);
        for (int k = 0; k < 3; k++) c[k] += p[k];
        uint32_t v = d->sel[i];
        if (a->r.has_cage && v < a->r.cage.nvids && a->r.cage.slot[v] != ST_NIL) {
            const float *q = a->r.cage.vdata + (size_t)a->r.cage.slot[v] * ST_RGEOM_VSTRIDE + 3;
            for (int k = 0; k < 3; k++) n[k] += q[k];
        }
    }
    if (d->nsel) for (int k = 0; k < 3; k++) c[k] /= d->nsel;
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0) for (int k = 0; k < 3; k++) n[k] /= len;
    else {
        double r[3], u[3];
        st_camctl_axes(&a->cc, r, u, n);
    }
}

/* ---- drag of the selection ---------------------------------------------------- */

void st_app_drag_start(st_app *a, int op)
{
    st_doc *d = &a->doc;
    if (!d->nsel) return;
    if (st_doc_drag_begin(d)) { st_app_message(a, 1, d->refusal[0] ? d->refusal : "cannot drag the selection"); return; }
    selection_frame(a, a->drag_anchor, a->drag_normal);
    a->op = op;
    a->op_lx = a->mx;
    a->op_ly = a->my;
}

int st_app_filter(st_app *a, const double *gains, unsigned n)
{
    st_error err;
    uint32_t depth = a->doc.undo_pos;
    if (st_doc_filter(&a->doc, gains, n, &err)) {
        st_app_message(a, 1, "%s", err.msg);
        return -1;
    }
    if (a->doc.undo_pos == depth) st_app_message(a, 0, "filter: every gain is 1, nothing changed");
    else st_app_message(a, 0, "filter applied (Ctrl+Z undoes it)");
    st_app_sync(a);
    return 0;
}

void st_app_drag_update(st_app *a)
{
    double dx = a->mx - a->op_x0, dy = a->my - a->op_y0, delta[3];
    int along = ((a->op_mods | a->mods) & (GLFW_MOD_CONTROL | GLFW_MOD_ALT)) != 0;
    if (along) {
        double px = st_camctl_pixel_size(&a->cc, a->fb_w, a->fb_h, a->drag_anchor);
        for (int k = 0; k < 3; k++) delta[k] = -dy * px * a->drag_normal[k];
    } else {
        st_camctl_screen_delta(&a->cc, a->fb_w, a->fb_h, a->drag_anchor, dx, dy, delta);
    }
    if (st_doc_drag_update(&a->doc, delta)) st_app_message(a, 1, "drag update failed");
    st_app_sync(a);
}

void st_app_drag_finish(st_app *a, int cancel)
{
    if (cancel) st_doc_drag_cancel(&a->doc);
    else st_doc_drag_end(&a->doc);
    a->op = ST_OP_NONE;
    st_app_sync(a);
    if (cancel) st_app_message(a, 0, "move cancelled");
}

/* ---- brush strokes ------------------------------------------------------------ */

/* The brush radius in pixels at the brush point. */
static double stroke_radius_px(st_app *a)
{
    double px = st_camctl_pixel_size(&a->cc, a->fb_w, a->fb_h, a->brush_pos);
    return a->doc.brush.radius / (px > 0 ? px : 1);
}

/* Strokes whose strength fades out at the end: every sculpt brush with a
 * fade (grab moves what it holds; the mask brush paints).  The brush point
 * trails the cursor by the fade length, so that the end is known when the
 * button comes up (ZBrush's and Blender's stroke taper at both ends). */
static int fades_out(const st_app *a)
{
    return !a->mask_brush && a->tool != ST_BRUSH_GRAB && a->doc.brush.fade > 0 && a->doc.brush.spacing > 0;
}

/* A dab of a spaced stroke at screen point s (brush_stroke.c): the surface
 * under it from the ID buffer. */
static void stroke_dab_at(void *ctx, const double s[3])
{
    st_app *a = ctx;
    double p[3], nrm[3];
    if (!st_pick_surface(&a->pick, &a->cc, (int)floor(s[0]), (int)floor(s[1]), p, nrm)) return;
    memcpy(a->brush_pos, p, sizeof p);
    memcpy(a->brush_nrm, nrm, sizeof nrm);
    static const double zero[3] = { 0, 0, 0 };
    if (a->mask_brush) st_doc_mask_stroke_dab(&a->doc, p);
    else if (st_doc_stroke_dab(&a->doc, p, nrm, zero)) st_app_message(a, 1, "brush dab failed");
}

/* Starts a stroke at the surface under the pointer; 0 when there is none
 * (the caller waits for the pointer to reach the surface, as Blender does). */
static int stroke_start(st_app *a, int mods)
{
    st_doc *d = &a->doc;
    if (ensure_pick(a)) return 1;
    double p[3], nrm[3];
    if (!st_pick_surface(&a->pick, &a->cc, (int)floor(a->mx), (int)floor(a->my), p, nrm)) return 0;
    st_brush_set_tool(&d->brush, a->tool);
    d->brush.invert = (mods & GLFW_MOD_CONTROL) != 0;
    /* Front faces only: the direction the view looks. */
    double right[3], up[3], back[3];
    st_camctl_axes(&a->cc, right, up, back);
    for (int k = 0; k < 3; k++) d->brush.view_dir[k] = -back[k];
    int started = a->mask_brush ? st_doc_mask_stroke_begin(d, (mods & GLFW_MOD_CONTROL) != 0) : st_doc_stroke_begin(d);
    if (started) {
        st_app_message(a, 1, "%s", d->refusal[0] ? d->refusal : "cannot start a stroke");
        a->op = ST_OP_NONE;
        return 1;
    }
    a->op = ST_OP_STROKE;
    a->op_lx = a->mx;
    a->op_ly = a->my;
    memcpy(a->stroke_pos, p, sizeof p);
    memcpy(a->brush_pos, p, sizeof p);
    memcpy(a->brush_nrm, nrm, sizeof nrm);
    a->brush_hit = 1;
    const double cursor[3] = { a->mx, a->my, 0 };
    st_stroke_path_begin(&a->stroke_path, cursor);
    static const double zero[3] = { 0, 0, 0 };
    if (a->mask_brush) st_doc_mask_stroke_dab(d, p);
    else if (a->tool != ST_BRUSH_GRAB && st_doc_stroke_dab(d, p, nrm, zero)) st_app_message(a, 1, "brush dab failed");
    st_app_sync(a);
    return 1;
}

static void stroke_move(st_app *a)
{
    st_doc *d = &a->doc;
    double dx = a->mx - a->op_lx, dy = a->my - a->op_ly;
    if (dx * dx + dy * dy < 1) return;
    if (a->tool == ST_BRUSH_GRAB && !a->mask_brush) {
        double delta[3];
        st_camctl_screen_delta(&a->cc, a->fb_w, a->fb_h, a->stroke_pos, dx, dy, delta);
        if (st_doc_stroke_dab(d, a->stroke_pos, a->brush_nrm, delta)) st_app_message(a, 1, "brush dab failed");
        for (int k = 0; k < 3; k++) a->stroke_pos[k] += delta[k];
    } else {
        /* The surface under the cursor, from an ID buffer redrawn after
         * every event; on a dense display (a full draw per mouse move would
         * make strokes lag) the buffer of the stroke's start is reused:
         * the dabs move the surface by a fraction of the radius.  Dabs are
         * spaced along the path in pixels: spacing and the stabiliser's
         * distance are fractions of the brush radius on the screen. */
        if (a->r.surf.ntris < STROKE_REPICK_TRIS) {
            st_app_sync(a);
            if (ensure_pick(a)) return;
        }
        double rpx = stroke_radius_px(a);
        double lazy = d->brush.stabilize ? d->brush.stabilize_dist * rpx : 0;
        if (fades_out(a) && d->brush.fade * rpx > lazy) lazy = d->brush.fade * rpx;
        const double cursor[3] = { a->mx, a->my, 0 };
        st_stroke_path_move(&a->stroke_path, cursor, d->brush.spacing * rpx, lazy, stroke_dab_at, a);
    }
    a->op_lx = a->mx;
    a->op_ly = a->my;
    st_app_sync(a);
}

/* The tail of a stroke that trailed the cursor: laid at the end with the
 * strength fading out (st_stroke_path_end). */
static void stroke_tail_dab(void *ctx, const double s[3], double k)
{
    st_app *a = ctx;
    st_doc_stroke_fade_out(&a->doc, k);
    stroke_dab_at(a, s);
}

static void stroke_finish(st_app *a)
{
    st_doc *d = &a->doc;
    if (d->active == 2 && fades_out(a) && !ensure_pick(a)) {
        const double cursor[3] = { a->mx, a->my, 0 };
        st_stroke_path_end(&a->stroke_path, cursor, d->brush.spacing * stroke_radius_px(a), stroke_tail_dab, a);
    }
    if (a->doc.active == 3) st_doc_mask_stroke_end(&a->doc);
    else st_doc_stroke_end(&a->doc);
    a->doc.brush.invert = 0;
    a->op = ST_OP_NONE;
    st_app_sync(a);
}

/* ---- selection ----------------------------------------------------------------- */

static void select_click(st_app *a, uint32_t v, int mods)
{
    st_doc *d = &a->doc;
    if (v == ST_NIL) {
        if (!(mods & (GLFW_MOD_SHIFT | GLFW_MOD_CONTROL))) st_doc_select(d, NULL, 0, ST_SELECT_REPLACE);
    } else if (mods & GLFW_MOD_SHIFT) {
        st_doc_select(d, &v, 1, is_selected(d, v) ? ST_SELECT_REMOVE : ST_SELECT_ADD);
    } else if (mods & GLFW_MOD_CONTROL) {
        st_doc_select(d, &v, 1, ST_SELECT_REMOVE);
    } else {
        st_doc_select(d, &v, 1, ST_SELECT_REPLACE);
    }
    st_app_sync(a);
}

static void select_rect(st_app *a)
{
    if (ensure_pick(a)) return;
    uint32_t *slots = NULL;
    int64_t n = st_pick_rect(&a->pick, (int)a->op_x0, (int)a->op_y0, (int)a->mx, (int)a->my, &slots);
    if (n < 0) { st_app_message(a, 1, "out of memory for the selection"); return; }
    int64_t k = 0;
    for (int64_t i = 0; i < n; i++)
        if (slots[i] < a->r.cage.nverts) slots[k++] = a->r.cage.vid[slots[i]];
    n = k;
    int mode = (a->op_mods & GLFW_MOD_CONTROL) ? ST_SELECT_REMOVE : (a->op_mods & GLFW_MOD_SHIFT) ? ST_SELECT_ADD : ST_SELECT_REPLACE;
    st_doc_select(&a->doc, slots, (uint32_t)n, mode);
    free(slots);
    st_app_sync(a);
}

void st_app_select_all(st_app *a, int none)
{
    if (none || !a->r.has_cage) { st_doc_select(&a->doc, NULL, 0, ST_SELECT_REPLACE); st_app_sync(a); return; }
    st_doc_select(&a->doc, a->r.cage.vid, a->r.cage.nverts, ST_SELECT_REPLACE);
    st_app_sync(a);
}

/* ---- interest-box handles ---------------------------------------------------------- */

#define HANDLE_PICK 10.0          /* pixels */

void st_box_handle_pos(const st_adapt_params *b, int k, double p[3])
{
    for (int i = 0; i < 3; i++) p[i] = 0.5 * (b->box_lo[i] + b->box_hi[i]);
    if (k < 6) p[k / 2] = k % 2 ? b->box_hi[k / 2] : b->box_lo[k / 2];
}

/* The handle nearest to the cursor within HANDLE_PICK pixels, -1 if none. */
static int pick_handle(st_app *a, double x, double y)
{
    if (!a->doc.loaded || !a->doc.box_on) return -1;
    int best = -1;
    double bestd = HANDLE_PICK * HANDLE_PICK;
    for (int k = 0; k < 7; k++) {
        double p[3], s[2];
        st_box_handle_pos(&a->doc.box, k, p);
        if (!st_camctl_project(&a->cc, a->fb_w, a->fb_h, p, s, NULL)) continue;
        double d = (s[0] - x) * (s[0] - x) + (s[1] - y) * (s[1] - y);
        if (d < bestd) { bestd = d; best = k; }
    }
    return best;
}

/* Box drag: a face handle moves that face along its axis (the cursor's
 * motion projected on the axis' screen direction), the centre handle moves
 * the box in the view plane.  Adaptive refinement follows at every step;
 * the whole drag is one undo step (st_doc_box_begin / end). */
static void box_drag_update(st_app *a)
{
    st_adapt_params b = a->box_start;
    int k = a->box_handle;
    double dx = a->mx - a->op_x0, dy = a->my - a->op_y0;
    double p[3];
    st_box_handle_pos(&a->box_start, k, p);
    if (k == 6) {
        double d[3];
        st_camctl_screen_delta(&a->cc, a->fb_w, a->fb_h, p, dx, dy, d);
        for (int i = 0; i < 3; i++) { b.box_lo[i] += d[i]; b.box_hi[i] += d[i]; }
    } else {
        int ax = k / 2;
        double q[3] = { p[0], p[1], p[2] }, s0[2], s1[2];
        double unit = 0.1 * (a->cc.radius > 0 ? a->cc.radius : 1);
        q[ax] += unit;
        if (!st_camctl_project(&a->cc, a->fb_w, a->fb_h, p, s0, NULL) ||
            !st_camctl_project(&a->cc, a->fb_w, a->fb_h, q, s1, NULL)) return;
        double ex = s1[0] - s0[0], ey = s1[1] - s0[1], e2 = ex * ex + ey * ey;
        if (e2 < 1e-6) return;   /* the axis points at the viewer */
        double t = (dx * ex + dy * ey) / e2 * unit;
        if (k % 2) b.box_hi[ax] += t; else b.box_lo[ax] += t;
        double minw = 0.01 * unit;
        if (b.box_hi[ax] - b.box_lo[ax] < minw) {
            if (k % 2) b.box_hi[ax] = b.box_lo[ax] + minw; else b.box_lo[ax] = b.box_hi[ax] - minw;
        }
    }
    st_error err;
    if (st_doc_set_box(&a->doc, &b, 1, &err)) st_app_message(a, 1, "cannot move the box: %s", err.msg);
    st_app_sync(a);
}

/* ---- callbacks ------------------------------------------------------------------ */

static void to_fb(const st_app *a, double x, double y, double *fx, double *fy)
{
    *fx = a->win_w > 0 ? x * a->fb_w / a->win_w : x;
    *fy = a->win_h > 0 ? y * a->fb_h / a->win_h : y;
}

void st_win_on_cursor(GLFWwindow *w, double x, double y)
{
    st_app *a = app_of(w);
    double fx, fy;
    st_gui_cursor(x, y);
    to_fb(a, x, y, &fx, &fy);
    double dx = fx - a->mx, dy = fy - a->my;
    a->mx = fx;
    a->my = fy;
    switch (a->op) {
    case ST_OP_ORBIT:
        st_camctl_orbit(&a->cc, (float)dx, (float)dy);
        st_pick_invalidate(&a->pick);
        break;
    case ST_OP_PAN:
        st_camctl_pan(&a->cc, (float)dx, (float)dy, a->fb_w, a->fb_h);
        st_pick_invalidate(&a->pick);
        break;
    case ST_OP_CLICK: {
        double mx = fx - a->op_x0, my = fy - a->op_y0;
        if (mx * mx + my * my < DRAG_THRESHOLD * DRAG_THRESHOLD) break;
        uint32_t v = a->hover_vid;
        if (v != ST_NIL) {
            /* Dragging a vertex: it joins (or makes) the selection, then the
             * whole selection moves (Blender's tweak). */
            if (!is_selected(&a->doc, v)) {
                st_doc_select(&a->doc, &v, 1, (a->op_mods & GLFW_MOD_SHIFT) ? ST_SELECT_ADD : ST_SELECT_REPLACE);
                st_app_sync(a);
            }
            st_app_drag_start(a, ST_OP_DRAG);
            if (a->op == ST_OP_DRAG) st_app_drag_update(a);
        } else {
            a->op = ST_OP_RECT;
        }
        break;
    }
    case ST_OP_DRAG:
    case ST_OP_GRAB:
        st_app_drag_update(a);
        break;
    case ST_OP_STROKE:
        stroke_move(a);
        break;
    case ST_OP_STROKE_WAIT:
        stroke_start(a, a->op_mods);
        break;
    case ST_OP_RECT:
        break;
    case ST_OP_BOX:
        box_drag_update(a);
        break;
    default: {
        int h = pick_handle(a, fx, fy);
        a->box_handle = h;
        if (h < 0) st_app_update_hover(a);
        else if (a->hover_vid != ST_NIL) { a->hover_vid = ST_NIL; st_renderer_set_hover(&a->r, ST_NIL); }
        break;
    }
    }
}

void st_win_on_mouse_button(GLFWwindow *w, int button, int action, int mods)
{
    st_app *a = app_of(w);
    if (st_gui_mouse_button(a, button, action, mods)) return;
    if (!a->doc.loaded) return;
    if (action == GLFW_PRESS) {
        if (a->op == ST_OP_GRAB) {
            st_app_drag_finish(a, button != GLFW_MOUSE_BUTTON_LEFT);
            return;
        }
        if (a->op != ST_OP_NONE) {
            if (button == GLFW_MOUSE_BUTTON_RIGHT && a->op == ST_OP_DRAG) st_app_drag_finish(a, 1);
            else if (button == GLFW_MOUSE_BUTTON_RIGHT && a->op == ST_OP_RECT) a->op = ST_OP_NONE;
            return;
        }
        a->op_button = button;
        a->op_mods = mods;
        a->op_x0 = a->mx;
        a->op_y0 = a->my;
        if (button == GLFW_MOUSE_BUTTON_MIDDLE || (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_ALT))) {
            a->op = (mods & GLFW_MOD_SHIFT) ? ST_OP_PAN : ST_OP_ORBIT;
        } else if (button == GLFW_MOUSE_BUTTON_LEFT && (a->box_handle = pick_handle(a, a->mx, a->my)) >= 0) {
            a->box_start = a->doc.box;
            st_doc_box_begin(&a->doc);
            a->op = ST_OP_BOX;
        } else if (button == GLFW_MOUSE_BUTTON_LEFT) {
            if (a->tool == ST_TOOL_SELECT && !a->mask_brush) {
                a->hover_vid = pick_vertex(a, a->mx, a->my);
                st_renderer_set_hover(&a->r, a->hover_vid);
                a->op = ST_OP_CLICK;
            } else if (!stroke_start(a, mods)) {
                a->op = ST_OP_STROKE_WAIT;
            }
        }
        return;
    }
    if (action != GLFW_RELEASE || button != a->op_button) return;
    switch (a->op) {
    case ST_OP_CLICK: a->op = ST_OP_NONE; select_click(a, a->hover_vid, a->op_mods); break;
    case ST_OP_RECT: a->op = ST_OP_NONE; select_rect(a); break;
    case ST_OP_DRAG: st_app_drag_finish(a, 0); break;
    case ST_OP_STROKE: stroke_finish(a); break;
    case ST_OP_STROKE_WAIT: a->op = ST_OP_NONE; break;
    case ST_OP_BOX:
        st_doc_box_end(&a->doc);
        a->op = ST_OP_NONE;
        st_app_sync(a);
        st_app_message(a, 0, "box %s", a->box_handle == 6 ? "moved" : "resized");
        break;
    case ST_OP_ORBIT:
    case ST_OP_PAN: a->op = ST_OP_NONE; st_app_update_hover(a); break;
    default: break;
    }
}

void st_win_on_scroll(GLFWwindow *w, double dx, double dy)
{
    st_app *a = app_of(w);
    if (st_gui_scroll(dx, dy)) return;
    if (a->mods & GLFW_MOD_CONTROL) {
        a->doc.brush.radius *= pow(1.1, dy);
        return;
    }
    st_camctl_zoom(&a->cc, (float)dy);
    st_pick_invalidate(&a->pick);
    if (a->op == ST_OP_NONE) st_app_update_hover(a);
}

void st_win_on_drop(GLFWwindow *w, int count, const char **paths)
{
    st_app *a = app_of(w);
    if (count < 1) return;
    if (a->op == ST_OP_DRAG || a->op == ST_OP_GRAB) st_app_drag_finish(a, 1);
    if (a->op == ST_OP_STROKE) stroke_finish(a);
    a->op = ST_OP_NONE;
    st_app_request_open(a, paths[0]);   /* a job: run by the main loop, not in this callback */
}

