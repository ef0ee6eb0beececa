/* Undo steps (editor_internal.h).
 *
 * An edit step (drag, stroke) stores, for every value the edit rewrote, the
 * value before and after: level-l positions and details of the moved
 * vertices, and the positions of every vertex of the levels above that
 * st_hier_edit re-synthesised.  Which ones those are, core says before the
 * edit (st_hier_edit_footprint: the edit's own region growth, recording
 * only).  Undo and redo write the stored values back (st_hier_restore), so
 * both are bit-exact whatever the floating-point history (re-synthesising
 * instead would round differently where a level was edited directly).
 *
 * Level and scheme changes store the whole other hierarchy (editor_clone.c)
 * and swap it in and out; box steps store the old and new parameters.
 * Adding a level stores nothing: undo removes it and redo refines again,
 * taking the id blocks in their first order, so the ids are the same
 * (checked).  Removing the finest level stores that level's positions and
 * details, restored after the same refinement.
 *
 * The document's history (st_doc_undo, st_doc_redo) is bounded by
 * undo_budget bytes; the oldest steps go first, and a single step larger
 * than the budget is not kept (d->note says so). */
#include "editor_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void rec_index_free(st_undo_step *s);

st_undo_step *ed_step_new(int kind)
{
    st_undo_step *s = calloc(1, sizeof *s);
    if (!s) abort();
    s->kind = kind;
    /* The usual operation of each kind; the others name theirs (a brush
     * stroke, the coarsest level removed, a rebuild). */
    static const char *const names[] = { [ED_STEP_EDIT] = "move", [ED_STEP_HIER] = "scheme change",
                                         [ED_STEP_BOX] = "interest box", [ED_STEP_ADD] = "add level",
                                         [ED_STEP_RMTOP] = "delete the finest level" };
    s->name = kind >= 0 && kind < (int)(sizeof names / sizeof names[0]) ? names[kind] : "edit";
    return s;
}

const char *st_doc_undo_name(const st_doc *d)
{
    return d->undo_pos ? d->undo[d->undo_pos - 1]->name : NULL;
}

const char *st_doc_redo_name(const st_doc *d)
{
    return d->undo_pos < d->nundo ? d->undo[d->undo_pos]->name : NULL;
}

void ed_step_free(st_undo_step *s)
{
    if (!s) return;
    free(s->key);
    free(s->oldv);
    free(s->newv);
    rec_index_free(s);
    free(s->moved);
    free(s->vids);
    free(s->vpos);
    free(s->det);
    if (s->kind == ED_STEP_HIER) st_hier_free(&s->snap);
    ed_step_free(s->lay);
    if (s->has_layers) {
        st_layers_free(&s->layers_old);
        st_layers_free(&s->layers_new);
    }
    st_mask_free(&s->mask_old);
    st_mask_free(&s->mask_new);
    free(s);
}

/* ---- recording: which values a step holds already ----------------------------
 *
 * A key is a vertex id in its low 32 bits under a "plane" in the high ones
 * (core/map/footprint.h: level and kind; ed_layer_key: layer slot and
 * level).  Each plane the step records in has a bitset over vertex ids, so
 * "already recorded in this step" is one bit test: no hashing, and a
 * stroke's recording reads a few small arrays (a level-6 blub's 455k ids
 * take 57 KB per plane) instead of probing a table of all its keys.  The
 * bitsets are dropped when the step is finished; keys appended before the
 * index existed are indexed on the next lookup (nindexed). */
struct ed_rec_plane {
    uint32_t plane;            /* key >> 32 */
    uint32_t nwords;
    uint64_t *bits;
};

static struct ed_rec_plane *rec_plane(st_undo_step *s, uint32_t plane)
{
    if (s->lastplane < s->nplanes && s->planes[s->lastplane].plane == plane) return &s->planes[s->lastplane];
    for (uint32_t i = 0; i < s->nplanes; i++)
        if (s->planes[i].plane == plane) {
            s->lastplane = i;
            return &s->planes[i];
        }
    if (s->nplanes == s->capplanes) {
        uint32_t cap = s->capplanes ? 2 * s->capplanes : 8;
        struct ed_rec_plane *p = realloc(s->planes, (size_t)cap * sizeof *p);
        if (!p) abort();
        s->planes = p;
        s->capplanes = cap;
    }
    struct ed_rec_plane *p = &s->planes[s->nplanes];
    p->plane = plane;
    p->nwords = 0;
    p->bits = NULL;
    s->lastplane = s->nplanes++;
    return p;
}

/* Sets the bit of key; returns its previous value. */
static int rec_test_set(st_undo_step *s, uint64_t key)
{
    struct ed_rec_plane *p = rec_plane(s, (uint32_t)(key >> 32));
    uint32_t vid = (uint32_t)key, w = vid >> 6;
    if (w >= p->nwords) {
        /* Geometric growth: ids arrive in any order during a stroke. */
        uint32_t nw = p->nwords ? 2 * p->nwords : 64;
        if (nw <= w) nw = w + 1;
        uint64_t *b = realloc(p->bits, (size_t)nw * sizeof *b);
        if (!b) abort();
        memset(b + p->nwords, 0, (size_t)(nw - p->nwords) * sizeof *b);
        p->bits = b;
        p->nwords = nw;
    }
    uint64_t m = 1ull << (vid & 63);
    int was = (p->bits[w] & m) != 0;
    p->bits[w] |= m;
    return was;
}

static void rec_index_free(st_undo_step *s)
{
    for (uint32_t i = 0; i < s->nplanes; i++) free(s->planes[i].bits);
    free(s->planes);
    s->planes = NULL;
    s->nplanes = s->capplanes = s->nindexed = s->lastplane = 0;
}

/* Index of key, appending it (value: *fresh = 1) when absent.  Only a fresh
 * key's index is used (its old value is written there). */
static uint32_t lookup(st_undo_step *s, uint64_t key, int *fresh)
{
    while (s->nindexed < s->n) (void)rec_test_set(s, s->key[s->nindexed++]);
    if (rec_test_set(s, key)) {
        *fresh = 0;
        return ST_NIL;
    }
    if (s->n == s->cap) {
        uint32_t cap = s->cap ? 2 * s->cap : 256;
        uint64_t *k = realloc(s->key, (size_t)cap * sizeof *k);
        double(*o)[3] = realloc(s->oldv, (size_t)cap * sizeof *o);
        if (!k || !o) abort();
        s->key = k;
        s->oldv = o;
        s->cap = cap;
    }
    s->key[s->n] = key;
    s->nindexed = s->n + 1;
    *fresh = 1;
    return s->n++;
}

int ed_step_touch_pos(st_undo_step *s, const st_hier *h, unsigned level, uint32_t vid)
{
    int fresh;
    uint32_t i = lookup(s, st_fp_key(level, ST_FP_POS, vid), &fresh);
    if (fresh) memcpy(s->oldv[i], st_pos(&h->map, vid, level), sizeof s->oldv[i]);
    return fresh;
}

void ed_step_touch_detail(st_undo_step *s, const st_hier *h, unsigned level, uint32_t vid)
{
    int fresh;
    uint32_t i = lookup(s, st_fp_key(level, ST_FP_DETAIL, vid), &fresh);
    if (fresh) st_hier_value(h, st_fp_key(level, ST_FP_DETAIL, vid), s->oldv[i]);
}

void ed_step_add_moved(st_undo_step *s, const st_map *m, unsigned level, uint32_t dart)
{
    /* Deduplication is the caller's: ed_step_touch_move adds a vertex when
     * its level-l position is recorded for the first time. */
    (void)m;
    (void)level;
    if (s->nmoved == s->capmoved) {
        uint32_t cap = s->capmoved ? 2 * s->capmoved : 64;
        uint32_t *p = realloc(s->moved, (size_t)cap * sizeof *p);
        if (!p) abort();
        s->moved = p;
        s->capmoved = cap;
    }
    s->moved[s->nmoved++] = dart;
}

/* ---- footprint of an edit ---------------------------------------------------- */

void ed_step_touch_move(st_undo_step *s, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n,
                        st_footprint *scratch)
{
    const st_map *m = &h->map;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = st_vert(m, darts[i], l);
        if (ed_step_touch_pos(s, h, l, v)) ed_step_add_moved(s, m, l, darts[i]);
        if (l > 0) ed_step_touch_detail(s, h, l, v);
    }
    /* The levels above, as core will write them. */
    scratch->n = 0;
    st_hier_edit_footprint(h, l, darts, n, scratch);
    for (uint32_t i = 0; i < scratch->n; i++) {
        uint64_t k = scratch->keys[i];
        if (st_fp_level(k) > l) ed_step_touch_pos(s, h, st_fp_level(k), st_fp_vid(k));
    }
}

/* ---- layer values (editor_layers.c) -------------------------------------------- */

void ed_step_touch_layer(st_undo_step *s, const st_layers *ls, int slot, unsigned level, uint32_t vid)
{
    int fresh;
    uint32_t i = lookup(s, ed_layer_key(slot, level, vid), &fresh);
    if (fresh) st_layers_get(ls, slot, level, vid, s->oldv[i]);
}

static void layer_key_parts(uint64_t k, int *slot, unsigned *level, uint32_t *vid)
{
    *slot = (int)(uint32_t)(k >> 40) - 2;
    *level = (unsigned)(k >> 33) & 127u;
    *vid = (uint32_t)k;
}

void ed_layer_values_capture(st_undo_step *s, const st_layers *ls)
{
    free(s->newv);
    s->newv = malloc((size_t)(s->n ? s->n : 1) * sizeof *s->newv);
    if (!s->newv) abort();
    for (uint32_t i = 0; i < s->n; i++) {
        int slot;
        unsigned l;
        uint32_t v;
        layer_key_parts(s->key[i], &slot, &l, &v);
        st_layers_get(ls, slot, l, v, s->newv[i]);
    }
}

void ed_layer_values_apply(const st_undo_step *s, st_layers *ls, int which)
{
    const double(*val)[3] = which ? (const double(*)[3])s->newv : (const double(*)[3])s->oldv;
    if (!val) return;
    for (uint32_t i = 0; i < s->n; i++) {
        int slot;
        unsigned l;
        uint32_t v;
        layer_key_parts(s->key[i], &slot, &l, &v);
        if (slot < (int)ls->n) st_layers_set(ls, slot, l, v, val[i]);
    }
}

void ed_step_capture_new(st_undo_step *s, const st_hier *h)
{
    free(s->newv);
    s->newv = malloc((size_t)(s->n ? s->n : 1) * sizeof *s->newv);
    if (!s->newv) abort();
    for (uint32_t i = 0; i < s->n; i++) st_hier_value(h, s->key[i], s->newv[i]);
}

void ed_step_apply(const st_undo_step *s, st_hier *h, int which, st_footprint *fp)
{
    const double(*v)[3] = which ? (const double(*)[3])s->newv : (const double(*)[3])s->oldv;
    if (!v) return;
    st_hier_restore(h, s->key, v, s->n, fp);
}

void ed_step_finish(st_undo_step *s)
{
    rec_index_free(s);
    s->bytes = sizeof *s + (size_t)s->n * (sizeof *s->key + 2 * sizeof *s->oldv) + (size_t)s->nmoved * sizeof *s->moved;
    if (s->kind == ED_STEP_HIER) s->bytes += ed_hier_bytes(&s->snap);
    if (s->lay) {
        ed_step_finish(s->lay);
        s->bytes += s->lay->bytes;
    }
    if (s->has_layers) s->bytes += st_layers_bytes(&s->layers_old) + st_layers_bytes(&s->layers_new);
    s->bytes += ((size_t)s->mask_old.cap + s->mask_new.cap) * sizeof(float);
    s->bytes += (size_t)s->nvids * (sizeof *s->vids + sizeof *s->vpos) + (size_t)s->detcap * 3 * sizeof(double);
}

/* ---- the document's history ------------------------------------------------------------ */

void ed_undo_clear(st_doc *d)
{
    for (uint32_t i = 0; i < d->nundo; i++) ed_step_free(d->undo[i]);
    d->nundo = d->undo_pos = 0;
    d->undo_bytes = 0;
    d->base_revision = d->revision; /* the state now is where the history starts */
}

void st_doc_forget_history(st_doc *d)
{
    ed_finish_active(d);
    ed_undo_clear(d);
}

void ed_push_step(st_doc *d, st_undo_step *s)
{
    /* The redo tail goes. */
    for (uint32_t i = d->undo_pos; i < d->nundo; i++) {
        d->undo_bytes -= d->undo[i]->bytes;
        ed_step_free(d->undo[i]);
    }
    d->nundo = d->undo_pos;
    if (d->nundo == d->capundo) {
        uint32_t cap = d->capundo ? 2 * d->capundo : 32;
        st_undo_step **p = realloc(d->undo, (size_t)cap * sizeof *p);
        if (!p) abort();
        d->undo = p;
        d->capundo = cap;
    }
    d->undo[d->nundo++] = s;
    d->undo_pos = d->nundo;
    s->serial = d->revision = ++d->last_serial;
    d->undo_bytes += s->bytes;
    /* Bounded memory: the oldest steps go first. */
    uint32_t drop = 0;
    while (drop < d->nundo && d->undo_bytes > d->undo_budget) {
        d->undo_bytes -= d->undo[drop]->bytes;
        d->base_revision = d->undo[drop]->serial;
        ed_step_free(d->undo[drop]);
        drop++;
    }
    if (drop) {
        memmove(d->undo, d->undo + drop, (size_t)(d->nundo - drop) * sizeof *d->undo);
        d->nundo -= drop;
        d->undo_pos -= drop;
        snprintf(d->note, sizeof d->note, "undo history: %u oldest step%s dropped (budget %.1f MiB)", drop,
                 drop > 1 ? "s" : "", st_mib(d->undo_budget));
    }
}

static void apply_hier_step(st_doc *d, st_undo_step *s)
{
    ed_hier_swap(&d->h, &s->snap);
    const st_scheme *sc = d->scheme;
    unsigned el = d->edit_level, dl = d->display_level;
    int rb = d->rebased;
    d->scheme = s->scheme;
    d->edit_level = s->edit_level;
    d->display_level = s->display_level;
    d->rebased = s->rebased;
    s->scheme = sc;
    s->edit_level = el;
    s->display_level = dl;
    s->rebased = rb;
    st_adapt_params bx = d->box;
    d->box = s->box_old;
    s->box_old = bx;
    d->opts = d->h.opts;
    /* The layers and the mask belong to their hierarchy. */
    st_layers lt = d->layers;
    d->layers = s->layers_old;
    s->layers_old = lt;
    st_mask mt = d->mask;
    d->mask = s->mask_old;
    s->mask_old = mt;
    ed_topology_changed(d);
    ed_mask_changed(d, NULL, 0);
}

/* Drops the steps after s (s is being redone). */
static void drop_redo_after(st_doc *d, st_undo_step *s)
{
    uint32_t i = 0;
    while (i < d->nundo && d->undo[i] != s) i++;
    for (uint32_t k = i + 1; k < d->nundo; k++) {
        d->undo_bytes -= d->undo[k]->bytes;
        ed_step_free(d->undo[k]);
    }
    if (i < d->nundo) d->nundo = i + 1;
}

/* Undo of a top removal: the level again, then its values. */
static int rmtop_undo(st_doc *d, st_undo_step *s, st_error *err)
{
    st_hier *h = &d->h;
    unsigned top = h->map.top;
    int rc = st_hier_subdivide_to(h, top + 1, err);
    if (rc) {
        while (h->map.top > top) st_hier_remove_top(h);
        return rc;
    }
    if (ed_top_ids_sum(&h->map) != s->idsum) {
        ed_remove_top_keep_order(h);
        return st_fail(err, ST_ERR_INVALID, "undo: the level came back with other ids; not restored");
    }
    unsigned L = top + 1;
    for (uint32_t i = 0; i < s->nvids; i++) st_hier_set_value(h, st_fp_key(L, ST_FP_POS, s->vids[i]), s->vpos[i]);
    free(h->detail[L]);
    h->detail[L] = NULL;
    h->detail_cap[L] = 0;
    if (s->det) {
        double *p = malloc((size_t)s->detcap * 3 * sizeof *p);
        if (!p) return st_fail(err, ST_ERR_MEMORY, "out of memory");
        memcpy(p, s->det, (size_t)s->detcap * 3 * sizeof *p);
        h->detail[L] = p;
        h->detail_cap[L] = s->detcap;
    }
    return ST_OK;
}

static int apply_step(st_doc *d, st_undo_step *s, int redo, st_error *err)
{
    switch (s->kind) {
    case ED_STEP_EDIT: {
        if (s->hd) {
            ed_hd_step_apply(d, s, redo);
            return ST_OK;
        }
        double t0 = ed_now_ms();
        uint32_t from = d->fp_model.n;
        ed_step_apply(s, &d->h, redo, &d->fp_model);
        if (s->lay) ed_layer_values_apply(s->lay, &d->layers, redo);
        ed_step_apply_extra(d, s, redo);
        ed_geometry_changed(d, s->level, s->moved, s->nmoved, t0, from);
        /* No vertex of its own level moved (a filter, ui/doc/editor_filter.c):
         * the levels above changed everywhere, not around moved vertices. */
        if (!s->nmoved && s->n) d->change.bits |= ST_CHANGE_ALL_POSITIONS;
        return ST_OK;
    }
    case ED_STEP_HIER:
        apply_hier_step(d, s);
        return ST_OK;
    case ED_STEP_RMTOP: {
        double t0 = ed_now_ms();
        if (!redo) {
            int rc = rmtop_undo(d, s, err);
            if (rc) { ed_topology_changed(d); return rc; }
            d->edit_level = s->edit_level;
            d->display_level = s->display_level;
            d->box = s->box_old;
        } else {
            ed_remove_top_keep_order(&d->h);
            d->edit_level = s->edit_after;
            d->display_level = s->display_after;
        }
        ed_topology_done(d, t0);
        return ST_OK;
    }
    case ED_STEP_ADD: {
        double t0 = ed_now_ms();
        if (!redo) {
            ed_remove_top_keep_order(&d->h);
            d->edit_level = s->edit_level;
            d->display_level = s->display_level;
            d->box = s->box_old;
        } else {
            unsigned top = d->h.map.top;
            int rc = st_hier_subdivide_to(&d->h, top + 1, err);
            if (rc) {
                while (d->h.map.top > top) st_hier_remove_top(&d->h);
                ed_topology_changed(d);
                return rc;
            }
            if (ed_top_ids_sum(&d->h.map) != s->idsum) {
                /* Other ids than the first time: the steps after this one
                 * name vertices that no longer exist; they go. */
                drop_redo_after(d, s);
                snprintf(d->note, sizeof d->note, "redo: the level came back with other ids; later steps dropped");
            }
            ed_mask_extend(d);
            d->display_level = s->display_after;
        }
        ed_topology_done(d, t0);
        return ST_OK;
    }
    case ED_STEP_BOX: {
        int rec = d->box_recording;
        d->box_recording = 1; /* no new step */
        int rc = st_doc_set_box(d, redo ? &s->box_new : &s->box_old, redo ? s->on_new : s->on_old, err);
        d->box_recording = rec;
        return rc;
    }
    }
    return ST_OK;
}

int st_doc_undo(st_doc *d, st_error *err)
{
    ed_finish_active(d);
    if (!d->undo_pos) return -1;
    st_undo_step *s = d->undo[d->undo_pos - 1];
    int rc = apply_step(d, s, 0, err);
    if (rc) return rc;
    d->undo_pos--;
    d->revision = d->undo_pos ? d->undo[d->undo_pos - 1]->serial : d->base_revision;
    return 0;
}

int st_doc_redo(st_doc *d, st_error *err)
{
    ed_finish_active(d);
    if (d->undo_pos >= d->nundo) return -1;
    st_undo_step *s = d->undo[d->undo_pos];
    int rc = apply_step(d, s, 1, err);
    if (rc) return rc;
    d->undo_pos++;
    d->revision = s->serial;
    return 0;
}
