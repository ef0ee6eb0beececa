/* Unsubdivide (core/rebuild/unsubdivide.h): cages from the shared meshes,
 * subdivided 1..4 times by Strata, then shuffled (vertex order, face order,
 * starting corners), are recognised with their depth, face and vertex
 * counts; the rebuilt hierarchy's cage matches the original cage's
 * positions (1e-9 of the diagonal), its details are zero, its finest level
 * is the input bit for bit with the same faces up to vertex order.  Locally
 * re-meshed inputs are refused with the place named; limits and scheme
 * compatibility behave as documented; one thread and two build the same
 * hierarchy to the bit. */
#include "testlib.h"
#include "core/rebuild/unsubdivide.h"
#include "core/rebuild/rebuild.h"
#include "core/io/session.h"
#include "core/rebuild/unsub_topo_internal.h"
#include "core/base/parallel.h"
#include "core/multires/hier_internal.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int load(const char *rel, st_mesh *m)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", STRATA_SHARED_DATA, rel);
    st_error err;
    st_mesh_init(m);
    if (st_mesh_load(path, m, &err)) {
        snprintf(path, sizeof path, "%s/%s", STRATA_ASSETS, rel);
        if (st_mesh_load(path, m, &err)) { fprintf(stderr, "%s\n", err.msg); return -1; }
    }
    return 0;
}

/* Level `levels` of the cage under scheme id, as a soup. */
static int subdivided(const st_mesh *cage, st_scheme_id id, unsigned levels, st_mesh *out)
{
    st_hier h;
    st_error err;
    st_mesh_init(out);
    if (st_hier_init(&h, cage, st_scheme_find(id == ST_SCHEME_CATMARK ? "catmull-clark" : id == ST_SCHEME_LOOP ? "loop"
                                                    : id == ST_SCHEME_BUTTERFLY ? "butterfly" : "quad-triangle"), NULL, &err))
        return -1;
    int rc = st_hier_subdivide_to(&h, levels, &err) || st_hier_level_mesh(&h, levels, out, &err);
    st_hier_free(&h);
    return rc ? -1 : 0;
}

#define ROTATE_ONLY (1ull << 62)

/* A copy with vertices and faces permuted and each face's start rotated. */
static void shuffle(const st_mesh *in, st_mesh *out, uint64_t seed)
{
    uint64_t rng = seed;
    uint32_t nv = in->nverts, nf = in->nfaces, nc = in->face_off[nf];
    uint32_t *vperm = malloc(nv * sizeof *vperm), *fperm = malloc(nf * sizeof *fperm);
    for (uint32_t i = 0; i < nv; i++) vperm[i] = i;
    for (uint32_t i = 0; i < nf; i++) fperm[i] = i;
    /* ROTATE_ONLY: same orders, every face starting two corners later (so
     * a face's coarse vertex and face point trade places in the seed). */
    int rotate_only = (seed & ROTATE_ONLY) != 0;
    for (uint32_t i = nv; i > 1 && !rotate_only; i--) { uint32_t j = tl_rand(&rng) % i, t = vperm[i - 1]; vperm[i - 1] = vperm[j]; vperm[j] = t; }
    for (uint32_t i = nf; i > 1 && !rotate_only; i--) { uint32_t j = tl_rand(&rng) % i, t = fperm[i - 1]; fperm[i - 1] = fperm[j]; fperm[j] = t; }
    st_mesh_init(out);
    out->nverts = nv;
    out->nfaces = nf;
    out->boundary_interp = in->boundary_interp;
    out->pos = malloc(3 * (size_t)nv * sizeof *out->pos);
    out->face_off = malloc(((size_t)nf + 1) * sizeof *out->face_off);
    out->face_idx = malloc((size_t)nc * sizeof *out->face_idx);
    for (uint32_t v = 0; v < nv; v++) memcpy(out->pos + 3 * (size_t)vperm[v], in->pos + 3 * (size_t)v, 3 * sizeof(double));
    uint32_t c = 0;
    for (uint32_t i = 0; i < nf; i++) {
        uint32_t f = fperm[i], b = in->face_off[f], n = in->face_off[f + 1] - b, r = rotate_only ? 2 % n : tl_rand(&rng) % n;
        out->face_off[i] = c;
        for (uint32_t k = 0; k < n; k++) out->face_idx[c++] = vperm[in->face_idx[b + (k + r) % n]];
    }
    out->face_off[nf] = c;
    free(vperm);
    free(fperm);
}

/* Faces as sorted lists of position ranks, each rotated to its smallest
 * rank: equal for two meshes with the same faces up to vertex order. */
static int cmp_pos(const void *a, const void *b, const double *pos)
{
    const double *p = pos + 3 * (size_t)*(const uint32_t *)a, *q = pos + 3 * (size_t)*(const uint32_t *)b;
    for (int k = 0; k < 3; k++) if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
    return 0;
}
static const double *g_pos;
static int cmp_pos_g(const void *a, const void *b) { return cmp_pos(a, b, g_pos); }
static uint32_t g_width;
static int cmp_rows(const void *a, const void *b) { return memcmp(a, b, g_width * sizeof(uint32_t)) ; }

static uint32_t *canonical(const st_mesh *m, uint32_t width)
{
    uint32_t *order = malloc(m->nverts * sizeof *order), *rank = malloc(m->nverts * sizeof *rank);
    for (uint32_t v = 0; v < m->nverts; v++) order[v] = v;
    g_pos = m->pos;
    qsort(order, m->nverts, sizeof *order, cmp_pos_g);
    for (uint32_t i = 0; i < m->nverts; i++) rank[order[i]] = i;
    uint32_t *rows = calloc((size_t)m->nfaces * width, sizeof *rows);
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t b = m->face_off[f], n = m->face_off[f + 1] - b, s = 0;
        for (uint32_t k = 1; k < n; k++) if (rank[m->face_idx[b + k]] < rank[m->face_idx[b + s]]) s = k;
        uint32_t *row = rows + (size_t)f * width;
        row[0] = n;
        for (uint32_t k = 0; k < n && k + 1 < width; k++) row[k + 1] = rank[m->face_idx[b + (s + k) % n]];
    }
    g_width = width;
    qsort(rows, m->nfaces, width * sizeof *rows, cmp_rows);
    free(order);
    free(rank);
    return rows;
}

static int same_faces(const st_mesh *a, const st_mesh *b)
{
    if (a->nverts != b->nverts || a->nfaces != b->nfaces) return 0;
    uint32_t *ra = canonical(a, 9), *rb = canonical(b, 9);
    int same = memcmp(ra, rb, (size_t)a->nfaces * 9 * sizeof *ra) == 0;
    free(ra);
    free(rb);
    return same;
}

/* Largest distance from a cage vertex to the nearest vertex of the other. */
static double cage_distance(const st_mesh *a, const st_mesh *b)
{
    double worst = 0;
    for (uint32_t i = 0; i < a->nverts; i++) {
        double best = INFINITY;
        for (uint32_t j = 0; j < b->nverts; j++) {
            double d = 0;
            for (int k = 0; k < 3; k++) { double x = a->pos[3 * (size_t)i + k] - b->pos[3 * (size_t)j + k]; d += x * x; }
            if (d < best) best = d;
        }
        if (sqrt(best) > worst) worst = sqrt(best);
    }
    return worst;
}

static void check_recovery(const char *rel, st_scheme_id id, unsigned levels, uint64_t seed)
{
    st_mesh cage, fine, in;
    if (load(rel, &cage)) { CHECKF(0, "cannot load %s", rel); return; }
    if (subdivided(&cage, id, levels, &fine)) { CHECKF(0, "cannot subdivide %s", rel); st_mesh_free(&cage); return; }
    if (seed) shuffle(&fine, &in, seed);
    else st_mesh_move(&in, &fine);
    st_mesh_free(&fine);
    st_unsub u;
    st_error err;
    st_unsub_opts o = { .max_levels = levels };
    int rc = st_unsubdivide(rel, &in, &o, &u, &err);
    CHECKF(rc == 0, "%s x%u seed %llu: %s", rel, levels, (unsigned long long)seed, rc ? err.msg : "");
    if (rc) { st_mesh_free(&cage); st_mesh_free(&in); return; }
    const st_mesh *got = &u.step[0].coarse;
    CHECKF(u.levels == levels && got->nfaces == cage.nfaces && got->nverts == cage.nverts,
           "%s x%u: found %u levels, cage %u faces %u vertices; expected %u faces %u vertices",
           rel, levels, u.levels, got->nfaces, got->nverts, cage.nfaces, cage.nverts);
    CHECK(u.pattern == (id == ST_SCHEME_CATMARK ? ST_UNSUB_POLY_SPLIT : ST_UNSUB_QUADRISECTION));
    st_hier h;
    uint32_t *fine_of = NULL;
    double res;
    const st_scheme *sc = st_scheme_find(id == ST_SCHEME_CATMARK ? "catmull-clark" : id == ST_SCHEME_LOOP ? "loop" : "butterfly");
    CHECK(st_unsub_scheme_fits(&u, sc));
    rc = st_unsub_build_hier(&in, &u, sc, NULL, &h, &fine_of, &res, &err);
    CHECKF(rc == 0, "%s: %s", rel, rc ? err.msg : "");
    if (!rc) {
        double diag = st_mesh_diagonal(&in);
        CHECKF(h.map.top == levels, "%s: top %u", rel, h.map.top);
        /* Level 0 is the original cage (a permutation of it). */
        st_mesh l0;
        st_mesh_init(&l0);
        CHECK(st_hier_level_mesh(&h, 0, &l0, &err) == 0);
        double dist = cage_distance(&l0, &cage);
        CHECKF(dist <= 1e-9 * diag, "%s x%u: cage off by %.3g (diagonal %.3g)", rel, levels, dist, diag);
        CHECKF(st_unsub_max_detail(&h) <= 1e-9 * diag, "%s x%u: detail %.3g", rel, levels, st_unsub_max_detail(&h));
        /* The finest level is the input, bit for bit, same faces. */
        st_dart_iter it;
        uint32_t exact = 1;
        for (uint32_t v = st_vertex_first(&h.map, levels, &it); v != ST_NIL; v = st_vertex_next(&h.map, levels, &it))
            exact &= memcmp(st_pos(&h.map, v, levels), in.pos + 3 * (size_t)fine_of[v], 3 * sizeof(double)) == 0;
        CHECKF(exact, "%s x%u: finest level differs from the input", rel, levels);
        st_mesh top;
        st_mesh_init(&top);
        CHECK(st_hier_level_mesh(&h, levels, &top, &err) == 0);
        CHECKF(same_faces(&top, &in), "%s x%u: finest faces differ from the input's", rel, levels);
        CHECK(st_map_validate(&h.map, &err) == 0);
        st_mesh_free(&top);
        st_mesh_free(&l0);
        free(fine_of);
        st_hier_free(&h);
    }
    st_unsub_free(&u);
    st_mesh_free(&cage);
    st_mesh_free(&in);
}

/* A subdivided cage whose pattern is broken locally is refused, the
 * message naming a place of the change. */
/* Flips the first edge of triangle f of a triangle mesh: faces f = (a b c)
 * and g = (b a d) become (a d c) and (d b c).  Returns g, ST_NIL when f's
 * edge a-b has no other face; near (if not NULL) receives a, b, c, d. */
static uint32_t flip_edge(st_mesh *m, uint32_t f, uint32_t near[4])
{
    uint32_t a = m->face_idx[3 * f], b = m->face_idx[3 * f + 1], cc = m->face_idx[3 * f + 2], g = ST_NIL, d = 0;
    for (uint32_t h = 0; h < m->nfaces && g == ST_NIL; h++)
        for (int k = 0; k < 3; k++)
            if (m->face_idx[3 * h + k] == b && m->face_idx[3 * h + (k + 1) % 3] == a) { g = h; d = m->face_idx[3 * h + (k + 2) % 3]; }
    if (g == ST_NIL) return ST_NIL;
    uint32_t nf[6] = { a, d, cc, d, b, cc };
    memcpy(m->face_idx + 3 * f, nf, 3 * sizeof *nf);
    memcpy(m->face_idx + 3 * g, nf + 3, 3 * sizeof *nf);
    if (near) { near[0] = a; near[1] = b; near[2] = cc; near[3] = d; }
    return g;
}

static void check_refusals(void)
{
    st_mesh cage, fine;
    st_error err;
    st_unsub u;
    /* One quad of a Catmull-Clark level split into two triangles. */
    CHECK(load("catmull_clark/blub_control_mesh.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_CATMARK, 2, &fine) == 0);
    {
        st_mesh m;
        st_mesh_init(&m);
        uint32_t q = fine.nfaces / 2, nf = fine.nfaces + 1;
        m.nverts = fine.nverts;
        m.pos = malloc(3 * (size_t)fine.nverts * sizeof *m.pos);
        memcpy(m.pos, fine.pos, 3 * (size_t)fine.nverts * sizeof *m.pos);
        m.nfaces = nf;
        m.face_off = malloc(((size_t)nf + 1) * sizeof *m.face_off);
        m.face_idx = malloc(((size_t)fine.face_off[fine.nfaces] + 2) * sizeof *m.face_idx);
        uint32_t c = 0, f2 = 0;
        for (uint32_t f = 0; f < fine.nfaces; f++) {
            const uint32_t *x = fine.face_idx + fine.face_off[f];
            if (f == q) {
                m.face_off[f2++] = c; m.face_idx[c++] = x[0]; m.face_idx[c++] = x[1]; m.face_idx[c++] = x[2];
                m.face_off[f2++] = c; m.face_idx[c++] = x[0]; m.face_idx[c++] = x[2]; m.face_idx[c++] = x[3];
            } else {
                m.face_off[f2++] = c;
                for (int k = 0; k < 4; k++) m.face_idx[c++] = x[k];
            }
        }
        m.face_off[nf] = c;
        CHECK(st_mesh_check("split", &m, &err) == 0);
        int rc = st_unsubdivide("split.obj", &m, NULL, &u, &err);
        char want[64];
        snprintf(want, sizeof want, "face %u has 3 sides", q + 1);
        CHECKF(rc == ST_ERR_TOPOLOGY && strstr(err.msg, want) && strstr(err.msg, "split.obj"), "message: %s", rc ? err.msg : "accepted");
        CHECK(u.levels == 0);
        st_mesh_free(&m);
    }
    st_mesh_free(&fine);
    st_mesh_free(&cage);
    /* One interior edge of a Loop level flipped. */
    CHECK(load("triangle/sphere_ico.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_LOOP, 1, &fine) == 0);
    {
        uint32_t f = 7, near[4] = { 0 }, g = flip_edge(&fine, f, near);
        CHECK(g != ST_NIL);
        CHECK(st_mesh_check("flip", &fine, &err) == 0);
        int rc = st_unsubdivide("flip.obj", &fine, NULL, &u, &err);
        CHECKF(rc == ST_ERR_TOPOLOGY, "flipped edge accepted");
        int named = 0;
        for (int i = 0; i < 4; i++) {
            char want[48];
            snprintf(want, sizeof want, "vertex %u ", near[i] + 1);
            if (strstr(err.msg, want)) named = 1;
        }
        char wf[2][48];
        snprintf(wf[0], sizeof wf[0], "face %u", f + 1);
        snprintf(wf[1], sizeof wf[1], "face %u", g + 1);
        if (strstr(err.msg, wf[0]) || strstr(err.msg, wf[1])) named = 1;
        CHECKF(named, "the message does not name the flipped edge's vertices %u %u %u %u or faces %u %u: %s",
               near[0] + 1, near[1] + 1, near[2] + 1, near[3] + 1, f + 1, g + 1, err.msg);
        fprintf(stderr, "flip refused: %s\n", err.msg);
    }
    st_mesh_free(&fine);
    /* A mesh that is no subdivision at all (the icosahedron's own cage). */
    CHECK(subdivided(&cage, ST_SCHEME_LOOP, 0, &fine) == 0);
    st_unsub_opts one = { .max_levels = 0 };
    CHECK(st_unsubdivide("ico.obj", &fine, &one, &u, &err) == 0 && u.levels == 2 && u.step[0].coarse.nfaces == 20);
    st_unsub_free(&u);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
}

/* --max-levels and --target-faces; scheme compatibility. */
static void check_limits(void)
{
    st_mesh cage, fine;
    st_error err;
    st_unsub u;
    CHECK(load("catmull_clark/dodecahedron_poly.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_CATMARK, 3, &fine) == 0); /* 960 quads */
    st_unsub_opts o = { 0 };
    CHECK(st_unsubdivide("d", &fine, &o, &u, &err) == 0 && u.levels == 3 && u.step[0].coarse.nfaces == 12);
    CHECK(st_unsub_scheme_fits(&u, st_scheme_find("catmull-clark")));
    CHECK(st_unsub_scheme_fits(&u, st_scheme_find("quad-triangle")));  /* pentagons: no triangles */
    CHECK(!st_unsub_scheme_fits(&u, st_scheme_find("loop")));
    CHECK(!st_unsub_scheme_fits(&u, st_scheme_find("doo-sabin")));
    st_unsub_free(&u);
    o.max_levels = 1;
    CHECK(st_unsubdivide("d", &fine, &o, &u, &err) == 0 && u.levels == 1 && u.step[0].coarse.nfaces == 240);
    st_unsub_free(&u);
    o.max_levels = 0;
    o.target_faces = 50;   /* 960 -> 240 -> 60; 12 would be fewer than 50 */
    CHECK(st_unsubdivide("d", &fine, &o, &u, &err) == 0 && u.levels == 2 && u.step[0].coarse.nfaces == 60);
    st_unsub_free(&u);
    o.target_faces = 240;
    CHECK(st_unsubdivide("d", &fine, &o, &u, &err) == 0 && u.levels == 1 && u.step[0].coarse.nfaces == 240);
    st_unsub_free(&u);
    o.target_faces = 1000;
    CHECK(st_unsubdivide("d", &fine, &o, &u, &err) != 0 && strstr(err.msg, "--target-faces"));
    st_mesh_free(&fine);
    st_mesh_free(&cage);
    /* Blub's cage has triangles: quad-triangle would quadrisect them. */
    CHECK(load("catmull_clark/blub_control_mesh.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_CATMARK, 1, &fine) == 0);
    CHECK(st_unsubdivide("b", &fine, NULL, &u, &err) == 0 && u.levels == 1);
    CHECK(!st_unsub_scheme_fits(&u, st_scheme_find("quad-triangle")));
    st_unsub_free(&u);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
    /* Quadrisection: loop, butterfly, quad-triangle. */
    CHECK(load("triangle/hemisphere.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_LOOP, 1, &fine) == 0);
    o.target_faces = 0;
    o.max_levels = 1;
    CHECK(st_unsubdivide("h", &fine, &o, &u, &err) == 0 && u.levels == 1);
    CHECK(st_unsub_scheme_fits(&u, st_scheme_find("loop")) && st_unsub_scheme_fits(&u, st_scheme_find("butterfly")) &&
          st_unsub_scheme_fits(&u, st_scheme_find("quad-triangle")) && !st_unsub_scheme_fits(&u, st_scheme_find("catmull-clark")));
    st_unsub_free(&u);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
}

/* The rebuilt hierarchy saves and loads like any session, byte for byte. */
static void check_session(void)
{
    st_mesh cage, fine;
    st_error err;
    st_unsub u;
    st_hier h;
    CHECK(load("triangle/cube_no_bottom.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_LOOP, 2, &fine) == 0);
    CHECK(st_unsubdivide("c", &fine, NULL, &u, &err) == 0);
    CHECK(st_unsub_build_hier(&fine, &u, st_scheme_find("loop"), NULL, &h, NULL, NULL, &err) == 0);
    st_session_ref r = { .h = &h, .display_level = h.map.top };
    st_session s;
    if (tl_session_roundtrip(&r, "mem", &s) == 0) st_session_free(&s);
    st_hier_free(&h);
    st_unsub_free(&u);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
}

/* The hierarchy is built on two threads (the input's adjacency beside the
 * refinement): one thread and two give the same hierarchy to the bit,
 * positions and details of every level, and the same correspondence. */
static void check_threads(void)
{
    st_mesh cage, fine, shuffled;
    st_error err;
    st_unsub u;
    st_hier h[2];
    uint32_t *fine_of[2] = { NULL, NULL }, *corner_of[2] = { NULL, NULL };
    CHECK(load("catmull_clark/spot_quadrangulated.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_CATMARK, 2, &fine) == 0);
    shuffle(&fine, &shuffled, 4242);
    CHECK(st_unsubdivide("spot", &shuffled, NULL, &u, &err) == 0);
    for (unsigned t = 0; t < 2; t++) {
        st_parallel_set_threads(t + 1);
        CHECKF(st_unsub_build_hier_corners(&shuffled, &u, st_scheme_find("catmull-clark"), NULL, &h[t], &fine_of[t],
                                           &corner_of[t], NULL, NULL, &err) == 0, "%u thread(s): %s", t + 1, err.msg);
    }
    st_parallel_set_threads(0);
    const st_map *a = &h[0].map, *b = &h[1].map;
    CHECK(a->top == b->top && a->verts.end == b->verts.end && a->darts.end == b->darts.end);
    uint64_t differ = 0, n = 0;
    for (unsigned l = 0; l <= a->top && a->verts.end == b->verts.end; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(a, l, &it); v != ST_NIL; v = st_vertex_next(a, l, &it), n++) {
            differ += memcmp(st_pos(a, v, l), st_pos(b, v, l), 3 * sizeof(double)) != 0;
            if (l) differ += memcmp(st_hier_detail(&h[0], l, v), st_hier_detail(&h[1], l, v), 3 * sizeof(double)) != 0;
        }
    }
    CHECKF(n > 50000 && differ == 0, "%llu of %llu vertices differ between one thread and two",
           (unsigned long long)differ, (unsigned long long)n);
    CHECK(a->verts.end != b->verts.end || !memcmp(fine_of[0], fine_of[1], a->verts.end * sizeof(uint32_t)));
    uint64_t corners = 0, other = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(a, a->top, &it); d != ST_NIL; d = st_dart_next(a, a->top, &it)) {
        corners += corner_of[0][d] != ST_NIL;
        other += corner_of[0][d] != corner_of[1][d];
    }
    CHECKF(corners == shuffled.face_off[shuffled.nfaces] && other == 0, "%llu darts with a corner, %u corners, %llu differ",
           (unsigned long long)corners, shuffled.face_off[shuffled.nfaces], (unsigned long long)other);
    for (unsigned t = 0; t < 2; t++) {
        free(fine_of[t]);
        free(corner_of[t]);
        st_hier_free(&h[t]);
    }
    st_unsub_free(&u);
    st_mesh_free(&shuffled);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
}

/* Vertices of any level whose position or detail differs by a bit. */
static uint64_t hier_differences(const st_hier *ha, const st_hier *hb)
{
    const st_map *a = &ha->map, *b = &hb->map;
    if (a->top != b->top || a->verts.end != b->verts.end) return UINT64_MAX;
    uint64_t differ = 0;
    for (unsigned l = 0; l <= a->top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(a, l, &it); v != ST_NIL; v = st_vertex_next(a, l, &it)) {
            differ += memcmp(st_pos(a, v, l), st_pos(b, v, l), 3 * sizeof(double)) != 0;
            if (l) differ += memcmp(st_hier_detail(ha, l, v), st_hier_detail(hb, l, v), 3 * sizeof(double)) != 0;
        }
    }
    return differ;
}

/* The analysis of an unsubdivided mesh (hier_analysis.c): spot x2,
 * shuffled, exact or moved by up to `noise` of its diagonal.  One, two and
 * four threads build the same hierarchy to the bit, whose finest level is
 * the input.  Exact: every level is accepted by the streamed pass (no
 * stored stencils), and analysing the result again, streamed or by the
 * stored rows and the solve, changes no bit: the streamed details are the
 * stored rows' from the same coarse positions.  Noisy: every level falls
 * back to the solve. */
static void check_streamed(double noise)
{
    st_mesh cage, fine, in;
    st_error err;
    st_unsub u;
    st_hier h[3];
    uint32_t *fine_of[3] = { NULL, NULL, NULL };
    CHECK(load("catmull_clark/spot_quadrangulated.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_CATMARK, 2, &fine) == 0);
    shuffle(&fine, &in, 99);
    double diag = st_mesh_diagonal(&in);
    uint64_t rng = 5;
    for (uint32_t i = 0; noise > 0 && i < 3 * in.nverts; i++)
        in.pos[i] += noise * diag * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
    st_unsub_opts o = { .max_levels = 2 };
    int rc = st_unsubdivide("spot x2", &in, &o, &u, &err);
    CHECKF(rc == 0 && u.levels == 2, "noise %g: %s", noise, rc ? err.msg : "not 2 levels");
    if (rc || u.levels != 2) { st_mesh_free(&in); st_mesh_free(&fine); st_mesh_free(&cage); if (!rc) st_unsub_free(&u); return; }
    static const unsigned threads[3] = { 1, 2, 4 };
    int built = 1;
    for (unsigned t = 0; t < 3; t++) {
        st_parallel_set_threads(threads[t]);
        rc = st_unsub_build_hier(&in, &u, st_scheme_find("catmull-clark"), NULL, &h[t], &fine_of[t], NULL, &err);
        CHECKF(rc == 0, "noise %g, %u thread(s): %s", noise, threads[t], rc ? err.msg : "");
        built &= rc == 0;
        if (rc) fine_of[t] = NULL;
    }
    st_parallel_set_threads(0);
    if (built) {
        CHECKF(hier_differences(&h[0], &h[1]) == 0 && hier_differences(&h[0], &h[2]) == 0,
               "noise %g: one, two and four threads differ", noise);
        uint32_t exact = 1, nv = 0;
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h[0].map, 2, &it); v != ST_NIL; v = st_vertex_next(&h[0].map, 2, &it), nv++)
            exact &= memcmp(st_pos(&h[0].map, v, 2), in.pos + 3 * (size_t)fine_of[0][v], 3 * sizeof(double)) == 0;
        CHECKF(exact && nv == in.nverts, "noise %g: the finest level is not the input", noise);
        double longest = st_unsub_max_detail(&h[0]);
        CHECKF(noise > 0 ? longest > 0.1 * noise * diag : longest < 1e-12 * diag, "noise %g: longest detail %.3g", noise, longest);
        st_analysis_report rep;
        st_hier_analyze_ex(&h[1], 0, 0, &rep);
        for (unsigned l = 1; l <= 2; l++)
            CHECKF(rep.streamed[l] == (noise == 0), "noise %g: level %u %s (row residual %.3g of the scale)", noise, l,
                   rep.streamed[l] ? "streamed" : "solved", rep.row_residual[l]);
        if (noise == 0) {
            CHECKF(hier_differences(&h[0], &h[1]) == 0, "exact: analysing again by the streamed pass changed %llu values",
                   (unsigned long long)hier_differences(&h[0], &h[1]));
            st_hier_analyze_ex(&h[2], 0, 1, &rep);
            CHECK(!rep.streamed[1] && !rep.streamed[2]);
            CHECKF(hier_differences(&h[0], &h[2]) == 0, "exact: the stored rows and the solve changed %llu values",
                   (unsigned long long)hier_differences(&h[0], &h[2]));
        }
    }
    for (unsigned t = 0; t < 3; t++) {
        free(fine_of[t]);
        if (built || fine_of[t]) st_hier_free(&h[t]);
    }
    st_unsub_free(&u);
    st_mesh_free(&in);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
}

/* The manifold check that stands in for st_mesh_check on coarse meshes
 * agrees with it on a few cases. */
static void check_manifold(void)
{
    static const double pos[7 * 3] = { 0 };
    static const uint32_t off[4] = { 0, 3, 6, 9 };
    /* Two triangles meeting at vertex 0 only (a bow-tie), then a fan. */
    static const uint32_t bowtie[6] = { 0, 1, 2, 0, 3, 4 }, fan[9] = { 0, 1, 2, 0, 2, 3, 0, 3, 4 };
    static const uint32_t twice[6] = { 0, 1, 2, 0, 1, 3 };   /* half-edge 0->1 twice */
    const uint32_t *idx[3] = { bowtie, fan, twice };
    uint32_t nf[3] = { 2, 3, 2 }, nv[3] = { 5, 5, 4 };
    int want[3] = { -1, 0, -1 };
    for (int i = 0; i < 3; i++) {
        st_mesh m;
        tl_mesh_make(&m, pos, nv[i], off, idx[i], nf[i]);
        st_unsub_topo t;
        st_error err;
        uint32_t where = ST_NIL;
        CHECK(st_unsub_topo_build(&t, &m) == 0);
        CHECKF(st_unsub_topo_manifold(&t, &where) == want[i], "case %d", i);
        CHECK((st_mesh_check("m", &m, &err) == 0) == (want[i] == 0));
        if (want[i]) CHECKF(where == 0 || where == 1, "case %d: vertex %u", i, where);
        st_unsub_topo_free(&t);
        st_mesh_free(&m);
    }
    st_mesh cube;
    tl_mesh_cube(&cube);
    st_unsub_topo t;
    uint32_t where;
    CHECK(st_unsub_topo_build(&t, &cube) == 0 && st_unsub_topo_manifold(&t, &where) == 0);
    st_unsub_topo_free(&t);
    st_mesh_free(&cube);
}

/* Sculpting a rebuilt hierarchy: a move at level 1 re-synthesises the
 * levels above locally (far vertices keep the input's bits), and moving it
 * back gives the input again up to rounding. */
static void check_edit(void)
{
    st_mesh cage, fine;
    st_error err;
    st_unsub u;
    st_hier h;
    uint32_t *fine_of = NULL;
    CHECK(load("catmull_clark/blub_control_mesh.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_CATMARK, 3, &fine) == 0);
    CHECK(st_unsubdivide("b", &fine, NULL, &u, &err) == 0);
    CHECK(st_unsub_build_hier(&fine, &u, st_scheme_find("catmull-clark"), NULL, &h, &fine_of, NULL, &err) == 0);
    double diag = st_mesh_diagonal(&fine);
    st_dart_iter it;
    uint32_t d = st_dart_first(&h.map, 1, &it);
    while (st_is_boundary(&h.map, d)) d = st_dart_next(&h.map, 1, &it);
    uint32_t v = st_vert(&h.map, d, 1);
    double old[1][3], moved[1][3];
    memcpy(old[0], st_pos(&h.map, v, 1), sizeof old[0]);
    memcpy(moved[0], old[0], sizeof moved[0]);
    moved[0][2] += 0.05 * diag;
    uint64_t n = st_hier_move(&h, 1, &d, (const double (*)[3])moved, 1);
    uint32_t same = 0, total = 0;
    for (uint32_t x = st_vertex_first(&h.map, 3, &it); x != ST_NIL; x = st_vertex_next(&h.map, 3, &it), total++)
        same += memcmp(st_pos(&h.map, x, 3), fine.pos + 3 * (size_t)fine_of[x], 3 * sizeof(double)) == 0;
    CHECKF(n > 0 && same > total / 2 && same < total, "move: %llu recomputed, %u of %u finest vertices unchanged", (unsigned long long)n, same, total);
    CHECK(st_map_validate(&h.map, &err) == 0);
    st_hier_move(&h, 1, &d, (const double (*)[3])old, 1);
    double worst = 0;
    for (uint32_t x = st_vertex_first(&h.map, 3, &it); x != ST_NIL; x = st_vertex_next(&h.map, 3, &it))
        for (int k = 0; k < 3; k++) {
            double e = fabs(st_pos(&h.map, x, 3)[k] - fine.pos[3 * (size_t)fine_of[x] + k]);
            if (e > worst) worst = e;
        }
    CHECKF(worst <= 1e-12 * diag, "moved back: off by %.3g", worst);
    free(fine_of);
    st_hier_free(&h);
    st_unsub_free(&u);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
}

/* ---- tags and UVs ------------------------------------------------------------ */

/* The vertex of m nearest to p (the cages here have distinct positions). */
static uint32_t nearest(const st_map *m, unsigned l, const double *p)
{
    uint32_t best = ST_NIL;
    double bd = INFINITY;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
        const double *q = st_pos(m, v, l);
        double d = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
        if (d < bd) { bd = d; best = v; }
    }
    return best;
}

/* The dart of level l from the vertex a to b, or ST_NIL. */
static uint32_t dart_between(const st_map *m, unsigned l, uint32_t a, uint32_t b)
{
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it))
        if (!st_is_boundary(m, d) && st_vert(m, d, l) == a && st_vert(m, st_phi1(m, d, l), l) == b) return d;
    return ST_NIL;
}

/* Level l of h as a soup with its edge and vertex sharpness as OBJ tags
 * (what a file written from it with its tags holds). */
static void tagged_level(st_hier *h, unsigned l, st_mesh *out)
{
    st_error err;
    st_mesh_init(out);
    CHECK(st_hier_level_mesh(h, l, out, &err) == 0);
    st_map *m = &h->map;
    uint32_t *index = malloc(((size_t)m->verts.end + 1) * sizeof *index), n = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) index[v] = n++;
    size_t nd = (size_t)m->darts.end + 1;
    out->crease_v = malloc(2 * nd * sizeof *out->crease_v);
    out->crease_s = malloc(nd * sizeof *out->crease_s);
    out->corner_v = malloc(((size_t)n + 1) * sizeof *out->corner_v);
    out->corner_s = malloc(((size_t)n + 1) * sizeof *out->corner_s);
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t e = st_beta0(m, d, l);
        float sh = st_hier_edge_sharpness(h, d, l);
        if (st_is_boundary(m, d) || (!st_is_boundary(m, e) && e < d) || sh <= 0) continue;
        out->crease_v[2 * out->ncreases] = index[st_vert(m, d, l)];
        out->crease_v[2 * out->ncreases + 1] = index[st_vert(m, st_phi1(m, d, l), l)];
        out->crease_s[out->ncreases++] = sh;
    }
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        if (st_hier_vertex_sharpness(h, v, l) > 0) {
            out->corner_v[out->ncorners] = index[v];
            out->corner_s[out->ncorners++] = st_hier_vertex_sharpness(h, v, l);
        }
    free(index);
    CHECK(st_mesh_check("tagged", out, &err) == 0);
}

/* A tagged cage (semi-sharp creases, an infinitely sharp one, a corner, a
 * hole, UVs with a seam at every edge) refined k times with linear UVs is
 * unsubdivided: the cage's positions (1e-9 of the diagonal), every edge's
 * and vertex's sharpness (to float rounding), its holes and its corner UVs
 * come back; the finest level's sharpness is the input's exactly and its
 * UVs are the input's (residual 0). */
static void check_tags(const char *rel, st_scheme_id id, unsigned k)
{
    st_mesh cage;
    if (load(rel, &cage)) { CHECKF(0, "cannot load %s", rel); return; }
    /* Tags: creases of sharpness 2.5, k + 0.7 and infinite on the first
     * edges of face 0 and 1, a corner on the last vertex, face 2 a hole. */
    uint32_t *f0 = cage.face_idx + cage.face_off[0], *f1 = cage.face_idx + cage.face_off[1];
    cage.ncreases = 3;
    cage.crease_v = malloc(6 * sizeof *cage.crease_v);
    cage.crease_s = malloc(3 * sizeof *cage.crease_s);
    uint32_t cv[6] = { f0[0], f0[1], f0[1], f0[2], f1[0], f1[1] };
    memcpy(cage.crease_v, cv, sizeof cv);
    cage.crease_s[0] = (float)k + 0.5f;
    cage.crease_s[1] = (float)k + 0.7f;
    cage.crease_s[2] = 10.0f;
    cage.ncorners = 1;
    cage.corner_v = malloc(sizeof *cage.corner_v);
    cage.corner_s = malloc(sizeof *cage.corner_s);
    cage.corner_v[0] = cage.nverts - 1;
    cage.corner_s[0] = (float)k + 1.25f;
    cage.face_hole = calloc(cage.nfaces, 1);
    cage.face_hole[2] = 1;
    uint32_t nc = cage.face_off[cage.nfaces];
    free(cage.uv); free(cage.face_uv);
    cage.nuvs = nc;
    cage.uv = malloc(2 * (size_t)nc * sizeof *cage.uv);
    cage.face_uv = malloc((size_t)nc * sizeof *cage.face_uv);
    for (uint32_t c = 0; c < nc; c++) {
        cage.face_uv[c] = c;
        cage.uv[2 * c] = 0.01 * c + 0.003 * (c % 7);
        cage.uv[2 * c + 1] = 1.0 - 0.02 * c;
    }
    st_error err;
    CHECK(st_mesh_check("cage", &cage, &err) == 0);
    const st_scheme *sc = st_scheme_find(id == ST_SCHEME_CATMARK ? "catmull-clark" : "loop");
    st_hier_opts ho = { .boundary = ST_BOUNDARY_UNSET, .uv_interp = ST_UV_ALL };
    st_hier h0, h1;
    CHECK(st_hier_init(&h0, &cage, sc, &ho, &err) == 0);
    CHECK(st_hier_subdivide_to(&h0, k, &err) == 0);
    st_mesh fine;
    tagged_level(&h0, k, &fine);
    st_unsub u;
    st_unsub_opts o = { .max_levels = k };
    int rc = st_unsubdivide(rel, &fine, &o, &u, &err);
    CHECKF(rc == 0 && u.levels == k, "%s x%u tagged: %s", rel, k, rc ? err.msg : "levels");
    uint32_t *fine_of = NULL;
    if (!rc) rc = st_unsub_build_hier(&fine, &u, sc, &ho, &h1, &fine_of, NULL, &err);
    CHECKF(rc == 0, "%s x%u tagged: %s", rel, k, rc ? err.msg : "");
    if (!rc) {
        double diag = st_mesh_diagonal(&cage);
        const st_map *a = &h0.map, *b = &h1.map;
        st_dart_iter it;
        double worst = 0, uvw = 0;
        float sworst = 0;
        uint32_t missing = 0, holes = 0, sharp = 0;
        /* Level 0: every dart of the rebuilt cage against the original's. */
        for (uint32_t d = st_dart_first(b, 0, &it); d != ST_NIL; d = st_dart_next(b, 0, &it)) {
            if (st_is_boundary(b, d)) continue;
            const double *p = st_pos(b, st_vert(b, d, 0), 0), *q = st_pos(b, st_vert(b, st_phi1(b, d, 0), 0), 0);
            uint32_t va = nearest(a, 0, p), vb = nearest(a, 0, q), e = dart_between(a, 0, va, vb);
            if (e == ST_NIL) { missing++; continue; }
            for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(p[c] - st_pos(a, va, 0)[c]));
            sworst = fmaxf(sworst, fabsf(st_hier_edge_sharpness(&h1, d, 0) - st_hier_edge_sharpness(&h0, e, 0)));
            sworst = fmaxf(sworst, fabsf(st_hier_vertex_sharpness(&h1, st_vert(b, d, 0), 0) - st_hier_vertex_sharpness(&h0, va, 0)));
            sharp += st_hier_edge_sharpness(&h1, d, 0) > 0;
            holes += st_is_hole(b, d) != st_is_hole(a, e);
            st_uv_map ma = st_hier_uv(&h0, 0), mb = st_hier_uv(&h1, 0);
            const double *ua = st_uv_map_at(&ma, e), *ub = st_uv_map_at(&mb, d);
            uvw = fmax(uvw, fmax(fabs(ua[0] - ub[0]), fabs(ua[1] - ub[1])));
        }
        CHECKF(!missing && worst <= 1e-9 * diag, "%s x%u tagged: cage off by %.3g, %u edges missing", rel, k, worst, missing);
        CHECKF(sworst <= 1e-5f && sharp == 6, "%s x%u tagged: cage sharpness off by %g, %u sharp darts (6 expected)", rel, k, (double)sworst, sharp);
        CHECKF(!holes, "%s x%u tagged: %u darts with another hole flag", rel, k, holes);
        CHECKF(uvw == 0, "%s x%u tagged: cage UVs off by %.3g", rel, k, uvw);
        /* Finest level: the input, sharpness and UVs included. */
        st_mesh top;
        tagged_level(&h1, k, &top);
        CHECKF(same_faces(&top, &fine) && top.ncreases == fine.ncreases && top.ncorners == fine.ncorners &&
               st_mesh_hole_faces(&top) == st_mesh_hole_faces(&fine) && st_mesh_hole_faces(&fine) > 0,
               "%s x%u tagged: finest level: %u creases %u corners %u holes, the input %u %u %u", rel, k,
               top.ncreases, top.ncorners, st_mesh_hole_faces(&top), fine.ncreases, fine.ncorners, st_mesh_hole_faces(&fine));
        uint32_t off = 0;
        for (uint32_t d = st_dart_first(b, k, &it); d != ST_NIL; d = st_dart_next(b, k, &it)) {
            if (st_is_boundary(b, d)) continue;
            const double *p = st_pos(b, st_vert(b, d, k), k), *q = st_pos(b, st_vert(b, st_phi1(b, d, k), k), k);
            uint32_t e = dart_between(a, k, nearest(a, k, p), nearest(a, k, q));
            off += e == ST_NIL || st_hier_edge_sharpness(&h1, d, k) != st_hier_edge_sharpness(&h0, e, k) ||
                   st_hier_vertex_sharpness(&h1, st_vert(b, d, k), k) != st_hier_vertex_sharpness(&h0, st_vert(a, e, k), k);
        }
        CHECKF(!off, "%s x%u tagged: %u finest darts whose sharpness is not the input's", rel, k, off);
        double r = st_unsub_uv_residual(&h1, &fine, fine_of);
        /* To rounding: a face point's UV sums its corners from another
         * starting corner than in h0. */
        CHECKF(r <= 1e-12, "%s x%u tagged: finest UVs off by %.3g under linear interpolation", rel, k, r);
        printf("%s x%u tagged: cage off by %.3g, sharpness %.3g, finest UV residual %.3g\n", rel, k, worst, (double)sworst, r);
        st_mesh_free(&top);
        free(fine_of);
        st_hier_free(&h1);
    }
    st_unsub_free(&u);
    /* Tags no coarser mesh gives are refused, naming what. */
    struct { const char *what; int kind; } bad[] = { { "crease:", 0 }, { "crease:", 1 }, { "corner:", 2 }, { "hole:", 3 } };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        st_mesh m;
        tagged_level(&h0, k, &m);
        if (bad[i].kind == 0) {                                 /* one half of a semi-sharp coarse edge changed */
            uint32_t c = 0;
            while (m.crease_s[c] >= 10.0f) c++;
            m.crease_s[c] += 0.25f;
        }
        if (bad[i].kind == 1) {                                 /* a sharp edge from a coarse vertex's ... */
            uint32_t f = 0;                                     /* ... face's middle: corners 1 and 2 of a fine face */
            while (f < m.nfaces && m.face_hole[f]) f++;
            uint32_t *fv = m.face_idx + m.face_off[f];
            m.crease_v[0] = fv[1]; m.crease_v[1] = fv[2];
            m.crease_v[2] = fv[2]; m.crease_v[3] = fv[id == ST_SCHEME_CATMARK ? 3 : 0];
        }
        if (bad[i].kind == 2) m.corner_v[0] = m.nverts - 1;    /* the last vertex, new at the finest level */
        if (bad[i].kind == 3) {                                 /* one child of the hole face made solid */
            uint32_t f = 0;
            while (!m.face_hole[f]) f++;
            m.face_hole[f] = 0;
        }
        st_unsub_opts one = { .max_levels = 1 };
        rc = st_unsubdivide("bad.obj", &m, &one, &u, &err);
        CHECKF(rc != 0 && strstr(err.msg, bad[i].what), "%s x%u bad %s (%d): %s", rel, k, bad[i].what, bad[i].kind,
               rc ? err.msg : "accepted");
        if (rc) printf("refused: %s\n", err.msg);
        else st_unsub_free(&u);
        st_mesh_free(&m);
    }
    st_mesh_free(&fine);
    st_hier_free(&h0);
    st_mesh_free(&cage);
}

/* ---- vertex order: st_rebuild works on the input renumbered by first use --------------------- */

/* The faces' vertices numbered in order of first use (what st_rebuild
 * does to an input whose order is not coherent); tags follow, UVs are per
 * corner and stay. */
static void first_use_order(const st_mesh *in, st_mesh *out, uint32_t *new_of)
{
    uint32_t nv = in->nverts, nc = in->face_off[in->nfaces], n = 0;
    for (uint32_t v = 0; v < nv; v++) new_of[v] = ST_NIL;
    for (uint32_t c = 0; c < nc; c++)
        if (new_of[in->face_idx[c]] == ST_NIL) new_of[in->face_idx[c]] = n++;
    CHECK(n == nv);
    st_mesh_init(out);
    *out = *in;
    out->pos = malloc(3 * (size_t)nv * sizeof *out->pos);
    out->face_off = malloc(((size_t)in->nfaces + 1) * sizeof *out->face_off);
    out->face_idx = malloc((size_t)nc * sizeof *out->face_idx);
    out->normals = NULL;
    memcpy(out->face_off, in->face_off, ((size_t)in->nfaces + 1) * sizeof *out->face_off);
    for (uint32_t v = 0; v < nv; v++) memcpy(out->pos + 3 * (size_t)new_of[v], in->pos + 3 * (size_t)v, 3 * sizeof(double));
    for (uint32_t c = 0; c < nc; c++) out->face_idx[c] = new_of[in->face_idx[c]];
    out->crease_v = malloc((2 * (size_t)in->ncreases + 1) * sizeof *out->crease_v);
    out->crease_s = malloc(((size_t)in->ncreases + 1) * sizeof *out->crease_s);
    for (uint32_t i = 0; i < 2 * in->ncreases; i++) out->crease_v[i] = new_of[in->crease_v[i]];
    if (in->ncreases) memcpy(out->crease_s, in->crease_s, in->ncreases * sizeof *out->crease_s);
    out->corner_v = malloc(((size_t)in->ncorners + 1) * sizeof *out->corner_v);
    out->corner_s = malloc(((size_t)in->ncorners + 1) * sizeof *out->corner_s);
    for (uint32_t i = 0; i < in->ncorners; i++) out->corner_v[i] = new_of[in->corner_v[i]];
    if (in->ncorners) memcpy(out->corner_s, in->corner_s, in->ncorners * sizeof *out->corner_s);
    out->face_hole = NULL;
    if (in->face_hole) {
        out->face_hole = malloc(in->nfaces);
        memcpy(out->face_hole, in->face_hole, in->nfaces);
    }
    out->uv = NULL;
    out->face_uv = NULL;
    if (in->face_uv) {
        out->uv = malloc(2 * (size_t)in->nuvs * sizeof *out->uv);
        out->face_uv = malloc((size_t)nc * sizeof *out->face_uv);
        memcpy(out->uv, in->uv, 2 * (size_t)in->nuvs * sizeof *out->uv);
        memcpy(out->face_uv, in->face_uv, (size_t)nc * sizeof *out->face_uv);
    }
}

/* The same mesh with its vertices shuffled: faces, their starting corners,
 * UVs and holes as they were; tags follow their vertices. */
static void shuffle_vertices_only(const st_mesh *in, st_mesh *out, uint64_t seed)
{
    uint32_t nv = in->nverts, *perm = malloc(((size_t)nv + 1) * sizeof *perm), *scratch = malloc(((size_t)nv + 1) * sizeof *perm);
    uint64_t rng = seed;
    for (uint32_t i = 0; i < nv; i++) perm[i] = i;
    for (uint32_t i = nv; i > 1; i--) { uint32_t j = tl_rand(&rng) % i, t = perm[i - 1]; perm[i - 1] = perm[j]; perm[j] = t; }
    /* first_use_order with new_of = perm: same copy, another numbering. */
    st_mesh tmp;
    first_use_order(in, &tmp, scratch);
    for (uint32_t v = 0; v < nv; v++) memcpy(tmp.pos + 3 * (size_t)perm[v], in->pos + 3 * (size_t)v, 3 * sizeof(double));
    for (uint32_t c = 0; c < in->face_off[in->nfaces]; c++) tmp.face_idx[c] = perm[in->face_idx[c]];
    for (uint32_t i = 0; i < 2 * in->ncreases; i++) tmp.crease_v[i] = perm[in->crease_v[i]];
    for (uint32_t i = 0; i < in->ncorners; i++) tmp.corner_v[i] = perm[in->corner_v[i]];
    *out = tmp;
    free(perm);
    free(scratch);
}

static int same_array(const void *a, const void *b, size_t n) { return n == 0 || (a && b && !memcmp(a, b, n)); }

/* Level l of both hierarchies as rebuild inputs (faces, positions, UVs,
 * tags): the same arrays. */
static void check_same_level(st_hier *a, st_hier *b, unsigned l, const char *what)
{
    st_mesh x, y;
    st_error err;
    CHECK(st_rebuild_level_input(a, l, &x, &err) == 0);
    CHECK(st_rebuild_level_input(b, l, &y, &err) == 0);
    uint32_t nc = x.nfaces ? x.face_off[x.nfaces] : 0;
    int same = x.nverts == y.nverts && x.nfaces == y.nfaces && x.nuvs == y.nuvs && x.ncreases == y.ncreases &&
               x.ncorners == y.ncorners && same_array(x.pos, y.pos, 3 * (size_t)x.nverts * sizeof(double)) &&
               same_array(x.face_off, y.face_off, ((size_t)x.nfaces + 1) * 4) && same_array(x.face_idx, y.face_idx, (size_t)nc * 4) &&
               same_array(x.uv, y.uv, 2 * (size_t)x.nuvs * sizeof(double)) && same_array(x.face_uv, y.face_uv, (size_t)nc * 4) &&
               same_array(x.crease_v, y.crease_v, 8 * (size_t)x.ncreases) && same_array(x.crease_s, y.crease_s, 4 * (size_t)x.ncreases) &&
               same_array(x.corner_v, y.corner_v, 4 * (size_t)x.ncorners) && same_array(x.corner_s, y.corner_s, 4 * (size_t)x.ncorners);
    CHECKF(same, "%s, level %u: %u/%u vertices, %u/%u faces, %u/%u creases, %u/%u corners; the arrays differ", what, l,
           x.nverts, y.nverts, x.nfaces, y.nfaces, x.ncreases, y.ncreases, x.ncorners, y.ncorners);
    st_mesh_free(&x);
    st_mesh_free(&y);
}

/* st_rebuild renumbers an input whose vertex order is not coherent by
 * first use in face order, so a shuffled input gives the levels of the
 * same input in that order, bit for bit (positions, faces, UVs, tags; a
 * least-squares cage summed in another order would differ in the last
 * bits), and its finest level is the input.  Its refusals still name the
 * input's own vertices: the message of the shuffled input is the one
 * st_unsubdivide gives on it, not the one of the renumbered copy. */
static void check_order(void)
{
    st_mesh cage, fine;
    st_error err;
    CHECK(load("catmull_clark/blub_control_mesh.obj", &cage) == 0);
    /* Tags on the cage (creases, a corner, a hole) so that the copy's tags
     * are exercised: the levels' sharpness must come back. */
    uint32_t *f0 = cage.face_idx + cage.face_off[0];
    cage.ncreases = 1;
    cage.crease_v = malloc(2 * sizeof *cage.crease_v);
    cage.crease_s = malloc(sizeof *cage.crease_s);
    cage.crease_v[0] = f0[0];
    cage.crease_v[1] = f0[1];
    cage.crease_s[0] = 3.5f;
    cage.ncorners = 1;
    cage.corner_v = malloc(sizeof *cage.corner_v);
    cage.corner_s = malloc(sizeof *cage.corner_s);
    cage.corner_v[0] = cage.nverts - 1;
    cage.corner_s[0] = 4.25f;
    cage.face_hole = calloc(cage.nfaces, 1);
    cage.face_hole[5] = 1;
    CHECK(st_mesh_check("cage", &cage, &err) == 0);
    st_hier_opts ho = { .boundary = ST_BOUNDARY_UNSET, .uv_interp = ST_UV_ALL };
    st_hier h0;
    CHECK(st_hier_init(&h0, &cage, st_scheme_find("catmull-clark"), &ho, &err) == 0);
    CHECK(st_hier_subdivide_to(&h0, 3, &err) == 0);
    tagged_level(&h0, 3, &fine);
    st_hier_free(&h0);
    CHECK(fine.nverts > 4096 && fine.face_uv && fine.ncreases && fine.ncorners);
    uint32_t *new_of = malloc(fine.nverts * sizeof *new_of);
    st_mesh ordered, shuffled;
    first_use_order(&fine, &ordered, new_of);
    shuffle_vertices_only(&ordered, &shuffled, 99);
    st_rebuild_opts o = { .method = ST_REBUILD_UNSUBDIVIDE, .uv_interp = ST_UV_ALL };
    st_hier ha, hb;
    st_rebuild_report ra, rb;
    int rc_a = st_rebuild("ordered.obj", &ordered, &o, &ha, &ra, &err);
    CHECKF(rc_a == 0, "ordered: %s", rc_a ? err.msg : "");
    int rc_b = st_rebuild("shuffled.obj", &shuffled, &o, &hb, &rb, &err);
    CHECKF(rc_b == 0, "shuffled: %s", rc_b ? err.msg : "");
    if (!rc_a && !rc_b) {
        CHECKF(ha.map.top == 3 && hb.map.top == 3, "levels %u and %u", ha.map.top, hb.map.top);
        CHECKF(!strcmp(ra.summary, rb.summary) && !strcmp(ra.stop, rb.stop), "reports differ:\n%s\n%s", ra.summary, rb.summary);
        for (unsigned l = 0; l <= ha.map.top && ha.map.top == hb.map.top; l++) check_same_level(&ha, &hb, l, "ordered vs shuffled");
        /* The finest level is the shuffled input itself, up to vertex order. */
        st_mesh top;
        CHECK(st_hier_level_mesh(&hb, hb.map.top, &top, &err) == 0);
        CHECKF(same_faces(&top, &shuffled), "the finest level is not the shuffled input");
        st_mesh_free(&top);
        st_hier_free(&ha);
        st_hier_free(&hb);
    }
    st_rebuild_report_free(&ra);
    st_rebuild_report_free(&rb);
    st_mesh_free(&ordered);
    st_mesh_free(&shuffled);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
    free(new_of);

    /* A refusal: one edge of a Loop level flipped, vertices shuffled. */
    CHECK(load("triangle/sphere_ico.obj", &cage) == 0);
    CHECK(subdivided(&cage, ST_SCHEME_LOOP, 2, &fine) == 0);
    CHECK(flip_edge(&fine, 1000, NULL) != ST_NIL);
    CHECK(fine.nverts > 2048 && st_mesh_check("flip", &fine, &err) == 0);
    shuffle_vertices_only(&fine, &shuffled, 7);
    new_of = malloc(fine.nverts * sizeof *new_of);
    first_use_order(&shuffled, &ordered, new_of);
    st_unsub u;
    char direct[sizeof err.msg], copy[sizeof err.msg];
    CHECK(st_unsubdivide("flip.obj", &shuffled, NULL, &u, &err) == ST_ERR_TOPOLOGY);
    snprintf(direct, sizeof direct, "%s", err.msg);
    CHECK(st_unsubdivide("flip.obj", &ordered, NULL, &u, &err) == ST_ERR_TOPOLOGY);
    snprintf(copy, sizeof copy, "%s", err.msg);
    /* Otherwise the check below would not tell the numberings apart. */
    CHECKF(strcmp(direct, copy), "the renumbered copy's refusal names the same place: %s", copy);
    st_hier h;
    st_rebuild_report r;
    int rc = st_rebuild("flip.obj", &shuffled, &o, &h, &r, &err);
    CHECKF(rc == ST_ERR_TOPOLOGY && !strcmp(err.msg, direct), "rebuild refusal: %s\nexpected: %s", rc ? err.msg : "accepted", direct);
    st_rebuild_report_free(&r);
    st_rebuild_opts oa = { .method = ST_REBUILD_AUTO };
    rc = st_rebuild("flip.obj", &shuffled, &oa, &h, &r, &err);
    CHECKF(rc == 0 && r.method == ST_REBUILD_PROGRESSIVE && !strcmp(r.refusal, direct), "auto: %s; refusal %s",
           rc ? err.msg : "built", r.refusal);
    if (!rc) st_hier_free(&h);
    st_rebuild_report_free(&r);
    fprintf(stderr, "shuffled flip refused: %s\n", direct);
    free(new_of);
    st_mesh_free(&ordered);
    st_mesh_free(&shuffled);
    st_mesh_free(&fine);
    st_mesh_free(&cage);
}

int main(void)
{
    static const struct { const char *mesh; st_scheme_id id; unsigned max; } cases[] = {
        { "catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, 3 },   /* triangles and quads */
        { "catmull_clark/dodecahedron_poly.obj", ST_SCHEME_CATMARK, 4 },   /* pentagons, valence 3 */
        { "catmull_clark/spot_quadrangulated.obj", ST_SCHEME_CATMARK, 2 },
        { "catmull_clark/newell_teapot_cage.obj", ST_SCHEME_CATMARK, 2 }, /* open, several pieces */
        { "edge_cases/grid_holes.obj", ST_SCHEME_CATMARK, 2 },             /* holes */
        { "cube.obj", ST_SCHEME_CATMARK, 3 },                              /* assets: valence 3 quads */
        { "torus.obj", ST_SCHEME_CATMARK, 2 },                             /* assets: regular grid */
        { "triangle/sphere_ico.obj", ST_SCHEME_CATMARK, 2 },               /* triangle cage under the polygon split */
        { "triangle/sphere_ico.obj", ST_SCHEME_LOOP, 3 },
        { "triangle/hemisphere.obj", ST_SCHEME_LOOP, 3 },                  /* open */
        { "triangle/cube_no_bottom.obj", ST_SCHEME_LOOP, 4 },              /* open */
        { "triangle/sphere_ico.obj", ST_SCHEME_BUTTERFLY, 2 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        for (unsigned l = 1; l <= cases[i].max; l++) {
            check_recovery(cases[i].mesh, cases[i].id, l, 0);
            check_recovery(cases[i].mesh, cases[i].id, l, 1000 + 17 * i + l);
        }
    /* Large components take the probe-then-label-in-place path: both
     * starting corners of the seed face (coarse vertex or face point). */
    check_recovery("catmull_clark/spot_quadrangulated.obj", ST_SCHEME_CATMARK, 3, ROTATE_ONLY | 1); /* 187k faces: sampled score */
    check_recovery("catmull_clark/spot_quadrangulated.obj", ST_SCHEME_CATMARK, 3, 5);
    check_recovery("triangle/sphere_ico.obj", ST_SCHEME_CATMARK, 3, ROTATE_ONLY | 1);
    check_recovery("triangle/sphere_ico.obj", ST_SCHEME_CATMARK, 3, 77);
    check_tags("cube.obj", ST_SCHEME_CATMARK, 1);
    check_tags("cube.obj", ST_SCHEME_CATMARK, 3);
    check_tags("catmull_clark/dodecahedron_poly.obj", ST_SCHEME_CATMARK, 2);
    check_tags("triangle/sphere_ico.obj", ST_SCHEME_LOOP, 2);
    check_edit();
    check_manifold();
    check_refusals();
    check_limits();
    check_session();
    check_threads();
    check_streamed(0);
    check_streamed(1e-4);
    check_order();
    return TEST_END();
}
