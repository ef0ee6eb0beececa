/* Helpers of adapt.c shared with the √3 path (adapt_sqrt3.c).  Not part of
 * the public API (adapt.h). */
#ifndef ST_ADAPT_INTERNAL_H
#define ST_ADAPT_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/adapt/adapt.h"

/* Context of st_adapt_place_sink: the vertices a subdivision just created
 * get their saved details back (or zero); old vertices keep theirs or get
 * back the ones parked for level L. */
typedef struct st_adapt_place_ctx {
    st_adapt *a;
    unsigned L;
    const uint32_t *created;   /* vertices made by this subdivision */
    uint32_t ncreated;
} st_adapt_place_ctx;

/* Stencil sink of a freshly subdivided face (ctx: st_adapt_place_ctx). */
void st_adapt_place_sink(void *ctx, const st_stencil *s);

/* Moves the details of the centre v created at L in the face of `dart`
 * (level L-1) into the saved store (world space, refinement-tree address). */
void st_adapt_save_centre_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v);

/* Parks the level-(l+1) detail of the vertex of d (level l) as a world-space
 * vector before its level-l vertex cell changes. */
void st_adapt_park_detail(st_adapt *a, uint32_t d, unsigned l);

/* Adds levels until top >= L. */
int st_adapt_ensure_level(st_hier *h, unsigned L, st_error *err);
/* st_face_is_subdivided in O(1) for the maps Algorithm 1 builds (every
 * scheme but √3); d a dart of level <= i on a real face of map i. */
int st_adapt_split_toward(const st_map *m, uint32_t d, unsigned i);
/* st_face_level(m, y, i) == i in O(face size) for the same maps. */
int st_adapt_face_of_level(const st_map *m, uint32_t y, unsigned i);

/* Base faces by place (adapt_grid.c).  Build: NULL when out of memory;
 * bbox gives a base face's box.  Near: the indices (into base) of the faces
 * whose box grown by their own size meets [lo, hi], in increasing order. */
typedef struct st_adapt_grid st_adapt_grid;
st_adapt_grid *st_adapt_grid_build(const st_map *m, const st_dart_list *base,
                                   void (*bbox)(const st_map *, uint32_t, unsigned, double *, double *));
void st_adapt_grid_near(const st_adapt_grid *g, const double lo[3], const double hi[3], st_dart_list *out_index);
void st_adapt_grid_free(st_adapt_grid *g);
/* A base face's box (lo xyz, hi xyz), grown by its own largest extent,
 * meets [lo, hi]: the face is near the boxes of an incremental update. */
int st_adapt_box_near(const double box[6], const double lo[3], const double hi[3]);

/* √3 (adapt_sqrt3.c): the same entry points as the quadrisection code, for
 * closed triangle meshes; the one-level restriction is always applied. */
int st_adapt_sqrt3_check(const st_hier *h, st_error *err);
int st_adapt_sqrt3_subdivide(st_adapt *a, uint32_t d, unsigned i, st_error *err);
int st_adapt_sqrt3_can_simplify(st_adapt *a, uint32_t d, unsigned i);
int st_adapt_sqrt3_simplify(st_adapt *a, uint32_t d, unsigned i, st_error *err);
/* The level the criteria p want for the face of d (level i), as the
 * updates use it for √3: read on the two level-(i-1) triangles of its old
 * edge and capped by what those want (adapt_sqrt3.c). */
unsigned st_adapt_sqrt3_wanted(const st_map *m, uint32_t d, unsigned i, const st_adapt_params *p);

/* The box part of the criteria (and base_level) for a bounding box. */
unsigned st_adapt_box_want(const double lo[3], const double hi[3], const st_adapt_params *p);

/* Doo-Sabin (adapt_doosabin.c): the same entry points, on the dual
 * encoding; the one-level restriction is always applied. */
int st_adapt_ds_subdivide(st_adapt *a, uint32_t d, unsigned i, st_error *err);
int st_adapt_ds_simplify(st_adapt *a, uint32_t d, unsigned i, st_error *err);
/* The criteria p for the Doo-Sabin cell of d (a face of the dual map: a
 * surface vertex) at level l, and the region it covers (adapt_doosabin.c). */
unsigned st_adapt_ds_wanted(const st_map *m, uint32_t d, unsigned l, const st_adapt_params *p);
void st_adapt_ds_cell_bbox(const st_map *m, uint32_t d, unsigned l, double lo[3], double hi[3]);

/* The one-level restriction before the face of d (level i) is subdivided:
 * every face sharing a vertex with it is brought to level i (adapt.c). */
int st_adapt_restrict(st_adapt *a, uint32_t d, unsigned i, st_error *err);

/* Takes out the centre vertex of level L that a polygon or centre split
 * made (spoke: a dart leaving it): uncuts spokes until the centre has
 * degree 2, unsplits it with `unsplit` (NULL: st_unsplit_edge) and uncuts
 * the edge left (adapt.c; used by every scheme's simplification). */
typedef int (*st_unsplit_fn)(st_map *m, uint32_t x, unsigned L, st_error *err);
int st_adapt_remove_centre(st_map *m, uint32_t spoke, unsigned L, st_unsplit_fn unsplit, st_error *err);
/* After a face of level i was simplified: its corner c, when no face of
 * level L = i+1 is left around it, falls back to its level-i position (at L
 * and, through the propagating setter, above). */
void st_adapt_corner_fallback(st_adapt *a, uint32_t c, unsigned i);

/* Moves the details of the Doo-Sabin vertex v created at L in the corner
 * of `dart` (a dart of level L-1 of its parent cell) into the saved store
 * (world space, refinement-tree address: the parent's path and the corner
 * index). */
void st_adapt_save_corner_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v);

#endif
