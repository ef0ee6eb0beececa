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
        if (d >= x->cap || d >= y->cap || memcmp(x->uv + 2 * (size_t)d, y->uv + 2 * (size_t)d, 2 * sizeof *x->uv) ||
            x->val[d] != y->val[d])
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
            seen = !st_is_boundary(&h->map, e) && !memcmp(z->uv + 2 * (size_t)e, x->uv + 2 * (size_t)d, 2 * sizeof *x->uv);
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

int main(void)
{
    test_builtin();
    test_shared();
    test_stencil_schemes();
    return TEST_END();
}
