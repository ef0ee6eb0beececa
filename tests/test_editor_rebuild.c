/* Rebuild levels in the document (ui/editor.h, st_doc_rebuild_levels):
 * unsubdivide on a subdivided cube, the progressive method on a triangle
 * mesh without subdivision connectivity, undo and redo bit for bit, and a
 * cancelled rebuild that leaves the document as it was. */
#include "editor.h"
#include "core/map/map_mesh.h"
#include "testlib.h"

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

int main(void)
{
    test_unsubdivide();
    test_unsubdivide_triangles();
    test_progressive();
    return TEST_END();
}
