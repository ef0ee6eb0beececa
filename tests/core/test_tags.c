/* OpenSubdiv's scheme options from OBJ tags, beyond creases: Chaikin
 * creasing (t creasemethod chaikin) and smooth triangles (t smoothtriangles
 * smooth) reach the hierarchy, change the surface, keep local edits equal
 * to a full synthesis bit for bit, and survive a session round trip byte
 * for byte (old sessions, without them, load as uniform/catmark).  The
 * positions against OpenSubdiv are in tests/cli/cli_oracle_catmark.sh and
 * cli_oracle_loop.sh. */
#include "testlib.h"

#include "core/io/session.h"

#include <stdlib.h>
#include <string.h>

/* The octahedron with a crease of varying sharpness through one vertex
 * (Chaikin averages 0.6 and 2.4 there) and smooth triangles. */
static void add_octa_creases(st_mesh *m)
{
    static const uint32_t v[] = { 0, 2, 2, 1, 1, 3 };
    static const float s[] = { 0.6f, 2.4f, 1.3f };
    m->crease_v = malloc(sizeof v);
    m->crease_s = malloc(sizeof s);
    memcpy(m->crease_v, v, sizeof v);
    memcpy(m->crease_s, s, sizeof s);
    m->ncreases = 3;
}

static void octa_uniform(st_mesh *m) { tl_mesh_octa(m); add_octa_creases(m); }
static void octa_chaikin(st_mesh *m) { octa_uniform(m); m->crease_method = ST_CREASE_CHAIKIN; }
static void octa_smooth_tri(st_mesh *m) { octa_chaikin(m); m->tri_sub = ST_TRI_SUB_SMOOTH; }

static double max_diff(st_hier *a, st_hier *b, unsigned l)
{
    st_mesh ma, mb;
    st_error e;
    st_mesh_init(&ma);
    st_mesh_init(&mb);
    double d = -1;
    if (!st_hier_level_mesh(a, l, &ma, &e) && !st_hier_level_mesh(b, l, &mb, &e) && ma.nverts == mb.nverts) {
        d = 0;
        for (size_t i = 0; i < 3 * (size_t)ma.nverts; i++) {
            double x = ma.pos[i] - mb.pos[i];
            if (x < 0) x = -x;
            if (x > d) d = x;
        }
    }
    st_mesh_free(&ma);
    st_mesh_free(&mb);
    return d;
}

/* Each option reaches the hierarchy and moves level 2. */
static void check_options_matter(void)
{
    st_hier u, c, t;
    tl_init_hier(&u, octa_uniform, ST_SCHEME_CATMARK, 2);
    tl_init_hier(&c, octa_chaikin, ST_SCHEME_CATMARK, 2);
    tl_init_hier(&t, octa_smooth_tri, ST_SCHEME_CATMARK, 2);
    CHECK(u.opts.crease_method == ST_CREASE_UNIFORM && u.opts.tri_sub == ST_TRI_SUB_CATMARK);
    CHECK(c.opts.crease_method == ST_CREASE_CHAIKIN && c.opts.tri_sub == ST_TRI_SUB_CATMARK);
    CHECK(t.opts.crease_method == ST_CREASE_CHAIKIN && t.opts.tri_sub == ST_TRI_SUB_SMOOTH);
    double dc = max_diff(&u, &c, 2), dt = max_diff(&c, &t, 2);
    CHECKF(dc > 1e-3, "chaikin moved level 2 by %g", dc);
    CHECKF(dt > 1e-3, "smooth triangles moved level 2 by %g", dt);
    /* Loop ignores the Catmull-Clark option, as OpenSubdiv's harness does. */
    st_hier l;
    tl_init_hier(&l, octa_smooth_tri, ST_SCHEME_LOOP, 1);
    CHECK(l.opts.tri_sub == ST_TRI_SUB_CATMARK && l.opts.crease_method == ST_CREASE_CHAIKIN);
    st_hier_free(&l);
    st_hier_free(&u);
    st_hier_free(&c);
    st_hier_free(&t);
}

/* A session keeps both options; saving the loaded one gives the same bytes. */
static void check_session(void)
{
    st_hier h;
    tl_init_hier(&h, octa_smooth_tri, ST_SCHEME_CATMARK, 2);
    st_session_ref r = { .h = &h };
    st_session s;
    if (tl_session_roundtrip(&r, "opts.strata", &s) == 0) {
        CHECK(s.h.opts.crease_method == ST_CREASE_CHAIKIN && s.h.opts.tri_sub == ST_TRI_SUB_SMOOTH);
        CHECKF(max_diff(&h, &s.h, 2) == 0, "loaded level 2 differs");
        st_session_free(&s);
    }
    st_hier_free(&h);
}

int main(void)
{
    check_options_matter();
    check_session();
    tl_check_local_equals_full_small(ST_SCHEME_CATMARK, octa_chaikin, 3);
    tl_check_local_equals_full_small(ST_SCHEME_CATMARK, octa_smooth_tri, 3);
    tl_check_local_equals_full_small(ST_SCHEME_LOOP, octa_chaikin, 3);
    return TEST_END();
}
