/* Face-varying UVs refined after the topology (st_fvar_refine_levels):
 * the map refined to level k first, then the UVs of levels 1..k, give the
 * UVs and value labels of refining them with each level (st_fvar_refine
 * after each refine(), as st_hier_subdivide_to does), bit for bit, for
 * every --uv-interp option, on meshes with seams, boundaries and creases,
 * and each level's arrays are no larger. */
#include "testlib.h"

#include "core/fvar/fvar_internal.h"
#include "core/io/mesh.h"
#include "core/map/map.h"
#include "core/multires/hier_internal.h"
#include "core/schemes/scheme.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int parse(const char *name, const char *text, st_mesh *m, st_error *err)
{
    st_mesh_init(m);
    int rc = st_mesh_parse_obj(name, text, strlen(text), m, err);
    if (!rc) rc = st_mesh_repair(name, m, NULL, err);
    return rc;
}

static int load(const char *rel, st_mesh *m)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", STRATA_SHARED_DATA, rel);
    size_t n;
    char *text = tl_read_file(path, &n);
    if (!text) {
        printf("note: %s not found: not checked\n", path);
        return -1;
    }
    st_error err = {0};
    int rc = parse(path, text, m, &err);
    CHECKF(rc == 0, "%s", err.msg);
    free(text);
    return rc;
}

/* A 6 x 6 grid (an open boundary) in two UV islands (a seam along x = 3,
 * ending at the boundary), a third island of one face (a UV corner inside),
 * a semi-sharp and an infinitely sharp crease and a sharp corner; tri 1:
 * half the quads split in two, 2: all of them; tags 0: no creases, no corner
 * (Doo-Sabin takes none). */
static void crease_grid(st_mesh *m, int tri, int tags)
{
    char text[16384];
    size_t k = 0;
    for (int y = 0; y <= 6; y++)
        for (int x = 0; x <= 6; x++) k += (size_t)snprintf(text + k, sizeof text - k, "v %d %d %g\n", x, y, 0.1 * ((x * y) % 4));
    for (int r = 0; r < 3; r++)
        for (int y = 0; y <= 6; y++)
            for (int x = 0; x <= 6; x++)
                k += (size_t)snprintf(text + k, sizeof text - k, "vt %g %g\n", x / 6.0 + 0.13 * r, y / 6.0 + 0.01 * r * x);
    for (int j = 0; j < 6; j++)
        for (int i = 0; i < 6; i++) {
            int r = (i == 1 && j == 4) ? 98 : i < 3 ? 0 : 49;
            int a = j * 7 + i + 1, b = a + 1, c = a + 8, d = a + 7;
            if (tri == 2 || (tri && (i + j) % 2))
                k += (size_t)snprintf(text + k, sizeof text - k, "f %d/%d %d/%d %d/%d\nf %d/%d %d/%d %d/%d\n", a, a + r,
                                      b, b + r, c, c + r, a, a + r, c, c + r, d, d + r);
            else
                k += (size_t)snprintf(text + k, sizeof text - k, "f %d/%d %d/%d %d/%d %d/%d\n", a, a + r, b, b + r, c,
                                      c + r, d, d + r);
        }
    /* 0-based vertex indices in tags */
    if (tags)
        k += (size_t)snprintf(text + k, sizeof text - k,
                          "t crease 2/1/0 8 9 1.5\nt crease 2/1/0 9 10 1.5\nt crease 2/1/0 15 16 10\n"
                          "t crease 2/1/0 16 17 10\nt corner 1/1/0 40 3\n");
    st_error err = {0};
    CHECKF(parse(tri ? "crease_grid_tri.obj" : "crease_grid.obj", text, m, &err) == 0, "%s", err.msg);
}

/* Level l of a and b: the same UV bits and labels at every real dart, and
 * b's arrays no larger than a's.  Returns the corners compared. */
static uint32_t same_level(const st_hier *a, const st_hier *b, unsigned l, const char *what)
{
    const st_fvar_level *x = &a->fvar->lv[l], *y = &b->fvar->lv[l];
    CHECKF(y->cap <= x->cap, "%s level %u: %u ids against %u", what, l, y->cap, x->cap);
    uint32_t n = 0, bad = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&a->map, l, &it); d != ST_NIL; d = st_dart_next(&a->map, l, &it)) {
        if (st_is_boundary(&a->map, d)) continue;
        n++;
        if (d >= x->cap || d >= y->cap || memcmp(st_fvar_uv_at(x, d), st_fvar_uv_at(y, d), 2 * sizeof *x->uv) ||
            st_fvar_label_at(x, d) != st_fvar_label_at(y, d))
            bad++;
    }
    CHECKF(bad == 0 && n > 0, "%s level %u: %u of %u corners differ", what, l, bad, n);
    return n;
}

/* How many corners of level l hold a value that no corner of level 0 has:
 * the rules computed something (a check that cannot pass on copies). */
static uint32_t new_values(const st_hier *h, unsigned l)
{
    const st_fvar_level *z = &h->fvar->lv[0], *x = &h->fvar->lv[l];
    uint32_t n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&h->map, l, &it); d != ST_NIL && n < 4; d = st_dart_next(&h->map, l, &it)) {
        if (st_is_boundary(&h->map, d) || h->map.darts.ins[d] != l) continue;  /* edge and face children */
        int seen = 0;
        st_dart_iter jt;
        for (uint32_t e = st_dart_first(&h->map, 0, &jt); e != ST_NIL && !seen; e = st_dart_next(&h->map, 0, &jt))
            seen = !st_is_boundary(&h->map, e) && !memcmp(st_fvar_uv_at(z, e), st_fvar_uv_at(x, d), 2 * sizeof *x->uv);
        n += !seen;
    }
    return n;
}

/* Interleaved (st_hier_subdivide_to) against topology first: levels 1..k,
 * and again in two calls (1..j, then j+1..k). */
static void check_mesh(const st_mesh *m, const st_scheme *sc, unsigned k, const char *name)
{
    for (int interp = 0; interp < ST_UV_INTERP_COUNT; interp++) {
        char what[160];
        snprintf(what, sizeof what, "%s %s uv-interp %s", name, sc->name, st_uv_interp_name(interp));
        st_hier_opts o = { .boundary = ST_BOUNDARY_UNSET, .crease_method = m->crease_method, .tri_sub = m->tri_sub,
                           .uv_interp = interp };
        st_hier a, b, c;
        st_error err = {0};
        CHECKF(st_hier_init(&a, m, sc, &o, &err) == 0 && st_hier_subdivide_to(&a, k, &err) == 0, "%s: %s", what, err.msg);
        CHECKF(st_hier_init(&b, m, sc, &o, &err) == 0, "%s: %s", what, err.msg);
        CHECKF(st_hier_init(&c, m, sc, &o, &err) == 0, "%s: %s", what, err.msg);
        for (unsigned l = 0; l < k; l++) {
            CHECK(st_hier_refine_topology(&b, &err) == 0);
            CHECK(st_hier_refine_topology(&c, &err) == 0);
        }
        CHECKF(a.fvar && b.fvar && a.fvar->levels == k + 1 && b.fvar->levels == 1, "%s", what);
        /* Beyond the map's top: refused, nothing done. */
        CHECK(st_hier_uv_refine_levels(&b, k + 1, &err) == ST_ERR_INVALID && b.fvar->levels == 1);
        CHECKF(st_hier_uv_refine_levels(&b, k, &err) == 0, "%s: %s", what, err.msg);
        CHECK(b.fvar->levels == k + 1);
        unsigned j = k / 2;
        CHECKF(st_hier_uv_refine_levels(&c, j, &err) == 0 && c.fvar->levels == j + 1, "%s: %s", what, err.msg);
        CHECKF(st_hier_uv_refine_levels(&c, k, &err) == 0 && c.fvar->levels == k + 1, "%s: %s", what, err.msg);
        CHECK(st_hier_uv_refine_levels(&c, k, &err) == 0 && c.fvar->levels == k + 1);  /* there already */
        for (unsigned l = 0; l <= k; l++) {
            same_level(&a, &b, l, what);
            same_level(&a, &c, l, what);
        }
        /* Below the top, a level's arrays cover its own darts, not the
         * finer map's: level k-1's about a quarter of level k's ids. */
        CHECKF(4 * b.fvar->lv[k - 1].cap < 2 * b.map.darts.end, "%s: level %u: %u ids of %u", what, k - 1,
               b.fvar->lv[k - 1].cap, b.map.darts.end);
        CHECKF(new_values(&b, k) > 0, "%s: level %u holds level 0's values only", what, k);
        st_hier_free(&a);
        st_hier_free(&b);
        st_hier_free(&c);
    }
}

static void test_builtin(void)
{
    st_mesh m;
    crease_grid(&m, 0, 1);
    check_mesh(&m, &st_scheme_catmark, 3, "crease_grid");
    check_mesh(&m, &st_scheme_quadtri, 2, "crease_grid");
    st_mesh_free(&m);
    crease_grid(&m, 1, 1);
    check_mesh(&m, &st_scheme_catmark, 3, "crease_grid_tri");
    check_mesh(&m, &st_scheme_quadtri, 2, "crease_grid_tri");
    st_mesh_free(&m);
}

static void test_shared(void)
{
    static const struct { const char *path; const st_scheme *sc; unsigned k; } cases[] = {
        { "catmull_clark/spot_quadrangulated.obj", &st_scheme_catmark, 2 },
        { "catmull_clark/blub_control_mesh.obj", &st_scheme_catmark, 3 },
        { "triangle/blub_open.obj", &st_scheme_loop, 1 },
        { "triangle/cube_no_bottom.obj", &st_scheme_loop, 3 },
        { "triangle/cube_no_bottom.obj", &st_scheme_butterfly, 2 },
        { "triangle/sphere_ico.obj", &st_scheme_catmark, 2 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        st_mesh m;
        if (load(cases[i].path, &m)) continue;
        CHECKF(m.face_uv != NULL, "%s has UVs", cases[i].path);
        check_mesh(&m, cases[i].sc, cases[i].k, cases[i].path);
        st_mesh_free(&m);
    }
}

/* √3 and Doo-Sabin read the top level: after the topology, refused unless
 * only the top is missing; then the same bits as with each level. */
static void test_stencil_schemes(void)
{
    st_mesh m;
    crease_grid(&m, 2, 0);
    const st_scheme *schemes[] = { &st_scheme_sqrt3, &st_scheme_doosabin };
    for (int s = 0; s < 2; s++) {
        st_hier a, b;
        st_error err = {0};
        CHECKF(st_hier_init(&a, &m, schemes[s], NULL, &err) == 0 && st_hier_subdivide_to(&a, 2, &err) == 0, "%s", err.msg);
        CHECKF(st_hier_init(&b, &m, schemes[s], NULL, &err) == 0, "%s", err.msg);
        CHECK(st_hier_refine_topology(&b, &err) == 0 && st_hier_uv_refine_levels(&b, 1, &err) == 0);
        CHECK(st_hier_refine_topology(&b, &err) == 0);
        CHECK(st_hier_uv_refine_levels(&b, 1, &err) == 0 && b.fvar->levels == 2);  /* there already */
        CHECK(st_hier_refine_topology(&b, &err) == 0);
        CHECKF(st_hier_uv_refine_levels(&b, 3, &err) == ST_ERR_INVALID && strstr(err.msg, schemes[s]->name), "%s", err.msg);
        CHECK(b.fvar->levels == 2);
        st_hier_remove_top(&b);
        CHECK(st_hier_uv_refine_levels(&b, 2, &err) == 0 && b.fvar->levels == 3);
        for (unsigned l = 0; l <= 2; l++) same_level(&a, &b, l, schemes[s]->name);
        st_hier_free(&a);
        st_hier_free(&b);
    }
    st_mesh_free(&m);
}

/* The compact form (st_fvar_level_compact) reads back every dart's UV
 * bits and label exactly: a level made dense again, with corners changed
 * to hold the same label with other bits and the same bits with another
 * label (both kept apart), and ids outside the level left zero or given a
 * value of their own.  Untouched, a level keeps well under a value per
 * dart. */
static void check_compact(const st_hier *h, unsigned l, const char *what)
{
    const st_fvar_level *src = &h->fvar->lv[l];
    uint32_t cap = src->cap, n = 0;
    CHECKF(src->idx && src->nvals > 0 && 2 * (uint64_t)src->nvals < cap, "%s level %u: %u values for %u ids", what, l,
           src->nvals, cap);
    for (int changed = 0; changed < 2; changed++) {
        st_fvar_level lv = { cap, 0, calloc(2 * (size_t)cap + 2, sizeof(double)), calloc((size_t)cap + 1, 4), NULL };
        double *want_uv = malloc(2 * (size_t)cap * sizeof *want_uv + 1);
        uint32_t *want_val = malloc((size_t)cap * sizeof *want_val + 1);
        CHECK(lv.uv && lv.val && want_uv && want_val);
        for (uint32_t d = 0; d < cap; d++) {
            int in = h->map.darts.ins[d] <= l;
            const double *p = st_fvar_uv_at(src, d);
            lv.uv[2 * (size_t)d] = p[0];
            lv.uv[2 * (size_t)d + 1] = p[1];
            lv.val[d] = st_fvar_label_at(src, d);
            if (changed && in && d % 7 == 3) lv.uv[2 * (size_t)d] = nextafter(p[0], INFINITY);
            if (changed && in && d % 11 == 5) lv.val[d] += 1000;
            if (changed && !in && d % 5 == 1) lv.uv[2 * (size_t)d + 1] = 0.25 + d;
            want_uv[2 * (size_t)d] = lv.uv[2 * (size_t)d];
            want_uv[2 * (size_t)d + 1] = lv.uv[2 * (size_t)d + 1];
            want_val[d] = lv.val[d];
        }
        CHECK(st_fvar_level_compact(&lv, &h->map, l) == 0 && lv.idx && lv.nvals <= cap + 1);
        uint32_t bad = 0;
        for (uint32_t d = 0; d < cap; d++, n++)
            bad += lv.idx[d] >= lv.nvals || memcmp(st_fvar_uv_at(&lv, d), want_uv + 2 * (size_t)d, 2 * sizeof *want_uv) ||
                   st_fvar_label_at(&lv, d) != want_val[d];
        CHECKF(bad == 0, "%s level %u%s: %u of %u ids read back otherwise", what, l, changed ? " changed" : "", bad, cap);
        if (!changed)
            CHECKF(lv.nvals == src->nvals, "%s level %u: compacted again, %u values for %u", what, l, lv.nvals,
                   src->nvals);
        free(lv.uv);
        free(lv.val);
        free(lv.idx);
        free(want_uv);
        free(want_val);
    }
    CHECK(n > 0);
}

static void test_compact(void)
{
    st_mesh m;
    crease_grid(&m, 0, 1);
    const st_scheme *schemes[] = { &st_scheme_catmark, &st_scheme_loop, &st_scheme_doosabin };
    for (int i = 0; i < 3; i++) {
        st_mesh t;
        st_mesh_init(&t);
        const st_mesh *in = &m;
        if (schemes[i] == &st_scheme_loop) {
            crease_grid(&t, 2, 1);
            in = &t;
        }
        st_hier h;
        st_error err = {0};
        CHECKF(st_hier_init(&h, in, schemes[i], NULL, &err) == 0 && st_hier_subdivide_to(&h, 2, &err) == 0, "%s: %s",
               schemes[i]->name, err.msg);
        for (unsigned l = 1; l <= 2; l++) check_compact(&h, l, schemes[i]->name);
        st_hier_free(&h);
        st_mesh_free(&t);
    }
    st_mesh_free(&m);
}

int main(void)
{
    test_builtin();
    test_shared();
    test_stencil_schemes();
    test_compact();
    return TEST_END();
}
