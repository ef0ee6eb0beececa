/* Shared checks for the adaptive-refinement tests (test_adapt*.c): mesh
 * factories, map validity, watertight displays, the one-level restriction,
 * point-set distances, and the drivers every adaptive scheme runs (random
 * box moves, agreement with the regular hierarchy, the detail round trip,
 * incremental == full updates, ...).  Each driver takes one case: the
 * scheme, the input mesh, whether it is closed, the display's face size,
 * the finest level and the size of the model. */
#ifndef ST_ADAPT_TESTLIB_H
#define ST_ADAPT_TESTLIB_H

#include "core/adapt/adapt.h"
#include "core/multires/hier_internal.h"
#include "testlib.h"

typedef struct at_case {
    st_scheme_id id;
    void (*make)(st_mesh *);
    const char *name;
    int closed;       /* every edge of the display in two faces (else one or two) */
    unsigned sides;   /* 3: the display is all triangles; 0: any polygons */
    unsigned max;     /* finest level */
    double extent;    /* size of the model: boxes and tolerances scale with it */
} at_case;

/* Fixtures. */
void at_torus(st_mesh *s);  /* tl_mesh_torus(8, 6) */
void at_grid(st_mesh *s);   /* tl_mesh_grid(4): open */

/* CHECKs that the map is valid. */
void at_valid(st_map *m, const char *what);
/* Every directed edge once and every face of >= 3 sides (exactly `sides`
 * when non-zero); closed: every edge's reverse present too. */
int at_watertight(const st_mesh *s, int closed, unsigned sides);
/* CHECKs the display of a is produced and watertight. */
void at_check_display(st_adapt *a, const at_case *c, int step);
/* Faces of the top level sharing a vertex differ by at most one level. */
int at_restriction_holds(st_map *m);
/* The box of half-size r around (cx, cy, cz). */
st_adapt_params at_box(double cx, double cy, double cz, double r, unsigned base, unsigned max);
/* Uniform in [-1, 1] (steps of 1/1000). */
double at_rand_unit(uint64_t *rng);
/* Largest distance from a point of a to the nearest point of b;
 * at_mesh_dist is the larger of both directions. */
double at_pointset_dist(const st_mesh *a, const st_mesh *b);
double at_mesh_dist(const st_mesh *a, const st_mesh *b);

/* Two hierarchies of the case's scheme and input (h with hlevels regular
 * levels, g with none) with an adaptive refinement each. */
typedef struct at_pair { st_hier h, g; st_adapt a, b; } at_pair;
void at_pair_init(at_pair *p, const at_case *c, unsigned hlevels);
void at_pair_free(at_pair *p);
/* CHECKs both displays are produced; their sizes in nf/nv, [0] a, [1] b;
 * returns the distance between them (both directions). */
double at_compare(st_adapt *a, st_adapt *b, uint32_t nf[2], uint32_t nv[2]);

/* Random box moves with a fixed seed: every level valid, display watertight,
 * restriction kept.  vary: box sizes change, some steps with a falloff and
 * some with no_restriction (for schemes that always restrict); else boxes
 * of 0.3 extent. */
void at_check_random_moves(const at_case *c, uint64_t seed, int steps, int vary);
/* Scheme-specific faces that must appear at the depth borders of every
 * level (NULL: none required). */
typedef int (*at_border_face)(st_map *m, uint32_t d, unsigned k);
/* Every corner of every face of level k has its level-k position in the
 * regular hierarchy; the box over everything gives the regular top level,
 * over nothing the base level (0 and 1), and back up. */
void at_check_matches_regular(const at_case *c, at_border_face border, const char *border_name);
/* Details on every vertex at every level, the box away and back, half away
 * and back: the same geometry. */
void at_check_detail_round_trip(const at_case *c);
/* The incremental update gives the same mesh as a full update, along a
 * random walk of the box (half-size r * extent). */
void at_check_incremental(const at_case *c, uint64_t seed, int steps, double r);
/* The same along a drag: small moves (1 to 6 % of the box's width) along
 * one axis at a time, to max levels, where the incremental update leaves
 * out the faces remote from where the boxes differ (adapt_update.c). */
void at_check_drag(const at_case *c, uint64_t seed, int steps, double r, unsigned max);
/* Resynthesis of an unedited adaptive hierarchy moves nothing; the same
 * criteria again touch nothing; the result equals a fresh full update. */
void at_check_resynth_and_repeat(const at_case *c);
/* Adapting on top of one regular level == from level 0 with base level 1. */
void at_check_on_regular_levels(const at_case *c);
/* The flatness criterion alone, then with a box: refined somewhere but not
 * everywhere. */
void at_check_flatness(const at_case *c);
/* Random criteria: the same criteria again touch nothing, and the mesh does
 * not depend on earlier updates. */
void at_check_history_free(const at_case *c, uint64_t seed);

/* The suite every scheme that adapts closed meshes only (√3, Doo-Sabin)
 * runs on each case: random moves (seed 31 + index, varied boxes), agreement
 * with the regular hierarchy (border faces as above), the detail round trip,
 * resynthesis and repeats one level coarser, adapting on a regular level;
 * then `extra` (NULL: none) on the case. */
void at_run_cases(const at_case *cases, size_t n, at_border_face border, const char *border_name,
                  void (*extra)(const at_case *));
/* at_check_incremental (seed 77, 24 steps) on each case, with its box. */
typedef struct at_inc { at_case c; double r; } at_inc;
void at_run_incremental(const at_inc *inc, size_t n);

#endif
