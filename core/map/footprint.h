/* st_footprint: the values a local edit of a multiresolution hierarchy wrote
 * (Kraemer 2008 §3.2: editing level i changes P_i and D_i of the moved
 * vertices and the positions of the levels above that the local
 * re-synthesis reaches).
 *
 * Core reports it once, where the values are written (core/multires/edit.h:
 * st_hier_edit, st_hier_restore, st_hier_resynth_around); the consumers take
 * it as it is: undo saves the old values of exactly these keys, the
 * interest box's display copies exactly these positions, the renderer
 * re-reads exactly these vertices.  A key is (level, kind, vertex id):
 * kind ST_FP_POS for the position of the vertex at that level, ST_FP_DETAIL
 * for its detail vector at that level.  A key may appear more than once.
 *
 * This header needs nothing but <stdint.h>, so that the renderer can take a
 * footprint without knowing the hierarchy or its scheme. */
#ifndef ST_FOOTPRINT_H
#define ST_FOOTPRINT_H

#include <stdint.h>

enum st_fp_kind { ST_FP_POS = 0, ST_FP_DETAIL = 1 };

static inline uint64_t st_fp_key(unsigned level, int kind, uint32_t vid)
{
    return (uint64_t)level << 33 | (uint64_t)(kind & 1) << 32 | vid;
}
static inline unsigned st_fp_level(uint64_t key) { return (unsigned)(key >> 33); }
static inline int st_fp_kind(uint64_t key) { return (int)(key >> 32) & 1; }
static inline uint32_t st_fp_vid(uint64_t key) { return (uint32_t)key; }

typedef struct st_footprint {
    uint64_t *keys;
    uint32_t n, cap;
} st_footprint;

/* Appends a key (grows; aborts when out of memory, as the synthesis does). */
void st_footprint_add_slow(st_footprint *f, uint64_t key);
static inline void st_footprint_add(st_footprint *f, uint64_t key)
{
    if (f->n < f->cap) f->keys[f->n++] = key; /* no call while there is room */
    else st_footprint_add_slow(f, key);
}
void st_footprint_free(st_footprint *f);

#endif
