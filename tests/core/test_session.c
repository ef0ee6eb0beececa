/* Session files (core/io/session.h): byte-identical round trips, bit-equal
 * geometry after reloading, identical behaviour of later edits and box
 * moves, refusal of truncated, bit-flipped, crafted and foreign-version
 * files; normals and the mesh writers. */
#include "core/adapt/adapt.h"
#include "core/multires/hier_internal.h"
#include "core/io/map_io_internal.h"
#include "core/io/session.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"
#include "core/rebuild/rebuild.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void torus(st_mesh *s) { tl_mesh_torus(s, 8, 6); }

/* The cube with two creases and a corner (Catmull-Clark sharpness). */
static void creased_cube(st_mesh *s)
{
    tl_mesh_cube(s);
    s->ncreases = 2;
    s->crease_v = malloc(4 * sizeof *s->crease_v);
    s->crease_s = malloc(2 * sizeof *s->crease_s);
    uint32_t f0 = s->face_off[0];
    s->crease_v[0] = s->face_idx[f0];
    s->crease_v[1] = s->face_idx[f0 + 1];
    s->crease_v[2] = s->face_idx[f0 + 1];
    s->crease_v[3] = s->face_idx[f0 + 2];
    s->crease_s[0] = 2.5f;
    s->crease_s[1] = 10.0f;
    s->ncorners = 1;
    s->corner_v = malloc(sizeof *s->corner_v);
    s->corner_s = malloc(sizeof *s->corner_s);
    s->corner_v[0] = s->face_idx[f0 + 3];
    s->corner_s[0] = 1.5f;
}

static void build(st_hier *h, void (*make)(st_mesh *), st_scheme_id id, unsigned levels, st_mesh *base)
{
    st_mesh s;
    st_error err;
    make(&s);
    int rc = st_hier_init(h, &s, st_scheme_get(id), NULL, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    rc = st_hier_subdivide_to(h, levels, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (base) st_mesh_move(base, &s);
    st_mesh_free(&s);
}


static int snaps_equal(const st_hier *a, const st_hier *b)
{
    tl_posnap x, y;
    tl_snap_pos(a, &x);
    tl_snap_pos(b, &y);
    int eq = x.levels == y.levels && x.n == y.n && !memcmp(x.p, y.p, (size_t)x.levels * x.n * 3 * sizeof *x.p);
    free(x.p);
    free(y.p);
    return eq;
}

/* Moves a few vertices of level l on h (deterministic). */
static void edit(st_hier *h, unsigned l, uint64_t seed)
{
    uint64_t rng = seed;
    uint32_t d[3];
    double p[3][3];
    for (int i = 0; i < 3; i++) {
        d[i] = tl_random_dart_at(&h->map, l, &rng);
        const double *q = st_dart_pos(&h->map, d[i], l);
        for (int k = 0; k < 3; k++) p[i][k] = q[k] + 0.05 * (k + 1) * (i + 1);
    }
    /* One dart per vertex: drop repeats. */
    uint32_t n = 0;
    for (int i = 0; i < 3; i++) {
        int dup = 0;
        for (uint32_t j = 0; j < n; j++) dup |= st_vert(&h->map, d[j], l) == st_vert(&h->map, d[i], l);
        if (!dup) { d[n] = d[i]; memcpy(p[n], p[i], sizeof p[n]); n++; }
    }
    st_hier_move(h, l, d, (const double (*)[3])p, n);
}

static st_adapt_params box_at(double x, unsigned max)
{
    st_adapt_params p;
    memset(&p, 0, sizeof p);
    p.base_level = 0;
    p.max_level = max;
    p.has_box = 1;
    p.box_lo[0] = x - 0.4; p.box_lo[1] = -0.4; p.box_lo[2] = -2;
    p.box_hi[0] = x + 0.4; p.box_hi[1] = 0.4; p.box_hi[2] = 2;
    return p;
}

/* save -> load -> save identical, geometry bit-equal, validator passes;
 * returns the loaded session (caller frees). */
static void round_trip(const char *what, const st_session_ref *r, st_session *out, void **bytes, size_t *nbytes)
{
    size_t n1, n2;
    void *b1 = tl_session_bytes(r, &n1);
    st_error err;
    st_session_init(out);
    int rc = st_session_parse("mem.strata", b1, n1, out, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
    if (rc) { free(b1); *bytes = NULL; return; }
    CHECKF(st_map_validate(&out->h.map, &err) == ST_OK, "%s: %s", what, err.msg);
    st_session_ref r2 = st_session_ref_of(out);
    void *b2 = tl_session_bytes(&r2, &n2);
    CHECKF(n1 == n2 && !memcmp(b1, b2, n1), "%s: load -> save differs (%zu vs %zu bytes)", what, n1, n2);
    CHECKF(snaps_equal(r->h, &out->h), "%s: positions differ after loading", what);
    CHECK(out->h.scheme == r->h->scheme);
    CHECK(out->edit_level == r->edit_level && out->display_level == r->display_level);
    free(b2);
    *bytes = b1;
    *nbytes = n1;
}

static void open_grid(st_mesh *m) { tl_mesh_grid(m, 4); }

/* Whether a session file holds a chunk with this tag. */
static int has_chunk(const unsigned char *b, size_t n, const char tag[4])
{
    for (size_t off = 28; off + 12 <= n - 4;) {
        uint64_t len = 0;
        for (int k = 0; k < 8; k++) len |= (uint64_t)b[off + 4 + k] << (8 * k);
        if (!memcmp(b + off, tag, 4)) return 1;
        off += 12 + len;
    }
    return 0;
}

/* The compact form (version 4: LVL0, POSN): r's hierarchy, saved compact
 * when `compact`, else whole (MAP), loads back as the same model: written
 * whole, the loaded session and r give the same bytes - every level's
 * pools, relations, flags, positions, sharpness and UVs, id for id. */
static void check_compact_form(const char *what, const st_session_ref *r, int compact)
{
    size_t n1, nw1, nw2;
    unsigned char *b1 = tl_session_bytes(r, &n1);
    /* A progressive hierarchy's compact form is its recipe (PMRC). */
    const char *tag = r->h->scheme->id == ST_SCHEME_PROGRESSIVE ? "PMRC" : "LVL0";
    CHECKF(has_chunk(b1, n1, tag) == compact && has_chunk(b1, n1, "MAP ") == !compact,
           "%s: saved %s", what, compact ? "whole, not compact" : "compact, but it cannot be regenerated");
    st_session s;
    st_error err;
    int rc = st_session_parse("compact.strata", b1, n1, &s, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
    if (!rc) {
        st_session_ref w1 = *r, w2 = st_session_ref_of(&s);
        w1.whole_map = w2.whole_map = 1;
        void *a = tl_session_bytes(&w1, &nw1), *b = tl_session_bytes(&w2, &nw2);
        CHECKF(nw1 == nw2 && !memcmp(a, b, nw1), "%s: the regenerated levels differ from the saved ones", what);
        CHECKF(!compact || nw1 > n1, "%s: compact %zu bytes, whole %zu", what, n1, nw1);
        CHECKF(st_hier_regenerable(&s.h) == compact, "%s: regenerable after loading: %d", what, st_hier_regenerable(&s.h));
        if (compact) printf("%s: compact %zu bytes, whole %zu bytes (%.2fx)\n", what, n1, nw1, (double)n1 / nw1);
        free(a);
        free(b);
        st_session_free(&s);
    }
    free(b1);
}

static void check_regular(st_scheme_id id, void (*make)(st_mesh *))
{
    const st_scheme *sc = st_scheme_get(id);
    st_hier h;
    st_mesh base;
    st_mesh_init(&base);
    build(&h, make, id, 3, &base);
    uint64_t rng = 7 + id;
    tl_random_details(&h, &rng, 0.01);
    edit(&h, 1, 99);
    st_session_view view = { { 0.5f, 0.25f, 0 }, 0.7f, 0.3f, 5, 0.8f, 0, 2 };
    st_session_ref r = { .h = &h, .edit_level = 1, .display_level = 3, .view = &view, .base = &base };
    st_session s;
    void *bytes;
    size_t n;
    char what[64];
    snprintf(what, sizeof what, "%s regular", sc->name);
    check_compact_form(what, &r, id != ST_SCHEME_DOOSABIN);   /* the dual encoding is stored whole */
    round_trip(what, &r, &s, &bytes, &n);
    if (!bytes) { st_hier_free(&h); st_mesh_free(&base); return; }
    CHECK(s.has_view && !memcmp(&s.view, &view, sizeof view));
    CHECK(s.has_base && s.base.nverts == base.nverts && !memcmp(s.base.pos, base.pos, 24 * (size_t)base.nverts));
    CHECK(s.h.has_sharpness == h.has_sharpness);
    /* The same later edit on both gives the same positions, bit for bit. */
    edit(&h, 1, 1234);
    edit(&s.h, 1, 1234);
    edit(&h, 2, 77);
    edit(&s.h, 2, 77);
    CHECKF(snaps_equal(&h, &s.h), "%s: edits after reloading differ", what);
    /* And adding a level. */
    st_error err;
    CHECK(st_hier_subdivide_to(&h, 4, &err) == ST_OK);
    CHECK(st_hier_subdivide_to(&s.h, 4, &err) == ST_OK);
    CHECKF(snaps_equal(&h, &s.h), "%s: a new level after reloading differs", what);

    /* A level taken off and added again reuses the removed level's blocks,
     * which a regeneration from level 0 would not: saved whole. */
    st_hier_remove_top(&h);
    CHECK(st_hier_subdivide_to(&h, 4, &err) == ST_OK);
    snprintf(what, sizeof what, "%s level removed and added", sc->name);
    st_session_ref rr = { .h = &h, .edit_level = 1, .display_level = 4 };
    check_compact_form(what, &rr, 0);

    /* Rebased (remove_bottom): ids no rebuild would give. */
    st_hier_remove_bottom(&h);
    st_session_ref rb = { .h = &h, .edit_level = 0, .display_level = h.map.top };
    snprintf(what, sizeof what, "%s rebased", sc->name);
    check_compact_form(what, &rb, 0);
    st_session s2;
    void *b2;
    size_t n2;
    snprintf(what, sizeof what, "%s rebased", sc->name);
    round_trip(what, &rb, &s2, &b2, &n2);
    if (b2) {
        edit(&h, 0, 5);
        edit(&s2.h, 0, 5);
        CHECKF(snaps_equal(&h, &s2.h), "%s: edits after reloading differ", what);
        st_session_free(&s2);
        free(b2);
    }
    st_session_free(&s);
    free(bytes);
    st_hier_free(&h);
    st_mesh_free(&base);
}

static void check_adaptive(st_scheme_id id, void (*make)(st_mesh *))
{
    const st_scheme *sc = st_scheme_get(id);
    st_hier h;
    st_adapt a;
    st_error err;
    build(&h, make, id, 0, NULL);
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    st_adapt_params p = box_at(0.6, 3);
    CHECKF(st_adapt_update(&a, &p, &err) == ST_OK, "%s", err.msg);
    /* Details at every level of the refined region, then a move that
     * coarsens part of it, so that saved and parked details exist. */
    uint64_t rng = 17 + id;
    for (unsigned l = 1; l <= h.map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            double d[3];
            for (int k = 0; k < 3; k++) d[k] = 0.01 * ((double)(tl_rand(&rng) % 2001) / 1000.0 - 1.0);
            st_hier_set_detail(&h, l, v, d);
        }
    }
    st_adapt_synthesize(&a, 0);
    edit(&h, 1, 3);
    st_adapt_synthesize(&a, 1);
    p = box_at(0.2, 3);
    CHECKF(st_adapt_update(&a, &p, &err) == ST_OK, "%s", err.msg);
    st_session_ref r = { .h = &h, .adapt = &a, .box = &p, .box_on = 1, .edit_level = 0, .display_level = h.map.top };
    st_session s;
    void *bytes;
    size_t n;
    char what[64];
    snprintf(what, sizeof what, "%s adaptive", sc->name);
    round_trip(what, &r, &s, &bytes, &n);
    if (!bytes) { st_adapt_free(&a); st_hier_free(&h); return; }
    CHECK(s.has_adapt && s.adapt.h == &s.h && s.box_on);
    CHECK(s.adapt.nsaved == a.nsaved && s.adapt.nparked == a.nparked);
    printf("%s: %zu bytes, levels 0..%u, %u saved and %u parked details\n", what, n, h.map.top, a.nsaved, a.nparked);
    CHECK(!memcmp(&s.box, &p, sizeof p));
    /* The same box moves on both: same bytes afterwards (incremental path). */
    double xs[] = { 0.1, 0.7, -0.3 };
    for (int k = 0; k < 3; k++) {
        st_adapt_params q = box_at(xs[k], 3);
        CHECK(st_adapt_update(&a, &q, &err) == ST_OK);
        CHECK(st_adapt_update(&s.adapt, &q, &err) == ST_OK);
        CHECKF(snaps_equal(&h, &s.h), "%s: box move %d after reloading differs", what, k);
    }
    st_session_ref r1 = { .h = &h, .adapt = &a, .box = &p, .box_on = 1, .display_level = h.map.top };
    st_session_ref r2 = st_session_ref_of(&s);
    r2.box = &p;
    size_t n1, n2;
    void *x1 = tl_session_bytes(&r1, &n1), *x2 = tl_session_bytes(&r2, &n2);
    CHECKF(n1 == n2 && !memcmp(x1, x2, n1), "%s: sessions differ after the same box moves", what);
    free(x1);
    free(x2);
    st_session_free(&s);
    free(bytes);
    st_adapt_free(&a);
    st_hier_free(&h);
}

/* Every prefix and every single-bit flip is refused with the file's name. */
static void check_damage(void)
{
    st_hier h;
    build(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 1, NULL);
    st_session_ref r = { .h = &h, .display_level = 1 };
    size_t n;
    unsigned char *b = tl_session_bytes(&r, &n);
    st_session s;
    st_error err;
    int refused = 0, named = 0, total = 0;
    for (size_t k = 0; k < n; k++) {
        memset(&s, 0xab, sizeof s); /* must stay untouched */
        int rc = st_session_parse("cut.strata", b, k, &s, &err);
        total++;
        refused += rc != ST_OK;
        named += rc != ST_OK && strstr(err.msg, "cut.strata") && !strchr(err.msg, '\n');
    }
    CHECKF(refused == total && named == total, "prefixes: %d of %d refused, %d named", refused, total, named);
    refused = named = total = 0;
    unsigned char *c = malloc(n);
    for (size_t k = 0; k < n; k++) {
        memcpy(c, b, n);
        c[k] ^= (unsigned char)(1u << (k % 8));
        int rc = st_session_parse("flip.strata", c, n, &s, &err);
        total++;
        refused += rc != ST_OK;
        named += rc != ST_OK && strstr(err.msg, "flip.strata") != NULL;
    }
    CHECKF(refused == total && named == total, "bit flips: %d of %d refused, %d named", refused, total, named);
    /* A newer version: clear message (header checksum made valid). */
    memcpy(c, b, n);
    c[8] = 7;
    uint32_t hc = st_crc32(0, c, 24);
    for (int k = 0; k < 4; k++) c[24 + k] = (unsigned char)(hc >> (8 * k));
    CHECK(st_session_parse("new.strata", c, n, &s, &err) != ST_OK);
    CHECKF(!strcmp(err.msg, "new.strata: session format version 7 is newer than this strata (5)"), "%s", err.msg);
    /* Not a session at all. */
    CHECK(st_session_parse("x.strata", "hello world, this is not a session file", 39, &s, &err) != ST_OK);
    CHECKF(strstr(err.msg, "x.strata: not a Strata session") != NULL, "%s", err.msg);
    free(c);
    free(b);
    st_hier_free(&h);
}

/* Crafted files with valid checksums: random byte changes must be refused
 * or give a session that validates (no crash: run under ASan). */
static void check_crafted(st_scheme_id id, void (*make)(st_mesh *), int adaptive)
{
    st_hier h;
    st_adapt a;
    st_error err;
    build(&h, make, id, adaptive ? 0 : 2, NULL);
    st_adapt_params p = box_at(0.5, 2);
    if (adaptive) {
        CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
        CHECK(st_adapt_update(&a, &p, &err) == ST_OK);
    }
    st_session_ref r = { .h = &h, .adapt = adaptive ? &a : NULL, .box = &p, .box_on = adaptive };
    size_t n;
    unsigned char *b = tl_session_bytes(&r, &n);
    unsigned char *c = malloc(n);
    uint64_t rng = 4242 + id;
    int accepted = 0;
    for (int it = 0; it < 3000; it++) {
        memcpy(c, b, n);
        int k = 1 + (int)(tl_rand(&rng) % 4);
        for (int j = 0; j < k; j++) {
            size_t at = 28 + tl_rand(&rng) % (n - 32);
            c[at] = (tl_rand(&rng) & 1) ? (unsigned char)tl_rand(&rng) : (unsigned char)(c[at] ^ (1u << (tl_rand(&rng) % 8)));
        }
        tl_session_fix_crc(c, n);
        st_session s;
        if (st_session_parse("crafted.strata", c, n, &s, &err) == ST_OK) {
            accepted++;
            CHECKF(st_map_validate(&s.h.map, &err) == ST_OK, "%s", err.msg);
            st_mesh m;
            st_mesh_init(&m);
            if (st_hier_level_mesh(&s.h, s.h.map.top, &m, &err) == ST_OK) st_mesh_free(&m);
            st_session_free(&s);
        } else {
            CHECKF(strstr(err.msg, "crafted.strata") != NULL, "%s", err.msg);
        }
    }
    (void)accepted;
    free(c);
    free(b);
    if (adaptive) st_adapt_free(&a);
    st_hier_free(&h);
}

/* Files: crash-safe save over an existing file, load, no stray temporary. */
static void check_files(void)
{
    char path[1024], tmp[1100];
    snprintf(path, sizeof path, "%s/test_session_%ld.strata", STRATA_TMP, (long)getpid());
    st_hier h;
    st_error err;
    build(&h, torus, ST_SCHEME_CATMARK, 2, NULL);
    st_session_ref r = { .h = &h, .display_level = 2 };
    CHECKF(st_session_save_ref(path, &r, &err) == ST_OK, "%s", err.msg);
    edit(&h, 0, 11);
    CHECKF(st_session_save_ref(path, &r, &err) == ST_OK, "%s", err.msg);
    snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid());
    CHECK(access(tmp, F_OK) != 0);
    st_session s;
    CHECKF(st_session_load(path, &s, &err) == ST_OK, "%s", err.msg);
    CHECK(snaps_equal(&h, &s.h));
    /* Moving a session keeps it usable (pointers re-aimed). */
    st_session t;
    st_session_init(&t);
    st_session_move(&t, &s);
    CHECK(st_hier_subdivide_to(&t.h, 3, &err) == ST_OK);
    CHECK(st_map_validate(&t.h.map, &err) == ST_OK);
    st_session_free(&t);
    st_session_free(&s);
    /* Moving a hierarchy with sharpness out of a session (what the window
     * does on Open): the map's attributes follow. */
    st_hier hc;
    build(&hc, creased_cube, ST_SCHEME_CATMARK, 1, NULL);
    st_session_ref rc = { .h = &hc, .display_level = 1 };
    CHECKF(st_session_save_ref(path, &rc, &err) == ST_OK, "%s", err.msg);
    CHECKF(st_session_load(path, &s, &err) == ST_OK, "%s", err.msg);
    st_hier *moved = malloc(sizeof *moved);
    st_session_move_hier(moved, &s.h);
    st_session_free(&s);
    CHECK(moved->has_sharpness && moved->map.ndart_attrs == 1 && moved->map.dart_attrs[0] == &moved->edge_sharp &&
          moved->map.vert_attrs[0] == &moved->vertex_sharp);
    CHECK(st_hier_subdivide_to(moved, 3, &err) == ST_OK && st_hier_subdivide_to(&hc, 3, &err) == ST_OK);
    CHECK(snaps_equal(moved, &hc));
    st_hier_free(moved);
    free(moved);
    st_hier_free(&hc);
    CHECK(st_session_load("/nonexistent/dir/x.strata", &s, &err) != ST_OK);
    CHECK(strstr(err.msg, "/nonexistent/dir/x.strata") != NULL);
    CHECK(st_session_save_ref("/nonexistent/dir/x.strata", &r, &err) != ST_OK);
    remove(path);
    /* Recovery path: the environment override wins. */
    char rec[512];
    setenv("STRATA_RECOVERY", "/tmp/strata-test-recovery/x/recovery.strata", 1);
    CHECK(st_session_recovery_path(rec, sizeof rec) == 0);
    CHECK(!strcmp(rec, "/tmp/strata-test-recovery/x/recovery.strata"));
    CHECK(access("/tmp/strata-test-recovery/x", F_OK) == 0);
    rmdir("/tmp/strata-test-recovery/x");
    rmdir("/tmp/strata-test-recovery");
    unsetenv("STRATA_RECOVERY");
    st_hier_free(&h);
}

/* The file a path holds, whole (NULL when it cannot be read). */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc(len > 0 ? (size_t)len : 1);
    *n = b && len > 0 && fread(b, 1, (size_t)len, f) == (size_t)len ? (size_t)len : 0;
    fclose(f);
    return b;
}

/* A model holding a number the reader refuses (an edit that overflowed the
 * double range) is not saved: the save fails with a message naming what
 * holds it, and a file already at the path stays as it was.  A value
 * that is only large is saved and read back. */
static void check_non_finite(void)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/test_session_nf_%ld.strata", STRATA_TMP, (long)getpid());
    st_hier h;
    st_error err;
    build(&h, torus, ST_SCHEME_CATMARK, 2, NULL);
    st_session_ref r = { .h = &h, .display_level = 2 };
    CHECKF(st_session_save_ref(path, &r, &err) == ST_OK, "%s", err.msg);
    size_t n0 = 0, n1 = 0;
    unsigned char *before = slurp(path, &n0);
    CHECK(before && n0 > 0);

    st_dart_iter it;
    uint32_t v = st_vert(&h.map, st_dart_first(&h.map, 2, &it), 2);
    double keep[3], p[3];
    memcpy(keep, st_pos(&h.map, v, 2), sizeof keep);
    for (int bad = 0; bad < 3; bad++) {
        const double value[3] = { INFINITY, NAN, -INFINITY };
        memcpy(p, keep, sizeof p);
        p[bad] = value[bad];
        st_set_pos(&h.map, v, 2, p);
        void *data = NULL;
        size_t nd = 0;
        CHECK(st_session_write_mem(&r, &data, &nd, &err) != ST_OK && data == NULL && nd == 0);
        CHECKF(strstr(err.msg, "positions") && strstr(err.msg, "not finite"), "%s", err.msg);
        CHECK(st_session_save_ref(path, &r, &err) != ST_OK);
        CHECKF(strstr(err.msg, path) && strstr(err.msg, "positions"), "%s", err.msg);
        unsigned char *after = slurp(path, &n1);
        CHECK(after && n1 == n0 && !memcmp(after, before, n0));
        free(after);
    }
    st_set_pos(&h.map, v, 2, keep);
    CHECKF(st_session_save_ref(path, &r, &err) == ST_OK, "%s", err.msg);

    /* A detail (an edit of level 1 gives them), then a large but finite
     * one, which loads back bit-equal. */
    edit(&h, 1, 5);
    CHECK(h.detail[1] != NULL && h.detail_cap[1] > 0);
    if (!h.detail[1] || !h.detail_cap[1]) { free(before); st_hier_free(&h); return; }
    double d0 = h.detail[1][0];
    h.detail[1][0] = NAN;
    CHECK(st_session_save_ref(path, &r, &err) != ST_OK);
    CHECKF(strstr(err.msg, "details") != NULL, "%s", err.msg);
    h.detail[1][0] = 1e300;
    size_t nb = 0;
    void *bytes = tl_session_bytes(&r, &nb);
    st_session s;
    CHECKF(st_session_parse("large.strata", bytes, nb, &s, &err) == ST_OK, "%s", err.msg);
    CHECK(s.h.detail[1] && s.h.detail[1][0] == 1e300);
    st_session_free(&s);
    free(bytes);
    h.detail[1][0] = d0;
    free(before);
    remove(path);
    st_hier_free(&h);
}

/* Normals: unit length, outward on a convex mesh; OBJ and PLY read back. */
static void check_normals(void)
{
    st_hier h;
    st_error err;
    st_mesh m, back;
    build(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 2, NULL);
    st_mesh_init(&m);
    st_mesh_init(&back);
    CHECK(st_hier_level_mesh(&h, 2, &m, &err) == ST_OK);
    CHECK(st_mesh_compute_normals(&m) == 0);
    double c[3] = { 0, 0, 0 };
    for (uint32_t v = 0; v < m.nverts; v++)
        for (int k = 0; k < 3; k++) c[k] += m.pos[3 * v + k] / m.nverts;
    int unit = 1, outward = 1;
    for (uint32_t v = 0; v < m.nverts; v++) {
        const double *n = m.normals + 3 * v, *p = m.pos + 3 * v;
        unit &= fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-12;
        outward &= n[0] * (p[0] - c[0]) + n[1] * (p[1] - c[1]) + n[2] * (p[2] - c[2]) > 0;
    }
    CHECK(unit);
    CHECK(outward);
    const char *exts[] = { "obj", "ply" };
    for (int e = 0; e < 2; e++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/test_session_normals_%ld.%s", STRATA_TMP, (long)getpid(), exts[e]);
        CHECKF(st_mesh_save(path, &m, &err) == ST_OK, "%s", err.msg);
        size_t size;
        char *text = tl_read_file(path, &size);
        CHECK(text != NULL);
        if (text && e == 0) CHECK(strstr(text, "\nvn ") && strstr(text, "//"));
        if (text && e == 1) CHECK(strstr(text, "property double nx") != NULL);
        free(text);
        CHECKF(st_mesh_load(path, &back, &err) == ST_OK, "%s", err.msg);
        CHECK(back.nverts == m.nverts && back.nfaces == m.nfaces);
        CHECK(back.nverts == m.nverts && !memcmp(back.pos, m.pos, 24 * (size_t)m.nverts));
        remove(path);
    }
    st_mesh_free(&back);
    st_mesh_free(&m);
    st_hier_free(&h);
}

/* The window's settings (ancillary chunk 'tool'): kept through save, load
 * and save to the byte; a session without them loads without; a value the
 * reader would refuse is refused by the writer, nothing written; a reader
 * meeting a bad value in the file names the chunk. */
static void check_tool(void)
{
    st_hier h;
    build(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 2, NULL);
    st_session_tool t = { .tool = 4, .radius = 0.25, .strength = 0.3, .falloff = 3, .mirror = 5,
                          .show = ST_SESSION_SHOW_WIRE | ST_SESSION_SHOW_FLAT };
    st_session_ref r = { .h = &h, .edit_level = 1, .display_level = 2, .tool = &t };
    st_session s;
    void *bytes;
    size_t n;
    round_trip("tool settings", &r, &s, &bytes, &n);
    if (bytes) {
        CHECK(s.has_tool && s.tool.tool == 4 && s.tool.radius == 0.25 && s.tool.strength == 0.3 && s.tool.falloff == 3 &&
              s.tool.mirror == 5 && s.tool.show == (ST_SESSION_SHOW_WIRE | ST_SESSION_SHOW_FLAT));
        /* A bad value in the file: refused, the chunk named. */
        unsigned char *c = bytes;
        size_t at = 0;
        for (size_t i = 0; i + 4 <= n; i++)
            if (!memcmp(c + i, "tool", 4)) at = i;
        CHECK(at > 0);
        if (at) {
            double bad = 2.0;   /* strength */
            memcpy(c + at + 4 + 8 + 4 + 8, &bad, 8);
            tl_session_fix_crc(c, n);
            st_session s3;
            st_error err;
            st_session_init(&s3);
            CHECK(st_session_parse("mem.strata", c, n, &s3, &err) != ST_OK);
            CHECKF(strstr(err.msg, "tool settings") && strstr(err.msg, "strength"), "bad strength: %s", err.msg);
            st_session_free(&s3);
        }
        free(bytes);
        st_session_free(&s);
    }
    st_session_ref none = { .h = &h, .edit_level = 0, .display_level = 2 };
    round_trip("no tool settings", &none, &s, &bytes, &n);
    if (bytes) {
        CHECK(!s.has_tool);
        free(bytes);
        st_session_free(&s);
    }
    t.strength = 1.5;
    void *data = NULL;
    size_t nd = 0;
    st_error err;
    CHECK(st_session_write_mem(&r, &data, &nd, &err) != ST_OK && strstr(err.msg, "strength"));
    free(data);
    st_hier_free(&h);
}

/* Every relation and pool of two maps equal, id for id. */
static int maps_equal(const st_map *a, const st_map *b)
{
    if (a->top != b->top || a->darts.end != b->darts.end || a->verts.end != b->verts.end) return 0;
    if (memcmp(a->darts.ins, b->darts.ins, a->darts.end) || memcmp(a->verts.ins, b->verts.ins, a->verts.end)) return 0;
    for (unsigned l = 0; l <= a->top; l++) {
        st_dart_iter it;
        for (uint32_t d = st_dart_first(a, l, &it); d != ST_NIL; d = st_dart_next(a, l, &it))
            if (st_beta0(a, d, l) != st_beta0(b, d, l) || st_beta1(a, d, l) != st_beta1(b, d, l) ||
                st_vert(a, d, l) != st_vert(b, d, l) || !st_dart_in_level(b, d, l))
                return 0;
    }
    return 1;
}

static int read_whole(const char *path, unsigned char **data, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    *data = malloc(len > 0 ? (size_t)len : 1);
    *n = *data && len > 0 ? fread(*data, 1, (size_t)len, f) : 0;
    fclose(f);
    return *n == (size_t)len ? 0 : -1;
}

/* Sessions written by earlier versions (1: the first; 2: with UVs; kept in
 * tests/data/session_old) open, save as version 3 and load back as the same
 * model: ids, relations and positions of every level, the same bytes on a
 * second save, the same positions after a new level; and the version-3
 * file, which stores attribute arrays only up to the last live id, is
 * smaller. */
static void check_old_versions(void)
{
    static const char *names[] = { "cube_cc1_layers_mask", "cube_crease1", "cube_ds2",
                                   "octa_progressive1_box", "tetra_loop_box", "uv_seam_cc1" };
    for (size_t k = 0; k < sizeof names / sizeof *names; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/session_old/%s.strata", STRATA_TEST_DATA, names[k]);
        unsigned char *old = NULL;
        size_t nold = 0;
        CHECKF(read_whole(path, &old, &nold) == 0 && nold > 12, "%s: cannot read", path);
        if (nold <= 12) { free(old); continue; }
        CHECKF(old[8] == 1 || old[8] == 2, "%s: version %u, not an old one", path, old[8]);
        st_session a, b;
        st_error err;
        int rc = st_session_parse(path, old, nold, &a, &err);
        CHECKF(rc == ST_OK, "%s", err.msg);
        if (rc) { free(old); continue; }
        st_session_ref ra = st_session_ref_of(&a);
        size_t n1, n2;
        void *b1 = tl_session_bytes(&ra, &n1);
        CHECKF(b1 && ((unsigned char *)b1)[8] == ST_SESSION_VERSION, "%s: saved as version %u", names[k],
               b1 ? ((unsigned char *)b1)[8] : 0);
        CHECKF(b1 && st_session_parse("v3.strata", b1, n1, &b, &err) == ST_OK, "%s: %s", names[k], err.msg);
        if (!b1) { st_session_free(&a); free(old); continue; }
        CHECKF(maps_equal(&a.h.map, &b.h.map), "%s: the map differs after version 3", names[k]);
        CHECKF(snaps_equal(&a.h, &b.h), "%s: positions differ after version 3", names[k]);
        st_session_ref rb = st_session_ref_of(&b);
        void *b2 = tl_session_bytes(&rb, &n2);
        CHECKF(n1 == n2 && !memcmp(b1, b2, n1), "%s: version 3 load -> save differs", names[k]);
        CHECKF(n1 < nold, "%s: version 3 is %zu bytes, version %u was %zu", names[k], n1, old[8], nold);
        printf("%s: version %u %zu bytes -> version 3 %zu bytes (%.2fx)\n", names[k], old[8], nold, n1, (double)n1 / nold);
        /* Later work is the same on both: a new level where the scheme
         * refines uniformly, positions bit-equal. */
        if (!a.has_adapt && a.h.map.top < 3) {
            st_error e1, e2;
            int r1 = st_hier_subdivide_to(&a.h, a.h.map.top + 1, &e1), r2 = st_hier_subdivide_to(&b.h, b.h.map.top + 1, &e2);
            CHECKF(r1 == r2, "%s: a new level: %d on version %u, %d on version 3", names[k], r1, old[8], r2);
            if (!r1 && !r2) CHECKF(maps_equal(&a.h.map, &b.h.map) && snaps_equal(&a.h, &b.h), "%s: a new level differs", names[k]);
        }
        free(b2);
        free(b1);
        st_session_free(&b);
        st_session_free(&a);
        free(old);
    }
}

/* A hierarchy rebuilt by unsubdivide (the cage refined, positions from the
 * input, UVs refined with the levels) is saved compact and loads back as
 * itself; so is one rebuilt by progressive simplification, as its recipe
 * (level 0 and the vertex splits, PMRC). */
static void check_rebuilt(void)
{
    for (int method = ST_REBUILD_UNSUBDIVIDE; method <= ST_REBUILD_PROGRESSIVE; method++) {
        st_hier fine, h;
        st_mesh in;
        st_error err;
        build(&fine, torus, ST_SCHEME_CATMARK, 2, NULL);
        uint64_t rng = 3;
        tl_random_details(&fine, &rng, 0.01);
        st_hier_synthesize(&fine, 0);
        st_mesh_init(&in);
        CHECK(st_rebuild_level_input(&fine, 2, &in, &err) == ST_OK);
        st_rebuild_opts o = { .method = method };
        st_rebuild_report rep;
        int rc = st_rebuild("torus.obj", &in, &o, &h, &rep, &err);
        CHECKF(rc == ST_OK, "%s", err.msg);
        if (!rc) {
            st_session_ref r = { .h = &h, .display_level = h.map.top };
            check_compact_form(method == ST_REBUILD_UNSUBDIVIDE ? "rebuilt by unsubdivide" : "rebuilt by progressive", &r, 1);
            st_hier_free(&h);
        }
        st_rebuild_report_free(&rep);
        st_mesh_free(&in);
        st_hier_free(&fine);
    }
}

int main(void)
{
    check_tool();
    check_regular(ST_SCHEME_CATMARK, creased_cube);
    check_regular(ST_SCHEME_CATMARK, torus);
    check_regular(ST_SCHEME_LOOP, tl_mesh_octa);
    check_regular(ST_SCHEME_DOOSABIN, tl_mesh_cube);
    check_regular(ST_SCHEME_DOOSABIN, open_grid); /* hole corners cut, β1 columns */
    check_regular(ST_SCHEME_SQRT3, tl_mesh_octa);
    check_regular(ST_SCHEME_BUTTERFLY, tl_mesh_octa);
    check_regular(ST_SCHEME_QUADTRI, tl_mesh_cube);
    check_adaptive(ST_SCHEME_CATMARK, creased_cube);
    check_adaptive(ST_SCHEME_CATMARK, torus);
    check_adaptive(ST_SCHEME_LOOP, tl_mesh_octa);
    check_adaptive(ST_SCHEME_BUTTERFLY, tl_mesh_octa);
    check_adaptive(ST_SCHEME_SQRT3, tl_mesh_octa);
    check_damage();
    check_crafted(ST_SCHEME_CATMARK, creased_cube, 0);
    check_crafted(ST_SCHEME_LOOP, tl_mesh_octa, 1);
    check_crafted(ST_SCHEME_DOOSABIN, tl_mesh_cube, 0);
    check_files();
    check_old_versions();
    check_rebuilt();
    check_non_finite();
    check_normals();
    return TEST_END();
}
