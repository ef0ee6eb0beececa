/* st_hier: a multiresolution subdivision surface (Kraemer 2008 §3.1).
 *
 * Positions of level l (map->pos) always satisfy
 *     P_l(v) = S(P_{l-1})(v) + F_l(v) · D_l(v)            (l >= 1)
 * where S is the scheme's subdivision step (stencils), D_l(v) the detail
 * vector of v at level l, stored in the orthonormal local frame F_l(v)
 * (tangent, bitangent, normal) of the coarse cell the stencil comes from,
 * computed from P_{l-1}.  Because frames come from the coarser surface, a
 * rigid motion of a coarse level moves every finer detail with it exactly.
 *
 * Synthesis (Algorithm 3) evaluates this for l = from+1..top; analysis
 * (Algorithm 4) goes the other way: P_{l-1} is the least-squares fit
 * argmin ||S(P_{l-1}) - P_l||² (so details are as small as possible and zero
 * when P_l is exactly a subdivision), then D_l is what remains.
 *
 * Editing (Blender multires conventions): moving vertices of level i changes
 * P_i and D_i of those vertices; levels above are re-synthesised locally,
 * keeping their details; levels below are untouched.
 */
#ifndef ST_HIER_H
#define ST_HIER_H

#include "core/map/map.h"
#include "core/base/mesh.h"
#include "core/schemes/scheme.h"
#include "core/fvar/fvar.h"

typedef struct st_hier_opts {
    int boundary;              /* ST_BOUNDARY_EDGE_ONLY or ST_BOUNDARY_EDGE_AND_CORNER */
    int crease_method;         /* enum st_crease_method (core/schemes/view.h; OpenSubdiv's default: uniform) */
    int tri_sub;               /* enum st_tri_sub (view.h; Catmull-Clark only; default catmark) */
    int uv_interp;             /* enum st_uv_interp (core/fvar/fvar.h); 0 is OpenSubdiv's default */
    int pm_predictor;          /* progressive scheme only: enum st_pm_predictor (core/progressive/
                                  progressive.h); 0, the relaxation, in sessions written before it */
} st_hier_opts;

typedef struct st_hier {
    st_map map;
    const st_scheme *scheme;
    st_hier_opts opts;
    /* Semi-sharp creases and corners (DeRose et al. 1998, OpenSubdiv):
     * sharpness per dart (both darts of an edge agree) and per vertex, per
     * level; NULL base when the mesh has none. */
    st_mla edge_sharp;         /* float per dart */
    st_mla vertex_sharp;       /* float per vertex */
    int has_sharpness;
    /* Detail vectors per level, indexed by vertex id (NULL: all zero). */
    double *detail[ST_MAX_LEVELS];
    uint32_t detail_cap[ST_MAX_LEVELS];
    /* Scratch reused by the passes. */
    st_stamps stamp;           /* per vertex id */
    /* Per coarse level, what a scheme's full-level synthesis derives from
     * the topology alone (Catmull-Clark: its tables), kept between
     * syntheses; the owner checks the map's generation before each use.
     * Transient: never saved; a deep copy starts without it. */
    st_level_cache cache[ST_MAX_LEVELS];
    /* What the scheme's local re-synthesis derived from the topology for
     * the last edit's region (Catmull-Clark: its records per level), kept
     * for the next edit of the same vertices, as in a drag; checked and
     * transient like cache. */
    st_level_cache local;
    /* Face-varying UVs per level (core/fvar/fvar_internal.h; read through
     * st_hier_uv below); NULL when the mesh had none.  Edits never change
     * them. */
    struct st_fvar *fvar;
    /* Whether levels 1..top can be regenerated from level 0 alone (the
     * compact session, docs/SESSION-FORMAT.md): non-zero, the map's
     * topology generation (st_map_generation) when level 0 was built and
     * every level above it added by the scheme's refinement since, with
     * the pools' ends as level 0 left them; any other change of the
     * topology gives the map a new generation, so the mark lapses. */
    uint64_t regen_gen;
    uint32_t regen_end[2];     /* darts.end, verts.end after level 0 */
    /* A progressive hierarchy's recipe as a session stores it (the PMRC
     * chunk's payload, core/progressive/progressive_recipe.c), kept by the
     * build and the reader so that a save need not read it back from the
     * map; it describes the map only while st_hier_regenerable.  NULL:
     * none kept (a save derives it). */
    unsigned char *pm_recipe;
    size_t pm_recipe_len;
} st_hier;

/* What h's scheme reads and writes of it (core/schemes/view.h): a view
 * into h, valid while h's sharpness attributes, stamps and caches stay
 * where they are (build one per call into the scheme, not per vertex). */
st_subdiv_view st_hier_view(st_hier *h);
/* h's scheme's emit() (scheme.h) of level L, through st_hier_view. */
void st_hier_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t nfaces, st_stencil_sink sink, void *ctx);
/* The same, where the scheme may leave out the fine vertices skip[0..nskip)
 * (vertex ids of level L whose positions the caller keeps: view.h's
 * emit_skip; Catmull-Clark and the primal emitter of Loop, Butterfly and
 * quad/triangle read it). */
void st_hier_emit_except(st_hier *h, unsigned L, const uint32_t *faces, uint32_t nfaces, const uint32_t *skip,
                         uint32_t nskip, st_stencil_sink sink, void *ctx);

/* Builds level 0 from a repaired soup: topology, positions, OBJ tags
 * (creases, corners, interpolateboundary unless opts overrides it).
 * The scheme's input requirements are checked (Loop, Butterfly, √3:
 * triangles only).  h is left empty on failure. */
int st_hier_init(st_hier *h, const st_mesh *mesh, const st_scheme *scheme, const st_hier_opts *opts, st_error *err);
void st_hier_free(st_hier *h);
/* Whether scheme can build on mesh, before building anything: loop,
 * butterfly and sqrt3 need triangles, holes (hole faces, or a mesh that
 * interpolates no boundary) need a face-splitting scheme.  ST_OK, or the
 * reason in err (the words st_hier_init would fail with).  The window
 * greys out the schemes a model cannot take (ui/gui.cc). */
int st_scheme_accepts(const st_scheme *scheme, const st_mesh *mesh, st_error *err);
/* The one wording of a hierarchy's depth, for every command and the
 * window: top 16 is "17 levels (0..16)", top 0 "1 level (0)".  Levels are
 * numbered from 0, so the count is top + 1.  Returns buf. */
char *st_levels_phrase(unsigned top, char *buf, size_t n);

/* Adds levels by regular refinement until top == levels (zero details). */
int st_hier_subdivide_to(st_hier *h, unsigned levels, st_error *err);
/* The same, calling progress(ctx, fraction) before each level's refinement
 * and before its synthesis (fraction of the levels to add done, each level
 * weighted by its share of the new faces; then 1 at the end).  A non-zero
 * return stops it there: ST_ERR_INVALID "cancelled", h holding the levels
 * finished and perhaps one refined but not synthesized; as after any
 * failure, the caller removes what it does not want (st_hier_remove_top).
 * progress NULL: st_hier_subdivide_to. */
int st_hier_subdivide_to_progress(st_hier *h, unsigned levels, int (*progress)(void *ctx, double fraction),
                                  void *ctx, st_error *err);
/* Adds level top+1 by the scheme's refine() alone: topology and sharpness,
 * no positions synthesized, no UVs (st_hier_uv_refine_levels adds them). */
int st_hier_refine_topology(st_hier *h, st_error *err);
/* Deletes the finest level. */
/* Whether levels 1..top are the scheme's refinement of level 0 as it is
 * (regen_gen above): a session may then store level 0 and regenerate the
 * rest (core/io/session.h). */
int st_hier_regenerable(const st_hier *h);
/* Marks h as regenerable now, level 0 having left the pools' ends at
 * end[0] (darts) and end[1] (vertices): the session reader, after it
 * regenerated the levels. */
void st_hier_mark_regenerable(st_hier *h, const uint32_t end[2]);
void st_hier_remove_top(st_hier *h);

/* Deletes the coarsest level: level 1 becomes the control mesh; finer
 * levels, their details and positions are unchanged. */
void st_hier_remove_bottom(st_hier *h);

/* Synthesis of levels from+1..top from level `from` (Algorithm 3). */
void st_hier_synthesize(st_hier *h, unsigned from);
/* Analysis of levels top-1..to from the finest level (Algorithm 4):
 * least-squares coarse positions and details.  Returns the largest of the
 * levels' residuals: the solver's final relative residual, or, for a
 * Catmull-Clark level that the streamed pass accepted as exact
 * (hier_analysis.c), its largest row residual over the level's scale. */
double st_hier_analyze(st_hier *h, unsigned to);

/* Editing: sets the level-l positions of the vertices of the darts given
 * (one dart per vertex), keeps every finer detail, and re-synthesises the
 * levels above locally.  Returns the number of vertex positions recomputed
 * above l (for tests and benchmarks).  st_hier_edit (edit.h) is the same
 * edit reporting what it wrote. */
uint64_t st_hier_move(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n);

/* Local frame of the coarse cell (enum st_frame_cell) at dart d of level l:
 * rows t, b, n, orthonormal. */
void st_hier_frame(const st_hier *h, unsigned l, uint32_t d, int cell, double f[3][3]);

/* Sharpness queries (0 when none; boundary edges are not sharp here: the
 * rules handle boundaries by themselves).  Setting a sharpness on level
 * l < top also gives the finer levels the child sharpness refinement would
 * have given them (OpenSubdiv's rules: uniform s-1 per level, or Chaikin's),
 * as if the levels above l had been refined after it. */
float st_hier_edge_sharpness(const st_hier *h, uint32_t d, unsigned l);
float st_hier_vertex_sharpness(const st_hier *h, uint32_t v, unsigned l);
void st_hier_set_edge_sharpness(st_hier *h, uint32_t d, unsigned l, float s);
void st_hier_set_vertex_sharpness(st_hier *h, uint32_t v, unsigned l, float s);

/* Level l as a soup (real faces), for writers and tests; with the level's
 * UVs (face_uv, one texture coordinate per vertex and UV value) when it
 * has some. */
int st_hier_level_mesh(st_hier *h, unsigned l, st_mesh *out, st_error *err);

/* ---- face-varying UVs (core/fvar/fvar.h; hier_fvar.c) ---- */

/* The UVs of level l: st_uv_map_at(&u, d) is the texture coordinate of
 * the face corner of dart d (the real face on d's left, at d's vertex), for
 * every dart of a real face of level l (all below u.cap).  Walking a
 * level's faces as st_hier_level_mesh does (darts in st_dart_first/next
 * order, each unvisited real face along φ1) and reading the UV at each dart
 * gives the corners in the order of that mesh's face_idx.  u.uv NULL when
 * the hierarchy has no UVs at level l; st_hier_has_uv says which. */
st_uv_map st_hier_uv(const st_hier *h, unsigned l);
int st_hier_has_uv(const st_hier *h, unsigned l);

/* For code that copies an st_hier field by field (the editor's undo
 * snapshots): dst->fvar becomes a deep copy of src's UVs (NULL when none),
 * *bytes (may be NULL) grows by what it allocated; -1 when out of memory
 * (dst->fvar NULL then).  st_hier_uv_free releases dst's. */
int st_hier_uv_copy(st_hier *dst, const st_hier *src, size_t *bytes);
void st_hier_uv_free(st_hier *h);

#endif
