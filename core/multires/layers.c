/* Sculpt layers (layers.h): offsets in local frames per layer, composed
 * into the hierarchy's details of their level.  The hierarchy is edited
 * through st_hier_edit_with, whose hook sees each moved vertex's new detail
 * and stores the composition instead. */
#include "core/multires/layers.h"
#include "core/multires/hier_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double zero3[3];
static const double none3[3] = { NAN, NAN, NAN };

void st_layers_init(st_layers *ls)
{
    memset(ls, 0, sizeof *ls);
    ls->active = -1;
}

void st_layers_free(st_layers *ls)
{
    for (uint32_t i = 0; i < ls->n; i++) free(ls->v[i].off);
    free(ls->v);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        free(ls->base[l]);
        free(ls->bpos[l]);
    }
    st_layers_init(ls);
}

static double *dup3(const double *p, uint32_t cap, int *fail)
{
    if (!p || !cap) return NULL;
    double *q = malloc(3 * (size_t)cap * sizeof *q);
    if (!q) { *fail = 1; return NULL; }
    memcpy(q, p, 3 * (size_t)cap * sizeof *q);
    return q;
}

int st_layers_copy(st_layers *dst, const st_layers *src)
{
    st_layers_init(dst);
    int fail = 0;
    if (src->n) {
        dst->v = calloc(src->n, sizeof *dst->v);
        if (!dst->v) return -1;
        dst->cap = src->n;
    }
    for (uint32_t i = 0; i < src->n; i++) {
        dst->v[i] = src->v[i];
        dst->v[i].off = dup3(src->v[i].off, src->v[i].cap, &fail);
        if (!dst->v[i].off) dst->v[i].cap = 0;
        dst->n = i + 1;
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        dst->base[l] = dup3(src->base[l], src->base_cap[l], &fail);
        dst->base_cap[l] = dst->base[l] ? src->base_cap[l] : 0;
        dst->bpos[l] = dup3(src->bpos[l], src->bpos_cap[l], &fail);
        dst->bpos_cap[l] = dst->bpos[l] ? src->bpos_cap[l] : 0;
    }
    dst->active = src->active;
    if (fail) { st_layers_free(dst); return -1; }
    return 0;
}

size_t st_layers_bytes(const st_layers *ls)
{
    size_t b = sizeof *ls + (size_t)ls->cap * sizeof *ls->v;
    for (uint32_t i = 0; i < ls->n; i++) b += 3 * (size_t)ls->v[i].cap * sizeof(double);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) b += 3 * (size_t)(ls->base_cap[l] + ls->bpos_cap[l]) * sizeof(double);
    return b;
}

uint32_t st_layers_on_level(const st_layers *ls, unsigned l)
{
    uint32_t c = 0;
    for (uint32_t i = 0; i < ls->n; i++) c += ls->v[i].level == l;
    return c;
}

/* Grows a 3-doubles-per-id array to hold id v (new entries: fill). */
static void grow3_fill(double **a, uint32_t *cap, uint32_t v, uint32_t hint, double fill)
{
    if (v < *cap) return;
    uint32_t nc = hint > v ? hint : v + 1;
    if (nc < 2 * *cap) nc = 2 * *cap; /* amortised: ids come one at a time from strokes */
    double *p = realloc(*a, 3 * (size_t)nc * sizeof *p);
    if (!p) abort(); /* out of memory while editing, as the synthesis does */
    for (size_t i = 3 * (size_t)*cap; i < 3 * (size_t)nc; i++) p[i] = fill;
    *a = p;
    *cap = nc;
}

static void grow3(double **a, uint32_t *cap, uint32_t v, uint32_t hint) { grow3_fill(a, cap, v, hint, 0); }

static void set_name(char *dst, const char *name)
{
    snprintf(dst, ST_LAYER_NAME, "%s", name && *name ? name : "layer");
}

int st_layers_add(st_layers *ls, const st_hier *h, unsigned l, const char *name, st_error *err)
{
    if (l > h->map.top)
        return st_fail(err, ST_ERR_INVALID, "a sculpt layer needs a level from 0 to %u (not %u)", h->map.top, l), -1;
    if (ls->n >= ST_LAYER_MAX) return st_fail(err, ST_ERR_INVALID, "at most %d sculpt layers", ST_LAYER_MAX), -1;
    if (ls->n == ls->cap) {
        uint32_t cap = ls->cap ? 2 * ls->cap : 8;
        st_layer *p = realloc(ls->v, (size_t)cap * sizeof *p);
        if (!p) return st_fail(err, ST_ERR_MEMORY, "out of memory"), -1;
        ls->v = p;
        ls->cap = cap;
    }
    if (!st_layers_on_level(ls, l)) {
        /* B_l: the level's details as they are now (level 0: its positions). */
        free(ls->base[l]);
        ls->base[l] = NULL;
        ls->base_cap[l] = 0;
        uint32_t cap = h->map.verts.end;
        grow3(&ls->base[l], &ls->base_cap[l], cap ? cap - 1 : 0, cap);
        /* Only the vertices of level l: an adaptive hierarchy's free ids
         * may hold stale values, and a vertex made there later must start
         * with B_l = 0 (st_layers_holds). */
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            const double *src = l == 0 ? st_pos(&h->map, v, 0) : st_hier_detail(h, l, v);
            memcpy(ls->base[l] + 3 * (size_t)v, src, 3 * sizeof(double));
        }
    }
    st_layer *y = &ls->v[ls->n];
    memset(y, 0, sizeof *y);
    set_name(y->name, name);
    y->level = l;
    y->strength = 1;
    ls->active = (int)ls->n;
    return (int)ls->n++;
}

static int contributes(const st_layer *y, unsigned l)
{
    return y->level == l && !y->hidden && y->strength != 0;
}

void st_layers_get(const st_layers *ls, int slot, unsigned l, uint32_t v, double out[3])
{
    const double *p = zero3;
    if (slot == ST_LAYERS_SLOT_BPOS) {
        p = ls->bpos[l] && v < ls->bpos_cap[l] ? ls->bpos[l] + 3 * (size_t)v : none3;
    } else if (slot < 0) {
        if (ls->base[l] && v < ls->base_cap[l]) p = ls->base[l] + 3 * (size_t)v;
    } else if ((uint32_t)slot < ls->n) {
        const st_layer *y = &ls->v[slot];
        if (y->off && v < y->cap) p = y->off + 3 * (size_t)v;
    }
    memcpy(out, p, 3 * sizeof *out);
}

void st_layers_set(st_layers *ls, int slot, unsigned l, uint32_t v, const double val[3])
{
    double *p;
    if (slot == ST_LAYERS_SLOT_BPOS) {
        if (!ls->bpos[l] && isnan(val[0])) return;
        grow3_fill(&ls->bpos[l], &ls->bpos_cap[l], v, v + 1, NAN);
        p = ls->bpos[l] + 3 * (size_t)v;
    } else if (slot < 0) {
        grow3(&ls->base[l], &ls->base_cap[l], v, v + 1);
        p = ls->base[l] + 3 * (size_t)v;
    } else {
        st_layer *y = &ls->v[slot];
        grow3(&y->off, &y->cap, v, v + 1);
        p = y->off + 3 * (size_t)v;
    }
    memcpy(p, val, 3 * sizeof *p);
}

/* Sum of the contributing layers of level l at v, leaving out `skip`;
 * returns how many layers added something. */
static int compose_except(const st_layers *ls, unsigned l, uint32_t v, int skip, double out[3])
{
    int terms = 0;
    st_layers_get(ls, -1, l, v, out);
    for (uint32_t i = 0; i < ls->n; i++) {
        const st_layer *y = &ls->v[i];
        if ((int)i == skip || !contributes(y, l) || !y->off || v >= y->cap) continue;
        const double *o = y->off + 3 * (size_t)v;
        if (o[0] == 0 && o[1] == 0 && o[2] == 0) continue;
        for (int c = 0; c < 3; c++) out[c] += y->strength * o[c];
        terms++;
    }
    return terms;
}

/* The detail of v composed into det, and its position: P0 where no layer
 * contributes and P0 is kept, else as a synthesis computes it. */
static void compose_vertex(const st_layers *ls, unsigned l, uint32_t v, double det[3], const double pred[3],
                           const double f[3][3], double pos[3])
{
    int terms = compose_except(ls, l, v, -1, det);
    double p0[3];
    st_layers_get(ls, ST_LAYERS_SLOT_BPOS, l, v, p0);
    if (!terms && !isnan(p0[0])) memcpy(pos, p0, sizeof p0);
    else st_hier_apply_detail(pred, f, det, pos);
}

/* Before the layers change the vertices of darts at level l: P0 kept for
 * those where no layer contributes yet (their position is the one without
 * layers). */
static void keep_bpos(st_layers *ls, const st_hier *h, unsigned l, const uint32_t *darts, uint32_t n)
{
    const st_map *m = &h->map;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = st_vert(m, darts[i], l);
        double p0[3], tmp[3];
        st_layers_get(ls, ST_LAYERS_SLOT_BPOS, l, v, p0);
        if (!isnan(p0[0]) || compose_except(ls, l, v, -1, tmp)) continue;
        st_layers_set(ls, ST_LAYERS_SLOT_BPOS, l, v, st_pos(m, v, l));
    }
}

void st_layers_follow(st_layers *ls, const st_hier *h, unsigned above, const uint64_t *keys, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++) {
        uint64_t k = keys[i];
        unsigned l = st_fp_level(k);
        if (l <= above || st_fp_kind(k) != ST_FP_POS || !ls->bpos[l]) continue;
        uint32_t v = st_fp_vid(k);
        double p0[3], tmp[3];
        st_layers_get(ls, ST_LAYERS_SLOT_BPOS, l, v, p0);
        if (isnan(p0[0])) continue;
        if (compose_except(ls, l, v, -1, tmp)) st_layers_set(ls, ST_LAYERS_SLOT_BPOS, l, v, none3);
        else st_layers_set(ls, ST_LAYERS_SLOT_BPOS, l, v, st_pos(&h->map, v, l));
    }
}

int st_layers_edit_target(const st_layers *ls, unsigned l, int target)
{
    return target >= 0 && (uint32_t)target < ls->n && contributes(&ls->v[target], l) ? target : -1;
}

void st_layers_compose(const st_layers *ls, unsigned l, uint32_t v, double det[3])
{
    compose_except(ls, l, v, -1, det);
}

static int nonzero3(const double *p) { return p[0] != 0 || p[1] != 0 || p[2] != 0; }

int st_layers_holds(const st_layers *ls, unsigned l, uint32_t v)
{
    if (l >= ST_MAX_LEVELS) return 0;
    if (ls->base[l] && v < ls->base_cap[l] && nonzero3(ls->base[l] + 3 * (size_t)v)) return 1;
    if (ls->bpos[l] && v < ls->bpos_cap[l] && !isnan(ls->bpos[l][3 * (size_t)v])) return 1;
    for (uint32_t i = 0; i < ls->n; i++) {
        const st_layer *y = &ls->v[i];
        if (y->level == l && y->off && v < y->cap && nonzero3(y->off + 3 * (size_t)v)) return 1;
    }
    return 0;
}

typedef struct hook_ctx { st_layers *ls; int target; } hook_ctx;

/* The new detail det of v (level 0: its new position) split: the change
 * goes into the target layer, or into B_l for target -1. */
static void split_change(st_layers *ls, unsigned l, uint32_t v, int target, const double det[3])
{
    if (target >= 0) {
        const st_layer *y = &ls->v[target];
        double rest[3], o[3];
        compose_except(ls, l, v, target, rest);
        for (int i = 0; i < 3; i++) o[i] = (det[i] - rest[i]) / y->strength;
        st_layers_set(ls, target, l, v, o);
    } else {
        double layers[3], b[3];
        compose_except(ls, l, v, -1, layers);
        double old[3];
        st_layers_get(ls, -1, l, v, old);
        /* layers - old = the layers' sum alone, added on top of B_l. */
        for (int i = 0; i < 3; i++) b[i] = det[i] - (layers[i] - old[i]);
        st_layers_set(ls, -1, l, v, b);
    }
}

void st_layers_take(st_layers *ls, unsigned l, uint32_t v, int target, double det[3])
{
    split_change(ls, l, v, target, det);
    compose_except(ls, l, v, -1, det);
}

/* st_hier_edit_with's hook for an edit: the change goes into the target,
 * the stored detail is the composition. */
static void edit_hook(void *ctx, unsigned l, uint32_t v, double det[3], const double pred[3], const double f[3][3],
                      double pos[3])
{
    hook_ctx *c = ctx;
    st_layers *ls = c->ls;
    split_change(ls, l, v, c->target, det);
    /* The surface without layers moved here too: P0 is no longer kept. */
    if (c->target < 0) st_layers_set(ls, ST_LAYERS_SLOT_BPOS, l, v, none3);
    compose_vertex(ls, l, v, det, pred, f, pos);
}

/* Level 0 (layers.h): the positions are the composition itself, written
 * by an ordinary edit of level 0, which re-synthesises above.  pos NULL:
 * recomposed from the values as they are. */
static uint64_t edit_level0(st_layers *ls, st_hier *h, int target, const uint32_t *darts, const double (*pos)[3],
                            uint32_t n, st_footprint *fp, st_edit_cache *cache)
{
    if (!n) return 0;
    double (*composed)[3] = malloc((size_t)n * sizeof *composed);
    if (!composed) abort(); /* out of memory while editing, as the synthesis does */
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = st_vert(&h->map, darts[i], 0);
        if (pos) split_change(ls, 0, v, target, pos[i]);
        compose_except(ls, 0, v, -1, composed[i]);
    }
    uint64_t r = st_hier_edit_cached(h, 0, darts, (const double(*)[3])composed, n, fp, NULL, NULL, cache);
    free(composed);
    return r;
}

static void recompose_hook(void *ctx, unsigned l, uint32_t v, double det[3], const double pred[3], const double f[3][3],
                           double pos[3])
{
    hook_ctx *c = ctx;
    compose_vertex(c->ls, l, v, det, pred, f, pos);
}

uint64_t st_layers_edit(st_layers *ls, st_hier *h, unsigned l, int target, const uint32_t *darts,
                        const double (*pos)[3], uint32_t n, st_footprint *fp, st_edit_cache *cache)
{
    if (!st_layers_on_level(ls, l)) return st_hier_edit_cached(h, l, darts, pos, n, fp, NULL, NULL, cache);
    target = st_layers_edit_target(ls, l, target);
    if (l == 0) return edit_level0(ls, h, target, darts, pos, n, fp, cache);
    keep_bpos(ls, h, l, darts, n);
    hook_ctx c = { ls, target };
    return st_hier_edit_cached(h, l, darts, pos, n, fp, edit_hook, &c, cache);
}

uint64_t st_layers_recompose(st_layers *ls, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n,
                             st_footprint *fp)
{
    if (!n) return 0;
    if (l == 0) return edit_level0(ls, h, -1, darts, NULL, n, fp, NULL);
    /* No P0 to keep here: a vertex gets offsets by an edit first
     * (st_layers_edit keeps it then), and the strengths may already have
     * changed, so the current position may hold layers. */
    hook_ctx c = { ls, -1 };
    return st_hier_edit_with(h, l, darts, NULL, n, fp, recompose_hook, &c);
}

uint32_t st_layers_support(const st_layers *ls, const st_hier *h, int k, uint32_t **darts, uint32_t *cap)
{
    if (k < 0 || (uint32_t)k >= ls->n) return 0;
    const st_layer *y = &ls->v[k];
    const st_map *m = &h->map;
    unsigned l = y->level;
    if (!y->off || l > m->top) return 0;
    uint8_t *seen = calloc(y->cap ? y->cap : 1, 1);
    if (!seen) abort();
    uint32_t n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t v = st_vert(m, d, l);
        if (v >= y->cap || seen[v]) continue;
        const double *o = y->off + 3 * (size_t)v;
        if (o[0] == 0 && o[1] == 0 && o[2] == 0) continue;
        seen[v] = 1;
        if (n == *cap) {
            uint32_t nc = *cap ? 2 * *cap : 256;
            uint32_t *p = realloc(*darts, (size_t)nc * sizeof *p);
            if (!p) abort();
            *darts = p;
            *cap = nc;
        }
        (*darts)[n++] = d;
    }
    free(seen);
    return n;
}

static int check_index(const st_layers *ls, int k, st_error *err)
{
    if (k < 0 || (uint32_t)k >= ls->n) return st_fail(err, ST_ERR_INVALID, "no sculpt layer %d", k);
    return ST_OK;
}

int st_layers_move(st_layers *ls, int k, int to, st_error *err)
{
    if (check_index(ls, k, err) || check_index(ls, to, err)) return -1;
    st_layer t = ls->v[k];
    if (to < k) memmove(ls->v + to + 1, ls->v + to, (size_t)(k - to) * sizeof t);
    else memmove(ls->v + k, ls->v + k + 1, (size_t)(to - k) * sizeof t);
    ls->v[to] = t;
    if (ls->active == k) ls->active = to;
    else if (ls->active >= 0) {
        if (k < ls->active && to >= ls->active) ls->active--;
        else if (k > ls->active && to <= ls->active) ls->active++;
    }
    return 0;
}

static void drop(st_layers *ls, int k)
{
    unsigned l = ls->v[k].level;
    free(ls->v[k].off);
    memmove(ls->v + k, ls->v + k + 1, (size_t)(ls->n - (uint32_t)k - 1) * sizeof *ls->v);
    ls->n--;
    if (ls->active == k) ls->active = k > 0 ? k - 1 : (ls->n ? 0 : -1);
    else if (ls->active > k) ls->active--;
    if (!st_layers_on_level(ls, l)) {
        free(ls->base[l]);
        ls->base[l] = NULL;
        ls->base_cap[l] = 0;
        free(ls->bpos[l]);
        ls->bpos[l] = NULL;
        ls->bpos_cap[l] = 0;
    }
}

int st_layers_merge_down(st_layers *ls, int k, st_error *err)
{
    if (check_index(ls, k, err)) return -1;
    if (k == 0) return st_fail(err, ST_ERR_INVALID, "layer '%s' is the bottom layer: nothing to merge into", ls->v[k].name), -1;
    st_layer *a = &ls->v[k - 1], *b = &ls->v[k];
    if (a->level != b->level)
        return st_fail(err, ST_ERR_INVALID, "layers '%s' (level %u) and '%s' (level %u) are on different levels",
                       b->name, b->level, a->name, a->level), -1;
    double sa = a->hidden ? 0 : a->strength, sb = b->hidden ? 0 : b->strength;
    uint32_t cap = a->cap > b->cap ? a->cap : b->cap;
    if (cap) grow3(&a->off, &a->cap, cap - 1, cap);
    for (uint32_t v = 0; v < cap; v++) {
        double *o = a->off + 3 * (size_t)v;
        const double *q = b->off && v < b->cap ? b->off + 3 * (size_t)v : zero3;
        for (int c = 0; c < 3; c++) o[c] = sa * o[c] + sb * q[c];
    }
    a->strength = 1;
    a->hidden = 0;
    drop(ls, k);
    ls->active = k - 1;
    return 0;
}

int st_layers_remove(st_layers *ls, int k, st_error *err)
{
    if (check_index(ls, k, err)) return -1;
    drop(ls, k);
    return 0;
}

int st_layers_rename(st_layers *ls, int k, const char *name, st_error *err)
{
    if (check_index(ls, k, err)) return -1;
    set_name(ls->v[k].name, name);
    return 0;
}

int st_layers_rebase(st_layers *ls, st_error *err)
{
    for (uint32_t i = 0; i < ls->n; i++)
        if (ls->v[i].level <= 1)
            return st_fail(err, ST_ERR_INVALID, "sculpt layer '%s' is on level %u, which %s; merge or delete it first",
                           ls->v[i].name, ls->v[i].level,
                           ls->v[i].level ? "would become the control mesh" : "would be removed"), -1;
    for (uint32_t i = 0; i < ls->n; i++) ls->v[i].level--;
    free(ls->base[0]);
    free(ls->bpos[0]);
    for (unsigned l = 0; l + 1 < ST_MAX_LEVELS; l++) {
        ls->base[l] = ls->base[l + 1];
        ls->base_cap[l] = ls->base_cap[l + 1];
        ls->bpos[l] = ls->bpos[l + 1];
        ls->bpos_cap[l] = ls->bpos_cap[l + 1];
    }
    ls->base[ST_MAX_LEVELS - 1] = NULL;
    ls->base_cap[ST_MAX_LEVELS - 1] = 0;
    ls->bpos[ST_MAX_LEVELS - 1] = NULL;
    ls->bpos_cap[ST_MAX_LEVELS - 1] = 0;
    return 0;
}

int st_layers_append(st_layers *dst, st_layers *src, st_error *err)
{
    for (uint32_t i = 0; i < src->n; i++)
        if (st_layers_on_level(dst, src->v[i].level))
            return st_fail(err, ST_ERR_INVALID, "level %u has sculpt layers on both sides", src->v[i].level), -1;
    if (dst->n + src->n > ST_LAYER_MAX) return st_fail(err, ST_ERR_INVALID, "at most %d sculpt layers", ST_LAYER_MAX), -1;
    if (!src->n) return 0;
    if (dst->n + src->n > dst->cap) {
        st_layer *p = realloc(dst->v, (size_t)(dst->n + src->n) * sizeof *p);
        if (!p) return st_fail(err, ST_ERR_MEMORY, "out of memory"), -1;
        dst->v = p;
        dst->cap = dst->n + src->n;
    }
    memcpy(dst->v + dst->n, src->v, (size_t)src->n * sizeof *src->v);
    if (dst->active < 0 && src->active >= 0) dst->active = (int)dst->n + src->active;
    dst->n += src->n;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (!src->base[l] && !src->bpos[l]) continue;
        /* (a level of src's layers: dst has none there, so no arrays) */
        free(dst->base[l]);
        free(dst->bpos[l]);
        dst->base[l] = src->base[l];
        dst->base_cap[l] = src->base_cap[l];
        dst->bpos[l] = src->bpos[l];
        dst->bpos_cap[l] = src->bpos_cap[l];
        src->base[l] = src->bpos[l] = NULL;
    }
    free(src->v);
    st_layers_init(src);
    return 0;
}
