/* Helpers shared by the full-level synthesis passes of the schemes.
 *
 * Block bits: which blocks of a pool (map.h: ids come in blocks of
 * ST_POOL_BLOCK, each owned by one insertion level) belong to level l.  For
 * any live id of level l, "inserted below l" (it reads its level-l column)
 * is then "its block is not one of level l's": one bit in a table of a few
 * kilobytes that stays in the first-level cache, instead of the id's
 * insertion level, a byte read at a random place per id. */
#ifndef ST_SYNTH_BLOCKS_H
#define ST_SYNTH_BLOCKS_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/map/map.h"

#include <stdint.h>
#include <stdlib.h>

/* Bit per block of p, set for the blocks of level l; NULL when out of memory. */
static inline uint64_t *st_block_bits(const st_pool *p, unsigned l)
{
    size_t nblocks = ((size_t)p->end >> ST_POOL_BLOCK_SHIFT) + 1;
    uint64_t *bits = calloc(nblocks / 64 + 1, sizeof *bits);
    if (!bits) return NULL;
    for (uint32_t i = 0; i < p->nblocks[l]; i++) bits[p->blocks[l][i] >> 6] |= 1ull << (p->blocks[l][i] & 63);
    return bits;
}

/* 1 if id lies in a block of the level the bits were made for. */
static inline unsigned st_block_bit(const uint64_t *bits, uint32_t id)
{
    uint32_t b = id >> ST_POOL_BLOCK_SHIFT;
    return (unsigned)(bits[b >> 6] >> (b & 63)) & 1u;
}

/* base or col, by a select: which one an id reads follows its insertion
 * level, which varies without pattern (a branch would be mispredicted). */
static inline const void *st_pick(const void *base, const void *col, int use_col)
{
    uintptr_t m = -(uintptr_t)(use_col != 0);
    return (const void *)(((uintptr_t)base & ~m) | ((uintptr_t)col & m));
}

#endif
