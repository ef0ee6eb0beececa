/* Sculpt layers of a multiresolution hierarchy.
 *
 * A layer lives at one level l >= 1 (level 0: below) and holds its own
 * detail offsets O_k(v), one per vertex of level l, in the same local
 * frames F_l(v) as the hierarchy's detail vectors (hier.h; Kraemer 2008
 * §3.1: frames come from the coarser surface, so whatever moves level l-1
 * or below carries the offsets along).  A level with layers keeps its details without any
 * layer, B_l(v), and the hierarchy's detail is always their composition
 *     D_l(v) = B_l(v) + s_1 O_1(v) + s_2 O_2(v) + ...
 * over the visible layers of level l with a strength s_k != 0, added in
 * stack order (bottom first).  The hierarchy itself stays an ordinary
 * st_hier: synthesis, exports, bakes and sessions see the visible layers
 * at their strengths and pay nothing for the layers themselves; a level
 * without layers has no B_l and is edited exactly as before.
 *
 * Exactness: a layer at strength 0 (or hidden) is left out of the sum, so
 * the details are bit for bit those without it.  Positions: a vertex with
 * a layer contribution gets its level-l position from its details as a
 * synthesis does, S(P_{l-1}) + F D, with the stencil found from the
 * smallest dart of the vertex (st_hier_edit_with), so the same strengths
 * give the same surface bit for bit (strength 1: the surface as sculpted).
 * A vertex with no contribution gets back the position it had without
 * layers, kept when a layer first changed it (P0_l), so strength 0 gives
 * the surface without the layer bit for bit.  An edit of a coarser level
 * rewrites P_l by the local re-synthesis: where no layer contributes, that
 * is the surface without layers and P0_l follows it (st_layers_follow);
 * where one does, P0_l is forgotten, and strength 0 later gives
 * S(P_{l-1}) + F B_l, equal to the re-synthesis without layers up to the
 * order of the stencil's sum (rounding, 1e-15 relative).
 *
 * Level 0 (the control mesh) has no coarser level, so no prediction, no
 * frames and no detail vectors: there a layer's offsets are plain
 * object-space offsets of the vertices, B_0 holds the positions without
 * layers and the position is the composition itself,
 *     P_0(v) = B_0(v) + s_1 O_1(v) + s_2 O_2(v) + ...
 * (same order and rule as above).  Strength 0 or hidden gives B_0, the
 * control mesh without the layer, bit for bit (no P0 is needed there);
 * the same strengths give the same positions bit for bit, and the levels
 * above are re-synthesised from them as after any edit of level 0.  A
 * level-0 offset is a fixed vector: it does not turn with the surface
 * (nothing is coarser to carry it).
 *
 * Layers at different levels combine: each level composes its own. */
#ifndef ST_LAYERS_H
#define ST_LAYERS_H

#include <stddef.h>
#include <stdint.h>

#include "core/base/st_error.h"
#include "core/multires/edit.h"
#include "core/multires/hier.h"

#define ST_LAYER_NAME 64
#define ST_LAYER_MAX 64
#define ST_LAYER_STRENGTH_MAX 2.0

typedef struct st_layer {
    char name[ST_LAYER_NAME];  /* NUL-terminated */
    unsigned level;            /* 0 .. top */
    double strength;           /* 0 .. ST_LAYER_STRENGTH_MAX */
    int hidden;
    double *off;               /* 3 doubles per vertex id below cap (NULL: all zero) */
    uint32_t cap;
} st_layer;

typedef struct st_layers {
    st_layer *v;               /* the stack, bottom first */
    uint32_t n, cap;
    int active;                /* index of the layer strokes go into, -1: the level's own details */
    double *base[ST_MAX_LEVELS];   /* B_l per vertex id (3 doubles), for levels with layers (level 0: positions) */
    uint32_t base_cap[ST_MAX_LEVELS];
    double *bpos[ST_MAX_LEVELS];   /* P0_l per vertex id (3 doubles; NaN: not kept); never for level 0 */
    uint32_t bpos_cap[ST_MAX_LEVELS];
} st_layers;

void st_layers_init(st_layers *ls);
void st_layers_free(st_layers *ls);
/* Deep copy; -1 when out of memory (dst empty). */
int st_layers_copy(st_layers *dst, const st_layers *src);
size_t st_layers_bytes(const st_layers *ls);
/* Number of layers at level l. */
uint32_t st_layers_on_level(const st_layers *ls, unsigned l);

/* A new empty layer on top of the stack at level l (0..top), made active.
 * The first layer of a level takes the level's details as B_l (level 0:
 * its positions).  Returns its index, or -1 with err filled (above top,
 * too many). */
int st_layers_add(st_layers *ls, const st_hier *h, unsigned l, const char *name, st_error *err);

/* One stored value: slot -1 is B_l(v), slot -2 is P0_l(v) (NaN when not
 * kept), slot k >= 0 is O_k(v) (l ignored).  Set grows the arrays; undo
 * writes values back with it. */
#define ST_LAYERS_SLOT_BASE (-1)
#define ST_LAYERS_SLOT_BPOS (-2)
void st_layers_get(const st_layers *ls, int slot, unsigned l, uint32_t v, double out[3]);
void st_layers_set(st_layers *ls, int slot, unsigned l, uint32_t v, const double val[3]);

/* An edit at level l (st_hier_edit's arguments) whose change of detail goes
 * into slot `target` (-1: B_l; else a visible layer of level l with a
 * strength != 0): O_t = (D_new - rest) / s_t, then D_l is recomposed
 * (level 0: D is the position).  Without layers on level l this is
 * st_hier_edit.  Same footprint as
 * st_hier_edit; cache as st_hier_edit_cached (may be NULL). */
uint64_t st_layers_edit(st_layers *ls, st_hier *h, unsigned l, int target, const uint32_t *darts,
                        const double (*pos)[3], uint32_t n, st_footprint *fp, st_edit_cache *cache);

/* Recomposes D_l of the vertices of the darts (level l) after a change of
 * strengths, visibility, order or offsets, and re-synthesises above. */
uint64_t st_layers_recompose(st_layers *ls, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n,
                             st_footprint *fp);

/* After an edit at level l reported its footprint (keys,
 * core/map/footprint.h): P0 of the vertices it rewrote on layered
 * levels above l follows where no layer contributes, else is forgotten. */
void st_layers_follow(st_layers *ls, const st_hier *h, unsigned l, const uint64_t *keys, uint32_t n);

/* The parts of an edit for callers that compute the details themselves:
 * core/adapt's HD edits (adapt.h, "HD levels"), whose positions are always
 * S(P_{l-1}) + F D (st_adapt_edit), so that D alone gives a position back
 * and these keep no P0: strength 0 or hidden gives S(P_{l-1}) + F B_l,
 * which is the surface without the layer bit for bit.
 * st_layers_edit_target: the slot an edit of level l into `target` goes
 * to (-1: B_l; a hidden layer, one at strength 0 or one of another level
 * takes nothing).  st_layers_take: the new detail det of v split into that
 * slot (O_t = (det - rest) / s_t, or B_l = det - the layers' sum), then det
 * becomes the composition D_l(v).  st_layers_compose: D_l(v) into det. */
int st_layers_edit_target(const st_layers *ls, unsigned l, int target);
void st_layers_take(st_layers *ls, unsigned l, uint32_t v, int target, double det[3]);
void st_layers_compose(const st_layers *ls, unsigned l, uint32_t v, double det[3]);

/* Whether v holds anything of the layers of level l: a non-zero B_l or
 * offset, or a kept P0.  An adaptive hierarchy keeps the faces around such
 * vertices refined (st_adapt.keep_layers), so that vertex ids the layers
 * index are never freed and re-used. */
int st_layers_holds(const st_layers *ls, unsigned l, uint32_t v);

/* Darts of the layer's level (one per vertex) of the vertices where layer
 * k has a non-zero offset, into *darts (grown; *cap its capacity).
 * Returns their number. */
uint32_t st_layers_support(const st_layers *ls, const st_hier *h, int k, uint32_t **darts, uint32_t *cap);

/* Stack operations (no geometry: the caller recomposes the support).
 * move: layer k to index `to`; merge_down: layer k into k-1 (same level),
 * O_{k-1} = s_{k-1} O_{k-1} + s_k O_k over the visible ones, strength 1,
 * visible; remove: layer k out of the stack, B_l dropped when it was the
 * level's last layer (recompose first with it hidden: D_l = B_l then). */
int st_layers_move(st_layers *ls, int k, int to, st_error *err);
int st_layers_merge_down(st_layers *ls, int k, st_error *err);
int st_layers_remove(st_layers *ls, int k, st_error *err);
int st_layers_rename(st_layers *ls, int k, const char *name, st_error *err);

/* Moves every layer of src (with its levels' B_l and P0) on top of dst's
 * stack; src is left empty.  Their levels must hold no layer of dst (a
 * session's HD layers join the model's).  dst's active layer stays, or
 * becomes src's when dst had none.  -1 with err filled: a level shared,
 * too many layers, out of memory (both unchanged). */
int st_layers_append(st_layers *dst, st_layers *src, st_error *err);

/* After the coarsest level was removed (st_hier_remove_bottom): levels shift
 * down by one.  Refused (-1) while a layer is on level 0 (it would be lost)
 * or 1 (its offsets are in frames that level 0 would no longer define). */
int st_layers_rebase(st_layers *ls, st_error *err);

#endif
