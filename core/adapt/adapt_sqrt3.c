/* Adaptive √3 refinement (thesis §3.4.2, Algorithm 8, fig. 3.48-3.49;
 * Kobbelt 2000, §5 "adaptive refinement").  Closed triangle meshes; see
 * adapt.h for the levels, the criteria and the details.
 *
 * Subdividing a triangle t of level i toward L = i+1 (Algorithm 8): split t
 * at level L by its centre (the three edges of fig. 3.46, as the regular
 * refine_sqrt3.c does), then flip every edge of t whose other side is
 * already subdivided toward L.  An edge whose other side is not subdivided
 * stays unflipped: the sub-triangle on it is *odd* (it has a neighbour of
 * lower level).  When that neighbour is subdivided later, the edge is
 * flipped then and both sides are *even*.
 *
 * State read from the map, nothing stored:
 *   - face level (§3.2.6, st_face_level): every face of every level is a
 *     triangle holding exactly one dart older than the face (a sub-triangle
 *     of a split: the old dart of its side, flipped or not), so the general
 *     definition gives the level the face was created at, which for √3 is
 *     also the largest insertion level of its darts (thesis §3.4.2);
 *   - subdivided toward i+1: as for the other schemes, the face of a dart
 *     at level i+1 has level i+1 (st_face_is_subdivided);
 *   - odd/even: a face of level i is odd when a face across one of its
 *     edges, at level i, has a lower level (then that edge is an unflipped
 *     edge of its parent);
 *   - an edge of t is flipped at L when its dart starts at another vertex
 *     at L than at i (a flipped dart starts at a centre);
 *   - edge levels are not used: √3 splits no edge.  Two steps trisect the
 *     edges of level i-2 (level = number of √3 steps).
 *
 * The one-level restriction is always applied for √3 (no_restriction is
 * ignored): a flip at level L changes β1 of old darts around four vertices,
 * and the levels above L follow only where they had not diverged, so the
 * maps above L stay valid only if no face around those vertices is
 * subdivided above L yet - which is what the restriction guarantees.
 * Before t (level i) is subdivided:
 *   - t must be even (mandatory: an odd triangle is not a triangle of the
 *     regular level-i mesh).  Asked to subdivide an odd triangle, its lower
 *     neighbour is subdivided instead, which flips the edge and replaces it
 *     by two even triangles, and nothing more: the criteria then judge
 *     those (st_adapt_update passes again after forced subdivisions);
 *   - every face around t's corners at level i must be an even triangle of
 *     level i (faces of lower level, and the lower neighbours of odd ones,
 *     are subdivided first).
 * Then the corners' level-i rings are the regular ones, and the even rule
 * over the level-i ring (listing 3.4.2, scheme_sqrt3.c's vertex stencil)
 * and the centre rule give the positions of the regular hierarchy.
 *
 * Simplification (Algorithm 6 for √3) of t, subdivided toward L: allowed
 * when none of the faces around its centre at L (its sub-triangles and the
 * even triangles across its flipped edges) is subdivided toward L+1, and no
 * face around the centre's level-L neighbours (t's corners, the centres of
 * the subdivided neighbours) has level L+1.  It flips t's flipped edges
 * back (their other sides become odd again), removes the centre (its
 * details are saved under the refinement-tree address of t,
 * adapt_details.c), and
 * puts back the level-i position at level L of the corners left without a
 * face of level L.  Only centres are ever removed: the old vertices of √3
 * are never deleted.
 *
 * Updates (st_adapt_update) are those of adapt_update.c: Algorithms 5 and
 * 6 call the functions below through the table st_adapt_ops_sqrt3 (at the
 * end).  The incremental path (box moved only) visits base faces
 * SQRT3_RINGS rings around the boxes, since forced refinement reaches
 * further than with quadrisection; the sub-faces of a subdivided face are
 * the faces of its three darts one level up (an odd triangle, or the even
 * triangle of a flipped edge - each holds exactly one older dart).
 *
 * Boundaries (the trisection of boundary edges every second step) are not
 * handled adaptively: st_adapt_init refuses √3 meshes with holes.
 */
#include "core/map/geometry.h"
#include "core/adapt/adapt_internal.h"
#include "core/map/refine_sqrt3_internal.h"

#include <math.h>
#include <stdlib.h>

static int sqrt3_check(const st_hier *h, st_error *err)
{
    const st_map *m = &h->map;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it))
        if (st_is_boundary(m, d))
            return st_fail(err, ST_ERR_INVALID, "adaptive sqrt3 needs a closed mesh (boundaries are not implemented "
                           "for adaptive sqrt3; the regular levels handle them)");
    return ST_OK;
}

/* A dart across an edge of the face of d (level i) whose face has a lower
 * level at i, or ST_NIL (the face is even).  Its face is unchanged since
 * its level, so every dart of it exists there. */
static uint32_t lower_neighbour(st_map *m, uint32_t d, unsigned i)
{
    uint32_t x = d;
    do {
        uint32_t e = st_beta0(m, x, i);
        if (!st_is_boundary(m, e) && st_face_level(m, e, i) < i) return e;
        x = st_phi1(m, x, i);
    } while (x != d);
    return ST_NIL;
}

/* One forced subdivision needed before the face of d (level i) may be
 * subdivided: *fd, *fl the face and its level; 0 when none is needed. */
static int needs_forcing(st_map *m, uint32_t d, unsigned i, uint32_t *fd, unsigned *fl)
{
    uint32_t e = lower_neighbour(m, d, i);
    if (e != ST_NIL) { *fd = e; *fl = st_face_level(m, e, i); return 1; }
    uint32_t x = d;
    do {
        uint32_t y = x;
        do {
            if (!st_is_boundary(m, y)) {
                unsigned j = st_face_level(m, y, i);
                if (j < i) { *fd = y; *fl = j; return 1; }
                e = lower_neighbour(m, y, i);
                if (e != ST_NIL) { *fd = e; *fl = st_face_level(m, e, i); return 1; }
            }
            y = st_beta1(m, y, i);
        } while (y != x);
        x = st_phi1(m, x, i);
    } while (x != d);
    return 0;
}

/* Centre split of the triangle of c0 at level L (refine_sqrt3.c, fig. 3.46);
 * returns the centre vertex. */
static uint32_t centre_split(st_map *m, uint32_t c0, unsigned L, const double centre[3])
{
    uint32_t c1 = st_phi1(m, c0, L), c2 = st_phi1(m, c1, L);
    uint32_t y = st_beta0(m, st_cut_face(m, c0, c1, L), L);
    uint32_t a = st_split_edge(m, y, L, centre);
    st_cut_face(m, st_beta0(m, y, L), c2, L);
    return st_vert(m, a, L);
}

/* The edge of x (a dart of a face of level L-1) is flipped at L. */
static int flipped(const st_map *m, uint32_t x, unsigned L)
{
    return st_vert(m, x, L) != st_vert(m, x, L - 1);
}

/* A dart starting at the centre (level L) of the subdivided face of d
 * (level L-1): the twin of a flipped dart, else φ1⁻¹(d) (refine_sqrt3.c). */
static uint32_t centre_dart(const st_map *m, uint32_t d, unsigned L)
{
    uint32_t x = d;
    do {
        if (flipped(m, x, L)) return st_beta0(m, x, L);
        x = st_phi1(m, x, L - 1);
    } while (x != d);
    return st_phi_1(m, d, L);
}

static int sqrt3_subdivide(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    unsigned L = i + 1;
    if (st_face_degree(m, d, i) != 3) return st_fail(err, ST_ERR_TOPOLOGY, "adapt sqrt3: face of %u sides", st_face_degree(m, d, i));
    /* Evenness and the restriction: force the coarser faces first, one at a
     * time, and look again (each forcing may change the faces around).  An
     * odd triangle is replaced by two even ones when its lower neighbour is
     * subdivided: it is not subdivided itself - the caller's criteria judge
     * the faces that replace it (st_adapt_update passes again after forced
     * subdivisions). */
    int was_odd = 0;
    for (;;) {
        if (st_face_level(m, d, i) != i) return st_fail(err, ST_ERR_INVALID, "adapt sqrt3: the face of dart %u is not of level %u", d, i);
        if (st_face_is_subdivided(m, d, i)) return ST_OK;
        uint32_t fd;
        unsigned fl;
        if (!needs_forcing(m, d, i, &fd, &fl)) break;
        if (lower_neighbour(m, d, i) != ST_NIL) was_odd = 1;
        a->forced++;
        int rc = sqrt3_subdivide(a, fd, fl, err);
        if (rc) return rc;
    }
    if (was_odd) return ST_OK;
    int rc = st_adapt_ensure_level(h, L, err);
    if (rc) return rc;
    double centre[3] = { 0, 0, 0 };
    uint32_t x = d;
    do {
        const double *p = st_dart_pos(m, x, i);
        for (int k = 0; k < 3; k++) centre[k] += p[k] / 3;
        x = st_phi1(m, x, i);
    } while (x != d);
    uint32_t c = centre_split(m, d, L, centre);
    /* Algorithm 8: flip the edges toward the neighbours already subdivided
     * toward L (their sub-triangle on that edge is odd, of level L). */
    x = d;
    do {
        uint32_t e = st_beta0(m, x, i);
        if (st_face_level(m, e, i) == i && st_face_is_subdivided(m, e, i)) {
            rc = st_flip_edge(m, x, L, err);
            if (rc) return rc;
        }
        x = st_phi1(m, x, i);
    } while (x != d);
    /* Positions: the centre rule and the even rule over the corners'
     * level-i rings (complete by the restriction), as the regular scheme. */
    st_adapt_place_ctx pc = { a, L, &c, 1 };
    st_hier_emit(h, L, &d, 1, st_adapt_place_sink, &pc);
    a->touched++;
    return ST_OK;
}

static int sqrt3_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted)
{
    (void)restricted; /* always on for √3 */
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    if (st_face_level(m, d, i) != i || !st_face_is_subdivided(m, d, i)) return 0;
    /* The faces around the centre: through each dart of t and its twin. */
    uint32_t x = d;
    do {
        if (st_face_is_subdivided(m, x, L) || st_face_is_subdivided(m, st_beta0(m, x, i), L)) return 0;
        x = st_phi1(m, x, i);
    } while (x != d);
    /* The centre and its level-L neighbours: no face of level L+1 around
     * them (so nothing above L has diverged there, and the restriction
     * still holds for the faces subdivided toward L+1). */
    uint32_t s0 = centre_dart(m, d, L), s = s0;
    do {
        uint32_t w[2] = { s, st_beta0(m, s, L) };
        for (int k = 0; k < 2; k++) {
            uint32_t y = w[k];
            do {
                if (!st_is_boundary(m, y) && st_face_level(m, y, L + 1) == L + 1) return 0;
                y = st_beta1(m, y, L + 1);
            } while (y != w[k]);
        }
        s = st_beta1(m, s, L);
    } while (s != s0);
    return 1;
}

/* ---- criteria ------------------------------------------------------------------
 * Two things make criteria read on the face itself unusable for √3:
 *   - an odd triangle and the two even triangles that replace it when its
 *     lower neighbour is subdivided cover different regions: the odd one
 *     may touch the box where the even ones do not, and each update would
 *     subdivide the lower neighbour (to make the odd triangle even) and
 *     simplify it again;
 *   - a face may want more than the faces it comes from, so the faces kept
 *     after a box move would depend on what was refined before: the box
 *     moved away and back would not give back the same mesh.
 * So the level wanted for a face t of level i >= 1 is
 *     want(t) = min(own(t), max(want(P), want(G)))
 * where P and G are the two level-(i-1) triangles of t's old edge (the one
 * dart of t older than i lies on an edge of level i-1, flipped when t is
 * even, not when it is odd), own(t) the criteria read on P and G with
 * level-(i-1) positions (box: the bounding box of their corners; flatness:
 * the angle between their normals), and want = the usual criteria for a
 * level-0 face.  An odd triangle and the even ones replacing it share P, G
 * and so their answer, and a face wants more than i only if one of the
 * faces it comes from wants that much: the refinement from the base level
 * reaches it, and the result of an update does not depend on the past. */

/* The dart of the face of d (level i >= 1) inserted before i, or ST_NIL. */
static uint32_t old_dart(const st_map *m, uint32_t d, unsigned i)
{
    uint32_t c = d;
    do {
        if (m->darts.ins[c] < i) return c;
        c = st_phi1(m, c, i);
    } while (c != d);
    return ST_NIL;
}

static unsigned own_want(const st_map *m, const uint32_t side[2], unsigned i, const st_adapt_params *p)
{
    unsigned l = i - 1;
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) { lo[k] = INFINITY; hi[k] = -INFINITY; }
    for (int s = 0; s < 2; s++) {
        uint32_t x = side[s];
        do {
            const double *q = st_dart_pos(m, x, l);
            for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], q[k]); hi[k] = fmax(hi[k], q[k]); }
            x = st_phi1(m, x, l);
        } while (x != side[s]);
    }
    unsigned want = st_adapt_box_want(lo, hi, p);
    if (p->flatness > 0 && i < p->max_level) {
        double n0[3], n1[3];
        st_face_newell(m, side[0], l, n0);
        st_face_newell(m, side[1], l, n1);
        double dn = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]) * sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
        if (dn > 0) {
            double cs = (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2]) / dn;
            if (acos(fmax(-1.0, fmin(1.0, cs))) > p->flatness) want = p->max_level;
        }
    }
    return want > p->max_level ? p->max_level : want;
}

/* min(cap, want(face of d at level i)); the second parent is visited only
 * when the first does not reach the cap. */
static unsigned want_capped(const st_map *m, uint32_t d, unsigned i, const st_adapt_params *p, unsigned cap)
{
    if (i == 0) {
        unsigned w = st_adapt_wanted_level(m, d, 0, p);
        return w < cap ? w : cap;
    }
    uint32_t c = old_dart(m, d, i);
    if (c == ST_NIL) { /* not a face of level i: cannot happen in an adaptive √3 map */
        unsigned w = st_adapt_wanted_level(m, d, i, p);
        return w < cap ? w : cap;
    }
    uint32_t side[2] = { c, st_beta0(m, c, i - 1) };
    unsigned o = own_want(m, side, i, p);
    if (o > cap) o = cap;
    unsigned a = want_capped(m, side[0], i - 1, p, o);
    if (a >= o) return o;
    unsigned b = want_capped(m, side[1], i - 1, p, o);
    return a > b ? a : b;
}

static unsigned sqrt3_wanted(const st_map *m, uint32_t d, unsigned i, const st_adapt_params *p)
{
    return want_capped(m, d, i, p, p->max_level);
}

static int sqrt3_simplify(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    unsigned L = i + 1;
    int rc = ST_OK;
    /* The level-L vertex cells of the centre and of its neighbours change:
     * park their level-(L+1) details first (adapt_details.c). */
    uint32_t s0 = centre_dart(m, d, L), s = s0;
    uint32_t c = st_vert(m, s0, L);
    do {
        st_adapt_park_detail(a, s, L);
        st_adapt_park_detail(a, st_beta0(m, s, L), L);
        s = st_beta1(m, s, L);
    } while (s != s0);
    /* Flip back: the sub-triangles across become odd again. */
    uint32_t x = d;
    do {
        if (flipped(m, x, L)) rc = st_flip_edge_back(m, x, L, err);
        if (rc) return rc;
        x = st_phi1(m, x, i);
    } while (x != d);
    /* Remove the centre (the reverse of centre_split): uncut spokes until
     * it has degree 2, unsplit it, uncut the edge left. */
    st_adapt_save_centre_detail(a, L, d, c);
    uint32_t spoke = st_phi_1(m, d, L);
    if (st_vert(m, spoke, L) != c) return st_fail(err, ST_ERR_INVALID, "adapt sqrt3: centre of dart %u not found", d);
    rc = st_adapt_remove_centre(m, spoke, L, NULL, err);
    if (rc) return rc;
    /* Corners no longer on a face of level L fall back to their level-i
     * position (and, through the propagating setter, above L too). */
    x = d;
    do { st_adapt_corner_fallback(a, x, i); x = st_phi1(m, x, i); } while (x != d);
    a->touched++;
    return ST_OK;
}

/* ---- the table ------------------------------------------------------------------- */

static int sqrt3_subdivide_face(st_adapt *a, uint32_t d, unsigned i, int restricted, st_error *err)
{
    (void)restricted; /* always on for √3 */
    return sqrt3_subdivide(a, d, i, err);
}

/* Faces are read by the general definitions: the flips re-link old darts,
 * so the O(1) readings of Algorithm 1's maps do not hold, and a listed dart
 * may have been flipped into a face of another level since it was listed. */
static int sqrt3_face_of_level(st_map *m, uint32_t y, unsigned i) { return st_face_level(m, y, i) == i; }

/* No sub-face without an old dart: each of a face's three darts lies in one
 * sub-face at i+1 (odd, or the even triangle of its flipped edge). */
static int no_central_child(unsigned n) { (void)n; return 0; }

/* √3: forced refinement goes further.  Before a face of level i is
 * subdivided, the faces around its corners must be even triangles of level
 * i, so the lower neighbours of odd triangles two faces away are forced: up
 * to about two faces of level i-1 per level, and faces shrink by √3 (not
 * 2) per level, a reach under 2 / (1 - 1/√3) < 5 base faces.  Six rings
 * leave a margin (tests/core/test_adapt_sqrt3.c compares with full updates). */
#ifndef SQRT3_RINGS
#define SQRT3_RINGS 6
#endif

const st_adapt_ops st_adapt_ops_sqrt3 = {
    .family = "sqrt3",
    .check = sqrt3_check,
    .subdivide = sqrt3_subdivide_face,
    .can_simplify = sqrt3_can_simplify,
    .simplify = sqrt3_simplify,
    .wanted = sqrt3_wanted,
    .cell_bbox = st_adapt_face_bbox,
    .subdivided = st_face_is_subdivided,
    .face_of_level = sqrt3_face_of_level,
    .still_listed = sqrt3_face_of_level,
    .central_child = no_central_child,
    .region_rings = SQRT3_RINGS,
    /* A forced subdivision flips edges of faces already examined: the next
     * pass goes over every face again. */
    .forced_children_only = 0,
};
