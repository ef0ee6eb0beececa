/* The recipe of a progressive hierarchy (core/progressive/progressive.h,
 * st_progressive_recipe / st_progressive_regenerate; the session's PMRC
 * chunk): replaying level 0 and the splits gives the build's map, ids,
 * pools, relations of every level and their sparse form included; the
 * compact session loads as the saved hierarchy written whole, byte for
 * byte, and keeps later edits bit-equal; a damaged recipe is refused with
 * the level and split named, never half-built.
 *
 * test_progressive_recipe --seed PATH writes the fuzz corpus's seed (a
 * small progressive session with a hole, in the PMRC form). */
#include "testlib.h"

#include "core/progressive/progressive_internal.h"
#include "core/multires/hier_internal.h"
#include "core/io/session.h"
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

static int load_shared(const char *name, st_mesh *m) { return tl_load_shared("triangle", name, m); }

static int build(const st_mesh *m, st_hier *h, uint64_t target, const char *what)
{
    st_error err;
    st_progressive_opts o = { .target_faces = target, .predictor = ST_PM_DEFAULT };
    int rc = st_progressive_build(m, &o, h, NULL, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
    return rc;
}

/* An empty hierarchy of the progressive scheme to regenerate into. */
static void empty_like(const st_hier *src, st_hier *h)
{
    memset(h, 0, sizeof *h);
    st_map_init(&h->map);
    st_mla_init(&h->edge_sharp, sizeof(float));
    st_mla_init(&h->vertex_sharp, sizeof(float));
    h->scheme = src->scheme;
    h->opts = src->opts;
}

static int same_pool(const st_pool *a, const st_pool *b)
{
    if (a->end != b->end || memcmp(a->ins, b->ins, a->end)) return 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (a->nblocks[l] != b->nblocks[l] || a->fill[l] != b->fill[l] || a->live[l] != b->live[l] ||
            a->freehead[l] != b->freehead[l])
            return 0;
        if (a->nblocks[l] && memcmp(a->blocks[l], b->blocks[l], a->nblocks[l] * sizeof *a->blocks[l])) return 0;
    }
    return 1;
}

/* The same sparse or dense form, the same column marks and capacities. */
static int same_form(const st_mla *a, const st_mla *b)
{
    if ((a->sp == NULL) != (b->sp == NULL) || a->maxcol != b->maxcol || memcmp(a->eff, b->eff, sizeof a->eff)) return 0;
    if (!a->sp) {
        for (unsigned l = 0; l < ST_MAX_LEVELS; l++) if ((a->col[l] == NULL) != (b->col[l] == NULL)) return 0;
        return 1;
    }
    const st_mla_sparse *x = a->sp, *y = b->sp;
    return x->n == y->n && x->npairs == y->npairs && !memcmp(x->has_col, y->has_col, sizeof x->has_col) &&
           !memcmp(x->colcap, y->colcap, sizeof x->colcap) && !memcmp(x->pairs_at, y->pairs_at, sizeof x->pairs_at) &&
           !memcmp(x->lvl, y->lvl, x->npairs) && !memcmp(x->val, y->val, (size_t)x->npairs * a->elem) &&
           !memcmp(x->boff, y->boff, ((size_t)x->n + 1) * sizeof *x->boff);
}

/* Every level's relations of every dart, the pools and the flags. */
static int same_topology(const st_map *a, const st_map *b)
{
    if (a->top != b->top || !same_pool(&a->darts, &b->darts) || !same_pool(&a->verts, &b->verts)) return 0;
    for (uint32_t d = 0; d < a->darts.end; d++)   /* flags of live darts (free ids hold whatever) */
        if (a->darts.ins[d] != ST_FREE_LEVEL && a->flags[d] != b->flags[d]) return 0;
    if (!same_form(&a->beta0, &b->beta0) || !same_form(&a->beta1, &b->beta1) || !same_form(&a->vert, &b->vert)) return 0;
    for (unsigned l = 0; l <= a->top; l++) {
        st_dart_iter it;
        for (uint32_t d = st_dart_first(a, l, &it); d != ST_NIL; d = st_dart_next(a, l, &it))
            if (st_beta0(a, d, l) != st_beta0(b, d, l) || st_beta1(a, d, l) != st_beta1(b, d, l) ||
                st_vert(a, d, l) != st_vert(b, d, l))
                return 0;
    }
    return 1;
}

static int has_chunk(const unsigned char *b, size_t n, const char *tag)
{
    for (size_t off = 28; off + 12 <= n - 4;) {
        if (!memcmp(b + off, tag, 4)) return 1;
        uint64_t len = 0;
        for (int k = 0; k < 8; k++) len |= (uint64_t)b[off + 4 + k] << (8 * k);
        off += 12 + (size_t)len;
    }
    return 0;
}

static void check_counts(const char *what, st_hier *h);

/* Recipe -> regenerated map == the build's; the session round trip. */
static void check_replay(const char *what, st_hier *h)
{
    st_pm_recipe rc;
    CHECKF(st_progressive_recipe(h, &rc) == 0, "%s: no recipe", what);
    if (!rc.split) return;
    /* The bytes the build kept are the recipe read back from its map. */
    size_t nb = st_pm_recipe_encode(&rc, NULL);
    unsigned char *enc = malloc(nb);
    if (enc) st_pm_recipe_encode(&rc, enc);
    CHECKF(enc && h->pm_recipe && h->pm_recipe_len == nb && !memcmp(enc, h->pm_recipe, nb),
           "%s: the build's recipe bytes are not its map's recipe", what);
    free(enc);
    CHECK(rc.top == h->map.top && rc.ndarts0 == h->map.darts.live[0] && rc.nverts0 == h->map.verts.live[0]);
    CHECK(st_pm_recipe_splits(&rc) == st_pool_count(&h->map.verts, h->map.top) - rc.nverts0);
    st_hier g;
    empty_like(h, &g);
    st_error err;
    int r = st_progressive_regenerate(&g, &rc, &err);
    CHECKF(r == ST_OK, "%s: %s", what, err.msg);
    if (!r) {
        CHECKF(same_topology(&h->map, &g.map), "%s: the regenerated map differs from the build's", what);
        CHECK(st_hier_regenerable(&g));
    }
    st_hier_free(&g);
    st_pm_recipe_free(&rc);

    /* The session: PMRC, smaller than whole, loads as the hierarchy
     * written whole, byte for byte, saves the same bytes again. */
    st_session_ref sr = { .h = h, .display_level = h->map.top };
    size_t n1, nw1, nw2, n2;
    unsigned char *b1 = tl_session_bytes(&sr, &n1);
    CHECKF(b1 && has_chunk(b1, n1, "PMRC") && !has_chunk(b1, n1, "MAP "), "%s: not saved as a recipe", what);
    CHECK(b1 && b1[8] == ST_SESSION_VERSION);
    st_session s;
    if (!b1 || st_session_parse("recipe.strata", b1, n1, &s, &err)) {
        CHECKF(0, "%s: %s", what, err.msg);
        free(b1);
        return;
    }
    CHECKF(s.h.pm_recipe && s.h.pm_recipe_len == h->pm_recipe_len && !memcmp(s.h.pm_recipe, h->pm_recipe, h->pm_recipe_len),
           "%s: the loaded hierarchy does not keep the file's recipe", what);
    check_counts(what, &s.h);
    st_session_ref w1 = sr, w2 = st_session_ref_of(&s);
    w1.whole_map = w2.whole_map = 1;
    unsigned char *a = tl_session_bytes(&w1, &nw1), *b = tl_session_bytes(&w2, &nw2);
    CHECKF(a && b && nw1 == nw2 && !memcmp(a, b, nw1), "%s: the loaded hierarchy differs from the saved one", what);
    CHECKF(n1 < nw1, "%s: recipe %zu bytes, whole %zu", what, n1, nw1);
    printf("%s: %u levels, recipe session %zu bytes, whole %zu bytes (%.2fx)\n", what, h->map.top + 1, n1, nw1,
           (double)n1 / (double)nw1);
    w2.whole_map = 0;
    unsigned char *c = tl_session_bytes(&w2, &n2);
    CHECKF(c && n2 == n1 && !memcmp(b1, c, n1), "%s: load -> save gives other bytes", what);
    free(a);
    free(b);
    free(c);
    free(b1);
    st_session_free(&s);
}

/* An edit keeps the recipe (positions and details are stored apart); a
 * change of topology drops it: the session is then written whole. */
static void check_lapse(const char *what, st_hier *h)
{
    uint32_t d = 0;
    const double *p = st_dart_pos(&h->map, d, 0);
    double q[1][3] = { { p[0] + 0.02, p[1] - 0.01, p[2] } };
    st_hier_move(h, 0, &d, q, 1);
    st_pm_recipe rc;
    CHECKF(st_progressive_recipe(h, &rc) == 0, "%s: an edit dropped the recipe", what);
    st_pm_recipe_free(&rc);
    st_session_ref sr = { .h = h, .display_level = h->map.top };
    st_session s;
    if (tl_session_roundtrip(&sr, what, &s) == 0) {
        tl_posnap x, y;
        tl_snap_pos(h, &x);
        tl_snap_pos(&s.h, &y);
        CHECKF(x.n == y.n && tl_snap_maxdiff(&x, &y) == 0, "%s: positions after an edit differ once loaded", what);
        /* the same later edit, the same bits */
        double q2[1][3] = { { p[0] - 0.03, p[1], p[2] + 0.01 } };
        st_hier_move(h, 0, &d, q2, 1);
        st_hier_move(&s.h, 0, &d, q2, 1);
        free(x.p);
        free(y.p);
        tl_snap_pos(h, &x);
        tl_snap_pos(&s.h, &y);
        CHECKF(x.n == y.n && tl_snap_maxdiff(&x, &y) == 0, "%s: an edit after loading differs", what);
        free(x.p);
        free(y.p);
        st_session_free(&s);
    }
    st_hier_remove_top(h);
    CHECKF(st_progressive_recipe(h, &rc) != 0, "%s: a recipe after the top level went", what);
    st_level_stats one;
    CHECKF(st_progressive_level_counts(h, &one) != 0, "%s: counts from the pools after the top level went", what);
    size_t n;
    unsigned char *b = tl_session_bytes(&sr, &n);
    CHECKF(b && has_chunk(b, n, "MAP ") && !has_chunk(b, n, "PMRC"), "%s: a changed topology saved as a recipe", what);
    free(b);
}

/* ---- damaged recipes --------------------------------------------------------------- */

static int copy_recipe(const st_pm_recipe *a, st_pm_recipe *b)
{
    *b = *a;
    size_t nd = a->ndarts0, ns = st_pm_recipe_splits(a);
    b->beta0 = malloc(nd * 4);
    b->beta1 = malloc(nd * 4);
    b->vert = malloc(nd * 4);
    b->boundary = malloc(nd);
    b->split = malloc((ns ? ns : 1) * sizeof *b->split);
    if (!b->beta0 || !b->beta1 || !b->vert || !b->boundary || !b->split) return -1;
    memcpy(b->beta0, a->beta0, nd * 4);
    memcpy(b->beta1, a->beta1, nd * 4);
    memcpy(b->vert, a->vert, nd * 4);
    memcpy(b->boundary, a->boundary, nd);
    memcpy(b->split, a->split, ns * sizeof *b->split);
    return 0;
}

/* Regenerating from `bad` fails with a message holding `words` (NULL: any
 * refusal or success is allowed, but the map is then valid), the map left
 * empty on failure. */
static void expect(const st_hier *like, const st_pm_recipe *bad, const char *words, const char *what)
{
    st_hier g;
    empty_like(like, &g);
    st_error err = { 0 };
    int r = st_progressive_regenerate(&g, bad, &err);
    if (words) {
        CHECKF(r != ST_OK && strstr(err.msg, words), "%s: %s (wanted '%s')", what, r ? err.msg : "accepted", words);
    } else if (r == ST_OK) {
        st_error e2;
        CHECKF(st_map_validate(&g.map, &e2) == ST_OK, "%s: accepted an invalid map: %s", what, e2.msg);
    }
    if (r != ST_OK) CHECKF(g.map.darts.end == 0 && g.map.verts.end == 0, "%s: a refused recipe left a map", what);
    st_hier_free(&g);
}

static uint64_t next_rand(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

static void check_damage(const char *what, const st_hier *h)
{
    st_pm_recipe rc, bad;
    if (st_progressive_recipe(h, &rc)) return;
    uint64_t l1 = rc.nsplits[1];
#define MUTATE(stmt, words, label)                         \
    do {                                                   \
        if (copy_recipe(&rc, &bad) == 0) {                 \
            stmt;                                          \
            expect(h, &bad, words, label);                 \
        }                                                  \
        st_pm_recipe_free(&bad);                           \
    } while (0)
    MUTATE(bad.beta0[0] = bad.ndarts0, "out of range", "β0 out of range");
    MUTATE(bad.beta0[0] = 0, "involution", "β0 fixed point");
    MUTATE(bad.vert[0] = (bad.vert[0] + 1) % bad.nverts0, "level 0", "a dart on another vertex");
    MUTATE(bad.boundary[0] ^= 1, "level 0", "a hole flag flipped");
    MUTATE(bad.split[0].b = bad.nverts0 + 5, "does not exist", "b out of range");
    MUTATE(bad.split[0].c = 1000, "past b's fan", "c past the fan");
    MUTATE(bad.split[0].d = bad.split[0].c, "one neighbour", "c = d");
    if (l1 > 1) MUTATE(bad.split[1].b = bad.split[0].b, "split twice", "b split twice in a level");
    MUTATE(bad.nsplits[1] = 0; bad.split += 0, "no split", "an empty level");
    /* A boundary split of a vertex away from the holes. */
    for (uint64_t i = 0; i < l1; i++)
        if (rc.split[i].d != ST_NIL) {
            MUTATE(bad.split[i].d = ST_NIL, NULL, "d dropped");
            break;
        }
    /* Random damage: refused or a valid map, never a crash (the sanitizer
     * build runs this too). */
    uint64_t seed = 0x9e3779b97f4a7c15ull, ns = st_pm_recipe_splits(&rc);
    for (int k = 0; k < 300; k++) {
        if (copy_recipe(&rc, &bad) == 0) {
            uint64_t i = next_rand(&seed) % ns, f = next_rand(&seed) % 3, v = next_rand(&seed) % 12;
            st_pm_split *s = &bad.split[i];
            if (f == 0) s->b = (uint32_t)(next_rand(&seed) % (bad.nverts0 + ns));
            else if (f == 1) s->c = (uint32_t)v;
            else s->d = v == 11 ? ST_NIL : (uint32_t)v;
            expect(h, &bad, NULL, "random damage");
        }
        st_pm_recipe_free(&bad);
    }
#undef MUTATE
    printf("%s: damaged recipes refused\n", what);
    st_pm_recipe_free(&rc);
}

/* Offset of chunk `tag`'s payload in a session's bytes, 0 if none. */
static size_t chunk_at(const unsigned char *b, size_t n, const char *tag, uint64_t *len)
{
    for (size_t off = 28; off + 12 <= n - 4;) {
        uint64_t l = 0;
        for (int k = 0; k < 8; k++) l |= (uint64_t)b[off + 4 + k] << (8 * k);
        if (!memcmp(b + off, tag, 4)) { *len = l; return off + 12; }
        off += 12 + (size_t)l;
    }
    return 0;
}

/* Bytes of the PMRC chunk changed (checksums made valid again): the file
 * is refused with its name in the message, or loads as a valid map. */
static void check_damaged_file(const char *what, st_hier *h)
{
    st_session_ref sr = { .h = h, .display_level = h->map.top };
    size_t n;
    unsigned char *b = tl_session_bytes(&sr, &n);
    uint64_t len = 0;
    size_t at = b ? chunk_at(b, n, "PMRC", &len) : 0;
    CHECKF(at && len > 16, "%s: no PMRC chunk", what);
    if (!at) { free(b); return; }
    unsigned char *c = malloc(n);
    int refused = 0, loaded = 0;
    uint64_t seed = 12345;
    for (int k = 0; k < 400 && c; k++) {
        memcpy(c, b, n);
        size_t off = at + (k < 12 ? (size_t)k : (size_t)(next_rand(&seed) % len));
        c[off] ^= (unsigned char)(1u << (next_rand(&seed) % 8));
        tl_session_fix_crc(c, n);
        st_session s;
        st_error err;
        if (st_session_parse("bad.strata", c, n, &s, &err) == ST_OK) {
            st_error e2;
            CHECKF(st_map_validate(&s.h.map, &e2) == ST_OK, "%s: a damaged recipe loaded an invalid map: %s", what, e2.msg);
            st_hier_synthesize(&s.h, 0);   /* works on what was accepted (the sanitizer build watches) */
            loaded++;
            st_session_free(&s);
        } else {
            CHECKF(strstr(err.msg, "bad.strata") != NULL, "%s: message without the file: %s", what, err.msg);
            refused++;
        }
    }
    printf("%s: 400 damaged PMRC chunks: %d refused, %d loaded as valid maps\n", what, refused, loaded);
    CHECK(refused > 0);
    free(c);
    free(b);
}

/* ---- the build against a reference ---------------------------------------------
 * The map as the build made it before it went through the replay
 * (progressive.c before version 5 of the session format): level 0 from
 * the coarsest working copy, then per group the collapses undone on the
 * working copy (pm_undo) and the darts of the restored triangles inserted,
 * every relation around a, b, c, d set through the map's setters, then
 * st_map_compact.  The build must give the same map, ids, pools, sparse
 * form and positions included. */
typedef struct ref { pm_work *w; st_map *m; uint32_t *dart_of, *vid_of; } ref;

static void ref_relations(ref *c, uint32_t e, unsigned l)
{
    pm_work *w = c->w;
    st_map *m = c->m;
    uint32_t d = c->dart_of[e];
    uint32_t b0 = c->dart_of[w->twin[e]], b1 = c->dart_of[pm_rot(w, e)], v = c->vid_of[w->org[e]];
    if (st_beta0(m, d, l) != b0) st_set_beta0(m, d, l, b0);
    if (st_beta1(m, d, l) != b1) st_set_beta1(m, d, l, b1);
    if (st_vert(m, d, l) != v) st_set_vert(m, d, l, v);
}

static void ref_dart(ref *c, uint32_t e, unsigned l)
{
    c->dart_of[e] = st_dart_new(c->m, l, c->vid_of[c->w->org[e]], (c->w->hflags[e] & PM_HE_BOUNDARY) ? ST_DART_BOUNDARY : 0);
}

static void ref_around(ref *c, uint32_t v, unsigned l)
{
    uint32_t h = c->w->vhe[v], x = h;
    do { ref_relations(c, x, l); x = pm_rot(c->w, x); } while (x != h);
}

static int reference_map(const st_mesh *in, uint64_t target, st_map *m)
{
    st_error err;
    pm_work w;
    for (uint32_t f = 0; f < in->nfaces; f++) if (in->face_off[f + 1] - in->face_off[f] != 3) return -1;
    if (pm_work_init(&w, in->pos, in->nverts, in->face_idx, in->nfaces, &err)) return -1;
    char note[256];
    if (pm_simplify(&w, target, ST_MAX_LEVELS - 1, NULL, NULL, note, sizeof note, &err)) { pm_work_free(&w); return -1; }
    st_map_init(m);
    ref c = { &w, m, malloc((size_t)w.nhe * 4), malloc((size_t)w.nv * 4) };
    for (uint32_t v = 0; v < w.nv; v++) c.vid_of[v] = w.vdead[v] ? ST_NIL : st_vertex_new(m, 0, w.pos + 3 * (size_t)v);
    for (uint32_t e = 0; e < w.nhe; e++) c.dart_of[e] = (w.hflags[e] & PM_HE_DEAD) ? ST_NIL : (ref_dart(&c, e, 0), c.dart_of[e]);
    for (uint32_t e = 0; e < w.nhe; e++) if (!(w.hflags[e] & PM_HE_DEAD)) ref_relations(&c, e, 0);
    for (unsigned l = 1; l <= w.ngroups; l++) {
        uint32_t k = w.ngroups - l, beg = w.group_beg[k], end = w.group_beg[k + 1];
        st_level_add(m, &err);
        for (uint32_t i = end; i-- > beg;) pm_undo(&w, i);
        for (uint32_t i = beg; i < end; i++) {
            const pm_collapse *cl = &w.col[i];
            c.vid_of[cl->a] = st_vertex_new(m, l, w.pos + 3 * (size_t)cl->a);
            uint32_t t = w.twin[cl->h];
            ref_dart(&c, cl->h, l);
            ref_dart(&c, w.next[cl->h], l);
            ref_dart(&c, w.prev[cl->h], l);
            ref_dart(&c, t, l);
            if (cl->d != ST_NIL) {
                ref_dart(&c, w.next[t], l);
                ref_dart(&c, w.prev[t], l);
            }
        }
        for (uint32_t i = beg; i < end; i++) {
            const pm_collapse *cl = &w.col[i];
            ref_around(&c, cl->a, l);
            ref_around(&c, cl->b, l);
            ref_around(&c, cl->c, l);
            if (cl->d != ST_NIL) ref_around(&c, cl->d, l);
        }
    }
    st_map_compact(m);
    free(c.dart_of);
    free(c.vid_of);
    pm_work_free(&w);
    return 0;
}

static void check_against_reference(const char *what, const st_mesh *in, uint64_t target, const st_hier *h)
{
    st_map ref_m;
    if (reference_map(in, target, &ref_m)) return;   /* polygons: the build fans them, the reference does not */
    int same = same_topology(&ref_m, &h->map);
    uint32_t bad = 0;
    for (uint32_t v = 0; v < ref_m.verts.end && same; v++)
        if (ref_m.verts.ins[v] != ST_FREE_LEVEL && memcmp(st_pos(&ref_m, v, ref_m.verts.ins[v]), st_pos(&h->map, v, ref_m.verts.ins[v]), 24))
            bad++;
    CHECKF(same && bad == 0, "%s: the build's map differs from the reference materialisation (topology %d, %u positions)", what,
           same, bad);
    st_map_free(&ref_m);
}

/* st_progressive_level_counts gives every level's walked counts. */
static void check_counts(const char *what, st_hier *h)
{
    st_level_stats *c = malloc(((size_t)h->map.top + 1) * sizeof *c);
    CHECKF(c && st_progressive_level_counts(h, c) == 0, "%s: no counts", what);
    int same = 1;
    for (unsigned l = 0; c && l <= h->map.top; l++) {
        st_level_stats w;
        st_level_stats_compute(&h->map, l, &w);
        same &= w.darts == c[l].darts && w.vertices == c[l].vertices && w.edges == c[l].edges && w.faces == c[l].faces &&
                w.boundary_loops == c[l].boundary_loops && w.boundary_edges == c[l].boundary_edges && w.euler == c[l].euler;
    }
    CHECKF(same, "%s: the counts from the pools differ from the walked ones", what);
    free(c);
}

static void check_mesh(const char *what, const st_mesh *m, uint64_t target)
{
    st_hier h;
    if (build(m, &h, target, what)) return;
    check_counts(what, &h);
    check_against_reference(what, m, target, &h);
    check_replay(what, &h);
    check_damage(what, &h);
    check_damaged_file(what, &h);
    check_lapse(what, &h);
    st_hier_free(&h);
}

static int write_seed(const char *path)
{
    st_mesh m;
    if (load_shared("hemisphere.obj", &m)) return 1;
    st_hier h;
    if (build(&m, &h, m.nfaces / 3, path)) return 1;
    st_session_ref r = { .h = &h, .display_level = h.map.top };
    st_error err;
    int rc = st_session_save_ref(path, &r, &err);
    if (rc) fprintf(stderr, "%s\n", err.msg);
    st_hier_free(&h);
    st_mesh_free(&m);
    return rc != 0;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--seed")) return write_seed(argv[2]);
    static const char *const names[] = { "sphere_ico.obj", "hemisphere.obj", "plane_holes.obj", "blub_open.obj",
                                         "hand_lowres.obj" };
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        st_mesh m;
        if (load_shared(names[i], &m)) continue;
        check_mesh(names[i], &m, m.nfaces / 20);
        st_mesh_free(&m);
    }
    st_mesh t;
    st_mesh_init(&t);
    tl_mesh_torus(&t, 24, 16);
    check_mesh("torus 24x16", &t, 40);
    st_mesh_free(&t);
    return TEST_END();
}
