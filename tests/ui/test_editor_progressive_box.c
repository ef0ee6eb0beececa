/* The interest box on a progressive model in the document (ui/editor.h,
 * ui/editor_display.c): the display is core's selected mesh (finest level
 * in the box, the base level away from it; core/adapt/adapt.h), it follows
 * box moves as a fresh selection would, follows drags and their undo, and
 * maps its vertices to the model's. */
#include "editor.h"
#include "core/map/map_mesh.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The document's display against a fresh selection on the model: same
 * triangles (by model vertex ids, in order) and every vertex at the
 * model's position of its level. */
static int display_is_selection(st_doc *d, const st_adapt_params *p, const char *what)
{
    const st_hier *dh = st_doc_display_hier(d);
    st_adapt a;
    st_error err;
    int ok = st_adapt_init(&a, &d->h, &err) == ST_OK && st_adapt_update(&a, p, &err) == ST_OK;
    CHECKF(ok, "%s: %s", what, err.msg);
    if (!ok) return 0;
    const st_pm_select *s = a.pm;
    st_mesh dm;
    st_mesh_init(&dm);
    CHECK(st_map_to_mesh((st_map *)&dh->map, 0, &dm, &err) == ST_OK);
    ok = dh->map.top == 0 && st_doc_display_map_level(d) == 0 && dm.nfaces == s->nfaces && dm.nverts == s->nverts;
    for (uint32_t f = 0; ok && f < s->nfaces; f++)
        for (int k = 0; k < 3; k++)
            ok &= st_doc_display_to_edit_vertex(d, dm.face_idx[3 * f + k]) == ST_NIL ||
                  st_doc_display_to_edit_vertex(d, dm.face_idx[3 * f + k]) == s->vid[s->tri[3 * f + k]];
    for (uint32_t i = 0; ok && i < s->nverts; i++) ok &= !memcmp(st_pos(&dh->map, i, 0), st_pos(&d->h.map, s->vid[i], s->lam[i]), 3 * sizeof(double));
    CHECKF(ok, "%s: the display is not the selected mesh (%u faces, selection %u)", what, dm.nfaces, s->nfaces);
    st_mesh_free(&dm);
    st_adapt_free(&a);
    return ok;
}

/* Every display vertex at the model's position of its level (the
 * display's own selection). */
static int display_follows(st_doc *d, const char *what)
{
    const st_pm_select *s = d->display.adapt.pm;
    const st_hier *dh = st_doc_display_hier(d);
    st_level_stats ds;
    st_level_stats_compute((st_map *)&dh->map, 0, &ds);
    int ok = s && ds.vertices == s->nverts;
    uint32_t bad = 0;
    for (uint32_t i = 0; ok && i < s->nverts; i++) {
        int b = memcmp(st_pos(&dh->map, i, 0), st_pos(&d->h.map, s->vid[i], s->lam[i]), 3 * sizeof(double)) != 0;
        bad += b;
    }
    ok &= bad == 0;
    CHECKF(ok, "%s: the display does not follow the model (%u vertices)", what, bad);
    return ok;
}

static void test_box(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    const char *path = STRATA_SHARED_DATA "/triangle/bob_small.ply";
    if (st_doc_open(&d, path, "loop", 0, &err)) {
        tl_skip("%s not opened (%s)", path, err.msg);
        st_doc_free(&d);
        return;
    }
    char msg[256];
    CHECK(st_doc_rebuild_levels(&d, NULL, NULL, msg, sizeof msg, &err) == 0);
    CHECK(d.scheme == st_scheme_find("progressive"));
    unsigned top = d.h.map.top;
    /* a box around one vertex of the finest level */
    st_dart_iter it;
    uint32_t v0 = st_vertex_first(&d.h.map, top, &it);
    const double *c = st_pos(&d.h.map, v0, top);
    st_adapt_params p = { .base_level = 1, .max_level = top, .has_box = 1 };
    for (int k = 0; k < 3; k++) { p.box_lo[k] = c[k] - 0.1; p.box_hi[k] = c[k] + 0.1; }
    CHECKF(st_doc_set_box(&d, &p, 1, &err) == 0, "%s", err.msg);
    uint64_t faces, verts;
    st_doc_display_counts(&d, &faces, &verts);
    st_level_stats sb, st;
    st_level_stats_compute(&d.h.map, 1, &sb);
    st_level_stats_compute(&d.h.map, top, &st);
    printf("bob_small box: %llu faces shown (level 1: %llu, level %u: %llu)\n", (unsigned long long)faces,
           (unsigned long long)sb.faces, top, (unsigned long long)st.faces);
    CHECK(faces > sb.faces && faces < st.faces);
    display_is_selection(&d, &p, "box on");
    st_doc_change ch = st_doc_take_change(&d);
    CHECK(ch.bits & ST_CHANGE_TOPOLOGY);
    /* moves: each is the fresh selection, and redraws everything */
    for (int i = 0; i < 3; i++) {
        st_adapt_params q = p;
        for (int k = 0; k < 3; k++) { q.box_lo[k] += 0.05 * (i + 1); q.box_hi[k] += 0.05 * (i + 1); }
        CHECK(st_doc_set_box(&d, &q, 1, &err) == 0);
        char what[64];
        snprintf(what, sizeof what, "move %d", i);
        display_is_selection(&d, &q, what);
        ch = st_doc_take_change(&d);
        CHECK((ch.bits & ST_CHANGE_TOPOLOGY) && !(ch.bits & ST_CHANGE_PATCH));
    }
    CHECK(st_doc_set_box(&d, &p, 1, &err) == 0);
    display_is_selection(&d, &p, "back");
    /* a drag of a level-0 vertex: the display follows */
    st_doc_set_edit_level(&d, 0);
    uint32_t v = st_vertex_first(&d.h.map, 0, &it);
    st_doc_select(&d, &v, 1, ST_SELECT_REPLACE);
    const st_hier *dh0 = st_doc_display_hier(&d);
    uint32_t nb = d.display.adapt.pm->nverts;
    double *before = malloc(3 * (size_t)nb * sizeof *before);
    for (uint32_t i = 0; i < nb; i++) memcpy(before + 3 * (size_t)i, st_pos(&dh0->map, i, 0), 3 * sizeof(double));
    CHECK(st_doc_drag_begin(&d) == 0);
    double delta[3] = { 0.02, -0.01, 0.03 };
    CHECK(st_doc_drag_update(&d, delta) == 0);
    st_doc_drag_end(&d);
    uint64_t f2, v2;
    st_doc_display_counts(&d, &f2, &v2);
    CHECK(f2 == faces && v2 == verts);
    display_follows(&d, "after a drag");
    uint32_t changed = 0;
    for (uint32_t i = 0; i < nb; i++) changed += memcmp(before + 3 * (size_t)i, st_pos(&st_doc_display_hier(&d)->map, i, 0), 3 * sizeof(double)) != 0;
    printf("bob_small box: a drag of level 0 moved %u of %u shown vertices\n", changed, nb);
    CHECK(changed > 0);
    free(before);
    ch = st_doc_take_change(&d);
    CHECK(ch.bits & (ST_CHANGE_DISPLAY | ST_CHANGE_ALL_POSITIONS));
    /* the display's vertices map to editing-level vertices where they are ones */
    uint32_t mapped = 0;
    for (uint32_t i = 0; i < (uint32_t)v2; i++) mapped += st_doc_display_to_edit_vertex(&d, i) != ST_NIL;
    CHECK(mapped > 0 && mapped < (uint32_t)v2);
    CHECK(st_doc_undo(&d, &err) == 0);
    display_follows(&d, "after undo");
    display_is_selection(&d, &p, "after undo");
    /* undo the rebuild with the box on: the display follows the model back
     * to Loop and forth to progressive again */
    while (d.scheme == st_scheme_find("progressive") && st_doc_undo(&d, &err) == 0) {}
    CHECK(d.scheme == st_scheme_find("loop"));
    const st_hier *sh = st_doc_display_hier(&d);
    CHECKF(st_map_validate((st_map *)&sh->map, &err) == ST_OK, "after undoing the rebuild: %s", err.msg);
    while (d.scheme != st_scheme_find("progressive") && st_doc_redo(&d, &err) == 0) {}
    CHECK(d.scheme == st_scheme_find("progressive"));
    if (d.box_on) display_is_selection(&d, &d.box, "after redoing the rebuild");
    CHECK(st_doc_set_box(&d, &p, 0, &err) == 0);
    CHECK(st_doc_display_hier(&d) == &d.h);
    st_doc_free(&d);
}

int main(void)
{
    test_box();
    return TEST_END();
}
