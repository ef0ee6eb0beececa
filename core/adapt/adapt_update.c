/* The updates of an adaptive hierarchy (Kraemer 2008 §3.2.5): Algorithm 5
 * (refine, coarse to fine) then Algorithm 6 (simplify, fine to coarse) with
 * the criteria of st_adapt_params, over the whole map or, when only the
 * interest box moved, over the region near the old and the new box.
 *
 * Invariant: the result of an update is the same whatever came before and
 * whichever path computed it - a full update and an incremental one give
 * the same map (tests/core/adapt_testlib.c compares them along random walks of
 * the box).  The passes only ask the family's table (adapt_internal.h)
 * what to subdivide, what may be simplified and how a face's level reads. */
#include "core/adapt/adapt_internal.h"
#include "core/multires/hier_internal.h"

#include <math.h>
#include <stdlib.h>

/* d, listed as a face of level i (by st_adapt_faces_of_level or
 * children), still is one. */
static int listed_face(st_map *m, const st_adapt_ops *ops, uint32_t d, unsigned i)
{
    return st_dart_live(m, d) && (!ops->still_listed || ops->still_listed(m, d, i));
}

/* ---- incremental updates --------------------------------------------------------
 * A face's wanted level depends only on its geometry and the box, so when
 * only the box moves, only faces near the old or the new box can change.
 * Children stay near their parents, so the visit starts from the base faces
 * near either box (grown by their own size), grown by the family's
 * region_rings so that faces refined only because the restriction forced
 * them are visited too, and descends through subdivided faces only. */

static int boxes_only_moved(const st_adapt *a, const st_adapt_params *p)
{
    const st_adapt_params *q = &a->prev;
    return a->has_prev && q->has_box && p->has_box && q->base_level == p->base_level && q->max_level == p->max_level &&
           q->falloff == p->falloff && q->flatness == 0 && p->flatness == 0 && q->no_restriction == p->no_restriction;
}

/* Base faces near either box, then the family's rings around them. */
static void region_roots(st_adapt *a, const st_adapt_ops *ops, const st_adapt_params *q, const st_adapt_params *p,
                         st_dart_list *roots)
{
    st_map *m = &a->h->map;
    double lo[3], hi[3], grow = p->falloff > 0 ? p->falloff * p->max_level : 0;
    for (int k = 0; k < 3; k++) {
        lo[k] = fmin(q->box_lo[k], p->box_lo[k]) - grow;
        hi[k] = fmax(q->box_hi[k], p->box_hi[k]) + grow;
    }
    st_dart_list seeds = { 0 }, near = { 0 };
    const st_dart_list *base = &a->base_faces;
    if (!a->grid) a->grid = st_adapt_grid_build(m, base, ops->cell_bbox);
    if (a->grid) st_adapt_grid_near(a->grid, lo, hi, &near);
    else /* (out of memory for the grid: the same test on every base face) */
        for (uint32_t k = 0; k < base->n; k++) {
            double fb[6];
            ops->cell_bbox(m, base->d[k], 0, fb, fb + 3);
            if (st_adapt_box_near(fb, lo, hi)) st_dart_list_push(&near, k);
        }
    for (uint32_t j = 0; j < near.n; j++) {
        uint32_t k = near.d[j];
        uint32_t x = base->d[k];
        do { st_dart_list_push(&seeds, x); x = st_phi1(m, x, 0); } while (x != base->d[k]);
    }
    st_dart_list_free(&near);
    roots->n = 0;
    if (seeds.n) st_region_faces(m, 0, seeds.d, seeds.n, ops->region_rings, roots);
    st_dart_list_free(&seeds);
}

/* A face deep inside both the old and the new box (its bounding box lo..hi
 * grown by its own size on every side, which covers the neighbourhood its
 * descendants' stencils read) is settled: the last update refined all its
 * descendants to max_level, they all still want max_level, and nothing
 * coarser around it is simplified into it (the restriction only spreads
 * refinement outward).  An incremental update need not look inside it, so
 * the visit costs the band where the boxes differ, not the whole box. */
static int settled_bbox(const st_adapt *a, const double lo[3], const double hi[3], const st_adapt_params *p)
{
    const st_adapt_params *q = &a->prev;
    double size = 0;
    for (int k = 0; k < 3; k++) size = fmax(size, hi[k] - lo[k]);
    for (int k = 0; k < 3; k++)
        if (lo[k] - size < fmax(q->box_lo[k], p->box_lo[k]) || hi[k] + size > fmin(q->box_hi[k], p->box_hi[k])) return 0;
    return 1;
}

/* How far, in multiples of a face's own size, a change of refinement can
 * reach a face's subtree: its descendants lie within its box grown by its
 * size (as for settled faces), and a face of level k is refined or
 * coarsened by the restriction only when a face of level k+1 or finer
 * changes within about the size of a level-k face (the graded band: a
 * face of level k+1 sharing a vertex with it, one of level k+2 sharing a
 * vertex with that one, ... a sum of halving sizes), taken twice over for
 * neighbours larger than the face. */
#define REMOTE_REACH 4.0

/* A face whose box, grown by REMOTE_REACH times its size, meets the old
 * and the new interest box in the same region (neither, or the same part
 * of both) is remote from where the two boxes differ: without a falloff a
 * face's wanted level only says whether its box meets the interest box,
 * so every face of its subtree and of that reach wants the same level in
 * both, and the restriction carries no change into it.  Its subtree is
 * left as it is, like a settled one: a move then costs the band where the
 * boxes differ, not the band along every side of the box (a move of 0.05 %
 * of the width cost 11 ms at HD level 10 for that band: bench_hd
 * --profile-step 0.001).  With a falloff the wanted levels change with the
 * distance to the box, and no face is taken as remote. */
static int remote_bbox(const st_adapt *a, const double lo[3], const double hi[3], const st_adapt_params *p)
{
    const st_adapt_params *q = &a->prev;
    if (p->falloff != 0 || q->falloff != 0) return 0;
    double size = 0;
    for (int k = 0; k < 3; k++) size = fmax(size, hi[k] - lo[k]);
    int meets_q = 1, meets_p = 1, same = 1;
    for (int k = 0; k < 3; k++) {
        double glo = lo[k] - REMOTE_REACH * size, ghi = hi[k] + REMOTE_REACH * size;
        double aq = fmax(glo, q->box_lo[k]), bq = fmin(ghi, q->box_hi[k]);
        double ap = fmax(glo, p->box_lo[k]), bp = fmin(ghi, p->box_hi[k]);
        /* (touching counts as meeting, as in st_adapt_box_want) */
        if (aq > bq) meets_q = 0;
        if (ap > bp) meets_p = 0;
        if (aq != ap || bq != bp) same = 0;
    }
    return meets_q == meets_p && (!meets_q || same);
}

static int settled(const st_adapt *a, const st_adapt_ops *ops, uint32_t d, unsigned lev, const st_adapt_params *p)
{
    double lo[3], hi[3];
    ops->cell_bbox(&a->h->map, d, lev, lo, hi);
    return settled_bbox(a, lo, hi, p);
}

/* What an incremental update reads of a listed face (refine_lists'
 * `known`), packed in one word so that the face's bounding box is walked
 * once, not up to three times (the wanted level for the refinement, the
 * settled test for its children, the wanted level again for the
 * simplification; the walks were a tenth of a box move's profile, the
 * saving about 2 % of its time, their cache misses moving elsewhere).
 * Both depend only on the face's own level-i positions and the boxes,
 * which neither pass changes. */
enum { KN_SUB = 1, KN_SETTLED = 2, KN_READ = 4, KN_WANT_SHIFT = 3 };

/* read: the face was listed (listed_face) and its box read; else only
 * `sub` (0) is meaningful. */
static uint32_t known_word(int read, int sub, int settled_face, unsigned want)
{
    if (!read) return 0;
    return KN_READ | (sub ? KN_SUB : 0) | (settled_face ? KN_SETTLED : 0) | (uint32_t)want << KN_WANT_SHIFT;
}

/* Appends to out the sub-faces (level lev+1) of the subdivided faces of
 * cur[0..n) (level lev): corner sub-faces hold their parent's darts (√3:
 * the face of each of the three darts at lev+1 is one sub-face each - odd,
 * or the even triangle of its flipped edge); a triangle quadrisection adds
 * the central triangle, across the corner triangle's inner edge.  With p
 * (an incremental update), settled faces are left out.  known (NULL, or
 * one word per face of cur: refine_lists) says which are subdivided, so
 * that their level-(lev+1) relations are not read again, and which are
 * settled. */
static void children(st_adapt *a, const st_adapt_ops *ops, const uint32_t *cur, uint32_t ncur, unsigned lev,
                     const st_adapt_params *p, const uint32_t *known, st_dart_list *out)
{
    st_map *m = &a->h->map;
    for (uint32_t k = 0; k < ncur; k++) {
        uint32_t d = cur[k];
        if (known ? !(known[k] & KN_SUB) : !listed_face(m, ops, d, lev) || !ops->subdivided(m, d, lev)) continue;
        if (p && (known ? (known[k] & KN_SETTLED) != 0 : settled(a, ops, d, lev, p))) continue;
        unsigned n = 0;
        uint32_t x = d;
        do { st_dart_list_push(out, x); n++; x = st_phi1(m, x, lev); } while (x != d);
        if (ops->central_child(n)) st_dart_list_push(out, st_beta0(m, st_phi1(m, d, lev + 1), lev + 1));
    }
}

/* Subdivided flags (refine_lists' `known`) hold for the families whose
 * forced steps leave the faces already examined as they are
 * (forced_children_only): while the faces of level i are examined, only
 * the face examined is subdivided (the restriction forces coarser faces
 * only), and until the simplification reaches level i nothing undoes a
 * subdivision of level i.  A flag 1 stays true from the end of level i's
 * examination to its simplification (a face listed twice excepted, which
 * the family's can_simplify, testing the subdivision first, turns down as
 * before); a flag 0 may turn true through later forced steps, so those
 * faces are tested again. */

/* Algorithm 5 over listed faces: level by level from `from`, each face of
 * lists[i] (level i) wanting more is subdivided, and the children of the
 * subdivided ones join lists[i+1] (lists has max_level + 1 entries).
 * known (NULL, or as many lists; only with prune): known[i] gets a word
 * per face of lists[i] (known_word): subdivided once level i is done,
 * settled, and its wanted level.  That reading of the wanted level holds
 * for the families with subdivided flags, whose `wanted` reads only the
 * cell's bounding box when p->flatness is 0 (as in every incremental
 * update: boxes_only_moved). */
static int refine_lists(st_adapt *a, const st_adapt_ops *ops, st_dart_list *lists, unsigned from,
                        const st_adapt_params *p, int prune, st_dart_list *known, st_error *err)
{
    st_map *m = &a->h->map;
    int rc = ST_OK;
    for (unsigned i = from; i < p->max_level && i <= m->top && !rc; i++) {
        st_dart_list *cur = &lists[i], *kn = known ? &known[i] : NULL;
        if (kn) kn->n = 0;
        for (uint32_t k = 0; k < cur->n && !rc; k++) {
            uint32_t d = cur->d[k];
            int sub = 0, settled_face = 0, read = 0;
            unsigned want = 0;
            if (listed_face(m, ops, d, i)) {
                read = 1;
                sub = ops->subdivided(m, d, i);
                if (kn) {
                    double lo[3], hi[3];
                    ops->cell_bbox(m, d, i, lo, hi);
                    want = st_adapt_box_want(lo, hi, p);
                    if (want > p->max_level) want = p->max_level;
                    settled_face = settled_bbox(a, lo, hi, p) || remote_bbox(a, lo, hi, p);
                } else if (!sub) {
                    want = ops->wanted(m, d, i, p);
                }
                if (!sub && want > i) {
                    rc = st_adapt_subdivide_face(a, d, i, !p->no_restriction, err);
                    sub = !rc && ops->subdivided(m, d, i); /* (hot: just written) */
                }
            }
            if (kn) st_dart_list_push(kn, known_word(read, sub, settled_face, want));
        }
        /* lists[max_level] is never read: refinement stops below max_level
         * and the simplification starts at max_level - 1.  Listing it cost
         * the incremental update a subdivided and settled test on every
         * face of the finest band (the most numerous). */
        if (i + 1 < p->max_level && !rc)
            children(a, ops, cur->d, cur->n, i, prune ? p : NULL, kn ? kn->d : NULL, &lists[i + 1]);
    }
    return rc;
}

/* After a pass, the faces the restriction subdivided (a->forced_faces:
 * dart, level pairs) have children nobody examined: faces made at levels
 * the pass had already left.  Only those can want more - every other face
 * was examined, and its wanted level reads its own geometry, which a
 * neighbour's subdivision leaves as it is (with the restriction, stencils
 * are complete and give the same points) - so the next pass starts from
 * them (families with forced_children_only). */
static int refine_forced(st_adapt *a, const st_adapt_ops *ops, const st_dart_list *forced, st_dart_list *lists,
                         const st_adapt_params *p, st_error *err)
{
    unsigned from = p->max_level;
    for (uint32_t k = 0; k + 1 < forced->n; k += 2) {
        uint32_t z = forced->d[k];
        unsigned j = forced->d[k + 1];
        if (j + 1 >= p->max_level) continue; /* (nothing to refine at max_level: refine_lists) */
        children(a, ops, &z, 1, j, NULL, NULL, &lists[j + 1]);
        if (j + 1 < from) from = j + 1;
    }
    int rc = refine_lists(a, ops, lists, from, p, 0, NULL, err);
    for (unsigned i = 0; i <= p->max_level; i++) lists[i].n = 0;
    return rc;
}

/* Algorithm 5 over every face of the map, level by level. */
static int refine_all(st_adapt *a, const st_adapt_ops *ops, const st_adapt_params *p, st_dart_list *faces,
                      st_error *err)
{
    st_map *m = &a->h->map;
    int rc = ST_OK;
    for (unsigned i = 0; i < p->max_level && i <= m->top && !rc; i++) {
        st_adapt_faces_of_level(m, i, faces);
        for (uint32_t k = 0; k < faces->n && !rc; k++) {
            uint32_t d = faces->d[k];
            if (!listed_face(m, ops, d, i) || ops->subdivided(m, d, i)) continue;
            if (ops->wanted(m, d, i, p) > i) rc = st_adapt_subdivide_face(a, d, i, !p->no_restriction, err);
        }
    }
    return rc;
}

int st_adapt_update(st_adapt *a, const st_adapt_params *p, st_error *err)
{
    if (st_adapt_is_progressive(a)) return st_adapt_pm_update(a, p, err);
    st_map *m = &a->h->map;
    const st_adapt_ops *ops = st_adapt_ops_of(a);
    int restricted = !p->no_restriction;
    st_dart_list faces = { 0 }, roots = { 0 };
    const st_dart_list *region = NULL;
    if (boxes_only_moved(a, p)) {
        region_roots(a, ops, &a->prev, p, &roots);
        region = &roots;
    } else { /* (level 0 may have moved: the grid is rebuilt, for the moves to come) */
        st_adapt_grid_free(a->grid);
        a->grid = p->has_box ? st_adapt_grid_build(m, &a->base_faces, ops->cell_bbox) : NULL;
    }
    a->touched = 0;
    /* (what the polygon split family's passes change, for the canonical
     * pass at the end) */
    st_adapt_canon canon = { .restricted = restricted };
    a->canon = a->exact && (ops == &st_adapt_ops_quads || ops == &st_adapt_ops_triangles || ops == &st_adapt_ops_quadtri)
                   ? &canon : NULL;
    int rc = ST_OK;
    /* Algorithm 5: refine, coarse to fine; again while the restriction
     * forced faces at levels already passed. */
    /* (region: lists holds the region's faces of each level after the first
     * pass, which the simplification below reuses, and known their
     * subdivided flags where the family keeps them true (refine_lists);
     * more holds the faces of the later passes.) */
    unsigned nl = p->max_level + 1;
    st_dart_list *lists = calloc(3 * (size_t)nl, sizeof *lists), *more = lists + nl, forced = { 0 };
    st_dart_list *known = region && ops->forced_children_only && lists ? lists + 2 * nl : NULL;
    if (!lists) rc = st_fail(err, ST_ERR_MEMORY, "adapt: out of memory");
    for (int pass = 0; !rc; pass++) {
        a->forced = 0;
        a->forced_faces.n = 0;
        if (pass && ops->forced_children_only) rc = refine_forced(a, ops, &forced, more, p, err);
        else if (region) {
            for (unsigned i = 0; i < nl; i++) lists[i].n = 0;
            for (uint32_t k = 0; k < region->n; k++) st_dart_list_push(&lists[0], region->d[k]);
            rc = refine_lists(a, ops, lists, 0, p, 1, known, err);
        } else
            rc = refine_all(a, ops, p, &faces, err);
        if (!a->forced) break;
        st_dart_list t = forced; forced = a->forced_faces; a->forced_faces = t;
    }
    st_dart_list_free(&forced);
    st_dart_list_free(&a->forced_faces);
    /* Algorithm 6: simplify, fine to coarse.  A simplification at level
     * j > i deletes only darts inserted above i, so the lists of the coarser
     * levels stay valid.  In a region, the lists are those of the first
     * refinement pass: the later passes only subdivided faces the
     * restriction needs (never simplifiable now) and made their children
     * (not subdivided, so nothing to simplify in them). */
    for (unsigned i = region && m->top >= nl ? nl - 1 : m->top; i-- > 0 && !rc;) {
        if (!region) st_adapt_faces_of_level(m, i, &faces);
        const st_dart_list *cur = region ? &lists[i] : &faces;
        const uint32_t *kn = known && known[i].n == cur->n ? known[i].d : NULL;
        for (uint32_t k = 0; k < cur->n && !rc; k++) {
            uint32_t d = cur->d[k];
            if (!(kn && (kn[k] & KN_SUB)) && (!listed_face(m, ops, d, i) || !ops->subdivided(m, d, i))) continue;
            unsigned want = kn && (kn[k] & KN_READ) ? kn[k] >> KN_WANT_SHIFT : ops->wanted(m, d, i, p);
            if (want > i || !ops->can_simplify(a, d, i, restricted)) continue;
            rc = ops->simplify(a, d, i, err);
        }
    }
    /* Positions as a full synthesis from the base level gives them
     * (adapt_resynth.c, "after an update"). */
    if (!rc && a->canon) (void)st_adapt_canon_update(a);
    a->canon = NULL;
    st_adapt_canon_free(&canon);
    if (lists)
        for (unsigned i = 0; i < 3 * nl; i++) st_dart_list_free(&lists[i]);
    free(lists);
    st_dart_list_free(&faces);
    st_dart_list_free(&roots);
    a->prev = *p;
    a->has_prev = !rc;
    return rc;
}
