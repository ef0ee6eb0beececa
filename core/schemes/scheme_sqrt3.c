/* √3 subdivision (Kobbelt 2000; Kraemer 2008 §3.4.2, adaptive §3.2.2-3.2.6)
 * on triangle meshes.  Topology: refine_sqrt3.c (centre split, then every old interior
 * edge flipped; level L has 3x the faces of level L-1).
 *
 * Rules, as stencils over level L-1 (emit):
 *   centre   C  = (V0 + V1 + V2) / 3                 frame: the coarse face
 *   interior P' = (1 - K) P + (K/n) Σ Vi,             frame: the coarse vertex
 *            K  = (4 - 2 cos(2π/n)) / 9, n = valence
 *
 * Boundaries: Kobbelt's rule, as CGAL 5.5 (Subdivision_method_3::Sqrt3,
 * internal::Sqrt3_1step + Sqrt3_mask_3::border_node) and OpenMesh 9
 * (Subdivider::Uniform::Sqrt3T) both implement it.  The boundary is refined
 * every second step only, and Strata ties that to the level number:
 *   - odd levels (1, 3, ...): boundary vertices keep their position, every
 *     triangle (boundary ones too) gets its centre, boundary edges are not
 *     flipped;
 *   - even levels (2, 4, ...): each boundary edge s-t is trisected by
 *       (16 s + 10 t + s') / 27  and  (10 s + 16 t + t') / 27
 *     (s', t': the other boundary neighbours of s and t), each boundary
 *     vertex moves to (4 p + 19 v + 4 q) / 27 (p, q: its boundary
 *     neighbours), and a triangle with a boundary edge gets no centre: it is
 *     split as a fan from its third corner to the two new edge points;
 *     interior vertices and triangles use the closed rules.
 * Frame of a new boundary point: its coarse boundary edge.
 *
 * This is what a user of either library gets from ONE call that makes all
 * the levels (CGAL: Sqrt3_subdivision with number_of_iterations(N), the
 * boundary refined on iterations i % 2 == 1; OpenMesh: attach() then
 * operator()(N) or N times operator()(1), generation counter gen % 2 == 1),
 * so level L here matches their N = L output point for point.
 * Where the libraries differ from each other (not from Strata on meshes
 * built this way):
 *   - both restart the parity on every call (CGAL's loop index; OpenMesh's
 *     prepare() resets the generation, so sub(mesh, 1) called repeatedly
 *     never refines the boundary); Strata's levels always form one sequence;
 *   - a triangle with two boundary edges on a boundary step: CGAL trisects
 *     only the first one it meets and leaves one vertex unsmoothed; OpenMesh
 *     smooths every boundary vertex and creates the points of both edges but
 *     links only one (isolated vertices).  Such a triangle cannot occur on a
 *     boundary step here (after a centre step every triangle has at most one
 *     boundary edge), and refine_sqrt3.c refuses it rather than guess;
 *   - OpenMesh's weight table has 50 entries (valence >= 50 reads past it
 *     unless init_weights() is called); CGAL computes K for any valence, as
 *     Strata does.
 * Neither library has creases or a corner rule: √3 ignores OBJ crease and
 * corner tags and the --boundary option (boundary vertices of valence 2 are
 * not kept as corners).
 *
 * support_rings = 2.  On closed meshes 1 would do (stencils and frames of
 * level L reach one ring of coarse faces around a vertex).  Boundary steps
 * reach further along the boundary: the point (16 p + 10 p' + v) / 27 next
 * to p on the edge p-p' moves with v although it lies outside v's faces,
 * so the vertices changed at level L can sit two boundary edges outside the
 * region, and the next level's region (grown from the region's darts) needs
 * the second ring (found by moving every vertex of an open grid, one at a
 * time: tests/core/test_scheme_sqrt3.c).  emit() on a face also emits every
 * boundary point and boundary vertex whose stencil reaches one of its
 * corners.
 */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/crease_internal.h"
#include "core/schemes/synth_internal.h"
#include "core/map/refine_sqrt3_internal.h"

#include <math.h>
#include <stdlib.h>

static double sqrt3_k(unsigned n) { return (4.0 - 2.0 * cos(2.0 * M_PI / (double)n)) / 9.0; }

/* Old vertex of the dart d (level L-1). */
static void vertex_stencil(const st_map *m, unsigned L, uint32_t d, st_stencil_buf *b)
{
    unsigned l = L - 1;
    uint32_t v = st_vert(m, d, l), hole, real;
    st_stencil_buf_clear(b);
    if (st_sqrt3_vertex_boundary(m, d, l, &hole, &real)) {
        if (!st_sqrt3_boundary_step(L)) {
            st_stencil_buf_add(b, v, 1.0);
        } else {
            st_stencil_buf_add(b, v, 19.0 / 27);
            st_stencil_buf_add(b, st_vert(m, st_beta0(m, hole, l), l), 4.0 / 27);
            st_stencil_buf_add(b, st_vert(m, st_beta0(m, real, l), l), 4.0 / 27);
        }
        return;
    }
    unsigned n = st_vertex_degree(m, d, l);
    double k = sqrt3_k(n);
    st_stencil_buf_add(b, v, 1.0 - k);
    uint32_t x = d;
    do {
        st_stencil_buf_add(b, st_vert(m, st_beta0(m, x, l), l), k / n);
        x = st_beta1(m, x, l);
    } while (x != d);
}

/* New boundary point next to the start s of y, y either dart of a boundary
 * edge s-t of level L-1: (16 s + 10 t + s') / 27. */
static void edge_point_stencil(const st_map *m, unsigned l, uint32_t y, st_stencil_buf *b)
{
    uint32_t s = st_vert(m, y, l), t = st_vert(m, st_beta0(m, y, l), l), hole, real, other = s;
    if (st_sqrt3_vertex_boundary(m, y, l, &hole, &real))
        other = st_is_boundary(m, y) ? st_vert(m, st_beta0(m, real, l), l) : st_vert(m, st_beta0(m, hole, l), l);
    st_stencil_buf_clear(b);
    st_stencil_buf_add(b, s, 16.0 / 27);
    st_stencil_buf_add(b, t, 10.0 / 27);
    st_stencil_buf_add(b, other, 1.0 / 27);
}

typedef struct emitter {
    const st_subdiv_view *sv;
    unsigned L;
    st_stencil_sink sink;
    void *ctx;
    st_stencil_buf buf;
} emitter;

static void emit_vertex(emitter *e, uint32_t d)
{
    const st_map *m = e->sv->map;
    vertex_stencil(m, e->L, d, &e->buf);
    st_stencil s = { st_vert(m, d, e->L - 1), e->buf.n, e->buf.src, e->buf.w, d, ST_CELL_VERTEX };
    e->sink(e->ctx, &s);
}

static void emit_centre(emitter *e, uint32_t f)
{
    const st_map *m = e->sv->map;
    unsigned l = e->L - 1;
    uint32_t c = st_sqrt3_centre(m, f, e->L);
    if (c == ST_NIL) return;
    st_stencil_buf_clear(&e->buf);
    uint32_t x = f;
    do { st_stencil_buf_add(&e->buf, st_vert(m, x, l), 1.0 / 3); x = st_phi1(m, x, l); } while (x != f);
    st_stencil s = { c, e->buf.n, e->buf.src, e->buf.w, f, ST_CELL_FACE };
    e->sink(e->ctx, &s);
}

static void emit_edge_point(emitter *e, uint32_t y)
{
    const st_map *m = e->sv->map;
    edge_point_stencil(m, e->L - 1, y, &e->buf);
    st_stencil s = { st_sqrt3_edge_point(m, y, e->L), e->buf.n, e->buf.src, e->buf.w, y, ST_CELL_EDGE };
    e->sink(e->ctx, &s);
}

/* Every fine vertex once: old vertices by marker, centres by face marker,
 * boundary points from the hole darts (one per boundary edge). */
static void emit_all(emitter *e)
{
    st_map *m = e->sv->map;
    unsigned l = e->L - 1;
    int boundary_step = st_sqrt3_boundary_step(e->L);
    int fb = st_marker_reserve(m), vb = st_marker_reserve(m);
    if (fb < 0 || vb < 0) abort();
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (!st_marked(m, vb, d)) { st_mark_vertex(m, vb, d, l); emit_vertex(e, d); }
        if (st_is_boundary(m, d)) {
            if (boundary_step) { emit_edge_point(e, d); emit_edge_point(e, st_beta0(m, d, l)); }
        } else if (!st_marked(m, fb, d)) {
            st_mark_face(m, fb, d, l);
            emit_centre(e, d);
        }
    }
    st_marker_release(m, fb, l);
    st_marker_release(m, vb, l);
}

/* Boundary corner v (dart d) on a boundary step: every boundary point and
 * boundary vertex whose stencil uses v.  Along the hole p' -> p -> v -> q -> q':
 * the points next to v, p and q on the edges p-v and v-q, the points next
 * to p on p-p' and next to q on q-q', and the vertices p and q. */
static void emit_boundary_corner(emitter *e, uint32_t d)
{
    const st_map *m = e->sv->map;
    unsigned l = e->L - 1;
    uint32_t hole, real, hole_p, real_p;
    if (!st_sqrt3_vertex_boundary(m, d, l, &hole, &real)) return;
    uint32_t to_q = st_beta0(m, hole, l), from_p = st_beta0(m, real, l); /* q -> v, p -> v */
    emit_edge_point(e, hole);
    emit_edge_point(e, to_q);
    emit_edge_point(e, real);
    emit_edge_point(e, from_p);
    emit_edge_point(e, st_phi1(m, hole, l)); /* q -> q' */
    if (st_sqrt3_vertex_boundary(m, from_p, l, &hole_p, &real_p)) emit_edge_point(e, real_p); /* p -> p' */
    emit_vertex(e, to_q);
    emit_vertex(e, from_p);
}

static void emit_faces(emitter *e, const uint32_t *faces, uint32_t n)
{
    const st_map *m = e->sv->map;
    unsigned l = e->L - 1;
    int boundary_step = st_sqrt3_boundary_step(e->L);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = faces[i], x = f;
        emit_centre(e, f);
        do {
            emit_vertex(e, x);
            if (boundary_step) emit_boundary_corner(e, x);
            x = st_phi1(m, x, l);
        } while (x != f);
    }
}

static void sqrt3_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    emitter e = { sv, L, sink, ctx, { 0 } };
    if (faces) emit_faces(&e, faces, n);
    else emit_all(&e);
    st_stencil_buf_free(&e.buf);
}

static int sqrt3_check(const st_subdiv_view *sv, st_error *err)
{
    st_map *m = sv->map;
    int fb = st_marker_reserve(m);
    if (fb < 0) return st_fail(err, ST_ERR_MEMORY, "no marker bit left");
    int rc = ST_OK;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL && !rc; d = st_dart_next(m, 0, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, 0);
        unsigned deg = st_face_degree(m, d, 0);
        if (deg != 3)
            rc = st_fail(err, ST_ERR_TOPOLOGY, "the sqrt3 scheme needs a triangle mesh, but a face has %u sides "
                         "(triangulate the mesh, or use catmull-clark)", deg);
    }
    st_marker_release(m, fb, 0);
    return rc;
}

static int sqrt3_refine(const st_subdiv_view *sv, st_error *err) { return st_refine_sqrt3(sv->map, err); }

const st_scheme st_scheme_sqrt3 = {
    .name = "sqrt3",
    .id = ST_SCHEME_SQRT3,
    .interpolating = 0,
    .support_rings = 2,
    .check = sqrt3_check,
    .refine = sqrt3_refine,
    .emit = sqrt3_emit,
};
