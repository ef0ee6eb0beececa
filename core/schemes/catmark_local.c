/* Catmull-Clark local re-synthesis of one level (scheme.h predict_around,
 * called by st_hier_move through core/multires) when the level has no
 * details: the points of the faces around the changed vertices, with the
 * arithmetic of the full-level synthesis (catmark_tables.h) and from the
 * same start darts, so that a local edit and a full synthesis give the
 * same bits.
 *
 * It reads the face points of faces outside the region from level L itself:
 * with no details at L, P_L = S(P_{L-1}) (core/multires/hier.h), and those
 * faces' corners did not change (the region holds every face around a
 * changed vertex).
 * Faces are told apart by their points' stamps: no marks to set and clear.
 *
 * It needs the level's tables (built here when stale, once per topology
 * change): when they are irregular (an adaptive level) it gives up before
 * writing anything, and the stencils do the level.
 *
 * A walk also records what it did as a plan of the level (below): the
 * records of the points it wrote, in the tables' form.  The next edit of
 * the same vertices (a drag: the same seeds at every level) replays the
 * plan instead of walking the faces again, with the same arithmetic in the
 * same order, so the same bits. */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/catmark_tables_internal.h"

/* Regular tables at l (catmark_fast.c) prove that every face of l has its
 * point at L and every edge its midpoint: nothing can fail, so points are
 * computed and written at once, face points first (edges and vertices read
 * them back from level L). */
typedef struct direct {
    const st_subdiv_view *sv;
    const st_map *m;
    unsigned l, L;
    uint32_t gen;
    const uint32_t *stamp;              /* sv->stamp->v: it does not move during the pass */
    st_level_view c;
    const uint32_t *b0L, *b1, *b0, *vt; /* β0 column of L; base relations (darts new at L, plain ones) */
    int plain;                          /* β1 and vert have no column at l (primal splits keep them) */
    const double *pL;                   /* level-L positions of the vertices new at L */
    st_synth_ctx *out;
    st_catmark_emitter e;
    u32vec faces;                       /* per face: dart, centre */
    u32vec walk;                        /* scratch: a face or a ring */
    struct local_plan *rec;             /* NULL, or where the walk records its plan */
} direct;

/* ---- plans ---- */

/* The plan of one level L for one list of seeds: every point the walk
 * wrote, as records of the tables' form (catmark_tables_internal.h) with
 * position refs of level L-1 (REF_COL: the column), in the walk's order.
 *   faces: centre, k, k corner refs
 *   mixed: 0, midpoint, ref d, ref e, face point of d, of e (an edge)
 *          n, vertex, its ref, n pairs (neighbour ref, face point)
 *   outs:  each vertex written (REF_COL: its level-L position is in the
 *          column), darts: its dart at L, the seeds of L+1.
 * It holds while the map's generation (which sharpness changes too), its
 * pools' ends, its top and the coarse positions' column stay, as the
 * tables do (synth_tables_internal.h).  A walk that met a crease, a
 * boundary or a triangle (stencils) records no plan, nor one that grows
 * past half a word per vertex id of the map (plan_room): a drag's region
 * is small, and a plan of a whole level would cost memory like the
 * tables. */
typedef struct local_plan {
    int valid;
    uint64_t gen;
    uint32_t dend, vend;
    unsigned top, plvl;
    uint32_t maxcol;                    /* largest vertex written to the column, +1 (0: none) */
    u32vec seeds, faces, mixed, outs, darts;
} local_plan;

typedef struct local_plans { local_plan level[ST_MAX_LEVELS]; } local_plans;

static void plans_free(void *p)
{
    local_plans *ps = p;
    for (unsigned L = 0; L < ST_MAX_LEVELS; L++) {
        local_plan *q = &ps->level[L];
        u32vec *v[] = { &q->seeds, &q->faces, &q->mixed, &q->outs, &q->darts };
        for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) free(v[i]->a);
    }
    free(ps);
}

/* Level L's plan slot, emptied and stamped with the map's state. */
static local_plan *plan_start(const st_subdiv_view *sv, unsigned L, const uint32_t *seeds, uint32_t n)
{
    if (sv->local->p && sv->local->free != plans_free) {
        sv->local->free(sv->local->p);
        sv->local->p = NULL;
    }
    if (!sv->local->p) {
        sv->local->p = calloc(1, sizeof(local_plans));
        if (!sv->local->p) return NULL; /* no plan: the walk alone */
        sv->local->free = plans_free;
    }
    st_map *m = sv->map;
    local_plan *q = &((local_plans *)sv->local->p)->level[L];
    q->valid = 1;
    q->gen = st_map_generation(m);
    q->dend = m->darts.end;
    q->vend = m->verts.end;
    q->top = m->top;
    q->plvl = m->pos.eff[L - 1];
    q->maxcol = 0;
    q->seeds.n = q->faces.n = q->mixed.n = q->outs.n = q->darts.n = 0;
    for (uint32_t i = 0; i < n; i++) vec_push(&q->seeds, seeds[i]);
    return q;
}

/* Level L's plan when it was made for these seeds on the map as it is. */
static const local_plan *plan_for(const st_subdiv_view *sv, unsigned L, const uint32_t *seeds, uint32_t n)
{
    const st_map *m = sv->map;
    if (!sv->local->p || sv->local->free != plans_free || m->log) return NULL;
    const local_plan *q = &((const local_plans *)sv->local->p)->level[L];
    if (!q->valid || q->gen != m->gen || q->dend != m->darts.end || q->vend != m->verts.end || q->top != m->top ||
        q->plvl != m->pos.eff[L - 1] || q->seeds.n != n || (n && memcmp(q->seeds.a, seeds, (size_t)n * sizeof *seeds)))
        return NULL;
    /* Writes go where st_synth_put puts them: the column must hold them. */
    const st_mla *a = &m->pos;
    if (q->maxcol && !(a->col[L] && q->maxcol <= a->colcap[L])) return NULL;
    return q;
}

static uint32_t direct_ref(const direct *x, uint32_t v) { return st_synth_ref(&x->c, NULL, v); }

/* Records vertex v written with dart d; returns v's output ref: REF_COL
 * when st_synth_put wrote it to the level's column (a vertex older than
 * L), not the base. */
static uint32_t plan_out(direct *x, uint32_t v, uint32_t d)
{
    local_plan *q = x->rec; /* not NULL: plan_room said so */
    int col = x->m->verts.ins[v] != x->L;
    if (col && v + 1 > q->maxcol) q->maxcol = v + 1;
    uint32_t o = v | (col ? REF_COL : 0);
    vec_push(&q->outs, o);
    vec_push(&q->darts, d);
    return o;
}

/* Where the level-L position of output ref o goes. */
static double *plan_dst(double *wbase, double *wcol, uint32_t o)
{
    return (double *)st_pick(wbase, wcol, (o & REF_COL) != 0) + 3 * (size_t)(o & REF_ID);
}

/* A point the walk leaves to the stencils: no plan of this level. */
static void plan_drop(direct *x)
{
    if (x->rec) x->rec->valid = 0;
    x->rec = NULL;
}

/* The plan to record the next point in, or NULL: none, or it would grow
 * past its bound (then it is dropped and its memory given back). */
static local_plan *plan_room(direct *x)
{
    local_plan *q = x->rec;
    if (!q) return NULL;
    size_t words = q->seeds.n + q->faces.n + q->mixed.n + q->outs.n + q->darts.n;
    if (words <= 4096 + x->m->verts.end / 2) return q;
    plan_drop(x);
    u32vec *v[] = { &q->seeds, &q->faces, &q->mixed, &q->outs, &q->darts };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        free(v[i]->a);
        *v[i] = (u32vec){ 0 };
    }
    return NULL;
}

/* Appends n darts to a list at once (its array grows as
 * st_dart_list_push grows it: realloc, doubling). */
static void changed_append(st_dart_list *l, const uint32_t *d, uint32_t n)
{
    if (!n) return;
    if ((uint64_t)l->n + n > l->cap) {
        uint64_t cap = l->cap ? l->cap : 64;
        while (cap < (uint64_t)l->n + n) cap *= 2;
        if (cap > UINT32_MAX) abort();
        uint32_t *p = realloc(l->d, (size_t)cap * sizeof *p);
        if (!p) abort(); /* out of memory during a synthesis pass */
        l->d = p;
        l->cap = (uint32_t)cap;
    }
    memcpy(l->d + l->n, d, (size_t)n * sizeof *d);
    l->n += n;
}

/* Positions a plan reads (level L-1: base, column) and writes (level L). */
typedef struct plan_io { const double *pbase, *pcol; double *wbase, *wcol; } plan_io;

/* A face record of k corners; inline, so that k = 4 (quads, every face
 * above level 0) unrolls. */
static inline void replay_face(const plan_io *io, const uint32_t *r, unsigned k)
{
    double f[3] = { 0, 0, 0 };
    for (unsigned i = 0; i < k; i++) st_cc_face_add(f, st_synth_ref_pos(io->pbase, io->pcol, r[2 + i]));
    st_cc_face_finish(f, k, plan_dst(io->wbase, io->wcol, r[0]));
}

/* A vertex record of valence n, likewise for n = 4. */
static inline void replay_vertex(const plan_io *io, const uint32_t *r, unsigned n)
{
    double s[3] = { 0, 0, 0 };
    for (unsigned j = 0; j < n; j++)
        st_cc_vertex_add(s, st_synth_ref_pos(io->pbase, io->pcol, r[3 + 2 * j]), io->wbase + 3 * (size_t)r[4 + 2 * j]);
    st_cc_vertex_finish(st_synth_ref_pos(io->pbase, io->pcol, r[2]), s, n, plan_dst(io->wbase, io->wcol, r[1]));
}

/* The level from its plan: the same records in the same order as the
 * walk, through the same arithmetic. */
static void plan_replay(const st_subdiv_view *sv, unsigned L, const local_plan *q, st_synth_ctx *out)
{
    st_map *m = sv->map;
    const plan_io io = { (const double *)m->pos.base, (const double *)m->pos.col[q->plvl], (double *)m->pos.base,
                         (double *)m->pos.col[L] };
    for (size_t i = 0; i < q->faces.n;) {
        const uint32_t *r = q->faces.a + i;
        unsigned k = r[1];
        if (k == 4) replay_face(&io, r, 4);
        else replay_face(&io, r, k);
        i += 2 + k;
    }
    for (size_t i = 0; i < q->mixed.n;) {
        const uint32_t *r = q->mixed.a + i;
        unsigned n = r[0];
        if (!n) {
            st_cc_edge_mix(st_synth_ref_pos(io.pbase, io.pcol, r[2]), st_synth_ref_pos(io.pbase, io.pcol, r[3]),
                           io.wbase + 3 * (size_t)r[4], io.wbase + 3 * (size_t)r[5], plan_dst(io.wbase, io.wcol, r[1]));
            i += 6;
            continue;
        }
        if (n == 4) replay_vertex(&io, r, 4);
        else replay_vertex(&io, r, n);
        i += 3 + 2 * n;
    }
    uint32_t nout = (uint32_t)q->outs.n;
    out->count += nout;
    if (out->fp)
        for (uint32_t i = 0; i < nout; i++) st_footprint_add(out->fp, st_fp_key(L, ST_FP_POS, q->outs.a[i] & REF_ID));
    if (out->changed) changed_append(out->changed, q->darts.a, nout);
}

static uint32_t direct_centre_dart(const direct *x, uint32_t d) { return x->b0[x->b1[x->b0L[d]]]; }
static const double *direct_face_point(const direct *x, uint32_t d) { return x->pL + 3 * (size_t)x->vt[direct_centre_dart(x, d)]; }
static uint32_t d_beta1(const direct *x, uint32_t d) { return x->plain ? x->b1[d] : st_v_beta1(&x->c, d); }
static uint32_t d_vert(const direct *x, uint32_t d) { return x->plain ? x->vt[d] : st_v_vert(&x->c, d); }
static uint32_t d_phi1(const direct *x, uint32_t d) { return d_beta1(x, st_v_beta0(&x->c, d)); }
static int direct_hole(const direct *x, uint32_t d) { return (x->m->flags[d] & ST_DART_BOUNDARY) != 0; }
static int direct_sharp(const direct *x, uint32_t d) { return x->sv->has_sharpness && st_subdiv_edge_sharpness(x->sv, d, x->l) > 0; }

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
    if (x->stamp[centre] == x->gen) return;
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
    local_plan *q = plan_room(x);
    if (!q) return;
    uint32_t o = plan_out(x, centre, cd);
    vec_push(&q->faces, o);
    vec_push(&q->faces, k);
    for (unsigned i = 0, j = s; i < k; i++, j = j + 1 < k ? j + 1 : 0) vec_push(&q->faces, direct_ref(x, d_vert(x, y[j])));
}

static void direct_edge(direct *x, uint32_t d, uint32_t centre)
{
    uint32_t md = x->b0L[d], mid = x->vt[md];
    if (x->stamp[mid] == x->gen) return;
    uint32_t e = st_v_beta0(&x->c, d);
    if (direct_hole(x, d) || direct_hole(x, e) || direct_sharp(x, d) || st_catmark_tri_edge(x->sv, d, x->l)) {
        /* from the smaller dart, as the tables: the stencil's order, its bits */
        st_catmark_emit_edge(x->sv, x->L, d < e ? d : e, &x->e, x->out->sink, x->out);
        plan_drop(x);
        return;
    }
    double out[3];
    st_cc_edge_mix(st_v_pos(&x->c, d_vert(x, d)), st_v_pos(&x->c, d_vert(x, e)), x->pL + 3 * (size_t)centre,
                   direct_face_point(x, e), out);
    st_synth_put(x->out, mid, md, out);
    local_plan *q = plan_room(x);
    if (!q) return;
    uint32_t rec[6] = { 0, plan_out(x, mid, md), direct_ref(x, d_vert(x, d)), direct_ref(x, d_vert(x, e)), centre,
                        x->vt[direct_centre_dart(x, e)] };
    for (int i = 0; i < 6; i++) vec_push(&q->mixed, rec[i]);
}

static void direct_vertex(direct *x, uint32_t d)
{
    uint32_t v = d_vert(x, d);
    if (x->stamp[v] == x->gen) return;
    int special = x->sv->has_sharpness && st_subdiv_vertex_sharpness(x->sv, v, x->l) > 0;
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
        st_catmark_emit_vertex(x->sv, x->L, r[lo], &x->e, x->out->sink, x->out);
        plan_drop(x);
        return;
    }
    double s[3] = { 0, 0, 0 }, out[3];
    for (unsigned i = 0, j = lo; i < n; i++, j = j + 1 < n ? j + 1 : 0)
        st_cc_vertex_add(s, st_v_pos(&x->c, d_vert(x, st_v_beta0(&x->c, r[j]))), direct_face_point(x, r[j]));
    st_cc_vertex_finish(st_v_pos(&x->c, v), s, n, out);
    st_synth_put(x->out, v, d, out);
    local_plan *q = plan_room(x);
    if (!q) return;
    uint32_t o = plan_out(x, v, d);
    u32vec *mx = &q->mixed;
    vec_push(mx, n);
    vec_push(mx, o);
    vec_push(mx, direct_ref(x, v));
    for (unsigned i = 0, j = lo; i < n; i++, j = j + 1 < n ? j + 1 : 0) {
        vec_push(mx, direct_ref(x, d_vert(x, st_v_beta0(&x->c, r[j]))));
        vec_push(mx, x->vt[direct_centre_dart(x, r[j])]);
    }
}

static void predict_direct(const st_subdiv_view *sv, unsigned L, const uint32_t *seeds, uint32_t n, st_synth_ctx *out)
{
    const st_map *m = sv->map;
    direct x = { .sv = sv, .m = m, .l = L - 1, .L = L, .gen = out->gen, .stamp = sv->stamp->v, .out = out };
    /* No plan where the map logs its writes (a replay would not). */
    if (!m->log) x.rec = plan_start(sv, L, seeds, n);
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

int st_catmark_predict_around(const st_subdiv_view *sv, unsigned L, const uint32_t *seeds, uint32_t n, st_synth_ctx *out)
{
    if (!sv->map->beta0.col[L] || st_cc_tables_for(sv, L)->irregular) return 0;
    const local_plan *q = plan_for(sv, L, seeds, n);
    if (q) plan_replay(sv, L, q, out);
    else predict_direct(sv, L, seeds, n, out);
    return 1;
}
