/* Details kept across coarsening and back (Kraemer 2008 §3.2.4: the details
 * of simplified cells are stored and given back exactly when the region is
 * refined again).
 *
 * Invariant: with the one-level restriction, an unedited adaptive surface
 * refined, coarsened and refined again gets exactly its fine geometry back
 * at every depth.  Two things stand in the way, and this file handles both:
 *   - the vertices a simplification removes are recreated with other ids,
 *     so their details are kept under their address in the refinement tree
 *     (stable: level-0 darts are permanent, child indices are read from the
 *     map), in the sorted "saved" store;
 *   - a detail lives in the local frame of a coarse cell, whose tangent
 *     comes from the cell's smallest dart id (hier_synth.c), and darts of a
 *     coarsened region come back with other ids: a detail whose frame cell
 *     is taken apart is first turned into a world-space vector, with the
 *     frame it was used with, and turned back with the new frame when the
 *     cell exists again.  With the restriction the cell is complete both
 *     times (every face around it at its level).  (Limit: an edit of a
 *     coarser level made while a region is coarsened moves the world-space
 *     details with it but does not rotate them.)
 *
 * When: the detail of v at level L uses a cell of level L-1 - the edge or
 * face v was created on when L is v's insertion level, else v's vertex cell.
 * Simplifying a face of level i changes the level-(i+1) vertex cells of all
 * its vertices, so their level-(i+2) details are "parked" (world space,
 * keyed by vertex id and level) first; a removed vertex takes its parked
 * details and its creation-level detail (converted then: that cell is of
 * level i and stays) into the saved store.  Subdividing gives them back:
 * the creation-level detail at once, the others parked until the vertex is
 * placed at their level (st_adapt_place_sink). */
#include "core/adapt/adapt_internal.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

enum { KIND_EDGE = 0, KIND_CENTRE = 1, KIND_CORNER = 2 /* Doo-Sabin: corner of a cell (adapt_doosabin.c) */ };

static const double zero[3] = { 0, 0, 0 };

/* ---- stable addresses ----------------------------------------------------------
 * A removed vertex is named by where it sits in the refinement tree, not by
 * dart ids: the canonical dart of its level-0 ancestor face and, per level,
 * the child index of the face that contains it.  A corner sub-face's index
 * is the position of its corner dart (the one dart older than the sub-face)
 * in the parent, counted from the parent's canonical dart; the central
 * triangle of a triangle split is child 3.  Canonical dart of a face: its
 * smallest dart id at level 0, its corner dart above, and for a central
 * triangle the dart facing the lowest-numbered corner. */
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

/* ---- the two sorted stores ----------------------------------------------------- */

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

/* ---- world space ------------------------------------------------------------------ */

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

void st_adapt_park_detail(st_adapt *a, uint32_t d, unsigned l)
{
    st_hier *h = a->h;
    unsigned at = l + 1;
    if (at >= ST_MAX_LEVELS || !h->detail[at]) return;
    uint32_t v = st_vert(&h->map, d, l);
    const double *dv = st_hier_detail(h, at, v);
    if (dv[0] == 0 && dv[1] == 0 && dv[2] == 0) return;
    double w[3];
    to_world(h, l, d, ST_CELL_VERTEX, dv, w);
    store_put(parked_store(a), park_key(v, at), w);
    st_hier_set_detail(h, at, v, zero);
}

/* ---- removal: into the saved store ------------------------------------------------ */

/* Moves the details of v (created at L on the edge or face of `dart`, level
 * L-1) into the saved store, as world-space vectors: the level-L one through
 * its creation cell (intact: it is of level L-1), the finer ones from the
 * parked store (their vertex cells are gone already). */
static void save_detail(st_adapt *a, unsigned L, int kind, uint32_t dart, uint32_t v)
{
    st_map *m = &a->h->map;
    uint32_t faces[2];
    unsigned nf = 0;
    saved_addr base[2];
    for (unsigned at = L; at <= m->top && at < ST_MAX_LEVELS; at++) {
        if (!a->h->detail[at]) continue;
        double w[3];
        if (at == L) {
            /* A zero detail is a zero vector in any frame (frames of finite
             * positions are finite: st_stencil_apply skips them the same
             * way), so it is skipped before its frame is built - most
             * removed vertices of a box move carry none. */
            const double *dl = st_hier_detail(a->h, L, v);
            if (dl[0] == 0 && dl[1] == 0 && dl[2] == 0) continue;
            int cell = kind == KIND_EDGE ? ST_CELL_EDGE : kind == KIND_CORNER ? ST_CELL_DUAL_FACE : ST_CELL_FACE;
            to_world(a->h, L - 1, dart, cell, dl, w);
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

void st_adapt_save_edge_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v)
{
    save_detail(a, L, KIND_EDGE, dart, v);
}

void st_adapt_save_centre_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v)
{
    save_detail(a, L, KIND_CENTRE, dart, v);
}

void st_adapt_save_corner_detail(st_adapt *a, unsigned L, uint32_t dart, uint32_t v)
{
    save_detail(a, L, KIND_CORNER, dart, v);
}

/* ---- refinement: back from the stores ---------------------------------------------- */

static int was_created(const st_adapt_place_ctx *c, uint32_t v)
{
    for (uint32_t k = 0; k < c->ncreated; k++)
        if (c->created[k] == v) return 1;
    return 0;
}

/* Gives a vertex created at L the details kept for its address (zero when
 * none), and drops the copy kept under the other naming face.  They are
 * world-space vectors: the level-L one is turned into the stencil's frame
 * now (its cell, of level L-1, is complete), the finer ones are parked. */
static void restore_details(st_adapt *a, const st_stencil *s, unsigned L, int kind)
{
    st_map *m = &a->h->map;
    uint32_t faces[2], v = s->fine;
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
    st_adapt_place_ctx *c = ctx;
    st_hier *h = c->a->h;
    int created = was_created(c, s->fine);
    if (c->a->canon) st_adapt_canon_write(c->a, s->fine, c->L, created);
    if (created) {
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
