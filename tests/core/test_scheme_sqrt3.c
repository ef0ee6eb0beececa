/* √3 subdivision (core/schemes/scheme_sqrt3.c, core/map/refine_sqrt3.c): values by
 * hand on tiny meshes, topology (×3 faces, boundary trisection every second
 * level, validator at every level), the golden lagrange sqrt3 step, the
 * multiresolution checks, and robustness on odd inputs.  The comparisons
 * with CGAL and OpenMesh are in cli_oracle_sqrt3.sh. */
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/map/map_mesh.h"
#include "core/map/refine_sqrt3_internal.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- fixtures -------------------------------------------------------------- */

static void single_triangle(st_mesh *m)
{
    static const double p[] = { 0,0,0, 1,0,0, 0.3,0.8,0.1 };
    static const uint32_t off[] = { 0, 3 };
    static const uint32_t idx[] = { 0, 1, 2 };
    tl_mesh_make(m, p, 3, off, idx, 1);
}

/* Closed torus of nu x nv quads, each split into two triangles. */
static void torus_tri_n(st_mesh *m, unsigned nu, unsigned nv)
{
    st_mesh q;
    tl_mesh_torus(&q, nu, nv);
    uint32_t nf = 2 * q.nfaces;
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(3 * (size_t)nf * sizeof *idx);
    for (uint32_t f = 0; f < q.nfaces; f++) {
        const uint32_t *c = q.face_idx + q.face_off[f];
        uint32_t t[6] = { c[0], c[1], c[2], c[0], c[2], c[3] };
        memcpy(idx + 6 * (size_t)f, t, sizeof t);
    }
    for (uint32_t f = 0; f <= nf; f++) off[f] = 3 * f;
    tl_mesh_make(m, q.pos, q.nverts, off, idx, nf);
    free(off);
    free(idx);
    st_mesh_free(&q);
}
static void torus_tri(st_mesh *m) { torus_tri_n(m, 8, 6); }
static void torus_small(st_mesh *m) { torus_tri_n(m, 6, 4); }

/* Open n x n grid (the quad grid of testlib, z varying), triangulated along
 * one diagonal: corners of valence 2 and 3, boundary vertices of valence 3-4. */
static void grid_tri_n(st_mesh *m, unsigned n)
{
    st_mesh q;
    tl_mesh_grid(&q, n);
    uint32_t nf = 2 * q.nfaces;
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(3 * (size_t)nf * sizeof *idx);
    for (uint32_t f = 0; f < q.nfaces; f++) {
        const uint32_t *c = q.face_idx + q.face_off[f];
        uint32_t t[6] = { c[0], c[1], c[2], c[0], c[2], c[3] };
        memcpy(idx + 6 * (size_t)f, t, sizeof t);
    }
    for (uint32_t f = 0; f <= nf; f++) off[f] = 3 * f;
    tl_mesh_make(m, q.pos, q.nverts, off, idx, nf);
    free(off);
    free(idx);
    st_mesh_free(&q);
}
static void grid_tri(st_mesh *m) { grid_tri_n(m, 5); }
static void grid_small(st_mesh *m) { grid_tri_n(m, 3); }

/* Bipyramid: n rim vertices on the unit circle, apexes (0,0,±h): two
 * vertices of valence n. */
static void bipyramid_n(st_mesh *m, unsigned n, double h)
{
    double *p = malloc(3 * (size_t)(n + 2) * sizeof *p);
    uint32_t *off = malloc((2 * (size_t)n + 1) * sizeof *off), *idx = malloc(6 * (size_t)n * sizeof *idx);
    for (unsigned i = 0; i < n; i++) {
        p[3 * i] = cos(2 * M_PI * i / n);
        p[3 * i + 1] = sin(2 * M_PI * i / n);
        p[3 * i + 2] = 0;
    }
    double apex[6] = { 0, 0, h, 0, 0, -h };
    memcpy(p + 3 * (size_t)n, apex, sizeof apex);
    for (unsigned i = 0; i < n; i++) {
        uint32_t a = i, b = (i + 1) % n;
        uint32_t t[6] = { a, b, n, b, a, n + 1 };
        memcpy(idx + 6 * (size_t)i, t, sizeof t);
    }
    for (unsigned f = 0; f <= 2 * n; f++) off[f] = 3 * f;
    tl_mesh_make(m, p, n + 2, off, idx, 2 * n);
    free(p);
    free(off);
    free(idx);
}
static void bipyramid16(st_mesh *m) { bipyramid_n(m, 16, 1.5); }

/* ---- helpers ----------------------------------------------------------------- */

static int build(st_hier *h, const st_mesh *s, unsigned levels)
{
    st_error err;
    int rc = st_hier_init(h, s, &st_scheme_sqrt3, NULL, &err);
    CHECKF(rc == ST_OK, "init: %s", err.msg);
    if (rc) return rc;
    rc = st_hier_subdivide_to(h, levels, &err);
    CHECKF(rc == ST_OK, "subdivide: %s", err.msg);
    return rc;
}

static int near3(const double *p, double x, double y, double z, double tol)
{
    return fabs(p[0] - x) <= tol && fabs(p[1] - y) <= tol && fabs(p[2] - z) <= tol;
}

/* Number of vertices of level l at (x, y, z). */
static int count_at(const st_map *m, unsigned l, double x, double y, double z, double tol)
{
    int n = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        n += near3(st_pos(m, v, l), x, y, z, tol);
    return n;
}

/* ---- values by hand ------------------------------------------------------------ */

/* Regular tetrahedron, n = 3, K = (4 - 2 cos 120°)/9 = 5/9:
 *   P' = 4/9 P + 5/27 ΣVi = 4/9 P - 5/27 P = 7/27 P   (ΣVi = -P);
 *   centre of (0,1,3) = ((1-1+1), (1-1-1), (1+1-1))/3 = (1/3, -1/3, 1/3). */
static void test_tetra_values(void)
{
    st_mesh s;
    st_hier h;
    tl_mesh_tetra(&s);
    if (build(&h, &s, 2)) { st_mesh_free(&s); return; }
    st_mesh_free(&s);
    const double tol = 1e-15, k = 7.0 / 27;
    static const double P[4][3] = { { 1, 1, 1 }, { -1, -1, 1 }, { -1, 1, -1 }, { 1, -1, -1 } };
    for (uint32_t v = 0; v < 4; v++) {
        const double *p = st_pos(&h.map, v, 1);
        CHECKF(near3(p, k * P[v][0], k * P[v][1], k * P[v][2], tol), "vertex %u: (%.17g %.17g %.17g)", v, p[0], p[1], p[2]);
    }
    /* The four centres are -P/3 of the opposite vertex. */
    for (int v = 0; v < 4; v++)
        CHECKF(count_at(&h.map, 1, -P[v][0] / 3, -P[v][1] / 3, -P[v][2] / 3, tol) == 1, "centre opposite %d", v);
    st_level_stats st;
    st_level_stats_compute(&h.map, 1, &st);
    CHECKF(st.vertices == 8 && st.faces == 12 && st.edges == 18, "level 1: V %llu F %llu E %llu",
           (unsigned long long)st.vertices, (unsigned long long)st.faces, (unsigned long long)st.edges);
    /* Level 1 is the triakis tetrahedron's refinement: old vertices keep
     * valence 3, centres have valence 6 (3 corners + 3 flipped edges). */
    st_dart_iter it;
    int bad = 0;
    int vb = st_marker_reserve(&h.map);
    for (uint32_t d = st_dart_first(&h.map, 1, &it); d != ST_NIL; d = st_dart_next(&h.map, 1, &it)) {
        if (st_marked(&h.map, vb, d)) continue;
        st_mark_vertex(&h.map, vb, d, 1);
        unsigned n = st_vertex_degree(&h.map, d, 1), want = st_vert(&h.map, d, 1) < 4 ? 3 : 6;
        bad += n != want;
    }
    st_marker_release(&h.map, vb, 1);
    CHECKF(bad == 0, "%d vertices of level 1 with a wrong valence", bad);
    /* Level 2 from level 1: vertex 0 still has valence 3 (K = 5/9), its
     * neighbours being the three level-1 centres around it. */
    const double *p0 = st_pos(&h.map, 0, 1);
    double sum[3] = { 0, 0, 0 };
    uint32_t d0 = ST_NIL;
    for (uint32_t d = st_dart_first(&h.map, 1, &it); d != ST_NIL; d = st_dart_next(&h.map, 1, &it))
        if (st_vert(&h.map, d, 1) == 0) { d0 = d; break; }
    uint32_t x = d0;
    do {
        const double *q = st_pos(&h.map, st_vert(&h.map, st_beta0(&h.map, x, 1), 1), 1);
        for (int i = 0; i < 3; i++) sum[i] += q[i];
        x = st_beta1(&h.map, x, 1);
    } while (x != d0);
    const double *p2 = st_pos(&h.map, 0, 2);
    double want[3];
    for (int i = 0; i < 3; i++) want[i] = 4.0 / 9 * p0[i] + 5.0 / 27 * sum[i];
    CHECKF(near3(p2, want[0], want[1], want[2], 1e-15), "level 2 vertex 0: (%.17g %.17g %.17g)", p2[0], p2[1], p2[2]);
    st_hier_free(&h);
}

/* Octahedron, n = 4, K = 4/9: P' = 5/9 P + 1/9 ΣVi = 5/9 P (ΣVi = 0);
 * centres (±1, ±1, ±1)/3. */
static void test_octa_values(void)
{
    st_mesh s;
    st_hier h;
    tl_mesh_octa(&s);
    if (build(&h, &s, 1)) { st_mesh_free(&s); return; }
    st_mesh_free(&s);
    const double tol = 1e-15;
    for (uint32_t v = 0; v < 6; v++) {
        const double *p = st_pos(&h.map, v, 0), *q = st_pos(&h.map, v, 1);
        CHECKF(near3(q, 5.0 / 9 * p[0], 5.0 / 9 * p[1], 5.0 / 9 * p[2], tol), "vertex %u: (%.17g %.17g %.17g)", v, q[0], q[1], q[2]);
    }
    int centres = 0;
    for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2)
            for (int sz = -1; sz <= 1; sz += 2) centres += count_at(&h.map, 1, sx / 3.0, sy / 3.0, sz / 3.0, tol);
    CHECKF(centres == 8, "%d of 8 centres at (±1,±1,±1)/3", centres);
    st_hier_free(&h);
}

/* Bipyramid with valence-16 apexes (rim centred at the origin): the apex
 * goes to (1 - K16)·apex, K16 = (4 - 2 cos(2π/16))/9. */
static void test_high_valence(void)
{
    unsigned ns[] = { 16, 60 };
    for (int i = 0; i < 2; i++) {
        unsigned n = ns[i];
        st_mesh s;
        st_hier h;
        bipyramid_n(&s, n, 1.5);
        if (build(&h, &s, 3)) { st_mesh_free(&s); continue; }
        st_mesh_free(&s);
        double k = (4 - 2 * cos(2 * M_PI / n)) / 9;
        const double *a = st_pos(&h.map, n, 1), *b = st_pos(&h.map, n + 1, 1);
        CHECKF(near3(a, 0, 0, 1.5 * (1 - k), 1e-15) && near3(b, 0, 0, -1.5 * (1 - k), 1e-15),
               "valence %u apex: (%.17g %.17g %.17g)", n, a[0], a[1], a[2]);
        /* The apexes keep valence n at every level. */
        st_dart_iter it;
        for (unsigned l = 1; l <= 3; l++)
            for (uint32_t d = st_dart_first(&h.map, l, &it); d != ST_NIL; d = st_dart_next(&h.map, l, &it))
                if (st_vert(&h.map, d, l) == n) { CHECKF(st_vertex_degree(&h.map, d, l) == n, "level %u apex valence %u", l, st_vertex_degree(&h.map, d, l)); break; }
        st_hier_free(&h);
    }
}

/* Open mesh, boundary step (level 2): on the straight boundary edge y = 0
 * of the grid (vertices (i, 0, z_i)), new points at (16 s + 10 t + s')/27
 * and old boundary vertices at (4 p + 19 v + 4 q)/27; level 1 keeps the
 * boundary vertices where they are. */
static void test_boundary_values(void)
{
    st_mesh s;
    st_hier h;
    grid_tri(&s);
    if (build(&h, &s, 2)) { st_mesh_free(&s); return; }
    st_mesh_free(&s);
    /* Vertices 0..5 are the row y = 0 (tl_mesh_grid numbering), x = i. */
    double z[6];
    for (int i = 0; i < 6; i++) {
        z[i] = st_pos(&h.map, i, 0)[2];
        const double *p1 = st_pos(&h.map, i, 1);
        CHECKF(near3(p1, i, 0, z[i], 0), "level 1 boundary vertex %d moved", i);
    }
    /* Vertex 2 (interior of the row): neighbours 1 and 3. */
    const double *v2 = st_pos(&h.map, 2, 2);
    CHECKF(near3(v2, (4 * 1 + 19 * 2 + 4 * 3) / 27.0, 0, (4 * z[1] + 19 * z[2] + 4 * z[3]) / 27, 1e-15),
           "level 2 boundary vertex 2: (%.17g %.17g %.17g)", v2[0], v2[1], v2[2]);
    /* Edge 2-3: points near 2 and near 3. */
    CHECK(count_at(&h.map, 2, (16 * 2 + 10 * 3 + 1) / 27.0, 0, (16 * z[2] + 10 * z[3] + z[1]) / 27, 1e-15) == 1);
    CHECK(count_at(&h.map, 2, (16 * 3 + 10 * 2 + 4) / 27.0, 0, (16 * z[3] + 10 * z[2] + z[4]) / 27, 1e-15) == 1);
    st_hier_free(&h);
}

/* ---- topology ---------------------------------------------------------------- */

/* Faces ×3 per level; V(L) = V + F on centre steps, V + F + Eb on boundary
 * steps (a fan face adds 2 points instead of a centre); Eb ×3 on boundary
 * steps only; Euler characteristic kept; the validator accepts every level. */
static void check_counts(const char *name, void (*make)(st_mesh *), unsigned levels)
{
    st_mesh s;
    st_hier h;
    make(&s);
    if (build(&h, &s, levels)) { st_mesh_free(&s); return; }
    st_mesh_free(&s);
    st_error err;
    int rc = st_map_validate(&h.map, &err);
    CHECKF(rc == ST_OK, "%s: %s", name, err.msg);
    st_level_stats prev, cur;
    st_level_stats_compute(&h.map, 0, &prev);
    for (unsigned L = 1; L <= levels; L++) {
        st_level_stats_compute(&h.map, L, &cur);
        int bstep = st_sqrt3_boundary_step(L);
        uint64_t want_v = prev.vertices + prev.faces + (bstep ? prev.boundary_edges : 0);
        CHECKF(cur.faces == 3 * prev.faces, "%s level %u: %llu faces, want %llu", name, L,
               (unsigned long long)cur.faces, 3 * (unsigned long long)prev.faces);
        CHECKF(cur.vertices == want_v, "%s level %u: %llu vertices, want %llu", name, L,
               (unsigned long long)cur.vertices, (unsigned long long)want_v);
        CHECKF(cur.boundary_edges == (bstep ? 3 : 1) * prev.boundary_edges, "%s level %u: %llu boundary edges", name, L,
               (unsigned long long)cur.boundary_edges);
        CHECKF(cur.euler == prev.euler && cur.boundary_loops == prev.boundary_loops, "%s level %u: euler %lld loops %llu",
               name, L, (long long)cur.euler, (unsigned long long)cur.boundary_loops);
        /* Every real face is a triangle. */
        st_mesh out;
        st_mesh_init(&out);
        CHECK(st_hier_level_mesh(&h, L, &out, &err) == ST_OK);
        int nontri = 0;
        for (uint32_t f = 0; f < out.nfaces; f++) nontri += out.face_off[f + 1] - out.face_off[f] != 3;
        CHECKF(nontri == 0, "%s level %u: %d faces are not triangles", name, L, nontri);
        st_mesh_free(&out);
        prev = cur;
    }
    printf("  %s: %u levels, %llu faces at level %u, validator ok\n", name, levels, (unsigned long long)prev.faces, levels);
    st_hier_free(&h);
}

static void test_topology(void)
{
    check_counts("tetra", tl_mesh_tetra, 5);
    check_counts("octa", tl_mesh_octa, 4);
    check_counts("torus", torus_tri, 4);
    check_counts("grid", grid_tri, 4);
    check_counts("triangle", single_triangle, 6);
    check_counts("bipyramid16", bipyramid16, 4);
}

static void test_refuses_quads(void)
{
    st_mesh s;
    st_hier h;
    st_error err;
    tl_mesh_cube(&s);
    int rc = st_hier_init(&h, &s, &st_scheme_sqrt3, NULL, &err);
    CHECKF(rc != ST_OK && strstr(err.msg, "triangle"), "quads accepted or bad message: %s", rc ? err.msg : "ok");
    if (rc) printf("  cube refused: %s\n", err.msg);
    else st_hier_free(&h);
    st_mesh_free(&s);
}

/* ---- golden data ---------------------------------------------------------------- */

/* Max over both directions of the nearest-neighbour distance between the
 * vertex sets, relative to a's bounding-box diagonal (brute force: small). */
static double pointset_rel(const st_mesh *a, const st_mesh *b)
{
    double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
    for (uint32_t i = 0; i < a->nverts; i++)
        for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], a->pos[3 * i + k]); hi[k] = fmax(hi[k], a->pos[3 * i + k]); }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double worst = 0;
    for (int dir = 0; dir < 2; dir++) {
        const st_mesh *p = dir ? b : a, *q = dir ? a : b;
        for (uint32_t i = 0; i < p->nverts; i++) {
            double best = 1e300;
            for (uint32_t j = 0; j < q->nverts; j++) {
                double dx = p->pos[3 * i] - q->pos[3 * j], dy = p->pos[3 * i + 1] - q->pos[3 * j + 1], dz = p->pos[3 * i + 2] - q->pos[3 * j + 2];
                best = fmin(best, dx * dx + dy * dy + dz * dz);
            }
            worst = fmax(worst, sqrt(best));
        }
    }
    return worst / (diag > 0 ? diag : 1);
}

/* Same faces up to vertex order: each vertex of a is matched to its nearest
 * vertex of b and every face of a (as a cyclic triple) must be a face of b. */
static int same_faces(const st_mesh *a, const st_mesh *b)
{
    if (a->nfaces != b->nfaces || a->nverts != b->nverts) return 0;
    uint32_t *map = malloc((size_t)a->nverts * sizeof *map);
    for (uint32_t i = 0; i < a->nverts; i++) {
        double best = 1e300;
        for (uint32_t j = 0; j < b->nverts; j++) {
            double dx = a->pos[3 * i] - b->pos[3 * j], dy = a->pos[3 * i + 1] - b->pos[3 * j + 1], dz = a->pos[3 * i + 2] - b->pos[3 * j + 2];
            double d2 = dx * dx + dy * dy + dz * dz;
            if (d2 < best) { best = d2; map[i] = j; }
        }
    }
    int ok = 1;
    for (uint32_t f = 0; f < a->nfaces && ok; f++) {
        const uint32_t *c = a->face_idx + a->face_off[f];
        uint32_t t[3] = { map[c[0]], map[c[1]], map[c[2]] };
        int found = 0;
        for (uint32_t g = 0; g < b->nfaces && !found; g++) {
            const uint32_t *e = b->face_idx + b->face_off[g];
            for (int r = 0; r < 3; r++)
                if (e[r] == t[0] && e[(r + 1) % 3] == t[1] && e[(r + 2) % 3] == t[2]) found = 1;
        }
        ok = found;
    }
    free(map);
    return ok;
}

static void test_lagrange_sphere(void)
{
    const char *in = STRATA_SHARED_DATA "/reference/lagrange_sqrt3/sphere.ply";
    const char *ref = STRATA_SHARED_DATA "/reference/lagrange_sqrt3/sphere_sqrt3.ply";
    st_mesh s, r, out;
    st_error err;
    st_mesh_init(&s);
    st_mesh_init(&r);
    st_mesh_init(&out);
    if (st_mesh_load(in, &s, &err) || st_mesh_load(ref, &r, &err)) {
        tl_skip("lagrange sphere: %s", err.msg);
        st_mesh_free(&s);
        return;
    }
    st_hier h;
    if (!build(&h, &s, 1)) {
        CHECK(st_hier_level_mesh(&h, 1, &out, &err) == ST_OK);
        double rel = pointset_rel(&out, &r);
        printf("  lagrange sphere_sqrt3 (level 1): verts %u/%u faces %u/%u, max point-set error %.3e of bbox diagonal\n",
               out.nverts, r.nverts, out.nfaces, r.nfaces, rel);
        CHECKF(out.nverts == r.nverts && out.nfaces == r.nfaces, "counts %u/%u %u/%u", out.nverts, r.nverts, out.nfaces, r.nfaces);
        CHECKF(rel <= 1e-9, "max relative error %.3e", rel);
        CHECKF(same_faces(&out, &r), "level 1 faces differ from sphere_sqrt3.ply");
        st_hier_free(&h);
    }
    st_mesh_free(&s);
    st_mesh_free(&r);
    st_mesh_free(&out);
}

/* ---- multiresolution ------------------------------------------------------------ */

/* Stronger than tl_check_local_equals_full: every vertex of levels
 * 0..levels-1, one at a time, moved and re-synthesised locally, must give
 * the full synthesis (this is what fixes support_rings, boundaries
 * included). */
static void check_every_vertex_local(const char *name, void (*make)(st_mesh *), unsigned levels)
{
    st_hier h;
    uint64_t rng = 4242;
    tl_init_hier(&h, make, ST_SCHEME_SQRT3, levels);
    tl_random_details(&h, &rng, 0.01);
    double worst = 0;
    unsigned moves = 0;
    for (unsigned l = 0; l < levels; l++) {
        st_dart_list verts = { 0 };
        int vb = st_marker_reserve(&h.map);
        st_dart_iter it;
        for (uint32_t d = st_dart_first(&h.map, l, &it); d != ST_NIL; d = st_dart_next(&h.map, l, &it))
            if (!st_marked(&h.map, vb, d)) { st_mark_vertex(&h.map, vb, d, l); st_dart_list_push(&verts, d); }
        st_marker_release(&h.map, vb, l);
        for (uint32_t i = 0; i < verts.n; i++) {
            double p[1][3];
            memcpy(p[0], st_dart_pos(&h.map, verts.d[i], l), sizeof p[0]);
            p[0][0] += 0.031; p[0][1] -= 0.017; p[0][2] += 0.05;
            st_hier_move(&h, l, &verts.d[i], (const double (*)[3])p, 1);
            tl_posnap a, b;
            tl_snap_pos(&h, &a);
            st_hier_synthesize(&h, l);
            tl_snap_pos(&h, &b);
            double dd = tl_snap_maxdiff(&a, &b);
            if (dd > worst) worst = dd;
            CHECKF(dd < 1e-12, "%s: moving vertex %u at level %u: local and full differ by %g", name,
                   st_vert(&h.map, verts.d[i], l), l, dd);
            free(a.p);
            free(b.p);
            moves++;
        }
        st_dart_list_free(&verts);
    }
    printf("  %s: %u single-vertex edits over levels 0..%u, local vs full max %.3g\n", name, moves, levels - 1, worst);
    st_hier_free(&h);
}

static void test_multires(void)
{
    /* (Every vertex of the bipyramid is within two rings of every face: too
     * small for the "local recomputes less" part of these checks.) */
    void (*fixtures[])(st_mesh *) = { torus_tri, grid_tri };
    for (int i = 0; i < 2; i++) {
        tl_check_local_equals_full(ST_SCHEME_SQRT3, fixtures[i], 3);
        tl_check_rigid_motion(ST_SCHEME_SQRT3, fixtures[i], 3);
        tl_check_details_kept(ST_SCHEME_SQRT3, fixtures[i], 3);
    }
    check_every_vertex_local("grid 3x3", grid_small, 3);
    check_every_vertex_local("triangle", single_triangle, 4);
    check_every_vertex_local("octa", tl_mesh_octa, 3);
    check_every_vertex_local("torus 6x4", torus_small, 3);
    check_every_vertex_local("bipyramid16", bipyramid16, 3);
}

/* Removing the finest levels drops their flips (β1/vert columns) too:
 * rebuilding them gives a valid map and the same surfaces (as point sets
 * with the same faces: freed ids may be handed out in another order). */
static void test_remove_top(void)
{
    st_mesh s, a[3], b[3];
    st_hier h;
    st_error err;
    grid_small(&s);
    if (build(&h, &s, 4)) { st_mesh_free(&s); return; }
    st_mesh_free(&s);
    for (unsigned l = 2; l <= 4; l++) { st_mesh_init(&a[l - 2]); CHECK(st_hier_level_mesh(&h, l, &a[l - 2], &err) == ST_OK); }
    st_hier_remove_top(&h);
    st_hier_remove_top(&h);
    CHECK(h.map.top == 2);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s", err.msg);
    CHECK(st_hier_subdivide_to(&h, 4, &err) == ST_OK);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s", err.msg);
    for (unsigned l = 2; l <= 4; l++) {
        st_mesh_init(&b[l - 2]);
        CHECK(st_hier_level_mesh(&h, l, &b[l - 2], &err) == ST_OK);
        double rel = pointset_rel(&a[l - 2], &b[l - 2]);
        CHECKF(rel == 0 && same_faces(&a[l - 2], &b[l - 2]), "level %u rebuilt differently (%.3g)", l, rel);
        st_mesh_free(&a[l - 2]);
        st_mesh_free(&b[l - 2]);
    }
    st_hier_free(&h);
}

/* ---- robustness ------------------------------------------------------------------ */

/* Odd but legal inputs from the shared edge-case folder (after the loader's
 * repair) and a mesh whose boundary loops have length 3: no crash, valid
 * map, or a clean refusal. */
static void test_odd_inputs(void)
{
    const char *files[] = { "edge_cases/fan3.obj", "edge_cases/grid_holes.obj", "triangle/cube_no_bottom.obj" };
    for (int i = 0; i < 3; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", STRATA_SHARED_DATA, files[i]);
        st_mesh s;
        st_error err;
        st_mesh_init(&s);
        if (st_mesh_load(path, &s, &err)) { printf("  %s: loader refuses: %s\n", files[i], err.msg); continue; }
        st_hier h;
        int rc = st_hier_init(&h, &s, &st_scheme_sqrt3, NULL, &err);
        if (!rc) {
            rc = st_hier_subdivide_to(&h, 4, &err);
            CHECKF(rc == ST_OK, "%s: %s", files[i], err.msg);
            rc = st_map_validate(&h.map, &err);
            CHECKF(rc == ST_OK, "%s: %s", files[i], err.msg);
            printf("  %s: 4 levels, validator %s\n", files[i], rc ? err.msg : "ok");
            st_hier_free(&h);
        } else {
            printf("  %s: refused: %s\n", files[i], err.msg);
        }
        st_mesh_free(&s);
    }
}

int main(void)
{
    test_tetra_values();
    test_octa_values();
    test_high_valence();
    test_boundary_values();
    test_topology();
    test_refuses_quads();
    test_lagrange_sphere();
    test_multires();
    test_remove_top();
    test_odd_inputs();
    return TEST_END();
}
