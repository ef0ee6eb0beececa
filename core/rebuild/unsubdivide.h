/* Unsubdivide: a dense mesh with subdivision connectivity back into a
 * coarse cage and a multiresolution hierarchy (the reverse of uniform
 * refinement, thesis §3.2.1; positions by the analysis of Algorithm 4).
 *
 * A mesh is recognised as k >= 1 steps of one of two refinements of a
 * coarser mesh, whatever the order of its vertices and faces and the
 * starting corner of each face (OpenSubdiv, Blender and Strata number
 * differently), boundaries included:
 *   - the polygon split of Catmull-Clark: each n-gon -> n quads through a
 *     face point and its edge points, every fine quad's corners reading
 *     (coarse vertex, edge point, face point, edge point);
 *   - triangle quadrisection (Loop, Butterfly): each triangle -> three
 *     corner triangles (coarse vertex, edge point, edge point) and one
 *     central triangle of edge points.
 * One step labels every vertex (coarse vertex V, edge point E, face point
 * F) by propagation over the faces from a seed face of each connected
 * component, for each of the few labellings of the seed (4 per pattern),
 * and checks the labelling: every vertex one label, an edge point has two
 * coarse neighbours (valence 4 / 3 on the boundary for the polygon split,
 * 6 / 4 for quadrisection), face points are interior, and the coarse mesh
 * read off the labelling is an oriented 2-manifold whose refinement is the
 * input.  Steps repeat while the pattern holds (and the limits allow).
 *
 * Several labellings can be consistent: a closed polygon-split mesh is also
 * the split of its cage's dual (V and F exchanged), and fully regular
 * components (a torus grid) admit shifted labellings.  The choice is
 * deterministic: (1) the smallest residual of a local identity the polygon
 * split satisfies exactly, 4 ΣE_i = 3 m F + Σ F'_i over the m edge points
 * E_i of a coarse face with face point F and the face points F'_i across
 * its edges (it follows from E = (v_a + v_b + F + F')/4 and F = mean of the
 * corners, Catmull-Clark 1978), evaluated on the positions of the level
 * being split (the input's, and at coarser steps positions recovered from
 * the finer level by inverting the vertex and edge rules where they are
 * invertible); (2) more quadrilateral coarse faces; (3) the first in the
 * enumeration order (seed = the component's first face in input order;
 * polygon split: coarse vertex at its corner 0, 2, 1, 3, as one
 * propagation serves a labelling and its V/F exchange; quadrisection:
 * corner triangle with the coarse vertex at corner 0, 1, 2, then central).
 *
 * Flat arrays per step, no allocation per vertex or face. */
#ifndef ST_UNSUBDIVIDE_H
#define ST_UNSUBDIVIDE_H

#include <stdint.h>

#include "core/io/mesh.h"
#include "core/map/map.h"
#include "core/multires/hier.h"

enum st_unsub_pattern {
    ST_UNSUB_NONE = 0,
    ST_UNSUB_POLY_SPLIT,        /* Catmull-Clark's polygon split */
    ST_UNSUB_QUADRISECTION,     /* triangle quadrisection (Loop, Butterfly) */
};

typedef struct st_unsub_opts {
    unsigned max_levels;        /* at most this many steps; 0: as many as the pattern allows */
    uint32_t target_faces;      /* 0: none; else no step that would leave fewer faces than this */
} st_unsub_opts;

/* One step: the coarse mesh of level j and where its cells went in level
 * j+1 (the next finer mesh; level k is the input). */
typedef struct st_unsub_step {
    st_mesh coarse;             /* faces counter-clockwise; positions: see st_unsubdivide */
    uint32_t *v_fine;           /* per coarse vertex: the same vertex in level j+1 */
    uint32_t *e_fine;           /* per coarse corner c (the edge from c to the next corner
                                   of its face): the edge point in level j+1 */
    uint32_t *f_fine;           /* polygon split: per coarse face its face point; else NULL */
} st_unsub_step;

typedef struct st_unsub {
    int pattern;                /* enum st_unsub_pattern */
    unsigned levels;            /* k: steps found */
    st_unsub_step step[ST_MAX_LEVELS];   /* step[j]: level j, j = 0 .. k-1 */
    char stop[1024];             /* why no further step was taken (one line) */
    /* The half-edge adjacency of level j's mesh (j = 0 .. k; level k is
     * the input), built by the steps and kept for st_unsub_build_hier,
     * which would otherwise build it again, and which frees it once read
     * (before the analysis, so that the peak is not raised; a second call
     * builds it anew).  Core-internal; NULL when out of memory or freed. */
    struct st_unsub_topo *topo[ST_MAX_LEVELS + 1];
} st_unsub;

void st_unsub_free(st_unsub *u);

/* Finds the cage of `in` (a repaired mesh, st_mesh_repair).  Returns 0 with
 * out->levels >= 1, or ST_ERR_TOPOLOGY when not even one step applies, with
 * a message naming where the pattern breaks (vertex or face number of `in`,
 * counted from 1 as in OBJ) and what was expected; *out is then empty.
 * Coarse positions are estimates (the inverted rules where invertible, else
 * the fine vertex's own position): st_unsub_build_hier replaces them by the
 * least-squares fit.  `name` prefixes messages (the file). */
int st_unsubdivide(const char *name, const st_mesh *in, const st_unsub_opts *o, st_unsub *out, st_error *err);

/* Whether scheme sc refines as pattern does (polygon split: catmull-clark,
 * and quad-triangle when the cage has no triangles; quadrisection: loop,
 * butterfly, quad-triangle). */
int st_unsub_scheme_fits(const st_unsub *u, const st_scheme *sc);

/* The hierarchy: level 0 = u's cage, refined u->levels times by sc, the
 * finest level's vertices given the input's positions through the
 * combinatorial correspondence (coarse vertex -> V, edge point -> E, face
 * point -> F, level by level), then analysed down to level 0
 * (st_hier_analyze): level 0 is the least-squares cage and the details
 * carry the rest (zero for an exact subdivision).  The finest level holds
 * the input's positions bit for bit.  fine_of (optional, verts.end entries
 * by the hierarchy's vertex id, ST_NIL for ids not at the finest level)
 * receives the input vertex of each finest vertex; *fine_of is malloc'ed.
 * Returns the analysis' worst relative solver residual in *residual. */
int st_unsub_build_hier(const st_mesh *in, st_unsub *u, const st_scheme *sc, const st_hier_opts *ho,
                        st_hier *h, uint32_t **fine_of, double *residual, st_error *err);

/* Tags and UVs (st_unsubdivide): the cage carries the input's OBJ tags
 * and UVs so that refinement gives them back.  A crease chain a-E-b of one
 * sharpness s (both halves of a coarse edge) makes the coarse edge s + 1
 * per level (OpenSubdiv's uniform rule: s - 1 per level, at or above 10
 * infinitely sharp and kept; an untagged chain, a smooth coarse edge); a
 * corner of a coarse vertex likewise; a coarse face is a hole when all its
 * fine faces are.  Tags no coarser mesh refines into are refused with the
 * edge, vertex or face (the two halves of a coarse edge of different
 * sharpness; a sharp edge inside a coarse face or a sharp edge or face
 * point; a hole beside a non-hole child of one coarse face; a sharpness
 * that one level coarser would be infinite; semi-sharp creases under
 * `t creasemethod chaikin`; `t interpolateboundary 0` with a boundary,
 * whose implied holes a coarser boundary would widen).  st_unsub_build_hier sets the finest level's
 * sharpness to the input's exactly after checking the refined values agree
 * (to float rounding of s + k).  UVs: the cage's corner UV at a coarse
 * vertex is the input's UV at that vertex's fine corner (coarse vertices
 * persist).  Refined with linear face-varying interpolation (uv_interp
 * all) an input whose UVs are the linear refinement of its cage's gets
 * them back; with the smooth options, or UVs edited after refinement, the
 * refined UVs differ: UVs have no details, so the finest level's UVs are
 * those refined from the cage.  st_unsub_uv_residual measures it: the
 * largest difference, per UV coordinate, between the finest level's UVs
 * and the input's (0 when the input has none; fine_of from
 * st_unsub_build_hier). */
double st_unsub_uv_residual(const st_hier *h, const st_mesh *in, const uint32_t *fine_of);

/* The same two without looking half-edges up again: corner_of (optional,
 * darts.end entries by the hierarchy's dart id) receives the input corner
 * of each dart of the finest level, ST_NIL for boundary darts; *corner_of
 * is malloc'ed.  st_unsub_uv_residual_corners reads it.  uv_residual
 * (optional) receives st_unsub_uv_residual_corners' value, measured while
 * the analysis' stencils are built (what `strata rebuild` does: one
 * adjacency of the input, not two). */
int st_unsub_build_hier_corners(const st_mesh *in, st_unsub *u, const st_scheme *sc, const st_hier_opts *ho,
                                st_hier *h, uint32_t **fine_of, uint32_t **corner_of, double *residual,
                                double *uv_residual, st_error *err);
double st_unsub_uv_residual_corners(const st_hier *h, const st_mesh *in, const uint32_t *corner_of);

/* The longest detail vector of levels 1..top (0 for an exact subdivision,
 * up to rounding). */
double st_unsub_max_detail(const st_hier *h);

#endif
