/* Half-edge adjacency of a polygon soup for the unsubdivide pass: flat
 * arrays indexed by corner (a face's corner c is the half-edge from its
 * vertex to the next corner's), built in O(corners) from a repaired mesh
 * (st_mesh_repair: an oriented 2-manifold, so a half-edge has at most one
 * twin). */
#ifndef ST_UNSUB_TOPO_INTERNAL_H
#define ST_UNSUB_TOPO_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/io/mesh.h"
#include "core/map/map.h"

typedef struct st_unsub_topo {
    uint32_t nv, nf, nc;
    const uint32_t *foff, *fidx;  /* the mesh's faces (not owned) */
    uint32_t *face_of;            /* per corner: its face */
    uint32_t *out_off;            /* nv + 1 offsets into out_c */
    uint32_t *out_c;              /* corners grouped by their vertex */
    uint32_t *out_t;              /* beside out_c: where each corner's half-edge ends (one
                                     cache line answers a half-edge lookup) */
    uint32_t *twin;               /* per corner: the opposite half-edge, ST_NIL on the boundary */
    uint8_t *bnd;                 /* per vertex: 1 on the boundary */
    uint32_t *valence;            /* per vertex: number of neighbours */
} st_unsub_topo;

/* -1 when out of memory (t is then empty). */
int st_unsub_topo_build(st_unsub_topo *t, const st_mesh *m);
void st_unsub_topo_free(st_unsub_topo *t);

/* What st_mesh_check promises for a mesh read off a labelling, in
 * O(corners) on t: faces of 3+ distinct vertices, each half-edge once,
 * every vertex used and its faces one fan.  0, or -1 with a vertex
 * (0-based) in *where. */
int st_unsub_topo_manifold(const st_unsub_topo *t, uint32_t *where);

static inline uint32_t st_unsub_next(const st_unsub_topo *t, uint32_t c)
{
    uint32_t f = t->face_of[c];
    return c + 1 == t->foff[f + 1] ? t->foff[f] : c + 1;
}
static inline uint32_t st_unsub_prev(const st_unsub_topo *t, uint32_t c)
{
    uint32_t f = t->face_of[c];
    return c == t->foff[f] ? t->foff[f + 1] - 1 : c - 1;
}
/* The vertex a corner's half-edge ends at. */
static inline uint32_t st_unsub_target(const st_unsub_topo *t, uint32_t c) { return t->fidx[st_unsub_next(t, c)]; }
/* The corner of the half-edge a -> b, or ST_NIL. */
static inline uint32_t st_unsub_find(const st_unsub_topo *t, uint32_t a, uint32_t b)
{
    for (uint32_t k = t->out_off[a]; k < t->out_off[a + 1]; k++)
        if (t->out_t[k] == b) return t->out_c[k];
    return ST_NIL;
}

#endif
