/* Doo-Sabin (1978) through the dual encoding (thesis §3.2.1, figs 3.19-3.20;
 * digest §4).
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
 * Boundaries: not supported yet — open meshes are refused with a message
 * (CGAL drops the faces along a boundary; a boundary rule is future work). */
#include "hier_internal.h"

#include <math.h>
#include <stdlib.h>

static int ds_prepare(st_hier *h, st_error *err)
{
    st_map *m = &h->map;
    st_dart_iter it;
    uint32_t holes = 0;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it))
        if (st_is_boundary(m, d)) holes++;
    if (holes)
        return st_fail(err, ST_ERR_TOPOLOGY, "doo-sabin: open meshes are not supported yet (%u boundary edges); "
                       "use catmull-clark or close the holes", holes);
    /* β1* = φ1 = β1∘β0, computed for every dart before any is written. */
    uint32_t *b1 = malloc((size_t)(m->darts.end ? m->darts.end : 1) * sizeof *b1);
    if (!b1) return st_fail(err, ST_ERR_MEMORY, "doo-sabin: out of memory");
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) b1[d] = st_phi1(m, d, 0);
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) st_set_beta1(m, d, 0, b1[d]);
    free(b1);
    m->face_embedded = 1;
    return ST_OK;
}

/* Catmull-Clark topology on M*, then one new surface vertex per face of the
 * new level; the vertices that the primal split created for M*'s edges and
 * faces mean nothing in the dual encoding and are released. */
static int ds_refine(st_hier *h, st_error *err)
{
    st_map *m = &h->map;
    int rc = st_refine_uniform(m, ST_SPLIT_POLY, err);
    if (rc) return rc;
    unsigned L = m->top;
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
static void emit_corner(const st_hier *h, unsigned L, uint32_t c, st_stencil_buf *buf, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
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

static void ds_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t nfaces, st_stencil_sink sink, void *ctx)
{
    st_map *m = &h->map;
    st_stencil_buf buf = { 0 };
    if (!faces) {
        /* Each face of level L holds exactly one dart of level L-1. */
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, L - 1, &it); d != ST_NIL; d = st_dart_next(m, L - 1, &it))
            emit_corner(h, L, d, &buf, sink, ctx);
    } else {
        for (uint32_t i = 0; i < nfaces; i++) {
            uint32_t x = faces[i];
            do { emit_corner(h, L, x, &buf, sink, ctx); x = st_phi1(m, x, L - 1); } while (x != faces[i]);
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
