/* Estimates of what an operation will cost (estimate.h). */
#include "core/multires/estimate.h"
#include "core/map/map_memory.h"
#include "core/map/pool_internal.h"
#include "core/fvar/fvar_internal.h"

/* Measured on the shared meshes (strata info: topology and position bytes
 * of each level over its darts and vertices): 11.5-12.2 bytes of topology
 * per dart of a level, 24.7-25 bytes of positions per vertex. */
#define TOPOLOGY_BYTES_PER_DART 11.8
#define POSITION_BYTES_PER_VERTEX 24.8
/* Peak resident growth over the map's own bytes (synthesis tables, scratch,
 * allocator slack), per scheme: measured by tests/core/test_membudget.c on the
 * shared meshes (Doo-Sabin's dual encoding and √3's flips keep the most). */
static double peak_over_map(st_scheme_id id)
{
    switch (id) {
    case ST_SCHEME_CATMARK: return 1.3;
    case ST_SCHEME_LOOP: return 1.2;
    case ST_SCHEME_SQRT3: return 1.4;
    case ST_SCHEME_DOOSABIN: return 1.65;
    default: return 1.15;
    }
}

void st_estimate_next_level(st_scheme_id scheme, unsigned next_level, const st_level_stats *l, uint64_t *triangles,
                            st_level_stats *n)
{
    uint64_t V = l->vertices, E = l->edges, F = l->faces;
    /* Σ deg over real faces: every edge has two sides, a boundary edge one. */
    uint64_t sum_deg = 2 * E - l->boundary_edges;
    *n = *l;
    switch (scheme) {
    case ST_SCHEME_LOOP:
    case ST_SCHEME_BUTTERFLY:
        n->vertices = V + E; n->edges = 2 * E + 3 * F; n->faces = 4 * F;
        n->boundary_edges = 2 * l->boundary_edges;
        break;
    case ST_SCHEME_QUADTRI: {
        /* triangles into 4 triangles, other n-gons into n quads */
        uint64_t T = *triangles;
        n->vertices = V + E + (F - T); n->edges = 2 * E + sum_deg; n->faces = T + sum_deg;
        n->boundary_edges = 2 * l->boundary_edges;
        *triangles = 4 * T;
        break;
    }
    case ST_SCHEME_SQRT3: {
        /* even levels trisect each boundary edge, and its triangle gets no
         * centre (core/schemes/scheme_sqrt3.c) */
        uint64_t B = next_level % 2 == 0 ? l->boundary_edges : 0;
        n->vertices = V + F + B; n->edges = E + 3 * F + B; n->faces = 3 * F;
        n->boundary_edges = l->boundary_edges + 2 * B;
        break;
    }
    case ST_SCHEME_DOOSABIN:
        /* a corner per face side, and Chaikin's two points per boundary vertex */
        n->vertices = 2 * E + l->boundary_edges; n->edges = 4 * E + l->boundary_edges; n->faces = F + E + V;
        n->boundary_edges = 2 * l->boundary_edges;
        break;
    default: /* polygon split */
        n->vertices = V + E + F; n->edges = 2 * E + sum_deg; n->faces = sum_deg;
        n->boundary_edges = 2 * l->boundary_edges;
        break;
    }
    n->darts = 2 * n->edges;
    n->euler = (int64_t)n->vertices - (int64_t)n->edges + (int64_t)n->faces;
}

static double level_bytes(const st_level_stats *s)
{
    return TOPOLOGY_BYTES_PER_DART * (double)s->darts + POSITION_BYTES_PER_VERTEX * (double)s->vertices;
}

uint64_t st_level_triangles(const st_map *m, unsigned l)
{
    uint64_t n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d)) continue;
        /* counted once, at the face's smallest dart */
        uint32_t x = st_phi1(m, d, l), y = st_phi1(m, x, l);
        if (st_phi1(m, y, l) == d && d < x && d < y) n++;
    }
    return n;
}

size_t st_hier_estimate_subdivide(st_hier *h, unsigned levels, st_level_stats *finest)
{
    st_map *m = &h->map;
    /* Nothing to add: no walk of the top level (an interest box's budget
     * check asks this at every move, with the base at or below the top,
     * and the walk follows the model's size, not the move's). */
    if (levels <= m->top && !finest) return 0;
    st_level_stats s;
    st_level_stats_compute(m, m->top, &s);
    uint64_t triangles = h->scheme->id == ST_SCHEME_QUADTRI && levels > m->top ? st_level_triangles(m, m->top) : 0;
    double bytes = 0;
    /* Face-varying UVs: a UV and a label per dart id of each new level. */
    double uv_per_dart = st_fvar_continues(h->fvar, h->map.top, h->scheme) ? ST_FVAR_BYTES_PER_DART : 0;
    for (unsigned l = m->top; l < levels; l++) {
        st_level_stats next;
        st_estimate_next_level(h->scheme->id, l + 1, &s, &triangles, &next);
        s = next;
        bytes += level_bytes(&s) + uv_per_dart * (double)s.darts;
    }
    if (finest) *finest = s;
    bytes *= peak_over_map(h->scheme->id);
    return bytes >= (double)SIZE_MAX ? SIZE_MAX : (size_t)bytes;
}

size_t st_estimate_position_columns(const st_map *m, unsigned from)
{
    double n = 0;
    for (unsigned l = from + 1; l <= m->top && l < ST_MAX_LEVELS; l++)
        if (!m->pos.col[l]) n += (double)st_pool_cover(&m->verts, l) * (double)m->pos.elem; /* st_mla_column */
    return n >= (double)SIZE_MAX ? SIZE_MAX : (size_t)n;
}

size_t st_hier_synth_estimate(const st_hier *h, unsigned from)
{
    if (h->scheme && h->scheme->synth_estimate) {
        st_subdiv_view v = st_hier_view((st_hier *)h); /* an estimate reads only */
        return h->scheme->synth_estimate(&v, from);
    }
    return st_estimate_position_columns(&h->map, from);
}

size_t st_estimate_mesh_bytes(uint64_t nverts, uint64_t nfaces, uint64_t ncorners)
{
    /* positions and normals in double, a uint32 index per corner and an
     * offset per face, twice over for the writer's copy. */
    double b = 2.0 * (48.0 * (double)nverts + 4.0 * (double)ncorners + 4.0 * (double)nfaces);
    return b >= (double)SIZE_MAX ? SIZE_MAX : (size_t)b;
}
