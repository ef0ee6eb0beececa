/* Synthesis of a progressive hierarchy from flat per-level ring tables
 * (the scheme's predict_level and predict_around, core/schemes/
 * progressive_scheme.c).
 *
 * Why tables: the map of a progressive hierarchy is in the pair form of
 * thesis §4.4.5 (st_map_compact), where each β0, β1 or vertex lookup scans
 * a dart's (level, value) pairs.  The stencils of progressive_scheme.c walk
 * a vertex's orbit four or five times, the split neighbours' orbits again,
 * and the frame walks the coarse orbit: some twenty lookups per dart, 43 %
 * of a full synthesis of koala.  A table of level l lists, once, each
 * vertex's ring at l (the vertex at the far end of each dart of its β1
 * orbit, from the orbit's smallest dart, as the stencils and st_hier_frame
 * walk it) with the few dart flags they read; stencils and frames are then
 * evaluated from flat arrays, in the same order of summation as
 * st_progressive_stencil + st_stencil_apply, hence to the same bits.
 *
 * A table is built on first use and kept in h->cache[l] until the map's
 * topology generation changes (as the Catmull-Clark tables are).  A map
 * this scheme did not build (no dart of level l-1 around a vertex, a split
 * vertex whose frame vertex is not a neighbour) marks the table irregular,
 * and the levels it serves go through the stencils instead.
 *
 * Local re-synthesis writes exactly the vertices whose position changes:
 * a vertex of level L is recomputed only if its stencil or its frame reads
 * a vertex that changed at L-1, and written (and passed on to level L+1)
 * only if its new position differs from the stored one.  What reads a
 * changed vertex u of level L-1 (progressive.h, point 5):
 *   - u itself, and its neighbours at L (their stencils read u);
 *   - for a split neighbour a of u at L, a's neighbours at L (their
 *     stencils read a's prediction, an average over a's ring);
 *   - the vertices z of u's closed ring at L-1 (the frame of z reads u),
 *     and the split vertices at L whose frame is z's (neighbours of z).
 */
#include "core/progressive/progressive_internal.h"
#include "core/multires/hier_internal.h"
#include "core/map/pool_internal.h"
#include "core/multires/estimate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum {
    RING_BORDER = 1u,    /* the dart or its β0 is on a hole (progressive_scheme.c: on_border) */
    RING_OPEN = 2u,      /* its β0 is on a hole: the frame's corner there is left out (st_hier_frame) */
    RING_FRAME_V = 4u,   /* split vertex: this neighbour is the vertex whose frame carries the detail */
};

enum {
    VERT_BORDER = 1u,    /* some dart of the orbit is RING_BORDER */
    VERT_NEAR = 2u,      /* a neighbour was split at l (progressive_scheme.c: near_split) */
};

typedef struct pm_ring_table {
    uint64_t gen;              /* the map's state it was built from */
    uint32_t dend, vend;
    unsigned top;
    int irregular;             /* not a map this scheme built: use the stencils */
    double mu;                 /* the relaxation's weight (pm_relax_weight) */
    uint32_t nidx;             /* vertex ids [0, nidx) have an entry in off */
    uint32_t *off;             /* nidx + 1: ring of vertex v is [off[v], off[v+1]), empty if v is not at l */
    uint32_t *first;           /* nidx: the smallest dart of v's orbit at l */
    uint32_t *split_of;        /* nidx, l >= 1: the vertex split from v at l (its frame is v's), or ST_NIL */
    uint32_t *nbr;             /* per ring entry: vertex at the other end of the dart's edge */
    uint8_t *fl;               /* per ring entry: RING_* */
    uint8_t *vk;               /* nidx: VERT_* */
    uint32_t *avg_n;           /* nidx: the neighbours a ring average of v reads (ring_average) */
} pm_ring_table;

static void table_free(void *p)
{
    pm_ring_table *t = p;
    if (!t) return;
    free(t->off);
    free(t->first);
    free(t->split_of);
    free(t->vk);
    free(t->avg_n);
    free(t->nbr);
    free(t->fl);
    free(t);
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p) abort(); /* out of memory for a synthesis table, as for the stencils */
    return p;
}

/* What the stencils test on the ring of v (entries [beg, end)) at l. */
static void vertex_summary(const st_map *m, unsigned l, pm_ring_table *t, uint32_t v, uint32_t beg, uint32_t end)
{
    uint8_t k = 0;
    for (uint32_t j = beg; j < end; j++) {
        if (t->fl[j] & RING_BORDER) k |= VERT_BORDER;
        if (m->verts.ins[t->nbr[j]] == l) k |= VERT_NEAR;
    }
    uint32_t n = 0;
    for (uint32_t j = beg; j < end; j++)
        n += (!(k & VERT_BORDER) || (t->fl[j] & RING_BORDER)) && m->verts.ins[t->nbr[j]] < l;
    t->vk[v] = k;
    t->avg_n[v] = n;
}

/* Ring of level l of every vertex, in orbit order from the smallest dart. */
static void table_fill(st_map *m, unsigned l, pm_ring_table *t)
{
    uint32_t vend = m->verts.end, nd = 0, nidx = 0;
    uint32_t *vmin = xmalloc((size_t)(vend ? vend : 1) * sizeof *vmin);
    for (uint32_t v = 0; v < vend; v++) vmin[v] = ST_NIL;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t v = st_vert(m, d, l);
        if (v >= vend) { t->irregular = 1; continue; }
        if (d < vmin[v]) vmin[v] = d;
        if (v + 1 > nidx) nidx = v + 1;
        nd++;
    }
    t->nidx = nidx;
    t->off = xmalloc(((size_t)nidx + 1) * sizeof *t->off);
    t->first = xmalloc((size_t)(nidx ? nidx : 1) * sizeof *t->first);
    t->split_of = xmalloc((size_t)(nidx ? nidx : 1) * sizeof *t->split_of);
    for (uint32_t v = 0; v < nidx; v++) t->split_of[v] = ST_NIL;
    t->vk = xmalloc((size_t)(nidx ? nidx : 1));
    t->avg_n = xmalloc((size_t)(nidx ? nidx : 1) * sizeof *t->avg_n);
    t->nbr = xmalloc((size_t)nd * sizeof *t->nbr);
    t->fl = xmalloc((size_t)nd * sizeof *t->fl);
    uint32_t k = 0;
    for (uint32_t v = 0; v < nidx; v++) {
        t->off[v] = k;
        uint32_t c = vmin[v];
        t->first[v] = c;
        t->vk[v] = 0;
        t->avg_n[v] = 0;
        if (c == ST_NIL) continue;
        uint32_t x = c, frame = ST_NIL, b = ST_NIL, beg = k;
        do {
            uint32_t e = st_beta0(m, x, l);
            if (k == nd) { t->irregular = 1; break; } /* an orbit longer than the level's darts */
            t->nbr[k] = st_vert(m, e, l);
            t->fl[k] = (uint8_t)((st_is_boundary(m, x) || st_is_boundary(m, e) ? RING_BORDER : 0) |
                                 (st_is_boundary(m, e) ? RING_OPEN : 0));
            if (l > 0 && frame == ST_NIL && m->darts.ins[x] < l) frame = x;
            k++;
            x = st_beta1(m, x, l);
        } while (x != c);
        vertex_summary(m, l, t, v, beg, k);
        if (l == 0) continue;
        /* The frame vertex at l-1 (st_progressive_stencil's frame dart):
         * the vertex itself unless it was split at l, then its neighbour b. */
        if (frame == ST_NIL) { t->irregular = 1; continue; }
        b = st_vert(m, frame, l - 1);
        if (m->verts.ins[v] < l) {
            t->irregular |= b != v;
            continue;
        }
        uint32_t j = beg;
        while (j < k && t->nbr[j] != b) j++;
        /* (progressive.h, point 3 (ii): no vertex is the target of two
         * collapses of one level) */
        if (j == k || b >= nidx || t->split_of[b] != ST_NIL) {
            t->irregular = 1;
            continue;
        }
        t->fl[j] |= RING_FRAME_V;
        t->split_of[b] = v;
    }
    t->off[nidx] = k;
    free(vmin);
}

/* The ring table of level l in the cache, if it was built from the map as
 * it is now; else NULL. */
static pm_ring_table *current_table(st_hier *h, unsigned l)
{
    st_map *m = &h->map;
    st_level_cache *cache = &h->cache[l];
    pm_ring_table *t = cache->free == table_free ? cache->p : NULL;
    if (t && t->gen == st_map_generation(m) && t->dend == m->darts.end && t->vend == m->verts.end && t->top == m->top &&
        t->mu == pm_relax_weight(h, l))
        return t;
    return NULL;
}

/* The ring table of level l, built if the cache holds none for the map as
 * it is now. */
static const pm_ring_table *ring_table(st_hier *h, unsigned l)
{
    st_map *m = &h->map;
    st_level_cache *cache = &h->cache[l];
    pm_ring_table *t = current_table(h, l);
    if (t) return t;
    uint64_t gen = st_map_generation(m);
    double mu = pm_relax_weight(h, l);
    if (cache->p) cache->free(cache->p);
    cache->p = NULL;
    t = calloc(1, sizeof *t);
    if (!t) abort();
    t->gen = gen;
    t->dend = m->darts.end;
    t->vend = m->verts.end;
    t->top = m->top;
    t->mu = mu;
    table_fill(m, l, t);
    cache->p = t;
    cache->free = table_free;
    return t;
}

/* ---- evaluation ------------------------------------------------------------- */

typedef struct level_pair {
    const st_map *m;
    unsigned L;
    const pm_ring_table *fine, *coarse;   /* tables of L and L-1 */
    st_level_view pv;                     /* positions of L-1 */
} level_pair;

static void acc(const level_pair *lp, double w, uint32_t u, double s[3])
{
    const double *p = st_v_pos(&lp->pv, u);
    s[0] += w * p[0];
    s[1] += w * p[1];
    s[2] += w * p[2];
}

static void ring_sum(const level_pair *lp, uint32_t v, int border, double w, double s[3])
{
    const pm_ring_table *t = lp->fine;
    for (uint32_t j = t->off[v]; j < t->off[v + 1]; j++)
        if ((!border || (t->fl[j] & RING_BORDER)) && lp->m->verts.ins[t->nbr[j]] < lp->L) acc(lp, w, t->nbr[j], s);
}

/* The frame vertex at L-1 of split vertex v. */
static uint32_t split_frame_vertex(const pm_ring_table *t, uint32_t v)
{
    for (uint32_t j = t->off[v]; j < t->off[v + 1]; j++)
        if (t->fl[j] & RING_FRAME_V) return t->nbr[j];
    return v; /* not reached: the table is irregular otherwise */
}

/* S(P_{L-1})(v): st_progressive_stencil's weights, summed in its order as
 * st_stencil_eval sums them. */
static void predict(const level_pair *lp, uint32_t v, double s[3])
{
    const st_map *m = lp->m;
    const pm_ring_table *t = lp->fine;
    unsigned L = lp->L;
    s[0] = s[1] = s[2] = 0;
    int border = t->vk[v] & VERT_BORDER;
    if (m->verts.ins[v] == L) {
        uint32_t n = t->avg_n[v];
        if (n) ring_sum(lp, v, border, 1.0 / n, s);
        else acc(lp, 1.0, split_frame_vertex(t, v), s);
        return;
    }
    if (!(t->vk[v] & VERT_NEAR)) {
        acc(lp, 1.0, v, s);
        return;
    }
    acc(lp, 1.0 - t->mu, v, s);
    unsigned k = t->off[v + 1] - t->off[v];
    if (border) {
        k = 0;
        for (uint32_t j = t->off[v]; j < t->off[v + 1]; j++) k += (t->fl[j] & RING_BORDER) != 0;
    }
    double wk = t->mu / k;
    for (uint32_t j = t->off[v]; j < t->off[v + 1]; j++) {
        if (border && !(t->fl[j] & RING_BORDER)) continue;
        uint32_t u = t->nbr[j];
        if (m->verts.ins[u] < L) {
            acc(lp, wk, u, s);
            continue;
        }
        uint32_t n = t->avg_n[u];
        if (!n) {
            acc(lp, 1.0 * wk, v, s);
            continue;
        }
        double wu = 1.0 / n * wk;
        ring_sum(lp, u, t->vk[u] & VERT_BORDER, wu, s);
    }
}

/* st_hier_frame's vertex frame of z at L-1, with its orthonormalisation
 * (st_frame_orthonormal, hier_internal.h): a frame must have the same bits
 * whichever path computed it (test_progressive compares both).  From z's
 * ring at L-1: the sum
 * of its corner normals over real faces, and the tangent to the first
 * neighbour. */
static void vertex_frame(const level_pair *lp, uint32_t z, double f[3][3])
{
    const pm_ring_table *t = lp->coarse;
    const double *p = st_v_pos(&lp->pv, z);
    double n[3] = { 0, 0, 0 }, tg[3];
    uint32_t beg = t->off[z], end = t->off[z + 1];
    for (uint32_t j = beg; j < end; j++) {
        if (t->fl[j] & RING_OPEN) continue;
        uint32_t jn = j + 1 < end ? j + 1 : beg;
        double a[3], b[3], cr[3];
        st_sub3(p, st_v_pos(&lp->pv, t->nbr[j]), a);
        st_sub3(st_v_pos(&lp->pv, t->nbr[jn]), p, b);
        st_cross3(a, b, cr);
        n[0] += cr[0]; n[1] += cr[1]; n[2] += cr[2];
    }
    st_sub3(st_v_pos(&lp->pv, t->nbr[beg]), p, tg);
    st_frame_orthonormal(tg, n, f);
}

/* P_L(v) = S(P_{L-1})(v) + F D_L(v) (st_stencil_apply). */
static void synth_vertex(const st_hier *h, const level_pair *lp, uint32_t v, double out[3])
{
    predict(lp, v, out);
    const double *d = st_hier_detail(h, lp->L, v);
    if (d[0] == 0 && d[1] == 0 && d[2] == 0) return;
    double f[3][3];
    vertex_frame(lp, lp->m->verts.ins[v] == lp->L ? split_frame_vertex(lp->fine, v) : v, f);
    for (int i = 0; i < 3; i++) out[i] += d[0] * f[0][i] + d[1] * f[1][i] + d[2] * f[2][i];
}

/* The tables of L and L-1, or 0 when either is irregular. */
static int level_pair_init(st_hier *h, unsigned L, level_pair *lp)
{
    if (L == 0 || L > h->map.top) return 0;
    lp->m = &h->map;
    lp->L = L;
    lp->coarse = ring_table(h, L - 1);
    lp->fine = ring_table(h, L);
    if (lp->coarse->irregular || lp->fine->irregular) return 0;
    st_level_view_init(&h->map, L - 1, &lp->pv);
    return 1;
}

int st_progressive_predict_vertex(st_hier *h, unsigned L, uint32_t v, double pred[3], double f[3][3])
{
    if (L == 0 || L > h->map.top) return 0;
    const pm_ring_table *fine = current_table(h, L), *coarse = current_table(h, L - 1);
    if (!fine || !coarse || fine->irregular || coarse->irregular) return 0;
    if (v >= fine->nidx || fine->off[v] == fine->off[v + 1]) return 0;
    level_pair lp = { .m = &h->map, .L = L, .fine = fine, .coarse = coarse };
    st_level_view_init(&h->map, L - 1, &lp.pv);
    predict(&lp, v, pred);
    vertex_frame(&lp, h->map.verts.ins[v] == L ? split_frame_vertex(fine, v) : v, f);
    return 1;
}

int st_progressive_synth_level(st_hier *h, unsigned L)
{
    level_pair lp;
    if (!level_pair_init(h, L, &lp)) return 0;
    const pm_ring_table *t = lp.fine;
    for (uint32_t v = 0; v < t->nidx; v++) {
        if (t->off[v] == t->off[v + 1]) continue;
        double p[3];
        synth_vertex(h, &lp, v, p);
        st_hier_write_pos(h, v, L, p);
    }
    return 1;
}

/* A set of vertex ids, a bit each (some thirty additions per changed
 * vertex: no bookkeeping besides the bit). */
typedef struct vset { uint64_t *w; } vset;

static void vset_add(vset *s, uint32_t v) { s->w[v >> 6] |= 1ull << (v & 63); }

static int vset_has(const vset *s, uint32_t v) { return (s->w[v >> 6] >> (v & 63)) & 1; }

/* (Zero words skipped: a fine level's set is sparse, and without -mpopcnt
 * each count is a library call.) */
static uint32_t vset_count(const vset *s, uint32_t words)
{
    uint32_t n = 0;
    for (uint32_t k = 0; k < words; k++)
        if (s->w[k]) n += (uint32_t)__builtin_popcountll(s->w[k]);
    return n;
}

/* The vertices of s, in id order, into out; returns how many. */
static uint32_t vset_list(const vset *s, uint32_t words, uint32_t *out)
{
    uint32_t n = 0;
    for (uint32_t k = 0; k < words; k++)
        for (uint64_t b = s->w[k]; b; b &= b - 1) out[n++] = (k << 6) | (uint32_t)__builtin_ctzll(b);
    return n;
}

/* ---- memory access of a local pass ------------------------------------------
 *
 * The vertices of an edit's region are numbered by the level that split
 * them (progressive.h), so where they are sparse among the ids each one
 * reads table rows and positions that no vertex before it brought into
 * the cache, some fifteen lines, where the full pass streams; and one
 * vertex's evaluation is too long for the processor to reach the next
 * one's loads by itself.  The local pass ran at a third of the full
 * pass's instructions per second.  So a sparse pass loads a block of
 * vertices' lines first, in short loops whose loads do not depend on each
 * other and overlap, then evaluates the block from the cache (prefetch
 * instructions a few vertices ahead gained about half as much on koala).
 * A dense pass (a coarse edit: one candidate in two ids) streams like the
 * full pass and loads nothing ahead.  The readers' walk, short per
 * vertex, prefetches. */
enum {
    BLOCK = 32,        /* vertices loaded, then evaluated: some 500 lines, in L1/L2 */
    SPARSE_GAP = 8,    /* sparse: fewer than one candidate in SPARSE_GAP ids */
    AHEAD_ROWS = 8,    /* readers' walk: rows of the vertex this far ahead, */
    AHEAD_RING = 4,    /* then its ring entries */
};

typedef struct touch_sum { uint64_t x; } touch_sum;   /* keeps the loads */

static void touch(touch_sum *t, const double *p)
{
    uint64_t w;
    memcpy(&w, p, sizeof w);
    t->x ^= w;
}

/* The rows of the block's vertices: their table entries at L and L-1,
 * stamp, detail, and positions at L (compared, then written) and L-1. */
static void touch_rows(const st_hier *h, const level_pair *lp, const uint32_t *v, uint32_t n, touch_sum *t)
{
    const pm_ring_table *ft = lp->fine, *ct = lp->coarse;
    unsigned L = lp->L;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t x = v[i];
        t->x ^= ft->off[x + 1] ^ ft->vk[x] ^ ft->avg_n[x] ^ ft->first[x] ^ h->stamp.v[x];
        if (x < ct->nidx) t->x ^= ct->off[x + 1];
        if (x < h->detail_cap[L]) touch(t, h->detail[L] + 3 * (size_t)x);
        touch(t, st_pos(lp->m, x, L));
        touch(t, st_v_pos(&lp->pv, x));
    }
}

/* Their rings at L and L-1 and the neighbours' positions at L-1 (the rows
 * are in the cache now).  The coarse ring's neighbours are mostly the fine
 * ring's: their positions are not loaded twice. */
static void touch_rings(const level_pair *lp, const uint32_t *v, uint32_t n, touch_sum *t)
{
    const pm_ring_table *ft = lp->fine, *ct = lp->coarse;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t x = v[i];
        for (uint32_t j = ft->off[x]; j < ft->off[x + 1]; j++) {
            t->x ^= ft->fl[j];
            touch(t, st_v_pos(&lp->pv, ft->nbr[j]));
        }
        if (x < ct->nidx && ct->off[x] < ct->off[x + 1]) t->x ^= ct->nbr[ct->off[x]];
    }
}

/* The rows readers_of reads first for u changed at L-1, and then its rings. */
static void prefetch_reader_rows(const level_pair *lp, uint32_t u)
{
    __builtin_prefetch(&lp->fine->off[u]);
    __builtin_prefetch(&lp->fine->split_of[u]);
    __builtin_prefetch(&lp->coarse->off[u]);
}

static void prefetch_reader_rings(const level_pair *lp, uint32_t u)
{
    __builtin_prefetch(&lp->fine->nbr[lp->fine->off[u]]);
    __builtin_prefetch(&lp->coarse->nbr[lp->coarse->off[u]]);
}

/* Recomputes v; writes it and lists it for level L+1 when its position
 * changed.  Where level L had no position column of its own for v when
 * the pass began (own_cap: the ids it covered), v's position at L was read
 * from L-1 (map.h, "Storage"), and the first write of the pass copies the
 * new values of L-1 into a new column: a vertex that changed at L-1
 * (moved) then changed at L too, whatever the value read now. */
static void resynth_one(st_hier *h, const level_pair *lp, uint32_t v, int moved, uint32_t own_cap, st_synth_ctx *out)
{
    double p[3];
    synth_vertex(h, lp, v, p);
    int shared = moved && h->map.verts.ins[v] < lp->L && v >= own_cap;
    if (!shared && memcmp(p, st_pos(&h->map, v, lp->L), sizeof p) == 0) return;
    st_synth_put(out, v, lp->fine->first[v], p);
}

/* The vertices of level L that read a vertex u changed at L-1 (see the
 * top of this file), into cand; a split vertex's ring once (grown), not
 * once for each of its changed neighbours. */
static void readers_of(const level_pair *lp, uint32_t u, vset *cand, vset *grown)
{
    const pm_ring_table *ft = lp->fine, *ct = lp->coarse;
    const uint8_t *ins = lp->m->verts.ins;
    unsigned L = lp->L;
    vset_add(cand, u);
    for (uint32_t j = ft->off[u]; j < ft->off[u + 1]; j++) {
        uint32_t w = ft->nbr[j];
        vset_add(cand, w);
        if (ins[w] != L || vset_has(grown, w)) continue;
        vset_add(grown, w);
        for (uint32_t k = ft->off[w]; k < ft->off[w + 1]; k++) vset_add(cand, ft->nbr[k]);
    }
    if (ft->split_of[u] != ST_NIL) vset_add(cand, ft->split_of[u]);
    for (uint32_t j = ct->off[u]; j < ct->off[u + 1]; j++) {
        uint32_t z = ct->nbr[j];
        vset_add(cand, z);
        if (ft->split_of[z] != ST_NIL) vset_add(cand, ft->split_of[z]);
    }
}

/* The vertices changed at L-1 (the seeds' vertices, each once), into
 * moved and `changed`; returns how many.  A loop of independent lookups,
 * whose misses the processor overlaps. */
static uint32_t changed_vertices(const st_map *m, unsigned L, const uint32_t *seeds, uint32_t nseeds, vset *moved,
                                 uint32_t *changed)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < nseeds; i++) {
        uint32_t u = st_vert(m, seeds[i], L - 1);
        if (vset_has(moved, u)) continue;
        vset_add(moved, u);
        changed[n++] = u;
    }
    return n;
}

/* Recomputes the candidates cand[0..n) (id order) a block at a time. */
static void resynth_blocks(st_hier *h, const level_pair *lp, const uint32_t *cand, uint32_t n, const vset *moved,
                           st_synth_ctx *out)
{
    const st_map *m = &h->map;
    uint32_t own = m->pos.col[lp->L] ? m->pos.colcap[lp->L] : 0;
    int sparse = (uint64_t)n * SPARSE_GAP < lp->fine->nidx;
    touch_sum ts = { 0 };
    for (uint32_t b = 0; b < n; b += BLOCK) {
        uint32_t e = n - b < BLOCK ? n : b + BLOCK;
        if (sparse) {
            touch_rows(h, lp, cand + b, e - b, &ts);
            touch_rings(lp, cand + b, e - b, &ts);
        }
        for (uint32_t i = b; i < e; i++) resynth_one(h, lp, cand[i], vset_has(moved, cand[i]), own, out);
    }
    __asm__ volatile("" ::"r"(ts.x)); /* the loads are not dead */
}

int st_progressive_resynth_around(st_hier *h, unsigned L, const uint32_t *seeds, uint32_t nseeds, st_synth_ctx *out)
{
    level_pair lp;
    if (!level_pair_init(h, L, &lp)) return 0;
    uint32_t words = (lp.fine->nidx + 63) >> 6;
    vset cand = { calloc(words ? words : 1, sizeof(uint64_t)) };
    vset moved = { calloc(words ? words : 1, sizeof(uint64_t)) };
    vset grown = { calloc(words ? words : 1, sizeof(uint64_t)) };
    uint32_t *changed = malloc((size_t)(nseeds ? nseeds : 1) * sizeof *changed);
    if (!cand.w || !moved.w || !grown.w || !changed) abort(); /* a bit per vertex */
    uint32_t nu = changed_vertices(&h->map, L, seeds, nseeds, &moved, changed);
    for (uint32_t i = 0; i < nu; i++) {
        if (i + AHEAD_ROWS < nu) prefetch_reader_rows(&lp, changed[i + AHEAD_ROWS]);
        if (i + AHEAD_RING < nu) prefetch_reader_rings(&lp, changed[i + AHEAD_RING]);
        readers_of(&lp, changed[i], &cand, &grown);
    }
    free(changed);
    /* In id order: the tables and positions are read in their order. */
    uint32_t n = vset_count(&cand, words);
    uint32_t *list = malloc((size_t)(n ? n : 1) * sizeof *list);
    if (!list) abort();
    vset_list(&cand, words, list);
    resynth_blocks(h, &lp, list, n, &moved, out);
    free(list);
    free(cand.w);
    free(moved.w);
    free(grown.w);
    return 1;
}

/* Bytes of a table of nidx vertex ids and `entries` ring entries (the
 * arrays table_fill allocates). */
static size_t table_bytes(uint64_t nidx, uint64_t entries)
{
    const pm_ring_table *t = NULL; /* sizeof only */
    double n = (double)sizeof *t + (double)(nidx + 1) * (double)sizeof *t->off +
               (double)nidx * (double)(sizeof *t->first + sizeof *t->split_of + sizeof *t->vk + sizeof *t->avg_n) +
               (double)entries * (double)(sizeof *t->nbr + sizeof *t->fl);
    return n >= (double)SIZE_MAX ? SIZE_MAX : (size_t)n;
}

static const pm_ring_table *cached_table(const st_hier *h, unsigned l)
{
    return h->cache[l].free == table_free ? h->cache[l].p : NULL;
}

size_t st_progressive_table_bytes(const st_hier *h)
{
    size_t n = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        const pm_ring_table *t = cached_table(h, l);
        if (t) n += table_bytes(t->nidx, t->off ? t->off[t->nidx] : 0);
    }
    return n;
}

size_t st_progressive_synth_estimate(const st_hier *h, unsigned from)
{
    const st_map *m = &h->map;
    if (from >= m->top) return 0;
    /* A table of level l has an entry per dart of l (the live darts of
     * levels 0..l: a progressive hierarchy removes none going finer) and
     * indexes the vertex ids up to the largest of l, which st_pool_cover
     * bounds by its block.  Levels from..top: synthesis of L reads the
     * tables of L and L-1. */
    double n = 0;
    for (unsigned l = from; l <= m->top; l++)
        if (!cached_table(h, l))
            n += (double)table_bytes(st_pool_cover(&m->verts, l + 1), st_pool_count(&m->darts, l));
    /* table_fill's scratch, a dart per vertex id, one table at a time;
     * the position columns the synthesis writes */
    n += (double)m->verts.end * sizeof(uint32_t) + (double)st_estimate_position_columns(m, from);
    return n >= (double)SIZE_MAX ? SIZE_MAX : (size_t)n;
}

/* ---- the build's details (progressive_internal.h) ---------------------------- */

int st_progressive_predict_range(st_hier *h, unsigned L, uint32_t begin, uint32_t end, pm_predicted_fn fn, void *ctx)
{
    level_pair lp;
    if (!level_pair_init(h, L, &lp)) return 0;
    const pm_ring_table *t = lp.fine;
    const uint8_t *ins = lp.m->verts.ins;
    if (end > t->nidx) end = t->nidx;
    for (uint32_t v = begin; v < end; v++) {
        if (t->off[v] == t->off[v + 1]) continue;
        int split = ins[v] == L;
        /* Predicted by itself (st_progressive_stencil's (v, 1)): a zero
         * detail, unless its position changed from L-1 (level 0's placed
         * vertices at level 1: progressive.h, point 8). */
        if (!split && !(t->vk[v] & VERT_NEAR)) {
            const double *below = st_v_pos(&lp.pv, v), *here = st_pos(lp.m, v, L);
            if (below == here || !memcmp(below, here, 3 * sizeof(double))) continue; /* (one slot: no read) */
        }
        double pred[3], f[3][3];
        predict(&lp, v, pred);
        vertex_frame(&lp, split ? split_frame_vertex(t, v) : v, f);
        fn(ctx, v, pred, f);
    }
    return 1;
}

void st_progressive_drop_table(st_hier *h, unsigned l)
{
    st_level_cache *cache = &h->cache[l];
    if (cache->free != table_free) return;
    table_free(cache->p);
    cache->p = NULL;
    cache->free = NULL;
}

