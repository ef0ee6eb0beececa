/* A level's UVs made compact (fvar_internal.h, st_fvar_level): one value
 * per distinct (label, UV bits) among the corners of a vertex, and per dart
 * the index of its value.
 *
 * The rules compute every corner on its own (fvar_rules.c), so a level is
 * born dense: 16 bytes of UV and 4 of label per dart.  Most corners of a
 * vertex share their value (a vertex off the seams has one), so the
 * compact form keeps about a value per vertex and seam.
 *
 * Done in place, with no second copy of the UVs, in two passes over the
 * dart ids:
 *  1. A dart whose (label, bits) a smaller dart of its vertex has is a
 *     copy: its label's slot gets that smaller dart.  The others are
 *     representatives (marked in rep) and keep their label.  The smaller
 *     dart is looked for first at the vertex's first dart (head, per
 *     vertex id: every corner of a vertex off the seams), then among the
 *     next AROUND_MAX corners around the vertex.  Any partition into darts
 *     of equal (label, bits) reads back the same, so the search need not
 *     be exhaustive to be exact; it is around vertices of up to 64
 *     corners.  The map must be valid (a damaged one still ends each walk
 *     at AROUND_MAX).
 *  2. The representatives in ascending id get the value indices 0, 1, ...:
 *     the j-th of them is dart id j or above, so moving its UV down to
 *     slot j overwrites only UVs already moved or never read again.  A
 *     copy's smaller dart is already numbered: the copy takes its index.
 * Ids below cap outside level L (free, or of a finer level sharing the id
 * range) hold zeros unless written: they share one last value (0, 0)
 * labelled 0, or are representatives of their own when written. */
#include "core/fvar/fvar_internal.h"

#include <stdlib.h>
#include <string.h>

#define ZERO_VALUE UINT32_MAX   /* pass 1: the dart reads the last value (0, 0), label 0 */

static inline int bit_get(const uint64_t *b, uint32_t d) { return (int)((b[d >> 6] >> (d & 63)) & 1); }
static inline void bit_set(uint64_t *b, uint32_t d) { b[d >> 6] |= 1ull << (d & 63); }

/* A corner's value as a key: the bits of its UV and its label. */
typedef struct value_key { uint64_t u, v; uint32_t label; } value_key;

static inline value_key key_of(const st_fvar_level *lv, uint32_t d)
{
    value_key k;
    memcpy(&k.u, lv->uv + 2 * (size_t)d, sizeof k.u);
    memcpy(&k.v, lv->uv + 2 * (size_t)d + 1, sizeof k.v);
    k.label = lv->val[d];
    return k;
}

static inline int same_key(value_key a, value_key b) { return a.u == b.u && a.v == b.v && a.label == b.label; }

/* During pass 1: the representative a dart below the current one copies
 * (its label's slot holds its smaller dart until a representative). */
static inline uint32_t rep_of(const st_fvar_level *lv, const uint64_t *rep, uint32_t y)
{
    while (!bit_get(rep, y))
        if ((y = lv->val[y]) >= lv->cap) return ST_NIL; /* (a zero id outside the level, met on a damaged map) */
    return y;
}

/* How far around a vertex a copy's smaller dart is looked for: a pole's
 * corners past it become representatives (more values, the same reads)
 * rather than make the pass quadratic in the valence. */
enum { AROUND_MAX = 64 };

/* A representative below d, within AROUND_MAX corners around d's vertex,
 * holding d's key k; or ST_NIL. */
static inline uint32_t earlier_around(const st_fvar_level *lv, const uint64_t *rep, const st_level_view *v, int dual,
                                      uint32_t d, value_key k, int sparse)
{
    uint32_t y = st_v_vertex_step_kind(v, dual, d, sparse);
    for (int n = 0; y != d && y < lv->cap && n < AROUND_MAX; n++, y = st_v_vertex_step_kind(v, dual, y, sparse)) {
        if (y > d) continue;
        uint32_t r = rep_of(lv, rep, y);
        if (r != ST_NIL && same_key(key_of(lv, r), k)) return r;
    }
    return ST_NIL;
}

/* Pass 1; returns the representatives. */
static inline uint32_t mark_copies_kind(st_fvar_level *lv, const st_map *m, unsigned L, const st_level_view *v,
                                        uint32_t *head, uint64_t *rep, int sparse)
{
    int dual = m->face_embedded;
    uint32_t nrep = 0;
    for (uint32_t d = 0; d < lv->cap; d++) {
        unsigned ins = m->darts.ins[d];
        value_key k = key_of(lv, d);
        if (ins == ST_FREE_LEVEL || ins > L) {
            if (!k.u && !k.v && !k.label) {
                lv->val[d] = ZERO_VALUE;
            } else {
                bit_set(rep, d);
                nrep++;
            }
            continue;
        }
        /* The vertex's first corner is a representative; a later one
         * copies the first, or another corner around (an id past the
         * vertex pool, on a damaged map: around only). */
        uint32_t vid = st_view_get_kind(&v->vert, v->ins, d, sparse), r = ST_NIL;
        if (vid < m->verts.end && head[vid] == ST_NIL) {
            head[vid] = d;
        } else {
            if (vid < m->verts.end) r = head[vid];
            if (r == ST_NIL || !same_key(key_of(lv, r), k)) r = earlier_around(lv, rep, v, dual, d, k, sparse);
            if (r != ST_NIL) {
                lv->val[d] = r;
                continue;
            }
        }
        bit_set(rep, d);
        nrep++;
    }
    return nrep;
}

/* Undoes pass 1 (out of memory): in ascending ids a copy's smaller dart
 * has its label back already. */
static void restore_labels(st_fvar_level *lv, const uint64_t *rep)
{
    for (uint32_t d = 0; d < lv->cap; d++)
        if (!bit_get(rep, d)) lv->val[d] = lv->val[d] == ZERO_VALUE ? 0 : lv->val[lv->val[d]];
}

int st_fvar_level_compact(st_fvar_level *lv, const st_map *m, unsigned L)
{
    if (lv->idx) return 0;
    uint32_t cap = lv->cap;
    uint64_t *rep = calloc(((size_t)cap + 63) / 64 + 1, sizeof *rep);
    uint32_t *head = malloc(((size_t)m->verts.end + 1) * sizeof *head);
    if (!rep || !head) {
        free(rep);
        free(head);
        return -1;
    }
    memset(head, 0xff, ((size_t)m->verts.end + 1) * sizeof *head);  /* ST_NIL */
    st_level_view view;
    st_level_view_init(m, L, &view);
    uint32_t nrep = st_level_view_is_sparse(&view) ? mark_copies_kind(lv, m, L, &view, head, rep, 1)
                                                   : mark_copies_kind(lv, m, L, &view, head, rep, 0);
    free(head);
    uint32_t *label = malloc(((size_t)nrep + 1) * sizeof *label);
    if (!label) {
        restore_labels(lv, rep);
        free(rep);
        return -1;
    }
    uint32_t j = 0;
    for (uint32_t d = 0; d < cap; d++) {
        if (bit_get(rep, d)) {
            label[j] = lv->val[d];
            lv->uv[2 * (size_t)j] = lv->uv[2 * (size_t)d];
            lv->uv[2 * (size_t)j + 1] = lv->uv[2 * (size_t)d + 1];
            lv->val[d] = j++;
        } else {
            lv->val[d] = lv->val[d] == ZERO_VALUE ? nrep : lv->val[lv->val[d]];
        }
    }
    free(rep);
    /* The last value, (0, 0) labelled 0: slot nrep is at most cap, inside
     * the dense array's 2 * cap + 2 (level_alloc). */
    lv->uv[2 * (size_t)nrep] = lv->uv[2 * (size_t)nrep + 1] = 0;
    label[nrep] = 0;
    double *uv = realloc(lv->uv, 2 * ((size_t)nrep + 1) * sizeof *uv);
    if (uv) lv->uv = uv;  /* else the longer block serves as well */
    lv->idx = lv->val;
    lv->val = label;
    lv->nvals = nrep + 1;
    return 0;
}
