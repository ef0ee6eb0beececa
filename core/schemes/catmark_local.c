/* Catmull-Clark local re-synthesis of one level (scheme.h predict_around,
 * called by st_hier_move) when the level has no details: the points of the
 * faces around the changed vertices, with the arithmetic of the full-level
 * synthesis (catmark_tables.h) and from the same start darts, so that a
 * local edit and a full synthesis give the same bits.
 *
 * It reads the face points of faces outside the region from level L itself:
 * with no details at L, P_L = S(P_{L-1}) (hier.h), and those faces' corners
 * did not change (the region holds every face around a changed vertex).
 * Faces are told apart by their points' stamps: no marks to set and clear.
 *
 * It needs the level's tables (built here when stale, once per topology
 * change): when they are irregular (an adaptive level) it gives up before
 * writing anything, and the stencils do the level. */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/catmark_tables_internal.h"

/* Regular tables at l (catmark_fast.c) prove that every face of l has its
 * point at L and every edge its midpoint: nothing can fail, so points are
 * computed and written at once, face points first (edges and vertices read
 * them back from level L). */
typedef struct direct {
    st_hier *h;
    const st_map *m;
    unsigned l, L;
    uint32_t gen;
    st_level_view c;
    const uint32_t *b0L, *b1, *b0, *vt; /* β0 column of L; base relations (darts new at L, plain ones) */
    int plain;                          /* β1 and vert have no column at l (primal splits keep them) */
    const double *pL;                   /* level-L positions of the vertices new at L */
    st_synth_ctx *out;
    st_catmark_emitter e;
    u32vec faces;                       /* per face: dart, centre */
    u32vec walk;                        /* scratch: a face or a ring */
} direct;

static uint32_t direct_centre_dart(const direct *x, uint32_t d) { return x->b0[x->b1[x->b0L[d]]]; }
static const double *direct_face_point(const direct *x, uint32_t d) { return x->pL + 3 * (size_t)x->vt[direct_centre_dart(x, d)]; }
static uint32_t d_beta1(const direct *x, uint32_t d) { return x->plain ? x->b1[d] : st_v_beta1(&x->c, d); }
static uint32_t d_vert(const direct *x, uint32_t d) { return x->plain ? x->vt[d] : st_v_vert(&x->c, d); }
static uint32_t d_phi1(const direct *x, uint32_t d) { return d_beta1(x, st_v_beta0(&x->c, d)); }
static int direct_hole(const direct *x, uint32_t d) { return (x->m->flags[d] & ST_DART_BOUNDARY) != 0; }
static int direct_sharp(const direct *x, uint32_t d) { return x->h->has_sharpness && st_hier_edge_sharpness(x->h, d, x->l) > 0; }

/* The corner the tables start a face at (catmark_fast.c), in the face's
 * corners y[0..k): on a level l >= 1 of the polygon split (which regular
 * tables prove), the dart before the face's one dart older than l; at level
 * 0 the smallest. */
static unsigned direct_start(const direct *x, const uint32_t *y, unsigned k)
{
    unsigned best = 0;
    for (unsigned i = 0; i < k; i++) {
        if (x->l > 0 && x->c.ins[y[i]] < x->l) return i ? i - 1 : k - 1;
        best = y[i] < y[best] ? i : best;
    }
    return best;
}

static void direct_face(direct *x, uint32_t c)
{
    uint32_t cd = direct_centre_dart(x, c), centre = x->vt[cd];
    if (x->h->stamp[centre] == x->gen) return;
    uint32_t z = c;
    x->walk.n = 0;
    do { vec_push(&x->walk, z); z = d_phi1(x, z); } while (z != c);
    const uint32_t *y = x->walk.a;
    unsigned k = (unsigned)x->walk.n, s = direct_start(x, y, k);
    double f[3] = { 0, 0, 0 }, out[3];
    for (unsigned i = 0, j = s; i < k; i++, j = j + 1 < k ? j + 1 : 0) st_cc_face_add(f, st_v_pos(&x->c, d_vert(x, y[j])));
    st_cc_face_finish(f, k, out);
    st_synth_put(x->out, centre, cd, out);
    vec_push(&x->faces, c);
    vec_push(&x->faces, centre);
}

static void direct_edge(direct *x, uint32_t d, uint32_t centre)
{
    uint32_t md = x->b0L[d], mid = x->vt[md];
    if (x->h->stamp[mid] == x->gen) return;
    uint32_t e = st_v_beta0(&x->c, d);
    if (direct_hole(x, d) || direct_hole(x, e) || direct_sharp(x, d) || st_catmark_tri_edge(x->h, d, x->l)) {
        /* from the smaller dart, as the tables: the stencil's order, its bits */
        st_catmark_emit_edge(x->h, x->L, d < e ? d : e, &x->e, st_synth_sink, x->out);
        return;
    }
    double out[3];
    st_cc_edge_mix(st_v_pos(&x->c, d_vert(x, d)), st_v_pos(&x->c, d_vert(x, e)), x->pL + 3 * (size_t)centre,
                   direct_face_point(x, e), out);
    st_synth_put(x->out, mid, md, out);
}

static void direct_vertex(direct *x, uint32_t d)
{
    uint32_t v = d_vert(x, d);
    if (x->h->stamp[v] == x->gen) return;
    int special = x->h->has_sharpness && st_hier_vertex_sharpness(x->h, v, x->l) > 0;
    uint32_t y = d;
    unsigned n = 0, lo = 0;
    x->walk.n = 0;
    do {
        special |= direct_hole(x, y) || direct_sharp(x, y);
        lo = (n == 0 || y < x->walk.a[lo]) ? n : lo;
        vec_push(&x->walk, y);
        n++;
        y = d_beta1(x, y);
    } while (y != d);
    const uint32_t *r = x->walk.a;
    if (special) {
        st_catmark_emit_vertex(x->h, x->L, r[lo], &x->e, st_synth_sink, x->out);
        return;
    }
    double s[3] = { 0, 0, 0 }, out[3];
    for (unsigned i = 0, j = lo; i < n; i++, j = j + 1 < n ? j + 1 : 0)
        st_cc_vertex_add(s, st_v_pos(&x->c, d_vert(x, st_v_beta0(&x->c, r[j]))), direct_face_point(x, r[j]));
    st_cc_vertex_finish(st_v_pos(&x->c, v), s, n, out);
    st_synth_put(x->out, v, d, out);
}

static void predict_direct(st_hier *h, unsigned L, const uint32_t *seeds, uint32_t n, st_synth_ctx *out)
{
    const st_map *m = &h->map;
    direct x = { .h = h, .m = m, .l = L - 1, .L = L, .gen = out->gen, .out = out };
    st_level_view_init(m, x.l, &x.c);
    x.b0L = (const uint32_t *)m->beta0.col[L];
    x.b0 = (const uint32_t *)m->beta0.base;
    x.b1 = (const uint32_t *)m->beta1.base;
    x.vt = (const uint32_t *)m->vert.base;
    x.pL = (const double *)m->pos.base;
    x.plain = m->beta1.eff[x.l] == 0 && m->vert.eff[x.l] == 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t y = seeds[i];
        do {
            if (!direct_hole(&x, y)) direct_face(&x, y);
            y = d_beta1(&x, y);
        } while (y != seeds[i]);
    }
    for (size_t i = 0; i < x.faces.n; i += 2) {
        uint32_t c = x.faces.a[i], centre = x.faces.a[i + 1], y = c;
        do {
            direct_edge(&x, y, centre);
            direct_vertex(&x, y);
            y = d_phi1(&x, y);
        } while (y != c);
    }
    free(x.faces.a);
    free(x.walk.a);
    st_stencil_buf_free(&x.e.buf);
    st_stencil_buf_free(&x.e.tmp);
}

int st_catmark_predict_around(st_hier *h, unsigned L, const uint32_t *seeds, uint32_t n, st_synth_ctx *out)
{
    if (!h->map.beta0.col[L] || st_cc_tables_for(h, L)->irregular) return 0;
    predict_direct(h, L, seeds, n, out);
    return 1;
}
