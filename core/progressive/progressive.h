/* Progressive multiresolution meshes (Kraemer 2008, ch. 4; GSS99).
 *
 * st_progressive_build turns a manifold triangle mesh (closed or open, any
 * genus) into an ordinary st_hier whose level 0 is coarse and whose finest
 * level is the input, so that synthesis, analysis, local edits, undo,
 * sessions and the renderer work on it unchanged.
 *
 * Design
 * ------
 * 1. Simplification on a flat working copy (progressive_work.c): a closed
 *    half-edge structure (twin/next/prev/origin arrays, holes as boundary
 *    loops of half-edges).  Collapses are *half-edge* collapses a -> b (the
 *    merged vertex sits on the endpoint b, as in GSS99 and thesis §4.4.6:
 *    "v takes the position of s1"), ranked by the quadric error metric
 *    (Garland-Heckbert 97: area-weighted face planes, plus planes through
 *    the boundary edges perpendicular to their face, so that open borders
 *    keep their shape).  The endpoint is chosen over the optimal position
 *    because every vertex then keeps its input position at every level it
 *    exists in: level positions need no per-level column, the details of
 *    the vertices that are not split are exactly zero, and the finest level
 *    is the input bit for bit.  (Level 0 may leave the rule: point 8.)
 *
 * 2. Before a collapse a -> b (c, d the vertices opposite the edge):
 *    - a on the boundary: the edge must be a boundary edge (a boundary
 *      vertex only moves along its boundary; an interior edge between two
 *      boundary vertices would pinch the surface);
 *    - link condition (thesis §4.4.3, P2; Dey et al. 1999 for boundaries):
 *      N(a) ∩ N(b) = {c, d}, or {c} for a boundary edge;
 *    - valences (§4.4.3, P1): an interior c or d keeps at least 3
 *      neighbours, a boundary one at least 2 (no dangling edge), the merged
 *      vertex at least 3 (interior) or 2 (boundary), and for a boundary
 *      edge b keeps a neighbour besides a and c (no "ear" whose every dart
 *      would be new when split again: see point 3 (ii));
 *    - no face around a flips its normal.
 *    A collapse that satisfies the link condition leaves the surface
 *    homeomorphic, so the Euler characteristic and the boundary loops are
 *    kept at every level; a hole can neither close nor pinch.
 *
 * 3. Independence (thesis §4.4.4, Algorithm 9, made precise).  The
 *    collapses of one group (one level) are made one after the other, and
 *    each passes the checks of point 2 on the mesh as the previous ones
 *    left it; so every level is a valid surface homeomorphic to the input
 *    (link condition), whatever the group.  (The thesis' rule — splits of
 *    one level share no neighbour, checked on the level before the group —
 *    does not ensure this by itself: two collapses that are each legal
 *    can together lower one vertex's valence below what the checks allow,
 *    or close a hole; checking each on the current mesh does.)
 *    What the group must still satisfy is what the hierarchy needs, for a
 *    group turning level L into level L-1, with N(a) the 1-ring at L:
 *      (i)  no removed vertex is a neighbour at L of another one
 *           (a' ∉ N(a) ∪ {a}): every vertex a split vertex is predicted
 *           from (its level-L neighbours) exists at level L-1, and so does
 *           every vertex a neighbour of a split reads;
 *      (ii) no vertex is the target b of two collapses: b keeps at level L
 *           a dart of level L-1 (an interior b has valence >= 3 at L and
 *           only two of its darts are new; point 2 keeps one for a
 *           boundary b), on which its detail frame sits (progressive_scheme.c).
 *    (i) also means a removed vertex is never a target (b ∈ N(a)), so no
 *    chain a -> b -> b' within a level.  Both are kept with two marker bits
 *    per vertex, set on a's ring before each collapse (tests/
 *    test_progressive.c checks them on the map at every level).  The groups
 *    are chosen greedily, cheapest quadric cost first, up to the target
 *    face count.
 *
 * 4. Materialisation: the groups are recorded fine to coarse with an undo
 *    log, and laid out once, coarse to fine, instead of shifting every
 *    level at each simplification step as thesis §4.4.1-4.4.2 do.  Level 0
 *    is built from the coarsest working copy; then, for L = 1..top, the
 *    group of level L is undone on the working copy and replayed on the map
 *    as vertex splits: the split vertex a and the darts of the two restored
 *    triangles (one triangle and one boundary dart for a boundary edge) are
 *    inserted at level L, and the darts around a, b, c, d take their level-L
 *    β0, β1 and vertex through the kernel's per-level columns (thesis
 *    §4.4.2: φ1 of the real faces never changes; β1 = φ1∘β0 changes where
 *    β0 does, and along the hole whose length changed).
 *
 * 5. Geometry: the "progressive" scheme (core/progressive/progressive_scheme.c)
 *    predicts, at level L, each split vertex a by the average of the
 *    level-(L-1) positions of its level-L neighbours (its two boundary
 *    neighbours on a border), each neighbour of a split vertex by half its
 *    own position and half the average of its neighbours (a split one at
 *    its prediction), and every other vertex by its own level-(L-1)
 *    position — relaxation operators in the sense of GSS99 §3 (uniform
 *    weights).  A detail, in the local frame of the vertex's coarse
 *    neighbourhood (for a, of the vertex b it was merged into), is what
 *    remains; the details of the other vertices are zero.  A rigid motion
 *    of a coarse level therefore moves the finer levels rigidly, and
 *    st_progressive_filter scales the details per level (multiresolution
 *    filtering, GSS99 §5, thesis §4.4.6): gain 0 on a band leaves the
 *    relaxed, smoother surface.  Synthesis reads flat per-level ring
 *    tables rather than the map's pair form (progressive_synth.c), to the
 *    stencils' bits; a local edit re-synthesises exactly the vertices
 *    whose position changes, level by level.  That support is the whole
 *    cone of the relaxation (two rings at each level, so a coarse edit
 *    reaches much of the finest level, most of it by tiny amounts: koala
 *    at 1 %, a level-0 edit changes 102090 of the 197876 positions above,
 *    60 % of them by less than 1e-6 of the edit's move), and it is
 *    written to the bit so that a local edit equals a full synthesis.
 *
 *    The predictor (st_progressive_opts.predictor, tagged in sessions):
 *    the relaxation above, P(v) = (1 - mu) v + mu avg(ring), with weight
 *    mu = 1/2 at every level (ST_PM_RELAXED: every session written before
 *    the tag, and a zero st_progressive_opts), 1/8 (ST_PM_LIGHT), or
 *    graded (ST_PM_GRADED, ST_PM_DEFAULT: what st_rebuild, hence `strata
 *    rebuild` and the window, build): mu = 1/2 on the two finest levels,
 *    1/10 below.  Chosen by bench/bench_transfer.c (issue 30: a bump
 *    applied at level L, measured at the finest level; 4 centres; figures
 *    at levels 0 / middle / top-1) and by tests/core/test_progressive.c,
 *    test_filter (spot_low_resolution's mean dihedral angle, 0.2432, must
 *    fall below 0.2310 with the 3 finest bands at gain 0):
 *      - Catmull-Clark levels of spot x3: one vertex moved alone keeps
 *        0.45 / 0.49 / 0.58 of its move; smooth bump peak 0.93-0.97,
 *        RMS error 0.009-0.023;
 *      - mu = 1/2, spot x3 (20 levels) and koala (17): one vertex 0.10 /
 *        0.15 / 0.77 and 0.12 / 0.15 / 0.53; smooth peak 0.83-0.99, RMS
 *        0.009-0.065; filter 0.2190;
 *      - mu = 1/8: 0.34 / 0.48 / 0.94 and 0.39 / 0.50 / 0.88; smooth
 *        peak 0.93-1.00, RMS 0.006-0.037; filter 0.2652 (fails);
 *      - mu = 0 (old vertices interpolated): 1.00 everywhere, RMS
 *        0.006-0.031, but a coarse vertex stays a cone tip at every finer
 *        level; filter 0.295 (rougher than the input);
 *      - mu from 1/10 at level 1 to 1/2 at the top, as ((L-1)/(top-1))^4:
 *        0.35 / 0.31 / 0.77 and 0.36 / 0.29 / 0.53, RMS up to 0.042;
 *        filter 0.2236 (the fine levels' strong relaxation still damps
 *        a middle level's edit);
 *      - 1/10 below, 1/2 on the 3 finest: 0.40 / 0.37 / 0.77 and 0.38 /
 *        0.32 / 0.53, smooth peak >= 0.91, RMS <= 0.038; filter 0.2190
 *        (spot's middle level 0.75x Catmull-Clark's: short of 0.8x);
 *      - graded (1/10 below, 1/2 on the 2 finest): 0.40 / 0.43 / 0.77 and
 *        0.395 / 0.38 / 0.53, that is 0.90x / 0.87x / 1.33x Catmull-Clark's
 *        on spot; smooth peak 0.92-0.99, RMS 0.009-0.036; filter 0.2257
 *        (boot 0.2488 -> 0.1424).  Issue 30's goals met;
 *      - 1/20 below, 1/2 on the 2 finest: 0.60 / 0.52 / 0.77 and 0.51 /
 *        0.44 / 0.53, filter 0.2266: more than Catmull-Clark keeps, so a
 *        sharper tip than its levels give; 1/10 is the closer match.
 *      - 1/2 on the finest level only (1/10 below): filter 0.2357 (fails).
 *    Why graded: a coarse edit crosses many levels, some five per octave
 *    of resolution here (t = 0.75-0.8) against one for Catmull-Clark, and
 *    the damping compounds per level, so the weight below must be small
 *    (1/10 damps about as Catmull-Clark's steps do over the same octaves).
 *    But removing the finest bands (st_progressive_filter, gain 0) smooths
 *    only through the relaxation of the old vertices of those levels,
 *    which keep their input positions otherwise, so the finest levels keep
 *    1/2; there a coarse edit has become a bump many fine edges wide,
 *    which a relaxation barely lowers.  Rendered (koala, a level-0 vertex
 *    on an ear moved alone by two level-0 edge lengths): a smooth raised
 *    ear, no spike or ripple.  The weight depends only on L and the top
 *    level, so removing the coarsest level keeps every level's predictor.
 *    The stencils are those of mu = 1/2, so the build costs the same
 *    (bench_progressive, koala: 0.43-0.44 s CPU graded, 0.41-0.46 s
 *    relaxed, on a shared 2-core machine).
 *    GSS99's non-uniform weights (thesis §4.3) and a wider split
 *    prediction (butterfly-like) were not tried: the old vertices'
 *    relaxation weight, not the shape of its stencil, is what both
 *    figures turn on.
 *
 * 6. Memory (thesis §4.4.8).  The kernel's dense form stores a relation's
 *    level-l values in a column over every dart inserted before l (map.h),
 *    and a vertex split changes β0, β1 and the vertex of darts of every
 *    earlier level, so each level l >= 1 would have three columns of
 *    |B^{l-1}| entries: about 14 + 12/(1-t) bytes per finest dart, t the
 *    fraction of vertices a level keeps (koala to 1 % in 17 levels,
 *    t = 0.75: 50.6 bytes per finest dart).  The build therefore ends with
 *    st_map_compact, which stores the three relations in the pair form of
 *    §4.4.5 (map.h, "Sparse form": per dart the (level, value) pairs at
 *    which a relation changes): koala 29.2 bytes per finest dart, of which
 *    15.1 for the pairs and their offsets, against the thesis' full φ2
 *    arrays, 4/(1-t) = 16 bytes per dart for φ2 alone, and the classic
 *    [Hop98] structure, 68 bytes per vertex, about 11.3 per dart.  Loading
 *    a session compacts the same way; any topology edit turns the map
 *    back into dense columns.
 *
 * 7. Selective display (thesis §4.4.7 leaves it open): the interest box
 *    shows the finest level inside it and a coarse level outside, by
 *    applying the collapses of the levels above the base except those the
 *    box or a finer kept split holds back; core/adapt/adapt_progressive.c
 *    has the rule and the proof that the result is a valid watertight
 *    surface of the input's topology.
 *
 * 8. Level 0's placement (st_progressive_opts.fit_coarse; what st_rebuild
 *    builds).  Point 1 keeps every vertex at its input position, which
 *    costs the coarsest level most: it is a subset of the input's points
 *    and cuts corners off every convex region.  Since a detail can absorb
 *    any difference, level 0 alone leaves that rule: each of its vertices
 *    moves to the minimum of its accumulated quadric (the sum of the
 *    quadrics of every input vertex collapsed into it, Garland-Heckbert 97
 *    §4's optimal placement) plus a pull toward its input point of a
 *    thousandth of the quadric's mean eigenvalue (pm_work_fit_coarse),
 *    unless a face around it would turn by more than 60 degrees.  The
 *    input positions of level 0's vertices stay, at level 1, in a position
 *    column over the lowest ids (level 0's), and level 1's details take
 *    the difference (progressive.c, compute_details: a vertex predicted by
 *    itself gets a detail when its position changed from the level below).
 *    Every level above 0 is the input's as before, to the bit; the map is
 *    the same.  Coarse-level quality at 1 % of the faces (bench_progressive,
 *    two-sided distances to the input, of the bounding box's diagonal),
 *    RMS without -> with the placement: koala 0.002397 -> 0.001713 (0.76x
 *    OpenMesh's Decimater, 0.81x meshoptimizer), sword 0.000541 ->
 *    0.000364, boot 0.006110 -> 0.004777; Hausdorff 0.01285 -> 0.01233,
 *    0.00502 -> 0.00494, 0.02823 -> 0.02161.
 *
 * Polygons are triangulated first (fans; rep->triangulated says so).
 */
#ifndef ST_PROGRESSIVE_H
#define ST_PROGRESSIVE_H

#include "core/multires/hier.h"

/* The progressive scheme's table (progressive_scheme.c): the prediction of
 * point 5, the synthesis of the ring tables. */
extern const st_scheme st_scheme_progressive;

/* The prediction of a progressive hierarchy (st_hier_opts.pm_predictor,
 * tagged in sessions: docs/SESSION-FORMAT.md, HIER; point 5 says which
 * and why). */
typedef enum st_pm_predictor {
    ST_PM_RELAXED = 0,         /* a split's old neighbours relaxed with weight 1/2: the default, and
                                  sessions written before the tag */
    ST_PM_LIGHT = 1,           /* the same relaxation with weight 1/8 */
    ST_PM_GRADED = 2,          /* weight 1/2 on the two finest levels, 1/10 below: new builds' default */
} st_pm_predictor;
/* What new builds get (st_rebuild, hence `strata rebuild` and the window);
 * a zero st_progressive_opts keeps ST_PM_RELAXED. */
#define ST_PM_DEFAULT ST_PM_GRADED

typedef struct st_progressive_opts {
    uint64_t target_faces;     /* stop at or just above this many faces; 0: as far as possible */
    unsigned max_levels;       /* most levels in all (level 0 included); 0: ST_MAX_LEVELS */
    int predictor;             /* enum st_pm_predictor; 0: ST_PM_RELAXED (ST_PM_DEFAULT is new builds') */
    /* Non-zero: level 0's vertices sit at their quadric's optimal point
     * (point 8 above; what st_rebuild builds), 0: at their input positions
     * like every other level's (a zero st_progressive_opts, as before). */
    int fit_coarse;
    /* Called after each level with the fraction of the work done; a
     * non-zero return cancels the build (ST_ERR_INVALID, "cancelled"). */
    int (*progress)(void *ctx, double fraction);
    void *progress_ctx;
} st_progressive_opts;

typedef struct st_progressive_report {
    unsigned levels;                       /* levels built: 0..levels-1 */
    uint64_t faces[ST_MAX_LEVELS];         /* faces of each level */
    uint64_t vertices[ST_MAX_LEVELS];      /* vertices of each level */
    double kept[ST_MAX_LEVELS];            /* t of level l >= 1: vertices(l-1) / vertices(l) */
    double bytes_per_dart;                 /* map topology bytes per finest dart */
    double detail_bytes_per_dart;          /* detail arrays (all levels) per finest dart */
    uint64_t inexact;                      /* (level, vertex) details whose synthesis misses the input's
                                              bits by an ulp or so (progressive.c, compute_details) */
    int triangulated;                      /* the input had polygons: fans were used */
    int target_reached;                    /* faces[0] <= target_faces */
    char note[256];                        /* why the simplification stopped */
} st_progressive_report;

/* Builds the hierarchy into *out (left empty on failure).  fine must be a
 * repaired soup (st_mesh_repair): manifold and consistently oriented.
 * rep may be NULL. */
int st_progressive_build(const st_mesh *fine, const st_progressive_opts *o, st_hier *out,
                         st_progressive_report *rep, st_error *err);

/* Multiresolution filtering: multiplies the details of level k+1 by
 * gains[k] (k < n; levels above n keep gain 1), then re-synthesises the
 * levels above the first level whose gain is not 1.  Gain 0 removes a band,
 * 1 keeps it (all gains 1 change no bit), > 1 enhances it.  The scaled
 * details stay: applying gains g then 1/g restores the details (up to
 * rounding).  Fails on a hierarchy of another scheme or a non-finite gain. */
int st_progressive_filter(st_hier *h, const double *gains, unsigned n, st_error *err);

/* The recipe of a progressive hierarchy's topology (progressive_recipe.c;
 * the session's PMRC chunk, docs/SESSION-FORMAT.md): level 0's darts and
 * vertex count, then per level its vertex splits in the order the build
 * made them.  Replaying it (st_progressive_regenerate) gives the map the
 * build made, ids included: a session stores this instead of every level's
 * relations.
 *
 * A split of level L is the undo of one collapse a -> b (point 4 above):
 * the new vertex a takes from b the fan of b's half-edges after b -> d up
 * to and including b -> c (interior edge), or from b's outgoing boundary
 * half-edge up to b -> c (d = ST_NIL, boundary edge); a's id and the darts
 * of the two restored triangles are the next ids of level L.  The darts
 * b -> c and b -> d are given by their rank in b's fan at level L-1, in
 * β1 order from b's dart of smallest id: a few bits where vertex ids
 * would take 32 (a session's bytes). */
typedef struct st_pm_split { uint32_t b, c, d; } st_pm_split;   /* b a vertex id; c, d ranks */

typedef struct st_pm_recipe {
    unsigned top;
    uint32_t nverts0, ndarts0;              /* level 0: vertex ids [0, nverts0), dart ids [0, ndarts0) */
    uint32_t *beta0, *beta1, *vert;         /* per level-0 dart */
    uint8_t *boundary;                      /* per level-0 dart: fills a hole */
    uint32_t nsplits[ST_MAX_LEVELS];        /* splits of level l (l >= 1) */
    st_pm_split *split;                     /* every level's, level 1 first */
} st_pm_recipe;

/* The recipe of h, read from its map: -1 when h is not as a progressive
 * build (or a regeneration) left it (st_hier_regenerable, the pools'
 * layout) or memory runs out; nothing to free then. */
int st_progressive_recipe(const st_hier *h, st_pm_recipe *out);
void st_pm_recipe_free(st_pm_recipe *r);
/* r's level-0 arrays for ndarts0 darts (r->ndarts0 set, contents left to
 * the caller); -1 when memory runs out (what was allocated goes with
 * st_pm_recipe_free). */
int st_pm_recipe_alloc_level0(st_pm_recipe *r, uint32_t ndarts0);
/* Splits in all (sum of nsplits). */
uint64_t st_pm_recipe_splits(const st_pm_recipe *r);
/* The counts of every level 0..top of a progressive hierarchy as its build
 * or a replay left it (st_hier_regenerable), without walking the levels
 * (st_level_stats_compute does): no level deletes a vertex or a dart, its
 * real faces are triangles and its holes keep their number (point 2), so
 * the pools' live counts and the hole darts give them.  out: top + 1
 * entries.  -1, nothing written, for any other hierarchy. */
int st_progressive_level_counts(const st_hier *h, st_level_stats *out);
/* The recipe as the session's PMRC chunk holds it (docs/SESSION-FORMAT.md)
 * into out, NULL: nothing written; returns the bytes. */
size_t st_pm_recipe_encode(const st_pm_recipe *r, unsigned char *out);
/* Builds h's map (h: scheme and options set, its map replaced) from r
 * (progressive_replay.c, which the build makes its map with too):
 * the topology of every level, positions zero (the caller reads them),
 * then marks h regenerable.  Checks every record first as the build
 * would have made it (level 0 a manifold triangle mesh with boundary
 * loops, at most one hole per vertex; each split's b, c, d existing
 * vertices around b, the groups' rules of point 3), so the levels are
 * valid maps by construction; a refused recipe leaves h's map empty and
 * names the level and split in err. */
int st_progressive_regenerate(st_hier *h, const st_pm_recipe *r, st_error *err);

#endif
