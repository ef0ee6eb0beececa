/* The memory budget before an edit in the document (ui/editor.c,
 * ed_edit_budget): a drag or a stroke re-synthesises the levels above the
 * editing level, and on a progressive model that first builds the ring
 * tables (core/progressive/progressive_synth.c).  Over the budget the drag
 * or stroke is refused with the estimate in d->refusal and nothing moves;
 * a mask stroke, which synthesises nothing, is not refused; within the
 * budget the edit goes through, after which the tables are held and the
 * estimate drops.  A subdivision model whose levels all have their
 * position columns needs nothing more and is never refused. */
#include "editor.h"
#include "editor_testlib.h"
#include "core/multires/estimate.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void select_first(st_doc *d, unsigned l)
{
    st_dart_iter it;
    st_doc_set_edit_level(d, l);
    uint32_t v = st_vertex_first(&d->h.map, l, &it);
    st_doc_select(d, &v, 1, ST_SELECT_REPLACE);
}

static void test_progressive(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    const char *path = STRATA_SHARED_DATA "/triangle/bob_small.ply";
    CHECKF(st_doc_open(&d, path, "loop", 0, &err) == 0, "%s: %s", path, err.msg);
    char msg[256];
    CHECK(st_doc_rebuild_levels(&d, NULL, NULL, msg, sizeof msg, &err) == 0);
    CHECK(d.scheme == st_scheme_find("progressive") && d.h.map.top >= 2);
    size_t need = st_hier_synth_estimate(&d.h, 0), have = st_doc_model_bytes(&d);
    /* the tables of every level and the scratch are not built yet */
    CHECKF(need > 0, "progressive synthesis estimate %zu", need);
    size_t n;
    double *before = ed_test_all_values(&d.h, &n);
    uint32_t nundo = d.nundo;

    d.mem_budget = have + need / 2;
    select_first(&d, 0);
    CHECK(st_doc_drag_begin(&d) != 0);
    CHECKF(strstr(d.refusal, "editing level 0 refused") && strstr(d.refusal, "MiB"), "refusal: '%s'", d.refusal);
    d.brush.radius = 0.5;
    CHECK(st_doc_stroke_begin(&d) != 0);
    CHECK(d.refusal[0] != 0);
    CHECK(ed_test_same_values(&d.h, before, n) && d.nundo == nundo && d.active == 0);
    printf("bob_small progressive: an edit of level 0 needs %.3f MiB; refused with %.3f MiB to spare: %s\n",
           need / 1048576.0, need / 2 / 1048576.0, d.refusal);

    /* a mask stroke synthesises nothing: not refused */
    CHECK(st_doc_mask_stroke_begin(&d, 0) == 0);
    st_doc_mask_stroke_end(&d);
    CHECK(ed_test_same_values(&d.h, before, n));

    /* within the budget: the drag moves the model, then the tables are held */
    d.mem_budget = st_doc_model_bytes(&d) + need + ((size_t)1 << 20);
    select_first(&d, 0);
    CHECK(st_doc_drag_begin(&d) == 0);
    CHECK(d.refusal[0] == 0);
    double delta[3] = { 0.02, -0.01, 0.03 };
    CHECK(st_doc_drag_update(&d, delta) == 0);
    st_doc_drag_end(&d);
    CHECK(!ed_test_same_values(&d.h, before, n));
    size_t after = st_hier_synth_estimate(&d.h, 0);
    CHECKF(after < need, "estimate after the edit %zu, before %zu", after, need);
    free(before);
    st_doc_free(&d);
}

static void test_subdivision(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    const char *path = STRATA_SHARED_DATA "/triangle/bob_small.ply";
    CHECKF(st_doc_open(&d, path, "loop", 2, &err) == 0, "%s: %s", path, err.msg);
    /* every level was synthesised whole: it has its columns, and an edit
     * adds nothing the guard counts */
    CHECK(st_hier_synth_estimate(&d.h, 0) == 0);
    d.mem_budget = st_doc_model_bytes(&d);
    select_first(&d, 0);
    CHECK(st_doc_drag_begin(&d) == 0);
    double delta[3] = { 0.01, 0.0, 0.0 };
    CHECK(st_doc_drag_update(&d, delta) == 0);
    st_doc_drag_end(&d);
    st_doc_free(&d);
}

int main(void)
{
    test_progressive();
    test_subdivision();
    return TEST_END();
}
