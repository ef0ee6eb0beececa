/* Coarse levels respond (issue 30, point 4), headless through the document
 * (ui/editor.h): the same vertical grab, once at editing level 1 and once
 * at level 4 of a Catmull-Clark hierarchy of depth 4, must move the finest
 * level at least 0.8 times as far at level 1 as at level 4.  Before the
 * brush's reach (st_doc_brush_reach), few level-1 vertices lay inside the
 * radius and the finest surface moved half as far (0.124 against 0.248 of
 * the diagonal on blub).  Prints the ratio with the reach off (as before)
 * and on (the default).
 *
 * The grab is the window's 150 px drag in object units: the brush radius
 * is the window's default (0.125 of the camera radius, half the diagonal),
 * the cursor on the front of the model, the drag a quarter of the diagonal
 * up, in one dab (grab moves what it captured by weight times the total). */
#include "editor.h"
#include "testlib.h"
#include "editor_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Largest displacement of a level-`top` vertex between p0 and now. */
static double most_moved(const st_doc *d, unsigned top, const uint32_t *v, uint32_t n, const double (*p0)[3])
{
    double most = 0;
    for (uint32_t i = 0; i < n; i++) most = fmax(most, ed_test_dist3(st_pos(&d->h.map, v[i], top), p0[i]));
    return most;
}

/* The finest level's largest displacement over the diagonal for a grab at
 * editing level l with the brush's reach on or off. */
static double grab_at(st_doc *d, unsigned l, int reach, double R, double diag, const double c[3], const double view[3],
                      const uint32_t *v, uint32_t n, const double (*p0)[3])
{
    unsigned top = d->h.map.top;
    st_doc_set_edit_level(d, l);
    st_brush_set_tool(&d->brush, ST_BRUSH_GRAB);
    d->brush.radius = R;
    d->brush.strength = 1;
    d->brush.reach_edges = reach ? ST_BRUSH_REACH_EDGES : 0;
    memcpy(d->brush.view_dir, view, sizeof d->brush.view_dir);
    const double nrm[3] = { -view[0], -view[1], -view[2] }, g[3] = { 0, 0.25 * diag, 0 };
    CHECK(st_doc_stroke_begin(d) == 0);
    CHECK(st_doc_stroke_dab(d, c, nrm, g) == 0);
    st_doc_stroke_end(d);
    double most = most_moved(d, top, v, n, p0) / diag;
    st_error err;
    CHECK(st_doc_undo(d, &err) == 0);
    return most;
}

static void test_cage(const char *label, const char *path, const double look[3])
{
    st_doc d;
    st_doc_init(&d);
    ed_test_open(&d, path, "catmull-clark", 4);
    st_brush_defaults(&d.brush, d.brush.radius);
    unsigned top = d.h.map.top;
    CHECK(top == 4);
    uint32_t *v, n = ed_test_level_vertices(&d, top, &v);
    double (*p0)[3] = malloc((size_t)n * sizeof *p0);
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    /* The cursor: the finest vertex furthest toward the viewer (along look). */
    double best = -INFINITY, c[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < n; i++) {
        memcpy(p0[i], st_pos(&d.h.map, v[i], top), sizeof p0[i]);
        for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], p0[i][k]); hi[k] = fmax(hi[k], p0[i][k]); }
        double s = p0[i][0] * look[0] + p0[i][1] * look[1] + p0[i][2] * look[2];
        if (s > best) { best = s; memcpy(c, p0[i], sizeof c); }
    }
    double diag = ed_test_dist3(lo, hi), len = sqrt(look[0] * look[0] + look[1] * look[1] + look[2] * look[2]);
    /* Level 1's mean edge length: the radius is half of it, as when the
     * window's radius (in object units) is smaller than a coarse face. */
    double esum = 0;
    uint64_t ne = 0;
    st_dart_iter it;
    for (uint32_t x = st_dart_first(&d.h.map, 1, &it); x != ST_NIL; x = st_dart_next(&d.h.map, 1, &it)) {
        uint32_t y = st_beta0(&d.h.map, x, 1);
        if (y < x) continue;
        esum += ed_test_dist3(st_dart_pos(&d.h.map, x, 1), st_dart_pos(&d.h.map, y, 1));
        ne++;
    }
    double R = 0.5 * esum / (double)ne;
    const double view[3] = { -look[0] / len, -look[1] / len, -look[2] / len };
    double r[2];
    for (int reach = 0; reach < 2; reach++) {
        double m1 = grab_at(&d, 1, reach, R, diag, c, view, v, n, (const double(*)[3])p0);
        double m4 = grab_at(&d, 4, reach, R, diag, c, view, v, n, (const double(*)[3])p0);
        r[reach] = m4 > 0 ? m1 / m4 : 0;
        st_doc_set_edit_level(&d, 1);
        double reach1 = st_doc_brush_reach(&d);
        printf("%s depth 4, seen along (%g %g %g), grab of 0.25 diagonal, radius %.4g diagonal (half level 1's mean edge), reach %s "
               "(%.4g diagonal from level 1's mean edge; near the cursor: its edges): finest moves %.4f at level 1, %.4f at level 4, ratio %.3f\n",
               label, -look[0], -look[1], -look[2], R / diag, reach ? "on" : "off", reach1 / diag, m1, m4, r[reach]);
    }
    CHECKF(r[1] >= 0.8, "%s: a grab at level 1 moves the finest level %.3f times as far as at level 4", label, r[1]);
    free(p0);
    free(v);
    st_doc_free(&d);
}

int main(void)
{
    /* The cursor on the front a little above, and on the side. */
    static const double front[3] = { 0, 0.5, 1 }, side[3] = { 1, 0.3, 0.2 };
    test_cage("blub", STRATA_SHARED_DATA "/catmull_clark/blub_quadrangulated.obj", front);
    test_cage("blub", STRATA_SHARED_DATA "/catmull_clark/blub_quadrangulated.obj", side);
    test_cage("spot", STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", front);
    test_cage("spot", STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", side);
    return TEST_END();
}
