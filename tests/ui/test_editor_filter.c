/* Multiresolution filtering in the document (ui/editor_filter.c,
 * st_doc_filter): the result is core's st_progressive_filter on the same
 * hierarchy, to the bit; it is one undo step, and undo and redo give back
 * every position and detail to the bit; gains of 1 make no step; a model
 * that is not progressive, one with sculpt layers and one over the memory
 * budget are refused with nothing changed. */
#include "editor.h"
#include "editor_testlib.h"
#include "core/progressive/progressive.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MESH STRATA_SHARED_DATA "/triangle/bob_small.ply"

static void open_progressive(st_doc *d)
{
    st_doc_init(d);
    ed_test_open(d, MESH, "loop", 0);
    char msg[256];
    st_error err;
    CHECKF(st_doc_rebuild_levels(d, NULL, NULL, msg, sizeof msg, &err) == 0, "rebuild: %s", err.msg);
    CHECK(d->scheme == st_scheme_find("progressive") && d->h.map.top >= 4);
}

static void test_filter_undo_redo(void)
{
    st_doc d, ref;
    st_error err;
    open_progressive(&d);
    open_progressive(&ref);
    unsigned top = d.h.map.top;
    size_t n;
    double *before = ed_test_all_values(&d.h, &n);
    CHECK(ed_test_same_values(&ref.h, before, n)); /* the rebuild is deterministic */

    /* gains of 1: nothing, no step */
    double ones[ST_MAX_LEVELS];
    for (unsigned k = 0; k < ST_MAX_LEVELS; k++) ones[k] = 1.0;
    uint32_t nundo = d.nundo;
    CHECK(st_doc_filter(&d, ones, top, &err) == 0);
    CHECK(d.nundo == nundo && ed_test_same_values(&d.h, before, n));

    /* the three finest bands removed, level 2's doubled */
    double g[ST_MAX_LEVELS];
    for (unsigned k = 0; k < top; k++) g[k] = k + 3 >= top ? 0.0 : 1.0;
    g[1] = 2.0;
    CHECKF(st_doc_filter(&d, g, top, &err) == 0, "filter: %s", err.msg);
    CHECK(d.nundo == nundo + 1 && d.undo_pos == d.nundo);
    CHECK(st_doc_undo_name(&d) && !strcmp(st_doc_undo_name(&d), "filter"));
    CHECK(st_progressive_filter(&ref.h, g, top, &err) == 0);
    size_t na;
    double *after = ed_test_all_values(&ref.h, &na);
    CHECK(na == n && memcmp(after, before, n * sizeof *after) != 0);
    CHECKF(ed_test_same_values(&d.h, after, na), "the document's filter differs from core's");
    st_doc_change ch = st_doc_take_change(&d);
    CHECK(ch.bits & ST_CHANGE_ALL_POSITIONS);

    CHECK(st_doc_undo(&d, &err) == 0);
    CHECKF(ed_test_same_values(&d.h, before, n), "undo of the filter is not exact");
    CHECK(st_doc_redo(&d, &err) == 0);
    CHECKF(ed_test_same_values(&d.h, after, na), "redo of the filter is not exact");
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(ed_test_same_values(&d.h, before, n));
    printf("bob_small, %u levels: filter, undo and redo exact (%zu values)\n", top + 1, n);

    /* over the budget: refused, nothing changed */
    d.mem_budget = st_doc_model_bytes(&d) + 1024;
    nundo = d.nundo;
    CHECK(st_doc_filter(&d, g, top, &err) == ST_ERR_MEMORY);
    CHECKF(strstr(err.msg, "filter refused"), "message: %s", err.msg);
    CHECK(ed_test_same_values(&d.h, before, n) && d.nundo == nundo);
    free(before);
    free(after);
    st_doc_free(&d);
    st_doc_free(&ref);
}

static void test_refusals(void)
{
    st_doc d;
    st_error err;
    double g[2] = { 1.0, 0.0 };
    st_doc_init(&d);
    ed_test_open(&d, MESH, "loop", 2);
    size_t n;
    double *before = ed_test_all_values(&d.h, &n);
    CHECK(st_doc_filter(&d, g, 2, &err) == ST_ERR_INVALID);
    CHECKF(strstr(err.msg, "progressive"), "message: %s", err.msg);
    CHECK(ed_test_same_values(&d.h, before, n) && d.nundo == 0);
    free(before);
    st_doc_free(&d);

    open_progressive(&d);
    CHECK(st_doc_layer_add(&d, "L", &err) == 0);
    uint32_t nundo = d.nundo;
    before = ed_test_all_values(&d.h, &n);
    CHECK(st_doc_filter(&d, g, 2, &err) == ST_ERR_INVALID);
    CHECKF(strstr(err.msg, "sculpt layer"), "message: %s", err.msg);
    CHECK(ed_test_same_values(&d.h, before, n) && d.nundo == nundo);
    double bad[2] = { 1.0, 0.0 / 0.0 };
    CHECK(st_doc_layer_delete(&d, 0, &err) == 0);
    CHECK(st_doc_filter(&d, bad, 2, &err) == ST_ERR_INVALID);
    free(before);
    st_doc_free(&d);
}

/* The Filter panel's presets: the gains they give, and what applying
 * them does to the details (a band at gain 0 holds no detail after it). */
static int band_is_zero(const st_hier *h, unsigned l)
{
    for (size_t i = 0; i < 3 * (size_t)h->detail_cap[l]; i++)
        if (h->detail[l][i] != 0) return 0;
    return 1;
}

static void test_presets(void)
{
    double g[ST_MAX_LEVELS];
    st_filter_preset_gains(ST_FILTER_SMOOTH, 9, g);
    CHECK(g[8] == 0 && g[6] == 0 && g[5] == 0.5 && g[3] == 0.5 && g[2] == 1 && g[0] == 1);
    st_filter_preset_gains(ST_FILTER_SHARPEN, 9, g);
    CHECK(g[8] == 1.5 && g[5] == 1.5 && g[4] == 1 && g[0] == 1);
    st_filter_preset_gains(ST_FILTER_KEEP_COARSE, 9, g);
    CHECK(g[0] == 1 && g[2] == 1 && g[3] == 0 && g[8] == 0);
    st_filter_preset_gains(ST_FILTER_KEEP_FINE, 9, g);
    CHECK(g[0] == 0 && g[2] == 0 && g[3] == 1 && g[8] == 1);
    st_filter_preset_gains(ST_FILTER_SMOOTH, 1, g);
    CHECK(g[0] == 0);   /* a shallow hierarchy still smooths */
    for (int p = 0; p < ST_FILTER_NPRESETS; p++) CHECK(strcmp(st_filter_preset_name(p), "?") != 0);

    st_doc d;
    st_error err;
    open_progressive(&d);
    unsigned top = d.h.map.top;
    uint32_t steps = d.nundo;
    st_filter_preset_gains(ST_FILTER_SMOOTH, top, g);
    CHECKF(st_doc_filter(&d, g, top, &err) == 0, "smooth preset: %s", err.msg);
    for (unsigned l = 1; l <= top; l++)
        if (g[l - 1] == 0) CHECKF(band_is_zero(&d.h, l), "smooth: level %u keeps details", l);
    CHECK(d.nundo == steps + 1);
    st_doc_free(&d);
}

int main(void)
{
    test_presets();
    test_filter_undo_redo();
    test_refusals();
    return TEST_END();
}
