/* Primal refinement with sharpness propagation: the topology of level
 * top+1 (core/map/refine.c, Kraemer 2008 §3.2.1) and the sharpness of its
 * child edges and vertices by the crease rules (DeRose et al. 1998;
 * OpenSubdiv's Sdc::Crease: uniform decay, or Chaikin's), what the primal
 * schemes' refine() does.  The children's sharpness is taken from level
 * top before the split, as Chaikin's rule reads the semi-sharp edges of the
 * parent level around each vertex. */
#include "core/schemes/crease_internal.h"
#include "core/map/pool_internal.h"

#include <stdlib.h>

void st_subdiv_store_edge_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l, float s)
{
    st_map *m = sv->map;
    st_map_changed(m); /* sharpness decides which cells take the crease rules: caches depend on it */
    st_mla_set(sv->edge_sharp, &m->darts, d, l, &s);
    st_mla_set(sv->edge_sharp, &m->darts, st_beta0(m, d, l), l, &s);
}

void st_subdiv_store_vertex_sharpness(const st_subdiv_view *sv, uint32_t v, unsigned l, float s)
{
    st_map_changed(sv->map);
    st_mla_set(sv->vertex_sharp, &sv->map->verts, v, l, &s);
}

/* A coarse edge (d, e) of level L-1 splits into (d, β0(d,L)) and
 * (e, β0(e,L)) at level L (st_split_edge). */
typedef struct sharp_edge { uint32_t d, e; float cd, ce; } sharp_edge;

static sharp_edge *collect_sharp_edges(const st_subdiv_view *sv, unsigned l, uint32_t *n)
{
    *n = 0;
    if (!sv->has_sharpness) return NULL;
    st_map *m = sv->map;
    uint32_t cap = 16;
    sharp_edge *out = malloc(cap * sizeof *out);
    if (!out) abort();
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t e = st_beta0(m, d, l);
        float s = st_subdiv_edge_sharpness(sv, d, l);
        if (d > e || s <= 0) continue;
        if (*n == cap) { cap *= 2; out = realloc(out, cap * sizeof *out); if (!out) abort(); }
        out[(*n)++] = (sharp_edge){ d, e, st_crease_child_edge_sharpness(sv, d, l), st_crease_child_edge_sharpness(sv, e, l) };
    }
    return out;
}

/* Level L is the top: nothing finer to derive again. */
static void propagate_sharpness(const st_subdiv_view *sv, unsigned L, const sharp_edge *edges, uint32_t n)
{
    if (!sv->has_sharpness) return;
    st_map *m = sv->map;
    for (uint32_t i = 0; i < n; i++) {
        st_subdiv_store_edge_sharpness(sv, edges[i].d, L, edges[i].cd);
        st_subdiv_store_edge_sharpness(sv, edges[i].e, L, edges[i].ce);
    }
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, L - 1, &it); v != ST_NIL; v = st_vertex_next(m, L - 1, &it)) {
        float s = st_subdiv_vertex_sharpness(sv, v, L - 1);
        if (s > 0) st_subdiv_store_vertex_sharpness(sv, v, L, st_crease_decay(s));
    }
}

int st_subdiv_refine_primal(const st_subdiv_view *sv, enum st_split_mode mode, st_error *err)
{
    uint32_t n;
    sharp_edge *edges = collect_sharp_edges(sv, sv->map->top, &n);
    int rc = st_refine_uniform(sv->map, mode, err);
    if (!rc) propagate_sharpness(sv, sv->map->top, edges, n);
    free(edges);
    return rc;
}
