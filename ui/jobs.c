/* Long document operations on a worker thread: opening a file, adding a
 * level, changing the scheme and rebuilding the levels (which Esc or the
 * progress window's Cancel button cancels).  The main thread keeps drawing a
 * "working..." panel (hud_panels.c) with the stage the editor's progress
 * callback reports and the elapsed time; see README.md "Modeller". */
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

#include "core/io/session.h"
#include "gui.h"

#define DEFAULT_LEVELS 2
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

enum { JOB_OPEN, JOB_ADD_LEVEL, JOB_SCHEME, JOB_REBUILD };

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
    /* JOB_REBUILD: set by the main thread (Esc), read by the rebuild's
     * progress callback; msg: which method made how many levels, and the
     * notes on tags and UVs (room left in the status line for the time). */
    atomic_int cancel;
    char msg[ST_MSG_LEN - 64];
    /* STRATA_JOB_HOLD_S (tests): until when its progress reports wait. */
    double hold_until_ms;
} doc_job;

/* With STRATA_JOB_HOLD_S=N, a cancellable job's progress reports wait for
 * a cancellation, N seconds at most in all: tests of the Cancel button
 * (tests/cli_gui_xdotool.sh) then do not race a fast machine; a Cancel
 * that does not work lets the job finish after N s and the test fails. */
static int job_cancelled(void *ctx, double fraction)
{
    doc_job *j = ctx;
    (void)fraction;
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

static void *job_main(void *p)
{
    doc_job *j = p;
    switch (j->kind) {
    case JOB_OPEN: j->rc = st_doc_open(j->d, j->path, j->scheme, j->levels, &j->err); break;
    case JOB_ADD_LEVEL: j->rc = st_doc_add_level(j->d, &j->err); break;
    case JOB_REBUILD: j->rc = st_doc_rebuild_levels(j->d, job_cancelled, j, j->msg, sizeof j->msg, &j->err); break;
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
/* A cancellable job's key callback while it runs: Esc cancels, every other
 * input waits (the worker owns the document). */
static doc_job *g_cancellable;
static void cancel_key(GLFWwindow *w, int key, int sc, int action, int mods)
{
    (void)w; (void)sc; (void)mods;
    if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS && g_cancellable) atomic_store(&g_cancellable->cancel, 1);
}

int st_app_job_cancellable(void) { return g_cancellable != NULL; }
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
    double t0 = st_now_ms(), next = t0 + 150;
    int shown = a->working[0] != 0;   /* show_working() already said it */
    /* A cancellable job runs from the main loop (st_app_run_requested), not
     * from a GLFW callback, so events can be polled: only Esc is listened
     * to, the window's other handlers are off until the job ends (replays
     * deliver their own events, none during a job, unless real input is let
     * through: STRATA_REPLAY_LIVE=1, window.c). */
    const char *live = getenv("STRATA_REPLAY_LIVE");
    int poll = j->kind == JOB_REBUILD && (!a->replay || (live && live[0] == '1'));
    GLFWkeyfun keyfun = NULL;
    GLFWmousebuttonfun buttonfun = NULL;
    GLFWcursorposfun cursorfun = NULL;
    GLFWscrollfun scrollfun = NULL;
    GLFWdropfun dropfun = NULL;
    GLFWcharfun charfun = NULL;
    if (poll) {
        g_cancellable = j;
        keyfun = glfwSetKeyCallback(a->win, cancel_key);
        buttonfun = glfwSetMouseButtonCallback(a->win, job_button);
        cursorfun = glfwSetCursorPosCallback(a->win, job_cursor);
        scrollfun = glfwSetScrollCallback(a->win, NULL);
        dropfun = glfwSetDropCallback(a->win, NULL);
        charfun = glfwSetCharCallback(a->win, NULL);
    }
    while (!atomic_load(&j->done)) {
        if (poll) glfwPollEvents();
        double t = st_now_ms();
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
    if (poll) {
        g_cancellable = NULL;
        glfwSetKeyCallback(a->win, keyfun);
        glfwSetMouseButtonCallback(a->win, buttonfun);
        glfwSetCursorPosCallback(a->win, cursorfun);
        glfwSetScrollCallback(a->win, scrollfun);
        glfwSetDropCallback(a->win, dropfun);
        glfwSetCharCallback(a->win, charfun);
    }
    a->doc.progress = NULL;
    a->doc.progress_ctx = NULL;
    pthread_mutex_destroy(&j->mu);
    a->busy = 0;
    a->working[0] = 0;
    return j->rc;
}

/* ---- opening, a level more, another scheme ------------------------------------- */

int st_app_open(st_app *a, const char *path)
{
    st_error err;
    if (st_session_is_path(path)) return st_app_restore(a, path);
    unsigned levels = a->opts.levels >= 0 ? (unsigned)a->opts.levels : DEFAULT_LEVELS;
    const char *scheme = a->opts.scheme ? a->opts.scheme : (a->doc.loaded && a->doc.scheme ? a->doc.scheme->name : "catmull-clark");
    double t0 = st_now_ms();
    char what[300];
    snprintf(what, sizeof what, "working... opening %s", st_path_base(path));
    doc_job j = { .kind = JOB_OPEN, .path = path, .scheme = scheme, .levels = levels };
    int rc = run_job(a, &j, what);
    err = j.err;
    if (rc) {
        st_app_message(a, 1, "cannot open %s: %s%s", st_path_base(path), err.msg,
                       a->doc.loaded ? " (the current model is kept)" : "");
        return rc;
    }
    a->shown_valid = 0;
    a->hover_vid = ST_NIL;
    a->op = ST_OP_NONE;
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
    char t[32];
    st_app_message(a, 0, "opened %s (%s, %u levels) in %s", st_path_base(path), a->doc.scheme->name, a->doc.h.map.top,
                   st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t));
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
    snprintf(what, sizeof what, "working... building level %u (about %.1fM faces, %.0f MB)", d->h.map.top + 1,
             faces / 1e6, bytes / 1048576.0);
    if (faces > WORKING_FACES) show_working(a, "%s", what);
    double t0 = st_now_ms();
    doc_job j = { .kind = JOB_ADD_LEVEL };
    int rc = run_job(a, &j, what);
    err = j.err;
    if (rc) { st_app_message(a, 1, "cannot add a level: %s", err.msg); return; }
    st_app_sync(a);
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
    snprintf(what, sizeof what, "working... rebuilding with %s", s);
    doc_job j = { .kind = JOB_SCHEME, .scheme = s };
    int rc = run_job(a, &j, what);
    err = j.err;
    if (rc) st_app_message(a, 1, "cannot change the scheme: %s", err.msg);
    st_app_sync(a);
    if (!rc) st_app_message(a, 0, "scheme is now %s", s);
}

/* ---- rebuilding the levels ------------------------------------------------------- */

/* The action only asks (it may run inside a GLFW key callback, where
 * events cannot be polled for Esc); the main loop runs it next
 * (st_app_run_requested, from st_gui_run_pending). */
static int g_rebuild_requested;

void st_app_request_rebuild(st_app *a)
{
    (void)a;
    g_rebuild_requested = 1;
}

static void rebuild_levels(st_app *a)
{
    double t0 = st_now_ms();
    doc_job j = { .kind = JOB_REBUILD };
    atomic_init(&j.cancel, 0);
    const char *hold = getenv("STRATA_JOB_HOLD_S");
    if (hold && atof(hold) > 0) j.hold_until_ms = st_now_ms() + 1000 * atof(hold);
    int rc = run_job(a, &j, "working... rebuilding the levels (Esc cancels)");
    st_app_sync(a);
    if (rc && atomic_load(&j.cancel)) {
        st_app_message(a, 0, "rebuild cancelled: the model is unchanged");
        return;
    }
    if (rc) { st_app_message(a, 1, "cannot rebuild the levels: %s", j.err.msg); return; }
    char t[32];
    st_app_message(a, 0, "%s, in %s", j.msg, st_app_fmt_ms(a, st_now_ms() - t0, t, sizeof t));
}

void st_app_run_requested(st_app *a)
{
    if (!g_rebuild_requested) return;
    g_rebuild_requested = 0;
    if (a->doc.loaded) rebuild_levels(a);
}
