/* Shared emission driver for the primal schemes (primal_emit.h). */
#include "core/schemes/primal_emit_internal.h"

#include <stdlib.h>

typedef struct emitter {
    const st_subdiv_view *sv;
    unsigned L;
    const st_primal_rules *r;
    st_stencil_buf buf, tmp;
    st_stencil_sink sink;
    void *ctx;
} emitter;

void st_add_face_centroid(const st_map *m, unsigned l, uint32_t d, double w, st_stencil_buf *out)
{
    unsigned n = st_face_degree(m, d, l);
    uint32_t x = d;
    do { st_stencil_buf_add(out, st_vert(m, x, l), w / n); x = st_phi1(m, x, l); } while (x != d);
}

static void emit(emitter *e, uint32_t fine, uint32_t dart, int cell)
{
    st_stencil s = { fine, e->buf.n, e->buf.src, e->buf.w, dart, (uint8_t)cell };
    e->sink(e->ctx, &s);
}

/* Face point: the centre vertex of the face of c, reached as φ1² of the
 * corner dart at level L (refine.c's polygon split). */
static void emit_face(emitter *e, uint32_t c)
{
    const st_map *m = e->sv->map;
    st_stencil_buf_clear(&e->buf);
    st_add_face_centroid(m, e->L - 1, c, 1.0, &e->buf);
    emit(e, st_vert(m, st_phi1(m, st_phi1(m, c, e->L), e->L), e->L), c, ST_CELL_FACE);
}

/* Edge point: the vertex splitting the edge of d is the vertex of β0(d, L). */
static void emit_edge(emitter *e, uint32_t d)
{
    const st_map *m = e->sv->map;
    if (e->r->creases) st_crease_edge_point(e->sv, e->L - 1, d, e->r->edge, &e->buf, &e->tmp);
    else { st_stencil_buf_clear(&e->buf); e->r->edge(e->sv, e->L - 1, d, &e->buf); }
    emit(e, st_vert(m, st_beta0(m, d, e->L), e->L), d, ST_CELL_EDGE);
}

static void emit_vertex(emitter *e, uint32_t d)
{
    uint32_t v = st_vert(e->sv->map, d, e->L - 1);
    st_stencil_buf_clear(&e->buf);
    if (!e->r->vertex) st_stencil_buf_add(&e->buf, v, 1.0);
    else if (e->r->creases) st_crease_vertex_point(e->sv, e->L - 1, d, e->r->vertex, &e->buf, &e->tmp);
    else e->r->vertex(e->sv, e->L - 1, d, &e->buf);
    emit(e, v, d, ST_CELL_VERTEX);
}

static int has_face_point(const emitter *e, uint32_t d)
{
    int fp = e->r->face_points;
    return fp == ST_FACE_POINTS_ALL || (fp == ST_FACE_POINTS_NON_TRIANGLES && st_face_degree(e->sv->map, d, e->L - 1) != 3);
}

/* Every fine vertex once: vertices and faces by marker, edges by d < β0(d). */
static void emit_all(emitter *e)
{
    st_map *m = e->sv->map;
    unsigned l = e->L - 1;
    int fb = st_marker_reserve(m), vb = st_marker_reserve(m);
    if (fb < 0 || vb < 0) abort(); /* programmer error: markers leaked */
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (!st_marked(m, vb, d)) { st_mark_vertex(m, vb, d, l); emit_vertex(e, d); }
        if (d < st_beta0(m, d, l)) emit_edge(e, d);
        if (e->r->face_points && !st_is_boundary(m, d) && !st_marked(m, fb, d)) {
            st_mark_face(m, fb, d, l);
            if (has_face_point(e, d)) emit_face(e, d);
        }
    }
    st_marker_release(m, fb, l);
    st_marker_release(m, vb, l);
}

/* v is one of the view's vertices to leave out (view.h: a short list, from
 * one face's subdivision). */
static int skipped(const st_subdiv_view *sv, uint32_t v)
{
    for (uint32_t k = 0; k < sv->emit_nskip; k++)
        if (sv->emit_skip[k] == v) return 1;
    return 0;
}

/* The fine vertices of the given coarse faces: face point, edge points,
 * corners (a vertex may come several times; the caller dedupes), less the
 * view's vertices to leave out. */
static void emit_faces(emitter *e, const uint32_t *faces, uint32_t n)
{
    const st_subdiv_view *sv = e->sv;
    const st_map *m = sv->map;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t c = faces[i], x = c;
        if (has_face_point(e, c)) emit_face(e, c);
        do {
            if (!sv->emit_nskip || !skipped(sv, st_vert(m, st_beta0(m, x, e->L), e->L))) emit_edge(e, x);
            if (!sv->emit_nskip || !skipped(sv, st_vert(m, x, e->L - 1))) emit_vertex(e, x);
            x = st_phi1(m, x, e->L - 1);
        } while (x != c);
    }
}

void st_primal_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx,
                    const st_primal_rules *r)
{
    emitter e = { .sv = sv, .L = L, .r = r, .sink = sink, .ctx = ctx };
    if (faces) emit_faces(&e, faces, n);
    else emit_all(&e);
    st_stencil_buf_free(&e.buf);
    st_stencil_buf_free(&e.tmp);
}

int st_check_triangles(const st_subdiv_view *sv, const char *scheme, st_error *err)
{
    const st_map *m = sv->map;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
        if (st_is_boundary(m, d)) continue;
        unsigned n = st_face_degree(m, d, 0);
        if (n != 3)
            return st_fail(err, ST_ERR_TOPOLOGY, "the %s scheme needs a triangle mesh, but the mesh has a face with %u sides",
                           scheme, n);
    }
    return ST_OK;
}
