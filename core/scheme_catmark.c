/* Catmull-Clark (1978) on any polygon mesh, with OpenSubdiv's boundary and
 * crease rules (crease.h).  Masks (digest §4, thesis fig. 3.14):
 *   face point   = average of the face's vertices;
 *   edge point   = (v0 + v1 + f0 + f1) / 4, f = adjacent face points;
 *   vertex point = ((n-2) v + Σe/n + Σf/n) / n  (= (Q + 2R + (n-3)S)/n).
 * Topology: polygon quadrisection (refine.c). */
#include "crease.h"
#include "hier_internal.h"
#include "parallel.h"
#include "pool.h"
#include "synth_blocks.h"

#include <stdatomic.h>
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

/* Edge point (v0 + v1 + f0 + f1) / 4: both ends lie on both faces. */
static void smooth_edge(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    st_level_view v;
    st_level_view_init(&h->map, l, &v);
    uint32_t e = st_v_beta0(&v, d);
    uint32_t at = out->n;
    buf_add(out, st_v_vert(&v, d), 0.25);
    buf_add(out, st_v_vert(&v, e), 0.25);
    unsigned kd = add_face_rest(&v, d, 0.25, out), ke = add_face_rest(&v, e, 0.25, out);
    double shared = 0.25 / kd + 0.25 / ke;
    out->w[at] += shared;
    out->w[at + 1] += shared;
}

/* Vertex point ((n-2) v + Σ neighbours / n + Σ face centroids / n) / n.  The
 * face of ring dart x runs v, u(x), ..., u(x') with u(x) = vert(β0 x) and x'
 * the ring dart before x, so u(x) lies on the faces of x and of β1(x). */
static void smooth_vertex(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    st_level_view v;
    st_level_view_init(&h->map, l, &v);
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

typedef struct emitter {
    st_stencil_buf buf, tmp;
} emitter;

static void emit_face(const st_hier *h, unsigned L, uint32_t c, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
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
static int plain_edge(const st_hier *h, uint32_t d, unsigned l)
{
    const st_map *m = &h->map;
    return !h->has_sharpness && !st_is_boundary(m, d) && !st_is_boundary(m, st_beta0(m, d, l));
}

static int plain_vertex(const st_hier *h, uint32_t d, unsigned l)
{
    if (h->has_sharpness) return 0;
    const st_map *m = &h->map;
    uint32_t x = d;
    do {
        if (st_is_boundary(m, x) || st_is_boundary(m, st_beta0(m, x, l))) return 0;
        x = st_beta1(m, x, l);
    } while (x != d);
    return 1;
}

static void emit_edge(const st_hier *h, unsigned L, uint32_t d, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
    uint32_t mid = st_vert(m, st_beta0(m, d, L), L);
    if (plain_edge(h, d, L - 1)) {
        st_stencil_buf_clear(&e->buf);
        smooth_edge(h, L - 1, d, &e->buf);
    } else {
        st_crease_edge_point(h, L - 1, d, smooth_edge, &e->buf, &e->tmp);
    }
    st_stencil s = { mid, e->buf.n, e->buf.src, e->buf.w, d, ST_CELL_EDGE };
    sink(ctx, &s);
}

static void emit_vertex(const st_hier *h, unsigned L, uint32_t d, emitter *e, st_stencil_sink sink, void *ctx)
{
    if (plain_vertex(h, d, L - 1)) {
        st_stencil_buf_clear(&e->buf);
        smooth_vertex(h, L - 1, d, &e->buf);
    } else {
        st_crease_vertex_point(h, L - 1, d, smooth_vertex, &e->buf, &e->tmp);
    }
    st_stencil s = { st_vert(&h->map, d, L - 1), e->buf.n, e->buf.src, e->buf.w, d, ST_CELL_VERTEX };
    sink(ctx, &s);
}

/* Every fine vertex once: faces and vertices by marker, edges by d < β0(d). */
static void emit_all(st_hier *h, unsigned L, emitter *e, st_stencil_sink sink, void *ctx)
{
    st_map *m = &h->map;
    unsigned l = L - 1;
    int fb = st_marker_reserve(m), vb = st_marker_reserve(m);
    if (fb < 0 || vb < 0) abort();
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (!st_marked(m, vb, d)) { st_mark_vertex(m, vb, d, l); emit_vertex(h, L, d, e, sink, ctx); }
        if (d < st_beta0(m, d, l)) emit_edge(h, L, d, e, sink, ctx);
        if (!st_is_boundary(m, d) && !st_marked(m, fb, d)) { st_mark_face(m, fb, d, l); emit_face(h, L, d, e, sink, ctx); }
    }
    st_marker_release(m, fb, l);
    st_marker_release(m, vb, l);
}

/* A set of vertex ids (open addressing): a fine vertex lies on several of
 * the faces given to emit_faces, and its stencil costs far more than a
 * look-up, so each is built once per call. */
typedef struct id_set { uint32_t *slot, mask, n; } id_set;

static void id_set_grow(id_set *s)
{
    uint32_t cap = s->slot ? 2 * (s->mask + 1) : 1024, *old = s->slot, oldcap = s->slot ? s->mask + 1 : 0;
    s->slot = malloc((size_t)cap * sizeof *s->slot);
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
    free(old);
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
 * corners (in that order, from the first face that holds them). */
static void emit_faces(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, emitter *e, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &h->map;
    id_set done = { 0 };
    while (done.mask + 1 < 8 * (uint64_t)n) id_set_grow(&done); /* ~3 fine vertices per quad, half full */
    for (uint32_t i = 0; i < n; i++) {
        uint32_t c = faces[i], x = c;
        if (id_set_add(&done, st_vert(m, st_phi1(m, st_phi1(m, c, L), L), L))) emit_face(h, L, c, e, sink, ctx);
        do {
            if (id_set_add(&done, st_vert(m, st_beta0(m, x, L), L))) emit_edge(h, L, x, e, sink, ctx);
            if (id_set_add(&done, st_vert(m, x, L - 1))) emit_vertex(h, L, x, e, sink, ctx);
            x = st_phi1(m, x, L - 1);
        } while (x != c);
    }
    free(done.slot);
}

static void catmark_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    emitter e = { 0 };
    if (faces) emit_faces(h, L, faces, n, &e, sink, ctx);
    else emit_all(h, L, &e, sink, ctx);
    st_stencil_buf_free(&e.buf);
    st_stencil_buf_free(&e.tmp);
}

static int catmark_refine(st_hier *h, st_error *err) { return st_hier_refine_primal(h, ST_SPLIT_POLY, err); }


/* ---- fast full-level synthesis ------------------------------------------------
 * Same rules as the stencils above, organised like OpenSubdiv's
 * PrimvarRefiner (face points first, then edge and vertex points), on the
 * map's own arrays.  Cells touching a boundary or a sharp feature take the
 * stencil path.
 *
 * Level L is the polygon split of l = L-1 (refine.c): a coarse dart d finds
 * the centre of its face at L in base arrays, β0(β1(β0(d, L))) starting at
 * it, and the midpoint of its edge as the vertex of β0(d, L).
 *
 * The passes are bound by memory latency and branch prediction, not by
 * arithmetic, so they are shaped for both:
 *   - the face pass leaves, per coarse dart y, G[y] = P(vert(φ1 y)) + F(y)
 *     (F: the point of y's face); then
 *       edge point   (d, e):  (G[d] + G[e]) / 4     (= (v0 + v1 + f0 + f1) / 4)
 *       vertex point v:       (n-2)/n P(v) + Σ_{y around v} G[y] / n²
 *     and the later passes read only β1 and G;
 *   - faces are visited in the order refine.c numbered them (that of the
 *     faces they came from), so a face's neighbourhood is close in memory;
 *   - the common cells (quads, valence 4) run straight-line code, checked
 *     afterwards, and choices that vary from one dart to the next are
 *     selects or list compaction rather than branches.
 *
 * Faces need no marks: on a level l >= 1 built by the polygon split each
 * face is a corner quad (n(d_i), d_{i+1}, in_{i+1}, out_i) (refine.c) in
 * which n(d_i) is the one dart new at l whose twin is old; so the blocks of
 * level l name each face once.  Level 0 takes a sequential pass with a
 * visited bit per dart.  A level without that structure (a face without
 * exactly one old dart, faces that miss some dart of the level, fine darts
 * that are not new) is done again by the stencils.
 *
 * Three passes, each shared out over threads by blocks (parallel.h); each
 * writes disjoint slots and reads only what earlier passes wrote.  The sum
 * around a vertex starts at its smallest dart, so that its rounding never
 * depends on the threads: one thread and two give the same bits. */

typedef struct fast_level {
    st_hier *h;
    unsigned l, L;
    st_level_view c;                /* coarse level l */
    int plain;                      /* β1 and vert have no column at level l: read the base */
    const uint32_t *b0L;            /* β0 column of level L: darts of levels <= l */
    const uint32_t *b0, *b1, *vt;   /* base relations (new darts at L; plain coarse ones) */
    double *pnew, *pold;            /* level-L positions: base (new vertices), column (old vertices) */
    double *g;                      /* G, 3 per coarse dart of a real face */
    _Atomic uint32_t *vd;           /* per coarse vertex: a dart of it in a real face, ST_NIL if none */
    uint32_t *blocks, nblocks;      /* first ids of the dart blocks of levels l, l-1, ..., 0 ... */
    uint32_t nnew;                  /* ... of which the first nnew are level l's */
    uint32_t *vblocks, nvblocks;    /* first ids of the vertex blocks of levels l, ..., 0 */
    uint32_t dcover, vcover;        /* 1 + largest coarse dart / vertex id */
    uint64_t *dnew, *vnew;          /* block bits (synth_blocks.h) of the darts / vertices of level l,
                                       NULL where β0 / positions have no level-l column */
    atomic_int irregular;           /* the level is not the polygon split this code assumes */
    _Atomic uint64_t covered;       /* darts in the faces the face pass found ... */
    _Atomic uint64_t holes;         /* ... and darts of holes (edge pass): every dart of level l */
} fast_level;

/* Per thread: scratch for the stencil path. */
typedef struct fast_worker { fast_level *x; emitter e; } fast_worker;

/* Work is shared out in chunks of this many blocks (2048 darts). */
#define FAST_CHUNK 8u
/* Levels with fewer blocks than this per thread run on fewer threads. */
#define FAST_MIN_BLOCKS_PER_THREAD 32u
/* Faces and vertex rings up to this size are walked once (kept on the stack). */
#define FAST_MAX_RING 16u

/* ---- reads of the coarse level ---- */

/* base or col, by a select: whether an element reads its level's column
 * follows its insertion level, which varies without pattern. */
static const void *pick(const void *base, const void *col, int use_col)
{
    uintptr_t m = -(uintptr_t)(use_col != 0);
    return (const void *)(((uintptr_t)base & ~m) | ((uintptr_t)col & m));
}

static uint32_t c_beta0(const fast_level *x, uint32_t d)
{
    const st_u32_view *r = &x->c.beta0;
    int use_col = x->dnew ? !st_block_bit(x->dnew, d) : x->c.ins[d] < r->lvl;
    return ((const uint32_t *)pick(r->base, r->col, use_col))[d];
}
static uint32_t c_beta1(const fast_level *x, uint32_t d) { return x->plain ? x->b1[d] : st_v_beta1(&x->c, d); }
static uint32_t c_vert(const fast_level *x, uint32_t d) { return x->plain ? x->vt[d] : st_v_vert(&x->c, d); }
static uint32_t c_phi1(const fast_level *x, uint32_t d) { return c_beta1(x, c_beta0(x, d)); }
static const double *c_pos(const fast_level *x, uint32_t v)
{
    int use_col = x->vnew ? !st_block_bit(x->vnew, v) : x->c.vins[v] < x->c.plvl;
    return (const double *)pick(x->c.pbase, x->c.pcol, use_col) + 3 * (size_t)v;
}

/* Dart d of level l was inserted below l. */
static int c_old(const fast_level *x, uint32_t d) { return x->dnew ? !st_block_bit(x->dnew, d) : x->c.ins[d] < x->l; }

static int is_live(const uint8_t *ins, uint32_t id) { return ins[id] != ST_FREE_LEVEL; }
static int is_hole(const fast_level *x, uint32_t d) { return (x->h->map.flags[d] & ST_DART_BOUNDARY) != 0; }
static int sharp_edge(const fast_level *x, uint32_t d)
{
    return x->h->has_sharpness && st_hier_edge_sharpness(x->h, d, x->l) > 0;
}

static double *fine_slot(const fast_level *x, uint32_t v)
{
    return (x->c.vins[v] == x->L ? x->pnew : x->pold) + 3 * (size_t)v;
}

static void sink_write(void *ctx, const st_stencil *s)
{
    fast_worker *w = ctx;
    st_stencil_eval(w->x->h, w->x->L, s, fine_slot(w->x, s->fine));
}

/* Any dart of v will do: the vertex pass starts its sums at the smallest. */
static void offer_dart(fast_level *x, uint32_t v, uint32_t d)
{
    atomic_store_explicit(&x->vd[v], d, memory_order_relaxed);
}

/* The centre of the face of coarse dart d at level L, or ST_NIL when the
 * chain does not end on a vertex new at L.  Each step reads a live dart
 * whatever the map, so only the end is checked (a check per step would read
 * as much memory again): a level whose faces passed the checks at level l
 * but were not split at L ends on an old vertex. */
static uint32_t centre_of(const fast_level *x, uint32_t d)
{
    uint32_t c = x->vt[x->b0[x->b1[x->b0L[d]]]];
    return x->c.vins[c] == x->L ? c : ST_NIL;
}

/* ---- face points ---- */

/* Face of k corners y[0..k) with positions p[]: its point at its centre
 * (from corner `from`, whose twin is in a sibling face: the chain to the
 * centre then starts next in memory), G of its darts, and their vertices
 * learn them.  0 when the centre cannot be found. */
static int face_finish(fast_level *x, const uint32_t *y, const uint32_t *v, const double *const *p, unsigned k, uint32_t from)
{
    uint32_t centre = centre_of(x, from);
    if (centre == ST_NIL) return 0;
    double f[3] = { 0, 0, 0 };
    for (unsigned i = 0; i < k; i++) { f[0] += p[i][0]; f[1] += p[i][1]; f[2] += p[i][2]; }
    double inv = 1.0 / k;
    f[0] *= inv; f[1] *= inv; f[2] *= inv;
    memcpy(x->pnew + 3 * (size_t)centre, f, sizeof f);
    for (unsigned i = 0; i < k; i++) {
        const double *q = p[i + 1 < k ? i + 1 : 0];
        double *g = x->g + 3 * (size_t)y[i];
        g[0] = q[0] + f[0]; g[1] = q[1] + f[1]; g[2] = q[2] + f[2];
        offer_dart(x, v[i], y[i]);
    }
    return 1;
}

/* A face larger than FAST_MAX_RING (level 0 only): walked twice. */
static int face_large(fast_level *x, uint32_t d)
{
    uint32_t centre = centre_of(x, d);
    if (centre == ST_NIL) return 0;
    double f[3] = { 0, 0, 0 };
    unsigned k = 0;
    uint32_t y = d;
    do { const double *p = c_pos(x, c_vert(x, y)); f[0] += p[0]; f[1] += p[1]; f[2] += p[2]; k++; y = c_phi1(x, y); } while (y != d);
    double inv = 1.0 / k;
    f[0] *= inv; f[1] *= inv; f[2] *= inv;
    memcpy(x->pnew + 3 * (size_t)centre, f, sizeof f);
    do {
        uint32_t next = c_phi1(x, y);
        const double *q = c_pos(x, c_vert(x, next));
        double *g = x->g + 3 * (size_t)y;
        g[0] = q[0] + f[0]; g[1] = q[1] + f[1]; g[2] = q[2] + f[2];
        offer_dart(x, c_vert(x, y), y);
        y = next;
    } while (y != d);
    return 1;
}

/* Any face, walked from d; with one_old, it must hold exactly one dart
 * older than l.  Returns its degree, 0 if it does not fit. */
static unsigned face_any(fast_level *x, uint32_t d, int one_old)
{
    uint32_t y[FAST_MAX_RING], v[FAST_MAX_RING];
    const double *p[FAST_MAX_RING];
    unsigned k = 0, old = 0;
    uint32_t z = d;
    do {
        old += x->c.ins[z] < x->l;
        if (k < FAST_MAX_RING) { y[k] = z; v[k] = c_vert(x, z); p[k] = c_pos(x, v[k]); }
        k++;
        z = c_phi1(x, z);
    } while (z != d);
    if (one_old && old != 1) return 0;
    if (k > FAST_MAX_RING) return face_large(x, d) ? k : 0;
    return face_finish(x, y, v, p, k, y[k - 1]) ? k : 0;
}

/* The corner quad of n = n(d_i) without a loop: (n, D, in, out), D old, in
 * and out new, φ1(out) = n; else the general walk.  Returns the degree. */
static unsigned face_from_new_dart(fast_level *x, uint32_t n)
{
    const uint8_t *ins = x->c.ins;
    uint32_t y[4], v[4];
    const double *p[4];
    y[0] = n;
    y[1] = c_phi1(x, n);
    y[2] = c_phi1(x, y[1]);
    y[3] = c_phi1(x, y[2]);
    int quad = (c_phi1(x, y[3]) == n) & (ins[y[1]] < x->l) & (ins[y[2]] == x->l) & (ins[y[3]] == x->l);
    if (!quad) return face_any(x, n, 1);
    for (int i = 0; i < 4; i++) { v[i] = c_vert(x, y[i]); p[i] = c_pos(x, v[i]); }
    return face_finish(x, y, v, p, 4, y[3]) ? 4 : 0;
}

/* One block of level l: its darts n(d_i) (new, twin old), gathered without
 * a branch per dart, each names a face.  With plain relations the faces are
 * walked in stages whose loads are independent across the block (so that
 * their cache misses overlap): φ1 three times, the check, the chain to the
 * centre, the corners' positions; then the sums. */
static uint64_t face_block(fast_level *x, uint32_t first)
{
    const uint8_t *ins = x->c.ins;
    uint32_t names[ST_POOL_BLOCK], n = 0;
    uint64_t covered = 0;
    for (uint32_t d = first; d < first + ST_POOL_BLOCK; d++) {
        if (!is_live(ins, d)) continue; /* free ids hold no relation */
        names[n] = d;
        n += (unsigned)!is_hole(x, d) & (unsigned)c_old(x, c_beta0(x, d)); /* branch-free on purpose */
    }
    if (!x->plain) {
        for (uint32_t i = 0; i < n; i++) {
            unsigned k = face_from_new_dart(x, names[i]);
            if (!k) atomic_store(&x->irregular, 1);
            covered += k;
        }
        return covered;
    }
    const uint32_t *b1 = x->b1, *vt = x->vt;
    uint32_t y1[ST_POOL_BLOCK], y2[ST_POOL_BLOCK], y3[ST_POOL_BLOCK], c[ST_POOL_BLOCK];
    const double *p[4][ST_POOL_BLOCK];
    uint8_t quad[ST_POOL_BLOCK];
    for (uint32_t i = 0; i < n; i++) y1[i] = b1[c_beta0(x, names[i])];
    for (uint32_t i = 0; i < n; i++) y2[i] = b1[c_beta0(x, y1[i])];
    for (uint32_t i = 0; i < n; i++) y3[i] = b1[c_beta0(x, y2[i])];
    for (uint32_t i = 0; i < n; i++)
        quad[i] = (uint8_t)((b1[c_beta0(x, y3[i])] == names[i]) & c_old(x, y1[i]) & !c_old(x, y2[i]) & !c_old(x, y3[i]));
    /* The centre of the face at L (centre_of), from the corner out_i. */
    for (uint32_t i = 0; i < n; i++) c[i] = x->b0L[y3[i]];
    for (uint32_t i = 0; i < n; i++) c[i] = b1[c[i]];
    for (uint32_t i = 0; i < n; i++) c[i] = x->b0[c[i]];
    for (uint32_t i = 0; i < n; i++) c[i] = vt[c[i]];
    for (uint32_t i = 0; i < n; i++) {
        p[0][i] = c_pos(x, vt[names[i]]);
        p[1][i] = c_pos(x, vt[y1[i]]);
        p[2][i] = c_pos(x, vt[y2[i]]);
        p[3][i] = c_pos(x, vt[y3[i]]);
    }
    for (uint32_t i = 0; i < n; i++) {
        if (!quad[i]) {
            unsigned k = face_any(x, names[i], 1);
            if (!k) atomic_store(&x->irregular, 1);
            covered += k;
            continue;
        }
        if (x->c.vins[c[i]] != x->L) { atomic_store(&x->irregular, 1); continue; }
        uint32_t y[4] = { names[i], y1[i], y2[i], y3[i] };
        const double *q[4] = { p[0][i], p[1][i], p[2][i], p[3][i] };
        double f[3] = { 0, 0, 0 };
        for (unsigned k = 0; k < 4; k++) { f[0] += q[k][0]; f[1] += q[k][1]; f[2] += q[k][2]; }
        double inv = 1.0 / 4;
        f[0] *= inv; f[1] *= inv; f[2] *= inv;
        memcpy(x->pnew + 3 * (size_t)c[i], f, sizeof f);
        for (unsigned k = 0; k < 4; k++) {
            const double *r = q[k + 1 < 4 ? k + 1 : 0];
            double *g = x->g + 3 * (size_t)y[k];
            g[0] = r[0] + f[0]; g[1] = r[1] + f[1]; g[2] = r[2] + f[2];
            offer_dart(x, vt[y[k]], y[k]);
        }
        covered += 4;
    }
    return covered;
}

static void faces_by_new_darts(st_team *team, fast_level *x)
{
    uint64_t covered = 0;
    uint32_t b, e;
    while (st_team_next(team, 0, x->nnew, FAST_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++) covered += face_block(x, x->blocks[i]);
    atomic_fetch_add(&x->covered, covered);
}

/* Level 0: faces in enumeration order, a visited bit per dart. */
static void faces_sequential(fast_level *x)
{
    uint64_t *seen = calloc((size_t)x->dcover / 64 + 1, sizeof *seen);
    if (!seen) abort(); /* out of memory for a bit per dart */
    for (uint32_t i = 0; i < x->nblocks; i++)
        for (uint32_t d = x->blocks[i]; d < x->blocks[i] + ST_POOL_BLOCK; d++) {
            if (!is_live(x->c.ins, d) || is_hole(x, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
            uint32_t y = d;
            do { seen[y >> 6] |= 1ull << (y & 63); y = c_phi1(x, y); } while (y != d);
            if (!face_any(x, d, 0)) atomic_store(&x->irregular, 1);
        }
    free(seen);
}

/* ---- edge points ---- */

/* The edges of one block whose smaller dart it holds, in stages whose loads
 * are independent across the block (so that their cache misses overlap);
 * returns the number of hole darts in the block. */
static uint32_t edge_block(fast_worker *w, uint32_t first)
{
    fast_level *x = w->x;
    const uint8_t *ins = x->c.ins;
    uint32_t dd[ST_POOL_BLOCK], ee[ST_POOL_BLOCK], mid[ST_POOL_BLOCK], n = 0, m = 0, holes = 0;
    for (uint32_t d = first; d < first + ST_POOL_BLOCK; d++) {
        if (!is_live(ins, d)) continue; /* free ids hold no relation */
        uint32_t e = c_beta0(x, d);
        holes += is_hole(x, d);
        dd[n] = d;
        ee[n] = e;
        n += d < e;
    }
    for (uint32_t i = 0; i < n; i++) {
        uint32_t d = dd[i], e = ee[i];
        if (is_hole(x, d) || is_hole(x, e) || sharp_edge(x, d)) {
            emit_edge(x->h, x->L, d, &w->e, sink_write, w);
            continue;
        }
        dd[m] = d;
        ee[m] = e;
        mid[m++] = x->b0L[d];
    }
    for (uint32_t i = 0; i < m; i++) mid[i] = x->vt[mid[i]];
    for (uint32_t i = 0; i < m; i++) {
        const double *gd = x->g + 3 * (size_t)dd[i], *ge = x->g + 3 * (size_t)ee[i];
        double *out = x->pnew + 3 * (size_t)mid[i];
        for (int k = 0; k < 3; k++) out[k] = 0.25 * gd[k] + 0.25 * ge[k];
    }
    return holes;
}

static void edges(st_team *team, fast_worker *w)
{
    fast_level *x = w->x;
    uint64_t holes = 0;
    uint32_t b, e;
    while (st_team_next(team, 1, x->nblocks, FAST_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++) holes += edge_block(w, x->blocks[i]);
    atomic_fetch_add(&x->holes, holes);
}

/* ---- vertex points ---- */

/* Position of the smallest of n darts. */
static unsigned smallest(const uint32_t *r, unsigned n)
{
    unsigned m = 0;
    for (unsigned i = 1; i < n; i++) m = r[i] < r[m] ? i : m;
    return m;
}

/* Vertex point ((n-2) v + Σ neighbours / n + Σ face points / n) / n, the
 * sum taken around from the smallest dart. */
static void vertex_finish(fast_worker *w, uint32_t v, const uint32_t *r, unsigned n, int special)
{
    fast_level *x = w->x;
    unsigned m = smallest(r, n);
    if (special) { emit_vertex(x->h, x->L, r[m], &w->e, sink_write, w); return; }
    double s[3] = { 0, 0, 0 };
    for (unsigned i = 0, j = m; i < n; i++, j = j + 1 < n ? j + 1 : 0) {
        const double *g = x->g + 3 * (size_t)r[j];
        s[0] += g[0]; s[1] += g[1]; s[2] += g[2];
    }
    const double *p = c_pos(x, v);
    double *out = x->pold + 3 * (size_t)v, wv = (double)(n - 2) / n, wn = 1.0 / ((double)n * n);
    for (int i = 0; i < 3; i++) out[i] = wv * p[i] + wn * s[i];
}

/* A ring larger than FAST_MAX_RING: walked once for its smallest dart and
 * its valence, then summed from that dart on a second walk. */
static void vertex_large(fast_worker *w, uint32_t v, uint32_t d, int special)
{
    fast_level *x = w->x;
    uint32_t lo = d, y = d;
    unsigned n = 0;
    do { lo = y < lo ? y : lo; special |= is_hole(x, y) | sharp_edge(x, y); n++; y = c_beta1(x, y); } while (y != d);
    if (special) { emit_vertex(x->h, x->L, lo, &w->e, sink_write, w); return; }
    double s[3] = { 0, 0, 0 };
    y = lo;
    do { const double *g = x->g + 3 * (size_t)y; s[0] += g[0]; s[1] += g[1]; s[2] += g[2]; y = c_beta1(x, y); } while (y != lo);
    const double *p = c_pos(x, v);
    double *out = x->pold + 3 * (size_t)v, wv = (double)(n - 2) / n, wn = 1.0 / ((double)n * n);
    for (int i = 0; i < 3; i++) out[i] = wv * p[i] + wn * s[i];
}

static void vertex_point(fast_worker *w, uint32_t v)
{
    fast_level *x = w->x;
    uint32_t d = atomic_load_explicit(&x->vd[v], memory_order_relaxed);
    if (d == ST_NIL) { memcpy(x->pold + 3 * (size_t)v, c_pos(x, v), 3 * sizeof(double)); return; } /* no real face: stays */
    int special = x->h->has_sharpness && st_hier_vertex_sharpness(x->h, v, x->l) > 0;
    uint32_t r[FAST_MAX_RING];
    /* Valence 4 without a loop, else the general walk. */
    r[0] = d;
    r[1] = c_beta1(x, d);
    r[2] = c_beta1(x, r[1]);
    r[3] = c_beta1(x, r[2]);
    unsigned n = 4;
    uint32_t y = c_beta1(x, r[3]);
    if (y != d) {
        if (r[1] == d) n = 1;
        else if (r[2] == d) n = 2;
        else if (r[3] == d) n = 3;
        else
            for (; y != d; y = c_beta1(x, y)) {
                if (n == FAST_MAX_RING) { vertex_large(w, v, d, special); return; }
                r[n++] = y;
            }
    }
    for (unsigned i = 0; i < n; i++) special |= is_hole(x, r[i]) | sharp_edge(x, r[i]);
    vertex_finish(w, v, r, n, special);
}

/* The vertices of a batch in stages whose loads are independent across the
 * batch (so that their cache misses overlap): darts, rings of valence 4,
 * then the sums; other valences and special vertices take vertex_point. */
#define VBATCH 128u

static void vertex_batch(fast_worker *w, const uint32_t *vs, uint32_t n)
{
    fast_level *x = w->x;
    const uint32_t *b1 = x->b1;
    uint32_t r[4][VBATCH];
    const double *p[VBATCH];
    uint8_t four[VBATCH];
    /* A vertex without a real face (ST_NIL) walks dart 0's ids instead
     * (every read stays in the arrays) and takes vertex_point. */
    for (uint32_t i = 0; i < n; i++) r[0][i] = atomic_load_explicit(&x->vd[vs[i]], memory_order_relaxed);
    for (uint32_t i = 0; i < n; i++) four[i] = r[0][i] != ST_NIL;
    for (uint32_t i = 0; i < n; i++) r[0][i] = four[i] ? r[0][i] : 0;
    for (uint32_t i = 0; i < n; i++) r[1][i] = four[i] ? b1[r[0][i]] : 0;
    for (uint32_t i = 0; i < n; i++) r[2][i] = four[i] ? b1[r[1][i]] : 0;
    for (uint32_t i = 0; i < n; i++) r[3][i] = four[i] ? b1[r[2][i]] : 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t d = r[0][i];
        four[i] = four[i] && b1[r[3][i]] == d && r[1][i] != d && r[2][i] != d && r[3][i] != d;
    }
    const uint8_t *flags = x->h->map.flags;
    for (uint32_t i = 0; i < n; i++)
        four[i] &= !((flags[r[0][i]] | flags[r[1][i]] | flags[r[2][i]] | flags[r[3][i]]) & ST_DART_BOUNDARY);
    for (uint32_t i = 0; i < n; i++) p[i] = c_pos(x, vs[i]);
    int sharpness = x->h->has_sharpness;
    for (uint32_t i = 0; i < n; i++) {
        if (!four[i] || sharpness) { vertex_point(w, vs[i]); continue; }
        uint32_t q[4] = { r[0][i], r[1][i], r[2][i], r[3][i] };
        unsigned m = smallest(q, 4);
        double s[3] = { 0, 0, 0 };
        for (unsigned k = 0, j = m; k < 4; k++, j = (j + 1) & 3) {
            const double *g = x->g + 3 * (size_t)q[j];
            s[0] += g[0]; s[1] += g[1]; s[2] += g[2];
        }
        double *out = x->pold + 3 * (size_t)vs[i], wv = (double)(4 - 2) / 4, wn = 1.0 / ((double)4 * 4);
        for (int k = 0; k < 3; k++) out[k] = wv * p[i][k] + wn * s[k];
    }
}

static void vertices(st_team *team, fast_worker *w)
{
    fast_level *x = w->x;
    uint32_t b, e, vs[VBATCH], n = 0;
    while (st_team_next(team, 2, x->nvblocks, FAST_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++)
            for (uint32_t v = x->vblocks[i]; v < x->vblocks[i] + ST_POOL_BLOCK; v++) {
                if (!is_live(x->c.vins, v)) continue;
                vs[n++] = v;
                if (n == VBATCH) { vertex_batch(w, vs, n); n = 0; }
            }
    vertex_batch(w, vs, n);
}

/* ---- the level ---- */

static void level_passes(st_team *team, unsigned t, void *ctx)
{
    fast_worker w = { .x = ctx };
    fast_level *x = w.x;
    if (x->l > 0) faces_by_new_darts(team, x);
    else if (t == 0) faces_sequential(x);
    st_team_sync(team);
    if (!atomic_load(&x->irregular)) {
        edges(team, &w);      /* edges and vertices write different slots */
        vertices(team, &w);
    }
    st_stencil_buf_free(&w.e.buf);
    st_stencil_buf_free(&w.e.tmp);
}

/* 1 + the largest id in the blocks. */
static uint32_t blocks_cover(const uint32_t *blocks, uint32_t n)
{
    uint32_t cover = 0;
    for (uint32_t i = 0; i < n; i++)
        if (blocks[i] + ST_POOL_BLOCK > cover) cover = blocks[i] + ST_POOL_BLOCK;
    return cover;
}

static int fast_level_init(fast_level *x, st_hier *h, unsigned L)
{
    st_map *m = &h->map;
    *x = (fast_level){ .h = h, .l = L - 1, .L = L };
    atomic_init(&x->irregular, 0);
    atomic_init(&x->covered, 0);
    atomic_init(&x->holes, 0);
    x->pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    if (!x->pold) return -1;
    x->pnew = (double *)m->pos.base;
    x->b0L = (const uint32_t *)m->beta0.col[L];
    x->b0 = (const uint32_t *)m->beta0.base;
    x->b1 = (const uint32_t *)m->beta1.base;
    x->vt = (const uint32_t *)m->vert.base;
    x->plain = m->beta1.eff[x->l] == 0 && m->vert.eff[x->l] == 0;
    st_level_view_init(m, x->l, &x->c);
    x->blocks = st_pool_blocks_newest_first(&m->darts, x->l, &x->nblocks);
    x->vblocks = st_pool_blocks_newest_first(&m->verts, x->l, &x->nvblocks);
    if (!x->blocks || !x->vblocks) return -1;
    x->nnew = m->darts.nblocks[x->l];
    x->dcover = blocks_cover(x->blocks, x->nblocks);
    x->vcover = blocks_cover(x->vblocks, x->nvblocks);
    x->g = malloc(((size_t)x->dcover + 1) * 3 * sizeof *x->g);
    x->vd = malloc(((size_t)x->vcover + 1) * sizeof *x->vd);
    if (!x->g || !x->vd) return -1;
    if (m->beta0.eff[x->l] == x->l && !(x->dnew = st_block_bits(&m->darts, x->l))) return -1;
    if (m->pos.eff[x->l] == x->l && !(x->vnew = st_block_bits(&m->verts, x->l))) return -1;
    for (uint32_t v = 0; v < x->vcover; v++) atomic_init(&x->vd[v], ST_NIL);
    return 0;
}

static void fast_level_free(fast_level *x)
{
    free(x->blocks);
    free(x->vblocks);
    free(x->g);
    free((void *)x->vd);
    free(x->dnew);
    free(x->vnew);
}

/* Every vertex of level L by its stencil (a level this file's fast path does
 * not recognise). */
static void predict_by_stencils(st_hier *h, unsigned L)
{
    fast_level x = { .h = h, .L = L, .l = L - 1 };
    x.pold = st_mla_column_for_overwrite(&h->map.pos, &h->map.verts, L);
    x.pnew = (double *)h->map.pos.base;
    if (!x.pold) abort(); /* out of memory for a level's positions */
    st_level_view_init(&h->map, L - 1, &x.c);
    fast_worker w = { .x = &x };
    catmark_emit(h, L, NULL, 0, sink_write, &w);
}

static void catmark_predict_level(st_hier *h, unsigned L)
{
    if (!h->map.beta0.col[L]) { predict_by_stencils(h, L); return; }
    fast_level x;
    if (fast_level_init(&x, h, L)) abort(); /* out of memory for a level's scratch */
    unsigned threads = st_parallel_threads();
    if (x.nblocks < FAST_MIN_BLOCKS_PER_THREAD * threads) threads = x.nblocks / FAST_MIN_BLOCKS_PER_THREAD;
    st_team_run(threads ? threads : 1, level_passes, &x);
    /* Every dart of level l must lie in a face found or in a hole. */
    int irregular = atomic_load(&x.irregular) ||
                    (x.l > 0 && atomic_load(&x.covered) + atomic_load(&x.holes) != st_pool_count(&h->map.darts, x.l));
    fast_level_free(&x);
    if (irregular) predict_by_stencils(h, L);
}

const st_scheme st_scheme_catmark = {
    .name = "catmull-clark",
    .id = ST_SCHEME_CATMARK,
    .interpolating = 0,
    .support_rings = 1,
    .check = NULL,
    .refine = catmark_refine,
    .emit = catmark_emit,
    .predict_level = catmark_predict_level,
};
