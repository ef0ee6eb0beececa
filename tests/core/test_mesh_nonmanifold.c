/* Edges shared by three or more faces open (issue 31 point 4).  The reader
 * splits them as core/io/mesh_repair.c says (after OpenMesh's importer):
 * the first face on the edge and the first later one running the other way
 * keep it, every further face gets its own copies of the edge's two
 * vertices.  Shapes in the spirit of OpenSubdiv's non-manifold regression
 * shapes (regression/shapes/catmark_nonman_edges.h): books of pages on one
 * spine.  Checked:
 *   - the face count is kept, the vertex count grows by the copies, the
 *     result passes st_mesh_check, and the note counts the split edges and
 *     vertices;
 *   - every level of Catmull-Clark (quads and triangles) and Loop
 *     (triangles) passes st_map_validate, with the input's faces at level 0;
 *   - a face further on two crowded edges through one vertex copies that
 *     corner once;
 *   - ST_MESH_STRICT refuses with today's message and leaves the mesh as it
 *     was;
 *   - the split mesh written to OBJ reads back strictly with no repair;
 *   - a Moebius strip is still refused (non-orientable). */
#include "core/io/mesh.h"
#include "core/map/map.h"
#include "core/multires/hier.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <math.h>
#include <string.h>

/* A book: n pages of `quads ? quad : triangle` on the spine 0-1 (the z
 * axis), page k fanned out at angle 2 pi k / n.  Page k runs along the
 * spine 0->1 when dir[k] is '+', 1->0 when '-'. */
static void book(st_mesh *m, unsigned n, int quads, const char *dir)
{
    double pos[3 * 18];
    uint32_t off[9], idx[4 * 8];
    uint32_t nv = 2, c = 0;
    pos[0] = pos[1] = pos[2] = 0;
    pos[3] = pos[4] = 0;
    pos[5] = 1;
    off[0] = 0;
    for (unsigned k = 0; k < n; k++) {
        double a = 6.283185307179586 * k / n, x = cos(a), y = sin(a);
        uint32_t p = nv;
        pos[3 * nv] = x, pos[3 * nv + 1] = y, pos[3 * nv + 2] = 0, nv++;
        if (quads) pos[3 * nv] = x, pos[3 * nv + 1] = y, pos[3 * nv + 2] = 1, nv++;
        /* the corners counter-clockwise seen from one side: 0 1 top bottom */
        uint32_t ring[4] = {0, 1, quads ? p + 1 : p, p};
        uint32_t deg = quads ? 4 : 3;
        if (dir[k] == '+')
            for (uint32_t i = 0; i < deg; i++) idx[c++] = ring[i];
        else
            for (uint32_t i = 0; i < deg; i++) idx[c++] = ring[deg - 1 - i];
        off[k + 1] = c;
    }
    tl_mesh_make(m, pos, nv, off, idx, n);
}

static int has_note(const st_notes *n, const char *what)
{
    for (uint32_t i = 0; i < n->count; i++)
        if (strstr(n->lines[i], what)) return 1;
    return 0;
}

static void print_notes(const char *name, const st_notes *n)
{
    for (uint32_t i = 0; i < n->count; i++) printf("  %s: %s\n", name, n->lines[i]);
}

/* Builds levels 0..3 of scheme on m and validates every level; level 0
 * has m's faces. */
static void check_levels(const char *name, const st_mesh *m, const char *scheme)
{
    st_hier h;
    st_error err = {0};
    int rc = st_hier_init(&h, m, st_scheme_find(scheme), NULL, &err);
    CHECKF(rc == ST_OK, "%s %s: %s", name, scheme, err.msg);
    if (rc) return;
    rc = st_hier_subdivide_to(&h, 3, &err);
    CHECKF(rc == ST_OK, "%s %s: %s", name, scheme, err.msg);
    CHECKF(st_map_validate(&h.map, &err) == ST_OK, "%s %s: %s", name, scheme, err.msg);
    st_mesh l0;
    st_mesh_init(&l0);
    CHECK(st_hier_level_mesh(&h, 0, &l0, &err) == ST_OK);
    CHECKF(l0.nfaces == m->nfaces, "%s %s: level 0 has %u faces, the input %u", name, scheme, l0.nfaces, m->nfaces);
    printf("%s %s: levels 0..%u valid\n", name, scheme, h.map.top);
    st_mesh_free(&l0);
    st_hier_free(&h);
}

/* Repairs a soup; expects its face count kept, nv vertices and the notes
 * (note2 may be NULL). */
static void opens2(const char *name, st_mesh *m, uint32_t nv, const char *note, const char *note2)
{
    uint32_t nf = m->nfaces;
    st_notes n = {0};
    st_error err = {0};
    int rc = st_mesh_repair(name, m, &n, &err);
    CHECKF(rc == 0, "%s: %s", name, err.msg);
    print_notes(name, &n);
    CHECKF(m->nfaces == nf, "%s: %u faces, expected %u", name, m->nfaces, nf);
    CHECKF(m->nverts == nv, "%s: %u vertices, expected %u", name, m->nverts, nv);
    CHECKF(st_mesh_check(name, m, &err) == 0, "%s: %s", name, err.msg);
    CHECKF(has_note(&n, note), "%s: no note says '%s'", name, note);
    CHECKF(!note2 || has_note(&n, note2), "%s: no note says '%s'", name, note2);
    st_notes_free(&n);
}

static void opens(const char *name, st_mesh *m, uint32_t nv, const char *note)
{
    opens2(name, m, nv, note, NULL);
}

static void test_books(void)
{
    st_mesh m;
    /* three quads on one edge, the second running the other way: pages 0
     * and 1 keep the spine, page 2 gets copies of both ends */
    book(&m, 3, 1, "+-+");
    opens("book3q", &m, 10, "split 1 non-manifold edge (3 or more faces on one edge): 1 further face given "
                            "its own copies of the edge's vertices (2 vertices split into 2 copies)");
    check_levels("book3q", &m, "catmull-clark");
    st_mesh_free(&m);
    /* all three the same way: the first two keep it (one is flipped) */
    book(&m, 3, 1, "+++");
    opens("book3q_same", &m, 10, "edge between vertices 0 and 1 split into 2 (faces 0, 1, 2; face 0 and face 1 keep it)");
    check_levels("book3q_same", &m, "catmull-clark");
    st_mesh_free(&m);
    /* four quads, the third the first to run against the first */
    book(&m, 4, 1, "++-+");
    opens("book4q", &m, 14, "edge between vertices 0 and 1 split into 3 (faces 0, 1, 2, 3; face 0 and face 2 keep it)");
    check_levels("book4q", &m, "catmull-clark");
    st_mesh_free(&m);
    /* three and five triangles: Loop too */
    book(&m, 3, 0, "+-+");
    opens("book3t", &m, 7, "split 1 non-manifold edge");
    check_levels("book3t", &m, "catmull-clark");
    check_levels("book3t", &m, "loop");
    st_mesh_free(&m);
    book(&m, 5, 0, "-+-+-");
    opens("book5t", &m, 13, "1 non-manifold edge (3 or more faces on one edge): 3 further faces given their own copies");
    check_levels("book5t", &m, "loop");
    st_mesh_free(&m);
}

/* Face 4 (0 1 2) is the third face on both 0-1 and 1-2: its corner at 1 is
 * copied once, so it gets three copies in all; without it, faces 0-1 and
 * 2-3 meet only at vertex 1, which the fan split then splits. */
static void test_two_crowded_edges(void)
{
    static const double pos[] = {0, 0, 0, 1, 0, 0, 2, 0, 1, 0.5, 1, 0, 0.5, -1, 0, 1.5, 1, 0, 1.5, -1, 0};
    static const uint32_t off[] = {0, 3, 6, 9, 12, 15};
    static const uint32_t idx[] = {1, 0, 3, 0, 1, 4, 1, 2, 5, 2, 1, 6, 0, 1, 2};
    st_mesh m;
    tl_mesh_make(&m, pos, 7, off, idx, 5);
    opens2("two_edges", &m, 11, "split 2 non-manifold edges (3 or more faces on one edge): 1 further face given "
                                "its own copies of the edge's vertices (3 vertices split into 3 copies)",
           "vertex 1 split into 2");
    check_levels("two_edges", &m, "loop");
    check_levels("two_edges", &m, "catmull-clark");
    st_mesh_free(&m);
}

static void test_strict(void)
{
    st_mesh m;
    st_notes n = {0};
    st_error err = {0};
    book(&m, 3, 1, "+-+");
    int rc = st_mesh_repair_flags("strict_book", &m, ST_MESH_STRICT, &n, &err);
    CHECKF(rc == ST_ERR_TOPOLOGY && strstr(err.msg, "strict_book: non-manifold edge between vertices 0 and 1: "
                                                    "3 faces share it (faces 0, 1, 2)"),
           "strict: rc %d, %s", rc, err.msg);
    CHECK(m.nverts == 8 && m.nfaces == 3 && n.count == 0);
    st_mesh_free(&m);
}

/* What a session or an export writes is the split mesh: it reads back
 * strictly, with no note. */
static void test_written_split(void)
{
    st_mesh m, back;
    st_error err = {0};
    st_notes n = {0};
    book(&m, 3, 1, "+-+");
    CHECK(st_mesh_repair("book", &m, NULL, &err) == 0);
    const char *path = STRATA_TMP "/nonman_book_split.obj";
    CHECKF(st_mesh_save(path, &m, &err) == 0, "%s", err.msg);
    st_mesh_init(&back);
    CHECKF(st_mesh_load_flags(path, &back, ST_MESH_STRICT, &n, &err) == 0, "%s", err.msg);
    CHECK(back.nverts == 10 && back.nfaces == 3 && n.count == 0);
    st_notes_free(&n);
    st_mesh_free(&back);
    st_mesh_free(&m);
}

static void test_moebius_refused(void)
{
    /* three quads glued with a half twist (as in test_mesh_bad_input.c) */
    static const double pos[] = {0, 0, 1, 1, 0, 1, 2, 0, 1, 0, 0, 0, 1, 0, 0, 2, 0, 0};
    static const uint32_t off[] = {0, 4, 8, 12};
    static const uint32_t idx[] = {0, 1, 4, 3, 1, 2, 5, 4, 2, 3, 0, 5};
    st_mesh m;
    st_error err = {0};
    tl_mesh_make(&m, pos, 6, off, idx, 3);
    int rc = st_mesh_repair("moebius", &m, NULL, &err);
    CHECKF(rc == ST_ERR_TOPOLOGY && strstr(err.msg, "non-orientable surface: cannot orient consistently"),
           "moebius: rc %d, %s", rc, err.msg);
    st_mesh_free(&m);
}

int main(void)
{
    test_books();
    test_two_crowded_edges();
    test_strict();
    test_written_split();
    test_moebius_refused();
    return TEST_END();
}
