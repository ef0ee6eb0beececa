/* Id pools: ids are handed out in blocks of ST_POOL_BLOCK, each block owned
 * by one insertion level, so that the ids of levels 0..l can be enumerated in
 * time proportional to their number (thesis §2.4: one dart list per N^i). */
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

void st_pool_init(st_pool *p)
{
    memset(p, 0, sizeof *p);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        p->fill[l] = ST_NIL;
        p->freehead[l] = ST_NIL;
    }
}

void st_pool_free(st_pool *p)
{
    free(p->ins);
    free(p->next_free);
    free(p->spare);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
        free(p->blocks[l]);
    st_pool_init(p);
}

static int grow_u32(uint32_t **a, uint32_t *cap, uint32_t need)
{
    if (need <= *cap) return 0;
    uint32_t n = *cap ? *cap : 8;
    while (n < need) n *= 2;
    uint32_t *q = realloc(*a, (size_t)n * sizeof **a);
    if (!q) return -1;
    *a = q;
    *cap = n;
    return 0;
}

/* huge: an exact reservation about to be filled (st_array_grow). */
static int set_cap(st_pool *p, uint32_t cap, int huge)
{
    if (st_array_grow(&p->ins, 1, p->end, cap, huge)) return -1;
    if (p->next_free) {
        uint32_t *nf = realloc(p->next_free, (size_t)cap * sizeof *nf);
        if (!nf) return -1;
        p->next_free = nf;
    }
    p->cap = cap;
    return 0;
}

void st_pool_trim(st_pool *p)
{
    if (!p->end || p->end >= p->cap) return;
    /* A shrinking realloc that fails leaves the larger block, still valid. */
    uint8_t *ins = realloc(p->ins, p->end);
    if (ins) p->ins = ins;
    if (p->next_free) {
        uint32_t *nf = realloc(p->next_free, (size_t)p->end * sizeof *nf);
        if (nf) p->next_free = nf;
    }
    p->cap = p->end;
}

uint32_t st_pool_reserve(st_pool *p, uint64_t more)
{
    uint64_t need = (uint64_t)p->end + ((more + 2 * ST_POOL_BLOCK - 1) & ~(uint64_t)(ST_POOL_BLOCK - 1));
    if (need > UINT32_MAX - ST_POOL_BLOCK) return 0;
    if (need <= p->cap) return p->cap;
    return set_cap(p, (uint32_t)need, 1) ? 0 : p->cap;
}

/* Appends a fresh block to level l; returns its first id or ST_NIL. */
static uint32_t new_block(st_pool *p, unsigned l, uint32_t *grow)
{
    if (p->end > UINT32_MAX - 2 * ST_POOL_BLOCK) return ST_NIL;
    if (grow_u32(&p->blocks[l], &p->capblocks[l], p->nblocks[l] + 1)) return ST_NIL;
    if (p->nspare) {
        /* Reuse a block of a removed level: ids are never renumbered. */
        uint32_t b = p->spare[--p->nspare];
        memset(p->ins + ((size_t)b << ST_POOL_BLOCK_SHIFT), ST_FREE_LEVEL, ST_POOL_BLOCK);
        p->blocks[l][p->nblocks[l]++] = b;
        return b << ST_POOL_BLOCK_SHIFT;
    }
    uint32_t first = p->end;
    if (first + ST_POOL_BLOCK > p->cap) {
        uint32_t cap = p->cap ? p->cap : ST_POOL_BLOCK;
        while (cap < first + ST_POOL_BLOCK) cap = cap > UINT32_MAX / 2 ? UINT32_MAX : cap * 2;
        if (set_cap(p, cap, 0)) return ST_NIL;
        *grow = cap;
    }
    memset(p->ins + first, ST_FREE_LEVEL, ST_POOL_BLOCK);
    p->blocks[l][p->nblocks[l]++] = first >> ST_POOL_BLOCK_SHIFT;
    p->end = first + ST_POOL_BLOCK;
    return first;
}

uint32_t st_pool_take(st_pool *p, unsigned l, uint32_t *grow)
{
    uint32_t id;
    *grow = 0;
    if (p->freehead[l] != ST_NIL) {
        id = p->freehead[l];
        p->freehead[l] = p->next_free[id];
    } else {
        if (p->fill[l] == ST_NIL) {
            p->fill[l] = new_block(p, l, grow);
            if (p->fill[l] == ST_NIL) return ST_NIL;
        }
        id = p->fill[l];
        uint32_t next = id + 1;
        p->fill[l] = (next & (ST_POOL_BLOCK - 1)) ? next : ST_NIL;
    }
    p->ins[id] = (uint8_t)l;
    p->live[l]++;
    return id;
}

uint32_t st_pool_take_run(st_pool *p, unsigned l, uint32_t want, uint32_t *got, uint32_t *grow)
{
    if (p->freehead[l] != ST_NIL || want <= 1) {
        *got = 1;
        return st_pool_take(p, l, grow);
    }
    *grow = 0;
    if (p->fill[l] == ST_NIL) {
        p->fill[l] = new_block(p, l, grow);
        if (p->fill[l] == ST_NIL) return ST_NIL;
    }
    uint32_t id = p->fill[l], room = ST_POOL_BLOCK - (id & (ST_POOL_BLOCK - 1));
    uint32_t n = want < room ? want : room;
    memset(p->ins + id, (int)l, n);
    p->live[l] += n;
    p->fill[l] = n == room ? ST_NIL : id + n;
    *got = n;
    return id;
}

void st_pool_release(st_pool *p, uint32_t id)
{
    unsigned l = p->ins[id];
    if (!p->next_free) {
        p->next_free = malloc((size_t)p->cap * sizeof *p->next_free);
        if (!p->next_free) { p->ins[id] = ST_FREE_LEVEL; p->live[l]--; return; } /* leaks the id only */
    }
    p->ins[id] = ST_FREE_LEVEL;
    p->next_free[id] = p->freehead[l];
    p->freehead[l] = id;
    p->live[l]--;
}

uint32_t st_pool_cover(const st_pool *p, unsigned j)
{
    uint32_t cover = 0;
    for (unsigned l = 0; l < j && l < ST_MAX_LEVELS; l++)
        for (uint32_t b = 0; b < p->nblocks[l]; b++) {
            uint32_t end = (p->blocks[l][b] + 1) << ST_POOL_BLOCK_SHIFT;
            if (end > cover) cover = end;
        }
    return cover;
}

void st_pool_drop_level(st_pool *p, unsigned l)
{
    /* The blocks go to the spare list; a later level reuses them. */
    if (grow_u32(&p->spare, &p->capspare, p->nspare + p->nblocks[l]) == 0)
        for (uint32_t b = 0; b < p->nblocks[l]; b++)
            p->spare[p->nspare++] = p->blocks[l][b];
    for (uint32_t b = 0; b < p->nblocks[l]; b++)
        memset(p->ins + ((size_t)p->blocks[l][b] << ST_POOL_BLOCK_SHIFT), ST_FREE_LEVEL, ST_POOL_BLOCK);
    p->nblocks[l] = 0;
    p->fill[l] = ST_NIL;
    p->freehead[l] = ST_NIL;
    p->live[l] = 0;
}

uint64_t st_pool_count(const st_pool *p, unsigned l)
{
    uint64_t n = 0;
    for (unsigned k = 0; k <= l && k < ST_MAX_LEVELS; k++) n += p->live[k];
    return n;
}

uint32_t st_pool_block_list(const st_pool *p, unsigned l, uint32_t *out)
{
    uint32_t n = 0;
    for (unsigned k = 0; k <= l && k < ST_MAX_LEVELS; k++)
        for (uint32_t b = 0; b < p->nblocks[k]; b++, n++)
            if (out) out[n] = p->blocks[k][b] << ST_POOL_BLOCK_SHIFT;
    return n;
}

void st_pool_drop_bottom(st_pool *p)
{
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++)
        for (uint32_t b = 0; b < p->nblocks[l]; b++) {
            uint8_t *ins = p->ins + ((size_t)p->blocks[l][b] << ST_POOL_BLOCK_SHIFT);
            for (uint32_t i = 0; i < ST_POOL_BLOCK; i++)
                if (ins[i] != ST_FREE_LEVEL) ins[i]--;
        }
    /* Level 1's blocks and free ids join level 0. */
    if (grow_u32(&p->blocks[0], &p->capblocks[0], p->nblocks[0] + p->nblocks[1]) == 0) {
        memcpy(p->blocks[0] + p->nblocks[0], p->blocks[1], p->nblocks[1] * sizeof *p->blocks[1]);
        p->nblocks[0] += p->nblocks[1];
    }
    if (p->freehead[1] != ST_NIL) {
        uint32_t last = p->freehead[1];
        while (p->next_free[last] != ST_NIL) last = p->next_free[last];
        p->next_free[last] = p->freehead[0];
        p->freehead[0] = p->freehead[1];
    }
    p->live[0] += p->live[1];
    if (p->fill[0] == ST_NIL) p->fill[0] = p->fill[1];
    free(p->blocks[1]);
    for (unsigned l = 1; l + 1 < ST_MAX_LEVELS; l++) {
        p->blocks[l] = p->blocks[l + 1];
        p->nblocks[l] = p->nblocks[l + 1];
        p->capblocks[l] = p->capblocks[l + 1];
        p->fill[l] = p->fill[l + 1];
        p->freehead[l] = p->freehead[l + 1];
        p->live[l] = p->live[l + 1];
    }
    unsigned t = ST_MAX_LEVELS - 1;
    p->blocks[t] = NULL;
    p->nblocks[t] = p->capblocks[t] = p->live[t] = 0;
    p->fill[t] = p->freehead[t] = ST_NIL;
}

uint32_t *st_pool_blocks_newest_first(const st_pool *p, unsigned l, uint32_t *n)
{
    *n = st_pool_block_list(p, l, NULL);
    uint32_t *out = malloc(((size_t)*n + 1) * sizeof *out), k = 0;
    if (!out) return NULL;
    for (unsigned lv = l + 1; lv-- > 0;)
        for (uint32_t i = 0; i < p->nblocks[lv]; i++) out[k++] = p->blocks[lv][i] << ST_POOL_BLOCK_SHIFT;
    return out;
}
