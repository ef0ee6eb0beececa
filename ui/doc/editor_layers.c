/* Sculpt layers in the document (editor.h; core/multires/layers.h).
 *
 * The hierarchy's details are always the composition of the layers, so
 * the display, exports and sessions need nothing else.  Strokes and drags
 * at the active layer's level go into that layer (st_layers_edit); a layer
 * that is hidden or at strength 0 takes no stroke (the level's own details
 * do, and `note` says so).  A layer operation recomposes the vertices where
 * the layers concerned have offsets and re-synthesises above them locally.
 *
 * Undo: a stroke or drag records the layer values it changes next to the
 * hierarchy's (st_undo_step.lay, keyed (slot, level, vertex)); a layer
 * operation records the hierarchy's values it rewrites and the whole layer
 * stack before and after (copies: a layer costs 24 bytes per vertex of its
 * level in each).
 *
 * Layers at HD levels (above the model's top, editor_hd.c) live in the same
 * stack: their offsets are indexed by the box display's vertex ids, they
 * are edited and recomposed through core/adapt's st_adapt_edit_layered,
 * and their steps are HD steps (st_undo_step.hd).  The display keeps the
 * faces they cover refined (st_adapt.keep_layers). */
#include "editor_internal.h"
#include "core/adapt/adapt.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int ed_layer_target(st_doc *d, unsigned l)
{
    const st_layers *ls = &d->layers;
    int a = ls->active;
    if (a < 0 || (uint32_t)a >= ls->n) return -1;
    const st_layer *y = &ls->v[a];
    if (y->level != l) return -1;
    if (y->hidden || y->strength == 0) {
        snprintf(d->note, sizeof d->note, "layer '%s' is %s: the stroke went into level %u's own details", y->name,
                 y->hidden ? "hidden" : "at strength 0", l);
        return -1;
    }
    return a;
}

/* Whether a layered level lies above l (its positions are rewritten by an
 * edit at l). */
static int layers_above(const st_layers *ls, unsigned l)
{
    for (uint32_t i = 0; i < ls->n; i++)
        if (ls->v[i].level > l) return 1;
    return 0;
}

void ed_model_touch_layers(st_doc *d, st_undo_step *s, unsigned l, const uint32_t *darts, uint32_t n)
{
    st_layers *ls = &d->layers;
    if (!s || !ls->n) return;
    if (!s->lay) s->lay = ed_step_new(ED_STEP_EDIT);
    if (st_layers_on_level(ls, l)) {
        int slot = ed_layer_target(d, l);
        for (uint32_t i = 0; i < n; i++) {
            uint32_t v = st_vert(&d->h.map, darts[i], l);
            ed_step_touch_layer(s->lay, ls, slot, l, v);
            /* Level 0 keeps no positions without layers (layers.h). */
            if (l > 0) ed_step_touch_layer(s->lay, ls, ST_LAYERS_SLOT_BPOS, l, v);
        }
    }
    /* The positions kept without layers on the levels above, which follow
     * the re-synthesis (st_layers_follow): the keys are the edit's
     * footprint, just asked (ed_step_touch_move). */
    if (!layers_above(ls, l)) return;
    for (uint32_t i = 0; i < d->fp_query.n; i++) {
        uint64_t k = d->fp_query.keys[i];
        unsigned L = st_fp_level(k);
        if (L > l && st_fp_kind(k) == ST_FP_POS && ls->bpos[L])
            ed_step_touch_layer(s->lay, ls, ST_LAYERS_SLOT_BPOS, L, st_fp_vid(k));
    }
}

void ed_model_edit(st_doc *d, st_undo_step *s, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n)
{
    if (s) {
        ed_step_touch_move(s, &d->h, l, darts, n, &d->fp_query);
        ed_model_touch_layers(d, s, l, darts, n);
    }
    /* A drag or a stroke re-touches its vertices update after update:
     * their predictions come from level l-1, which does not change
     * before it ends. */
    st_edit_cache *cache = NULL;
    if (d->active == 1 || d->active == 2) {
        if (!d->ecache) d->ecache = st_edit_cache_new();
        if (d->ecache_serial != d->edit_serial) {
            st_edit_cache_clear(d->ecache);
            d->ecache_serial = d->edit_serial;
        }
        cache = d->ecache;
    }
    uint32_t from = d->fp_model.n;
    if (st_layers_on_level(&d->layers, l))
        st_layers_edit(&d->layers, &d->h, l, ed_layer_target(d, l), darts, pos, n, &d->fp_model, cache);
    else
        st_hier_edit_cached(&d->h, l, darts, pos, n, &d->fp_model, NULL, NULL, cache);
    if (layers_above(&d->layers, l)) st_layers_follow(&d->layers, &d->h, l, d->fp_model.keys + from, d->fp_model.n - from);
}

void ed_step_apply_extra(st_doc *d, const st_undo_step *s, int which)
{
    if (s->has_layers) {
        st_layers_free(&d->layers);
        if (st_layers_copy(&d->layers, which ? &s->layers_new : &s->layers_old)) abort(); /* out of memory in undo */
    }
    if (s->has_mask) {
        st_mask_free(&d->mask);
        if (st_mask_copy(&d->mask, which ? &s->mask_new : &s->mask_old)) abort();
        ed_mask_changed(d, NULL, 0);
    }
}

/* ---- layer operations -------------------------------------------------------- */

static int check_layer(const st_doc *d, int k, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    if (k < 0 || (uint32_t)k >= d->layers.n) return st_fail(err, ST_ERR_INVALID, "no sculpt layer %d", k);
    return ST_OK;
}

static st_undo_step *op_begin(st_doc *d, const char *name, st_error *err)
{
    ed_finish_active(d);
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->name = name;
    s->has_layers = 1;
    st_layers_init(&s->layers_new);
    if (st_layers_copy(&s->layers_old, &d->layers)) {
        ed_step_free(s);
        st_fail(err, ST_ERR_MEMORY, "out of memory keeping the layers for undo");
        return NULL;
    }
    return s;
}

/* Darts of level l where any of the layers in `which` (bit k: layer k) has
 * an offset, deduplicated by vertex. */
typedef struct dart_set { uint32_t *d, n, cap; } dart_set;

/* The hierarchy holding level l's layers: the model's, or the box
 * display's for an HD level. */
static st_hier *layer_hier(st_doc *d, unsigned l)
{
    return l > d->h.map.top ? &d->display.hier : &d->h;
}

static void support_of(st_doc *d, int k, dart_set *out)
{
    uint32_t *tmp = NULL, cap = 0;
    uint32_t n = st_layers_support(&d->layers, layer_hier(d, d->layers.v[k].level), k, &tmp, &cap);
    if (out->n + n > out->cap) {
        out->cap = out->n + n;
        uint32_t *p = realloc(out->d, (size_t)(out->cap ? out->cap : 1) * sizeof *p);
        if (!p) abort();
        out->d = p;
    }
    if (n) memcpy(out->d + out->n, tmp, (size_t)n * sizeof *tmp);
    out->n += n;
    free(tmp);
}

/* Records the hierarchy's values the recomposition will write (old). */
static void op_touch(st_doc *d, st_undo_step *s, unsigned l, const dart_set *ds)
{
    s->level = l;
    if (l > d->h.map.top) {
        /* An HD step: the level's values, the levels above re-synthesise
         * around them on undo (ed_hd_step_apply). */
        s->hd = 1;
        ed_hd_record_values(d, s, ds->d, ds->n);
        return;
    }
    if (ds->n) ed_step_touch_move(s, &d->h, l, ds->d, ds->n, &d->fp_query);
}

/* Writes level l's sums again over ds's vertices, and tells the document. */
static void recompose(st_doc *d, unsigned l, const dart_set *ds, double t0)
{
    if (!ds->n) return;
    if (l > d->h.map.top) {
        ed_hd_recompose(d, l, ds->d, ds->n, t0);
        return;
    }
    uint32_t from = d->fp_model.n;
    st_layers_recompose(&d->layers, &d->h, l, ds->d, ds->n, &d->fp_model);
    st_layers_follow(&d->layers, &d->h, l, d->fp_model.keys + from, d->fp_model.n - from);
    ed_geometry_changed(d, l, ds->d, ds->n, t0, from);
}

/* Recomposes, then pushes the step with the stack after. */
static int op_end(st_doc *d, st_undo_step *s, unsigned l, dart_set *ds, double t0, st_error *err)
{
    recompose(d, l, ds, t0);
    free(ds->d);
    ds->d = NULL;
    ed_step_capture_new(s, layer_hier(d, l));
    if (st_layers_copy(&s->layers_new, &d->layers)) {
        /* The operation is done but cannot be undone: no step. */
        ed_step_free(s);
        return st_fail(err, ST_ERR_MEMORY, "out of memory keeping the layers for undo (the operation was done)");
    }
    ed_step_finish(s);
    ed_push_step(d, s);
    return ST_OK;
}

int st_doc_layer_add(st_doc *d, const char *name, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    st_undo_step *s = op_begin(d, "add layer", err);
    if (!s) return ST_ERR_MEMORY;
    char auto_name[ST_LAYER_NAME];
    if (!name || !*name) {
        snprintf(auto_name, sizeof auto_name, "Layer %u", d->layers.n + 1);
        name = auto_name;
    }
    /* At an HD level the layer goes on the display's level (editor_hd.c):
     * HD mode on, so that what it covers stays refined. */
    unsigned l = st_doc_sculpt_level(d);
    if (l > d->h.map.top && ed_hd_enter(d)) {
        ed_step_free(s);
        return st_fail(err, ST_ERR_INVALID, "%s", d->refusal);
    }
    if (st_layers_add(&d->layers, layer_hier(d, l), l, name, err) < 0) {
        ed_step_free(s);
        return ST_ERR_INVALID;
    }
    dart_set ds = { 0 };
    return op_end(d, s, l, &ds, ed_now_ms(), err);
}

int st_doc_layer_set_active(st_doc *d, int k, st_error *err)
{
    if (k == -1) {
        d->layers.active = -1;
        return ST_OK;
    }
    int rc = check_layer(d, k, err);
    if (rc) return rc;
    d->layers.active = k;
    st_doc_set_edit_level(d, d->layers.v[k].level);
    return ST_OK;
}

/* A change of one layer's strength or visibility: its support recomposed. */
static int set_layer(st_doc *d, int k, double strength, int hidden, const char *name, st_error *err)
{
    int rc = check_layer(d, k, err);
    if (rc) return rc;
    st_layer *y = &d->layers.v[k];
    if (y->strength == strength && y->hidden == hidden) return ST_OK;
    double t0 = ed_now_ms();
    st_undo_step *s = op_begin(d, name, err);
    if (!s) return ST_ERR_MEMORY;
    dart_set ds = { 0 };
    support_of(d, k, &ds);
    op_touch(d, s, y->level, &ds);
    y = &d->layers.v[k];
    y->strength = strength;
    y->hidden = hidden;
    return op_end(d, s, y->level, &ds, t0, err);
}

int st_doc_layer_set_strength(st_doc *d, int k, double strength, st_error *err)
{
    if (!(strength >= 0)) strength = 0; /* also NaN */
    if (strength > ST_LAYER_STRENGTH_MAX) strength = ST_LAYER_STRENGTH_MAX;
    if (check_layer(d, k, err)) return ST_ERR_INVALID;
    return set_layer(d, k, strength, d->layers.v[k].hidden, "layer strength", err);
}

int st_doc_layer_set_hidden(st_doc *d, int k, int hidden, st_error *err)
{
    if (check_layer(d, k, err)) return ST_ERR_INVALID;
    return set_layer(d, k, d->layers.v[k].strength, hidden != 0, hidden ? "hide layer" : "show layer", err);
}

int st_doc_layer_rename(st_doc *d, int k, const char *name, st_error *err)
{
    int rc = check_layer(d, k, err);
    if (rc) return rc;
    st_undo_step *s = op_begin(d, "rename layer", err);
    if (!s) return ST_ERR_MEMORY;
    st_layers_rename(&d->layers, k, name, err);
    dart_set ds = { 0 };
    return op_end(d, s, d->layers.v[k].level, &ds, ed_now_ms(), err);
}

/* Every layer of level l: the sums there change with the order. */
static void level_support(st_doc *d, unsigned l, dart_set *ds)
{
    for (uint32_t i = 0; i < d->layers.n; i++)
        if (d->layers.v[i].level == l) support_of(d, (int)i, ds);
}

/* An operation that changes the sums of all of layer k's level: begun,
 * with what it will write recorded for undo. */
typedef struct level_op { st_undo_step *s; unsigned l; dart_set ds; double t0; } level_op;

static int level_op_begin(st_doc *d, int k, const char *name, level_op *op, st_error *err)
{
    op->t0 = ed_now_ms();
    op->s = op_begin(d, name, err);
    if (!op->s) return ST_ERR_MEMORY;
    op->l = d->layers.v[k].level;
    op->ds = (dart_set){ 0 };
    level_support(d, op->l, &op->ds);
    op_touch(d, op->s, op->l, &op->ds);
    return ST_OK;
}

int st_doc_layer_move(st_doc *d, int k, int to, st_error *err)
{
    int rc = check_layer(d, k, err);
    if (!rc) rc = check_layer(d, to, err);
    if (rc) return rc;
    if (k == to) return ST_OK;
    level_op op;
    if (level_op_begin(d, k, "reorder layers", &op, err)) return ST_ERR_MEMORY;
    st_layers_move(&d->layers, k, to, err);
    return op_end(d, op.s, op.l, &op.ds, op.t0, err);
}

int st_doc_layer_merge_down(st_doc *d, int k, st_error *err)
{
    int rc = check_layer(d, k, err);
    if (rc) return rc;
    if (k == 0) return st_fail(err, ST_ERR_INVALID, "layer '%s' is the bottom layer: nothing to merge into", d->layers.v[k].name);
    if (d->layers.v[k].level != d->layers.v[k - 1].level)
        return st_fail(err, ST_ERR_INVALID, "layers '%s' and '%s' are on different levels (%u, %u)", d->layers.v[k].name,
                       d->layers.v[k - 1].name, d->layers.v[k].level, d->layers.v[k - 1].level);
    level_op op;
    if (level_op_begin(d, k, "merge layers", &op, err)) return ST_ERR_MEMORY;
    if (st_layers_merge_down(&d->layers, k, err)) {
        free(op.ds.d);
        ed_step_free(op.s);
        return ST_ERR_INVALID;
    }
    return op_end(d, op.s, op.l, &op.ds, op.t0, err);
}

int st_doc_layer_delete(st_doc *d, int k, st_error *err)
{
    int rc = check_layer(d, k, err);
    if (rc) return rc;
    double t0 = ed_now_ms();
    st_undo_step *s = op_begin(d, "delete layer", err);
    if (!s) return ST_ERR_MEMORY;
    unsigned l = d->layers.v[k].level;
    dart_set ds = { 0 };
    support_of(d, k, &ds);
    op_touch(d, s, l, &ds);
    /* Recomposed without it first (D_l = B_l where it was the only one),
     * then taken out of the stack. */
    d->layers.v[k].hidden = 1;
    recompose(d, l, &ds, t0);
    st_layers_remove(&d->layers, k, err);
    ds.n = 0;
    return op_end(d, s, l, &ds, t0, err);
}
