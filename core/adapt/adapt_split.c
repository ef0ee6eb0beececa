/* The polygon split family: adaptive Catmull-Clark, Loop, Butterfly and
 * quad/triangle (Kraemer 2008 §3.2.2, Algorithm 1; §3.2.3, Algorithm 6 and
 * listing 3.2.3), and the steps every family shares: the one-level
 * restriction, the removal of a centre, the corners' fallback.
 *
 * Subdividing a face of level i toward L = i+1 splits each side not split
 * yet (by a finer neighbour) and cuts the face: around a centre into quads,
 * or (a triangle of Loop, Butterfly, quad/triangle) into four triangles.
 * Simplifying removes the inner edges and unsplits the sides whose other
 * face is not subdivided toward L.
 *
 * Invariants kept:
 *   - every level is a closed 2-map: a face next to a finer one simply has
 *     more sides (its split edges);
 *   - with the one-level restriction (on by default), faces sharing a vertex
 *     differ by at most one level: before a face of level i is subdivided,
 *     every face sharing a vertex with it is brought to level i, and a face
 *     is simplified only when no face around its vertices would then be
 *     more than one level finer.  So every stencil of a new vertex finds its
 *     complete regular neighbourhood, and positions equal those of a regular
 *     hierarchy.  With the restriction off the map stays valid; stencils are
 *     taken over whatever the neighbourhood is (positions then differ from
 *     the regular ones near depth borders). */
#include "core/adapt/adapt_internal.h"
#include "core/multires/layers.h"
#include "core/multires/hier_internal.h"
#include "core/map/refine_internal.h"
#include "core/schemes/crease_internal.h"

#include <string.h>

/* ---- Algorithm 1 ------------------------------------------------------------------ */

int st_adapt_ensure_level(st_hier *h, unsigned L, st_error *err)
{
    while (h->map.top < L)
        if (st_level_add(&h->map, err)) return err ? err->code : ST_ERR_RANGE;
    return ST_OK;
}

/* Edge and vertex sharpness of the children, as the uniform path does. */
static void decay_sharpness(st_hier *h, uint32_t d, unsigned L)
{
    if (!h->has_sharpness) return;
    float s = st_hier_edge_sharpness(h, d, L - 1);
    uint32_t e = st_beta0(&h->map, d, L - 1);
    if (s > 0) {
        st_subdiv_view v = st_hier_view(h);
        float cd = st_crease_child_edge_sharpness(&v, d, L - 1), ce = st_crease_child_edge_sharpness(&v, e, L - 1);
        st_hier_set_edge_sharpness(h, d, L, cd);
        st_hier_set_edge_sharpness(h, e, L, ce);
    }
    uint32_t v = st_vert(&h->map, d, L - 1);
    float vs = st_hier_vertex_sharpness(h, v, L - 1);
    if (vs > 0) st_hier_set_vertex_sharpness(h, v, L, st_crease_decay(vs));
}

/* The faces it brings to their level are recorded in a->forced_faces (dart,
 * level pairs), which the update's later passes start from. */
int st_adapt_restrict(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    st_map *m = &a->h->map;
    for (int again = 1; again;) {
        again = 0;
        uint32_t x = d;
        do {
            /* (around each corner x: the other faces; x's is d, of level i) */
            uint32_t y = st_beta1(m, x, i);
            for (; y != x; y = st_beta1(m, y, i)) {
                if (!st_is_boundary(m, y)) {
                    unsigned j = st_adapt_face_of_level(m, y, i) ? i : st_face_level(m, y, i);
                    if (j < i) {
                        /* Walk the coarser face from a dart that exists at its level. */
                        uint32_t z = y;
                        while (m->darts.ins[z] > j) z = st_phi1(m, z, i);
                        a->forced++;
                        int rc = st_adapt_subdivide_face(a, z, j, 1, err);
                        if (rc) return rc;
                        st_dart_list_push(&a->forced_faces, z);
                        st_dart_list_push(&a->forced_faces, j);
                        again = 1;
                        break;
                    }
                }
            }
            x = st_phi1(m, x, i);
        } while (x != d && !again);
    }
    return ST_OK;
}

/* Corner c of a face of level i, before that face is subdivided: another
 * face around c's vertex is subdivided toward i+1 already, so the vertex
 * has its level-(i+1) position (the vertex point its stencil gives: no
 * corner fallback while a face of level i+1 holds it). */
static int corner_placed(const st_map *m, uint32_t c, unsigned i)
{
    for (uint32_t y = st_beta1(m, c, i); y != c; y = st_beta1(m, y, i))
        if (!st_is_boundary(m, y) && st_adapt_split_toward(m, y, i)) return 1;
    return 0;
}

static int split_subdivide(st_adapt *a, uint32_t d, unsigned i, int restricted, st_error *err)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    unsigned L = i + 1;
    if (st_adapt_split_toward(m, d, i)) return ST_OK;
    if (restricted) {
        int rc = st_adapt_restrict(a, d, i, err);
        if (rc) return rc;
    }
    int rc = st_adapt_ensure_level(h, L, err);
    if (rc) return rc;
    unsigned n = st_face_degree(m, d, i);
    if (n > 255) return st_fail(err, ST_ERR_RANGE, "adapt: face of %u sides", n);
    uint32_t created[256], ncreated = 0;
    /* Vertices that stand at level L already are not placed again: the
     * corners another subdivided face holds, and the points of the sides
     * the face across split (a corner shared by four faces was placed four
     * times, a side's point twice: emission was about a third of an
     * interest-box move's instructions).  Their level-L positions are
     * vertex and edge points over the same level-i neighbourhood, which
     * the restriction keeps complete; no parked detail waits for them (a
     * face holding the vertex at level L forbids the simplification that
     * would park one).  With the update's canonical pass (st_adapt.exact)
     * positions end as before, bit for bit: it re-emits every vertex of
     * the faces the update subdivided (adapt_resynth.c, "after an
     * update").  Without it a shared vertex keeps the stencil of the face
     * that placed it first instead of the last one's: last bits apart from
     * a full synthesis either way.  Without the restriction every vertex
     * is placed. */
    uint32_t skip[2 * 256], nskip = 0, split_before[256], nsplit = 0;
    uint32_t x = d;
    if (restricted)
        do {
            if (corner_placed(m, x, i)) skip[nskip++] = st_vert(m, x, i);
            x = st_phi1(m, x, i);
        } while (x != d);
    double centre[3] = { 0, 0, 0 };
    x = d;
    do {
        const double *p = st_dart_pos(m, x, i);
        for (int k = 0; k < 3; k++) centre[k] += p[k] / n;
        uint32_t next = st_phi1(m, x, i);
        if (!st_adapt_edge_split(m, x, i)) {
            const double *q = st_dart_pos(m, st_beta0(m, x, i), i);
            double mid[3] = { (p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2 };
            created[ncreated++] = st_vert(m, st_split_edge(m, x, L, mid), L);
        } else if (restricted) {
            split_before[nsplit++] = x;
        }
        decay_sharpness(h, x, L);
        x = next;
    } while (x != d);
    if (st_adapt_ops_of(a)->central_child(n)) st_split_face_tri(m, d, L);
    else {
        st_split_face_poly(m, d, L, centre);
        created[ncreated++] = st_vert(m, st_phi1(m, st_phi1(m, d, L), L), L);
    }
    for (uint32_t k = 0; k < nsplit; k++) skip[nskip++] = st_vert(m, st_beta0(m, split_before[k], L), L);
    st_adapt_place_ctx c = { a, L, created, ncreated };
    st_hier_emit_except(h, L, &d, 1, skip, nskip, st_adapt_place_sink, &c);
    st_adapt_canon_record(a, d, i, 0);
    a->touched++;
    return ST_OK;
}

/* ---- Algorithm 6 ---------------------------------------------------------------- */

/* After the face f of d (level i) is subdivided, its outline at level
 * L = i+1 is made of each coarse dart c and of m(c) = β0(β0(c, i), L), the
 * half-edge from the midpoint to the next corner on f's side (whichever side
 * split the edge).  Every other dart of f's sub-faces is inner. */
static uint32_t half_after(const st_map *m, uint32_t c, unsigned i)
{
    return st_beta0(m, st_beta0(m, c, i), i + 1);
}

typedef struct outline { uint32_t *d; uint32_t n; } outline;

static int on_outline(const st_map *m, const outline *o, uint32_t x, unsigned i)
{
    for (uint32_t k = 0; k < o->n; k++)
        if (x == o->d[k] || x == half_after(m, o->d[k], i)) return 1;
    return 0;
}

/* Sub-faces at level L: one dart each (the corner sub-faces start at the
 * coarse darts; a triangle's central sub-face, when the family's split
 * makes one (central), is across a corner's inner edge).  Returns the
 * count. */
static uint32_t sub_faces(const st_map *m, const outline *o, unsigned i, int central, uint32_t *out)
{
    uint32_t n = 0;
    for (uint32_t k = 0; k < o->n; k++) out[n++] = o->d[k];
    if (!central) return n;
    uint32_t x = o->d[0];
    do {
        if (!on_outline(m, o, x, i)) {
            uint32_t e = st_beta0(m, x, i + 1);
            /* The central triangle is the one sub-face without a coarse dart. */
            uint32_t y = e;
            int has_corner = 0;
            do { if (m->darts.ins[y] <= i) has_corner = 1; y = st_phi1(m, y, i + 1); } while (y != e);
            if (!has_corner) out[n++] = e;
            break;
        }
        x = st_phi1(m, x, i + 1);
    } while (x != o->d[0]);
    return n;
}

static void get_outline(const st_map *m, uint32_t d, unsigned i, outline *o)
{
    o->n = 0;
    uint32_t x = d;
    do { o->d[o->n++] = x; x = st_phi1(m, x, i); } while (x != d);
}

/* The face's darts at level i in o (room for 256), in one walk; 0 when it
 * has more sides than that. */
static int get_outline_max(const st_map *m, uint32_t d, unsigned i, outline *o)
{
    o->n = 0;
    uint32_t x = d;
    do {
        if (o->n == 256) return 0;
        o->d[o->n++] = x;
        x = st_phi1(m, x, i);
    } while (x != d);
    return 1;
}

/* st_adapt_split_can_simplify, leaving the face's outline at level i in o
 * (room for 256 darts) for the tests that follow it (the sculpt kept):
 * one walk instead of three. */
static int can_simplify_outline(st_adapt *a, uint32_t d, unsigned i, int restricted, outline *o)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    if (!st_adapt_split_toward(m, d, i)) return 0;
    if (!get_outline_max(m, d, i, o)) return 0;
    /* (At the map's top level nothing is finer than L: no sub-face is
     * subdivided, and the ring test below would walk every ring of the
     * face's level-L vertices for nothing; the faces next to the finest
     * level are most of those an update simplifies.) */
    if (L >= m->top) return 1;
    uint32_t subs[256 + 1];
    uint32_t n = sub_faces(m, o, i, st_adapt_ops_of(a)->central_child(o->n), subs);
    for (uint32_t k = 0; k < n; k++)
        if (st_adapt_split_toward(m, subs[k], L)) return 0;
    if (!restricted) return 1;
    /* Once f is back at level i, no face sharing one of its vertices may be
     * finer than level i+1: its corners, and the midpoints of its sides
     * that stay split because the face across is subdivided.  (A face of
     * the top map finer than L holds such a vertex c, of level <= L, exactly
     * when one of the level-L faces around c is subdivided toward L+1: its
     * corner sub-face at c is the ancestor of the finer face.) */
    for (uint32_t k = 0; k < 2 * o->n; k++) {
        uint32_t c = k < o->n ? o->d[k] : half_after(m, o->d[k - o->n], i), y = c;
        do {
            if (!st_is_boundary(m, y) && st_adapt_split_toward(m, y, L)) return 0;
            y = st_beta1(m, y, L);
        } while (y != c);
    }
    return 1;
}

int st_adapt_split_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted)
{
    uint32_t buf[256];
    outline o = { buf, 0 };
    return can_simplify_outline(a, d, i, restricted, &o);
}

/* Sculpted detail is kept (st_adapt.keep_above, adapt.h "HD levels"): a
 * face of level i with i+1 > keep_above stays subdivided while a vertex of
 * its level-(i+1) subdivision - its corners, the points of its sides, its
 * centre - has a non-zero detail at any level from i+1 to the top.
 * Simplification would keep such details (adapt_details.c), but the
 * surface would no longer show them, and an HD sculpt is meant to stay
 * visible when the interest box moves on.  The corners make it
 * conservative: the faces around a sculpted vertex older than its level
 * stay refined too (one ring more than the detail's own support), which
 * the one-level restriction needs around the kept faces anyway.  Details
 * at levels <= keep_above (the uniform levels) never hold a face.  The
 * update's result then depends on the sculpting done, as it must, no
 * longer on the criteria alone. */
static int holds_detail(const st_adapt *a, uint32_t v, unsigned L)
{
    const st_hier *h = a->h;
    for (unsigned k = L; k <= h->map.top; k++) {
        const double *d = st_hier_detail(h, k, v);
        if (d[0] != 0 || d[1] != 0 || d[2] != 0) return 1;
        /* A layer's offsets (its B_l and P0 too) count as detail: at
         * strength 0 the detail may be zero where the layer is not. */
        if (a->keep_layers && st_layers_holds(a->keep_layers, k, v)) return 1;
    }
    return 0;
}

static int keeps_sculpt(const st_adapt *a, const outline *o, unsigned i, int tri)
{
    const st_map *m = &a->h->map;
    unsigned L = i + 1;
    if (!a->keep_above || L <= a->keep_above) return 0;
    for (uint32_t k = 0; k < o->n; k++)
        if (holds_detail(a, st_vert(m, o->d[k], L), L) || holds_detail(a, st_vert(m, half_after(m, o->d[k], i), L), L))
            return 1;
    return !tri && holds_detail(a, st_vert(m, st_phi1(m, st_phi1(m, o->d[0], L), L), L), L);
}

/* The polygon split family's test: the shared one (Doo-Sabin's too), then
 * the sculpt kept (the dual family does not take part in HD sculpting). */
static int split_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted)
{
    uint32_t buf[256];
    outline o = { buf, 0 };
    if (!can_simplify_outline(a, d, i, restricted, &o)) return 0;
    if (!a->keep_above) return 1;
    return !keeps_sculpt(a, &o, i, st_adapt_ops_of(a)->central_child(o.n));
}

/* Before the level-(i+1) structure of a face is taken apart: park the
 * level-(i+2) details of every vertex it has at level i+1 - corners, edge
 * points, centre - since their vertex cells of level i+1 change
 * (adapt_details.c). */
static void park_face_details(st_adapt *a, const outline *o, unsigned i, int tri)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    if (L + 1 >= ST_MAX_LEVELS || !a->h->detail[L + 1]) return;
    for (uint32_t k = 0; k < o->n; k++) {
        st_adapt_park_detail(a, o->d[k], L);
        st_adapt_park_detail(a, half_after(m, o->d[k], i), L);
    }
    if (!tri) st_adapt_park_detail(a, st_phi1(m, st_phi1(m, o->d[0], L), L), L);
}

/* Removes the inner edges of f's subdivision (the reverse of
 * st_split_face_tri / st_split_face_poly).  Triangle split: the corner
 * triangle of c_k is (c_k x ...), x = φ1(c_k) the inner dart; uncut the
 * three.  Polygon split: the corner quad of c_k is (c_k, mid->centre,
 * centre->mid', ...), so φ1²(c_k) leaves the centre; uncut spokes until the
 * centre has degree 2, unsplit it (saving its detail), uncut the edge left. */
static int remove_inner(st_adapt *a, const outline *o, unsigned i, int tri, st_error *err)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    int rc = ST_OK;
    if (tri) {
        uint32_t x[3];
        for (int k = 0; k < 3; k++) x[k] = st_phi1(m, o->d[k], L);
        for (int k = 0; k < 3 && !rc; k++) rc = st_uncut_face(m, x[k], L, err);
        return rc;
    }
    uint32_t spoke = st_phi1(m, st_phi1(m, o->d[0], L), L);
    st_adapt_save_centre_detail(a, L, o->d[0], st_vert(m, spoke, L));
    return st_adapt_remove_centre(m, spoke, L, NULL, err);
}

int st_adapt_remove_centre(st_map *m, uint32_t spoke, unsigned L, st_unsplit_fn unsplit, st_error *err)
{
    int rc = ST_OK;
    while (!rc && st_vertex_degree(m, spoke, L) > 2) {
        uint32_t next = st_beta1(m, spoke, L);
        rc = st_uncut_face(m, spoke, L, err);
        spoke = next;
    }
    if (rc) return rc;
    uint32_t left = st_beta0(m, st_beta1(m, spoke, L), L); /* mid-side dart of the merged edge */
    rc = unsplit ? unsplit(m, spoke, L, err) : st_unsplit_edge(m, spoke, L, err);
    if (!rc) rc = st_uncut_face(m, left, L, err);
    return rc;
}

/* The level-L position of c's vertex becomes its level-i one (and,
 * through the propagating setter, above L too). */
static void fall_back(st_map *m, uint32_t c, unsigned i)
{
    uint32_t v = st_vert(m, c, i);
    double p[3];
    memcpy(p, st_pos(m, v, i), sizeof p);
    st_set_pos(m, v, i + 1, p);
}

void st_adapt_corner_fallback(st_adapt *a, uint32_t c, unsigned i)
{
    st_map *m = &a->h->map;
    const st_adapt_ops *ops = st_adapt_ops_of(a);
    unsigned L = i + 1;
    uint32_t y = c;
    do {
        if (!st_is_boundary(m, y) && ops->face_of_level(m, y, L)) return;
        y = st_beta1(m, y, L);
    } while (y != c);
    fall_back(m, c, i);
}

/* The same for the polygon split family, corner c of the face just
 * simplified (of level i again): c's vertex, older than L, is on a face of
 * level L exactly when a face around it at level i is subdivided toward L
 * (the ancestor of that face: its corner sub-face at c).  Two relations a
 * face, where the generic test walks each level-L face to its parent. */
static void split_corner_fallback(st_adapt *a, uint32_t c, unsigned i)
{
    st_map *m = &a->h->map;
    if (!corner_placed(m, c, i) && !st_adapt_split_toward(m, c, i)) fall_back(m, c, i);
}

static int split_simplify(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    unsigned deg = st_face_degree(m, d, i);
    if (deg > 256) return st_fail(err, ST_ERR_RANGE, "adapt: face of %u sides", deg);
    uint32_t buf[256];
    outline o = { buf, 0 };
    get_outline(m, d, i, &o);
    int tri = st_adapt_ops_of(a)->central_child(deg);
    park_face_details(a, &o, i, tri);
    int rc = remove_inner(a, &o, i, tri, err);
    if (rc) return rc;
    /* Unsplit the edges whose other side is not subdivided toward L. */
    for (uint32_t k = 0; k < o.n; k++) {
        uint32_t c = o.d[k], e = st_beta0(m, c, i);
        if (!st_is_boundary(m, e) && st_adapt_face_of_level(m, e, i) && st_adapt_split_toward(m, e, i)) continue;
        uint32_t half = half_after(m, c, i);
        uint32_t v = st_vert(m, half, L);
        st_adapt_save_edge_detail(a, L, c, v);
        rc = st_unsplit_edge(m, half, L, err);
        if (rc) return rc;
    }
    /* Corners no longer on a face of level L fall back to their level-i
     * position (their level-L detail stays for a later refinement)... */
    for (uint32_t k = 0; k < o.n; k++) split_corner_fallback(a, o.d[k], i);
    st_adapt_canon_record(a, d, i, 1);
    a->touched++;
    return ST_OK;
}

/* ---- the tables -------------------------------------------------------------------- */

static int split_subdivided(st_map *m, uint32_t d, unsigned i) { return st_adapt_split_toward(m, d, i); }

static int split_face_of_level(st_map *m, uint32_t y, unsigned i) { return st_adapt_face_of_level(m, y, i); }

static int never(unsigned n) { (void)n; return 0; }
static int always(unsigned n) { (void)n; return 1; }
static int when_triangle(unsigned n) { return n == 3; }

/* Forced refinement spreads one face per level, and faces double in size
 * per level toward the base: its reach in base faces is a geometric sum,
 * under 2 rings; 3 leave a margin. */
enum { SPLIT_RINGS = 3 };

/* still_listed: in the maps of Algorithm 1 a listed dart is a corner
 * (level <= i) of its face, which refining other faces (new darts of other
 * faces, or of this face's sides at levels above i) and simplifying faces
 * of level >= i (only darts inserted above i go) leave a face of level i:
 * liveness is enough. */
#define SPLIT_OPS(central)                                                                     \
    {                                                                                          \
        .family = "polygon split", .check = NULL, .subdivide = split_subdivide,                \
        .can_simplify = split_can_simplify, .simplify = split_simplify,                        \
        .wanted = st_adapt_wanted_level, .cell_bbox = st_adapt_face_bbox,                      \
        .subdivided = split_subdivided, .face_of_level = split_face_of_level,                  \
        .still_listed = NULL, .central_child = central,                                        \
        .region_rings = SPLIT_RINGS, .forced_children_only = 1                                 \
    }

/* Catmull-Clark: every face into quads around its centre. */
const st_adapt_ops st_adapt_ops_quads = SPLIT_OPS(never);
/* Loop, Butterfly: triangles into four triangles. */
const st_adapt_ops st_adapt_ops_triangles = SPLIT_OPS(always);
/* Quad/triangle (Stam-Loop 2003): triangles into four, other faces into quads. */
const st_adapt_ops st_adapt_ops_quadtri = SPLIT_OPS(when_triangle);
