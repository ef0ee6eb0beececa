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

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pool.h"

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

static void loop_predict_level(st_hier *h, unsigned L)
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
    for (unsigned lv = 0; lv < L; lv++)
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
};
