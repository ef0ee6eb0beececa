/* √3 refinement in the multiresolution map (see refine_sqrt3.h).
 *
 * Centre split of a triangle (c0 c1 c2) at level L (fig. 3.46):
 *
 *   cut_face(c0, c1)   x: c0 -> c1 in (x c1 c2), y = β0(x) in the 2-gon (c0 y)
 *   split_edge(y, C)   y: c1 -> C, a: C -> c0: triangle (c0 y a),
 *                      b = β0(y): C -> c1 in the quad (x b c1 c2)
 *   cut_face(b, c2)    triangles (z c2 x) and (β0(z) b c1)
 *
 * so the level-L triangle of each old dart c is (c, ., φ1⁻¹(c)) with
 * φ1⁻¹(c) starting at the centre.  Flipping the old edge (c, e) then makes
 * c start at the centre of e's face and e at the centre of c's face:
 * vert(β0(c), L) is the centre of c's level-(L-1) face (st_sqrt3_centre).
 *
 * Boundary fan of a triangle (d d1 d2), d: u -> w a boundary edge:
 *
 *   split_edge(d, A), split_edge(a, B)   (d a a2 d1 d2): u -> A -> B -> w -> x
 *   cut_face(d2, a), cut_face(z, a2)     triangles (u A x) (A B x) (B w x)
 */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/map/refine_sqrt3_internal.h"

#include <stdlib.h>

uint32_t st_sqrt3_face_boundary_dart(const st_map *m, uint32_t f, unsigned l)
{
    uint32_t x = f;
    do {
        if (st_is_boundary(m, st_beta0(m, x, l))) return x;
        x = st_phi1(m, x, l);
    } while (x != f);
    return ST_NIL;
}

uint32_t st_sqrt3_centre(const st_map *m, uint32_t f, unsigned L)
{
    unsigned l = L - 1;
    uint32_t x = f, interior = ST_NIL;
    int boundary = 0;
    do {
        if (!st_is_boundary(m, st_beta0(m, x, l))) { if (interior == ST_NIL) interior = x; }
        else boundary = 1;
        x = st_phi1(m, x, l);
    } while (x != f);
    if (boundary && st_sqrt3_boundary_step(L)) return ST_NIL; /* boundary fan */
    /* A flipped edge: β0(x) now starts at the centre of x's old face.  A
     * flipped dart starts at a centre, not at its level-l vertex; adaptive
     * refinement (adapt_sqrt3.c) leaves the edges toward unrefined
     * neighbours unflipped, so the first interior dart is not enough there.
     * (In a regular level every interior edge is flipped: the first
     * interior dart answers, as it always did.) */
    if (interior != ST_NIL) {
        x = interior;
        do {
            if (!st_is_boundary(m, st_beta0(m, x, l)) && st_vert(m, x, L) != st_vert(m, x, l))
                return st_vert(m, st_beta0(m, x, L), L);
            x = st_phi1(m, x, l);
        } while (x != interior);
    }
    /* No edge flipped (an isolated triangle, or an adaptive face whose
     * neighbours are all unrefined): the face of f at level L is
     * (f, ., φ1⁻¹(f)) and φ1⁻¹(f) starts at the centre. */
    return st_vert(m, st_phi_1(m, f, L), L);
}

int st_sqrt3_vertex_boundary(const st_map *m, uint32_t d, unsigned l, uint32_t *hole, uint32_t *real)
{
    *hole = *real = ST_NIL;
    uint32_t x = d;
    do {
        if (st_is_boundary(m, x)) {
            if (*hole == ST_NIL) *hole = x;
        } else if (st_is_boundary(m, st_beta0(m, x, l))) {
            if (*real == ST_NIL) *real = x;
        }
        x = st_beta1(m, x, l);
    } while (x != d);
    if (*hole == ST_NIL || *real == ST_NIL) { *hole = *real = ST_NIL; return 0; }
    return 1;
}

static void centre_split(st_map *m, uint32_t c0, unsigned L, const double centre[3])
{
    uint32_t c1 = st_phi1(m, c0, L), c2 = st_phi1(m, c1, L);
    uint32_t y = st_beta0(m, st_cut_face(m, c0, c1, L), L);
    st_split_edge(m, y, L, centre);
    st_cut_face(m, st_beta0(m, y, L), c2, L);
}

static void fan_split(st_map *m, uint32_t d, unsigned L, const double pa[3], const double pb[3])
{
    uint32_t d2 = st_phi_1(m, d, L);
    uint32_t a = st_split_edge(m, d, L, pa);
    uint32_t a2 = st_split_edge(m, a, L, pb);
    uint32_t z = st_cut_face(m, d2, a, L);
    st_cut_face(m, z, a2, L);
}

typedef struct sqrt3_cells {
    uint32_t *faces, nfaces;   /* one dart per real face of level l */
    uint32_t *bdart;           /* per face: its boundary dart on boundary steps, else ST_NIL */
    uint32_t *edges, nedges;   /* one dart per interior edge of level l */
} sqrt3_cells;

static void cells_free(sqrt3_cells *c)
{
    free(c->faces);
    free(c->bdart);
    free(c->edges);
}

static int collect(st_map *m, unsigned l, int boundary_step, sqrt3_cells *c, st_error *err)
{
    st_level_stats s;
    st_level_stats_compute(m, l, &s);
    c->faces = malloc((s.faces + 1) * sizeof *c->faces);
    c->bdart = malloc((s.faces + 1) * sizeof *c->bdart);
    c->edges = malloc((s.edges + 1) * sizeof *c->edges);
    c->nfaces = c->nedges = 0;
    if (!c->faces || !c->bdart || !c->edges)
        return st_fail(err, ST_ERR_MEMORY, "out of memory refining level %u", l);
    int fbit = st_marker_reserve(m);
    if (fbit < 0) return st_fail(err, ST_ERR_MEMORY, "no marker bit left refining level %u", l);
    int rc = ST_OK;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t e = st_beta0(m, d, l);
        if (d < e && !st_is_boundary(m, d) && !st_is_boundary(m, e)) c->edges[c->nedges++] = d;
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        st_mark_face(m, fbit, d, l);
        unsigned n = st_face_degree(m, d, l);
        if (n != 3 && !rc)
            rc = st_fail(err, ST_ERR_TOPOLOGY, "sqrt3 needs a triangle mesh: level %u has a face with %u sides", l, n);
        uint32_t b = boundary_step ? st_sqrt3_face_boundary_dart(m, d, l) : ST_NIL;
        int more = b != ST_NIL && (st_is_boundary(m, st_beta0(m, st_phi1(m, b, l), l)) ||
                                   st_is_boundary(m, st_beta0(m, st_phi_1(m, b, l), l)));
        if (more && !rc)
            /* Cannot happen on levels built by this file (after a centre step
             * every triangle has at most one boundary edge); refuse rather
             * than build something CGAL and OpenMesh do not agree on. */
            rc = st_fail(err, ST_ERR_TOPOLOGY, "sqrt3: level %u has a triangle with two boundary edges on a boundary step", l);
        c->bdart[c->nfaces] = b;
        c->faces[c->nfaces++] = d;
    }
    st_marker_release(m, fbit, l);
    return rc;
}

int st_refine_sqrt3(st_map *m, st_error *err)
{
    unsigned l = m->top, L = l + 1;
    if (L >= ST_MAX_LEVELS) return st_fail(err, ST_ERR_RANGE, "cannot add level %u: at most %d levels", L, ST_MAX_LEVELS - 1);
    int boundary_step = st_sqrt3_boundary_step(L);
    sqrt3_cells c = { 0 };
    int rc = collect(m, l, boundary_step, &c, err);
    if (!rc) {
        /* Exact growth: centre split 6 darts + 1 vertex; fan 8 darts + 2 vertices. */
        uint64_t darts = 0, verts = 0;
        for (uint32_t i = 0; i < c.nfaces; i++) {
            int fan = c.bdart[i] != ST_NIL;
            darts += fan ? 8 : 6;
            verts += fan ? 2 : 1;
        }
        if (st_map_reserve(m, darts, verts))
            rc = st_fail(err, ST_ERR_MEMORY, "level %u needs %llu more darts: out of memory", L, (unsigned long long)darts);
    }
    double *pts = NULL;
    if (!rc) {
        pts = malloc(((size_t)c.nfaces + 1) * 6 * sizeof *pts);
        if (!pts) rc = st_fail(err, ST_ERR_MEMORY, "out of memory refining level %u", l);
    }
    if (!rc) rc = st_level_add(m, err);
    if (rc) { free(pts); cells_free(&c); return rc; }
    /* Provisional positions from level l (linear rules); the scheme's
     * synthesis overwrites them. */
    for (uint32_t i = 0; i < c.nfaces; i++) {
        double *p = pts + 6 * (size_t)i;
        uint32_t d = c.bdart[i] != ST_NIL ? c.bdart[i] : c.faces[i];
        const double *u = st_dart_pos(m, d, l), *w = st_dart_pos(m, st_phi1(m, d, l), l);
        const double *x = st_dart_pos(m, st_phi_1(m, d, l), l);
        for (int k = 0; k < 3; k++) {
            if (c.bdart[i] != ST_NIL) {
                p[k] = (2 * u[k] + w[k]) / 3;
                p[3 + k] = (u[k] + 2 * w[k]) / 3;
            } else {
                p[k] = (u[k] + w[k] + x[k]) / 3;
            }
        }
    }
    for (uint32_t i = 0; i < c.nfaces; i++) {
        const double *p = pts + 6 * (size_t)i;
        if (c.bdart[i] != ST_NIL) fan_split(m, c.bdart[i], L, p, p + 3);
        else centre_split(m, c.faces[i], L, p);
    }
    for (uint32_t i = 0; i < c.nedges && !rc; i++) rc = st_flip_edge(m, c.edges[i], L, err);
    free(pts);
    cells_free(&c);
    return rc;
}
