/* The modeller window: GLFW setup, renderer updates, screenshots, the
 * test probes and the frame loop; see window.h.  The pointer handlers and
 * what they drive (selection, drags, strokes, the box's handles) are
 * controller.c's.  Keys go through
 * the action table (actions.c), the overlay is drawn by hud_panels.c, and
 * opening, adding a level and changing the scheme run on a worker thread
 * (jobs.c). */
#include "window.h"

#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "actions.h"
#include "core/adapt/adapt.h"
#include "core/fvar/fvar.h"
#include "gui.h"
#include "render/image.h"
#include "prefs.h"
#include "replay.h"

#ifndef STRATA_ASSETS
#define STRATA_ASSETS "assets"
#endif
#ifndef STRATA_INSTALLED_ASSETS
#define STRATA_INSTALLED_ASSETS "../share/strata/assets"
#endif
#define DEFAULT_ASSET "torus.obj"

static char glfw_error[512];

static void on_glfw_error(int code, const char *desc)
{
    snprintf(glfw_error, sizeof glfw_error, "%s (GLFW error 0x%x)", desc ? desc : "?", code);
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

double st_now_ms(void) { return now_ms(); }

const char *st_path_base(const char *p)
{
    const char *s = strrchr(p, '/');
    return s ? s + 1 : p;
}

static st_app *app_of(GLFWwindow *w) { return (st_app *)glfwGetWindowUserPointer(w); }

void st_app_message(st_app *a, int error, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(a->msg, sizeof a->msg, fmt, ap);
    va_end(ap);
    a->msg_error = error;
    a->msg_time = glfwGetTime();
    st_app_want_frames(a);
    if (error || a->opts.replay) fprintf(stderr, "strata: %s\n", a->msg);
}

/* Times in the HUD and messages: masked in replays so that screenshots of
 * the same script are the same pixels. */
const char *st_app_fmt_ms(const st_app *a, double ms, char *buf, size_t n)
{
    if (a->masked_times) snprintf(buf, n, "-- ms");
    else if (ms >= 1000) snprintf(buf, n, "%.2f s", ms / 1000);
    else snprintf(buf, n, "%.1f ms", ms);
    return buf;
}

float st_app_aspect(const st_app *a) { return a->fb_h > 0 ? (float)a->fb_w / (float)a->fb_h : 1; }

/* ---- document -> renderer ----------------------------------------------------- */

/* The document's change in the renderer's words (render/scene_sync.h). */
static st_scene_change scene_change(const st_doc_change *ch)
{
    static const struct { unsigned doc, scene; } bit[] = {
        { ST_CHANGE_TOPOLOGY, ST_SCENE_TOPOLOGY }, { ST_CHANGE_POSITIONS, ST_SCENE_POSITIONS },
        { ST_CHANGE_ALL_POSITIONS, ST_SCENE_ALL_POSITIONS }, { ST_CHANGE_DISPLAY, ST_SCENE_DISPLAY },
        { ST_CHANGE_PATCH, ST_SCENE_PATCH },
    };
    st_scene_change c = { 0, ch->nmoved, ch->footprint, ch->disp_footprint, ch->patch };
    for (size_t i = 0; i < sizeof bit / sizeof bit[0]; i++)
        if (ch->bits & bit[i].doc) c.bits |= bit[i].scene;
    return c;
}

int st_app_sync(st_app *a)
{
    st_doc *d = &a->doc;
    st_doc_change ch = st_doc_take_change(d);
    if (!d->loaded) {
        int was_shown = a->shown.valid;
        st_renderer_clear(&a->r, ST_TARGET_MESHES);
        a->shown.valid = 0;
        return was_shown || ch.bits;
    }
    double t0 = now_ms();
    unsigned disp = st_doc_display_map_level(d);
    const st_hier *dh = st_doc_display_hier(d);
    unsigned cage_level;
    const st_map *cage = st_doc_cage_map(d, &cage_level);
    st_scene scene = { cage, &dh->map, disp, cage_level, st_doc_display_adaptive(d) };
    st_scene_change sc = scene_change(&ch);
    /* At an HD level the cage is the display's (st_doc_cage_map): a box
     * move changed its map too, so it is built again rather than patched. */
    if (cage == &dh->map && (sc.bits & ST_SCENE_PATCH))
        sc.bits = (sc.bits & ~(unsigned)ST_SCENE_PATCH) | ST_SCENE_TOPOLOGY;
    st_error err;
    unsigned done = st_renderer_show(&a->r, &a->shown, &scene, &sc, &err);
    if (done & ST_SCENE_FAILED) st_app_message(a, 1, "cannot draw the model: %s", err.msg);
    if (done & ST_SCENE_PATCHED) a->patches++;
    if ((done & ST_SCENE_REBUILT) || (ch.bits & ST_CHANGE_PATCH)) a->hover_vid = ST_NIL;
    int rebuild = (done & ST_SCENE_REBUILT) != 0;
    int touched = (done & ST_SCENE_TOUCHED) != 0;
    /* The mask darkens the surface.  The box's display has its own vertex
     * ids: it takes the mask over them whole (st_doc_display_mask) when the
     * mask changed or a box move patched the surface. */
    if (dh == &d->h && (rebuild || (ch.bits & ST_CHANGE_MASK))) {
        int all = rebuild || !ch.nmask_vids;
        if (all && !st_mask_any(&d->mask)) st_renderer_set_mask(&a->r, NULL, 0, NULL, 0);
        else st_renderer_set_mask(&a->r, d->mask.v, d->mask.cap, all ? NULL : ch.mask_vids, ch.nmask_vids);
        touched = 1;
    } else if (dh != &d->h && (rebuild || (ch.bits & (ST_CHANGE_MASK | ST_CHANGE_PATCH)))) {
        const st_mask *dmk = st_mask_any(&d->mask) ? st_doc_display_mask(d) : NULL;
        st_renderer_set_mask(&a->r, dmk ? dmk->v : NULL, dmk ? dmk->cap : 0, NULL, 0);
        touched = 1;
    }
    /* UVs per triangle corner: uploaded again whenever the triangles
     * change or the checker is switched on (position edits keep them). */
    int checker = a->checker && (dh == &d->h || st_doc_display_adaptive(d));
    if (checker != a->shown_checker || (checker && (rebuild || (ch.bits & ST_CHANGE_PATCH)))) {
        /* with the interest box: the adaptive mesh's own UVs, computed
         * again after each box move (core/adapt/adapt.h) */
        st_adapt_uv auv = { 0 };
        st_uv_map uv = { NULL, NULL, 0 };
        if (checker && dh == &d->h) uv = st_hier_uv(&d->h, disp);
        else if (checker && d->display.built && !st_adapt_uv_absent(&d->display.adapt) &&
                 st_adapt_uv_build(&d->display.adapt, &auv, &err) == ST_OK)
            uv = (st_uv_map){ auv.uv, NULL, auv.cap };
        if (st_renderer_set_uvs(&a->r, &dh->map, &uv, &err)) st_app_message(a, 1, "cannot draw the UV checker: %s", err.msg);
        st_adapt_uv_free(&auv);
        a->shown_checker = checker;
        touched = 1;
    }
    if (rebuild || (ch.bits & ST_CHANGE_SELECTION)) {
        st_renderer_set_selection(&a->r, d->sel, d->nsel);
        touched = 1;
    }
    if (rebuild || (ch.bits & ST_CHANGE_BOX)) {
        float lo[3], hi[3];
        for (int i = 0; i < 3; i++) { lo[i] = (float)d->box.box_lo[i]; hi[i] = (float)d->box.box_hi[i]; }
        st_renderer_set_box(&a->r, lo, hi, d->box_on);
        touched = 1;
    }
    if (touched) {
        st_renderer_set_hover(&a->r, a->hover_vid);
        st_pick_invalidate(&a->pick);
        a->update_ms = now_ms() - t0;
    }
    if (ch.bits & (ST_CHANGE_TOPOLOGY | ST_CHANGE_POSITIONS | ST_CHANGE_ALL_POSITIONS | ST_CHANGE_BOX | ST_CHANGE_MASK))
        a->autosave_dirty = 1;
    return touched || ch.bits;
}

/* ---- drawing: the scene, then the overlay (hud_panels.c) ---------------------- */

void st_app_draw(st_app *a)
{
    const st_gl *gl = &a->gl;
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl->Viewport(0, 0, a->fb_w, a->fb_h);
    st_draw_opts o;
    memset(&o, 0, sizeof o);
    o.shading = a->shading;
    o.wire = a->wire;
    o.cage = a->cage;
    o.checker = a->checker;
    o.box = 1;
    o.clear = 1;
    /* Cage points and lines thinner when the editing level is dense for
     * the window (a level of thousands of vertices would be a carpet). */
    float spacing = a->r.has_cage && a->r.cage.nverts ? sqrtf((float)a->fb_w * a->fb_h / a->r.cage.nverts) : 100;
    o.point_size = fminf(7.0f, fmaxf(2.5f, 0.45f * spacing));
    o.line_width = spacing < 12 ? 0.8f : 1.2f;
    int scene = a->r.has_surf && (a->busy || a->doc.loaded);   /* busy: the worker owns the document */
    /* View > Show baked map: the bake's base level with its normal map. */
    int baked = scene && !a->busy && a->bake.show && st_app_draw_baked(a);
    if (baked) { /* drawn */ }
    else if (scene) st_renderer_draw(&a->r, &a->cc.cam, a->fb_w, a->fb_h, &o);
    else {
        gl->ClearColor(a->r.background[0], a->r.background[1], a->r.background[2], 1);
        gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    st_hud_begin(&a->hud, a->fb_w, a->fb_h);
    if (!a->busy) {
        st_app_draw_handles(a);
        st_app_draw_overlays(a);
        st_app_draw_hud(a);
    } else {
        st_app_draw_working(a);
    }
    st_hud_flush(&a->hud);
    st_gui_frame(a);
}

/* ---- camera -------------------------------------------------------------------- */

/* Framing fits the model into the part of the window the side panel
 * leaves free, and centres it there: the fit uses that part's aspect, and
 * a pan of half the panel's width moves the model to its centre. */
static void centre_in_free_part(st_app *a, int view)
{
    int panel = a->win_w > 0 ? (int)lround(st_gui_panel_pixels(a->win_w) * a->fb_w / a->win_w) : 0;
    int free_w = a->fb_w - panel > a->fb_w / 4 ? a->fb_w - panel : a->fb_w;
    float aspect = a->fb_h > 0 ? (float)free_w / (float)a->fb_h : 1;
    if (view < 0) st_camctl_frame_all(&a->cc, a->r.surf.bbox, aspect);
    else st_camctl_view(&a->cc, view, aspect);
    if (free_w < a->fb_w) st_camctl_pan(&a->cc, -0.5f * (float)(a->fb_w - free_w), 0, a->fb_w, a->fb_h);
    st_pick_invalidate(&a->pick);
}

void st_app_frame_model(st_app *a)
{
    if (a->r.has_surf && a->r.surf.nverts) centre_in_free_part(a, -1);
    st_pick_invalidate(&a->pick);
}

void st_app_view(st_app *a, int view) { centre_in_free_part(a, view); }

void st_win_on_resize(GLFWwindow *w, int width, int height)
{
    st_app *a = app_of(w);
    (void)width; (void)height;
    glfwGetFramebufferSize(w, &a->fb_w, &a->fb_h);
    glfwGetWindowSize(w, &a->win_w, &a->win_h);
    st_pick_invalidate(&a->pick);
}

void st_win_on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    st_app *a = app_of(w);
    int gui = st_gui_key(key, scancode, action, mods);   /* a text field or dialog takes keys */
    int bit = 0;
    switch (key) {
    case GLFW_KEY_LEFT_SHIFT: case GLFW_KEY_RIGHT_SHIFT: bit = GLFW_MOD_SHIFT; break;
    case GLFW_KEY_LEFT_CONTROL: case GLFW_KEY_RIGHT_CONTROL: bit = GLFW_MOD_CONTROL; break;
    case GLFW_KEY_LEFT_ALT: case GLFW_KEY_RIGHT_ALT: bit = GLFW_MOD_ALT; break;
    case GLFW_KEY_LEFT_SUPER: case GLFW_KEY_RIGHT_SUPER: bit = GLFW_MOD_SUPER; break;
    default: break;
    }
    if (bit) {
        if (action == GLFW_RELEASE) a->mods &= ~bit;
        else a->mods |= bit;
        if ((a->op == ST_OP_DRAG || a->op == ST_OP_GRAB) && bit != GLFW_MOD_SHIFT) st_app_drag_update(a);
        return;
    }
    if (action == GLFW_RELEASE || gui) return;
    st_app_key(a, key, mods);
}

/* What GLFW calls: the handlers above, except during a replay, when only
 * the script's events (the same handlers, called by replay.c) count, so
 * that a stray pointer of the X server cannot change the result
 * ($STRATA_REPLAY_LIVE=1 lets real input through as well). */
static int live_input(GLFWwindow *w)
{
    static int live = -1;
    if (live < 0) { const char *e = getenv("STRATA_REPLAY_LIVE"); live = e && e[0] == '1'; }
    return !app_of(w)->replay || live;
}

/* Any input, and anything that changes what is on screen, owes a few
 * frames: the GUI sees a press one frame and its release the next, a
 * window that fits its content is placed from its second frame, and an
 * action chosen in a menu runs before the frame after the click.  With no
 * frames owed the loop sleeps until the next event instead of redrawing:
 * at 25 million triangles a frame takes tens of seconds under a software
 * rasteriser, and an idle redraw would hold up the input that follows. */
void st_app_want_frames(st_app *a) { a->frames_owed = 3; }

static int input(GLFWwindow *w)
{
    st_app_want_frames(app_of(w));
    return live_input(w);
}

static void glfw_key(GLFWwindow *w, int key, int sc, int action, int mods) { if (input(w)) st_win_on_key(w, key, sc, action, mods); }
static void glfw_button(GLFWwindow *w, int b, int action, int mods) { if (input(w)) st_win_on_mouse_button(w, b, action, mods); }
static void glfw_cursor(GLFWwindow *w, double x, double y) { if (input(w)) st_win_on_cursor(w, x, y); }
static void glfw_scroll(GLFWwindow *w, double dx, double dy) { if (input(w)) st_win_on_scroll(w, dx, dy); }
static void glfw_drop(GLFWwindow *w, int n, const char **p) { if (input(w)) st_win_on_drop(w, n, p); }
static void glfw_char(GLFWwindow *w, unsigned c) { if (input(w)) st_gui_char(c); }

st_win_input st_win_swap_input(GLFWwindow *w, st_win_input in)
{
    st_win_input was;
    was.key = glfwSetKeyCallback(w, in.key);
    was.button = glfwSetMouseButtonCallback(w, in.button);
    was.cursor = glfwSetCursorPosCallback(w, in.cursor);
    was.scroll = glfwSetScrollCallback(w, in.scroll);
    was.drop = glfwSetDropCallback(w, in.drop);
    was.chr = glfwSetCharCallback(w, in.chr);
    return was;
}
static void glfw_resize(GLFWwindow *w, int width, int height) { st_app_want_frames(app_of(w)); st_win_on_resize(w, width, height); }
/* Uncovered, or focus and pointer coming and going (the GUI's hover). */
static void glfw_refresh(GLFWwindow *w) { st_app_want_frames(app_of(w)); }
static void glfw_focus(GLFWwindow *w, int focused) { (void)focused; st_app_want_frames(app_of(w)); }
static void glfw_enter(GLFWwindow *w, int entered) { (void)entered; st_app_want_frames(app_of(w)); }
/* The window manager's close button asks like Ctrl+Q. */
static void glfw_close(GLFWwindow *w)
{
    st_app *a = app_of(w);
    st_app_request_quit(a);
    if (!a->quit) glfwSetWindowShouldClose(w, GLFW_FALSE);
}

/* ---- screenshots ------------------------------------------------------------------ */

static void shot_path(char *out, size_t n, const char *dir, const char *name, const char *suffix)
{
    size_t len = strlen(name);
    if (len > 4 && !strcmp(name + len - 4, ".png")) len -= 4;
    snprintf(out, n, "%s%s%.*s%s.png", dir ? dir : "", dir && dir[0] ? "/" : "", (int)len, name, suffix);
}

/* Reads the frame just drawn from the back buffer and writes NAME (under
 * --screenshot-dir); with --compare-dir, compares it with the reference of
 * the same name there (tolerances of render/image.h) and writes
 * NAME.expected.png and NAME.diff.png next to it on a mismatch. */
static int take_screenshot(st_app *a, const char *name)
{
    const st_gl *gl = &a->gl;
    int w = a->fb_w, h = a->fb_h;
    unsigned char *px = malloc((size_t)w * h * 4), *img = malloc((size_t)w * h * 4);
    if (!px || !img) { free(px); free(img); fprintf(stderr, "strata: out of memory for a screenshot\n"); return -1; }
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl->ReadBuffer(GL_BACK);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px);
    for (int y = 0; y < h; y++) memcpy(img + (size_t)y * w * 4, px + (size_t)(h - 1 - y) * w * 4, (size_t)w * 4);
    free(px);
    char path[4200];
    shot_path(path, sizeof path, a->opts.screenshot_dir, name, "");
    st_error err;
    int rc = st_png_write(path, w, h, img, &err);
    if (rc) { fprintf(stderr, "strata: screenshot: %s\n", err.msg); free(img); return -1; }
    fprintf(stderr, "strata: screenshot %s (%dx%d)\n", path, w, h);
    if (a->opts.compare_dir) {
        char ref[4200];
        shot_path(ref, sizeof ref, a->opts.compare_dir, name, "");
        int rw = 0, rh = 0;
        unsigned char *exp = NULL;
        if (st_png_read(ref, &rw, &rh, &exp, &err)) {
            fprintf(stderr, "strata: screenshot %s: no reference %s (%s); to accept it: cp %s %s\n", name, ref, err.msg, path, ref);
            rc = -1;
        } else if (rw != w || rh != h) {
            fprintf(stderr, "strata: screenshot %s is %dx%d, the reference %s is %dx%d\n", name, w, h, ref, rw, rh);
            rc = -1;
        } else {
            unsigned char *diff = malloc((size_t)w * h * 4);
            st_image_diff dd;
            st_image_compare(img, exp, w, h, ST_IMAGE_TOL, &dd, diff);
            if (!st_image_match(&dd, ST_IMAGE_MAX_FRACTION)) {
                char pe[4200], pd[4200];
                shot_path(pe, sizeof pe, a->opts.screenshot_dir, name, ".expected");
                shot_path(pd, sizeof pd, a->opts.screenshot_dir, name, ".diff");
                st_png_write(pe, w, h, exp, NULL);
                if (diff) st_png_write(pd, w, h, diff, NULL);
                fprintf(stderr, "strata: screenshot %s differs from %s: %llu of %llu pixels (%.3f%%, limit %.3f%%) differ by more than %d, "
                                "max delta %d; wrote %s, %s and %s\n",
                        name, ref, (unsigned long long)dd.differing, (unsigned long long)dd.pixels, 100 * dd.fraction,
                        100 * ST_IMAGE_MAX_FRACTION, ST_IMAGE_TOL, dd.max_delta, path, pe, pd);
                rc = -1;
            } else {
                fprintf(stderr, "strata: screenshot %s matches %s (%llu pixels differ, max delta %d)\n", name, ref,
                        (unsigned long long)dd.differing, dd.max_delta);
            }
            free(diff);
            free(exp);
        }
    }
    free(img);
    return rc;
}

/* ---- set-up and the loop ------------------------------------------------------------ */

/* glfwInit, tried again for about 2 s when $DISPLAY is set: an X server
 * with other clients connecting at once (Xvfb under a test run's xdotool
 * searches) can turn a connection away; without $DISPLAY there is nothing
 * to wait for. */
static int init_glfw(void)
{
    const char *display = getenv("DISPLAY");
    int tries = display && display[0] ? 10 : 1;
    for (int i = 0; i < tries; i++) {
        if (glfwInit()) return 1;
        struct timespec ts = { 0, 200000000 };
        if (i + 1 < tries) nanosleep(&ts, NULL);
    }
    return 0;
}

static int make_window(st_app *a, int visible)
{
    glfwSetErrorCallback(on_glfw_error);
    if (!init_glfw()) {
        fprintf(stderr, "strata: cannot open a window: %s\n"
                        "strata: (no display? set DISPLAY or run under xvfb-run; `strata render` draws without a display)\n",
                glfw_error[0] ? glfw_error : "glfwInit failed");
        return 3;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, 4);
    a->win = glfwCreateWindow(a->opts.width, a->opts.height, "Strata", NULL, NULL);
    if (!a->win) {
        glfwWindowHint(GLFW_SAMPLES, 0);
        a->win = glfwCreateWindow(a->opts.width, a->opts.height, "Strata", NULL, NULL);
    }
    if (!a->win) {
        fprintf(stderr, "strata: cannot create an OpenGL 3.3 core window: %s\n", glfw_error[0] ? glfw_error : "?");
        glfwTerminate();
        return 3;
    }
    glfwMakeContextCurrent(a->win);
    st_error err;
    if (st_gl_load(&a->gl, glfwGetProcAddress, &err)) {
        fprintf(stderr, "strata: OpenGL: %s\n", err.msg);
        glfwDestroyWindow(a->win);
        glfwTerminate();
        return 3;
    }
    glfwSetWindowUserPointer(a->win, a);
    glfwGetFramebufferSize(a->win, &a->fb_w, &a->fb_h);
    glfwGetWindowSize(a->win, &a->win_w, &a->win_h);
    return 0;
}

/* ---- tests driving the real window (tests/cli/cli_gui_xdotool.sh) ------------------
 * With STRATA_GUI_PROBE=DIR (gui.cc writes DIR/gui, the widget rectangles),
 * SIGUSR1 asks for a screenshot: the name in DIR/shot, taken from the next
 * frame (under --screenshot-dir, compared under --compare-dir as a replay's)
 * and reported as a line "NAME ok" or "NAME failed" appended to DIR/shots.
 * Times are masked, as in replays, so that screenshots are comparable. */
static volatile sig_atomic_t g_shot_signal;
static void on_shot_signal(int sig) { (void)sig; g_shot_signal = 1; }

static const char *probe_dir(void)
{
    const char *d = getenv("STRATA_GUI_PROBE");
    return d && d[0] ? d : NULL;
}

static void probe_shot_request(st_app *a)
{
    char path[4200];
    if (!g_shot_signal || !probe_dir()) return;
    g_shot_signal = 0;
    snprintf(path, sizeof path, "%s/shot", probe_dir());
    FILE *f = fopen(path, "r");
    if (!f) return;
    if (fgets(a->shot, sizeof a->shot, f)) {
        a->shot[strcspn(a->shot, "\r\n")] = 0;
        a->shot_pending = a->shot[0] && !strchr(a->shot, '/');
        a->shot_probe = a->shot_pending;
    }
    fclose(f);
}

static void probe_shot_done(st_app *a, int rc)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/shots", probe_dir());
    FILE *f = fopen(path, "a");
    if (f) { fprintf(f, "%s %s\n", a->shot, rc ? "failed" : "ok"); fclose(f); }
}

/* Brush defaults (preferences): the tool by name, the radius as a fraction
 * of the model's size, the strength. */
static void brush_prefs_apply(st_app *a)
{
    const char *t = st_prefs_brush_tool();
    if (!strcmp(t, "select")) a->tool = ST_TOOL_SELECT;
    for (int i = 0; i < ST_BRUSH_COUNT; i++)
        if (!strcmp(t, st_brush_name(i))) a->tool = i;
    if (st_prefs_brush_radius() > 0) a->brush_radius_frac = st_prefs_brush_radius();
    if (st_prefs_brush_strength() > 0) a->doc.brush.strength = st_prefs_brush_strength();
}

static void brush_prefs_keep(const st_app *a)
{
    double frac = a->doc.loaded && a->cc.radius > 0 ? a->doc.brush.radius / a->cc.radius : a->brush_radius_frac;
    st_prefs_set_brush(a->tool == ST_TOOL_SELECT ? "select" : st_brush_name(a->tool), frac, a->doc.brush.strength);
}

/* The default model's folder: $STRATA_ASSETS; else the installed copy,
 * found from the executable's own place (<prefix>/bin/strata ->
 * <prefix>/share/strata/assets, STRATA_INSTALLED_ASSETS from
 * cmake/ui.cmake), so an installed or unpacked tree (dpkg -x) finds it
 * wherever it lies; else the assets/ of the source tree the build was made
 * from (a build run in place). */
static void default_asset(st_app *a)
{
    const char *dir = getenv("STRATA_ASSETS");
    if (dir && dir[0]) {
        snprintf(a->default_path, sizeof a->default_path, "%s/%s", dir, DEFAULT_ASSET);
        return;
    }
    char exe[2048];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    char *slash = NULL;
    if (n > 0) {
        exe[n] = 0;
        slash = strrchr(exe, '/');
    }
    if (slash) {
        *slash = 0;
        int w = snprintf(a->default_path, sizeof a->default_path, "%s/%s/%s", exe, STRATA_INSTALLED_ASSETS, DEFAULT_ASSET);
        if (w > 0 && (size_t)w < sizeof a->default_path && access(a->default_path, R_OK) == 0) return;
    }
    snprintf(a->default_path, sizeof a->default_path, "%s/%s", STRATA_ASSETS, DEFAULT_ASSET);
}

int st_window_main(const st_win_opts *o)
{
    st_app *a = calloc(1, sizeof *a);
    if (!a) { fprintf(stderr, "strata: out of memory\n"); return 1; }
    a->opts = *o;
    a->tool = ST_TOOL_SELECT;
    a->shading = ST_SHADE_SMOOTH;
    a->cage = 1;
    a->hover_vid = ST_NIL;
    a->box_handle = -1;
    a->masked_times = o->replay != NULL || probe_dir();
    a->brush_radius_frac = 0.125;
    st_doc_init(&a->doc);
    if (o->mem_budget_mb > 0) a->doc.mem_budget = (size_t)(o->mem_budget_mb * 1048576.0);
    if (o->strict) a->doc.read_flags |= ST_MESH_STRICT;
    a->doc.load_mesh = o->load_mesh;
    default_asset(a);

    /* Preferences (recent files, window size, UI scale): not in replays,
     * which must not depend on the user's files. */
    if (!o->replay) {
        st_prefs_load();
        int pw, ph;
        st_prefs_window(&pw, &ph);
        if (!o->size_given && pw >= 64 && ph >= 64 && pw <= 8192 && ph <= 8192) { a->opts.width = pw; a->opts.height = ph; }
        brush_prefs_apply(a);
    }
    if (probe_dir()) {
        /* sigaction: signal() may reset the handler after one signal. */
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_shot_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESTART;
        sigaction(SIGUSR1, &sa, NULL);
    }
    st_replay *rp = NULL;
    st_error err;
    if (o->replay && st_replay_load(&rp, o->replay, &err)) {
        fprintf(stderr, "strata: --replay: %s\n", err.msg);
        st_doc_free(&a->doc);
        free(a);
        return 2;
    }
    int rc = make_window(a, 1);
    if (rc) { st_replay_free(rp); st_doc_free(&a->doc); free(a); return rc; }
    a->replay = rp;
    if (st_renderer_init(&a->r, &a->gl, &err) || st_pick_init(&a->pick, &a->gl, &err) || st_hud_init(&a->hud, &a->gl, &err)) {
        fprintf(stderr, "strata: %s\n", err.msg);
        glfwDestroyWindow(a->win);
        glfwTerminate();
        st_replay_free(rp);
        st_doc_free(&a->doc);
        free(a);
        return 1;
    }
    st_win_swap_input(a->win, (st_win_input){ glfw_key, glfw_button, glfw_cursor, glfw_scroll, glfw_drop, glfw_char });
    glfwSetFramebufferSizeCallback(a->win, glfw_resize);
    glfwSetWindowRefreshCallback(a->win, glfw_refresh);
    glfwSetWindowFocusCallback(a->win, glfw_focus);
    glfwSetCursorEnterCallback(a->win, glfw_enter);
    glfwSetWindowCloseCallback(a->win, glfw_close);
    /* Replays start with the GUI hidden (their references predate it; the
     * script's `gui on` shows it). */
    st_gui_init(a, !o->no_gui && !rp);
    glfwSwapInterval(rp ? 0 : 1);
    float bb[6] = { -1, -1, -1, 1, 1, 1 };
    st_camctl_init(&a->cc, bb, st_app_aspect(a));

    const char *path = o->file ? o->file : a->default_path;
    int opened = st_app_open(a, path);
    a->showing_default = !o->file && !opened;
    if (opened && o->file && !rp) {
        /* The file given on the command line failed: say so, fall back to
         * the default asset so that the window still opens. */
        char keep[ST_MSG_LEN];
        memcpy(keep, a->msg, sizeof keep);
        a->showing_default = !st_app_open(a, a->default_path);
        memcpy(a->msg, keep, sizeof keep);
        a->msg_error = 1;
    }
    int autosave = !rp || getenv("STRATA_RECOVERY");
    if (!rp) st_app_check_recovery(a);
    if (rp && !a->doc.loaded) {
        fprintf(stderr, "strata: --replay: the model did not load\n");
        a->exit_code = 1;
        a->quit = 1;
    }

    while (!a->quit && !glfwWindowShouldClose(a->win)) {
        if (rp) {
            glfwPollEvents();
            int s = st_replay_step(rp, a);
            if (s < 0) { a->exit_code = 1; break; }
            if (s > 0) break;
        } else {
            if (a->op == ST_OP_NONE && a->frames_owed <= 0) glfwWaitEventsTimeout(0.25);
            else glfwPollEvents();
        }
        st_gui_run_pending(a);
        glfwGetFramebufferSize(a->win, &a->fb_w, &a->fb_h);
        glfwGetWindowSize(a->win, &a->win_w, &a->win_h);
        if (st_app_sync(a) || st_gui_wants_frames()) st_app_want_frames(a);
        probe_shot_request(a);
        /* Idle: nothing came in, nothing changed, no drag or stroke going
         * on.  The timeout still wakes the loop for the recovery save and
         * the probe's screenshot signal; STRATA_GUI_PROBE keeps the frames
         * coming, as test scripts count frames to know input was seen. */
        if (!rp && a->op == ST_OP_NONE && a->frames_owed <= 0 && !a->shot_pending && !probe_dir()) {
            if (autosave) st_app_autosave_tick(a, 0);
            continue;
        }
        if (a->frames_owed > 0) a->frames_owed--;
        double t0 = now_ms();   /* frame time: drawing and presenting, not the wait for events */
        st_app_draw(a);
        if (a->shot_pending) {
            a->shot_pending = 0;
            int shot_rc = take_screenshot(a, a->shot);
            /* A test's screenshot: reported, and the run goes on to the
             * end (its exit status says a screenshot failed). */
            if (a->shot_probe) { a->shot_probe = 0; probe_shot_done(a, shot_rc); if (shot_rc) a->exit_code = 1; }
            else if (shot_rc) { a->exit_code = 1; break; }
        }
        glfwSwapBuffers(a->win);
        a->frame_ms = now_ms() - t0;
        if (autosave) st_app_autosave_tick(a, 0);
        a->frames++;
    }
    if (autosave && !a->exit_code) st_app_autosave_tick(a, 1);
    rc = a->exit_code;
    if (rp && !rc) fprintf(stderr, "strata: replay %s passed (%llu frames)\n", o->replay, (unsigned long long)a->frames);
    if (!rp) {
        st_prefs_set_window(a->win_w, a->win_h);
        brush_prefs_keep(a);
        st_prefs_save();
    }
    st_prefs_free();
    st_gui_shutdown();
    st_replay_free(rp);
    st_hud_free(&a->hud);
    st_app_bake_free(a);
    st_pick_free(&a->pick);
    st_renderer_free(&a->r);
    glfwDestroyWindow(a->win);
    glfwTerminate();
    st_doc_free(&a->doc);
    free(a);
    return rc;
}
