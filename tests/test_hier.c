/* Multiresolution geometry: synthesis, details in local frames, local
 * re-synthesis after edits, for every registered scheme that applies. */
#include "hier.h"
#include "hier_internal.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void init_hier(st_hier *h, void (*make)(st_mesh *), st_scheme_id id, unsigned levels)
{
    st_mesh s;
    st_error err;
    make(&s);
    const st_scheme *sc = st_scheme_get(id);
    CHECK(sc != NULL);
    int rc = st_hier_init(h, &s, sc, NULL, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    st_mesh_free(&s);
    rc = st_hier_subdivide_to(h, levels, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    rc = st_map_validate(&h->map, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
}

/* Positions of every vertex at every level, indexed [level][vertex id]. */
typedef struct posnap { unsigned levels; uint32_t n; double *p; } posnap;

static void snap_pos(const st_hier *h, posnap *s)
{
    s->levels = h->map.top + 1;
    s->n = h->map.verts.end;
    s->p = calloc((size_t)s->levels * s->n * 3 + 1, sizeof *s->p);
    for (unsigned l = 0; l < s->levels; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
            memcpy(s->p + ((size_t)l * s->n + v) * 3, st_pos(&h->map, v, l), 3 * sizeof(double));
    }
}

static double snap_maxdiff(const posnap *a, const posnap *b)
{
    double m = 0;
    for (size_t i = 0; i < (size_t)a->levels * a->n * 3; i++) m = fmax(m, fabs(a->p[i] - b->p[i]));
    return m;
}

static void cube_scaled(st_mesh *s) { tl_mesh_cube(s); }
static void torus(st_mesh *s) { tl_mesh_torus(s, 10, 6); }
static void grid(st_mesh *s) { tl_mesh_grid(s, 5); }

/* Catmull-Clark on the unit cube: the corner (0,0,0) goes to (2/9,2/9,2/9)
 * (F = (1/3)³, R = (1/6)³, n = 3), a face centre stays, an edge point of
 * the edge (0,0,0)-(1,0,0) is (1/2, 1/8, 1/8). */
static void test_catmark_cube_values(void)
{
    st_hier h;
    init_hier(&h, cube_scaled, ST_SCHEME_CATMARK, 1);
    const double *c = st_pos(&h.map, 0, 1);
    CHECKF(fabs(c[0] - 2.0 / 9) < 1e-15 && fabs(c[1] - 2.0 / 9) < 1e-15 && fabs(c[2] - 2.0 / 9) < 1e-15,
           "(%g %g %g)", c[0], c[1], c[2]);
    int found_edge = 0, found_face = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, 1, &it); v != ST_NIL; v = st_vertex_next(&h.map, 1, &it)) {
        const double *p = st_pos(&h.map, v, 1);
        if (fabs(p[0] - 0.5) < 1e-15 && fabs(p[1] - 0.125) < 1e-15 && fabs(p[2] - 0.125) < 1e-15) found_edge++;
        if (fabs(p[0] - 0.5) < 1e-15 && fabs(p[1] - 0.5) < 1e-15 && fabs(p[2]) < 1e-15) found_face++;
    }
    CHECK(found_edge == 1 && found_face == 1);
    st_hier_free(&h);
}

/* Random details at every level >= 1, then a full synthesis. */
static void random_details(st_hier *h, uint64_t *rng, double scale)
{
    for (unsigned l = 1; l <= h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            double d[3];
            for (int i = 0; i < 3; i++) d[i] = scale * ((double)(tl_rand(rng) % 2001) / 1000.0 - 1.0);
            st_hier_set_detail(h, l, v, d);
        }
    }
    st_hier_synthesize(h, 0);
}

/* A dart of some vertex of level l, chosen at random. */
static uint32_t random_dart_at(const st_map *m, unsigned l, uint64_t *rng)
{
    for (;;) {
        uint32_t d = tl_rand(rng) % m->darts.end;
        if (st_dart_in_level(m, d, l)) return d;
    }
}

/* Local re-synthesis after moving vertices at level l equals a full
 * synthesis from level l, and recomputes far fewer vertices. */
static void check_local_equals_full(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    st_hier h;
    uint64_t rng = 12345 + id;
    init_hier(&h, make, id, levels);
    random_details(&h, &rng, 0.01);
    for (unsigned l = 0; l < levels; l++) {
        uint32_t darts[3];
        double pos[3][3];
        for (int k = 0; k < 3; k++) {
            darts[k] = random_dart_at(&h.map, l, &rng);
            const double *p = st_dart_pos(&h.map, darts[k], l);
            for (int i = 0; i < 3; i++) pos[k][i] = p[i] + 0.05 * (k + 1) * (i + 1);
        }
        /* Two darts of one vertex would be one vertex moved twice: keep distinct vertices. */
        uint32_t n = 1;
        for (int k = 1; k < 3; k++) {
            int dup = 0;
            for (uint32_t j = 0; j < n; j++) dup |= st_vert(&h.map, darts[j], l) == st_vert(&h.map, darts[k], l);
            if (!dup) { darts[n] = darts[k]; memcpy(pos[n], pos[k], sizeof pos[k]); n++; }
        }
        uint64_t count = st_hier_move(&h, l, darts, (const double (*)[3])pos, n);
        posnap local, full;
        snap_pos(&h, &local);
        st_hier_synthesize(&h, l);
        snap_pos(&h, &full);
        double diff = snap_maxdiff(&local, &full);
        CHECKF(diff < 1e-12, "%s: edit at level %u: local and full synthesis differ by %g", h.scheme->name, l, diff);
        for (int k = 0; k < (int)n; k++) {
            const double *p = st_dart_pos(&h.map, darts[k], l);
            CHECK(fabs(p[0] - pos[k][0]) < 1e-12 && fabs(p[2] - pos[k][2]) < 1e-12);
        }
        uint64_t total = 0;
        for (unsigned L = l + 1; L <= h.map.top; L++) {
            st_level_stats s;
            st_level_stats_compute(&h.map, L, &s);
            total += s.vertices;
        }
        if (l + 2 <= levels) CHECKF(count < total, "%s: local update recomputed %llu of %llu", h.scheme->name, (unsigned long long)count, (unsigned long long)total);
        free(local.p);
        free(full.p);
    }
    st_hier_free(&h);
}

/* A rigid motion of level 0 moves every finer level rigidly, details
 * included (they live in local frames of the coarser surface). */
static void check_rigid_motion(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    st_hier h;
    uint64_t rng = 777 + id;
    init_hier(&h, make, id, levels);
    random_details(&h, &rng, 0.02);
    posnap before;
    snap_pos(&h, &before);
    double c = cos(0.7), s = sin(0.7), t[3] = { 0.3, -1.2, 2.5 };
    st_dart_list darts = { 0 };
    int vb = st_marker_reserve(&h.map);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&h.map, 0, &it); d != ST_NIL; d = st_dart_next(&h.map, 0, &it))
        if (!st_marked(&h.map, vb, d)) { st_mark_vertex(&h.map, vb, d, 0); st_dart_list_push(&darts, d); }
    st_marker_release(&h.map, vb, 0);
    double (*pos)[3] = malloc(darts.n * sizeof *pos);
    for (uint32_t i = 0; i < darts.n; i++) {
        const double *p = st_dart_pos(&h.map, darts.d[i], 0);
        pos[i][0] = c * p[0] - s * p[1] + t[0];
        pos[i][1] = s * p[0] + c * p[1] + t[1];
        pos[i][2] = p[2] + t[2];
    }
    st_hier_move(&h, 0, darts.d, (const double (*)[3])pos, darts.n);
    double worst = 0;
    for (unsigned l = 0; l <= h.map.top; l++)
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            const double *p = before.p + ((size_t)l * before.n + v) * 3, *q = st_pos(&h.map, v, l);
            double r[3] = { c * p[0] - s * p[1] + t[0], s * p[0] + c * p[1] + t[1], p[2] + t[2] };
            for (int i = 0; i < 3; i++) worst = fmax(worst, fabs(r[i] - q[i]));
        }
    CHECKF(worst < 1e-12, "%s: rigid motion error %g", h.scheme->name, worst);
    free(pos);
    free(before.p);
    st_dart_list_free(&darts);
    st_hier_free(&h);
}

/* Moving a vertex at level i keeps the details of every finer level. */
static void check_details_kept(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    st_hier h;
    uint64_t rng = 99 + id;
    init_hier(&h, make, id, levels);
    random_details(&h, &rng, 0.01);
    double *saved = malloc((size_t)h.detail_cap[levels] * 3 * sizeof *saved);
    memcpy(saved, h.detail[levels], (size_t)h.detail_cap[levels] * 3 * sizeof *saved);
    uint32_t d = random_dart_at(&h.map, 1, &rng);
    double p[1][3];
    memcpy(p[0], st_dart_pos(&h.map, d, 1), sizeof p[0]);
    p[0][2] += 0.3;
    st_hier_move(&h, 1, &d, (const double (*)[3])p, 1);
    CHECK(memcmp(saved, h.detail[levels], (size_t)h.detail_cap[levels] * 3 * sizeof *saved) == 0);
    free(saved);
    st_hier_free(&h);
}

int main(void)
{
    test_catmark_cube_values();
    struct { st_scheme_id id; void (*make)(st_mesh *); unsigned levels; } cases[] = {
        { ST_SCHEME_CATMARK, torus, 4 },
        { ST_SCHEME_CATMARK, grid, 3 },
        { ST_SCHEME_CATMARK, cube_scaled, 4 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        check_local_equals_full(cases[i].id, cases[i].make, cases[i].levels);
        check_rigid_motion(cases[i].id, cases[i].make, cases[i].levels);
        check_details_kept(cases[i].id, cases[i].make, cases[i].levels);
    }
    return TEST_END();
}
