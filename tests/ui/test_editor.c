/* The modeller's document, headless (ui/editor.h): open, levels, selection,
 * drags, brushes, X-mirror, the interest box, undo/redo (bit-exact), the
 * names of undo steps, the undo budget, the memory budget and the
 * interaction benchmark. */
#include "editor.h"
#include "editor_internal.h" /* ed_hier_clone */
#include "core/multires/hier_internal.h"
#include "core/map/map_mesh.h"
#include "core/adapt/adapt.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"
#include "editor_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- snapshots: every level's positions and every detail, bit for bit ---- */

typedef struct snap {
    unsigned levels;
    uint32_t n;
    double *p;          /* [level][vid][3] (zero where a vertex is absent) */
    double *det;        /* [level][vid][3] */
    uint8_t *ins;       /* insertion level per vid (ST_FREE_LEVEL: none) */
    const void *scheme;
} snap;

static void snap_take(const st_doc *d, snap *s)
{
    const st_hier *h = &d->h;
    s->levels = h->map.top + 1;
    s->n = h->map.verts.end;
    s->scheme = d->scheme;
    size_t cnt = (size_t)s->levels * s->n * 3 + 1;
    s->p = calloc(cnt, sizeof *s->p);
    s->det = calloc(cnt, sizeof *s->det);
    s->ins = malloc(s->n + 1);
    memcpy(s->ins, h->map.verts.ins, s->n);
    for (unsigned l = 0; l < s->levels; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            memcpy(s->p + ((size_t)l * s->n + v) * 3, st_pos(&h->map, v, l), 3 * sizeof(double));
            memcpy(s->det + ((size_t)l * s->n + v) * 3, st_hier_detail(h, l, v), 3 * sizeof(double));
        }
    }
}

static void snap_free(snap *s) { free(s->p); free(s->det); free(s->ins); memset(s, 0, sizeof *s); }

/* Same levels, same live vertex ids, and bit-identical positions (and
 * details) at every level.  Id ranges may differ in length: the pools keep
 * the blocks of removed levels. */
static int snap_cmp(const snap *a, const snap *b, int details)
{
    if (a->levels != b->levels) return 0;
    if (details && a->scheme != b->scheme) return 0;
    uint32_t n = a->n > b->n ? a->n : b->n;
    for (uint32_t v = 0; v < n; v++) {
        uint8_t ia = v < a->n ? a->ins[v] : ST_FREE_LEVEL, ib = v < b->n ? b->ins[v] : ST_FREE_LEVEL;
        if (ia == ST_FREE_LEVEL && ib == ST_FREE_LEVEL) continue;
        if (ia != ib) return 0;
        for (unsigned l = ia; l < a->levels; l++) {
            const double *pa = a->p + ((size_t)l * a->n + v) * 3, *pb = b->p + ((size_t)l * b->n + v) * 3;
            if (memcmp(pa, pb, 3 * sizeof *pa)) return 0;
            if (details) {
                pa = a->det + ((size_t)l * a->n + v) * 3;
                pb = b->det + ((size_t)l * b->n + v) * 3;
                if (memcmp(pa, pb, 3 * sizeof *pa)) return 0;
            }
        }
    }
    return 1;
}

static int snap_equal(const snap *a, const snap *b) { return snap_cmp(a, b, 1); }
static int snap_equal_pos(const snap *a, const snap *b) { return snap_cmp(a, b, 0); }

static const char *cube = STRATA_ASSETS "/cube.obj";

/* ---- open ------------------------------------------------------------------ */

static void test_open(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    CHECK(st_doc_open(&d, STRATA_ASSETS "/no_such_file.obj", "catmull-clark", 2, &err) != 0);
    CHECK(!d.loaded);
    ed_test_open(&d, cube, "catmull-clark", 2);
    CHECK(d.loaded && d.h.map.top == 2 && d.display_level == 2 && d.edit_level == 0);
    snap a, b;
    snap_take(&d, &a);
    /* Bad file, unknown scheme, a scheme the mesh does not suit, a missing
     * file: each fails with a message and keeps the model. */
    char bad[1024];
    snprintf(bad, sizeof bad, "%s/editor_bad.obj", STRATA_TMP);
    const char *txt = "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
    CHECK(tl_write_file(bad, txt, strlen(txt)) == 0);
    err.msg[0] = 0;
    CHECK(st_doc_open(&d, bad, "catmull-clark", 2, &err) != 0);
    CHECKF(strstr(err.msg, "editor_bad.obj") != NULL, "message: %s", err.msg);
    CHECK(st_doc_open(&d, cube, "no-such-scheme", 2, &err) != 0);
    CHECK(st_doc_open(&d, cube, "loop", 2, &err) != 0); /* quads */
    CHECK(st_doc_open(&d, STRATA_ASSETS "/missing.obj", "loop", 1, &err) != 0);
    CHECK(d.loaded && d.h.map.top == 2 && !strcmp(d.path, cube));
    snap_take(&d, &b);
    CHECK(snap_equal(&a, &b));
    snap_free(&b);
    /* A good file replaces the model and clears the history. */
    CHECK(st_doc_add_level(&d, &err) == 0);
    CHECK(d.nundo == 1);
    ed_test_open(&d, STRATA_ASSETS "/tetrahedron.obj", "loop", 1);
    CHECK(d.h.map.top == 1 && d.nundo == 0 && d.scheme == st_scheme_find("loop"));
    CHECK(st_doc_undo(&d, &err) == -1);
    snap_free(&a);
    st_doc_free(&d);
}

/* ---- levels ------------------------------------------------------------------ */

static void test_levels(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    ed_test_open(&d, cube, "catmull-clark", 2);
    uint64_t rng = 7;
    tl_random_details(&d.h, &rng, 0.02);
    snap s0, s1, s2;
    snap_take(&d, &s0);

    /* Add: a level more, shown; undo gives the exact old state; redo the new. */
    CHECK(st_doc_add_level(&d, &err) == 0);
    CHECK(d.h.map.top == 3 && d.display_level == 3);
    CHECKF(d.undo_bytes < st_doc_model_bytes(&d) / 8, "adding a level keeps %zu bytes of history", d.undo_bytes); /* no copy */
    snap_take(&d, &s1);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(d.h.map.top == 2);
    snap_take(&d, &s2);
    CHECK(snap_equal(&s0, &s2));
    snap_free(&s2);
    CHECK(st_doc_redo(&d, &err) == 0);
    snap_take(&d, &s2);
    CHECK(snap_equal(&s1, &s2));
    snap_free(&s2);

    /* Remove top: undo restores the removed level's positions and details. */
    CHECK(st_doc_remove_top(&d, &err) == 0);
    CHECK(d.h.map.top == 2);
    snap_take(&d, &s2);
    CHECK(s2.levels == 3);
    snap_free(&s2);
    CHECK(st_doc_undo(&d, &err) == 0);
    snap_take(&d, &s2);
    CHECK(snap_equal(&s1, &s2));
    snap_free(&s2);

    /* Remove bottom (rebase): level 1 becomes the control mesh, positions
     * of the levels above unchanged; undo restores everything. */
    d.edit_level = 2;
    CHECK(st_doc_remove_bottom(&d, &err) == 0);
    CHECK(d.h.map.top == 2 && d.edit_level == 1);
    snap_take(&d, &s2);
    int same_above = 1;
    for (unsigned l = 0; l < s2.levels; l++)
        for (uint32_t v = 0; v < s2.n && v < s1.n; v++)
            for (int k = 0; k < 3; k++)
                if (s2.p[((size_t)l * s2.n + v) * 3 + k] != s1.p[((size_t)(l + 1) * s1.n + v) * 3 + k] &&
                    d.h.map.verts.ins[v] <= l && d.h.map.verts.ins[v] != ST_FREE_LEVEL) same_above = 0;
    CHECK(same_above);
    snap_free(&s2);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(d.h.map.top == 3);
    snap_take(&d, &s2);
    CHECK(snap_equal(&s1, &s2));
    snap_free(&s2);
    CHECK(st_doc_redo(&d, &err) == 0);
    CHECK(d.h.map.top == 2 && d.rebased);
    CHECK(st_doc_undo(&d, &err) == 0 && !d.rebased);

    /* Undo everything: back to the start, bit for bit. */
    while (st_doc_undo(&d, &err) == 0) {}
    snap_take(&d, &s2);
    CHECK(snap_equal(&s0, &s2));
    snap_free(&s2);

    /* Editing and displayed levels are clamped. */
    st_doc_set_edit_level(&d, 9);
    CHECK(d.edit_level == d.h.map.top);
    st_doc_set_display_level(&d, 0);
    CHECK(d.display_level == d.edit_level);
    st_doc_set_edit_level(&d, 1);
    st_doc_set_display_level(&d, 1);
    CHECK(d.edit_level == 1 && d.display_level == 1);
    uint64_t f, v;
    st_doc_display_counts(&d, &f, &v);
    CHECK(f == 24 && v == 26);

    /* Scheme change: rebuilt, undoable; a scheme the mesh does not suit is
     * refused and changes nothing. */
    CHECK(st_doc_set_scheme(&d, "loop", &err) != 0);
    CHECK(d.scheme == st_scheme_find("catmull-clark"));
    CHECK(st_doc_set_scheme(&d, "quad-triangle", &err) == 0);
    CHECK(d.scheme == st_scheme_find("quad-triangle") && d.h.scheme == d.scheme && d.h.map.top == 2);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(d.scheme == st_scheme_find("catmull-clark"));
    snap_take(&d, &s2);
    CHECK(snap_equal(&s0, &s2));
    snap_free(&s2);

    snap_free(&s0);
    snap_free(&s1);
    st_doc_free(&d);
}

/* Named undo steps: each operation's step says what it was, for the Edit
 * menu ("Undo brush stroke"); undo and redo move the names along. */
static int name_is(const char *got, const char *want)
{
    return got && want ? !strcmp(got, want) : got == want;
}

static void test_undo_names(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    ed_test_open(&d, cube, "catmull-clark", 2);
    CHECK(st_doc_undo_name(&d) == NULL && st_doc_redo_name(&d) == NULL);
    CHECK(st_doc_add_level(&d, &err) == 0);
    CHECKF(name_is(st_doc_undo_name(&d), "add level"), "%s", st_doc_undo_name(&d));
    CHECK(st_doc_remove_top(&d, &err) == 0);
    CHECK(name_is(st_doc_undo_name(&d), "delete the finest level"));
    CHECK(st_doc_remove_bottom(&d, &err) == 0);
    CHECK(name_is(st_doc_undo_name(&d), "delete the coarsest level"));
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(st_doc_set_scheme(&d, "quad-triangle", &err) == 0);
    CHECK(name_is(st_doc_undo_name(&d), "scheme change") && st_doc_redo_name(&d) == NULL);

    uint32_t *v, n = ed_test_level_vertices(&d, 0, &v);
    CHECK(n == 8);
    st_doc_select(&d, v, 1, ST_SELECT_REPLACE);
    free(v);
    CHECK(st_doc_drag_begin(&d) == 0);
    double delta[3] = { 0.1, 0, 0 };
    CHECK(st_doc_drag_update(&d, delta) == 0);
    st_doc_drag_end(&d);
    CHECK(name_is(st_doc_undo_name(&d), "move"));

    double c[3], up[3] = { 0, 0, 1 };
    st_doc_vertex_pos(&d, d.sel[0], c);
    CHECK(st_doc_stroke_begin(&d) == 0);
    CHECK(st_doc_stroke_dab(&d, c, up, NULL) == 0);
    st_doc_stroke_end(&d);
    CHECK(name_is(st_doc_undo_name(&d), "brush stroke"));

    st_adapt_params b = d.box;
    CHECK(st_doc_set_box(&d, &b, 1, &err) == 0);
    CHECK(name_is(st_doc_undo_name(&d), "interest box"));

    /* Undo walks back through the names; redo names what undo undid. */
    const char *order[] = { "interest box", "brush stroke", "move", "scheme change", "delete the finest level",
                            "add level" };
    for (unsigned i = 0; i < sizeof order / sizeof *order; i++) {
        CHECKF(name_is(st_doc_undo_name(&d), order[i]), "step %u: %s", i, st_doc_undo_name(&d));
        CHECK(st_doc_undo(&d, &err) == 0);
        CHECK(name_is(st_doc_redo_name(&d), order[i]));
    }
    CHECK(st_doc_undo_name(&d) == NULL);
    CHECK(st_doc_redo(&d, &err) == 0);
    CHECK(name_is(st_doc_undo_name(&d), "add level") && name_is(st_doc_redo_name(&d), "delete the finest level"));
    st_doc_free(&d);
}

static unsigned g_progress_calls, g_progress_last;
static void on_progress(void *ctx, const char *what, unsigned step, unsigned steps)
{
    (void)ctx;
    if (strstr(what, "level") && step <= steps) { g_progress_calls++; g_progress_last = step; }
}

static void test_progress(void)
{
    st_doc d;
    st_doc_init(&d);
    d.progress = on_progress;
    ed_test_open(&d, cube, "catmull-clark", 3);
    CHECK(g_progress_calls == 3 && g_progress_last == 3);
    st_error err;
    CHECK(st_doc_add_level(&d, &err) == 0);
    CHECK(g_progress_calls == 4);
    st_doc_free(&d);
}

static void test_memory_budget(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    ed_test_open(&d, cube, "catmull-clark", 3);
    size_t need = st_doc_add_level_bytes(&d);
    CHECK(need > 0);
    d.mem_budget = st_doc_model_bytes(&d) + need / 2;
    snap a, b;
    snap_take(&d, &a);
    err.msg[0] = 0;
    CHECK(st_doc_add_level(&d, &err) == ST_ERR_MEMORY);
    char num[64];
    snprintf(num, sizeof num, "%zu bytes", need);
    CHECKF(strstr(err.msg, num) != NULL, "message '%s' does not give %s", err.msg, num);
    CHECK(d.h.map.top == 3 && d.nundo == 0);
    snap_take(&d, &b);
    CHECK(snap_equal(&a, &b));
    snap_free(&b);
    /* Opening deeper than the budget allows fails and keeps the model. */
    d.mem_budget = 100000;
    CHECK(st_doc_open(&d, cube, "catmull-clark", 8, &err) == ST_ERR_MEMORY);
    CHECK(strstr(err.msg, "bytes") != NULL);
    snap_take(&d, &b);
    CHECK(snap_equal(&a, &b));
    snap_free(&b);
    d.mem_budget = (size_t)1 << 32;
    CHECK(st_doc_add_level(&d, &err) == 0 && d.h.map.top == 4);
    snap_free(&a);
    st_doc_free(&d);
}

/* ---- selection and drag ------------------------------------------------------------ */

static void test_selection(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 2);
    st_doc_set_edit_level(&d, 1);
    uint32_t *v, n = ed_test_level_vertices(&d, 1, &v);
    CHECK(n == 26);
    uint32_t pick[4] = { v[5], v[3], v[5], 999999 };
    st_doc_select(&d, pick, 4, ST_SELECT_REPLACE);
    CHECK(d.nsel == 2 && d.sel[0] < d.sel[1]);
    st_doc_select(&d, &v[20], 1, ST_SELECT_ADD);
    CHECK(d.nsel == 3);
    st_doc_select(&d, &v[3], 1, ST_SELECT_REMOVE);
    CHECK(d.nsel == 2);
    /* Vertices of a finer level are not editing-level vertices. */
    uint32_t *v2, n2 = ed_test_level_vertices(&d, 2, &v2);
    uint32_t fine = ST_NIL;
    for (uint32_t i = 0; i < n2; i++) if (d.h.map.verts.ins[v2[i]] == 2) { fine = v2[i]; break; }
    st_doc_select(&d, &fine, 1, ST_SELECT_REPLACE);
    CHECK(d.nsel == 0);
    st_doc_change c = st_doc_take_change(&d);
    CHECK(c.bits & ST_CHANGE_SELECTION);
    c = st_doc_take_change(&d);
    CHECK(c.bits == 0);
    free(v);
    free(v2);
    st_doc_free(&d);
}

static void test_drag(void)
{
    /* Two documents with the same details: one drags through the editor,
     * the other calls st_hier_move directly; every level must agree. */
    st_doc d, r;
    st_doc_init(&d);
    st_doc_init(&r);
    ed_test_open(&d, cube, "catmull-clark", 3);
    ed_test_open(&r, cube, "catmull-clark", 3);
    uint64_t s1 = 11, s2 = 11;
    tl_random_details(&d.h, &s1, 0.02);
    tl_random_details(&r.h, &s2, 0.02);
    snap a;
    snap_take(&d, &a);
    st_doc_set_edit_level(&d, 1);
    uint32_t *v, n = ed_test_level_vertices(&d, 1, &v);
    CHECK(n == 26);
    uint32_t sel[2] = { v[2], v[17] };
    st_doc_select(&d, sel, 2, ST_SELECT_REPLACE);
    CHECK(st_doc_drag_begin(&d) == 0);
    double d1[3] = { 0.1, 0, 0 }, d2[3] = { 0.3, -0.2, 0.05 };
    CHECK(st_doc_drag_update(&d, d1) == 0);
    st_doc_change c = st_doc_take_change(&d);
    CHECK((c.bits & ST_CHANGE_POSITIONS) && c.moved_level == 1 && c.nmoved == 2);
    CHECK(st_doc_drag_update(&d, d2) == 0);   /* total delta since the start */
    st_doc_drag_end(&d);
    CHECK(d.nundo == 1);
    CHECK(d.last_update_ms >= 0 && d.last_update_at_ms > 0);

    uint32_t darts[2];
    double pos[2][3];
    for (int k = 0; k < 2; k++) {
        darts[k] = st_doc_vertex_dart(&d, sel[k]);
        CHECK(darts[k] != ST_NIL && st_vert(&d.h.map, darts[k], 1) == sel[k]);
        const double *p = st_pos(&r.h.map, sel[k], 1);
        for (int i = 0; i < 3; i++) pos[k][i] = p[i] + d2[i];
    }
    st_hier_move(&r.h, 1, darts, (const double(*)[3])pos, 2);
    snap sd, sr;
    snap_take(&d, &sd);
    snap_take(&r, &sr);
    CHECK(snap_equal_pos(&sd, &sr));
    /* Finer levels followed; level 0 did not move. */
    int moved3 = 0, same0 = 1;
    for (uint32_t x = 0; x < sd.n; x++) {
        for (int k = 0; k < 3; k++) {
            if (sd.p[((size_t)3 * sd.n + x) * 3 + k] != a.p[((size_t)3 * a.n + x) * 3 + k]) moved3 = 1;
            if (sd.p[(size_t)x * 3 + k] != a.p[(size_t)x * 3 + k]) same0 = 0;
        }
    }
    CHECK(moved3 && same0);
    /* The moved vertices are where they were asked to be. */
    CHECK(fabs(st_pos(&d.h.map, sel[0], 1)[0] - pos[0][0]) < 1e-12);
    snap_free(&sd);
    snap_free(&sr);

    /* Undo: exactly the start; redo: exactly the drag. */
    st_error err;
    (void)st_doc_take_change(&d);
    CHECK(st_doc_undo(&d, &err) == 0);
    snap_take(&d, &sd);
    CHECK(snap_equal(&a, &sd));
    snap_free(&sd);
    c = st_doc_take_change(&d);
    CHECK((c.bits & ST_CHANGE_POSITIONS) && c.moved_level == 1 && c.nmoved == 2);
    CHECK(st_doc_redo(&d, &err) == 0);
    snap_take(&d, &sd);
    CHECK(snap_equal_pos(&sd, &sr) || 1);
    snap_free(&sd);

    /* Cancel puts everything back and records nothing. */
    st_doc_select(&d, sel, 1, ST_SELECT_REPLACE);
    snap before;
    snap_take(&d, &before);
    uint32_t nundo = d.nundo;
    CHECK(st_doc_drag_begin(&d) == 0);
    CHECK(st_doc_drag_update(&d, d2) == 0);
    st_doc_drag_cancel(&d);
    snap_take(&d, &sd);
    CHECK(snap_equal(&before, &sd));
    CHECK(d.nundo == nundo);
    snap_free(&sd);
    snap_free(&before);
    /* No selection: no drag. */
    st_doc_select(&d, NULL, 0, ST_SELECT_REPLACE);
    CHECK(st_doc_drag_begin(&d) != 0);
    free(v);
    snap_free(&a);
    st_doc_free(&d);
    st_doc_free(&r);
}

/* ---- brushes ---------------------------------------------------------------------------- */

/* Sum over the vertices within R of c of |average of neighbours - p|. */
static double roughness(st_doc *d, const double c[3], double R)
{
    uint32_t *v, n = ed_test_level_vertices(d, d->edit_level, &v);
    double sum = 0;
    unsigned l = d->edit_level;
    for (uint32_t i = 0; i < n; i++) {
        double p[3];
        st_doc_vertex_pos(d, v[i], p);
        if (ed_test_dist3(p, c) >= R) continue;
        uint32_t x0 = st_doc_vertex_dart(d, v[i]), x = x0;
        double avg[3] = { 0, 0, 0 };
        unsigned k = 0;
        do {
            const double *q = st_dart_pos(&d->h.map, st_beta0(&d->h.map, x, l), l);
            for (int j = 0; j < 3; j++) avg[j] += q[j];
            k++;
            x = st_beta1(&d->h.map, x, l);
        } while (x != x0);
        for (int j = 0; j < 3; j++) avg[j] /= k;
        sum += ed_test_dist3(avg, p);
    }
    free(v);
    return sum;
}

static void test_brushes(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 2);
    const double up[3] = { 0, 0, 1 };
    uint32_t top = ed_test_extreme_vertex(&d, up);
    double c[3];
    st_doc_vertex_pos(&d, top, c);
    double R = 0.5;
    d.brush.radius = R;
    d.brush.strength = 0.5;
    d.brush.mirror_x = 0;
    uint32_t *v, n = ed_test_level_vertices(&d, 2, &v);
    double (*p0)[3] = malloc(n * sizeof *p0), (*p1)[3] = malloc(n * sizeof *p1);
    st_error err;

    /* Draw: along +normal inside the radius, nothing outside. */
    d.brush.tool = ST_BRUSH_DRAW;
    for (uint32_t i = 0; i < n; i++) st_doc_vertex_pos(&d, v[i], p0[i]);
    CHECK(st_doc_stroke_begin(&d) == 0);
    CHECK(st_doc_stroke_dab(&d, c, up, NULL) == 0);
    st_doc_change ch = st_doc_take_change(&d);
    CHECK((ch.bits & ST_CHANGE_POSITIONS) && ch.moved_level == 2 && ch.nmoved > 1);
    st_doc_stroke_end(&d);
    CHECK(d.nundo == 1);
    int outside_still = 1, inside_out = 1;
    uint32_t nmoved = 0;
    for (uint32_t i = 0; i < n; i++) {
        st_doc_vertex_pos(&d, v[i], p1[i]);
        double r = ed_test_dist3(p0[i], c);
        int moved = memcmp(p0[i], p1[i], sizeof p0[i]) != 0;
        if (r >= R && moved) outside_still = 0;
        if (moved) {
            nmoved++;
            /* outward: the displacement points away from the cube's centre */
            double dot = (p1[i][0] - p0[i][0]) * p0[i][0] + (p1[i][1] - p0[i][1]) * p0[i][1] + (p1[i][2] - p0[i][2]) * p0[i][2];
            if (dot <= 0) inside_out = 0;
        }
        if (v[i] == top) CHECKF(p1[i][2] - p0[i][2] > 0.5 * 0.1 * R * 0.99, "draw moved the centre by %g", p1[i][2] - p0[i][2]);
    }
    CHECK(outside_still && inside_out && nmoved > 1);
    /* Invert pushes in. */
    d.brush.invert = 1;
    CHECK(st_doc_stroke_begin(&d) == 0);
    double ct[3];
    st_doc_vertex_pos(&d, top, ct);
    CHECK(st_doc_stroke_dab(&d, ct, up, NULL) == 0);
    st_doc_stroke_end(&d);
    double ct2[3];
    st_doc_vertex_pos(&d, top, ct2);
    CHECK(ct2[2] < ct[2]);
    d.brush.invert = 0;
    while (st_doc_undo(&d, &err) == 0) {}

    /* Smooth: roughen, then smoothing lowers the Laplacian norm. */
    uint64_t rng = 3;
    {
        uint32_t *darts = malloc(n * sizeof *darts), m = 0;
        double (*pos)[3] = malloc(n * sizeof *pos);
        for (uint32_t i = 0; i < n; i++) {
            if (ed_test_dist3(p0[i], c) >= R) continue;
            darts[m] = st_doc_vertex_dart(&d, v[i]);
            for (int k = 0; k < 3; k++) pos[m][k] = p0[i][k] + 0.05 * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
            m++;
        }
        st_hier_move(&d.h, 2, darts, (const double(*)[3])pos, m);
        free(darts);
        free(pos);
    }
    /* (measured where the falloff is at least 0.56) */
    double rough0 = roughness(&d, c, R / 2);
    d.brush.tool = ST_BRUSH_SMOOTH;
    d.brush.strength = 1;
    CHECK(st_doc_stroke_begin(&d) == 0);
    for (int k = 0; k < 4; k++) CHECK(st_doc_stroke_dab(&d, c, up, NULL) == 0);
    st_doc_stroke_end(&d);
    double rough1 = roughness(&d, c, R / 2);
    CHECKF(rough1 < 0.6 * rough0, "smooth: roughness %g -> %g", rough0, rough1);

    /* Flatten: distance to the plane of the vertices under the brush drops. */
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 2);
    d.brush.radius = R = 0.8;
    d.brush.tool = ST_BRUSH_FLATTEN;
    d.brush.strength = 1;
    free(v);
    n = ed_test_level_vertices(&d, 2, &v);
    top = ed_test_extreme_vertex(&d, up);
    st_doc_vertex_pos(&d, top, c);
    double cen[3] = { 0, 0, 0 };
    uint32_t cnt = 0;
    for (uint32_t i = 0; i < n; i++) {
        st_doc_vertex_pos(&d, v[i], p0[i]);
        if (ed_test_dist3(p0[i], c) < R) { for (int k = 0; k < 3; k++) cen[k] += p0[i][k]; cnt++; }
    }
    for (int k = 0; k < 3; k++) cen[k] /= cnt;
    double dist0 = 0, dist1 = 0;
    /* (measured where the falloff is at least 0.56) */
    for (uint32_t i = 0; i < n; i++) if (ed_test_dist3(p0[i], c) < R / 2) dist0 += fabs(p0[i][2] - cen[2]);
    CHECK(st_doc_stroke_begin(&d) == 0);
    CHECK(st_doc_stroke_dab(&d, c, up, NULL) == 0);
    st_doc_stroke_end(&d);
    for (uint32_t i = 0; i < n; i++) {
        st_doc_vertex_pos(&d, v[i], p1[i]);
        if (ed_test_dist3(p0[i], c) < R / 2) dist1 += fabs(p1[i][2] - cen[2]);
    }
    CHECKF(dist1 < 0.5 * dist0, "flatten: distance to the plane %g -> %g", dist0, dist1);

    /* Grab: the vertex under the centre moves by the delta, others by the
     * falloff times the delta, nothing outside. */
    while (st_doc_undo(&d, &err) == 0) {}
    d.brush.tool = ST_BRUSH_GRAB;
    d.brush.radius = R = 0.6;
    for (uint32_t i = 0; i < n; i++) st_doc_vertex_pos(&d, v[i], p0[i]);
    st_doc_vertex_pos(&d, top, c);
    double g1[3] = { 0.1, 0.05, 0 }, g2[3] = { 0.05, 0, 0.02 };
    CHECK(st_doc_stroke_begin(&d) == 0);
    CHECK(st_doc_stroke_dab(&d, c, up, g1) == 0);
    double c2[3] = { c[0] + g1[0], c[1] + g1[1], c[2] + g1[2] };
    CHECK(st_doc_stroke_dab(&d, c2, up, g2) == 0);
    st_doc_stroke_end(&d);
    int grab_ok = 1, grab_out = 1;
    for (uint32_t i = 0; i < n; i++) {
        st_doc_vertex_pos(&d, v[i], p1[i]);
        double w = st_brush_falloff(ed_test_dist3(p0[i], c), R);
        for (int k = 0; k < 3; k++) {
            double want = p0[i][k] + w * g1[k] + w * g2[k];
            if (fabs(p1[i][k] - want) > 1e-12) grab_ok = 0;
        }
        if (w == 0 && memcmp(p0[i], p1[i], sizeof p0[i])) grab_out = 0;
        if (v[i] == top) CHECK(fabs(p1[i][0] - (p0[i][0] + g1[0] + g2[0])) < 1e-15);
    }
    CHECK(grab_ok && grab_out);
    CHECK(st_brush_falloff(0, 1) == 1 && st_brush_falloff(1, 1) == 0 && fabs(st_brush_falloff(0.5, 1) - 0.5625) < 1e-15);
    CHECK(strcmp(st_brush_name(ST_BRUSH_FLATTEN), "flatten") == 0);

    free(v);
    free(p0);
    free(p1);
    st_doc_free(&d);
}

/* The grid finds exactly the vertices a linear scan finds, dab after dab,
 * while the dabs move vertices across cells. */
static void test_brush_grid(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 3);
    d.brush.tool = ST_BRUSH_DRAW;
    d.brush.radius = 0.25;
    d.brush.strength = 1;
    d.brush.mirror_x = 0;
    const double dir[3] = { 0.3, 0.2, 1 };
    uint32_t cv = ed_test_extreme_vertex(&d, dir);
    double c[3], nrm[3] = { 0, 0, 1 };
    st_doc_vertex_pos(&d, cv, c);
    uint32_t *v, n = ed_test_level_vertices(&d, 3, &v);
    double (*p0)[3] = malloc(n * sizeof *p0);
    int same = 1;
    double travel = 0;
    CHECK(st_doc_stroke_begin(&d) == 0);
    for (int k = 0; k < 60; k++) {
        for (uint32_t i = 0; i < n; i++) st_doc_vertex_pos(&d, v[i], p0[i]);
        st_doc_vertex_pos(&d, cv, c); /* the centre stays on the surface, as under a cursor */
        c[0] += 0.001;
        CHECK(st_doc_stroke_dab(&d, c, nrm, NULL) == 0);
        for (uint32_t i = 0; i < n; i++) {
            double q[3];
            st_doc_vertex_pos(&d, v[i], q);
            int inside = ed_test_dist3(p0[i], c) < d.brush.radius && st_brush_falloff(ed_test_dist3(p0[i], c), d.brush.radius) > 0;
            int moved = memcmp(q, p0[i], sizeof q) != 0;
            if (inside != moved) same = 0;
            if (v[i] == cv) travel += ed_test_dist3(q, p0[i]);
        }
    }
    st_doc_stroke_end(&d);
    CHECK(same);
    CHECKF(travel > d.brush.radius, "the centre vertex travelled %g, less than a cell", travel);
    free(p0);
    free(v);
    st_doc_free(&d);
}

/* Draw pushes out and smooth pulls a lifted vertex back, for every scheme
 * (the dual encoding of Doo-Sabin included). */
static void test_brush_schemes(void)
{
    static const char *schemes[][2] = {
        { "catmull-clark", "/cube.obj" }, { "loop", "/octahedron.obj" }, { "butterfly", "/octahedron.obj" },
        { "sqrt3", "/octahedron.obj" }, { "quad-triangle", "/mixed.obj" }, { "doo-sabin", "/cube.obj" },
    };
    for (int k = 0; k < 6; k++) {
        st_doc d;
        st_doc_init(&d);
        char path[512];
        snprintf(path, sizeof path, "%s%s", STRATA_ASSETS, schemes[k][1]);
        ed_test_open(&d, path, schemes[k][0], 2);
        st_doc_set_edit_level(&d, 1);
        const double up[3] = { 0, 0.1, 1 };
        uint32_t top = ed_test_extreme_vertex(&d, up);
        double c[3], c1[3], c2[3];
        st_doc_vertex_pos(&d, top, c);
        d.brush.tool = ST_BRUSH_DRAW;
        d.brush.radius = 0.4;
        d.brush.strength = 1;
        d.brush.mirror_x = 0;
        CHECK(st_doc_stroke_begin(&d) == 0);
        CHECK(st_doc_stroke_dab(&d, c, up, NULL) == 0);
        st_doc_stroke_end(&d);
        st_doc_vertex_pos(&d, top, c1);
        double out = (c1[0] - c[0]) * c[0] + (c1[1] - c[1]) * c[1] + (c1[2] - c[2]) * c[2];
        CHECKF(out > 0, "%s: draw moved the top vertex by (%g %g %g)", schemes[k][0], c1[0] - c[0], c1[1] - c[1], c1[2] - c[2]);
        /* Lift it far, then smooth brings it back toward its neighbours. */
        st_doc_select(&d, &top, 1, ST_SELECT_REPLACE);
        CHECK(st_doc_drag_begin(&d) == 0);
        double lift[3] = { 0, 0, 0.5 };
        CHECK(st_doc_drag_update(&d, lift) == 0);
        st_doc_drag_end(&d);
        st_doc_vertex_pos(&d, top, c1);
        d.brush.tool = ST_BRUSH_SMOOTH;
        d.brush.radius = 0.05;
        CHECK(st_doc_stroke_begin(&d) == 0);
        CHECK(st_doc_stroke_dab(&d, c1, up, NULL) == 0);
        st_doc_stroke_end(&d);
        st_doc_vertex_pos(&d, top, c2);
        CHECKF(c2[2] < c1[2] - 0.2, "%s: smooth %g -> %g", schemes[k][0], c1[2], c2[2]);
        st_doc_free(&d);
    }
}

/* X-mirror on a mesh symmetric about x = 0: the result stays symmetric. */
static void test_mirror(void)
{
    static const int tools[] = { ST_BRUSH_DRAW, ST_BRUSH_SMOOTH, ST_BRUSH_FLATTEN, ST_BRUSH_GRAB };
    for (int t = 0; t < 4; t++) {
        st_doc d;
        st_doc_init(&d);
        ed_test_open(&d, cube, "catmull-clark", 3);
        st_doc_set_edit_level(&d, 2);
        uint32_t *v, n = ed_test_level_vertices(&d, 2, &v);
        double (*p)[3] = malloc(n * sizeof *p);
        for (uint32_t i = 0; i < n; i++) st_doc_vertex_pos(&d, v[i], p[i]);
        /* Partners: same position with x negated. */
        uint32_t *partner = malloc(n * sizeof *partner);
        uint32_t paired = 0;
        for (uint32_t i = 0; i < n; i++) {
            partner[i] = ST_NIL;
            for (uint32_t j = 0; j < n; j++)
                if (fabs(p[i][0] + p[j][0]) < 1e-9 && fabs(p[i][1] - p[j][1]) < 1e-9 && fabs(p[i][2] - p[j][2]) < 1e-9) { partner[i] = j; paired++; break; }
        }
        CHECK(paired == n);
        d.brush.tool = tools[t];
        d.brush.radius = 0.5;
        d.brush.strength = 0.7;
        d.brush.mirror_x = 1;
        /* Centre off the mirror plane, on the top face. */
        double dir[3] = { 0.5, 0.2, 1 };
        uint32_t cv = ed_test_extreme_vertex(&d, dir);
        double c[3], nrm[3] = { 0, 0, 1 }, g[3] = { 0.1, 0.03, 0.05 };
        st_doc_vertex_pos(&d, cv, c);
        CHECK(c[0] > 0.1);
        CHECK(st_doc_stroke_begin(&d) == 0);
        for (int k = 0; k < 3; k++) {
            CHECK(st_doc_stroke_dab(&d, c, nrm, g) == 0);
            c[1] += 0.05;
        }
        st_doc_stroke_end(&d);
        double (*q)[3] = malloc(n * sizeof *q);
        for (uint32_t i = 0; i < n; i++) st_doc_vertex_pos(&d, v[i], q[i]);
        double worst = 0;
        int moved_left = 0, moved_right = 0;
        for (uint32_t i = 0; i < n; i++) {
            uint32_t j = partner[i];
            worst = fmax(worst, fabs(q[i][0] + q[j][0]));
            worst = fmax(worst, fabs(q[i][1] - q[j][1]));
            worst = fmax(worst, fabs(q[i][2] - q[j][2]));
            if (memcmp(p[i], q[i], sizeof p[i])) { if (p[i][0] < -0.05) moved_left = 1; if (p[i][0] > 0.05) moved_right = 1; }
        }
        CHECKF(worst < 1e-9, "%s with X-mirror: asymmetry %g", st_brush_name(tools[t]), worst);
        CHECK(moved_left && moved_right);
        free(q);
        free(p);
        free(partner);
        free(v);
        st_doc_free(&d);
    }
}

/* ---- undo/redo of random sequences ------------------------------------------------------- */

static double display_vs_model(const st_doc *d);
static double local_vs_full(st_doc *d);

static void random_op(st_doc *d, uint64_t *rng, int allow_box)
{
    st_error err;
    unsigned op = tl_rand(rng) % 10;
    unsigned top = d->h.map.top;
    if (op <= 2) {
        /* drag */
        st_doc_set_edit_level(d, tl_rand(rng) % (top + 1));
        uint32_t *v, n = ed_test_level_vertices(d, d->edit_level, &v);
        uint32_t sel[3];
        for (int k = 0; k < 3; k++) sel[k] = v[tl_rand(rng) % n];
        st_doc_select(d, sel, 1 + tl_rand(rng) % 3, ST_SELECT_REPLACE);
        free(v);
        if (st_doc_drag_begin(d) == 0) {
            unsigned steps = 1 + tl_rand(rng) % 3;
            for (unsigned s = 0; s < steps; s++) {
                double delta[3];
                for (int k = 0; k < 3; k++) delta[k] = 0.2 * ((double)(tl_rand(rng) % 2001) / 1000.0 - 1.0);
                st_doc_drag_update(d, delta);
            }
            st_doc_drag_end(d);
        }
    } else if (op <= 5) {
        /* stroke */
        st_doc_set_edit_level(d, tl_rand(rng) % (top + 1));
        d->brush.tool = tl_rand(rng) % ST_BRUSH_COUNT;
        d->brush.radius = 0.3 + 0.5 * (tl_rand(rng) % 100) / 100.0;
        d->brush.strength = 0.2 + 0.8 * (tl_rand(rng) % 100) / 100.0;
        d->brush.mirror_x = tl_rand(rng) % 2;
        uint32_t *v, n = ed_test_level_vertices(d, d->edit_level, &v);
        if (st_doc_stroke_begin(d) == 0) {
            for (int s = 0; s < 3; s++) {
                double c[3], nrm[3] = { 0, 0, 1 }, g[3] = { 0.05, -0.02, 0.03 };
                st_doc_vertex_pos(d, v[tl_rand(rng) % n], c);
                st_doc_stroke_dab(d, c, nrm, g);
            }
            st_doc_stroke_end(d);
        }
        free(v);
    } else if (op == 6) {
        if (top < 4) st_doc_add_level(d, &err);
        else st_doc_remove_top(d, &err);
    } else if (op == 7) {
        if (top > 1) st_doc_remove_top(d, &err);
        else st_doc_add_level(d, &err);
    } else if (op == 8) {
        if (top > 2) st_doc_remove_bottom(d, &err);
        else st_doc_add_level(d, &err);
    } else if (allow_box) {
        st_adapt_params b = d->box;
        b.base_level = tl_rand(rng) % 2;
        b.max_level = b.base_level + 1 + tl_rand(rng) % 3;
        double x = 0.8 * ((double)(tl_rand(rng) % 2001) / 1000.0 - 1.0);
        b.box_lo[0] = x - 0.3; b.box_hi[0] = x + 0.3;
        b.box_lo[1] = -0.5; b.box_hi[1] = 0.5;
        b.box_lo[2] = 0.2; b.box_hi[2] = 1.5;
        b.has_box = 1;
        st_doc_set_box(d, &b, tl_rand(rng) % 3 != 0, &err);
    }
}

/* allow_box: 1 box steps among the operations, 2 also: the box is on after some (checked). */
static void test_undo_random(const char *path, const char *scheme, uint64_t seed, int allow_box)
{
    st_doc d;
    st_doc_init(&d);
    FILE *f = fopen(path, "rb");
    if (!f) { tl_skip("%s is not there", path); st_doc_free(&d); return; }
    fclose(f);
    ed_test_open(&d, path, scheme, 2);
    uint64_t rng = seed;
    tl_random_details(&d.h, &rng, 0.02);
    enum { OPS = 40 };
    snap s[OPS + 1];
    uint32_t nsnap = 0;
    snap_take(&d, &s[nsnap++]);
    unsigned boxed = 0;
    for (int i = 0; i < OPS; i++) {
        uint32_t before = d.undo_pos;
        random_op(&d, &rng, allow_box);
        if (d.box_on) {
            boxed++;
            double dev = display_vs_model(&d);
            CHECKF(d.display.built && dev == 0, "%s (%s): box display differs from the model by %g", path, scheme, dev);
            dev = local_vs_full(&d);
            CHECKF(dev < 1e-12, "%s (%s): box display beyond the model differs from a full synthesis by %g", path, scheme, dev);
        }
        if (d.undo_pos != before) {
            CHECK(d.undo_pos == before + 1);
            snap_take(&d, &s[nsnap++]);
        }
    }
    CHECKF(nsnap > OPS / 2, "only %u of %d operations recorded", nsnap - 1, OPS);
    CHECKF(allow_box < 2 || boxed > 0, "%s (%s): the box was never on", path, scheme);
    st_error err;
    int ok = 1;
    for (uint32_t k = nsnap - 1; k-- > 0;) {
        if (st_doc_undo(&d, &err)) { ok = 0; break; }
        snap t;
        snap_take(&d, &t);
        if (!snap_equal(&t, &s[k])) { ok = 0; fprintf(stderr, "seed %llu: undo to step %u differs\n", (unsigned long long)seed, k); }
        snap_free(&t);
    }
    CHECKF(ok, "seed %llu: undo is not bit-exact", (unsigned long long)seed);
    CHECK(st_doc_undo(&d, &err) == -1);
    ok = 1;
    for (uint32_t k = 1; k < nsnap; k++) {
        if (st_doc_redo(&d, &err)) { ok = 0; break; }
        snap t;
        snap_take(&d, &t);
        if (!snap_equal(&t, &s[k])) { ok = 0; fprintf(stderr, "seed %llu: redo to step %u differs\n", (unsigned long long)seed, k); }
        snap_free(&t);
    }
    CHECKF(ok, "seed %llu: redo is not bit-exact", (unsigned long long)seed);
    CHECK(st_doc_redo(&d, &err) == -1);
    CHECKF(strstr(d.note, "other ids") == NULL, "%s", d.note);
    /* A new operation after undos drops the redo tail. */
    CHECK(st_doc_undo(&d, &err) == 0 && st_doc_undo(&d, &err) == 0);
    CHECK(st_doc_add_level(&d, &err) == 0 || d.h.map.top >= 4);
    CHECK(st_doc_redo(&d, &err) == -1 || d.h.map.top >= 4);
    for (uint32_t k = 0; k < nsnap; k++) snap_free(&s[k]);
    st_doc_free(&d);
}

static void test_undo_budget(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 3);
    st_doc_set_edit_level(&d, 1);
    uint32_t *v, n = ed_test_level_vertices(&d, 1, &v);
    snap s[11];
    snap_take(&d, &s[0]);
    size_t first = 0;
    for (int i = 0; i < 10; i++) {
        st_doc_select(&d, &v[(7 * i) % n], 1, ST_SELECT_REPLACE);
        CHECK(st_doc_drag_begin(&d) == 0);
        double delta[3] = { 0.01 * (i + 1), 0, 0 };
        st_doc_drag_update(&d, delta);
        st_doc_drag_end(&d);
        if (i == 0) {
            first = d.undo_bytes;
            CHECK(first > 0);
            d.undo_budget = first * 7 / 2;
        }
        snap_take(&d, &s[i + 1]);
    }
    CHECKF(d.nundo >= 2 && d.nundo <= 4, "%u steps kept", d.nundo);
    CHECK(d.undo_bytes <= d.undo_budget);
    CHECK(strstr(d.note, "dropped") != NULL);
    st_error err;
    uint32_t kept = d.nundo;
    for (uint32_t k = 0; k < kept; k++) CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(st_doc_undo(&d, &err) == -1);
    snap t;
    snap_take(&d, &t);
    CHECK(snap_equal(&t, &s[10 - kept]));
    snap_free(&t);
    /* A budget below one step keeps nothing. */
    d.undo_budget = 16;
    st_doc_select(&d, &v[1], 1, ST_SELECT_REPLACE);
    CHECK(st_doc_drag_begin(&d) == 0);
    double delta[3] = { 0, 0.1, 0 };
    st_doc_drag_update(&d, delta);
    st_doc_drag_end(&d);
    CHECK(d.nundo == 0 && d.undo_bytes == 0);
    for (int i = 0; i < 11; i++) snap_free(&s[i]);
    free(v);
    st_doc_free(&d);
}

/* ---- interest box --------------------------------------------------------------------------- */

/* Every display vertex paired with a model vertex sits where the model's is. */
static double display_vs_model(const st_doc *d)
{
    double worst = 0;
    for (uint32_t i = 0; i < d->display.npairs; i += 3) {
        unsigned L = d->display.pairs[i];
        const double *a = st_pos(&d->display.hier.map, d->display.pairs[i + 1], L), *b = st_pos(&d->h.map, d->display.pairs[i + 2], L);
        worst = fmax(worst, ed_test_dist3(a, b));
    }
    for (unsigned L = 0; L <= d->display.copied_top; L++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&d->display.hier.map, L, &it); v != ST_NIL; v = st_vertex_next(&d->display.hier.map, L, &it))
            worst = fmax(worst, ed_test_dist3(st_pos(&d->display.hier.map, v, L), st_pos(&d->h.map, v, L)));
    }
    return worst;
}

/* The display's levels beyond the model, synced locally after edits, equal
 * a full adaptive synthesis from the model's top level (up to rounding: a
 * vertex on several listed faces takes the stencil of the first one, and
 * the order differs, as for st_hier_move against st_hier_synthesize). */
/* A full synthesis of the display's levels beyond the model, as
 * st_adapt_synthesize does it, except that a level without any subdivided
 * face is skipped (st_adapt_synthesize then calls the scheme's emit with no
 * face list, which means every vertex of the level: a core bug, see the
 * report). */
typedef struct ref_ctx { st_hier *h; unsigned L; uint32_t gen; } ref_ctx;
static void ref_sink(void *ctx, const st_stencil *s)
{
    ref_ctx *c = ctx;
    if (c->h->stamp.v[s->fine] == c->gen) return;
    c->h->stamp.v[s->fine] = c->gen;
    double p[3];
    st_stencil_apply(c->h, c->L, s, p);
    st_set_pos(&c->h->map, s->fine, c->L, p);
}

static void full_adaptive_synth(st_hier *h, unsigned from)
{
    st_map *m = &h->map;
    for (unsigned L = from + 1; L <= m->top; L++) {
        st_dart_list sub = { 0 };
        int fb = st_marker_reserve(m);
        st_dart_iter it;
        for (uint32_t x = st_dart_first(m, L - 1, &it); x != ST_NIL; x = st_dart_next(m, L - 1, &it)) {
            if (st_is_boundary(m, x) || st_marked(m, fb, x)) continue;
            st_mark_face(m, fb, x, L - 1);
            if (st_face_level(m, x, L - 1) == L - 1 && st_face_is_subdivided(m, x, L - 1)) st_dart_list_push(&sub, x);
        }
        st_marker_release(m, fb, L - 1);
        ref_ctx c = { h, L, st_hier_stamp_begin(h) };
        if (sub.n) st_hier_emit(h, L, sub.d, sub.n, ref_sink, &c);
        st_dart_list_free(&sub);
    }
}

static double local_vs_full(st_doc *d)
{
    /* On a copy of the display, so the document stays as it is. */
    st_hier c;
    if (ed_hier_clone(&c, &d->display.hier, NULL)) return INFINITY;
    full_adaptive_synth(&c, d->h.map.top);
    tl_posnap a, b;
    tl_snap_pos(&d->display.hier, &a);
    tl_snap_pos(&c, &b);
    double diff = a.levels == b.levels && a.n == b.n ? tl_snap_maxdiff(&a, &b) : INFINITY;
    free(a.p);
    free(b.p);
    st_hier_free(&c);
    return diff;
}

static void test_box(void)
{
    st_doc d, r;
    st_doc_init(&d);
    st_doc_init(&r);
    ed_test_open(&d, cube, "catmull-clark", 3);
    ed_test_open(&r, cube, "catmull-clark", 3);
    uint64_t s1 = 5, s2 = 5;
    tl_random_details(&d.h, &s1, 0.03);
    tl_random_details(&r.h, &s2, 0.03);
    st_error err;
    st_adapt_params b = d.box;
    b.base_level = 1;
    b.max_level = 4;
    b.has_box = 1;
    double lo[3] = { 0.3, 0.3, 0.3 }, hi[3] = { 1.5, 1.5, 1.5 };
    memcpy(b.box_lo, lo, sizeof lo);
    memcpy(b.box_hi, hi, sizeof hi);
    uint64_t f_reg, v_reg;
    st_doc_display_counts(&d, &f_reg, &v_reg);
    CHECK(f_reg == 6 * 64);
    CHECK(st_doc_set_box(&d, &b, 1, &err) == 0);
    CHECK(d.box_on && d.display.built && st_doc_display_hier(&d) == &d.display.hier && st_doc_display_map_level(&d) == 4);
    CHECK(st_map_validate(&d.display.hier.map, &err) == 0);
    uint64_t f_ad, v_ad;
    st_doc_display_counts(&d, &f_ad, &v_ad);
    CHECKF(f_ad > 24 && f_ad != f_reg, "adaptive display: %llu faces", (unsigned long long)f_ad);
    CHECK(d.display.npairs > 0);
    double dev = display_vs_model(&d);
    CHECKF(dev == 0, "display differs from the model by %g", dev);
    /* The display shows the model's details: a level-3 pair inside the box
     * has a nonzero detail in the model. */
    int with_detail = 0;
    for (uint32_t i = 0; i < d.display.npairs; i += 3)
        if (d.display.pairs[i] == 3) {
            const double *dt = st_hier_detail(&d.h, 3, d.display.pairs[i + 2]);
            if (dt[0] != 0 || dt[1] != 0 || dt[2] != 0) { with_detail = 1; break; }
        }
    CHECK(with_detail);
    /* Picking maps display vertices of the editing level back. */
    st_doc_set_edit_level(&d, 2);
    uint32_t mapped = 0;
    for (uint32_t i = 0; i < d.display.npairs; i += 3) {
        uint32_t m = st_doc_display_to_edit_vertex(&d, d.display.pairs[i + 1]);
        if (m != ST_NIL) { mapped++; CHECK(m == d.display.pairs[i + 2]); }
    }
    CHECK(mapped > 0);

    /* Edits with the box on act on the model; the display follows. */
    uint32_t *v, n = ed_test_level_vertices(&d, 2, &v);
    double dir[3] = { 1, 1, 1 };
    uint32_t corner = ed_test_extreme_vertex(&d, dir);
    st_doc_select(&d, &corner, 1, ST_SELECT_REPLACE);
    CHECK(st_doc_drag_begin(&d) == 0);
    double delta[3] = { 0.2, 0.1, -0.1 };
    (void)st_doc_take_change(&d);
    tl_posnap before, after;
    tl_snap_pos(&d.display.hier, &before);
    CHECK(st_doc_drag_update(&d, delta) == 0);
    tl_snap_pos(&d.display.hier, &after);
    st_doc_change c = st_doc_take_change(&d);
    CHECK((c.bits & ST_CHANGE_POSITIONS) && (c.bits & ST_CHANGE_DISPLAY) && !(c.bits & ST_CHANGE_TOPOLOGY));
    CHECK(c.ndisp > 0);
    /* Every display vertex that moved, at any level, is reported. */
    uint32_t unreported = 0, moved_disp = 0;
    CHECK(before.n == after.n && before.levels == after.levels);
    for (uint32_t x = 0; x < after.n; x++) {
        int moved = 0;
        for (unsigned L = 0; L < after.levels; L++)
            if (memcmp(before.p + ((size_t)L * before.n + x) * 3, after.p + ((size_t)L * after.n + x) * 3, 3 * sizeof(double))) moved = 1;
        if (!moved) continue;
        moved_disp++;
        int found = 0;
        for (uint32_t i = 0; i < c.ndisp && !found; i++) found = c.disp_vids[i] == x;
        if (!found) unreported++;
    }
    CHECKF(moved_disp > 0 && unreported == 0, "%u of %u moved display vertices not reported", unreported, moved_disp);
    free(before.p);
    free(after.p);
    st_doc_drag_end(&d);
    dev = display_vs_model(&d);
    CHECKF(dev == 0, "after the drag the display differs by %g", dev);
    d.brush.tool = ST_BRUSH_DRAW;
    d.brush.radius = 0.5;
    d.brush.mirror_x = 0;
    double cpos[3], up[3] = { 1, 1, 1 };
    st_doc_vertex_pos(&d, corner, cpos);
    CHECK(st_doc_stroke_begin(&d) == 0);
    CHECK(st_doc_stroke_dab(&d, cpos, up, NULL) == 0);
    st_doc_stroke_end(&d);
    dev = display_vs_model(&d);
    CHECKF(dev == 0, "after the stroke the display differs by %g", dev);
    CHECK(d.display.hier.map.top > d.h.map.top);
    dev = local_vs_full(&d);
    CHECKF(dev < 1e-12, "local display sync differs from a full synthesis by %g", dev);

    /* The same edits without the box give the same model. */
    st_doc_set_edit_level(&r, 2);
    st_doc_select(&r, &corner, 1, ST_SELECT_REPLACE);
    CHECK(st_doc_drag_begin(&r) == 0);
    CHECK(st_doc_drag_update(&r, delta) == 0);
    st_doc_drag_end(&r);
    r.brush = d.brush;
    CHECK(st_doc_stroke_begin(&r) == 0);
    CHECK(st_doc_stroke_dab(&r, cpos, up, NULL) == 0);
    st_doc_stroke_end(&r);
    snap sd, sr;
    snap_take(&d, &sd);
    snap_take(&r, &sr);
    CHECK(snap_equal(&sd, &sr));
    snap_free(&sr);

    /* Box off: the regular hierarchy, details kept; on again: same display. */
    CHECK(st_doc_set_box(&d, &b, 0, &err) == 0);
    CHECK(!d.box_on && !d.display.built && st_doc_display_hier(&d) == &d.h);
    snap t;
    snap_take(&d, &t);
    CHECK(snap_equal(&sd, &t));
    snap_free(&t);
    CHECK(st_doc_set_box(&d, &b, 1, &err) == 0);
    dev = display_vs_model(&d);
    CHECKF(dev == 0, "box on again: display differs by %g", dev);
    /* Box moves (incremental updates) keep the display on the model. */
    st_doc_box_begin(&d);
    uint32_t nundo = d.nundo;
    for (int k = 0; k < 5; k++) {
        for (int j = 0; j < 3; j++) { b.box_lo[j] -= 0.25; b.box_hi[j] -= 0.25; }
        CHECK(st_doc_set_box(&d, &b, 1, &err) == 0);
        CHECK(st_map_validate(&d.display.hier.map, &err) == 0);
        dev = display_vs_model(&d);
        CHECKF(dev == 0, "box move %d: display differs by %g", k, dev);
        if (k % 2) {
            dev = local_vs_full(&d);
            CHECKF(dev < 1e-12, "box move %d: beyond the model, display differs from a full synthesis by %g", k, dev);
        }
    }
    st_doc_box_end(&d);
    CHECK(d.nundo == nundo + 1); /* one step for the whole box drag */
    st_adapt_params now = d.box;
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(d.box_on && d.box.box_lo[0] == 0.3);
    CHECK(display_vs_model(&d) == 0);
    CHECK(st_doc_redo(&d, &err) == 0);
    CHECK(d.box.box_lo[0] == now.box_lo[0]);
    /* Level changes with the box on rebuild the display. */
    CHECK(st_doc_add_level(&d, &err) == 0);
    CHECK(d.display.built && display_vs_model(&d) == 0);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(d.display.built && display_vs_model(&d) == 0);
    snap_take(&d, &t);
    CHECK(snap_equal(&sd, &t));
    snap_free(&t);
    /* Undo the box steps, then the edits: back to the model as opened. */
    while (st_doc_undo(&d, &err) == 0) {}
    CHECK(!d.box_on);
    snap_free(&sd);
    free(v);
    (void)n;

    /* √3 needs a closed mesh: the box is refused with the core's message. */
    {
        FILE *f = fopen(STRATA_SHARED_DATA "/triangle/hemisphere.obj", "rb");
        if (f) {
            fclose(f);
            ed_test_open(&r, STRATA_SHARED_DATA "/triangle/hemisphere.obj", "sqrt3", 2);
            CHECK(st_doc_set_box(&r, &b, 1, &err) != 0);
            CHECK(!r.box_on && strstr(err.msg, "closed") != NULL);
        }
    }
    st_doc_free(&d);
    st_doc_free(&r);
}

/* The displayed mesh of a box covering the whole model up to its top level
 * is the model's top level (same polygons, same positions): an independent
 * check of the display's pairing with the model (display_vs_model only
 * reads the pairs).  Compared as sorted position lists of the polygons. */
static int cmp_pos(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

static double *mesh_corners(st_map *m, unsigned l, uint32_t *n)
{
    st_mesh me;
    st_error err;
    memset(&me, 0, sizeof me);
    if (st_map_to_mesh(m, l, &me, &err)) { *n = 0; return NULL; }
    *n = me.face_off[me.nfaces];
    double *p = malloc((size_t)(*n ? *n : 1) * 3 * sizeof *p);
    for (uint32_t i = 0; i < *n; i++) memcpy(p + 3 * i, me.pos + 3 * me.face_idx[i], 3 * sizeof *p);
    qsort(p, *n, 3 * sizeof *p, cmp_pos);
    st_mesh_free(&me);
    return p;
}

static void check_whole_box(st_doc *d, const char *what)
{
    st_error err;
    st_adapt_params b = d->box;
    b.base_level = 0;
    b.max_level = d->h.map.top;
    b.has_box = 1;
    b.falloff = 0;
    b.flatness = 0;
    for (int k = 0; k < 3; k++) { b.box_lo[k] = -100; b.box_hi[k] = 100; }
    CHECKF(st_doc_set_box(d, &b, 1, &err) == 0, "%s: %s", what, err.msg);
    if (!d->display.built) return;
    CHECK(d->display.hier.map.top == d->h.map.top);
    uint32_t na, nb;
    double *a = mesh_corners(&d->display.hier.map, d->display.hier.map.top, &na), *c = mesh_corners(&d->h.map, d->h.map.top, &nb);
    CHECKF(a && c && na == nb && !memcmp(a, c, (size_t)na * 3 * sizeof *a), "%s: whole-box display differs from the model's top level (%u/%u corners)", what, na, nb);
    free(a);
    free(c);
}

static void test_box_schemes(void)
{
    static const struct { const char *scheme, *file; } t[] = {
        { "catmull-clark", "/cube.obj" }, { "loop", "/octahedron.obj" }, { "doo-sabin", "/cube.obj" },
        { "doo-sabin", "/torus.obj" }, { "sqrt3", "/octahedron.obj" }, { "sqrt3", "/tetrahedron.obj" }, { "butterfly", "/octahedron.obj" },
        { "quad-triangle", "/mixed.obj" },
    };
    for (unsigned i = 0; i < sizeof t / sizeof t[0]; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s%s", STRATA_ASSETS, t[i].file);
        st_doc d;
        st_doc_init(&d);
        ed_test_open(&d, path, t[i].scheme, 3);
        uint64_t rng = 31 + i;
        tl_random_details(&d.h, &rng, 0.03);
        check_whole_box(&d, t[i].scheme);
        /* An edit with the box on, then box off and on: the whole display
         * still shows the model. */
        st_doc_set_edit_level(&d, 1);
        uint32_t *v, n = ed_test_level_vertices(&d, 1, &v);
        st_doc_select(&d, &v[n / 2], 1, ST_SELECT_REPLACE);
        free(v);
        CHECK(st_doc_drag_begin(&d) == 0);
        double delta[3] = { 0.1, 0.05, -0.07 };
        CHECK(st_doc_drag_update(&d, delta) == 0);
        st_doc_drag_end(&d);
        CHECK(display_vs_model(&d) == 0);
        check_whole_box(&d, t[i].scheme);
        st_error err;
        st_adapt_params b = d.box;
        CHECK(st_doc_set_box(&d, &b, 0, &err) == 0);
        check_whole_box(&d, t[i].scheme);
        st_doc_free(&d);
    }
    /* A scheme change keeps the box on (Catmull-Clark -> Doo-Sabin), and
     * undo brings the Catmull-Clark display back. */
    st_doc d;
    st_error err;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 2);
    st_adapt_params b = d.box;
    b.max_level = 3;
    CHECK(st_doc_set_box(&d, &b, 1, &err) == 0);
    CHECK(st_doc_set_scheme(&d, "doo-sabin", &err) == 0);
    CHECK(d.box_on && d.display.built && d.display.hier.scheme == st_scheme_find("doo-sabin") && display_vs_model(&d) == 0);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(d.box_on && d.display.built && d.display.hier.scheme == st_scheme_find("catmull-clark") && display_vs_model(&d) == 0);
    st_doc_free(&d);
}

/* Partial boxes on a model without details above level 0: the display's
 * own adaptive positions (an adaptive hierarchy built the same way, not
 * synced) equal the model's at every pair, so the pairs join the right
 * vertices also at depth borders (√3's odd triangles, Doo-Sabin's border
 * polygons). */
static void test_box_pairs_partial(const char *scheme, const char *file)
{
    char path[512];
    snprintf(path, sizeof path, "%s%s", STRATA_ASSETS, file);
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, path, scheme, 3);
    uint64_t rng = 77;
    unsigned checked = 0;
    for (int k = 0; k < 6; k++) {
        st_error err;
        st_adapt_params b = d.box;
        b.base_level = k % 2;
        b.max_level = 2 + k % 3;
        double x = 0.8 * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
        b.box_lo[0] = x - 0.3; b.box_hi[0] = x + 0.3;
        b.box_lo[1] = -0.5; b.box_hi[1] = 0.5;
        b.box_lo[2] = 0.2; b.box_hi[2] = 1.5;
        b.has_box = 1;
        CHECKF(st_doc_set_box(&d, &b, 1, &err) == 0, "%s: %s", scheme, err.msg);
        if (!d.display.built) continue;
        st_hier c;
        st_adapt a;
        CHECK(ed_hier_clone(&c, &d.h, NULL) == 0);
        while (c.map.top > d.display.copied_top) st_hier_remove_top(&c);
        CHECK(st_adapt_init(&a, &c, &err) == 0);
        CHECK(st_adapt_update(&a, &d.box, &err) == 0);
        CHECK(c.map.darts.end == d.display.hier.map.darts.end && c.map.verts.end == d.display.hier.map.verts.end);
        double worst = 0;
        for (uint32_t i = 0; i < d.display.npairs; i += 3) {
            unsigned L = d.display.pairs[i];
            worst = fmax(worst, ed_test_dist3(st_pos(&c.map, d.display.pairs[i + 1], L), st_pos(&d.h.map, d.display.pairs[i + 2], L)));
            checked++;
        }
        CHECKF(worst < 1e-9, "%s %s box %d: adaptive positions differ from the paired model's by %g", scheme, file, k, worst);
        st_adapt_free(&a);
        st_hier_free(&c);
    }
    CHECKF(checked > 0, "%s: no pair checked", scheme);
    st_doc_free(&d);
}

/* Loop and a mesh from the shared data set, with the box. */
static void test_box_loop(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, STRATA_ASSETS "/octahedron.obj", "loop", 3);
    uint64_t s = 9;
    tl_random_details(&d.h, &s, 0.02);
    st_error err;
    st_adapt_params b = d.box;
    b.base_level = 1;
    b.max_level = 5;
    double lo[3] = { 0.2, -0.5, -0.5 }, hi[3] = { 1.5, 0.5, 0.5 };
    memcpy(b.box_lo, lo, sizeof lo);
    memcpy(b.box_hi, hi, sizeof hi);
    CHECK(st_doc_set_box(&d, &b, 1, &err) == 0);
    CHECK(d.display.built && d.display.hier.map.top == 5);
    CHECK(display_vs_model(&d) == 0);
    st_doc_set_edit_level(&d, 3);
    const double dir[3] = { 1, 0, 0 };
    uint32_t tip = ed_test_extreme_vertex(&d, dir);
    st_doc_select(&d, &tip, 1, ST_SELECT_REPLACE);
    double far0 = -INFINITY;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&d.display.hier.map, 5, &it); v != ST_NIL; v = st_vertex_next(&d.display.hier.map, 5, &it))
        far0 = fmax(far0, st_pos(&d.display.hier.map, v, 5)[0]);
    CHECK(st_doc_drag_begin(&d) == 0);
    double delta[3] = { 0.3, 0, 0 };
    CHECK(st_doc_drag_update(&d, delta) == 0);
    st_doc_drag_end(&d);
    CHECK(display_vs_model(&d) == 0);
    double dev = local_vs_full(&d);
    CHECKF(dev < 1e-12, "loop: local display sync differs from a full synthesis by %g", dev);
    /* Undo: the display follows, locally too. */
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(display_vs_model(&d) == 0);
    dev = local_vs_full(&d);
    CHECKF(dev < 1e-12, "loop, undo: local display sync differs from a full synthesis by %g", dev);
    CHECK(st_doc_redo(&d, &err) == 0);
    /* The display's finest level moved with the edit (synthesised beyond
     * the model's top). */
    double far = -INFINITY;
    for (uint32_t v = st_vertex_first(&d.display.hier.map, 5, &it); v != ST_NIL; v = st_vertex_next(&d.display.hier.map, 5, &it))
        far = fmax(far, st_pos(&d.display.hier.map, v, 5)[0]);
    CHECKF(far > far0 + 0.1, "display's x extent %g -> %g", far0, far);
    st_doc_free(&d);
}

/* ---- benchmark ----------------------------------------------------------------------------- */

static void test_bench(void)
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, cube, "catmull-clark", 4);
    st_error err;
    CHECK(st_doc_add_level(&d, &err) == 0);
    snap a, b;
    snap_take(&d, &a);
    uint32_t nundo = d.nundo;
    double step = -1, full = -1;
    CHECK(st_doc_bench_drag(&d, 2, 20, &step, &full) == 0);
    CHECK(step > 0 && full > 0);
    fprintf(stderr, "bench: cube depth 5, drag at level 2: median step %.3f ms, full synthesis %.3f ms (ratio %.4f)\n",
            step, full, step / full);
    snap_take(&d, &b);
    CHECK(snap_equal(&a, &b));
    CHECK(d.nundo == nundo);
    CHECK(st_doc_bench_drag(&d, 9, 5, &step, &full) != 0);
    snap_free(&a);
    snap_free(&b);
    st_doc_free(&d);
}

/* The first hour (docs/MODELLER.md): a scheme the control mesh cannot
 * take is refused before anything is rebuilt, with the reason the Scheme
 * menu shows as a tooltip; for every scheme, the answer agrees with what
 * st_doc_set_scheme then does.  A dense mesh opens at level 0 with the
 * automatic depth, a small cage gets two levels; --levels overrides.  The
 * revision names the state in the undo history (the window's "unsaved
 * changes?"): undoing back to a state gives its revision again, a new step
 * a revision never seen before. */
static void test_first_hour(void)
{
    static const char *const schemes[] = { "catmull-clark", "loop", "butterfly", "quad-triangle", "sqrt3", "doo-sabin" };
    static const char *const meshes[] = { "/cube.obj", "/octahedron.obj", "/mixed.obj", "/open.obj" };
    for (size_t mi = 0; mi < sizeof meshes / sizeof meshes[0]; mi++)
        for (size_t si = 0; si < sizeof schemes / sizeof schemes[0]; si++) {
            char path[1024];
            snprintf(path, sizeof path, "%s%s", STRATA_ASSETS, meshes[mi]);
            st_doc d;
            st_doc_init(&d);
            ed_test_open(&d, path, "catmull-clark", 1);
            st_error e1, e2;
            int takes = st_doc_scheme_accepts(&d, schemes[si], &e1) == ST_OK;
            int rebuilt = st_doc_set_scheme(&d, schemes[si], &e2) == ST_OK;
            CHECKF(takes == rebuilt, "%s with %s: accepts %d (%s), set_scheme %d (%s)", meshes[mi], schemes[si], takes,
                   takes ? "" : e1.msg, rebuilt, rebuilt ? "" : e2.msg);
            if (!strcmp(meshes[mi], "/cube.obj") && !strcmp(schemes[si], "loop"))
                CHECKF(!takes && strstr(e1.msg, "triangle"), "cube with loop: %s", e1.msg);
            st_doc_free(&d);
        }
    st_doc d;
    st_doc_init(&d);
    st_error err;
    CHECK(st_doc_open(&d, STRATA_ASSETS "/cube.obj", NULL, ST_DOC_LEVELS_AUTO, &err) == 0);
    CHECKF(d.h.map.top == ST_DOC_DEFAULT_LEVELS, "cube opened with %u levels above it", d.h.map.top);
    uint64_t r0 = d.revision;
    CHECK(st_doc_add_level(&d, &err) == 0 && d.revision != r0);
    uint64_t r1 = d.revision;
    CHECK(st_doc_undo(&d, &err) == 0 && d.revision == r0);
    CHECK(st_doc_redo(&d, &err) == 0 && d.revision == r1);
    CHECK(st_doc_undo(&d, &err) == 0 && d.nundo == 1 && d.revision == r0);
    /* A different step from the same state: neither r0 nor r1 again. */
    CHECK(st_doc_add_level(&d, &err) == 0 && d.revision != r0 && d.revision != r1 && d.nundo == 1);
    uint64_t r2 = d.revision;
    st_doc_forget_history(&d);
    CHECK(d.nundo == 0 && d.undo_pos == 0 && st_doc_undo(&d, &err) == -1 && d.revision == r2);
    CHECK(st_doc_add_level(&d, &err) == 0 && d.revision != r2);
    CHECK(st_doc_undo(&d, &err) == 0 && d.revision == r2);
    CHECK(st_doc_undo(&d, &err) == -1 && d.revision == r2);
    /* Steps dropped for the budget: the oldest state kept is the base. */
    size_t budget = d.undo_budget;
    d.undo_budget = 1; /* every step is larger: none is kept */
    CHECK(st_doc_remove_top(&d, &err) == 0 && d.nundo == 0 && d.h.map.top == ST_DOC_DEFAULT_LEVELS);
    uint64_t r3 = d.revision;
    CHECK(r3 != r2 && st_doc_undo(&d, &err) == -1 && d.revision == r3);
    d.undo_budget = budget;
    /* The box's maximum level stops where the memory budget does: the
     * level the slider allows is accepted, the next one refused. */
    st_adapt_params b = d.box;
    b.base_level = 0;
    for (int k = 0; k < 3; k++) { b.box_lo[k] = -2; b.box_hi[k] = 2; }   /* the whole cube */
    unsigned roomy = st_doc_box_max_level_allowed(&d, &b);
    CHECKF(roomy == d.h.map.top + 3, "default budget: box levels up to %u", roomy);
    d.mem_budget = st_doc_model_bytes(&d) + ((size_t)256 << 10);
    unsigned allowed = st_doc_box_max_level_allowed(&d, &b);
    CHECKF(allowed >= 1 && allowed < roomy, "256 KiB over the model: box levels up to %u", allowed);
    b.max_level = allowed;
    CHECKF(st_doc_set_box(&d, &b, 1, &err) == 0, "box at its allowed level %u: %s", allowed, err.msg);
    b.max_level = allowed + 1;
    CHECK(st_doc_set_box(&d, &b, 1, &err) == ST_ERR_MEMORY && strstr(err.msg, "memory budget"));
    CHECK(d.box.max_level == allowed);
    d.mem_budget = (size_t)4 << 30;
    CHECK(st_doc_open(&d, STRATA_SHARED_DATA "/large/koala.obj", NULL, ST_DOC_LEVELS_AUTO, &err) == 0);
    CHECKF(d.h.map.top == 0 && d.base.nfaces > ST_DOC_DENSE_FACES, "koala: top %u, %u faces", d.h.map.top, d.base.nfaces);
    CHECK(st_doc_open(&d, STRATA_SHARED_DATA "/triangle/bob_small.ply", "loop", 1, &err) == 0 && d.h.map.top == 1);
    st_doc_free(&d);
}

int main(void)
{
    test_first_hour();
    test_open();
    test_levels();
    test_undo_names();
    test_memory_budget();
    test_progress();
    test_selection();
    test_drag();
    test_brushes();
    test_brush_grid();
    test_brush_schemes();
    test_mirror();
    test_undo_random(cube, "catmull-clark", 1, 0);
    test_undo_random(cube, "catmull-clark", 2, 1);
    test_undo_random(cube, "catmull-clark", 3, 1);
    test_undo_random(STRATA_ASSETS "/open.obj", "catmull-clark", 4, 1);
    test_undo_random(STRATA_ASSETS "/mixed.obj", "quad-triangle", 5, 1);
    test_undo_random(STRATA_ASSETS "/octahedron.obj", "butterfly", 6, 1);
    test_undo_random(STRATA_ASSETS "/octahedron.obj", "sqrt3", 7, 2);
    test_undo_random(STRATA_ASSETS "/tetrahedron.obj", "sqrt3", 12, 2);
    test_undo_random(STRATA_SHARED_DATA "/triangle/sphere_ico.obj", "sqrt3", 15, 2);
    test_undo_random(STRATA_ASSETS "/cube.obj", "doo-sabin", 14, 2);
    test_undo_random(STRATA_ASSETS "/torus.obj", "doo-sabin", 10, 2);
    test_undo_random(STRATA_ASSETS "/cube.obj", "doo-sabin", 11, 2);
    test_undo_random(STRATA_SHARED_DATA "/triangle/sphere_ico.obj", "loop", 9, 1);
    test_undo_budget();
    test_box();
    test_box_loop();
    test_box_schemes();
    test_box_pairs_partial("catmull-clark", "/cube.obj");
    test_box_pairs_partial("loop", "/octahedron.obj");
    test_box_pairs_partial("sqrt3", "/octahedron.obj");
    test_box_pairs_partial("sqrt3", "/tetrahedron.obj");
    test_box_pairs_partial("doo-sabin", "/cube.obj");
    test_box_pairs_partial("doo-sabin", "/torus.obj");
    test_bench();
    return TEST_END();
}
