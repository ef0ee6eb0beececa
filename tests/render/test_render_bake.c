/* Rendering a coarse level with the normal map baked from a fine one
 * (core/bake/bake.h, render/nmap.h) looks like the fine level: headless
 * images of level L (the renderer's smooth mode), of level B with its
 * tangent-space (and object-space) normal map, and of level B with its
 * vertex normals only, compared on the pixels the surface covers in both.
 * Level 5 of a Catmull-Clark cube sculpted with small bumps, baked onto
 * level 2 (1024² map).  Measured here (llvmpipe): with the tangent-space map
 * mean 3.8/255 and 2.7 % of the pixels off by more than 16/255; plain level 2
 * mean 10.0/255 and 20 % (what remains is mostly the silhouette, which a
 * normal map cannot change).  Asserted: the mapped image at least 2 times
 * closer than the plain one in mean, at most 4 % of its pixels off by more
 * than 16/255, and at least 4 times fewer such pixels than the plain one.
 * Images are written to STRATA_TMP.
 *
 *     test_render_bake --compare FINE.png MAPPED.png PLAIN.png
 * applies the same comparison and thresholds to three 320x320 renders
 * (used by tests/cli/cli_bake.sh on `strata render --normal-map`). */
#include "testlib.h"

#include "core/bake/bake.h"
#include "core/progressive/scheme_registry.h"
#include "render/image.h"
#include "render/nmap.h"
#include "render/offscreen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 320
#define MAP 1024
#define TOL 16


/* Sculpted detail: every vertex of level L moved along its smooth normal by
 * a smooth bump of its position. */
static void sculpt(st_hier *h, unsigned L)
{
    st_map *m = &h->map;
    st_mesh mesh;
    st_error err;
    st_mesh_init(&mesh);
    CHECK(st_hier_level_mesh(h, L, &mesh, &err) == ST_OK);
    double *n = malloc(3 * (size_t)mesh.nverts * sizeof *n);
    CHECK(st_mesh_vertex_normals(&mesh, n) == 0);
    /* st_map_to_mesh numbers vertices in the order of their ids. */
    uint32_t *vd = malloc(m->verts.end * sizeof *vd), *index = malloc(m->verts.end * sizeof *index), k = 0;
    double (*pos)[3] = malloc(m->verts.end * sizeof *pos);
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, L, &it); v != ST_NIL; v = st_vertex_next(m, L, &it)) index[v] = k++;
    uint8_t *seen = calloc(m->verts.end, 1);
    uint32_t cnt = 0;
    for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
        uint32_t v = st_vert(m, d, L);
        if (seen[v]) continue;
        seen[v] = 1;
        const double *p = st_pos(m, v, L), *nn = n + 3 * (size_t)index[v];
        double b = 0.025 * sin(12 * p[0]) * sin(12 * p[1]) * sin(12 * p[2] + 0.3);
        for (int c = 0; c < 3; c++) pos[cnt][c] = p[c] + b * nn[c];
        vd[cnt++] = d;
    }
    st_hier_move(h, L, vd, (const double (*)[3])pos, cnt);
    free(seen);
    free(vd);
    free(index);
    free(pos);
    free(n);
    st_mesh_free(&mesh);
}

typedef struct cmp { double mean; double frac; uint64_t both; } cmp;

/* Mean absolute channel difference and the fraction of pixels off by more
 * than TOL, over the pixels where neither image shows the background. */
static cmp compare(const unsigned char *a, const unsigned char *b)
{
    const unsigned char bg[3] = { (unsigned char)lround(0.93 * 255), (unsigned char)lround(0.94 * 255), (unsigned char)lround(0.96 * 255) };
    cmp c = { 0, 0, 0 };
    uint64_t off = 0;
    double sum = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        const unsigned char *p = a + 4 * i, *q = b + 4 * i;
        int pb = abs(p[0] - bg[0]) + abs(p[1] - bg[1]) + abs(p[2] - bg[2]) <= 3;
        int qb = abs(q[0] - bg[0]) + abs(q[1] - bg[1]) + abs(q[2] - bg[2]) <= 3;
        if (pb || qb) continue;
        int worst = 0;
        for (int k = 0; k < 3; k++) {
            int d = abs(p[k] - q[k]);
            sum += d;
            if (d > worst) worst = d;
        }
        if (worst > TOL) off++;
        c.both++;
    }
    c.mean = c.both ? sum / (3.0 * c.both) : 0;
    c.frac = c.both ? (double)off / c.both : 0;
    return c;
}

static void save(const char *name, const unsigned char *rgba)
{
    char path[1024];
    st_error err;
    snprintf(path, sizeof path, "%s/%s", STRATA_TMP, name);
    CHECKF(st_png_write(path, W, H, rgba, &err) == ST_OK, "%s", err.msg);
}

static void to_rgba8(const st_bake_maps *m, unsigned char *out)
{
    for (size_t i = 0; i < (size_t)m->size * m->size; i++) {
        for (int k = 0; k < 3; k++) {
            double x = 0.5 * m->normal[3 * i + k] + 0.5;
            out[4 * i + k] = (unsigned char)lround(255 * (x < 0 ? 0 : x > 1 ? 1 : x));
        }
        out[4 * i + 3] = 255;
    }
}

static void check_space(st_hier *h, unsigned B, unsigned L, const st_bake_uvs *uvs, int space, st_offscreen *off,
                        const st_camera *cam, const unsigned char *fine, const char *name)
{
    st_error err;
    st_bake_opts o = { .base = B, .level = L, .size = MAP, .space = space, .normal = 1, .padding = 8 };
    st_bake_maps maps;
    CHECKF(st_bake(h, uvs, &o, &maps, &err) == ST_OK, "%s", err.msg);
    unsigned char *tex = malloc((size_t)MAP * MAP * 4), *with = malloc(4 * W * H), *plain = malloc(4 * W * H);
    to_rgba8(&maps, tex);
    {
        char path[1024];
        snprintf(path, sizeof path, "%s/bake_%s_map.png", STRATA_TMP, name);
        CHECKF(st_png_write(path, MAP, MAP, tex, &err) == ST_OK, "%s", err.msg);
    }
    st_nmap_mesh mesh;
    CHECKF(st_nmap_mesh_build(h, B, uvs, &mesh, &err) == ST_OK, "%s", err.msg);
    st_headless_begin(&off->hl);
    st_nmap nm;
    CHECKF(st_nmap_init(&nm, &off->hl.gl, &err) == ST_OK, "%s", err.msg);
    st_nmap_set_mesh(&nm, &mesh);
    st_nmap_set_map(&nm, tex, MAP, MAP);
    st_nmap_draw(&nm, cam, W, H, space == ST_BAKE_OBJECT ? ST_NMAP_OBJECT : ST_NMAP_TANGENT);
    CHECK(st_headless_read(&off->hl, with, &err) == ST_OK);
    st_headless_begin(&off->hl);
    st_nmap_draw(&nm, cam, W, H, ST_NMAP_NONE);
    CHECK(st_headless_read(&off->hl, plain, &err) == ST_OK);
    st_nmap_free(&nm);
    cmp cw = compare(with, fine), cp = compare(plain, fine);
    printf("%s: level %u with the normal map vs level %u: mean %.2f/255, %.2f %% of %llu pixels off by > %d; "
           "level %u plain: mean %.2f/255, %.2f %% off\n",
           name, B, L, cw.mean, 100 * cw.frac, (unsigned long long)cw.both, TOL, B, cp.mean, 100 * cp.frac);
    CHECK(cw.both > W * H / 8);
    CHECKF(cw.mean * 2 < cp.mean, "%s: normal map mean %.2f not 2x below plain %.2f", name, cw.mean, cp.mean);
    CHECKF(cw.frac <= 0.04, "%s: %.2f %% of pixels off by more than %d", name, 100 * cw.frac, TOL);
    CHECKF(cw.frac * 4 < cp.frac, "%s: %.2f %% of pixels off, plain %.2f %%", name, 100 * cw.frac, 100 * cp.frac);
    char fn[256];
    snprintf(fn, sizeof fn, "bake_%s_B%u_mapped.png", name, B);
    save(fn, with);
    snprintf(fn, sizeof fn, "bake_%s_B%u_plain.png", name, B);
    save(fn, plain);
    st_nmap_mesh_free(&mesh);
    st_bake_maps_free(&maps);
    free(tex);
    free(with);
    free(plain);
}

static void make_hier(st_hier *h, st_scheme_id id, void (*make)(st_mesh *), unsigned L)
{
    st_mesh s;
    st_error err;
    make(&s);
    CHECKF(st_hier_init(h, &s, st_scheme_get(id), NULL, &err) == ST_OK, "%s", err.msg);
    st_mesh_free(&s);
    CHECKF(st_hier_subdivide_to(h, L, &err) == ST_OK, "%s", err.msg);
}

/* The thresholds of check_space on files. */
static int compare_files(const char *fine_path, const char *with_path, const char *plain_path)
{
    const char *paths[3] = { fine_path, with_path, plain_path };
    unsigned char *img[3] = { NULL, NULL, NULL };
    st_error err;
    int ok = 1;
    for (int k = 0; k < 3 && ok; k++) {
        int w = 0, h = 0;
        if (st_png_read(paths[k], &w, &h, &img[k], &err)) { fprintf(stderr, "compare: %s\n", err.msg); ok = 0; }
        else if (w != W || h != H) { fprintf(stderr, "compare: %s is %dx%d, not %dx%d\n", paths[k], w, h, W, H); ok = 0; }
    }
    if (ok) {
        cmp cw = compare(img[1], img[0]), cp = compare(img[2], img[0]);
        ok = cw.both > W * H / 8 && cw.mean * 2 < cp.mean && cw.frac <= 0.04 && cw.frac * 4 < cp.frac;
        printf("compare: %s vs %s: mean %.2f/255, %.2f %% of %llu pixels off by > %d; %s: mean %.2f/255, %.2f %% off: %s\n",
               with_path, fine_path, cw.mean, 100 * cw.frac, (unsigned long long)cw.both, TOL, plain_path, cp.mean,
               100 * cp.frac, ok ? "close" : "NOT CLOSE");
    }
    for (int k = 0; k < 3; k++) free(img[k]);
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc == 5 && !strcmp(argv[1], "--compare")) return compare_files(argv[2], argv[3], argv[4]);
    st_hier h;
    const unsigned B = 2, L = 5;
    make_hier(&h, ST_SCHEME_CATMARK, tl_mesh_cube, L);
    sculpt(&h, L);
    st_error err;
    st_offscreen off;
    if (st_offscreen_init(&off, W, H, &err)) {
        tl_skip("no headless OpenGL (%s)", err.msg);
        st_hier_free(&h);
        return TEST_END();
    }
    unsigned char *fine = malloc(4 * W * H);
    st_render_spec spec = st_render_spec_default();
    spec.level = L;
    spec.mode = ST_MODE_SMOOTH;
    CHECK(st_offscreen_prepare(&off, &h.map, &spec, &err) == ST_OK);
    CHECK(st_offscreen_draw(&off, &spec, fine, &err) == ST_OK);
    st_camera cam;
    st_offscreen_camera(&off, &spec, &cam);
    save("bake_fine_L5.png", fine);
    st_bake_layout lay;
    CHECKF(st_bake_auto_uvs(&h, B, &lay, &err) == ST_OK, "%s", err.msg);
    st_bake_uvs uvs = st_bake_layout_uvs(&lay);
    check_space(&h, B, L, &uvs, ST_BAKE_TANGENT, &off, &cam, fine, "tangent");
    check_space(&h, B, L, &uvs, ST_BAKE_OBJECT, &off, &cam, fine, "object");
    st_bake_layout_free(&lay);
    free(fine);
    st_offscreen_free(&off);
    st_hier_free(&h);
    return TEST_END();
}
