/* Dense renumbering of a map's ids (renumber_internal.h). */
#include "core/map/renumber_internal.h"
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

/* Marks the blocks the kept levels own (they keep their numbers). */
static void mark_kept_blocks(const st_pool *p, unsigned keep, uint8_t *kept)
{
    for (unsigned l = 0; l <= keep && l < ST_MAX_LEVELS; l++)
        for (uint32_t b = 0; b < p->nblocks[l]; b++) kept[p->blocks[l][b]] = 1;
}

/* Block lists of the levels above keep, sized for their live ids packed
 * (every block full but the last).  -1 when out of memory. */
static int alloc_packed_lists(const st_pool *p, unsigned keep, st_pool *q)
{
    for (unsigned l = keep + 1; l < ST_MAX_LEVELS; l++) {
        uint32_t n = (p->live[l] + ST_POOL_BLOCK - 1) >> ST_POOL_BLOCK_SHIFT;
        if (!n) continue;
        q->blocks[l] = malloc((size_t)n * sizeof *q->blocks[l]);
        if (!q->blocks[l]) return -1;
        q->capblocks[l] = n;
    }
    return 0;
}

/* The new ids: kept ids unchanged, the others packed per level in old id
 * order into blocks taken from the lowest number no kept level owns, in
 * the order the scan first needs them.  cursor[l] ends as the level's fill
 * pointer.  Returns 1 + the highest block number in use. */
static uint32_t assign_ids(const st_pool *p, unsigned keep, const uint8_t *kept, st_pool_renumber *r,
                           uint32_t cursor[ST_MAX_LEVELS])
{
    st_pool *q = &r->pool;
    uint32_t nextb = 0, used = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) cursor[l] = ST_NIL;
    for (uint32_t b = 0; b < p->end >> ST_POOL_BLOCK_SHIFT; b++)
        if (kept[b]) used = b + 1;
    for (uint32_t i = 0; i < p->end; i++) {
        unsigned l = p->ins[i];
        if (l == ST_FREE_LEVEL) { r->new_of[i] = ST_NIL; continue; }
        if (l <= keep) { r->new_of[i] = i; continue; }
        if (cursor[l] == ST_NIL) {
            while (kept[nextb]) nextb++;   /* (packing never needs more blocks than p has) */
            q->blocks[l][q->nblocks[l]++] = nextb;
            cursor[l] = nextb << ST_POOL_BLOCK_SHIFT;
            if (nextb + 1 > used) used = nextb + 1;
            nextb++;
        }
        r->new_of[i] = cursor[l]++;
        if (!(cursor[l] & (ST_POOL_BLOCK - 1))) cursor[l] = ST_NIL;   /* block full: the next id opens one */
    }
    return used;
}

/* ins, old_of, fill pointers and free lists of the renumbered pool. */
static int fill_pool(const st_pool *p, unsigned keep, const uint8_t *kept, st_pool_renumber *r,
                     const uint32_t cursor[ST_MAX_LEVELS])
{
    st_pool *q = &r->pool;
    size_t n = q->end ? q->end : 1;
    q->ins = malloc(n);
    r->old_of = malloc(n * sizeof *r->old_of);
    if (!q->ins || !r->old_of) return -1;
    memset(q->ins, ST_FREE_LEVEL, n);
    for (uint32_t j = 0; j < q->end; j++) r->old_of[j] = ST_NIL;
    for (uint32_t b = 0; b < q->end >> ST_POOL_BLOCK_SHIFT; b++)
        if (kept[b]) memcpy(q->ins + ((size_t)b << ST_POOL_BLOCK_SHIFT), p->ins + ((size_t)b << ST_POOL_BLOCK_SHIFT), ST_POOL_BLOCK);
    for (uint32_t i = 0; i < p->end; i++) {
        uint32_t j = r->new_of[i];
        if (j == ST_NIL) continue;
        q->ins[j] = p->ins[i];
        r->old_of[j] = i;
    }
    int kept_free = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        q->live[l] = p->live[l];
        q->fill[l] = l <= keep ? p->fill[l] : cursor[l];
        q->freehead[l] = l <= keep ? p->freehead[l] : ST_NIL;
        kept_free |= q->freehead[l] != ST_NIL;
    }
    /* The kept levels' free ids keep their chains (their ids are kept). */
    if (kept_free) {
        q->next_free = malloc(n * sizeof *q->next_free);
        if (!q->next_free) return -1;
        for (uint32_t j = 0; j < q->end; j++) q->next_free[j] = ST_NIL;
        for (unsigned l = 0; l <= keep && l < ST_MAX_LEVELS; l++)
            for (uint32_t id = p->freehead[l]; id != ST_NIL; id = p->next_free[id]) q->next_free[id] = p->next_free[id];
    }
    return 0;
}

/* Block numbers below the end that no level owns: the spare list, in
 * increasing order, so that later levels reuse them as st_pool does. */
static int spare_blocks(st_pool_renumber *r, const uint8_t *kept)
{
    st_pool *q = &r->pool;
    uint32_t nb = q->end >> ST_POOL_BLOCK_SHIFT;
    uint8_t *owned = calloc(nb ? nb : 1, 1);
    if (!owned) return -1;
    for (uint32_t b = 0; b < nb; b++) owned[b] = kept[b];
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
        for (uint32_t k = 0; k < q->nblocks[l]; k++) owned[q->blocks[l][k]] = 1;
    uint32_t n = 0;
    for (uint32_t b = 0; b < nb; b++) n += !owned[b];
    if (n) {
        q->spare = malloc((size_t)n * sizeof *q->spare);
        if (!q->spare) { free(owned); return -1; }
        for (uint32_t b = 0; b < nb; b++)
            if (!owned[b]) q->spare[q->nspare++] = b;
        q->capspare = n;
    }
    free(owned);
    return 0;
}

static void pool_renumber_free(st_pool_renumber *r)
{
    st_pool_free(&r->pool);
    free(r->new_of);
    free(r->old_of);
    r->new_of = r->old_of = NULL;
}

static int pool_renumber(const st_pool *p, unsigned keep, st_pool_renumber *r)
{
    st_pool_init(&r->pool);
    r->old_of = NULL;
    uint32_t nb = p->end >> ST_POOL_BLOCK_SHIFT;
    /* one more entry: the scan for a free block number may look one past */
    uint8_t *kept = calloc((size_t)nb + 1, 1);
    r->new_of = malloc((p->end ? p->end : 1) * sizeof *r->new_of);
    int rc = -1;
    if (!kept || !r->new_of) goto out;
    mark_kept_blocks(p, keep, kept);
    /* Kept levels: their block lists as they are. */
    for (unsigned l = 0; l <= keep && l < ST_MAX_LEVELS; l++) {
        uint32_t n = p->nblocks[l];
        if (!n) continue;
        r->pool.blocks[l] = malloc((size_t)n * sizeof *r->pool.blocks[l]);
        if (!r->pool.blocks[l]) goto out;
        memcpy(r->pool.blocks[l], p->blocks[l], (size_t)n * sizeof *p->blocks[l]);
        r->pool.nblocks[l] = r->pool.capblocks[l] = n;
    }
    if (alloc_packed_lists(p, keep, &r->pool)) goto out;
    uint32_t cursor[ST_MAX_LEVELS];
    r->pool.end = r->pool.cap = assign_ids(p, keep, kept, r, cursor) << ST_POOL_BLOCK_SHIFT;
    if (fill_pool(p, keep, kept, r, cursor) || spare_blocks(r, kept)) goto out;
    rc = 0;
out:
    free(kept);
    if (rc) pool_renumber_free(r);
    return rc;
}

int st_map_renumber_make(const st_map *m, unsigned keep, st_map_renumber *rn)
{
    memset(rn, 0, sizeof *rn);
    rn->keep = keep;
    if (pool_renumber(&m->darts, keep, &rn->darts)) return -1;
    if (pool_renumber(&m->verts, keep, &rn->verts)) {
        pool_renumber_free(&rn->darts);
        return -1;
    }
    return 0;
}

void st_map_renumber_free(st_map_renumber *rn)
{
    pool_renumber_free(&rn->darts);
    pool_renumber_free(&rn->verts);
}

static int pool_same_ids(const st_pool_renumber *r)
{
    for (uint32_t j = 0; j < r->pool.end; j++)
        if (r->old_of[j] != ST_NIL && r->old_of[j] != j) return 0;
    return 1;
}

int st_map_renumber_is_identity(const st_map_renumber *rn)
{
    return pool_same_ids(&rn->darts) && pool_same_ids(&rn->verts);
}
