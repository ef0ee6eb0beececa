/* Multilevel attributes: a value per id at its insertion level (base) plus
 * one dense column per level that differs from the level below (map.h,
 * "Storage").  This replaces the thesis' per-dart truncated arrays (listing
 * 2.4.6) by per-level columns: no per-dart offset is needed, a lookup is one
 * comparison and one load, and for quadrisection the columns hold exactly
 * the values that change. */
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

void st_mla_init(st_mla *a, uint32_t elem)
{
    memset(a, 0, sizeof *a);
    a->elem = elem;
}

void st_mla_free(st_mla *a)
{
    free(a->base);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) free(a->col[l]);
    st_mla_init(a, a->elem);
}

int st_mla_grow(st_mla *a, uint32_t cap)
{
    unsigned char *b = realloc(a->base, (size_t)cap * a->elem);
    if (!b) return -1;
    a->base = b;
    return 0;
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
    if (l == 0 || l >= ST_MAX_LEVELS) return NULL;
    if (!a->col[l] && materialize(a, p, l)) return NULL;
    if (ensure_cap(a, l, st_pool_cover(p, l))) return NULL;
    return a->col[l];
}

void st_mla_insert(st_mla *a, const st_pool *p, uint32_t id, const void *v)
{
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
    size_t n = (size_t)cap * a->elem;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) n += (size_t)a->colcap[l] * a->elem;
    return n;
}

void st_mla_drop_bottom(st_mla *a, const st_pool *p)
{
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
