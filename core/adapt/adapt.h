/* Adaptive refinement (Kraemer 2008 §3.2.2-3.2.6, Algorithms 1, 5 and 6)
 * for the primal quadrisection schemes: Catmull-Clark, Loop, Butterfly and
 * quad/triangle, for √3 on closed triangle meshes (Algorithm 8,
 * adapt_sqrt3.c; see "√3" below), and for Doo-Sabin through the dual
 * encoding (adapt_doosabin.c; see "Doo-Sabin" below).
 *
 * Only faces chosen by a criterion are subdivided.  Every level is still a
 * closed 2-map: a face next to a finer one simply has more sides.  Whether a
 * cell is subdivided is read from the map, nothing is stored (§3.2.6):
 *   - an edge of level i is split toward i+1 when β0 of its dart at level
 *     i+1 is a dart inserted at i+1;
 *   - the subdivision level of a face in the map of level l is the smallest
 *     j >= ℓ (ℓ the lowest insertion level of its darts, taken at that dart
 *     b) such that the level-j face orbit of b lies inside the face; a face
 *     of level i is subdivided toward i+1 when its dart's face in the map of
 *     level i+1 has level i+1 (a query above the top level is allowed).
 *
 * The one-level restriction (on by default): before a face of level i is
 * subdivided, every face sharing a vertex with it is brought to level i
 * first, so neighbouring faces differ by at most one level.  Then every stencil of the new vertices finds its complete
 * regular neighbourhood, and positions equal those of a regular hierarchy.
 * With the restriction off the map stays valid; stencils are taken over
 * whatever the neighbourhood is at level i (positions then differ from the
 * regular ones near depth borders).
 *
 * Simplification keeps the detail vectors of the vertices it removes, at
 * every level, under the vertex's address in the refinement tree (adapt_details.c:
 * level-0 dart plus child indices, so recreated darts find them again), and
 * gives them back when the region is refined again.  Local frames take their
 * tangent from the smallest dart id of the coarse cell (hier_synth.c) and a
 * coarsened region's darts come back with other ids, so a detail whose frame
 * cell is taken apart is kept as a world-space vector and turned back into
 * the new frame when the cell is complete again: with the restriction on,
 * an unedited coarse surface gets exactly its fine geometry back at every
 * depth.  (An edit of a coarser level made while a region is coarsened
 * carries those details along but does not rotate them.)
 *
 * √3 (adapt_sqrt3.c has the details).  A level is one √3 step (two steps
 * trisect the edges).  Subdividing a triangle of level i splits it by its
 * centre at i+1 and flips each of its edges whose other side is already
 * subdivided toward i+1; the edges toward unsubdivided neighbours stay
 * unflipped and the sub-triangles on them are "odd" until the neighbour is
 * subdivided.  No edge is split, so st_edge_is_split does not apply; every
 * face is a triangle holding exactly one dart older than it, and the face
 * level and "subdivided toward i+1" above read the same from the map; a
 * face of level i is odd when a face across one of its edges has a lower
 * level at i.  Nothing is stored.  The one-level restriction is always
 * applied for √3 (no_restriction is ignored; the `restricted` arguments
 * below too): an odd triangle is never subdivided (its lower neighbour is,
 * first), and the faces around the corners of a face being subdivided are
 * made even triangles of its level first - the flips change β1 of old
 * darts, which the levels above may only take where they have not
 * diverged.  Simplification flips the edges back and removes the centre
 * (the only vertex √3 creates), keeping its details like the others.  The
 * updates read the criteria of a √3 face of level i >= 1 on the two
 * level-(i-1) triangles of its old edge, capped by what those want (so an
 * odd triangle and the even ones replacing it agree, and the result of an
 * update does not depend on earlier ones); st_adapt_wanted_level below is
 * the plain per-face reading.
 * Meshes with holes are refused (boundary trisection is not adaptive).
 *
 * Doo-Sabin (adapt_doosabin.c has the details).  The map holds the dual M*
 * (scheme_doosabin.c): a face of M* is a surface vertex, a vertex of M* a
 * surface face.  Adaptive Doo-Sabin is adaptive Catmull-Clark topology on
 * M* - the face and edge levels, the polygon split, the restriction, the
 * can-simplify test and the refinement-tree addresses above all apply as
 * they are - with the dual vertex handling: each quad of a subdivided face
 * of M* gets a fresh vertex id placed by the Doo-Sabin mask (the ids the
 * primal operators make for midpoints and centres are released), the new
 * dart a split edge puts into the unsplit face across carries that face's
 * id, and simplification gives the face its coarse id back and keeps the
 * quads' details under (path of the face, corner index).  The one-level
 * restriction is always applied (no_restriction is ignored).  Criteria: a
 * cell of level 0 covers the dual cell of its vertex (the vertex, the
 * midpoints of its edges, the centroids of its faces); a cell of level
 * l >= 1, cut at the corner of its parent's vertex u in the surface face W,
 * covers W's corner quad at u (u, the midpoints of W's two sides at u, W's
 * centroid, all of level l-1) and its own vertex - so children tile their
 * parent's region and every reading is of a neighbourhood that is complete
 * while the cell exists; flatness is the largest angle between consecutive
 * faces around the parent's vertex (level 0: the vertex's own).  The
 * displayed mesh is the dual of the top level (st_map_to_mesh): closed, its
 * polygons at depth borders mixing corners of two levels.
 *
 * Progressive hierarchies (core/progressive/progressive.h; the proof is in
 * adapt_progressive.c).  Nothing is refined: every level exists already.
 * The displayed mesh is level max_level with the collapses of the levels
 * base_level+1..max_level applied, except those whose 1-ring at their level
 * holds a vertex of a level-max_level face that wants their level (the box,
 * its falloff bands) and those whose 1-ring meets the ring of a collapse
 * left out at a finer level.  It is a valid closed-or-bordered triangle
 * mesh of the input's topology made of triangles of several levels: level
 * max_level where faces touch the box, level base_level far from it.  Its
 * vertices take the position of the level of the coarsest collapse applied
 * around them.  The map is never changed; st_adapt_update recomputes the
 * mesh (O(darts)), and st_adapt_display_map / st_adapt_mesh give it.
 * Flatness and the restriction flag are not used there. */
#ifndef ST_ADAPT_H
#define ST_ADAPT_H

#include "core/multires/hier.h"
#include "core/map/dart_list.h"
#include "core/map/footprint.h"
#include "core/multires/edit.h"

int st_edge_is_split(const st_map *m, uint32_t d, unsigned i);
/* Subdivision level of the face of d in the map of level l. */
unsigned st_face_level(st_map *m, uint32_t d, unsigned l);
/* The face of d, of subdivision level i, is subdivided toward i+1. */
int st_face_is_subdivided(st_map *m, uint32_t d, unsigned i);

typedef struct st_adapt_params {
    unsigned base_level;     /* every face refined at least to this level */
    unsigned max_level;      /* faces touching the box go to this level */
    double box_lo[3], box_hi[3];
    int has_box;
    double falloff;          /* band around the box (object units) with one level less per band width; 0: none */
    double flatness;         /* > 0: also refine faces whose normals deviate more than this (radians) */
    int no_restriction;      /* 1: one-level restriction off (ignored by √3 and Doo-Sabin: always on) */
} st_adapt_params;

/* Adaptive state kept between updates (saved details of removed vertices). */
typedef struct st_adapt_saved {
    uint64_t path;           /* refinement-tree address of the face (adapt_details.c) */
    uint32_t meta;           /* creation level, detail level, kind, element */
    double d[3];
} st_adapt_saved;

typedef struct st_adapt {
    st_hier *h;
    st_adapt_saved *saved;   /* sorted by (path, meta); d in world space */
    uint32_t nsaved, capsaved;
    st_adapt_saved *parked;  /* details of live vertices whose frame cell was taken apart:
                                path = vertex id, meta = level, d in world space (adapt_details.c) */
    uint32_t nparked, capparked;
    uint64_t touched;        /* faces subdivided or simplified by the last update */
    uint64_t forced;         /* coarser faces subdivided by the restriction in the current pass */
    st_dart_list forced_faces; /* those faces, as (dart, level) pairs (adapt_update.c; during an update only) */
    struct st_adapt_canon *canon; /* what the current update changed, for its canonical pass (adapt_resynth.c):
                                     polygon split family, during an update only; NULL otherwise */
    st_adapt_params prev;    /* criteria of the last update */
    int has_prev;            /* prev is valid and the geometry has not changed since */
    st_dart_list base_faces; /* one dart per base face */
    struct st_adapt_grid *grid; /* base faces by place (adapt_grid.c): a cache, never saved */
    const struct st_adapt_ops *ops; /* the refinement family's operations (adapt_internal.h), chosen from
                                       the scheme by st_adapt_init (or on first use): never saved */
    struct st_pm_select *pm; /* progressive hierarchies: the selection (below); NULL otherwise; never saved */
    st_map *pm_view;         /* progressive hierarchies: the selected mesh as a one-level map; never saved */
    unsigned keep_above;     /* 0: off; else no face is simplified that would drop a non-zero detail
                                of a level > keep_above (sculpted HD detail; see "HD levels" below).
                                Polygon split family only; st_adapt_init sets 0; not saved by sessions */
    const struct st_layers *keep_layers; /* NULL, or sculpt layers whose levels > keep_above belong to this
                                hierarchy: with keep_above, a face is kept refined as for a detail while a
                                vertex of its subdivision holds anything of them (st_layers_holds), so the
                                vertex ids they index stay; st_adapt_init sets NULL; not saved */
    int exact;               /* 1: every update ends with the canonical pass (adapt_resynth.c, "after an
                                update"), so that positions stay what st_adapt_synthesize(a, base) gives
                                bit for bit, as HD edits need (their local edits are compared with a
                                full re-synthesis); it costs box moves 10 to 85 % (bench_adapt,
                                bench_hd).  Only from a state that already is a full synthesis.
                                Polygon split family only; st_adapt_init sets 0; not saved */
} st_adapt;

/* Selective display of a progressive hierarchy (see "Progressive hierarchies"
 * above; adapt_progressive.c).  The selected mesh: nverts vertices, vertex i
 * being the hierarchy's vertex vid[i] at its position of level lam[i], and
 * nfaces triangles of vertex indices (tri, 3 each). */
typedef struct st_pm_select {
    unsigned base, max;       /* the levels of the last update (clamped to the hierarchy) */
    int valid;                /* an update succeeded */
    uint32_t nverts, nfaces;
    uint32_t *vid;
    uint8_t *lam;
    uint32_t *tri;
    uint64_t kept, applied;   /* collapses of levels base+1..max left out / applied */
    /* caches of the hierarchy's topology (valid for cache_map at cache_gen) */
    const st_map *cache_map;
    uint64_t cache_gen;
    uint32_t cache_nv;
    uint32_t *split_dart;     /* per vertex of level l >= 1: a dart of level l leaving it */
    uint32_t *order;          /* vertices by insertion level: level l at [level_beg[l], level_beg[l+1]) */
    uint32_t level_beg[ST_MAX_LEVELS + 1];
    uint8_t *want, *skip, *held, *lamv; /* per vertex (scratch of an update; skip: collapse left out) */
    uint32_t *disp;           /* per vertex: its index in the selected mesh, or ST_NIL */
} st_pm_select;

/* Recomputes the selection for p (h must be progressive; the map is not
 * changed, only read; h is not const because the topology cache reads the
 * map's generation). */
int st_pm_select_update(st_pm_select *s, st_hier *h, const st_adapt_params *p, st_error *err);
/* The selected mesh, with the positions h has now. */
int st_pm_select_mesh(const st_pm_select *s, const st_hier *h, st_mesh *out, st_error *err);
void st_pm_select_free(st_pm_select *s);

/* The map and level that show the result of the last update: the
 * hierarchy's top level, or for a progressive hierarchy the one-level map
 * of the selected mesh (built from the saved criteria after a session
 * load; NULL when out of memory). */
const st_map *st_adapt_display_map(st_adapt *a, unsigned *level);

int st_adapt_init(st_adapt *a, st_hier *h, st_error *err);
void st_adapt_free(st_adapt *a);

/* Subdivides the face of d (subdivision level i) toward i+1 (Algorithm 1),
 * after its coarser neighbours when the restriction is on, and computes the
 * level-(i+1) positions of its vertices. */
int st_adapt_subdivide_face(st_adapt *a, uint32_t d, unsigned i, int restricted, st_error *err);
/* Whether the face of d (level i, subdivided toward i+1) may go back to
 * level i (§3.2.3, listing 3.2.3). */
int st_adapt_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted);
/* Algorithm 6 for one face: removes its inner edges and the edge splits no
 * neighbour needs; keeps the removed vertices' details. */
int st_adapt_simplify_face(st_adapt *a, uint32_t d, unsigned i, st_error *err);

/* Level the criteria of p want for the face of d at level l of a primal
 * map (box, falloff, flatness; never below p->base_level): what the polygon
 * split schemes' updates read.  (√3 updates use a variant, see "√3" above;
 * Doo-Sabin reads the region of its cells, see "Doo-Sabin".) */
unsigned st_adapt_wanted_level(const st_map *m, uint32_t d, unsigned l, const st_adapt_params *p);

/* Algorithms 5 then 6 with the criteria of p.  When only the box moved since
 * the last update (same levels, falloff and restriction, no flatness
 * criterion, no edit in between), only the faces that descend from the base
 * faces near the old or the new box are visited (incremental update: base
 * faces found through a grid, faces deep inside both boxes not entered,
 * later passes only below the faces the restriction forced); the result is
 * the same as a full update.  Polygon split family (Catmull-Clark, Loop,
 * Butterfly, quad/triangle): the update ends with a canonical local pass
 * over the faces it subdivided or simplified (adapt_resynth.c), so that
 * every position is the one st_adapt_synthesize(a, p->base_level) would
 * give, bit for bit, given a hierarchy that was so before (one that only
 * updates, st_adapt_edit and st_adapt_synthesize made); its cost follows
 * what the update touched. */
int st_adapt_update(st_adapt *a, const st_adapt_params *p, st_error *err);

/* Synthesis of an adaptive hierarchy from level `from`: every vertex of a
 * subdivided face gets S(P_{L-1}) + frame · detail at each level L. */
void st_adapt_synthesize(st_adapt *a, unsigned from);

/* The displayed adaptive mesh: the real faces of the top level, with each
 * vertex at the finest level where it has a position, and the UVs of
 * st_adapt_uv_build when the hierarchy carries them there. */
int st_adapt_mesh(st_adapt *a, st_mesh *out, st_error *err);

/* ---- HD levels (adapt_hd.c) ------------------------------------------------
 * "HD sculpting": levels 0..N of the hierarchy are uniform (adapt params
 * base_level = N) and the levels above N are refined only inside the
 * interest box; the user sculpts at levels > N.  Edits at such a level go
 * through st_adapt_edit (the regular edit's region growth, st_hier_edit,
 * would visit unsubdivided faces); a brush only moves the vertices
 * st_adapt_vertex_editable accepts; keep_above (st_adapt) keeps sculpted
 * regions refined when the box moves on.  Polygon split schemes only
 * (Catmull-Clark, Loop, Butterfly, quad/triangle): the caller refuses HD
 * for √3, Doo-Sabin and progressive hierarchies. */

/* An edit at level l of an adaptive hierarchy: the darts' vertices get the
 * positions pos at level l (l >= 1: the detail D = F^T (P - S(P_{l-1})) is
 * stored and the position is written as st_hier_apply_detail(S(P_{l-1}),
 * F, D), so that a full synthesis from l-1 (st_adapt_synthesize) gives the
 * same bits; levels above l where the vertex only inherits its level-l
 * position follow), then levels l+1..top are re-synthesised around the
 * darts (st_hier_resynth_around).  fp (NULL: nothing) gets the level-l keys
 * of st_hier_edit_level, the inherited positions above l that followed,
 * and the re-synthesised positions.  cache: st_hier_edit_cached's (NULL:
 * none).  For l >= 1 the darts' vertices should be editable
 * (st_adapt_vertex_editable): S(P_{l-1}) is then the one a synthesis takes
 * (adapt_resynth.c, canonical stencils), so the result equals a full
 * st_adapt_synthesize from l-1 or lower bit for bit, given a hierarchy
 * that did before.  Returns the number of positions written above l
 * (followed plus re-synthesised; a vertex once per level and pass). */
uint64_t st_adapt_edit(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                       st_footprint *fp, st_edit_cache *cache);

/* st_adapt_edit with sculpt layers on level l (core/multires/layers.h, the
 * part "for callers that compute the details themselves"): the change of
 * detail goes into the stack's slot `target` (st_layers_edit_target) and
 * the detail stored is the composition.  pos NULL: no change, the darts'
 * vertices get the composition as it is now (after a change of strengths,
 * visibility, order or offsets).  ls NULL or without a layer on l, with
 * pos: st_adapt_edit.  The same bits as a full synthesis, as there. */
struct st_layers;
uint64_t st_adapt_edit_layered(st_hier *h, struct st_layers *ls, int target, unsigned l, const uint32_t *darts,
                               const double (*pos)[3], uint32_t n, st_footprint *fp, st_edit_cache *cache);

/* Non-zero when L >= 1 and every real face around the vertex of d at level L
 * is a face of subdivision level L (holes around it are allowed): only such
 * a vertex has a level-L prediction S(P_{L-1}) from a complete
 * neighbourhood, so only it may be moved at level L (a vertex on the
 * border of the refined region shows a coarser face's corner). */
int st_adapt_vertex_editable(st_map *m, uint32_t d, unsigned L);
/* Whether hierarchies of scheme sc have HD levels: the polygon split
 * family (Catmull-Clark, Loop, Butterfly, quad/triangle), whose
 * syntheses take canonical stencils (adapt_resynth.c); √3, Doo-Sabin and
 * progressive ones do not. */
int st_adapt_scheme_has_hd(const st_scheme *sc);

/* Per level L = from+1..top of a polygon split map: faces[L] the real faces
 * of subdivision level L stored at L, bytes[L] an estimate of what level L
 * costs: st_map_level_memory's bytes (darts and vertices inserted at L,
 * the level-L columns of the relations and positions) plus one detail
 * (3 doubles) per vertex inserted at L.  Levels <= from and above top are
 * set to 0.  (The details of older vertices at L, kept in the hierarchy's
 * dense per-level arrays, are not counted: the map alone does not know
 * them.) */
void st_adapt_hd_levels(const st_map *m, unsigned from, uint64_t faces[ST_MAX_LEVELS], uint64_t bytes[ST_MAX_LEVELS]);

/* ---- UVs (adapt_uv.c) ------------------------------------------------------ */

/* Face-varying UVs of the adaptive mesh, per dart id of the top level: the
 * level-0 UVs carried up the adaptive map with the rules of
 * docs/SUBDIVISION-RULES.md §7b, on the subdivided faces only.  Every
 * corner holds the value of the finest level at which its vertex was
 * computed, in the chart of its face (as st_adapt_mesh shows each vertex at
 * its finest position): the corners of a face whose vertices all have
 * level L hold the level-L values of the rules; a face next to finer ones
 * holds, at its corners and at the split points of its sides, the values
 * the finer level gives those points on its side of a seam.  So two faces
 * sharing an edge inside a UV island share the values at its ends.
 * level[d] is the level of d's value, val[d] its value label (fvar.c:
 * corners of one vertex with one label hold one value). */
typedef struct st_adapt_uv {
    uint32_t cap;      /* dart ids below cap */
    double *uv;        /* 2 per dart; NULL: the adaptive mesh has no UVs */
    uint32_t *val;
    uint8_t *level;
    uint32_t *rank;    /* a regular level's numbering of the darts above level 0 (adapt_uv.c; for
                          Doo-Sabin, of M*'s) */
} st_adapt_uv;

/* Why the adaptive mesh of a carries no UVs (NULL: it does): a mesh without
 * UVs, a progressive hierarchy. */
const char *st_adapt_uv_absent(const st_adapt *a);
/* Computes them for the map as it is now (O(darts) per level); u->uv stays
 * NULL when st_adapt_uv_absent says why. */
int st_adapt_uv_build(st_adapt *a, st_adapt_uv *u, st_error *err);
void st_adapt_uv_free(st_adapt_uv *u);
/* Sets out's nuvs, uv, face_uv for the mesh st_map_to_mesh made of the top
 * level (same face walk): one texture coordinate per vertex, level and
 * value label.  Nothing when u has no UVs. */
int st_adapt_uv_mesh(st_adapt *a, const st_adapt_uv *u, st_mesh *out, st_error *err);

/* ---- local re-synthesis (adapt_resynth.c) -------------------------------- */

/* Level L of an adaptive hierarchy on the given faces of level L-1 (one dart
 * each, faces subdivided toward L): S(P_{L-1}) + F·D, each vertex once
 * (st_adapt_synthesize's arithmetic). */
void st_hier_resynth_faces(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n);

/* Levels from+1..top of an adaptive hierarchy re-synthesised around seeds
 * (darts of level `from` whose vertices moved): the region growth of
 * st_hier_edit on the faces subdivided toward the next level only, with one
 * ring more (a face next to a moved vertex may be unsubdivided while a
 * corner of it is a corner of a subdivided face one ring further, whose
 * stencils read the moved vertex).  Appends (L, ST_FP_POS) of every vertex
 * written to fp (NULL: nothing).  Returns the number of positions written
 * (a vertex once per level). */
uint64_t st_hier_resynth_around(st_hier *h, unsigned from, const uint32_t *seeds, uint32_t n, st_footprint *fp);

#endif
