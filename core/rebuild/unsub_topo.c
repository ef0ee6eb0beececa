/* Half-edge adjacency for the unsubdivide pass (unsub_topo_internal.h). */
#include "core/rebuild/unsub_topo_internal.h"
#include "core/base/hugepage.h"
#include "core/base/parallel.h"

#include <stdlib.h>
#include <string.h>

void st_unsub_topo_free(st_unsub_topo *t)
{
    free(t->face_of); free(t->out_off); free(t->out_c); free(t->out_t); free(t->twin); free(t->bnd); free(t->valence);
    memset(t, 0, sizeof *t);
}

typedef struct topo_slot { uint32_t c, t, in_c, in_s; } topo_slot;

/* The twin of a -> b is the in-coming half-edge b -> a: one in an
 * oriented manifold; in a mesh read off a wrong labelling there may be
 * more, and the smallest corner is taken, as st_unsub_find(b, a) gives
 * (b's slots are in corner order), so that the manifold check reports
 * the same vertex either way.  Vertices a in [v0, v1): each writes its own
 * slots' entries and the twins of its own out-going corners only, so
 * vertex ranges run on separate threads with the same result. */
static void twins_of(st_unsub_topo *t, const topo_slot *slot, uint32_t v0, uint32_t v1)
{
    for (uint32_t a = v0; a < v1; a++) {
        uint32_t lo = t->out_off[a], hi = t->out_off[a + 1];
        for (uint32_t k = lo; k < hi; k++) {
            uint32_t b = slot[k].t, tw = ST_NIL;
            for (uint32_t j = lo; j < hi; j++)
                if (slot[j].in_s == b && slot[j].in_c < tw) tw = slot[j].in_c;
            t->twin[slot[k].c] = tw;
            t->out_c[k] = slot[k].c;
            t->out_t[k] = b;
            if (tw == ST_NIL) t->bnd[a] = 1;
        }
        /* A boundary fan has one neighbour more than out-going half-edges. */
        t->valence[a] = hi - lo + t->bnd[a];
    }
}

typedef struct twins_job { st_unsub_topo *t; const topo_slot *slot; } twins_job;

static void twins_task(st_team *team, unsigned th, void *ctx)
{
    (void)th;
    twins_job *j = ctx;
    uint32_t b, e;
    while (st_team_next(team, 0, j->t->nv, 16384, &b, &e)) twins_of(j->t, j->slot, b, e);
}

/* Fewer vertices than this: one thread (starting threads costs more). */
#define TWINS_MIN_VERTS 65536u

int st_unsub_topo_build(st_unsub_topo *t, const st_mesh *m)
{
    memset(t, 0, sizeof *t);
    t->nv = m->nverts;
    t->nf = m->nfaces;
    t->nc = m->face_off[m->nfaces];
    t->foff = m->face_off;
    t->fidx = m->face_idx;
    size_t nc = (size_t)t->nc + 1, nv = (size_t)t->nv + 1;
    /* Written in full right away: huge pages, one fault per 2 MiB
     * (hugepage.h; this function took a sixth of bench_unsubdivide's page
     * faults with 4 KiB pages). */
    t->face_of = st_malloc_huge(nc * sizeof *t->face_of);
    t->out_off = st_calloc_huge(nv + 1, sizeof *t->out_off);
    t->out_c = st_malloc_huge(nc * sizeof *t->out_c);
    t->out_t = st_malloc_huge(nc * sizeof *t->out_t);
    t->twin = st_malloc_huge(nc * sizeof *t->twin);
    t->bnd = st_calloc_huge(nv, 1);
    t->valence = st_malloc_huge(nv * sizeof *t->valence);
    if (!t->face_of || !t->out_off || !t->out_c || !t->out_t || !t->twin || !t->bnd || !t->valence) {
        st_unsub_topo_free(t);
        return -1;
    }
    for (uint32_t f = 0; f < t->nf; f++)
        for (uint32_t c = t->foff[f]; c < t->foff[f + 1]; c++) {
            t->face_of[c] = f;
            t->out_off[t->fidx[c] + 1]++;
        }
    for (uint32_t v = 0; v < t->nv; v++) t->out_off[v + 1] += t->out_off[v];
    /* Counting sort by vertex; valence[] is the fill cursor for now.
     * Slot k of a's out-going corner c first takes, in one record, c, where
     * its half-edge ends, the corner before c in its face (the half-edge
     * coming into a) and where that one starts: one cache line written per
     * corner, where four arrays would be four (with an arbitrary vertex
     * order, another program's, the slots of consecutive corners lie far
     * apart).  a's in-coming half-edges are then all in a's own slots, so
     * its twins are found there, without reading the slots of a's
     * neighbours.  (Cachegrind with a 2 MiB last-level cache,
     * bench_unsubdivide --levels 3 --no-hier: 11.5 M last-level misses in
     * this function when each twin was looked up in the neighbour's slots,
     * 5.8 M so.) */
    topo_slot *slot = st_malloc_huge(nc * sizeof *slot);
    if (!slot) {
        st_unsub_topo_free(t);
        return -1;
    }
    memcpy(t->valence, t->out_off, (size_t)t->nv * sizeof *t->valence);
    for (uint32_t f = 0; f < t->nf; f++) {
        uint32_t lo = t->foff[f], hi = t->foff[f + 1];
        for (uint32_t c = lo; c < hi; c++) {
            uint32_t pc = c > lo ? c - 1 : hi - 1;
            slot[t->valence[t->fidx[c]]++] = (topo_slot){ c, t->fidx[c + 1 < hi ? c + 1 : lo], pc, t->fidx[pc] };
        }
    }
    twins_job j = { t, slot };
    st_team_run(t->nv < TWINS_MIN_VERTS ? 1 : st_parallel_threads(), twins_task, &j);
    free(slot);
    return 0;
}

/* The faces around v from corner c0 one way (c -> twin(prev(c))), then, on
 * the boundary, the other way (c -> next(twin(c))): one fan iff every
 * out-going half-edge of v is reached. */
static uint32_t fan_size(const st_unsub_topo *t, uint32_t c0)
{
    uint32_t n = 0, c = c0, cap = t->nc;
    do {
        n++;
        c = t->twin[st_unsub_prev(t, c)];
    } while (c != ST_NIL && c != c0 && n <= cap);
    if (c == c0) return n;
    for (uint32_t x = t->twin[c0]; x != ST_NIL && n <= cap; x = t->twin[x]) {
        n++;
        x = st_unsub_next(t, x);
        if (x == c0) break;
    }
    return n;
}

int st_unsub_topo_manifold(const st_unsub_topo *t, uint32_t *where)
{
    for (uint32_t f = 0; f < t->nf; f++) {
        uint32_t b = t->foff[f], n = t->foff[f + 1] - b;
        if (n < 3) { *where = n ? t->fidx[b] : 0; return -1; }
        for (uint32_t i = 0; i < n; i++)
            for (uint32_t j = i + 1; j < n; j++)
                if (t->fidx[b + i] == t->fidx[b + j]) { *where = t->fidx[b + i]; return -1; }
    }
    for (uint32_t v = 0; v < t->nv; v++) {
        uint32_t lo = t->out_off[v], hi = t->out_off[v + 1];
        if (lo == hi) { *where = v; return -1; }
        for (uint32_t k = lo; k < hi; k++)
            for (uint32_t j = k + 1; j < hi; j++)
                if (t->out_t[k] == t->out_t[j]) { *where = v; return -1; }
        if (fan_size(t, t->out_c[lo]) != hi - lo) { *where = v; return -1; }
    }
    return 0;
}
