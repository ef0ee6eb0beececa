/* Dense renumbering of a map's ids, for writing a map without the ids it
 * freed (the session's HD image, core/io/session_write.c, chunk hdlv).
 *
 * Why: an adaptive hierarchy frees the darts and vertices of the faces it
 * coarsens, and its pools keep their slots (free lists, blocks of removed
 * levels).  A map written as it is carries those slots; written under this
 * renumbering it carries the live ids only, so that its bytes follow the
 * faces stored, not the ids ever handed out.
 *
 * The renumbering never touches the live map: it is a pair of tables and
 * the pools the map would have, which the writer reads the map through
 * (map_io_internal.h, st_map_write_renumbered).  The document keeps its
 * ids (undo steps hold them).
 *
 * What holds:
 *   - ids inserted at levels <= keep keep their numbers, and their blocks,
 *     fill pointers and free lists stay as they are: those levels are the
 *     model's, whose ids the display shares (ui/doc/editor_display.c reads
 *     a model vertex V of a level <= the base as display vertex V);
 *   - the live ids of each level above keep are packed into that level's
 *     blocks in increasing old id order (order-preserving within a level;
 *     across levels the block rule of st_pool, one level per block, allows
 *     no more), the blocks numbered from the lowest number no kept level
 *     owns, in the order the scan first needs them; every block of such a
 *     level is full but its last;
 *   - no free list above keep, no spare block: block numbers below the end
 *     that no level owns become the spare list (increasing);
 *   - it is idempotent: a map already in this form gets the identity, so
 *     that a map read back from the written bytes writes the same bytes. */
#ifndef ST_RENUMBER_INTERNAL_H
#define ST_RENUMBER_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/map/map.h"

/* One pool renumbered: the pool the ids would have and both directions. */
typedef struct st_pool_renumber {
    st_pool pool;          /* the renumbered pool (cap == end; no attached arrays) */
    uint32_t *new_of;      /* old id -> new id, ST_NIL for a free old id (old pool's end entries) */
    uint32_t *old_of;      /* new id -> old id, ST_NIL for a free new id (pool.end entries) */
} st_pool_renumber;

typedef struct st_map_renumber {
    unsigned keep;         /* ids of levels <= keep are kept */
    st_pool_renumber darts, verts;
} st_map_renumber;

/* The renumbering of m (see above).  -1 when out of memory (rn then empty). */
int st_map_renumber_make(const st_map *m, unsigned keep, st_map_renumber *rn);
void st_map_renumber_free(st_map_renumber *rn);
/* Whether it changes no id (the map is already in the renumbered form). */
int st_map_renumber_is_identity(const st_map_renumber *rn);

#endif
