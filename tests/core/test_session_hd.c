/* The HD hierarchy in a session (ancillary chunk `hdlv`, core/io/session.h,
 * docs/SESSION-FORMAT.md): bit-equal round trips and the same bytes on a
 * second save; the chunk adds nothing else to the file (deleting it gives
 * the bytes of the session without HD, and a reader that does not know it
 * loads the uniform model); a damaged or foreign chunk fails the whole load
 * with the chunk named, leaving the output untouched.
 *
 * Also a generator for other tests:
 *   test_session_hd --write OUT.strata   a cube, model to level 2, HD to 4
 *                                        (tests/cli/cli_session_hd.sh)
 *   test_session_hd --seed OUT.strata    a cube, model to level 1, HD to 3
 *                                        (the fuzzer's seed
 *                                        tests/fuzz/corpus/session/cube_cc1_hd.strata)
 *   test_session_hd --write-layer OUT.strata  the --write cube with a sculpt
 *                                        layer at HD level 4 (cli_session_hd.sh)
 *   test_session_hd --seed-layer OUT.strata   the same with a sculpt layer
 *                                        at HD level 3 (cube_cc1_hd_layer.strata) */
#include "core/adapt/adapt.h"
#include "core/multires/hier_internal.h"
#include "core/io/map_io_internal.h"
#include "core/map/renumber_internal.h"
#include "core/io/session.h"
#include "core/multires/layers.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A model (main hierarchy) and an HD hierarchy made from it. */
typedef struct hd_doc {
    st_hier h;
    st_session copy;   /* the HD hierarchy: copy.h, its adaptive state copy.adapt */
} hd_doc;


/* The model: make() refined by `scheme` to `levels`. */
static int build_model(st_hier *h, void (*make)(st_mesh *), st_scheme_id id, unsigned levels)
{
    st_mesh s;
    st_error err;
    make(&s);
    int rc = st_hier_init(h, &s, st_scheme_get(id), NULL, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (!rc) {
        rc = st_hier_subdivide_to(h, levels, &err);
        CHECKF(rc == ST_OK, "%s", err.msg);
        if (rc) st_hier_free(h);
    }
    st_mesh_free(&s);
    return rc;
}

/* A copy of h with the same ids: its saved bytes parsed again. */
static int copy_hier(const st_hier *h, st_session *out)
{
    st_session_ref r = { .h = h, .whole_map = 1 };
    size_t n = 0;
    void *b = tl_session_bytes(&r, &n);
    st_error err;
    int rc = b ? st_session_parse("copy", b, n, out, &err) : -1;
    CHECKF(rc == ST_OK, "copy: %s", b ? err.msg : "not written");
    free(b);
    return rc;
}

/* The HD hierarchy: the model copied, refined adaptively from its top to
 * max_level inside the box, a few non-zero details set at the two finest
 * levels and the levels above the model synthesised. */
static int make_hd(hd_doc *d, void (*make)(st_mesh *), unsigned levels, unsigned max_level, const double lo[3], const double hi[3])
{
    if (build_model(&d->h, make, ST_SCHEME_CATMARK, levels)) return -1;
    if (copy_hier(&d->h, &d->copy)) { st_hier_free(&d->h); return -1; }
    st_session *c = &d->copy;
    st_error err;
    int rc = st_adapt_init(&c->adapt, &c->h, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (rc) goto fail;
    c->has_adapt = 1;
    st_adapt_params p = { .base_level = levels, .max_level = max_level, .has_box = 1 };
    memcpy(p.box_lo, lo, sizeof p.box_lo);
    memcpy(p.box_hi, hi, sizeof p.box_hi);
    rc = st_adapt_update(&c->adapt, &p, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (rc) goto fail;
    CHECKF(c->h.map.top == max_level, "HD top %u, wanted %u", c->h.map.top, max_level);
    unsigned set = 0;
    for (unsigned l = max_level - 1; l <= max_level; l++) {
        st_dart_iter it;
        unsigned k = 0;
        for (uint32_t v = st_vertex_first(&c->h.map, l, &it); v != ST_NIL; v = st_vertex_next(&c->h.map, l, &it)) {
            if (c->h.map.verts.ins[v] != l || k++ % 3) continue;
            double dd[3] = { 0.001 * (v % 7), -0.002 * (l % 3 + 1), 0.0005 * (double)(k % 5) + 0.0001 };
            st_hier_set_detail(&c->h, l, v, dd);
            set++;
        }
    }
    CHECKF(set > 3, "details set on %u vertices", set);
    st_adapt_synthesize(&c->adapt, levels);
    return 0;
fail:
    st_session_free(c);
    st_hier_free(&d->h);
    return -1;
}

static void free_hd(hd_doc *d)
{
    st_session_free(&d->copy);
    st_hier_free(&d->h);
}

static st_session_ref ref_of(hd_doc *d, int with_hd)
{
    st_session_ref r = { .h = &d->h, .display_level = d->h.map.top };
    if (with_hd) {
        r.hd = &d->copy.h;
        r.hd_adapt = &d->copy.adapt;
        r.hd_from = d->h.map.top;
    }
    return r;
}

/* Detail of vertex v at level l, +0 past the array (as st_hier_detail). */
static const double *detail_at(const st_hier *h, unsigned l, uint32_t v)
{
    static const double zero[3];
    return h->detail[l] && v < h->detail_cap[l] ? h->detail[l] + 3 * (size_t)v : zero;
}

/* Same topology counts, positions of every level and details, bit for bit. */
static int hier_same(const st_hier *a, const st_hier *b)
{
    const st_map *x = &a->map, *y = &b->map;
    if (x->top != y->top || x->darts.end != y->darts.end || x->verts.end != y->verts.end) return 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
        if (x->darts.live[l] != y->darts.live[l] || x->verts.live[l] != y->verts.live[l]) return 0;
    tl_posnap p, q;
    tl_snap_pos(a, &p);
    tl_snap_pos(b, &q);
    int eq = p.levels == q.levels && p.n == q.n && !memcmp(p.p, q.p, (size_t)p.levels * p.n * 3 * sizeof *p.p);
    free(p.p);
    free(q.p);
    for (unsigned l = 1; eq && l <= x->top; l++)
        for (uint32_t v = 0; eq && v < x->verts.end; v++) eq = !memcmp(detail_at(a, l, v), detail_at(b, l, v), 3 * sizeof(double));
    return eq;
}

/* Offset of the chunk `tag` in session bytes, or 0. */
static size_t chunk_at(const unsigned char *b, size_t n, const char tag[4], uint64_t *len)
{
    size_t off = 28;
    while (off + 12 <= n - 4) {
        uint64_t l = 0;
        for (int k = 0; k < 8; k++) l |= (uint64_t)b[off + 4 + k] << (8 * k);
        if (!memcmp(b + off, tag, 4)) { *len = l; return off; }
        off += 12 + (size_t)l;
    }
    return 0;
}

/* The bytes with `cut` bytes of the chunk at off taken out from its
 * payload's end (the whole chunk when cut is its length plus 12), the
 * chunk's length and the checksums made right again. */
static unsigned char *cut_chunk(const unsigned char *b, size_t n, size_t off, uint64_t len, size_t cut, size_t *out_n)
{
    unsigned char *c = malloc(n);
    size_t end = off + 12 + (size_t)len;
    memcpy(c, b, end - cut);
    memcpy(c + end - cut, b + end, n - end);
    *out_n = n - cut;
    if (cut < len + 12) {
        uint64_t nl = len - cut;
        for (int k = 0; k < 8; k++) c[off + 4 + k] = (unsigned char)(nl >> (8 * k));
    }
    tl_session_fix_crc(c, *out_n);
    return c;
}

/* Session bytes of `base` (no hdlv) with an hdlv chunk of hd_from and the
 * image appended: what a writer would make of any image. */
static unsigned char *splice_hd(const unsigned char *base, size_t n, uint32_t from, const void *img, size_t ni, size_t *out_n)
{
    size_t m = n + 12 + 4 + ni;
    unsigned char *c = malloc(m);
    memcpy(c, base, n - 4);
    unsigned char *q = c + n - 4;
    memcpy(q, "hdlv", 4);
    uint64_t len = 4 + ni;
    for (int k = 0; k < 8; k++) q[4 + k] = (unsigned char)(len >> (8 * k));
    for (int k = 0; k < 4; k++) q[12 + k] = (unsigned char)(from >> (8 * k));
    memcpy(q + 16, img, ni);
    tl_session_fix_crc(c, m);
    *out_n = m;
    return c;
}

/* Refused, naming the chunk (and `what` when given), *out untouched. */
static void check_refused(const char *label, const unsigned char *b, size_t n, const char *what)
{
    st_session out;
    memset(&out, 0x5a, sizeof out);
    unsigned char sentinel[sizeof out];
    memset(sentinel, 0x5a, sizeof sentinel);
    st_error err = { 0 };
    int rc = st_session_parse("x.strata", b, n, &out, &err);
    CHECKF(rc != ST_OK, "%s: accepted", label);
    if (rc == ST_OK) { st_session_free(&out); return; }
    CHECKF(strstr(err.msg, "x.strata: chunk 'hdlv'") != NULL, "%s: message '%s' does not name the chunk", label, err.msg);
    CHECKF(!what || strstr(err.msg, what), "%s: message '%s' lacks '%s'", label, err.msg, what);
    CHECKF(!memcmp(&out, sentinel, sizeof out), "%s: output touched", label);
    printf("%s: %s\n", label, err.msg);
}

static void check_round_trip(const char *label, hd_doc *d)
{
    st_session_ref r = ref_of(d, 1), r0 = ref_of(d, 0);
    size_t n = 0, n0 = 0, n2 = 0;
    unsigned char *b = tl_session_bytes(&r, &n), *b0 = tl_session_bytes(&r0, &n0);
    if (!b || !b0) { free(b); free(b0); return; }
    printf("%s: %zu bytes, %zu without HD\n", label, n, n0);
    st_session s;
    st_error err;
    int rc = st_session_parse(label, b, n, &s, &err);
    CHECKF(rc == ST_OK, "%s: %s", label, err.msg);
    if (!rc) {
        CHECKF(s.has_hd && s.hd_from == d->h.map.top, "%s: has_hd %d from %u", label, s.has_hd, s.hd_from);
        CHECKF(s.hd_adapt.h == &s.hd, "%s: the HD adaptive state is not the HD hierarchy's", label);
        CHECKF(hier_same(&s.hd, &d->copy.h), "%s: HD hierarchy differs after loading", label);
        CHECKF(hier_same(&s.h, &d->h), "%s: model differs after loading", label);
        CHECKF(s.hd_adapt.nsaved == d->copy.adapt.nsaved && s.hd_adapt.base_faces.n == d->copy.adapt.base_faces.n,
               "%s: HD adaptive state differs", label);
        /* Moved, the HD hierarchy keeps its adaptive state. */
        st_session moved;
        st_session_init(&moved);
        st_session_move(&moved, &s);
        CHECK(moved.has_hd && moved.hd_adapt.h == &moved.hd && !s.has_hd);
        st_session_ref r2 = st_session_ref_of(&moved);
        CHECK(r2.hd == &moved.hd && r2.hd_adapt == &moved.hd_adapt && r2.hd_from == moved.hd_from);
        unsigned char *b2 = tl_session_bytes(&r2, &n2);
        CHECKF(b2 && n2 == n && !memcmp(b, b2, n), "%s: save -> load -> save changed the bytes", label);
        free(b2);
        /* The adaptive hierarchy loaded works: one more update and its mesh. */
        st_mesh m;
        st_mesh_init(&m);
        CHECKF(st_adapt_mesh(&moved.hd_adapt, &m, &err) == ST_OK && m.nfaces > 0, "%s: adaptive mesh: %s", label, err.msg);
        st_mesh_free(&m);
        /* keep_above is not in the file: the load sets it to hd_from, so the
         * sculpted faces stay refined when the box goes off. */
        CHECKF(moved.hd_adapt.keep_above == moved.hd_from, "%s: keep_above %u after a load, hd_from %u", label,
               moved.hd_adapt.keep_above, moved.hd_from);
        st_adapt_params off = { .base_level = moved.hd_from, .max_level = moved.hd_from };
        CHECKF(st_adapt_update(&moved.hd_adapt, &off, &err) == ST_OK, "%s: box-off update: %s", label, err.msg);
        uint64_t faces[ST_MAX_LEVELS], bytes[ST_MAX_LEVELS], above = 0;
        st_adapt_hd_levels(&moved.hd.map, moved.hd_from, faces, bytes);
        for (unsigned l = moved.hd_from + 1; l < ST_MAX_LEVELS; l++) above += faces[l];
        printf("%s: %llu HD faces after the box went off\n", label, (unsigned long long)above);
        CHECKF(above > 0, "%s: the box going off after a load coarsened the sculpted HD faces", label);
        st_session_free(&moved);
        st_session_free(&s);
    }
    /* Without the chunk: the bytes of the session without HD. */
    uint64_t len = 0;
    size_t off = chunk_at(b, n, "hdlv", &len), nc = 0;
    CHECKF(off > 0 && off + 12 + len == n - 4, "%s: hdlv is not the last chunk", label);
    if (off) {
        unsigned char *c = cut_chunk(b, n, off, len, (size_t)len + 12, &nc);
        CHECKF(nc == n0 && !memcmp(c, b0, n0), "%s: deleting hdlv does not give the session without HD", label);
        free(c);
        /* A reader that does not know the tag skips it (any unknown
         * lower-case tag): the uniform model. */
        c = malloc(n);
        memcpy(c, b, n);
        c[off + 3] = 'z';
        tl_session_fix_crc(c, n);
        rc = st_session_parse(label, c, n, &s, &err);
        CHECKF(rc == ST_OK, "%s: skipped chunk: %s", label, err.msg);
        if (!rc) {
            CHECKF(!s.has_hd && hier_same(&s.h, &d->h), "%s: a reader skipping hdlv gets another model", label);
            st_session_free(&s);
        }
        free(c);
    }
    free(b);
    free(b0);
}

static void check_cube(void)
{
    hd_doc d;
    static const double lo[3] = { 0.6, 0.6, 0.6 }, hi[3] = { 1.2, 1.2, 1.2 };
    if (make_hd(&d, tl_mesh_cube, 2, 5, lo, hi)) return;
    check_round_trip("cube, model 2, HD 5", &d);
    free_hd(&d);
}

static void spot(st_mesh *m)
{
    st_error err;
    st_mesh_init(m);   /* st_mesh_load replaces what out holds */
    int rc = st_mesh_load(STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", m, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
}

static void check_spot(void)
{
    FILE *f = fopen(STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj", "rb");
    if (!f) { printf("note: spot_quadrangulated.obj not found: not checked\n"); return; }
    fclose(f);
    hd_doc d;
    static const double lo[3] = { 0.2, 0.2, 0.2 }, hi[3] = { 0.5, 0.6, 0.6 };
    if (make_hd(&d, spot, 2, 4, lo, hi)) return;
    check_round_trip("spot, model 2, HD 4", &d);
    free_hd(&d);
}

/* Damaged and foreign chunks, and the writer's refusals. */
static void check_damage(void)
{
    hd_doc d;
    static const double lo[3] = { 0.6, 0.6, 0.6 }, hi[3] = { 1.2, 1.2, 1.2 };
    if (make_hd(&d, tl_mesh_cube, 2, 4, lo, hi)) return;
    st_session_ref r = ref_of(&d, 1), r0 = ref_of(&d, 0);
    size_t n = 0, n0 = 0, nc = 0;
    unsigned char *b = tl_session_bytes(&r, &n), *b0 = tl_session_bytes(&r0, &n0);
    uint64_t len = 0;
    size_t off = b ? chunk_at(b, n, "hdlv", &len) : 0;
    CHECK(off > 0);
    if (!off || !b0) goto done;
    /* Truncated nested image. */
    unsigned char *c = cut_chunk(b, n, off, len, 100, &nc);
    check_refused("truncated image", c, nc, NULL);
    free(c);
    /* Only hd_from, no image. */
    c = cut_chunk(b, n, off, len, (size_t)len - 4, &nc);
    check_refused("empty image", c, nc, "too short");
    free(c);
    /* A flipped byte inside the image, the outer checksum made right: the
     * image's own checksum refuses it. */
    c = malloc(n);
    memcpy(c, b, n);
    c[off + 16 + (size_t)len / 2] ^= 0x10;
    tl_session_fix_crc(c, n);
    check_refused("flipped byte", c, n, "checksum");
    free(c);
    /* Foreign images spliced in as a writer would (it refuses to make them). */
    st_session_ref hr = { .h = &d.copy.h, .adapt = &d.copy.adapt, .whole_map = 1 };
    size_t ni = 0;
    unsigned char *img = tl_session_bytes(&hr, &ni);
    c = splice_hd(b0, n0, 1, img, ni, &nc);
    check_refused("wrong hd_from", c, nc, "the model's top is 2");
    free(c);
    /* The splice of the right values is the writer's file. */
    c = splice_hd(b0, n0, 2, img, ni, &nc);
    CHECKF(nc == n && !memcmp(c, b, n), "splice: not the writer's bytes");
    free(c);
    /* An image holding an hdlv chunk of its own (the whole file as image). */
    c = splice_hd(b0, n0, 2, b, n, &nc);
    check_refused("nested hdlv", c, nc, "an HD hierarchy inside an HD hierarchy");
    free(c);
    free(img);
    hr.adapt = NULL;
    img = tl_session_bytes(&hr, &ni);
    c = splice_hd(b0, n0, 2, img, ni, &nc);
    check_refused("no adaptive state", c, nc, "no adaptive state");
    free(c);
    free(img);
    /* A Loop hierarchy for a Catmull-Clark model. */
    st_hier lh;
    st_adapt la;
    st_error err;
    if (!build_model(&lh, tl_mesh_octa, ST_SCHEME_LOOP, 2)) {
        CHECK(st_adapt_init(&la, &lh, &err) == ST_OK);
        st_session_ref lr = { .h = &lh, .adapt = &la, .whole_map = 1 };
        img = tl_session_bytes(&lr, &ni);
        c = splice_hd(b0, n0, 2, img, ni, &nc);
        check_refused("wrong scheme", c, nc, "its scheme is loop, the model's catmull-clark");
        free(c);
        free(img);
        /* The writer refuses it too. */
        st_session_ref bad = r;
        bad.hd = &lh;
        bad.hd_adapt = &la;
        void *data = NULL;
        size_t nd = 0;
        CHECK(st_session_write_mem(&bad, &data, &nd, &err) != ST_OK && !data);
        st_adapt_free(&la);
        st_hier_free(&lh);
    }
    /* A model of other levels (the counts of level 1 differ). */
    st_hier other;
    if (!build_model(&other, tl_mesh_tetra, ST_SCHEME_CATMARK, 2)) {
        st_session_ref orf = { .h = &other, .display_level = 2 };
        size_t no = 0;
        unsigned char *bo = tl_session_bytes(&orf, &no);
        img = tl_session_bytes(&(st_session_ref){ .h = &d.copy.h, .adapt = &d.copy.adapt, .whole_map = 1 }, &ni);
        c = splice_hd(bo, no, 2, img, ni, &nc);
        check_refused("another model", c, nc, "level 0 has");
        free(c);
        free(img);
        free(bo);
        st_hier_free(&other);
    }
    /* The writer refuses an hd_from other than the model's top. */
    st_session_ref bad = r;
    bad.hd_from = 1;
    void *data = NULL;
    size_t nd = 0;
    CHECK(st_session_write_mem(&bad, &data, &nd, &err) != ST_OK && !data);
done:
    free(b);
    free(b0);
    free_hd(&d);
}

/* ---- ids freed by the box: the image holds live ids only ------------------ */

/* Details on the vertices of levels max-1 and max within `radius` of the
 * first vertex inserted at level max inside the box: a sculpted spot,
 * whose faces the box going away leaves refined (keep_above). */
static unsigned sculpt_spot(st_session *c, unsigned max_level, const double lo[3], const double hi[3], double radius)
{
    const st_map *m = &c->h.map;
    const double *ctr = NULL;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, max_level, &it); v != ST_NIL && !ctr; v = st_vertex_next(m, max_level, &it)) {
        const double *p = st_pos(m, v, max_level);
        int in = m->verts.ins[v] == max_level;
        for (int k = 0; k < 3; k++) in &= p[k] >= lo[k] && p[k] <= hi[k];
        if (in) ctr = p;
    }
    if (!ctr) return 0;
    double cc[3] = { ctr[0], ctr[1], ctr[2] };
    unsigned set = 0;
    for (unsigned l = max_level - 1; l <= max_level; l++)
        for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
            const double *p = st_pos(m, v, l);
            double dx = p[0] - cc[0], dy = p[1] - cc[1], dz = p[2] - cc[2];
            if (m->verts.ins[v] != l || dx * dx + dy * dy + dz * dz > radius * radius) continue;
            double dd[3] = { 0.001 * (v % 7), -0.002 * (l % 3 + 1), 0.0005 * (double)(set % 5) + 0.0001 };
            st_hier_set_detail(&c->h, l, v, dd);
            set++;
        }
    return set;
}

static int box_update(st_session *c, unsigned base, unsigned max_level, const double lo[3], const double hi[3])
{
    st_adapt_params p = { .base_level = base, .max_level = lo ? max_level : base, .has_box = lo != NULL };
    if (lo) {
        memcpy(p.box_lo, lo, sizeof p.box_lo);
        memcpy(p.box_hi, hi, sizeof p.box_hi);
    }
    st_error err;
    int rc = st_adapt_update(&c->adapt, &p, &err);
    CHECKF(rc == ST_OK, "box update: %s", err.msg);
    return rc;
}

/* The cube's model to level 2; HD to level 5 in a box at one corner, a spot
 * sculpted there; the box moved to the opposite corner, a spot sculpted
 * there; the box off.  Both spots stay refined (keep_above), the rest of
 * both boxes coarsens: the pools keep the ids it freed. */
static int make_hd_coarsened(hd_doc *d)
{
    static const double alo[3] = { 0.6, 0.6, 0.6 }, ahi[3] = { 1.2, 1.2, 1.2 };
    static const double blo[3] = { -0.2, -0.2, -0.2 }, bhi[3] = { 0.4, 0.4, 0.4 };
    if (make_hd(d, tl_mesh_cube, 2, 5, alo, ahi)) return -1;
    st_session *c = &d->copy;
    c->adapt.keep_above = 2;
    unsigned set = sculpt_spot(c, 5, alo, ahi, 0.1);
    st_adapt_synthesize(&c->adapt, 2);
    if (box_update(c, 2, 5, blo, bhi)) goto fail;
    set += sculpt_spot(c, 5, blo, bhi, 0.1);
    st_adapt_synthesize(&c->adapt, 2);
    if (box_update(c, 2, 5, NULL, NULL)) goto fail;
    CHECKF(set > 10 && c->h.map.top == 5, "%u details set, HD top %u", set, c->h.map.top);
    return 0;
fail:
    free_hd(d);
    return -1;
}

/* Ids of p handed out but not live, at levels above `from`. */
static uint64_t dead_ids(const st_pool *p, unsigned from)
{
    uint64_t n = 0;
    for (unsigned l = from + 1; l < ST_MAX_LEVELS; l++) n += (uint64_t)p->nblocks[l] * ST_POOL_BLOCK - p->live[l];
    return n + (uint64_t)p->nspare * ST_POOL_BLOCK;
}

/* Every level above `from` of p packed: one partly used block at most,
 * no free list, no spare block, and the end right after the blocks. */
static int pool_packed(const st_pool *p, unsigned from)
{
    uint64_t blocks = p->nspare;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        blocks += p->nblocks[l];
        if (l <= from) continue;
        if (p->nblocks[l] != (p->live[l] + ST_POOL_BLOCK - 1) / ST_POOL_BLOCK || p->freehead[l] != ST_NIL) return 0;
    }
    return p->nspare == 0 && (uint64_t)p->end == blocks * ST_POOL_BLOCK;
}

/* The loaded map b is a under the renumbering rn: same insertion levels
 * and flags, the relations of every level translated, the positions and
 * details of every level bit for bit; within a level the new ids keep the
 * old ids' order.  0 when all hold. */
static int same_under(const st_hier *ha, const st_hier *hb, const st_map_renumber *rn)
{
    const st_map *a = &ha->map, *b = &hb->map;
    const uint32_t *dn = rn->darts.new_of, *vn = rn->verts.new_of;
    uint32_t last[ST_MAX_LEVELS];
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) last[l] = ST_NIL;
    for (uint32_t d = 0; d < a->darts.end; d++) {
        unsigned i = a->darts.ins[d];
        if (i == ST_FREE_LEVEL) continue;
        uint32_t e = dn[d];
        if (e >= b->darts.end || b->darts.ins[e] != i || b->flags[e] != a->flags[d]) return 1;
        if (last[i] != ST_NIL && e <= last[i]) return 2;
        last[i] = e;
        for (unsigned l = i; l <= a->top; l++)
            if (dn[st_beta0(a, d, l)] != st_beta0(b, e, l) || dn[st_beta1(a, d, l)] != st_beta1(b, e, l) ||
                vn[st_vert(a, d, l)] != st_vert(b, e, l))
                return 3;
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) last[l] = ST_NIL;
    for (uint32_t v = 0; v < a->verts.end; v++) {
        unsigned i = a->verts.ins[v];
        if (i == ST_FREE_LEVEL) continue;
        uint32_t w = vn[v];
        if (w >= b->verts.end || b->verts.ins[w] != i) return 4;
        if (last[i] != ST_NIL && w <= last[i]) return 5;
        last[i] = w;
        for (unsigned l = i; l <= a->top; l++) {
            if (memcmp(st_pos(a, v, l), st_pos(b, w, l), 3 * sizeof(double))) return 6;
            if (memcmp(detail_at(ha, l, v), detail_at(hb, l, w), 3 * sizeof(double))) return 7;
        }
    }
    return 0;
}

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* The displayed surface, whatever the ids: the vertex positions' bits and
 * each face's corners (an order-free hash of their bits), both sorted. */
static uint64_t *surface_keys(st_adapt *a, uint32_t *n)
{
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    if (st_adapt_mesh(a, &m, &err)) { CHECKF(0, "adaptive mesh: %s", err.msg); return NULL; }
    *n = m.nverts + m.nfaces;
    uint64_t *k = malloc(((size_t)*n + 1) * sizeof *k);
    uint64_t *vh = malloc(((size_t)m.nverts + 1) * sizeof *vh);
    for (uint32_t v = 0; v < m.nverts; v++) {
        uint64_t h = 1469598103934665603ull;
        const unsigned char *b = (const unsigned char *)(m.pos + 3 * (size_t)v);
        for (size_t i = 0; i < 3 * sizeof(double); i++) h = (h ^ b[i]) * 1099511628211ull;
        k[v] = vh[v] = h;
    }
    for (uint32_t f = 0; f < m.nfaces; f++) {
        uint64_t h = m.face_off[f + 1] - m.face_off[f];
        for (uint32_t c = m.face_off[f]; c < m.face_off[f + 1]; c++) h += vh[m.face_idx[c]] * 0x9e3779b97f4a7c15ull;
        k[m.nverts + f] = h;
    }
    qsort(k, m.nverts, sizeof *k, cmp_u64);
    qsort(k + m.nverts, m.nfaces, sizeof *k, cmp_u64);
    free(vh);
    st_mesh_free(&m);
    return k;
}

static void check_coarsened(void)
{
    hd_doc d;
    if (make_hd_coarsened(&d)) return;
    const char *label = "cube, HD regions coarsened";
    const st_map *om = &d.copy.h.map;
    uint64_t dead = dead_ids(&om->darts, 2) + dead_ids(&om->verts, 2);
    printf("%s: %u darts and %u vertex ids handed out, %llu of the HD levels' not live\n", label, om->darts.end,
           om->verts.end, (unsigned long long)dead);
    CHECKF(dead > 0, "%s: the box going off freed no id (the test needs some)", label);
    st_session_ref r = ref_of(&d, 1);
    size_t n = 0, n2 = 0;
    unsigned char *b = tl_session_bytes(&r, &n);
    st_session s;
    st_error err;
    int rc = b ? st_session_parse(label, b, n, &s, &err) : -1;
    CHECKF(rc == ST_OK, "%s: %s", label, b ? err.msg : "not written");
    if (rc) goto done;
    const st_map *lm = &s.hd.map;
    /* (a) No dead slot: the HD levels packed, and the hdlv image is what
     * the loaded hierarchy (no freed id) gives written as it is, smaller
     * than the image of the original's pools by the freed ids. */
    CHECKF(pool_packed(&lm->darts, 2) && pool_packed(&lm->verts, 2), "%s: the loaded pools are not packed", label);
    CHECKF(lm->darts.end < om->darts.end && lm->verts.end < om->verts.end, "%s: ends %u/%u, were %u/%u", label,
           lm->darts.end, lm->verts.end, om->darts.end, om->verts.end);
    uint64_t len = 0;
    size_t off = chunk_at(b, n, "hdlv", &len), ni = 0, no = 0;
    st_session_ref lr = { .h = &s.hd, .adapt = &s.hd_adapt, .whole_map = 1 };
    st_session_ref orr = { .h = &d.copy.h, .adapt = &d.copy.adapt, .whole_map = 1 };
    unsigned char *img = tl_session_bytes(&lr, &ni), *oimg = tl_session_bytes(&orr, &no);
    CHECKF(off && img && len == 4 + ni && !memcmp(b + off + 16, img, ni),
           "%s: the hdlv image is not the loaded hierarchy's own image", label);
    printf("%s: hdlv image %zu bytes; the original's pools as they are: %zu bytes\n", label, ni, no);
    CHECKF(ni < no, "%s: the image is not smaller than with the freed ids", label);
    free(img);
    free(oimg);
    /* (b) The loaded hierarchy is the original under the renumbering, bit
     * for bit, and its displayed surface the same whatever the ids. */
    st_map_renumber rn;
    CHECK(st_map_renumber_make(om, 2, &rn) == 0);
    int why = same_under(&d.copy.h, &s.hd, &rn);
    CHECKF(why == 0, "%s: the loaded HD hierarchy is not the original renumbered (check %d)", label, why);
    CHECKF(!st_map_renumber_is_identity(&rn), "%s: the renumbering changed no id", label);
    st_map_renumber_free(&rn);
    CHECK(st_map_renumber_make(lm, 2, &rn) == 0);
    CHECKF(st_map_renumber_is_identity(&rn), "%s: the loaded map is renumbered again", label);
    st_map_renumber_free(&rn);
    CHECKF(hier_same(&s.h, &d.h), "%s: model differs after loading", label);
    uint32_t ka = 0, kb = 0;
    uint64_t *sa = surface_keys(&d.copy.adapt, &ka), *sb = surface_keys(&s.hd_adapt, &kb);
    CHECKF(sa && sb && ka == kb && !memcmp(sa, sb, (size_t)ka * sizeof *sa), "%s: the displayed surface differs", label);
    free(sa);
    free(sb);
    /* (c) save -> load -> save: the same bytes. */
    st_session_ref r2 = st_session_ref_of(&s);
    unsigned char *b2 = tl_session_bytes(&r2, &n2);
    CHECKF(b2 && n2 == n && !memcmp(b, b2, n), "%s: save -> load -> save changed the bytes", label);
    free(b2);
    st_session_free(&s);
done:
    free(b);
    free_hd(&d);
}

/* Writes a cube session with HD for other tests (see the header). */
/* A sculpt layer at HD level l of d's HD hierarchy: an offset on every
 * vertex of that level with a non-zero detail there (the values need not
 * be a composition: the file's checks do not recompute one). */
static uint32_t add_hd_layer(hd_doc *d, st_layers *hl, unsigned l)
{
    st_error err;
    st_layers_init(hl);
    CHECKF(st_layers_add(hl, &d->copy.h, l, "hd layer", &err) == 0, "%s", err.msg);
    hl->v[0].strength = 0.5;
    uint32_t n = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&d->copy.h.map, l, &it); v != ST_NIL; v = st_vertex_next(&d->copy.h.map, l, &it)) {
        const double *det = detail_at(&d->copy.h, l, v);
        if (det[0] == 0 && det[1] == 0 && det[2] == 0) continue;
        const double o[3] = { 0.25 * det[0], -det[1], 0.001 * (double)(v % 11) };
        st_layers_set(hl, 0, l, v, o);
        n++;
    }
    return n;
}

/* HD sculpt layers travel in the hdlv image (session_write.c), their
 * vertex arrays under the image's renumbering: after the box freed ids,
 * every offset is found at the renumbered id, the layer's name, level and
 * strength are kept, and a second save gives the same bytes. */
static void check_layers(void)
{
    hd_doc d;
    if (make_hd_coarsened(&d)) return;
    st_layers hl;
    uint32_t set = add_hd_layer(&d, &hl, 5);
    CHECKF(set > 10, "%u offsets", set);
    st_session_ref r = ref_of(&d, 1);
    r.hd_layers = &hl;
    void *b1 = NULL, *b2 = NULL;
    size_t n1 = 0, n2 = 0;
    st_error err;
    CHECKF(st_session_write_mem(&r, &b1, &n1, &err) == ST_OK, "%s", err.msg);
    st_session s;
    CHECKF(st_session_parse("layers.strata", b1, n1, &s, &err) == ST_OK, "%s", err.msg);
    CHECK(s.has_hd && s.layers.n == 0 && s.hd_layers.n == 1);
    if (s.hd_layers.n == 1) {
        const st_layer *y = &s.hd_layers.v[0];
        CHECK(y->level == 5 && y->strength == 0.5 && !strcmp(y->name, "hd layer") && s.hd_layers.active == 0);
        st_map_renumber rn;
        CHECK(st_map_renumber_make(&d.copy.h.map, 2, &rn) == 0);
        CHECK(!st_map_renumber_is_identity(&rn)); /* the box freed ids */
        uint32_t same = 0, nz = 0;
        for (uint32_t j = 0; j < rn.verts.pool.end; j++) {
            uint32_t o = rn.verts.old_of[j];
            double a[3], b[3];
            st_layers_get(&s.hd_layers, 0, 5, j, a);
            if (o == ST_NIL) { nz += a[0] != 0 || a[1] != 0 || a[2] != 0; continue; }
            st_layers_get(&hl, 0, 5, o, b);
            same += !memcmp(a, b, sizeof a);
            st_layers_get(&s.hd_layers, ST_LAYERS_SLOT_BASE, 5, j, a);
            st_layers_get(&hl, ST_LAYERS_SLOT_BASE, 5, o, b);
            same += !memcmp(a, b, sizeof a);
        }
        CHECKF(!nz, "%u offsets on free ids", nz);
        uint32_t live = 0;
        for (uint32_t j = 0; j < rn.verts.pool.end; j++) live += rn.verts.old_of[j] != ST_NIL;
        CHECKF(same == 2 * live, "%u of %u values at their renumbered ids", same, 2 * live);
        st_map_renumber_free(&rn);
    }
    st_session_ref r2 = st_session_ref_of(&s);
    CHECKF(st_session_write_mem(&r2, &b2, &n2, &err) == ST_OK, "%s", err.msg);
    CHECK(n1 == n2 && b1 && b2 && !memcmp(b1, b2, n1));
    st_session_free(&s);
    free(b1);
    free(b2);
    st_layers_free(&hl);
    free_hd(&d);
}

static int write_file(const char *path, unsigned levels, unsigned max_level, const double lo[3], const double hi[3],
                      int layer)
{
    hd_doc d;
    if (make_hd(&d, tl_mesh_cube, levels, max_level, lo, hi)) return 1;
    st_session_ref r = ref_of(&d, 1);
    st_layers hl;
    st_layers_init(&hl);
    if (layer) {
        add_hd_layer(&d, &hl, max_level);
        r.hd_layers = &hl;
    }
    st_error err;
    int rc = st_session_save_ref(path, &r, &err);
    if (rc) fprintf(stderr, "%s\n", err.msg);
    st_layers_free(&hl);
    free_hd(&d);
    return rc ? 1 : 0;
}

int main(int argc, char **argv)
{
    /* A corner of the cube; for the seed, the middle of one face (fewer
     * faces refined: a smaller file). */
    static const double lo[3] = { 0.6, 0.6, 0.6 }, hi[3] = { 1.2, 1.2, 1.2 };
    static const double slo[3] = { 0.4, 0.4, 0.6 }, shi[3] = { 0.6, 0.6, 1.1 };
    if (argc == 3 && !strcmp(argv[1], "--write")) return write_file(argv[2], 2, 4, lo, hi, 0);
    if (argc == 3 && !strcmp(argv[1], "--seed")) return write_file(argv[2], 1, 3, slo, shi, 0);
    if (argc == 3 && !strcmp(argv[1], "--write-layer")) return write_file(argv[2], 2, 4, lo, hi, 1);
    if (argc == 3 && !strcmp(argv[1], "--seed-layer")) return write_file(argv[2], 1, 3, slo, shi, 1);
    check_cube();
    check_spot();
    check_coarsened();
    check_damage();
    check_layers();
    return TEST_END();
}
