/* Multiresolution geometry: synthesis, details in local frames, local
 * re-synthesis after edits, for every registered scheme that applies. */
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/multires/edit.h"
#include "core/base/parallel.h"
#include "core/schemes/synth_tables_internal.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void cube_scaled(st_mesh *s) { tl_mesh_cube(s); }
static void torus(st_mesh *s) { tl_mesh_torus(s, 10, 6); }
static void grid(st_mesh *s) { tl_mesh_grid(s, 5); }

/* Catmull-Clark on the unit cube: the corner (0,0,0) goes to (2/9,2/9,2/9)
 * (F = (1/3)³, R = (1/6)³, n = 3), a face centre stays, an edge point of
 * the edge (0,0,0)-(1,0,0) is (1/2, 1/8, 1/8). */
static void test_catmark_cube_values(void)
{
    st_hier h;
    tl_init_hier(&h, cube_scaled, ST_SCHEME_CATMARK, 1);
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

/* Largest gap between the positions of levels 1..top and their stencils
 * evaluated on the level below. */
typedef struct gap_ctx { const st_hier *h; unsigned L; double worst; uint64_t n; } gap_ctx;

static void gap_sink(void *ctx, const st_stencil *s)
{
    gap_ctx *c = ctx;
    double p[3];
    st_stencil_eval(&c->h->map, c->L, s, p);
    const double *q = st_pos(&c->h->map, s->fine, c->L);
    for (int k = 0; k < 3; k++) c->worst = fmax(c->worst, fabs(p[k] - q[k]));
    c->n++;
}

static double stencil_gap(st_hier *h)
{
    gap_ctx c = { .h = h };
    for (c.L = 1; c.L <= h->map.top; c.L++) st_hier_emit(h, c.L, NULL, 0, gap_sink, &c);
    CHECK(c.n > 0);
    return c.worst;
}

static void icosa(st_mesh *s) { tl_mesh_icosa(s); }

/* A torus with a semi-sharp crease along one ring of edges and a corner:
 * the crease rules (special cells) inside local and full synthesis. */
static void torus_creased(st_mesh *s)
{
    tl_mesh_torus(s, 10, 6);
    s->ncreases = 10;
    s->crease_v = malloc(2 * 10 * sizeof *s->crease_v);
    s->crease_s = malloc(10 * sizeof *s->crease_s);
    for (uint32_t i = 0; i < 10; i++) {
        s->crease_v[2 * i] = i;
        s->crease_v[2 * i + 1] = (i + 1) % 10;
        s->crease_s[i] = 2.5f;
    }
    s->ncorners = 1;
    s->corner_v = malloc(sizeof *s->corner_v);
    s->corner_s = malloc(sizeof *s->corner_s);
    s->corner_v[0] = 23;
    s->corner_s[0] = 1.5f;
}
static void tetra(st_mesh *s) { tl_mesh_tetra(s); }

/* Catmull-Clark's and Loop's full syntheses read tables cached per level
 * (synth_tables.h) that must follow every change of topology or sharpness:
 * after each change the levels still equal their stencils, one thread and
 * two agree to the bit, and later syntheses repeat the first (the first
 * synthesis after a change walks the level and the second builds the
 * tables: st_synth_tables_defer; a third and a fourth read them). */
static void check_tables(st_scheme_id id, void (*make)(st_mesh *), size_t i)
{
    {
        st_hier h;
        st_error err;
        tl_init_hier(&h, make, id, 3);
        for (int step = 0; step < 4; step++) {
            if (step == 1) { /* a crease and a corner on level 0: other rules at level 1 */
                uint32_t d = st_dart_first(&h.map, 0, &(st_dart_iter){ 0 });
                st_hier_set_edge_sharpness(&h, d, 0, 1.5f);
                st_hier_set_vertex_sharpness(&h, st_vert(&h.map, st_beta0(&h.map, d, 0), 0), 0, 3.0f);
            }
            if (step == 2) st_hier_remove_bottom(&h);
            if (step == 3) {
                st_hier_remove_top(&h);
                CHECK(st_hier_subdivide_to(&h, h.map.top + 2, &err) == ST_OK);
            }
            st_parallel_set_threads(1);
            st_hier_synthesize(&h, 0);
            /* The first synthesis leaves marks, the second tables. */
            st_subdiv_view v = st_hier_view(&h);
            const st_synth_table *t = st_synth_tables_if_fresh(&v, 0, id);
            CHECKF(t && t->deferred, "mesh %zu, step %d: level 0 not marked", i, step);
            double gap = stencil_gap(&h);
            CHECKF(gap < 1e-13, "mesh %zu, step %d: levels and stencils differ by %g", i, step, gap);
            tl_posnap one, again, two, cached;
            tl_snap_pos(&h, &one);
            st_hier_synthesize(&h, 0);
            tl_snap_pos(&h, &again);
            t = st_synth_tables_if_fresh(&v, 0, id);
            CHECKF(t && !t->deferred, "mesh %zu, step %d: no tables after the second synthesis", i, step);
            st_parallel_set_threads(2);
            st_hier_synthesize(&h, 0);
            tl_snap_pos(&h, &two);
            st_parallel_set_threads(1);
            st_hier_synthesize(&h, 0);
            tl_snap_pos(&h, &cached);
            CHECKF(tl_snap_maxdiff(&one, &again) == 0 && tl_snap_maxdiff(&one, &two) == 0 && tl_snap_maxdiff(&one, &cached) == 0,
                   "mesh %zu, step %d", i, step);
            free(one.p);
            free(again.p);
            free(two.p);
            free(cached.p);
        }
        st_hier_free(&h);
    }
}

static void octa(st_mesh *s) { tl_mesh_octa(s); }

/* A cone: a 20-gon base and a valence-20 apex (faces and rings larger than
 * any fixed-size scratch). */
static void cone20(st_mesh *s)
{
    enum { N = 20 };
    double p[3 * (N + 1)];
    uint32_t off[N + 2], idx[N + 3 * N];
    for (unsigned i = 0; i < N; i++) {
        p[3 * i] = cos(2 * M_PI * i / N);
        p[3 * i + 1] = sin(2 * M_PI * i / N);
        p[3 * i + 2] = 0;
        idx[i] = N - 1 - i; /* base, facing down */
    }
    p[3 * N] = 0; p[3 * N + 1] = 0; p[3 * N + 2] = 1.5;
    off[0] = 0;
    off[1] = N;
    for (unsigned i = 0; i < N; i++) {
        idx[N + 3 * i] = i;
        idx[N + 3 * i + 1] = (i + 1) % N;
        idx[N + 3 * i + 2] = N;
        off[i + 2] = N + 3 * (i + 1);
    }
    tl_mesh_make(s, p, N + 1, off, idx, N + 1);
}

/* The icosahedron under Catmull-Clark with smooth triangles: every edge
 * takes the stencil path (st_catmark_tri_edge). */
static void icosa_smooth_tri(st_mesh *s)
{
    tl_mesh_icosa(s);
    s->tri_sub = ST_TRI_SUB_SMOOTH;
}

/* The icosahedron with a crease around one vertex's fan and a corner. */
static void icosa_creased(st_mesh *s)
{
    tl_mesh_icosa(s);
    s->ncreases = 2;
    s->crease_v = malloc(4 * sizeof *s->crease_v);
    s->crease_s = malloc(2 * sizeof *s->crease_s);
    s->crease_v[0] = s->face_idx[0]; s->crease_v[1] = s->face_idx[1];
    s->crease_v[2] = s->face_idx[1]; s->crease_v[3] = s->face_idx[2];
    s->crease_s[0] = 2.0f;
    s->crease_s[1] = 0.5f;
    s->ncorners = 1;
    s->corner_v = malloc(sizeof *s->corner_v);
    s->corner_s = malloc(sizeof *s->corner_s);
    s->corner_v[0] = s->face_idx[4];
    s->corner_s[0] = 4.0f;
}

/* Relations with a column at a level (a map not built by the uniform
 * split alone, e.g. from a session file): the tables read them through the
 * level views, or give way to the general paths; full synthesis still
 * equals the stencils and a local edit the full synthesis. */
static void check_columns(st_scheme_id id, void (*make)(st_mesh *))
{
    st_hier h;
    tl_init_hier(&h, make, id, 3);
    st_map *m = &h.map;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 1, &it); d != ST_NIL; d = st_dart_next(m, 1, &it))
        st_set_beta1(m, d, 1, st_beta1(m, d, 1)); /* same values, a column of its own */
    CHECK(m->beta1.eff[1] == 1);
    st_hier_synthesize(&h, 0);
    double gap = stencil_gap(&h);
    CHECKF(gap < 1e-13, "%s with a β1 column: levels and stencils differ by %g", h.scheme->name, gap);
    uint32_t d = st_dart_first(m, 1, &it);
    const double *p = st_dart_pos(m, d, 1);
    double q[1][3] = { { p[0] + 0.1, p[1] - 0.05, p[2] + 0.2 } };
    st_hier_move(&h, 1, &d, (const double (*)[3])q, 1);
    tl_posnap local, full;
    tl_snap_pos(&h, &local);
    st_hier_synthesize(&h, 1);
    tl_snap_pos(&h, &full);
    double diff = tl_snap_maxdiff(&local, &full);
    CHECKF(diff <= (id == ST_SCHEME_CATMARK ? 0 : 1e-12), "%s with a β1 column: local and full differ by %g", h.scheme->name, diff);
    free(local.p);
    free(full.p);
    st_hier_free(&h);
}

static void test_tables(void)
{
    check_columns(ST_SCHEME_CATMARK, torus_creased);
    check_columns(ST_SCHEME_CATMARK, grid);
    check_columns(ST_SCHEME_LOOP, icosa_creased);
    void (*quads[])(st_mesh *) = { torus, grid, icosa, tetra, cube_scaled, torus_creased, cone20, icosa_smooth_tri };
    for (size_t i = 0; i < sizeof quads / sizeof *quads; i++) check_tables(ST_SCHEME_CATMARK, quads[i], i);
    void (*tris[])(st_mesh *) = { icosa, tetra, octa, icosa_creased };
    for (size_t i = 0; i < sizeof tris / sizeof *tris; i++) check_tables(ST_SCHEME_LOOP, tris[i], 100 + i);
}

static int cmp_key(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* One edit of `darts` at level l by `step`: equal to a full synthesis to
 * the bit, its footprint the one the footprint query finds; returns the
 * number of positions it recomputed. */
static uint64_t drag_step(st_hier *h, unsigned l, const uint32_t *darts, uint32_t n, int step, const char *what)
{
    double pos[2][3];
    for (uint32_t k = 0; k < n; k++) {
        const double *p = st_dart_pos(&h->map, darts[k], l);
        for (int i = 0; i < 3; i++) pos[k][i] = p[i] + 0.01 * (step % 3 + 1) * (i + 1 + k) * (step % 2 ? -1 : 1);
    }
    st_footprint fp = { 0 }, query = { 0 };
    uint64_t count = st_hier_edit(h, l, darts, (const double (*)[3])pos, n, &fp);
    tl_posnap local, full;
    tl_snap_pos(h, &local);
    st_hier_synthesize(h, l);
    tl_snap_pos(h, &full);
    double diff = tl_snap_maxdiff(&local, &full);
    CHECKF(diff == 0, "drag, %s, step %d: local and full synthesis differ by %g", what, step, diff);
    st_hier_edit_footprint(h, l, darts, n, &query);
    qsort(fp.keys, fp.n, sizeof *fp.keys, cmp_key);
    qsort(query.keys, query.n, sizeof *query.keys, cmp_key);
    CHECKF(fp.n == query.n && (!fp.n || !memcmp(fp.keys, query.keys, fp.n * sizeof *fp.keys)),
           "drag, %s, step %d: the edit wrote %u values, the footprint query finds %u", what, step, fp.n, query.n);
    free(local.p);
    free(full.p);
    st_footprint_free(&fp);
    st_footprint_free(&query);
    return count;
}

/* A drag moves the same vertices again and again: Catmull-Clark replays
 * the plan of the first edit's walk (catmark_local.c) while the topology
 * and the sharpness stay.  Every step equals a full synthesis to the bit
 * and reports what it wrote, also after a crease (at crease_level: below
 * top-1 the finer levels take its children's sharpness), after the top
 * level went and came back, and after an edit of other vertices in between. */
static void check_drag(void (*make)(st_mesh *), unsigned levels, unsigned crease_level, const char *what)
{
    st_hier h;
    st_error err;
    uint64_t rng = 4242;
    tl_init_hier(&h, make, ST_SCHEME_CATMARK, levels);
    unsigned l = 1;
    uint32_t darts[2], other;
    darts[0] = tl_random_dart_at(&h.map, l, &rng);
    do darts[1] = tl_random_dart_at(&h.map, l, &rng);
    while (st_vert(&h.map, darts[1], l) == st_vert(&h.map, darts[0], l));
    do other = tl_random_dart_at(&h.map, l, &rng);
    while (st_vert(&h.map, other, l) == st_vert(&h.map, darts[0], l) || st_vert(&h.map, other, l) == st_vert(&h.map, darts[1], l));
    uint64_t first = 0;
    for (int step = 0; step < 9; step++) {
        if (step == 3) st_hier_set_edge_sharpness(&h, darts[0], crease_level, 2.0f);
        if (step == 5) {
            st_hier_remove_top(&h);
            CHECK(st_hier_subdivide_to(&h, levels, &err) == ST_OK);
        }
        if (step == 7) drag_step(&h, l, &other, 1, step, what);
        uint64_t count = drag_step(&h, l, darts, 2, step, what);
        if (step == 0) first = count;
        if (step < 3) CHECKF(count == first, "drag, %s, step %d: %llu positions, the first edit %llu", what, step,
                             (unsigned long long)count, (unsigned long long)first);
        if (step == 0) CHECKF(h.local.p != NULL, "drag, %s: no plan kept after the first edit", what);
    }
    st_hier_free(&h);
}

/* A sharpness set on level 1 of a hierarchy of 4 levels reaches the finer
 * levels as refinement would have given it (OpenSubdiv's uniform rule: one
 * less per level, both darts of each child edge alike), and a corner
 * likewise; setting it back to 0 takes it away again. */
static void test_crease_below_top(void)
{
    st_hier h;
    uint64_t rng = 77;
    tl_init_hier(&h, cube_scaled, ST_SCHEME_CATMARK, 4);
    uint32_t d = tl_random_dart_at(&h.map, 1, &rng), e = st_beta0(&h.map, d, 1);
    uint32_t v = st_vert(&h.map, d, 1);
    for (int pass = 0; pass < 2; pass++) {
        float s = pass ? 0.0f : 2.5f;
        st_hier_set_edge_sharpness(&h, d, 1, s);
        st_hier_set_vertex_sharpness(&h, v, 1, s);
        for (unsigned l = 2; l <= 4; l++) {
            float want = s - (float)(l - 1) > 0 ? s - (float)(l - 1) : 0.0f;
            uint32_t halves[2] = { d, e };
            for (int i = 0; i < 2; i++) {
                uint32_t x = halves[i], y = st_beta0(&h.map, x, l);
                CHECKF(st_hier_edge_sharpness(&h, x, l) == want && st_hier_edge_sharpness(&h, y, l) == want,
                       "crease %g at level 1: level %u child edge has %g / %g, want %g", (double)s, l,
                       (double)st_hier_edge_sharpness(&h, x, l), (double)st_hier_edge_sharpness(&h, y, l), (double)want);
            }
            CHECKF(st_hier_vertex_sharpness(&h, v, l) == want, "corner %g at level 1: level %u has %g, want %g",
                   (double)s, l, (double)st_hier_vertex_sharpness(&h, v, l), (double)want);
        }
    }
    st_hier_free(&h);
}

/* Creases set on level 1 of a hierarchy of 4 levels give every finer level
 * the sharpness, and the positions, that refining after setting them gives
 * (to the bit), with either rule; two semi-sharp edges at one vertex make
 * Chaikin's rule differ from the uniform one. */
static void creases_on(st_hier *h, uint32_t d, int method)
{
    h->opts.crease_method = method;
    st_hier_set_edge_sharpness(h, d, 1, 2.5f);
    st_hier_set_edge_sharpness(h, st_beta1(&h->map, d, 1), 1, 1.25f);
    st_hier_set_vertex_sharpness(h, st_vert(&h->map, st_beta0(&h->map, d, 1), 1), 1, 1.5f);
}

static void test_crease_matches_refinement(int method)
{
    st_hier late, early;
    st_error err;
    uint64_t rng = 91;
    tl_init_hier(&late, torus, ST_SCHEME_CATMARK, 4);
    tl_init_hier(&early, torus, ST_SCHEME_CATMARK, 1);
    uint32_t d = tl_random_dart_at(&late.map, 1, &rng);
    creases_on(&late, d, method);
    st_hier_synthesize(&late, 1);
    creases_on(&early, d, method);
    CHECK(st_hier_subdivide_to(&early, 4, &err) == ST_OK);
    unsigned bad = 0;
    for (unsigned l = 1; l <= 4; l++) {
        st_dart_iter it;
        for (uint32_t x = st_dart_first(&late.map, l, &it); x != ST_NIL; x = st_dart_next(&late.map, l, &it))
            bad += st_hier_edge_sharpness(&late, x, l) != st_hier_edge_sharpness(&early, x, l);
        for (uint32_t v = st_vertex_first(&late.map, l, &it); v != ST_NIL; v = st_vertex_next(&late.map, l, &it))
            bad += st_hier_vertex_sharpness(&late, v, l) != st_hier_vertex_sharpness(&early, v, l);
    }
    CHECKF(bad == 0, "creases at level 1, method %d: %u sharpness values differ from refining after them", method, bad);
    tl_posnap a, b;
    tl_snap_pos(&late, &a);
    tl_snap_pos(&early, &b);
    double diff = tl_snap_maxdiff(&a, &b);
    CHECKF(diff == 0, "creases at level 1, method %d: positions differ from refining after them by %g", method, diff);
    free(a.p);
    free(b.p);
    st_hier_free(&late);
    st_hier_free(&early);
}

int main(void)
{
    test_catmark_cube_values();
    test_tables();
    check_drag(torus, 4, 3, "torus");
    check_drag(grid, 3, 2, "grid");
    check_drag(cube_scaled, 4, 3, "cube");
    check_drag(torus, 4, 1, "torus, crease at level 1");
    check_drag(grid, 3, 1, "grid, crease at level 1");
    check_drag(cube_scaled, 4, 1, "cube, crease at level 1");
    test_crease_below_top();
    test_crease_matches_refinement(ST_CREASE_UNIFORM);
    test_crease_matches_refinement(ST_CREASE_CHAIKIN);
    struct { st_scheme_id id; void (*make)(st_mesh *); unsigned levels; } cases[] = {
        { ST_SCHEME_CATMARK, torus, 4 },
        { ST_SCHEME_CATMARK, grid, 3 },
        { ST_SCHEME_CATMARK, cube_scaled, 4 },
        { ST_SCHEME_CATMARK, torus_creased, 4 },
        { ST_SCHEME_LOOP, icosa_creased, 3 },
        { ST_SCHEME_DOOSABIN, torus, 3 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        tl_check_local_equals_full(cases[i].id, cases[i].make, cases[i].levels);
        tl_check_rigid_motion(cases[i].id, cases[i].make, cases[i].levels);
        tl_check_details_kept(cases[i].id, cases[i].make, cases[i].levels);
    }
    /* Meshes whose every vertex a level-0 edit reaches: one face of the cone
     * holds every base vertex; Doo-Sabin's support (two rings) covers the
     * cube (the vertex counts are the surface's since the statistics count
     * the dual encoding's surface cells). */
    tl_check_local_equals_full_small(ST_SCHEME_CATMARK, cone20, 3);
    tl_check_rigid_motion(ST_SCHEME_CATMARK, cone20, 3);
    tl_check_details_kept(ST_SCHEME_CATMARK, cone20, 3);
    tl_check_local_equals_full_small(ST_SCHEME_DOOSABIN, cube_scaled, 3);
    tl_check_rigid_motion(ST_SCHEME_DOOSABIN, cube_scaled, 3);
    tl_check_details_kept(ST_SCHEME_DOOSABIN, cube_scaled, 3);
    return TEST_END();
}
