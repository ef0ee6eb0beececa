/* The modeller window: GLFW setup, the event handlers, renderer updates and
 * the frame loop; see window.h. */
#include "window.h"

#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "image.h"
#include "replay.h"
#include "core/io/session.h"

#ifndef STRATA_ASSETS
#define STRATA_ASSETS "assets"
#endif
#define DEFAULT_ASSET "torus.obj"
#define DEFAULT_LEVELS 2
#define DRAG_THRESHOLD 4.0           /* pixels before a press becomes a drag */
#define WORKING_FACES 150000         /* show a "working" frame above this */
#define STROKE_REPICK_TRIS 400000    /* brush strokes re-pick the surface per dab below this */

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

static st_app *app_of(GLFWwindow *w) { return (st_app *)glfwGetWindowUserPointer(w); }

void st_app_message(st_app *a, int error, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(a->msg, sizeof a->msg, fmt, ap);
    va_end(ap);
    a->msg_error = error;
    a->msg_time = glfwGetTime();
    if (error || a->opts.replay) fprintf(stderr, "strata: %s\n", a->msg);
}

/* Times in the HUD and messages: masked in replays so that screenshots of
 * the same script are the same pixels. */
static const char *fmt_ms(const st_app *a, double ms, char *buf, size_t n)
{
    if (a->masked_times) snprintf(buf, n, "-- ms");
    else if (ms >= 1000) snprintf(buf, n, "%.2f s", ms / 1000);
    else snprintf(buf, n, "%.1f ms", ms);
    return buf;
}

static float aspect(const st_app *a) { return a->fb_h > 0 ? (float)a->fb_w / (float)a->fb_h : 1; }

/* ---- document -> renderer ----------------------------------------------------- */

static unsigned shown_level(const st_doc *d) { return st_doc_display_map_level(d); }

/* Every position changed: the surface is read from the displayed hierarchy
 * (the adaptive one when the box is on) and the cage from the model. */
static void refresh_all(st_app *a)
{
    const st_doc *d = &a->doc;
    const st_hier *dh = st_doc_display_hier(d);
    if (dh == &d->h) { st_renderer_refresh_all(&a->r, ST_TARGET_MESHES, &d->h.map); return; }
    st_renderer_refresh_all(&a->r, ST_TARGET_SURFACE, &dh->map);
    st_renderer_refresh_all(&a->r, ST_TARGET_CAGE, &d->h.map);
}

void st_app_sync(st_app *a)
{
    st_doc *d = &a->doc;
    st_doc_change ch = st_doc_take_change(d);
    if (!d->loaded) {
        st_renderer_clear(&a->r, ST_TARGET_MESHES);
        a->shown_valid = 0;
        return;
    }
    double t0 = now_ms();
    int touched = 0;
    unsigned disp = shown_level(d);
    const st_hier *dh = st_doc_display_hier(d);
    int rebuild = !a->shown_valid || (ch.bits & ST_CHANGE_TOPOLOGY) || disp != a->shown_display ||
                  d->edit_level != a->shown_edit || d->h.map.top != a->shown_top || d->box_on != a->shown_box_on;
    st_error err;
    if (rebuild) {
        if (st_renderer_set_level(&a->r, &dh->map, disp, &err) ||
            st_renderer_set_cage(&a->r, &d->h.map, d->edit_level, &err))
            st_app_message(a, 1, "cannot draw the model: %s", err.msg);
        a->shown_display = disp;
        a->shown_edit = d->edit_level;
        a->shown_top = d->h.map.top;
        a->shown_box_on = d->box_on;
        a->shown_valid = 1;
        a->hover_vid = ST_NIL;
        touched = 1;
    }
    if (!rebuild && (ch.bits & ST_CHANGE_PATCH)) {
        /* A box move: only the touched faces are re-tessellated. */
        if (st_renderer_patch(&a->r, &dh->map, ch.patch)) {
            if (st_renderer_set_level(&a->r, &dh->map, disp, &err))
                st_app_message(a, 1, "cannot draw the model: %s", err.msg);
        } else {
            a->patches++;
        }
        a->hover_vid = ST_NIL;
        touched = 1;
    }
    if (rebuild) {
        /* (the buffers were just built from the current positions) */
    } else if ((ch.bits & ST_CHANGE_ALL_POSITIONS) ||
               ((ch.bits & ST_CHANGE_POSITIONS) && dh != &d->h && !(ch.bits & ST_CHANGE_DISPLAY))) {
        refresh_all(a);
        touched = 1;
    } else if (dh != &d->h && (ch.bits & (ST_CHANGE_POSITIONS | ST_CHANGE_DISPLAY))) {
        /* Box on: what core wrote in the display hierarchy for the
         * surface, what it wrote in the model for the cage. */
        int rc = 0;
        if (ch.bits & ST_CHANGE_DISPLAY)
            rc |= st_renderer_refresh(&a->r, ST_TARGET_SURFACE, &dh->map, ch.disp_footprint);
        if (ch.bits & ST_CHANGE_POSITIONS) rc |= st_renderer_refresh(&a->r, ST_TARGET_CAGE, &d->h.map, ch.footprint);
        if (rc) refresh_all(a);
        touched = 1;
    } else if ((ch.bits & ST_CHANGE_POSITIONS) && ch.nmoved) {
        if (st_renderer_refresh(&a->r, ST_TARGET_MESHES, &d->h.map, ch.footprint)) {
            /* Out of memory for the incremental path: rebuild. */
            st_renderer_set_level(&a->r, &dh->map, disp, &err);
            st_renderer_set_cage(&a->r, &d->h.map, d->edit_level, &err);
            rebuild = 1;
        }
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
    if (ch.bits & (ST_CHANGE_TOPOLOGY | ST_CHANGE_POSITIONS | ST_CHANGE_ALL_POSITIONS | ST_CHANGE_BOX))
        a->autosave_dirty = 1;
}

/* ---- drawing ------------------------------------------------------------------ */

static const float C_TEXT[4] = { 0.08f, 0.09f, 0.12f, 1 };
static const float C_DIM[4] = { 0.30f, 0.32f, 0.38f, 1 };
static const float C_ERR[4] = { 0.80f, 0.05f, 0.05f, 1 };
static const float C_OK[4] = { 0.05f, 0.40f, 0.15f, 1 };
static const float C_PANEL[4] = { 1, 1, 1, 0.6f };
static const float C_DARK[4] = { 0.10f, 0.11f, 0.14f, 0.88f };
static const float C_WHITE[4] = { 1, 1, 1, 1 };
static const float C_BRUSH[4] = { 0.95f, 0.35f, 0.10f, 0.9f };
static const float C_RECT[4] = { 0.10f, 0.30f, 0.85f, 0.9f };
static const float C_RECT_FILL[4] = { 0.10f, 0.30f, 0.85f, 0.12f };

/* Text scale: the font's 7-pixel glyphs enlarged, less in small windows. */
static float hud_scale = 1.6f;
#define HUD_SCALE hud_scale
#define HUD_LINE (12 * HUD_SCALE)

static const char *file_base(const char *p)
{
    const char *s = strrchr(p, '/');
    return s ? s + 1 : p;
}

/* The "working..." panel of a long operation (reads nothing of the
 * document: a worker thread may own it). */
static void draw_working(st_app *a)
{
    st_hud *u = &a->hud;
    if (!a->working[0]) return;
    float sc = 2 * HUD_SCALE;
    float w = st_hud_text_width(a->working, sc);
    if (w > (float)a->fb_w - 48) { sc *= ((float)a->fb_w - 48) / w; w = st_hud_text_width(a->working, sc); }
    float h = 12 * sc, x = 0.5f * ((float)a->fb_w - w), y = 0.5f * ((float)a->fb_h - h);
    st_hud_rect(u, x - 20, y - 16, x + w + 20, y + h + 8, C_DARK);
    st_hud_text(u, x, y, sc, C_WHITE, a->working);
}

static void draw_hud(st_app *a)
{
    st_hud *u = &a->hud;
    st_doc *d = &a->doc;
    hud_scale = a->fb_h < 600 || a->fb_w < 800 ? 1.2f : 1.6f;
    char line[10][256], t1[32], t2[32];
    int n = 0;
    if (d->loaded) {
        uint64_t faces = 0, verts = 0;
        st_doc_display_counts(d, &faces, &verts);
        snprintf(line[n++], 256, "%s   %s", file_base(d->path), d->scheme ? d->scheme->name : "?");
        snprintf(line[n++], 256, "levels 0..%u   editing %u   displayed %s%u", d->h.map.top, d->edit_level,
                 d->box_on ? "adaptive " : "", shown_level(d));
        snprintf(line[n++], 256, "faces %llu   vertices %llu   editing-level vertices %u",
                 (unsigned long long)faces, (unsigned long long)verts, a->r.has_cage ? a->r.cage.nverts : 0);
        if (a->tool == ST_TOOL_SELECT)
            snprintf(line[n++], 256, "tool select/move   selected %u", d->nsel);
        else
            snprintf(line[n++], 256, "tool brush %s   radius %.3g   strength %.2f%s%s   selected %u",
                     st_brush_name(a->tool), d->brush.radius, d->brush.strength,
                     d->brush.mirror_x ? "   mirror X" : "", d->brush.invert ? "   inverted" : "", d->nsel);
        if (d->box_on)
            snprintf(line[n++], 256, "box (%.2f %.2f %.2f)-(%.2f %.2f %.2f)   levels %u..%u",
                     d->box.box_lo[0], d->box.box_lo[1], d->box.box_lo[2], d->box.box_hi[0], d->box.box_hi[1],
                     d->box.box_hi[2], d->box.base_level, d->box.max_level);
        else
            snprintf(line[n++], 256, "box off (I)");
        snprintf(line[n++], 256, "undo %u/%u   %s", d->undo_pos, d->nundo, a->cc.cam.ortho ? "ortho" : "persp");
    } else {
        snprintf(line[n++], 256, "no model: drop a mesh file on the window");
    }
    char t3[32];
    snprintf(line[n++], 256, "frame %s   last update: geometry %s + buffers %s   F1 help", fmt_ms(a, a->frame_ms, t1, sizeof t1),
             fmt_ms(a, d->loaded ? d->last_update_ms : 0, t2, sizeof t2), fmt_ms(a, a->update_ms, t3, sizeof t3));
    float wmax = 0;
    for (int i = 0; i < n; i++) {
        float w = st_hud_text_width(line[i], HUD_SCALE);
        if (w > wmax) wmax = w;
    }
    st_hud_rect(u, 0, 0, wmax + 16, 8 + n * HUD_LINE, C_PANEL);
    for (int i = 0; i < n; i++) st_hud_text(u, 8, 6 + i * HUD_LINE, HUD_SCALE, i == 0 ? C_TEXT : C_DIM, line[i]);

    /* Status line and questions at the bottom. */
    const char *msg = a->msg;
    char ask[256];
    if (a->pending_scheme) {
        snprintf(ask, sizeof ask, "Change the scheme to %s? The hierarchy is rebuilt, details are lost. Y: yes, K: next scheme, N: no",
                 a->pending_scheme);
        msg = ask;
    }
    if (msg[0]) {
        /* Wrapped at spaces to the window's width (long error messages). */
        char lines[4][ST_MSG_LEN];
        int nl = 0;
        float maxw = (float)a->fb_w - 16, wmax = 0;
        const char *p = msg;
        while (*p && nl < 4) {
            size_t n = strlen(p), cut = n;
            if (st_hud_text_width(p, HUD_SCALE) > maxw && nl < 3) {
                /* The longest prefix ending at a space that fits. */
                char tmp[ST_MSG_LEN];
                size_t best = 0;
                for (size_t i = 1; i < n && i < sizeof tmp; i++) {
                    if (p[i] != ' ') continue;
                    memcpy(tmp, p, i);
                    tmp[i] = 0;
                    if (st_hud_text_width(tmp, HUD_SCALE) > maxw) break;
                    best = i;
                }
                if (best) cut = best;
            }
            if (cut >= sizeof lines[0]) cut = sizeof lines[0] - 1;
            memcpy(lines[nl], p, cut);
            lines[nl][cut] = 0;
            float w = st_hud_text_width(lines[nl], HUD_SCALE);
            if (w > wmax) wmax = w;
            nl++;
            p += cut;
            while (*p == ' ') p++;
        }
        float y = (float)a->fb_h - nl * HUD_LINE - 6;
        st_hud_rect(u, 0, y - 4, wmax + 16, (float)a->fb_h, C_PANEL);
        for (int i = 0; i < nl; i++)
            st_hud_text(u, 8, y + i * HUD_LINE, HUD_SCALE, a->pending_scheme ? C_TEXT : a->msg_error ? C_ERR : C_OK, lines[i]);
    }

    if (a->help) {
        /* Two columns (keys, what they do), at a scale that fits. */
        float colw = 0, wmaxd = 0;
        for (unsigned i = 0; i < st_nbindings; i++) {
            float w = st_hud_text_width(st_bindings[i].keys, 1);
            if (w > colw) colw = w;
            w = st_hud_text_width(st_bindings[i].what, 1);
            if (w > wmaxd) wmaxd = w;
        }
        float s = HUD_SCALE;
        float sw = ((float)a->fb_w - 60) / (colw + 16 + wmaxd), sh = ((float)a->fb_h - 40) / (12.0f * (st_nbindings + 2));
        if (sw < s) s = sw;
        if (sh < s) s = sh;
        float lh = 12 * s, x0 = 24, y0 = 0.5f * ((float)a->fb_h - (st_nbindings + 1) * lh);
        st_hud_rect(u, x0 - 12, y0 - 10, x0 + (colw + 16 + wmaxd) * s + 12, y0 + (st_nbindings + 1) * lh + 4, C_DARK);
        st_hud_text(u, x0, y0, s, C_BRUSH, "Key bindings (F1 closes)");
        for (unsigned i = 0; i < st_nbindings; i++) {
            st_hud_text(u, x0, y0 + (i + 1) * lh, s, C_BRUSH, st_bindings[i].keys);
            st_hud_text(u, x0 + (colw + 16) * s, y0 + (i + 1) * lh, s, C_WHITE, st_bindings[i].what);
        }
    }

    draw_working(a);
}

static void draw_overlays(st_app *a)
{
    st_hud *u = &a->hud;
    if (a->op == ST_OP_RECT) {
        float x0 = (float)a->op_x0, y0 = (float)a->op_y0, x1 = (float)a->mx, y1 = (float)a->my;
        st_hud_rect(u, fminf(x0, x1), fminf(y0, y1), fmaxf(x0, x1), fmaxf(y0, y1), C_RECT_FILL);
        st_hud_line(u, x0, y0, x1, y0, 1.5f, C_RECT);
        st_hud_line(u, x1, y0, x1, y1, 1.5f, C_RECT);
        st_hud_line(u, x1, y1, x0, y1, 1.5f, C_RECT);
        st_hud_line(u, x0, y1, x0, y0, 1.5f, C_RECT);
    }
    if (a->tool != ST_TOOL_SELECT && a->doc.loaded) {
        /* The brush circle: its radius projected at the surface point under
         * the cursor (or at the grab centre during a grab stroke). */
        const double *p = a->op == ST_OP_STROKE && a->tool == ST_BRUSH_GRAB ? a->stroke_pos : a->brush_pos;
        if (a->brush_hit || a->op == ST_OP_STROKE) {
            double s[2];
            double px = st_camctl_pixel_size(&a->cc, a->fb_w, a->fb_h, p);
            float rad = (float)(a->doc.brush.radius / (px > 0 ? px : 1));
            if (st_camctl_project(&a->cc, a->fb_w, a->fb_h, p, s, NULL))
                st_hud_circle(u, (float)s[0], (float)s[1], rad, 2, C_BRUSH);
            if (a->doc.brush.mirror_x) {
                double q[3] = { -p[0], p[1], p[2] };
                if (st_camctl_project(&a->cc, a->fb_w, a->fb_h, q, s, NULL))
                    st_hud_circle(u, (float)s[0], (float)s[1], rad, 1, C_BRUSH);
            }
        } else {
            st_hud_circle(u, (float)a->mx, (float)a->my, 30, 1, C_DIM);
        }
    }
}

static void draw_handles(st_app *a);

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
    o.box = 1;
    o.clear = 1;
    /* Cage points and lines thinner when the editing level is dense for
     * the window (a level of thousands of vertices would be a carpet). */
    float spacing = a->r.has_cage && a->r.cage.nverts ? sqrtf((float)a->fb_w * a->fb_h / a->r.cage.nverts) : 100;
    o.point_size = fminf(7.0f, fmaxf(2.5f, 0.45f * spacing));
    o.line_width = spacing < 12 ? 0.8f : 1.2f;
    int scene = a->r.has_surf && (a->busy || a->doc.loaded);   /* busy: the worker owns the document */
    if (scene) st_renderer_draw(&a->r, &a->cc.cam, a->fb_w, a->fb_h, &o);
    else {
        gl->ClearColor(a->r.background[0], a->r.background[1], a->r.background[2], 1);
        gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    st_hud_begin(&a->hud, a->fb_w, a->fb_h);
    if (!a->busy) {
        draw_handles(a);
        draw_overlays(a);
        draw_hud(a);
    } else {
        draw_working(a);
    }
    st_hud_flush(&a->hud);
}

/* A frame saying what is being done, drawn before a long operation starts. */
static void show_working(st_app *a, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(a->working, sizeof a->working, fmt, ap);
    va_end(ap);
    st_app_draw(a);
    glfwSwapBuffers(a->win);
    a->gl.Finish();
    fprintf(stderr, "strata: %s\n", a->working);
}

/* ---- long document operations on a worker thread ------------------------------------- */

enum { JOB_OPEN, JOB_ADD_LEVEL, JOB_SCHEME };

typedef struct doc_job {
    st_doc *d;
    int kind;
    const char *path, *scheme;
    unsigned levels;
    st_error err;
    int rc;
    atomic_int done;
    /* The editor's progress callback (on the worker): the current stage. */
    pthread_mutex_t mu;
    char stage[160];
    unsigned step, steps;
} doc_job;

static void job_progress(void *ctx, const char *what, unsigned step, unsigned steps)
{
    doc_job *j = ctx;
    pthread_mutex_lock(&j->mu);
    snprintf(j->stage, sizeof j->stage, "%s", what ? what : "");
    j->step = step;
    j->steps = steps;
    pthread_mutex_unlock(&j->mu);
}

static void *job_main(void *p)
{
    doc_job *j = p;
    switch (j->kind) {
    case JOB_OPEN: j->rc = st_doc_open(j->d, j->path, j->scheme, j->levels, &j->err); break;
    case JOB_ADD_LEVEL: j->rc = st_doc_add_level(j->d, &j->err); break;
    default: j->rc = st_doc_set_scheme(j->d, j->scheme, &j->err); break;
    }
    atomic_store(&j->done, 1);
    return NULL;
}

/* Runs a document operation on a worker thread while this thread, after
 * 150 ms, redraws a "working" frame with the elapsed time every 100 ms: the
 * scene from the renderer's own buffers and the message, nothing read from
 * the document meanwhile, and the stage the editor's progress callback last
 * reported ("building level 6, step 6 of 6").  Input is not processed until
 * it ends (GLFW forbids polling events from inside a callback, where this
 * runs). */
static int run_job(st_app *a, doc_job *j, const char *what)
{
    j->d = &a->doc;
    atomic_init(&j->done, 0);
    pthread_mutex_init(&j->mu, NULL);
    j->stage[0] = 0;
    j->step = j->steps = 0;
    pthread_t th;
    a->doc.progress = job_progress;
    a->doc.progress_ctx = j;
    if (pthread_create(&th, NULL, job_main, j)) {
        show_working(a, "%s", what);
        job_main(j);
        a->doc.progress = NULL;
        a->doc.progress_ctx = NULL;
        pthread_mutex_destroy(&j->mu);
        a->working[0] = 0;
        return j->rc;
    }
    double t0 = now_ms(), next = t0 + 150;
    int shown = a->working[0] != 0;   /* show_working() already said it */
    while (!atomic_load(&j->done)) {
        double t = now_ms();
        if (t >= next) {
            char el[32];
            if (a->masked_times) snprintf(el, sizeof el, "--");
            else snprintf(el, sizeof el, "%.1f s", (t - t0) / 1000);
            char stage[200] = "";
            pthread_mutex_lock(&j->mu);
            if (j->stage[0] && j->steps > 1) snprintf(stage, sizeof stage, "%s, step %u of %u, ", j->stage, j->step, j->steps);
            else if (j->stage[0]) snprintf(stage, sizeof stage, "%s, ", j->stage);
            pthread_mutex_unlock(&j->mu);
            snprintf(a->working, sizeof a->working, "%s  (%s%s)", what, stage, el);
            if (!shown) fprintf(stderr, "strata: %s\n", what);
            shown = 1;
            a->busy = 1;
            st_app_draw(a);
            glfwSwapBuffers(a->win);
            next = t + 100;
        } else {
            struct timespec ts = { 0, 2000000 };
            nanosleep(&ts, NULL);
        }
    }
    pthread_join(th, NULL);
    a->doc.progress = NULL;
    a->doc.progress_ctx = NULL;
    pthread_mutex_destroy(&j->mu);
    a->busy = 0;
    a->working[0] = 0;
    return j->rc;
}

/* ---- opening ------------------------------------------------------------------ */

static void frame_model(st_app *a)
{
    if (a->r.has_surf && a->r.surf.nverts) st_camctl_frame_all(&a->cc, a->r.surf.bbox, aspect(a));
    st_pick_invalidate(&a->pick);
}

int st_app_open(st_app *a, const char *path)
{
    st_error err;
    if (st_session_is_path(path)) return st_app_restore(a, path);
    unsigned levels = a->opts.levels >= 0 ? (unsigned)a->opts.levels : DEFAULT_LEVELS;
    const char *scheme = a->opts.scheme ? a->opts.scheme : (a->doc.loaded && a->doc.scheme ? a->doc.scheme->name : "catmull-clark");
    double t0 = now_ms();
    char what[300];
    snprintf(what, sizeof what, "working... opening %s", file_base(path));
    doc_job j = { .kind = JOB_OPEN, .path = path, .scheme = scheme, .levels = levels };
    int rc = run_job(a, &j, what);
    err = j.err;
    if (rc) {
        st_app_message(a, 1, "cannot open %s: %s%s", file_base(path), err.msg,
                       a->doc.loaded ? " (the current model is kept)" : "");
        return rc;
    }
    a->shown_valid = 0;
    a->hover_vid = ST_NIL;
    a->op = ST_OP_NONE;
    st_app_sync(a);
    a->autosave_dirty = 0;   /* opening is not an edit */
    frame_model(a);
    /* Brush radius in model units: an eighth of the half-diagonal, so
     * that models of any scale get a usable brush. */
    a->doc.brush.radius = 0.125 * a->cc.radius;
    char title[512];
    snprintf(title, sizeof title, "Strata - %s", file_base(path));
    glfwSetWindowTitle(a->win, title);
    char t[32];
    st_app_message(a, 0, "opened %s (%s, %u levels) in %s", file_base(path), a->doc.scheme->name, a->doc.h.map.top,
                   fmt_ms(a, now_ms() - t0, t, sizeof t));
    return 0;
}

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

static void update_hover(st_app *a)
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

static void drag_start(st_app *a, int op)
{
    st_doc *d = &a->doc;
    if (!d->nsel) return;
    if (st_doc_drag_begin(d)) { st_app_message(a, 1, "cannot drag the selection"); return; }
    selection_frame(a, a->drag_anchor, a->drag_normal);
    a->op = op;
    a->op_lx = a->mx;
    a->op_ly = a->my;
}

static void drag_update(st_app *a)
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

static void drag_finish(st_app *a, int cancel)
{
    if (cancel) st_doc_drag_cancel(&a->doc);
    else st_doc_drag_end(&a->doc);
    a->op = ST_OP_NONE;
    st_app_sync(a);
    if (cancel) st_app_message(a, 0, "move cancelled");
}

/* ---- brush strokes ------------------------------------------------------------ */

static void stroke_start(st_app *a, int mods)
{
    st_doc *d = &a->doc;
    if (ensure_pick(a)) return;
    double p[3], nrm[3];
    if (!st_pick_surface(&a->pick, &a->cc, (int)floor(a->mx), (int)floor(a->my), p, nrm)) return;
    d->brush.tool = a->tool;
    d->brush.invert = (mods & GLFW_MOD_CONTROL) != 0;
    if (st_doc_stroke_begin(d)) { st_app_message(a, 1, "cannot start a stroke"); return; }
    a->op = ST_OP_STROKE;
    a->op_lx = a->mx;
    a->op_ly = a->my;
    memcpy(a->stroke_pos, p, sizeof p);
    memcpy(a->brush_pos, p, sizeof p);
    memcpy(a->brush_nrm, nrm, sizeof nrm);
    a->brush_hit = 1;
    static const double zero[3] = { 0, 0, 0 };
    if (a->tool != ST_BRUSH_GRAB && st_doc_stroke_dab(d, p, nrm, zero)) st_app_message(a, 1, "brush dab failed");
    st_app_sync(a);
}

static void stroke_move(st_app *a)
{
    st_doc *d = &a->doc;
    double dx = a->mx - a->op_lx, dy = a->my - a->op_ly;
    if (dx * dx + dy * dy < 1) return;
    if (a->tool == ST_BRUSH_GRAB) {
        double delta[3];
        st_camctl_screen_delta(&a->cc, a->fb_w, a->fb_h, a->stroke_pos, dx, dy, delta);
        if (st_doc_stroke_dab(d, a->stroke_pos, a->brush_nrm, delta)) st_app_message(a, 1, "brush dab failed");
        for (int k = 0; k < 3; k++) a->stroke_pos[k] += delta[k];
    } else {
        /* The surface under the cursor, from an ID buffer redrawn after
         * every dab; on a dense display (a full draw per mouse move would
         * make strokes lag) the buffer of the stroke's start is reused:
         * the dabs move the surface by a fraction of the radius. */
        if (a->r.surf.ntris < STROKE_REPICK_TRIS) {
            st_app_sync(a);
            if (ensure_pick(a)) return;
        }
        double p[3], nrm[3];
        if (st_pick_surface(&a->pick, &a->cc, (int)floor(a->mx), (int)floor(a->my), p, nrm)) {
            static const double zero[3] = { 0, 0, 0 };
            memcpy(a->brush_pos, p, sizeof p);
            memcpy(a->brush_nrm, nrm, sizeof nrm);
            if (st_doc_stroke_dab(d, p, nrm, zero)) st_app_message(a, 1, "brush dab failed");
        }
    }
    a->op_lx = a->mx;
    a->op_ly = a->my;
    st_app_sync(a);
}

static void stroke_finish(st_app *a)
{
    st_doc_stroke_end(&a->doc);
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

static void select_all(st_app *a, int none)
{
    if (none || !a->r.has_cage) { st_doc_select(&a->doc, NULL, 0, ST_SELECT_REPLACE); st_app_sync(a); return; }
    st_doc_select(&a->doc, a->r.cage.vid, a->r.cage.nverts, ST_SELECT_REPLACE);
    st_app_sync(a);
}

/* ---- interest-box handles ---------------------------------------------------------- */

#define HANDLE_PICK 10.0          /* pixels */

static void handle_pos(const st_adapt_params *b, int k, double p[3])
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
        handle_pos(&a->doc.box, k, p);
        if (!st_camctl_project(&a->cc, a->fb_w, a->fb_h, p, s, NULL)) continue;
        double d = (s[0] - x) * (s[0] - x) + (s[1] - y) * (s[1] - y);
        if (d < bestd) { bestd = d; best = k; }
    }
    return best;
}

static void draw_handles(st_app *a)
{
    static const float c[4] = { 0.10f, 0.45f, 0.90f, 0.95f }, hot[4] = { 0.35f, 0.95f, 1.00f, 1 };
    if (!a->doc.loaded || !a->doc.box_on) return;
    for (int k = 0; k < 7; k++) {
        double p[3], s[2];
        handle_pos(&a->doc.box, k, p);
        if (!st_camctl_project(&a->cc, a->fb_w, a->fb_h, p, s, NULL)) continue;
        float r = k == 6 ? 6.0f : 4.5f;
        const float *col = k == a->box_handle ? hot : c;
        if (k == 6) st_hud_circle(&a->hud, (float)s[0], (float)s[1], r, 2.5f, col);
        else st_hud_rect(&a->hud, (float)s[0] - r, (float)s[1] - r, (float)s[0] + r, (float)s[1] + r, col);
    }
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
    handle_pos(&a->box_start, k, p);
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
            drag_start(a, ST_OP_DRAG);
            if (a->op == ST_OP_DRAG) drag_update(a);
        } else {
            a->op = ST_OP_RECT;
        }
        break;
    }
    case ST_OP_DRAG:
    case ST_OP_GRAB:
        drag_update(a);
        break;
    case ST_OP_STROKE:
        stroke_move(a);
        break;
    case ST_OP_RECT:
        break;
    case ST_OP_BOX:
        box_drag_update(a);
        break;
    default: {
        int h = pick_handle(a, fx, fy);
        a->box_handle = h;
        if (h < 0) update_hover(a);
        else if (a->hover_vid != ST_NIL) { a->hover_vid = ST_NIL; st_renderer_set_hover(&a->r, ST_NIL); }
        break;
    }
    }
}

void st_win_on_mouse_button(GLFWwindow *w, int button, int action, int mods)
{
    st_app *a = app_of(w);
    if (!a->doc.loaded) return;
    if (action == GLFW_PRESS) {
        if (a->op == ST_OP_GRAB) {
            drag_finish(a, button != GLFW_MOUSE_BUTTON_LEFT);
            return;
        }
        if (a->op != ST_OP_NONE) {
            if (button == GLFW_MOUSE_BUTTON_RIGHT && a->op == ST_OP_DRAG) drag_finish(a, 1);
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
            if (a->tool == ST_TOOL_SELECT) {
                a->hover_vid = pick_vertex(a, a->mx, a->my);
                st_renderer_set_hover(&a->r, a->hover_vid);
                a->op = ST_OP_CLICK;
            } else {
                stroke_start(a, mods);
            }
        }
        return;
    }
    if (action != GLFW_RELEASE || button != a->op_button) return;
    switch (a->op) {
    case ST_OP_CLICK: a->op = ST_OP_NONE; select_click(a, a->hover_vid, a->op_mods); break;
    case ST_OP_RECT: a->op = ST_OP_NONE; select_rect(a); break;
    case ST_OP_DRAG: drag_finish(a, 0); break;
    case ST_OP_STROKE: stroke_finish(a); break;
    case ST_OP_BOX:
        st_doc_box_end(&a->doc);
        a->op = ST_OP_NONE;
        st_app_sync(a);
        st_app_message(a, 0, "box %s", a->box_handle == 6 ? "moved" : "resized");
        break;
    case ST_OP_ORBIT:
    case ST_OP_PAN: a->op = ST_OP_NONE; update_hover(a); break;
    default: break;
    }
}

void st_win_on_scroll(GLFWwindow *w, double dx, double dy)
{
    st_app *a = app_of(w);
    (void)dx;
    if (a->mods & GLFW_MOD_CONTROL) {
        a->doc.brush.radius *= pow(1.1, dy);
        return;
    }
    st_camctl_zoom(&a->cc, (float)dy);
    st_pick_invalidate(&a->pick);
    if (a->op == ST_OP_NONE) update_hover(a);
}

void st_win_on_drop(GLFWwindow *w, int count, const char **paths)
{
    st_app *a = app_of(w);
    if (count < 1) return;
    if (a->op == ST_OP_DRAG || a->op == ST_OP_GRAB) drag_finish(a, 1);
    if (a->op == ST_OP_STROKE) stroke_finish(a);
    a->op = ST_OP_NONE;
    st_app_open(a, paths[0]);
}

void st_win_on_resize(GLFWwindow *w, int width, int height)
{
    st_app *a = app_of(w);
    (void)width; (void)height;
    glfwGetFramebufferSize(w, &a->fb_w, &a->fb_h);
    glfwGetWindowSize(w, &a->win_w, &a->win_h);
    st_pick_invalidate(&a->pick);
}

/* ---- keys ------------------------------------------------------------------------ */

static const char *const scheme_cycle[] = { "catmull-clark", "loop", "butterfly", "quad-triangle", "sqrt3", "doo-sabin" };
#define NSCHEMES (sizeof scheme_cycle / sizeof scheme_cycle[0])

static const char *next_scheme(const char *cur)
{
    for (unsigned i = 0; i < NSCHEMES; i++)
        if (cur && !strcmp(cur, scheme_cycle[i])) return scheme_cycle[(i + 1) % NSCHEMES];
    return scheme_cycle[0];
}

static void report(st_app *a, int rc, const st_error *err, const char *what)
{
    if (rc) st_app_message(a, 1, "%s: %s", what, err->msg);
    st_app_sync(a);
}

static void add_level(st_app *a)
{
    st_doc *d = &a->doc;
    st_error err;
    size_t bytes = st_doc_add_level_bytes(d);
    double faces = a->r.surf.nfaces;
    for (unsigned l = shown_level(d); l <= d->h.map.top; l++) faces *= 4;
    char what[256];
    snprintf(what, sizeof what, "working... building level %u (about %.1fM faces, %.0f MB)", d->h.map.top + 1,
             faces / 1e6, bytes / 1048576.0);
    if (faces > WORKING_FACES) show_working(a, "%s", what);
    double t0 = now_ms();
    doc_job j = { .kind = JOB_ADD_LEVEL };
    int rc = run_job(a, &j, what);
    err = j.err;
    if (rc) { st_app_message(a, 1, "cannot add a level: %s", err.msg); return; }
    st_app_sync(a);
    uint64_t f = 0, v = 0;
    st_doc_display_counts(d, &f, &v);
    char t[32];
    st_app_message(a, 0, "level %u built (%llu faces) in %s", d->h.map.top, (unsigned long long)f,
                   fmt_ms(a, now_ms() - t0, t, sizeof t));
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
    double t0 = now_ms();
    int rc = st_doc_set_box(d, &b, 1, &err);
    report(a, rc, &err, "cannot move the box");
    if (!rc) {
        char t[32];
        st_app_message(a, 0, "box %s, adaptive mesh updated in %s", resize ? "resized" : "moved",
                       fmt_ms(a, now_ms() - t0, t, sizeof t));
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

static void toggle_box(st_app *a)
{
    st_doc *d = &a->doc;
    st_adapt_params b = d->box;
    if (!b.has_box || (b.box_lo[0] == b.box_hi[0] && b.box_lo[1] == b.box_hi[1])) {
        const float *bb = a->cc.bbox;
        for (int k = 0; k < 3; k++) {
            double c = 0.5 * (bb[k] + bb[k + 3]), h = 0.2 * (bb[k + 3] - bb[k]);
            b.box_lo[k] = c - h;
            b.box_hi[k] = c + h;
        }
        /* Start the box on the right half, so that it is not all inside. */
        double sx = 0.3 * (bb[3] - bb[0]);
        b.box_lo[0] += sx;
        b.box_hi[0] += sx;
        b.has_box = 1;
        if (b.max_level == 0) { b.base_level = 0; b.max_level = d->h.map.top + 1; }
    }
    st_error err;
    double t0 = now_ms();
    int rc = st_doc_set_box(d, &b, !d->box_on, &err);
    report(a, rc, &err, "cannot change the interest box");
    if (!rc) {
        char t[32];
        st_app_message(a, 0, "interest box %s (%s)", d->box_on ? "on" : "off", fmt_ms(a, now_ms() - t0, t, sizeof t));
    }
}

static void key_press(st_app *a, int key, int mods)
{
    st_doc *d = &a->doc;
    st_error err;
    int ctrl = (mods & GLFW_MOD_CONTROL) != 0, shift = (mods & GLFW_MOD_SHIFT) != 0, alt = (mods & GLFW_MOD_ALT) != 0;

    if (a->pending_scheme) {
        const char *s = a->pending_scheme;
        if (key == GLFW_KEY_K) { a->pending_scheme = next_scheme(s); return; }
        a->pending_scheme = NULL;
        if (key == GLFW_KEY_Y || key == GLFW_KEY_ENTER) {
            char what[128];
            snprintf(what, sizeof what, "working... rebuilding with %s", s);
            doc_job j = { .kind = JOB_SCHEME, .scheme = s };
            int rc = run_job(a, &j, what);
            err = j.err;
            report(a, rc, &err, "cannot change the scheme");
            if (!rc) st_app_message(a, 0, "scheme is now %s", s);
        } else {
            st_app_message(a, 0, "scheme unchanged");
        }
        return;
    }
    if (key == GLFW_KEY_F1) { a->help = !a->help; return; }
    if (key == GLFW_KEY_Q && ctrl) { a->quit = 1; return; }
    if (key == GLFW_KEY_ESCAPE) {
        if (a->help) a->help = 0;
        else if (a->op == ST_OP_DRAG || a->op == ST_OP_GRAB) drag_finish(a, 1);
        else if (a->op == ST_OP_RECT) a->op = ST_OP_NONE;
        else if (a->op == ST_OP_BOX) {
            st_doc_set_box(d, &a->box_start, 1, &err);
            st_doc_box_end(d);
            a->op = ST_OP_NONE;
            st_app_sync(a);
        }
        return;
    }
    if ((key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER) && a->op == ST_OP_GRAB) { drag_finish(a, 0); return; }
    if (a->op != ST_OP_NONE && a->op != ST_OP_ORBIT && a->op != ST_OP_PAN) return;  /* keys wait for the mouse */

    /* View. */
    switch (key) {
    case GLFW_KEY_HOME: frame_model(a); return;
    case GLFW_KEY_KP_1: case GLFW_KEY_1: st_camctl_view(&a->cc, ctrl ? ST_CV_BACK : ST_CV_FRONT, aspect(a)); st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_KP_3: case GLFW_KEY_3: st_camctl_view(&a->cc, ctrl ? ST_CV_LEFT : ST_CV_RIGHT, aspect(a)); st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_KP_7: case GLFW_KEY_7: st_camctl_view(&a->cc, ctrl ? ST_CV_BOTTOM : ST_CV_TOP, aspect(a)); st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_KP_5: case GLFW_KEY_5: st_camctl_toggle_ortho(&a->cc); st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_KP_4: st_camctl_orbit(&a->cc, 15 / 0.4f, 0); st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_KP_6: st_camctl_orbit(&a->cc, -15 / 0.4f, 0); st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_KP_8: st_camctl_orbit(&a->cc, 0, 15 / 0.4f); st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_KP_2: st_camctl_orbit(&a->cc, 0, -15 / 0.4f); st_pick_invalidate(&a->pick); return;
    default: break;
    }
    if (!d->loaded) return;

    /* Levels. */
    int up = key == GLFW_KEY_PAGE_UP || key == GLFW_KEY_KP_ADD || key == GLFW_KEY_EQUAL;
    int down = key == GLFW_KEY_PAGE_DOWN || key == GLFW_KEY_KP_SUBTRACT || key == GLFW_KEY_MINUS;
    if ((up || down) && !ctrl && !alt) {
        if (shift) {
            if (d->box_on) { st_app_message(a, 0, "the interest box decides the display: I hides it"); return; }
            unsigned l = d->display_level;
            if (down && l > d->edit_level) l--;
            if (up && l < d->h.map.top) l++;
            st_doc_set_display_level(d, l);
        } else {
            unsigned l = d->edit_level;
            if (down && l > 0) l--;
            if (up && l < d->h.map.top) l++;
            st_doc_set_edit_level(d, l);
        }
        st_app_sync(a);
        update_hover(a);
        return;
    }
    if (key == GLFW_KEY_D && ctrl) {
        if (shift) report(a, st_doc_remove_top(d, &err), &err, "cannot delete the finest level");
        else if (alt) report(a, st_doc_remove_bottom(d, &err), &err, "cannot delete the coarsest level");
        else add_level(a);
        return;
    }
    if (key == GLFW_KEY_Z && ctrl) {
        int rc = shift ? st_doc_redo(d, &err) : st_doc_undo(d, &err);
        if (rc == -1) st_app_message(a, 0, "nothing to %s", shift ? "redo" : "undo");
        else if (rc) st_app_message(a, 1, "%s failed: %s", shift ? "redo" : "undo", err.msg);
        else st_app_message(a, 0, "%s (%u/%u)", shift ? "redone" : "undone", d->undo_pos, d->nundo);
        st_app_sync(a);
        return;
    }
    if (key == GLFW_KEY_S && ctrl) { st_app_save(a); return; }
    if (key == GLFW_KEY_R && ctrl) { st_app_restore_recovery(a); return; }
    if (key == GLFW_KEY_Y && ctrl) {
        int rc = st_doc_redo(d, &err);
        if (rc == -1) st_app_message(a, 0, "nothing to redo");
        else if (rc) st_app_message(a, 1, "redo failed: %s", err.msg);
        st_app_sync(a);
        return;
    }
    if (ctrl) return;

    /* Tools and brush settings. */
    switch (key) {
    case GLFW_KEY_W: a->tool = ST_TOOL_SELECT; update_hover(a); return;
    case GLFW_KEY_B: a->tool = ST_BRUSH_GRAB; update_hover(a); return;
    case GLFW_KEY_D: a->tool = ST_BRUSH_DRAW; update_hover(a); return;
    case GLFW_KEY_S: a->tool = ST_BRUSH_SMOOTH; update_hover(a); return;
    case GLFW_KEY_F: a->tool = ST_BRUSH_FLATTEN; update_hover(a); return;
    case GLFW_KEY_X: d->brush.mirror_x = !d->brush.mirror_x; return;
    case GLFW_KEY_LEFT_BRACKET:
        if (shift) d->brush.strength = fmax(0.02, d->brush.strength - 0.05);
        else d->brush.radius /= 1.15;
        return;
    case GLFW_KEY_RIGHT_BRACKET:
        if (shift) d->brush.strength = fmin(1.0, d->brush.strength + 0.05);
        else d->brush.radius *= 1.15;
        return;
    case GLFW_KEY_G:
        if (!d->nsel) { st_app_message(a, 0, "nothing selected to grab"); return; }
        a->op_x0 = a->mx;
        a->op_y0 = a->my;
        a->op_mods = 0;
        drag_start(a, ST_OP_GRAB);
        return;
    case GLFW_KEY_A:
        select_all(a, alt);
        return;
    case GLFW_KEY_Z:
        if (shift) a->wire = !a->wire;
        else a->shading = a->shading == ST_SHADE_SMOOTH ? ST_SHADE_FLAT : ST_SHADE_SMOOTH;
        return;
    case GLFW_KEY_C: a->cage = !a->cage; st_pick_invalidate(&a->pick); return;
    case GLFW_KEY_K:
        a->pending_scheme = next_scheme(d->scheme ? d->scheme->name : NULL);
        return;
    case GLFW_KEY_I: toggle_box(a); return;
    case GLFW_KEY_LEFT: move_box(a, 0, -1, shift); return;
    case GLFW_KEY_RIGHT: move_box(a, 0, 1, shift); return;
    case GLFW_KEY_UP: move_box(a, alt ? 2 : 1, 1, shift); return;
    case GLFW_KEY_DOWN: move_box(a, alt ? 2 : 1, -1, shift); return;
    case GLFW_KEY_PERIOD: box_levels(a, shift, 1); return;
    case GLFW_KEY_COMMA: box_levels(a, shift, -1); return;
    default: break;
    }
}

void st_win_on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    st_app *a = app_of(w);
    (void)scancode;
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
        if ((a->op == ST_OP_DRAG || a->op == ST_OP_GRAB) && bit != GLFW_MOD_SHIFT) drag_update(a);
        return;
    }
    if (action == GLFW_RELEASE) return;
    key_press(a, key, mods);
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

static void glfw_key(GLFWwindow *w, int key, int sc, int action, int mods) { if (live_input(w)) st_win_on_key(w, key, sc, action, mods); }
static void glfw_button(GLFWwindow *w, int b, int action, int mods) { if (live_input(w)) st_win_on_mouse_button(w, b, action, mods); }
static void glfw_cursor(GLFWwindow *w, double x, double y) { if (live_input(w)) st_win_on_cursor(w, x, y); }
static void glfw_scroll(GLFWwindow *w, double dx, double dy) { if (live_input(w)) st_win_on_scroll(w, dx, dy); }
static void glfw_drop(GLFWwindow *w, int n, const char **p) { if (live_input(w)) st_win_on_drop(w, n, p); }

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

static int make_window(st_app *a, int visible)
{
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
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

static void default_asset(st_app *a)
{
    const char *dir = getenv("STRATA_ASSETS");
    snprintf(a->default_path, sizeof a->default_path, "%s/%s", dir && dir[0] ? dir : STRATA_ASSETS, DEFAULT_ASSET);
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
    a->masked_times = o->replay != NULL;
    st_doc_init(&a->doc);
    if (o->mem_budget_mb > 0) a->doc.mem_budget = (size_t)(o->mem_budget_mb * 1048576.0);
    default_asset(a);

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
    glfwSetKeyCallback(a->win, glfw_key);
    glfwSetMouseButtonCallback(a->win, glfw_button);
    glfwSetCursorPosCallback(a->win, glfw_cursor);
    glfwSetScrollCallback(a->win, glfw_scroll);
    glfwSetDropCallback(a->win, glfw_drop);
    glfwSetFramebufferSizeCallback(a->win, st_win_on_resize);
    glfwSwapInterval(rp ? 0 : 1);
    float bb[6] = { -1, -1, -1, 1, 1, 1 };
    st_camctl_init(&a->cc, bb, aspect(a));

    const char *path = o->file ? o->file : a->default_path;
    if (st_app_open(a, path) && o->file && !rp) {
        /* The file given on the command line failed: say so, fall back to
         * the default asset so that the window still opens. */
        char keep[ST_MSG_LEN];
        memcpy(keep, a->msg, sizeof keep);
        st_app_open(a, a->default_path);
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
            if (a->op == ST_OP_NONE) glfwWaitEventsTimeout(0.25);
            else glfwPollEvents();
        }
        glfwGetFramebufferSize(a->win, &a->fb_w, &a->fb_h);
        glfwGetWindowSize(a->win, &a->win_w, &a->win_h);
        st_app_sync(a);
        double t0 = now_ms();   /* frame time: drawing and presenting, not the wait for events */
        st_app_draw(a);
        if (a->shot_pending) {
            a->shot_pending = 0;
            if (take_screenshot(a, a->shot)) { a->exit_code = 1; break; }
        }
        glfwSwapBuffers(a->win);
        a->frame_ms = now_ms() - t0;
        if (autosave) st_app_autosave_tick(a, 0);
        a->frames++;
    }
    if (autosave && !a->exit_code) st_app_autosave_tick(a, 1);
    rc = a->exit_code;
    if (rp && !rc) fprintf(stderr, "strata: replay %s passed (%llu frames)\n", o->replay, (unsigned long long)a->frames);
    st_replay_free(rp);
    st_hud_free(&a->hud);
    st_pick_free(&a->pick);
    st_renderer_free(&a->r);
    glfwDestroyWindow(a->win);
    glfwTerminate();
    st_doc_free(&a->doc);
    free(a);
    return rc;
}
