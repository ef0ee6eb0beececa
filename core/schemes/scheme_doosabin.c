/* Doo-Sabin (1978) through the dual encoding (Kraemer 2008 §3.2.1,
 * figs 3.19-3.20).
 *
 * The map stores the *dual* of the surface: reading a half-edge map K as a
 * primal map with β1* = φ1_K gives a map M* whose vertices are K's faces and
 * whose faces are K's vertices, on the same darts.  The vertex embedding then
 * becomes a face embedding (st_map.face_embedded): vert(d) names the surface
 * vertex of d's face in M*.  One Doo-Sabin step on the surface is one
 * Catmull-Clark *topological* step on M* (its vertex, edge and face points
 * are Doo-Sabin's vertex-, edge- and face-faces), so the levels nest as in
 * any primal scheme and β1 never changes.
 *
 * Positions use the Doo-Sabin mask: the new vertex for corner g of a face W
 * of N vertices (g, w1, ..., w_{N-1} in order) is
 *     α0 g + Σ αj wj,  α0 = 1/4 + 5/(4N),  αj = (3 + 2 cos(2πj/N)) / (4N).
 * In M*, that new vertex is the face of level L containing the old dart c
 * that runs along W (a vertex orbit of M*) from g: its stencil is W's
 * β1 orbit starting at c.  These are Doo and Sabin's original weights, the
 * ones CGAL uses (9/16, 3/16, 1/16, 3/16 on quads).
 *
 * Boundaries (Strata's rule; CGAL instead drops the faces along a
 * boundary).  A hole of the surface is a vertex H of M* whose darts carry
 * ST_DART_BOUNDARY (the validator and the renderer read that flag on the
 * embedded cells of the dual encoding).  After the Catmull-Clark step on M*
 * (with the flags off, so that refine.c splits every face as on a closed
 * map), each face of level L at a corner (H, v) of the hole, the quad
 * (n, D, in, out) with D the old hole dart, is cut from H to the centre:
 * the surface vertex it stood for becomes two boundary vertices joined by a
 * boundary edge, and the hole gets twice as many sides.  Only darts new at
 * L are added (the dart sets stay nested); the old hole darts' β1 changes at
 * L.  The surface then has an edge face (quad) along every boundary edge
 * and a vertex face at every boundary vertex, as inside, and the two new
 * boundary vertices of corner v are Chaikin's points
 *     3/4 v + 1/4 w   (w: the other end of the boundary edge),
 * so the boundary converges to the quadratic B-spline of the boundary
 * polygon (the 1-D Doo-Sabin), while interior masks are unchanged. */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/crease_internal.h"
#include "core/schemes/synth_internal.h"

#include <math.h>
#include <stdlib.h>

static int ds_prepare(const st_subdiv_view *sv, st_error *err)
{
    st_map *m = sv->map;
    st_dart_iter it;
    /* A hole face of the primal map becomes a vertex H of M*: its darts keep
     * their flag.  β1* = φ1 = β1∘β0, computed for every dart before any is
     * written. */
    uint32_t *b1 = malloc((size_t)(m->darts.end ? m->darts.end : 1) * sizeof *b1);
    if (!b1) return st_fail(err, ST_ERR_MEMORY, "doo-sabin: out of memory");
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) b1[d] = st_phi1(m, d, 0);
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) st_set_beta1(m, d, 0, b1[d]);
    free(b1);
    m->face_embedded = 1;
    return ST_OK;
}

/* Old hole darts of level l, their flags cleared (refine.c reads the flag
 * as a primal hole, which M*'s are not). */
static void holes_off(st_map *m, unsigned l, st_dart_list *holes)
{
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it))
        if (st_is_boundary(m, d)) {
            st_dart_list_push(holes, d);
            m->flags[d] &= (uint8_t)~ST_DART_BOUNDARY;
        }
}

/* The face of level L at hole dart D, (n, D, in, out), cut from H to the
 * centre into (y, D, in) and (x, out, n); x joins the hole. */
static void cut_hole_corner(st_map *m, uint32_t D, unsigned L)
{
    uint32_t out = st_phi1(m, st_phi1(m, D, L), L);
    uint32_t x = st_cut_face(m, D, out, L), y = st_beta0(m, x, L);
    m->flags[x] |= ST_DART_BOUNDARY;
    m->flags[y] &= (uint8_t)~ST_DART_BOUNDARY;
}

/* Catmull-Clark topology on M*, the hole corners cut, then one new surface
 * vertex per face of the new level; the vertices that the primal split
 * created for M*'s edges and faces mean nothing in the dual encoding and are
 * released. */
static int ds_refine(const st_subdiv_view *sv, st_error *err)
{
    st_map *m = sv->map;
    st_dart_list holes = { 0 };
    holes_off(m, m->top, &holes);
    int rc = st_refine_uniform(m, ST_SPLIT_POLY, err);
    for (uint32_t i = 0; i < holes.n; i++) m->flags[holes.d[i]] |= ST_DART_BOUNDARY;
    if (rc) { st_dart_list_free(&holes); return rc; }
    unsigned L = m->top;
    for (uint32_t i = 0; i < holes.n; i++) cut_hole_corner(m, holes.d[i], L);
    st_dart_list_free(&holes);
    st_dart_list garbage = { 0 };
    for (uint32_t b = 0; b < m->verts.nblocks[L]; b++) {
        uint32_t first = m->verts.blocks[L][b] << ST_POOL_BLOCK_SHIFT;
        for (uint32_t v = first; v < first + ST_POOL_BLOCK; v++)
            if (m->verts.ins[v] == L) st_dart_list_push(&garbage, v);
    }
    int fb = st_marker_reserve(m);
    st_dart_iter it;
    static const double origin[3] = { 0, 0, 0 };
    for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
        if (st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, L);
        uint32_t v = st_vertex_new(m, L, origin), x = d;
        do { st_set_vert(m, x, L, v); x = st_phi1(m, x, L); } while (x != d);
    }
    st_marker_release(m, fb, L);
    for (uint32_t i = 0; i < garbage.n; i++) st_vertex_delete(m, garbage.d[i]);
    st_dart_list_free(&garbage);
    return ST_OK;
}

/* Stencil of the level-L vertex on the face that contains the old dart c. */
static void emit_corner(const st_subdiv_view *sv, unsigned L, uint32_t c, st_stencil_buf *buf, st_stencil_sink sink, void *ctx)
{
    const st_map *m = sv->map;
    unsigned l = L - 1, n = st_vertex_degree(m, c, l), j = 0;
    st_stencil_buf_clear(buf);
    uint32_t x = c;
    do {
        double w = j == 0 ? 0.25 + 5.0 / (4.0 * n) : (3.0 + 2.0 * cos(2.0 * M_PI * j / n)) / (4.0 * n);
        st_stencil_buf_add(buf, st_vert(m, x, l), w);
        j++;
        x = st_beta1(m, x, l);
    } while (x != c);
    st_stencil s = { st_vert(m, c, L), buf->n, buf->src, buf->w, c, ST_CELL_DUAL_FACE };
    sink(ctx, &s);
}

/* The two boundary vertices of level L at hole dart D (ds_refine): on D's
 * face, Chaikin's point toward the other end of D's boundary edge; on the
 * face across the cut, toward the other end of the boundary edge before it
 * around the hole (e, β1(e) = D at level l).  Frames: those of the real
 * faces along the two boundary edges. */
static void emit_hole_corner(const st_subdiv_view *sv, unsigned L, uint32_t D, st_stencil_buf *buf, st_stencil_sink sink, void *ctx)
{
    const st_map *m = sv->map;
    unsigned l = L - 1;
    uint32_t v = st_vert(m, D, l), e = st_beta1_inv(m, D, l);
    uint32_t x = st_beta0(m, st_phi_1(m, D, L), L); /* the cut's dart at H: before D around the hole at L */
    uint32_t across[2] = { st_beta0(m, D, l), st_beta0(m, e, l) };
    uint32_t fine[2] = { st_vert(m, D, L), st_vert(m, x, L) };
    for (int k = 0; k < 2; k++) {
        st_stencil_buf_clear(buf);
        st_stencil_buf_add(buf, v, 0.75);
        st_stencil_buf_add(buf, st_vert(m, k ? e : across[0], l), 0.25);
        st_stencil s = { fine[k], buf->n, buf->src, buf->w, across[k], ST_CELL_DUAL_FACE };
        sink(ctx, &s);
    }
}

static void emit_dart(const st_subdiv_view *sv, unsigned L, uint32_t c, st_stencil_buf *buf, st_stencil_sink sink, void *ctx)
{
    if (st_is_boundary(sv->map, c)) emit_hole_corner(sv, L, c, buf, sink, ctx);
    else emit_corner(sv, L, c, buf, sink, ctx);
}

static void ds_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t nfaces, st_stencil_sink sink, void *ctx)
{
    st_map *m = sv->map;
    st_stencil_buf buf = { 0 };
    if (!faces) {
        /* Each face of level L holds exactly one dart of level L-1, but for
         * the cut hole corners (two faces per old hole dart). */
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, L - 1, &it); d != ST_NIL; d = st_dart_next(m, L - 1, &it))
            emit_dart(sv, L, d, &buf, sink, ctx);
    } else {
        for (uint32_t i = 0; i < nfaces; i++) {
            uint32_t x = faces[i];
            do { emit_dart(sv, L, x, &buf, sink, ctx); x = st_phi1(m, x, L - 1); } while (x != faces[i]);
        }
    }
    st_stencil_buf_free(&buf);
}

const st_scheme st_scheme_doosabin = {
    .name = "doo-sabin",
    .id = ST_SCHEME_DOOSABIN,
    .interpolating = 0,
    .support_rings = 2,
    .check = ds_prepare,
    .refine = ds_refine,
    .emit = ds_emit,
};
