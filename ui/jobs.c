/* Long document operations on a worker thread: opening a file, adding a
 * level, changing the scheme and rebuilding the levels (which Esc or the
 * progress window's Cancel button cancels).  The main thread keeps drawing a
 * "working..." panel (hud_panels.c) with the stage the editor's progress
 * callback reports and the elapsed time; see docs/MODELLER.md. */
#include "window.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "formats/bake_run.h"
#include "core/io/session.h"
#include "gui.h"

#define WORKING_FACES 150000         /* show a "working" frame above this */

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

enum { JOB_NONE, JOB_OPEN, JOB_ADD_LEVEL, JOB_SCHEME, JOB_REBUILD, JOB_SAVE, JOB_LOAD_SESSION, JOB_RECOVERY, JOB_BAKE };

typedef struct doc_job {
    st_doc *d;
    int kind;
    const char *path, *scheme;
    unsigned levels;
    const st_session_view *view;   /* JOB_SAVE */
    const st_session_tool *tool;   /* JOB_SAVE */
    st_session *session;           /* JOB_LOAD_SESSION: loaded here, the document untouched */
    st_bake_request *bake;         /* JOB_BAKE: st_bake_run on bake_src (progress and say filled here) */
    st_hier *bake_src;             /* JOB_BAKE: the model, or its HD levels (st_doc_hd_bake_source) */
    st_bake_result bake_res;
    st_error err;
    int rc;
    atomic_int done;
    /* The editor's progress callback (on the worker): the current stage. */
    pthread_mutex_t mu;
    char stage[160];
    unsigned step, steps;
    /* Set by the main thread (Esc, Cancel), read by the editor's fraction
     * callback (job_cancelled); fraction: the last one reported, -1 none
     * yet (under mu).  msg (JOB_REBUILD): which method made how many
     * levels, and the notes on tags and UVs (room left in the status line
     * for the time). */
    atomic_int cancel;
    double fraction;
    char msg[ST_MSG_LEN - 64];
    /* STRATA_JOB_HOLD_S (tests): until when its progress reports wait. */
    double hold_until_ms;
} doc_job;

/* Test only: with STRATA_JOB_HOLD_S=N, a job's progress reports wait for a
 * cancellation, N seconds at most in all (the opening at start excepted:
 * jobs once the main loop runs, g_loop_started): tests of the Cancel
 * button (tests/cli/cli_gui_xdotool.sh) then do not race a fast machine; a
 * Cancel that does not work lets the job finish after N s and the test
 * fails. */
static int g_loop_started;
static int job_cancelled(void *ctx, double fraction)
{
    doc_job *j = ctx;
    pthread_mutex_lock(&j->mu);
    j->fraction = fraction;
    pthread_mutex_unlock(&j->mu);
    while (!atomic_load(&j->cancel) && st_now_ms() < j->hold_until_ms) {
        struct timespec ts = { 0, 5000000 };
        nanosleep(&ts, NULL);
    }
    return atomic_load(&j->cancel);
}

static void job_progress(void *ctx, const char *what, unsigned step, unsigned steps)
{
    doc_job *j = ctx;
    pthread_mutex_lock(&j->mu);
    snprintf(j->stage, sizeof j->stage, "%s", what ? what : "");
    j->step = step;
    j->steps = steps;
    pthread_mutex_unlock(&j->mu);
}

/* The bake's notes (wrap-around, tiles): the first one kept for the
 * status line, every line on stderr as strata bake prints them. */
static void bake_say(void *ctx, const char *line)
{
    doc_job *j = ctx;
    fprintf(stderr, "strata: bake: %s\n", line);
    if (!strncmp(line, "note: ", 6) && !j->msg[0]) snprintf(j->msg, sizeof j->msg, "%s", line + 6);
}

static void *job_main(void *p)
{
    doc_job *j = p;
    switch (j->kind) {
    case JOB_OPEN: j->rc = st_doc_open_progress(j->d, j->path, j->scheme, j->levels, job_cancelled, j, &j->err); break;
    case JOB_ADD_LEVEL: j->rc = st_doc_add_level_progress(j->d, job_cancelled, j, &j->err); break;
    case JOB_REBUILD: j->rc = st_doc_rebuild_levels(j->d, job_cancelled, j, j->msg, sizeof j->msg, &j->err); break;
    case JOB_SAVE: j->rc = st_doc_save_session(j->d, j->path, j->view, j->tool, job_cancelled, j, &j->err); break;
    case JOB_LOAD_SESSION:
        /* Reading a session has no progress of its own: a cancel before it,
         * or during it (the loaded session is then dropped). */
        if (job_cancelled(j, 0)) { j->rc = st_fail(&j->err, ST_ERR_INVALID, "cancelled"); break; }
        j->rc = st_session_load(j->path, j->session, &j->err);
        if (!j->rc && job_cancelled(j, 1)) {
            st_session_free(j->session);
            j->rc = st_fail(&j->err, ST_ERR_INVALID, "cancelled");
        }
        break;
    case JOB_BAKE:
        job_progress(j, "baking", 0, 0);
        j->bake->progress = job_cancelled;
        j->bake->progress_ctx = j;
        j->bake->say = bake_say;
        j->bake->say_ctx = j;
        j->rc = st_bake_run(j->bake_src ? j->bake_src : &j->d->h, j->bake, &j->bake_res, &j->err);
        break;
    default: j->rc = st_doc_set_scheme_progress(j->d, j->scheme, job_cancelled, j, &j->err); break;
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
/* A cancellable job's key callback while it runs: Esc cancels, every other
 * input waits (the worker owns the document). */
static doc_job *g_cancellable;
static void cancel_key(GLFWwindow *w, int key, int sc, int action, int mods)
{
    (void)w; (void)sc; (void)mods;
    if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS && g_cancellable) atomic_store(&g_cancellable->cancel, 1);
}

int st_app_job_cancellable(void) { return g_cancellable != NULL; }
double st_app_job_fraction(void)
{
    if (!g_cancellable) return -1;
    pthread_mutex_lock(&g_cancellable->mu);
    double f = g_cancellable->fraction;
    pthread_mutex_unlock(&g_cancellable->mu);
    return f;
}
int st_app_job_cancelling(void) { return g_cancellable && atomic_load(&g_cancellable->cancel); }
void st_app_cancel_job(void)
{
    if (g_cancellable) atomic_store(&g_cancellable->cancel, 1);
}

/* The pointer and buttons during such a job go to the GUI alone, for the
 * progress window's Cancel (gui.h); the 3D view waits. */
static void job_cursor(GLFWwindow *w, double x, double y)
{
    (void)w;
    st_gui_cursor(x, y);
}

static void job_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)w;
    (void)mods;
    st_gui_job_mouse_button(button, action);
}

/* Whether the job was cancelled (it failed after a cancellation was
 * asked: the editor's "cancelled", the document as it was). */
static int job_was_cancelled(doc_job *j) { return j->rc && atomic_load(&j->cancel); }

static int run_job(st_app *a, doc_job *j, const char *what)
{
    j->d = &a->doc;
    atomic_init(&j->done, 0);
    atomic_init(&j->cancel, 0);
    pthread_mutex_init(&j->mu, NULL);
    j->stage[0] = 0;
    j->step = j->steps = 0;
    j->fraction = -1;
    const char *hold = getenv("STRATA_JOB_HOLD_S");
    if (hold && atof(hold) > 0 && g_loop_started) j->hold_until_ms = st_now_ms() + 1000 * atof(hold);
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
    double t0 = st_now_ms(), next = t0 + 150;
    int shown = a->working[0] != 0;   /* show_working() already said it */
    /* Jobs run from the main loop (st_app_run_requested, the GUI's pending
     * actions), never from a GLFW callback, so events can be polled: only
     * Esc and the progress window's Cancel are listened to, the window's
     * other handlers are off until the job ends (replays deliver their own
     * events, none during a job, unless real input is let through:
     * STRATA_REPLAY_LIVE=1, window.c).  The opening of the file given at
     * start, before the main loop, is not cancelled: there is no model to
     * go back to. */
    const char *live = getenv("STRATA_REPLAY_LIVE");
    int poll = g_loop_started && (!a->replay || (live && live[0] == '1'));
    st_win_input outside = { 0 };
    if (poll) {
        g_cancellable = j;
        outside = st_win_swap_input(a->win, (st_win_input){ cancel_key, job_button, job_cursor, NULL, NULL, NULL });
    }
    while (!atomic_load(&j->done)) {
        if (poll) glfwPollEvents();
        if (poll && glfwWindowShouldClose(a->win)) atomic_store(&j->cancel, 1);   /* closing the window cancels */
        double t = st_now_ms();
        if (t >= next) {
            char el[32];
            if (a->masked_times) snprintf(el, sizeof el, "--");
            else snprintf(el, sizeof el, "%.1f s", (t - t0) / 1000);
            char stage[200] = "";
            pthread_mutex_lock(&j->mu);
            if (j->fraction >= 0 && j->stage[0]) snprintf(stage, sizeof stage, "%s, %.0f %%, ", j->stage, 100 * j->fraction);
            else if (j->stage[0] && j->steps > 1) snprintf(stage, sizeof stage, "%s, step %u of %u, ", j->stage, j->step, j->steps);
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
    if (poll) {
        g_cancellable = NULL;
        st_win_swap_input(a->win, outside);
    }
    a->doc.progress = NULL;
    a->doc.progress_ctx = NULL;
    pthread_mutex_destroy(&j->mu);
    a->busy = 0;
    a->working[0] = 0;
    return j->rc;
}

/* ---- opening, a level more, another scheme, saving ------------------------------ */

int st_app_open(st_app *a, const char *path)
{
    st_error err;
    if (st_session_is_path(path)) return st_app_restore(a, path);
    unsigned levels = a->opts.levels >= 0 ? (unsigned)a->opts.levels : ST_DOC_LEVELS_AUTO;
    const char *scheme = a->opts.scheme ? a->opts.scheme : (a->doc.loaded && a->doc.scheme ? a->doc.scheme->name : "catmull-clark");
    double t0 = st_now_ms();
    char what[300];
    snprintf(what, sizeof what, "working... opening %s%s", st_path_base(path), g_loop_started ? " (Esc cancels)" : "");
    doc_job j = { .kind = JOB_OPEN, .path = path, .scheme = scheme, .levels = levels };
    int rc = run_job(a, &j, what);
    err = j.err;
    if (job_was_cancelled(&j)) {
        st_app_message(a, 0, "opening %s cancelled%s", st_path_base(path),
                       a->doc.loaded ? ": the current model is kept" : "");
        return ST_APP_CANCELLED;
    }
    if (rc) {
        st_app_message(a, 1, "cannot open %s: %s%s", st_path_base(path), err.msg,
                       a->doc.loaded ? " (the current model is kept)" : "");
        return rc;
    }
    a->shown.valid = 0;
    a->hover_vid = ST_NIL;
    a->op = ST_OP_NONE;
    a->untitled = 0;
    st_app_bake_forget(a);      /* the last bake was of another model */
    a->showing_default = 0;
    a->box_placed = 0;
    st_app_sync(a);
    a->autosave_dirty = 0;   /* opening is not an edit */
    st_app_frame_model(a);
    /* Brush radius in model units: a fraction of the half-diagonal (an
     * eighth, or the preference), so that models of any scale get a
     * usable brush. */
    a->doc.brush.radius = a->brush_radius_frac * a->cc.radius;
    char title[512];
    snprintf(title, sizeof title, "Strata - %s", st_path_base(path));
    glfwSetWindowTitle(a->win, title);
    char t[32], lv[48];
    st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t);
    st_levels_phrase(a->doc.h.map.top, lv, sizeof lv);
    a->saved_revision = a->recovery_revision = a->doc.revision;
    uint32_t nf = a->doc.base.nfaces;
    if (levels == ST_DOC_LEVELS_AUTO && a->doc.h.map.top == 0 && nf > ST_DOC_DENSE_FACES)
        st_app_message(a, 0, "opened %s as it is (%u faces, %s) in %s: a dense mesh gets no level added; "
                       "Mesh > Rebuild levels makes coarse levels to sculpt", st_path_base(path), nf, lv, t);
    else
        st_app_message(a, 0, "opened %s (%s, %s) in %s", st_path_base(path), a->doc.scheme->name, lv, t);
    return 0;
}

/* File > Import... (docs/MODELLER.md): Open... opens a document, a
 * .strata session or a mesh file, which then names it (Save writes
 * STEM.strata, Open Recent keeps it); Import... reads a mesh format only,
 * as a new untitled document, as Blender's File > Import: the file is a
 * source, not the document, so it is not in Open Recent and Save asks
 * where to write the session. */
int st_app_import(st_app *a, const char *path)
{
    if (st_session_is_path(path)) {
        st_app_message(a, 1, "cannot import %s: a .strata session opens with File > Open...", st_path_base(path));
        return -1;
    }
    int rc = st_app_open(a, path);
    if (rc) return rc;
    a->untitled = 1;
    char title[512];
    snprintf(title, sizeof title, "Strata - untitled (imported %s)", st_path_base(path));
    glfwSetWindowTitle(a->win, title);
    char lv[48];
    st_levels_phrase(a->doc.h.map.top, lv, sizeof lv);
    st_app_message(a, 0, "imported %s as a new document (%s, %s): Save asks for a name", st_path_base(path),
                   a->doc.scheme->name, lv);
    return 0;
}

void st_app_add_level(st_app *a)
{
    st_doc *d = &a->doc;
    st_error err;
    size_t bytes = st_doc_add_level_bytes(d);
    double faces = a->r.surf.nfaces;
    for (unsigned l = st_doc_display_map_level(d); l <= d->h.map.top; l++) faces *= 4;
    char what[256];
    snprintf(what, sizeof what, "working... building level %u (about %.1fM faces, %.0f MB; Esc cancels)",
             d->h.map.top + 1, faces / 1e6, bytes / 1048576.0);
    if (faces > WORKING_FACES) show_working(a, "%s", what);
    double t0 = st_now_ms();
    doc_job j = { .kind = JOB_ADD_LEVEL };
    int rc = run_job(a, &j, what);
    err = j.err;
    st_app_sync(a);
    if (job_was_cancelled(&j)) { st_app_message(a, 0, "adding a level cancelled: the model is unchanged"); return; }
    if (rc) { st_app_message(a, 1, "cannot add a level: %s", err.msg); return; }
    uint64_t f = 0, v = 0;
    st_doc_display_counts(d, &f, &v);
    char t[32];
    st_app_message(a, 0, "level %u built (%llu faces) in %s", d->h.map.top, (unsigned long long)f,
                   st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t));
}

void st_app_change_scheme(st_app *a, const char *s)
{
    st_error err;
    char what[128];
    snprintf(what, sizeof what, "working... rebuilding with %s (Esc cancels)", s);
    doc_job j = { .kind = JOB_SCHEME, .scheme = s };
    int rc = run_job(a, &j, what);
    err = j.err;
    st_app_sync(a);
    if (job_was_cancelled(&j)) { st_app_message(a, 0, "scheme change cancelled: the model is unchanged"); return; }
    if (rc) st_app_message(a, 1, "cannot change the scheme: %s", err.msg);
    else st_app_message(a, 0, "scheme is now %s", s);
}

int st_app_job_load_session(st_app *a, const char *path, st_session *s, st_error *err)
{
    char what[300];
    snprintf(what, sizeof what, "working... opening %s%s", st_path_base(path), g_loop_started ? " (Esc cancels)" : "");
    doc_job j = { .kind = JOB_LOAD_SESSION, .path = path, .session = s };
    int rc = run_job(a, &j, what);
    if (err) *err = j.err;
    return job_was_cancelled(&j) ? ST_APP_CANCELLED : rc;
}

int st_app_job_save(st_app *a, const char *path, const st_session_view *view, const st_session_tool *tool, st_error *err)
{
    char what[300];
    snprintf(what, sizeof what, "working... saving %s (Esc cancels)", st_path_base(path));
    doc_job j = { .kind = JOB_SAVE, .path = path, .view = view, .tool = tool };
    int rc = run_job(a, &j, what);
    if (err) *err = j.err;
    return job_was_cancelled(&j) ? ST_APP_CANCELLED : rc;
}

/* ---- requests: jobs the main loop runs ------------------------------------------
 * An action may run inside a GLFW key or drop callback, where events cannot
 * be polled for Esc and the Cancel button: it only asks, and the main loop
 * runs the job next (st_app_run_requested, from st_gui_run_pending) on the
 * worker thread.  Replays see the result at their next event. */
static struct {
    int kind;                  /* JOB_NONE: nothing asked */
    const char *scheme;        /* JOB_SCHEME: a scheme's static name */
    char path[4096];           /* JOB_OPEN */
} g_request;

void st_app_request_rebuild(st_app *a) { (void)a; g_request.kind = JOB_REBUILD; }
void st_app_request_bake(st_app *a) { (void)a; g_request.kind = JOB_BAKE; }
void st_app_request_add_level(st_app *a) { (void)a; g_request.kind = JOB_ADD_LEVEL; }
void st_app_request_save(st_app *a) { (void)a; g_request.kind = JOB_SAVE; }
void st_app_request_recovery(st_app *a) { (void)a; g_request.kind = JOB_RECOVERY; }
void st_app_request_scheme(st_app *a, const char *scheme)
{
    (void)a;
    g_request.kind = JOB_SCHEME;
    g_request.scheme = scheme;
}
void st_app_request_open(st_app *a, const char *path)
{
    if (strlen(path) >= sizeof g_request.path) { st_app_message(a, 1, "cannot open %.200s...: path too long", path); return; }
    g_request.kind = JOB_OPEN;
    memcpy(g_request.path, path, strlen(path) + 1);
}

static void rebuild_levels(st_app *a)
{
    double t0 = st_now_ms();
    doc_job j = { .kind = JOB_REBUILD };
    int rc = run_job(a, &j, "working... rebuilding the levels (Esc cancels)");
    st_app_sync(a);
    if (job_was_cancelled(&j)) {
        st_app_message(a, 0, "rebuild cancelled: the model is unchanged");
        return;
    }
    if (rc) { st_app_message(a, 1, "cannot rebuild the levels: %s", j.err.msg); return; }
    char t[32];
    st_app_message(a, 0, "%s, in %s", j.msg, st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t));
}

/* The Bake dialog's settings as strata bake's request; the maps written
 * atomically (formats/bake_run.h), the old ones kept on a refusal or a
 * cancellation. */
int st_app_bake_maps(st_app *a)
{
    st_app_bake *b = &a->bake;
    if (!a->doc.loaded) { st_app_message(a, 1, "nothing to bake"); return -1; }
    st_app_bake_defaults(a);
    st_bake_request r = { .normal_path = b->want_normal ? b->normal : NULL, .disp_path = b->want_disp ? b->disp : NULL,
                          .base = (unsigned)b->base, .level = (unsigned)b->level, .size = (uint32_t)b->size,
                          .padding = (uint32_t)b->padding, .bits = b->bits16 ? 16 : 8, .space = b->space,
                          .vector = b->want_disp && b->vector, .auto_uv = b->auto_uv, .udim = b->udim };
    st_error err;
    if (st_bake_request_check(&r, &err)) { st_app_message(a, 1, "cannot bake: %s", err.msg); return -1; }
    double t0 = st_now_ms();
    char what[300];
    snprintf(what, sizeof what, "working... baking level %d onto level %d, %dx%d (Esc cancels)", b->level, b->base, b->size, b->size);
    /* With HD detail, the top level bakes from the HD levels: each texel
     * from the finest face there (as strata bake on such a session). */
    doc_job j = { .kind = JOB_BAKE, .bake = &r, .bake_src = st_doc_hd_bake_source(&a->doc, &r.level) };
    int rc = run_job(a, &j, what);
    if (job_was_cancelled(&j) || (rc && j.bake_res.cancelled)) {
        st_app_message(a, 0, "bake cancelled: the maps on disk are as they were");
        return ST_APP_CANCELLED;
    }
    if (rc) { st_app_message(a, 1, "cannot bake: %s", j.err.msg); return rc; }
    const st_bake_result *res = &j.bake_res;
    if (r.normal_path) {
        /* What the view and the export read: the map, or its UDIM set. */
        b->have = 1;
        b->have_base = r.base;
        b->have_auto_uv = r.auto_uv;
        b->have_size = r.size;
        b->have_padding = r.padding;
        b->have_space = r.space;
        const char *tok = strstr(r.normal_path, "<UDIM>"), *dot = strrchr(r.normal_path, '.');
        if (res->udim && !tok) snprintf(b->have_map, sizeof b->have_map, "%.*s.<UDIM>%s", (int)(dot - r.normal_path), r.normal_path, dot);
        else if (!res->udim && tok) {
            char *one = st_bake_tile_path(r.normal_path, 0);
            snprintf(b->have_map, sizeof b->have_map, "%s", one ? one : r.normal_path);
            free(one);
        } else snprintf(b->have_map, sizeof b->have_map, "%s", r.normal_path);
        b->serial++;
    }
    char t[32], maps[64] = "";
    if (res->udim) snprintf(maps, sizeof maps, ", %u UDIM tiles", res->maps);
    const char *name = st_path_base(r.normal_path ? b->have_map : r.disp_path);
    st_app_message(a, 0, "baked level %u onto level %u: %s%s%s (%llu texels%s) in %s%s%s", r.level, r.base, name,
                   r.normal_path && r.disp_path ? " and the displacement" : "", maps, (unsigned long long)res->baked,
                   res->by_rays ? ", by rays" : "", st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t),
                   j.msg[0] ? "; " : "", j.msg);
    return 0;
}

void st_app_run_requested(st_app *a)
{
    g_loop_started = 1;
    int kind = g_request.kind;
    g_request.kind = JOB_NONE;
    if (kind == JOB_OPEN) { st_app_open(a, g_request.path); return; }
    if (kind == JOB_RECOVERY) { st_app_restore_recovery(a); return; }
    if (!a->doc.loaded) return;
    switch (kind) {
    case JOB_REBUILD: rebuild_levels(a); break;
    case JOB_BAKE: st_app_bake_maps(a); break;
    case JOB_ADD_LEVEL: st_app_add_level(a); break;
    case JOB_SCHEME: st_app_change_scheme(a, g_request.scheme); break;
    case JOB_SAVE:
        /* The quit question's Save quits once saved; a failed save stays. */
        if (!st_app_save(a) && a->quit_after_save) a->quit = 1;
        else if (!a->untitled) a->quit_after_save = 0;
        break;
    default: break;
    }
}
