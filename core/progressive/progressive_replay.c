/* The replay of a progressive recipe (progressive.h, progressive_internal.h
 * pm_replay_*): the map a progressive build makes, and a session's reader
 * makes again (st_progressive_regenerate), from level 0 and the vertex
 * splits of each level.
 *
 * Level 0's vertices and darts are created in id order with their
 * relations; then, per level L, for each split in order, the vertex a and
 * the darts h (a->b), next(h), prev(h), t (b->a) and, on an interior edge,
 * next(t), prev(t), each with the vertex it leaves at level L and t's hole
 * flag, on a half-edge copy indexed by dart and vertex ids where each split
 * is the exact inverse of a collapse (progressive_work.c collapse); then
 * the level-L relations of the darts the splits changed.  The build before
 * version 5 of the sessions undid the collapses on its working copy and set
 * the relations around a, b, c, d through the map's setters: the same
 * values at every level, ids included (tests/core/test_progressive_recipe.c
 * keeps it as a reference). */
#include "core/progressive/progressive_internal.h"
#include "core/multires/hier_internal.h"
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

/* ---- the replay --------------------------------------------------------------------- */

/* The half-edge copy of the level being built, indexed by dart and vertex
 * ids (the build's working copy under its map's numbering). */
/* The changes of one relation at the levels above an id's insertion, in
 * level order (st_mla_set_changes). */
typedef struct changes { uint32_t *id, *val; uint8_t *lvl; uint64_t n, cap; } changes;

struct pm_replay {
    st_map *m;
    st_hier *h;
    uint32_t end0[2];                       /* the pools' ends after level 0 (st_hier_mark_regenerable) */
    uint32_t *new_a, na, cap_a;             /* the vertices the last level's splits made, in order */
    int record;                             /* keep the splits as ranks (pm_replay_recipe) */
    st_pm_split *rec;                       /* every level's splits so far, c and d as ranks */
    uint64_t nrec, cap_rec;
    uint32_t rec_n[ST_MAX_LEVELS];
    uint32_t *cur[3];                       /* per dart id: β0, β1, vert at the level being built */
    changes ch[3];
    int oom;
    uint32_t *twin, *next, *prev, *org;    /* per dart id */
    uint8_t *hole;                          /* per dart id: ST_DART_BOUNDARY */
    uint32_t *vhe;                          /* per vertex id: an outgoing dart */
    uint32_t *stamp;                        /* per vertex id: scratch of the level-0 checks */
    uint32_t *touched;                      /* darts whose relations the level's splits changed */
    uint64_t ntouched, cap_touched;
    uint32_t *target;                       /* per vertex id: level + 1 at which it was a target b */
    uint32_t cap_d, cap_v;
    st_error *err;
};
typedef struct pm_replay replay;

static uint32_t rot(const replay *r, uint32_t x) { return r->next[r->twin[x]]; }   /* next dart around org[x] */
static uint32_t dest(const replay *r, uint32_t x) { return r->org[r->next[x]]; }

static int grow_u32(uint32_t **a, uint32_t old, uint32_t cap)
{
    uint32_t *p = realloc(*a, (size_t)cap * sizeof *p);
    if (!p) return -1;
    memset(p + old, 0, (size_t)(cap - old) * sizeof *p);
    *a = p;
    return 0;
}

/* Arrays for the ids the map has handed out so far. */
static int replay_fit(replay *r)
{
    uint32_t nd = r->m->darts.end, nv = r->m->verts.end;
    if (nd > r->cap_d) {
        uint32_t c = nd + nd / 2 + ST_POOL_BLOCK;
        uint8_t *hp = realloc(r->hole, c);
        if (!hp) return -1;
        memset(hp + r->cap_d, 0, c - r->cap_d);
        r->hole = hp;
        if (grow_u32(&r->twin, r->cap_d, c) || grow_u32(&r->next, r->cap_d, c) || grow_u32(&r->prev, r->cap_d, c) ||
            grow_u32(&r->org, r->cap_d, c) || grow_u32(&r->cur[0], r->cap_d, c) || grow_u32(&r->cur[1], r->cap_d, c) ||
            grow_u32(&r->cur[2], r->cap_d, c))
            return -1;
        r->cap_d = c;
    }
    if (nv > r->cap_v) {
        uint32_t c = nv + nv / 2 + ST_POOL_BLOCK;
        if (grow_u32(&r->vhe, r->cap_v, c) || grow_u32(&r->stamp, r->cap_v, c) || grow_u32(&r->target, r->cap_v, c))
            return -1;
        r->cap_v = c;
    }
    return 0;
}

/* The half-edge copy, once every level is in (the changes stay). */
static void free_copy(replay *r)
{
    free(r->twin); free(r->next); free(r->prev); free(r->org); free(r->hole);
    free(r->vhe); free(r->stamp); free(r->target); free(r->touched); free(r->new_a);
    for (int k = 0; k < 3; k++) free(r->cur[k]);
    r->twin = r->next = r->prev = r->org = r->vhe = r->stamp = r->target = r->touched = r->new_a = NULL;
    r->hole = NULL;
    r->cur[0] = r->cur[1] = r->cur[2] = NULL;
    r->cap_d = r->cap_v = r->cap_a = 0;
    r->cap_touched = 0;
}

static void replay_free(replay *r)
{
    free_copy(r);
    free(r->rec);
    for (int k = 0; k < 3; k++) {
        free(r->ch[k].id);
        free(r->ch[k].val);
        free(r->ch[k].lvl);
    }
}

static void push_change(replay *r, changes *c, uint32_t id, unsigned l, uint32_t v)
{
    if (c->n == c->cap) {
        uint64_t cap = c->cap ? 2 * c->cap : 4096;
        uint32_t *i = realloc(c->id, cap * sizeof *i), *w = i ? realloc(c->val, cap * sizeof *w) : NULL;
        if (i) c->id = i;
        if (w) c->val = w;
        uint8_t *lv = w ? realloc(c->lvl, cap) : NULL;
        if (!lv) { r->oom = 1; return; }
        c->lvl = lv;
        c->cap = cap;
    }
    c->id[c->n] = id;
    c->val[c->n] = v;
    c->lvl[c->n] = (uint8_t)l;
    c->n++;
}

/* The level-l relations of dart x from the copy (progressive.c
 * set_relations, which sets them where they differ): a dart of level l
 * takes them as its base values, an older one records a change where its
 * value at l differs from the one it had (st_mla_set_changes makes the
 * map's form of them once every level is in). */
static void set_relations(replay *r, uint32_t x, unsigned l)
{
    st_map *m = r->m;
    uint32_t v[3] = { r->twin[x], rot(r, x), r->org[x] };
    st_mla *rel[3] = { &m->beta0, &m->beta1, &m->vert };
    int fresh = m->darts.ins[x] == l;
    for (int k = 0; k < 3; k++) {
        if (fresh) ((uint32_t *)rel[k]->base)[x] = v[k];
        else if (r->cur[k][x] != v[k]) push_change(r, &r->ch[k], x, l, v[k]);
        r->cur[k][x] = v[k];
    }
}

/* Dart x's relations changed in a split: set again once the level is
 * complete. */
static void touch(replay *r, uint32_t x)
{
    if (r->ntouched == r->cap_touched) {
        uint64_t cap = r->cap_touched ? 2 * r->cap_touched : 4096;
        uint32_t *p = realloc(r->touched, cap * sizeof *p);
        if (!p) { r->oom = 1; return; }
        r->touched = p;
        r->cap_touched = cap;
    }
    r->touched[r->ntouched++] = x;
}

/* ---- level 0 ---- */

/* Level 0's records as the build makes them: a closed triangle mesh whose
 * holes are loops of hole darts, each vertex one fan with at most one
 * hole and no two darts to the same neighbour. */
static int check_level0(const st_pm_recipe *rc, uint32_t *seen, st_error *err)
{
    uint32_t nd = rc->ndarts0, nv = rc->nverts0;
    for (uint32_t d = 0; d < nd; d++) {
        uint32_t b0 = rc->beta0[d], b1 = rc->beta1[d];
        if (b0 >= nd || b1 >= nd || rc->vert[d] >= nv || rc->boundary[d] > 1)
            return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: relation out of range", d);
        if (b0 == d || rc->beta0[b0] != d) return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: β0 is not an involution", d);
        if (rc->vert[b1] != rc->vert[d]) return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: β1 leaves its vertex", d);
        if (rc->boundary[d] && rc->boundary[b0]) return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: two holes meet", d);
        seen[b1]++;
    }
    for (uint32_t d = 0; d < nd; d++)
        if (seen[d] != 1) return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: β1 is not a permutation", d);
    for (uint32_t d = 0; d < nd; d++) {
        uint32_t n1 = rc->beta1[rc->beta0[d]], n2 = rc->beta1[rc->beta0[n1]], n3 = rc->beta1[rc->beta0[n2]];
        if (rc->boundary[n1] != rc->boundary[d]) return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: a face half a hole", d);
        if (!rc->boundary[d] && (n3 != d || n1 == d || n2 == d))
            return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: a face that is not a triangle", d);
        if (rc->vert[n1] == rc->vert[d]) return st_fail(err, ST_ERR_TOPOLOGY, "level 0, dart %u: an edge from a vertex to itself", d);
    }
    return ST_OK;
}

static int build_level0(replay *r, const st_pm_recipe *rc)
{
    st_map *m = r->m;
    static const double zero[3];
    for (uint32_t v = 0; v < rc->nverts0; v++) st_vertex_new(m, 0, zero);
    for (uint32_t d = 0; d < rc->ndarts0; d++) st_dart_new(m, 0, rc->vert[d], rc->boundary[d] ? ST_DART_BOUNDARY : 0);
    if (replay_fit(r)) return st_fail(r->err, ST_ERR_MEMORY, "progressive: out of memory for level 0");
    for (uint32_t v = 0; v < rc->nverts0; v++) r->vhe[v] = ST_NIL;
    for (uint32_t d = 0; d < rc->ndarts0; d++) {
        r->twin[d] = rc->beta0[d];
        r->next[d] = rc->beta1[rc->beta0[d]];   /* φ1 = β1 ∘ β0 */
        r->org[d] = rc->vert[d];
        r->hole[d] = rc->boundary[d];
        r->vhe[rc->vert[d]] = d;
    }
    for (uint32_t d = 0; d < rc->ndarts0; d++) r->prev[r->next[d]] = d;
    /* Each vertex one fan (a manifold vertex), at most one hole dart and
     * no neighbour twice in it. */
    uint64_t around = 0;
    for (uint32_t v = 0; v < rc->nverts0; v++) {
        if (r->vhe[v] == ST_NIL) return st_fail(r->err, ST_ERR_TOPOLOGY, "level 0, vertex %u has no dart", v);
        unsigned holes = 0;
        uint32_t x = r->vhe[v];
        do {
            holes += r->hole[x];
            uint32_t w = dest(r, x);
            if (r->stamp[w] == v + 1) return st_fail(r->err, ST_ERR_TOPOLOGY, "level 0, vertex %u: two edges to vertex %u", v, w);
            r->stamp[w] = v + 1;
            around++;
            x = rot(r, x);
        } while (x != r->vhe[v] && around <= rc->ndarts0);
        if (holes > 1) return st_fail(r->err, ST_ERR_TOPOLOGY, "level 0, vertex %u touches two holes", v);
    }
    if (around != rc->ndarts0) return st_fail(r->err, ST_ERR_TOPOLOGY, "level 0: a vertex has more than one fan");
    for (uint32_t v = 0; v < rc->nverts0; v++) r->stamp[v] = 0;
    for (uint32_t d = 0; d < rc->ndarts0; d++) set_relations(r, d, 0);
    return ST_OK;
}

/* ---- the splits ---- */

/* b's darts to c and to d (or its hole dart when d is ST_NIL), in one
 * walk of b's fan. */
static int find_fan(const replay *r, uint32_t b, uint32_t c, uint32_t d, uint32_t *ec, uint32_t *ed)
{
    *ec = *ed = ST_NIL;
    uint32_t x = r->vhe[b], n = 0;
    do {
        uint32_t w = dest(r, x);
        if (w == c) *ec = x;
        if (d == ST_NIL ? r->hole[x] != 0 : w == d) *ed = x;
        x = rot(r, x);
    } while (x != r->vhe[b] && ++n < r->m->darts.end);
    return *ec == ST_NIL || *ed == ST_NIL ? -1 : 0;
}

/* Split k's neighbours c and d as vertex ids, from their ranks in b's fan
 * (progressive.h), on the copy as level l - 1 left it (no split of the
 * level applied yet).  Each b once a level (point 3 (ii)), so the walks
 * take one pass over the level's fans. */
static int resolve(replay *r, unsigned l, uint64_t k, const st_pm_split *in, st_pm_split *out)
{
    st_map *m = r->m;
    uint32_t b = in->b;
#define REFUSE(what) st_fail(r->err, ST_ERR_TOPOLOGY, "level %u, split %llu: %s", l, (unsigned long long)k, what)
    if (b >= m->verts.end || m->verts.ins[b] >= l) return REFUSE("a vertex that does not exist at the level below");
    if (r->target[b] == l + 1) return REFUSE("a vertex split twice in one level");
    r->target[b] = l + 1;
    if (in->c == in->d) return REFUSE("c and d are one neighbour");
    uint32_t x = r->vhe[b], lo = x, n = 0;
    do { if (x < lo) lo = x; x = rot(r, x); } while (x != r->vhe[b] && ++n < m->darts.end);
    *out = (st_pm_split){ b, ST_NIL, ST_NIL };
    uint32_t j = 0;
    x = lo;
    do {
        if (j == in->c) out->c = dest(r, x);
        if (j == in->d) out->d = dest(r, x);
        j++;
        x = rot(r, x);
    } while (x != lo && j <= n);
    if (out->c == ST_NIL || (in->d != ST_NIL && out->d == ST_NIL)) return REFUSE("a neighbour rank past b's fan");
#undef REFUSE
    return ST_OK;
}

/* The split s of level l (the inverse of progressive_work.c collapse):
 * checks it as the build's group rules allow (progressive.h point 3),
 * then creates a and the darts in the build's order and re-links the
 * copy. */
static int split(replay *r, unsigned l, uint64_t k, const st_pm_split *s)
{
    st_map *m = r->m;
    uint32_t b = s->b, c = s->c, d = s->d;
    int bedge = d == ST_NIL;
#define REFUSE(what) st_fail(r->err, ST_ERR_TOPOLOGY, "level %u, split %llu: %s", l, (unsigned long long)k, what)
    if (b >= m->verts.end || c >= m->verts.end || (!bedge && d >= m->verts.end) || m->verts.ins[b] >= l)
        return REFUSE("a vertex that does not exist at the level below");
    if (m->verts.ins[c] >= l || (!bedge && m->verts.ins[d] >= l)) return REFUSE("two split vertices are neighbours");
    uint32_t ec, ed;
    if (find_fan(r, b, c, d, &ec, &ed)) return REFUSE(bedge ? "b is not on a hole, or c not around b" : "c or d not around b");
    /* The darts a takes: after ed up to ec (interior edge), or from the
     * hole dart ed up to ec; b keeps at least one (its detail frame's,
     * point 3 (ii)), a interior unless the edge is on the hole, and every
     * neighbour of a from the level below (point 3 (i)). */
    uint32_t first = bedge ? ed : rot(r, ed), x = first;
    for (;;) {
        if (x == ed && !bedge) return REFUSE("c is not after d around b");
        if (!bedge && r->hole[x]) return REFUSE("an interior split would put a on a hole");
        if (m->verts.ins[dest(r, x)] >= l) return REFUSE("two split vertices are neighbours");
        if (x == ec) break;
        x = rot(r, x);
        if (x == first) return REFUSE("c is not around b");
    }
    if (bedge && rot(r, ec) == ed) return REFUSE("b would keep no dart of the level below");
    static const double zero[3];
    uint32_t a = st_vertex_new(m, l, zero);
    if (r->na == r->cap_a) {
        uint32_t cap = r->cap_a ? 2 * r->cap_a : 1024, *p = realloc(r->new_a, (size_t)cap * sizeof *p);
        if (!p) return st_fail(r->err, ST_ERR_MEMORY, "progressive: out of memory for level %u", l);
        r->new_a = p;
        r->cap_a = cap;
    }
    r->new_a[r->na++] = a;
    uint32_t h = st_dart_new(m, l, a, 0), h1 = st_dart_new(m, l, b, 0), h2 = st_dart_new(m, l, c, 0);
    uint32_t t = st_dart_new(m, l, b, bedge ? ST_DART_BOUNDARY : 0);
    uint32_t t1 = bedge ? ST_NIL : st_dart_new(m, l, a, 0), t2 = bedge ? ST_NIL : st_dart_new(m, l, d, 0);
    if (replay_fit(r)) return st_fail(r->err, ST_ERR_MEMORY, "progressive: out of memory for level %u", l);
    for (x = first;; x = rot(r, x)) {
        r->org[x] = a;
        touch(r, x);
        if (x == ec) break;
    }
#undef REFUSE
    /* What changes: the new darts; the movers' vertex (above); the twins
     * o1..o4 of the new darts (their β0, and β1 = φ1 ∘ β0 of a twin); on
     * a hole, the dart whose β1 is the one before t (φ1 of p changes). */
    uint32_t o1 = r->twin[ec], o2 = ec;
    r->org[h] = a; r->next[h] = h1; r->prev[h] = h2; r->twin[h] = t; r->hole[h] = 0;
    r->org[h1] = b; r->next[h1] = h2; r->prev[h1] = h; r->twin[h1] = o1; r->hole[h1] = 0;
    r->org[h2] = c; r->next[h2] = h; r->prev[h2] = h1; r->twin[h2] = o2; r->hole[h2] = 0;
    r->twin[o1] = h1;
    r->twin[o2] = h2;
    r->org[t] = b; r->twin[t] = h;
    if (bedge) {
        /* t joins the hole between the dart ending at b and a's hole dart. */
        uint32_t n = ed, p = r->prev[ed];
        r->hole[t] = 1;
        r->next[t] = n; r->prev[t] = p;
        r->next[p] = t; r->prev[n] = t;
    } else {
        uint32_t o3 = r->twin[ed], o4 = ed;
        r->hole[t] = 0; r->next[t] = t1; r->prev[t] = t2;
        r->org[t1] = a; r->next[t1] = t2; r->prev[t1] = t; r->twin[t1] = o3; r->hole[t1] = 0;
        r->org[t2] = d; r->next[t2] = t; r->prev[t2] = t1; r->twin[t2] = o4; r->hole[t2] = 0;
        r->twin[o3] = t1;
        r->twin[o4] = t2;
    }
    r->vhe[a] = h;
    r->vhe[b] = h1;
    uint32_t changed[10] = { h, h1, h2, t, o1, o2 }, nc = 6;
    if (bedge) {
        changed[nc++] = r->twin[r->prev[t]];
    } else {
        changed[nc++] = t1;
        changed[nc++] = t2;
        changed[nc++] = r->twin[t1];
        changed[nc++] = r->twin[t2];
    }
    for (uint32_t i = 0; i < nc; i++) touch(r, changed[i]);
    return ST_OK;
}

/* The inverse of resolve: c and d of a split with vertex ids as their ranks
 * among b's neighbours, on the copy as level l - 1 left it. */
static int ranks_of(const replay *r, const st_pm_split *in, st_pm_split *out)
{
    uint32_t b = in->b, x = r->vhe[b], lo = x, n = 0;
    do { if (x < lo) lo = x; x = rot(r, x); } while (x != r->vhe[b] && ++n < r->m->darts.end);
    *out = (st_pm_split){ b, ST_NIL, ST_NIL };
    uint32_t j = 0;
    x = lo;
    do {
        uint32_t w = dest(r, x);
        if (w == in->c) out->c = j;
        if (in->d != ST_NIL && w == in->d) out->d = j;
        j++;
        x = rot(r, x);
    } while (x != lo && j <= n);
    return out->c == ST_NIL || (in->d != ST_NIL && out->d == ST_NIL) ? -1 : 0;
}

static int record_ranks(replay *r, unsigned l, const st_pm_split *s, uint32_t n)
{
    if (r->nrec + n > r->cap_rec) {
        uint64_t cap = 2 * (r->nrec + n);
        st_pm_split *p = realloc(r->rec, cap * sizeof *p);
        if (!p) return st_fail(r->err, ST_ERR_MEMORY, "progressive: out of memory");
        r->rec = p;
        r->cap_rec = cap;
    }
    for (uint32_t i = 0; i < n; i++)
        if (s[i].b >= r->m->verts.end || ranks_of(r, &s[i], &r->rec[r->nrec + i]))
            return st_fail(r->err, ST_ERR_TOPOLOGY, "level %u, split %u: c or d not around b", l, i);
    r->nrec += n;
    r->rec_n[l] = n;
    return ST_OK;
}

/* Level l from its n splits, b, c and d as vertex ids (resolved). */
int pm_replay_level(pm_replay *r, unsigned l, const st_pm_split *s, uint32_t n, uint64_t first)
{
    st_map *m = r->m;
    if (n == 0) return st_fail(r->err, ST_ERR_TOPOLOGY, "level %u has no split", l);
    if (r->record) {
        int rc = record_ranks(r, l, s, n);
        if (rc) return rc;
    }
    if (st_level_add(m, r->err)) return r->err ? r->err->code : ST_ERR_INVALID;
    r->na = 0;
    for (uint32_t i = 0; i < n; i++) {
        int rc = split(r, l, first + i, &s[i]);
        if (rc) return rc;
    }
    /* The level's relations once every split is in (materialise's second
     * loop sets those of every dart around a, b, c, d where they differ:
     * the same values, on the darts the splits changed). */
    for (uint64_t i = 0; i < r->ntouched; i++) set_relations(r, r->touched[i], l);
    r->ntouched = 0;
    return r->oom ? st_fail(r->err, ST_ERR_MEMORY, "progressive: out of memory") : ST_OK;
}

const uint32_t *pm_replay_new_vertices(const pm_replay *r) { return r->new_a; }

void pm_replay_record(pm_replay *r) { r->record = 1; }

int pm_replay_keep_recipe(pm_replay *r, const st_pm_recipe *level0)
{
    st_pm_recipe rc = *level0;
    memcpy(rc.nsplits, r->rec_n, sizeof rc.nsplits);
    rc.split = r->rec;
    size_t n = st_pm_recipe_encode(&rc, NULL);
    unsigned char *b = malloc(n);
    if (!b) return st_fail(r->err, ST_ERR_MEMORY, "progressive: out of memory");
    st_pm_recipe_encode(&rc, b);
    free(r->h->pm_recipe);
    r->h->pm_recipe = b;
    r->h->pm_recipe_len = n;
    return ST_OK;
}

int pm_replay_begin(pm_replay **out, st_hier *h, const st_pm_recipe *rc, st_error *err)
{
    *out = NULL;
    st_map *m = &h->map;
    st_map_free(m);
    st_map_init(m);
    if (rc->top >= ST_MAX_LEVELS) return st_fail(err, ST_ERR_RANGE, "progressive: %u levels", rc->top + 1);
    if (!rc->nverts0 || !rc->ndarts0) return st_fail(err, ST_ERR_TOPOLOGY, "progressive: level 0 is empty");
    uint64_t splits = 0;
    for (unsigned l = 1; l <= rc->top; l++) splits += rc->nsplits[l];
    replay *r = calloc(1, sizeof *r);
    uint32_t *seen = calloc(rc->ndarts0, sizeof *seen);
    if (!r || !seen) {
        free(r);
        free(seen);
        return st_fail(err, ST_ERR_MEMORY, "progressive: out of memory");
    }
    r->m = m;
    r->h = h;
    r->err = err;
    r->end0[0] = rc->ndarts0;
    r->end0[1] = rc->nverts0;
    int res = check_level0(rc, seen, err);
    free(seen);
    if (!res && st_map_reserve(m, (uint64_t)rc->ndarts0 + 6 * splits, (uint64_t)rc->nverts0 + splits))
        res = st_fail(err, ST_ERR_MEMORY, "progressive: out of memory for the map");
    if (!res) res = build_level0(r, rc);
    if (res) {
        pm_replay_free(r);
        return res;
    }
    *out = r;
    return ST_OK;
}

/* The relations' changes into the map: as dense columns (dense: a builder
 * that reads the levels before pm_replay_sparsify), or in the form
 * st_map_compact would leave. */
int pm_replay_relations(pm_replay *r, int dense)
{
    st_map *m = r->m;
    free_copy(r);   /* no level comes after: the memory back before the columns */
    st_mla *rel[3] = { &m->beta0, &m->beta1, &m->vert };
    for (int k = 0; k < 3; k++) {
        const changes *c = &r->ch[k];
        int bad = dense ? st_mla_columns_from_changes(rel[k], &m->darts, c->id, c->lvl, c->val, c->n)
                        : st_mla_set_changes(rel[k], &m->darts, c->id, c->lvl, c->val, c->n);
        if (bad) return st_fail(r->err, ST_ERR_MEMORY, "progressive: out of memory");
    }
    return ST_OK;
}

int pm_replay_sparsify(pm_replay *r)
{
    st_map *m = r->m;
    st_mla *rel[3] = { &m->beta0, &m->beta1, &m->vert };
    for (int k = 0; k < 3; k++) st_mla_drop_columns(rel[k]);
    return pm_replay_relations(r, 0);
}

/* The map as st_map_compact leaves a built one, marked regenerable. */
void pm_replay_finish(pm_replay *r)
{
    st_map_compact(r->m);
    st_hier_mark_regenerable(r->h, r->end0);
}

void pm_replay_free(pm_replay *r)
{
    if (!r) return;
    replay_free(r);
    free(r);
}

int st_progressive_regenerate(st_hier *h, const st_pm_recipe *rc, st_error *err)
{
    pm_replay *r;
    int res = pm_replay_begin(&r, h, rc, err);
    if (res) return res;
    uint32_t most = 0;
    for (unsigned l = 1; l <= rc->top; l++) if (rc->nsplits[l] > most) most = rc->nsplits[l];
    st_pm_split *resolved = malloc((size_t)(most ? most : 1) * sizeof *resolved);
    if (!resolved) res = st_fail(err, ST_ERR_MEMORY, "progressive: out of memory");
    uint64_t at = 0;
    for (unsigned l = 1; l <= rc->top && !res; l++) {
        for (uint32_t i = 0; i < rc->nsplits[l] && !res; i++) res = resolve(r, l, at + i, &rc->split[at + i], &resolved[i]);
        if (!res) res = pm_replay_level(r, l, resolved, rc->nsplits[l], at);
        at += rc->nsplits[l];
    }
    free(resolved);
    if (!res) res = pm_replay_relations(r, 0);
    if (!res) pm_replay_finish(r);
    pm_replay_free(r);
    if (res) {
        st_map_free(&h->map);
        st_map_init(&h->map);
    }
    return res;
}
