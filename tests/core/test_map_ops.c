/* Randomized sequences of operators at random levels (fixed seeds), with the
 * validator after every operation, and exact inverse checks: an operator
 * followed by its inverse gives back every relation at every level. */
#include "core/map/map.h"
#include "core/map/map_mesh.h"
#include "core/map/refine_internal.h"
#include "testlib.h"

#include <stdlib.h>
#include <string.h>

typedef struct snapshot {
    uint32_t n, levels;
    uint32_t *rel;     /* n * levels * 3 */
    uint8_t *live;
} snapshot;

static void snap(const st_map *m, snapshot *s)
{
    s->n = m->darts.end;
    s->levels = m->top + 1;
    s->rel = calloc((size_t)s->n * s->levels * 3 + 1, sizeof *s->rel);
    s->live = calloc(s->n + 1, 1);
    for (uint32_t d = 0; d < s->n; d++) {
        s->live[d] = st_dart_live(m, d) ? (uint8_t)(1 + m->darts.ins[d]) : 0;
        if (!s->live[d]) continue;
        for (unsigned l = m->darts.ins[d]; l < s->levels; l++) {
            uint32_t *r = s->rel + ((size_t)d * s->levels + l) * 3;
            r[0] = st_beta0(m, d, l); r[1] = st_beta1(m, d, l); r[2] = st_vert(m, d, l);
        }
    }
}

static int snap_equal(const snapshot *a, const snapshot *b)
{
    if (a->levels != b->levels) return 0;
    uint32_t n = a->n < b->n ? a->n : b->n;
    for (uint32_t d = 0; d < n; d++)
        if (a->live[d] != b->live[d]) return 0;
    for (uint32_t d = n; d < b->n; d++)
        if (b->live[d]) return 0;
    return memcmp(a->rel, b->rel, (size_t)n * a->levels * 3 * sizeof *a->rel) == 0;
}

static void snap_free(snapshot *s) { free(s->rel); free(s->live); }

static int dart_stable(const st_map *m, uint32_t d, unsigned l)
{
    for (unsigned k = l + 1; k <= m->top; k++)
        if (st_beta0(m, d, k) != st_beta0(m, d, l) || st_beta1(m, d, k) != st_beta1(m, d, l) || st_vert(m, d, k) != st_vert(m, d, l))
            return 0;
    return 1;
}

/* A face (and the darts across its edges) unchanged above level l: the
 * precondition for operating on it at level l (map.h, "Setting"). */
static int face_stable(const st_map *m, uint32_t d, unsigned l)
{
    uint32_t x = d;
    do {
        if (!dart_stable(m, x, l) || !dart_stable(m, st_beta0(m, x, l), l)) return 0;
        x = st_phi1(m, x, l);
    } while (x != d);
    return 1;
}

static uint32_t random_dart(const st_map *m, unsigned l, uint64_t *rng)
{
    for (int tries = 0; tries < 1000; tries++) {
        uint32_t d = tl_rand(rng) % m->darts.end;
        if (st_dart_in_level(m, d, l)) return d;
    }
    return ST_NIL;
}

static void validate(st_map *m, const char *what, unsigned seed, int step)
{
    st_error err;
    int rc = st_map_validate(m, &err);
    CHECKF(rc == ST_OK, "seed %u step %d after %s: %s", seed, step, what, err.msg);
}

static const double P0[3] = { 0.5, 0.25, 0.125 };

/* Applies one random operator and, half of the time, its inverse, checking
 * that the inverse restores the snapshot exactly. */
static const char *random_op(st_map *m, uint64_t *rng, int check_inverse)
{
    st_error err;
    unsigned l = tl_rand(rng) % (m->top + 1);
    uint32_t d = random_dart(m, l, rng);
    if (d == ST_NIL) return "none";
    snapshot before;
    snap(m, &before);
    const char *what = "none";
    int inverted = 0;
    switch (tl_rand(rng) % 3) {
    case 0:
        if (!dart_stable(m, d, l) || !dart_stable(m, st_beta0(m, d, l), l)) break;
        {
            uint32_t a = st_split_edge(m, d, l, P0);
            what = "split";
            if (check_inverse) {
                CHECKF(st_unsplit_edge(m, a, l, &err) == ST_OK, "%s", err.msg);
                inverted = 1;
            }
        }
        break;
    case 1: {
        unsigned n = st_face_degree(m, d, l);
        if (st_is_boundary(m, d) || n < 4 || !face_stable(m, d, l)) break;
        uint32_t d2 = d;
        unsigned k = 2 + tl_rand(rng) % (n - 3);
        for (unsigned i = 0; i < k; i++) d2 = st_phi1(m, d2, l);
        uint32_t x = st_cut_face(m, d, d2, l);
        what = "cut";
        if (check_inverse) {
            CHECKF(st_uncut_face(m, x, l, &err) == ST_OK, "%s", err.msg);
            inverted = 1;
        }
        break;
    }
    default: {
        uint32_t e = st_beta0(m, d, l);
        if (st_is_boundary(m, d) || st_is_boundary(m, e) || !face_stable(m, d, l) || !face_stable(m, e, l)) break;
        if (st_vertex_degree(m, d, l) < 3 || st_vertex_degree(m, e, l) < 3) break;
        if (st_flip_edge(m, d, l, &err) != ST_OK) break;
        what = "flip";
        if (check_inverse) {
            CHECKF(st_flip_edge_back(m, d, l, &err) == ST_OK, "%s", err.msg);
            inverted = 1;
        }
        break;
    }
    }
    if (inverted) {
        snapshot after;
        snap(m, &after);
        CHECKF(snap_equal(&before, &after), "%s followed by its inverse changed the map", what);
        snap_free(&after);
    }
    snap_free(&before);
    return what;
}

static void run_seed(unsigned seed, void (*make)(st_mesh *), unsigned levels, int steps)
{
    st_mesh s;
    st_map m;
    st_error err;
    make(&s);
    st_map_init(&m);
    CHECK(st_map_from_mesh(&m, &s, &err) == ST_OK);
    st_mesh_free(&s);
    for (unsigned k = 0; k < levels; k++) CHECK(st_refine_uniform(&m, ST_SPLIT_POLY, &err) == ST_OK);
    uint64_t rng = 0x9E3779B97F4A7C15ull ^ seed;
    int counts[4] = { 0 };
    for (int step = 0; step < steps; step++) {
        unsigned r = tl_rand(&rng) % 100;
        const char *what;
        if (r < 3 && m.top + 1 < 5) { CHECK(st_level_add(&m, &err) == ST_OK); what = "add level"; }
        else if (r < 5 && m.top > 0) { st_level_remove_top(&m); what = "remove top level"; }
        else what = random_op(&m, &rng, r % 2);
        if (!strcmp(what, "split")) counts[0]++;
        if (!strcmp(what, "cut")) counts[1]++;
        if (!strcmp(what, "flip")) counts[2]++;
        validate(&m, what, seed, step);
    }
    CHECKF(counts[0] > 0 && counts[1] > 0 && counts[2] > 0, "seed %u: splits %d cuts %d flips %d", seed, counts[0], counts[1], counts[2]);
    st_map_free(&m);
}

static void grid4(st_mesh *s) { tl_mesh_grid(s, 4); }

int main(void)
{
    for (unsigned seed = 1; seed <= 12; seed++) run_seed(seed, tl_mesh_cube, 2, 300);
    for (unsigned seed = 100; seed <= 106; seed++) run_seed(seed, grid4, 1, 300);
    for (unsigned seed = 200; seed <= 204; seed++) run_seed(seed, tl_mesh_tetra, 2, 300);
    return TEST_END();
}
