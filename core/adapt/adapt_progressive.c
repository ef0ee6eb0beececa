/* Selective display of a progressive hierarchy (adapt.h, "Progressive";
 * Kraemer 2008 §4.4.7 leaves it open; the vertex hierarchy of Hoppe 97 and
 * Xia-Varshney 96 is the same idea on one split at a time).
 *
 * The hierarchy (core/progressive/progressive.h) is the sequence of
 * half-edge collapses c_1, c_2, ... that turns level M into level B, made
 * group by group, finest group first; every collapse a -> b of the group of
 * level l was legal (link condition) on the mesh the ones before it left.
 * The displayed mesh C is what a *subsequence* of them makes of level M:
 * the collapses left out are kept as splits (fine detail).
 *
 * The rule.  V(c) = {a} ∪ N_l(a) for the collapse c of a at level l (its
 * 1-ring at level l, read from the map); b its target.  A collapse is left
 * out when
 *   (w) some vertex of V(c) wants level >= l: a vertex wants the highest
 *       level st_adapt_box_want gives a face of level M around it (max_level
 *       on faces touching the box, one less per falloff band), or
 *   (d) a or b is in V(c') of a collapse c' left out in a finer group
 *       (level > l): "held", the vertices whose star in C may differ from
 *       their star in the full sequence.
 * Collapses of the same group never hold each other back.
 *
 * Claim: every collapse applied to C acts on C exactly as it acted in the
 * full sequence, and C stays a 2-manifold with the input's boundary loops
 * (valid map, watertight: every edge has two faces or is an input boundary
 * edge, Euler characteristic kept).  Proof, by induction on the sequence;
 * write F_j for the full sequence's mesh before c_j = (a -> b), C_j for ours:
 *  - every face of the star of a in F_j is in C_j: one made by some
 *    c_i, i < j, has its corners in {y_i} ∪ N(x_i) ⊆ V(c_i), so a ∈ V(c_i);
 *    c_i is in a finer group (in the same group a ∈ N(x_i) is excluded by
 *    the independence rule (i), progressive.h point 3, and a = y_i too: a
 *    removed vertex is never a target), so (d) would have left c_j out had
 *    c_i been left out; applied, c_i made the face in C as well;
 *  - C_j has no other face around a: such a face was destroyed in the full
 *    sequence by some c_k, k < j, left out here, with a ∈ N(x_k) ⊆ V(c_k);
 *    (i) puts c_k in a finer group, and (d) again;
 *  - so the collapse replaces the same faces by the same faces, and the
 *    link condition N(a) ∩ N(b) = {c, d} holds in C_j: an edge b-w,
 *    w ∈ N(a) \ {c, d}, in C_j and not in F_j belongs to a face (b, w, x_k)
 *    destroyed by a left-out c_k (x_k, the one corner not alive in F_j);
 *    then b ∈ N(x_k) ⊆ V(c_k); in the same group the edge b-w would still
 *    be in F_j (a collapse removes no edge of which x_k is not an end), a
 *    contradiction, and in a finer group (d) applies.
 *  The link condition keeps a closed or bordered triangle 2-manifold one
 *  (Dey et al. 1999; a boundary vertex a only moves along its boundary
 *  edge, as in F_j).
 *
 * Width of the transition.  The held set grows by about one ring of each
 * level between M and B, and a level's edges are about 1/sqrt(t) longer
 * than the next finer level's (t = 0.75 per level on the shared meshes): the
 * band between the box and the faces of level B is some 4-7 edges of level
 * B wide.  A coarse B on a small mesh is then mostly transition; a B a few
 * levels below M keeps it narrow.  (A split-by-split dependency as in Hoppe
 * 97's view-dependent meshes, vertex split by vertex split, would narrow
 * it, at the price of a per-split neighbourhood record.)
 *
 * Reading C off the map, without replaying anything.  A face (φ1 orbit) of
 * the map is only ever removed by the collapse of the split that inserted
 * its darts, so it is in C when it was inserted at or below B or by a split
 * left out.  The corner of dart x is vert(x, M) renamed by the collapses
 * applied: while v was inserted above B and its collapse applied,
 * v = vert(x, ins(v) - 1), its target b (the walk stops at a level where x
 * exists: a corner of a face inserted at level l' is in V of that split,
 * left out, so (d) keeps every coarser collapse of it).  A vertex takes its
 * position of level λ = (the lowest level of an applied collapse whose V
 * holds it) - 1, or M: positions change from level l-1 to l only for the
 * vertices of V(c) of the group of l (progressive_scheme.c), so a vertex far
 * from the box has exactly its level-B position, one a box face touches
 * exactly its level-M position, and every face of C is a triangle of some
 * level (no triangulation is needed: the renderer draws C as is).
 *
 * Everything is recomputed from the map at each update, O(darts of level
 * M), reading each level-(l) ring once; the map is never changed, so
 * moving the box anywhere and back gives back the same mesh to the bit,
 * and edits of the hierarchy carry into C through the positions. */
#include "core/adapt/adapt_internal.h"
#include "core/map/map_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void st_pm_select_free(st_pm_select *s)
{
    free(s->vid);
    free(s->lam);
    free(s->tri);
    free(s->split_dart);
    free(s->order);
    free(s->want);
    free(s->skip);
    free(s->held);
    free(s->lamv);
    free(s->disp);
    memset(s, 0, sizeof *s);
}

static int grow(void **p, size_t n, size_t size)
{
    void *q = realloc(*p, (n ? n : 1) * size);
    if (!q) return -1;
    *p = q;
    return 0;
}

/* Per vertex inserted at l >= 1, a dart of level l leaving it (its split's
 * ring at l starts there), and the vertices ordered by insertion level. */
static int build_topology_cache(st_pm_select *s, st_map *m)
{
    uint32_t nv = m->verts.end;
    if (grow((void **)&s->split_dart, nv, sizeof *s->split_dart) || grow((void **)&s->order, nv, sizeof *s->order) ||
        grow((void **)&s->want, nv, 1) || grow((void **)&s->skip, nv, 1) || grow((void **)&s->held, nv, 1) ||
        grow((void **)&s->lamv, nv, 1) || grow((void **)&s->disp, nv, sizeof *s->disp))
        return -1;
    for (uint32_t v = 0; v < nv; v++) s->split_dart[v] = ST_NIL;
    for (uint32_t d = 0; d < m->darts.end; d++) {
        unsigned l = m->darts.ins[d];
        if (l == ST_FREE_LEVEL || l == 0 || st_is_boundary(m, d)) continue;
        uint32_t v = st_vert(m, d, l);
        if (m->verts.ins[v] == l && s->split_dart[v] == ST_NIL) s->split_dart[v] = d;
    }
    memset(s->level_beg, 0, sizeof s->level_beg);
    for (uint32_t v = 0; v < nv; v++)
        if (m->verts.ins[v] != ST_FREE_LEVEL) s->level_beg[m->verts.ins[v] + 1]++;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) s->level_beg[l + 1] += s->level_beg[l];
    uint32_t at[ST_MAX_LEVELS];
    memcpy(at, s->level_beg, sizeof at);
    for (uint32_t v = 0; v < nv; v++)
        if (m->verts.ins[v] != ST_FREE_LEVEL) s->order[at[m->verts.ins[v]]++] = v;
    s->cache_nv = nv;
    s->cache_gen = st_map_generation(m);
    s->cache_map = m;
    return 0;
}

/* The level each vertex of level M wants: the most any level-M face
 * around it wants (each face once, at its smallest dart). */
static void vertex_wants(st_pm_select *s, const st_map *m, unsigned M, const st_adapt_params *p)
{
    memset(s->want, 0, s->cache_nv);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, M, &it); d != ST_NIL; d = st_dart_next(m, M, &it)) {
        uint32_t x, y;
        if (!st_tri_first_dart(m, d, M, &x, &y)) continue;
        double lo[3], hi[3];
        st_adapt_face_bbox(m, d, M, lo, hi);
        unsigned w = st_adapt_box_want(lo, hi, p);
        uint8_t w8 = (uint8_t)(w < M ? w : M);
        uint32_t z = d;
        do {
            uint32_t v = st_vert(m, z, M);
            if (s->want[v] < w8) s->want[v] = w8;
            z = st_phi1(m, z, M);
        } while (z != d);
    }
}

/* Rules (w) and (d) for the collapse a -> b (level l): 1 to leave it out.
 * b is the vertex at l-1 of a dart around a older than l (the collapse
 * renamed a to b in every old dart around a). */
static int held_back(const st_pm_select *s, const st_map *m, uint32_t a, unsigned l)
{
    if (s->want[a] >= l || s->held[a]) return 1;
    uint32_t d0 = s->split_dart[a], x = d0;
    do {
        uint32_t u = st_vert(m, st_beta0(m, x, l), l);
        if (s->want[u] >= l) return 1;
        if (m->darts.ins[x] < l && s->held[st_vert(m, x, l - 1)]) return 1;
        x = st_beta1(m, x, l);
    } while (x != d0);
    return 0;
}

/* After the group of level l was decided: the V of every collapse left out
 * holds the coarser ones back; the V of every applied one takes positions
 * of level l-1 at most. */
static void mark_group(st_pm_select *s, const st_map *m, unsigned l)
{
    for (uint32_t k = s->level_beg[l]; k < s->level_beg[l + 1]; k++) {
        uint32_t a = s->order[k], d0 = s->split_dart[a], x = d0;
        int out = s->skip[a];
        if (out) s->held[a] = 1;
        do {
            uint32_t u = st_vert(m, st_beta0(m, x, l), l);
            if (out) s->held[u] = 1;
            else if (s->lamv[u] > l - 1) s->lamv[u] = (uint8_t)(l - 1);
            x = st_beta1(m, x, l);
        } while (x != d0);
    }
}

/* The corner of dart x in C (see above). */
static uint32_t corner(const st_pm_select *s, const st_map *m, uint32_t x, unsigned B, unsigned M)
{
    uint32_t v = st_vert(m, x, M);
    while (m->verts.ins[v] > B && !s->skip[v]) v = st_vert(m, x, m->verts.ins[v] - 1u);
    return v;
}

/* The face of d (level M) is in C. */
static int face_shown(const st_pm_select *s, const st_map *m, uint32_t d, unsigned B)
{
    unsigned lf = m->darts.ins[d];
    if (lf <= B) return 1;
    uint32_t z = d;
    do {
        uint32_t v = st_vert(m, z, lf);
        if (m->verts.ins[v] == lf) return s->skip[v];
        z = st_phi1(m, z, lf);
    } while (z != d);
    return 1; /* cannot happen on a map st_progressive_build made: the split vertex is a corner */
}

static int push_vertex(st_pm_select *s, uint32_t v, uint32_t *cap)
{
    if (s->disp[v] != ST_NIL) return 0;
    if (s->nverts == *cap) {
        uint32_t c = *cap ? 2 * *cap : 1024;
        if (grow((void **)&s->vid, c, sizeof *s->vid) || grow((void **)&s->lam, c, 1)) return -1;
        *cap = c;
    }
    s->disp[v] = s->nverts;
    s->vid[s->nverts] = v;
    s->lam[s->nverts] = s->lamv[v];
    s->nverts++;
    return 0;
}

int st_pm_select_update(st_pm_select *s, st_hier *h, const st_adapt_params *p, st_error *err)
{
    st_map *m = &h->map;
    if (h->scheme->id != ST_SCHEME_PROGRESSIVE)
        return st_fail(err, ST_ERR_INVALID, "adapt: the hierarchy is %s, not progressive", h->scheme->name);
    unsigned M = p->max_level < m->top ? p->max_level : m->top, B = p->base_level < M ? p->base_level : M;
    if (s->cache_map != m || s->cache_nv != m->verts.end || s->cache_gen != st_map_generation(m))
        if (build_topology_cache(s, m)) return st_fail(err, ST_ERR_MEMORY, "adapt: out of memory");
    st_adapt_params q = *p;
    q.max_level = M;
    q.base_level = B;
    vertex_wants(s, m, M, &q);
    uint32_t nv = s->cache_nv;
    memset(s->skip, 0, nv);
    memset(s->held, 0, nv);
    memset(s->lamv, (int)M, nv);
    s->applied = s->kept = 0;
    for (unsigned l = M; l > B; l--) {
        for (uint32_t k = s->level_beg[l]; k < s->level_beg[l + 1]; k++) {
            uint32_t a = s->order[k];
            s->skip[a] = (uint8_t)held_back(s, m, a, l);
            if (s->skip[a]) s->kept++;
            else s->applied++;
        }
        mark_group(s, m, l);
    }
    /* The faces of C and their corners, in the order of the darts. */
    for (uint32_t v = 0; v < nv; v++) s->disp[v] = ST_NIL;
    uint32_t capv = 0, capt = 0;
    free(s->vid);
    free(s->lam);
    s->vid = NULL;
    s->lam = NULL;
    s->nverts = s->nfaces = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, M, &it); d != ST_NIL; d = st_dart_next(m, M, &it)) {
        if (st_is_boundary(m, d)) continue;
        uint32_t x = st_phi1(m, d, M), y = st_phi1(m, x, M);
        if (x < d || y < d || st_phi1(m, y, M) != d) continue;
        if (!face_shown(s, m, d, B)) continue;
        if (s->nfaces == capt) {
            capt = capt ? 2 * capt : 1024;
            if (grow((void **)&s->tri, 3 * (size_t)capt, sizeof *s->tri)) return st_fail(err, ST_ERR_MEMORY, "adapt: out of memory");
        }
        uint32_t c[3] = { corner(s, m, d, B, M), corner(s, m, x, B, M), corner(s, m, y, B, M) };
        for (int k = 0; k < 3; k++) {
            if (push_vertex(s, c[k], &capv)) return st_fail(err, ST_ERR_MEMORY, "adapt: out of memory");
            s->tri[3 * (size_t)s->nfaces + k] = s->disp[c[k]];
        }
        s->nfaces++;
    }
    s->base = B;
    s->max = M;
    s->valid = 1;
    return ST_OK;
}

int st_pm_select_mesh(const st_pm_select *s, const st_hier *h, st_mesh *out, st_error *err)
{
    st_mesh r;
    st_mesh_init(&r);
    r.nverts = s->nverts;
    r.nfaces = s->nfaces;
    r.pos = malloc(3 * (size_t)(s->nverts ? s->nverts : 1) * sizeof *r.pos);
    r.face_off = malloc(((size_t)s->nfaces + 1) * sizeof *r.face_off);
    r.face_idx = malloc(3 * (size_t)(s->nfaces ? s->nfaces : 1) * sizeof *r.face_idx);
    if (!r.pos || !r.face_off || !r.face_idx) {
        st_mesh_free(&r);
        return st_fail(err, ST_ERR_MEMORY, "adapt: out of memory for the selected mesh");
    }
    for (uint32_t i = 0; i < s->nverts; i++) memcpy(r.pos + 3 * (size_t)i, st_pos(&h->map, s->vid[i], s->lam[i]), 3 * sizeof(double));
    for (uint32_t f = 0; f <= s->nfaces; f++) r.face_off[f] = 3 * f;
    if (s->nfaces) memcpy(r.face_idx, s->tri, 3 * (size_t)s->nfaces * sizeof *r.face_idx);
    st_mesh_move(out, &r);
    return ST_OK;
}

/* ---- st_adapt on a progressive hierarchy (adapt.c dispatches here) ----------- */

/* The one-level map of C that st_adapt_display_map hands out. */
static int rebuild_view(st_adapt *a, st_error *err)
{
    st_mesh c;
    st_mesh_init(&c);
    int rc = st_pm_select_mesh(a->pm, a->h, &c, err);
    if (rc) return rc;
    if (!a->pm_view) {
        a->pm_view = malloc(sizeof *a->pm_view);
        if (!a->pm_view) { st_mesh_free(&c); return st_fail(err, ST_ERR_MEMORY, "adapt: out of memory"); }
    } else {
        st_map_free(a->pm_view);
    }
    st_map_init(a->pm_view);
    rc = st_map_from_mesh(a->pm_view, &c, err);
    st_mesh_free(&c);
    return rc;
}

/* The selection and its view for p; the saved fields stay as they are. */
static int select_and_view(st_adapt *a, const st_adapt_params *p, st_error *err)
{
    if (!a->pm) {
        a->pm = calloc(1, sizeof *a->pm);
        if (!a->pm) return st_fail(err, ST_ERR_MEMORY, "adapt: out of memory");
    }
    int rc = st_pm_select_update(a->pm, a->h, p, err);
    if (!rc) rc = rebuild_view(a, err);
    return rc;
}

int st_adapt_pm_update(st_adapt *a, const st_adapt_params *p, st_error *err)
{
    int rc = select_and_view(a, p, err);
    if (rc) return rc;
    a->prev = *p;
    a->has_prev = 1;
    a->touched = a->pm->kept;
    a->forced = 0;
    return ST_OK;
}

int st_adapt_pm_ensure(st_adapt *a, st_error *err)
{
    return a->pm && a->pm->valid && a->pm_view ? ST_OK : select_and_view(a, &a->prev, err);
}

/* After an edit of the hierarchy: the view's positions follow; the
 * selection stays until the next update (the box's faces moved, so the
 * next update may choose others, as for the other families). */
int st_adapt_pm_refresh(st_adapt *a, st_error *err)
{
    if (!a->pm || !a->pm->valid || !a->pm_view) return st_adapt_pm_ensure(a, err);
    /* st_map_from_mesh numbers the vertices as the mesh does */
    for (uint32_t i = 0; i < a->pm->nverts; i++)
        st_set_pos(a->pm_view, i, 0, st_pos(&a->h->map, a->pm->vid[i], a->pm->lam[i]));
    return ST_OK;
}

void st_adapt_pm_free(st_adapt *a)
{
    if (a->pm) st_pm_select_free(a->pm);
    free(a->pm);
    if (a->pm_view) st_map_free(a->pm_view);
    free(a->pm_view);
    a->pm = NULL;
    a->pm_view = NULL;
}
