/* HD levels through the document (ui/doc/editor_hd.c; editor.h, "HD
 * levels"), headless: a Catmull-Clark cube of depth 2 with the interest box
 * over one corner and HD levels to 6.
 *   - the editing level goes above the top only with the box on, and the
 *     box's base becomes the top;
 *   - a draw stroke at HD level 5 moves the display, never the model, and
 *     equals a full adaptive re-synthesis bit for bit;
 *   - undo and redo give back the display's values bit for bit;
 *   - a stroke at a lower HD level carries the detail of a finer one;
 *   - the mask brush at an HD level paints the model's top, which the HD
 *     strokes then respect;
 *   - a selected HD vertex is dragged where the drag puts it, undone bit
 *     for bit; a vertex at the HD region's border cannot be selected;
 *   - the box moved away, and then off: the sculpted faces stay refined,
 *     the others coarsen, the display stays shown;
 *   - a coarse stroke at level 1 carries the HD detail (the display still
 *     equals its full re-synthesis, the HD vertex moved);
 *   - adding a level is refused while HD detail exists;
 *   - a session keeps the HD levels (chunk hdlv) and a document opened
 *     from it shows the same display values;
 *   - HD levels are refused for a scheme without them. */
#include "editor.h"
#include "editor_testlib.h"
#include "testlib.h"
#include "core/adapt/adapt.h"
#include "core/io/session.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void stroke_at(st_doc *d, int tool, const double c[3], double radius, double strength)
{
    st_brush_set_tool(&d->brush, tool);
    d->brush.radius = radius;
    d->brush.strength = strength;
    double len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    const double nrm[3] = { c[0] / len, c[1] / len, c[2] / len };
    const double g[3] = { 0.1 * nrm[0], 0.1 * nrm[1], 0.1 * nrm[2] };
    CHECK(st_doc_stroke_begin(d) == 0);
    CHECK(st_doc_stroke_dab(d, c, nrm, tool == ST_BRUSH_GRAB ? g : NULL) == 0);
    st_doc_stroke_end(d);
}

int main(void)
{
    char obj[64], ses[64];
    snprintf(obj, sizeof obj, "/tmp/strata_hd_%d.obj", (int)getpid());
    snprintf(ses, sizeof ses, "/tmp/strata_hd_%d.strata", (int)getpid());
    st_mesh cube;
    st_error err;
    tl_mesh_cube(&cube);
    CHECK(st_mesh_save(obj, &cube, &err) == 0);
    st_mesh_free(&cube);

    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, obj, "catmull-clark", 2);
    const unsigned N = 2, L = 5;
    CHECK(d.h.map.top == N);

    /* Without the box: no HD level, the top at most. */
    st_doc_set_edit_level(&d, L);
    CHECK(st_doc_sculpt_level(&d) == N && d.hd_level == 0);

    d.box.base_level = 0;
    d.box.max_level = 6;
    ed_test_set_box(&d, 0.2, 2.0, 1);
    st_doc_set_edit_level(&d, L);
    CHECK(st_doc_sculpt_level(&d) == L && d.hd_level == L && d.edit_level == N);
    CHECK(d.box.base_level == N);
    CHECK(st_doc_level_limit(&d) == 6);
    {
        /* The box's maximum level: past the top + 3 only with its base at
         * the top (HD levels), within the budget. */
        st_adapt_params q = d.box;
        CHECK(st_doc_box_max_level_allowed(&d, &q) > N + 3);
        q.base_level = 0;
        CHECK(st_doc_box_max_level_allowed(&d, &q) == N + 3);
    }
    uint64_t faces_box = 0, verts;
    st_doc_display_counts(&d, &faces_box, &verts);

    size_t nm0, nd0;
    double *model0 = ed_test_all_values(&d.h, &nm0);
    double *disp0 = ed_test_all_values(&d.display.hier, &nd0);
    uint32_t dart = ST_NIL, hv = ed_test_hd_middle_vertex(&d, L, &dart);
    CHECK(hv != ST_NIL);
    double c[3], before[3];
    memcpy(c, st_pos(&d.display.hier.map, hv, L), sizeof c);
    memcpy(before, st_pos(&d.display.hier.map, hv, 6), sizeof before);

    stroke_at(&d, ST_BRUSH_DRAW, c, 0.15, 1.0);
    CHECK(ed_test_same_values(&d.h, model0, nm0));          /* the model did not move */
    CHECK(!ed_test_same_values(&d.display.hier, disp0, nd0));
    CHECK(ed_test_dist3(st_pos(&d.display.hier.map, hv, 6), before) > 1e-4); /* the finer level followed */
    CHECK(ed_test_display_is_synthesis(&d, N));
    CHECK(st_doc_hd_faces(&d) > 0);
    size_t nd1;
    double *disp1 = ed_test_all_values(&d.display.hier, &nd1);

    /* Undo, redo: bit for bit. */
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(ed_test_same_values(&d.display.hier, disp0, nd0));
    CHECK(st_doc_redo(&d, &err) == 0);
    CHECK(ed_test_same_values(&d.display.hier, disp1, nd1));

    /* A stroke at HD level 6, then one at the lower HD level 5 over it: the
     * level-6 detail is carried along (the fine vertex moves, the display
     * stays a full re-synthesis); two undos give the state before both. */
    st_doc_set_edit_level(&d, 6);
    CHECK(d.hd_level == 6);
    uint32_t fdart = ST_NIL, fv = ed_test_hd_middle_vertex(&d, 6, &fdart);
    CHECK(fv != ST_NIL);
    double fc[3], fine[3];
    memcpy(fc, st_pos(&d.display.hier.map, fv, 6), sizeof fc);
    stroke_at(&d, ST_BRUSH_DRAW, fc, 0.05, 0.5);
    memcpy(fine, st_pos(&d.display.hier.map, fv, 6), sizeof fine);
    CHECK(ed_test_dist3(fine, fc) > 1e-6);
    CHECK(ed_test_display_is_synthesis(&d, N));
    st_doc_set_edit_level(&d, 5);
    stroke_at(&d, ST_BRUSH_GRAB, fc, 0.3, 1.0);
    CHECK(ed_test_dist3(st_pos(&d.display.hier.map, fv, 6), fine) > 1e-3);
    CHECK(ed_test_display_is_synthesis(&d, N));
    CHECK(st_doc_undo(&d, &err) == 0 && st_doc_undo(&d, &err) == 0);
    CHECK(ed_test_same_values(&d.display.hier, disp1, nd1));
    st_doc_set_edit_level(&d, L);

    /* The mask brush at an HD level paints the model's top; the HD level
     * takes its subdivision: a draw stroke over the mask moves less. */
    {
        double p0[3], moved[2];
        memcpy(p0, st_pos(&d.display.hier.map, hv, L), sizeof p0);
        d.brush.radius = 0.6;
        d.brush.strength = 1;
        CHECK(st_doc_mask_stroke_begin(&d, 0) == 0);
        for (int k = 0; k < 3; k++) CHECK(st_doc_mask_stroke_dab(&d, c) == 0);
        st_doc_mask_stroke_end(&d);
        CHECK(st_mask_any(&d.mask));
        CHECK(d.hd_level == L);
        for (int pass = 0; pass < 2; pass++) {
            stroke_at(&d, ST_BRUSH_DRAW, c, 0.15, 1.0);
            moved[pass] = ed_test_dist3(st_pos(&d.display.hier.map, hv, L), p0);
            CHECK(st_doc_undo(&d, &err) == 0);
            if (!pass) CHECK(st_doc_undo(&d, &err) == 0 && !st_mask_any(&d.mask)); /* the mask goes */
        }
        CHECKF(moved[0] < 0.5 * moved[1], "masked %g, free %g", moved[0], moved[1]);
        CHECK(ed_test_same_values(&d.display.hier, disp1, nd1));
    }

    /* A drag of a selected HD vertex: the selection holds display ids of
     * the HD level; the vertex goes where the drag puts it (to rounding),
     * the display stays a full re-synthesis, undo gives the bits back. */
    {
        st_doc_select(&d, &hv, 1, ST_SELECT_REPLACE);
        CHECK(d.nsel == 1 && d.sel[0] == hv);
        double p0[3], p1[3], q[3];
        st_doc_vertex_pos(&d, hv, p0);
        CHECK(!memcmp(p0, st_pos(&d.display.hier.map, hv, L), sizeof p0));
        const double delta[3] = { 0.01, 0.02, -0.01 };
        CHECK(st_doc_drag_begin(&d) == 0);
        CHECK(st_doc_drag_update(&d, delta) == 0);
        st_doc_drag_end(&d);
        memcpy(p1, st_pos(&d.display.hier.map, hv, L), sizeof p1);
        for (int k = 0; k < 3; k++) q[k] = p0[k] + delta[k];
        CHECK(ed_test_dist3(p1, q) < 1e-12);
        CHECK(ed_test_same_values(&d.h, model0, nm0)); /* the model did not move */
        CHECK(ed_test_display_is_synthesis(&d, N));
        CHECK(st_doc_undo_name(&d) && !strcmp(st_doc_undo_name(&d), "move"));
        CHECK(st_doc_undo(&d, &err) == 0);
        CHECK(ed_test_same_values(&d.display.hier, disp1, nd1));
        /* a vertex at the border of the HD region cannot be selected */
        uint32_t border = ST_NIL;
        st_dart_iter it;
        st_map *dm = &d.display.hier.map;
        for (uint32_t x = st_dart_first(dm, L, &it); x != ST_NIL && border == ST_NIL; x = st_dart_next(dm, L, &it))
            if (!st_is_boundary(dm, x) && st_face_level(dm, x, L) == L && !st_adapt_vertex_editable(dm, x, L))
                border = st_vert(dm, x, L);
        CHECK(border != ST_NIL);
        st_doc_select(&d, &border, 1, ST_SELECT_REPLACE);
        CHECK(d.nsel == 0);
    }

    /* The box moves to the opposite corner: the sculpted faces stay. */
    double sculpted[3];
    memcpy(sculpted, st_pos(&d.display.hier.map, hv, L), sizeof sculpted);
    ed_test_set_box(&d, -2.0, -0.2, 1);
    CHECK(st_doc_hd_faces(&d) > 0);
    CHECK(!memcmp(st_pos(&d.display.hier.map, hv, L), sculpted, sizeof sculpted));
    /* Box off: the display stays, with the sculpted faces only. */
    ed_test_set_box(&d, -2.0, -0.2, 0);
    CHECK(!d.box_on && st_doc_display_adaptive(&d));
    uint64_t faces_off = 0;
    st_doc_display_counts(&d, &faces_off, &verts);
    CHECK(st_doc_hd_faces(&d) > 0);
    CHECK(faces_off < faces_box);
    {
        /* the document's counts (without a walk) are the map's */
        st_level_stats ls;
        st_level_stats_compute(&d.display.hier.map, d.display.hier.map.top, &ls);
        CHECK(faces_off == ls.faces && verts == ls.vertices);
    }
    CHECK(!memcmp(st_pos(&d.display.hier.map, hv, L), sculpted, sizeof sculpted));
    /* The window's box updates place new vertices with the stencil of the
     * face that made them (st_adapt.exact off, editor_hd.c), which may
     * round differently from a full synthesis: one full synthesis here, so
     * that the coarse edit below is compared with a full re-synthesis bit
     * for bit.  (core/adapt's exact updates: tests/core/test_adapt_hd.c) */
    CHECK(!d.display.adapt.exact);
    st_adapt_synthesize(&d.display.adapt, N);
    CHECK(ed_test_display_is_synthesis(&d, N));

    /* A coarse stroke at level 1 carries the HD detail. */
    st_doc_set_edit_level(&d, 1);
    CHECK(d.hd_level == 0 && d.edit_level == 1);
    stroke_at(&d, ST_BRUSH_GRAB, c, 1.0, 1.0);
    CHECK(ed_test_dist3(st_pos(&d.display.hier.map, hv, L), sculpted) > 1e-3);
    CHECK(ed_test_display_is_synthesis(&d, N));
    CHECK(st_doc_hd_faces(&d) > 0);

    /* Operations that rebuild the model's levels are refused. */
    CHECK(st_doc_add_level(&d, &err) != 0);
    CHECK(strstr(err.msg, "HD") != NULL);
    CHECK(d.h.map.top == N);

    /* A session keeps them. */
    size_t ndv;
    double *dispv = ed_test_all_values(&d.display.hier, &ndv);
    CHECKF(st_doc_save_session(&d, ses, NULL, NULL, NULL, NULL, &err) == 0, "save: %s", err.msg);
    st_session s;
    CHECKF(st_session_load(ses, &s, &err) == 0, "load: %s", err.msg);
    CHECK(s.has_hd);
    st_doc e;
    ed_test_open_hd_session(&e, obj, &s);
    CHECK(st_doc_display_adaptive(&e));
    CHECK(e.display.built && ed_test_same_values(&e.display.hier, dispv, ndv));
    CHECK(st_doc_hd_faces(&e) == st_doc_hd_faces(&d));
    st_session_free(&s);
    st_doc_free(&e);

    free(model0);
    free(disp0);
    free(disp1);
    free(dispv);
    st_doc_free(&d);

    /* A scheme without HD levels. */
    st_doc_init(&d);
    ed_test_open(&d, obj, "doo-sabin", 2);
    ed_test_set_box(&d, 0.2, 2.0, 1);
    st_doc_set_edit_level(&d, 4);
    CHECK(d.hd_level == 0 && st_doc_sculpt_level(&d) == d.h.map.top);
    CHECK(st_doc_hd_refusal(&d) && strstr(st_doc_hd_refusal(&d), "quadrisection"));
    st_doc_free(&d);
    unlink(obj);
    unlink(ses);
    return TEST_END();
}
