/* Loop (1987) on triangle meshes, with OpenSubdiv 3.5's boundary, corner
 * and semi-sharp crease rules (crease.h; Sdc::Scheme<SCHEME_LOOP>,
 * sdc/loopScheme.h).  Masks (Kraemer 2008 §3.2.1, fig. 3.14, listing 3.2.1):
 *   edge point   = 3/8 (a + b) + 1/8 (c + d), c and d opposite the edge;
 *   vertex point = (1 - nβ) v + β Σ neighbours, Loop's original
 *                  β = (1/n) (5/8 - (3/8 + cos(2π/n) / 4)²),
 *                  exactly 1/16 (and 5/8 for v) at valence 6.
 * The weights are computed with OpenSubdiv's own expression order
 * (assignSmoothMaskForVertex) so that both agree to the last bits.
 * Boundaries: boundary edges are infinitely sharp (midpoints, B-spline
 * boundary curves); with edge-and-corner a boundary vertex with one face is
 * a corner.  Topology: triangle quadrisection (refine.c, ST_SPLIT_TRI). */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/primal_emit_internal.h"
#include "core/schemes/crease_internal.h"
#include "core/schemes/synth_internal.h"
#include "core/schemes/synth_blocks_internal.h"
#include "core/schemes/synth_tables_internal.h"
#include "core/base/parallel.h"
#include "core/map/pool_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Vertex opposite the edge of d in d's triangle (level l). */
static uint32_t opposite(const st_map *m, uint32_t d, unsigned l)
{
    return st_vert(m, st_phi1(m, st_phi1(m, d, l), l), l);
}

/* Only called for edges with two real faces (boundary edges are sharp). */
static void smooth_edge(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = sv->map;
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
static void smooth_vertex(const st_subdiv_view *sv, unsigned l, uint32_t d, st_stencil_buf *out)
{
    const st_map *m = sv->map;
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
    const st_subdiv_view *sv;
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
    st_stencil_eval(x->sv->map, x->L, &s, slot(x, fine));
}

static int sharp_edge(const loop_fast *x, uint32_t d, uint32_t e)
{
    const st_map *m = x->sv->map;
    return st_is_boundary(m, d) || st_is_boundary(m, e) ||
           (x->sv->has_sharpness && st_subdiv_edge_sharpness(x->sv, d, x->L - 1) > 0);
}

static void axpy(double *acc, double w, const double *p)
{
    acc[0] += w * p[0]; acc[1] += w * p[1]; acc[2] += w * p[2];
}

static void fast_edge(loop_fast *x, uint32_t d, uint32_t e)
{
    uint32_t mid = st_v_vert(&x->f, st_v_beta0(&x->f, d));
    if (sharp_edge(x, d, e)) {
        st_crease_edge_point(x->sv, x->L - 1, d, smooth_edge, &x->buf, &x->tmp);
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
    int smooth = !x->sv->has_sharpness || st_subdiv_vertex_sharpness(x->sv, v, x->L - 1) <= 0;
    do {
        if (sharp_edge(x, y, st_v_beta0(c, y))) smooth = 0;
        n++;
        y = st_v_beta1(c, y);
    } while (y != d);
    if (!smooth) {
        st_crease_vertex_point(x->sv, x->L - 1, d, smooth_vertex, &x->buf, &x->tmp);
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

/* Level views and a stamp per vertex: any map (used when the tables below
 * do not apply). */
static void loop_predict_views(const st_subdiv_view *sv, unsigned L)
{
    st_map *m = sv->map;
    loop_fast x = { .sv = sv, .L = L };
    x.pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    x.pnew = (double *)m->pos.base;
    if (!x.pold) abort(); /* out of memory for a level's positions */
    st_level_view_init(m, L - 1, &x.c);
    st_level_view_init(m, L, &x.f);
    uint32_t gen = st_subdiv_stamp_begin(sv), *stamp = sv->stamp->v;
    const st_pool *p = &m->darts;
    for (unsigned lv = L; lv-- > 0;)
        for (uint32_t b = 0; b < p->nblocks[lv]; b++) {
            uint32_t first = p->blocks[lv][b] << ST_POOL_BLOCK_SHIFT;
            for (uint32_t d = first; d < first + ST_POOL_BLOCK; d++) {
                if (p->ins[d] == ST_FREE_LEVEL) continue;
                uint32_t e = st_v_beta0(&x.c, d), v = st_v_vert(&x.c, d);
                if (d < e) fast_edge(&x, d, e);
                if (stamp[v] != gen) { stamp[v] = gen; fast_vertex(&x, d); }
            }
        }
    st_stencil_buf_free(&x.buf);
    st_stencil_buf_free(&x.tmp);
}

/* ---- tables --------------------------------------------------------------------
 * Full-level synthesis by index tables cached per level (synth_tables.h;
 * the design: catmark_fast.c), records read off each vertex ring of level
 * l: with the ring darts y_0 .. y_{n-1} (β1 order) and u_j = vert(β0 y_j),
 * the face of y_j is (v, u_j, u_{j-1}) and that of β0(y_j) is
 * (u_j, v, u_{j+1}), so
 *   vertex v   vdata: ref v, then ref u_j for j from the smallest dart:
 *              vw(n) P(v) + Σ ew(n) P(u_j), summed in that order;
 *   edge y_j   (the ring of the end whose dart is the smaller one) 5 words:
 *              ref v, ref u_j, ref u_{j-1}, ref u_{j+1}, midpoint id:
 *              3/8 P(v) + 3/8 P(u_j) + 1/8 P(u_{j-1}) + 1/8 P(u_{j+1}),
 *   the order of fast_edge and fast_vertex, so the tables give their bits.
 * Special cells (a ring touching a hole, sharpness) keep a dart for the
 * stencil path; vertices on no real face are copied.  A level that is not
 * the triangle split (β1 or vert with a column at l, a midpoint not new at
 * L) is irregular: loop_predict_views does it. */

#define RING_MAX 32u          /* valences with precomputed weights */

typedef struct lbuild {
    const st_subdiv_view *sv;
    unsigned l, L;
    st_level_view c;                 /* coarse level l */
    const uint32_t *b0L, *b1, *vt;   /* β0 column of L; base β1 and vert (no column at l) */
    uint32_t *vd;                    /* per coarse vertex: one of its darts, ST_NIL if none */
    uint64_t *vnew;                  /* block bits of level l's vertices when positions have a level-l column */
    st_synth_table *t;
    u32vec ring, twin;               /* scratch: a ring and the twins of its darts */
    int irregular;
} lbuild;

static uint32_t lref(const lbuild *x, uint32_t v) { return st_synth_ref(&x->c, x->vnew, v); }

static int ring_sharp(const st_subdiv_view *sv, uint32_t d, unsigned l) { return sv->has_sharpness && st_subdiv_edge_sharpness(sv, d, l) > 0; }

static void build_vertex(lbuild *x, uint32_t v)
{
    st_synth_table *t = x->t;
    const uint8_t *flags = x->sv->map->flags;
    uint32_t d = x->vd[v];
    if (d == ST_NIL) { vec_push(&t->copy, lref(x, v)); return; }
    x->ring.n = x->twin.n = 0;
    int special = x->sv->has_sharpness && st_subdiv_vertex_sharpness(x->sv, v, x->l) > 0;
    uint32_t y = d;
    do {
        /* The face of β0(y_j) is that of y_{j+1}: the ring darts' flags say
         * which edges touch a hole. */
        special |= (flags[y] & ST_DART_BOUNDARY) || ring_sharp(x->sv, y, x->l);
        vec_push(&x->ring, y);
        vec_push(&x->twin, st_v_beta0(&x->c, y));
        y = x->b1[y];
    } while (y != d);
    const uint32_t *r = x->ring.a, *e = x->twin.a;
    unsigned n = (unsigned)x->ring.n, lo = 0;
    for (unsigned j = 1; j < n; j++) lo = r[j] < r[lo] ? j : lo;
    if (special) {
        vec_push(&t->svert, r[lo]);
    } else {
        if (!t->voff.n) vec_push(&t->voff, 0);
        vec_push(&t->vdata, lref(x, v));
        for (unsigned i = 0, j = lo; i < n; i++, j = j + 1 < n ? j + 1 : 0) vec_push(&t->vdata, lref(x, x->vt[e[j]]));
        vec_push(&t->voff, (uint32_t)t->vdata.n);
    }
    for (unsigned j = 0; j < n; j++) {
        if (r[j] > e[j]) continue;
        unsigned jn = j + 1 < n ? j + 1 : 0, jp = j ? j - 1 : n - 1;
        uint32_t mid = x->vt[x->b0L[r[j]]];
        if (x->c.vins[mid] != x->L) { x->irregular = 1; return; }
        if (special && (((flags[r[j]] | flags[r[jn]]) & ST_DART_BOUNDARY) || ring_sharp(x->sv, r[j], x->l))) {
            vec_push(&t->sedge, r[j]);
            continue;
        }
        uint32_t rec[5] = { lref(x, v), lref(x, x->vt[e[j]]), lref(x, x->vt[e[jp]]), lref(x, x->vt[e[jn]]), mid };
        for (int k = 0; k < 5; k++) vec_push(&t->edge, rec[k]);
    }
}

/* Whether level L is the triangle split tables describe: β1 and vert read
 * from their base arrays, β0 at l and at L from their columns. */
static int tables_apply(const st_map *m, unsigned L)
{
    unsigned l = L - 1;
    return m->beta0.col[L] && !m->beta1.eff[l] && !m->vert.eff[l] && m->beta0.eff[l] == l;
}

static int loop_build(const st_subdiv_view *sv, unsigned L, st_synth_table *t)
{
    st_map *m = sv->map;
    if (!tables_apply(m, L)) return 1;
    lbuild x = { .sv = sv, .l = L - 1, .L = L, .t = t };
    x.b0L = (const uint32_t *)m->beta0.col[L];
    x.b1 = (const uint32_t *)m->beta1.base;
    x.vt = (const uint32_t *)m->vert.base;
    st_level_view_init(m, x.l, &x.c);
    uint32_t nblocks, nvblocks;
    uint32_t *blocks = st_pool_blocks_newest_first(&m->darts, x.l, &nblocks);
    uint32_t *vblocks = st_pool_blocks_newest_first(&m->verts, x.l, &nvblocks);
    x.vd = malloc(((size_t)m->verts.end + 1) * sizeof *x.vd);
    x.vnew = m->pos.eff[x.l] == x.l ? st_block_bits(&m->verts, x.l) : NULL;
    if (!blocks || !vblocks || !x.vd || (m->pos.eff[x.l] == x.l && !x.vnew)) abort(); /* out of memory for a level's scratch */
    memset(x.vd, 0xff, ((size_t)m->verts.end + 1) * sizeof *x.vd); /* ST_NIL */
    uint64_t darts = st_pool_count(&m->darts, x.l), verts = st_pool_count(&m->verts, x.l);
    vec_reserve(&t->edge, 5 * (size_t)(darts / 2) + 5);
    vec_reserve(&t->vdata, (size_t)(darts + verts) + 1);
    vec_reserve(&t->voff, (size_t)verts + 2);
    for (uint32_t i = 0; i < nblocks; i++)
        for (uint32_t d = blocks[i]; d < blocks[i] + ST_POOL_BLOCK; d++)
            if (m->darts.ins[d] != ST_FREE_LEVEL) x.vd[x.vt[d]] = d;
    for (uint32_t i = 0; i < nvblocks && !x.irregular; i++)
        for (uint32_t v = vblocks[i]; v < vblocks[i] + ST_POOL_BLOCK && !x.irregular; v++)
            if (m->verts.ins[v] != ST_FREE_LEVEL) build_vertex(&x, v);
    free(blocks);
    free(vblocks);
    free(x.vd);
    free(x.vnew);
    free(x.ring.a);
    free(x.twin.a);
    return x.irregular;
}

typedef struct leval {
    const st_subdiv_view *sv;
    unsigned l, L;
    const st_synth_table *t;
    const double *pbase, *pcol;      /* level-l positions: base, column */
    double *pnew, *pold;             /* level-L positions: new vertices, old vertices */
    double vw[RING_MAX + 1], ew[RING_MAX + 1];
} leval;

typedef struct lworker { const leval *x; loop_fast s; } lworker;

static const double *lpos(const leval *x, uint32_t r) { return st_synth_ref_pos(x->pbase, x->pcol, r); }

static void vertex_item(lworker *w, uint32_t i)
{
    const leval *x = w->x;
    const st_synth_table *t = x->t;
    uint32_t nv = st_synth_count(&t->voff), ns = (uint32_t)t->svert.n;
    if (i < nv) {
        const uint32_t *r = t->vdata.a + t->voff.a[i];
        unsigned n = t->voff.a[i + 1] - t->voff.a[i] - 1;
        double vw, ew, acc[3] = { 0, 0, 0 };
        if (n <= RING_MAX) { vw = x->vw[n]; ew = x->ew[n]; }
        else loop_weights(n, &vw, &ew);
        axpy(acc, vw, lpos(x, r[0]));
        for (unsigned j = 1; j <= n; j++) axpy(acc, ew, lpos(x, r[j]));
        memcpy(x->pold + 3 * (size_t)(r[0] & REF_ID), acc, sizeof acc);
        return;
    }
    i -= nv;
    if (i < ns) {
        loop_fast *s = &w->s;
        uint32_t d = t->svert.a[i];
        st_crease_vertex_point(s->sv, x->l, d, smooth_vertex, &s->buf, &s->tmp);
        write_stencil(s, st_v_vert(&s->c, d), d, ST_CELL_VERTEX);
        return;
    }
    uint32_t r = t->copy.a[i - ns];
    memcpy(x->pold + 3 * (size_t)(r & REF_ID), lpos(x, r), 3 * sizeof(double));
}

static void edge_item(lworker *w, uint32_t i)
{
    const leval *x = w->x;
    const st_synth_table *t = x->t;
    uint32_t ne = (uint32_t)(t->edge.n / 5);
    if (i < ne) {
        const uint32_t *r = t->edge.a + 5 * (size_t)i;
        double acc[3] = { 0, 0, 0 };
        axpy(acc, 0.375, lpos(x, r[0]));
        axpy(acc, 0.375, lpos(x, r[1]));
        axpy(acc, 0.125, lpos(x, r[2]));
        axpy(acc, 0.125, lpos(x, r[3]));
        memcpy(x->pnew + 3 * (size_t)r[4], acc, sizeof acc);
        return;
    }
    loop_fast *s = &w->s;
    uint32_t d = t->sedge.a[i - ne];
    st_crease_edge_point(s->sv, x->l, d, smooth_edge, &s->buf, &s->tmp);
    write_stencil(s, st_v_vert(&s->f, st_v_beta0(&s->f, d)), d, ST_CELL_EDGE);
}

/* Vertex and edge points write different slots and read level l only. */
static void eval_passes(st_team *team, unsigned tid, void *ctx)
{
    (void)tid;
    const leval *x = ctx;
    const st_synth_table *t = x->t;
    lworker w = { .x = x, .s = { .sv = x->sv, .L = x->L, .pnew = x->pnew, .pold = x->pold } };
    st_level_view_init(x->sv->map, x->l, &w.s.c);
    st_level_view_init(x->sv->map, x->L, &w.s.f);
    uint32_t b, e, nv = st_synth_count(&t->voff) + (uint32_t)(t->svert.n + t->copy.n), ne = (uint32_t)(t->edge.n / 5 + t->sedge.n);
    while (st_team_next(team, 0, nv, ST_SYNTH_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++) vertex_item(&w, i);
    while (st_team_next(team, 1, ne, ST_SYNTH_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++) edge_item(&w, i);
    st_stencil_buf_free(&w.s.buf);
    st_stencil_buf_free(&w.s.tmp);
}

static void loop_predict_level(const st_subdiv_view *sv, unsigned L)
{
    st_map *m = sv->map;
    /* The first synthesis after a change walks the level (the same bits as
     * the tables, above): building the tables costs more than the walk
     * (koala, Loop depth 3: first synthesis 1.47 s -> 1.24 s of processor
     * time, medians under load), and the next synthesis builds them. */
    if (st_synth_tables_defer(sv, L, ST_SCHEME_LOOP)) { loop_predict_views(sv, L); return; }
    const st_synth_table *t = st_synth_tables_for(sv, L, ST_SCHEME_LOOP, loop_build);
    if (t->irregular) { loop_predict_views(sv, L); return; }
    leval x = { .sv = sv, .l = L - 1, .L = L, .t = t };
    x.pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    if (!x.pold) abort(); /* out of memory for a level's positions */
    x.pnew = (double *)m->pos.base;
    x.pbase = (const double *)m->pos.base;
    x.pcol = (const double *)m->pos.col[t->plvl];
    for (unsigned n = 1; n <= RING_MAX; n++) loop_weights(n, &x.vw[n], &x.ew[n]);
    x.vw[0] = x.ew[0] = 0;
    st_synth_run(st_synth_count(&t->voff) + t->edge.n / 5, eval_passes, &x);
}

static const st_primal_rules loop_rules = { smooth_vertex, smooth_edge, 1, ST_FACE_POINTS_NONE };

static void loop_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    st_primal_emit(sv, L, faces, n, sink, ctx, &loop_rules);
}

static int loop_check(const st_subdiv_view *sv, st_error *err) { return st_check_triangles(sv, "loop", err); }

static int loop_refine(const st_subdiv_view *sv, st_error *err) { return st_subdiv_refine_primal(sv, ST_SPLIT_TRI, err); }

const st_scheme st_scheme_loop = {
    .name = "loop",
    .id = ST_SCHEME_LOOP,
    .interpolating = 0,
    .support_rings = 1,
    .check = loop_check,
    .refine = loop_refine,
    .emit = loop_emit,
    .predict_level = loop_predict_level,
};
