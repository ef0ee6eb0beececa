/* HD levels (adapt.h, "HD levels"): editing an adaptive hierarchy at a
 * level above its uniform ones, which vertices such an edit may move, and
 * what each adaptive level holds.
 *
 * An edit at level l of an adaptive hierarchy is the regular one at l (the
 * level-l positions, details D_l = F^T (P_l - S(P_{l-1})), Kraemer 2008
 * §3.2, and their footprint: st_hier_edit_level) followed by the adaptive
 * region growth above l (st_hier_resynth_around, which keeps to the faces
 * subdivided toward the next level, §3.3.1).  The regular edit's own growth
 * (st_hier_edit) would re-synthesise unsubdivided faces, whose children do
 * not exist in an adaptive map. */
#include "core/adapt/adapt_internal.h"
#include "core/map/map_memory.h"
#include "core/multires/edit.h"
#include "core/multires/hier_internal.h"
#include "core/multires/layers.h"

#include <string.h>

/* ---- editing ---------------------------------------------------------------- */

typedef struct hd_edit {
    st_hier *h;
    uint32_t dart;             /* the vertex being edited */
    const double *target;      /* the position the edit asks for */
    st_footprint *fp;
    st_edit_cache *cache;      /* NULL, or the edit sequence's predictions (edit.h) */
    st_layers *ls;             /* NULL, or the sculpt layers of the edited level */
    int slot;                  /* where the change goes (st_layers_edit_target) */
    uint64_t followed;         /* inherited positions above l that followed */
} hd_edit;

/* Sets P_l(v) to p with the levels above l that still inherit its old
 * value following (st_set_pos stops at the first level that diverged: there
 * v is a vertex of a subdivided face, which the re-synthesis rewrites).
 * The adaptive synthesis writes with st_set_pos too, so a vertex that no
 * finer face holds shows its level-l position at the top level, as after
 * a full synthesis.  The followed levels are read first, for fp. */
static void set_following(hd_edit *c, uint32_t v, unsigned l, const double p[3])
{
    st_map *m = &c->h->map;
    double old[3];
    memcpy(old, st_pos(m, v, l), sizeof old);
    for (unsigned k = l + 1; k <= m->top; k++) {
        if (memcmp(st_pos(m, v, k), old, sizeof old) != 0) break;
        c->followed++;
        if (c->fp) st_footprint_add(c->fp, st_fp_key(k, ST_FP_POS, v));
    }
    st_set_pos(m, v, l, p);
}

/* The detail hook (edit.h) of an HD edit: D = F^T (P - S(P_{l-1})) for the
 * asked position P, and the level-l position pred + F^T D summed as
 * st_stencil_apply sums it, so that re-synthesising level l from l-1 gives
 * these bits back (P itself may differ from them in the last bit).  pred
 * is the one of the stencil a synthesis takes (adapt_resynth.c: the
 * canonical face's), which may differ in the last bit from the one the
 * edit found on the vertex's first face; the frame is the same (frames
 * are taken from their cell's smallest dart, hier_synth.c). */
static void hd_hook(void *ctx, unsigned l, uint32_t v, double det[3], const double pred0[3], const double f[3][3],
                    double pos[3])
{
    hd_edit *c = ctx;
    double r[3], pred[3];
    /* The canonical prediction once per vertex and edit sequence: the
     * cache gives it back as pred0 afterwards. */
    if (st_edit_cache_pred_fixed(c->cache, l, v)) memcpy(pred, pred0, sizeof pred);
    else if (st_adapt_canonical_pred(c->h, l, c->dart, pred)) st_edit_cache_set_pred(c->cache, l, v, pred);
    else memcpy(pred, pred0, sizeof pred);
    if (!c->target) {
        st_layers_compose(c->ls, l, v, det); /* a recomposition */
    } else {
        st_sub3(c->target, pred, r);
        for (int i = 0; i < 3; i++) det[i] = st_dot3(f[i], r);
        if (c->ls) st_layers_take(c->ls, l, v, c->slot, det);
    }
    st_hier_apply_detail(pred, f, det, pos);
    set_following(c, v, l, pos);
}

uint64_t st_adapt_edit(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                       st_footprint *fp, st_edit_cache *cache)
{
    return st_adapt_edit_layered(h, NULL, -1, l, darts, pos, n, fp, cache);
}

uint64_t st_adapt_edit_layered(st_hier *h, st_layers *ls, int target, unsigned l, const uint32_t *darts,
                               const double (*pos)[3], uint32_t n, st_footprint *fp, st_edit_cache *cache)
{
    st_map *m = &h->map;
    if (ls && (!l || !st_layers_on_level(ls, l))) ls = NULL; /* (level 0 is never an HD level) */
    if (!ls && !pos) return 0;
    hd_edit c = { .h = h, .fp = fp, .cache = cache, .ls = ls, .slot = ls ? st_layers_edit_target(ls, l, target) : -1 };
    /* One vertex per call, the hook's target being that vertex's position:
     * the hook is given the vertex id, not the index in darts.  pos NULL in
     * the call, so that the old level-l position is still there for the
     * levels above to follow (set_following). */
    for (uint32_t i = 0; i < n; i++) {
        c.dart = darts[i];
        c.target = pos ? pos[i] : NULL;
        if (l == 0) set_following(&c, st_vert(m, darts[i], 0), 0, pos[i]); /* no detail (nor layer) at level 0 */
        st_hier_edit_level(h, l, &darts[i], NULL, 1, fp, l ? hd_hook : NULL, &c, cache);
    }
    return c.followed + st_hier_resynth_around(h, l, darts, n, fp);
}

int st_adapt_scheme_has_hd(const st_scheme *sc)
{
    if (!sc) return 0;
    switch (sc->id) {
    case ST_SCHEME_CATMARK:
    case ST_SCHEME_LOOP:
    case ST_SCHEME_BUTTERFLY:
    case ST_SCHEME_QUADTRI: return 1;
    default: return 0;
    }
}

/* ---- which vertices a level-L brush may move ------------------------------------ */

int st_adapt_vertex_editable(st_map *m, uint32_t d, unsigned L)
{
    if (L < 1 || L > m->top) return 0;
    uint32_t x = d;
    do {
        /* A hole has no subdivision level; the vertex's real faces decide. */
        if (!st_is_boundary(m, x) && st_face_level(m, x, L) != L) return 0;
        x = st_beta1(m, x, L);
    } while (x != d);
    return 1;
}

/* ---- what each level holds ------------------------------------------------------- */

/* d is the smallest dart of its face at level L: each face counted once
 * without a marker bit (the map is const here). */
static int face_leader(const st_map *m, uint32_t d, unsigned L)
{
    uint32_t x = st_phi1(m, d, L);
    for (; x != d; x = st_phi1(m, x, L))
        if (x < d) return 0;
    return 1;
}

void st_adapt_hd_levels(const st_map *m, unsigned from, uint64_t faces[ST_MAX_LEVELS], uint64_t bytes[ST_MAX_LEVELS])
{
    for (unsigned L = 0; L < ST_MAX_LEVELS; L++) faces[L] = bytes[L] = 0;
    for (unsigned L = from + 1; L <= m->top && L < ST_MAX_LEVELS; L++) {
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it))
            if (!st_is_boundary(m, d) && face_leader(m, d, L) && st_adapt_face_of_level(m, d, L)) faces[L]++;
        st_map_bytes b;
        st_map_level_memory(m, L, &b);
        bytes[L] = b.topology + b.positions + (uint64_t)m->verts.live[L] * 3 * sizeof(double);
    }
}
