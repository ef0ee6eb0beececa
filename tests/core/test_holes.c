/* Hole faces (OBJ `t hole`, OpenSubdiv's Far hole tag; and the faces
 * `t interpolateboundary 0` removes): they stay in the rules of their
 * vertices, so every position is the one without holes, bit for bit; their
 * children are holes at every level; extraction marks them, the writers
 * leave them out, sessions keep them byte for byte; schemes that do not
 * split faces refuse them.  The positions against OpenSubdiv are in
 * tests/cli/cli_oracle_catmark.sh and cli_oracle_loop.sh. */
#include "testlib.h"

#include "core/io/session.h"
#include "core/map/map.h"
#include "core/progressive/scheme_registry.h"

#include <stdlib.h>
#include <string.h>

/* The cube with faces 2 and 5 (0-based) as holes. */
static void holed_cube(st_mesh *m)
{
    tl_mesh_cube(m);
    m->face_hole = calloc(m->nfaces, 1);
    m->face_hole[2] = m->face_hole[5] = 1;
}

/* The octahedron with faces 0, 3 and 5 as holes. */
static void holed_octa(st_mesh *m)
{
    tl_mesh_octa(m);
    m->face_hole = calloc(m->nfaces, 1);
    m->face_hole[0] = m->face_hole[3] = m->face_hole[5] = 1;
}

static uint32_t count_holes(const st_mesh *m)
{
    uint32_t n = 0;
    for (uint32_t f = 0; m->face_hole && f < m->nfaces; f++) n += m->face_hole[f] != 0;
    return n;
}

/* Positions with and without holes are the same at every level; level l
 * has holes * 4^l hole faces (quads and triangles split in 4). */
static void check_same_surface(st_scheme_id id, void (*plain)(st_mesh *), void (*holed)(st_mesh *),
                               uint32_t holes, unsigned levels)
{
    st_hier a, b;
    tl_init_hier(&a, plain, id, levels);
    tl_init_hier(&b, holed, id, levels);
    for (unsigned l = 0; l <= levels; l++) {
        st_mesh ma, mb;
        st_error e;
        st_mesh_init(&ma);
        st_mesh_init(&mb);
        CHECK(st_hier_level_mesh(&a, l, &ma, &e) == 0 && st_hier_level_mesh(&b, l, &mb, &e) == 0);
        CHECKF(ma.nverts == mb.nverts && ma.nfaces == mb.nfaces, "level %u: %u/%u vertices, %u/%u faces", l,
               ma.nverts, mb.nverts, ma.nfaces, mb.nfaces);
        if (ma.nverts == mb.nverts)
            CHECKF(memcmp(ma.pos, mb.pos, 3 * sizeof(double) * ma.nverts) == 0,
                   "%s level %u: holes moved a vertex", st_scheme_get(id)->name, l);
        CHECKF(ma.face_hole == NULL, "level %u without holes has a hole flag array", l);
        uint32_t expect = holes << (2 * l);
        CHECKF(count_holes(&mb) == expect, "%s level %u: %u hole faces, expected %u", st_scheme_get(id)->name, l,
               count_holes(&mb), expect);
        st_mesh_free(&ma);
        st_mesh_free(&mb);
    }
    st_hier_free(&a);
    st_hier_free(&b);
}

/* The OBJ writer leaves hole faces out and keeps every vertex. */
static void check_writer(void)
{
    st_hier h;
    tl_init_hier(&h, holed_cube, ST_SCHEME_CATMARK, 2);
    st_mesh m, back;
    st_error e;
    st_mesh_init(&m);
    st_mesh_init(&back);
    CHECK(st_hier_level_mesh(&h, 2, &m, &e) == 0);
    const char *path = STRATA_TMP "/holes_level2.obj";
    CHECK(st_mesh_save_obj(path, &m, &e) == 0);
    CHECK(st_mesh_load_obj(path, &back, &e) == 0);
    /* 96 faces, 32 of them holes.  The file keeps all 98 vertices; the
     * reader drops the 21 only hole faces use (9 inside each of the two
     * adjacent hole faces, 3 inside their shared edge). */
    CHECKF(back.nfaces == 64, "written level 2: %u faces, expected 64", back.nfaces);
    CHECKF(m.nverts == 98 && back.nverts == 77, "level 2: %u vertices, read back %u", m.nverts, back.nverts);
    CHECK(back.face_hole == NULL);
    st_mesh_free(&back);
    st_mesh_free(&m);
    st_hier_free(&h);
}

/* Sessions keep the hole flags: the loaded hierarchy has the same holes,
 * and saving it again gives the same bytes. */
static void check_session(void)
{
    st_hier h;
    tl_init_hier(&h, holed_octa, ST_SCHEME_LOOP, 3);
    st_session_ref r = { .h = &h };
    st_error e;
    st_session s;
    if (tl_session_roundtrip(&r, "holes.strata", &s) == 0) {
        st_mesh m;
        st_mesh_init(&m);
        CHECK(st_hier_level_mesh(&s.h, 3, &m, &e) == 0);
        CHECKF(count_holes(&m) == 3 * 64, "loaded level 3: %u holes", count_holes(&m));
        st_mesh_free(&m);
        st_session_free(&s);
    }
    st_hier_free(&h);
}

/* √3 and Doo-Sabin do not split faces inside themselves: refused. */
static void check_refused(void)
{
    static const st_scheme_id ids[] = { ST_SCHEME_SQRT3, ST_SCHEME_DOOSABIN };
    for (unsigned i = 0; i < 2; i++) {
        st_mesh m;
        st_mesh_init(&m);
        if (ids[i] == ST_SCHEME_SQRT3) holed_octa(&m);
        else holed_cube(&m);
        st_hier h;
        st_error e = { 0 };
        int rc = st_hier_init(&h, &m, st_scheme_get(ids[i]), NULL, &e);
        CHECKF(rc != 0 && strstr(e.msg, "holes need a face-splitting scheme"), "%s with holes: rc %d '%s'",
               st_scheme_get(ids[i])->name, rc, e.msg);
        if (!rc) st_hier_free(&h);
        st_mesh_free(&m);
    }
}

/* interpolateboundary 0 on an open 4 x 4 grid: the 12 faces at a boundary
 * vertex are holes, the 4 inner ones are not; with every boundary edge
 * infinitely sharp (crease 10) no face is. */
static void check_boundary_none(void)
{
    for (int sharp = 0; sharp < 2; sharp++) {
        st_mesh m;
        st_mesh_init(&m);
        tl_mesh_grid(&m, 4);
        m.boundary_interp = ST_BOUNDARY_NONE;
        if (sharp) {
            /* The 16 boundary edges of the grid ((n+1)^2 vertices, row-major). */
            m.crease_v = malloc(32 * sizeof *m.crease_v);
            m.crease_s = malloc(16 * sizeof *m.crease_s);
            for (uint32_t i = 0; i < 4; i++) {
                uint32_t e[4][2] = { { i, i + 1 }, { 20 + i, 21 + i }, { 5 * i, 5 * i + 5 }, { 5 * i + 4, 5 * i + 9 } };
                for (int k = 0; k < 4; k++) {
                    m.crease_v[2 * m.ncreases] = e[k][0];
                    m.crease_v[2 * m.ncreases + 1] = e[k][1];
                    m.crease_s[m.ncreases++] = 10.0f;
                }
            }
        }
        st_hier h;
        st_error e = { 0 };
        int rc = st_hier_init(&h, &m, st_scheme_get(ST_SCHEME_CATMARK), NULL, &e);
        CHECKF(rc == 0, "grid with interpolateboundary 0: %s", e.msg);
        if (!rc) {
            CHECK(h.opts.boundary == ST_BOUNDARY_EDGE_ONLY);
            st_mesh out;
            st_mesh_init(&out);
            CHECK(st_hier_level_mesh(&h, 0, &out, &e) == 0);
            uint32_t expect = sharp ? 0 : 12;
            CHECKF(count_holes(&out) == expect, "interpolateboundary 0%s: %u holes, expected %u",
                   sharp ? " with sharp boundary" : "", count_holes(&out), expect);
            st_mesh_free(&out);
            st_hier_free(&h);
        }
        st_mesh_free(&m);
    }
}

int main(void)
{
    check_same_surface(ST_SCHEME_CATMARK, tl_mesh_cube, holed_cube, 2, 3);
    check_same_surface(ST_SCHEME_LOOP, tl_mesh_octa, holed_octa, 3, 3);
    check_same_surface(ST_SCHEME_BUTTERFLY, tl_mesh_octa, holed_octa, 3, 2);
    check_same_surface(ST_SCHEME_QUADTRI, tl_mesh_cube, holed_cube, 2, 2);
    /* Local re-synthesis with holes == full synthesis (bit-exact). */
    tl_check_local_equals_full_small(ST_SCHEME_CATMARK, holed_cube, 3);
    tl_check_local_equals_full_small(ST_SCHEME_LOOP, holed_octa, 3);
    check_writer();
    check_session();
    check_refused();
    check_boundary_none();
    return TEST_END();
}
