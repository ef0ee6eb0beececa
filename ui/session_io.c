/* Sessions in the window: Ctrl+S saves the model as a .strata session
 * (core/io/session.h), edits are autosaved to the recovery file, a recovery
 * file found at start is offered (Ctrl+R restores it), and .strata files
 * open like meshes (command line or drop). */
#include "window.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/io/session.h"
#include "gui.h"

#define AUTOSAVE_SECONDS 10.0
#define DEG_PER_RAD 57.29577951308232

static void view_of(const st_app *a, st_session_view *v)
{
    const st_camera *c = &a->cc.cam;
    memset(v, 0, sizeof *v);
    memcpy(v->target, c->target, sizeof v->target);
    v->az = (float)(c->az / DEG_PER_RAD);
    v->el = (float)(c->el / DEG_PER_RAD);
    v->dist = c->dist;
    v->fovy = (float)(c->fovy / DEG_PER_RAD);
    v->ortho = c->ortho;
    v->ortho_height = c->ortho_height;
}

/* The window's settings that a session keeps (core/io/session.h). */
static void tool_of(const st_app *a, st_session_tool *t)
{
    const st_brush *b = &a->doc.brush;
    memset(t, 0, sizeof *t);
    t->tool = a->tool == ST_TOOL_SELECT ? ST_SESSION_NO_TOOL : (uint32_t)a->tool;
    t->radius = b->radius > 0 && isfinite(b->radius) ? b->radius : 1;
    t->strength = b->strength < 0 ? 0 : b->strength > 1 ? 1 : b->strength;
    t->falloff = (uint32_t)b->falloff;
    t->mirror = (b->mirror_x ? 1u : 0) | (b->mirror_y ? 2u : 0) | (b->mirror_z ? 4u : 0);
    t->show = (a->cage ? ST_SESSION_SHOW_CAGE : 0) | (a->wire ? ST_SESSION_SHOW_WIRE : 0) |
              (a->shading == ST_SHADE_FLAT ? ST_SESSION_SHOW_FLAT : 0) | (a->checker ? ST_SESSION_SHOW_CHECKER : 0);
}

/* Back from a session: the tool made current as its button does
 * (st_brush_set_tool, so the per-tool settings follow), then the values
 * saved. */
static void tool_apply(st_app *a, const st_session_tool *t)
{
    st_brush *b = &a->doc.brush;
    if (t->tool == ST_SESSION_NO_TOOL) a->tool = ST_TOOL_SELECT;
    else if (t->tool < ST_BRUSH_COUNT) { st_brush_set_tool(b, (int)t->tool); a->tool = (int)t->tool; }
    b->radius = t->radius;
    b->strength = t->strength;
    if (t->falloff < ST_FALLOFF_COUNT) b->falloff = (int)t->falloff;
    b->mirror_x = (t->mirror & 1) != 0;
    b->mirror_y = (t->mirror & 2) != 0;
    b->mirror_z = (t->mirror & 4) != 0;
    a->cage = (t->show & ST_SESSION_SHOW_CAGE) != 0;
    a->wire = (t->show & ST_SESSION_SHOW_WIRE) != 0;
    a->shading = t->show & ST_SESSION_SHOW_FLAT ? ST_SHADE_FLAT : ST_SHADE_SMOOTH;
    a->checker = (t->show & ST_SESSION_SHOW_CHECKER) != 0;
}

/* A save the user asked for runs as a job with a Cancel button (jobs.c);
 * the autosave (quiet) does not. */
int st_app_save_session(st_app *a, const char *path, int quiet)
{
    if (!a->doc.loaded) return -1;
    st_session_view v;
    view_of(a, &v);
    st_session_tool t;
    tool_of(a, &t);
    st_error err;
    int rc = quiet ? st_doc_save_session(&a->doc, path, &v, &t, NULL, NULL, &err) : st_app_job_save(a, path, &v, &t, &err);
    if (rc == ST_APP_CANCELLED) {
        st_app_message(a, 0, "save cancelled: %s is as it was", path);
        return -1;
    }
    if (rc) {
        st_app_message(a, 1, "cannot save %s: %s", path, err.msg);
        return -1;
    }
    if (!quiet) st_app_message(a, 0, "saved %s", path);
    return 0;
}

/* Ctrl+S: a .strata model saves over itself; a mesh saves as STEM.strata
 * in the current directory. */
int st_app_save(st_app *a)
{
    /* An imported mesh has no document file yet: ask where (gui.cc). */
    if (a->untitled) {
        st_app_message(a, 0, "an imported mesh is untitled: choose where to save the session");
        int keep = a->quit_after_save;   /* opening the dialog forgets it */
        st_gui_open_dialog(a, ST_DIALOG_SAVE_AS);
        a->quit_after_save = keep;
        return -1;
    }
    char path[4200];
    const char *p = a->doc.path;
    if (st_session_is_path(p)) snprintf(path, sizeof path, "%s", p);
    else {
        const char *b = strrchr(p, '/');
        b = b ? b + 1 : p;
        const char *dot = strrchr(b, '.');
        int n = dot ? (int)(dot - b) : (int)strlen(b);
        snprintf(path, sizeof path, "%.*s.strata", n, b[0] ? b : "model");
    }
    if (st_app_save_session(a, path, 0)) return -1;
    if (strlen(path) < sizeof a->doc.path) memcpy(a->doc.path, path, strlen(path) + 1);
    st_app_saved(a);
    return 0;
}

static void remove_recovery(void)
{
    char rec[4096];
    if (!st_session_recovery_path(rec, sizeof rec)) unlink(rec);
}

/* The document was saved where the user asked: nothing is unsaved, and the
 * recovery file, older than the save, goes. */
void st_app_saved(st_app *a)
{
    a->autosave_dirty = 0;
    a->saved_revision = a->recovery_revision = a->doc.revision;
    remove_recovery();
}

int st_app_unsaved(const st_app *a)
{
    return a->doc.loaded && a->doc.revision != a->saved_revision;
}

/* Blender, GIMP and every editor ask before quitting with unsaved work;
 * the answer is the quit question (gui.cc's window, or the status line
 * and S / D / any key without the GUI). */
void st_app_request_quit(st_app *a)
{
    if (a->busy) return;
    if (!st_app_unsaved(a)) { a->quit = 1; return; }
    a->quit_asking = 1;
    st_app_want_frames(a);
}

int st_app_restore(st_app *a, const char *path)
{
    st_session s;
    st_error err;
    int rc = st_app_job_load_session(a, path, &s, &err);
    if (rc == ST_APP_CANCELLED) {
        st_app_message(a, 0, "opening %s cancelled%s", path, a->doc.loaded ? ": the current model is kept" : "");
        return rc;
    }
    if (rc) {
        st_app_message(a, 1, "cannot open %s: %s%s", path, err.msg, a->doc.loaded ? " (the current model is kept)" : "");
        return -1;
    }
    st_doc *d = &a->doc;
    a->untitled = 0;
    a->showing_default = 0;
    st_app_bake_forget(a);      /* the last bake was of another model */
    /* The window's settings outlive the model: the brush, and the budgets
     * given on the command line (--mem-budget). */
    st_brush brush = d->brush;
    size_t mem_budget = d->mem_budget, undo_budget = d->undo_budget;
    st_doc_free(d);
    st_doc_init(d);
    d->brush = brush;
    d->mem_budget = mem_budget;
    d->undo_budget = undo_budget;
    st_session_move_hier(&d->h, &s.h);
    d->scheme = d->h.scheme;
    d->opts = d->h.opts;
    d->loaded = 1;
    if (s.has_base) st_mesh_move(&d->base, &s.base);
    /* The sculpt layers and the mask move over with their hierarchy. */
    st_layers_free(&d->layers);
    d->layers = s.layers;
    st_layers_init(&s.layers);
    st_mask_free(&d->mask);
    d->mask = s.mask;
    s.mask = (st_mask){ 0 };
    snprintf(d->path, sizeof d->path, "%s", path);
    unsigned top = d->h.map.top;
    d->edit_level = s.edit_level <= top ? s.edit_level : top;
    /* An out-of-range value first, so that the editor recounts the display. */
    d->display_level = top + 1;
    st_doc_set_display_level(d, s.display_level);
    if (d->display_level > top) { d->display_level = top + 1; st_doc_set_display_level(d, top); }
    if (s.box.has_box || s.box.max_level) d->box = s.box;
    /* HD levels (chunk hdlv) become the display before the box is set, so
     * that the box moves over them in place. */
    if (s.has_hd && st_doc_adopt_hd(d, &s.hd, &s.hd_adapt, &s.hd_layers, &err))
        st_app_message(a, 1, "HD levels of %s not loaded: %s", path, err.msg);
    a->box_placed = s.box_on;
    if (s.box_on && st_doc_set_box(d, &d->box, 1, &err))
        st_app_message(a, 1, "interest box of %s: %s", path, err.msg);
    a->shown.valid = 0;
    a->hover_vid = ST_NIL;
    a->op = ST_OP_NONE;
    st_app_sync(a);
    /* Opening is not an edit: switching the file's box on above is part of
     * the file, not a step to undo (Ctrl+Z right after opening would turn
     * it off), and nothing is unsaved. */
    st_doc_forget_history(d);
    a->autosave_dirty = 0;
    a->saved_revision = a->recovery_revision = d->revision;
    if (s.has_view) {
        st_camctl_frame_all(&a->cc, a->r.surf.bbox, a->fb_h > 0 ? (float)a->fb_w / a->fb_h : 1);
        st_camera *c = &a->cc.cam;
        memcpy(c->target, s.view.target, sizeof c->target);
        c->az = (float)(s.view.az * DEG_PER_RAD);
        c->el = (float)(s.view.el * DEG_PER_RAD);
        if (s.view.dist > 0) c->dist = s.view.dist;
        if (s.view.fovy > 0) c->fovy = (float)(s.view.fovy * DEG_PER_RAD);
        c->ortho = s.view.ortho;
        if (s.view.ortho_height > 0) c->ortho_height = s.view.ortho_height;
        st_camctl_orbit(&a->cc, 0, 0);   /* recomputes the clip planes */
    } else {
        st_camctl_frame_all(&a->cc, a->r.surf.bbox, a->fb_h > 0 ? (float)a->fb_w / a->fb_h : 1);
    }
    if (s.has_tool) tool_apply(a, &s.tool);
    st_pick_invalidate(&a->pick);
    st_session_free(&s);
    char lv[48];
    st_app_message(a, 0, "opened session %s (%s, %s)", path, d->scheme->name, st_levels_phrase(top, lv, sizeof lv));
    return 0;
}

void st_app_autosave_tick(st_app *a, int force)
{
    /* A completed step (a stroke, a drag, an undo) is written at once, so
     * that the recovery file holds every step however soon the process
     * ends; other changes (the box, the view) wait for the timer. */
    if (a->doc.loaded && a->doc.revision != a->recovery_revision && a->doc.revision == a->saved_revision) {
        /* Undone back to the state last saved or opened: nothing is left
         * to recover (as after st_app_saved). */
        remove_recovery();
        a->recovery_revision = a->doc.revision;
        a->autosave_dirty = 0;
        return;
    }
    if (a->doc.loaded && a->doc.revision != a->recovery_revision) { a->autosave_dirty = 1; force = 1; }
    if (!a->autosave_dirty || !a->doc.loaded || a->op != ST_OP_NONE || a->doc.active) return;
    double t = glfwGetTime();
    if (!force && t - a->autosave_t < AUTOSAVE_SECONDS) return;
    char rec[4096];
    a->autosave_t = t;
    if (st_session_recovery_path(rec, sizeof rec)) return;
    char keep[ST_MSG_LEN];
    int keep_err = a->msg_error;
    memcpy(keep, a->msg, sizeof keep);
    if (!st_app_save_session(a, rec, 1)) { a->autosave_dirty = 0; a->recovery_revision = a->doc.revision; }
    else {
        /* Not retried before the timer: a full disk would fail every frame. */
        a->recovery_revision = a->doc.revision;
        memcpy(a->msg, keep, sizeof keep);
        a->msg_error = keep_err;
        fprintf(stderr, "strata: autosave to %s failed\n", rec);
    }
}

void st_app_check_recovery(st_app *a)
{
    char rec[4096];
    struct stat st;
    if (st_session_recovery_path(rec, sizeof rec) || stat(rec, &st)) return;
    char when[64];
    struct tm tm;
    localtime_r(&st.st_mtime, &tm);
    strftime(when, sizeof when, "%Y-%m-%d %H:%M", &tm);
    st_app_message(a, 0, "unsaved work from %s was recovered in %s: Ctrl+R restores it", when, rec);
}

void st_app_restore_recovery(st_app *a)
{
    char rec[4096];
    if (st_session_recovery_path(rec, sizeof rec)) { st_app_message(a, 1, "no recovery path (no HOME?)"); return; }
    if (access(rec, R_OK)) { st_app_message(a, 0, "no recovery file (%s)", rec); return; }
    st_app_restore(a, rec);
}
