/* Internal to core/adapt: the operations table that tells the refinement
 * families apart, and the helpers their files share.  Not part of the
 * public API (adapt.h).
 *
 * The files of adaptive refinement, by concern:
 *   adapt.c           lifetime of an st_adapt; the family's table is chosen
 *                     there, once, and the public entry points go through it
 *   adapt_levels.c    subdivision levels of cells, read from the map (§3.2.6)
 *   adapt_details.c   details kept in world space across coarsening (§3.2.4)
 *   adapt_criteria.c  the level a polygon face wants (box, falloff, flatness)
 *   adapt_split.c     polygon split family: Algorithm 1 with the one-level
 *                     restriction (§3.2.2), Algorithm 6 for one face (§3.2.3)
 *   adapt_sqrt3.c     √3 family (§3.4.2, Algorithm 8)
 *   adapt_doosabin.c  Doo-Sabin family (§3.2.1: Catmull-Clark topology on M*)
 *   adapt_update.c    the updates: Algorithms 5 and 6 over the map, and the
 *                     incremental update when only the box moved (§3.2.5)
 *   adapt_grid.c      base faces by place, for the incremental update */
#ifndef ST_ADAPT_INTERNAL_H
#define ST_ADAPT_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/adapt/adapt.h"

/* ---- the operations of a refinement family ----------------------------------
 * What differs between the families: how a cell is subdivided and
 * simplified, how its criteria are read, and which map readings are O(1).
 * Everything else (the update passes, the details, the cell levels) is
 * shared and calls these.  The schemes map to families as:
 *   Catmull-Clark             polygon split, quads around a centre
 *   Loop, Butterfly           polygon split, triangle quadrisection
 *   quad/triangle             polygon split, triangles and quads mixed
 *   √3                        centre splits and flips (adapt_sqrt3.c)
 *   Doo-Sabin                 Catmull-Clark topology on the dual M*
 *                             (adapt_doosabin.c) */
typedef struct st_adapt_ops {
    const char *family;    /* for messages and tests: "polygon split", "sqrt3", "doo-sabin" */
    /* Refuses the hierarchies the family cannot adapt (NULL: none). */
    int (*check)(const st_hier *h, st_error *err);
    /* Algorithm 1 for the face (cell) of d, of level i, toward i+1, with
     * the level-(i+1) positions of its vertices.  restricted: the one-level
     * restriction (families that always apply it ignore the flag).  Called
     * after st_adapt_subdivide_face's checks (a real face, i+1 in range). */
    int (*subdivide)(st_adapt *a, uint32_t d, unsigned i, int restricted, st_error *err);
    /* The face of d (level i) is subdivided toward i+1 and may go back to
     * level i (§3.2.3, listing 3.2.3). */
    int (*can_simplify)(st_adapt *a, uint32_t d, unsigned i, int restricted);
    /* Algorithm 6 for the face of d (level i): back to level i, keeping the
     * details of the vertices it removes. */
    int (*simplify)(st_adapt *a, uint32_t d, unsigned i, st_error *err);
    /* The level the criteria p want for the cell of d at level l, as the
     * updates read it.  With p->flatness 0, the families with
     * forced_children_only read the cell's box only: the smaller of
     * st_adapt_box_want(cell_bbox) and max_level (the incremental update
     * computes it so, with the box it also tests: adapt_update.c). */
    unsigned (*wanted)(const st_map *m, uint32_t d, unsigned l, const st_adapt_params *p);
    /* The region the cell of d (level l) covers: its bounding box.  The
     * incremental update tests it against the boxes (settled cells, the
     * grid of base cells). */
    void (*cell_bbox)(const st_map *m, uint32_t d, unsigned l, double lo[3], double hi[3]);
    /* st_face_is_subdivided(m, d, i) for a face of level i of this
     * family's maps (O(1) where the map allows it). */
    int (*subdivided)(st_map *m, uint32_t d, unsigned i);
    /* st_face_level(m, y, i) == i on this family's maps. */
    int (*face_of_level)(st_map *m, uint32_t y, unsigned i);
    /* A live dart listed as a face of level i (one of its darts of level
     * <= i, as st_adapt_faces_of_level and the update's children list
     * them) still is a face of level i after other faces were refined or
     * faces of level >= i simplified.  NULL: always (liveness is enough). */
    int (*still_listed)(st_map *m, uint32_t d, unsigned i);
    /* A subdivided face of n sides has a sub-face that holds none of its
     * darts: the central triangle of a triangle quadrisection.  The polygon
     * split family chooses its split by it; the updates list that child. */
    int (*central_child)(unsigned n);
    /* Rings of base faces around those near the boxes that an incremental
     * update visits: how far forced refinement reaches (adapt_update.c). */
    unsigned region_rings;
    /* 1: after a pass, the restriction's forced subdivisions left the faces
     * already examined as they were, so the next pass starts from the
     * forced faces' children; 0: forced steps also change examined faces
     * (√3's flips), so the next pass goes over everything again. */
    int forced_children_only;
} st_adapt_ops;

/* The families' tables (adapt_split.c, adapt_sqrt3.c, adapt_doosabin.c). */
extern const st_adapt_ops st_adapt_ops_quads;      /* Catmull-Clark */
extern const st_adapt_ops st_adapt_ops_triangles;  /* Loop, Butterfly */
extern const st_adapt_ops st_adapt_ops_quadtri;    /* quad/triangle */
extern const st_adapt_ops st_adapt_ops_sqrt3;
extern const st_adapt_ops st_adapt_ops_doosabin;

/* The table of a's scheme: chosen by st_adapt_init; an st_adapt filled in
 * field by field (a session load) gets it on first use (adapt.c). */
const st_adapt_ops *st_adapt_choose_ops(st_adapt *a);
static inline const st_adapt_ops *st_adapt_ops_of(st_adapt *a)
{
    return a->ops ? a->ops : st_adapt_choose_ops(a);
}

/* ---- cell levels (adapt_levels.c) ----------------------------------------- */

/* The readings below are inline: the restriction and the update passes
 * call them for every dart around every face they look at. */

/* st_edge_is_split. */
static inline int st_adapt_edge_split(const st_map *m, uint32_t d, unsigned i)
{
    return m->darts.ins[st_beta0(m, d, i + 1)] == i + 1;
}

/* st_face_is_subdivided in O(1) for the maps Algorithm 1 builds (every
 * family but √3); d a dart of level <= i on a real face of map i.
 * Subdividing a face splits every side and then cuts the face, so the face
 * is subdivided toward i+1 exactly when, at i+1, the next dart after d was
 * inserted at i+1 (d's side is split, or d is followed by an inner edge)
 * and so is the one after it (an inner edge: a face whose sides are only
 * split by finer neighbours goes back to one of its older darts there). */
static inline int st_adapt_split_toward(const st_map *m, uint32_t d, unsigned i)
{
    const uint8_t *ins = m->darts.ins;
    uint32_t x = st_phi1(m, d, i + 1);
    return ins[x] == i + 1 && ins[st_phi1(m, x, i + 1)] == i + 1;
}

/* st_face_level(m, y, i) == i in O(face size) for the same maps: a face of
 * level i >= 1 is a sub-face of a face of map i-1 subdivided toward i, and
 * its darts older than i are darts of that parent (one corner, or none for
 * the central triangle of a triangle split); a face of lower level is a
 * face of map i-1 not subdivided toward i. */
static inline int st_adapt_face_of_level(const st_map *m, uint32_t y, unsigned i)
{
    if (i == 0) return 1;
    uint32_t z = y;
    do {
        if (m->darts.ins[z] < i) return st_adapt_split_toward(m, z, i - 1);
        z = st_phi1(m, z, i);
    } while (z != y);
    return 1;
}
/* One dart per real face of map l whose subdivision level is l. */
void st_adapt_faces_of_level(st_map *m, unsigned l, st_dart_list *out);

/* ---- canonical stencils (adapt_resynth.c) ------------------------------------ */

/* Polygon split family: each listed face of map l by its smallest dart, in
 * increasing order, so that a fine vertex takes the stencil of the same
 * face in a full and a local synthesis (bit for bit).  Other families: the
 * list as it is. */
void st_adapt_canonical_faces(const st_hier *h, unsigned l, st_dart_list *faces);
/* S(P_{L-1}) of the vertex of d (map L, on faces of level L only) with the
 * stencil a synthesis of level L gives it (the canonical face's); 0 when
 * not found (other families, a vertex of more than 64 faces). */
int st_adapt_canonical_pred(st_hier *h, unsigned L, uint32_t d, double pred[3]);
/* What an update of the polygon split family changed (a->canon during
 * the update): the faces it subdivided or simplified, and the level-L
 * position of each vertex before its first write at L (or that it was
 * created there). */
typedef struct st_adapt_canon_pos {
    uint32_t v, level, seq, created;
    double p[3];
} st_adapt_canon_pos;
typedef struct st_adapt_canon {
    st_dart_list faces;        /* (dart, level) pairs */
    st_adapt_canon_pos *pos;
    uint32_t npos, cappos;
    int restricted;            /* the update keeps the one-level restriction */
} st_adapt_canon;
/* With a->canon set: the face of d (level i) was subdivided toward i+1 or
 * simplified back to i. */
void st_adapt_canon_record(st_adapt *a, uint32_t d, unsigned i, int simplified);
/* With a->canon set: vertex v is about to be written at level L (created:
 * by the subdivision that made it). */
void st_adapt_canon_write(st_adapt *a, uint32_t v, unsigned L, int created);
void st_adapt_canon_free(st_adapt_canon *c);
/* The end of an update (polygon split family): re-places canonically what
 * the recorded faces may have left otherwise, so that every position is
 * the one st_adapt_synthesize from the base level gives (bit for bit,
 * given a hierarchy that was so before).  Returns the positions changed. */
uint64_t st_adapt_canon_update(st_adapt *a);

/* ---- details (adapt_details.c) -------------------------------------------- */

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

/* Move the details of a vertex v created at L, about to be removed, into
 * the saved store (world space, under its refinement-tree address): the
 * midpoint of the edge of `dart`, the centre of the face of `dart`, or
 * (Doo-Sabin) the vertex in the corner of `dart` of its parent cell; dart
 * is of level L-1. */
void st_adapt_save_edge_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v);
void st_adapt_save_centre_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v);
void st_adapt_save_corner_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v);

/* Parks the level-(l+1) detail of the vertex of d (level l) as a world-space
 * vector before its level-l vertex cell changes. */
void st_adapt_park_detail(st_adapt *a, uint32_t d, unsigned l);

/* ---- criteria (adapt_criteria.c) ------------------------------------------ */

/* The box part of the criteria (and base_level) for a bounding box. */
unsigned st_adapt_box_want(const double lo[3], const double hi[3], const st_adapt_params *p);
/* The bounding box of the corners of the face of d at level l. */
void st_adapt_face_bbox(const st_map *m, uint32_t d, unsigned l, double lo[3], double hi[3]);

/* ---- shared by the families' subdivisions and simplifications (adapt_split.c) */

/* Adds levels until top >= L. */
int st_adapt_ensure_level(st_hier *h, unsigned L, st_error *err);

/* The one-level restriction before the face of d (level i) is subdivided:
 * every face sharing a vertex with it is brought to level i. */
int st_adapt_restrict(st_adapt *a, uint32_t d, unsigned i, st_error *err);

/* The polygon split family's can-simplify test (Doo-Sabin's too, on M*). */
int st_adapt_split_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted);

/* Takes out the centre vertex of level L that a polygon or centre split
 * made (spoke: a dart leaving it): uncuts spokes until the centre has
 * degree 2, unsplits it with `unsplit` (NULL: st_unsplit_edge) and uncuts
 * the edge left (used by every family's simplification). */
typedef int (*st_unsplit_fn)(st_map *m, uint32_t x, unsigned L, st_error *err);
int st_adapt_remove_centre(st_map *m, uint32_t spoke, unsigned L, st_unsplit_fn unsplit, st_error *err);
/* After a face of level i was simplified: its corner c, when no face of
 * level L = i+1 is left around it, falls back to its level-i position (at L
 * and, through the propagating setter, above). */
void st_adapt_corner_fallback(st_adapt *a, uint32_t c, unsigned i);

/* ---- progressive hierarchies (adapt_progressive.c) ------------------------- */

/* st_adapt_update, st_adapt_synthesize's follow-up and st_adapt_free's part
 * for a progressive hierarchy (adapt.c dispatches on a->pm's scheme). */
int st_adapt_pm_update(st_adapt *a, const st_adapt_params *p, st_error *err);
int st_adapt_pm_refresh(st_adapt *a, st_error *err);
/* The selection of a->prev when there is none yet (a session loaded field
 * by field keeps only the criteria), leaving the saved fields alone. */
int st_adapt_pm_ensure(st_adapt *a, st_error *err);
void st_adapt_pm_free(st_adapt *a);
static inline int st_adapt_is_progressive(const st_adapt *a)
{
    return a->h && a->h->scheme && a->h->scheme->id == ST_SCHEME_PROGRESSIVE;
}

/* ---- base faces by place (adapt_grid.c) ----------------------------------- */

/* Build: NULL when out of memory; bbox gives a base face's box.  Near: the
 * indices (into base) of the faces whose box grown by their own size meets
 * [lo, hi], in increasing order. */
typedef struct st_adapt_grid st_adapt_grid;
st_adapt_grid *st_adapt_grid_build(const st_map *m, const st_dart_list *base,
                                   void (*bbox)(const st_map *, uint32_t, unsigned, double *, double *));
void st_adapt_grid_near(const st_adapt_grid *g, const double lo[3], const double hi[3], st_dart_list *out_index);
void st_adapt_grid_free(st_adapt_grid *g);
/* A base face's box (lo xyz, hi xyz), grown by its own largest extent,
 * meets [lo, hi]: the face is near the boxes of an incremental update. */
int st_adapt_box_near(const double box[6], const double lo[3], const double hi[3]);

#endif
