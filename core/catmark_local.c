/* Catmull-Clark local re-synthesis of one level (scheme.h predict_around,
 * called by st_hier_move) when the level has no details: the fine vertices
 * of the faces around the changed vertices are planned as records of the tables of
 * catmark_tables.h, then evaluated by the same code as the full-level
 * synthesis, so that a local edit and a full synthesis give the same bits.
 *
 * It reads the face points of faces outside the region from level L itself:
 * with no details at L, P_L = S(P_{L-1}) (hier.h), and those faces' corners
 * did not change (the region holds every face around a changed vertex).
 *
 * Planning checks the structure first (each face split at L with its centre
 * new at L, each edge by a vertex new at L) and gives up before writing
 * anything when it does not hold (adaptive levels): the stencils do it. */
#include "catmark_tables.h"

typedef struct plan {
    st_hier *h;
    const st_map *m;
    unsigned l, L;
    uint32_t gen;                  /* the caller's stamp generation */
    st_level_view c;               /* coarse level l */
    const uint32_t *b0L;           /* β0 column of level L */
    cc_table t;                    /* records: general faces and vertices, edges, special cells */
    u32vec fdart, edart, vdart;    /* per record: a dart of level L at its fine vertex */
    u32vec walk;                   /* scratch: a face or a ring */
} plan;

static uint32_t ref_of(const plan *p, uint32_t v) { return v | (p->c.vins[v] < p->c.plvl ? REF_COL : 0); }
static int is_hole(const plan *p, uint32_t d) { return (p->m->flags[d] & ST_DART_BOUNDARY) != 0; }

/* Faces are told apart by their points' stamps: no marks to set and
 * clear. */

/* The dart of level L at the centre of coarse dart d's face (refine.c's
 * polygon split), ST_NIL when the face was not split so. */
static uint32_t centre_dart(const plan *p, uint32_t d)
{
    /* β0(d, L) is in the level-L column (d is older than L); the darts
     * after it are new at L: their base values are their level-L ones. */
    const st_map *m = p->m;
    uint32_t x = ((const uint32_t *)m->beta0.base)[((const uint32_t *)m->beta1.base)[p->b0L[d]]];
    return m->verts.ins[((const uint32_t *)m->vert.base)[x]] == p->L ? x : ST_NIL;
}

static uint32_t centre_of(const plan *p, uint32_t d)
{
    uint32_t x = centre_dart(p, d);
    return x == ST_NIL ? ST_NIL : st_vert(p->m, x, p->L);
}

/* The corner the full-level tables start a face of level l at: for l >= 1
 * the one dart new at l whose twin is older (catmark_fast.c); at level 0
 * the smallest dart (the enumeration order, up to rounding). */
static unsigned face_start(const plan *p, const uint32_t *y, unsigned k)
{
    unsigned s = 0;
    for (unsigned i = 0; i < k; i++) {
        if (p->l == 0) { s = y[i] < y[s] ? i : s; continue; }
        if (p->c.ins[y[i]] == p->l && p->c.ins[st_v_beta0(&p->c, y[i])] < p->l) return i;
    }
    return s;
}

/* The face of c, unless planned already (its point's stamp): 1 if planned
 * now, 0 if it was, -1 if not split at L. */
static int plan_face(plan *p, uint32_t c, uint32_t *centre_out)
{
    uint32_t cd = centre_dart(p, c);
    if (cd == ST_NIL) return -1;
    uint32_t centre = ((const uint32_t *)p->m->vert.base)[cd];
    *centre_out = centre;
    if (p->h->stamp[centre] == p->gen) return 0;
    p->h->stamp[centre] = p->gen;
    p->walk.n = 0;
    uint32_t y = c;
    do { vec_push(&p->walk, y); y = st_v_phi1(&p->c, y); } while (y != c);
    unsigned k = (unsigned)p->walk.n, s = face_start(p, p->walk.a, k);
    if (!p->t.foff.n) vec_push(&p->t.foff, 0);
    vec_push(&p->t.fdata, centre);
    for (unsigned i = 0, j = s; i < k; i++, j = j + 1 < k ? j + 1 : 0) vec_push(&p->t.fdata, ref_of(p, st_v_vert(&p->c, p->walk.a[j])));
    vec_push(&p->t.foff, (uint32_t)p->t.fdata.n);
    vec_push(&p->fdart, cd);
    return 1;
}

/* Edge of d, whose face has its point at cd. */
static int plan_edge(plan *p, uint32_t d, uint32_t cd)
{
    uint32_t md = p->b0L[d], mid = ((const uint32_t *)p->m->vert.base)[md]; /* md: new at L */
    if (p->m->verts.ins[mid] != p->L) return -1;
    if (p->h->stamp[mid] == p->gen) return 0;
    uint32_t e = st_v_beta0(&p->c, d);
    if (is_hole(p, d) || is_hole(p, e) || (p->h->has_sharpness && st_hier_edge_sharpness(p->h, d, p->l) > 0)) {
        vec_push(&p->t.sedge, d < e ? d : e); /* from the smaller dart, as the tables; the sink stamps it */
        return 0;
    }
    uint32_t ce = centre_of(p, e);
    if (ce == ST_NIL) return -1;
    p->h->stamp[mid] = p->gen;
    uint32_t r[5] = { ref_of(p, st_v_vert(&p->c, d)), ref_of(p, st_v_vert(&p->c, e)), cd, ce, mid };
    for (int i = 0; i < 5; i++) vec_push(&p->t.edge, r[i]);
    vec_push(&p->edart, md);
    return 0;
}

static int plan_vertex(plan *p, uint32_t d)
{
    uint32_t v = st_v_vert(&p->c, d);
    if (p->h->stamp[v] == p->gen) return 0;
    int special = p->h->has_sharpness && st_hier_vertex_sharpness(p->h, v, p->l) > 0;
    p->walk.n = 0;
    uint32_t y = d;
    do {
        special |= is_hole(p, y) || (p->h->has_sharpness && st_hier_edge_sharpness(p->h, y, p->l) > 0);
        vec_push(&p->walk, y);
        y = st_v_beta1(&p->c, y);
    } while (y != d);
    const uint32_t *r = p->walk.a;
    unsigned n = (unsigned)p->walk.n, m = 0;
    for (unsigned i = 1; i < n; i++) m = r[i] < r[m] ? i : m;
    if (special) { vec_push(&p->t.svert, r[m]); return 0; }
    size_t at = p->t.vdata.n;
    vec_push(&p->t.vdata, ref_of(p, v));
    for (unsigned i = 0, j = m; i < n; i++, j = j + 1 < n ? j + 1 : 0) {
        uint32_t c = centre_of(p, r[j]);
        if (c == ST_NIL) { p->t.vdata.n = at; return -1; }
        vec_push(&p->t.vdata, ref_of(p, st_v_vert(&p->c, st_v_beta0(&p->c, r[j]))));
        vec_push(&p->t.vdata, c);
    }
    p->h->stamp[v] = p->gen;
    if (!p->t.voff.n) vec_push(&p->t.voff, 0);
    vec_push(&p->t.voff, (uint32_t)p->t.vdata.n);
    vec_push(&p->vdart, d);
    return 0;
}

static void plan_free(plan *p)
{
    u32vec *v[] = { &p->t.quad, &p->t.foff, &p->t.fdata, &p->t.edge, &p->t.sedge, &p->t.v4, &p->t.voff, &p->t.vdata,
                    &p->t.svert, &p->t.copy, &p->fdart, &p->edart, &p->vdart, &p->walk };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) free(v[i]->a);
}

/* The faces around the seeds' vertices, each once, then their edges and
 * corners. */
static int plan_region(plan *p, const uint32_t *seeds, uint32_t nseeds)
{
    u32vec faces = { 0 }, centres = { 0 };
    int rc = 0;
    for (uint32_t i = 0; i < nseeds && rc >= 0; i++) {
        uint32_t x = seeds[i], centre;
        do {
            if (!is_hole(p, x) && (rc = plan_face(p, x, &centre)) > 0) {
                vec_push(&faces, x);
                vec_push(&centres, centre);
            }
            x = st_v_beta1(&p->c, x);
        } while (x != seeds[i] && rc >= 0);
    }
    rc = rc < 0 ? -1 : 0;
    for (size_t i = 0; i < faces.n && !rc; i++) {
        uint32_t x = faces.a[i];
        do {
            rc = plan_edge(p, x, centres.a[i]) || plan_vertex(p, x);
            x = st_v_phi1(&p->c, x);
        } while (x != faces.a[i] && !rc);
    }
    free(faces.a);
    free(centres.a);
    return rc;
}

/* Faces first: edges and vertices read their points at level L. */
static void evaluate(plan *p, st_synth_ctx *sc)
{
    st_map *m = &p->h->map;
    cc_eval x = { .h = p->h, .L = p->L, .pbase = (const double *)m->pos.base, .pcol = (const double *)m->pos.col[p->c.plvl] };
    double v[3];
    const cc_table *t = &p->t;
    for (uint32_t i = 0; i < st_cc_nfaces_general(t); i++) {
        const uint32_t *r = t->fdata.a + t->foff.a[i];
        st_cc_face_value(&x, r + 1, t->foff.a[i + 1] - t->foff.a[i] - 1, v);
        st_synth_put(sc, r[0], p->fdart.a[i], v);
    }
    x.pnew = (double *)m->pos.base; /* the face points, read back */
    for (size_t i = 0; i < t->edge.n / 5; i++) {
        st_cc_edge_value(&x, t->edge.a + 5 * i, v);
        st_synth_put(sc, t->edge.a[5 * i + 4], p->edart.a[i], v);
    }
    for (uint32_t i = 0; i < st_cc_nverts_general(t); i++) {
        const uint32_t *r = t->vdata.a + t->voff.a[i];
        st_cc_vertex_value(&x, r, (t->voff.a[i + 1] - t->voff.a[i] - 1) / 2, v);
        st_synth_put(sc, r[0] & REF_ID, p->vdart.a[i], v);
    }
    st_catmark_emitter e = { 0 };
    for (size_t i = 0; i < t->sedge.n; i++) st_catmark_emit_edge(p->h, p->L, t->sedge.a[i], &e, st_synth_sink, sc);
    for (size_t i = 0; i < t->svert.n; i++) st_catmark_emit_vertex(p->h, p->L, t->svert.a[i], &e, st_synth_sink, sc);
    st_stencil_buf_free(&e.buf);
    st_stencil_buf_free(&e.tmp);
}

/* ---- direct path: level l is known to be the whole polygon split ---- */

/* With fresh regular tables at l (catmark_fast.c), every face of l has its
 * point at L and every edge its midpoint: nothing can fail, so points are
 * computed and written at once, face points first (edges and vertices read
 * them back from level L), without records. */
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

/* The corner the tables start a face at (as face_start), in the face's
 * corners y[0..k): on a level l >= 1 of the polygon split (which fresh
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
    if (direct_hole(x, d) || direct_hole(x, e) || direct_sharp(x, d)) {
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
    if (!h->map.beta0.col[L]) return 0;
    const cc_table *t = st_cc_tables_if_fresh(h, L - 1);
    if (t && !t->irregular) {
        predict_direct(h, L, seeds, n, out);
        return 1;
    }
    plan p = { .h = h, .m = &h->map, .l = L - 1, .L = L, .gen = out->gen, .b0L = (const uint32_t *)h->map.beta0.col[L] };
    st_level_view_init(&h->map, p.l, &p.c);
    int ok = plan_region(&p, seeds, n) == 0;
    if (ok) evaluate(&p, out);
    plan_free(&p);
    return ok;
}
