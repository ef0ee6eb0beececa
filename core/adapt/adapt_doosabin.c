/* Adaptive Doo-Sabin through the dual encoding (adapt.h, "Doo-Sabin";
 * scheme_doosabin.c; Kraemer 2008 §3.2.1 and §3.2.2).
 *
 * The map stores the dual M* of the surface: a face of M* is a surface
 * vertex (all its darts carry that vertex's id), a vertex of M* (β1 orbit)
 * is a surface face.  One Doo-Sabin step is one Catmull-Clark topological
 * step on M*, so adaptive Doo-Sabin is adaptive Catmull-Clark topology on M*
 * (the face and edge levels of adapt_levels.c, the one-level restriction
 * and can-simplify of adapt_split.c, the refinement-tree addresses of
 * adapt_details.c all read the same), with the dual vertex
 * handling of scheme_doosabin.c's ds_refine:
 *   - subdividing a face F* of M* (a surface vertex v of level i) splits
 *     its edges that are not split yet and cuts it into one quad per corner
 *     (st_split_face_poly); the ids the primal operators made for M*'s edge
 *     midpoints and centre mean nothing here and are released; each new
 *     quad (the Doo-Sabin vertex of corner (v, W), W the surface face at
 *     that corner) gets a fresh vertex id, placed by the Doo-Sabin mask over
 *     W at level i (the scheme's emit); the new dart a split edge puts into
 *     the unsplit face across carries that face's id;
 *   - simplifying F* saves the details of its quads' vertices (world space,
 *     keyed by refinement-tree address: F*'s path and the corner index,
 *     adapt_details.c's corner kind), removes the spokes and centre, gives
 *     every dart of F* at level i+1 its level-i id back, unsplits the edges
 *     whose other side is not subdivided, and releases the quad ids.
 * A Doo-Sabin vertex exists at one level only (its face is cut at the next
 * level), so its only detail is the one of its creation level: nothing is
 * ever parked (the frame cell of a level-L detail, the surface face W at
 * level L-1, only changes when a face around it is simplified, which the
 * restriction refuses while the level-L vertex exists).
 *
 * The one-level restriction is always applied (no_restriction is ignored,
 * as for √3): without it a surface face at a depth border would mix
 * vertices of several levels into the Doo-Sabin mask.
 *
 * Criteria: the region a Doo-Sabin cell (the face of M* of vertex v)
 * covers.  At level 0, v's dual cell on the base polygon mesh: v, the
 * midpoints of its edges and the centroids of its faces.  At level l >= 1
 * the cell was cut at the corner of its parent's vertex u in the surface
 * face W (level l-1): it covers W's corner quad at u (u, the midpoints of
 * W's two sides at u, W's centroid) and v itself.  So the children of a
 * cell tile its region, and the surface refined from v lies there (the
 * Doo-Sabin points of corner (v, W) are in W, near v).  Only level l-1
 * is read around u, which is complete while the cell exists (the
 * restriction brought every face around u to level l-1 before the parent
 * was cut, and can-simplify keeps them): reading level l instead, whose
 * neighbours may still be coarser, made the answer depend on earlier
 * updates (refine/simplify cycles).  The box test uses the bounding box of
 * the region; the flatness test the largest angle between the normals of
 * two consecutive faces around u at level l-1 (level 0: around v).
 *
 * Displayed mesh: the surface polygons are the vertex orbits of M* at the
 * top level (st_map_to_mesh extracts the dual).  Around a subdivided cell
 * next to a coarser one they are Doo-Sabin's border polygons: a surface
 * face with some corners at level i and others at i+1, and a triangle
 * (two new vertices of the finer cell and the coarser vertex) for each
 * edge of M* split on one side only.  Every M* edge is shared by exactly
 * two surface polygons, so the mesh is closed. */
#include "core/map/geometry.h"
#include "core/adapt/adapt.h"
#include "core/adapt/adapt_internal.h"
#include "core/map/refine_internal.h"

#include <math.h>
#include <string.h>

static const double origin[3] = { 0, 0, 0 };

/* The map must hold the dual encoding; the hole corners' cut
 * (scheme_doosabin.c) has no adaptive form yet. */
static int ds_check(const st_hier *h, st_error *err)
{
    if (!h->map.face_embedded)
        return st_fail(err, ST_ERR_INVALID, "adapt: a %s hierarchy must hold the dual encoding", h->scheme->name);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&h->map, 0, &it); d != ST_NIL; d = st_dart_next(&h->map, 0, &it))
        if (st_is_boundary(&h->map, d))
            return st_fail(err, ST_ERR_TOPOLOGY, "adapt: adaptive doo-sabin on open meshes is not supported yet; "
                           "use uniform levels or catmull-clark");
    return ST_OK;
}

/* ---- criteria ---------------------------------------------------------------- */

static void grow(double lo[3], double hi[3], const double p[3])
{
    for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], p[k]); hi[k] = fmax(hi[k], p[k]); }
}

/* The dart of the face of d (level l >= 1) inserted before l: the corner of
 * its parent cell it was cut at.  ST_NIL at level 0. */
static uint32_t parent_corner(const st_map *m, uint32_t d, unsigned l)
{
    if (l == 0) return ST_NIL;
    uint32_t x = d;
    do { if (m->darts.ins[x] < l) return x; x = st_phi1(m, x, l); } while (x != d);
    return ST_NIL;
}

static void centroid(const st_map *m, uint32_t x, unsigned l, double c[3])
{
    unsigned n = 0;
    c[0] = c[1] = c[2] = 0;
    uint32_t y = x;
    do {
        const double *p = st_dart_pos(m, y, l);
        for (int k = 0; k < 3; k++) c[k] += p[k];
        n++;
        y = st_beta1(m, y, l);
    } while (y != x);
    for (int k = 0; k < 3; k++) c[k] /= n;
}

static void grow_mid(double lo[3], double hi[3], const double a[3], const double b[3])
{
    double mid[3] = { (a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2 };
    grow(lo, hi, mid);
}

static void ds_cell_bbox(const st_map *m, uint32_t d, unsigned l, double lo[3], double hi[3])
{
    const double *v = st_dart_pos(m, d, l);
    for (int k = 0; k < 3; k++) lo[k] = hi[k] = v[k];
    double c[3];
    uint32_t pc = parent_corner(m, d, l);
    if (pc != ST_NIL) {
        /* The corner quad of the parent's surface face W at the parent
         * vertex u (level l-1): u, the midpoints of W's two sides at u, W's
         * centroid. */
        unsigned j = l - 1;
        const double *u = st_dart_pos(m, pc, j);
        grow(lo, hi, u);
        grow_mid(lo, hi, u, st_dart_pos(m, st_beta1(m, pc, j), j));
        grow_mid(lo, hi, u, st_dart_pos(m, st_beta1_inv(m, pc, j), j));
        centroid(m, pc, j, c);
        grow(lo, hi, c);
        return;
    }
    /* Level 0: the dual cell of the vertex. */
    uint32_t x = d;
    do {
        grow_mid(lo, hi, v, st_dart_pos(m, st_beta0(m, x, l), l));
        centroid(m, x, l, c);
        grow(lo, hi, c);
        x = st_phi1(m, x, l);
    } while (x != d);
}


static double angle(const double a[3], const double b[3])
{
    double dn = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    if (!(dn > 0)) return 0;
    double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / dn;
    return acos(fmax(-1.0, fmin(1.0, c)));
}

/* Largest angle between the normals of two consecutive surface faces
 * around the vertex of the face of d at level l (all of level >= l). */
static double ring_bend(const st_map *m, uint32_t d, unsigned l)
{
    double first[3], prev[3], cur[3], worst = 0;
    st_face_newell(m, d, l, first);
    memcpy(prev, first, sizeof prev);
    for (uint32_t x = st_phi1(m, d, l); x != d; x = st_phi1(m, x, l)) {
        st_face_newell(m, x, l, cur);
        worst = fmax(worst, angle(prev, cur));
        memcpy(prev, cur, sizeof prev);
    }
    return fmax(worst, angle(prev, first));
}

static unsigned ds_wanted(const st_map *m, uint32_t d, unsigned l, const st_adapt_params *p)
{
    double lo[3], hi[3];
    ds_cell_bbox(m, d, l, lo, hi);
    unsigned want = st_adapt_box_want(lo, hi, p);
    if (p->flatness > 0 && l < p->max_level) {
        /* Read around the parent vertex at level l-1 (level 0: the vertex
         * itself), whose neighbourhood is complete while the cell exists. */
        uint32_t pc = parent_corner(m, d, l);
        double bend = pc != ST_NIL ? ring_bend(m, pc, l - 1) : ring_bend(m, d, l);
        if (bend > p->flatness) want = p->max_level;
    }
    return want > p->max_level ? p->max_level : want;
}

/* ---- subdivision --------------------------------------------------------------- */

static int ds_subdivide(st_adapt *a, uint32_t d, unsigned i, int restricted, st_error *err)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    unsigned L = i + 1;
    if (st_adapt_split_toward(m, d, i)) return ST_OK;
    (void)restricted; /* always on for Doo-Sabin */
    int rc = st_adapt_restrict(a, d, i, err);
    if (rc) return rc;
    rc = st_adapt_ensure_level(h, L, err);
    if (rc) return rc;
    unsigned n = st_face_degree(m, d, i);
    if (n > 255) return st_fail(err, ST_ERR_RANGE, "adapt: doo-sabin cell of %u sides", n);
    uint32_t corner[256], garbage[257], created[256], ng = 0;
    uint32_t x = d;
    for (unsigned k = 0; k < n; k++) { corner[k] = x; x = st_phi1(m, x, i); }
    for (unsigned k = 0; k < n; k++) {
        x = corner[k];
        if (st_adapt_edge_split(m, x, i)) continue;
        uint32_t e = st_beta0(m, x, i);
        uint32_t half = st_split_edge(m, x, L, origin);
        garbage[ng++] = st_vert(m, half, L);
        /* The new dart on the other side lies in e's face (unsplit toward L):
         * it carries that surface vertex. */
        st_set_vert(m, st_beta0(m, x, L), L, st_vert(m, e, L));
    }
    st_split_face_poly(m, d, L, origin);
    garbage[ng++] = st_vert(m, st_phi1(m, st_phi1(m, d, L), L), L);
    for (unsigned k = 0; k < n; k++) {
        uint32_t v = st_vertex_new(m, L, origin);
        created[k] = v;
        x = corner[k];
        do { st_set_vert(m, x, L, v); x = st_phi1(m, x, L); } while (x != corner[k]);
    }
    for (uint32_t k = 0; k < ng; k++) st_vertex_delete(m, garbage[k]);
    st_adapt_place_ctx c = { a, L, created, n };
    st_hier_emit(h, L, &d, 1, st_adapt_place_sink, &c);
    a->touched++;
    return ST_OK;
}

/* ---- simplification (Algorithm 6) ------------------------------------------------ */

/* Unsplits the degree-2 vertex of x (inserted at level L) of M*: its two
 * darts carry face ids here, so they get a throw-away id first, which
 * st_unsplit_edge releases with them. */
static int unsplit(st_map *m, uint32_t x, unsigned L, st_error *err)
{
    uint32_t t = st_vertex_new(m, L, origin);
    st_set_vert(m, x, L, t);
    st_set_vert(m, st_beta1(m, x, L), L, t);
    return st_unsplit_edge(m, x, L, err);
}

static int ds_simplify(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    unsigned L = i + 1;
    unsigned n = st_face_degree(m, d, i);
    if (n > 256) return st_fail(err, ST_ERR_RANGE, "adapt: doo-sabin cell of %u sides", n);
    uint32_t corner[256], quad[256];
    uint32_t x = d;
    for (unsigned k = 0; k < n; k++) { corner[k] = x; x = st_phi1(m, x, i); }
    uint32_t old = st_vert(m, d, i);
    for (unsigned k = 0; k < n; k++) {
        quad[k] = st_vert(m, corner[k], L);
        st_adapt_save_corner_detail(a, L, corner[k], quad[k]);
    }
    /* The spokes, then the centre and the edge left (adapt_split.c's remove_inner). */
    int rc = st_adapt_remove_centre(m, st_phi1(m, st_phi1(m, corner[0], L), L), L, unsplit, err);
    if (rc) return rc;
    /* F* is one face again: its level-i surface vertex. */
    x = corner[0];
    do { st_set_vert(m, x, L, old); x = st_phi1(m, x, L); } while (x != corner[0]);
    /* Unsplit the edges whose other side is not subdivided toward L. */
    for (unsigned k = 0; k < n && !rc; k++) {
        uint32_t e = st_beta0(m, corner[k], i);
        if (st_adapt_face_of_level(m, e, i) && st_adapt_split_toward(m, e, i)) continue;
        rc = unsplit(m, st_beta0(m, e, L), L, err);
    }
    if (rc) return rc;
    double p[3];
    memcpy(p, st_pos(m, old, i), sizeof p);
    st_set_pos(m, old, L, p);
    for (unsigned k = 0; k < n; k++) st_vertex_delete(m, quad[k]);
    a->touched++;
    return ST_OK;
}

/* ---- the table ------------------------------------------------------------------- */

/* adapt_split.c's test on M*, with the restriction always on. */
static int ds_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted)
{
    (void)restricted;
    return st_adapt_split_can_simplify(a, d, i, 1);
}

/* The readings of Algorithm 1's maps (adapt_levels.c): M* is refined by
 * polygon splits. */
static int ds_subdivided(st_map *m, uint32_t d, unsigned i) { return st_adapt_split_toward(m, d, i); }
static int ds_face_of_level(st_map *m, uint32_t y, unsigned i) { return st_adapt_face_of_level(m, y, i); }
/* Cells are cut into quads around a centre: every quad holds a corner. */
static int ds_no_central_child(unsigned n) { (void)n; return 0; }

const st_adapt_ops st_adapt_ops_doosabin = {
    .family = "doo-sabin",
    .check = ds_check,
    .subdivide = ds_subdivide,
    .can_simplify = ds_can_simplify,
    .simplify = ds_simplify,
    .wanted = ds_wanted,
    .cell_bbox = ds_cell_bbox,
    .subdivided = ds_subdivided,
    .face_of_level = ds_face_of_level,
    .still_listed = NULL, /* as for the polygon split family: liveness is enough */
    .central_child = ds_no_central_child,
    .region_rings = 3, /* as the polygon split family: forced refinement spreads the same way on M* */
    .forced_children_only = 1,
};
