/* Primal quadrisection in the multiresolution map (thesis §3.2.1, figs
 * 3.13 and 3.15).  Level L = l+1 starts as a copy of level l (O(1), map.h);
 * then every edge is split at L, and every face is cut at L.  Only β0 of old
 * darts changes across levels: β1 and vert of old darts never do, which is
 * what keeps the topology at ~15 bytes per finest dart.
 *
 * Two writers build the same level: the generic operators (st_split_edge,
 * st_cut_face: st_refine_uniform_ops), and a bulk writer for the uniform
 * step at the top level that writes the final relations directly (below). */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/base/hugepage.h"
#include "core/map/refine_internal.h"
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

/* Triangle quadrisection of the face (c0 m0 c1 m1 c2 m2) at level L: cut
 * the three corners off.  cut_face(m1, m0) leaves the corner (x m0 c1) and
 * the rest (y m1 c2 m2 c0) with y = β0(x) starting at mid0; cut_face(m2, m1)
 * cuts corner 2; the last corner is cut from y, the rest's dart at mid0. */
void st_split_face_tri(st_map *m, uint32_t c0, unsigned L)
{
    uint32_t m0 = st_phi1(m, c0, L);
    uint32_t m1 = st_phi1(m, st_phi1(m, m0, L), L);
    uint32_t m2 = st_phi1(m, st_phi1(m, m1, L), L);
    uint32_t y = st_beta0(m, st_cut_face(m, m1, m0, L), L);
    st_cut_face(m, m2, m1, L);
    st_cut_face(m, y, m2, L);
}

/* Polygon quadrisection of (c0 m0 c1 m1 ... c(n-1) m(n-1)) at level L:
 * cut corner 1 off by an edge mid1->mid0, split that edge by the centre,
 * then connect the centre to mid2 .. mid(n-1); each cut leaves one quad. */
void st_split_face_poly(st_map *m, uint32_t c0, unsigned L, const double centre[3])
{
    uint32_t mids[64], *mid = mids;
    unsigned n = st_face_degree(m, c0, L) / 2;
    if (n > 64) mid = malloc(n * sizeof *mid);
    if (!mid) abort();
    uint32_t x = st_phi1(m, c0, L);
    for (unsigned i = 0; i < n; i++) {
        mid[i] = x;
        x = st_phi1(m, st_phi1(m, x, L), L);
    }
    uint32_t y = st_beta0(m, st_cut_face(m, mid[1], mid[0], L), L);
    uint32_t from_centre = st_split_edge(m, y, L, centre);
    for (unsigned i = 2; i < n; i++)
        from_centre = st_cut_face(m, from_centre, mid[i], L);
    if (mid != mids) free(mid);
}

static void face_centroid(const st_map *m, uint32_t d, unsigned l, double c[3])
{
    unsigned n = 0;
    uint32_t x = d;
    c[0] = c[1] = c[2] = 0;
    do {
        const double *p = st_dart_pos(m, x, l);
        c[0] += p[0]; c[1] += p[1]; c[2] += p[2];
        n++;
        x = st_phi1(m, x, l);
    } while (x != d);
    c[0] /= n; c[1] /= n; c[2] /= n;
}

typedef struct cells {
    uint32_t *faces, nfaces;   /* one dart per real face of level l */
    uint32_t *edges, nedges;   /* one dart per edge of level l */
} cells;

static int collect_cells(st_map *m, unsigned l, cells *c, st_error *err)
{
    /* Bounds from the dart count (every face has >= 3 darts, every edge 2):
     * no counting pass over the level. */
    uint64_t darts = 0;
    for (unsigned k = 0; k <= l; k++) darts += m->darts.live[k];
    c->faces = malloc((darts / 3 + 1) * sizeof *c->faces);
    c->edges = malloc((darts / 2 + 1) * sizeof *c->edges);
    c->nfaces = c->nedges = 0;
    if (!c->faces || !c->edges) return st_fail(err, ST_ERR_MEMORY, "out of memory refining level %u", l);
    int fbit = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (d < st_beta0(m, d, l)) c->edges[c->nedges++] = d;
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        st_mark_face(m, fbit, d, l);
        c->faces[c->nfaces++] = d;
    }
    st_marker_release(m, fbit, l);
    return ST_OK;
}

static int check_mode(const st_map *m, const cells *c, unsigned l, enum st_split_mode mode, st_error *err)
{
    if (mode != ST_SPLIT_TRI) return ST_OK;
    for (uint32_t i = 0; i < c->nfaces; i++)
        if (st_face_degree(m, c->faces[i], l) != 3)
            return st_fail(err, ST_ERR_TOPOLOGY, "level %u has a face with %u sides; this scheme needs triangles", l, st_face_degree(m, c->faces[i], l));
    return ST_OK;
}

/* Exact counts of what a uniform step adds, so the arrays are sized once
 * (no doubling: peak memory is what the level needs).  Per edge: 2 darts and
 * 1 vertex.  Per n-gon: triangle split 6 darts; polygon split 2n darts and
 * 1 vertex (1 cut + 1 split + (n-2) cuts). */
static int reserve_for_level(st_map *m, const cells *c, unsigned l, enum st_split_mode mode, st_error *err)
{
    uint64_t darts = 2ull * c->nedges, verts = c->nedges;
    for (uint32_t i = 0; i < c->nfaces; i++) {
        unsigned n = st_face_degree(m, c->faces[i], l);
        if (n == 3 && mode != ST_SPLIT_POLY) darts += 6;
        else { darts += 2ull * n; verts++; }
    }
    if (st_map_reserve(m, darts, verts))
        return st_fail(err, ST_ERR_MEMORY, "level %u needs %llu more darts: out of memory", l + 1, (unsigned long long)darts);
    return ST_OK;
}

int st_refine_uniform_ops(st_map *m, enum st_split_mode mode, st_error *err)
{
    unsigned l = m->top, L = l + 1;
    cells c;
    int rc = collect_cells(m, l, &c, err);
    if (!rc) rc = check_mode(m, &c, l, mode, err);
    if (!rc) rc = reserve_for_level(m, &c, l, mode, err);
    if (!rc) rc = st_level_add(m, err);
    if (rc) { free(c.faces); free(c.edges); return rc; }
    /* Face centres are computed at level l before any edge is split. */
    double *centre = malloc(((size_t)c.nfaces + 1) * 3 * sizeof *centre);
    if (!centre) abort();
    for (uint32_t i = 0; i < c.nfaces; i++) face_centroid(m, c.faces[i], l, centre + 3 * (size_t)i);
    for (uint32_t i = 0; i < c.nedges; i++) {
        uint32_t d = c.edges[i];
        const double *p = st_dart_pos(m, d, l), *q = st_dart_pos(m, st_beta0(m, d, l), l);
        double mid[3] = { (p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2 };
        st_split_edge(m, d, L, mid);
    }
    for (uint32_t i = 0; i < c.nfaces; i++) {
        uint32_t d = c.faces[i];
        int tri = st_face_degree(m, d, L) == 6;
        if (tri && mode != ST_SPLIT_POLY) st_split_face_tri(m, d, L);
        else st_split_face_poly(m, d, L, centre + 3 * (size_t)i);
    }
    free(centre);
    free(c.faces);
    free(c.edges);
    return ST_OK;
}

/* ---- bulk uniform refinement ---------------------------------------------------
 *
 * The operators keep every level a valid map after each call, which costs a
 * multilevel setter per relation, a face walk per cut and an allocation per
 * dart.  A uniform step at the top level needs none of that: nothing lies
 * above L, so level L is the base arrays of its new darts plus one β0 column
 * for the old darts, which is all the operators change (β1 and vert of old
 * darts never do).  This writer produces the map the operators build (the
 * same relations at every level, up to the numbering of the new darts and
 * vertices) in one pass over the faces of level l.
 *
 * Names, for a real face (d_0 ... d_{k-1}) of level l, d_i running from
 * corner i to corner i+1 along the face, e_i = β0(d_i, l), mid_i the
 * midpoint vertex of d_i's edge:
 *   n(d)    the new dart that continues d from the midpoint (split_edge's a
 *           for d, b for β0(d)): β0(d, L) = n(β0 d), β0(n(d), L) = β0(d, l);
 *   polygon split (centre c): in_i: mid_i -> c, out_i: c -> mid_i, giving
 *           the quads (n(d_i), d_{i+1}, in_{i+1}, out_i);
 *   triangle split: u_i: mid_i -> mid_{i+1} (the inner triangle) and
 *           t_i = β0(u_i), giving the corners (n(d_i), d_{i+1}, t_i).
 * β1 of a new dart x is φ1(β0(x)), read off those faces.  first(d) = φ1(d, L),
 * the new dart that leaves mid_i into d's face (in_i, or t_{i-1}), links
 * the two sides of an edge: β1(n(d)) = first(β0 d), or n(β0 d) when β0(d)
 * lies on a hole (holes are not split).
 *
 * Numbering (why): the ids of level L follow the faces of level l, and the
 * faces are visited newest level first, so that the children of one face
 * are consecutive and so are, recursively, its grandchildren.  A face's new
 * darts n(d_i), in_i, out_i, its centre and the midpoints it is first to
 * reach are numbered together, and the passes over a level (synthesis,
 * analysis, the next refinement) find a face's neighbourhood in a few cache
 * lines instead of one line per relation per dart.
 *
 * An edge is met from its two faces.  The first creates its midpoint and
 * leaves first(d) in β1(n(d)) (a mailbox: n(β0 d) does not exist yet); the
 * second reads it back and writes both β1 links. */

/* Allocation cursor: ids come in runs (st_dart_take_run); `left` keeps the
 * runs within the count reserved for the level. */
typedef struct id_cursor { uint32_t next, end; uint64_t left; } id_cursor;

/* One corner of the face being split: its coarse dart and the twin, the new
 * darts n(d), first(d) and the other dart it allocates (out_i, or t_i's
 * partner), and the midpoint. */
typedef struct corner { uint32_t d, e, n, in, out, mid; } corner;

typedef struct bulk {
    st_map *m;
    unsigned l, L;
    enum st_split_mode mode;
    st_level_view c;            /* level l, read */
    uint32_t *b0L;              /* β0 column of level L: old darts */
    uint32_t *b0, *b1, *vt;     /* base arrays: new darts */
    double *pos;                /* base positions: new vertices */
    uint64_t *seen;             /* one bit per dart id of levels 0..l: face visited */
    uint64_t *mine;             /* counting pass: the darts of the current face */
    size_t nseen;               /* words in seen and mine */
    uint32_t *blocks, nblocks;  /* dart blocks of levels l, l-1, ..., 0 (newest first) */
    id_cursor darts, verts;
    corner *fc;                 /* the face being split */
    uint32_t fcap;
    /* counting pass */
    uint64_t centres;
    unsigned bad_degree;        /* degree of the first face the mode refuses, 0 if none */
    int odd;                    /* a face with fewer than 3 sides, or along itself: left to the operators */
} bulk;

/* Base pointers move when the arrays grow; re-read after each run. */
static void bulk_pointers(bulk *b)
{
    st_map *m = b->m;
    b->b0 = (uint32_t *)m->beta0.base;
    b->b1 = (uint32_t *)m->beta1.base;
    b->vt = (uint32_t *)m->vert.base;
    b->pos = (double *)m->pos.base;
    st_level_view_init(m, b->l, &b->c);
}

/* A new run of ids: the slow path of take_id, out of line so that the
 * common case (the run has ids left) is a compare and an increment where
 * it is used. */
static uint32_t take_run_of(bulk *b, id_cursor *c, uint32_t (*take_run)(st_map *, unsigned, uint32_t, uint32_t *))
{
    uint32_t got, want = c->left > UINT32_MAX ? UINT32_MAX : (uint32_t)c->left;
    c->next = take_run(b->m, b->L, want ? want : 1, &got);
    c->end = c->next + got;
    c->left -= got <= c->left ? got : c->left;
    bulk_pointers(b);
    return c->next++;
}

static inline uint32_t take_dart(bulk *b)
{
    return b->darts.next != b->darts.end ? b->darts.next++ : take_run_of(b, &b->darts, st_dart_take_run);
}
static inline uint32_t take_vertex(bulk *b)
{
    return b->verts.next != b->verts.end ? b->verts.next++ : take_run_of(b, &b->verts, st_vertex_take_run);
}

static int bit(const uint64_t *s, uint32_t d) { return (s[d >> 6] >> (d & 63)) & 1; }
static void set_bit(uint64_t *s, uint32_t d) { s[d >> 6] |= 1ull << (d & 63); }
static void clear_bit(uint64_t *s, uint32_t d) { s[d >> 6] &= ~(1ull << (d & 63)); }

/* The corners of the face of d at level l into b->fc, marked seen; returns
 * the degree. */
static uint32_t walk_face(bulk *b, uint32_t d)
{
    uint32_t k = 0, x = d;
    do {
        if (k == b->fcap) {
            uint32_t cap = b->fcap ? 2 * b->fcap : 64;
            corner *p = realloc(b->fc, cap * sizeof *p);
            if (!p) abort(); /* a face larger than memory: nothing sensible left */
            b->fc = p;
            b->fcap = cap;
        }
        uint32_t e = st_v_beta0(&b->c, x);
        b->fc[k].d = x;
        b->fc[k].e = e;
        set_bit(b->seen, x);
        k++;
        x = st_v_beta1(&b->c, e);
    } while (x != d);
    return k;
}

/* Calls fn once per real face of level l, with its corners in b->fc from
 * the first dart met, visiting the blocks newest level first. */
static void for_each_face(bulk *b, void (*fn)(bulk *b, uint32_t k))
{
    const uint8_t *ins = b->m->darts.ins;
    memset(b->seen, 0, b->nseen * sizeof *b->seen);
    for (uint32_t i = 0; i < b->nblocks; i++)
        for (uint32_t d = b->blocks[i]; d < b->blocks[i] + ST_POOL_BLOCK; d++) {
            if (ins[d] == ST_FREE_LEVEL || st_is_boundary(b->m, d) || bit(b->seen, d)) continue;
            fn(b, walk_face(b, d));
        }
}

static void count_face(bulk *b, uint32_t k)
{
    corner *f = b->fc;
    if (k < 3) b->odd = 1;
    if (k != 3 && b->mode == ST_SPLIT_TRI && !b->bad_degree) b->bad_degree = k;
    if (k != 3 || b->mode == ST_SPLIT_POLY) b->centres++;
    /* An edge with the face on both sides would meet itself as its own
     * neighbour: such maps go to the operators. */
    for (uint32_t i = 0; i < k; i++) set_bit(b->mine, f[i].d);
    for (uint32_t i = 0; i < k; i++)
        if (bit(b->mine, f[i].e)) b->odd = 1;
    for (uint32_t i = 0; i < k; i++) clear_bit(b->mine, f[i].d);
}

/* n(d) and the midpoint for corner f, and the links across its edge (see
 * "An edge is met from its two faces"); f->in is first(f->d). */
static void split_side(bulk *b, corner *f)
{
    st_map *m = b->m;
    uint32_t d = f->d, e = f->e, nd = f->n;
    b->b0[nd] = e;
    b->b0L[e] = nd;
    m->flags[nd] = m->flags[d];
    if (bit(b->seen, e) && !st_is_boundary(m, e)) {
        /* Second side (e's face was split before this one: no face lies
         * along itself, bulk_count): it left its first() in β1(n(e)). */
        uint32_t ne = b->b0L[d];
        f->mid = b->vt[ne];
        b->b1[nd] = b->b1[ne];
        b->b1[ne] = f->in;
        b->vt[nd] = f->mid;
        return;
    }
    const double *p = st_v_pos(&b->c, st_v_vert(&b->c, d)), *q = st_v_pos(&b->c, st_v_vert(&b->c, e));
    double mid[3] = { (p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2 };
    f->mid = take_vertex(b);
    memcpy(b->pos + 3 * (size_t)f->mid, mid, sizeof mid);
    b->vt[nd] = f->mid;
    if (!st_is_boundary(m, e)) {
        b->b1[nd] = f->in;            /* mailbox for the other face */
        return;
    }
    /* A hole is not split: n(e) is made here, with the 2-cycle β1(n(d)) = n(e). */
    uint32_t ne = take_dart(b);
    b->vt[ne] = f->mid;
    b->b0[ne] = d;
    b->b0L[d] = ne;
    m->flags[ne] = m->flags[e];
    b->b1[ne] = f->in;
    b->b1[nd] = ne;
}

/* Polygon split of the face in b->fc (k corners). */
static void split_poly(bulk *b, uint32_t k)
{
    corner *f = b->fc;
    /* The centroid sums from the face's oldest dart, where the operators'
     * enumeration (oldest level first) starts it: the same bits. */
    const uint8_t *ins = b->c.ins;
    uint32_t first = 0;
    for (uint32_t i = 1; i < k; i++)
        if (ins[f[i].d] < ins[f[first].d] || (ins[f[i].d] == ins[f[first].d] && f[i].d < f[first].d)) first = i;
    double c[3] = { 0, 0, 0 };
    for (uint32_t j = 0, i = first; j < k; j++, i = i + 1 < k ? i + 1 : 0) {
        const double *p = st_v_pos(&b->c, st_v_vert(&b->c, f[i].d));
        c[0] += p[0]; c[1] += p[1]; c[2] += p[2];
    }
    c[0] /= k; c[1] /= k; c[2] /= k;
    uint32_t centre = take_vertex(b);
    memcpy(b->pos + 3 * (size_t)centre, c, sizeof c);
    uint8_t fl = b->m->flags[f[1].d];
    for (uint32_t i = 0; i < k; i++) {
        f[i].n = take_dart(b);
        f[i].in = take_dart(b);
        f[i].out = take_dart(b);
        split_side(b, &f[i]);
    }
    for (uint32_t i = 0, prev = k - 1; i < k; prev = i++) {
        uint32_t in = f[i].in, out = f[i].out;
        b->vt[in] = f[i].mid;
        b->vt[out] = centre;
        b->b0[in] = out;
        b->b0[out] = in;
        b->b1[in] = f[i].n;
        b->b1[out] = f[prev].out;
        b->m->flags[in] = b->m->flags[out] = fl;
    }
}

/* Triangle split of the face in b->fc: f[i].in = first(d_i) = t_{i-1},
 * f[i].out = u_i (so t_i is f[i+1].in). */
static void split_tri(bulk *b, uint32_t k)
{
    (void)k;
    corner *f = b->fc;
    for (int i = 0; i < 3; i++) {
        f[i].n = take_dart(b);
        f[i].in = take_dart(b);
        f[i].out = take_dart(b);
    }
    for (int i = 0; i < 3; i++) split_side(b, &f[i]);
    /* Flags as st_split_face_tri's cuts give them: t_0, u_0, t_2, u_2 from
     * d_1, t_1 and u_1 from d_2. */
    uint8_t fl1 = b->m->flags[f[1].d], fl2 = b->m->flags[f[2].d];
    for (int i = 0; i < 3; i++) {
        uint32_t t = f[(i + 1) % 3].in, u = f[i].out;
        b->vt[t] = f[(i + 1) % 3].mid;
        b->vt[u] = f[i].mid;
        b->b0[t] = u;
        b->b0[u] = t;
        b->b1[t] = f[(i + 1) % 3].out;
        b->b1[u] = f[i].n;
        b->m->flags[t] = b->m->flags[u] = i == 1 ? fl2 : fl1;
    }
}

static void split_face(bulk *b, uint32_t k)
{
    if (k == 3 && b->mode != ST_SPLIT_POLY) split_tri(b, k);
    else split_poly(b, k);
}

/* The bulk writer needs a fresh top level: no column at or above L. */
static int bulk_applies(const st_map *m, unsigned L)
{
    const st_mla *a[] = { &m->beta0, &m->beta1, &m->vert, &m->pos };
    for (size_t i = 0; i < sizeof a / sizeof *a; i++)
        if (a[i]->maxcol >= L) return 0;
    for (uint32_t i = 0; i < m->ndart_attrs; i++)
        if (m->dart_attrs[i]->maxcol >= L) return 0;
    for (uint32_t i = 0; i < m->nvert_attrs; i++)
        if (m->vert_attrs[i]->maxcol >= L) return 0;
    return L < ST_MAX_LEVELS;
}

static void bulk_free(bulk *b)
{
    free(b->seen);
    free(b->mine);
    free(b->blocks);
    free(b->fc);
}

/* Counting pass: the exact growth (as reserve_for_level), and the mode
 * check (as check_mode). */
static int bulk_count(bulk *b, uint64_t *darts, uint64_t *verts, st_error *err)
{
    st_map *m = b->m;
    uint64_t n = st_pool_count(&m->darts, b->l), boundary = 0;
    for (uint32_t i = 0; i < b->nblocks; i++)
        for (uint32_t d = b->blocks[i]; d < b->blocks[i] + ST_POOL_BLOCK; d++)
            if (m->darts.ins[d] != ST_FREE_LEVEL && st_is_boundary(m, d)) boundary++;
    for_each_face(b, count_face);
    if (b->bad_degree)
        return st_fail(err, ST_ERR_TOPOLOGY, "level %u has a face with %u sides; this scheme needs triangles", b->l, b->bad_degree);
    /* Per edge 2 darts and a vertex; per real face 2 darts per side. */
    *darts = n + 2 * (n - boundary);
    *verts = n / 2 + b->centres;
    return ST_OK;
}

/* Block list of levels l down to 0. */
static int bulk_blocks(bulk *b)
{
    const st_pool *p = &b->m->darts;
    b->nblocks = st_pool_block_list(p, b->l, NULL);
    b->blocks = malloc(((size_t)b->nblocks + 1) * sizeof *b->blocks);
    if (!b->blocks) return -1;
    uint32_t n = 0;
    for (unsigned lv = b->l + 1; lv-- > 0;)
        for (uint32_t i = 0; i < p->nblocks[lv]; i++) b->blocks[n++] = p->blocks[lv][i] << ST_POOL_BLOCK_SHIFT;
    return 0;
}

int st_refine_uniform(st_map *m, enum st_split_mode mode, st_error *err)
{
    unsigned l = m->top, L = l + 1;
    if (!bulk_applies(m, L)) return st_refine_uniform_ops(m, mode, err);
    bulk b = { .m = m, .l = l, .L = L, .mode = mode };
    b.nseen = (size_t)m->darts.end / 64 + 1;
    b.seen = malloc(b.nseen * sizeof *b.seen);
    b.mine = calloc(b.nseen, sizeof *b.mine);
    if (bulk_blocks(&b) || !b.seen || !b.mine) { bulk_free(&b); return st_fail(err, ST_ERR_MEMORY, "out of memory refining level %u", l); }
    st_level_view_init(m, l, &b.c);
    uint64_t darts = 0, verts = 0;
    int rc = bulk_count(&b, &darts, &verts, err);
    if (!rc && b.odd) { bulk_free(&b); return st_refine_uniform_ops(m, mode, err); }
    if (!rc && st_map_reserve(m, darts, verts))
        rc = st_fail(err, ST_ERR_MEMORY, "level %u needs %llu more darts: out of memory", L, (unsigned long long)darts);
    if (!rc) rc = st_level_add(m, err);
    if (rc) { bulk_free(&b); return rc; }
    st_map_advise_reserved(m);
    b.b0L = st_mla_column_for_overwrite(&m->beta0, &m->darts, L);
    if (!b.b0L) abort(); /* level L exists already: no consistent state to return to */
    st_advise_huge(b.b0L, (size_t)m->beta0.colcap[L] * sizeof *b.b0L);
    b.darts.left = darts;
    b.verts.left = verts;
    bulk_pointers(&b);
    for_each_face(&b, split_face);
    bulk_free(&b);
    return ST_OK;
}
