/* Cancelling the document's long operations (ui/editor.h,
 * st_doc_*_progress, st_doc_save_session): opening, adding a level, a
 * scheme change and saving, each cancelled by its progress callback at
 * several fractions (the first report, halfway, late, the last), leave the
 * document bit-identical to before: its session bytes (every level's
 * positions and details, the pools with their ids, box, levels, layers,
 * mask), the undo history, the levels shown and the path; a cancelled save
 * leaves the file on disk as it was (or absent) and no temporary.  Then a
 * level added after the cancelled attempts is the one a document without
 * them gets, to the bit (ids included), and the reports go from 0 to 1
 * without going back. */
#define _POSIX_C_SOURCE 200809L
#include "editor.h"
#include "editor_testlib.h"
#include "testlib.h"
#include "core/progressive/scheme_registry.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define TORUS STRATA_ASSETS "/torus.obj"
#define CUBE STRATA_ASSETS "/cube.obj"

/* The document as bytes: its session (core/io/session.h) as
 * st_doc_save_session writes it, then the undo counters, levels and path. */
typedef struct fingerprint {
    unsigned char *bytes;      /* the session as the document saves it */
    size_t n;
    unsigned char *whole;      /* the same with every level's topology (whole_map) */
    size_t nwhole;
    double *model;             /* per level, per vertex: id, position, detail */
    size_t nmodel;
    uint32_t nundo, undo_pos;
    unsigned edit_level, display_level, top;
    const st_scheme *scheme;
    char path[4096];
} fingerprint;

/* Every level's vertices in enumeration order: id, position, detail. */
static void model_take(const st_hier *h, fingerprint *f)
{
    size_t cap = 1024, n = 0;
    double *o = malloc(cap * sizeof *o);
    for (unsigned l = 0; l <= h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            if (n + 8 > cap) o = realloc(o, (cap *= 2) * sizeof *o);
            o[n++] = l;
            o[n++] = v;
            memcpy(o + n, st_pos(&h->map, v, l), 3 * sizeof *o);
            n += 3;
            if (l && h->detail[l] && v < h->detail_cap[l]) memcpy(o + n, h->detail[l] + 3 * (size_t)v, 3 * sizeof *o);
            else memset(o + n, 0, 3 * sizeof *o);
            n += 3;
        }
    }
    f->model = o;
    f->nmodel = n;
}

static void fp_take(const st_doc *d, fingerprint *f)
{
    memset(f, 0, sizeof *f);
    model_take(&d->h, f);
    st_session_ref r = { .h = &d->h, .box = &d->box, .box_on = d->box_on, .edit_level = d->edit_level,
                         .display_level = d->display_level, .base = d->base.nverts ? &d->base : NULL,
                         .layers = &d->layers, .mask = &d->mask };
    st_error err;
    void *b = NULL, *w = NULL;
    CHECKF(st_session_write_mem(&r, &b, &f->n, &err) == ST_OK, "%s", err.msg);
    f->bytes = b;
    /* Compared: every level's topology, id for id, even where a save stores
     * level 0 alone (a document that cancelled a level keeps the same ids,
     * but no longer knows them regenerable, and saves them whole). */
    r.whole_map = 1;
    CHECKF(st_session_write_mem(&r, &w, &f->nwhole, &err) == ST_OK, "%s", err.msg);
    f->whole = w;
    f->nundo = d->nundo;
    f->undo_pos = d->undo_pos;
    f->edit_level = d->edit_level;
    f->display_level = d->display_level;
    f->top = d->h.map.top;
    f->scheme = d->scheme;
    snprintf(f->path, sizeof f->path, "%s", d->path);
}

/* model_only: the model, levels, undo and path, not the session's bytes
 * (see check_cancels). */
static int fp_equal(const fingerprint *a, const fingerprint *b, int model_only)
{
    if (!model_only && !(a->nwhole == b->nwhole && a->whole && b->whole && !memcmp(a->whole, b->whole, a->nwhole))) return 0;
    return a->nmodel == b->nmodel && !memcmp(a->model, b->model, a->nmodel * sizeof *a->model) && a->nundo == b->nundo &&
           a->undo_pos == b->undo_pos && a->edit_level == b->edit_level && a->display_level == b->display_level &&
           a->top == b->top && a->scheme == b->scheme && !strcmp(a->path, b->path);
}

static void fp_free(fingerprint *f) { free(f->bytes); free(f->whole); free(f->model); memset(f, 0, sizeof *f); }

/* The progress callback: records the reports, cancels at the first one
 * at or past `at` (at > 1: never). */
typedef struct watcher {
    double at;
    int calls, cancelled, backwards;
    double first, last;
} watcher;

static int watch(void *ctx, double f)
{
    watcher *w = ctx;
    if (w->calls && f < w->last) w->backwards = 1;
    if (!w->calls) w->first = f;
    w->calls++;
    w->last = f;
    if (f >= w->at) { w->cancelled = 1; return 1; }
    return 0;
}

/* Open the torus at 2 levels, move one vertex (one undo step, details
 * above level 0). */
static void prepare(st_doc *d)
{
    st_doc_init(d);
    ed_test_open(d, TORUS, "catmull-clark", 2);
    const double dir[3] = { 1, 0.2, 0.1 };
    uint32_t v = ed_test_extreme_vertex(d, dir);
    st_doc_select(d, &v, 1, ST_SELECT_REPLACE);
    CHECK(st_doc_drag_begin(d) == 0);
    const double delta[3] = { 0.05, 0.02, -0.01 };
    CHECK(st_doc_drag_update(d, delta) == 0);
    st_doc_drag_end(d);
    CHECK(d->undo_pos == 1);
}

static const double fractions[] = { 0.0, 0.3, 0.7, 1.0 };
#define NFRACTIONS (sizeof fractions / sizeof fractions[0])

/* op(d, watcher) cancelled at every fraction: the document as before.
 * model_only: a level refined then cancelled leaves its ids on the pools'
 * spare stacks (as undo of a level does), so the pools keep the grown
 * capacity and the session has more (free) bytes; the model, to the bit,
 * is checked here, and that the ids come back in order by the level added
 * afterwards (test_levels_scheme_open). */
static void check_cancels(st_doc *d, const char *what, int (*op)(st_doc *, watcher *, st_error *), int model_only)
{
    fingerprint before, after;
    fp_take(d, &before);
    for (unsigned i = 0; i < NFRACTIONS; i++) {
        watcher w = { .at = fractions[i] };
        st_error err = { 0 };
        int rc = op(d, &w, &err);
        CHECKF(rc != ST_OK && strstr(err.msg, "cancelled"), "%s cancelled at %.1f: rc %d, %s", what, fractions[i], rc,
               err.msg);
        CHECKF(w.cancelled && w.last >= fractions[i], "%s: no report at or past %.1f (%d reports, last %g)", what,
               fractions[i], w.calls, w.last);
        CHECKF(!w.backwards, "%s: the fraction went back", what);
        fp_take(d, &after);
        CHECKF(fp_equal(&before, &after, model_only), "%s cancelled at %.1f: the document changed", what, fractions[i]);
        fp_free(&after);
    }
    fp_free(&before);
}

static int op_add_level(st_doc *d, watcher *w, st_error *err) { return st_doc_add_level_progress(d, watch, w, err); }
static int op_scheme(st_doc *d, watcher *w, st_error *err)
{
    return st_doc_set_scheme_progress(d, "quad-triangle", watch, w, err);
}
static int op_open(st_doc *d, watcher *w, st_error *err) { return st_doc_open_progress(d, CUBE, "catmull-clark", 3, watch, w, err); }

/* An uncancelled run reports from 0 to 1, in order, and succeeds. */
static void check_complete(st_doc *d, const char *what, int (*op)(st_doc *, watcher *, st_error *))
{
    watcher w = { .at = 2 };
    st_error err = { 0 };
    CHECKF(op(d, &w, &err) == ST_OK, "%s: %s", what, err.msg);
    CHECKF(w.calls >= 2 && w.first == 0 && w.last == 1 && !w.backwards, "%s: %d reports, %g .. %g%s", what, w.calls,
           w.first, w.last, w.backwards ? ", backwards" : "");
}

static void test_levels_scheme_open(void)
{
    st_doc d;
    prepare(&d);
    check_cancels(&d, "add a level", op_add_level, 1);
    check_cancels(&d, "scheme change", op_scheme, 0);
    check_cancels(&d, "open", op_open, 0);

    /* A level added now is the level a document without the cancelled
     * attempts gets (same ids, same values, same undo). */
    check_complete(&d, "add a level", op_add_level);
    st_doc fresh;
    prepare(&fresh);
    st_error err;
    CHECKF(st_doc_add_level(&fresh, &err) == ST_OK, "%s", err.msg);
    fingerprint a, b;
    fp_take(&d, &a);
    fp_take(&fresh, &b);
    CHECK(a.top == 3 && a.nundo == 2);
    CHECKF(fp_equal(&a, &b, 0), "a level added after cancelled attempts differs from one added without (%zu, %zu bytes)",
           a.n, b.n);
    fp_free(&a);
    fp_free(&b);
    /* Undo of that level, then the scheme change and the open complete. */
    CHECK(st_doc_undo(&d, &err) == 0 && d.h.map.top == 2);
    check_complete(&d, "scheme change", op_scheme);
    CHECK(d.h.scheme == st_scheme_find("quad-triangle"));
    check_complete(&d, "open", op_open);
    CHECK(d.h.map.top == 3 && d.nundo == 0 && strstr(d.path, "cube.obj"));
    st_doc_free(&fresh);
    st_doc_free(&d);
}

/* ---- saving ------------------------------------------------------------------ */

static const char *g_save_path;
static int op_save(st_doc *d, watcher *w, st_error *err) { return st_doc_save_session(d, g_save_path, NULL, NULL, watch, w, err); }

/* Files in STRATA_TMP whose name starts with `stem` (temporaries). */
static int count_files(const char *stem)
{
    DIR *dir = opendir(STRATA_TMP);
    if (!dir) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(dir)))
        if (!strncmp(e->d_name, stem, strlen(stem))) n++;
    closedir(dir);
    return n;
}

static void test_save(void)
{
    st_doc d;
    prepare(&d);
    st_error err;
    /* A session of several 64 KiB buffers (two levels more: a session
     * stores level 0's topology and every level's positions). */
    CHECKF(st_doc_add_level(&d, &err) == ST_OK && st_doc_add_level(&d, &err) == ST_OK, "%s", err.msg);
    const char *path = STRATA_TMP "/cancel_save.strata", *absent = STRATA_TMP "/cancel_absent.strata";
    unlink(absent);
    const char old[] = "the file before the save\n";
    CHECK(tl_write_file(path, old, sizeof old - 1) == 0);
    fingerprint before;
    fp_take(&d, &before);
    CHECKF(before.n > 4 * 65536, "the session is %zu bytes: too small to be cancelled halfway", before.n);
    for (int k = 0; k < 2; k++) {
        g_save_path = k ? absent : path;
        check_cancels(&d, k ? "save (new file)" : "save (over a file)", op_save, 0);
        size_t n = 0;
        char *now = tl_read_file(path, &n);
        CHECKF(now && n == sizeof old - 1 && !memcmp(now, old, n), "a cancelled save changed %s", path);
        free(now);
        CHECKF(access(absent, F_OK) != 0, "a cancelled save created %s", absent);
        CHECKF(count_files("cancel_save.strata.") == 0 && count_files("cancel_absent.strata") == 0,
               "a cancelled save left a temporary");
    }
    /* Uncancelled: the file holds the document's session, byte for byte. */
    g_save_path = path;
    check_complete(&d, "save", op_save);
    size_t n = 0;
    char *now = tl_read_file(path, &n);
    CHECKF(now && n == before.n && !memcmp(now, before.bytes, n), "the saved file is not the document's session");
    free(now);
    fp_free(&before);
    unlink(path);
    st_doc_free(&d);
}

int main(void)
{
    test_levels_scheme_open();
    test_save();
    return TEST_END();
}
