/* What the renderer sends to the GPU for a level (render/geom.h):
 *
 *  - no cracks: for every scheme on meshes that fit it, at every level, the
 *    triangle list welded by vertex index is a 2-manifold with the map's
 *    own borders: every polygon side is a triangle edge once, in the face's
 *    direction; every side shared by two real faces is met in both
 *    directions; every triangulation diagonal is met once each way; no
 *    directed edge twice; V - E + F equals the polygon mesh's (closed meshes:
 *    every edge in exactly two triangles, consistently oriented); and the
 *    same on adaptive meshes (interest-box refinement, restriction on and
 *    off) for every scheme that refines adaptively;
 *  - boundary faces are never drawn, faces/corners/vertices agree with the
 *    level's polygon soup, the wireframe holds each polygon side once and
 *    no diagonal, regular faces never fall outside the case tables;
 *  - incremental updates: after st_hier_move at a coarser level, the edit
 *    region + refresh give bit-identical vertex data and face normals to a
 *    full rebuild, and the dirty ranges cover every changed entry.
 */
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/adapt/adapt.h"
#include "core/fvar/fvar.h"
#include "core/multires/edit.h"
#include "render/geom.h"
#include "render/triangulate.h"    /* the case ids of st_rgeom.face_case (render internal) */
#include "core/map/map_mesh.h"
#include "core/progressive/scheme_registry.h"

typedef struct edge { uint32_t a, b; } edge;

static int cmp_edge(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

static int has(const edge *e, size_t n, uint32_t a, uint32_t b)
{
    edge k = { a, b };
    return bsearch(&k, e, n, sizeof k, cmp_edge) != NULL;
}

/* tables: every face of up to 8 sides must be in the case tables (regular
 * levels; adaptive ones with the restriction on and no n-gon in the input). */
static int check_geom(const st_rgeom *g, st_map *m, const char *name, int tables)
{
    int failures = tl_failed;
    unsigned l = g->level;
    /* Against the level's polygon soup (either encoding). */
    st_mesh soup;
    st_error err;
    st_mesh_init(&soup);
    CHECKF(st_map_to_mesh(m, l, &soup, &err) == ST_OK, "%s: %s", name, err.msg);
    CHECKF(g->nfaces == soup.nfaces, "%s level %u: %u faces drawn, the level has %u", name, l, g->nfaces, soup.nfaces);
    CHECKF(g->nverts == soup.nverts, "%s level %u: %u vertices, the level has %u", name, l, g->nverts, soup.nverts);
    CHECKF(g->face_off[g->nfaces] == (soup.nfaces ? soup.face_off[soup.nfaces] : 0), "%s level %u: corners", name, l);
    uint32_t ncorner = g->face_off[g->nfaces];
    CHECKF(g->ntris == ncorner - 2 * g->nfaces, "%s level %u: %u triangles for %u corners", name, l, g->ntris, ncorner);
    st_mesh_free(&soup);

    /* Boundary faces are not drawn; every real dart maps to its face. */
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t f = g->dart_face[d];
        if (st_is_boundary(m, d)) { CHECKF(f >= g->nfaces, "%s level %u: boundary dart %u drawn", name, l, d); }
        else if (!m->face_embedded) CHECKF(f < g->nfaces, "%s level %u: dart %u of a real face not drawn", name, l, d);
    }

    /* Directed polygon sides P and triangle edges T. */
    edge *P = malloc((size_t)(ncorner ? ncorner : 1) * sizeof *P);
    edge *T = malloc(3 * (size_t)(g->ntris ? g->ntris : 1) * sizeof *T);
    for (uint32_t f = 0; f < g->nfaces; f++)
        for (uint32_t k = g->face_off[f]; k < g->face_off[f + 1]; k++) {
            uint32_t k1 = k + 1 < g->face_off[f + 1] ? k + 1 : g->face_off[f];
            P[k].a = g->corner[k];
            P[k].b = g->corner[k1];
        }
    size_t nt = 0;
    int degenerate = 0;
    for (uint32_t t = 0; t < g->ntris; t++) {
        const uint32_t *v = g->tris + 3 * (size_t)t;
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) degenerate++;
        for (int k = 0; k < 3; k++) { T[nt].a = v[k]; T[nt].b = v[(k + 1) % 3]; nt++; }
        uint32_t f = g->tri_face[t];
        int in = 0;
        for (int k = 0; k < 3; k++)
            for (uint32_t c = g->face_off[f]; c < g->face_off[f + 1]; c++) in += g->corner[c] == v[k];
        CHECKF(in == 3, "%s level %u: triangle %u is not on the corners of its face %u", name, l, t, f);
    }
    CHECKF(!degenerate, "%s level %u: %d triangles repeat a vertex", name, l, degenerate);
    qsort(P, ncorner, sizeof *P, cmp_edge);
    qsort(T, nt, sizeof *T, cmp_edge);
    size_t dupP = 0, dupT = 0, missing = 0, unpaired = 0, border = 0;
    for (size_t i = 1; i < ncorner; i++) dupP += !cmp_edge(&P[i - 1], &P[i]);
    for (size_t i = 1; i < nt; i++) dupT += !cmp_edge(&T[i - 1], &T[i]);
    for (size_t i = 0; i < ncorner; i++) {
        if (!has(T, nt, P[i].a, P[i].b)) missing++;
        if (!has(P, ncorner, P[i].b, P[i].a)) {
            border++;
            if (has(T, nt, P[i].b, P[i].a)) unpaired++;     /* a diagonal over a border side */
        }
    }
    for (size_t i = 0; i < nt; i++)
        if (!has(P, ncorner, T[i].a, T[i].b) && !has(T, nt, T[i].b, T[i].a)) unpaired++;  /* a diagonal met one way only */
    CHECKF(!dupP && !dupT, "%s level %u: %zu sides, %zu triangle edges repeated in the same direction", name, l, dupP, dupT);
    CHECKF(!missing, "%s level %u: %zu polygon sides missing from the triangles (a crack)", name, l, missing);
    CHECKF(!unpaired, "%s level %u: %zu triangle edges without their opposite", name, l, unpaired);
    /* Border sides are the surface's boundary edges (the statistics count
     * the surface's cells in the dual encoding too). */
    st_level_stats s;
    st_level_stats_compute(m, l, &s);
    CHECKF(border == s.boundary_edges, "%s level %u: %zu border sides, the surface has %llu boundary edges",
           name, l, border, (unsigned long long)s.boundary_edges);
    CHECKF(g->nlines == s.edges, "%s level %u: %u wire edges, the surface has %llu edges", name, l, g->nlines,
           (unsigned long long)s.edges);
    /* Euler characteristic: the triangulation changes E and F alike. */
    size_t ue = 0;
    for (size_t i = 0; i < nt; i++) if (T[i].a < T[i].b || !has(T, nt, T[i].b, T[i].a)) ue++;
    size_t pe = 0;
    for (size_t i = 0; i < ncorner; i++) if (P[i].a < P[i].b || !has(P, ncorner, P[i].b, P[i].a)) pe++;
    long chi_t = (long)g->nverts - (long)ue + (long)g->ntris, chi_p = (long)g->nverts - (long)pe + (long)g->nfaces;
    CHECKF(chi_t == chi_p, "%s level %u: chi of the triangles %ld, of the polygons %ld", name, l, chi_t, chi_p);
    /* Wire edges: each polygon side once (either direction), no diagonal. */
    size_t wrong = 0;
    for (uint32_t i = 0; i < g->nlines; i++) {
        uint32_t a = g->lines[2 * i], b = g->lines[2 * i + 1];
        if (!has(P, ncorner, a, b) && !has(P, ncorner, b, a)) wrong++;
    }
    CHECKF(!wrong, "%s level %u: %zu wire edges are not polygon sides", name, l, wrong);
    CHECKF(g->nlines == pe, "%s level %u: %u wire edges, %zu polygon edges", name, l, g->nlines, pe);
    /* Faces of up to 8 sides of a regular hierarchy are all in the tables. */
    for (uint32_t f = 0; f < g->nfaces && tables; f++) {
        uint32_t n = g->face_off[f + 1] - g->face_off[f];
        if (n <= ST_TRI_TABLE_MAX_SIDES)
            CHECKF(g->face_case[f] != ST_TRI_FALLBACK, "%s level %u: regular face %u of %u sides outside the tables", name, l, f, n);
    }
    /* Normals are unit length. */
    for (uint32_t v = 0; v < g->nverts; v++) {
        const float *n = g->vdata + ST_RGEOM_VSTRIDE * (size_t)v + 3;
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        if (fabs(len - 1) > 1e-5) { CHECKF(0, "%s level %u: normal of vertex %u has length %g", name, l, v, len); break; }
    }
    free(P);
    free(T);
    return tl_failed == failures;
}

/* ---- meshes and schemes -------------------------------------------------------- */

typedef struct mesh_case { const char *file; int shared; st_scheme_id scheme; unsigned levels; } mesh_case;

static int load_hier(st_hier *h, const mesh_case *c, char *name, size_t namesz)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", c->shared ? STRATA_SHARED_DATA : STRATA_ASSETS, c->file);
    const st_scheme *sc = st_scheme_get(c->scheme);
    snprintf(name, namesz, "%s/%s", c->file, sc->name);
    st_mesh mesh;
    st_error err;
    st_mesh_init(&mesh);
    if (st_mesh_load(path, &mesh, &err)) {
        if (c->shared) { tl_skip("%s not available (%s)", path, err.msg); return -1; }
        CHECKF(0, "%s", err.msg);
        return -1;
    }
    int rc = st_hier_init(h, &mesh, sc, NULL, &err);
    st_mesh_free(&mesh);
    CHECKF(rc == ST_OK, "%s: %s", name, err.msg);
    if (rc) return -1;
    rc = st_hier_subdivide_to(h, c->levels, &err);
    CHECKF(rc == ST_OK, "%s: %s", name, err.msg);
    if (rc) { st_hier_free(h); return -1; }
    return 0;
}

static const mesh_case regular_cases[] = {
    { "cube.obj", 0, ST_SCHEME_CATMARK, 3 },
    { "torus.obj", 0, ST_SCHEME_CATMARK, 2 },
    { "mixed.obj", 0, ST_SCHEME_CATMARK, 2 },
    { "ngon.obj", 0, ST_SCHEME_CATMARK, 2 },
    { "open.obj", 0, ST_SCHEME_CATMARK, 2 },
    { "tetrahedron.obj", 0, ST_SCHEME_CATMARK, 2 },
    { "tetrahedron.obj", 0, ST_SCHEME_LOOP, 3 },
    { "octahedron.obj", 0, ST_SCHEME_LOOP, 3 },
    { "tetrahedron.obj", 0, ST_SCHEME_BUTTERFLY, 3 },
    { "octahedron.obj", 0, ST_SCHEME_BUTTERFLY, 2 },
    { "tetrahedron.obj", 0, ST_SCHEME_SQRT3, 4 },
    { "octahedron.obj", 0, ST_SCHEME_SQRT3, 3 },
    { "cube.obj", 0, ST_SCHEME_QUADTRI, 2 },
    { "mixed.obj", 0, ST_SCHEME_QUADTRI, 3 },
    { "open.obj", 0, ST_SCHEME_QUADTRI, 2 },
    { "octahedron.obj", 0, ST_SCHEME_QUADTRI, 2 },
    { "cube.obj", 0, ST_SCHEME_DOOSABIN, 3 },
    { "octahedron.obj", 0, ST_SCHEME_DOOSABIN, 2 },
    { "torus.obj", 0, ST_SCHEME_DOOSABIN, 2 },
    { "tetrahedron.obj", 0, ST_SCHEME_DOOSABIN, 2 },
    { "ngon.obj", 0, ST_SCHEME_DOOSABIN, 2 },
    { "open.obj", 0, ST_SCHEME_DOOSABIN, 3 },
    { "catmull_clark/hole_capsule.off", 1, ST_SCHEME_DOOSABIN, 2 },
    { "catmull_clark/dodecahedron_poly.obj", 1, ST_SCHEME_CATMARK, 2 },
    { "catmull_clark/dodecahedron_poly.obj", 1, ST_SCHEME_DOOSABIN, 2 },
    { "catmull_clark/hexa_sphere.off", 1, ST_SCHEME_CATMARK, 1 },
    { "catmull_clark/hole_capsule.off", 1, ST_SCHEME_CATMARK, 2 },
    { "catmull_clark/chamfer_cube.off", 1, ST_SCHEME_QUADTRI, 2 },
    { "triangle/cube_no_bottom.obj", 1, ST_SCHEME_LOOP, 2 },
    { "triangle/cube_no_bottom.obj", 1, ST_SCHEME_SQRT3, 2 },
    { "triangle/cube_no_bottom.obj", 1, ST_SCHEME_BUTTERFLY, 2 },
    { "triangle/sphere_ico.obj", 1, ST_SCHEME_SQRT3, 2 },
};

static void test_no_cracks(void)
{
    st_rgeom g;
    st_rgeom_init(&g);
    for (size_t i = 0; i < sizeof regular_cases / sizeof regular_cases[0]; i++) {
        st_hier h;
        char name[256];
        if (load_hier(&h, &regular_cases[i], name, sizeof name)) continue;
        for (unsigned l = 0; l <= h.map.top; l++) {
            st_error err;
            int rc = st_rgeom_build(&g, &h.map, l, &err);
            CHECKF(rc == ST_OK, "%s: %s", name, err.msg);
            if (!rc) check_geom(&g, &h.map, name, 1);
        }
        st_hier_free(&h);
    }
    st_rgeom_free(&g);
}

/* No cracks on adaptive meshes: the displayed (top) level after interest-box
 * refinements - faces of several depths side by side, their borders drawn
 * through the case tables - for every scheme that refines adaptively, with
 * the restriction and without it (fallback triangulation). */
static const mesh_case adaptive_cases[] = {
    { "torus.obj", 0, ST_SCHEME_CATMARK, 3 },
    { "open.obj", 0, ST_SCHEME_CATMARK, 3 },
    { "mixed.obj", 0, ST_SCHEME_QUADTRI, 3 },
    { "octahedron.obj", 0, ST_SCHEME_LOOP, 3 },
    { "octahedron.obj", 0, ST_SCHEME_BUTTERFLY, 3 },
    { "octahedron.obj", 0, ST_SCHEME_SQRT3, 4 },
    { "torus.obj", 0, ST_SCHEME_DOOSABIN, 3 },
    { "catmull_clark/blub_control_mesh.obj", 1, ST_SCHEME_CATMARK, 3 },
    { "triangle/cube_no_bottom.obj", 1, ST_SCHEME_LOOP, 3 },
};

/* ---- patches after box moves ------------------------------------------------------ */

typedef struct vkey { uint32_t a[3]; } vkey;

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

/* A hash per live face: its cycle of vertex ids from the smallest (so the
 * walk's start does not matter), sorted. */
static uint64_t *face_keys(const st_rgeom *g, uint32_t *n)
{
    uint64_t *k = malloc(((size_t)g->nfaces + 1) * sizeof *k);
    *n = 0;
    for (uint32_t f = 0; f < g->nfaces; f++) {
        if (g->face_dart[f] == ST_NIL) continue;
        uint32_t a = g->face_off[f], b = g->face_off[f + 1], start = a;
        for (uint32_t c = a; c < b; c++) if (g->vid[g->corner[c]] < g->vid[g->corner[start]]) start = c;
        uint64_t h = 1469598103934665603ull;
        for (uint32_t i = 0; i < b - a; i++) {
            uint32_t c = a + (start - a + i) % (b - a);
            h = (h ^ g->vid[g->corner[c]]) * 1099511628211ull;
        }
        k[(*n)++] = h ^ (b - a);
    }
    qsort(k, *n, sizeof *k, cmp_u64);
    return k;
}

/* Polygon edges as sorted vertex-id pairs (degenerate ones skipped). */
static uint64_t *line_keys(const st_rgeom *g, uint32_t *n)
{
    uint64_t *k = malloc(((size_t)g->nlines + 1) * sizeof *k);
    *n = 0;
    for (uint32_t i = 0; i < g->nlines; i++) {
        uint32_t a = g->lines[2 * i], b = g->lines[2 * i + 1];
        if (a == b) continue;
        uint64_t x = g->vid[a], y = g->vid[b];
        k[(*n)++] = x < y ? x << 32 | y : y << 32 | x;
    }
    qsort(k, *n, sizeof *k, cmp_u64);
    return k;
}

/* Triangles of the live faces as vertex-id triples (rotated to start at the
 * smallest, orientation kept), hashed and sorted. */
static uint64_t *tri_keys(const st_rgeom *g, uint32_t *n)
{
    uint64_t *k = malloc(((size_t)g->ntris + 1) * sizeof *k);
    *n = 0;
    for (uint32_t t = 0; t < g->ntris; t++) {
        if (g->face_dart[g->tri_face[t]] == ST_NIL) continue;
        uint32_t v[3], m = 0;
        for (int i = 0; i < 3; i++) v[i] = g->vid[g->tris[3 * t + i]];
        for (uint32_t i = 1; i < 3; i++) if (v[i] < v[m]) m = i;
        uint64_t h = 1469598103934665603ull;
        for (uint32_t i = 0; i < 3; i++) h = (h ^ v[(m + i) % 3]) * 1099511628211ull;
        k[(*n)++] = h;
    }
    qsort(k, *n, sizeof *k, cmp_u64);
    return k;
}

/* Directed triangle sides (vertex ids) of the live faces: each at most
 * once, and as many without a twin as in the fresh build. */
static int unmatched_sides(const st_rgeom *g, int *repeated)
{
    size_t n = 0;
    uint64_t *e = malloc(3 * ((size_t)g->ntris + 1) * sizeof *e);
    for (uint32_t t = 0; t < g->ntris; t++) {
        if (g->face_dart[g->tri_face[t]] == ST_NIL) continue;
        for (int i = 0; i < 3; i++) {
            uint64_t a = g->vid[g->tris[3 * t + i]], b = g->vid[g->tris[3 * t + (i + 1) % 3]];
            e[n++] = a << 32 | b;
        }
    }
    qsort(e, n, sizeof *e, cmp_u64);
    int unmatched = 0;
    *repeated = 0;
    for (size_t i = 0; i < n; i++) {
        if (i && e[i] == e[i - 1]) (*repeated)++;
        uint64_t twin = (e[i] << 32) | (e[i] >> 32);
        if (!bsearch(&twin, e, n, sizeof *e, cmp_u64)) unmatched++;
    }
    free(e);
    return unmatched;
}

/* The patched geometry draws what a fresh build draws: same faces (vertex
 * cycles), same triangles, same polygon edges, a closed triangle soup
 * wherever the build's is, and the same positions and normals at every
 * drawn vertex. */
static void compare_patched(const st_rgeom *pg, const st_rgeom *g, const char *what)
{
    uint32_t na, nb;
    uint64_t *fa = face_keys(pg, &na), *fb = face_keys(g, &nb);
    CHECKF(na == nb && !memcmp(fa, fb, (size_t)na * sizeof *fa), "%s: patched faces differ (%u vs %u built)", what, na, nb);
    free(fa); free(fb);
    fa = line_keys(pg, &na);
    fb = line_keys(g, &nb);
    CHECKF(na == nb && !memcmp(fa, fb, (size_t)na * sizeof *fa), "%s: patched polygon edges differ (%u vs %u built)",
           what, na, nb);
    free(fa); free(fb);
    fa = tri_keys(pg, &na);
    fb = tri_keys(g, &nb);
    CHECKF(na == nb && !memcmp(fa, fb, (size_t)na * sizeof *fa), "%s: patched triangles differ (%u vs %u built)", what,
           na, nb);
    free(fa); free(fb);
    int ra, rb, ua = unmatched_sides(pg, &ra), ub = unmatched_sides(g, &rb);
    CHECKF(ra == 0 && ua == ub, "%s: patched triangles: %d repeated sides, %d without twin (built: %d)", what, ra, ua, ub);
    double worst = 0;
    uint32_t missing = 0;
    for (uint32_t s = 0; s < g->nverts; s++) {
        uint32_t v = g->vid[s], t = v < pg->nvids ? pg->slot[v] : ST_NIL;
        if (t == ST_NIL) { missing++; continue; }
        for (int k = 0; k < ST_RGEOM_VSTRIDE; k++)
            worst = fmax(worst, fabs((double)pg->vdata[ST_RGEOM_VSTRIDE * (size_t)t + k] - g->vdata[ST_RGEOM_VSTRIDE * (size_t)s + k]));
    }
    CHECKF(missing == 0 && worst < 1e-5, "%s: patched vertices: %u missing, position/normal differs by %g", what, missing, worst);
    /* The patched bounding box only grows (geom_patch.c): it holds the
     * built one, which is that of the drawn vertices. */
    int holds = 1;
    for (int k = 0; k < 3; k++) holds &= pg->bbox[k] <= g->bbox[k] && pg->bbox[3 + k] >= g->bbox[3 + k];
    CHECKF(holds, "%s: patched bounding box (%g %g %g .. %g %g %g) misses the built one (%g %g %g .. %g %g %g)", what,
           pg->bbox[0], pg->bbox[1], pg->bbox[2], pg->bbox[3], pg->bbox[4], pg->bbox[5], g->bbox[0], g->bbox[1],
           g->bbox[2], g->bbox[3], g->bbox[4], g->bbox[5]);
}

static void test_no_cracks_adaptive(void)
{
    st_rgeom g;
    st_rgeom_init(&g);
    uint64_t rng = 0xada;
    for (size_t i = 0; i < sizeof adaptive_cases / sizeof adaptive_cases[0]; i++) {
        mesh_case c0 = adaptive_cases[i];
        c0.levels = 0;
        st_hier h;
        char name[256];
        if (load_hier(&h, &c0, name, sizeof name)) continue;
        st_adapt a;
        st_error err;
        if (st_adapt_init(&a, &h, &err)) {
            printf("%s: no adaptive refinement for this scheme yet (%s)\n", name, err.msg);
            st_hier_free(&h);
            continue;
        }
        st_mesh soup;
        st_mesh_init(&soup);
        CHECK(st_map_to_mesh(&h.map, 0, &soup, &err) == ST_OK);
        double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
        for (uint32_t v = 0; v < soup.nverts; v++)
            for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], soup.pos[3 * v + k]); hi[k] = fmax(hi[k], soup.pos[3 * v + k]); }
        /* Input polygons the scheme makes anyway (quads for Catmull-Clark,
         * triangles for Loop and Butterfly, both for quad/triangle): then
         * every restricted face is in the tables. */
        int native = 1;
        for (uint32_t f = 0; f < soup.nfaces; f++) {
            uint32_t n = soup.face_off[f + 1] - soup.face_off[f];
            st_scheme_id id = adaptive_cases[i].scheme;
            if (id == ST_SCHEME_CATMARK ? n != 4 : id == ST_SCHEME_QUADTRI ? (n != 3 && n != 4) : n != 3) native = 0;
        }
        st_mesh_free(&soup);
        unsigned faces_seen = 0, depths = 0, patched = 0, rebuilt = 0;
        st_rgeom pg;
        st_rgeom_init(&pg);
        st_map_log log = { 0 };
        int have_pg = 0;
        st_adapt_params p = { 0 };
        /* Random boxes (steps 0-4 and 11, the last without the restriction)
         * and, in between, six small moves of the box (5 % of its size along
         * x, as a drag does). */
        for (int step = 0; step < 12; step++) {
            if (step < 5 || step == 11) {
                p = (st_adapt_params){ .base_level = (unsigned)step % 2, .max_level = adaptive_cases[i].levels, .has_box = 1 };
                for (int k = 0; k < 3; k++) {
                    double ext = hi[k] - lo[k], c = lo[k] + ext * (double)(tl_rand(&rng) % 1001) / 1000.0;
                    p.box_lo[k] = c - 0.2 * ext;
                    p.box_hi[k] = c + 0.2 * ext;
                }
                p.no_restriction = step == 11;
                p.falloff = step == 3 ? 0.3 * (hi[0] - lo[0]) : 0;
            } else {
                double shift = 0.05 * (p.box_hi[0] - p.box_lo[0]);
                p.box_lo[0] += shift;
                p.box_hi[0] += shift;
            }
            st_map_log_clear(&log);
            unsigned top0 = h.map.top;
            h.map.log = &log;
            int rc = st_adapt_update(&a, &p, &err);
            h.map.log = NULL;
            CHECKF(rc == ST_OK, "%s step %d: %s", name, step, err.msg);
            if (rc) break;
            /* The renderer's patch after the move (same displayed level). */
            if (have_pg && h.map.top == top0) {
                st_rgeom_dirty dirty = { 0 };
                int pr = st_rgeom_patch(&pg, &h.map, &log, &dirty);
                CHECKF(pr >= 0, "%s step %d: st_rgeom_patch failed", name, step);
                if (pr == 1) { rebuilt++; have_pg = 0; }
                else patched++;
                st_rgeom_dirty_free(&dirty);
            } else have_pg = 0;
            if (!have_pg) have_pg = st_rgeom_build(&pg, &h.map, h.map.top, &err) == ST_OK;
            rc = st_rgeom_build(&g, &h.map, h.map.top, &err);
            CHECKF(rc == ST_OK, "%s: %s", name, err.msg);
            if (rc) break;
            char what[300];
            snprintf(what, sizeof what, "%s adaptive step %d%s", name, step, p.no_restriction ? " (no restriction)" : "");
            check_geom(&g, &h.map, what, native && !p.no_restriction);
            compare_patched(&pg, &g, what);
            faces_seen += g.nfaces;
            unsigned mixed = 0;
            for (unsigned k = 0; k < 31; k++) mixed += g.ncase[k] > 0;
            if (mixed > depths) depths = mixed;
        }
        printf("%s: adaptive meshes crack-free over 12 box moves (%u faces drawn in all, up to %u triangulation cases); "
               "%u patched like a fresh build, %u compacted\n", name, faces_seen, depths, patched, rebuilt);
        CHECKF(patched > 0, "%s: no move was patched", name);
        st_rgeom_free(&pg);
        st_map_log_free(&log);
        st_adapt_free(&a);
        st_hier_free(&h);
    }
    st_rgeom_free(&g);
}

/* ---- incremental updates --------------------------------------------------------- */

static int in_ranges(const st_range_list *r, uint32_t i)
{
    for (uint32_t k = 0; k < r->n; k++)
        if (i >= r->r[k].first && i - r->r[k].first < r->r[k].count) return 1;
    return 0;
}

static const mesh_case edit_cases[] = {
    { "torus.obj", 0, ST_SCHEME_CATMARK, 3 },
    { "open.obj", 0, ST_SCHEME_CATMARK, 3 },
    { "octahedron.obj", 0, ST_SCHEME_LOOP, 3 },
    { "octahedron.obj", 0, ST_SCHEME_BUTTERFLY, 3 },
    { "octahedron.obj", 0, ST_SCHEME_SQRT3, 3 },
    { "mixed.obj", 0, ST_SCHEME_QUADTRI, 3 },
    { "torus.obj", 0, ST_SCHEME_DOOSABIN, 3 },
    { "triangle/cube_no_bottom.obj", 1, ST_SCHEME_SQRT3, 3 },
    { "triangle/cube_no_bottom.obj", 1, ST_SCHEME_LOOP, 3 },
};

static void test_incremental(void)
{
    uint64_t rng = 0x5eed;
    for (size_t i = 0; i < sizeof edit_cases / sizeof edit_cases[0]; i++) {
        st_hier h;
        char name[256];
        if (load_hier(&h, &edit_cases[i], name, sizeof name)) continue;
        tl_random_details(&h, &rng, 0.02);
        for (unsigned l = 0; l < h.map.top; l++)
            for (unsigned D = l; D <= h.map.top; D++) {
                st_rgeom g, fresh;
                st_rgeom_init(&g);
                st_rgeom_init(&fresh);
                st_error err;
                CHECKF(st_rgeom_build(&g, &h.map, D, &err) == ST_OK, "%s", err.msg);
                float *before = malloc((size_t)g.nverts * ST_RGEOM_VSTRIDE * sizeof *before);
                float *fbefore = malloc(4 * (size_t)g.nfaces * sizeof *fbefore);
                memcpy(before, g.vdata, (size_t)g.nverts * ST_RGEOM_VSTRIDE * sizeof *before);
                memcpy(fbefore, g.fnormal, 4 * (size_t)g.nfaces * sizeof *fbefore);
                /* Move two vertices of level l. */
                uint32_t darts[2];
                double pos[2][3];
                darts[0] = tl_random_dart_at(&h.map, l, &rng);
                do darts[1] = tl_random_dart_at(&h.map, l, &rng);
                while (st_vert(&h.map, darts[1], l) == st_vert(&h.map, darts[0], l));
                for (int k = 0; k < 2; k++) {
                    const double *p = st_dart_pos(&h.map, darts[k], l);
                    for (int c = 0; c < 3; c++) pos[k][c] = p[c] + 0.1 * (c + 1) * (k ? -1 : 1);
                }
                st_footprint fp = { 0 };
                st_hier_edit(&h, l, darts, (const double (*)[3])pos, 2, &fp);
                uint32_t *vids = NULL, n = 0, cap = 0;
                CHECK(st_rgeom_footprint_vids(&g, &h.map, &fp, &vids, &n, &cap) == 0);
                st_footprint_free(&fp);
                st_range_list vr = { 0 }, fr = { 0 };
                CHECK(st_rgeom_refresh(&g, &h.map, vids, n, &vr, &fr) == 0);
                CHECKF(st_rgeom_build(&fresh, &h.map, D, &err) == ST_OK, "%s", err.msg);
                size_t vb = (size_t)g.nverts * ST_RGEOM_VSTRIDE * sizeof(float), fb = 4 * (size_t)g.nfaces * sizeof(float);
                int same_v = g.nverts == fresh.nverts && !memcmp(g.vdata, fresh.vdata, vb);
                int same_f = g.nfaces == fresh.nfaces && !memcmp(g.fnormal, fresh.fnormal, fb);
                CHECKF(same_v && same_f, "%s: edit at level %u shown at level %u: incremental != rebuild (vertices %s, faces %s)",
                       name, l, D, same_v ? "same" : "DIFFER", same_f ? "same" : "DIFFER");
                /* Every changed entry lies in a dirty range. */
                uint32_t changed = 0, uncovered = 0;
                for (uint32_t v = 0; v < g.nverts; v++)
                    if (memcmp(before + ST_RGEOM_VSTRIDE * (size_t)v, g.vdata + ST_RGEOM_VSTRIDE * (size_t)v,
                               ST_RGEOM_VSTRIDE * sizeof(float))) {
                        changed++;
                        if (!in_ranges(&vr, v)) uncovered++;
                    }
                for (uint32_t f = 0; f < g.nfaces; f++)
                    if (memcmp(fbefore + 4 * (size_t)f, g.fnormal + 4 * (size_t)f, 4 * sizeof(float)) && !in_ranges(&fr, f))
                        uncovered++;
                CHECKF(!uncovered, "%s: %u changed entries outside the dirty ranges", name, uncovered);
                CHECKF(changed > 0, "%s: edit at level %u changed nothing at level %u", name, l, D);
                /* Local: on the torus at depth 3, an edit at level 1 touches
                 * a part of the finest level (Doo-Sabin's support is wider). */
                if (!strcmp(edit_cases[i].file, "torus.obj") && l == 1 && D == 3) {
                    uint32_t up = 0;
                    for (uint32_t k = 0; k < vr.n; k++) up += vr.r[k].count;
                    CHECKF(up < g.nverts / 2, "%s: %u of %u vertices re-uploaded after a level-1 edit", name, up, g.nverts);
                    printf("%s: edit at level 1, level 3 shown: %u of %u vertices re-uploaded in %u ranges (%u region vertices)\n",
                           name, up, g.nverts, vr.n, n);
                }
                st_range_list_free(&vr);
                st_range_list_free(&fr);
                free(vids);
                free(before);
                free(fbefore);
                st_rgeom_free(&g);
                st_rgeom_free(&fresh);
            }
        st_hier_free(&h);
    }
}

/* UVs per triangle corner (st_rgeom_corner_uvs, the UV checker's input):
 * two quads with a UV seam along their shared edge (x = 1), whose UVs are
 * u = x / 2 on the left quad and u = 0.6 + 0.4 (x - 1) on the right one,
 * v = y on both.  Every triangle corner must carry its own face's UV, so
 * the two seam vertices show u = 0.5 in one face and u = 0.6 in the other. */
static void test_corner_uvs(void)
{
    static const char *obj =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
        "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 0.6 0\nvt 0.6 1\nvt 1 0\nvt 1 1\n"
        "f 1/1 2/2 3/3 4/4\n"
        "f 2/5 5/7 6/8 3/6\n";
    st_mesh mesh;
    st_error err = { 0 };
    st_mesh_init(&mesh);
    CHECKF(st_mesh_parse_obj("seam.obj", obj, strlen(obj), &mesh, &err) == 0, "%s", err.msg);
    st_hier h;
    CHECKF(st_hier_init(&h, &mesh, &st_scheme_catmark, NULL, &err) == 0, "%s", err.msg);
    st_mesh_free(&mesh);
    st_uv_map uv = st_hier_uv(&h, 0);
    CHECK(uv.uv != NULL);
    st_rgeom g;
    st_rgeom_init(&g);
    CHECK(st_rgeom_build(&g, &h.map, 0, &err) == 0);
    CHECK(g.ntris == 4);
    float *t = malloc(6 * (size_t)g.ntris * sizeof *t);
    st_rgeom_corner_uvs(&g, &h.map, &uv, t);
    int seam_left = 0, seam_right = 0;
    for (uint32_t i = 0; i < g.ntris; i++) {
        /* The face is on the right when its centroid is. */
        double cx = 0;
        for (int j = 0; j < 3; j++) cx += g.vdata[ST_RGEOM_VSTRIDE * (size_t)g.tris[3 * i + j]] / 3;
        int right = cx > 1;
        for (int j = 0; j < 3; j++) {
            const float *p = g.vdata + ST_RGEOM_VSTRIDE * (size_t)g.tris[3 * i + j];
            double u = right ? 0.6 + 0.4 * (p[0] - 1) : 0.5 * p[0], v = p[1];
            CHECKF(fabs(t[6 * i + 2 * j] - u) < 1e-6 && fabs(t[6 * i + 2 * j + 1] - v) < 1e-6,
                   "triangle %u corner %d at (%g, %g): uv (%g, %g), expected (%g, %g)", i, j, p[0], p[1], t[6 * i + 2 * j],
                   t[6 * i + 2 * j + 1], u, v);
            if (p[0] == 1) { seam_left += !right; seam_right += right; }
        }
    }
    CHECK(seam_left > 0 && seam_right > 0);
    free(t);
    st_rgeom_free(&g);
    st_hier_free(&h);
}

int main(void)
{
    test_corner_uvs();
    test_no_cracks();
    test_no_cracks_adaptive();
    test_incremental();
    return TEST_END();
}
