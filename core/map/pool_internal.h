/* Internal: id pools and multilevel attributes behind st_map (see map.h). */
#ifndef ST_POOL_H
#define ST_POOL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/map/map.h"

void st_pool_init(st_pool *p);
void st_pool_free(st_pool *p);
/* Takes an id inserted at level l.  *grow is set to the new capacity the
 * attached arrays must reach (0 when the capacity did not change); the pool's
 * own ins[] is already grown.  Returns ST_NIL when memory runs out. */
uint32_t st_pool_take(st_pool *p, unsigned l, uint32_t *grow);
/* Takes a run of up to `want` (>= 1) consecutive ids at level l, in the order
 * st_pool_take would hand them out (free ids of the level first, one at a
 * time; then the rest of the level's current block, then a fresh block).
 * Returns the first id and sets *got; ST_NIL when memory runs out. */
uint32_t st_pool_take_run(st_pool *p, unsigned l, uint32_t want, uint32_t *got, uint32_t *grow);
/* Makes room for `more` further ids without doubling; returns the new
 * capacity (attached arrays must follow) or 0 when out of memory. */
uint32_t st_pool_reserve(st_pool *p, uint64_t more);
void st_pool_release(st_pool *p, uint32_t id);
/* 1 + the largest id ever handed out to a level < j (0 if none). */
uint32_t st_pool_cover(const st_pool *p, unsigned j);
/* Frees every id of level l and its blocks (level removal). */
void st_pool_drop_level(st_pool *p, unsigned l);
/* Live ids of levels 0..l. */
uint64_t st_pool_count(const st_pool *p, unsigned l);
/* Blocks of levels 0..l in enumeration order (st_dart_first/next): writes
 * their first ids to out (NULL: count only); returns how many. */
uint32_t st_pool_block_list(const st_pool *p, unsigned l, uint32_t *out);
/* First ids of the blocks of levels l, l-1, ..., 0 (newest first), malloc'd
 * (NULL when out of memory), *n of them: refinement numbers level l in the
 * order of the faces it came from, so neighbourhoods are close in memory in
 * this order (the synthesis passes of the schemes walk it). */
uint32_t *st_pool_blocks_newest_first(const st_pool *p, unsigned l, uint32_t *n);

void st_mla_init(st_mla *a, uint32_t elem);
void st_mla_free(st_mla *a);
/* A flat array (`*base`, elem bytes an element) to cap elements, keeping its
 * first `used`.  huge: an exact reservation (st_map_reserve) about to be
 * filled, moved into fresh huge-page memory before the elements in use are
 * copied (hugepage.h, st_realloc_huge); otherwise realloc, which keeps every
 * element: a doubling for one more id stays with realloc, since huge pages
 * would round its partly used tail up to 2 MiB.  -1 when out of memory
 * (*base then unchanged). */
int st_array_grow(unsigned char **base, size_t elem, uint32_t used, uint32_t cap, int huge);
/* st_array_grow of a's base array. */
int st_mla_grow(st_mla *a, uint32_t used, uint32_t cap, int huge);
/* New id inserted at level l with value v at every level >= l. */
void st_mla_insert(st_mla *a, const st_pool *p, uint32_t id, const void *v);
/* Value at level l := v, and at the levels above that still had the old
 * level-l value.  l >= ins[id]. */
void st_mla_set(st_mla *a, const st_pool *p, uint32_t id, unsigned l, const void *v);
/* Writable column of level l (materialised if needed); NULL when l == 0 or
 * out of memory.  Only for bulk writers that know no column above l exists. */
void *st_mla_column(st_mla *a, const st_pool *p, unsigned l);
/* Same, without copying level l-1 into a new column: every value of ids
 * inserted before l must then be written by the caller. */
void *st_mla_column_for_overwrite(st_mla *a, const st_pool *p, unsigned l);
/* Removes the column of level l (level removal). */
void st_mla_drop_column(st_mla *a, unsigned l);
/* Level 1 becomes level 0 (call before st_pool_drop_bottom: it reads the
 * old insertion levels). */
void st_mla_drop_bottom(st_mla *a, const st_pool *p);
/* Merges levels 0 and 1 and renumbers the levels above one down. */
void st_pool_drop_bottom(st_pool *p);
/* Shrinks base to the pool's capacity and each column to the ids it can
 * hold (st_pool_cover); never fails (a failed shrink keeps the block). */
void st_mla_trim(st_mla *a, const st_pool *p);
/* Capacity := end (the ids handed out); attached arrays must follow. */
void st_pool_trim(st_pool *p);
/* Sparse form (map.h, "Sparse form"): 1 when a now holds it, 0 when it
 * stays dense (no columns, or the sparse form would not halve them), -1
 * when out of memory (dense, unchanged). */
int st_mla_freeze(st_mla *a, const st_pool *p);
/* Back to the dense columns it came from (aborts when out of memory, like
 * the setters that call it); nothing when a is dense. */
void st_mla_thaw(st_mla *a, const st_pool *p);
/* A 4-byte attribute with no column (its base values written) takes the
 * n changes (id[k], lvl[k], val[k]), in increasing level order, each the
 * value of an id inserted below lvl[k] at that level, differing from its
 * value one level down, an id at most once a level: a ends as the map
 * after st_mla_set of each change and st_map_compact would leave it,
 * sparse form, column marks and capacities included, without making the
 * dense columns when the sparse form is chosen (a progressive map
 * replayed from its recipe, core/progressive/progressive_replay.c).
 * -1: out of memory (a may hold some changes; the caller frees it). */
int st_mla_set_changes(st_mla *a, const st_pool *p, const uint32_t *id, const uint8_t *lvl, const uint32_t *val,
                       uint64_t n);
/* The same changes as the dense columns st_mla_set of each would make
 * (before any st_map_compact): for a builder that reads the levels before
 * compacting them; st_mla_drop_columns then st_mla_set_changes turns them
 * into what st_map_compact would, without comparing the columns.  -1: out
 * of memory (a may hold some columns; the caller frees it). */
int st_mla_columns_from_changes(st_mla *a, const st_pool *p, const uint32_t *id, const uint8_t *lvl, const uint32_t *val,
                                uint64_t n);
void st_mla_drop_columns(st_mla *a);
size_t st_mla_sparse_bytes(const st_mla *a);
size_t st_mla_bytes(const st_mla *a, uint32_t cap);

/* ---- bulk writers (refine.c) ------------------------------------------------
 * Runs of new darts / vertices inserted at level l (st_pool_take_run) whose
 * relations, flags and positions the caller writes itself, straight into the
 * base arrays: attached attributes and marks are zeroed, nothing else is
 * initialised.  They abort when memory runs out, like st_dart_new. */
uint32_t st_dart_take_run(st_map *m, unsigned l, uint32_t want, uint32_t *got);
uint32_t st_vertex_take_run(st_map *m, unsigned l, uint32_t want, uint32_t *got);

#endif
