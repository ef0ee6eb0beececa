/* Catmull-Clark (1978) on any polygon mesh, with OpenSubdiv's boundary and
 * crease rules (crease.h).  Masks (Kraemer 2008 §3.2.1, fig. 3.14):
 *   face point   = average of the face's vertices;
 *   edge point   = (v0 + v1 + f0 + f1) / 4, f = adjacent face points;
 *   vertex point = ((n-2) v + Σe/n + Σf/n) / n  (= (Q + 2R + (n-3)S)/n).
 * Topology: polygon quadrisection (refine.c). */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/catmark_internal.h"
#include "core/schemes/crease_internal.h"

#include <stdlib.h>
#include <string.h>

/* st_stencil_buf_add without a call while the buffer has room: local
 * re-synthesis builds a stencil per fine vertex. */
static void buf_add(st_stencil_buf *b, uint32_t v, double w)
{
    if (b->n < b->cap) {
        b->src[b->n] = v;
        b->w[b->n++] = w;
    } else {
        st_stencil_buf_add(b, v, w);
    }
}

/* Adds w · (face centroid of d's face) as vertex weights (one walk for
 * faces up to 16 corners).  v: level view of the coarse level. */
static void add_face_centroid(const st_level_view *v, uint32_t d, double w, st_stencil_buf *out)
{
    uint32_t c[16], x = d;
    unsigned n = 0;
    do {
        if (n < 16) c[n] = st_v_vert(v, x);
        n++;
        x = st_v_phi1(v, x);
    } while (x != d);
    double wn = w / n;
    if (n <= 16) {
        for (unsigned i = 0; i < n; i++) buf_add(out, c[i], wn);
        return;
    }
    do { buf_add(out, st_v_vert(v, x), wn); x = st_v_phi1(v, x); } while (x != d);
}

/* Adds w/k for the corners of the face of d (degree k) that follow vert(d)
 * and vert(φ1 d), i.e. all but the face's first two; returns k.  The masks
 * below merge the corners they share, so that a stencil has one entry per
 * source vertex: half as many to build and to evaluate. */
static unsigned add_face_rest(const st_level_view *v, uint32_t d, double w, st_stencil_buf *out)
{
    uint32_t c[16], x = st_v_phi1(v, st_v_phi1(v, d));
    unsigned n = 2;
    for (; x != d; x = st_v_phi1(v, x)) {
        if (n - 2 < 16) c[n - 2] = st_v_vert(v, x);
        n++;
    }
    double wn = w / n;
    if (n - 2 <= 16) {
        for (unsigned i = 0; i + 2 < n; i++) buf_add(out, c[i], wn);
        return n;
    }
    for (x = st_v_phi1(v, st_v_phi1(v, d)); x != d; x = st_v_phi1(v, x)) buf_add(out, st_v_vert(v, x), wn);
    return n;
}

static unsigned face_degree(const st_level_view *v, uint32_t d)
{
    unsigned n = 0;
    uint32_t x = d;
    do { n++; x = st_v_phi1(v, x); } while (x != d);
    return n;
}

/* Catmull-Clark's weight of a triangle's face point in an edge point under
 * Sdc::Options::TRI_SUB_SMOOTH (Sdc::Scheme<SCHEME_CATMARK>::
 * assignSmoothMaskForEdge, after Hbr). */
#define TRI_SMOOTH_FACE_WEIGHT 0.470

int st_catmark_tri_edge(const st_subdiv_view *sv, uint32_t d, unsigned l)
{
    if (sv->opts.tri_sub != ST_TRI_SUB_SMOOTH) return 0;
    const st_map *m = sv->map;
    uint32_t e = st_beta0(m, d, l);
    if (st_is_boundary(m, d) || st_is_boundary(m, e)) return 0;
    st_level_view v;
    st_level_view_init(m, l, &v);
    return face_degree(&v, d) == 3 || face_degree(&v, e) == 3;
}

/* Edge point (v0 + v1 + f0 + f1) / 4: both ends lie on both faces.  With
 * smooth triangles an edge next to a triangle weighs both face points by
 * fw = (w0 + w1) / 2 (w = 0.47 for a triangle, 1/4 else) and its ends by
 * (1 - 2 fw) / 2. */
static void smooth_edge(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out)
{
    st_level_view v;
    st_level_view_init(sv->map, l, &v);
    uint32_t e = st_v_beta0(&v, d);
    double vw = 0.25, fw = 0.25;
    if (sv->opts.tri_sub == ST_TRI_SUB_SMOOTH) {
        unsigned nd = face_degree(&v, d), ne = face_degree(&v, e);
        if (nd == 3 || ne == 3) {
            double w0 = nd == 3 ? TRI_SMOOTH_FACE_WEIGHT : 0.25, w1 = ne == 3 ? TRI_SMOOTH_FACE_WEIGHT : 0.25;
            fw = 0.5 * (w0 + w1);
            vw = 0.5 * (1.0 - 2.0 * fw);
        }
    }
    uint32_t at = out->n;
    buf_add(out, st_v_vert(&v, d), vw);
    buf_add(out, st_v_vert(&v, e), vw);
    unsigned kd = add_face_rest(&v, d, fw, out), ke = add_face_rest(&v, e, fw, out);
    double shared = fw / kd + fw / ke;
    out->w[at] += shared;
    out->w[at + 1] += shared;
}

/* Vertex point ((n-2) v + Σ neighbours / n + Σ face centroids / n) / n.  The
 * face of ring dart x runs v, u(x), ..., u(x') with u(x) = vert(β0 x) and x'
 * the ring dart before x, so u(x) lies on the faces of x and of β1(x). */
static void smooth_vertex(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out)
{
    st_level_view v;
    st_level_view_init(sv->map, l, &v);
    unsigned n = 0;
    uint32_t x = d;
    do { n++; x = st_v_beta1(&v, x); } while (x != d);
    double inv = 1.0 / ((double)n * n), self = (double)(n - 2) / n;
    uint32_t at = out->n;
    buf_add(out, st_v_vert(&v, d), 0);
    /* Entry at + 1 + i: u of the i-th ring dart; the faces' other corners follow. */
    for (unsigned i = 0; i < n; i++, x = st_v_beta1(&v, x)) buf_add(out, st_v_vert(&v, st_v_beta0(&v, x)), inv);
    for (unsigned i = 0; i < n; i++, x = st_v_beta1(&v, x)) {
        /* The face of x: v, u(x), its middle corners, u(x') (x' = the dart before x). */
        uint32_t c[16], y = st_v_phi1(&v, st_v_phi1(&v, x));
        unsigned k = 2, mid = 0;
        for (; st_v_phi1(&v, y) != x; y = st_v_phi1(&v, y)) {
            if (mid < 16) c[mid] = st_v_vert(&v, y);
            mid++;
            k++;
        }
        k++; /* u(x') */
        double wf = inv / k;
        self += wf;
        out->w[at + 1 + i] += wf;
        out->w[at + 1 + (i + n - 1) % n] += wf;
        if (mid <= 16)
            for (unsigned j = 0; j < mid; j++) buf_add(out, c[j], wf);
        else
            for (y = st_v_phi1(&v, st_v_phi1(&v, x)); st_v_phi1(&v, y) != x; y = st_v_phi1(&v, y)) buf_add(out, st_v_vert(&v, y), wf);
    }
    out->w[at] = self;
}

typedef st_catmark_emitter emitter;

void st_catmark_emit_face(const st_subdiv_view *sv, unsigned L, uint32_t c, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = sv->map;
    uint32_t centre = st_vert(m, st_phi1(m, st_phi1(m, c, L), L), L);
    st_level_view v;
    st_level_view_init(m, L - 1, &v);
    st_stencil_buf_clear(&e->buf);
    add_face_centroid(&v, c, 1.0, &e->buf);
    st_stencil s = { centre, e->buf.n, e->buf.src, e->buf.w, c, ST_CELL_FACE };
    sink(ctx, &s);
}

/* Without sharpness, a cell off the boundary takes the smooth mask: the
 * crease rules (crease.c) would pick it after the same checks. */
static int plain_edge(const st_subdiv_view *sv, uint32_t d, unsigned l)
{
    const st_map *m = sv->map;
    return !sv->has_sharpness && !st_is_boundary(m, d) && !st_is_boundary(m, st_beta0(m, d, l));
}


static int plain_vertex(const st_subdiv_view *sv, uint32_t d, unsigned l)
{
    if (sv->has_sharpness) return 0;
    const st_map *m = sv->map;
    uint32_t x = d;
    do {
        if (st_is_boundary(m, x) || st_is_boundary(m, st_beta0(m, x, l))) return 0;
        x = st_beta1(m, x, l);
    } while (x != d);
    return 1;
}

void st_catmark_emit_edge(const st_subdiv_view *sv, unsigned L, uint32_t d, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = sv->map;
    uint32_t mid = st_vert(m, st_beta0(m, d, L), L);
    if (plain_edge(sv, d, L - 1)) {
        st_stencil_buf_clear(&e->buf);
        smooth_edge(sv, L - 1, d, &e->buf);
    } else {
        st_crease_edge_point(sv, L - 1, d, smooth_edge, &e->buf, &e->tmp);
    }
    st_stencil s = { mid, e->buf.n, e->buf.src, e->buf.w, d, ST_CELL_EDGE };
    sink(ctx, &s);
}

void st_catmark_emit_vertex(const st_subdiv_view *sv, unsigned L, uint32_t d, emitter *e, st_stencil_sink sink, void *ctx)
{
    if (plain_vertex(sv, d, L - 1)) {
        st_stencil_buf_clear(&e->buf);
        smooth_vertex(sv, L - 1, d, &e->buf);
    } else {
        st_crease_vertex_point(sv, L - 1, d, smooth_vertex, &e->buf, &e->tmp);
    }
    st_stencil s = { st_vert(sv->map, d, L - 1), e->buf.n, e->buf.src, e->buf.w, d, ST_CELL_VERTEX };
    sink(ctx, &s);
}

/* Every fine vertex once: faces and vertices by marker, edges by d < β0(d). */
static void emit_all(const st_subdiv_view *sv, unsigned L, emitter *e, st_stencil_sink sink, void *ctx)
{
    st_map *m = sv->map;
    unsigned l = L - 1;
    int fb = st_marker_reserve(m), vb = st_marker_reserve(m);
    if (fb < 0 || vb < 0) abort();
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (!st_marked(m, vb, d)) { st_mark_vertex(m, vb, d, l); st_catmark_emit_vertex(sv, L, d, e, sink, ctx); }
        if (d < st_beta0(m, d, l)) st_catmark_emit_edge(sv, L, d, e, sink, ctx);
        if (!st_is_boundary(m, d) && !st_marked(m, fb, d)) { st_mark_face(m, fb, d, l); st_catmark_emit_face(sv, L, d, e, sink, ctx); }
    }
    st_marker_release(m, fb, l);
    st_marker_release(m, vb, l);
}

/* A set of vertex ids (open addressing): a fine vertex lies on several of
 * the faces given to emit_faces, and its stencil costs far more than a
 * look-up, so each is built once per call. */
typedef struct id_set { uint32_t *slot, mask, n; uint32_t *local; } id_set;

/* The first table is `local`, ID_SET_LOCAL slots on the caller's stack:
 * an adaptive subdivision emits one face at a time, and a heap table of
 * 1024 slots, cleared and freed per face, cost 2 % of an interest-box
 * move's instructions.  Larger tables are on the heap. */
enum { ID_SET_LOCAL = 64 };

static void id_set_grow(id_set *s)
{
    uint32_t oldcap = s->slot ? s->mask + 1 : 0, *old = s->slot;
    uint32_t cap = old ? 2 * oldcap : ID_SET_LOCAL;
    s->slot = old ? malloc((size_t)cap * sizeof *s->slot) : s->local;
    if (!s->slot) abort(); /* out of memory for a local edit's scratch */
    memset(s->slot, 0xff, (size_t)cap * sizeof *s->slot);
    s->mask = cap - 1;
    s->n = 0;
    for (uint32_t i = 0; i < oldcap; i++)
        if (old[i] != ST_NIL) {
            uint32_t k = (old[i] * 2654435761u) & s->mask;
            while (s->slot[k] != ST_NIL) k = (k + 1) & s->mask;
            s->slot[k] = old[i];
            s->n++;
        }
    if (old != s->local) free(old);
}

/* Adds v; returns 0 if it was there already. */
static int id_set_add(id_set *s, uint32_t v)
{
    if (!s->slot || 2 * (s->n + 1) > s->mask + 1) id_set_grow(s);
    uint32_t k = (v * 2654435761u) & s->mask;
    for (; s->slot[k] != ST_NIL; k = (k + 1) & s->mask)
        if (s->slot[k] == v) return 0;
    s->slot[k] = v;
    s->n++;
    return 1;
}

/* Fine vertices of the given faces, each once: centre, edge points,
 * corners (in that order, from the first face that holds them), less
 * those the view says to leave out (they start in the set). */
static void emit_faces(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = sv->map;
    uint32_t local[ID_SET_LOCAL];
    id_set done = { 0, 0, 0, local };
    while (done.mask + 1 < 8 * (uint64_t)n + 2 * (uint64_t)sv->emit_nskip) id_set_grow(&done); /* ~3 fine vertices per quad, half full */
    for (uint32_t k = 0; k < sv->emit_nskip; k++) (void)id_set_add(&done, sv->emit_skip[k]);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t c = faces[i], x = c;
        if (id_set_add(&done, st_vert(m, st_phi1(m, st_phi1(m, c, L), L), L))) st_catmark_emit_face(sv, L, c, e, sink, ctx);
        do {
            if (id_set_add(&done, st_vert(m, st_beta0(m, x, L), L))) st_catmark_emit_edge(sv, L, x, e, sink, ctx);
            if (id_set_add(&done, st_vert(m, x, L - 1))) st_catmark_emit_vertex(sv, L, x, e, sink, ctx);
            x = st_phi1(m, x, L - 1);
        } while (x != c);
    }
    if (done.slot != local) free(done.slot);
}

void st_catmark_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    emitter e = { 0 };
    if (faces) emit_faces(sv, L, faces, n, &e, sink, ctx);
    else emit_all(sv, L, &e, sink, ctx);
    st_stencil_buf_free(&e.buf);
    st_stencil_buf_free(&e.tmp);
}

static int catmark_refine(const st_subdiv_view *sv, st_error *err) { return st_subdiv_refine_primal(sv, ST_SPLIT_POLY, err); }


const st_scheme st_scheme_catmark = {
    .name = "catmull-clark",
    .id = ST_SCHEME_CATMARK,
    .interpolating = 0,
    .support_rings = 1,
    .check = NULL,
    .refine = catmark_refine,
    .emit = st_catmark_emit,
    .predict_level = st_catmark_predict_level,
    .predict_around = st_catmark_predict_around,
};
