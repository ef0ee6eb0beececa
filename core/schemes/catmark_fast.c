/* Catmull-Clark full-level synthesis by tables (the scheme's predict_level).
 *
 * Same rules as the stencils of scheme_catmark.c, organised like OpenSubdiv's
 * PrimvarRefiner: face points first, then edge and vertex points, each read
 * from flat index tables.  The tables of coarse level l depend on the
 * topology only (and on sharpness, which decides the special cells), so
 * they are built once, on the second synthesis after a change, and kept in
 * sv->cache[l] while the map's generation (map.h) stays the same.  Building
 * them walks the 2-map; using them reads a few sequential 32-bit indices
 * per fine vertex instead of a chain of dependent loads through β0, β1 and
 * the embedding, which bound the walk by memory latency.
 *
 * The first synthesis after a change (st_synth_tables_defer) takes the
 * same walks and evaluates each record as it meets it instead of storing
 * it: the tables' bits without building them, since a one-shot synthesis
 * (a command that subdivides and writes) would never read them again.
 * spot, depth 4, first synthesis: 392 M instructions building the tables
 * and reading them, 191 M walking (callgrind).
 *
 * Tables of level l (each record in the order the build met it):
 *   quad   5 per quad face: its corners' position refs from the dart new at
 *          l (below), then the id of its face point at L
 *   face   other faces (level 0): foff into fdata = centre, refs...
 *   edge   5 per smooth edge (d < e = β0 d): ref vert(d), ref vert(e),
 *          face points of d's and e's faces, id of the edge point
 *   v4     9 per smooth vertex of valence 4: ref v, then per ring dart y
 *          from the smallest: ref vert(β0 y), face point of y's face
 *   vn     other valences: voff into vdata = ref v, pairs as in v4
 *   sedge, svert   special cells (hole, crease, corner): a dart, for the
 *          stencil path (crease.c rules)
 *   copy   refs of vertices on no real face: they keep their position
 * A position ref is a vertex id, with REF_COL when its level-l position is
 * in the level's column rather than the base (map.h, "Storage").
 *
 * The arithmetic is the one of the walk it replaces, operation for
 * operation: with G(y) = P(vert(φ1 y)) + F(y) per coarse dart y,
 *   face point   F = (Σ corners) · (1/k), summed from the first corner;
 *   edge point   (G(d) + G(e)) / 4  as  0.25 G(d) + 0.25 G(e);
 *   vertex point (n-2)/n P(v) + (1/n²) Σ G(y), summed from the smallest y,
 * so every value is the same whichever thread computes it.
 *
 * Faces need no marks: on a level l >= 1 built by the polygon split each
 * face is a corner quad (n(d_i), d_{i+1}, in_{i+1}, out_i) (refine.c) in
 * which n(d_i) is the one dart new at l whose twin is old; so the blocks of
 * level l name each face once.  Level 0 takes a sequential pass with a
 * visited bit per dart.  A level without that structure (a face without
 * exactly one old dart, faces that miss some dart of the level, a face not
 * split at L) gets a table marked irregular: its synthesis is done by the
 * stencils. */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/catmark_tables_internal.h"
#include "core/base/parallel.h"
#include "core/map/pool_internal.h"
#include "core/schemes/synth_blocks_internal.h"

#include <stdlib.h>
#include <string.h>

/* Per thread: scratch for the stencil path. */
typedef struct cc_worker { const cc_eval *x; st_catmark_emitter e; } cc_worker;

static void sink_write(void *ctx, const st_stencil *s)
{
    const cc_eval *x = ((cc_worker *)ctx)->x;
    double *slot = (x->sv->map->verts.ins[s->fine] == x->L ? x->pnew : x->pold) + 3 * (size_t)s->fine;
    st_stencil_eval(x->sv->map, x->L, s, slot);
}

/* ---- building: walks of the coarse level ---- */

typedef struct builder {
    const st_subdiv_view *sv;
    unsigned l, L;
    st_level_view c;                /* coarse level l */
    int plain;                      /* β1 and vert have no column at level l: read the base */
    const uint32_t *b0L;            /* β0 column of level L: darts of levels <= l */
    const uint32_t *b0, *b1, *vt;   /* base relations (new darts at L; plain coarse ones) */
    uint32_t *blocks, nblocks;      /* first ids of the dart blocks of levels l, l-1, ..., 0 ... */
    uint32_t nnew;                  /* ... of which the first nnew are level l's */
    uint32_t *vblocks, nvblocks;    /* first ids of the vertex blocks of levels l, ..., 0 */
    uint32_t dcover, vcover;        /* 1 + largest coarse dart / vertex id */
    uint64_t *dnew, *vnew;          /* block bits (synth_blocks.h) of the darts / vertices of level l,
                                       NULL where β0 / positions have no level-l column */
    uint32_t *fc;                   /* per coarse dart: the face point of its face, ST_NIL if none */
    uint32_t *vd;                   /* per coarse vertex: a dart of it in a real face, ST_NIL if none */
    u32vec walk;                    /* scratch: a face or a ring */
    int irregular;
    uint64_t covered, holes;        /* darts in the faces found, darts of holes: every dart of level l */
    const uint8_t *flags;           /* the map's dart flags (holes) */
    int sharp, tri_smooth;          /* sharpness anywhere; smooth triangles (st_catmark_tri_edge) */
    cc_table *t;                    /* the records, when building tables ... */
    cc_worker *w;                   /* ... or, walking the level (NULL t), the evaluation they would feed, */
    double *P;                      /* with the level-l positions gathered: P + 3v is the position the
                                       ref of v names (st_synth_ref_pos), read without its select */
} builder;

static uint32_t c_beta0(const builder *x, uint32_t d)
{
    const st_u32_view *r = &x->c.beta0;
    int use_col = x->dnew ? !st_block_bit(x->dnew, d) : x->c.ins[d] < r->lvl;
    return ((const uint32_t *)st_pick(r->base, r->col, use_col))[d];
}
static uint32_t c_beta1(const builder *x, uint32_t d) { return x->plain ? x->b1[d] : st_v_beta1(&x->c, d); }
static uint32_t c_vert(const builder *x, uint32_t d) { return x->plain ? x->vt[d] : st_v_vert(&x->c, d); }
static uint32_t c_phi1(const builder *x, uint32_t d) { return c_beta1(x, c_beta0(x, d)); }
/* Dart d of level l was inserted below l. */
static int c_old(const builder *x, uint32_t d) { return x->dnew ? !st_block_bit(x->dnew, d) : x->c.ins[d] < x->l; }
static int is_live(const uint8_t *ins, uint32_t id) { return ins[id] != ST_FREE_LEVEL; }
static int is_hole(const builder *x, uint32_t d) { return (x->flags[d] & ST_DART_BOUNDARY) != 0; }
static int sharp_edge(const builder *x, uint32_t d) { return x->sharp && st_subdiv_edge_sharpness(x->sv, d, x->l) > 0; }

static uint32_t ref_of(const builder *x, uint32_t v) { return st_synth_ref(&x->c, x->vnew, v); }
/* Walking: the level-l position of coarse vertex v. */
static const double *wpos(const builder *x, uint32_t v) { return x->P + 3 * (size_t)v; }

/* The centre of the face of coarse dart d at level L, or ST_NIL when the
 * chain does not end on a vertex new at L.  Each step reads a live dart
 * whatever the map, so only the end is checked: a level whose faces passed
 * the checks at level l but were not split at L ends on an old vertex. */
static uint32_t centre_of(const builder *x, uint32_t d)
{
    uint32_t c = x->vt[x->b0[x->b1[x->b0L[d]]]];
    return x->c.vins[c] == x->L ? c : ST_NIL;
}

/* Records the face of corners y[0..k) with face point `centre`; its darts
 * and vertices learn it. */
static void record_face(builder *x, const uint32_t *y, unsigned k, uint32_t centre)
{
    cc_table *t = x->t;
    if (!t) {
        /* Walking: the face point now, as st_cc_face_value on the record. */
        const cc_eval *ev = x->w->x;
        double f[3] = { 0, 0, 0 };
        for (unsigned i = 0; i < k; i++) st_cc_face_add(f, wpos(x, c_vert(x, y[i])));
        st_cc_face_finish(f, k, ev->pnew + 3 * (size_t)centre);
    } else if (k == 4) {
        for (unsigned i = 0; i < 4; i++) vec_push(&t->quad, ref_of(x, c_vert(x, y[i])));
        vec_push(&t->quad, centre);
    } else {
        if (!t->foff.n) vec_push(&t->foff, 0);
        vec_push(&t->fdata, centre);
        for (unsigned i = 0; i < k; i++) vec_push(&t->fdata, ref_of(x, c_vert(x, y[i])));
        vec_push(&t->foff, (uint32_t)t->fdata.n);
    }
    for (unsigned i = 0; i < k; i++) {
        x->fc[y[i]] = centre;
        x->vd[c_vert(x, y[i])] = y[i];
    }
    x->covered += k;
}

/* Any face, walked from d; with one_old, it must hold exactly one dart
 * older than l. */
static void face_general(builder *x, uint32_t d, int one_old)
{
    unsigned old = 0;
    uint32_t z = d;
    x->walk.n = 0;
    do {
        old += x->c.ins[z] < x->l;
        vec_push(&x->walk, z);
        z = c_phi1(x, z);
    } while (z != d);
    uint32_t centre = centre_of(x, x->walk.a[x->walk.n - 1]);
    if ((one_old && old != 1) || centre == ST_NIL) { x->irregular = 1; return; }
    record_face(x, x->walk.a, (unsigned)x->walk.n, centre);
}

/* One block of level l: its darts n(d_i) (new, twin old), gathered without
 * a branch per dart, each names a face.  With plain relations the faces are
 * walked in stages whose loads are independent across the block (so that
 * their cache misses overlap): φ1 three times, the check, the chain to the
 * centre. */
static void face_block(builder *x, uint32_t first)
{
    const uint8_t *ins = x->c.ins;
    uint32_t names[ST_POOL_BLOCK], n = 0;
    for (uint32_t d = first; d < first + ST_POOL_BLOCK; d++) {
        if (!is_live(ins, d)) continue; /* free ids hold no relation */
        names[n] = d;
        n += (unsigned)!is_hole(x, d) & (unsigned)c_old(x, c_beta0(x, d)); /* branch-free on purpose */
    }
    if (!x->plain) {
        for (uint32_t i = 0; i < n; i++) face_general(x, names[i], 1);
        return;
    }
    const uint32_t *b1 = x->b1;
    uint32_t y1[ST_POOL_BLOCK], y2[ST_POOL_BLOCK], y3[ST_POOL_BLOCK], c[ST_POOL_BLOCK];
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
    for (uint32_t i = 0; i < n; i++) c[i] = x->vt[c[i]];
    for (uint32_t i = 0; i < n; i++) {
        if (!quad[i]) { face_general(x, names[i], 1); continue; }
        if (x->c.vins[c[i]] != x->L) { x->irregular = 1; continue; }
        uint32_t y[4] = { names[i], y1[i], y2[i], y3[i] };
        record_face(x, y, 4, c[i]);
    }
}

/* Walking a level l >= 1 with plain relations and block bits: each face
 * from its one dart older than l (the blocks below l's hold only such
 * darts), quad (n, o, y2, y3) with n = φ1(y3), the name face_block gives it
 * and so the corner the tables start it at.  Returns 0, having recorded
 * nothing, unless every such face is one that face_block takes as a quad
 * named by n alone (n new, not a hole, twin old; y2 and y3 new with twins
 * new): the caller then walks the faces as face_block does.  The selects
 * vanish: an old dart's β0 is in the column, a new one's in the base. */
static int faces_from_old(builder *x)
{
    const uint32_t *b0 = x->c.beta0.base, *b0c = x->c.beta0.col, *b1 = x->b1, *vt = x->vt, *b0L = x->b0L;
    const uint64_t *dn = x->dnew;
    for (uint32_t i = x->nnew; i < x->nblocks; i++)
        for (uint32_t o = x->blocks[i]; o < x->blocks[i] + ST_POOL_BLOCK; o++) {
            if (!is_live(x->c.ins, o) || is_hole(x, o)) continue;
            uint32_t y2 = b1[b0c[o]], e2 = b0[y2], y3 = b1[e2], e3 = b0[y3], n = b1[e3], en = b0[n];
            unsigned ok = (b1[en] == o) & st_block_bit(dn, y2) & st_block_bit(dn, y3) & st_block_bit(dn, n) &
                          !st_block_bit(dn, en) & st_block_bit(dn, e2) & st_block_bit(dn, e3) & !is_hole(x, n);
            if (!ok) { x->covered = 0; return 0; }
            uint32_t c = vt[b0[b1[b0L[y3]]]]; /* centre_of(y3) */
            if (x->c.vins[c] != x->L) { x->irregular = 1; return 1; }
            /* record_face, walking, on the quad */
            uint32_t y[4] = { n, o, y2, y3 };
            double f[3] = { 0, 0, 0 };
            for (unsigned k = 0; k < 4; k++) {
                uint32_t v = vt[y[k]];
                st_cc_face_add(f, wpos(x, v));
                x->fc[y[k]] = c;
                x->vd[v] = y[k];
            }
            st_cc_face_finish(f, 4, x->w->x->pnew + 3 * (size_t)c);
            x->covered += 4;
        }
    return 1;
}

/* Level 0: faces in enumeration order, a visited bit per dart, each from its
 * smallest dart. */
static void faces_sequential(builder *x)
{
    uint64_t *seen = calloc((size_t)x->dcover / 64 + 1, sizeof *seen);
    if (!seen) abort(); /* out of memory for a bit per dart */
    for (uint32_t i = 0; i < x->nblocks && !x->irregular; i++)
        for (uint32_t d = x->blocks[i]; d < x->blocks[i] + ST_POOL_BLOCK; d++) {
            if (!is_live(x->c.ins, d) || is_hole(x, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
            /* From the face's smallest dart: where catmark_local.c starts it too. */
            uint32_t y = d, lo = d;
            do { seen[y >> 6] |= 1ull << (y & 63); lo = y < lo ? y : lo; y = c_phi1(x, y); } while (y != d);
            face_general(x, lo, 0);
        }
    free(seen);
}

/* Walking: the edge point of (d, e) now, as st_cc_edge_value on the
 * record.  Its midpoint must be new at L: the tables prove it for all
 * edges before they write, a walk writes as it goes. */
static void walk_edge(builder *x, uint32_t d, uint32_t e)
{
    const cc_eval *ev = x->w->x;
    uint32_t mid = x->vt[x->b0L[d]];
    if (x->c.vins[mid] != x->L) { x->irregular = 1; return; }
    st_cc_edge_mix(wpos(x, c_vert(x, d)), wpos(x, c_vert(x, e)),
                   ev->pnew + 3 * (size_t)x->fc[d], ev->pnew + 3 * (size_t)x->fc[e], ev->pnew + 3 * (size_t)mid);
}

static void build_edges(builder *x)
{
    cc_table *t = x->t;
    for (uint32_t i = 0; i < x->nblocks; i++) {
        /* With block bits, β0 of a whole block comes from one array: the
         * base for level l's blocks, the column for older ones (c_beta0). */
        const uint32_t *b0 = !x->dnew ? NULL : i < x->nnew ? x->c.beta0.base : x->c.beta0.col;
        for (uint32_t d = x->blocks[i]; d < x->blocks[i] + ST_POOL_BLOCK; d++) {
            if (!is_live(x->c.ins, d)) continue;
            uint32_t e = b0 ? b0[d] : c_beta0(x, d);
            x->holes += is_hole(x, d);
            if (d > e) continue;
            if ((is_hole(x, d) | is_hole(x, e)) || sharp_edge(x, d) || (x->tri_smooth && st_catmark_tri_edge(x->sv, d, x->l))) {
                if (t) vec_push(&t->sedge, d);
                else st_catmark_emit_edge(x->sv, x->L, d, &x->w->e, sink_write, x->w);
                continue;
            }
            if (x->fc[d] == ST_NIL || x->fc[e] == ST_NIL) { x->irregular = 1; return; }
            if (!t) { walk_edge(x, d, e); if (x->irregular) return; continue; }
            if (t->edge.n + 5 > t->edge.cap) vec_reserve(&t->edge, 2 * t->edge.cap + 5);
            uint32_t *r = t->edge.a + t->edge.n;
            r[0] = ref_of(x, c_vert(x, d));
            r[1] = ref_of(x, c_vert(x, e));
            r[2] = x->fc[d];
            r[3] = x->fc[e];
            r[4] = x->vt[x->b0L[d]];
            t->edge.n += 5;
        }
    }
}

/* Walking: the vertex point of v now, as st_cc_vertex_value on the record
 * (ring r[0..n), summed from r[m], the smallest dart). */
static void walk_vertex(builder *x, uint32_t v, const uint32_t *r, unsigned n, unsigned m)
{
    const cc_eval *ev = x->w->x;
    double s[3] = { 0, 0, 0 };
    for (unsigned i = 0, j = m; i < n; i++, j = j + 1 < n ? j + 1 : 0) {
        if (x->fc[r[j]] == ST_NIL) { x->irregular = 1; return; }
        st_cc_vertex_add(s, wpos(x, c_vert(x, c_beta0(x, r[j]))), ev->pnew + 3 * (size_t)x->fc[r[j]]);
    }
    st_cc_vertex_finish(wpos(x, v), s, n, ev->pold + 3 * (size_t)v);
}

static void build_vertex(builder *x, uint32_t v)
{
    cc_table *t = x->t;
    uint32_t d = x->vd[v];
    if (d == ST_NIL) {
        if (t) vec_push(&t->copy, ref_of(x, v));
        else memcpy(x->w->x->pold + 3 * (size_t)v, wpos(x, v), 3 * sizeof(double));
        return;
    }
    int special = x->sharp && st_subdiv_vertex_sharpness(x->sv, v, x->l) > 0;
    x->walk.n = 0;
    uint32_t y = d, lo = d;
    unsigned m = 0;
    do {
        special |= is_hole(x, y) | sharp_edge(x, y);
        m = y < lo ? (unsigned)x->walk.n : m;
        lo = y < lo ? y : lo;
        vec_push(&x->walk, y);
        y = c_beta1(x, y);
    } while (y != d);
    const uint32_t *r = x->walk.a;
    unsigned n = (unsigned)x->walk.n;
    if (special && !t) { st_catmark_emit_vertex(x->sv, x->L, r[m], &x->w->e, sink_write, x->w); return; }
    if (special) { vec_push(&t->svert, r[m]); return; }
    if (!t) { walk_vertex(x, v, r, n, m); return; }
    u32vec *out = n == 4 ? &t->v4 : &t->vdata;
    vec_push(out, ref_of(x, v));
    for (unsigned i = 0, j = m; i < n; i++, j = j + 1 < n ? j + 1 : 0) {
        if (x->fc[r[j]] == ST_NIL) { x->irregular = 1; return; }
        vec_push(out, ref_of(x, c_vert(x, c_beta0(x, r[j]))));
        vec_push(out, x->fc[r[j]]);
    }
    if (n != 4) {
        if (!t->voff.n) vec_push(&t->voff, 0);
        vec_push(&t->voff, (uint32_t)t->vdata.n);
    }
}

/* Walking, plain relations and no sharpness: vertex v's point as
 * walk_vertex (the ring in a local array, its darts' holes or-ed); rings
 * longer than RING_LOCAL, a copy and the special ones go to build_vertex. */
#define RING_LOCAL 64u
static void walk_vertex_plain(builder *x, uint32_t v)
{
    uint32_t d = x->vd[v], r[RING_LOCAL], y = d;
    unsigned n = 0, m = 0;
    uint8_t flags = 0;
    if (d == ST_NIL) { build_vertex(x, v); return; }
    do {
        if (n == RING_LOCAL) { build_vertex(x, v); return; }
        flags |= x->flags[y];
        m = y < r[m] || !n ? n : m;
        r[n++] = y;
        y = x->b1[y];
    } while (y != d);
    if (flags & ST_DART_BOUNDARY) { build_vertex(x, v); return; }
    const cc_eval *ev = x->w->x;
    double s[3] = { 0, 0, 0 };
    for (unsigned i = 0; i < n; i++) {
        uint32_t y = r[i + m < n ? i + m : i + m - n], f = x->fc[y];
        if (f == ST_NIL) { x->irregular = 1; return; }
        st_cc_vertex_add(s, wpos(x, x->vt[c_beta0(x, y)]), ev->pnew + 3 * (size_t)f);
    }
    st_cc_vertex_finish(wpos(x, v), s, n, ev->pold + 3 * (size_t)v);
}

static void build_vertices(builder *x)
{
    int fast = !x->t && x->plain && !x->sharp;
    for (uint32_t i = 0; i < x->nvblocks && !x->irregular; i++)
        for (uint32_t v = x->vblocks[i]; v < x->vblocks[i] + ST_POOL_BLOCK; v++) {
            if (!is_live(x->c.vins, v)) continue;
            if (fast) walk_vertex_plain(x, v);
            else build_vertex(x, v);
        }
}

/* 1 + the largest id in the blocks. */
static uint32_t blocks_cover(const uint32_t *blocks, uint32_t n)
{
    uint32_t cover = 0;
    for (uint32_t i = 0; i < n; i++)
        if (blocks[i] + ST_POOL_BLOCK > cover) cover = blocks[i] + ST_POOL_BLOCK;
    return cover;
}

/* Walking: P, the level-l positions of the vertices of level l, each
 * copied from where its ref points (the base or the column), so that the
 * walk reads each without the select (a vertex is read about 13 times). */
static int gather_positions(builder *x)
{
    x->P = malloc(((size_t)x->vcover + 1) * 3 * sizeof *x->P);
    if (!x->P) return -1;
    const cc_eval *ev = x->w->x;
    for (uint32_t i = 0; i < x->nvblocks; i++)
        for (uint32_t v = x->vblocks[i]; v < x->vblocks[i] + ST_POOL_BLOCK; v++)
            if (is_live(x->c.vins, v)) memcpy(x->P + 3 * (size_t)v, st_cc_ref_pos(ev, ref_of(x, v)), 3 * sizeof(double));
    return 0;
}

static int builder_init(builder *x, const st_subdiv_view *sv, unsigned L, cc_table *t, cc_worker *w)
{
    st_map *m = sv->map;
    *x = (builder){ .sv = sv, .l = L - 1, .L = L, .t = t, .w = w, .flags = m->flags, .sharp = sv->has_sharpness,
                    .tri_smooth = sv->opts.tri_sub == ST_TRI_SUB_SMOOTH };
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
    x->fc = malloc(((size_t)x->dcover + 1) * sizeof *x->fc);
    x->vd = malloc(((size_t)x->vcover + 1) * sizeof *x->vd);
    if (!x->fc || !x->vd) return -1;
    memset(x->fc, 0xff, ((size_t)x->dcover + 1) * sizeof *x->fc);
    memset(x->vd, 0xff, ((size_t)x->vcover + 1) * sizeof *x->vd);
    if (m->beta0.eff[x->l] == x->l && !(x->dnew = st_block_bits(&m->darts, x->l))) return -1;
    if (m->pos.eff[x->l] == x->l && !(x->vnew = st_block_bits(&m->verts, x->l))) return -1;
    if (!t) return gather_positions(x);
    /* Sizes of a level of quads (every level >= 1): one allocation each. */
    uint64_t darts = st_pool_count(&m->darts, x->l), verts = st_pool_count(&m->verts, x->l);
    vec_reserve(&t->quad, 5 * (size_t)(darts / 4) + 5);
    vec_reserve(&t->edge, 5 * (size_t)(darts / 2) + 5);
    vec_reserve(&t->v4, 9 * (size_t)verts + 9);
    return 0;
}

static void builder_free(builder *x)
{
    free(x->blocks);
    free(x->vblocks);
    free(x->fc);
    free(x->vd);
    free(x->dnew);
    free(x->vnew);
    free(x->walk.a);
    free(x->P);
}

/* The walks of level L's coarse level: they record t's records, or, with
 * t NULL, evaluate each record as they meet it for w (the first synthesis
 * after a change, predict_by_walk); returns 1 if the level is irregular
 * (a walk may have written some points by then: the stencils redo them). */
static int walk_coarse_level(const st_subdiv_view *sv, unsigned L, cc_table *t, cc_worker *w)
{
    builder x = { 0 };
    if (builder_init(&x, sv, L, t, w)) { builder_free(&x); return 1; } /* no memory for the scratch */
    unsigned l = L - 1;
    if (l > 0) {
        int done = !t && x.plain && x.dnew && faces_from_old(&x);
        for (uint32_t i = 0; i < x.nnew && !x.irregular && !done; i++) face_block(&x, x.blocks[i]);
    } else
        faces_sequential(&x);
    if (!x.irregular) build_edges(&x);
    if (!x.irregular) build_vertices(&x);
    /* Every dart of level l must lie in a face found or in a hole. */
    int irregular = x.irregular || (l > 0 && x.covered + x.holes != st_pool_count(&sv->map->darts, l));
    builder_free(&x);
    return irregular;
}

/* The Catmull-Clark records of level L's coarse level (st_synth_build). */
static int build_tables_of(const st_subdiv_view *sv, unsigned L, cc_table *t) { return walk_coarse_level(sv, L, t, NULL); }

const cc_table *st_cc_tables_for(const st_subdiv_view *sv, unsigned L) { return st_synth_tables_for(sv, L, ST_SCHEME_CATMARK, build_tables_of); }

/* ---- evaluation ---- */

static void face_item(const cc_eval *x, uint32_t i)
{
    const cc_table *t = x->t;
    uint32_t nquad = (uint32_t)(t->quad.n / 5);
    if (i < nquad) {
        const uint32_t *r = t->quad.a + 5 * (size_t)i;
        st_cc_face_value(x, r, 4, x->pnew + 3 * (size_t)r[4]);
        return;
    }
    i -= nquad;
    const uint32_t *r = t->fdata.a + t->foff.a[i];
    st_cc_face_value(x, r + 1, t->foff.a[i + 1] - t->foff.a[i] - 1, x->pnew + 3 * (size_t)r[0]);
}

static void edge_item(cc_worker *w, uint32_t i)
{
    const cc_eval *x = w->x;
    const cc_table *t = x->t;
    uint32_t nedge = (uint32_t)(t->edge.n / 5);
    if (i >= nedge) { st_catmark_emit_edge(x->sv, x->L, t->sedge.a[i - nedge], &w->e, sink_write, w); return; }
    const uint32_t *r = t->edge.a + 5 * (size_t)i;
    st_cc_edge_value(x, r, x->pnew + 3 * (size_t)r[4]);
}

static void vertex_item(cc_worker *w, uint32_t i)
{
    const cc_eval *x = w->x;
    const cc_table *t = x->t;
    uint32_t n4 = (uint32_t)(t->v4.n / 9), nn = st_cc_nverts_general(t), ns = (uint32_t)t->svert.n;
    if (i < n4) {
        const uint32_t *r = t->v4.a + 9 * (size_t)i;
        st_cc_vertex_value(x, r, 4, x->pold + 3 * (size_t)(r[0] & REF_ID));
        return;
    }
    i -= n4;
    if (i < nn) {
        const uint32_t *r = t->vdata.a + t->voff.a[i];
        st_cc_vertex_value(x, r, (t->voff.a[i + 1] - t->voff.a[i] - 1) / 2, x->pold + 3 * (size_t)(r[0] & REF_ID));
        return;
    }
    i -= nn;
    if (i < ns) { st_catmark_emit_vertex(x->sv, x->L, t->svert.a[i], &w->e, sink_write, w); return; }
    i -= ns;
    uint32_t r = t->copy.a[i];
    memcpy(x->pold + 3 * (size_t)(r & REF_ID), st_cc_ref_pos(x, r), 3 * sizeof(double));
}

static void eval_passes(st_team *team, unsigned tid, void *ctx)
{
    (void)tid;
    cc_worker w = { .x = ctx };
    const cc_table *t = w.x->t;
    uint32_t b, e;
    uint32_t nf = (uint32_t)(t->quad.n / 5) + st_cc_nfaces_general(t);
    while (st_team_next(team, 0, nf, ST_SYNTH_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++) face_item(w.x, i);
    st_team_sync(team); /* edge and vertex points read the face points */
    uint32_t ne = (uint32_t)(t->edge.n / 5 + t->sedge.n);
    while (st_team_next(team, 1, ne, ST_SYNTH_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++) edge_item(&w, i);
    uint32_t nv = (uint32_t)(t->v4.n / 9) + st_cc_nverts_general(t) + (uint32_t)(t->svert.n + t->copy.n);
    while (st_team_next(team, 2, nv, ST_SYNTH_CHUNK, &b, &e))
        for (uint32_t i = b; i < e; i++) vertex_item(&w, i);
    st_stencil_buf_free(&w.e.buf);
    st_stencil_buf_free(&w.e.tmp);
}

/* ---- the level ---- */

/* Every vertex of level L by its stencil (a level the tables do not fit). */
static void predict_by_stencils(const st_subdiv_view *sv, unsigned L)
{
    cc_eval x = { .sv = sv, .L = L };
    x.pold = st_mla_column_for_overwrite(&sv->map->pos, &sv->map->verts, L);
    x.pnew = (double *)sv->map->pos.base;
    if (!x.pold) abort(); /* out of memory for a level's positions */
    cc_worker w = { .x = &x };
    st_catmark_emit(sv, L, NULL, 0, sink_write, &w);
}

/* Level L by the walks that build the tables, each record evaluated as
 * met (the same records, the same arithmetic, so the tables' bits) on one
 * thread; returns 1 if the level is irregular (the stencils' then). */
static int predict_by_walk(const st_subdiv_view *sv, unsigned L)
{
    st_map *m = sv->map;
    if (m->verts.end > REF_ID) return 1; /* refs keep one bit for the column, as the tables' */
    cc_eval x = { .sv = sv, .L = L };
    x.pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    if (!x.pold) abort(); /* out of memory for a level's positions */
    x.pnew = (double *)m->pos.base;
    x.pbase = (const double *)m->pos.base;
    x.pcol = (const double *)m->pos.col[m->pos.eff[L - 1]];
    cc_worker w = { .x = &x };
    int irregular = walk_coarse_level(sv, L, NULL, &w);
    st_stencil_buf_free(&w.e.buf);
    st_stencil_buf_free(&w.e.tmp);
    return irregular;
}

void st_catmark_predict_level(const st_subdiv_view *sv, unsigned L)
{
    st_map *m = sv->map;
    if (!m->beta0.col[L]) { predict_by_stencils(sv, L); return; }
    /* The first synthesis after a change walks the level instead of
     * building the tables (which a one-shot synthesis, a command that
     * subdivides and writes, would never read again); the next builds
     * them (st_synth_tables_defer). */
    if (st_synth_tables_defer(sv, L, ST_SCHEME_CATMARK)) {
        if (predict_by_walk(sv, L)) predict_by_stencils(sv, L);
        return;
    }
    const cc_table *t = st_cc_tables_for(sv, L);
    if (t->irregular) { predict_by_stencils(sv, L); return; }
    cc_eval x = { .sv = sv, .L = L, .t = t };
    x.pold = st_mla_column_for_overwrite(&m->pos, &m->verts, L);
    if (!x.pold) abort(); /* out of memory for a level's positions */
    x.pnew = (double *)m->pos.base;
    x.pbase = (const double *)m->pos.base;
    x.pcol = (const double *)m->pos.col[t->plvl];
    st_synth_run(t->quad.n / 5 + t->edge.n / 5 + t->v4.n / 9, eval_passes, &x);
}
