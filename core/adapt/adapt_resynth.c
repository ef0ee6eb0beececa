/* Local re-synthesis of adaptive hierarchies (adapt.h): the region growth
 * of an edit (core/multires/hier_synth.c) restricted to the faces that are
 * subdivided toward the next level, for the interest box's display, which
 * copies the model's edited positions and re-synthesises its own finer
 * adaptive levels around them.  Kept in core/adapt because it reads the
 * cells' subdivision levels (Kraemer 2008 §3.3.1). */
#include "core/adapt/adapt_internal.h"
#include "core/multires/edit.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

/* ---- canonical stencils ----------------------------------------------------------
 * A fine vertex shared by several subdivided faces takes its stencil from
 * the first listed face that holds it (the scheme's emit), and two faces
 * sum the same weights in different orders: the results may differ in the
 * last bit.  So that a local re-synthesis and st_adapt_synthesize give the
 * same bits (an HD edit, adapt_hd.c, is checked against a full synthesis),
 * both list the faces of a level by their smallest dart, in increasing
 * order; the canonical face of a fine vertex is then the listed face with
 * the smallest dart, which a full synthesis always meets first.  A local
 * pass that meets a vertex first on another face (the canonical one lies
 * outside its region: a vertex at the region's edge, whose value does not
 * change) takes the stencil of the canonical face instead.  Polygon split
 * family only (its O(1) subdivision reading, adapt_internal.h); the other
 * families keep the listing order. */

static int canonical_family(const st_hier *h) { return st_adapt_scheme_has_hd(h->scheme); }

static uint32_t face_min(const st_map *m, uint32_t d, unsigned l)
{
    uint32_t best = d;
    for (uint32_t x = st_phi1(m, d, l); x != d; x = st_phi1(m, x, l))
        if (x < best) best = x;
    return best;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Each face by its smallest dart of level l, in increasing order (the
 * sort only when the list is not in order already: a full level listed by
 * the pools mostly is). */
static void canonical_order(const st_map *m, unsigned l, uint32_t *faces, uint32_t n)
{
    int sorted = 1;
    for (uint32_t k = 0; k < n; k++) {
        faces[k] = face_min(m, faces[k], l);
        if (k && faces[k] < faces[k - 1]) sorted = 0;
    }
    if (!sorted) qsort(faces, n, sizeof *faces, cmp_u32);
}

void st_adapt_canonical_faces(const st_hier *h, unsigned l, st_dart_list *faces)
{
    if (canonical_family(h)) canonical_order(&h->map, l, faces->d, faces->n);
}

/* The face of d (map l) is a real face subdivided toward l+1: one that a
 * synthesis of level l+1 lists. */
static int listed(const st_map *m, uint32_t d, unsigned l)
{
    return !st_is_boundary(m, d) && st_adapt_split_toward(m, d, l);
}

/* The canonical face (its smallest dart, map L-1) of the fine vertex of
 * stencil s; ST_NIL when the cell is not one the family reads. */
static uint32_t canonical_face(const st_map *m, const st_stencil *s, unsigned L)
{
    unsigned l = L - 1;
    uint32_t d = s->frame_dart, best = ST_NIL;
    if (s->frame_cell == ST_CELL_FACE) return face_min(m, d, l);
    if (s->frame_cell == ST_CELL_EDGE) {
        uint32_t e = st_beta0(m, d, l);
        if (listed(m, d, l)) best = face_min(m, d, l);
        if (listed(m, e, l)) { uint32_t f = face_min(m, e, l); if (f < best) best = f; }
        return best;
    }
    if (s->frame_cell != ST_CELL_VERTEX) return ST_NIL;
    uint32_t x = d;
    do {
        if (listed(m, x, l)) { uint32_t f = face_min(m, x, l); if (f < best) best = f; }
        x = st_beta1(m, x, l);
    } while (x != d);
    return best;
}

/* The stencil of one fine vertex, taken from one face's emission. */
typedef struct capture_ctx {
    const st_hier *h;
    unsigned L;
    uint32_t v;
    int apply;                 /* 1: with the detail (st_stencil_apply); 0: S(P_{L-1}) only */
    int found;
    double p[3];
} capture_ctx;

static void capture_sink(void *ctx, const st_stencil *s)
{
    capture_ctx *c = ctx;
    if (c->found || s->fine != c->v) return;
    if (c->apply) st_stencil_apply(c->h, c->L, s, c->p);
    else st_stencil_eval(&c->h->map, c->L, s, c->p);
    c->found = 1;
}

int st_adapt_canonical_pred(st_hier *h, unsigned L, uint32_t d, double pred[3])
{
    const st_map *m = &h->map;
    if (!canonical_family(h) || L < 1) return 0;
    /* The parents (map L-1) of the faces around the vertex: each face of
     * level L holds a dart of its parent (a corner, or for the central
     * triangle of a triangle split none: its neighbours' parents are the
     * same face).  Valence is bounded by the local array. */
    enum { MAXP = 64 };
    uint32_t par[MAXP], n = 0, x = d;
    do {
        if (!st_is_boundary(m, x)) {
            uint32_t y = x;
            do {
                if (m->darts.ins[y] < L) break;
                y = st_phi1(m, y, L);
            } while (y != x);
            if (m->darts.ins[y] < L && listed(m, y, L - 1)) {
                if (n == MAXP) return 0;
                par[n++] = y;
            }
        }
        x = st_beta1(m, x, L);
    } while (x != d);
    canonical_order(m, L - 1, par, n);
    capture_ctx c = { .h = h, .L = L, .v = st_vert(m, d, L) };
    for (uint32_t k = 0; k < n && !c.found; k++)
        if (!k || par[k] != par[k - 1]) st_hier_emit(h, L, &par[k], 1, capture_sink, &c);
    if (c.found) for (int i = 0; i < 3; i++) pred[i] = c.p[i];
    return c.found;
}

/* ---- passes ---------------------------------------------------------------------- */

typedef struct resynth_ctx {
    st_hier *h;
    unsigned L;
    uint32_t gen;
    st_dart_list *changed;   /* NULL: no seeds for a next level */
    int lost;
    int canonical;           /* the faces are in canonical order: vertices met off their canonical face
                                take its stencil */
    st_footprint *fp;
    uint64_t count;          /* positions written */
} resynth_ctx;


/* The level-L position of s's fine vertex as its canonical face's stencil
 * gives it (canonical: 0, s's own), st_stencil_apply's sum: the face that
 * emitted s may not be the canonical one at a region's edge, and then one
 * emission of the canonical face finds the vertex's stencil there. */
static void canonical_apply(st_hier *h, unsigned L, const st_stencil *s, int canonical, double p[3])
{
    uint32_t canon = canonical ? canonical_face(&h->map, s, L) : ST_NIL;
    if (canon != ST_NIL && canon != face_min(&h->map, s->frame_dart, L - 1)) {
        capture_ctx cap = { .h = h, .L = L, .v = s->fine, .apply = 1 };
        st_hier_emit(h, L, &canon, 1, capture_sink, &cap);
        if (cap.found) {
            memcpy(p, cap.p, 3 * sizeof *p);
            return;
        }
    }
    st_stencil_apply(h, L, s, p);
}

/* Applies stencil s at level L unless its fine vertex was already written
 * in this pass (stamp gen); st_set_pos writes the level's column as
 * st_adapt_synthesize does. */
static void resynth_sink(void *ctx, const st_stencil *s)
{
    resynth_ctx *c = ctx;
    st_hier *h = c->h;
    if (h->stamp.v[s->fine] == c->gen) return;
    h->stamp.v[s->fine] = c->gen;
    double p[3];
    canonical_apply(h, c->L, s, c->canonical, p);
    st_set_pos(&h->map, s->fine, c->L, p);
    c->count++;
    if (c->fp) st_footprint_add(c->fp, st_fp_key(c->L, ST_FP_POS, s->fine));
    if (!c->changed) return;
    uint32_t x = st_dart_on_cell(&h->map, s->fine, s->frame_dart, c->L);
    if (x == ST_NIL) c->lost = 1;
    else st_dart_list_push(c->changed, x);
}

void st_hier_resynth_faces(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n)
{
    if (!n) return;
    resynth_ctx c = { .h = h, .L = L, .gen = st_hier_stamp_begin(h) };
    st_hier_emit(h, L, faces, n, resynth_sink, &c);
}

typedef struct around_ctx {
    st_hier *h;
    st_footprint *fp;
    unsigned extra;            /* more rings: a vertex was lost at the level below */
    uint64_t count;            /* positions written, all levels */
    st_dart_list faces, kept;
} around_ctx;

static int around_step(void *ctx, unsigned L, const st_dart_list *seeds, st_dart_list *next)
{
    around_ctx *a = ctx;
    st_hier *h = a->h;
    st_map *m = &h->map;
    if (!seeds->n) return 1;
    a->faces.n = 0;
    st_region_faces(m, L - 1, seeds->d, seeds->n, h->scheme->support_rings + 1 + a->extra, &a->faces);
    a->kept.n = 0;
    for (uint32_t i = 0; i < a->faces.n; i++)
        if (st_face_level(m, a->faces.d[i], L - 1) == L - 1 && st_face_is_subdivided(m, a->faces.d[i], L - 1))
            st_dart_list_push(&a->kept, a->faces.d[i]);
    st_adapt_canonical_faces(h, L - 1, &a->kept);
    resynth_ctx c = { .h = h, .L = L, .gen = st_hier_stamp_begin(h), .changed = next, .fp = a->fp,
                      .canonical = canonical_family(h) };
    if (a->kept.n) st_hier_emit(h, L, a->kept.d, a->kept.n, resynth_sink, &c);
    a->extra = c.lost;
    a->count += c.count;
    /* A vertex not found on its frame cell: every dart of the kept faces
     * seeds the next level, with one more ring. */
    if (c.lost) {
        next->n = 0;
        st_dart_list_push_faces(next, m, L - 1, a->kept.d, a->kept.n);
    }
    return 0;
}

uint64_t st_hier_resynth_around(st_hier *h, unsigned from, const uint32_t *seeds0, uint32_t n, st_footprint *fp)
{
    st_dart_list seeds = { 0 };
    for (uint32_t i = 0; i < n; i++) st_dart_list_push(&seeds, seeds0[i]);
    around_ctx a = { .h = h, .fp = fp };
    st_hier_levels_up(h, from, &seeds, around_step, &a);
    st_dart_list_free(&a.faces);
    st_dart_list_free(&a.kept);
    return a.count;
}

/* ---- after an update -------------------------------------------------------------
 * An update (adapt_update.c) places the vertices of each face it subdivides
 * with that face's stencils, in the order it happens to subdivide faces:
 * the face's new vertices, and those it shares with older ones that no
 * other face of the new level held yet (a vertex another subdivided face
 * holds keeps its position: adapt_split.c, split_subdivide).  So a vertex
 * may end with another face's stencil than its canonical one (last bit),
 * or with a stencil read before a coarser neighbour forced later re-placed
 * a vertex of its support.  So the polygon split family records what an
 * update changes (a->canon: the faces it subdivides or simplifies, the
 * positions its writes replace), and the update ends with a canonical
 * local pass, level by level from the coarsest recorded face, which leaves
 * every position as st_adapt_synthesize from the base level would (given
 * a hierarchy that was so before the update):
 *   - level L is re-emitted, in canonical order and with canonical
 *     stencils, on the faces of level L-1 subdivided by the update (the
 *     vertices they created or re-placed, whose canonical face may be
 *     theirs now), on the subdivided faces within one ring of a face
 *     simplified (the vertices it left with another canonical face), and
 *     on the subdivided faces within the
 *     support (support_rings + 1, as an edit's growth) of the vertices of
 *     level L-1 whose value differs from before the update;
 *   - a vertex is written where its value changes.  It differs from
 *     before the update when its new value is not the one it had before
 *     the update's first write at its level (or before the pass, for a
 *     vertex the update did not write there); it is then carried upward
 *     while the level above shows the value of the level below (the
 *     setter carried the write there: it stops at the first level that
 *     diverged, and a level that diverged was written itself or kept its
 *     value).
 * With the one-level restriction a vertex the update created needs no
 * support region: whatever reads it at the next level is a face that the
 * same update subdivided (every face around a face subdivided toward L
 * was of level L-1 before it, and the created vertex's faces were not),
 * and a fallen-back corner of a simplified face is read by no subdivided
 * face.  Without it, every vertex of a recorded face counts as changed.
 * A vertex that no recorded face reaches and whose support did not
 * change keeps its value, which was the canonical one.  Cost: the
 * recorded faces and one ring around them, plus the support of what
 * really moved, per level. */

enum { SIMPLIFIED = 1u << 31 };

void st_adapt_canon_record(st_adapt *a, uint32_t d, unsigned i, int simplified)
{
    if (!a->canon) return;
    st_dart_list_push(&a->canon->faces, d);
    st_dart_list_push(&a->canon->faces, i | (simplified ? SIMPLIFIED : 0));
}

void st_adapt_canon_write(st_adapt *a, uint32_t v, unsigned L, int created)
{
    st_adapt_canon *c = a->canon;
    if (!c) return;
    if (c->npos == c->cappos) {
        c->cappos = c->cappos ? 2 * c->cappos : 256;
        c->pos = realloc(c->pos, c->cappos * sizeof *c->pos);
        if (!c->pos) abort(); /* (as st_dart_list_push) */
    }
    st_adapt_canon_pos *r = &c->pos[c->npos];
    r->v = v;
    r->level = L;
    r->seq = c->npos++;
    r->created = (uint32_t)created;
    memcpy(r->p, st_pos(&a->h->map, v, L), sizeof r->p);
}

void st_adapt_canon_free(st_adapt_canon *c)
{
    st_dart_list_free(&c->faces);
    free(c->pos);
    memset(c, 0, sizeof *c);
}

typedef struct canon_ctx {
    st_hier *h;
    unsigned L;
    uint32_t gen;
    st_dart_list *changed;           /* darts of level L of the vertices that differ from before the update */
    const st_adapt_canon_pos *pos;   /* the update's writes (a->canon) */
    const uint32_t *slot;            /* open addressing by vertex: index into pos of the first write at L, or ST_NIL */
    uint32_t mask;
    int lost;
    uint64_t count;
} canon_ctx;

static uint32_t hash_v(uint32_t v) { return v * 2654435761u; }

static const st_adapt_canon_pos *find_before(const canon_ctx *c, uint32_t v)
{
    if (!c->slot) return NULL;
    for (uint32_t k = hash_v(v) & c->mask;; k = (k + 1) & c->mask) {
        uint32_t s = c->slot[k];
        if (s == ST_NIL) return NULL;
        if (c->pos[s].v == v) return &c->pos[s];
    }
}

/* The canonical stencil's value (resynth_sink's choice), written where it
 * differs from the vertex's position. */
static void canon_sink(void *ctx, const st_stencil *s)
{
    canon_ctx *c = ctx;
    st_hier *h = c->h;
    st_map *m = &h->map;
    if (h->stamp.v[s->fine] == c->gen) return;
    h->stamp.v[s->fine] = c->gen;
    double p[3];
    canonical_apply(h, c->L, s, 1, p);
    const double *cur = st_pos(m, s->fine, c->L);
    const st_adapt_canon_pos *b = find_before(c, s->fine);
    int differs = b ? !b->created && memcmp(b->p, p, sizeof p) : memcmp(cur, p, sizeof p);
    if (memcmp(cur, p, sizeof p)) {
        st_set_pos(m, s->fine, c->L, p); /* (the levels above that showed the old value follow) */
        c->count++;
    }
    if (!differs) return;
    uint32_t x = st_dart_on_cell(m, s->fine, s->frame_dart, c->L);
    if (x == ST_NIL) c->lost = 1;
    else st_dart_list_push(c->changed, x);
}

/* A record (d, i) still names a face of map i: d not removed by a coarser
 * simplification of the same update (that one's record covers it). */
static int record_live(const st_map *m, uint32_t d, unsigned i)
{
    return st_dart_in_level(m, d, i) && !st_is_boundary(m, d);
}

/* The darts at map l = i+1 of the face recorded at (d, i): each corner's
 * face at l (a subdivided face's corner sub-faces: corners, side points,
 * centre; a simplified face: the face itself, once per corner). */
static void push_record_darts(const st_map *m, uint32_t d, unsigned i, st_dart_list *out)
{
    unsigned l = i + 1, n = 0;
    uint32_t x = d;
    do {
        uint32_t y = x;
        unsigned k = 0;
        do { st_dart_list_push(out, y); y = st_phi1(m, y, l); } while (y != x && ++k < 1024);
        x = st_phi1(m, x, i);
    } while (x != d && ++n < 1024);
}

/* Keeps one dart per vertex (stamps of a new generation). */
static void unique_vertices(st_hier *h, unsigned l, st_dart_list *list)
{
    uint32_t gen = st_hier_stamp_begin(h), n = 0;
    for (uint32_t k = 0; k < list->n; k++) {
        uint32_t v = st_vert(&h->map, list->d[k], l);
        if (h->stamp.v[v] == gen) continue;
        h->stamp.v[v] = gen;
        list->d[n++] = list->d[k];
    }
    list->n = n;
}

uint64_t st_adapt_canon_update(st_adapt *a)
{
    st_hier *h = a->h;
    st_map *m = &h->map;
    const st_adapt_canon *cn = a->canon;
    const st_dart_list *rec = &cn->faces;
    if (rec->n < 2 || !canonical_family(h)) return 0;
    unsigned lo = ~0u;
    for (uint32_t k = 0; k + 1 < rec->n; k += 2)
        if ((rec->d[k + 1] & ~SIMPLIFIED) < lo) lo = rec->d[k + 1] & ~SIMPLIFIED;
    st_dart_list chg = { 0 }, next = { 0 }, seeds = { 0 }, faces = { 0 }, kept = { 0 };
    uint32_t *slot = NULL, cap = 0;
    unsigned extra = 0;
    uint64_t count = 0;
    for (unsigned L = lo + 1; L <= m->top; L++) {
        unsigned l = L - 1;
        seeds.n = 0;
        faces.n = 0;
        for (uint32_t k = 0; k + 1 < rec->n; k += 2) {
            uint32_t d = rec->d[k];
            unsigned i = rec->d[k + 1] & ~SIMPLIFIED;
            if (!cn->restricted && i + 1 == l && record_live(m, d, i)) push_record_darts(m, d, i, &chg);
            if (i != l || !record_live(m, d, i)) continue;
            if (!(rec->d[k + 1] & SIMPLIFIED)) {
                /* (its fine vertices are all its own: the face itself) */
                st_dart_list_push(&faces, d);
                continue;
            }
            uint32_t x = d;
            do { st_dart_list_push(&seeds, x); x = st_phi1(m, x, l); } while (x != d);
        }
        unique_vertices(h, l, &chg);
        if (chg.n) st_region_faces(m, l, chg.d, chg.n, h->scheme->support_rings + 1 + extra, &faces);
        if (seeds.n) st_region_faces(m, l, seeds.d, seeds.n, 1, &faces);
        kept.n = 0;
        for (uint32_t k = 0; k < faces.n; k++)
            if (st_adapt_face_of_level(m, faces.d[k], l) && listed(m, faces.d[k], l)) st_dart_list_push(&kept, faces.d[k]);
        canonical_order(m, l, kept.d, kept.n);
        uint32_t nk = 0; /* (the two regions may share faces) */
        for (uint32_t k = 0; k < kept.n; k++)
            if (!nk || kept.d[k] != kept.d[nk - 1]) kept.d[nk++] = kept.d[k];
        kept.n = nk;
        /* the update's first write of each vertex at L, by vertex */
        uint32_t nb = 0, mask = 0;
        for (uint32_t k = 0; k < cn->npos; k++) nb += cn->pos[k].level == L;
        if (nb) {
            uint32_t want = 16;
            while (want < 2 * nb) want *= 2;
            if (want > cap) {
                free(slot);
                slot = malloc(want * sizeof *slot);
                if (!slot) abort();
                cap = want;
            }
            mask = want - 1;
            memset(slot, 0xff, want * sizeof *slot); /* ST_NIL */
            for (uint32_t k = 0; k < cn->npos; k++) {
                if (cn->pos[k].level != L) continue;
                uint32_t j = hash_v(cn->pos[k].v) & mask;
                while (slot[j] != ST_NIL && cn->pos[slot[j]].v != cn->pos[k].v) j = (j + 1) & mask;
                if (slot[j] == ST_NIL) slot[j] = k; /* (the first write wins) */
            }
        }
        next.n = 0;
        canon_ctx c = { .h = h, .L = L, .gen = st_hier_stamp_begin(h), .changed = &next, .pos = cn->pos,
                        .slot = nb ? slot : NULL, .mask = mask };
        if (kept.n) st_hier_emit(h, L, kept.d, kept.n, canon_sink, &c);
        count += c.count;
        extra = c.lost;
        if (c.lost) st_dart_list_push_faces(&next, m, l, kept.d, kept.n);
        /* Carried up where level L shows the level-l value; darts of map l
         * are darts of map L, on the same vertices. */
        for (uint32_t k = 0; k < chg.n; k++) {
            uint32_t v = st_vert(m, chg.d[k], l);
            if (!memcmp(st_pos(m, v, l), st_pos(m, v, L), 3 * sizeof(double))) st_dart_list_push(&next, chg.d[k]);
        }
        st_dart_list t = chg; chg = next; next = t;
    }
    free(slot);
    st_dart_list_free(&chg);
    st_dart_list_free(&next);
    st_dart_list_free(&seeds);
    st_dart_list_free(&faces);
    st_dart_list_free(&kept);
    return count;
}
