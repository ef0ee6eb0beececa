/* Masks and sculpt layers in the document, headless (ui/editor.h,
 * core/multires/mask.h, core/multires/layers.h): a mask of 1 protects
 * vertices bit for bit from every brush, drags and grabs, and in
 * proportion below 1; masks follow the hierarchy's correspondence across
 * levels and survive added levels and undo; layer strength 0 gives the
 * surface without the layer and strength 1 the surface as sculpted, both
 * bit for bit, at level 0 (object-space offsets of the control mesh) as at
 * finer levels; layers ride a coarse rigid motion; local recomposition
 * equals a full synthesis; a random sequence of strokes, mask and layer
 * operations is undone and redone bit for bit; sessions round-trip. */
#include "editor.h"
#include "editor_internal.h" /* ed_hier_clone */
#include "core/io/map_io_internal.h" /* st_session_checksum */
#include "core/io/session.h"
#include "core/multires/hier_internal.h"
#include "testlib.h"
#include "editor_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *cube = STRATA_ASSETS "/cube.obj";

/* ---- state snapshots: positions and details of every level, the mask,
 * the layer stack (without the active index, which is not undoable) ---- */

typedef struct state {
    size_t n;
    unsigned char *b;
} state;

static void put(state *s, const void *p, size_t n)
{
    s->b = realloc(s->b, s->n + n);
    memcpy(s->b + s->n, p, n);
    s->n += n;
}

static void state_take(const st_doc *d, state *s, int with_extra)
{
    memset(s, 0, sizeof *s);
    const st_hier *h = &d->h;
    for (unsigned l = 0; l <= h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            put(s, &l, sizeof l);
            put(s, &v, sizeof v);
            put(s, st_pos(&h->map, v, l), 3 * sizeof(double));
            put(s, st_hier_detail(h, l, v), 3 * sizeof(double));
            if (with_extra) {
                float m = st_mask_get(&d->mask, v);
                put(s, &m, sizeof m);
            }
        }
    }
    if (!with_extra) return;
    const st_layers *ls = &d->layers;
    put(s, &ls->n, sizeof ls->n);
    for (uint32_t i = 0; i < ls->n; i++) {
        const st_layer *y = &ls->v[i];
        put(s, y->name, strlen(y->name) + 1);
        put(s, &y->level, sizeof y->level);
        put(s, &y->strength, sizeof y->strength);
        put(s, &y->hidden, sizeof y->hidden);
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, y->level, &it); v != ST_NIL; v = st_vertex_next(&h->map, y->level, &it)) {
            double o[3];
            st_layers_get(ls, (int)i, y->level, v, o);
            put(s, o, sizeof o);
        }
    }
    for (unsigned l = 0; l <= h->map.top; l++) {
        if (!st_layers_on_level(ls, l)) continue;
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            double o[3];
            st_layers_get(ls, -1, l, v, o);
            put(s, o, sizeof o);
        }
    }
}

static int state_eq(const state *a, const state *b) { return a->n == b->n && memcmp(a->b, b->b, a->n) == 0; }

/* States taken without the extras: details of every level and positions of
 * levels <= exact bit for bit, positions above within tol. */
enum { REC = 56 };
static int state_close(const state *a, const state *b, unsigned exact, double tol)
{
    if (a->n != b->n || a->n % REC) return 0;
    for (size_t r = 0; r < a->n / REC; r++) {
        const unsigned char *x = a->b + r * REC, *y = b->b + r * REC;
        unsigned l;
        memcpy(&l, x, sizeof l);
        if (memcmp(x, y, 8) || memcmp(x + 32, y + 32, 24)) {  /* level, id, detail */
            if (getenv("STRATA_TEST_VERBOSE")) {
                double p[3], q[3];
                memcpy(p, x + 32, 24);
                memcpy(q, y + 32, 24);
                fprintf(stderr, "record %zu level %u: detail %.17g %.17g %.17g vs %.17g %.17g %.17g\n", r, l, p[0], p[1], p[2], q[0], q[1], q[2]);
            }
            return 0;
        }
        double p[3], q[3];
        memcpy(p, x + 8, sizeof p);
        memcpy(q, y + 8, sizeof q);
        for (int k = 0; k < 3; k++)
            if (l <= exact ? p[k] != q[k] : fabs(p[k] - q[k]) > tol) {
                if (getenv("STRATA_TEST_VERBOSE")) fprintf(stderr, "record %zu level %u: pos[%d] %.17g vs %.17g\n", r, l, k, p[k], q[k]);
                return 0;
            }
    }
    return 1;
}

static void state_free(state *s) { free(s->b); memset(s, 0, sizeof *s); }

static void dab(st_doc *d, const double c[3], const double nrm[3], const double g[3])
{
    CHECK(st_doc_stroke_begin(d) == 0);
    CHECK(st_doc_stroke_dab(d, c, nrm, g) == 0);
    st_doc_stroke_end(d);
}

/* ---- masks ----------------------------------------------------------------- */

static void test_mask_protects(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 2);
    unsigned l = 2;
    const double up[3] = { 0, 0, 1 };
    uint32_t top = ed_test_extreme_vertex(&d, up);
    double c[3];
    st_doc_vertex_pos(&d, top, c);
    d.brush.radius = 0.6;
    d.brush.strength = 1;
    d.brush.mirror_x = 0;
    /* Mask 1 everywhere, then erased around the top: a ring of partial
     * values, the rest stays 1 exactly. */
    CHECK(st_doc_mask_invert(&d) == 0);
    uint32_t *v, n = ed_test_level_vertices(&d, l, &v);
    int all_one = 1;
    for (uint32_t i = 0; i < n; i++) all_one &= st_doc_mask(&d, v[i]) == 1.0f;
    CHECK(all_one);
    d.brush.radius = 0.4;
    st_doc_take_change(&d);
    CHECK(st_doc_mask_stroke_begin(&d, 1) == 0);
    CHECK(st_doc_mask_stroke_dab(&d, c) == 0);
    st_doc_change ch = st_doc_take_change(&d);
    CHECK((ch.bits & ST_CHANGE_MASK) && ch.nmask_vids > 0);
    st_doc_mask_stroke_end(&d);
    CHECK(!strcmp(st_doc_undo_name(&d), "mask stroke"));
    uint32_t partial = 0, full = 0;
    for (uint32_t i = 0; i < n; i++) {
        float m = st_doc_mask(&d, v[i]);
        partial += m < 1.0f;
        full += m == 1.0f;
    }
    CHECKF(partial > 0 && full > partial, "partial %u, full %u", partial, full);
    d.brush.radius = 0.8;
    double (*p0)[3] = malloc(n * sizeof *p0), (*d0)[3] = malloc(n * sizeof *d0);
    const double grab[3] = { 0.05, -0.1, 0.2 };
    for (int tool = 0; tool < ST_BRUSH_COUNT + 1; tool++) {
        for (uint32_t i = 0; i < n; i++) {
            memcpy(p0[i], st_pos(&d.h.map, v[i], l), sizeof p0[i]);
            memcpy(d0[i], st_hier_detail(&d.h, l, v[i]), sizeof d0[i]);
        }
        if (tool < ST_BRUSH_COUNT) {
            d.brush.tool = tool;
            dab(&d, c, up, grab);
        } else {
            /* Drag of the whole level: each vertex moves by (1 - mask) delta. */
            st_doc_select(&d, v, n, ST_SELECT_REPLACE);
            CHECK(st_doc_drag_begin(&d) == 0);
            CHECK(st_doc_drag_update(&d, grab) == 0);
            st_doc_drag_end(&d);
        }
        int kept = 1, partial_moved = 0, proportional = 1;
        for (uint32_t i = 0; i < n; i++) {
            float m = st_doc_mask(&d, v[i]);
            const double *p = st_pos(&d.h.map, v[i], l);
            if (m == 1.0f) {
                kept &= !memcmp(p, p0[i], sizeof p0[i]);
                kept &= !memcmp(st_hier_detail(&d.h, l, v[i]), d0[i], sizeof d0[i]);
            } else if (memcmp(p, p0[i], sizeof p0[i])) {
                partial_moved++;
            }
            if (tool == ST_BRUSH_COUNT)
                for (int k = 0; k < 3; k++)
                    if (fabs(p[k] - p0[i][k] - (1.0 - m) * grab[k]) > 1e-12) proportional = 0;
        }
        CHECKF(kept, "tool %d moved a vertex whose mask is 1", tool);
        CHECKF(partial_moved > 0, "tool %d moved nothing", tool);
        CHECKF(proportional, "drag: a vertex did not move by (1 - mask) * delta");
    }
    /* Draw with a half mask moves half as far (the dab's displacement is
     * computed from the same positions). */
    CHECK(st_doc_mask_clear(&d) == 0);
    CHECK(!st_mask_any(&d.mask));
    st_doc mref;
    st_doc_init(&mref);
    ed_test_open(&mref, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&mref, 2);
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 2);
    for (uint32_t i = 0; i < n; i++) st_mask_set(&d.mask, v[i], 0.5f);
    st_mask_propagate(&d.mask, &d.h, 2, NULL, 0);
    d.brush = mref.brush;
    d.brush.tool = mref.brush.tool = ST_BRUSH_DRAW;
    d.brush.radius = mref.brush.radius = 0.6;
    d.brush.mirror_x = mref.brush.mirror_x = 0;
    dab(&d, c, up, NULL);
    dab(&mref, c, up, NULL);
    double worst = 0;
    /* Displacements: d moved half of mref's, vertex by vertex. */
    st_doc fresh;
    st_doc_init(&fresh);
    ed_test_open(&fresh, cube, "catmull-clark", 3);
    for (uint32_t i = 0; i < n; i++) {
        const double *p = st_pos(&d.h.map, v[i], l), *q = st_pos(&mref.h.map, v[i], l), *o = st_pos(&fresh.h.map, v[i], l);
        for (int k = 0; k < 3; k++) {
            double e = fabs((p[k] - o[k]) - 0.5 * (q[k] - o[k]));
            if (e > worst) worst = e;
        }
    }
    CHECKF(worst < 1e-12, "half mask: displacement differs from half by %g", worst);
    st_doc_free(&fresh);
    st_doc_free(&mref);
    free(p0);
    free(d0);
    free(v);
    st_doc_free(&d);
}

/* A mask painted at level 1 seen at level 3: level-1 vertices keep their
 * values (same ids), the others have the stencil average of the level
 * below, clamped; a constant mask stays constant through added levels;
 * a fully masked region at level 1 protects the same region at level 3. */
static void test_mask_levels(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 2);
    st_doc_set_edit_level(&d, 1);
    const double up[3] = { 0, 0, 1 };
    uint32_t top = ed_test_extreme_vertex(&d, up);
    double c[3];
    st_doc_vertex_pos(&d, top, c);
    d.brush.radius = 0.9;
    d.brush.strength = 1;
    CHECK(st_doc_mask_stroke_begin(&d, 0) == 0);
    for (int i = 0; i < 6; i++) CHECK(st_doc_mask_stroke_dab(&d, c) == 0);
    st_doc_mask_stroke_end(&d);
    /* One more level: the mask extends to it. */
    st_error err;
    CHECK(st_doc_add_level(&d, &err) == 0);
    uint32_t *v1, n1 = ed_test_level_vertices(&d, 1, &v1);
    float *m1 = malloc(n1 * sizeof *m1);
    for (uint32_t i = 0; i < n1; i++) m1[i] = st_doc_mask(&d, v1[i]);
    /* Every level-3 vertex: the coinciding vertex's value or the stencil
     * average of level 2, which is itself that of level 1. */
    st_hier *h = &d.h;
    uint32_t *v3, n3 = ed_test_level_vertices(&d, 3, &v3);
    uint32_t ones = 0, mids = 0;
    for (uint32_t i = 0; i < n3; i++) {
        float m = st_doc_mask(&d, v3[i]);
        CHECK(m >= 0 && m <= 1);
        ones += m == 1.0f;
        mids += m > 0 && m < 1;
    }
    CHECKF(ones > 0 && mids > 0, "level 3: %u ones, %u partial", ones, mids);
    /* Recomputing the levels above 1 from level 1 gives the same values. */
    st_mask copy;
    CHECK(st_mask_copy(&copy, &d.mask) == 0);
    for (uint32_t v = 0; v < copy.cap && v < h->map.verts.end; v++)
        if (h->map.verts.ins[v] > 1 && h->map.verts.ins[v] != ST_FREE_LEVEL) copy.v[v] = -1;
    st_mask_propagate(&copy, h, 1, NULL, 0);
    int same = 1;
    for (uint32_t i = 0; i < n3; i++) same &= st_mask_get(&copy, v3[i]) == st_doc_mask(&d, v3[i]);
    CHECK(same);
    st_mask_free(&copy);
    /* The level-1 values are unchanged by the added level. */
    int kept = 1;
    for (uint32_t i = 0; i < n1; i++) kept &= st_doc_mask(&d, v1[i]) == m1[i];
    CHECK(kept);
    /* At level 3, the vertices masked 1 do not move under a draw. */
    st_doc_set_edit_level(&d, 3);
    double (*p0)[3] = malloc(n3 * sizeof *p0);
    for (uint32_t i = 0; i < n3; i++) memcpy(p0[i], st_pos(&h->map, v3[i], 3), sizeof p0[i]);
    d.brush.tool = ST_BRUSH_DRAW;
    d.brush.radius = 1.5;
    dab(&d, c, up, NULL);
    int still = 1, moved = 0;
    for (uint32_t i = 0; i < n3; i++) {
        int m = memcmp(st_pos(&h->map, v3[i], 3), p0[i], sizeof p0[i]) != 0;
        if (st_doc_mask(&d, v3[i]) == 1.0f) still &= !m;
        moved += m;
    }
    CHECK(still && moved > 0);
    /* Undo of the draw, the level and the stroke: the mask is gone. */
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(!st_mask_any(&d.mask));
    CHECK(st_doc_redo(&d, &err) == 0);
    int back = 1;
    for (uint32_t i = 0; i < n1; i++) back &= st_doc_mask(&d, v1[i]) == m1[i];
    CHECK(back);
    /* A constant mask stays constant at every level. */
    CHECK(st_doc_mask_clear(&d) == 0);
    st_doc_set_edit_level(&d, 0);
    CHECK(st_doc_mask_invert(&d) == 0);
    CHECK(st_doc_add_level(&d, &err) == 0);
    uint32_t *v4, n4 = ed_test_level_vertices(&d, d.h.map.top, &v4);
    int allone = 1;
    for (uint32_t i = 0; i < n4; i++) allone &= st_doc_mask(&d, v4[i]) == 1.0f;
    CHECK(allone);
    /* Grow / shrink / smooth / cavity on a partial mask keep values in range
     * and are each one undo step. */
    CHECK(st_doc_mask_clear(&d) == 0);
    st_doc_set_edit_level(&d, 2);
    CHECK(st_doc_mask_stroke_begin(&d, 0) == 0);
    d.brush.radius = 0.5;
    CHECK(st_doc_mask_stroke_dab(&d, c) == 0);
    st_doc_mask_stroke_end(&d);
    uint32_t *v2, n2 = ed_test_level_vertices(&d, 2, &v2);
    double before = 0, after = 0;
    for (uint32_t i = 0; i < n2; i++) before += st_doc_mask(&d, v2[i]);
    CHECK(st_doc_mask_grow(&d) == 0);
    for (uint32_t i = 0; i < n2; i++) after += st_doc_mask(&d, v2[i]);
    CHECKF(after > before, "grow: %g -> %g", before, after);
    CHECK(!strcmp(st_doc_undo_name(&d), "grow mask"));
    before = after;
    after = 0;
    CHECK(st_doc_mask_shrink(&d) == 0);
    for (uint32_t i = 0; i < n2; i++) after += st_doc_mask(&d, v2[i]);
    CHECKF(after < before, "shrink: %g -> %g", before, after);
    CHECK(st_doc_mask_smooth(&d) == 0);
    free(v1);
    free(v2);
    free(v3);
    free(v4);
    free(m1);
    free(p0);
    st_doc_free(&d);
}

/* Mask by cavity on a cube with a pushed-in dent: the dent's bottom is
 * masked, the flat faces far from it are not. */
static void test_mask_cavity(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 3);
    const double up[3] = { 0, 0, 1 };
    uint32_t top = ed_test_extreme_vertex(&d, up);
    double c[3];
    st_doc_vertex_pos(&d, top, c);
    d.brush.tool = ST_BRUSH_DRAW;
    d.brush.invert = 1;
    d.brush.radius = 0.15;
    d.brush.strength = 1;
    d.brush.mirror_x = 0;
    for (int i = 0; i < 4; i++) dab(&d, c, up, NULL);
    CHECK(st_doc_mask_cavity(&d) == 0);
    CHECKF(st_doc_mask(&d, top) > 0.5f, "dent bottom mask %g", st_doc_mask(&d, top));
    const double down[3] = { 0, 0, -1 };
    uint32_t bottom = ed_test_extreme_vertex(&d, down);
    CHECKF(st_doc_mask(&d, bottom) == 0.0f, "convex bottom mask %g", st_doc_mask(&d, bottom));
    st_doc_free(&d);
}

/* ---- layers ------------------------------------------------------------------ */

/* A document whose levels 2 and 3 carry details and whose positions are
 * a full synthesis (so a recomposition from the details gives them back). */
/* The mask over the interest box's display (st_doc_display_mask), which
 * has vertex ids of its own and a level beyond the model's top: every
 * display vertex paired with a model vertex has that vertex's value, a
 * constant mask stays constant on the display's finer level, and a painted
 * one reaches it (values strictly between 0 and 1 there too). */
static void test_mask_display(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 2);
    st_doc_set_edit_level(&d, 2);
    CHECK(st_doc_display_mask(&d) == &d.mask);   /* box off: the model's own */
    st_adapt_params b = d.box;
    b.base_level = 0;
    b.max_level = 3;
    for (int k = 0; k < 3; k++) { b.box_lo[k] = 0; b.box_hi[k] = 1.5; }
    st_error err;
    CHECK(st_doc_set_box(&d, &b, 1, &err) == 0);
    const st_hier *dh = st_doc_display_hier(&d);
    CHECK(dh != &d.h && dh->map.top == 3);
    CHECK(st_doc_mask_invert(&d) == 0);   /* 1 everywhere */
    const st_mask *dm = st_doc_display_mask(&d);
    CHECK(dm != &d.mask && dm->cap == dh->map.verts.end);
    st_dart_iter it;
    int ones = 1;
    uint32_t beyond = 0;
    for (uint32_t v = st_vertex_first(&dh->map, 3, &it); v != ST_NIL; v = st_vertex_next(&dh->map, 3, &it)) {
        ones &= st_mask_get(dm, v) == 1.0f;
        beyond += st_vertex_level(&dh->map, v) == 3;
    }
    CHECK(ones && beyond > 0);
    /* A spot painted at the box's corner of the cube. */
    CHECK(st_doc_mask_clear(&d) == 0);
    CHECK(st_doc_mask_stroke_begin(&d, 0) == 0);
    d.brush.radius = 0.6;
    d.brush.strength = 0.5;
    const double corner[3] = { 0.6, 0.6, 0.6 };
    st_doc_mask_stroke_dab(&d, corner);
    st_doc_mask_stroke_end(&d);
    dm = st_doc_display_mask(&d);
    int paired_equal = 1;
    uint32_t paired = 0, partial_beyond = 0;
    for (uint32_t v = st_vertex_first(&dh->map, 3, &it); v != ST_NIL; v = st_vertex_next(&dh->map, 3, &it)) {
        uint32_t mv = st_box_display_model_vertex(&d.display, v);
        float x = st_mask_get(dm, v);
        if (mv != ST_NIL) {
            paired++;
            paired_equal &= x == st_mask_get(&d.mask, mv);
        } else if (x > 0 && x < 1) {
            partial_beyond++;
        }
    }
    CHECK(paired_equal && paired > 0);
    CHECKF(partial_beyond > 0, "no vertex beyond the model's top took the painted mask");
    st_doc_free(&d);
}

static void open_detailed(st_doc *d, double *c)
{
    ed_test_open(d, cube, "catmull-clark", 3);
    const double up[3] = { 0, 0, 1 };
    d->brush.tool = ST_BRUSH_DRAW;
    d->brush.radius = 0.5;
    d->brush.strength = 0.5;
    d->brush.mirror_x = 0;
    st_doc_set_edit_level(d, 3);
    uint32_t top = ed_test_extreme_vertex(d, up);
    st_doc_vertex_pos(d, top, c);
    dab(d, c, up, NULL);
    st_doc_set_edit_level(d, 2);
    const double side[3] = { 0.3, 0.1, 0.2 };
    dab(d, side, up, NULL);
    st_hier_synthesize(&d->h, 0);
}

/* Strength 0 and hidden give the surface without the layer, strength 1 the
 * surface as sculpted: details of every level and positions up to the
 * layer's level bit for bit; the levels above it are re-synthesised
 * locally, whose stencil sums may round in another order than the ones
 * that made them (as any local edit with details, hier.h): 1e-12. */
static void layer_strength_at(unsigned level)
{
    st_doc d;
    st_doc_init(&d);
    double c[3];
    open_detailed(&d, c);
    st_doc_set_edit_level(&d, level);
    st_error err;
    const double tol = 1e-12;
    state a, b, x;
    state_take(&d, &a, 0);
    CHECK(st_doc_layer_add(&d, "", &err) == 0);
    CHECK(d.layers.n == 1 && !strcmp(d.layers.v[0].name, "Layer 1") && d.layers.v[0].level == level && d.layers.active == 0);
    state_take(&d, &x, 0);
    CHECK(state_eq(&a, &x));   /* an empty layer changes nothing */
    state_free(&x);
    const double up[3] = { 0, 0, 1 };
    d.brush.radius = level ? 0.7 : 1.5;   /* level 0: the cube's corners */
    for (int t = 0; t < ST_BRUSH_COUNT; t++) {
        d.brush.tool = t;
        const double g[3] = { 0, 0, 0.1 };
        dab(&d, c, up, g);
    }
    state_take(&d, &b, 0);
    CHECK(!state_close(&a, &b, level, 1e-9));
    uint32_t *sup = NULL, cap = 0;
    CHECK(st_layers_support(&d.layers, &d.h, 0, &sup, &cap) > 0);
    free(sup);
    /* Strength 0: the surface without the layer. */
    CHECK(st_doc_layer_set_strength(&d, 0, 0, &err) == 0);
    state_take(&d, &x, 0);
    CHECKF(state_close(&a, &x, level, tol), "level %u: strength 0", level);
    state_free(&x);
    /* Local recomposition == full synthesis of the levels above. */
    st_doc_layer_set_strength(&d, 0, 0.5, &err);
    st_hier full;
    CHECK(ed_hier_clone(&full, &d.h, NULL) == 0);
    st_hier_synthesize(&full, level);
    double worst = 0;
    st_dart_iter it;
    for (unsigned l = level; l <= full.map.top; l++)
        for (uint32_t v = st_vertex_first(&full.map, l, &it); v != ST_NIL; v = st_vertex_next(&full.map, l, &it))
            for (int k = 0; k < 3; k++) {
                double e = fabs(st_pos(&full.map, v, l)[k] - st_pos(&d.h.map, v, l)[k]);
                if (e > worst) worst = e;
            }
    CHECKF(worst <= tol, "level %u: local recomposition differs from a full synthesis by %g", level, worst);
    st_hier_free(&full);
    state_take(&d, &x, 0);
    CHECK(!state_close(&a, &x, level, 1e-9) && !state_close(&b, &x, level, 1e-9));
    state_free(&x);
    /* Strength 1: the surface as sculpted. */
    CHECK(st_doc_layer_set_strength(&d, 0, 1, &err) == 0);
    state_take(&d, &x, 0);
    CHECKF(state_close(&b, &x, level, tol), "level %u: strength 1", level);
    state_free(&x);
    /* Hidden == strength 0; shown again == as sculpted. */
    CHECK(st_doc_layer_set_hidden(&d, 0, 1, &err) == 0);
    state_take(&d, &x, 0);
    CHECK(state_close(&a, &x, level, tol));
    state_free(&x);
    CHECK(st_doc_layer_set_hidden(&d, 0, 0, &err) == 0);
    state_take(&d, &x, 0);
    CHECK(state_close(&b, &x, level, tol));
    state_free(&x);
    /* Strength is clamped to 0..2. */
    CHECK(st_doc_layer_set_strength(&d, 0, 5, &err) == 0);
    CHECK(d.layers.v[0].strength == 2);
    CHECK(st_doc_layer_set_strength(&d, 0, 1, &err) == 0);
    /* A second layer at the other level combines with the first. */
    unsigned other = level == 3 ? 2 : 3;
    st_doc_set_edit_level(&d, other);
    CHECK(st_doc_layer_add(&d, "other", &err) == 0);
    CHECK(d.layers.v[1].level == other && d.layers.active == 1);
    d.brush.tool = ST_BRUSH_DRAW;
    dab(&d, c, up, NULL);
    state_take(&d, &x, 0);
    CHECK(!state_close(&b, &x, 3, 1e-9));
    state_free(&x);
    CHECK(st_doc_layer_set_strength(&d, 1, 0, &err) == 0);
    state_take(&d, &x, 0);
    CHECK(state_close(&b, &x, level < other ? level : other, tol));
    state_free(&x);
    /* Deleting both gives back the surface without layers. */
    CHECK(st_doc_layer_delete(&d, 1, &err) == 0);
    CHECK(st_doc_layer_delete(&d, 0, &err) == 0);
    CHECK(d.layers.n == 0 && !d.layers.base[level] && !d.layers.base[other] && !d.layers.bpos[level] && !d.layers.bpos[other]);
    state_take(&d, &x, 0);
    CHECK(state_close(&a, &x, level < other ? level : other, tol));
    state_free(&x);
    /* A layer needs a level of the hierarchy. */
    CHECK(st_layers_add(&d.layers, &d.h, d.h.map.top + 1, "above", &err) < 0 && d.layers.n == 0);
    state_free(&a);
    state_free(&b);
    st_doc_free(&d);
}

static void test_layer_strength(void)
{
    layer_strength_at(3);   /* the top level: the whole surface bit for bit */
    layer_strength_at(2);
    layer_strength_at(0);   /* object-space offsets of the control mesh */
}

/* A rigid translation of level 0 carries the layer: its offsets and the
 * level's details stay bit for bit, the layer's contribution to the finest
 * level is translated with it (to rounding), and strength 0 still gives the
 * moved surface without the layer bit for bit. */
static void test_layer_rides_coarse_motion(void)
{
    st_doc d, e;
    st_doc_init(&d);
    st_doc_init(&e);
    double c[3];
    open_detailed(&d, c);
    open_detailed(&e, c);
    st_error err;
    CHECK(st_doc_layer_add(&d, "ride", &err) == 0);
    const double up[3] = { 0, 0, 1 };
    d.brush.radius = 0.7;
    dab(&d, c, up, NULL);
    uint32_t *v3, n3 = ed_test_level_vertices(&d, 3, &v3);
    double (*diff)[3] = malloc(n3 * sizeof *diff);
    for (uint32_t i = 0; i < n3; i++)
        for (int k = 0; k < 3; k++) diff[i][k] = st_pos(&d.h.map, v3[i], 3)[k] - st_pos(&e.h.map, v3[i], 3)[k];
    uint32_t *v2, n2 = ed_test_level_vertices(&d, 2, &v2);
    double (*det)[3] = malloc(n2 * sizeof *det);
    for (uint32_t i = 0; i < n2; i++) memcpy(det[i], st_hier_detail(&d.h, 2, v2[i]), sizeof det[i]);
    /* The same translation of level 0 in both. */
    const double t[3] = { 0.25, -0.5, 0.125 };
    st_doc *docs[2] = { &d, &e };
    for (int k = 0; k < 2; k++) {
        st_doc_set_edit_level(docs[k], 0);
        uint32_t *v0, n0 = ed_test_level_vertices(docs[k], 0, &v0);
        st_doc_select(docs[k], v0, n0, ST_SELECT_REPLACE);
        CHECK(st_doc_drag_begin(docs[k]) == 0);
        CHECK(st_doc_drag_update(docs[k], t) == 0);
        st_doc_drag_end(docs[k]);
        free(v0);
    }
    int kept = 1;
    for (uint32_t i = 0; i < n2; i++) kept &= !memcmp(det[i], st_hier_detail(&d.h, 2, v2[i]), sizeof det[i]);
    CHECK(kept);
    double worst = 0;
    for (uint32_t i = 0; i < n3; i++)
        for (int k = 0; k < 3; k++) {
            double x = st_pos(&d.h.map, v3[i], 3)[k] - st_pos(&e.h.map, v3[i], 3)[k];
            if (fabs(x - diff[i][k]) > worst) worst = fabs(x - diff[i][k]);
        }
    CHECKF(worst < 1e-12, "layer's contribution moved by %g", worst);
    /* Strength 0: the moved surface without the layer.  The translation
     * re-synthesised level 2 with the layer in its details; recomposing
     * without it sums the stencils in another order than e's re-synthesis
     * (layers.h), so positions agree to rounding, details bit for bit. */
    CHECK(st_doc_layer_set_strength(&d, 0, 0, &err) == 0);
    state sd, se;
    state_take(&d, &sd, 0);
    state_take(&e, &se, 0);
    CHECK(state_close(&sd, &se, 1, 1e-12));
    state_free(&sd);
    state_free(&se);
    free(v2);
    free(v3);
    free(det);
    free(diff);
    st_doc_free(&d);
    st_doc_free(&e);
}

/* A layer on level 0 moves the control mesh; a layer on level 2 rides on
 * it (its offsets and the level's details stay bit for bit), and strength 0 of the level-0 layer
 * gives back the control mesh bit for bit.  Removing level 0 is refused
 * while a layer is on it. */
static void test_layer_level0_carries_finer(void)
{
    st_doc d;
    st_doc_init(&d);
    double c[3];
    open_detailed(&d, c);
    st_error err;
    const double up[3] = { 0, 0, 1 };
    CHECK(st_doc_layer_add(&d, "fine", &err) == 0 && d.layers.v[0].level == 2);
    d.brush.radius = 0.7;
    dab(&d, c, up, NULL);
    uint32_t *v0, n0 = ed_test_level_vertices(&d, 0, &v0);
    uint32_t *v2, n2 = ed_test_level_vertices(&d, 2, &v2);
    double (*p0)[3] = malloc(n0 * sizeof *p0), (*o2)[3] = malloc(n2 * sizeof *o2), (*det)[3] = malloc(n2 * sizeof *det);
    for (uint32_t i = 0; i < n0; i++) memcpy(p0[i], st_pos(&d.h.map, v0[i], 0), sizeof p0[i]);
    for (uint32_t i = 0; i < n2; i++) {
        st_layers_get(&d.layers, 0, 2, v2[i], o2[i]);
        memcpy(det[i], st_hier_detail(&d.h, 2, v2[i]), sizeof det[i]);
    }
    st_doc_set_edit_level(&d, 0);
    CHECK(st_doc_layer_add(&d, "coarse", &err) == 0 && d.layers.n == 2 && d.layers.v[1].level == 0);
    d.brush.radius = 1.5;
    d.brush.tool = ST_BRUSH_DRAW;
    dab(&d, c, up, NULL);
    uint32_t moved = 0;
    for (uint32_t i = 0; i < n0; i++) moved += memcmp(p0[i], st_pos(&d.h.map, v0[i], 0), sizeof p0[i]) != 0;
    CHECK(moved > 0);
    int kept = 1;
    for (uint32_t i = 0; i < n2; i++) {
        double o[3];
        st_layers_get(&d.layers, 0, 2, v2[i], o);
        kept &= !memcmp(o, o2[i], sizeof o) && !memcmp(det[i], st_hier_detail(&d.h, 2, v2[i]), sizeof det[i]);
    }
    CHECK(kept);
    /* Level 0 takes the offsets as they are: position = B_0 + O. */
    double worst = 0;
    for (uint32_t i = 0; i < n0; i++) {
        double b[3], o[3];
        st_layers_get(&d.layers, ST_LAYERS_SLOT_BASE, 0, v0[i], b);
        st_layers_get(&d.layers, 1, 0, v0[i], o);
        CHECK(!memcmp(b, p0[i], sizeof b));
        for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(st_pos(&d.h.map, v0[i], 0)[k] - (b[k] + o[k])));
    }
    CHECK(worst == 0);
    CHECK(st_doc_remove_bottom(&d, &err) != 0 && strstr(err.msg, "level 0"));
    CHECK(st_doc_layer_set_strength(&d, 1, 0, &err) == 0);
    int back = 1;
    for (uint32_t i = 0; i < n0; i++) back &= !memcmp(p0[i], st_pos(&d.h.map, v0[i], 0), sizeof p0[i]);
    CHECK(back);
    free(v0);
    free(v2);
    free(p0);
    free(o2);
    free(det);
    st_doc_free(&d);
}

/* ---- random sequences, undone and redone ----------------------------------------- */

static double frand(uint64_t *rng) { return (double)tl_rand(rng) / 4294967296.0; }

/* lowest: the coarsest level the sequence edits and puts layers on. */
static void random_op(st_doc *d, uint64_t *rng, int *did, unsigned lowest)
{
    st_error err;
    uint32_t r = tl_rand(rng) % 16;
    *did = 1;
    double c[3] = { 2 * frand(rng) - 1, 2 * frand(rng) - 1, 2 * frand(rng) - 1 };
    double len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double reach = d->edit_level == 0 ? 1.6 : 0.5;   /* level 0: near the cube's corners */
    for (int k = 0; k < 3; k++) c[k] = reach * c[k] / (len > 0 ? len : 1);
    const double nrm[3] = { c[0], c[1], c[2] };
    uint32_t nl = d->layers.n;
    int k = nl ? (int)(tl_rand(rng) % nl) : -1;
    switch (r) {
    case 0: case 1: case 2: {
        /* The level-0 sequence sends half its strokes into a layer on
         * level 0 when there is one (they are rare otherwise). */
        for (uint32_t i = 0; lowest == 0 && i < nl; i++)
            if (d->layers.v[i].level == 0 && tl_rand(rng) % 2) {
                st_doc_layer_set_active(d, (int)i, &err);
                break;
            }
        d->brush.tool = (int)(tl_rand(rng) % ST_BRUSH_COUNT);
        d->brush.radius = 0.2 + 0.4 * frand(rng);
        if (d->edit_level == 0) d->brush.radius += 0.6;   /* reaches the cube's corners */
        d->brush.strength = 0.2 + 0.6 * frand(rng);
        const double g[3] = { 0.1 * frand(rng), -0.1 * frand(rng), 0.05 };
        CHECK(st_doc_stroke_begin(d) == 0);
        st_doc_stroke_dab(d, c, nrm, g);
        st_doc_stroke_dab(d, c, nrm, g);
        st_doc_stroke_end(d);
        break;
    }
    case 3:
        CHECK(st_doc_mask_stroke_begin(d, tl_rand(rng) & 1) == 0);
        d->brush.radius = 0.3 + 0.3 * frand(rng);
        st_doc_mask_stroke_dab(d, c);
        st_doc_mask_stroke_end(d);
        break;
    case 4: st_doc_mask_invert(d); break;
    case 5: st_doc_mask_grow(d); break;
    case 6: st_doc_mask_smooth(d); break;
    case 7: st_doc_mask_cavity(d); break;
    case 8: if (tl_rand(rng) % 4 == 0) st_doc_mask_clear(d); else *did = 0; break;
    case 9:
        if (d->edit_level >= lowest) st_doc_layer_add(d, NULL, &err);
        else *did = 0;
        break;
    case 10: if (k >= 0) st_doc_layer_set_strength(d, k, 2 * frand(rng), &err); break;
    case 11: if (k >= 0) st_doc_layer_set_hidden(d, k, !d->layers.v[k].hidden, &err); break;
    case 12: if (k >= 0) st_doc_layer_rename(d, k, "renamed", &err); break;
    case 13: if (k >= 1) st_doc_layer_move(d, k, 0, &err); else *did = 0; break;
    case 14: if (k >= 1 && st_doc_layer_merge_down(d, k, &err)) *did = 0; break;
    case 15:
        if (k >= 0 && tl_rand(rng) % 2) st_doc_layer_delete(d, k, &err);
        else if (k >= 0) st_doc_layer_set_active(d, k, &err), *did = 0;
        else *did = 0;
        break;
    }
    if (r >= 10 && r <= 12 && k < 0) *did = 0;
    if (tl_rand(rng) % 5 == 0) st_doc_set_edit_level(d, lowest + tl_rand(rng) % (d->h.map.top + 1 - lowest));
}

static void random_undo_redo(unsigned lowest, uint64_t rng)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 2);
    d.brush.mirror_x = 0;
    const int N = lowest ? 90 : 240;
    state *s = calloc(N + 1, sizeof *s);
    uint32_t nsteps = 0;
    int level0_layers_seen = 0;
    state_take(&d, &s[0], 1);
    for (int i = 0; i < N; i++) {
        uint32_t before = d.undo_pos;
        int did;
        random_op(&d, &rng, &did, lowest);
        if (d.undo_pos == before) continue; /* nothing recorded (nothing changed, or refused) */
        CHECK(d.undo_pos == before + 1);
        state_take(&d, &s[++nsteps], 1);
        for (uint32_t k = 0; k < d.layers.n; k++) {
            if (d.layers.v[k].level != 0) continue;
            uint32_t *sup = NULL, cap = 0;
            level0_layers_seen |= st_layers_support(&d.layers, &d.h, (int)k, &sup, &cap) > 0;
            free(sup);
        }
    }
    CHECKF(nsteps > 30, "only %u steps", nsteps);
    st_error err;
    int ok = 1;
    for (uint32_t i = nsteps; i > 0; i--) {
        CHECK(st_doc_undo(&d, &err) == 0);
        state x;
        state_take(&d, &x, 1);
        if (!state_eq(&x, &s[i - 1])) { ok = 0; fprintf(stderr, "undo to step %u differs\n", i - 1); }
        state_free(&x);
    }
    CHECK(ok);
    for (uint32_t i = 1; i <= nsteps; i++) {
        CHECK(st_doc_redo(&d, &err) == 0);
        state x;
        state_take(&d, &x, 1);
        if (!state_eq(&x, &s[i])) { ok = 0; fprintf(stderr, "redo to step %u differs\n", i); }
        state_free(&x);
    }
    CHECK(ok);
    for (uint32_t i = 0; i <= nsteps; i++) state_free(&s[i]);
    free(s);
    if (lowest == 0) CHECKF(level0_layers_seen, "no stroke went into a layer on level 0");
    st_doc_free(&d);
}

static void test_random_undo_redo(void)
{
    random_undo_redo(1, 0x5eed1234);
    random_undo_redo(0, 0x1e7e11);   /* with strokes and layers at level 0 */
}

/* ---- sessions ------------------------------------------------------------------- */

static void test_session_round_trip(void)
{
    st_doc d;
    st_doc_init(&d);
    double c[3];
    open_detailed(&d, c);
    st_error err;
    const double up[3] = { 0, 0, 1 };
    CHECK(st_doc_layer_add(&d, "first", &err) == 0);
    dab(&d, c, up, NULL);
    st_doc_set_edit_level(&d, 3);
    CHECK(st_doc_layer_add(&d, "second", &err) == 0);
    dab(&d, c, up, NULL);
    CHECK(st_doc_layer_set_strength(&d, 1, 0.25, &err) == 0);
    CHECK(st_doc_layer_set_hidden(&d, 0, 1, &err) == 0);
    CHECK(st_doc_mask_stroke_begin(&d, 0) == 0);
    st_doc_mask_stroke_dab(&d, c);
    st_doc_mask_stroke_end(&d);
    st_session_ref r = { .h = &d.h, .edit_level = d.edit_level, .display_level = d.display_level,
                         .layers = &d.layers, .mask = &d.mask };
    void *b1 = NULL, *b2 = NULL;
    size_t n1 = 0, n2 = 0;
    CHECK(st_session_write_mem(&r, &b1, &n1, &err) == 0);
    st_session s;
    int rc = st_session_parse("mem.strata", b1, n1, &s, &err);
    CHECKF(rc == 0, "%s", err.msg);
    if (!rc) {
        CHECK(s.layers.n == 2 && !strcmp(s.layers.v[0].name, "first") && s.layers.v[0].hidden && s.layers.v[1].strength == 0.25);
        CHECK(s.layers.active == d.layers.active);
        int same = 1;
        for (uint32_t v = 0; v < d.h.map.verts.end; v++) same &= st_mask_get(&s.mask, v) == st_mask_get(&d.mask, v);
        CHECK(same);
        st_session_ref r2 = st_session_ref_of(&s);
        CHECK(st_session_write_mem(&r2, &b2, &n2, &err) == 0);
        CHECK(n1 == n2 && !memcmp(b1, b2, n1));
        st_session_free(&s);
    }
    /* Without layers and mask: no new chunks (older readers load it). */
    free(b2);
    st_session_ref r3 = { .h = &d.h };
    CHECK(st_session_write_mem(&r3, &b2, &n2, &err) == 0);
    CHECK(n2 < n1);
    free(b1);
    free(b2);
    /* A small one through a file: save -> load -> save gives the same bytes
     * (also the fuzzer's seed tests/fuzz/corpus/session/cube_cc1_layers_mask.strata). */
    ed_test_open(&d, cube, "catmull-clark", 1);
    st_doc_set_edit_level(&d, 1);
    CHECK(st_doc_layer_add(&d, "seed", &err) == 0);
    const double corner[3] = { 0.5, 0.5, 0.5 };
    d.brush.radius = 0.8;
    dab(&d, corner, up, NULL);
    CHECK(st_doc_mask_stroke_begin(&d, 0) == 0);
    st_doc_mask_stroke_dab(&d, corner);
    st_doc_mask_stroke_end(&d);
    st_session_ref r4 = { .h = &d.h, .edit_level = 1, .display_level = 1, .layers = &d.layers, .mask = &d.mask };
    const char *path = STRATA_TMP "/masks_layers_seed.strata", *path2 = STRATA_TMP "/masks_layers_seed2.strata";
    tl_session_file_roundtrip(&r4, path, path2);
    st_doc_free(&d);
}

/* Offset of the chunk tag t in a session's bytes, or -1. */
static long find_tag(const unsigned char *b, size_t n, const char *t)
{
    for (size_t i = 0; i + 4 <= n; i++)
        if (!memcmp(b + i, t, 4)) return (long)i;
    return -1;
}

/* A layer on level 0 is stored under the tag lay0 (a reader from before
 * level-0 layers skips it and gets the composed surface); save -> load ->
 * save gives the same bytes; the loaded layers recompose to the same
 * surface; lay0 with its layer's level changed to 1.. is still read, and
 * layr refuses a layer on level 0 with a message. */
static void test_session_level0(void)
{
    st_doc d;
    st_doc_init(&d);
    double c[3];
    open_detailed(&d, c);
    st_error err;
    const double up[3] = { 0, 0, 1 };
    st_doc_set_edit_level(&d, 0);
    CHECK(st_doc_layer_add(&d, "coarse", &err) == 0);
    d.brush.tool = ST_BRUSH_DRAW;
    d.brush.radius = 1.5;
    dab(&d, c, up, NULL);
    st_doc_set_edit_level(&d, 2);
    CHECK(st_doc_layer_add(&d, "fine", &err) == 0);
    d.brush.radius = 0.7;
    dab(&d, c, up, NULL);
    CHECK(st_doc_layer_set_strength(&d, 0, 0.75, &err) == 0);
    st_session_ref r = { .h = &d.h, .edit_level = d.edit_level, .display_level = d.display_level, .layers = &d.layers };
    unsigned char *b1 = NULL, *b2 = NULL;
    size_t n1 = 0, n2 = 0;
    CHECK(st_session_write_mem(&r, (void **)&b1, &n1, &err) == 0);
    CHECK(find_tag(b1, n1, "lay0") > 0 && find_tag(b1, n1, "layr") < 0);
    st_session s;
    int rc = st_session_parse("mem.strata", b1, n1, &s, &err);
    CHECKF(rc == 0, "%s", err.msg);
    if (!rc) {
        CHECK(s.layers.n == 2 && s.layers.v[0].level == 0 && s.layers.v[1].level == 2 && s.layers.v[0].strength == 0.75);
        st_session_ref r2 = st_session_ref_of(&s);
        CHECK(st_session_write_mem(&r2, (void **)&b2, &n2, &err) == 0);
        CHECK(n1 == n2 && !memcmp(b1, b2, n1));
        /* The loaded stack recomposes as the document's: the level-0 layer
         * at strength 0 in both gives the same positions of every level
         * bit for bit. */
        CHECK(st_doc_layer_set_strength(&d, 0, 0, &err) == 0);
        uint32_t *sup = NULL, cap = 0;
        uint32_t ns = st_layers_support(&s.layers, &s.h, 0, &sup, &cap);
        CHECK(ns > 0);
        s.layers.v[0].strength = 0;
        st_layers_recompose(&s.layers, &s.h, 0, sup, ns, NULL);
        free(sup);
        int same = 1;
        for (unsigned l = 0; l <= d.h.map.top; l++) {
            st_dart_iter it;
            for (uint32_t v = st_vertex_first(&d.h.map, l, &it); v != ST_NIL; v = st_vertex_next(&d.h.map, l, &it))
                same &= !memcmp(st_pos(&d.h.map, v, l), st_pos(&s.h.map, v, l), 3 * sizeof(double));
        }
        CHECK(same);
        st_session_free(&s);
    }
    free(b2);
    /* The same bytes with the tag made layr: refused with a message. */
    long at = find_tag(b1, n1, "lay0");
    memcpy(b1 + at, "layr", 4);
    uint32_t crc = st_session_checksum(b1, n1);
    for (int k = 0; k < 4; k++) b1[n1 - 4 + k] = (unsigned char)(crc >> (8 * k));
    rc = st_session_parse("mem.strata", b1, n1, &s, &err);
    CHECKF(rc != 0 && strstr(err.msg, "level 0 in chunk 'lay0'"), "%s", err.msg);
    if (!rc) st_session_free(&s);
    free(b1);
    /* Without a layer on level 0: layr as before. */
    CHECK(st_doc_layer_delete(&d, 0, &err) == 0);
    st_session_ref r3 = { .h = &d.h, .layers = &d.layers };
    CHECK(st_session_write_mem(&r3, (void **)&b1, &n1, &err) == 0);
    CHECK(find_tag(b1, n1, "layr") > 0 && find_tag(b1, n1, "lay0") < 0);
    free(b1);
    /* A small one through a file: save -> load -> save gives the same bytes
     * (also the fuzzer's seed tests/fuzz/corpus/session/cube_cc1_layer0.strata). */
    ed_test_open(&d, cube, "catmull-clark", 1);
    st_doc_set_edit_level(&d, 0);
    CHECK(st_doc_layer_add(&d, "control", &err) == 0);
    const double corner[3] = { 1, 1, 1 }, diag[3] = { 0.577, 0.577, 0.577 };
    d.brush.tool = ST_BRUSH_DRAW;
    d.brush.radius = 0.5;
    dab(&d, corner, diag, NULL);
    uint32_t *sup = NULL, cap = 0;
    CHECK(st_layers_support(&d.layers, &d.h, 0, &sup, &cap) > 0);
    free(sup);
    st_session_ref r4 = { .h = &d.h, .layers = &d.layers };
    const char *path = STRATA_TMP "/masks_layers_level0.strata", *path2 = STRATA_TMP "/masks_layers_level0_2.strata";
    tl_session_file_roundtrip(&r4, path, path2);
    st_doc_free(&d);
}

int main(void)
{
    test_mask_protects();
    test_mask_levels();
    test_mask_cavity();
    test_mask_display();
    test_layer_strength();
    test_layer_rides_coarse_motion();
    test_layer_level0_carries_finer();
    test_random_undo_redo();
    test_session_round_trip();
    test_session_level0();
    return TEST_END();
}
