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
 * and swap it in and out; box steps store the old and new parameters. */
#include "editor_internal.h"

#include <stdlib.h>
#include <string.h>

st_undo_step *ed_step_new(int kind)
{
    st_undo_step *s = calloc(1, sizeof *s);
    if (!s) abort();
    s->kind = kind;
    return s;
}

void ed_step_free(st_undo_step *s)
{
    if (!s) return;
    free(s->key);
    free(s->oldv);
    free(s->newv);
    free(s->hkey);
    free(s->hidx);
    free(s->moved);
    free(s->vids);
    free(s->vpos);
    free(s->det);
    if (s->kind == ED_STEP_HIER) st_hier_free(&s->snap);
    free(s);
}

static uint64_t hash64(uint64_t k)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ull;
    k ^= k >> 33;
    return k;
}

#define EMPTY_KEY UINT64_MAX

static void rehash(st_undo_step *s, uint32_t cap)
{
    free(s->hkey);
    free(s->hidx);
    s->hkey = malloc((size_t)cap * sizeof *s->hkey);
    s->hidx = malloc((size_t)cap * sizeof *s->hidx);
    if (!s->hkey || !s->hidx) abort();
    for (uint32_t i = 0; i < cap; i++) s->hkey[i] = EMPTY_KEY;
    s->hcap = cap;
    for (uint32_t i = 0; i < s->n; i++) {
        uint32_t h = (uint32_t)hash64(s->key[i]) & (cap - 1);
        while (s->hkey[h] != EMPTY_KEY) h = (h + 1) & (cap - 1);
        s->hkey[h] = s->key[i];
        s->hidx[h] = i;
    }
}

/* Index of key, inserting it (value: *fresh = 1) when absent. */
static uint32_t lookup(st_undo_step *s, uint64_t key, int *fresh)
{
    if (2 * (s->n + 1) > s->hcap) rehash(s, s->hcap ? 2 * s->hcap : 1024);
    uint32_t h = (uint32_t)hash64(key) & (s->hcap - 1);
    while (s->hkey[h] != EMPTY_KEY) {
        if (s->hkey[h] == key) { *fresh = 0; return s->hidx[h]; }
        h = (h + 1) & (s->hcap - 1);
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
    s->hkey[h] = key;
    s->hidx[h] = s->n;
    s->key[s->n] = key;
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
    free(s->hkey);
    free(s->hidx);
    s->hkey = NULL;
    s->hidx = NULL;
    s->hcap = 0;
    s->bytes = sizeof *s + (size_t)s->n * (sizeof *s->key + 2 * sizeof *s->oldv) + (size_t)s->nmoved * sizeof *s->moved;
    if (s->kind == ED_STEP_HIER) s->bytes += ed_hier_bytes(&s->snap);
    s->bytes += (size_t)s->nvids * (sizeof *s->vids + sizeof *s->vpos) + (size_t)s->detcap * 3 * sizeof(double);
}
