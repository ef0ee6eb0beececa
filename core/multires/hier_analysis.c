/* Analysis (thesis Algorithm 4): from the finest level down, fit level l-1
 * to level l in the least-squares sense,
 *     P_{l-1} = argmin_x || S x - P_l ||²,
 * then store what remains as details, D_l = F^T (P_l - S P_{l-1}).
 * This minimises the sum of squared detail lengths at each level and gives
 * zero details when P_l is exactly a subdivision of some coarse mesh (S has
 * full column rank for every scheme here: each coarse vertex has an even
 * child or, for √3 and Doo-Sabin, enough children to pin it).  For
 * interpolating schemes S restricted to even vertices is the identity and
 * the fit is exact restriction.  The normal equations S^T S x = S^T P_l are
 * solved by conjugate gradients, warm-started from the current P_{l-1}.
 * The stencils of level l are cached in CSR form for the solve; a
 * Catmull-Clark level that P_{l-1} already predicts to rounding (an exact
 * subdivision) is instead checked and given its details by one streamed
 * pass, without stored stencils (stream_level). */
#include "core/multires/hier_internal.h"
#include "core/base/hugepage.h"
#include "core/map/pool_internal.h"
#include "core/base/parallel.h"
#include "core/schemes/catmark_internal.h"

#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

typedef struct csr {
    uint32_t nrows;           /* fine vertices */
    uint32_t *row_vertex;     /* fine vertex id per row */
    uint32_t *off;            /* nrows + 1 */
    uint32_t *col;            /* coarse vertex ids */
    double *w;
    uint32_t *frame_dart;
    uint8_t *frame_cell;
    uint32_t cap_rows, cap_nz;
} csr;

static void *grow(void *p, size_t n, size_t elem)
{
    void *q = realloc(p, n * elem);
    if (!q) abort(); /* analysis scratch: out of memory is fatal here */
    st_advise_huge(q, n * elem);
    return q;
}

static void csr_sink(void *ctx, const st_stencil *s)
{
    csr *c = ctx;
    if (c->nrows + 1 >= c->cap_rows) {
        c->cap_rows = c->cap_rows ? 2 * c->cap_rows : 1024;
        c->row_vertex = grow(c->row_vertex, c->cap_rows, sizeof *c->row_vertex);
        c->off = grow(c->off, c->cap_rows + 1, sizeof *c->off);
        c->frame_dart = grow(c->frame_dart, c->cap_rows, sizeof *c->frame_dart);
        c->frame_cell = grow(c->frame_cell, c->cap_rows, sizeof *c->frame_cell);
    }
    uint32_t nz = c->off[c->nrows];
    if (nz + s->n > c->cap_nz) {
        while (nz + s->n > c->cap_nz) c->cap_nz = c->cap_nz ? 2 * c->cap_nz : 8192;
        c->col = grow(c->col, c->cap_nz, sizeof *c->col);
        c->w = grow(c->w, c->cap_nz, sizeof *c->w);
    }
    memcpy(c->col + nz, s->src, s->n * sizeof *s->src);
    memcpy(c->w + nz, s->w, s->n * sizeof *s->w);
    c->row_vertex[c->nrows] = s->fine;
    c->frame_dart[c->nrows] = s->frame_dart;
    c->frame_cell[c->nrows] = s->frame_cell;
    c->off[++c->nrows] = nz + s->n;
}

static void csr_free(csr *c)
{
    free(c->row_vertex); free(c->off); free(c->col); free(c->w); free(c->frame_dart); free(c->frame_cell);
}

static void csr_destroy(csr *c)
{
    if (!c) return;
    csr_free(c);
    free(c);
}

/* An empty c with room for rows rows and nz weights. */
static void csr_reserve(csr *c, uint32_t rows, uint32_t nz)
{
    c->cap_rows = rows;
    c->cap_nz = nz;
    c->row_vertex = grow(NULL, c->cap_rows, sizeof *c->row_vertex);
    c->off = grow(NULL, c->cap_rows + 1, sizeof *c->off);
    c->frame_dart = grow(NULL, c->cap_rows, sizeof *c->frame_dart);
    c->frame_cell = grow(NULL, c->cap_rows, sizeof *c->frame_cell);
    c->col = grow(NULL, c->cap_nz, sizeof *c->col);
    c->w = grow(NULL, c->cap_nz, sizeof *c->w);
    c->off[0] = 0;
}

/* The stencils of every vertex of level l, in the scheme's order.  The
 * arrays start at their likely size (a row per vertex id level l can hold,
 * 8 weights a row: Catmull-Clark averages about 6.3), so that a large
 * level is not copied by each doubling. */
static csr *level_stencils(st_hier *h, unsigned l)
{
    csr *c = calloc(1, sizeof *c);
    if (!c) abort();
    uint32_t rows = st_pool_cover(&h->map.verts, l) + 2;
    csr_reserve(c, rows, rows > UINT32_MAX / 8 ? UINT32_MAX : 8 * rows);
    st_hier_emit(h, l, NULL, 0, csr_sink, c);
    return c;
}

/* ---- Catmull-Clark's stencils in emit_all's order, on several threads ----
 *
 * The scheme's emit (faces NULL) goes through the darts of level l = L-1 in
 * enumeration order and, at each dart d, emits the vertex point of vert(d)
 * if no earlier dart of its vertex (β1 orbit) did, the edge point if
 * d < β0(d), then the face point if no earlier dart of its face (φ1 orbit)
 * did, each from d: the dart a stencil starts from decides the order of
 * its entries and so the bits of its sum.  The same choice without
 * markers: a dart emits a vertex or a face point when it comes first, in
 * enumeration order, in that orbit.  So any range of the enumeration emits
 * the stencils emit would give there, in the same order, independently of
 * the other ranges. */
typedef struct dart_order {
    const st_hier *h;
    st_subdiv_view sv;             /* h's, for the scheme's stencils (read only here) */
    unsigned L;
    st_level_view v;               /* the coarse level l = L-1 */
    const uint8_t *ins;
    uint32_t *first, nblocks;      /* first ids of level l's dart blocks, in enumeration order */
    uint32_t *place;               /* per block number: its place in that order */
} dart_order;

static void dart_order_free(dart_order *o)
{
    free(o->first);
    free(o->place);
}

static int dart_order_init(dart_order *o, const st_hier *h, unsigned L)
{
    const st_pool *p = &h->map.darts;
    memset(o, 0, sizeof *o);
    o->h = h;
    o->sv = st_hier_view((st_hier *)h); /* the analysis only reads what the view points to */
    o->L = L;
    o->ins = p->ins;
    st_level_view_init(&h->map, L - 1, &o->v);
    o->nblocks = st_pool_block_list(p, L - 1, NULL);
    o->first = malloc(((size_t)o->nblocks + 1) * sizeof *o->first);
    o->place = malloc(((size_t)(p->end >> ST_POOL_BLOCK_SHIFT) + 1) * sizeof *o->place);
    if (!o->first || !o->place) { dart_order_free(o); return -1; }
    st_pool_block_list(p, L - 1, o->first);
    for (uint32_t i = 0; i < o->nblocks; i++) o->place[o->first[i] >> ST_POOL_BLOCK_SHIFT] = i;
    return 0;
}

/* Place of dart d in the enumeration (blocks hold ST_POOL_BLOCK ids). */
static uint32_t rank_of(const dart_order *o, uint32_t d)
{
    return o->place[d >> ST_POOL_BLOCK_SHIFT] << ST_POOL_BLOCK_SHIFT | (d & (ST_POOL_BLOCK - 1));
}

static int first_of_vertex(const dart_order *o, uint32_t d)
{
    uint32_t r = rank_of(o, d);
    for (uint32_t x = st_v_beta1(&o->v, d); x != d; x = st_v_beta1(&o->v, x))
        if (rank_of(o, x) < r) return 0;
    return 1;
}

static int first_of_face(const dart_order *o, uint32_t d)
{
    uint32_t r = rank_of(o, d);
    for (uint32_t x = st_v_phi1(&o->v, d); x != d; x = st_v_phi1(&o->v, x))
        if (rank_of(o, x) < r) return 0;
    return 1;
}

/* The stencils of the darts of blocks [b, e) of the enumeration, as
 * st_catmark_emit would emit them there (scheme_catmark.c, emit_all). */
static void emit_blocks(const dart_order *o, uint32_t b, uint32_t e, st_catmark_emitter *em, st_stencil_sink sink, void *ctx)
{
    const st_map *m = &o->h->map;
    for (uint32_t i = b; i < e; i++)
        for (uint32_t d = o->first[i]; d < o->first[i] + ST_POOL_BLOCK; d++) {
            if (o->ins[d] == ST_FREE_LEVEL) continue;
            if (first_of_vertex(o, d)) st_catmark_emit_vertex(&o->sv, o->L, d, em, sink, ctx);
            if (d < st_v_beta0(&o->v, d)) st_catmark_emit_edge(&o->sv, o->L, d, em, sink, ctx);
            if (!st_is_boundary(m, d) && first_of_face(o, d)) st_catmark_emit_face(&o->sv, o->L, d, em, sink, ctx);
        }
}

static void emitter_free(st_catmark_emitter *em)
{
    st_stencil_buf_free(&em->buf);
    st_stencil_buf_free(&em->tmp);
}

/* Blocks per piece of the work: 16 blocks of 256 darts, about 4096 rows. */
#define ORDER_CHUNK 16u

/* Threads for a pass over n blocks: one below 64 pieces, where starting
 * threads costs more than it saves. */
static unsigned threads_for(uint32_t nblocks)
{
    unsigned threads = st_parallel_threads(), most = nblocks / (4 * ORDER_CHUNK);
    return threads < most ? threads : most ? most : 1;
}

/* The stored rows, built piece by piece on several threads: piece i holds
 * the stencils of blocks [i·ORDER_CHUNK, (i+1)·ORDER_CHUNK), and the pieces
 * are joined in order, so that the rows are those of
 * level_stencils, in its order, on any number of threads. */
typedef struct csr_job {
    const dart_order *o;
    csr *piece;
    uint32_t npieces;
} csr_job;

static void csr_piece_init(csr *c, uint32_t blocks)
{
    memset(c, 0, sizeof *c);
    uint32_t rows = blocks * ST_POOL_BLOCK + 2;   /* about a row a dart (a quad's 4 darts: 1 + 2 + 1) */
    csr_reserve(c, rows, 8 * rows);
}

static void csr_pieces(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    csr_job *j = ctx;
    st_catmark_emitter em = { 0 };
    uint32_t b, e;
    while (st_team_next(team, 0, j->npieces, 1, &b, &e)) {
        uint32_t lo = b * ORDER_CHUNK, hi = lo + ORDER_CHUNK < j->o->nblocks ? lo + ORDER_CHUNK : j->o->nblocks;
        csr_piece_init(&j->piece[b], hi - lo);
        emit_blocks(j->o, lo, hi, &em, csr_sink, &j->piece[b]);
    }
    emitter_free(&em);
}

static csr *csr_join(csr *piece, uint32_t n)
{
    csr *c = calloc(1, sizeof *c);
    if (!c) abort();
    uint64_t rows = 0, nz = 0;
    for (uint32_t i = 0; i < n; i++) { rows += piece[i].nrows; nz += piece[i].off[piece[i].nrows]; }
    if (nz > UINT32_MAX) abort(); /* as csr_sink's 32-bit offsets */
    csr_reserve(c, (uint32_t)rows + 1, (uint32_t)nz + 1);
    for (uint32_t i = 0; i < n; i++) {
        const csr *p = &piece[i];
        uint32_t r0 = c->nrows, z0 = c->off[r0], pz = p->off[p->nrows];
        memcpy(c->row_vertex + r0, p->row_vertex, p->nrows * sizeof *c->row_vertex);
        memcpy(c->frame_dart + r0, p->frame_dart, p->nrows * sizeof *c->frame_dart);
        memcpy(c->frame_cell + r0, p->frame_cell, p->nrows * sizeof *c->frame_cell);
        memcpy(c->col + z0, p->col, pz * sizeof *c->col);
        memcpy(c->w + z0, p->w, pz * sizeof *c->w);
        for (uint32_t r = 1; r <= p->nrows; r++) c->off[r0 + r] = z0 + p->off[r];
        c->nrows += p->nrows;
    }
    return c;
}

/* level_stencils of a Catmull-Clark level, on several threads. */
static csr *catmark_stencils(st_hier *h, unsigned L)
{
    dart_order o;
    if (dart_order_init(&o, h, L)) abort(); /* analysis scratch, as grow() */
    csr_job j = { &o, NULL, (o.nblocks + ORDER_CHUNK - 1) / ORDER_CHUNK };
    j.piece = calloc((size_t)j.npieces + 1, sizeof *j.piece);
    if (!j.piece) abort();
    st_team_run(threads_for(o.nblocks), csr_pieces, &j);
    csr *c = csr_join(j.piece, j.npieces);
    for (uint32_t i = 0; i < j.npieces; i++) csr_free(&j.piece[i]);
    free(j.piece);
    dart_order_free(&o);
    return c;
}

/* Σ w[k] x[src[k]] from the first entry: the prediction of a fine vertex
 * by its stencil, in the one order both paths (stored rows, streamed
 * stencils) use, so that their details are the same to the bit. */
static void stencil_times(const uint32_t *src, const double *w, uint32_t n, const double *x, double out[3])
{
    double a = 0, b = 0, d = 0;
    for (uint32_t k = 0; k < n; k++) {
        const double *p = x + 3 * (size_t)src[k];
        a += w[k] * p[0]; b += w[k] * p[1]; d += w[k] * p[2];
    }
    out[0] = a; out[1] = b; out[2] = d;
}

/* Row r of S applied to x: the prediction of fine vertex r. */
static void row_times(const csr *c, uint32_t r, const double *x, double out[3])
{
    stencil_times(c->col + c->off[r], c->w + c->off[r], c->off[r + 1] - c->off[r], x, out);
}

/* d = F^T (target - pred), F the rows of a frame. */
static void detail_in_frame(const double fr[3][3], const double target[3], const double pred[3], double d[3])
{
    for (int i = 0; i < 3; i++)
        d[i] = fr[i][0] * (target[0] - pred[0]) + fr[i][1] * (target[1] - pred[1]) + fr[i][2] * (target[2] - pred[2]);
}

/* Row r of S transposed, scaled by y, added into x. */
static void add_row_t(const csr *c, uint32_t r, const double y[3], double *x)
{
    for (uint32_t k = c->off[r]; k < c->off[r + 1]; k++) {
        double *p = x + 3 * (size_t)c->col[k];
        p[0] += c->w[k] * y[0]; p[1] += c->w[k] * y[1]; p[2] += c->w[k] * y[2];
    }
}

/* out = S^T S x (n coarse entries), and, with f, b = S^T f alongside: one
 * pass over the stencils instead of one for S x and one per S^T.  Each
 * entry of out and b receives its terms in the order of the rows, as a
 * product through a stored S x would give, so the sums are the same to
 * the bit. */
static void mul_sts(const csr *c, const double *x, double *out, const double *f, double *b, uint32_t n)
{
    memset(out, 0, 3 * (size_t)n * sizeof *out);
    if (f) memset(b, 0, 3 * (size_t)n * sizeof *b);
    for (uint32_t r = 0; r < c->nrows; r++) {
        double y[3];
        row_times(c, r, x, y);
        if (!f) {
            add_row_t(c, r, y, out);
            continue;
        }
        const double *g = f + 3 * (size_t)r;
        for (uint32_t k = c->off[r]; k < c->off[r + 1]; k++) {
            double *p = out + 3 * (size_t)c->col[k], *q = b + 3 * (size_t)c->col[k], w = c->w[k];
            p[0] += w * y[0]; p[1] += w * y[1]; p[2] += w * y[2];
            q[0] += w * g[0]; q[1] += w * g[1]; q[2] += w * g[2];
        }
    }
}

/* S^T S x on several threads: thread t owns the coarse entries
 * [lo[t], lo[t+1]) and goes through the rows that name one of them, in
 * order, adding only into its own entries.  Every entry receives the same
 * terms in the same order as from mul_sts, so the sums are the same to
 * the bit on any number of threads.  The rows of each part are listed
 * once per level (a row near a part's border is in both lists). */
#define STS_MAX_PARTS 8
typedef struct sts_plan {
    unsigned parts;                        /* 1: mul_sts alone */
    uint32_t lo[STS_MAX_PARTS + 1];
    uint32_t *rows[STS_MAX_PARTS], nrows[STS_MAX_PARTS];
} sts_plan;

/* Levels of fewer rows take one thread: starting threads per product
 * (st_team_run) costs more than it saves there. */
#define STS_MIN_ROWS 65536u

static void sts_plan_init(sts_plan *pl, const csr *c, uint32_t n)
{
    memset(pl, 0, sizeof *pl);
    unsigned threads = st_parallel_threads();
    pl->parts = c->nrows < STS_MIN_ROWS || threads < 2 ? 1 : threads < STS_MAX_PARTS ? threads : STS_MAX_PARTS;
    if (pl->parts == 1) return;
    for (unsigned t = 0; t <= pl->parts; t++) pl->lo[t] = (uint32_t)((uint64_t)n * t / pl->parts);
    for (unsigned t = 0; t < pl->parts; t++) {
        pl->rows[t] = st_malloc_huge(((size_t)c->nrows + 1) * sizeof *pl->rows[t]);
        if (!pl->rows[t]) abort(); /* analysis scratch, as grow() */
    }
    for (uint32_t r = 0; r < c->nrows; r++)
        for (unsigned t = 0; t < pl->parts; t++)
            for (uint32_t k = c->off[r]; k < c->off[r + 1]; k++)
                if (c->col[k] - pl->lo[t] < pl->lo[t + 1] - pl->lo[t]) {
                    pl->rows[t][pl->nrows[t]++] = r;
                    break;
                }
}

static void sts_plan_free(sts_plan *pl)
{
    for (unsigned t = 0; t < STS_MAX_PARTS; t++) free(pl->rows[t]);
}

typedef struct sts_job {
    const csr *c;
    const sts_plan *pl;
    const double *x, *f;
    double *out, *b;
} sts_job;

static void sts_part(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    const sts_job *j = ctx;
    const csr *c = j->c;
    uint32_t part, end;
    while (st_team_next(team, 0, j->pl->parts, 1, &part, &end)) {
        uint32_t lo = j->pl->lo[part], span = j->pl->lo[part + 1] - lo;
        memset(j->out + 3 * (size_t)lo, 0, 3 * (size_t)span * sizeof *j->out);
        if (j->f) memset(j->b + 3 * (size_t)lo, 0, 3 * (size_t)span * sizeof *j->b);
        for (uint32_t i = 0; i < j->pl->nrows[part]; i++) {
            uint32_t r = j->pl->rows[part][i];
            double y[3];
            row_times(c, r, j->x, y);
            const double *g = j->f ? j->f + 3 * (size_t)r : NULL;
            for (uint32_t k = c->off[r]; k < c->off[r + 1]; k++) {
                if (c->col[k] - lo >= span) continue;
                double *p = j->out + 3 * (size_t)c->col[k], w = c->w[k];
                p[0] += w * y[0]; p[1] += w * y[1]; p[2] += w * y[2];
                if (!g) continue;
                double *q = j->b + 3 * (size_t)c->col[k];
                q[0] += w * g[0]; q[1] += w * g[1]; q[2] += w * g[2];
            }
        }
    }
}

static void mul_sts_plan(const csr *c, const sts_plan *pl, const double *x, double *out, const double *f, double *b,
                         uint32_t n)
{
    if (pl->parts == 1) {
        mul_sts(c, x, out, f, b, n);
        return;
    }
    sts_job j = { c, pl, x, f, out, b };
    st_team_run(pl->parts, sts_part, &j);
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

/* CG on S^T S x = S^T f, per component pair summed (the three components
 * share the operator; solving them jointly keeps the code short and the
 * iteration count is set by the worst one).  Returns the relative residual. */
static double solve(const csr *c, const double *f, double *x, uint32_t n)
{
    size_t nn = 3 * (size_t)n;
    double *b = malloc(nn * sizeof *b), *r = malloc(nn * sizeof *r), *p = malloc(nn * sizeof *p);
    double *ap = malloc(nn * sizeof *ap);
    if (!b || !r || !p || !ap) abort();
    sts_plan pl;
    sts_plan_init(&pl, c, n);
    mul_sts_plan(c, &pl, x, r, f, b, n);
    for (size_t i = 0; i < nn; i++) { r[i] = b[i] - r[i]; p[i] = r[i]; }
    double bb = dot(b, b, nn), rr = dot(r, r, nn);
    for (int it = 0; it < 2000 && rr > 1e-30 * bb && rr > 0; it++) {
        mul_sts_plan(c, &pl, p, ap, NULL, NULL, n);
        double pap = dot(p, ap, nn);
        if (pap <= 0) break;
        double alpha = rr / pap, rr2 = 0;
        for (size_t i = 0; i < nn; i++) {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
            rr2 += r[i] * r[i];
        }
        for (size_t i = 0; i < nn; i++) p[i] = r[i] + (rr2 / rr) * p[i];
        rr = rr2;
    }
    sts_plan_free(&pl);
    free(b); free(r); free(p); free(ap);
    return bb > 0 ? sqrt(rr / bb) : 0;
}

/* The details of level l: d = F^T (P_l - S P_{l-1}) per row, with F the
 * frame of level l-1 (positions written, read only here).  Rows are
 * independent: threads share them, each row's bits the same on any. */
typedef struct detail_job {
    const st_hier *h;
    unsigned l;
    const csr *c;
    const double *x, *f;
    double *d;
} detail_job;

static void detail_rows(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    const detail_job *j = ctx;
    uint32_t b, e;
    while (st_team_next(team, 0, j->c->nrows, 2048, &b, &e))
        for (uint32_t r = b; r < e; r++) {
            /* x is level l-1 as just written (st_stencil_eval would read the
             * same doubles back and sum them in the same order). */
            double pred[3], fr[3][3];
            const double *target = j->f + 3 * (size_t)r;
            row_times(j->c, r, j->x, pred);
            st_hier_frame(j->h, j->l - 1, j->c->frame_dart[r], j->c->frame_cell[r], fr);
            detail_in_frame(fr, target, pred, j->d + 3 * (size_t)r);
        }
}

/* The ids a detail array of level l needs: those of the vertices of
 * levels 0..l (st_hier_detail reads zero past an array's end, and
 * st_hier_set_detail grows it), rather than every vertex id of the map:
 * when levels are built coarse to fine the finer levels' ids lie above, and
 * each coarse level's array would be as long as the finest's (spot x4: 4
 * arrays of 24 MB, where 32 MB hold them all). */
static uint32_t detail_ids(const st_hier *h, unsigned l)
{
    return st_pool_cover(&h->map.verts, l + 1);
}

/* Level l's detail array, zeroed by calloc's fresh pages instead of grown
 * from nothing and cleared with memset. */
static void preallocate_details(st_hier *h, unsigned l, const double *dd, uint32_t nrows)
{
    if (h->detail[l]) return;
    size_t i = 0, n = 3 * (size_t)nrows;
    while (i < n && dd[i] == 0) i++;
    if (i == n) return;
    uint32_t cap = detail_ids(h, l);
    double *p = st_calloc_huge(3 * (size_t)cap, sizeof *p);
    if (!p) abort(); /* as st_hier_set_detail */
    h->detail[l] = p;
    h->detail_cap[l] = cap;
}

/* ---- the streamed pass: an exact subdivision without stored stencils ----
 *
 * Where the current level l-1 already predicts level l to rounding (an
 * input that is an exact subdivision, started from the positions
 * unsubdivide's inversion of the rules gave), the solve has nothing to do
 * and the stencils of level l are used once, for the details.  So one pass
 * takes each fine vertex's stencil from the scheme's emitter, as the rows
 * would hold it, forms the prediction with the rows' summation
 * (stencil_times) and the detail in its frame, and measures the residual
 * |f - S x|; it stores no stencil (the finest level's rows are about 100 MB
 * for 750k quads).  If every residual is within the tolerance
 * (stream_tolerance) x is the level's solution and the details are kept:
 * they are the bits the stored rows give from the same x.  Otherwise the
 * level takes the stored rows and the solve.  Rows are independent and the
 * largest residual does not depend on the order it is taken in, so the
 * decision and every bit are the same on any number of threads.  Catmull-
 * Clark only (its emitter is callable per cell). */
typedef struct stream_job {
    const dart_order *o;
    const double *x;               /* level l-1 by vertex id */
    double *d;                     /* details by fine vertex id */
    double tol;
    atomic_int over;               /* a residual above tol was met: the pass stops */
    double worst[ST_PARALLEL_MAX];
    uint64_t rows[ST_PARALLEL_MAX];
} stream_job;

typedef struct stream_worker {
    const stream_job *j;
    double worst;
    uint64_t rows;
} stream_worker;

static void stream_sink(void *ctx, const st_stencil *s)
{
    stream_worker *w = ctx;
    const stream_job *j = w->j;
    const st_hier *h = j->o->h;
    unsigned L = j->o->L;
    const double *target = st_pos(&h->map, s->fine, L);
    double pred[3], fr[3][3];
    stencil_times(s->src, s->w, s->n, j->x, pred);
    for (int i = 0; i < 3; i++) w->worst = fmax(w->worst, fabs(target[i] - pred[i]));
    w->rows++;
    if (w->worst > j->tol) return; /* the level will be solved: no frame to compute */
    st_hier_frame(h, L - 1, s->frame_dart, s->frame_cell, fr);
    detail_in_frame(fr, target, pred, j->d + 3 * (size_t)s->fine);
}

static void stream_part(st_team *team, unsigned t, void *ctx)
{
    stream_job *j = ctx;
    stream_worker w = { j, 0, 0 };
    st_catmark_emitter em = { 0 };
    uint32_t b, e;
    while (!atomic_load_explicit(&j->over, memory_order_relaxed) && st_team_next(team, 0, j->o->nblocks, ORDER_CHUNK, &b, &e)) {
        emit_blocks(j->o, b, e, &em, stream_sink, &w);
        if (w.worst > j->tol) atomic_store_explicit(&j->over, 1, memory_order_relaxed);
    }
    emitter_free(&em);
    j->worst[t] = w.worst;
    j->rows[t] = w.rows;
}

/* Level L's details by fine vertex id become the level's detail array, as
 * preallocate_details would leave it (detail_ids long, none kept when all
 * are zero). */
static void install_details(st_hier *h, unsigned L, double *d, uint32_t cap)
{
    if (!h->detail[L]) {
        size_t i = 0, n = 3 * (size_t)cap;
        while (i < n && d[i] == 0) i++;
        if (i == n) { free(d); return; }
        h->detail[L] = d;
        h->detail_cap[L] = cap;
        return;
    }
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h->map, L, &it); v != ST_NIL; v = st_vertex_next(&h->map, L, &it))
        st_hier_set_detail(h, L, v, d + 3 * (size_t)v);
    free(d);
}

/* The streamed pass of level L from x (level L-1 by vertex id, as
 * written); returns 1 when x is accepted, its details stored, with the
 * largest residual component in *worst (a lower bound when 0 is
 * returned: the pass stops at the first row above tol). */
static int stream_level(st_hier *h, unsigned L, const double *x, double tol, double *worst)
{
    dart_order o;
    *worst = 0;
    if (dart_order_init(&o, h, L)) return 0;
    uint32_t cap = detail_ids(h, L);
    double *d = st_calloc_huge(3 * (size_t)cap + 3, sizeof *d);
    stream_job *j = calloc(1, sizeof *j);
    if (!d || !j) { free(d); free(j); dart_order_free(&o); return 0; }
    j->o = &o;
    j->x = x;
    j->d = d;
    j->tol = tol;
    atomic_init(&j->over, 0);
    st_team_run(threads_for(o.nblocks), stream_part, j);
    uint64_t rows = 0;
    for (unsigned t = 0; t < ST_PARALLEL_MAX; t++) { rows += j->rows[t]; *worst = fmax(*worst, j->worst[t]); }
    int accept = !atomic_load(&j->over) && *worst <= tol && rows == st_pool_count(&h->map.verts, L);
    if (accept) install_details(h, L, d, cap);
    else free(d);
    free(j);
    dart_order_free(&o);
    return accept;
}

/* The tolerance of the streamed pass: TOL_ULPS units of rounding
 * (DBL_EPSILON) of the level's scale, the larger of its bounding-box
 * diagonal and its largest coordinate (rounding is relative to the
 * coordinates, and a mesh far from the origin is predicted no better).
 * An exact subdivision computed in doubles is predicted by the coarse
 * positions it came from, or by those unsubdivide recovers from it, to a
 * few ulps: 1 to 9 on the finest two levels of the shared cages subdivided
 * 2 to 4 times, where the solve from the same x takes 0 steps (its test,
 * ||S^T r|| <= 1e-15 ||S^T f||, weighs every row, not the largest).  Lower
 * levels, whose starting positions went through more inversions, show 13
 * to 140 ulps and take 2 to 5 steps, which change x by about the residual
 * (the least-squares correction (S^T S)^-1 S^T r of these well-conditioned
 * S): 16 ulps accepts the former and sends most of the latter to the
 * solve; a level accepted where the solve would have moved x differs from
 * it by ~1e-14 of the scale (capsule x3: level 0 by 3.4e-15 of the
 * diagonal).  Levels with noise above rounding are far above it. */
#define TOL_ULPS 16.0

static double analyze_level(st_hier *h, unsigned l, int may_stream, st_analysis_report *rep)
{
    st_map *m = &h->map;
    st_dart_iter it;
    /* x holds level l-1 by vertex id, up to its largest id rather than the
     * map's (zeroing the rest cost 2 % of the analysis). */
    uint32_t nx = 0;
    for (uint32_t v = st_vertex_first(m, l - 1, &it); v != ST_NIL; v = st_vertex_next(m, l - 1, &it))
        if (v >= nx) nx = v + 1;
    double *x = calloc(3 * (size_t)nx + 1, sizeof *x), lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    if (!x) abort();
    for (uint32_t v = st_vertex_first(m, l - 1, &it); v != ST_NIL; v = st_vertex_next(m, l - 1, &it)) {
        const double *p = st_pos(m, v, l - 1);
        memcpy(x + 3 * (size_t)v, p, 3 * sizeof *x);
        for (int i = 0; i < 3; i++) { lo[i] = fmin(lo[i], p[i]); hi[i] = fmax(hi[i], p[i]); }
    }
    if (may_stream && h->scheme->id == ST_SCHEME_CATMARK && nx) {
        double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
        double scale = diag;
        for (int i = 0; i < 3; i++) scale = fmax(scale, fmax(fabs(lo[i]), fabs(hi[i])));
        double worst = 0, tol = TOL_ULPS * DBL_EPSILON * scale;
        int ok = scale > 0 && isfinite(scale) && stream_level(h, l, x, tol, &worst);
        if (rep) { rep->streamed[l] = (uint8_t)ok; rep->row_residual[l] = scale > 0 ? worst / scale : 0; }
        if (ok) { free(x); return scale > 0 ? worst / scale : 0; }
    }
    /* stored_only (!may_stream) is the reference: the scheme's emit itself. */
    csr *cp = may_stream && h->scheme->id == ST_SCHEME_CATMARK ? catmark_stencils(h, l) : level_stencils(h, l), c = *cp;
    /* The solve runs over the coarse ids the stencils name, not every
     * vertex id of the map (the finer levels' ids lie above them when
     * levels are built coarse to fine): the vectors of the CG shrink
     * fourfold per level below the top, with the same bits, as the ids
     * left out have no column and so stay as they were. */
    uint32_t ncol = 0;
    for (uint32_t k = 0; k < c.off[c.nrows]; k++)
        if (c.col[k] >= ncol) ncol = c.col[k] + 1;
    if (ncol > nx) abort(); /* a stencil names a vertex level l-1 lacks: no valid map */
    double *f = malloc((3 * (size_t)c.nrows + 1) * sizeof *f);
    if (!f) abort();
    for (uint32_t r = 0; r < c.nrows; r++) memcpy(f + 3 * (size_t)r, st_pos(m, c.row_vertex[r], l), 3 * sizeof *f);
    double res = solve(&c, f, x, ncol ? ncol : 1);
    /* New level l-1, then level l rewritten exactly (it may have inherited
     * from l-1) with details re-expressed against the new coarse surface. */
    for (uint32_t v = st_vertex_first(m, l - 1, &it); v != ST_NIL; v = st_vertex_next(m, l - 1, &it))
        st_hier_write_pos(h, v, l - 1, x + 3 * (size_t)v);
    double *dd = malloc((3 * (size_t)c.nrows + 1) * sizeof *dd);
    if (!dd) abort();
    detail_job job = { h, l, &c, x, f, dd };
    unsigned threads = st_parallel_threads(), most = c.nrows / 8192u;   /* at least 8192 rows a thread */
    st_team_run(threads < most ? threads : most ? most : 1, detail_rows, &job);
    preallocate_details(h, l, dd, c.nrows);
    for (uint32_t r = 0; r < c.nrows; r++) {
        st_hier_set_detail(h, l, c.row_vertex[r], dd + 3 * (size_t)r);
        st_hier_write_pos(h, c.row_vertex[r], l, f + 3 * (size_t)r);
    }
    free(dd);
    free(x);
    free(f);
    csr_destroy(cp);
    return res;
}

double st_hier_analyze_ex(st_hier *h, unsigned to, int stored_only, st_analysis_report *rep)
{
    if (rep) memset(rep, 0, sizeof *rep);
    double worst = 0;
    for (unsigned l = h->map.top; l > to; l--) {
        double r = analyze_level(h, l, !stored_only, rep);
        if (r > worst) worst = r;
    }
    return worst;
}

double st_hier_analyze(st_hier *h, unsigned to) { return st_hier_analyze_ex(h, to, 0, NULL); }
