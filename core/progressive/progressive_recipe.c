/* The recipe of a progressive hierarchy's topology (progressive.h,
 * docs/SESSION-FORMAT.md PMRC): its bytes as a session stores them, the
 * recipe read back from a map (st_progressive_recipe: the splits of each
 * level from its darts in allocation order, which is the order the build
 * and the replay, progressive_replay.c, made them in), and the level
 * counts such a map has without walking it. */
#include "core/progressive/progressive_internal.h"
#include "core/multires/hier_internal.h"
#include "core/map/pool_internal.h"

#include <stdlib.h>
#include <string.h>

void st_pm_recipe_free(st_pm_recipe *r)
{
    free(r->beta0);
    free(r->beta1);
    free(r->vert);
    free(r->boundary);
    free(r->split);
    memset(r, 0, sizeof *r);
}

int st_pm_recipe_alloc_level0(st_pm_recipe *r, uint32_t ndarts0)
{
    size_t n = ndarts0 ? ndarts0 : 1;
    r->ndarts0 = ndarts0;
    r->beta0 = malloc(n * sizeof *r->beta0);
    r->beta1 = malloc(n * sizeof *r->beta1);
    r->vert = malloc(n * sizeof *r->vert);
    r->boundary = malloc(n);
    return r->beta0 && r->beta1 && r->vert && r->boundary ? 0 : -1;
}

uint64_t st_pm_recipe_splits(const st_pm_recipe *r)
{
    uint64_t n = 0;
    for (unsigned l = 1; l <= r->top && l < ST_MAX_LEVELS; l++) n += r->nsplits[l];
    return n;
}

/* ---- the session's bytes ------------------------------------------------------------ */

static size_t put_u32(unsigned char *out, size_t at, uint32_t v)
{
    if (out) for (int k = 0; k < 4; k++) out[at + k] = (unsigned char)(v >> (8 * k));
    return at + 4;
}

/* An unsigned LEB128 number: 7 bits a byte, low first. */
static size_t put_varint(unsigned char *out, size_t at, uint32_t v)
{
    while (v >= 0x80) {
        if (out) out[at] = (unsigned char)(v | 0x80);
        at++;
        v >>= 7;
    }
    if (out) out[at] = (unsigned char)v;
    return at + 1;
}

size_t st_pm_recipe_encode(const st_pm_recipe *rc, unsigned char *out)
{
    size_t at = put_u32(out, 0, rc->top);
    at = put_u32(out, at, rc->nverts0);
    at = put_u32(out, at, rc->ndarts0);
    for (uint32_t d = 0; d < rc->ndarts0; d++) {
        at = put_u32(out, at, rc->beta0[d]);
        at = put_u32(out, at, rc->beta1[d]);
        at = put_u32(out, at, rc->vert[d]);
        if (out) out[at] = rc->boundary[d];
        at++;
    }
    const st_pm_split *sp = rc->split;
    for (unsigned l = 1; l <= rc->top; l++) {
        at = put_u32(out, at, rc->nsplits[l]);
        for (uint32_t i = 0; i < rc->nsplits[l]; i++, sp++) {
            at = put_u32(out, at, sp->b);
            at = put_varint(out, at, sp->c);
            at = put_varint(out, at, sp->d == ST_NIL ? 0 : sp->d + 1);
        }
    }
    return at;
}

/* ---- counts ---------------------------------------------------------------------- */

int st_progressive_level_counts(const st_hier *h, st_level_stats *out)
{
    const st_map *m = &h->map;
    if (h->scheme != &st_scheme_progressive || !st_hier_regenerable(h) || m->face_embedded) return -1;
    uint64_t holes_at[ST_MAX_LEVELS] = { 0 };
    for (uint32_t d = 0; d < m->darts.end; d++)
        if (m->darts.ins[d] != ST_FREE_LEVEL && st_is_boundary(m, d)) holes_at[m->darts.ins[d]]++;
    /* The hole loops of level 0, whose number every level keeps. */
    uint64_t loops = 0;
    uint8_t *seen = calloc(m->darts.end ? m->darts.end : 1, 1);
    if (!seen) return -1;
    for (uint32_t d = 0; d < m->darts.end; d++) {
        if (m->darts.ins[d] != 0 || !st_is_boundary(m, d) || seen[d]) continue;
        loops++;
        uint32_t x = d, k = 0;
        do {
            seen[x] = 1;
            x = st_beta1(m, st_beta0(m, x, 0), 0);
        } while (x != d && ++k < m->darts.end);
    }
    free(seen);
    uint64_t darts = 0, verts = 0, bnd = 0;
    for (unsigned l = 0; l <= m->top; l++) {
        darts += m->darts.live[l];
        verts += m->verts.live[l];
        bnd += holes_at[l];
        st_level_stats *s = &out[l];
        s->darts = darts;
        s->vertices = verts;
        s->edges = darts / 2;
        s->boundary_edges = bnd;
        s->faces = (darts - bnd) / 3;
        s->boundary_loops = loops;
        s->euler = (int64_t)s->vertices - (int64_t)s->edges + (int64_t)s->faces;
    }
    return 0;
}

/* ---- reading the recipe from a map ------------------------------------------------ */

/* Ids of level l of pool p in allocation order: its blocks in list order,
 * each block's ids of level l ascending (a build takes them in that
 * order and frees none). */
typedef struct id_walk { const st_pool *p; unsigned l; uint32_t blk, id, end; } id_walk;

static uint32_t id_next(id_walk *w)
{
    for (;;) {
        while (w->id < w->end) {
            uint32_t i = w->id++;
            if (w->p->ins[i] == w->l) return i;
        }
        if (w->blk >= w->p->nblocks[w->l]) return ST_NIL;
        w->id = w->p->blocks[w->l][w->blk++] << ST_POOL_BLOCK_SHIFT;
        w->end = w->id + ST_POOL_BLOCK;
        if (w->end > w->p->end) w->end = w->p->end;
    }
}

static uint32_t face_next(const st_map *m, uint32_t x, unsigned l) { return st_beta1(m, st_beta0(m, x, l), l); }

/* The rank of neighbour w among v's at level l: v's darts in β1 order
 * from its dart of smallest id (ids the replay reproduces), x any dart of
 * v at l.  ST_NIL when w is not a neighbour. */
static uint32_t neighbour_rank(const st_map *m, uint32_t x, unsigned l, uint32_t w)
{
    uint32_t lo = x, k = 0, y = x;
    do { if (y < lo) lo = y; y = st_beta1(m, y, l); } while (y != x && ++k < m->darts.end);
    y = lo;
    k = 0;
    do {
        if (st_vert(m, st_beta0(m, y, l), l) == w) return k;
        k++;
        y = st_beta1(m, y, l);
    } while (y != lo && k < m->darts.end);
    return ST_NIL;
}

/* The splits of level l, in the build's order: each new vertex a comes
 * with the darts h, next(h), prev(h), t = β0(h) and, on an interior edge,
 * next(t), prev(t), the next ones of the level; b is t's vertex, c
 * prev(h)'s, d prev(t)'s.  c and d are recorded by their rank among b's
 * neighbours at level l - 1, from one of b's darts of that level (b keeps
 * one, point 3 (ii)). */
static int splits_of_level(const st_map *m, unsigned l, st_pm_split *out)
{
    id_walk vw = { &m->verts, l, 0, 0, 0 }, dw = { &m->darts, l, 0, 0, 0 };
    uint32_t n = 0;
    for (uint32_t a = id_next(&vw); a != ST_NIL; a = id_next(&vw), n++) {
        uint32_t h = id_next(&dw), h1 = id_next(&dw), h2 = id_next(&dw), t = id_next(&dw);
        if (t == ST_NIL || st_vert(m, h, l) != a || st_beta0(m, h, l) != t || face_next(m, h, l) != h1 ||
            face_next(m, h1, l) != h2 || face_next(m, h2, l) != h)
            return -1;
        uint32_t b = st_vert(m, t, l), old = h1, k = 0;
        while (m->darts.ins[old] >= l && ++k < m->darts.end) old = st_beta1(m, old, l);
        if (m->darts.ins[old] >= l || st_vert(m, old, l - 1) != b) return -1;
        st_pm_split s = { b, neighbour_rank(m, old, l - 1, st_vert(m, h2, l)), ST_NIL };
        if (s.c == ST_NIL) return -1;
        if (!st_is_boundary(m, t)) {
            uint32_t t1 = id_next(&dw), t2 = id_next(&dw);
            if (t2 == ST_NIL || face_next(m, t, l) != t1 || face_next(m, t1, l) != t2) return -1;
            s.d = neighbour_rank(m, old, l - 1, st_vert(m, t2, l));
            if (s.d == ST_NIL) return -1;
        }
        out[n] = s;
    }
    return n == m->verts.live[l] && id_next(&dw) == ST_NIL ? 0 : -1;
}

int st_progressive_recipe(const st_hier *h, st_pm_recipe *out)
{
    const st_map *m = &h->map;
    memset(out, 0, sizeof *out);
    if (h->scheme != &st_scheme_progressive || !st_hier_regenerable(h) || m->face_embedded) return -1;
    uint32_t nd = m->darts.live[0], nv = m->verts.live[0];
    /* Level 0 holds the first ids, every one live (the build's level 0). */
    for (uint32_t d = 0; d < nd; d++) if (d >= m->darts.end || m->darts.ins[d] != 0) return -1;
    for (uint32_t v = 0; v < nv; v++) if (v >= m->verts.end || m->verts.ins[v] != 0) return -1;
    uint64_t total = 0;
    for (unsigned l = 1; l <= m->top; l++) total += m->verts.live[l];
    out->top = m->top;
    out->nverts0 = nv;
    if (st_pm_recipe_alloc_level0(out, nd)) goto fail;
    out->split = malloc((size_t)(total ? total : 1) * sizeof *out->split);
    if (!out->split) goto fail;
    for (uint32_t d = 0; d < nd; d++) {
        out->beta0[d] = st_beta0(m, d, 0);
        out->beta1[d] = st_beta1(m, d, 0);
        out->vert[d] = st_vert(m, d, 0);
        out->boundary[d] = st_is_boundary(m, d);
    }
    uint64_t at = 0;
    for (unsigned l = 1; l <= m->top; l++) {
        out->nsplits[l] = m->verts.live[l];
        if (!out->nsplits[l] || splits_of_level(m, l, out->split + at)) goto fail;
        at += out->nsplits[l];
    }
    return 0;
fail:
    st_pm_recipe_free(out);
    return -1;
}

