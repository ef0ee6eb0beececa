/* Primal quadrisection in the multiresolution map (thesis §3.2.1, figs
 * 3.13 and 3.15).  Level L = l+1 starts as a copy of level l (O(1), map.h);
 * then every edge is split at L, and every face is cut at L.  Only β0 of old
 * darts changes across levels: β1 and vert of old darts never do, which is
 * what keeps the topology at ~15 bytes per finest dart. */
#include "refine.h"

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

int st_refine_uniform(st_map *m, enum st_split_mode mode, st_error *err)
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
