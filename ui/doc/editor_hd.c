/* HD levels (editor.h, "HD levels"): sculpting above the model's top in
 * the interest box's adaptive display (Kraemer 2008 §3.2-3.3: adaptive
 * multiresolution maps, detail vectors at local levels, kept when a region
 * coarsens).
 *
 * Decisions (where the requirements leave a choice):
 *   - The display is the HD model: its levels 0..N (N the model's top)
 *     stay copies of the model's, its levels above N hold the HD details.
 *     Entering an HD level sets the box's base level to N (ZBrush shows the
 *     top subdivision level around HD geometry) and st_adapt's keep_above
 *     to N, so a face carrying HD detail never coarsens: only unsculpted
 *     faces follow the box.  With the box off the display stays shown
 *     (base N everywhere, HD faces where there is detail).
 *   - A stroke at HD level L moves only the vertices whose faces around
 *     them at L are all of level L (st_adapt_vertex_editable): the others
 *     get the mask value 1, so the brush kernel leaves them alone and the
 *     border of the refined region stays where the box's faces are.
 *   - Undo of an HD stroke keeps the level-L positions and details of the
 *     moved vertices only: writing them back and re-synthesising the levels
 *     above around them (st_hier_resynth_around) gives the same bits, since
 *     every position above an edited level is a synthesis (st_adapt_edit).
 *     Where a box update placed a vertex there with another face's stencil
 *     (st_adapt.exact is off here), the undo gives the synthesis' bits,
 *     which may differ in the last bit from the update's.
 *   - The mask brush at an HD level paints the model's top level (the
 *     editing level stays there); the HD levels take its subdivision.
 *   - At an HD level the selection holds display vertex ids of that level
 *     (those a brush may move: ed_hd_vertex_ok) and a drag writes them as
 *     a dab does; the window's cage and picking are that level's
 *     (ui/window.c).  A box move clears such a selection (ids change).
 *   - Sculpt layers at HD levels are in the document's one stack
 *     (editor_layers.c): their offsets index the display's vertices, the
 *     faces they cover stay refined (st_adapt.keep_layers) and they keep
 *     no P0 (core/multires/layers.h: an HD position is always a synthesis).
 *   - Operations that rebuild the model's levels are refused while HD
 *     detail exists; when the display is rebuilt anyway (undo past a level
 *     change, which first undoes every HD stroke after it), the HD state
 *     and the history's HD steps go (ed_hd_forget). */
#include "editor_internal.h"
#include "core/adapt/adapt.h"
#include "core/sculpt/sculpt.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int ed_display_on(const st_doc *d)
{
    return (d->box_on || d->hd) && d->display.built;
}

int st_doc_display_adaptive(const st_doc *d) { return ed_display_on(d); }

unsigned st_doc_sculpt_level(const st_doc *d) { return d->hd_level ? d->hd_level : d->edit_level; }

const char *st_doc_hd_refusal(const st_doc *d)
{
    if (!d->loaded) return "no model";
    if (!st_adapt_scheme_has_hd(d->h.scheme))
        return "HD levels need a quadrisection scheme (Catmull-Clark, Loop, Butterfly, quad/triangle)";
    if (!ed_display_on(d)) return "HD levels are refined inside the interest box: switch it on (I) first";
    return NULL;
}

const st_map *st_doc_cage_map(const st_doc *d, unsigned *level)
{
    int hd = d->hd_level && ed_display_on(d);
    *level = hd ? d->hd_level : d->edit_level;
    return hd ? &d->display.hier.map : &d->h.map;
}

unsigned st_doc_level_limit(const st_doc *d)
{
    if (!d->loaded) return 0;
    unsigned top = d->h.map.top;
    if (st_doc_hd_refusal(d)) return top;
    unsigned t = d->display.hier.map.top;
    return t > top ? t : top;
}

/* A sculpt layer on a level above the model's top. */
static int hd_layers_present(const st_layers *ls, unsigned top)
{
    for (uint32_t i = 0; i < ls->n; i++)
        if (ls->v[i].level > top) return 1;
    return 0;
}

int ed_hd_detail_present(const st_doc *d)
{
    if (!d->hd || !d->display.built) return 0;
    if (hd_layers_present(&d->layers, d->h.map.top)) return 1;
    const st_hier *h = &d->display.hier;
    for (unsigned L = d->h.map.top + 1; L <= h->map.top; L++) {
        const double *p = h->detail[L];
        for (size_t i = 0; p && i < 3 * (size_t)h->detail_cap[L]; i++)
            if (p[i] != 0) return 1;
    }
    return 0;
}

uint64_t st_doc_hd_faces(const st_doc *d)
{
    if (!ed_display_on(d)) return 0;
    uint64_t faces[ST_MAX_LEVELS] = { 0 }, bytes[ST_MAX_LEVELS];
    st_adapt_hd_levels(&d->display.hier.map, d->h.map.top, faces, bytes);
    uint64_t n = 0;
    for (unsigned L = d->h.map.top + 1; L < ST_MAX_LEVELS; L++) n += faces[L];
    return n;
}

int ed_hd_blocks(st_doc *d, const char *what, st_error *err)
{
    if (!ed_hd_detail_present(d)) return ST_OK;
    return st_fail(err, ST_ERR_INVALID,
                   "%s would drop the sculpted detail of the HD levels above level %u (undo the HD strokes, or "
                   "export the adaptive mesh, first)",
                   what, d->h.map.top);
}

/* The layers of levels above top out of a stack (their ids were the old
 * display's). */
static uint32_t strip_hd_layers(st_layers *ls, unsigned top)
{
    uint32_t dropped = 0;
    for (uint32_t k = ls->n; k-- > 0;)
        if (ls->v[k].level > top) {
            st_layers_remove(ls, (int)k, NULL);
            dropped++;
        }
    return dropped;
}

void ed_hd_forget(st_doc *d)
{
    if (!d->hd && !d->hd_level) return;
    d->hd = 0;
    d->hd_level = 0;
    unsigned top = d->h.map.top;
    uint32_t lost = strip_hd_layers(&d->layers, top);
    uint32_t k = 0, dropped = 0, pos = d->undo_pos;
    for (uint32_t i = 0; i < d->nundo; i++) {
        st_undo_step *s = d->undo[i];
        if (s->has_layers) {
            strip_hd_layers(&s->layers_old, top);
            strip_hd_layers(&s->layers_new, top);
        }
        if (s->kind == ED_STEP_EDIT && s->hd) {
            d->undo_bytes -= s->bytes;
            ed_step_free(s);
            if (i < d->undo_pos) pos--;
            dropped++;
            continue;
        }
        d->undo[k++] = s;
    }
    d->nundo = k;
    d->undo_pos = pos;
    if (dropped || lost)
        snprintf(d->note, sizeof d->note, "the HD levels were rebuilt: %u HD step%s left the history, %u HD layer%s went",
                 dropped, dropped == 1 ? "" : "s", lost, lost == 1 ? "" : "s");
}

/* ---- strokes ------------------------------------------------------------------------ */

/* The kernel's mask at hd_level: 1 on the vertices that cannot move there,
 * the display's mask (the model's, subdivided) elsewhere. */
static void hd_mask_build(st_doc *d, const st_map *m, unsigned L)
{
    const st_mask *dmk = st_mask_any(&d->mask) ? st_doc_display_mask(d) : NULL;
    st_mask *mk = &d->hd_mask;
    if (mk->cap < d->nhd_vdart) {
        float *p = realloc(mk->v, (size_t)d->nhd_vdart * sizeof *p);
        if (!p) abort();
        mk->v = p;
        mk->cap = d->nhd_vdart;
    }
    for (uint32_t v = 0; v < mk->cap; v++) {
        uint32_t x = v < d->nhd_vdart ? d->hd_vdart[v] : ST_NIL;
        int free_vertex = x != ST_NIL && st_adapt_vertex_editable((st_map *)m, x, L);
        mk->v[v] = free_vertex ? (dmk ? st_mask_get(dmk, v) : 0.0f) : 1.0f;
    }
}

void ed_hd_tables(st_doc *d)
{
    d->hd_tables_ok = 0;
    if (!d->hd_level || !d->display.built || d->hd_level > d->display.hier.map.top) return;
    d->hd_tables_ok = 1;
    const st_map *m = &d->display.hier.map;
    free(d->hd_vdart);
    d->hd_vdart = st_sculpt_vertex_darts(m, d->hd_level, &d->nhd_vdart);
    if (!d->hd_vdart) abort();
    hd_mask_build(d, m, d->hd_level);
}

int ed_hd_vertex_ok(const st_doc *d, uint32_t v)
{
    /* The tables are a cache of the display, built when first asked after
     * a change (a box move would otherwise pay a walk of the whole
     * display for them); const as far as the document's state goes. */
    if (!d->hd_tables_ok) ed_hd_tables((st_doc *)d);
    return d->hd_level && d->display.built && v < d->nhd_vdart && d->hd_vdart[v] != ST_NIL &&
           v < d->hd_mask.cap && d->hd_mask.v[v] < 1.0f;
}

int ed_hd_enter(st_doc *d)
{
    const char *why = st_doc_hd_refusal(d);
    if (!why && d->hd_level > d->display.hier.map.top) why = "the HD level is above the interest box's maximum level";
    if (why) {
        snprintf(d->refusal, sizeof d->refusal, "%s", why);
        return -1;
    }
    st_box_display *bd = &d->display;
    bd->adapt.keep_above = d->h.map.top;
    bd->adapt.keep_layers = &d->layers;
    /* (st_adapt.exact stays off: its canonical pass made a box jump
     * across a level-10 model nine times as slow, bench_hd 21 s against
     * 2.3 s; box updates then place new vertices with the stencil of the
     * face that made them, last bits apart from a full synthesis) */
    d->hd = 1;
    d->refusal[0] = 0;
    return 0;
}

int ed_hd_stroke_begin(st_doc *d)
{
    if (ed_hd_enter(d)) return -1;
    ed_hd_tables(d);
    if (!d->hd_cache) d->hd_cache = st_edit_cache_new();
    st_edit_cache_clear(d->hd_cache);
    return 0;
}

void ed_hd_record_values(st_doc *d, st_undo_step *s, const uint32_t *darts, uint32_t n)
{
    st_hier *dh = &d->display.hier;
    unsigned L = s->level;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = st_vert(&dh->map, darts[i], L);
        if (ed_step_touch_pos(s, dh, L, v)) ed_step_add_moved(s, &dh->map, L, darts[i]);
        ed_step_touch_detail(s, dh, L, v);
    }
}

void ed_hd_record(st_doc *d, st_undo_step *s, const uint32_t *darts, uint32_t n)
{
    ed_hd_record_values(d, s, darts, n);
    unsigned L = s->level;
    if (!st_layers_on_level(&d->layers, L)) return;
    /* The one slot the edit changes (B_L or the active layer's offsets);
     * no P0 at HD levels. */
    if (!s->lay) s->lay = ed_step_new(ED_STEP_EDIT);
    int slot = ed_layer_target(d, L);
    for (uint32_t i = 0; i < n; i++)
        ed_step_touch_layer(s->lay, &d->layers, slot, L, st_vert(&d->display.hier.map, darts[i], L));
}

void ed_hd_recompose(st_doc *d, unsigned l, const uint32_t *darts, uint32_t n, double t0)
{
    st_box_display *bd = &d->display;
    uint32_t from = bd->written.n;
    st_adapt_edit_layered(&bd->hier, &d->layers, -1, l, darts, NULL, n, &bd->written, NULL);
    st_box_display_written(bd, from);
    d->change.bits |= ST_CHANGE_DISPLAY;
    double now = ed_now_ms();
    d->last_update_ms = now - t0;
    d->last_update_at_ms = now;
}

void ed_hd_dab_write(st_doc *d, st_undo_step *s, const uint32_t *darts, const double (*pos)[3], uint32_t n, double t0)
{
    st_box_display *bd = &d->display;
    st_hier *dh = &bd->hier;
    unsigned L = d->hd_level;
    if (s) ed_hd_record(d, s, darts, n);
    uint32_t from = bd->written.n;
    int slot = st_layers_on_level(&d->layers, L) ? ed_layer_target(d, L) : -1;
    st_adapt_edit_layered(dh, &d->layers, slot, L, darts, pos, n, &bd->written, d->hd_cache);
    st_box_display_written(bd, from);
    d->change.bits |= ST_CHANGE_DISPLAY;
    double now = ed_now_ms();
    d->last_update_ms = now - t0;
    d->last_update_at_ms = now;
}

/* st_hier_restore as an HD edit writes (st_adapt_edit): a position with
 * st_set_pos, so that the levels above that still show the value being
 * replaced follow it back (a vertex whose finer faces coarsened away keeps
 * columns there that only inherit). */
static void hd_restore(st_hier *h, const uint64_t *keys, const double (*v)[3], uint32_t n, st_footprint *fp)
{
    for (uint32_t i = 0; i < n; i++) {
        if (st_fp_kind(keys[i]) == ST_FP_POS) st_set_pos(&h->map, st_fp_vid(keys[i]), st_fp_level(keys[i]), v[i]);
        else st_hier_set_value(h, keys[i], v[i]);
        st_footprint_add(fp, keys[i]);
    }
}

void ed_hd_step_apply(st_doc *d, const st_undo_step *s, int redo)
{
    if (!d->display.built) return; /* (ed_hd_forget removes the steps before the display goes) */
    double t0 = ed_now_ms();
    st_box_display *bd = &d->display;
    const double(*v)[3] = redo ? (const double(*)[3])s->newv : (const double(*)[3])s->oldv;
    uint32_t from = bd->written.n;
    if (v) hd_restore(&bd->hier, s->key, v, s->n, &bd->written);
    /* The layers' values go back with the level's (the composed details
     * just restored are their sums). */
    if (s->lay) ed_layer_values_apply(s->lay, &d->layers, redo);
    ed_step_apply_extra(d, s, redo);
    st_hier_resynth_around(&bd->hier, s->level, s->moved, s->nmoved, &bd->written);
    st_box_display_written(bd, from);
    d->change.bits |= ST_CHANGE_DISPLAY;
    double now = ed_now_ms();
    d->last_update_ms = now - t0;
    d->last_update_at_ms = now;
}

int st_doc_adopt_hd(st_doc *d, st_hier *hd, st_adapt *hd_adapt, st_layers *hd_layers, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    if (!st_adapt_scheme_has_hd(d->h.scheme)) return st_fail(err, ST_ERR_INVALID, "%s", st_doc_hd_refusal(d));
    for (uint32_t i = 0; hd_layers && i < hd_layers->n; i++)
        if (hd_layers->v[i].level <= d->h.map.top || hd_layers->v[i].level > hd->map.top)
            return st_fail(err, ST_ERR_INVALID, "HD layer '%s' is on level %u, outside the HD levels %u..%u",
                           hd_layers->v[i].name, hd_layers->v[i].level, d->h.map.top + 1, hd->map.top);
    if (hd_layers && d->layers.n + hd_layers->n > ST_LAYER_MAX)
        return st_fail(err, ST_ERR_INVALID, "%u sculpt layers with the HD levels' (at most %d)", d->layers.n + hd_layers->n,
                       ST_LAYER_MAX);
    int rc = st_box_display_adopt(&d->display, &d->h, hd, hd_adapt, err);
    if (rc) return rc;
    /* (the levels differ from the model's layers', checked above) */
    if (hd_layers && st_layers_append(&d->layers, hd_layers, err)) return ST_ERR_MEMORY;
    d->display.adapt.keep_above = d->h.map.top;
    d->display.adapt.keep_layers = &d->layers;
    d->display.adapt.exact = 0; /* (as ed_hd_stroke_begin says) */
    d->hd = 1;
    d->box.base_level = d->h.map.top;
    d->change.bits |= ST_CHANGE_TOPOLOGY | ST_CHANGE_ALL_POSITIONS;
    ed_count_display(d);
    return ST_OK;
}

st_hier *st_doc_hd_bake_source(st_doc *d, unsigned *level)
{
    if (!d->loaded || *level != d->h.map.top || !ed_hd_detail_present(d)) return NULL;
    *level = d->display.hier.map.top;
    return &d->display.hier;
}
