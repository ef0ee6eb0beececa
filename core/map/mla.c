/* Multilevel attributes: a value per id at its insertion level (base) plus
 * one dense column per level that differs from the level below (map.h,
 * "Storage").  This replaces the thesis' per-dart truncated arrays (listing
 * 2.4.6) by per-level columns: no per-dart offset is needed, a lookup is one
 * comparison and one load, and for quadrisection the columns hold exactly
 * the values that change. */
#include "core/base/hugepage.h"
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

void st_mla_init(st_mla *a, uint32_t elem)
{
    memset(a, 0, sizeof *a);
    a->elem = elem;
}

void st_mla_sparse_free(st_mla_sparse *s)
{
    if (!s) return;
    free(s->bbase);
    free(s->boff);
    free(s->lvl);
    free(s->val);
    free(s);
}

void st_mla_free(st_mla *a)
{
    free(a->base);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) free(a->col[l]);
    st_mla_sparse_free(a->sp);
    st_mla_init(a, a->elem);
}

int st_array_grow(unsigned char **base, size_t elem, uint32_t used, uint32_t cap, int huge)
{
    unsigned char *b = huge ? st_realloc_huge(*base, (size_t)used * elem, (size_t)cap * elem)
                            : realloc(*base, (size_t)cap * elem);
    if (!b) return -1;
    *base = b;
    return 0;
}

int st_mla_grow(st_mla *a, uint32_t used, uint32_t cap, int huge)
{
    return st_array_grow(&a->base, a->elem, used, cap, huge);
}

static void refresh_eff(st_mla *a)
{
    unsigned last = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (a->col[l]) last = l;
        a->eff[l] = (uint8_t)last;
    }
    a->maxcol = (uint8_t)last;
}

/* Makes col[j] hold at least n elements. */
static int ensure_cap(st_mla *a, unsigned j, uint32_t n)
{
    if (n <= a->colcap[j]) return 0;
    uint32_t cap = a->colcap[j] + a->colcap[j] / 2;
    if (cap < n) cap = n;
    unsigned char *c = realloc(a->col[j], (size_t)cap * a->elem);
    if (!c) return -1;
    a->col[j] = c;
    a->colcap[j] = cap;
    return 0;
}

/* ---- sparse form (map.h, "Sparse form") ---------------------------------- */

static inline uint32_t pair_start(const st_mla_sparse *s, uint32_t i)
{
    return s->bbase[i >> ST_POOL_BLOCK_SHIFT] + s->boff[i];
}

const void *st_mla_sparse_at(const st_mla *a, const uint8_t *ins, uint32_t i, unsigned l)
{
    const st_mla_sparse *s = a->sp;
    if (ins[i] < l && i < s->n) {
        /* Pairs in increasing level order: the last one at or below l holds. */
        uint32_t b = pair_start(s, i);
        for (uint32_t k = pair_start(s, i + 1); k > b; k--)
            if (s->lvl[k - 1] <= l) return s->val + (size_t)(k - 1) * a->elem;
    }
    return a->base + (size_t)i * a->elem;
}

/* Calls fn for each pair of the dense form in id, then level order:
 * the levels at which id i's value differs from the level below. */
typedef void (*pair_fn)(void *ctx, uint32_t i, unsigned l, const void *v);

static void walk_changes(const st_mla *a, const st_pool *p, pair_fn fn, void *ctx)
{
    for (uint32_t i = 0; i < p->end; i++) {
        unsigned in = p->ins[i];
        if (in == ST_FREE_LEVEL) continue;
        const unsigned char *prev = a->base + (size_t)i * a->elem;
        for (unsigned l = in + 1; l <= a->maxcol; l++) {
            if (!a->col[l]) continue; /* inherits: no change */
            const unsigned char *v = a->col[l] + (size_t)i * a->elem;
            if (memcmp(v, prev, a->elem) == 0) continue;
            fn(ctx, i, l, v);
            prev = v;
        }
    }
}

typedef struct count_ctx { uint32_t *per_id; uint64_t total; } count_ctx;

static void count_pair(void *ctx, uint32_t i, unsigned l, const void *v)
{
    (void)l;
    (void)v;
    count_ctx *c = ctx;
    c->per_id[i]++;
    c->total++;
}

typedef struct fill_ctx { st_mla_sparse *s; uint32_t *next; uint32_t elem; } fill_ctx;

static void fill_pair(void *ctx, uint32_t i, unsigned l, const void *v)
{
    fill_ctx *c = ctx;
    uint32_t k = c->next[i]++;
    c->s->lvl[k] = (uint8_t)l;
    memcpy(c->s->val + (size_t)k * c->elem, v, c->elem);
    c->s->pairs_at[l]++;
}

static size_t dense_column_bytes(const st_mla *a)
{
    size_t n = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) n += (size_t)a->colcap[l] * a->elem;
    return n;
}

static size_t sparse_bytes(const st_mla_sparse *s, uint32_t elem)
{
    return sizeof *s + ((size_t)(s->n >> ST_POOL_BLOCK_SHIFT) + 1) * sizeof(uint32_t) + ((size_t)s->n + 1) * sizeof(uint16_t)
           + (size_t)s->npairs * (1 + elem);
}

int st_mla_freeze(st_mla *a, const st_pool *p)
{
    if (a->sp || a->maxcol == 0) return 0;
    uint32_t n = p->end;
    uint32_t *per_id = calloc((size_t)n + 1, sizeof *per_id);
    if (!per_id) return -1;
    count_ctx cc = { per_id, 0 };
    walk_changes(a, p, count_pair, &cc);
    size_t want = sizeof(st_mla_sparse) + ((size_t)(n >> ST_POOL_BLOCK_SHIFT) + 1) * 4 + ((size_t)n + 1) * 2 + cc.total * (1 + a->elem);
    /* Worth it only when it halves the columns (map.h); a block's pairs must
     * fit the 16-bit offsets (at most ST_POOL_BLOCK * ST_MAX_LEVELS). */
    if (want * 2 > dense_column_bytes(a) || cc.total > UINT32_MAX) { free(per_id); return 0; }
    st_mla_sparse *s = calloc(1, sizeof *s);
    if (!s) { free(per_id); return -1; }
    s->n = n;
    s->npairs = (uint32_t)cc.total;
    s->bbase = malloc(((size_t)(n >> ST_POOL_BLOCK_SHIFT) + 1) * sizeof *s->bbase);
    s->boff = malloc(((size_t)n + 1) * sizeof *s->boff);
    s->lvl = malloc(cc.total ? cc.total : 1);
    s->val = malloc(cc.total ? cc.total * a->elem : 1);
    uint32_t *next = malloc(((size_t)n + 1) * sizeof *next);
    if (!s->bbase || !s->boff || !s->lvl || !s->val || !next) {
        st_mla_sparse_free(s);
        free(per_id);
        free(next);
        return -1;
    }
    uint32_t at = 0;
    for (uint32_t i = 0; i <= n; i++) {
        if ((i & (ST_POOL_BLOCK - 1)) == 0) s->bbase[i >> ST_POOL_BLOCK_SHIFT] = at;
        s->boff[i] = (uint16_t)(at - s->bbase[i >> ST_POOL_BLOCK_SHIFT]);
        next[i] = at;
        at += per_id[i];
    }
    free(per_id);
    fill_ctx fc = { s, next, a->elem };
    walk_changes(a, p, fill_pair, &fc);
    free(next);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        s->has_col[l] = a->col[l] != NULL;
        s->colcap[l] = a->colcap[l];
        free(a->col[l]);
        a->col[l] = NULL;
        a->colcap[l] = 0;
        a->eff[l] = a->eff[l] ? (uint8_t)(ST_MLA_SPARSE | l) : 0;
    }
    a->sp = s;
    return 1;
}

static void set_u32(st_mla *a, const st_pool *p, uint32_t id, unsigned l, uint32_t v);

/* st_mla_freeze's choice and result, from the changes themselves: the
 * columns set_u32 would make are those of the levels changed, each of
 * st_pool_cover's size once trimmed; walk_changes would find exactly
 * these pairs, per id in level order (the input's order, kept by the
 * counting sort below). */
int st_mla_set_changes(st_mla *a, const st_pool *p, const uint32_t *id, const uint8_t *lvl, const uint32_t *val,
                       uint64_t n)
{
    if (a->elem != sizeof(uint32_t) || a->sp || a->maxcol) return -1;
    unsigned char has[ST_MAX_LEVELS] = { 0 };
    for (uint64_t k = 0; k < n; k++) has[lvl[k]] = 1;
    size_t dense = 0;
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++) dense += has[l] ? (size_t)st_pool_cover(p, l) * a->elem : 0;
    uint32_t ids = p->end;
    size_t want = sizeof(st_mla_sparse) + ((size_t)(ids >> ST_POOL_BLOCK_SHIFT) + 1) * 4 + ((size_t)ids + 1) * 2 + n * (1 + a->elem);
    if (n == 0) return 0;
    if (want * 2 > dense || n > UINT32_MAX) {
        for (uint64_t k = 0; k < n; k++) set_u32(a, p, id[k], lvl[k], val[k]);
        return 0;
    }
    st_mla_sparse *s = calloc(1, sizeof *s);
    uint32_t *next = calloc((size_t)ids + 1, sizeof *next);
    if (s) {
        s->bbase = malloc(((size_t)(ids >> ST_POOL_BLOCK_SHIFT) + 1) * sizeof *s->bbase);
        s->boff = malloc(((size_t)ids + 1) * sizeof *s->boff);
        s->lvl = malloc(n);
        s->val = malloc(n * a->elem);
    }
    if (!s || !next || !s->bbase || !s->boff || !s->lvl || !s->val) {
        if (s) st_mla_sparse_free(s);
        free(next);
        return -1;
    }
    s->n = ids;
    s->npairs = (uint32_t)n;
    for (uint64_t k = 0; k < n; k++) next[id[k]]++;
    uint32_t at = 0;
    for (uint32_t i = 0; i <= ids; i++) {
        if ((i & (ST_POOL_BLOCK - 1)) == 0) s->bbase[i >> ST_POOL_BLOCK_SHIFT] = at;
        s->boff[i] = (uint16_t)(at - s->bbase[i >> ST_POOL_BLOCK_SHIFT]);
        uint32_t c = next[i];
        next[i] = at;
        at += c;
    }
    for (uint64_t k = 0; k < n; k++) {
        uint32_t j = next[id[k]]++;
        s->lvl[j] = lvl[k];
        memcpy(s->val + (size_t)j * a->elem, &val[k], a->elem);
        s->pairs_at[lvl[k]]++;
    }
    free(next);
    unsigned last = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        s->has_col[l] = has[l];
        s->colcap[l] = has[l] ? st_pool_cover(p, l) : 0;
        if (has[l]) last = l;
        a->eff[l] = last ? (uint8_t)(ST_MLA_SPARSE | l) : 0;
    }
    a->maxcol = (uint8_t)last;
    a->sp = s;
    return 0;
}

/* The dense columns set_u32 would leave after the same changes made in
 * level order (materialize's copy of level l - 1 for the ids inserted
 * below l, of st_pool_cover's size, then the level's changes), built a
 * column at a time instead of a change at a time. */
int st_mla_columns_from_changes(st_mla *a, const st_pool *p, const uint32_t *id, const uint8_t *lvl, const uint32_t *val,
                                uint64_t n)
{
    if (a->elem != sizeof(uint32_t) || a->sp || a->maxcol) return -1;
    const uint32_t *base = (const uint32_t *)a->base;
    unsigned prev = 0;          /* the last column made, 0: none (base) */
    for (uint64_t k = 0; k < n;) {
        unsigned l = lvl[k];
        uint32_t cap = st_pool_cover(p, l);
        uint32_t *c = malloc((size_t)(cap ? cap : 1) * sizeof *c);
        if (!c) return -1;
        const uint32_t *pc = prev ? (const uint32_t *)a->col[prev] : NULL;
        for (uint32_t i = 0; i < cap; i++)
            if (p->ins[i] < l) c[i] = pc && prev > p->ins[i] ? pc[i] : base[i];
        for (; k < n && lvl[k] == l; k++) c[id[k]] = val[k];
        a->col[l] = (unsigned char *)c;
        a->colcap[l] = cap;
        prev = l;
    }
    refresh_eff(a);
    return 0;
}

/* Back to no column (what st_mla_set_changes starts from). */
void st_mla_drop_columns(st_mla *a)
{
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        free(a->col[l]);
        a->col[l] = NULL;
        a->colcap[l] = 0;
    }
    refresh_eff(a);
}

void st_mla_thaw(st_mla *a, const st_pool *p)
{
    st_mla_sparse *s = a->sp;
    if (!s) return;
    unsigned char *col[ST_MAX_LEVELS] = { 0 };
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++) {
        if (!s->has_col[l]) continue;
        uint32_t n = s->colcap[l];
        col[l] = calloc(n ? n : 1, a->elem);
        if (!col[l]) abort(); /* out of memory in a setter: cannot keep the map valid */
        for (uint32_t i = 0; i < n && i < p->end; i++)
            if (p->ins[i] < l) memcpy(col[l] + (size_t)i * a->elem, st_mla_sparse_at(a, p->ins, i, l), a->elem);
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        a->col[l] = col[l];
        a->colcap[l] = s->has_col[l] ? s->colcap[l] : 0;
    }
    a->sp = NULL;
    st_mla_sparse_free(s);
    refresh_eff(a);
}

static void *dup_array(const void *src, size_t n)
{
    void *p = malloc(n ? n : 1);
    if (p && n) memcpy(p, src, n);
    return p;
}

int st_mla_sparse_copy(st_mla *dst, const st_mla *src, size_t *bytes)
{
    dst->sp = NULL;
    const st_mla_sparse *s = src->sp;
    if (!s) return 0;
    st_mla_sparse *d = malloc(sizeof *d);
    if (!d) return -1;
    *d = *s;
    size_t nb = ((size_t)(s->n >> ST_POOL_BLOCK_SHIFT) + 1) * sizeof *s->bbase, no = ((size_t)s->n + 1) * sizeof *s->boff;
    d->bbase = dup_array(s->bbase, nb);
    d->boff = dup_array(s->boff, no);
    d->lvl = dup_array(s->lvl, s->npairs);
    d->val = dup_array(s->val, (size_t)s->npairs * src->elem);
    if (!d->bbase || !d->boff || !d->lvl || !d->val) {
        st_mla_sparse_free(d);
        return -1;
    }
    dst->sp = d;
    if (bytes) *bytes += sparse_bytes(s, src->elem);
    return 0;
}

size_t st_mla_sparse_bytes(const st_mla *a)
{
    return a->sp ? sparse_bytes(a->sp, a->elem) : 0;
}

/* Creates col[j] as a copy of level j-1 for the ids inserted before j. */
static int materialize(st_mla *a, const st_pool *p, unsigned j)
{
    uint32_t n = st_pool_cover(p, j);
    unsigned char *c = malloc(n ? (size_t)n * a->elem : 1);
    if (!c) return -1;
    for (uint32_t i = 0; i < n; i++)
        if (p->ins[i] < j)
            memcpy(c + (size_t)i * a->elem, st_mla_at(a, p->ins, i, j - 1), a->elem);
    a->col[j] = c;
    a->colcap[j] = n;
    refresh_eff(a);
    return 0;
}

void *st_mla_column(st_mla *a, const st_pool *p, unsigned l)
{
    st_mla_thaw(a, p);
    if (l == 0 || l >= ST_MAX_LEVELS) return NULL;
    if (!a->col[l] && materialize(a, p, l)) return NULL;
    if (ensure_cap(a, l, st_pool_cover(p, l))) return NULL;
    return a->col[l];
}

void st_mla_insert(st_mla *a, const st_pool *p, uint32_t id, const void *v)
{
    st_mla_thaw(a, p);
    unsigned l = p->ins[id];
    if (a->elem == sizeof(uint32_t)) memcpy(a->base + (size_t)id * 4, v, 4);
    else memcpy(a->base + (size_t)id * a->elem, v, a->elem);
    if (a->maxcol <= l) return;
    for (unsigned k = l + 1; k <= a->maxcol; k++) {
        if (!a->col[k]) continue;
        if (ensure_cap(a, k, id + 1)) abort(); /* out of memory in a column: cannot keep the map valid */
        memcpy(a->col[k] + (size_t)id * a->elem, v, a->elem);
    }
}

/* 4-byte values (relations): the same as the generic setter below without
 * memcpy/memcmp per level. */
static void set_u32(st_mla *a, const st_pool *p, uint32_t id, unsigned l, uint32_t v)
{
    uint32_t old = st_mla_u32(a, p->ins, id, l);
    if (l == p->ins[id]) {
        ((uint32_t *)a->base)[id] = v;
    } else {
        if (!a->col[l] && materialize(a, p, l)) abort();
        if (id >= a->colcap[l] && ensure_cap(a, l, id + 1)) abort();
        ((uint32_t *)a->col[l])[id] = v;
    }
    for (unsigned k = l + 1; k <= a->maxcol; k++) {
        if (!a->col[k]) continue;
        uint32_t *slot = (uint32_t *)a->col[k] + id;
        if (*slot != old) break;
        *slot = v;
    }
}

void st_mla_set(st_mla *a, const st_pool *p, uint32_t id, unsigned l, const void *v)
{
    st_mla_thaw(a, p);
    if (a->elem == sizeof(uint32_t)) {
        uint32_t x;
        memcpy(&x, v, sizeof x);
        set_u32(a, p, id, l, x);
        return;
    }
    unsigned char old[64];
    memcpy(old, st_mla_at(a, p->ins, id, l), a->elem);
    if (l == p->ins[id]) {
        memcpy(a->base + (size_t)id * a->elem, v, a->elem);
    } else {
        if (!a->col[l] && materialize(a, p, l)) abort();
        if (ensure_cap(a, l, id + 1)) abort();
        memcpy(a->col[l] + (size_t)id * a->elem, v, a->elem);
    }
    /* Levels above that had not diverged from the old value follow. */
    for (unsigned k = l + 1; k <= a->maxcol; k++) {
        if (!a->col[k]) continue;
        unsigned char *slot = a->col[k] + (size_t)id * a->elem;
        if (memcmp(slot, old, a->elem) != 0) break;
        memcpy(slot, v, a->elem);
    }
}

void st_mla_drop_column(st_mla *a, unsigned l)
{
    free(a->col[l]);
    a->col[l] = NULL;
    a->colcap[l] = 0;
    refresh_eff(a);
}

void st_mla_trim(st_mla *a, const st_pool *p)
{
    if (a->sp) return; /* sized exactly already */
    uint32_t cap = p->cap ? p->cap : 1;
    unsigned char *b = realloc(a->base, (size_t)cap * a->elem);
    if (b) a->base = b; /* a failed shrink keeps the larger block */
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++) {
        uint32_t n = st_pool_cover(p, l);
        if (!a->col[l] || a->colcap[l] <= n) continue;
        unsigned char *c = realloc(a->col[l], n ? (size_t)n * a->elem : 1);
        if (!c) continue;
        a->col[l] = c;
        a->colcap[l] = n;
    }
}

size_t st_mla_bytes(const st_mla *a, uint32_t cap)
{
    size_t n = (size_t)cap * a->elem + st_mla_sparse_bytes(a);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) n += (size_t)a->colcap[l] * a->elem;
    return n;
}

void st_mla_drop_bottom(st_mla *a, const st_pool *p)
{
    st_mla_thaw(a, p);
    /* Ids of level 0 take their level-1 value as base; columns move down. */
    for (uint32_t i = 0; i < p->end; i++)
        if (p->ins[i] == 0)
            memmove(a->base + (size_t)i * a->elem, st_mla_at(a, p->ins, i, 1), a->elem);
    free(a->col[1]);
    for (unsigned l = 1; l + 1 < ST_MAX_LEVELS; l++) {
        a->col[l] = a->col[l + 1];
        a->colcap[l] = a->colcap[l + 1];
    }
    a->col[ST_MAX_LEVELS - 1] = NULL;
    a->colcap[ST_MAX_LEVELS - 1] = 0;
    refresh_eff(a);
}

void *st_mla_column_for_overwrite(st_mla *a, const st_pool *p, unsigned l)
{
    st_mla_thaw(a, p);
    if (l == 0 || l >= ST_MAX_LEVELS) return NULL;
    if (!a->col[l]) {
        /* The caller overwrites every value: allocate without copying. */
        uint32_t n = st_pool_cover(p, l);
        a->col[l] = malloc(n ? (size_t)n * a->elem : 1);
        if (!a->col[l]) return NULL;
        a->colcap[l] = n;
        refresh_eff(a);
    }
    if (ensure_cap(a, l, st_pool_cover(p, l))) return NULL;
    return a->col[l];
}
