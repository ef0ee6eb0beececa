/* st_doc: the modeller's document (editor.h), without GL.
 *
 * Decisions (where the requirements leave a choice):
 *   - The model is always the regular hierarchy d->h.  Drags and brushes
 *     act at the editing level of h through st_hier_edit (finer levels
 *     follow with their details).  The interest box only changes what is
 *     displayed: d->display (editor_display.c) is derived from h and
 *     follows every edit.
 *   - Core reports what each edit wrote (its footprint, core/multires/
 *     footprint.h): undo saves exactly those values, the box's display
 *     copies exactly those positions, and the change handed to the window
 *     carries the footprints for the renderer.
 *   - Undo (undo.c): every operation here that changes the model pushes
 *     one step (ed_push_step).
 *   - A new level's memory is estimated from the current top level's
 *     dart and vertex counts (st_doc_add_level_bytes).
 *
 * About 1,000 lines, one file: opening, the scheme, the levels, the
 * selection, change tracking and the interest box share the document's
 * progress spans, level steps and display rebuild (static here); the drag
 * is editor_drag.c, brushes brush.c, undo undo.c.
 */
#define _POSIX_C_SOURCE 200809L
#include "editor_internal.h"
#include "core/rebuild/rebuild.h"
#include "core/multires/estimate.h"
#include "core/adapt/adapt_estimate.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

double ed_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int display_build(st_doc *d, const st_adapt_params *p, st_error *err);
static void display_changed(st_doc *d);

/* ---- lifetime ------------------------------------------------------------- */

void st_doc_init(st_doc *d)
{
    memset(d, 0, sizeof *d);
    st_mesh_init(&d->base);
    st_brush_defaults(&d->brush, 0.25);
    d->undo_budget = (size_t)256 << 20;
    long pages = sysconf(_SC_PHYS_PAGES), psize = sysconf(_SC_PAGESIZE);
    d->mem_budget = pages > 0 && psize > 0 ? (size_t)pages * (size_t)psize / 2 : (size_t)4 << 30;
    d->box.base_level = 0;
    d->box.max_level = 3;
    d->box.has_box = 1;
    d->vdart_level = -1;
    st_layers_init(&d->layers);
}

void st_doc_free(st_doc *d)
{
    ed_finish_active(d);
    ed_undo_clear(d);
    free(d->undo);
    st_box_display_free(&d->display);
    free(d->hd_vdart);
    st_mask_free(&d->hd_mask);
    st_edit_cache_free(d->hd_cache);
    if (d->loaded) st_hier_free(&d->h);
    st_mesh_free(&d->base);
    free(d->sel);
    st_footprint_free(&d->fp_model);
    st_footprint_free(&d->fp_query);
    st_footprint_free(&d->fp_taken[0]);
    st_footprint_free(&d->fp_taken[1]);
    free(d->vdart);
    ed_brush_state_free(d->bs);
    st_layers_free(&d->layers);
    st_mask_free(&d->mask);
    st_mask_free(&d->display_mask);
    free(d->change.mask_vids);
    st_edit_cache_free(d->ecache);
    memset(d, 0, sizeof *d);
}

/* ---- memory ------------------------------------------------------------------ */

size_t st_doc_model_bytes(const st_doc *d)
{
    if (!d->loaded) return 0;
    size_t n = ed_hier_bytes(&d->h);
    if (d->display.built) n += ed_hier_bytes(&d->display.hier);
    return n;
}

static size_t level_bytes_for(const st_hier *h)
{
    const st_map *m = &h->map;
    uint64_t nd = 0, nv = 0;
    for (unsigned k = 0; k <= m->top; k++) {
        nd += m->darts.live[k];
        nv += m->verts.live[k];
    }
    uint64_t f = h->scheme && h->scheme->id == ST_SCHEME_SQRT3 ? 3 : 4;
    /* New level: every dart's relations, insertion level and flags (14 bytes),
     * the β0 column of the old darts, positions and insertion level of every
     * vertex plus the column of the old ones, and room for details. */
    uint64_t b = f * nd * 14 + nd * 4 + f * nv * (24 + 1 + 24) + nv * 24;
    return (size_t)b;
}

size_t st_doc_add_level_bytes(const st_doc *d)
{
    return d->loaded ? level_bytes_for(&d->h) : 0;
}

static void progress(const st_doc *d, const char *what, unsigned step, unsigned steps)
{
    if (d->progress) d->progress(d->progress_ctx, what, step, steps);
}

/* ---- progress and cancellation ------------------------------------------------
 * Long operations take the caller's int (*progress)(void *ctx, double
 * fraction), as the rebuild does (editor_rebuild.c): called with the
 * fraction done, a non-zero return cancels and the document stays as it
 * was.  A span maps a stage's own 0..1 into its part [lo, hi] of the whole,
 * so that core's callbacks (st_hier_subdivide_to_progress) report overall
 * fractions. */
typedef struct ed_span {
    int (*fn)(void *ctx, double fraction);
    void *ctx;
    double lo, hi;
    int stopped;               /* the callback asked to cancel */
} ed_span;

/* The point at x of [lo, hi], the ends exactly: a stage's 1 is the next
 * one's 0, never above it, and the reports never go back. */
static double span_at(double lo, double hi, double x) { return x <= 0 ? lo : x >= 1 ? hi : lo + x * (hi - lo); }

static int span_report(void *p, double f)
{
    ed_span *s = p;
    if (!s->fn) return 0;
    if (s->fn(s->ctx, span_at(s->lo, s->hi, f))) s->stopped = 1;
    return s->stopped;
}

/* The callback at fraction f; ST_ERR_INVALID "cancelled" when it says so. */
static int span_cancelled(ed_span *s, double f, st_error *err)
{
    if (!span_report(s, f)) return 0;
    st_fail(err, ST_ERR_INVALID, "cancelled");
    return 1;
}

/* Refines h to `levels`, refusing a level that would go over the budget
 * (`extra`: bytes already in use besides h).  Progress: the span's range,
 * each level weighted by 4^k as core weighs it. */
static int build_levels(const st_doc *d, st_hier *h, unsigned levels, size_t budget, size_t extra, ed_span *sp,
                        st_error *err)
{
    unsigned from = h->map.top;
    double total = 0, done = 0;
    for (unsigned l = from + 1; l <= levels; l++) total += ldexp(1.0, 2 * (int)(l - from));
    while (h->map.top < levels) {
        char what[64];
        snprintf(what, sizeof what, "building level %u", h->map.top + 1);
        progress(d, what, h->map.top + 1, levels);
        size_t need = level_bytes_for(h), have = ed_hier_bytes(h) + extra;
        if (have + need > budget)
            return st_fail(err, ST_ERR_MEMORY,
                           "level %u refused: it needs about %zu bytes (%.1f MiB) more, the model uses %.1f MiB "
                           "and the memory budget is %.1f MiB",
                           h->map.top + 1, need, st_mib(need), st_mib(have), st_mib(budget));
        double w = ldexp(1.0, 2 * (int)(h->map.top + 1 - from));
        ed_span level = { sp->fn, sp->ctx, span_at(sp->lo, sp->hi, done / total), span_at(sp->lo, sp->hi, (done + w) / total), 0 };
        int rc = st_hier_subdivide_to_progress(h, h->map.top + 1, span_report, &level, err);
        sp->stopped |= level.stopped;
        if (rc) return rc;
        done += w;
    }
    return ST_OK;
}

/* ---- open and scheme -------------------------------------------------------------- */

static void default_box(st_doc *d)
{
    const st_mesh *m = &d->base;
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t v = 0; v < m->nverts; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->pos[3 * v + k]);
            hi[k] = fmax(hi[k], m->pos[3 * v + k]);
        }
    double diag = 0;
    for (int k = 0; k < 3; k++) {
        double c = (lo[k] + hi[k]) / 2, h = (hi[k] - lo[k]) / 4;
        d->box.box_lo[k] = c - h;
        d->box.box_hi[k] = c + h;
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    d->box.has_box = 1;
    d->box.base_level = 0;
    d->box.max_level = d->h.map.top + 1 < ST_MAX_LEVELS ? d->h.map.top + 1 : d->h.map.top;
    d->box.falloff = 0;
    d->box.flatness = 0;
    d->box.no_restriction = 0;
    if (diag > 0) d->brush.radius = 0.1 * sqrt(diag);
}

int st_doc_open(st_doc *d, const char *path, const char *scheme, unsigned levels, st_error *err)
{
    return st_doc_open_progress(d, path, scheme, levels, NULL, NULL, err);
}

/* Opening: reading and level 0 are the first tenth, the levels the rest. */
#define OPEN_READ_SHARE 0.1

int st_doc_open_progress(st_doc *d, const char *path, const char *scheme, unsigned levels,
                         int (*fraction)(void *ctx, double f), void *ctx, st_error *err)
{
    ed_span sp = { fraction, ctx, 0, 1, 0 };
    const char *name = scheme ? scheme : "catmull-clark";
    const st_scheme *sc = st_scheme_find(name);
    if (!sc) return st_fail(err, ST_ERR_INVALID, "unknown scheme '%s' (catmull-clark, loop, butterfly, quad-triangle, sqrt3, doo-sabin)", name);
    if (levels != ST_DOC_LEVELS_AUTO && levels >= ST_MAX_LEVELS)
        return st_fail(err, ST_ERR_RANGE, "%u levels: at most %d", levels, ST_MAX_LEVELS - 1);
    if (strlen(path) >= sizeof d->path) return st_fail(err, ST_ERR_RANGE, "path too long");
    if (span_cancelled(&sp, 0, err)) return ST_ERR_INVALID;
    st_mesh mesh;
    st_mesh_init(&mesh);
    st_notes notes = { 0 };
    int rc = d->load_mesh ? d->load_mesh(path, &mesh, d->read_flags, &notes, err)
                          : st_mesh_load_flags(path, &mesh, d->read_flags, &notes, err);
    if (rc) { st_notes_free(&notes); return rc; }
    st_hier h;
    st_hier_opts opts = { .boundary = ST_BOUNDARY_UNSET, .crease_method = ST_CREASE_UNIFORM };
    rc = span_cancelled(&sp, OPEN_READ_SHARE / 2, err) ? ST_ERR_INVALID : st_hier_init(&h, &mesh, sc, &opts, err);
    if (rc && sp.stopped) {
        st_mesh_free(&mesh);
        st_notes_free(&notes);
        return rc;
    }
    if (rc) {
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s", err ? err->msg : "");
        st_fail(err, rc, "%s: %s", path, msg);
        st_mesh_free(&mesh);
        st_notes_free(&notes);
        return rc;
    }
    if (levels == ST_DOC_LEVELS_AUTO) levels = mesh.nfaces > ST_DOC_DENSE_FACES ? 0 : ST_DOC_DEFAULT_LEVELS;
    sp.lo = OPEN_READ_SHARE;
    rc = span_cancelled(&sp, 0, err) ? ST_ERR_INVALID : build_levels(d, &h, levels, d->mem_budget, 0, &sp, err);
    if (!rc) {
        sp.lo = 0;
        if (span_cancelled(&sp, 1, err)) rc = ST_ERR_INVALID;
    }
    if (rc) {
        st_hier_free(&h);
        st_mesh_free(&mesh);
        st_notes_free(&notes);
        return rc;
    }
    /* Success: the old model goes. */
    ed_finish_active(d);
    ed_undo_clear(d);
    st_box_display_drop(&d->display);
    d->box_on = 0;
    d->hd = 0;
    d->hd_level = 0;
    if (d->loaded) st_hier_free(&d->h);
    d->h = h;
    ed_hier_fix(&d->h);
    st_layers_free(&d->layers);
    st_mask_free(&d->mask);
    st_mesh_move(&d->base, &mesh);
    d->scheme = sc;
    d->opts = d->h.opts;
    d->loaded = 1;
    d->rebased = 0;
    snprintf(d->path, sizeof d->path, "%s", path);
    d->note[0] = 0;
    if (notes.count) snprintf(d->note, sizeof d->note, "%.200s%s", notes.lines[0], notes.count > 1 ? " (and more repairs)" : "");
    st_notes_free(&notes);
    d->edit_level = 0;
    d->display_level = d->h.map.top;
    d->nsel = 0;
    default_box(d);
    ed_topology_changed(d);
    return ST_OK;
}

unsigned st_doc_schemes_accepted(st_doc *d, const char *const *schemes, unsigned n, int *rc, st_error *errs)
{
    unsigned ok = 0;
    st_mesh m;
    st_mesh_init(&m);
    st_error merr;
    int mrc = d->loaded ? st_hier_level_mesh(&d->h, 0, &m, &merr) : st_fail(&merr, ST_ERR_INVALID, "no model");
    for (unsigned i = 0; i < n; i++) {
        const st_scheme *sc = st_scheme_find(schemes[i] ? schemes[i] : "");
        if (mrc) { rc[i] = mrc; errs[i] = merr; }
        else if (!sc) rc[i] = st_fail(&errs[i], ST_ERR_INVALID, "unknown scheme '%s'", schemes[i] ? schemes[i] : "");
        else rc[i] = st_scheme_accepts(sc, &m, &errs[i]);
        ok += rc[i] == ST_OK;
    }
    st_mesh_free(&m);
    return ok;
}

int st_doc_scheme_accepts(st_doc *d, const char *scheme, st_error *err)
{
    int rc;
    st_doc_schemes_accepted(d, &scheme, 1, &rc, err);
    return rc;
}

int st_doc_set_scheme(st_doc *d, const char *scheme, st_error *err)
{
    return st_doc_set_scheme_progress(d, scheme, NULL, NULL, err);
}

int st_doc_set_scheme_progress(st_doc *d, const char *scheme, int (*fraction)(void *ctx, double f), void *ctx,
                               st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    ed_span sp = { fraction, ctx, 0, 1, 0 };
    if (span_cancelled(&sp, 0, err)) return ST_ERR_INVALID;
    const st_scheme *sc = st_scheme_find(scheme ? scheme : "");
    if (!sc) return st_fail(err, ST_ERR_INVALID, "unknown scheme '%s'", scheme ? scheme : "");
    if (ed_hd_blocks(d, "a scheme change", err)) return ST_ERR_INVALID;
    ed_finish_active(d);
    /* The control mesh as it is now (edits of level 0 kept); the file's
     * tags are kept while level 0 is still the loaded one.  Once it is not
     * (a rebuild or a removed bottom level made it), level 0's own sharpness
     * and holes are its tags, read as the rebuild reads a level. */
    st_mesh mesh;
    st_mesh_init(&mesh);
    int rc = d->rebased ? st_rebuild_level_input(&d->h, 0, &mesh, err) : st_hier_level_mesh(&d->h, 0, &mesh, err);
    if (rc) return rc;
    if (!d->rebased && mesh.nverts == d->base.nverts) {
        const st_mesh *b = &d->base;
        mesh.boundary_interp = b->boundary_interp;
        if (b->ncreases) {
            mesh.crease_v = malloc((size_t)b->ncreases * 2 * sizeof *mesh.crease_v);
            mesh.crease_s = malloc((size_t)b->ncreases * sizeof *mesh.crease_s);
            if (!mesh.crease_v || !mesh.crease_s) { st_mesh_free(&mesh); return st_fail(err, ST_ERR_MEMORY, "out of memory"); }
            memcpy(mesh.crease_v, b->crease_v, (size_t)b->ncreases * 2 * sizeof *mesh.crease_v);
            memcpy(mesh.crease_s, b->crease_s, (size_t)b->ncreases * sizeof *mesh.crease_s);
            mesh.ncreases = b->ncreases;
        }
        if (b->ncorners) {
            mesh.corner_v = malloc((size_t)b->ncorners * sizeof *mesh.corner_v);
            mesh.corner_s = malloc((size_t)b->ncorners * sizeof *mesh.corner_s);
            if (!mesh.corner_v || !mesh.corner_s) { st_mesh_free(&mesh); return st_fail(err, ST_ERR_MEMORY, "out of memory"); }
            memcpy(mesh.corner_v, b->corner_v, (size_t)b->ncorners * sizeof *mesh.corner_v);
            memcpy(mesh.corner_s, b->corner_s, (size_t)b->ncorners * sizeof *mesh.corner_s);
            mesh.ncorners = b->ncorners;
        }
    }
    st_hier h;
    st_hier_opts opts = { .boundary = d->h.opts.boundary, .crease_method = d->h.opts.crease_method,
                          .tri_sub = d->h.opts.tri_sub };
    rc = st_hier_init(&h, &mesh, sc, &opts, err);
    st_mesh_free(&mesh);
    if (rc) return rc;
    /* The old hierarchy stays (in the undo step) while the new one grows. */
    sp.lo = OPEN_READ_SHARE;
    rc = span_cancelled(&sp, 0, err) ? ST_ERR_INVALID
                                     : build_levels(d, &h, d->h.map.top, d->mem_budget, st_doc_model_bytes(d), &sp, err);
    if (!rc) {
        sp.lo = 0;
        if (span_cancelled(&sp, 1, err)) rc = ST_ERR_INVALID;
    }
    if (rc) { st_hier_free(&h); return rc; }
    st_undo_step *s = ed_swap_hier(d, &h);
    ed_topology_changed(d);
    ed_step_finish(s);
    ed_push_step(d, s);
    return ST_OK;
}

/* A new hierarchy for the document, the old one moved into a hierarchy undo
 * step (with the scheme, levels and box that went with it): a scheme change
 * and a rebuild of levels both replace the model so. */
/* What a hierarchy step restores besides the hierarchy: the scheme, the
 * levels shown and edited, the rebase flag, the box. */
static void keep_view(st_undo_step *s, const st_doc *d)
{
    s->scheme = d->scheme;
    s->edit_level = d->edit_level;
    s->display_level = d->display_level;
    s->rebased = d->rebased;
    s->box_old = d->box;
}

st_undo_step *ed_swap_hier(st_doc *d, st_hier *h)
{
    st_undo_step *s = ed_step_new(ED_STEP_HIER);
    s->snap = d->h;
    ed_hier_fix(&s->snap);
    keep_view(s, d);
    /* The layers and the mask go with the old hierarchy (the new one has
     * other vertices). */
    s->has_layers = 1;
    s->layers_old = d->layers;
    st_layers_init(&s->layers_new);
    st_layers_init(&d->layers);
    s->mask_old = d->mask;
    d->mask = (st_mask){ 0 };
    d->change.bits |= ST_CHANGE_MASK;
    d->mask_all = 1;
    d->h = *h;
    ed_hier_fix(&d->h);
    d->scheme = d->h.scheme;
    d->opts = d->h.opts;
    return s;
}

/* ---- levels ---------------------------------------------------------------------- */

static void clamp_levels(st_doc *d)
{
    unsigned top = d->h.map.top;
    if (d->edit_level > top) d->edit_level = top;
    if (d->display_level > top) d->display_level = top;
    if (d->display_level < d->edit_level) d->display_level = d->edit_level;
}

/* Copy of the current state into a new hierarchy step (before an in-place
 * change). */
static st_undo_step *hier_step_begin(st_doc *d, st_error *err)
{
    st_undo_step *s = ed_step_new(ED_STEP_HIER);
    if (ed_hier_clone(&s->snap, &d->h, NULL)) {
        free(s);
        st_fail(err, ST_ERR_MEMORY, "out of memory keeping the undo copy");
        return NULL;
    }
    keep_view(s, d);
    s->has_layers = 1;
    st_layers_init(&s->layers_new);
    if (st_layers_copy(&s->layers_old, &d->layers) || st_mask_copy(&s->mask_old, &d->mask)) {
        ed_step_free(s);
        st_fail(err, ST_ERR_MEMORY, "out of memory keeping the undo copy");
        return NULL;
    }
    return s;
}

/* After a change of the levels begun at t0: topology bits, timing. */
void ed_topology_done(st_doc *d, double t0)
{
    ed_topology_changed(d);
    d->last_update_at_ms = ed_now_ms();
    d->last_update_ms = d->last_update_at_ms - t0;
}

static void hier_step_end(st_doc *d, st_undo_step *s, double t0)
{
    ed_topology_done(d, t0);
    ed_step_finish(s);
    ed_push_step(d, s);
}

/* ---- adding levels without a copy ----------------------------------------------
 * Removing the top level puts its id blocks on the pool's spare stack in
 * the order the level took them; refining again would pop them in reverse
 * and give other ids.  Reversing that segment of the stack first makes the
 * refinement take the same blocks in the same order, so the level comes
 * back with the same ids (checked by a sum over its ids) and the same
 * values (refinement and synthesis are deterministic). */

uint64_t ed_top_ids_sum(const st_map *m)
{
    unsigned l = m->top;
    uint64_t h = 1469598103934665603ull;
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, l, &it); x != ST_NIL; x = st_dart_next(m, l, &it)) { h ^= x; h *= 1099511628211ull; }
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) { h ^= v; h *= 1099511628211ull; }
    return h;
}

void ed_remove_top_keep_order(st_hier *h)
{
    st_pool *pools[2] = { &h->map.darts, &h->map.verts };
    unsigned l = h->map.top;
    uint32_t nb[2] = { pools[0]->nblocks[l], pools[1]->nblocks[l] };
    st_hier_remove_top(h);
    for (int k = 0; k < 2; k++) {
        st_pool *p = pools[k];
        if (nb[k] > p->nspare) continue; /* the spare list could not grow: nothing pushed */
        uint32_t *a = p->spare + (p->nspare - nb[k]);
        for (uint32_t i = 0, j = nb[k] ? nb[k] - 1 : 0; i < j; i++, j--) { uint32_t t = a[i]; a[i] = a[j]; a[j] = t; }
    }
}

int st_doc_add_level(st_doc *d, st_error *err)
{
    return st_doc_add_level_progress(d, NULL, NULL, err);
}

int st_doc_add_level_progress(st_doc *d, int (*fraction)(void *ctx, double f), void *ctx, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    ed_span sp = { fraction, ctx, 0, 1, 0 };
    ed_finish_active(d);
    if (ed_hd_blocks(d, "adding a level", err)) return ST_ERR_INVALID;
    if (d->h.map.top + 1 >= ST_MAX_LEVELS) return st_fail(err, ST_ERR_RANGE, "level %u is beyond the limit", d->h.map.top + 1);
    size_t need = st_doc_add_level_bytes(d), have = st_doc_model_bytes(d);
    if (have + need > d->mem_budget)
        return st_fail(err, ST_ERR_MEMORY,
                       "level %u refused: it needs about %zu bytes (%.1f MiB) more, the model uses %.1f MiB "
                       "and the memory budget is %.1f MiB",
                       d->h.map.top + 1, need, st_mib(need), st_mib(have), st_mib(d->mem_budget));
    double t0 = ed_now_ms();
    unsigned top = d->h.map.top;
    char what[64];
    snprintf(what, sizeof what, "building level %u", top + 1);
    progress(d, what, 1, d->box_on ? 2 : 1);
    int rc = st_hier_subdivide_to_progress(&d->h, top + 1, span_report, &sp, err);
    if (rc && sp.stopped) {
        /* Cancelled: the level goes as undo removes it (its ids back on
         * the pools' spare stacks in order), so that the document is the
         * one before, to the bit, and a later level gets the same ids. */
        while (d->h.map.top > top) ed_remove_top_keep_order(&d->h);
        return rc;
    }
    if (rc) {
        while (d->h.map.top > top) st_hier_remove_top(&d->h);
        ed_topology_changed(d);
        return rc;
    }
    /* No copy kept: undo removes the level, redo refines again (add_redo). */
    st_undo_step *s = ed_step_new(ED_STEP_ADD);
    s->edit_level = d->edit_level;
    s->display_level = d->display_level;
    s->box_old = d->box;
    s->idsum = ed_top_ids_sum(&d->h.map);
    d->display_level = d->h.map.top;
    s->display_after = d->display_level;
    ed_mask_extend(d);
    hier_step_end(d, s, t0);
    return ST_OK;
}

/* Before a level is removed: a model above its control mesh, no drag or
 * stroke in progress. */
static int removal_begin(st_doc *d, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    if (d->h.map.top == 0) return st_fail(err, ST_ERR_INVALID, "only the control mesh is left");
    if (ed_hd_blocks(d, "deleting a level", err)) return ST_ERR_INVALID;
    ed_finish_active(d);
    return ST_OK;
}

int st_doc_remove_top(st_doc *d, st_error *err)
{
    int rc = removal_begin(d, err);
    if (rc) return rc;
    double t0 = ed_now_ms();
    /* Kept for undo: the level's positions and details (no copy of the
     * rest: the topology comes back from refinement, same ids). */
    st_hier *h = &d->h;
    unsigned top = h->map.top;
    if (st_layers_on_level(&d->layers, top))
        return st_fail(err, ST_ERR_INVALID, "level %u has sculpt layers: merge or delete them first", top);
    st_undo_step *s = ed_step_new(ED_STEP_RMTOP);
    s->idsum = ed_top_ids_sum(&h->map);
    uint32_t n = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h->map, top, &it); v != ST_NIL; v = st_vertex_next(&h->map, top, &it)) n++;
    s->vids = malloc((size_t)(n ? n : 1) * sizeof *s->vids);
    s->vpos = malloc((size_t)(n ? n : 1) * sizeof *s->vpos);
    if (h->detail[top]) s->det = malloc((size_t)h->detail_cap[top] * 3 * sizeof *s->det);
    if (!s->vids || !s->vpos || (h->detail[top] && !s->det)) {
        ed_step_free(s);
        return st_fail(err, ST_ERR_MEMORY, "out of memory keeping the level for undo");
    }
    for (uint32_t v = st_vertex_first(&h->map, top, &it); v != ST_NIL; v = st_vertex_next(&h->map, top, &it)) {
        s->vids[s->nvids] = v;
        memcpy(s->vpos[s->nvids++], st_pos(&h->map, v, top), sizeof s->vpos[0]);
    }
    if (h->detail[top]) {
        memcpy(s->det, h->detail[top], (size_t)h->detail_cap[top] * 3 * sizeof *s->det);
        s->detcap = h->detail_cap[top];
    }
    s->edit_level = d->edit_level;
    s->display_level = d->display_level;
    s->box_old = d->box;
    ed_remove_top_keep_order(h);
    clamp_levels(d);
    s->edit_after = d->edit_level;
    s->display_after = d->display_level;
    hier_step_end(d, s, t0);
    return ST_OK;
}

int st_doc_remove_bottom(st_doc *d, st_error *err)
{
    int rc = removal_begin(d, err);
    if (rc) return rc;
    double t0 = ed_now_ms();
    st_undo_step *s = hier_step_begin(d, err);
    if (!s) return ST_ERR_MEMORY;
    s->name = "delete the coarsest level";
    if (st_layers_rebase(&d->layers, err)) {
        ed_step_free(s);
        return ST_ERR_INVALID;
    }
    st_hier_remove_bottom(&d->h);
    if (d->edit_level > 0) d->edit_level--;
    if (d->display_level > 0) d->display_level--;
    d->rebased = 1;
    if (d->box.base_level > 0) d->box.base_level--;
    if (d->box.max_level > d->box.base_level) d->box.max_level--;
    clamp_levels(d);
    hier_step_end(d, s, t0);
    return ST_OK;
}

void st_doc_set_edit_level(st_doc *d, unsigned l)
{
    if (!d->loaded) return;
    ed_finish_active(d);
    unsigned top = d->h.map.top, hd = 0;
    if (l > top) {
        /* An HD level (editor_hd.c): the box's base becomes the top, so
         * that the display is the model's top outside the HD region. */
        unsigned lim = st_doc_level_limit(d);
        if (l > lim) l = lim;
        if (l > top && d->box.base_level != top) {
            st_adapt_params p = d->box;
            p.base_level = top;
            st_error e;
            if (st_doc_set_box(d, &p, 1, &e)) {
                snprintf(d->note, sizeof d->note, "HD level %u refused: %.200s", l, e.msg);
                l = top;
            }
        }
        if (l > top) hd = l;
        else if (st_doc_hd_refusal(d)) snprintf(d->note, sizeof d->note, "%s", st_doc_hd_refusal(d));
        l = top;
    }
    if (l != d->edit_level || hd != d->hd_level || d->nsel) d->change.bits |= ST_CHANGE_SELECTION;
    d->edit_level = l;
    d->hd_level = hd;
    d->nsel = 0;
    d->hd_tables_ok = 0;
    if (d->display_level < l) {
        d->display_level = l;
        display_changed(d);
    }
}

void st_doc_set_display_level(st_doc *d, unsigned l)
{
    if (!d->loaded) return;
    if (l > d->h.map.top) l = d->h.map.top;
    if (l < d->edit_level) l = d->edit_level;
    if (l != d->display_level) {
        d->display_level = l;
        display_changed(d);
    }
}

/* ---- selection ---------------------------------------------------------------------- */

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

static int edit_vertex_ok(const st_doc *d, uint32_t v)
{
    if (d->hd_level) return ed_hd_vertex_ok(d, v); /* a display vertex of the HD level */
    const st_map *m = &d->h.map;
    return v < m->verts.end && m->verts.ins[v] != ST_FREE_LEVEL && m->verts.ins[v] <= d->edit_level;
}

void st_doc_select(st_doc *d, const uint32_t *vids, uint32_t n, int mode)
{
    if (!d->loaded) return;
    ed_finish_active(d);
    uint32_t *keep = NULL, nk = 0;
    if (mode == ST_SELECT_REMOVE) {
        uint32_t *rm = malloc((size_t)(n ? n : 1) * sizeof *rm);
        if (!rm) abort();
        if (n) memcpy(rm, vids, (size_t)n * sizeof *rm);
        qsort(rm, n, sizeof *rm, cmp_u32);
        uint32_t j = 0;
        for (uint32_t i = 0; i < d->nsel; i++) {
            uint32_t lo = 0, hi = n;
            while (lo < hi) { uint32_t mid = (lo + hi) / 2; if (rm[mid] < d->sel[i]) lo = mid + 1; else hi = mid; }
            if (!(lo < n && rm[lo] == d->sel[i])) d->sel[j++] = d->sel[i];
        }
        d->nsel = j;
        free(rm);
        d->change.bits |= ST_CHANGE_SELECTION;
        return;
    }
    uint64_t total = (uint64_t)n + (mode == ST_SELECT_ADD ? d->nsel : 0);
    keep = malloc((size_t)(total ? total : 1) * sizeof *keep);
    if (!keep) abort();
    if (mode == ST_SELECT_ADD && d->nsel) { memcpy(keep, d->sel, (size_t)d->nsel * sizeof *keep); nk = d->nsel; }
    for (uint32_t i = 0; i < n; i++)
        if (edit_vertex_ok(d, vids[i])) keep[nk++] = vids[i];
    qsort(keep, nk, sizeof *keep, cmp_u32);
    uint32_t j = 0;
    for (uint32_t i = 0; i < nk; i++)
        if (j == 0 || keep[j - 1] != keep[i]) keep[j++] = keep[i];
    free(d->sel);
    d->sel = keep;
    d->nsel = j;
    d->capsel = (uint32_t)(total ? total : 1);
    d->change.bits |= ST_CHANGE_SELECTION;
}

void st_doc_vertex_pos(const st_doc *d, uint32_t vid, double p[3])
{
    if (!d->loaded || !edit_vertex_ok(d, vid)) { p[0] = p[1] = p[2] = 0; return; }
    if (d->hd_level) memcpy(p, st_pos(&d->display.hier.map, vid, d->hd_level), 3 * sizeof *p);
    else memcpy(p, st_pos(&d->h.map, vid, d->edit_level), 3 * sizeof *p);
}

const uint32_t *ed_vertex_darts(st_doc *d, uint32_t *n)
{
    unsigned l = d->edit_level;
    if (d->vdart_level != (int)l) {
        /* Sized by the largest vertex id of the level, not of the map: the
         * ids of finer levels come later.  A real face's dart preferred
         * (core/sculpt/sculpt.h). */
        free(d->vdart);
        d->vdart = st_sculpt_vertex_darts(&d->h.map, l, &d->nvdart);
        if (!d->vdart) abort();
        d->vdart_level = (int)l;
    }
    *n = d->nvdart;
    return d->vdart;
}

uint32_t ed_vertex_dart(st_doc *d, uint32_t vid)
{
    if (!d->loaded || !edit_vertex_ok(d, vid)) return ST_NIL;
    if (d->hd_level) return d->hd_vdart[vid];
    uint32_t n;
    const uint32_t *vd = ed_vertex_darts(d, &n);
    return vid < n ? vd[vid] : ST_NIL;
}

uint32_t st_doc_vertex_dart(st_doc *d, uint32_t vid) { return ed_vertex_dart(d, vid); }

/* ---- change tracking ---------------------------------------------------------------- */

static void change_add_darts(st_doc *d, unsigned l, const uint32_t *darts, uint32_t n)
{
    st_doc_change *c = &d->change;
    if (!(c->bits & ST_CHANGE_POSITIONS)) {
        c->bits |= ST_CHANGE_POSITIONS;
        c->moved_level = l;
        c->nmoved = 0;
    } else if (c->moved_level != l) {
        c->bits |= ST_CHANGE_ALL_POSITIONS;
    }
    (void)darts; /* which vertices moved is in the footprint (fp_model); the count is what is read */
    c->nmoved += n;
}

void ed_geometry_changed(st_doc *d, unsigned l, const uint32_t *darts, uint32_t n, double t0, uint32_t from)
{
    if (ed_display_on(d)) {
        if (from <= d->fp_model.n) {
            st_box_display_follow_edit(&d->display, &d->h, d->fp_model.keys + from, d->fp_model.n - from);
            d->change.bits |= ST_CHANGE_DISPLAY;
        } else {
            st_box_display_follow_model(&d->display, &d->h, l);
            d->change.bits |= ST_CHANGE_ALL_POSITIONS;
        }
    }
    change_add_darts(d, l, darts, n);
    double now = ed_now_ms();
    d->last_update_ms = now - t0;
    d->last_update_at_ms = now;
}

st_doc_change st_doc_take_change(st_doc *d)
{
    /* The footprints handed out stay valid until the next take. */
    st_footprint t = d->fp_taken[0];
    d->fp_taken[0] = d->fp_model;
    d->fp_model = t;
    d->fp_model.n = 0;
    t = d->fp_taken[1];
    d->fp_taken[1] = d->display.written;
    d->display.written = t;
    d->display.written.n = 0;
    st_doc_change c = d->change;
    c.disp_vids = d->display.moved;
    c.ndisp = d->display.nmoved;
    d->display.nmoved = 0;
    c.footprint = &d->fp_taken[0];
    if (d->mask_all) c.nmask_vids = 0;
    d->mask_all = 0;
    d->change.nmask_vids = 0;
    c.disp_footprint = &d->fp_taken[1];
    d->change.bits = 0;
    d->change.nmoved = 0;
    d->change.ndisp = 0;
    d->change.moved_level = 0;
    return c;
}

/* The counts of the box's display at its top level without a walk: an
 * adaptive refinement of level 0 keeps its surface, so V - E + F (real
 * faces, taken once when the display was built) and the holes are level 0's, every live dart and vertex is there
 * at the top, and each edge has two darts (hole faces included): F =
 * euler - V + D / 2.  A walk of a million-face display took a third of a
 * box move (bench_hd). */
static int display_counts_fast(st_doc *d, st_level_stats *s)
{
    if (d->h.scheme->id == ST_SCHEME_PROGRESSIVE) return 0;
    const st_map *m = &d->display.hier.map;
    uint64_t darts = 0, verts = 0;
    for (unsigned l = 0; l <= m->top; l++) {
        darts += m->darts.live[l];
        verts += m->verts.live[l];
    }
    memset(s, 0, sizeof *s);
    s->vertices = verts;
    s->faces = (uint64_t)(d->display.euler0 - (int64_t)verts + (int64_t)(darts / 2));
    return 1;
}

void ed_count_display(st_doc *d)
{
    d->disp_faces = d->disp_verts = 0;
    if (!d->loaded) return;
    st_level_stats s;
    if (ed_display_on(d)) {
        if (!display_counts_fast(d, &s)) st_level_stats_compute(&d->display.hier.map, d->display.hier.map.top, &s);
    } else {
        st_level_stats_compute(&d->h.map, d->display_level, &s);
    }
    d->disp_faces = s.faces;
    d->disp_verts = s.vertices;
}

void ed_topology_changed(st_doc *d)
{
    d->vdart_level = -1;
    /* Footprints name vertices of the old topology; the window rebuilds. */
    d->fp_model.n = 0;
    d->display.written.n = 0;
    d->change.bits |= ST_CHANGE_TOPOLOGY | ST_CHANGE_ALL_POSITIONS;
    if (d->nsel) d->change.bits |= ST_CHANGE_SELECTION;
    d->nsel = 0;
    if (d->loaded) clamp_levels(d);
    /* The model's levels changed: the display is built again, without the
     * HD state (the operations that would drop HD detail are refused
     * first, ed_hd_blocks). */
    if (d->hd) {
        ed_hd_forget(d);
        if (!d->box_on) st_box_display_drop(&d->display);
    }
    if (d->box_on) {
        st_error err;
        if (display_build(d, &d->box, &err)) {
            d->box_on = 0;
            st_box_display_drop(&d->display);
            snprintf(d->note, sizeof d->note, "interest box off: %.200s", err.msg);
        }
    }
    ed_count_display(d);
}

/* The displayed level changed, the model did not. */
static void display_changed(st_doc *d)
{
    d->change.bits |= ST_CHANGE_TOPOLOGY | ST_CHANGE_ALL_POSITIONS;
    ed_count_display(d);
}

void st_doc_display_counts(const st_doc *d, uint64_t *faces, uint64_t *verts)
{
    if (faces) *faces = d->disp_faces;
    if (verts) *verts = d->disp_verts;
}

const st_hier *st_doc_display_hier(const st_doc *d)
{
    return ed_display_on(d) ? &d->display.hier : &d->h;
}

unsigned st_doc_display_map_level(const st_doc *d)
{
    return ed_display_on(d) ? d->display.hier.map.top : d->display_level;
}

uint32_t st_doc_display_to_edit_vertex(const st_doc *d, uint32_t dv)
{
    if (!d->loaded) return ST_NIL;
    if (!ed_display_on(d) || d->hd_level) return edit_vertex_ok(d, dv) ? dv : ST_NIL;
    uint32_t v = st_box_display_model_vertex(&d->display, dv);
    return v != ST_NIL && edit_vertex_ok(d, v) ? v : ST_NIL;
}

/* ---- interest box -------------------------------------------------------------------------- */

/* Bytes the box's display of p needs beside the model: a copy of the
 * model (cut to the base), then the adaptive refinement inside the box
 * (core/adapt/adapt_estimate.h, estimated from level 0). */
static size_t box_display_bytes(st_doc *d, const st_adapt_params *p)
{
    return ed_hier_bytes(&d->h) + st_adapt_estimate_bytes(&d->h, p);
}

unsigned st_doc_box_max_level_allowed(st_doc *d, const st_adapt_params *p)
{
    if (!d->loaded) return p->base_level;
    size_t have = ed_hier_bytes(&d->h);   /* the model; a display being replaced does not count */
    /* Three levels past the top; with the base at the top (HD levels,
     * editor_hd.c: the box then only adds levels where it is) as high as
     * the map's level limit and the budget allow, with the estimate
     * doubled past the three: at a dozen levels it is the least sure, and
     * a box over a whole model reaches the budget there. */
    unsigned top = d->h.map.top, three = top + 3 < ST_MAX_LEVELS ? top + 3 : ST_MAX_LEVELS - 1;
    int hd = p->base_level >= top && !st_doc_hd_refusal(d);
    unsigned limit = hd ? ST_MAX_LEVELS - 1 : three;
    st_adapt_params q = *p;
    unsigned m = p->base_level;
    for (unsigned l = p->base_level + 1; l <= limit; l++) {
        q.max_level = l;
        size_t need = box_display_bytes(d, &q);
        if (l > three) need = need > SIZE_MAX / 2 ? SIZE_MAX : 2 * need;
        if (need > d->mem_budget || have + need > d->mem_budget) break;
        m = l;
    }
    return m;
}

/* The box's display of p within the memory budget, whether it is built
 * anew or moved in place (the display it replaces does not count). */
static int box_budget_check(st_doc *d, const st_adapt_params *p, st_error *err)
{
    size_t have = ed_hier_bytes(&d->h), need = box_display_bytes(d, p);
    if (have + need <= d->mem_budget) return ST_OK;
    return st_fail(err, ST_ERR_MEMORY,
                   "interest box refused: its display up to level %u needs about %zu bytes (%.1f MiB) more, the "
                   "model uses %.1f MiB and the memory budget is %.1f MiB",
                   p->max_level, need, st_mib(need), st_mib(have), st_mib(d->mem_budget));
}

/* Builds the box's display for p within the memory budget; d->box = p on
 * success. */
static int display_build(st_doc *d, const st_adapt_params *p, st_error *err)
{
    st_box_display_drop(&d->display);
    if (box_budget_check(d, p, err)) return ST_ERR_MEMORY;
    progress(d, "refining the interest box", 1, 1);
    int rc = st_box_display_build(&d->display, &d->h, p, err);
    if (!rc) d->box = *p;
    return rc;
}

int st_doc_set_box(st_doc *d, const st_adapt_params *box, int on, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    ed_finish_active(d);
    st_adapt_params p = *box;
    if (p.max_level >= ST_MAX_LEVELS) p.max_level = ST_MAX_LEVELS - 1;
    if (p.base_level > p.max_level) p.base_level = p.max_level;
    for (int k = 0; k < 3; k++)
        if (p.box_lo[k] > p.box_hi[k]) { double t = p.box_lo[k]; p.box_lo[k] = p.box_hi[k]; p.box_hi[k] = t; }
    /* With HD levels the display's base stays the model's top (editor_hd.c). */
    if (d->hd) p.base_level = d->h.map.top;
    st_adapt_params old = d->box;
    int old_on = d->box_on;
    if ((on != 0) == (old_on != 0) && (!on || d->display.built) && !memcmp(&old, &p, sizeof p)) return ST_OK;
    double t0 = ed_now_ms();
    int rc = ST_OK, patched = 0;
    if (on && box_budget_check(d, &p, err)) return ST_ERR_MEMORY;
    if (on) {
        unsigned N = d->h.map.top;
        unsigned ob = old.base_level < N ? old.base_level : N, nb = p.base_level < N ? p.base_level : N;
        if (!ed_display_on(d) || ob != nb || d->h.scheme->id == ST_SCHEME_PROGRESSIVE) {
            rc = display_build(d, &p, err);
        } else {
            /* In place: the renderer re-tessellates what the map's log
             * holds (ST_CHANGE_PATCH); moves it has not taken yet add up. */
            rc = st_box_display_move(&d->display, &d->h, &p, (d->change.bits & ST_CHANGE_PATCH) != 0, err);
            if (!rc) {
                d->box = p;
                patched = 1;
            }
        }
        if (rc) {
            /* Back to the previous display. */
            st_error e2;
            st_box_display_drop(&d->display);
            d->box = old;
            d->box_on = old_on;
            if (old_on && display_build(d, &old, &e2)) d->box_on = 0;
            ed_count_display(d);
            return rc;
        }
    } else if (ed_hd_detail_present(d)) {
        /* Box off over HD detail: the display stays, the model's top
         * everywhere except the faces that carry the detail. */
        st_adapt_params q = p;
        q.has_box = 0;
        q.flatness = 0;
        q.base_level = q.max_level = d->h.map.top;
        rc = st_box_display_move(&d->display, &d->h, &q, (d->change.bits & ST_CHANGE_PATCH) != 0, err);
        if (rc) {
            ed_hd_forget(d);
            st_box_display_drop(&d->display);
        } else {
            patched = 1;
        }
    } else {
        ed_hd_forget(d);
        st_box_display_drop(&d->display);
    }
    d->box = p;
    d->box_on = on != 0;
    if (d->hd_level) {
        /* The display's ids changed where the box went: HD selections go,
         * the HD tables are made again when next asked. */
        if (d->nsel) d->change.bits |= ST_CHANGE_SELECTION;
        d->nsel = 0;
        d->hd_tables_ok = 0;
    }
    if (patched && !(d->change.bits & ST_CHANGE_TOPOLOGY)) {
        d->change.bits |= ST_CHANGE_BOX | ST_CHANGE_PATCH;
        d->change.patch = &d->display.patch_log;
    } else {
        d->change.bits = (d->change.bits & ~(unsigned)ST_CHANGE_PATCH) | ST_CHANGE_BOX | ST_CHANGE_TOPOLOGY |
                         ST_CHANGE_ALL_POSITIONS;
    }
    ed_count_display(d);
    d->last_update_at_ms = ed_now_ms();
    d->last_update_ms = d->last_update_at_ms - t0;
    if (!d->box_recording && (old_on != d->box_on || memcmp(&old, &p, sizeof p))) {
        st_undo_step *s = ed_step_new(ED_STEP_BOX);
        s->box_old = old;
        s->on_old = old_on;
        s->box_new = p;
        s->on_new = d->box_on;
        ed_step_finish(s);
        ed_push_step(d, s);
    }
    return ST_OK;
}

void st_doc_box_begin(st_doc *d)
{
    if (d->box_recording) return;
    d->box_recording = 1;
    d->box_rec_params = d->box;
    d->box_rec_on = d->box_on;
}

void st_doc_box_end(st_doc *d)
{
    if (!d->box_recording) return;
    d->box_recording = 0;
    if (d->box_rec_on == d->box_on && !memcmp(&d->box_rec_params, &d->box, sizeof d->box)) return;
    st_undo_step *s = ed_step_new(ED_STEP_BOX);
    s->box_old = d->box_rec_params;
    s->on_old = d->box_rec_on;
    s->box_new = d->box;
    s->on_new = d->box_on;
    ed_step_finish(s);
    ed_push_step(d, s);
}

