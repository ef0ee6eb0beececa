/* Rebuild levels in the document (ui/editor.h, st_doc_rebuild_levels):
 * unsubdivide on a subdivided cube, the progressive method on a triangle
 * mesh without subdivision connectivity, undo and redo bit for bit, a
 * cancelled rebuild that leaves the document as it was, and the tags: a
 * creased cage subdivided twice and saved with its OBJ tags gets its
 * creases and corner back at level 0, as `strata rebuild` gives them
 * (core/rebuild/rebuild.h), and the progressive method names what it
 * dropped. */
#include "editor.h"
#include "core/map/map_mesh.h"
#include "core/rebuild/rebuild.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Every level's positions, by vertex id, bit for bit. */
typedef struct snap {
    unsigned levels;
    uint32_t n;
    double *p;          /* [level][vid][3] (zero where a vertex is absent) */
    uint8_t *ins;
    const void *scheme;
} snap;

static void snap_take(const st_doc *d, snap *s)
{
    const st_hier *h = &d->h;
    s->levels = h->map.top + 1;
    s->n = h->map.verts.end;
    s->scheme = d->scheme;
    s->p = calloc((size_t)s->levels * s->n * 3 + 1, sizeof *s->p);
    s->ins = malloc(s->n + 1);
    memcpy(s->ins, h->map.verts.ins, s->n);
    for (unsigned l = 0; l < s->levels; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
            memcpy(s->p + ((size_t)l * s->n + v) * 3, st_pos(&h->map, v, l), 3 * sizeof(double));
    }
}

static void snap_free(snap *s) { free(s->p); free(s->ins); memset(s, 0, sizeof *s); }

static int snap_equal(const snap *a, const snap *b)
{
    if (a->levels != b->levels || a->n != b->n || a->scheme != b->scheme) return 0;
    if (memcmp(a->ins, b->ins, a->n)) return 0;
    return !memcmp(a->p, b->p, (size_t)a->levels * a->n * 3 * sizeof *a->p);
}

static uint32_t level_faces(st_doc *d, unsigned l)
{
    st_mesh m;
    st_mesh_init(&m);
    st_error err;
    uint32_t n = st_hier_level_mesh(&d->h, l, &m, &err) ? 0 : m.nfaces;
    st_mesh_free(&m);
    return n;
}

static int g_calls;
static double g_last;
static int cancel_at_second(void *ctx, double f)
{
    (void)ctx;
    g_last = f;
    return ++g_calls >= 2;
}
static int count_progress(void *ctx, double f)
{
    (void)ctx;
    g_last = f;
    g_calls++;
    return 0;
}
static int cancel_now(void *ctx, double f)
{
    (void)ctx;
    (void)f;
    return 1;
}

/* Rebuild, undo (the old hierarchy bit for bit), redo (the rebuilt one bit
 * for bit). */
static void check_undo_redo(st_doc *d, const snap *before)
{
    st_error err;
    snap after, s;
    snap_take(d, &after);
    CHECK(st_doc_undo_name(d) && !strcmp(st_doc_undo_name(d), "rebuild levels"));
    CHECK(st_doc_undo(d, &err) == 0);
    CHECK(st_doc_redo_name(d) && !strcmp(st_doc_redo_name(d), "rebuild levels"));
    snap_take(d, &s);
    CHECK(snap_equal(&s, before));
    snap_free(&s);
    CHECK(st_doc_redo(d, &err) == 0);
    snap_take(d, &s);
    CHECK(snap_equal(&s, &after));
    CHECK(d->edit_level == 0 && d->display_level == d->h.map.top);
    snap_free(&s);
    snap_free(&after);
}

/* A cube subdivided twice by Catmull-Clark, written as a soup: unsubdivide
 * finds the 6-face cage and 3 levels. */
static void test_unsubdivide(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    CHECK(st_doc_open(&d, STRATA_ASSETS "/cube.obj", "catmull-clark", 2, &err) == 0);
    st_mesh fine;
    st_mesh_init(&fine);
    CHECK(st_hier_level_mesh(&d.h, 2, &fine, &err) == 0);
    CHECK(fine.nfaces == 96);
    const char *path = "test_editor_rebuild_cube2.obj";
    CHECK(st_mesh_save(path, &fine, &err) == 0);
    st_mesh_free(&fine);
    CHECK(st_doc_open(&d, path, "catmull-clark", 0, &err) == 0);
    CHECK(d.h.map.top == 0 && level_faces(&d, 0) == 96);
    snap before;
    snap_take(&d, &before);

    /* Cancelled at the end: nothing changes, no undo step. */
    char msg[256];
    CHECK(st_doc_rebuild_levels(&d, cancel_now, NULL, msg, sizeof msg, &err) != 0);
    CHECKF(strstr(err.msg, "cancelled") != NULL, "%s", err.msg);
    snap s;
    snap_take(&d, &s);
    CHECK(snap_equal(&s, &before) && d.nundo == 0);
    snap_free(&s);

    g_calls = 0;
    CHECK(st_doc_rebuild_levels(&d, count_progress, NULL, msg, sizeof msg, &err) == 0);
    printf("cube, 2 steps: %s\n", msg);
    CHECKF(strstr(msg, "unsubdivide") && strstr(msg, "3 levels"), "%s", msg);
    CHECK(d.h.map.top == 2 && level_faces(&d, 0) == 6 && level_faces(&d, 2) == 96);
    CHECK(d.scheme == st_scheme_find("catmull-clark"));
    CHECK(g_calls >= 1 && g_last == 1.0);
    CHECK(d.edit_level == 0 && d.display_level == 2 && d.nundo == 1);
    check_undo_redo(&d, &before);
    snap_free(&before);
    remove(path);
    st_doc_free(&d);
}

/* The hemisphere is a triangle quadrisection twice over: unsubdivide
 * finds its 40-face cage and Loop. */
static void test_unsubdivide_triangles(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    CHECK(st_doc_open(&d, STRATA_SHARED_DATA "/triangle/hemisphere.obj", "loop", 0, &err) == 0);
    CHECK(level_faces(&d, 0) == 640);
    snap before;
    snap_take(&d, &before);
    char msg[256];
    CHECK(st_doc_rebuild_levels(&d, NULL, NULL, msg, sizeof msg, &err) == 0);
    printf("hemisphere: %s\n", msg);
    CHECKF(strstr(msg, "unsubdivide (loop)") && strstr(msg, "3 levels"), "%s", msg);
    CHECK(d.h.map.top == 2 && level_faces(&d, 0) == 40 && level_faces(&d, 2) == 640);
    check_undo_redo(&d, &before);
    snap_free(&before);
    st_doc_free(&d);
}

/* A triangle mesh without subdivision connectivity: the progressive
 * method, several levels, the finest level the input's faces; a cancel from
 * the progress callback keeps the model. */
static void test_progressive(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    const char *path = STRATA_SHARED_DATA "/triangle/bob_small.ply";
    CHECK(st_doc_open(&d, path, "loop", 0, &err) == 0);
    uint32_t nf = level_faces(&d, 0);
    snap before;
    snap_take(&d, &before);

    char msg[256];
    g_calls = 0;
    CHECK(st_doc_rebuild_levels(&d, cancel_at_second, NULL, msg, sizeof msg, &err) != 0);
    CHECKF(strstr(err.msg, "cancelled") != NULL, "%s", err.msg);
    CHECK(g_calls == 2);
    snap s;
    snap_take(&d, &s);
    CHECK(snap_equal(&s, &before) && d.nundo == 0 && d.h.map.top == 0);
    snap_free(&s);

    g_calls = 0;
    CHECK(st_doc_rebuild_levels(&d, count_progress, NULL, msg, sizeof msg, &err) == 0);
    printf("bob_small: %s (%d progress calls)\n", msg, g_calls);
    CHECKF(strstr(msg, "progressive") != NULL, "%s", msg);
    CHECK(d.h.map.top >= 3);
    CHECK(level_faces(&d, d.h.map.top) == nf);
    CHECK(level_faces(&d, 0) < nf / 4);
    CHECK(g_calls >= 2 && g_last > 0.99 && g_last <= 1.0);
    CHECK(d.scheme == st_scheme_find("progressive"));
    check_undo_redo(&d, &before);
    snap_free(&before);
    st_doc_free(&d);
}

/* ---- tags ------------------------------------------------------------------------- */

/* The vertex of m at p (within tol), or UINT32_MAX. */
static uint32_t vertex_at(const st_mesh *m, const double *p, double tol)
{
    for (uint32_t v = 0; v < m->nverts; v++) {
        const double *q = m->pos + 3 * (size_t)v;
        if (fabs(q[0] - p[0]) <= tol && fabs(q[1] - p[1]) <= tol && fabs(q[2] - p[2]) <= tol) return v;
    }
    return UINT32_MAX;
}

/* The sharpness of the crease a-b of m (either direction), or -1. */
static float crease_of(const st_mesh *m, uint32_t a, uint32_t b)
{
    for (uint32_t i = 0; i < m->ncreases; i++) {
        uint32_t u = m->crease_v[2 * i], w = m->crease_v[2 * i + 1];
        if ((u == a && w == b) || (u == b && w == a)) return m->crease_s[i];
    }
    return -1;
}

static float corner_of(const st_mesh *m, uint32_t v)
{
    for (uint32_t i = 0; i < m->ncorners; i++)
        if (m->corner_v[i] == v) return m->corner_s[i];
    return -1;
}

/* Every crease and corner tag of `want` is in `got` with the same
 * sharpness, at the vertices of the same positions (tol), and got has no
 * others. */
static int same_tags(const st_mesh *want, const st_mesh *got, double tol)
{
    if (want->ncreases != got->ncreases || want->ncorners != got->ncorners) return 0;
    for (uint32_t i = 0; i < want->ncreases; i++) {
        uint32_t a = vertex_at(got, want->pos + 3 * (size_t)want->crease_v[2 * i], tol);
        uint32_t b = vertex_at(got, want->pos + 3 * (size_t)want->crease_v[2 * i + 1], tol);
        if (a == UINT32_MAX || b == UINT32_MAX || crease_of(got, a, b) != want->crease_s[i]) return 0;
    }
    for (uint32_t i = 0; i < want->ncorners; i++) {
        uint32_t v = vertex_at(got, want->pos + 3 * (size_t)want->corner_v[i], tol);
        if (v == UINT32_MAX || corner_of(got, v) != want->corner_s[i]) return 0;
    }
    return 1;
}

/* The cube with two semi-sharp creases (3.5), an infinitely sharp one (10)
 * and a corner (2.5), saved as an OBJ with its tags. */
static void write_creased_cube(const char *path, st_mesh *cage)
{
    st_error err;
    CHECK(st_mesh_load(STRATA_ASSETS "/cube.obj", cage, &err) == 0 && cage->nverts == 8);
    static const uint32_t edges[] = { 0, 1, 1, 5, 5, 4 };
    static const float sharp[] = { 3.5f, 3.5f, 10.0f };
    cage->ncreases = 3;
    cage->crease_v = malloc(sizeof edges);
    cage->crease_s = malloc(sizeof sharp);
    memcpy(cage->crease_v, edges, sizeof edges);
    memcpy(cage->crease_s, sharp, sizeof sharp);
    cage->ncorners = 1;
    cage->corner_v = malloc(sizeof *cage->corner_v);
    cage->corner_s = malloc(sizeof *cage->corner_s);
    cage->corner_v[0] = 1;
    cage->corner_s[0] = 2.5f;
    CHECK(st_mesh_save(path, cage, &err) == 0);
}

/* The creased cube subdivided twice in the document, its finest level saved
 * with its tags (creases 1.5 and 10, corner 0.5 along the chains), then
 * opened as a flat mesh and rebuilt: unsubdivide recovers the cube, and
 * level 0 carries the cube's tags, the same as st_rebuild on the file
 * (what `strata rebuild` runs) gives; the message says which tags were
 * kept.  Undo gives the flat mesh back. */
static void test_unsubdivide_tags(void)
{
    const char *cage_path = "test_editor_rebuild_creased.obj", *fine_path = "test_editor_rebuild_creased2.obj";
    st_mesh cage, fine, lv0, file, cli0;
    st_mesh_init(&cage);
    st_mesh_init(&file);
    write_creased_cube(cage_path, &cage);
    st_doc d;
    st_doc_init(&d);
    st_error err;
    CHECK(st_doc_open(&d, cage_path, "catmull-clark", 2, &err) == 0);
    CHECK(st_rebuild_level_input(&d.h, 2, &fine, &err) == 0);
    CHECKF(fine.nfaces == 96 && fine.ncreases == 12 && fine.ncorners == 1, "finest level: %u faces, %u creases, %u corners",
           fine.nfaces, fine.ncreases, fine.ncorners);
    CHECK(st_mesh_save(fine_path, &fine, &err) == 0);
    st_mesh_free(&fine);

    CHECK(st_doc_open(&d, fine_path, "catmull-clark", 0, &err) == 0);
    CHECK(d.h.map.top == 0 && level_faces(&d, 0) == 96);
    snap before;
    snap_take(&d, &before);
    char msg[512];
    CHECKF(st_doc_rebuild_levels(&d, NULL, NULL, msg, sizeof msg, &err) == 0, "%s", err.msg);
    printf("creased cube, 2 steps: %s\n", msg);
    CHECKF(strstr(msg, "unsubdivide") && strstr(msg, "3 levels") &&
           strstr(msg, "tags kept: cage 3 crease edges, 1 corner, 0 hole faces"), "%s", msg);
    CHECK(d.h.map.top == 2 && level_faces(&d, 0) == 6);
    CHECK(st_rebuild_level_input(&d.h, 0, &lv0, &err) == 0);
    CHECKF(same_tags(&cage, &lv0, 1e-9), "level 0: %u creases, %u corners; the cage %u, %u", lv0.ncreases, lv0.ncorners,
           cage.ncreases, cage.ncorners);
    /* The finest level keeps the file's tags. */
    CHECK(st_rebuild_level_input(&d.h, 2, &fine, &err) == 0);
    CHECK(st_mesh_load(fine_path, &file, &err) == 0);
    CHECK(same_tags(&file, &fine, 0));
    st_mesh_free(&fine);

    /* The CLI's path on the file itself. */
    st_hier h;
    st_rebuild_report rep;
    st_rebuild_opts ro = { .method = ST_REBUILD_AUTO };
    CHECKF(st_rebuild(fine_path, &file, &ro, &h, &rep, &err) == 0, "%s", err.msg);
    CHECK(rep.method == ST_REBUILD_UNSUBDIVIDE && h.map.top == 2);
    CHECK(st_rebuild_level_input(&h, 0, &cli0, &err) == 0);
    CHECK(same_tags(&cli0, &lv0, 1e-12) && cli0.nverts == lv0.nverts && cli0.nfaces == lv0.nfaces);
    st_mesh_free(&cli0);
    st_rebuild_report_free(&rep);
    st_hier_free(&h);
    st_mesh_free(&lv0);

    check_undo_redo(&d, &before);
    /* A scheme change after the rebuild keeps level 0's creases and corner
     * (level 0 is no longer the loaded file, whose tags are the fine ones). */
    CHECKF(st_doc_set_scheme(&d, "quad-triangle", &err) == 0, "%s", err.msg);
    CHECK(st_rebuild_level_input(&d.h, 0, &lv0, &err) == 0);
    CHECKF(same_tags(&cage, &lv0, 1e-9), "after a scheme change, level 0: %u creases, %u corners", lv0.ncreases,
           lv0.ncorners);
    st_mesh_free(&lv0);
    CHECK(st_doc_undo(&d, &err) == 0);
    CHECK(st_doc_undo(&d, &err) == 0 && d.h.map.top == 0);
    CHECK(st_rebuild_level_input(&d.h, 0, &fine, &err) == 0 && same_tags(&file, &fine, 0));
    st_mesh_free(&fine);
    snap_free(&before);
    st_mesh_free(&file);
    st_mesh_free(&cage);
    remove(cage_path);
    remove(fine_path);
    st_doc_free(&d);
}

/* The creased cube itself has no subdivision connectivity: the progressive
 * method, whose message names the tags it dropped. */
static void test_progressive_drops_tags(void)
{
    const char *path = "test_editor_rebuild_creased_cage.obj";
    st_mesh cage;
    st_mesh_init(&cage);
    write_creased_cube(path, &cage);
    st_doc d;
    st_doc_init(&d);
    st_error err;
    CHECK(st_doc_open(&d, path, "catmull-clark", 0, &err) == 0);
    char msg[512];
    CHECKF(st_doc_rebuild_levels(&d, NULL, NULL, msg, sizeof msg, &err) == 0, "%s", err.msg);
    printf("creased cube cage: %s\n", msg);
    CHECKF(strstr(msg, "progressive") && strstr(msg, "dropped 3 crease tags, 1 corner tag"), "%s", msg);
    st_mesh_free(&cage);
    remove(path);
    st_doc_free(&d);
}

int main(void)
{
    test_unsubdivide();
    test_unsubdivide_triangles();
    test_progressive();
    test_unsubdivide_tags();
    test_progressive_drops_tags();
    return TEST_END();
}
