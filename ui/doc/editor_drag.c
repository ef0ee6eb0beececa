/* The document's drag of the selection and the end of every edit step
 * (editor.h: st_doc_drag_*; editor_internal.h: ed_edit_budget,
 * ed_take_pending, ed_push_edit, ed_finish_active): the selected vertices
 * of the editing level move by one translation through ed_model_edit (a
 * sculpt layer's edit when one is active), the old values recorded once at
 * begin; brush strokes (brush.c) and mask strokes (editor_mask.c) end
 * through the same pending step. */
#define _POSIX_C_SOURCE 200809L
#include "editor_internal.h"
#include "core/multires/estimate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int ed_edit_budget(st_doc *d, unsigned l)
{
    size_t need = st_hier_synth_estimate(&d->h, l), have = st_doc_model_bytes(d);
    d->refusal[0] = 0;
    if (have + need <= d->mem_budget) return 0;
    snprintf(d->refusal, sizeof d->refusal,
             "editing level %u refused: the synthesis of the levels above needs about %.1f MiB more, the model uses "
             "%.1f MiB and the memory budget is %.1f MiB",
             l, st_mib(need), st_mib(have), st_mib(d->mem_budget));
    return -1;
}

/* A drag at an HD level (editor_hd.c): the selection holds display
 * vertices of hd_level; their level values are recorded once, then every
 * update writes old + (1 - mask) delta through st_adapt_edit. */
static int hd_drag_begin(st_doc *d)
{
    const char *why = st_doc_hd_refusal(d);
    if (why) {
        snprintf(d->refusal, sizeof d->refusal, "%s", why);
        return -1;
    }
    ed_hd_tables(d);
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->level = d->hd_level;
    s->hd = 1;
    uint32_t *darts = malloc((size_t)d->nsel * sizeof *darts);
    if (!darts) abort();
    uint32_t n = 0;
    for (uint32_t i = 0; i < d->nsel; i++)
        if (ed_hd_vertex_ok(d, d->sel[i])) darts[n++] = d->hd_vdart[d->sel[i]];
    if (!n) { free(darts); ed_step_free(s); return -1; }
    ed_hd_record(d, s, darts, n);
    free(darts);
    if (!d->hd_cache) d->hd_cache = st_edit_cache_new();
    st_edit_cache_clear(d->hd_cache);
    d->pending = s;
    d->active = 1;
    return 0;
}

int st_doc_drag_begin(st_doc *d)
{
    if (!d->loaded) return -1;
    ed_finish_active(d);
    if (!d->nsel) return -1;
    if (d->hd_level) return hd_drag_begin(d);
    unsigned l = d->edit_level;
    if (ed_edit_budget(d, l)) return -1;
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->level = l;
    uint32_t *darts = malloc((size_t)d->nsel * sizeof *darts);
    if (!darts) abort();
    uint32_t n = 0;
    for (uint32_t i = 0; i < d->nsel; i++) {
        uint32_t x = ed_vertex_dart(d, d->sel[i]);
        /* Fully masked vertices do not move at all (bit for bit). */
        if (x != ST_NIL && st_mask_get(&d->mask, d->sel[i]) < 1.0f) darts[n++] = x;
    }
    if (!n) { free(darts); ed_step_free(s); return -1; }
    /* An edit's footprint depends on the seeds only: one query covers
     * every update of this drag. */
    ed_step_touch_move(s, &d->h, l, darts, n, &d->fp_query);
    ed_model_touch_layers(d, s, l, darts, n);
    free(darts);
    d->pending = s;
    d->active = 1;
    return 0;
}

int st_doc_drag_update(st_doc *d, const double delta[3])
{
    if (d->active != 1 || !d->pending) return -1;
    st_undo_step *s = d->pending;
    unsigned l = s->level;
    /* s->moved holds the darts in the order touched; their original
     * positions are the recorded "old" values of (l, pos, vid). */
    double t0 = ed_now_ms();
    double(*pos)[3] = malloc((size_t)(s->nmoved ? s->nmoved : 1) * sizeof *pos);
    if (!pos) abort();
    const st_map *m = s->hd ? &d->display.hier.map : &d->h.map;
    const st_mask *mk = s->hd ? &d->hd_mask : &d->mask;
    /* The first nmoved entries of the step are the moved vertices' level-l
     * positions (and details when l > 0), in the order of s->moved. */
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->n && k < s->nmoved; i++) {
        unsigned lev = (unsigned)(s->key[i] >> 33);
        int kind = (int)(s->key[i] >> 32) & 1;
        if (lev != l || kind) continue;
        uint32_t vid = (uint32_t)s->key[i];
        if (vid != st_vert(m, s->moved[k], l)) continue;
        /* The mask protects in proportion: the displacement times 1 - mask. */
        double keep = 1.0 - (double)st_mask_get(mk, vid);
        for (int c = 0; c < 3; c++) pos[k][c] = s->oldv[i][c] + keep * delta[c];
        k++;
    }
    if (s->hd) {
        ed_hd_dab_write(d, NULL, s->moved, (const double(*)[3])pos, k, t0);
        free(pos);
        return 0;
    }
    uint32_t from = d->fp_model.n;
    ed_model_edit(d, NULL, l, s->moved, (const double(*)[3])pos, k);
    free(pos);
    ed_geometry_changed(d, l, s->moved, k, t0, from);
    return 0;
}

st_undo_step *ed_take_pending(st_doc *d, int active)
{
    if (d->active != active) return NULL;
    st_undo_step *s = d->pending;
    d->pending = NULL;
    d->active = 0;
    d->edit_serial++;   /* the predictions cached during it may go stale now */
    if (s && active == 2) s->name = "brush stroke";
    if (s && active == 3) s->name = "mask stroke";
    return s;
}

void ed_push_edit(st_doc *d, st_undo_step *s)
{
    ed_step_capture_new(s, s->hd ? &d->display.hier : &d->h);
    if (s->lay) ed_layer_values_capture(s->lay, &d->layers);
    /* Nothing moved (no update, or back where it started): no step. */
    int same = 1;
    for (uint32_t i = 0; i < s->n && same; i++)
        if (memcmp(s->oldv[i], s->newv[i], sizeof s->oldv[i])) same = 0;
    if (same) { ed_step_free(s); return; }
    ed_step_finish(s);
    ed_push_step(d, s);
}

void st_doc_drag_end(st_doc *d)
{
    st_undo_step *s = ed_take_pending(d, 1);
    if (s) ed_push_edit(d, s);
}

void st_doc_drag_cancel(st_doc *d)
{
    st_undo_step *s = ed_take_pending(d, 1);
    if (!s) return;
    if (s->hd) {
        ed_hd_step_apply(d, s, 0);
        ed_step_free(s);
        return;
    }
    double t0 = ed_now_ms();
    uint32_t from = d->fp_model.n;
    ed_step_apply(s, &d->h, 0, &d->fp_model);
    ed_geometry_changed(d, s->level, s->moved, s->nmoved, t0, from);
    ed_step_free(s);
}

void ed_finish_active(st_doc *d)
{
    if (d->active == 1) st_doc_drag_end(d);
    else if (d->active == 2) st_doc_stroke_end(d);
    else if (d->active == 3) st_doc_mask_stroke_end(d);
}
