/* Local edits of an st_hier that report their footprint (footprint.h).
 *
 * Editing at level l (Kraemer 2008 §3.2; Blender multires conventions, see
 * hier.h) writes P_l and D_l of the moved vertices and re-synthesises the
 * levels above locally; coarser levels never change.  Core knows exactly
 * which values it writes, so it reports them once here and the callers
 * (undo, the interest box's display, the renderer) take that set instead
 * of working the region out again. */
#ifndef ST_EDIT_H
#define ST_EDIT_H

#include "core/map/footprint.h"
#include "core/multires/hier.h"

/* st_hier_move, appending to fp (NULL: nothing) every value it wrote:
 * (l, ST_FP_POS) and, for l >= 1, (l, ST_FP_DETAIL) of the moved vertices,
 * then (L, ST_FP_POS) of each vertex re-synthesised at L = l+1..top, level
 * by level.  Returns the number of positions recomputed above l. */
uint64_t st_hier_edit(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                      st_footprint *fp);

/* Decides what st_hier_edit_with stores for vertex v of level l >= 1: det
 * holds F^T (P_l - S(P_{l-1})) for the position the edit gave; pred is
 * S(P_{l-1}) and f the frame (rows t, b, n).  The hook writes the detail
 * to store into det and the level-l position into pos (sculpt layers,
 * core/multires/layers.h, split the change between the layers and store
 * their composition). */
typedef void (*st_detail_hook)(void *ctx, unsigned l, uint32_t v, double det[3], const double pred[3],
                               const double f[3][3], double pos[3]);

/* st_hier_edit, where for l >= 1 the hook (NULL: none, st_hier_edit)
 * chooses each moved vertex's detail and position.  With a hook, the
 * stencil of v is the one found from the smallest dart of v's vertex orbit
 * at level l, so that the prediction is the same for the same vertex
 * whatever dart the caller gave.  pos NULL: the positions are not written
 * first (the hook recomposes the details from elsewhere).  The same
 * footprint as st_hier_edit. */
uint64_t st_hier_edit_with(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                           st_footprint *fp, st_detail_hook hook, void *ctx);

/* A cache of the predictions S(P_{l-1})(v) and frames of the vertices an
 * edit sequence at one level touches (a brush stroke re-touches the same
 * vertices dab after dab).  They depend on level l-1 only: the owner
 * clears the cache (or drops it) before anything may have changed level
 * l-1 or the topology; within a stroke or drag at level l nothing does.
 * The values are the ones the edit would compute, so the results are the
 * same bit for bit. */
typedef struct st_edit_cache st_edit_cache;
st_edit_cache *st_edit_cache_new(void);
void st_edit_cache_clear(st_edit_cache *c);
void st_edit_cache_free(st_edit_cache *c);
/* A caller that takes another prediction for v than the edit's (core/adapt's
 * HD edits take the canonical face's, adapt_resynth.c) puts it in the
 * cache once, for the next edits of the sequence, whose hook then gets it
 * as `pred`; st_edit_cache_pred_fixed tells whether it was put there. */
void st_edit_cache_set_pred(st_edit_cache *c, unsigned l, uint32_t v, const double pred[3]);
int st_edit_cache_pred_fixed(const st_edit_cache *c, unsigned l, uint32_t v);
/* st_hier_edit_with using the cache (NULL: none). */
uint64_t st_hier_edit_cached(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                             st_footprint *fp, st_detail_hook hook, void *ctx, st_edit_cache *cache);

/* The level-l part of st_hier_edit_cached alone: writes the positions (pos
 * NULL: none), refreshes the details of the darts' vertices for l >= 1
 * (with the hook, as st_hier_edit_with), and appends (l, ST_FP_POS) and,
 * for l >= 1, (l, ST_FP_DETAIL) of each to fp (NULL: nothing).  Nothing
 * above l is re-synthesised: the caller does it, e.g. an adaptive
 * hierarchy, whose region growth must keep to the subdivided faces
 * (core/adapt: st_adapt_edit).  Returns the number of values named at l
 * (n positions, and n details for l >= 1; a vertex given twice counts
 * twice). */
uint64_t st_hier_edit_level(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                            st_footprint *fp, st_detail_hook hook, void *ctx, st_edit_cache *cache);

/* The position a synthesis gives from a prediction, a frame and a detail:
 * pred + F^T det, summed as st_stencil_apply sums it. */
static inline void st_hier_apply_detail(const double pred[3], const double f[3][3], const double det[3], double out[3])
{
    for (int i = 0; i < 3; i++) out[i] = pred[i];
    if (det[0] == 0 && det[1] == 0 && det[2] == 0) return;
    for (int i = 0; i < 3; i++) out[i] += det[0] * f[0][i] + det[1] * f[1][i] + det[2] * f[2][i];
}

/* The footprint st_hier_edit(h, l, darts, ., n, .) writes, appended to fp
 * without writing anything, so that old values can be saved first (undo).
 * The same region growth and stencils as the edit, with a sink that only
 * records; the region depends on the seeds and the topology, not on the new
 * positions, so one query covers every update of a drag. */
void st_hier_edit_footprint(st_hier *h, unsigned l, const uint32_t *darts, uint32_t n, st_footprint *fp);

/* The value a key names: the position at its level, or the detail vector
 * (zero when none is stored). */
void st_hier_value(const st_hier *h, uint64_t key, double out[3]);
/* Writes the value a key names (positions are stored only where they differ
 * from the inherited value, hier.h).  Nothing is re-synthesised. */
void st_hier_set_value(st_hier *h, uint64_t key, const double v[3]);

/* Writes saved values back, e.g. undo and redo of an edit with the values of
 * its whole footprint, and appends the keys to fp (NULL: nothing).  Nothing
 * is re-synthesised: the keys cover every value the edit wrote, so writing
 * them back is bit-exact, where a re-synthesis would round differently on a
 * level that was edited directly. */
void st_hier_restore(st_hier *h, const uint64_t *keys, const double (*values)[3], uint32_t n, st_footprint *fp);

#endif
