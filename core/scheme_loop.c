/* Loop (1987) on triangle meshes, with OpenSubdiv 3.5's boundary, corner
 * and semi-sharp crease rules (crease.h; Sdc::Scheme<SCHEME_LOOP>,
 * sdc/loopScheme.h).  Masks (digest §4, thesis fig. 3.14, listing 3.2.1):
 *   edge point   = 3/8 (a + b) + 1/8 (c + d), c and d opposite the edge;
 *   vertex point = (1 - nβ) v + β Σ neighbours, Loop's original
 *                  β = (1/n) (5/8 - (3/8 + cos(2π/n) / 4)²),
 *                  exactly 1/16 (and 5/8 for v) at valence 6.
 * The weights are computed with OpenSubdiv's own expression order
 * (assignSmoothMaskForVertex) so that both agree to the last bits.
 * Boundaries: boundary edges are infinitely sharp (midpoints, B-spline
 * boundary curves); with edge-and-corner a boundary vertex with one face is
 * a corner.  Topology: triangle quadrisection (refine.c, ST_SPLIT_TRI). */
#include "primal_emit.h"
#include "hier_internal.h"
#include "synth_blocks.h"

#include "parallel.h"
#include "pool.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Vertex opposite the edge of d in d's triangle (level l). */
static uint32_t opposite(const st_map *m, uint32_t d, unsigned l)
{
    return st_vert(m, st_phi1(m, st_phi1(m, d, l), l), l);
}

/* Only called for edges with two real faces (boundary edges are sharp). */
static void smooth_edge(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = &h->map;
    uint32_t e = st_beta0(m, d, l);
    st_stencil_buf_add(out, st_vert(m, d, l), 0.375);
    st_stencil_buf_add(out, st_vert(m, e, l), 0.375);
    st_stencil_buf_add(out, opposite(m, d, l), 0.125);
    st_stencil_buf_add(out, opposite(m, e, l), 0.125);
}

/* Loop's original weights, in OpenSubdiv's arithmetic (double). */
static void loop_weights(unsigned n, double *vw, double *ew)
{
    if (n == 6) { *vw = 0.625; *ew = 0.0625; return; }
    double dn = (double)n, inv = 1.0 / dn;
    double c = cos(M_PI * 2.0 * inv);
    double beta = 0.25 * c + 0.375;
    *ew = (0.625 - beta * beta) * inv;
    *vw = 1.0 - *ew * dn;
}

/* Smooth (and dart) vertices are interior: every face around is real. */
static void smooth_vertex(const st_hier *h, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = &h->map;
    unsigned n = st_vertex_degree(m, d, l);
    double vw, ew;
    loop_weights(n, &vw, &ew);
    st_stencil_buf_add(out, st_vert(m, d, l), vw);
    uint32_t x = d;
    do {
        st_stencil_buf_add(out, st_vert(m, st_beta0(m, x, l), l), ew);
        x = st_beta1(m, x, l);
    } while (x != d);
}

/* ---- fast full-level synthesis ---------------------------------------------
 * The same masks as above, with the relations read through level views and
 * no stencil buffers; boundary and sharp cells take the stencil path. */

typedef struct loop_fast {
    st_hier *h;
    unsigned L;
    st_level_view c, f;           /* coarse level L-1, fine level L */
    double *pnew, *pold;          /* level-L positions: new vertices, old vertices */
    st_stencil_buf buf, tmp;
} loop_fast;

static double *slot(const loop_fast *x, uint32_t v)
{
    return (x->c.vins[v] == x->L ? x->pnew : x->pold) + 3 * (size_t)v;
}

static void write_stencil(loop_fast *x, uint32_t fine, uint32_t dart, int cell)
{
    st_stencil s = { fine, x->buf.n, x->buf.src, x->buf.w, dart, (uint8_t)cell };
    st_stencil_eval(x->h, x->L, &s, slot(x, fine));
}

static int sharp_edge(const loop_fast *x, uint32_t d, uint32_t e)
{
    const st_map *m = &x->h->map;
    return st_is_boundary(m, d) || st_is_boundary(m, e) ||
           (x->h->has_sharpness && st_hier_edge_sharpness(x->h, d, x->L - 1) > 0);
}

static void axpy(double *acc, double w, const double *p)
{
    acc[0] += w * p[0]; acc[1] += w * p[1]; acc[2] += w * p[2];
}

static void fast_edge(loop_fast *x, uint32_t d, uint32_t e)
{
    uint32_t mid = st_v_vert(&x->f, st_v_beta0(&x->f, d));
    if (sharp_edge(x, d, e)) {
        st_crease_edge_point(x->h, x->L - 1, d, smooth_edge, &x->buf, &x->tmp);
        write_stencil(x, mid, d, ST_CELL_EDGE);
        return;
    }
    const st_level_view *c = &x->c;
    double acc[3] = { 0, 0, 0 };
    axpy(acc, 0.375, st_v_pos(c, st_v_vert(c, d)));
    axpy(acc, 0.375, st_v_pos(c, st_v_vert(c, e)));
    axpy(acc, 0.125, st_v_pos(c, st_v_vert(c, st_v_phi1(c, st_v_phi1(c, d)))));
    axpy(acc, 0.125, st_v_pos(c, st_v_vert(c, st_v_phi1(c, st_v_phi1(c, e)))));
    memcpy(slot(x, mid), acc, sizeof acc);
}

static void fast_vertex(loop_fast *x, uint32_t d)
{
    const st_level_view *c = &x->c;
    uint32_t v = st_v_vert(c, d), y = d;
    unsigned n = 0;
    int smooth = !x->h->has_sharpness || st_hier_vertex_sharpness(x->h, v, x->L - 1) <= 0;
    do {
        if (sharp_edge(x, y, st_v_beta0(c, y))) smooth = 0;
        n++;
        y = st_v_beta1(c, y);
    } while (y != d);
    if (!smooth) {
        st_crease_vertex_point(x->h, x->L - 1, d, smooth_vertex, &x->buf, &x->tmp);
        write_stencil(x, v, d, ST_CELL_VERTEX);
        return;
    }
    double vw, ew, acc[3] = { 0, 0, 0 };
    loop_weights(n, &vw, &ew);
    axpy(acc, vw, st_v_pos(c, v));
    do {
        axpy(acc, ew, st_v_pos(c, st_v_vert(c, st_v_beta0(c, y))));
        y = st_v_beta1(c, y);
    } while (y != d);
    memcpy(slot(x, v), acc, sizeof acc);
}

/* Level views and a stamp per vertex: any map (used when the ring pass below
 * does not apply). */
static void loop_predict_views(st_hier *h, unsigned L)
{
    st_map *m = &h->map;
    loop_fast x = { .h = h, .L = L };
    x.pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    x.pnew = (double *)m->pos.base;
    if (!x.pold) abort(); /* out of memory for a level's positions */
    st_level_view_init(m, L - 1, &x.c);
    st_level_view_init(m, L, &x.f);
    uint32_t gen = st_hier_stamp_begin(h);
    const st_pool *p = &m->darts;
    for (unsigned lv = L; lv-- > 0;)
        for (uint32_t b = 0; b < p->nblocks[lv]; b++) {
            uint32_t first = p->blocks[lv][b] << ST_POOL_BLOCK_SHIFT;
            for (uint32_t d = first; d < first + ST_POOL_BLOCK; d++) {
                if (p->ins[d] == ST_FREE_LEVEL) continue;
                uint32_t e = st_v_beta0(&x.c, d), v = st_v_vert(&x.c, d);
                if (d < e) fast_edge(&x, d, e);
                if (h->stamp[v] != gen) { h->stamp[v] = gen; fast_vertex(&x, d); }
            }
        }
    st_stencil_buf_free(&x.buf);
    st_stencil_buf_free(&x.tmp);
}

/* ---- ring pass -----------------------------------------------------------------
 * One walk of each vertex ring of level l gives both its vertex point and
 * the edge points of the ring edges whose smaller dart leaves it: with the
 * ring darts y_0 .. y_{n-1} (β1 order) and u_j = vert(β0 y_j), the face of
 * y_j is (v, u_j, u_{j-1}) and that of β0(y_j) is (u_j, v, u_{j+1}), so the
 * edge point of y_j is 3/8 (v + u_j) + 1/8 (u_{j-1} + u_{j+1}), summed in the
 * order of fast_edge.  Each vertex position and each relation of the ring is
 * read once per level instead of once per mask that uses it.
 *
 * Two passes shared out over threads by blocks (parallel.h): every dart
 * offers itself to its vertex; then every vertex walks its ring from its
 * smallest dart (so that the sums never depend on the threads) and writes
 * its vertex point and the edge points it owns: each fine vertex has one
 * writer.  Holes and sharp cells take the stencil path. */

#define RING_MAX 32u          /* rings up to this valence are kept on the stack */
#define RING_CHUNK 8u         /* blocks per st_team_next chunk */
#define RING_MIN_BLOCKS_PER_THREAD 32u

typedef struct ring_level {
    st_hier *h;
    unsigned l, L;
    st_level_view c;                 /* coarse level l */
    const uint32_t *b0L;             /* β0 column of level L (darts of levels <= l) */
    const uint32_t *b1, *vt;         /* base β1 and vert: no column at level l (checked) */
    const uint8_t *flags;
    double *pnew, *pold;             /* level-L positions: new vertices, old vertices */
    _Atomic uint32_t *vd;            /* per coarse vertex: one of its darts, ST_NIL if none */
    int vd_given;                    /* vd was filled by the level below (no offer pass) */
    uint32_t *next_vd;               /* when the level above follows: vd of level L, filled here */
    uint32_t *blocks, nblocks;       /* first ids of the dart blocks of levels l..0 */
    uint32_t *vblocks, nvblocks;     /* ... and of the vertex blocks */
    uint32_t vcover;
    uint64_t *dnew;                  /* block bits (synth_blocks.h) of the darts of level l ... */
    uint64_t *vnew;                  /* ... and of its vertices when positions have a level-l column (else NULL) */
    double vw[RING_MAX + 1], ew[RING_MAX + 1]; /* loop_weights by valence */
} ring_level;

typedef struct ring_worker { ring_level *x; loop_fast s; } ring_worker;

/* β0 at level l (whose column is level l's: checked), a column read for
 * the darts older than l. */
static uint32_t r_beta0(const ring_level *x, uint32_t d)
{
    const st_u32_view *r = &x->c.beta0;
    return ((const uint32_t *)st_pick(r->base, r->col, !st_block_bit(x->dnew, d)))[d];
}

static const double *r_pos(const ring_level *x, uint32_t v)
{
    int use_col = x->vnew ? !st_block_bit(x->vnew, v) : x->c.vins[v] < x->c.plvl;
    return (const double *)st_pick(x->c.pbase, x->c.pcol, use_col) + 3 * (size_t)v;
}

static void ring_offer(st_team *team, ring_level *x)
{
    const uint8_t *ins = x->c.ins;
    uint32_t b, e;
    while (st_team_next(team, 0, x->nblocks, RING_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++)
            for (uint32_t d = x->blocks[i]; d < x->blocks[i] + ST_POOL_BLOCK; d++)
                if (ins[d] != ST_FREE_LEVEL) atomic_store_explicit(&x->vd[x->vt[d]], d, memory_order_relaxed);
}

static int ring_sharp(const ring_level *x, uint32_t d)
{
    return x->h->has_sharpness && st_hier_edge_sharpness(x->h, d, x->l) > 0;
}

/* Stencil path for one vertex point / edge point (holes, sharpness). */
static void ring_stencil_vertex(ring_worker *w, uint32_t d)
{
    loop_fast *s = &w->s;
    st_crease_vertex_point(s->h, s->L - 1, d, smooth_vertex, &s->buf, &s->tmp);
    write_stencil(s, st_v_vert(&s->c, d), d, ST_CELL_VERTEX);
}

static void ring_stencil_edge(ring_worker *w, uint32_t d)
{
    loop_fast *s = &w->s;
    st_crease_edge_point(s->h, s->L - 1, d, smooth_edge, &s->buf, &s->tmp);
    write_stencil(s, st_v_vert(&s->f, st_v_beta0(&s->f, d)), d, ST_CELL_EDGE);
}

/* A ring larger than RING_MAX: the views path, from its smallest dart. */
static void ring_large(ring_worker *w, uint32_t d)
{
    ring_level *x = w->x;
    uint32_t y = d, small = d;
    do { small = y < small ? y : small; y = x->b1[y]; } while (y != d);
    y = small;
    do {
        uint32_t t = r_beta0(x, y);
        if (y < t) {
            fast_edge(&w->s, y, t);
            if (x->next_vd) x->next_vd[x->vt[x->b0L[y]]] = x->b0L[y];
        }
        y = x->b1[y];
    } while (y != small);
    fast_vertex(&w->s, small);
    if (x->next_vd) x->next_vd[x->vt[small]] = small;
}

/* The vertices of a batch are done in stages whose loads are independent
 * across the batch (so that their cache misses overlap): the rings, then
 * β0 of every ring dart, then the neighbours and their positions, then the
 * level-L midpoints, then the sums. */
#define BATCH_DARTS 1024u

typedef struct ring_batch {
    uint32_t v[BATCH_DARTS / 2], at[BATCH_DARTS / 2 + 1], lo[BATCH_DARTS / 2]; /* per vertex: id, first entry, smallest */
    uint32_t r[BATCH_DARTS], e[BATCH_DARTS], u[BATCH_DARTS], mid[BATCH_DARTS];  /* per ring dart */
    const double *q[BATCH_DARTS];
    uint32_t nv, nd;
} ring_batch;

static void batch_finish(ring_worker *w, ring_batch *B)
{
    ring_level *x = w->x;
    uint32_t nd = B->nd;
    for (uint32_t k = 0; k < nd; k++) B->e[k] = r_beta0(x, B->r[k]);
    for (uint32_t k = 0; k < nd; k++) B->u[k] = x->vt[B->e[k]];
    for (uint32_t k = 0; k < nd; k++) B->q[k] = r_pos(x, B->u[k]);
    for (uint32_t k = 0; k < nd; k++) B->mid[k] = B->r[k] < B->e[k] ? x->b0L[B->r[k]] : B->r[k];
    for (uint32_t k = 0; k < nd; k++) B->mid[k] = x->vt[B->mid[k]];
    const uint8_t *flags = x->flags;
    int sharpness = x->h->has_sharpness;
    for (uint32_t i = 0; i < B->nv; i++) {
        uint32_t v = B->v[i], n = B->at[i + 1] - B->at[i], lo = B->lo[i];
        const uint32_t *r = B->r + B->at[i], *e = B->e + B->at[i], *mid = B->mid + B->at[i];
        const double *const *q = B->q + B->at[i];
        /* The face of β0(y_j) is that of y_{j+1}: the ring darts' flags say
         * which edges touch a hole. */
        unsigned holes = 0;
        for (uint32_t j = 0; j < n; j++) holes |= flags[r[j]];
        int special = (holes & ST_DART_BOUNDARY) != 0;
        if (sharpness) {
            special |= st_hier_vertex_sharpness(x->h, v, x->l) > 0;
            for (uint32_t j = 0; j < n; j++) special |= ring_sharp(x, r[j]);
        }
        const double *p = r_pos(x, v);
        if (x->next_vd) {
            x->next_vd[v] = r[lo];   /* an old vertex keeps its ring at L */
            for (uint32_t j = 0; j < n; j++)
                if (r[j] < e[j]) x->next_vd[mid[j]] = x->b0L[r[j]]; /* β0(y_j, L) leaves the midpoint */
        }
        if (special) {
            ring_stencil_vertex(w, r[lo]);
        } else {
            double acc[3] = { 0, 0, 0 };
            axpy(acc, x->vw[n], p);
            for (uint32_t c = 0, j = lo; c < n; c++, j = j + 1 < n ? j + 1 : 0) axpy(acc, x->ew[n], q[j]);
            memcpy(x->pold + 3 * (size_t)v, acc, sizeof acc);
        }
        for (uint32_t j = 0; j < n; j++) {
            if (r[j] > e[j]) continue;
            uint32_t jn = j + 1 < n ? j + 1 : 0, jp = j ? j - 1 : n - 1;
            if (special && (((flags[r[j]] | flags[r[jn]]) & ST_DART_BOUNDARY) || ring_sharp(x, r[j]))) {
                ring_stencil_edge(w, r[j]);
                continue;
            }
            double acc[3] = { 0, 0, 0 };
            axpy(acc, 0.375, p);
            axpy(acc, 0.375, q[j]);
            axpy(acc, 0.125, q[jp]);
            axpy(acc, 0.125, q[jn]);
            memcpy(x->pnew + 3 * (size_t)mid[j], acc, sizeof acc);
        }
    }
    B->nv = B->nd = 0;
}

/* Adds vertex v's ring to the batch (or does v at once: no dart, a large ring). */
static void batch_add(ring_worker *w, ring_batch *B, uint32_t v)
{
    ring_level *x = w->x;
    uint32_t d = atomic_load_explicit(&x->vd[v], memory_order_relaxed);
    if (d == ST_NIL) { memcpy(x->pold + 3 * (size_t)v, r_pos(x, v), 3 * sizeof(double)); return; } /* no dart: stays */
    uint32_t at = B->nd, n = 0, lo = 0, y = d;
    do {
        if (n == RING_MAX) { ring_large(w, d); return; }
        B->r[at + n] = y;
        lo = y < B->r[at + lo] ? n : lo;
        n++;
        y = x->b1[y];
    } while (y != d);
    B->v[B->nv] = v;
    B->at[B->nv] = at;
    B->lo[B->nv] = lo;
    B->nv++;
    B->nd = at + n;
    B->at[B->nv] = B->nd;
    if (B->nd + RING_MAX > BATCH_DARTS || B->nv == BATCH_DARTS / 2) batch_finish(w, B);
}

static void ring_vertices(st_team *team, ring_worker *w)
{
    ring_level *x = w->x;
    const uint8_t *vins = x->c.vins;
    ring_batch *B = malloc(sizeof *B);
    if (!B) abort(); /* out of memory for a thread's scratch */
    B->nv = B->nd = 0;
    B->at[0] = 0;
    uint32_t b, e;
    while (st_team_next(team, 1, x->nvblocks, RING_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++)
            for (uint32_t v = x->vblocks[i]; v < x->vblocks[i] + ST_POOL_BLOCK; v++)
                if (vins[v] != ST_FREE_LEVEL) batch_add(w, B, v);
    batch_finish(w, B);
    free(B);
}

static void ring_passes(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    ring_level *x = ctx;
    ring_worker w = { .x = x, .s = { .h = x->h, .L = x->L, .pnew = x->pnew, .pold = x->pold } };
    st_level_view_init(&x->h->map, x->l, &w.s.c);
    st_level_view_init(&x->h->map, x->L, &w.s.f);
    if (!x->vd_given) {
        ring_offer(team, x);
        st_team_sync(team);
    }
    ring_vertices(team, &w);
    st_stencil_buf_free(&w.s.buf);
    st_stencil_buf_free(&w.s.tmp);
}

/* 1 + the last id of the vertex blocks of levels 0..l. */
static uint32_t vblock_cover(const st_pool *p, unsigned l)
{
    uint32_t cover = 0;
    for (unsigned lv = 0; lv <= l; lv++)
        for (uint32_t i = 0; i < p->nblocks[lv]; i++) {
            uint32_t end = (p->blocks[lv][i] + 1) << ST_POOL_BLOCK_SHIFT;
            cover = end > cover ? end : cover;
        }
    return cover;
}

/* Whether level L can take the ring pass: β1 and vert read from their base
 * arrays, β0 at l and at L from their columns. */
static int ring_applies(const st_map *m, unsigned L)
{
    unsigned l = L - 1;
    return m->beta0.col[L] && !m->beta1.eff[l] && !m->vert.eff[l] && m->beta0.eff[l] == l;
}

/* Level L by the ring pass.  vd: a dart per vertex of level l from the
 * level below (taken over and freed), or NULL; with want_next, returns
 * the same for level L (else NULL). */
static _Atomic uint32_t *ring_level_run(st_hier *h, unsigned L, _Atomic uint32_t *vd, int want_next)
{
    st_map *m = &h->map;
    unsigned l = L - 1;
    ring_level x = { .h = h, .l = l, .L = L };
    x.pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    x.pnew = (double *)m->pos.base;
    if (!x.pold) abort(); /* out of memory for a level's positions */
    x.b0L = (const uint32_t *)m->beta0.col[L];
    x.b1 = (const uint32_t *)m->beta1.base;
    x.vt = (const uint32_t *)m->vert.base;
    x.flags = m->flags;
    st_level_view_init(m, l, &x.c);
    x.blocks = st_pool_blocks_newest_first(&m->darts, l, &x.nblocks);
    x.vblocks = st_pool_blocks_newest_first(&m->verts, l, &x.nvblocks);
    x.vcover = vblock_cover(&m->verts, l);
    x.vd = vd;
    x.vd_given = vd != NULL;
    if (!vd) x.vd = malloc(((size_t)x.vcover + 1) * sizeof *x.vd);
    x.dnew = st_block_bits(&m->darts, l);
    x.vnew = m->pos.eff[l] == l ? st_block_bits(&m->verts, l) : NULL;
    if (!x.blocks || !x.vblocks || !x.vd || !x.dnew || (m->pos.eff[l] == l && !x.vnew)) abort(); /* out of memory for a level's scratch */
    if (!vd)
        for (uint32_t v = 0; v < x.vcover; v++) atomic_init(&x.vd[v], ST_NIL);
    uint32_t next_cover = want_next ? vblock_cover(&m->verts, L) : 0;
    if (want_next) {
        x.next_vd = malloc(((size_t)next_cover + 1) * sizeof *x.next_vd);
        if (!x.next_vd) abort(); /* out of memory for a level's scratch */
        memset(x.next_vd, 0xff, ((size_t)next_cover + 1) * sizeof *x.next_vd); /* ST_NIL */
    }
    for (unsigned n = 1; n <= RING_MAX; n++) loop_weights(n, &x.vw[n], &x.ew[n]);
    x.vw[0] = x.ew[0] = 0;
    unsigned threads = st_parallel_threads();
    if (x.nblocks < RING_MIN_BLOCKS_PER_THREAD * threads) threads = x.nblocks / RING_MIN_BLOCKS_PER_THREAD;
    st_team_run(threads ? threads : 1, ring_passes, &x);
    free(x.blocks);
    free(x.vblocks);
    free((void *)x.vd);
    free(x.dnew);
    free(x.vnew);
    /* Every thread wrote its entries before st_team_run returned. */
    return (_Atomic uint32_t *)x.next_vd;
}

static void loop_predict_level(st_hier *h, unsigned L)
{
    if (!ring_applies(&h->map, L)) { loop_predict_views(h, L); return; }
    ring_level_run(h, L, NULL, 0);
}

/* Levels from+1..to: each level's ring pass leaves the next one a dart per
 * vertex (its own rings and midpoints), which saves that level a pass over
 * its darts. */
static void loop_predict_levels(st_hier *h, unsigned from, unsigned to)
{
    _Atomic uint32_t *vd = NULL;
    for (unsigned L = from + 1; L <= to; L++) {
        if (!ring_applies(&h->map, L)) {
            free((void *)vd);
            vd = NULL;
            loop_predict_views(h, L);
            continue;
        }
        vd = ring_level_run(h, L, vd, L < to && ring_applies(&h->map, L + 1));
    }
    free((void *)vd);
}

static const st_primal_rules loop_rules = { smooth_vertex, smooth_edge, 1, ST_FACE_POINTS_NONE };

static void loop_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    st_primal_emit(h, L, faces, n, sink, ctx, &loop_rules);
}

static int loop_check(st_hier *h, st_error *err) { return st_check_triangles(h, err); }

static int loop_refine(st_hier *h, st_error *err) { return st_hier_refine_primal(h, ST_SPLIT_TRI, err); }

const st_scheme st_scheme_loop = {
    .name = "loop",
    .id = ST_SCHEME_LOOP,
    .interpolating = 0,
    .support_rings = 1,
    .check = loop_check,
    .refine = loop_refine,
    .emit = loop_emit,
    .predict_level = loop_predict_level,
    .predict_levels = loop_predict_levels,
};
