/* Subdivision levels of cells in an adaptive map (Kraemer 2008 §3.2.6).
 *
 * Invariant: whether a cell is subdivided, and the level of a face, are read
 * from the map alone - the insertion levels of darts and the relations of
 * each level - and nothing is stored, so no refinement or simplification
 * has anything to keep up to date:
 *   - an edge of level i is split toward i+1 when β0 of its dart at level
 *     i+1 is a dart inserted at i+1;
 *   - the level of a face of the map of level l is the smallest j >= ℓ (ℓ
 *     the lowest insertion level of its darts) such that the level-j face
 *     orbit of that oldest dart lies inside the face;
 *   - a face of level i is subdivided toward i+1 when its face in the map of
 *     level i+1 has level i+1.
 * The general readings hold for every family; the O(1) ones
 * (st_adapt_split_toward, st_adapt_face_of_level: inline, in
 * adapt_internal.h) hold for the maps Algorithm 1 builds (all but √3, whose
 * flips re-link old darts), and tests/core/adapt_testlib.c checks them against
 * the general ones. */
#include "core/adapt/adapt_internal.h"

#include <stdlib.h>

int st_edge_is_split(const st_map *m, uint32_t d, unsigned i)
{
    return st_adapt_edge_split(m, d, i);
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

void st_adapt_faces_of_level(st_map *m, unsigned l, st_dart_list *out)
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
