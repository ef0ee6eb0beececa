/* Image-comparison tests of the renderer, headless (OSMesa).
 *
 * A matrix of meshes x schemes x display modes, regular levels and adaptive
 * (interest-box) meshes, is rendered at 160x120 and
 * compared with the reference PNGs in tests/render_ref/.  Metric (render/
 * image.h): a pixel differs when one of its channels is off by more than
 * ST_IMAGE_TOL = 4 (1.6 % of 255, Blender's per-pixel threshold); an image
 * passes when at most ST_IMAGE_MAX_FRACTION = 0.3 % of its pixels differ
 * (three.js's limit; Blender allows 1 %).  On a failure the actual,
 * expected and diff images are written to <build>/tests/render_out/ and
 * their paths printed.
 *
 * Regenerating the references on purpose (after a deliberate change to
 * the renderer's look; look at the new images before committing them):
 *
 *     STRATA_UPDATE_REFS=1 ctest --test-dir build/release -R render
 *
 * The comparison is itself tested: a rendering twice is identical, small
 * noise passes, and a missing face or a camera moved by 2 degrees fail.
 *
 *     test_render_images --compare EXPECTED.png ACTUAL.png
 * compares two files with the same metric (used by tests/cli/cli_render.sh). */
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/adapt/adapt.h"
#include "core/progressive/scheme_registry.h"
#include "render/image.h"
#include "render/offscreen.h"

#define W 160
#define H 120

typedef struct img_case {
    const char *name;          /* reference file name without .png */
    const char *file;          /* mesh, under assets/ or the shared folder */
    int shared;
    st_scheme_id scheme;
    unsigned levels;           /* built, and shown */
    int mode;
    int view;                  /* preset, or -1 for the orbit */
    float az, el;
    /* Adaptive display: an interest box (fractions of the bounding box,
     * min xyz then max xyz) refining from level 0 to `levels`; all zero:
     * the regular level. */
    float box[6];
} img_case;

#define A 0
#define S 1
static const img_case cases[] = {
    { "cube_catmark_l1_smooth", "cube.obj", A, ST_SCHEME_CATMARK, 1, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "cube_catmark_l3_smooth", "cube.obj", A, ST_SCHEME_CATMARK, 3, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "cube_catmark_l2_flat", "cube.obj", A, ST_SCHEME_CATMARK, 2, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { 0 } },
    { "cube_catmark_l2_wire", "cube.obj", A, ST_SCHEME_CATMARK, 2, ST_MODE_WIRE, ST_VIEW_FRONT, 0, 0, { 0 } },
    { "cube_catmark_l2_cage", "cube.obj", A, ST_SCHEME_CATMARK, 2, ST_MODE_CAGE, ST_VIEW_ISO, 0, 0, { 0 } },
    { "cube_doosabin_l1_flat", "cube.obj", A, ST_SCHEME_DOOSABIN, 1, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { 0 } },
    { "cube_doosabin_l3_wire", "cube.obj", A, ST_SCHEME_DOOSABIN, 3, ST_MODE_WIRE, ST_VIEW_ISO, 0, 0, { 0 } },
    { "mixed_quadtri_l2_smooth", "mixed.obj", A, ST_SCHEME_QUADTRI, 2, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "mixed_quadtri_l2_wire", "mixed.obj", A, ST_SCHEME_QUADTRI, 2, ST_MODE_WIRE, ST_VIEW_TOP, 0, 0, { 0 } },
    { "mixed_catmark_l1_cage", "mixed.obj", A, ST_SCHEME_CATMARK, 1, ST_MODE_CAGE, ST_VIEW_ISO, 0, 0, { 0 } },
    { "tetrahedron_loop_l3_smooth", "tetrahedron.obj", A, ST_SCHEME_LOOP, 3, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "tetrahedron_loop_l1_wire", "tetrahedron.obj", A, ST_SCHEME_LOOP, 1, ST_MODE_WIRE, ST_VIEW_ISO, 0, 0, { 0 } },
    { "octahedron_loop_l2_flat", "octahedron.obj", A, ST_SCHEME_LOOP, 2, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { 0 } },
    { "tetrahedron_butterfly_l3_flat", "tetrahedron.obj", A, ST_SCHEME_BUTTERFLY, 3, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { 0 } },
    { "octahedron_butterfly_l2_wire", "octahedron.obj", A, ST_SCHEME_BUTTERFLY, 2, ST_MODE_WIRE, ST_VIEW_RIGHT, 0, 0, { 0 } },
    { "tetrahedron_sqrt3_l4_smooth", "tetrahedron.obj", A, ST_SCHEME_SQRT3, 4, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "octahedron_sqrt3_l2_wire", "octahedron.obj", A, ST_SCHEME_SQRT3, 2, ST_MODE_WIRE, ST_VIEW_ISO, 0, 0, { 0 } },
    { "octahedron_doosabin_l2_cage", "octahedron.obj", A, ST_SCHEME_DOOSABIN, 2, ST_MODE_CAGE, ST_VIEW_ISO, 0, 0, { 0 } },
    { "torus_catmark_l2_smooth", "torus.obj", A, ST_SCHEME_CATMARK, 2, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "torus_doosabin_l2_flat", "torus.obj", A, ST_SCHEME_DOOSABIN, 2, ST_MODE_FLAT, -1, 20, 50, { 0 } },
    { "torus_quadtri_l1_wire", "torus.obj", A, ST_SCHEME_QUADTRI, 1, ST_MODE_WIRE, ST_VIEW_FRONT, 0, 0, { 0 } },
    { "ngon_catmark_l0_flat", "ngon.obj", A, ST_SCHEME_CATMARK, 0, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { 0 } },
    { "ngon_catmark_l2_wire", "ngon.obj", A, ST_SCHEME_CATMARK, 2, ST_MODE_WIRE, ST_VIEW_ISO, 0, 0, { 0 } },
    { "ngon_doosabin_l1_smooth", "ngon.obj", A, ST_SCHEME_DOOSABIN, 1, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "open_catmark_l2_smooth", "open.obj", A, ST_SCHEME_CATMARK, 2, ST_MODE_SMOOTH, -1, -30, 20, { 0 } },
    { "open_quadtri_l2_cage", "open.obj", A, ST_SCHEME_QUADTRI, 2, ST_MODE_CAGE, -1, 200, 25, { 0 } },
    { "dodecahedron_catmark_l0_flat", "catmull_clark/dodecahedron_poly.obj", S, ST_SCHEME_CATMARK, 0, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { 0 } },
    { "dodecahedron_catmark_l2_smooth", "catmull_clark/dodecahedron_poly.obj", S, ST_SCHEME_CATMARK, 2, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "blub_catmark_l2_cage", "catmull_clark/blub_control_mesh.obj", S, ST_SCHEME_CATMARK, 2, ST_MODE_CAGE, ST_VIEW_LEFT, 0, 0, { 0 } },
    { "hole_capsule_catmark_l2_smooth", "catmull_clark/hole_capsule.off", S, ST_SCHEME_CATMARK, 2, ST_MODE_SMOOTH, -1, 120, -30, { 0 } },
    { "bob_loop_l1_smooth", "triangle/bob_small.ply", S, ST_SCHEME_LOOP, 1, ST_MODE_SMOOTH, ST_VIEW_ISO, 0, 0, { 0 } },
    { "bob_sqrt3_l2_flat", "triangle/bob_small.ply", S, ST_SCHEME_SQRT3, 2, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { 0 } },
    { "spot_butterfly_l1_smooth", "triangle/spot_low_resolution.obj", S, ST_SCHEME_BUTTERFLY, 1, ST_MODE_SMOOTH, ST_VIEW_RIGHT, 0, 0, { 0 } },
    { "hemisphere_loop_l1_wire", "triangle/hemisphere.obj", S, ST_SCHEME_LOOP, 1, ST_MODE_WIRE, -1, 20, -35, { 0 } },
    /* Adaptive: faces of several depths side by side, drawn through the case tables. */
    { "cube_catmark_box3_wire", "cube.obj", A, ST_SCHEME_CATMARK, 3, ST_MODE_WIRE, ST_VIEW_ISO, 0, 0, { .5f, -.1f, -.1f, 1.1f, 1.1f, 1.1f } },
    { "cube_catmark_box3_flat", "cube.obj", A, ST_SCHEME_CATMARK, 3, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { -.1f, .5f, -.1f, 1.1f, 1.1f, 1.1f } },
    { "torus_catmark_box3_flat", "torus.obj", A, ST_SCHEME_CATMARK, 3, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { .5f, -.1f, -.1f, 1.1f, 1.1f, 1.1f } },
    { "octahedron_loop_box3_wire", "octahedron.obj", A, ST_SCHEME_LOOP, 3, ST_MODE_WIRE, ST_VIEW_ISO, 0, 0, { .5f, -.1f, -.1f, 1.1f, 1.1f, 1.1f } },
    { "tetrahedron_butterfly_box3_flat", "tetrahedron.obj", A, ST_SCHEME_BUTTERFLY, 3, ST_MODE_FLAT, ST_VIEW_ISO, 0, 0, { -.1f, -.1f, .4f, .6f, 1.1f, 1.1f } },
    { "mixed_quadtri_box3_wire", "mixed.obj", A, ST_SCHEME_QUADTRI, 3, ST_MODE_WIRE, ST_VIEW_TOP, 0, 0, { -.1f, -.1f, -.1f, .5f, 1.1f, .5f } },
    { "blub_catmark_box3_wire", "catmull_clark/blub_control_mesh.obj", S, ST_SCHEME_CATMARK, 3, ST_MODE_WIRE, ST_VIEW_LEFT, 0, 0, { -.1f, .5f, -.1f, 1.1f, 1.1f, 1.1f } },
};

static char out_dir[1024];

static int is_adaptive(const img_case *c)
{
    for (int k = 0; k < 6; k++)
        if (c->box[k] != 0) return 1;
    return 0;
}

/* The case's box in object space, from fractions of the mesh's bounding box. */
static void adaptive_box(const img_case *c, const st_mesh *m, double lo[3], double hi[3])
{
    double bmin[3] = { INFINITY, INFINITY, INFINITY }, bmax[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t v = 0; v < m->nverts; v++)
        for (int k = 0; k < 3; k++) { bmin[k] = fmin(bmin[k], m->pos[3 * v + k]); bmax[k] = fmax(bmax[k], m->pos[3 * v + k]); }
    for (int k = 0; k < 3; k++) {
        lo[k] = bmin[k] + c->box[k] * (bmax[k] - bmin[k]);
        hi[k] = bmin[k] + c->box[k + 3] * (bmax[k] - bmin[k]);
    }
}

/* box (may be NULL): the interest box of an adaptive case, for drawing. */
static int load(const img_case *c, st_hier *h, float box[6])
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", c->shared ? STRATA_SHARED_DATA : STRATA_ASSETS, c->file);
    st_mesh mesh;
    st_error err;
    st_mesh_init(&mesh);
    if (st_mesh_load(path, &mesh, &err)) {
        if (c->shared) { tl_skip("%s not available: %s", path, c->name); return 1; }
        CHECKF(0, "%s", err.msg);
        return -1;
    }
    int rc = st_hier_init(h, &mesh, st_scheme_get(c->scheme), NULL, &err);
    if (!rc && is_adaptive(c)) {
        st_adapt_params p = { .base_level = 0, .max_level = c->levels, .has_box = 1 };
        adaptive_box(c, &mesh, p.box_lo, p.box_hi);
        for (int k = 0; box && k < 3; k++) { box[k] = (float)p.box_lo[k]; box[k + 3] = (float)p.box_hi[k]; }
        st_adapt a;
        rc = st_adapt_init(&a, h, &err);
        if (!rc) rc = st_adapt_update(&a, &p, &err);
        if (!rc) st_adapt_free(&a);
    } else if (!rc) {
        rc = st_hier_subdivide_to(h, c->levels, &err);
    }
    st_mesh_free(&mesh);
    CHECKF(rc == ST_OK, "%s: %s", c->name, err.msg);
    return rc ? -1 : 0;
}

static st_render_spec spec_of(const img_case *c)
{
    st_render_spec s = st_render_spec_default();
    s.level = c->levels;
    s.mode = c->mode;
    s.view = c->view;
    s.az = c->az;
    s.el = c->el;
    return s;
}

static void save(const char *name, const char *suffix, const unsigned char *rgba)
{
    char p[1200];
    st_error err;
    snprintf(p, sizeof p, "%s/%s.%s.png", out_dir, name, suffix);
    if (st_png_write(p, W, H, rgba, &err)) fprintf(stderr, "  cannot write %s\n", err.msg);
    else fprintf(stderr, "  %-9s %s\n", suffix, p);
}

/* Compares with the reference; writes actual/expected/diff on a failure.
 * Returns 1 on a match. */
static int compare_with_ref(const char *name, const unsigned char *rgba, int update, st_image_diff *d)
{
    char ref[1200];
    st_error err;
    snprintf(ref, sizeof ref, "%s/%s.png", STRATA_RENDER_REF, name);
    if (update) {
        int rc = st_png_write(ref, W, H, rgba, &err);
        CHECKF(rc == ST_OK, "%s", err.msg);
        printf("updated %s\n", ref);
        return 1;
    }
    int w, h;
    unsigned char *exp = NULL;
    if (st_png_read(ref, &w, &h, &exp, &err)) {
        CHECKF(0, "%s: no reference image (%s); to create it on purpose: STRATA_UPDATE_REFS=1 ctest -R render", name, err.msg);
        save(name, "actual", rgba);
        return 0;
    }
    if (w != W || h != H) {
        CHECKF(0, "%s: reference is %dx%d, rendering %dx%d", name, w, h, W, H);
        free(exp);
        return 0;
    }
    unsigned char *diff = malloc((size_t)W * H * 4);
    st_image_compare(rgba, exp, W, H, ST_IMAGE_TOL, d, diff);
    int ok = st_image_match(d, ST_IMAGE_MAX_FRACTION);
    if (!ok) {
        fprintf(stderr, "%s: %llu of %llu pixels (%.3f%%) differ by more than %d (max %d); limit %.1f%%\n", name,
                (unsigned long long)d->differing, (unsigned long long)d->pixels, 100 * d->fraction, ST_IMAGE_TOL,
                d->max_delta, 100 * ST_IMAGE_MAX_FRACTION);
        save(name, "actual", rgba);
        save(name, "expected", exp);
        save(name, "diff", diff);
    }
    free(diff);
    free(exp);
    return ok;
}

static void test_matrix(st_offscreen *o, int update)
{
    unsigned char *rgba = malloc((size_t)W * H * 4);
    unsigned passed = 0, skipped = 0;
    double worst = 0;
    int worst_delta = 0;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const img_case *c = &cases[i];
        st_hier h;
        float box[6];
        int rc = load(c, &h, box);
        if (rc) { skipped += rc > 0; continue; }
        st_render_spec s = spec_of(c);
        if (is_adaptive(c)) {
            s.level = h.map.top;
            s.has_box = 1;
            memcpy(s.box, box, sizeof box);
        }
        st_error err;
        rc = st_offscreen_prepare(o, &h.map, &s, &err);
        if (!rc) rc = st_offscreen_draw(o, &s, rgba, &err);
        CHECKF(rc == ST_OK, "%s: %s", c->name, err.msg);
        st_image_diff d = { 0 };
        if (!rc) {
            int ok = compare_with_ref(c->name, rgba, update, &d);
            CHECKF(ok, "%s: differs from its reference", c->name);
            passed += ok;
            if (d.fraction > worst) worst = d.fraction;
            if (d.max_delta > worst_delta) worst_delta = d.max_delta;
        }
        st_hier_free(&h);
    }
    printf("image matrix: %u of %zu images match (%u skipped); worst differing fraction %.4f%% (limit %.1f%%), "
           "largest channel difference %d (tolerance %d)\n",
           passed, sizeof cases / sizeof cases[0], skipped, 100 * worst, 100 * ST_IMAGE_MAX_FRACTION, worst_delta, ST_IMAGE_TOL);
    free(rgba);
}

/* The comparison catches wrong images and accepts tiny differences. */
static void test_comparison_catches(st_offscreen *o)
{
    const img_case *c = &cases[0];                 /* cube, Catmull-Clark level 1, smooth, iso */
    st_hier h;
    if (load(c, &h, NULL)) return;
    st_render_spec s = spec_of(c);
    st_error err;
    unsigned char *a = malloc((size_t)W * H * 4), *b = malloc((size_t)W * H * 4);
    CHECK(st_offscreen_prepare(o, &h.map, &s, &err) == ST_OK);
    CHECK(st_offscreen_draw(o, &s, a, &err) == ST_OK);
    /* Same inputs, same image, to the byte. */
    CHECK(st_offscreen_prepare(o, &h.map, &s, &err) == ST_OK);
    CHECK(st_offscreen_draw(o, &s, b, &err) == ST_OK);
    st_image_diff d;
    st_image_compare(a, b, W, H, 0, &d, NULL);
    CHECKF(d.differing == 0 && d.max_delta == 0, "rendering twice: %llu pixels differ", (unsigned long long)d.differing);
    /* Noise within the tolerance passes. */
    uint64_t rng = 7;
    for (size_t i = 0; i < (size_t)W * H * 4; i++) {
        int v = b[i] + (int)(tl_rand(&rng) % 7) - 3;
        b[i] = (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
    }
    st_image_compare(a, b, W, H, ST_IMAGE_TOL, &d, NULL);
    CHECKF(st_image_match(&d, ST_IMAGE_MAX_FRACTION), "noise of +-3 fails the comparison (%.3f%%)", 100 * d.fraction);

    /* A missing face: drop the triangles of the face most turned to the eye. */
    st_camera cam;
    st_offscreen_camera(o, &s, &cam);
    float eye[3];
    st_camera_eye(&cam, eye);
    st_rgeom *g = &o->r.surf;
    uint32_t best = 0;
    double bd = -1e30;
    for (uint32_t f = 0; f < g->nfaces; f++) {
        const float *n = g->fnormal + 4 * (size_t)f;
        const float *p = g->vdata + ST_RGEOM_VSTRIDE * (size_t)g->corner[g->face_off[f]];
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        double dd = ((eye[0] - p[0]) * n[0] + (eye[1] - p[1]) * n[1] + (eye[2] - p[2]) * n[2]) / len;
        if (dd > bd) { bd = dd; best = f; }
    }
    uint32_t k = 0;
    for (uint32_t t = 0; t < g->ntris; t++) {
        if (g->tri_face[t] == best) continue;
        memmove(g->tris + 3 * (size_t)k, g->tris + 3 * (size_t)t, 3 * sizeof *g->tris);
        g->tri_face[k++] = g->tri_face[t];
    }
    g->ntris = k;
    st_renderer_reupload(&o->r);
    CHECK(st_offscreen_draw(o, &s, b, &err) == ST_OK);
    st_image_compare(b, a, W, H, ST_IMAGE_TOL, &d, NULL);
    CHECKF(!st_image_match(&d, ST_IMAGE_MAX_FRACTION), "a missing face passes the comparison (%.3f%% differ)", 100 * d.fraction);
    printf("missing face: %.2f%% of the pixels differ (limit %.1f%%): caught\n", 100 * d.fraction, 100 * ST_IMAGE_MAX_FRACTION);
    save("negative_missing_face", "actual", b);
    /* ...and against the stored reference too, as the matrix compares. */
    unsigned char *diff = malloc((size_t)W * H * 4);
    st_image_compare(b, a, W, H, ST_IMAGE_TOL, &d, diff);
    save("negative_missing_face", "diff", diff);

    /* A camera turned by 2 degrees. */
    CHECK(st_offscreen_prepare(o, &h.map, &s, &err) == ST_OK);
    st_render_spec moved = s;
    moved.view = -1;
    st_view_angles(s.view, &moved.az, &moved.el);
    moved.az += 2;
    CHECK(st_offscreen_draw(o, &moved, b, &err) == ST_OK);
    st_image_compare(b, a, W, H, ST_IMAGE_TOL, &d, diff);
    CHECKF(!st_image_match(&d, ST_IMAGE_MAX_FRACTION), "a camera moved by 2 degrees passes (%.3f%% differ)", 100 * d.fraction);
    printf("camera turned by 2 degrees: %.2f%% of the pixels differ: caught\n", 100 * d.fraction);
    save("negative_camera", "actual", b);
    save("negative_camera", "diff", diff);
    /* The orbit form with the preset's own angles gives the preset's image. */
    moved.az -= 2;
    CHECK(st_offscreen_draw(o, &moved, b, &err) == ST_OK);
    st_image_compare(b, a, W, H, 0, &d, NULL);
    CHECKF(d.differing == 0, "--orbit with the iso angles differs from --view iso (%llu pixels)", (unsigned long long)d.differing);
    free(diff);
    free(a);
    free(b);
    st_hier_free(&h);
}

/* Selection, hover and the interest box draw (API for the window). */
static void test_overlays(st_offscreen *o)
{
    st_hier h;
    if (load(&cases[4], &h, NULL)) return;                /* cube, cage mode */
    st_render_spec s = spec_of(&cases[4]);
    st_error err;
    unsigned char *a = malloc((size_t)W * H * 4), *b = malloc((size_t)W * H * 4);
    CHECK(st_offscreen_prepare(o, &h.map, &s, &err) == ST_OK);
    CHECK(st_offscreen_draw(o, &s, a, &err) == ST_OK);
    uint32_t sel[2] = { 0, 1 };
    CHECK(st_renderer_set_selection(&o->r, sel, 2) == 0);
    st_renderer_set_hover(&o->r, 6);
    CHECK(st_offscreen_draw(o, &s, b, &err) == ST_OK);
    st_image_diff d;
    st_image_compare(a, b, W, H, ST_IMAGE_TOL, &d, NULL);
    CHECKF(d.differing > 20, "selected and hovered vertices change only %llu pixels", (unsigned long long)d.differing);
    save("overlay_selection", "actual", b);
    s.has_box = 1;
    float box[6] = { 0.6f, 0.6f, 0.6f, 1.1f, 1.1f, 1.1f };
    memcpy(s.box, box, sizeof box);
    CHECK(st_offscreen_draw(o, &s, b, &err) == ST_OK);
    st_image_compare(a, b, W, H, ST_IMAGE_TOL, &d, NULL);
    CHECKF(d.differing > 50, "the interest box changes only %llu pixels", (unsigned long long)d.differing);
    save("overlay_box", "actual", b);
    free(a);
    free(b);
    st_hier_free(&h);
}

static int compare_files(const char *e, const char *a)
{
    int w1, h1, w2, h2;
    unsigned char *p = NULL, *q = NULL;
    st_error err;
    if (st_png_read(e, &w1, &h1, &p, &err) || st_png_read(a, &w2, &h2, &q, &err)) {
        fprintf(stderr, "compare: %s\n", err.msg);
        free(p);
        return 2;
    }
    if (w1 != w2 || h1 != h2) {
        fprintf(stderr, "compare: sizes differ: %dx%d and %dx%d\n", w1, h1, w2, h2);
        free(p); free(q);
        return 1;
    }
    st_image_diff d;
    st_image_compare(q, p, w1, h1, ST_IMAGE_TOL, &d, NULL);
    int ok = st_image_match(&d, ST_IMAGE_MAX_FRACTION);
    printf("compare: %s vs %s: %.3f%% of pixels differ by more than %d (max %d): %s\n", a, e, 100 * d.fraction,
           ST_IMAGE_TOL, d.max_delta, ok ? "match" : "DIFFERENT");
    free(p);
    free(q);
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "--compare")) return compare_files(argv[2], argv[3]);
    const char *u = getenv("STRATA_UPDATE_REFS");
    int update = u && *u && strcmp(u, "0");
    snprintf(out_dir, sizeof out_dir, "%s/render_out", STRATA_TMP);
    mkdir(out_dir, 0777);
    st_offscreen o;
    st_error err;
    int rc = st_offscreen_init(&o, W, H, &err);
    CHECKF(rc == ST_OK, "headless context: %s", err.msg);
    if (rc) return TEST_END();
    test_matrix(&o, update);
    test_comparison_catches(&o);
    test_overlays(&o);
    st_offscreen_free(&o);
    return TEST_END();
}
