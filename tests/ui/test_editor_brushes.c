/* The brush set of the modeller's document, headless (ui/editor.h,
 * ui/brush.c, ui/brush_tools.c, ui/brush_stroke.c): every brush's direction
 * and magnitude on a flat grid and on a sphere, the falloff presets' shapes,
 * symmetry across X, Y, Z and all three keeping a symmetric mesh symmetric,
 * front faces only, dab spacing independent of the event rate, the
 * stabiliser, each tool's own strength and falloff, and undo/redo of a
 * stroke with each brush bit for bit. */
#include "editor.h"
#include "core/multires/hier_internal.h" /* st_hier_detail */
#include "testlib.h"
#include "editor_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *cube = STRATA_ASSETS "/cube.obj";
static const char *sphere = STRATA_SHARED_DATA "/triangle/sphere_ico.obj";

static double norm3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* A brush set to `tool` with the given radius and strength, smooth falloff,
 * no symmetry, viewed along -n (front faces only on). */
static void brush_set(st_doc *d, int tool, double R, double s, const double n[3])
{
    st_brush_set_tool(&d->brush, tool);
    d->brush.radius = R;
    d->brush.strength = s;
    d->brush.falloff = ST_FALLOFF_SMOOTH;
    d->brush.mirror_x = d->brush.mirror_y = d->brush.mirror_z = 0;
    d->brush.invert = 0;
    d->brush.front_only = 1;
    double len = norm3(n);
    for (int k = 0; k < 3; k++) d->brush.view_dir[k] = -n[k] / len;
}

static void one_dab(st_doc *d, const double c[3], const double n[3], const double g[3])
{
    CHECK(st_doc_stroke_begin(d) == 0);
    CHECK(st_doc_stroke_dab(d, c, n, g) == 0);
    st_doc_stroke_end(d);
}

/* Positions of the editing level, by index into v. */
static double (*positions(const st_doc *d, const uint32_t *v, uint32_t n))[3]
{
    double (*p)[3] = malloc((size_t)n * sizeof *p);
    for (uint32_t i = 0; i < n; i++) st_doc_vertex_pos(d, v[i], p[i]);
    return p;
}

/* ---- falloff presets ------------------------------------------------------------ */

static void test_falloffs(void)
{
    /* Blender's curves of t = 1 - r/R (smooth: Strata's (1 - q^2)^2). */
    static const double at_half[ST_FALLOFF_COUNT] = { 0.5625, 0.86602540378443865, 0.70710678118654752, 0.25, 0.5, 1 };
    for (int k = 0; k < ST_FALLOFF_COUNT; k++) {
        const char *name = st_falloff_name(k);
        CHECKF(st_falloff_by_name(name) == k, "%s", name);
        CHECKF(st_falloff_eval(k, 0, 2) == 1, "%s at 0: %g", name, st_falloff_eval(k, 0, 2));
        CHECKF(fabs(st_falloff_eval(k, 1, 2) - at_half[k]) < 1e-15, "%s at R/2: %.17g", name, st_falloff_eval(k, 1, 2));
        CHECKF(st_falloff_eval(k, 2, 2) == 0 && st_falloff_eval(k, 3, 2) == 0, "%s at and past R", name);
        CHECKF(st_falloff_eval(k, 0.5, 0) == 0, "%s with radius 0", name);
        double prev = 1;
        int monotone = 1, in_range = 1;
        for (int i = 0; i <= 1000; i++) {
            double f = st_falloff_eval(k, 2.0 * i / 1000, 2);
            if (f > prev) monotone = 0;
            if (!(f >= 0 && f <= 1)) in_range = 0;
            prev = f;
        }
        CHECKF(monotone && in_range, "%s: monotone %d, in [0,1] %d", name, monotone, in_range);
    }
    CHECK(st_falloff_by_name("wobbly") == -1);
    CHECK(st_brush_falloff(1, 2) == st_falloff_eval(ST_FALLOFF_SMOOTH, 1, 2));
    /* Near R: sharp falls faster than linear, root and sphere slower. */
    CHECK(st_falloff_eval(ST_FALLOFF_SHARP, 1.8, 2) < st_falloff_eval(ST_FALLOFF_LINEAR, 1.8, 2));
    CHECK(st_falloff_eval(ST_FALLOFF_ROOT, 1.8, 2) > st_falloff_eval(ST_FALLOFF_LINEAR, 1.8, 2));
    CHECK(st_falloff_eval(ST_FALLOFF_SPHERE, 1.8, 2) > st_falloff_eval(ST_FALLOFF_LINEAR, 1.8, 2));
    /* The brush weighs by its falloff: a draw dab with each preset moves a
     * vertex at r by strength * f(r) * R/10 (flat grid, below). */
}

/* ---- flat grid -------------------------------------------------------------------- */

/* An n x n quad grid over [-1, 1]^2 in z = 0, written as OBJ. */
static void write_grid(const char *path, unsigned n)
{
    size_t cap = (size_t)(n + 1) * (n + 1) * 64 + (size_t)n * n * 64, len = 0;
    char *s = malloc(cap);
    for (unsigned j = 0; j <= n; j++)
        for (unsigned i = 0; i <= n; i++)
            len += (size_t)snprintf(s + len, cap - len, "v %.17g %.17g 0\n", -1 + 2.0 * i / n, -1 + 2.0 * j / n);
    for (unsigned j = 0; j < n; j++)
        for (unsigned i = 0; i < n; i++) {
            unsigned a = j * (n + 1) + i + 1;
            len += (size_t)snprintf(s + len, cap - len, "f %u %u %u %u\n", a, a + 1, a + n + 2, a + n + 1);
        }
    CHECK(tl_write_file(path, s, len) == 0);
    free(s);
}

static char grid_path[1024];

static void open_grid(st_doc *d)
{
    st_doc_init(d);
    ed_test_open(d, grid_path, "catmull-clark", 1);
    st_doc_set_edit_level(d, 0);
}

/* Every brush on a flat grid: a dab at the origin with the normal +z. */
static void test_grid_brushes(void)
{
    const double up[3] = { 0, 0, 1 }, c[3] = { 0, 0, 0 };
    const double R = 0.5, s = 0.5;
    for (int tool = 0; tool < ST_BRUSH_COUNT; tool++) {
        for (int inv = 0; inv < 2; inv++) {
            st_doc d;
            open_grid(&d);
            uint32_t *v, n = ed_test_level_vertices(&d, 0, &v);
            double (*p0)[3] = positions(&d, v, n);
            brush_set(&d, tool, R, s, up);
            d.brush.invert = inv;
            double sg = inv ? -1 : 1, g[3] = { 0.1, -0.05, 0.02 };
            one_dab(&d, c, up, g);
            double (*p1)[3] = positions(&d, v, n);
            const char *name = st_brush_name(tool);
            double worst = 0;
            int outside_still = 1;
            for (uint32_t i = 0; i < n; i++) {
                double r = ed_test_dist3(p0[i], c), w = s * st_brush_falloff(r, R), want[3] = { 0, 0, 0 };
                double d3[3] = { p1[i][0] - p0[i][0], p1[i][1] - p0[i][1], p1[i][2] - p0[i][2] };
                if (r >= R && (d3[0] || d3[1] || d3[2])) outside_still = 0;
                switch (tool) {
                case ST_BRUSH_GRAB: for (int k = 0; k < 3; k++) want[k] = w * g[k]; break;
                case ST_BRUSH_DRAW: case ST_BRUSH_INFLATE: case ST_BRUSH_CLAY_STRIPS:
                    /* on a flat sheet all three raise by w R/10 (clay strips:
                     * the plane z = sgn R/10, every vertex below it) */
                    want[2] = sg * w * R / 10;
                    break;
                case ST_BRUSH_CREASE:
                    want[0] = -0.5 * w * p0[i][0];
                    want[1] = -0.5 * w * p0[i][1];
                    want[2] = -sg * w * R / 10;
                    break;
                case ST_BRUSH_PINCH:
                    want[0] = -sg * 0.5 * w * p0[i][0];
                    want[1] = -sg * 0.5 * w * p0[i][1];
                    break;
                case ST_BRUSH_LAYER: want[2] = sg * w * R / 10; break;
                default: continue; /* smooth, flatten, relax: a flat sheet stays (below) */
                }
                for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(d3[k] - want[k]));
            }
            CHECKF(worst < 1e-15, "%s%s on a flat grid: off by %g", name, inv ? " inverted" : "", worst);
            CHECKF(outside_still, "%s moved a vertex outside the radius", name);
            if (tool == ST_BRUSH_SMOOTH || tool == ST_BRUSH_FLATTEN || tool == ST_BRUSH_RELAX) {
                /* A regular flat grid is already smooth, flat and relaxed. */
                double most = 0;
                for (uint32_t i = 0; i < n; i++) most = fmax(most, ed_test_dist3(p0[i], p1[i]));
                CHECKF(most < 1e-15, "%s moved a regular flat grid by %g", name, most);
            }
            free(p0);
            free(p1);
            free(v);
            st_doc_free(&d);
        }
    }
}

/* Falloff presets through a draw dab: the vertex at r moves by s f(r) R/10. */
static void test_grid_falloffs(void)
{
    const double up[3] = { 0, 0, 1 }, c[3] = { 0, 0, 0 }, R = 0.55, s = 0.8;
    for (int k = 0; k < ST_FALLOFF_COUNT; k++) {
        st_doc d;
        open_grid(&d);
        uint32_t *v, n = ed_test_level_vertices(&d, 0, &v);
        double (*p0)[3] = positions(&d, v, n);
        brush_set(&d, ST_BRUSH_DRAW, R, s, up);
        d.brush.falloff = k;
        one_dab(&d, c, up, NULL);
        double (*p1)[3] = positions(&d, v, n), worst = 0;
        for (uint32_t i = 0; i < n; i++)
            worst = fmax(worst, fabs(p1[i][2] - p0[i][2] - s * st_falloff_eval(k, ed_test_dist3(p0[i], c), R) * R / 10));
        CHECKF(worst < 1e-15, "draw with falloff %s: off by %g", st_falloff_name(k), worst);
        free(p0);
        free(p1);
        free(v);
        st_doc_free(&d);
    }
}

/* Clay strips builds a flat top and leaves what stands above it; layer
 * rises to its height once per stroke, however many dabs; relax slides
 * vertices in the plane, never out of it. */
static void test_grid_build_up(void)
{
    const double up[3] = { 0, 0, 1 }, c[3] = { 0, 0, 0 }, R = 0.5;
    st_doc d;
    open_grid(&d);
    uint32_t *v = NULL, n = ed_test_level_vertices(&d, 0, &v);
    double (*p0)[3] = positions(&d, v, n);
    /* Clay strips, strength 1, constant falloff: one dab lifts everything
     * under it to z = R/10 exactly: a flat top. */
    brush_set(&d, ST_BRUSH_CLAY_STRIPS, R, 1, up);
    d.brush.falloff = ST_FALLOFF_CONSTANT;
    one_dab(&d, c, up, NULL);
    double (*p1)[3] = positions(&d, v, n), worst = 0;
    for (uint32_t i = 0; i < n; i++)
        if (ed_test_dist3(p0[i], c) < R) worst = fmax(worst, fabs(p1[i][2] - R / 10));
    CHECKF(worst < 1e-15, "clay strips: top not flat at R/10 (off by %g)", worst);
    /* A spike above the clay plane stays where it is. */
    st_error err;
    while (st_doc_undo(&d, &err) == 0) {}
    uint32_t top = ST_NIL;
    for (uint32_t i = 0; i < n; i++) if (ed_test_dist3(p0[i], c) == 0) top = v[i];
    CHECK(top != ST_NIL);
    uint32_t x = st_doc_vertex_dart(&d, top);
    const double spike[1][3] = { { 0, 0, 0.3 } };
    st_hier_move(&d.h, 0, &x, spike, 1);
    double before[3], after[3];
    st_doc_vertex_pos(&d, top, before);
    d.brush.falloff = ST_FALLOFF_SMOOTH;
    one_dab(&d, c, up, NULL);
    st_doc_vertex_pos(&d, top, after);
    CHECKF(memcmp(before, after, sizeof before) == 0, "clay strips moved the spike above its plane by %g",
           after[2] - before[2]);
    st_doc_free(&d);

    /* Layer: five dabs in one stroke rise to the height of one. */
    open_grid(&d);
    brush_set(&d, ST_BRUSH_LAYER, R, 0.6, up);
    CHECK(st_doc_stroke_begin(&d) == 0);
    for (int k = 0; k < 5; k++) CHECK(st_doc_stroke_dab(&d, c, up, NULL) == 0);
    double q[3] = { 0.1, 0.05, 0 };
    double (*pm)[3] = positions(&d, v, n); /* the second dab weighs by distances to these */
    CHECK(st_doc_stroke_dab(&d, q, up, NULL) == 0); /* beside: only where it asks more */
    st_doc_stroke_end(&d);
    free(p1);
    p1 = positions(&d, v, n);
    worst = 0;
    for (uint32_t i = 0; i < n; i++) {
        double h = 0.6 * fmax(st_brush_falloff(ed_test_dist3(p0[i], c), R), st_brush_falloff(ed_test_dist3(pm[i], q), R)) * R / 10;
        /* along the normal each vertex had when the stroke reached it (up
         * at first; tilted where the second dab reached it first) */
        worst = fmax(worst, fabs(ed_test_dist3(p1[i], p0[i]) - h));
        if (ed_test_dist3(p0[i], c) < R) worst = fmax(worst, fabs(p1[i][2] - h));
    }
    CHECKF(worst < 1e-15, "layer: heights off the cap by %g", worst);
    free(pm);
    /* A new stroke builds another layer on top (along the normal there now). */
    double cb[3], ct[3];
    st_doc_vertex_pos(&d, top, cb);
    one_dab(&d, cb, up, NULL);
    st_doc_vertex_pos(&d, top, ct);
    CHECKF(fabs(ed_test_dist3(ct, cb) - 0.6 * R / 10) < 1e-15 && ct[2] > cb[2], "layer: second stroke moved %g", ed_test_dist3(ct, cb));
    st_doc_free(&d);

    /* Relax: in-plane jitter evens out, z stays 0 exactly. */
    open_grid(&d);
    uint64_t rng = 7;
    uint32_t *darts = malloc(n * sizeof *darts), m = 0;
    double (*pos)[3] = malloc(n * sizeof *pos);
    for (uint32_t i = 0; i < n; i++) {
        if (ed_test_dist3(p0[i], c) >= R) continue;
        darts[m] = st_doc_vertex_dart(&d, v[i]);
        pos[m][0] = p0[i][0] + 0.03 * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        pos[m][1] = p0[i][1] + 0.03 * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        pos[m][2] = 0;
        m++;
    }
    st_hier_move(&d.h, 0, darts, (const double(*)[3])pos, m);
    free(p1);
    p1 = positions(&d, v, n);
    double err0 = 0, err1 = 0;
    for (uint32_t i = 0; i < n; i++) if (ed_test_dist3(p0[i], c) < R / 2) err0 += ed_test_dist3(p0[i], p1[i]);
    brush_set(&d, ST_BRUSH_RELAX, R, 1, up);
    CHECK(st_doc_stroke_begin(&d) == 0);
    for (int k = 0; k < 6; k++) CHECK(st_doc_stroke_dab(&d, c, up, NULL) == 0);
    st_doc_stroke_end(&d);
    double (*p2)[3] = positions(&d, v, n), zmax = 0;
    for (uint32_t i = 0; i < n; i++) {
        zmax = fmax(zmax, fabs(p2[i][2]));
        if (ed_test_dist3(p0[i], c) < R / 2) err1 += ed_test_dist3(p0[i], p2[i]);
    }
    CHECKF(zmax == 0, "relax left the plane by %g", zmax);
    CHECKF(err1 < 0.5 * err0, "relax: distance to the regular grid %g -> %g", err0, err1);
    free(p2);
    free(darts);
    free(pos);
    free(p1);
    free(p0);
    free(v);
    st_doc_free(&d);
}

/* ---- sphere ------------------------------------------------------------------------ */

/* Every brush at the top of a unit sphere (162 vertices), normal and view
 * along the radius: direction and magnitude of the top vertex's motion. */
static void test_sphere_brushes(void)
{
    const double R = 0.6, s = 0.5;
    double shrink_smooth = 0, shrink_relax = 0;
    for (int tool = 0; tool < ST_BRUSH_COUNT; tool++) {
        st_doc d;
        st_doc_init(&d);
        ed_test_open(&d, sphere, "loop", 1);
        st_doc_set_edit_level(&d, 0);
        const double dir[3] = { 0.1, 0.2, 1 };
        uint32_t t = ed_test_extreme_vertex(&d, dir);
        double c[3];
        st_doc_vertex_pos(&d, t, c);
        double n[3] = { c[0] / norm3(c), c[1] / norm3(c), c[2] / norm3(c) };
        uint32_t *v, nv = ed_test_level_vertices(&d, 0, &v);
        double (*p0)[3] = positions(&d, v, nv);
        brush_set(&d, tool, R, s, n);
        double g[3] = { 0.05, 0.02, 0.04 };
        one_dab(&d, c, n, g);
        double (*p1)[3] = positions(&d, v, nv);
        const char *name = st_brush_name(tool);
        double ct[3];
        st_doc_vertex_pos(&d, t, ct);
        double dv[3] = { ct[0] - c[0], ct[1] - c[1], ct[2] - c[2] };
        double radial = dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2], len = norm3(dv);
        /* Mean change of the distance to the centre under the brush. */
        double dr = 0;
        unsigned under = 0, closer = 0, pinched = 0;
        for (uint32_t i = 0; i < nv; i++) {
            if (ed_test_dist3(p0[i], c) >= R) continue;
            under++;
            dr += norm3(p1[i]) - norm3(p0[i]);
            if (v[i] != t && ed_test_dist3(p1[i], c) < ed_test_dist3(p0[i], c) - 1e-9) closer++;
            if (v[i] != t) pinched++;
        }
        dr /= under;
        switch (tool) {
        case ST_BRUSH_GRAB:
            CHECKF(fabs(dv[0] - s * g[0]) < 1e-15 && fabs(dv[1] - s * g[1]) < 1e-15 && fabs(dv[2] - s * g[2]) < 1e-15,
                   "grab moved the top by %g, expected %g", len, s * norm3(g));
            break;
        case ST_BRUSH_DRAW:
            CHECKF(fabs(radial - s * R / 10) < 1e-15 && fabs(len - s * R / 10) < 1e-15, "%s: top moved %g (radial %g)",
                   name, len, radial);
            break;
        case ST_BRUSH_INFLATE: case ST_BRUSH_LAYER:
            /* along its own normal: nearly radial, by s R/10 exactly */
            CHECKF(fabs(len - s * R / 10) < 1e-15 && radial > 0.99 * len, "%s: top moved %g (radial %g)", name, len, radial);
            CHECKF(dr > 0, "%s: the cap moved inward (%g)", name, dr);
            break;
        case ST_BRUSH_CREASE:
            CHECKF(fabs(radial + s * R / 10) < 1e-15, "crease: top moved %g radially", radial);
            CHECKF(closer == pinched, "crease: %u of %u vertices came closer to the centre", closer, pinched);
            break;
        case ST_BRUSH_PINCH:
            CHECKF(len < 1e-15, "pinch moved the centre vertex by %g", len);
            CHECKF(closer == pinched && pinched > 3, "pinch: %u of %u vertices came closer", closer, pinched);
            break;
        case ST_BRUSH_SMOOTH: case ST_BRUSH_FLATTEN:
            CHECKF(radial < -1e-4 && dr < 0, "%s: top moved %g radially (cap %g)", name, radial, dr);
            if (tool == ST_BRUSH_SMOOTH) shrink_smooth = -dr;
            break;
        case ST_BRUSH_CLAY_STRIPS:
            /* the cap's rim rises to the raised plane; nothing goes down */
            CHECKF(dr > 0 && radial >= -1e-15, "clay strips: cap %g, top %g", dr, radial);
            break;
        case ST_BRUSH_RELAX:
            shrink_relax = fabs(dr);
            break;
        default: break;
        }
        free(p0);
        free(p1);
        free(v);
        st_doc_free(&d);
    }
    /* Relax keeps the shape: it moves the cap off the sphere far less than
     * smooth does. */
    CHECKF(shrink_relax < 0.1 * shrink_smooth, "relax changed the radius by %g, smooth by %g", shrink_relax, shrink_smooth);
}

/* Front faces only: a dab whose radius covers the whole sphere moves only
 * the half that faces the viewer; switched off it reaches the back. */
static void test_front_faces(void)
{
    for (int front = 0; front < 2; front++) {
        st_doc d;
        st_doc_init(&d);
        ed_test_open(&d, sphere, "loop", 1);
        st_doc_set_edit_level(&d, 0);
        const double up[3] = { 0, 0, 1 };
        uint32_t t = ed_test_extreme_vertex(&d, up);
        double c[3];
        st_doc_vertex_pos(&d, t, c);
        uint32_t *v, n = ed_test_level_vertices(&d, 0, &v);
        double (*p0)[3] = positions(&d, v, n);
        brush_set(&d, ST_BRUSH_INFLATE, 2.5, 1, up);
        d.brush.falloff = ST_FALLOFF_CONSTANT;
        d.brush.front_only = front;
        one_dab(&d, c, up, NULL);
        double (*p1)[3] = positions(&d, v, n);
        unsigned back_moved = 0, front_moved = 0, back = 0;
        for (uint32_t i = 0; i < n; i++) {
            int moved = memcmp(p0[i], p1[i], sizeof p0[i]) != 0;
            if (p0[i][2] < -0.2) { back++; back_moved += moved; }
            if (p0[i][2] > 0.2) front_moved += moved;
        }
        if (front) CHECKF(back_moved == 0 && front_moved > 0, "front faces only: %u of %u back vertices moved", back_moved, back);
        else CHECKF(back_moved == back, "front faces off: %u of %u back vertices moved", back_moved, back);
        free(p0);
        free(p1);
        free(v);
        st_doc_free(&d);
    }
}

/* ---- symmetry ------------------------------------------------------------------------ */

/* Largest distance between a vertex of level l reflected by `which` and the
 * vertex at that reflected place (partner found once, to 1e-9). */
static double asymmetry(const st_doc *d, unsigned l, unsigned which, const uint32_t *partner, const uint32_t *v,
                        uint32_t n)
{
    double worst = 0;
    for (uint32_t i = 0; i < n; i++) {
        double a[3], b[3];
        memcpy(a, st_pos(&d->h.map, v[i], l), sizeof a);
        memcpy(b, st_pos(&d->h.map, v[partner[i]], l), sizeof b);
        for (int k = 0; k < 3; k++) worst = fmax(worst, fabs((which >> k & 1 ? -a[k] : a[k]) - b[k]));
    }
    return worst;
}

static uint32_t *partners(const st_doc *d, unsigned l, unsigned which, const uint32_t *v, uint32_t n)
{
    uint32_t *pt = malloc(n * sizeof *pt), found = 0;
    for (uint32_t i = 0; i < n; i++) {
        const double *a = st_pos(&d->h.map, v[i], l);
        double r[3];
        for (int k = 0; k < 3; k++) r[k] = which >> k & 1 ? -a[k] : a[k];
        pt[i] = i;
        for (uint32_t j = 0; j < n; j++)
            if (ed_test_dist3(r, st_pos(&d->h.map, v[j], l)) < 1e-9) { pt[i] = j; found++; break; }
    }
    CHECKF(found == n, "only %u of %u vertices have a mirror partner", found, n);
    return pt;
}

/* Every brush with symmetry X, Y, Z and XYZ on the Catmull-Clark cube (symmetric
 * about the three planes): a stroke of three dabs off every plane leaves the
 * editing level and the finest level symmetric to 1e-12, and reaches the
 * mirrored places. */
static void test_symmetry(void)
{
    static const unsigned sets[] = { 1, 2, 4, 7 };
    static const char *const set_names[] = { "X", "Y", "Z", "XYZ" };
    for (int si = 0; si < 4; si++) {
        unsigned sym = sets[si];
        for (int tool = 0; tool < ST_BRUSH_COUNT; tool++) {
            st_doc d;
            st_doc_init(&d);
            ed_test_open(&d, cube, "catmull-clark", 3);
            st_doc_set_edit_level(&d, 2);
            uint32_t *v, n = ed_test_level_vertices(&d, 2, &v), *vt, nt = ed_test_level_vertices(&d, 3, &vt);
            uint32_t *pe[8] = { 0 }, *pt[8] = { 0 };
            double before = 0;
            for (unsigned m = 1; m < 8; m++) {
                if (m & ~sym) continue;
                pe[m] = partners(&d, 2, m, v, n);
                pt[m] = partners(&d, 3, m, vt, nt);
                before = fmax(before, asymmetry(&d, 3, m, pt[m], vt, nt));
            }
            double (*p0)[3] = positions(&d, v, n);
            /* Off every plane, on the face z = +max, viewed from outside. */
            const double dir[3] = { 0.45, 0.3, 1 };
            uint32_t cv = ed_test_extreme_vertex(&d, dir);
            double c[3], nrm[3] = { 0.1, 0.1, 1 }, g[3] = { 0.04, -0.03, 0.05 };
            st_doc_vertex_pos(&d, cv, c);
            brush_set(&d, tool, 0.45, 0.7, nrm);
            d.brush.mirror_x = sym & 1;
            d.brush.mirror_y = sym >> 1 & 1;
            d.brush.mirror_z = sym >> 2 & 1;
            CHECK(st_doc_stroke_begin(&d) == 0);
            for (int k = 0; k < 3; k++) {
                CHECK(st_doc_stroke_dab(&d, c, nrm, g) == 0);
                c[1] -= 0.04;
            }
            st_doc_stroke_end(&d);
            double worst = 0, worst_top = 0;
            for (unsigned m = 1; m < 8; m++) {
                if (!pe[m]) continue;
                worst = fmax(worst, asymmetry(&d, 2, m, pe[m], v, n));
                worst_top = fmax(worst_top, asymmetry(&d, 3, m, pt[m], vt, nt));
            }
            CHECKF(worst < 1e-12 && worst_top < 1e-12, "%s with symmetry %s: asymmetry %g (finest level %g, before %g)",
                   st_brush_name(tool), set_names[si], worst, worst_top, before);
            /* Every octant the symmetry reaches moved. */
            double (*p1)[3] = positions(&d, v, n);
            unsigned octants = 0;
            for (uint32_t i = 0; i < n; i++)
                if (memcmp(p0[i], p1[i], sizeof p0[i]))
                    octants |= 1u << ((p0[i][0] < 0) | (p0[i][1] < 0) << 1 | (p0[i][2] < 0) << 2);
            unsigned want = 0;
            for (unsigned m = 0; m < 8; m++) if (!(m & ~sym)) want |= 1u << m;
            CHECKF((octants & want) == want, "%s with symmetry %s: octants moved %x, expected at least %x",
                   st_brush_name(tool), set_names[si], octants, want);
            for (unsigned m = 0; m < 8; m++) { free(pe[m]); free(pt[m]); }
            free(p0);
            free(p1);
            free(v);
            free(vt);
            st_doc_free(&d);
        }
    }
}

/* ---- spacing and stabiliser ---------------------------------------------------------- */

typedef struct dabs { double p[512][3]; unsigned n; } dabs;

static void record(void *ctx, const double p[3])
{
    dabs *r = ctx;
    if (r->n < 512) memcpy(r->p[r->n], p, sizeof r->p[0]);
    r->n++;
}

typedef struct tail_rec { double p[64][3], k[64]; unsigned n; } tail_rec;

static void record_tail(void *ctx, const double p[3], double k)
{
    tail_rec *r = ctx;
    if (r->n < 64) { memcpy(r->p[r->n], p, sizeof r->p[0]); r->k[r->n] = k; }
    r->n++;
}

/* A polyline with corners, as events: `per_edge` events per edge. */
static const double path_pts[][3] = { { 0, 0, 0 }, { 10, 0, 0 }, { 10, 7, 0 }, { 3, 7, 0 }, { 3, 12, 0 } };

static void feed(st_stroke_path *sp, unsigned per_edge, double spacing, double lazy, dabs *out)
{
    st_stroke_path_begin(sp, path_pts[0]);
    for (unsigned e = 0; e + 1 < sizeof path_pts / sizeof path_pts[0]; e++)
        for (unsigned k = 1; k <= per_edge; k++) {
            double q[3];
            for (int j = 0; j < 3; j++) q[j] = path_pts[e][j] + (path_pts[e + 1][j] - path_pts[e][j]) * k / per_edge;
            st_stroke_path_move(sp, q, spacing, lazy, record, out);
        }
}

static void test_spacing(void)
{
    static dabs slow, fast, lazy_slow, lazy_fast, none;
    st_stroke_path sp;
    feed(&sp, 97, 0.75, 0, &slow);
    feed(&sp, 1, 0.75, 0, &fast);
    /* Path length 10 + 7 + 7 + 5 = 29: a dab every 0.75 gives 38. */
    CHECKF(slow.n == 38 && fast.n == 38, "dabs: %u slow, %u fast, expected 38", slow.n, fast.n);
    double worst = 0;
    for (unsigned i = 0; i < slow.n && i < fast.n && i < 512; i++) worst = fmax(worst, ed_test_dist3(slow.p[i], fast.p[i]));
    CHECKF(worst < 1e-12, "spacing: fast and slow dabs differ by %g", worst);
    /* Consecutive dabs on one edge are `spacing` apart. */
    CHECK(fabs(ed_test_dist3(slow.p[0], slow.p[1]) - 0.75) < 1e-12 && fabs(slow.p[0][0] - 0.75) < 1e-12);
    /* The stabiliser: the brush trails the cursor by 2.  Along a straight
     * path the dabs do not depend on the event rate either (at a corner the
     * trailing brush cuts it, by a path that depends on the events, as a
     * lazy mouse does), and they stop 2 short of the cursor. */
    const double a[3] = { 0, 0, 0 }, b[3] = { 12, 5, 0 }; /* length 13 */
    for (int r = 0; r < 2; r++) {
        dabs *out = r ? &lazy_fast : &lazy_slow;
        unsigned events = r ? 2 : 83;
        st_stroke_path_begin(&sp, a);
        for (unsigned k = 1; k <= events; k++) {
            double q[3];
            for (int j = 0; j < 3; j++) q[j] = a[j] + (b[j] - a[j]) * k / events;
            st_stroke_path_move(&sp, q, 0.5, 2, record, out);
        }
    }
    CHECKF(lazy_slow.n == 22 && lazy_fast.n == 22, "lazy: %u slow, %u fast, expected 22", lazy_slow.n, lazy_fast.n);
    worst = 0;
    for (unsigned i = 0; i < lazy_slow.n && i < 512; i++) worst = fmax(worst, ed_test_dist3(lazy_slow.p[i], lazy_fast.p[i]));
    CHECKF(worst < 1e-12, "stabiliser: fast and slow dabs differ by %g", worst);
    double dist_end = ed_test_dist3(sp.brush, b);
    CHECKF(fabs(dist_end - 2) < 1e-12, "the stabilised brush is %g behind the cursor, expected 2", dist_end);
    /* The end of the trailing stroke (fade-out): the dabs still due between
     * the brush point and the cursor, spaced as before, with factors falling
     * from about 1 to 0.1, and the whole path covered: 22 + 4 = 26 dabs at
     * 0.5 over 13. */
    tail_rec tail = { 0 };
    unsigned nt = st_stroke_path_end(&sp, b, 0.5, record_tail, &tail);
    CHECKF(nt == 4 && tail.n == 4, "tail: %u dabs, expected 4", nt);
    int falling = 1;
    for (unsigned i = 1; i < tail.n && i < 64; i++) falling &= tail.k[i] < tail.k[i - 1];
    CHECKF(falling && tail.k[0] > 0.7 && tail.k[0] <= 1 && tail.k[3] >= 0.1 && tail.k[3] < 0.2,
           "tail factors %g %g %g %g", tail.k[0], tail.k[1], tail.k[2], tail.k[3]);
    CHECK(fabs(ed_test_dist3(tail.p[3], b)) < 1e-12 && ed_test_dist3(sp.brush, b) == 0);
    CHECK(fabs(ed_test_dist3(tail.p[0], lazy_slow.p[21]) - 0.5) < 1e-12);
    /* Within the stabiliser's distance nothing moves. */
    st_stroke_path_begin(&sp, path_pts[0]);
    const double near[3] = { 1.5, 0.5, 0 };
    CHECK(st_stroke_path_move(&sp, near, 0.1, 2, record, &none) == 0 && none.n == 0);
    /* No spacing: one dab per event, at the cursor. */
    none.n = 0;
    feed(&sp, 3, 0, 0, &none);
    CHECK(none.n == 12 && ed_test_dist3(none.p[11], path_pts[4]) == 0);
}

/* The same stroke on the grid from fast and slow event sequences: the same
 * dabs, so the same surface (draw accumulates per dab). */
struct grid_ctx { st_doc *d; };
static void grid_dab(void *ctx, const double p[3])
{
    struct grid_ctx *g = ctx;
    const double up[3] = { 0, 0, 1 };
    CHECK(st_doc_stroke_dab(g->d, p, up, NULL) == 0);
}

static void test_spacing_stroke(void)
{
    double (*res[2])[3] = { 0 };
    uint32_t *v = NULL, n = 0;
    static const unsigned rates[2] = { 40, 2 };
    for (int r = 0; r < 2; r++) {
        st_doc d;
        open_grid(&d);
        free(v);
        n = ed_test_level_vertices(&d, 0, &v);
        const double up[3] = { 0, 0, 1 };
        brush_set(&d, ST_BRUSH_DRAW, 0.3, 0.5, up);
        struct grid_ctx g = { &d };
        st_stroke_path sp;
        const double a[3] = { -0.6, -0.2, 0 }, b[3] = { 0.6, 0.3, 0 };
        CHECK(st_doc_stroke_begin(&d) == 0);
        st_stroke_path_begin(&sp, a);
        grid_dab(&g, a);
        for (unsigned k = 1; k <= rates[r]; k++) {
            double q[3];
            for (int j = 0; j < 3; j++) q[j] = a[j] + (b[j] - a[j]) * k / rates[r];
            st_stroke_path_move(&sp, q, 0.1 * d.brush.radius, 0, grid_dab, &g);
        }
        st_doc_stroke_end(&d);
        res[r] = positions(&d, v, n);
        st_doc_free(&d);
    }
    double worst = 0;
    for (uint32_t i = 0; i < n; i++) worst = fmax(worst, ed_test_dist3(res[0][i], res[1][i]));
    CHECKF(worst < 1e-12, "a stroke from 40 and from 2 events differs by %g", worst);
    free(res[0]);
    free(res[1]);
    free(v);
}

/* The fade-out (st_doc_stroke_fade_out): the same stroke whose last dabs
 * get factors 0.8 .. 0.1 moves the surface there less than at full
 * strength, and nothing else changes (before them the surfaces are equal). */
static void test_fade_out(void)
{
    double (*res[2])[3] = { 0 };
    uint32_t *v = NULL, n = 0;
    static const double ks[4] = { 0.8, 0.5, 0.25, 0.1 };
    for (int r = 0; r < 2; r++) {
        st_doc d;
        open_grid(&d);
        free(v);
        n = ed_test_level_vertices(&d, 0, &v);
        const double up[3] = { 0, 0, 1 };
        brush_set(&d, ST_BRUSH_DRAW, 0.3, 0.5, up);
        d.brush.fade = 1;
        CHECK(st_doc_stroke_begin(&d) == 0);
        for (int k = 0; k <= 12; k++) {
            double p[3] = { -0.6 + 0.1 * k, 0, 0 };
            if (k >= 9 && r) st_doc_stroke_fade_out(&d, ks[k - 9]);
            CHECK(st_doc_stroke_dab(&d, p, up, NULL) == 0);
        }
        st_doc_stroke_end(&d);
        res[r] = positions(&d, v, n);
        st_doc_free(&d);
    }
    /* Heights (z) at the stroke's end (x = 0.6) and at its start (x = -0.6). */
    double end_full = 0, end_faded = 0, start_diff = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (fabs(res[0][i][0] - 0.6) < 0.05 && fabs(res[0][i][1]) < 0.05) {
            end_full = fmax(end_full, res[0][i][2]);
            end_faded = fmax(end_faded, res[1][i][2]);
        }
        if (res[0][i][0] < -0.55) start_diff = fmax(start_diff, ed_test_dist3(res[0][i], res[1][i]));
    }
    CHECKF(end_faded < 0.6 * end_full && end_faded > 0, "fade-out: the end raised %g against %g at full strength", end_faded,
           end_full);
    CHECKF(start_diff == 0, "fade-out changed the stroke's start by %g", start_diff);
    free(res[0]);
    free(res[1]);
    free(v);
}

/* ---- per-tool settings, undo/redo ------------------------------------------------------ */

static void test_tool_settings(void)
{
    st_brush b;
    st_brush_defaults(&b, 0.3);
    CHECK(b.tool == ST_BRUSH_DRAW && b.front_only == 1 && b.falloff == ST_FALLOFF_SMOOTH && b.spacing > 0);
    b.strength = 0.9;
    b.falloff = ST_FALLOFF_SHARP;
    st_brush_set_tool(&b, ST_BRUSH_GRAB);
    CHECK(b.strength == 1.0 && b.falloff == ST_FALLOFF_SMOOTH);
    b.falloff = ST_FALLOFF_LINEAR;
    st_brush_set_tool(&b, ST_BRUSH_DRAW);
    CHECK(b.strength == 0.9 && b.falloff == ST_FALLOFF_SHARP && b.radius == 0.3);
    st_brush_set_tool(&b, ST_BRUSH_GRAB);
    CHECK(b.falloff == ST_FALLOFF_LINEAR);
    st_brush_set_tool(&b, ST_BRUSH_COUNT);
    CHECK(b.tool == ST_BRUSH_GRAB);
    for (int t = 0; t < ST_BRUSH_COUNT; t++) CHECK(strcmp(st_brush_name(t), "?") != 0);
    CHECK(strcmp(st_brush_name(ST_BRUSH_CLAY_STRIPS), "clay strips") == 0 && strcmp(st_brush_name(-1), "?") == 0);
}

/* Every level's positions and every detail. */
static double *take(const st_doc *d, size_t *count)
{
    const st_hier *h = &d->h;
    uint32_t nv = h->map.verts.end;
    size_t n = (size_t)(h->map.top + 1) * nv * 6, i = 0;
    double *s = calloc(n + 1, sizeof *s);
    for (unsigned l = 0; l <= h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            i = ((size_t)l * nv + v) * 6;
            memcpy(s + i, st_pos(&h->map, v, l), 3 * sizeof *s);
            memcpy(s + i + 3, st_hier_detail(h, l, v), 3 * sizeof *s);
        }
    }
    *count = n;
    return s;
}

static void test_undo_redo(void)
{
    for (int tool = 0; tool < ST_BRUSH_COUNT; tool++) {
        st_doc d;
        st_doc_init(&d);
        ed_test_open(&d, cube, "catmull-clark", 3);
        st_doc_set_edit_level(&d, 1);
        size_t n0, n1, n2, n3;
        double *before = take(&d, &n0);
        const double dir[3] = { 0.3, 0.4, 1 }, nrm[3] = { 0.2, 0.2, 1 }, g[3] = { 0.05, 0.01, 0.03 };
        uint32_t cv = ed_test_extreme_vertex(&d, dir);
        double c[3];
        st_doc_vertex_pos(&d, cv, c);
        brush_set(&d, tool, 0.7, 0.8, nrm);
        d.brush.mirror_x = 1;
        d.brush.falloff = tool % ST_FALLOFF_COUNT;
        CHECK(st_doc_stroke_begin(&d) == 0);
        for (int k = 0; k < 4; k++) {
            CHECK(st_doc_stroke_dab(&d, c, nrm, g) == 0);
            c[0] -= 0.05;
        }
        st_doc_stroke_end(&d);
        double *after = take(&d, &n1);
        st_error err;
        CHECK(d.undo_pos == 1 && st_doc_undo(&d, &err) == 0);
        double *undone = take(&d, &n2);
        CHECK(st_doc_redo(&d, &err) == 0);
        double *redone = take(&d, &n3);
        CHECKF(n0 == n2 && memcmp(before, undone, n0 * sizeof *before) == 0, "%s: undo is not bit-exact", st_brush_name(tool));
        CHECKF(n1 == n3 && memcmp(after, redone, n1 * sizeof *after) == 0, "%s: redo is not bit-exact", st_brush_name(tool));
        CHECKF(n0 == n1 && memcmp(before, after, n0 * sizeof *before) != 0, "%s: the stroke changed nothing", st_brush_name(tool));
        free(before);
        free(after);
        free(undone);
        free(redone);
        st_doc_free(&d);
    }
}

int main(void)
{
    snprintf(grid_path, sizeof grid_path, "%s/brushes_grid.obj", STRATA_TMP);
    write_grid(grid_path, 20);
    test_falloffs();
    test_grid_brushes();
    test_grid_falloffs();
    test_grid_build_up();
    test_sphere_brushes();
    test_front_faces();
    test_symmetry();
    test_spacing();
    test_spacing_stroke();
    test_fade_out();
    test_tool_settings();
    test_undo_redo();
    return TEST_END();
}
