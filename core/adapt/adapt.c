/* Adaptive refinement and simplification (adapt.h). */
#include "core/adapt/adapt.h"
#include "core/adapt/adapt_internal.h"
#include "core/schemes/crease_internal.h"
#include "core/map/map_mesh.h"
#include "core/multires/hier_internal.h"
#include "core/map/refine_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { KIND_EDGE = 0, KIND_CENTRE = 1, KIND_CORNER = 2 /* Doo-Sabin: corner of a cell (adapt_doosabin.c) */ };

/* ---- cell subdivision levels (§3.2.6) ------------------------------------- */

int st_edge_is_split(const st_map *m, uint32_t d, unsigned i)
{
    return m->darts.ins[st_beta0(m, d, i + 1)] == i + 1;
}

unsigned st_face_level(st_map *m, uint32_t d, unsigned l)
{
    /* The face's darts at level l in a small local list (faces of an
     * adaptive map have a few sides: a linear search beats marking darts in
     * the shared marker array and clearing them again); larger faces fall
     * back to a marker bit. */
    enum { LOCAL = 64 };
    uint32_t local[LOCAL];
    unsigned n = 0;
    uint32_t b = d, x = d, levels = 0;
    do {
        if (m->darts.ins[x] < m->darts.ins[b]) b = x;
        levels |= 1u << m->darts.ins[x];
        if (n < LOCAL) local[n] = x;
        n++;
        x = st_phi1(m, x, l);
    } while (x != d);
    int bit = -1;
    if (n > LOCAL) {
        bit = st_marker_reserve(m);
        if (bit < 0) abort(); /* programmer error: markers leaked */
        st_mark_face(m, bit, d, l);
    }
    unsigned level = l;
    /* Only levels at which one of its darts was inserted can be the face's
     * level: a face made by subdividing at level j has inner darts of level
     * j (a level-0 face: its smallest insertion level). */
    for (unsigned j = m->darts.ins[b]; j < l && level == l; j++) {
        if (!(levels >> j & 1u)) continue;
        int inside = 1;
        x = b;
        do {
            int in = 0;
            if (bit >= 0) in = st_marked(m, bit, x);
            else for (unsigned k = 0; k < n && !in; k++) in = local[k] == x;
            if (!in) { inside = 0; break; }
            x = st_phi1(m, x, j);
        } while (x != b);
        if (inside) level = j;
    }
    if (bit >= 0) {
        x = d;
        do { st_unmark(m, bit, x); x = st_phi1(m, x, l); } while (x != d);
        m->marks_used &= ~(1u << bit);
    }
    return level;
}

int st_face_is_subdivided(st_map *m, uint32_t d, unsigned i)
{
    return st_face_level(m, d, i + 1) == i + 1;
}

/* st_face_is_subdivided in O(1) for the maps Algorithm 1 builds (all but
 * √3): subdividing a face splits every side and then cuts the face, so for
 * a dart d of level <= i on a face of map i, the face is subdivided toward
 * i+1 exactly when, at i+1, the next dart after d was inserted at i+1 (d's
 * side is split, or d is followed by an inner edge) and so is the one after
 * it (an inner edge: a face whose sides are only split by finer neighbours
 * goes back to one of its older darts there).  test_adapt checks it against
 * st_face_is_subdivided on every face of random adaptive maps. */
int st_adapt_split_toward(const st_map *m, uint32_t d, unsigned i)
{
    const uint8_t *ins = m->darts.ins;
    uint32_t x = st_phi1(m, d, i + 1);
    return ins[x] == i + 1 && ins[st_phi1(m, x, i + 1)] == i + 1;
}

/* st_face_level(m, y, i) == i, for the same maps: a face of level i >= 1 is
 * a sub-face of a face of map i-1 subdivided toward i, and its darts older
 * than i are darts of that parent (one corner, or none for the central
 * triangle of a triangle split); a face of lower level is a face of map i-1
 * not subdivided toward i.  (Checked like st_adapt_split_toward.) */
int st_adapt_face_of_level(const st_map *m, uint32_t y, unsigned i)
{
    if (i == 0) return 1;
    uint32_t z = y;
    do {
        if (m->darts.ins[z] < i) return st_adapt_split_toward(m, z, i - 1);
        z = st_phi1(m, z, i);
    } while (z != y);
    return 1;
}

/* st_face_level(m, y, i) == i on the map of a: the O(1) reading where the
 * map is built by Algorithm 1 (all but √3, whose flips re-link old darts). */
static int face_of_level(st_adapt *a, uint32_t y, unsigned i)
{
    st_map *m = &a->h->map;
    return a->h->scheme->id == ST_SCHEME_SQRT3 ? st_face_level(m, y, i) == i : st_adapt_face_of_level(m, y, i);
}

/* ---- saved details ----------------------------------------------------------- */

/* ---- stable addresses ----------------------------------------------------------
 * A removed vertex is named by where it sits in the refinement tree, not by
 * dart ids (darts of a coarsened region are recreated with other ids): the
 * canonical dart of its level-0 ancestor face (level-0 darts are permanent)
 * and, per level, the child index of the face that contains it.  A corner
 * sub-face's index is the position of its corner dart (the one dart older
 * than the sub-face) in the parent, counted from the parent's canonical dart;
 * the central triangle of a triangle split is child 3.  Canonical dart of a
 * face: its smallest dart id at level 0, its corner dart above, and for a
 * central triangle the dart facing the lowest-numbered corner. */
enum { PATH_NONE = 0 };

static uint32_t corner_of(const st_map *m, uint32_t d, unsigned j)
{
    uint32_t x = d;
    do { if (m->darts.ins[x] < j) return x; x = st_phi1(m, x, j); } while (x != d);
    return ST_NIL;
}

static uint32_t canonical(const st_map *m, uint32_t d, unsigned j);

/* Position of c in the face of level j containing it, from that face's canonical dart. */
static unsigned index_in_face(const st_map *m, uint32_t c, unsigned j)
{
    uint32_t x = canonical(m, c, j);
    unsigned k = 0;
    while (x != c && k < 1024) { x = st_phi1(m, x, j); k++; }
    return k;
}

static uint32_t canonical(const st_map *m, uint32_t d, unsigned j)
{
    if (j == 0) {
        uint32_t best = d, x = d;
        do { if (x < best) best = x; x = st_phi1(m, x, 0); } while (x != d);
        return best;
    }
    uint32_t c = corner_of(m, d, j);
    if (c != ST_NIL) return c;
    /* Central triangle: the dart whose twin lies in the lowest corner. */
    uint32_t best = d, x = d;
    unsigned bk = ~0u;
    do {
        uint32_t cc = corner_of(m, st_beta0(m, x, j), j);
        unsigned k = cc == ST_NIL ? ~0u : index_in_face(m, cc, j - 1);
        if (k < bk) { bk = k; best = x; }
        x = st_phi1(m, x, j);
    } while (x != d);
    return best;
}

/* Path of the face of d at level j: 32 bits of level-0 dart, 8 bits of
 * child index at level 1, 2 bits per level above, and the top bit set (so
 * that no valid path equals PATH_NONE).  PATH_NONE when it does not fit
 * (level-0 face of more than 254 sides, or j > 12). */
static uint64_t face_path(const st_map *m, uint32_t d, unsigned j)
{
    if (j > 12) return PATH_NONE;
    unsigned idx[16];
    uint32_t x = d;
    for (unsigned lev = j; lev >= 1; lev--) {
        uint32_t c = corner_of(m, x, lev);
        if (c == ST_NIL) {
            idx[lev] = 3;
            c = corner_of(m, st_beta0(m, x, lev), lev);
            if (c == ST_NIL) return PATH_NONE;
        } else {
            idx[lev] = index_in_face(m, c, lev - 1);
        }
        x = c;
    }
    uint64_t path = 1ull << 63 | canonical(m, x, 0);
    if (j >= 1) {
        if (idx[1] >= 255) return PATH_NONE;
        path |= (uint64_t)(idx[1] + 1) << 32;
    }
    for (unsigned lev = 2; lev <= j; lev++) path |= (uint64_t)(idx[lev] & 3) << (40 + 2 * (lev - 2));
    return path;
}

/* Key of a vertex created at level L, kind, element (edge index in its face),
 * and the level `at` of the detail kept. */
typedef struct saved_addr { uint64_t path; uint32_t meta; } saved_addr;

static saved_addr vertex_addr(const st_map *m, uint32_t face_dart, unsigned L, int kind, unsigned at)
{
    saved_addr k = { face_path(m, face_dart, L - 1), 0 };
    unsigned elem = kind != KIND_CENTRE ? index_in_face(m, face_dart, L - 1) : 0;
    k.meta = (uint32_t)L << 24 | (uint32_t)at << 16 | (uint32_t)kind << 8 | (elem & 0xff);
    return k;
}

static int addr_less(saved_addr a, saved_addr b)
{
    return a.path < b.path || (a.path == b.path && a.meta < b.meta);
}

static int addr_equal(saved_addr a, saved_addr b) { return a.path == b.path && a.meta == b.meta; }

static saved_addr addr_of(const st_adapt_saved *r) { saved_addr k = { r->path, r->meta }; return k; }

/* The two stores of an st_adapt share one sorted-array implementation. */
typedef struct store_ref { st_adapt_saved **r; uint32_t *n, *cap; } store_ref;

static store_ref saved_store(st_adapt *a) { store_ref s = { &a->saved, &a->nsaved, &a->capsaved }; return s; }
static store_ref parked_store(st_adapt *a) { store_ref s = { &a->parked, &a->nparked, &a->capparked }; return s; }

static int64_t store_find(store_ref s, saved_addr key)
{
    uint32_t lo = 0, hi = *s.n;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (addr_less(addr_of(&(*s.r)[mid]), key)) lo = mid + 1; else hi = mid;
    }
    return lo < *s.n && addr_equal(addr_of(&(*s.r)[lo]), key) ? (int64_t)lo : -1 - (int64_t)lo;
}

static void store_put(store_ref s, saved_addr key, const double d[3])
{
    int64_t at = store_find(s, key);
    if (at >= 0) { memcpy((*s.r)[at].d, d, sizeof (*s.r)[at].d); return; }
    if (d[0] == 0 && d[1] == 0 && d[2] == 0) return;
    uint32_t pos = (uint32_t)(-1 - at);
    if (*s.n == *s.cap) {
        *s.cap = *s.cap ? 2 * *s.cap : 64;
        *s.r = realloc(*s.r, *s.cap * sizeof **s.r);
        if (!*s.r) abort();
    }
    st_adapt_saved *r = *s.r;
    memmove(r + pos + 1, r + pos, (*s.n - pos) * sizeof *r);
    r[pos].path = key.path;
    r[pos].meta = key.meta;
    memcpy(r[pos].d, d, sizeof r[pos].d);
    (*s.n)++;
}

/* Takes a record out of the store; returns 0 (and zero) when none. */
static int store_take(store_ref s, saved_addr key, double d[3])
{
    int64_t at = store_find(s, key);
    if (at < 0) { d[0] = d[1] = d[2] = 0; return 0; }
    st_adapt_saved *r = *s.r;
    memcpy(d, r[at].d, 3 * sizeof *d);
    memmove(r + at, r + at + 1, (*s.n - at - 1) * sizeof *r);
    (*s.n)--;
    return 1;
}

/* ---- details kept in world space ------------------------------------------------
 * A detail is stored in the local frame of a coarse cell, and that frame's
 * tangent comes from the cell's smallest dart id (hier_synth.c).  Darts of a
 * coarsened region are recreated with other ids, so a detail whose frame
 * cell is taken apart is first turned into a world-space vector, with the
 * frame it was used with, and turned back with the new frame when the cell
 * exists again.  With the one-level restriction the cell is complete both
 * times (every face around it at its level), so an unedited coarse surface
 * gets back exactly its fine geometry.  (Limit: an edit of a coarser level
 * made while a region is coarsened moves the world-space details with it
 * but does not rotate them.)
 *
 * When: the detail of v at level L uses a cell of level L-1 - the edge or
 * face v was created on when L is v's insertion level, else v's vertex cell.
 * Simplifying a face of level i changes the level-(i+1) vertex cells of all
 * its vertices, so their level-(i+2) details are "parked" (world space,
 * keyed by vertex id and level) first; a removed vertex takes its parked
 * details and its creation-level detail (converted then: that cell is of
 * level i and stays) into the saved store.  Subdividing gives them back:
 * the creation-level detail at once, the others parked until the vertex is
 * placed at their level. */
static void to_world(const st_hier *h, unsigned l, uint32_t dart, int cell, const double d[3], double w[3])
{
    double f[3][3];
    st_hier_frame(h, l, dart, cell, f);
    for (int k = 0; k < 3; k++) w[k] = d[0] * f[0][k] + d[1] * f[1][k] + d[2] * f[2][k];
}

static void from_world(const st_hier *h, unsigned l, uint32_t dart, int cell, const double w[3], double d[3])
{
    double f[3][3];
    st_hier_frame(h, l, dart, cell, f);
    for (int k = 0; k < 3; k++) d[k] = f[k][0] * w[0] + f[k][1] * w[1] + f[k][2] * w[2];
}

static saved_addr park_key(uint32_t v, unsigned level)
{
    saved_addr k = { v, level };
    return k;
}

/* Parks the level-(l+1) detail of the vertex of dart d (level l). */
static void park_detail(st_adapt *a, uint32_t d, unsigned l)
{
    st_hier *h = a->h;
    unsigned at = l + 1;
    if (at >= ST_MAX_LEVELS || !h->detail[at]) return;
    uint32_t v = st_vert(&h->map, d, l);
    const double *dv = st_hier_detail(h, at, v);
    if (dv[0] == 0 && dv[1] == 0 && dv[2] == 0) return;
    double w[3];
    static const double zero[3] = { 0, 0, 0 };
    to_world(h, l, d, ST_CELL_VERTEX, dv, w);
    store_put(parked_store(a), park_key(v, at), w);
    st_hier_set_detail(h, at, v, zero);
}

/* ---- lifetime ------------------------------------------------------------------ */

static enum st_split_mode split_mode(const st_hier *h)
{
    switch (h->scheme->id) {
    case ST_SCHEME_CATMARK:
    case ST_SCHEME_DOOSABIN: return ST_SPLIT_POLY; /* (Catmull-Clark topology on the dual) */
    case ST_SCHEME_LOOP:
    case ST_SCHEME_BUTTERFLY: return ST_SPLIT_TRI;
    default: return ST_SPLIT_MIXED;
    }
}

int st_adapt_init(st_adapt *a, st_hier *h, st_error *err)
{
    memset(a, 0, sizeof *a);
    a->h = h;
    st_scheme_id id = h->scheme->id;
    if (id == ST_SCHEME_DOOSABIN && !h->map.face_embedded)
        return st_fail(err, ST_ERR_INVALID, "adapt: a %s hierarchy must hold the dual encoding", h->scheme->name);
    if (id == ST_SCHEME_DOOSABIN) {
        /* The hole corners' cut (scheme_doosabin.c) has no adaptive form yet. */
        st_dart_iter it0;
        for (uint32_t d = st_dart_first(&h->map, 0, &it0); d != ST_NIL; d = st_dart_next(&h->map, 0, &it0))
            if (st_is_boundary(&h->map, d))
                return st_fail(err, ST_ERR_TOPOLOGY, "adapt: adaptive doo-sabin on open meshes is not supported yet; "
                               "use uniform levels or catmull-clark");
    }
    if (id == ST_SCHEME_SQRT3 && st_adapt_sqrt3_check(h, err)) return err ? err->code : ST_ERR_INVALID;
    /* The base faces (level 0 never changes while adapting): one dart each. */
    st_map *m = &h->map;
    int fb = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, 0);
        st_dart_list_push(&a->base_faces, d);
    }
    st_marker_release(m, fb, 0);
    return ST_OK;
}

void st_adapt_free(st_adapt *a)
{
    free(a->saved);
    free(a->parked);
    st_dart_list_free(&a->base_faces);
    st_adapt_grid_free(a->grid);
    st_dart_list_free(&a->forced_faces);
    memset(a, 0, sizeof *a);
}

/* ---- geometry of a freshly subdivided face ------------------------------------ */

typedef st_adapt_place_ctx place_ctx;

static int was_created(const place_ctx *c, uint32_t v)
{
    for (uint32_t k = 0; k < c->ncreated; k++)
        if (c->created[k] == v) return 1;
    return 0;
}

/* The faces of level L-1 that name a vertex created at L: its face, and for
 * an edge point also the face across the edge when that face is of level
 * L-1 too (either may be the one that creates the vertex again). */
static unsigned naming_faces(st_map *m, unsigned L, int kind, uint32_t dart, uint32_t out[2])
{
    unsigned n = 0;
    out[n++] = dart;
    if (kind == KIND_EDGE) {
        uint32_t t = st_beta0(m, dart, L - 1);
        if (!st_is_boundary(m, t) && st_adapt_face_of_level(m, t, L - 1)) out[n++] = t; /* (√3 has no edge points) */
    }
    return n;
}

/* Gives a vertex created at L the details kept for its address (zero when
 * none), and drops the copy kept under the other naming face.  They are
 * world-space vectors: the level-L one is turned into the stencil's frame
 * now (its cell, of level L-1, is complete), the finer ones are parked. */
static void restore_details(st_adapt *a, const st_stencil *s, unsigned L, int kind)
{
    st_map *m = &a->h->map;
    uint32_t faces[2], v = s->fine;
    static const double zero[3] = { 0, 0, 0 };
    if (!a->nsaved) { /* nothing kept anywhere: a zero detail */
        if (a->h->detail[L]) st_hier_set_detail(a->h, L, v, zero);
        return;
    }
    /* The addresses differ only by level: compute them once per naming face. */
    unsigned nf = naming_faces(m, L, kind, s->frame_dart, faces);
    saved_addr base[2];
    for (unsigned k = 0; k < nf; k++) base[k] = vertex_addr(m, faces[k], L, kind, 0);
    for (unsigned at = L; at <= m->top && at < ST_MAX_LEVELS; at++) {
        double w[3] = { 0, 0, 0 }, other[3];
        for (unsigned k = 0; k < nf; k++) {
            if (base[k].path == PATH_NONE) continue;
            saved_addr key = { base[k].path, base[k].meta | (uint32_t)at << 16 };
            store_take(saved_store(a), key, k == 0 ? w : other);
            if (k == 1 && w[0] == 0 && w[1] == 0 && w[2] == 0) memcpy(w, other, sizeof w);
        }
        if (at == L) {
            double d[3];
            from_world(a->h, L - 1, s->frame_dart, s->frame_cell, w, d);
            st_hier_set_detail(a->h, L, v, d);
        } else {
            store_put(parked_store(a), park_key(v, at), w);
        }
    }
}

/* New vertices get their saved detail back (or zero); old vertices keep the
 * detail they have at level L, or get back the one parked for L. */
void st_adapt_place_sink(void *ctx, const st_stencil *s)
{
    place_ctx *c = ctx;
    st_hier *h = c->a->h;
    if (was_created(c, s->fine)) {
        int kind = s->frame_cell == ST_CELL_EDGE ? KIND_EDGE : s->frame_cell == ST_CELL_DUAL_FACE ? KIND_CORNER : KIND_CENTRE;
        restore_details(c->a, s, c->L, kind);
    } else {
        double w[3], d[3];
        if (store_take(parked_store(c->a), park_key(s->fine, c->L), w)) {
            from_world(h, c->L - 1, s->frame_dart, s->frame_cell, w, d);
            st_hier_set_detail(h, c->L, s->fine, d);
        }
    }
    double p[3];
    st_stencil_apply(h, c->L, s, p);
    /* Propagating setter: the levels above L that still showed the old
     * position follow, so a vertex displays its finest defined position. */
    st_set_pos(&h->map, s->fine, c->L, p);
}

/* Edge and vertex sharpness of the children, as the uniform path does. */
static void decay_sharpness(st_hier *h, uint32_t d, unsigned L)
{
    if (!h->has_sharpness) return;
    float s = st_hier_edge_sharpness(h, d, L - 1);
    uint32_t e = st_beta0(&h->map, d, L - 1);
    if (s > 0) {
        st_hier_set_edge_sharpness(h, d, L, st_crease_decay(s));
        st_hier_set_edge_sharpness(h, e, L, st_crease_decay(s));
    }
    uint32_t v = st_vert(&h->map, d, L - 1);
    float vs = st_hier_vertex_sharpness(h, v, L - 1);
    if (vs > 0) st_hier_set_vertex_sharpness(h, v, L, st_crease_decay(vs));
}

/* ---- Algorithm 1 ------------------------------------------------------------------ */

int st_adapt_ensure_level(st_hier *h, unsigned L, st_error *err)
{
    while (h->map.top < L)
        if (st_level_add(&h->map, err)) return err ? err->code : ST_ERR_RANGE;
    return ST_OK;
}

/* With the restriction, every face sharing a vertex with the face of d
 * (level i) is brought to level i first. */
static int restrict_neighbours(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    st_map *m = &a->h->map;
    for (int again = 1; again;) {
        again = 0;
        uint32_t x = d;
        do {
            uint32_t y = x;
            do {
                if (!st_is_boundary(m, y)) {
                    unsigned j = st_adapt_face_of_level(m, y, i) ? i : st_face_level(m, y, i);
                    if (j < i) {
                        /* Walk the coarser face from a dart that exists at its level. */
                        uint32_t z = y;
                        while (m->darts.ins[z] > j) z = st_phi1(m, z, i);
                        a->forced++;
                        int rc = st_adapt_subdivide_face(a, z, j, 1, err);
                        if (rc) return rc;
                        st_dart_list_push(&a->forced_faces, z);
                        st_dart_list_push(&a->forced_faces, j);
                        again = 1;
                    }
                }
                y = st_beta1(m, y, i);
            } while (y != x && !again);
            x = st_phi1(m, x, i);
        } while (x != d && !again);
    }
    return ST_OK;
}

int st_adapt_subdivide_face(st_adapt *a, uint32_t d, unsigned i, int restricted, st_error *err)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    unsigned L = i + 1;
    if (st_is_boundary(m, d)) return st_fail(err, ST_ERR_INVALID, "adapt: dart %u is on a hole", d);
    if (L >= ST_MAX_LEVELS) return st_fail(err, ST_ERR_RANGE, "adapt: level %u is beyond the limit", L);
    if (h->scheme->id == ST_SCHEME_SQRT3) return st_adapt_sqrt3_subdivide(a, d, i, err);
    if (h->scheme->id == ST_SCHEME_DOOSABIN) return st_adapt_ds_subdivide(a, d, i, err);
    if (st_adapt_split_toward(m, d, i)) return ST_OK;
    if (restricted) {
        int rc = restrict_neighbours(a, d, i, err);
        if (rc) return rc;
    }
    int rc = st_adapt_ensure_level(h, L, err);
    if (rc) return rc;
    unsigned n = st_face_degree(m, d, i);
    if (n > 255) return st_fail(err, ST_ERR_RANGE, "adapt: face of %u sides", n);
    uint32_t created[256], ncreated = 0;
    double centre[3] = { 0, 0, 0 };
    uint32_t x = d;
    do {
        const double *p = st_dart_pos(m, x, i);
        for (int k = 0; k < 3; k++) centre[k] += p[k] / n;
        uint32_t next = st_phi1(m, x, i);
        if (!st_edge_is_split(m, x, i)) {
            const double *q = st_dart_pos(m, st_beta0(m, x, i), i);
            double mid[3] = { (p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2 };
            created[ncreated++] = st_vert(m, st_split_edge(m, x, L, mid), L);
        }
        decay_sharpness(h, x, L);
        x = next;
    } while (x != d);
    enum st_split_mode mode = split_mode(h);
    if (mode == ST_SPLIT_TRI || (mode == ST_SPLIT_MIXED && n == 3)) st_split_face_tri(m, d, L);
    else {
        st_split_face_poly(m, d, L, centre);
        created[ncreated++] = st_vert(m, st_phi1(m, st_phi1(m, d, L), L), L);
    }
    place_ctx c = { a, L, created, ncreated };
    h->scheme->emit(h, L, &d, 1, st_adapt_place_sink, &c);
    a->touched++;
    return ST_OK;
}

/* ---- Algorithm 6 ---------------------------------------------------------------- */

/* After the face f of d (level i) is subdivided, its outline at level
 * L = i+1 is made of each coarse dart c and of m(c) = β0(β0(c, i), L), the
 * half-edge from the midpoint to the next corner on f's side (whichever side
 * split the edge).  Every other dart of f's sub-faces is inner. */
static uint32_t half_after(const st_map *m, uint32_t c, unsigned i)
{
    return st_beta0(m, st_beta0(m, c, i), i + 1);
}

typedef struct outline { uint32_t *d; uint32_t n; } outline;

static int on_outline(const st_map *m, const outline *o, uint32_t x, unsigned i)
{
    for (uint32_t k = 0; k < o->n; k++)
        if (x == o->d[k] || x == half_after(m, o->d[k], i)) return 1;
    return 0;
}

/* Sub-faces at level L: one dart each (the corner sub-faces start at the
 * coarse darts; a triangle's central sub-face is across a corner's inner
 * edge).  Returns the count. */
static uint32_t sub_faces(const st_map *m, const outline *o, unsigned i, uint32_t *out)
{
    uint32_t n = 0;
    for (uint32_t k = 0; k < o->n; k++) out[n++] = o->d[k];
    uint32_t x = o->d[0];
    do {
        if (!on_outline(m, o, x, i)) {
            uint32_t e = st_beta0(m, x, i + 1);
            /* The central triangle is the one sub-face without a coarse dart. */
            uint32_t y = e;
            int has_corner = 0;
            do { if (m->darts.ins[y] <= i) has_corner = 1; y = st_phi1(m, y, i + 1); } while (y != e);
            if (!has_corner) out[n++] = e;
            break;
        }
        x = st_phi1(m, x, i + 1);
    } while (x != o->d[0]);
    return n;
}

static void get_outline(const st_map *m, uint32_t d, unsigned i, outline *o)
{
    o->n = 0;
    uint32_t x = d;
    do { o->d[o->n++] = x; x = st_phi1(m, x, i); } while (x != d);
}

int st_adapt_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted)
{
    st_map *m = &a->h->map;
    if (a->h->scheme->id == ST_SCHEME_SQRT3) return st_adapt_sqrt3_can_simplify(a, d, i);
    if (a->h->scheme->id == ST_SCHEME_DOOSABIN) restricted = 1; /* always on (adapt_doosabin.c) */
    unsigned L = i + 1;
    if (!st_adapt_split_toward(m, d, i)) return 0;
    unsigned deg = st_face_degree(m, d, i);
    uint32_t buf[2 * 256], subs[256 + 1];
    if (deg > 256) return 0;
    outline o = { buf, 0 };
    get_outline(m, d, i, &o);
    uint32_t n = sub_faces(m, &o, i, subs);
    for (uint32_t k = 0; k < n; k++)
        if (st_adapt_split_toward(m, subs[k], L)) return 0;
    if (!restricted) return 1;
    /* Once f is back at level i, no face sharing one of its vertices may be
     * finer than level i+1: its corners, and the midpoints of its sides
     * that stay split because the face across is subdivided.  (A face of
     * the top map finer than L holds such a vertex c, of level <= L, exactly
     * when one of the level-L faces around c is subdivided toward L+1: its
     * corner sub-face at c is the ancestor of the finer face.) */
    for (uint32_t k = 0; k < 2 * o.n; k++) {
        uint32_t c = k < o.n ? o.d[k] : half_after(m, o.d[k - o.n], i), y = c;
        do {
            if (!st_is_boundary(m, y) && st_adapt_split_toward(m, y, L)) return 0;
            y = st_beta1(m, y, L);
        } while (y != c);
    }
    return 1;
}

/* Moves the details of v (created at L on the edge or face of `dart`, level
 * L-1) into the saved store, as world-space vectors: the level-L one through
 * its creation cell (intact: it is of level L-1), the finer ones from the
 * parked store (their vertex cells are gone already). */
static void save_detail(st_adapt *a, unsigned L, int kind, uint32_t dart, uint32_t v)
{
    static const double zero[3] = { 0, 0, 0 };
    st_map *m = &a->h->map;
    uint32_t faces[2];
    unsigned nf = 0;
    saved_addr base[2];
    for (unsigned at = L; at <= m->top && at < ST_MAX_LEVELS; at++) {
        if (!a->h->detail[at]) continue;
        double w[3];
        if (at == L) {
            int cell = kind == KIND_EDGE ? ST_CELL_EDGE : kind == KIND_CORNER ? ST_CELL_DUAL_FACE : ST_CELL_FACE;
            to_world(a->h, L - 1, dart, cell, st_hier_detail(a->h, L, v), w);
        } else if (!store_take(parked_store(a), park_key(v, at), w)) {
            /* Never used (no face of level at-1 around v was subdivided
             * since it was set): kept as it is. */
            memcpy(w, st_hier_detail(a->h, at, v), sizeof w);
        }
        if (w[0] == 0 && w[1] == 0 && w[2] == 0) continue; /* zero: nothing to keep (and already zero) */
        if (!nf) { /* the addresses, once (they differ only by level) */
            nf = naming_faces(m, L, kind, dart, faces);
            for (unsigned k = 0; k < nf; k++) base[k] = vertex_addr(m, faces[k], L, kind, 0);
        }
        for (unsigned k = 0; k < nf; k++) {
            saved_addr key = { base[k].path, base[k].meta | (uint32_t)at << 16 };
            if (key.path != PATH_NONE) store_put(saved_store(a), key, w);
        }
        st_hier_set_detail(a->h, at, v, zero);
    }
}

/* Before the level-(i+1) structure of a face is taken apart: park the
 * level-(i+2) details of every vertex it has at level i+1 - corners, edge
 * points, centre - since their vertex cells of level i+1 change. */
static void park_face_details(st_adapt *a, const outline *o, unsigned i, int tri)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    if (L + 1 >= ST_MAX_LEVELS || !a->h->detail[L + 1]) return;
    for (uint32_t k = 0; k < o->n; k++) {
        park_detail(a, o->d[k], L);
        park_detail(a, half_after(m, o->d[k], i), L);
    }
    if (!tri) park_detail(a, st_phi1(m, st_phi1(m, o->d[0], L), L), L);
}

/* Removes the inner edges of f's subdivision (the reverse of
 * st_split_face_tri / st_split_face_poly).  Triangle split: the corner
 * triangle of c_k is (c_k x ...), x = φ1(c_k) the inner dart; uncut the
 * three.  Polygon split: the corner quad of c_k is (c_k, mid->centre,
 * centre->mid', ...), so φ1²(c_k) leaves the centre; uncut spokes until the
 * centre has degree 2, unsplit it (saving its detail), uncut the edge left. */
static int remove_inner(st_adapt *a, const outline *o, unsigned i, int tri, st_error *err)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    int rc = ST_OK;
    if (tri) {
        uint32_t x[3];
        for (int k = 0; k < 3; k++) x[k] = st_phi1(m, o->d[k], L);
        for (int k = 0; k < 3 && !rc; k++) rc = st_uncut_face(m, x[k], L, err);
        return rc;
    }
    uint32_t spoke = st_phi1(m, st_phi1(m, o->d[0], L), L);
    save_detail(a, L, KIND_CENTRE, o->d[0], st_vert(m, spoke, L));
    return st_adapt_remove_centre(m, spoke, L, NULL, err);
}

int st_adapt_remove_centre(st_map *m, uint32_t spoke, unsigned L, st_unsplit_fn unsplit, st_error *err)
{
    int rc = ST_OK;
    while (!rc && st_vertex_degree(m, spoke, L) > 2) {
        uint32_t next = st_beta1(m, spoke, L);
        rc = st_uncut_face(m, spoke, L, err);
        spoke = next;
    }
    if (rc) return rc;
    uint32_t left = st_beta0(m, st_beta1(m, spoke, L), L); /* mid-side dart of the merged edge */
    rc = unsplit ? unsplit(m, spoke, L, err) : st_unsplit_edge(m, spoke, L, err);
    if (!rc) rc = st_uncut_face(m, left, L, err);
    return rc;
}

void st_adapt_corner_fallback(st_adapt *a, uint32_t c, unsigned i)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    uint32_t y = c;
    do {
        if (!st_is_boundary(m, y) && face_of_level(a, y, L)) return;
        y = st_beta1(m, y, L);
    } while (y != c);
    /* (and, through the propagating setter, above L too) */
    uint32_t v = st_vert(m, c, i);
    double p[3];
    memcpy(p, st_pos(m, v, i), sizeof p);
    st_set_pos(m, v, L, p);
}

int st_adapt_simplify_face(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    if (h->scheme->id == ST_SCHEME_SQRT3) return st_adapt_sqrt3_simplify(a, d, i, err);
    if (h->scheme->id == ST_SCHEME_DOOSABIN) return st_adapt_ds_simplify(a, d, i, err);
    unsigned L = i + 1;
    unsigned deg = st_face_degree(m, d, i);
    if (deg > 256) return st_fail(err, ST_ERR_RANGE, "adapt: face of %u sides", deg);
    uint32_t buf[256];
    outline o = { buf, 0 };
    get_outline(m, d, i, &o);
    enum st_split_mode mode = split_mode(h);
    int tri = mode == ST_SPLIT_TRI || (mode == ST_SPLIT_MIXED && deg == 3);
    park_face_details(a, &o, i, tri);
    int rc = remove_inner(a, &o, i, tri, err);
    if (rc) return rc;
    /* Unsplit the edges whose other side is not subdivided toward L. */
    for (uint32_t k = 0; k < o.n; k++) {
        uint32_t c = o.d[k], e = st_beta0(m, c, i);
        if (!st_is_boundary(m, e) && st_adapt_face_of_level(m, e, i) && st_adapt_split_toward(m, e, i)) continue;
        uint32_t half = half_after(m, c, i);
        uint32_t v = st_vert(m, half, L);
        save_detail(a, L, KIND_EDGE, c, v);
        rc = st_unsplit_edge(m, half, L, err);
        if (rc) return rc;
    }
    /* Corners no longer on a face of level L fall back to their level-i
     * position (their level-L detail stays for a later refinement)... */
    for (uint32_t k = 0; k < o.n; k++) st_adapt_corner_fallback(a, o.d[k], i);
    a->touched++;
    return ST_OK;
}

/* ---- criteria and update (Algorithms 5 and 6) ----------------------------------- */

static void face_bbox(const st_map *m, uint32_t d, unsigned l, double *lo, double *hi)
{
    /* Dual encoding: the region of a Doo-Sabin cell (adapt_doosabin.c). */
    if (m->face_embedded) { st_adapt_ds_cell_bbox(m, d, l, lo, hi); return; }
    for (int k = 0; k < 3; k++) { lo[k] = INFINITY; hi[k] = -INFINITY; }
    uint32_t x = d;
    do {
        const double *p = st_dart_pos(m, x, l);
        /* (Comparisons, not fmin/fmax: positions are finite, and these are
         * calls in a hot loop.) */
        for (int k = 0; k < 3; k++) {
            if (p[k] < lo[k]) lo[k] = p[k];
            if (p[k] > hi[k]) hi[k] = p[k];
        }
        x = st_phi1(m, x, l);
    } while (x != d);
}

/* Level the criteria want for the face of d at level l. */
unsigned st_adapt_box_want(const double lo[3], const double hi[3], const st_adapt_params *p)
{
    unsigned want = p->base_level;
    if (p->has_box) {
        double gap = 0;
        for (int k = 0; k < 3; k++) {
            double g0 = p->box_lo[k] - hi[k], g1 = lo[k] - p->box_hi[k], g = g0 > g1 ? g0 : g1;
            if (g > gap) gap = g;
        }
        unsigned w = p->max_level;
        if (gap > 0) {
            unsigned steps = p->falloff > 0 ? (unsigned)ceil(gap / p->falloff) : p->max_level;
            w = steps >= p->max_level ? 0 : p->max_level - steps;
        }
        if (w > want) want = w;
    }
    return want;
}

unsigned st_adapt_wanted_level(const st_map *m, uint32_t d, unsigned l, const st_adapt_params *p)
{
    if (m->face_embedded) return st_adapt_ds_wanted(m, d, l, p);
    double lo[3], hi[3];
    face_bbox(m, d, l, lo, hi);
    unsigned want = st_adapt_box_want(lo, hi, p);
    if (p->flatness > 0 && l < p->max_level) {
        /* Flatness: the largest angle between the face normal and the
         * normals of its edge-neighbours. */
        double n0[3] = { 0, 0, 0 };
        uint32_t x = d;
        do {
            const double *a = st_dart_pos(m, x, l), *b = st_dart_pos(m, st_phi1(m, x, l), l);
            n0[0] += (a[1] - b[1]) * (a[2] + b[2]); n0[1] += (a[2] - b[2]) * (a[0] + b[0]); n0[2] += (a[0] - b[0]) * (a[1] + b[1]);
            x = st_phi1(m, x, l);
        } while (x != d);
        double worst = 0;
        x = d;
        do {
            uint32_t e = st_beta0(m, x, l);
            if (!st_is_boundary(m, e)) {
                double n1[3] = { 0, 0, 0 };
                uint32_t y = e;
                do {
                    const double *a = st_dart_pos(m, y, l), *b = st_dart_pos(m, st_phi1(m, y, l), l);
                    n1[0] += (a[1] - b[1]) * (a[2] + b[2]); n1[1] += (a[2] - b[2]) * (a[0] + b[0]); n1[2] += (a[0] - b[0]) * (a[1] + b[1]);
                    y = st_phi1(m, y, l);
                } while (y != e);
                double dn = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]) * sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
                if (dn > 0) {
                    double c = (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2]) / dn;
                    worst = fmax(worst, acos(fmax(-1.0, fmin(1.0, c))));
                }
            }
            x = st_phi1(m, x, l);
        } while (x != d);
        if (worst > p->flatness) want = p->max_level;
    }
    return want > p->max_level ? p->max_level : want;
}

/* The criteria for the face of d at level l, as the update uses them (√3:
 * adapt_sqrt3.c). */
static unsigned wanted(st_adapt *a, uint32_t d, unsigned l, const st_adapt_params *p)
{
    if (a->h->scheme->id == ST_SCHEME_SQRT3) return st_adapt_sqrt3_wanted(&a->h->map, d, l, p);
    return st_adapt_wanted_level(&a->h->map, d, l, p);
}

/* st_face_is_subdivided, in O(1) where the map is built by Algorithm 1. */
static int subdivided(st_adapt *a, uint32_t d, unsigned i)
{
    if (a->h->scheme->id == ST_SCHEME_SQRT3) return st_face_is_subdivided(&a->h->map, d, i);
    return st_adapt_split_toward(&a->h->map, d, i);
}

/* d, listed as a face of level i (by faces_of_level or children), still is
 * one.  In the maps of Algorithm 1 a listed dart is a corner (level <= i) of
 * its face, which refining other faces (new darts of other faces, or of
 * this face's sides at levels above i) and simplifying faces of level >= i
 * (only darts inserted above i go) leave a face of level i: only liveness
 * is checked.  √3's flips re-link old darts, so there the level is read. */
static int listed_face(st_adapt *a, uint32_t d, unsigned i)
{
    st_map *m = &a->h->map;
    if (!st_dart_live(m, d)) return 0;
    return a->h->scheme->id != ST_SCHEME_SQRT3 || st_face_level(m, d, i) == i;
}

/* One dart per real face of map l whose subdivision level is l. */
static void faces_of_level(st_map *m, unsigned l, st_dart_list *out)
{
    out->n = 0;
    int fb = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, l);
        if (st_face_level(m, d, l) == l) st_dart_list_push(out, d);
    }
    st_marker_release(m, fb, l);
}

/* ---- incremental updates --------------------------------------------------------
 * A face's wanted level depends only on its geometry and the box, so when
 * only the box moves, only faces near the old or the new box can change.
 * Children stay near their parents, so the visit starts from the base faces
 * near either box (grown by their own size), grown by three rings (√3:
 * SQRT3_RINGS) so that faces refined only because the restriction forced
 * them are visited too, and descends through subdivided faces only. */

static int boxes_only_moved(const st_adapt *a, const st_adapt_params *p)
{
    const st_adapt_params *q = &a->prev;
    return a->has_prev && q->has_box && p->has_box && q->base_level == p->base_level && q->max_level == p->max_level &&
           q->falloff == p->falloff && q->flatness == 0 && p->flatness == 0 && q->no_restriction == p->no_restriction;
}

/* √3: forced refinement goes further.  Before a face of level i is
 * subdivided, the faces around its corners must be even triangles of level
 * i, so the lower neighbours of odd triangles two faces away are forced: up
 * to about two faces of level i-1 per level, and faces shrink by √3 (not
 * 2) per level, a reach under 2 / (1 - 1/√3) < 5 base faces.  Six rings
 * leave a margin (tests/test_adapt_sqrt3.c compares with full updates). */
#ifndef SQRT3_RINGS
#define SQRT3_RINGS 6
#endif

/* Base faces near either box, then three rings around them (√3: SQRT3_RINGS). */
static void region_roots(st_adapt *a, const st_adapt_params *q, const st_adapt_params *p, st_dart_list *roots)
{
    st_map *m = &a->h->map;
    double lo[3], hi[3], grow = p->falloff > 0 ? p->falloff * p->max_level : 0;
    for (int k = 0; k < 3; k++) {
        lo[k] = fmin(q->box_lo[k], p->box_lo[k]) - grow;
        hi[k] = fmax(q->box_hi[k], p->box_hi[k]) + grow;
    }
    st_dart_list seeds = { 0 }, near = { 0 };
    const st_dart_list *base = &a->base_faces;
    if (!a->grid) a->grid = st_adapt_grid_build(m, base, face_bbox);
    if (a->grid) st_adapt_grid_near(a->grid, lo, hi, &near);
    else /* (out of memory for the grid: the same test on every base face) */
        for (uint32_t k = 0; k < base->n; k++) {
            double fb[6];
            face_bbox(m, base->d[k], 0, fb, fb + 3);
            if (st_adapt_box_near(fb, lo, hi)) st_dart_list_push(&near, k);
        }
    for (uint32_t j = 0; j < near.n; j++) {
        uint32_t k = near.d[j];
        uint32_t x = base->d[k];
        do { st_dart_list_push(&seeds, x); x = st_phi1(m, x, 0); } while (x != base->d[k]);
    }
    st_dart_list_free(&near);
    roots->n = 0;
    /* Forced refinement spreads one face per level, and faces double in size
     * per level toward the base: its reach in base faces is a geometric sum,
     * under 2 rings; 3 leave a margin. */
    if (seeds.n) st_region_faces(m, 0, seeds.d, seeds.n, a->h->scheme->id == ST_SCHEME_SQRT3 ? SQRT3_RINGS : 3, roots);
    st_dart_list_free(&seeds);
}

/* A face deep inside both the old and the new box (its bounding box grown
 * by its own size on every side, which covers the neighbourhood its
 * descendants' stencils read) is settled: the last update refined all its
 * descendants to max_level, they all still want max_level, and nothing
 * coarser around it is simplified into it (the restriction only spreads
 * refinement outward).  An incremental update need not look inside it, so
 * the visit costs the band where the boxes differ, not the whole box. */
static int settled(const st_adapt *a, uint32_t d, unsigned lev, const st_adapt_params *p)
{
    const st_adapt_params *q = &a->prev;
    double lo[3], hi[3], size = 0;
    face_bbox(&a->h->map, d, lev, lo, hi);
    for (int k = 0; k < 3; k++) size = fmax(size, hi[k] - lo[k]);
    for (int k = 0; k < 3; k++)
        if (lo[k] - size < fmax(q->box_lo[k], p->box_lo[k]) || hi[k] + size > fmin(q->box_hi[k], p->box_hi[k])) return 0;
    return 1;
}

/* Appends to out the sub-faces (level lev+1) of the subdivided faces of
 * cur[0..n) (level lev): corner sub-faces hold their parent's darts; a
 * triangle split adds the central triangle, across the corner triangle's
 * inner edge.  With p (an incremental update), settled faces are left out. */
static void children(st_adapt *a, const uint32_t *cur, uint32_t ncur, unsigned lev, const st_adapt_params *p,
                     st_dart_list *out)
{
    st_map *m = &a->h->map;
    enum st_split_mode mode = split_mode(a->h);
    for (uint32_t k = 0; k < ncur; k++) {
        uint32_t d = cur[k];
        if (!listed_face(a, d, lev) || !subdivided(a, d, lev)) continue;
        if (p && settled(a, d, lev, p)) continue;
        unsigned n = 0;
        uint32_t x = d;
        do { st_dart_list_push(out, x); n++; x = st_phi1(m, x, lev); } while (x != d);
        /* (√3: the face of each of the three darts at lev+1 is one sub-face
         * each - odd, or the even triangle of its flipped edge - and no
         * other sub-face holds no old dart.) */
        if (a->h->scheme->id != ST_SCHEME_SQRT3 && (mode == ST_SPLIT_TRI || (mode == ST_SPLIT_MIXED && n == 3)))
            st_dart_list_push(out, st_beta0(m, st_phi1(m, d, lev + 1), lev + 1));
    }
}

/* Algorithm 5 over listed faces: level by level from `from`, each face of
 * lists[i] (level i) wanting more is subdivided, and the children of the
 * subdivided ones join lists[i+1] (lists has max_level + 1 entries). */
static int refine_lists(st_adapt *a, st_dart_list *lists, unsigned from, const st_adapt_params *p, int prune,
                        st_error *err)
{
    st_map *m = &a->h->map;
    int rc = ST_OK;
    for (unsigned i = from; i < p->max_level && i <= m->top && !rc; i++) {
        st_dart_list *cur = &lists[i];
        for (uint32_t k = 0; k < cur->n && !rc; k++) {
            uint32_t d = cur->d[k];
            if (!listed_face(a, d, i) || subdivided(a, d, i)) continue;
            if (wanted(a, d, i, p) > i) rc = st_adapt_subdivide_face(a, d, i, !p->no_restriction, err);
        }
        children(a, cur->d, cur->n, i, prune ? p : NULL, &lists[i + 1]);
    }
    return rc;
}

/* After a pass, the faces the restriction subdivided (a->forced_faces:
 * dart, level pairs) have children nobody examined: faces made at levels
 * the pass had already left.  Only those can want more - every other face
 * was examined, and its wanted level reads its own geometry, which a
 * neighbour's subdivision leaves as it is (with the restriction, stencils
 * are complete and give the same points) - so the next pass starts from
 * them.  (√3's forced steps also flip edges of faces already examined: it
 * passes over everything again instead.) */
static int refine_forced(st_adapt *a, const st_dart_list *forced, st_dart_list *lists, const st_adapt_params *p,
                         st_error *err)
{
    unsigned from = p->max_level;
    for (uint32_t k = 0; k + 1 < forced->n; k += 2) {
        uint32_t z = forced->d[k];
        unsigned j = forced->d[k + 1];
        if (j + 1 > p->max_level) continue;
        children(a, &z, 1, j, NULL, &lists[j + 1]);
        if (j + 1 < from) from = j + 1;
    }
    int rc = refine_lists(a, lists, from, p, 0, err);
    for (unsigned i = 0; i <= p->max_level; i++) lists[i].n = 0;
    return rc;
}

int st_adapt_update(st_adapt *a, const st_adapt_params *p, st_error *err)
{
    st_map *m = &a->h->map;
    int restricted = !p->no_restriction;
    st_dart_list faces = { 0 }, roots = { 0 };
    const st_dart_list *region = NULL;
    if (boxes_only_moved(a, p)) {
        region_roots(a, &a->prev, p, &roots);
        region = &roots;
    } else { /* (level 0 may have moved: the grid is rebuilt, for the moves to come) */
        st_adapt_grid_free(a->grid);
        a->grid = p->has_box ? st_adapt_grid_build(m, &a->base_faces, face_bbox) : NULL;
    }
    a->touched = 0;
    int rc = ST_OK;
    /* Algorithm 5: refine, coarse to fine; again (refine_forced) while the
     * restriction forced faces at levels already passed. */
    /* (region: lists holds the region's faces of each level after the first
     * pass, which the simplification below reuses; more holds the faces of
     * the later passes.) */
    unsigned nl = p->max_level + 1;
    st_dart_list *lists = calloc(2 * (size_t)nl, sizeof *lists), *more = lists + nl, forced = { 0 };
    if (!lists) rc = st_fail(err, ST_ERR_MEMORY, "adapt: out of memory");
    for (int pass = 0; !rc; pass++) {
        a->forced = 0;
        a->forced_faces.n = 0;
        if (pass && a->h->scheme->id != ST_SCHEME_SQRT3) rc = refine_forced(a, &forced, more, p, err);
        else if (region) {
            for (unsigned i = 0; i < nl; i++) lists[i].n = 0;
            for (uint32_t k = 0; k < region->n; k++) st_dart_list_push(&lists[0], region->d[k]);
            rc = refine_lists(a, lists, 0, p, 1, err);
        } else
            for (unsigned i = 0; i < p->max_level && i <= m->top && !rc; i++) {
                faces_of_level(m, i, &faces);
                for (uint32_t k = 0; k < faces.n && !rc; k++) {
                    uint32_t d = faces.d[k];
                    if (!listed_face(a, d, i) || subdivided(a, d, i)) continue;
                    if (wanted(a, d, i, p) > i) rc = st_adapt_subdivide_face(a, d, i, restricted, err);
                }
            }
        if (!a->forced) break;
        st_dart_list t = forced; forced = a->forced_faces; a->forced_faces = t;
    }
    st_dart_list_free(&forced);
    st_dart_list_free(&a->forced_faces);
    /* Algorithm 6: simplify, fine to coarse.  A simplification at level
     * j > i deletes only darts inserted above i, so the lists of the coarser
     * levels stay valid.  In a region, the lists are those of the first
     * refinement pass: the later passes only subdivided faces the
     * restriction needs (never simplifiable now) and made their children
     * (not subdivided, so nothing to simplify in them). */
    for (unsigned i = region && m->top >= nl ? nl - 1 : m->top; i-- > 0 && !rc;) {
        if (!region) faces_of_level(m, i, &faces);
        const st_dart_list *cur = region ? &lists[i] : &faces;
        for (uint32_t k = 0; k < cur->n && !rc; k++) {
            uint32_t d = cur->d[k];
            if (!listed_face(a, d, i) || !subdivided(a, d, i)) continue;
            if (wanted(a, d, i, p) > i || !st_adapt_can_simplify(a, d, i, restricted)) continue;
            rc = st_adapt_simplify_face(a, d, i, err);
        }
    }
    if (lists)
        for (unsigned i = 0; i < 2 * nl; i++) st_dart_list_free(&lists[i]);
    free(lists);
    st_dart_list_free(&faces);
    st_dart_list_free(&roots);
    a->prev = *p;
    a->has_prev = !rc;
    return rc;
}

typedef struct resynth_ctx { st_hier *h; unsigned L; uint32_t gen; } resynth_ctx;

static void resynth_sink(void *ctx, const st_stencil *s)
{
    resynth_ctx *c = ctx;
    if (c->h->stamp[s->fine] == c->gen) return;
    c->h->stamp[s->fine] = c->gen;
    double p[3];
    st_stencil_apply(c->h, c->L, s, p);
    st_set_pos(&c->h->map, s->fine, c->L, p);
}

void st_adapt_synthesize(st_adapt *a, unsigned from)
{
    a->has_prev = 0; /* the geometry changed: the next update visits everything */
    st_hier *h = a->h;
    st_map *m = &h->map;
    st_dart_list faces = { 0 }, sub = { 0 };
    for (unsigned L = from + 1; L <= m->top; L++) {
        faces_of_level(m, L - 1, &faces);
        sub.n = 0;
        for (uint32_t k = 0; k < faces.n; k++)
            if (st_face_is_subdivided(m, faces.d[k], L - 1)) st_dart_list_push(&sub, faces.d[k]);
        if (!sub.n) continue; /* (emit with no face means every vertex of level L) */
        resynth_ctx c = { h, L, st_hier_stamp_begin(h) };
        h->scheme->emit(h, L, sub.d, sub.n, resynth_sink, &c);
    }
    st_dart_list_free(&faces);
    st_dart_list_free(&sub);
}

int st_adapt_mesh(st_adapt *a, st_mesh *out, st_error *err)
{
    return st_map_to_mesh(&a->h->map, a->h->map.top, out, err);
}

/* ---- shared with adapt_sqrt3.c (adapt_internal.h) ------------------------------- */

void st_adapt_save_centre_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v)
{
    save_detail(a, L, KIND_CENTRE, dart, v);
}

void st_adapt_park_detail(st_adapt *a, uint32_t d, unsigned l) { park_detail(a, d, l); }

void st_adapt_save_corner_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v)
{
    save_detail(a, L, KIND_CORNER, dart, v);
}

int st_adapt_restrict(st_adapt *a, uint32_t d, unsigned i, st_error *err) { return restrict_neighbours(a, d, i, err); }
