/* Face-varying UVs of an adaptive mesh (adapt.h: "UVs").
 *
 * The level-0 UVs of the hierarchy (core/fvar) are carried up the adaptive
 * map level by level with the rules of docs/SUBDIVISION-RULES.md §7b, the
 * ones core/fvar/fvar.c applies to a whole level, here applied to the
 * faces subdivided toward the next level only:
 *   - a face subdivided toward L = l+1 gets its face child (centroid of its
 *     corners' level-l values), written at φ1²(d) of each child quad;
 *   - an edge split toward L gets its edge child on each side, written at
 *     the corners of the split point in the faces on that side - on the side
 *     of a face not subdivided (a transition face) that is the one dart the
 *     split inserted there, so the transition face holds the fine point's
 *     value in its own chart;
 *   - a vertex that is a corner of a subdivided face gets its vertex child,
 *     written at every corner around it, so faces not subdivided that share
 *     the vertex show it at its finest value, as they show it at its finest
 *     position (st_adapt_mesh).
 * Every corner of the top level thus holds the value of the finest level at
 * which its vertex was computed, in the chart of its face.  With the
 * one-level restriction every stencil reads complete level-l faces (Kraemer
 * 2008 §3.2.2), the same neighbourhood as a regular level; the arithmetic
 * is fvar.c's, term for term, and its sums start where fvar.c's start on a
 * regular level (order_children), so the values are the regular level's
 * bit for bit.  Without the restriction a stencil reads whatever the
 * neighbourhood is, as the positions do.
 *
 * The rules are core/fvar/fvar_rules.c's, the one copy that fvar.c's
 * regular levels use too; tests/core/test_adapt_uv.c compares the two bit for
 * bit.
 *
 * Catmull-Clark and Loop follow OpenSubdiv's face-varying rules (the
 * hierarchy's --uv-interp), Butterfly and quad/triangle are linear.  √3
 * and Doo-Sabin run the stencil rules of core/fvar/fvar_stencil.c on the
 * faces subdivided toward each level (stencil_step); those sum in an order
 * of their terms, not of dart ids, so the values are again the regular
 * level's bit for bit.  Doo-Sabin's E- and V-faces take as home the source
 * face whose first dart a regular level's scan meets first
 * (docs/SUBDIVISION-RULES.md §7b): a Doo-Sabin step refines M* as
 * Catmull-Clark refines the surface (Kraemer 2008 §3.2.1), so
 * order_children ranks the adaptive map's darts of each level in the
 * regular level's order there too, and the homes are the regular level's.
 * Where a cell of M* is cut next to one that is not, the border triangle's
 * corner at the coarser vertex (the dart the split inserted on the uncut
 * side) shows that vertex as its other corners do, in the triangle's home
 * chart.  Progressive hierarchies (level 0's UVs only) carry none above
 * level 0 (st_adapt_uv_absent says why). */
#include "core/adapt/adapt_internal.h"
#include "core/fvar/fvar_internal.h"
#include "core/map/map_mesh.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

static int rules_of(const st_hier *h) { return st_fvar_rules_of(h->scheme); }

const char *st_adapt_uv_absent(const st_adapt *a)
{
    const st_hier *h = a->h;
    if (!st_hier_has_uv(h, 0)) return "the mesh has no texture coordinates";
    if (st_adapt_is_progressive(a)) return "a progressive hierarchy's adaptive mesh carries no UVs";
    if (rules_of(h) < 0 && h->map.top > 0)
        return "this scheme keeps the UVs of level 0 only, and adaptive meshes above level 0 carry none";
    return NULL;
}

void st_adapt_uv_free(st_adapt_uv *u)
{
    free(u->uv);
    free(u->val);
    free(u->level);
    free(u->rank);
    memset(u, 0, sizeof *u);
}

/* ---- one step l -> L = l+1 ------------------------------------------------------ */

/* The step's rules are fvar_rules.c's (st_fvar_step), restricted to the
 * faces subdivided toward L: sub marks them, cent keeps every face's
 * centroid, rank orders the map's darts as a regular level numbers them. */
static int split_toward(const st_map *m, uint32_t d, unsigned l) { return st_adapt_split_toward(m, d, l); }

/* ---- a regular level's numbering ------------------------------------------------ */

/* The bulk refinement (core/map/refine.c) numbers the darts of level L face
 * by face of level l, each face from the first of its darts of level l met
 * (level 0: its smallest id), corner i giving n(d_i), then first(d_i) =
 * φ1(d_i) at L, then out_i = β0(in_i) (a triangle split: u_i =
 * β0(first(d_{i+1}))).  Ranking the adaptive map's darts of level L by
 * (rank of the face, 3 i + role) gives their order there, which the
 * vertex rules need to sum as fvar.c does on a regular level. */
typedef struct rank_key { uint32_t face, pos, dart; } rank_key;

static int cmp_rank(const void *pa, const void *pb)
{
    const rank_key *a = pa, *b = pb;
    if (a->face != b->face) return a->face < b->face ? -1 : 1;
    if (a->pos != b->pos) return a->pos < b->pos ? -1 : 1;
    return (a->dart > b->dart) - (a->dart < b->dart);
}

static int order_children(st_fvar_step *w)
{
    st_map *m = w->m;
    unsigned l = w->l, L = w->L;
    const uint8_t *ins = m->darts.ins;
    size_t cap = 64, n = 0;
    rank_key *k = malloc(cap * sizeof *k);
    if (!k) return -1;
    int fbit = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        st_mark_face(m, fbit, d, l);
        if (!w->sub[d]) continue;
        /* the face's first dart: its newest darts' first in the scan */
        uint32_t f0 = d, x = st_phi1(m, d, l);
        while (x != d) {
            if (ins[x] > ins[f0] || (ins[x] == ins[f0] && st_fvar_regular_before(w, x, f0))) f0 = x;
            x = st_phi1(m, x, l);
        }
        uint32_t face = l ? w->rank[f0] : f0;
        int tri = st_face_degree(m, f0, L) == 3;
        uint32_t i = 0;
        x = f0;
        do {
            if (n + 3 > cap) {
                rank_key *g = realloc(k, 2 * cap * sizeof *k);
                if (!g) { free(k); st_marker_release(m, fbit, l); return -1; }
                k = g;
                cap *= 2;
            }
            uint32_t in = st_phi1(m, x, L);
            uint32_t out = tri ? st_beta0(m, st_phi1(m, st_phi1(m, x, l), L), L) : st_beta0(m, in, L);
            k[n++] = (rank_key){ face, 3 * i, st_beta0(m, st_beta0(m, x, l), L) };
            k[n++] = (rank_key){ face, 3 * i + 1, in };
            k[n++] = (rank_key){ face, 3 * i + 2, out };
            i++;
            x = st_phi1(m, x, l);
        } while (x != f0);
    }
    st_marker_release(m, fbit, l);
    qsort(k, n, sizeof *k, cmp_rank);
    for (size_t j = 0; j < n; j++)
        if (ins[k[j].dart] == L) w->rank[k[j].dart] = (uint32_t)j;
    free(k);
    return 0;
}

static int step(st_fvar_step *w)
{
    st_map *m = w->m;
    size_t cap = m->darts.end;
    memcpy(w->out_uv, w->uv, 2 * cap * sizeof *w->out_uv);
    memcpy(w->out_val, w->val, cap * sizeof *w->out_val);
    memset(w->sub, 0, cap);
    if (st_fvar_face_children(w)) return -1;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, w->l, &it); d != ST_NIL; d = st_dart_next(m, w->l, &it))
        if (!st_is_boundary(m, d) && st_adapt_edge_split(m, d, w->l)) st_fvar_edge_child(w, d);
    if (st_fvar_vertex_children(w) || order_children(w)) return -1;
    st_fvar_inner_triangles(w);
    return 0;
}

/* √3 and Doo-Sabin (fvar_stencil.c's rules): the faces of level l
 * subdivided toward L, whose stencils give every vertex the step computes.
 * Doo-Sabin's E- and V-faces take as home the source face a regular
 * level's scan meets first, so its step also ranks the darts of level L as
 * a regular level numbers them: Doo-Sabin refines M* as Catmull-Clark
 * refines the surface (a polygon split, core/map/refine.c), whose order
 * order_children gives. */
static int stencil_step(st_fvar_step *w)
{
    st_map *m = w->m;
    size_t cap = m->darts.end, n = 0, nf = 64;
    int dual = m->face_embedded;
    memcpy(w->out_uv, w->uv, 2 * cap * sizeof *w->out_uv);
    memcpy(w->out_val, w->val, cap * sizeof *w->out_val);
    if (dual) memset(w->sub, 0, cap);
    uint32_t *faces = malloc(nf * sizeof *faces);
    if (!faces) return -1;
    int fbit = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, w->l, &it); d != ST_NIL; d = st_dart_next(m, w->l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        st_mark_face(m, fbit, d, w->l);
        if (!(dual ? st_adapt_split_toward(m, d, w->l) : st_face_is_subdivided(m, d, w->l))) continue;
        if (n == nf) {
            uint32_t *g = realloc(faces, 2 * nf * sizeof *faces);
            if (!g) { free(faces); st_marker_release(m, fbit, w->l); return -1; }
            faces = g;
            nf *= 2;
        }
        faces[n++] = d;
        uint32_t x = d;
        do { if (dual) w->sub[x] = 1; x = st_phi1(m, x, w->l); } while (x != d);
    }
    st_marker_release(m, fbit, w->l);
    int rc = st_fvar_stencil_step(&w->sv, w->scheme, w->l, w->uv, w->val, faces, (uint32_t)n, dual ? w->rank : NULL, w->out_uv,
                                  w->out_val, w->out_level);
    free(faces);
    if (!rc && dual) rc = order_children(w);
    return rc;
}

/* ---- the whole map --------------------------------------------------------------- */

int st_adapt_uv_build(st_adapt *a, st_adapt_uv *u, st_error *err)
{
    memset(u, 0, sizeof *u);
    if (st_adapt_uv_absent(a)) return ST_OK;
    st_hier *h = a->h;
    st_map *m = &h->map;
    const st_fvar *f = h->fvar;
    uint32_t cap = m->darts.end;
    size_t n = (size_t)cap + 1;
    double *buf = malloc(2 * n * sizeof *buf), *cent = malloc(2 * n * sizeof *cent);
    uint32_t *vbuf = malloc(n * sizeof *vbuf);
    uint8_t *sub = malloc(n);
    uint32_t *rank = malloc(n * sizeof *rank);
    u->uv = calloc(2 * n, sizeof *u->uv);
    u->val = calloc(n, sizeof *u->val);
    u->level = calloc(n, 1);
    int rc = !buf || !cent || !vbuf || !sub || !rank || !u->uv || !u->val || !u->level;
    for (size_t i = 0; !rc && i < n; i++) rank[i] = ST_NIL;
    if (!rc) {
        /* level 0: the hierarchy's own (level-0 darts never change while adapting) */
        uint32_t n0 = f->lv[0].cap < cap ? f->lv[0].cap : cap;
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
            if (d >= n0) continue;
            const double *p = st_fvar_uv_at(&f->lv[0], d);
            u->uv[2 * (size_t)d] = p[0];
            u->uv[2 * (size_t)d + 1] = p[1];
            u->val[d] = st_fvar_label_at(&f->lv[0], d);
        }
        u->cap = cap;
    }
    st_fvar_step w = { .sv = st_hier_view(h), .scheme = h->scheme, .m = m, .interp = f->interp, .rules = rules_of(h), .out_level = u->level,
                       .cent = cent, .sub = sub, .split_toward = split_toward, .rank = rank };
    for (unsigned L = 1; !rc && L <= m->top; L++) {
        /* the values so far go to buf/vbuf, the step writes back into u */
        memcpy(buf, u->uv, 2 * (size_t)cap * sizeof *buf);
        memcpy(vbuf, u->val, (size_t)cap * sizeof *vbuf);
        w.l = L - 1;
        w.L = L;
        w.uv = buf;
        w.val = vbuf;
        w.out_uv = u->uv;
        w.out_val = u->val;
        rc = w.rules == ST_FVAR_STENCIL ? stencil_step(&w) : step(&w);
    }
    st_fvar_step_free(&w);
    free(buf);
    free(cent);
    free(vbuf);
    free(sub);
    u->rank = rank;
    if (rc) {
        st_adapt_uv_free(u);
        return st_fail(err, ST_ERR_MEMORY, "out of memory for the adaptive mesh's texture coordinates");
    }
    return ST_OK;
}

/* ---- the displayed mesh's texture coordinates ------------------------------------ */

/* A dart's place in a regular level's scan (level, then numbering). */
static uint64_t scan_key(const st_map *m, const st_adapt_uv *u, uint32_t x)
{
    uint8_t ins = m->darts.ins[x];
    uint32_t r = ins == 0 ? x : (x < u->cap && u->rank ? u->rank[x] : ST_NIL);
    return (uint64_t)ins << 32 | r;
}

int st_adapt_uv_mesh(st_adapt *a, const st_adapt_uv *u, st_mesh *out, st_error *err)
{
    if (!u->uv) return ST_OK;
    st_map *m = &a->h->map;
    unsigned top = m->top;
    uint32_t nc = out->nfaces ? out->face_off[out->nfaces] : 0;
    st_fvar_soup so;
    if (st_fvar_soup_alloc(&so, nc)) return st_fail(err, ST_ERR_MEMORY, "out of memory for the adaptive mesh's texture coordinates");
    st_fvar_corner_key *k = so.k;
    uint32_t *darts = so.darts;
    /* The face walk of st_map_to_mesh (core/map/map_mesh.c): st_face_step
     * (no holes: adaptive Doo-Sabin refuses open meshes). */
    int fbit = st_marker_reserve(m);
    uint32_t c = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, top, &it); d != ST_NIL && c < nc; d = st_dart_next(m, top, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fbit, d)) continue;
        uint64_t face = UINT64_MAX;
        uint32_t x = d;
        do {
            uint64_t s = scan_key(m, u, x);
            face = s < face ? s : face;
            x = st_face_step(m, x, top);
        } while (x != d);
        do {
            st_mark(m, fbit, x);
            darts[c] = x;
            k[c] = (st_fvar_corner_key){ out->face_idx[c], x < u->cap ? u->level[x] : 0, x < u->cap ? u->val[x] : 0, c, face };
            c++;
            x = st_face_step(m, x, top);
        } while (x != d && c < nc);
    }
    st_marker_release(m, fbit, top);
    /* One texture coordinate per (vertex, level, value): seams stay seams,
     * and corners holding one value share one coordinate - that of the
     * face a regular level's walk meets first, as st_hier_level_mesh takes
     * it (the two sides of a smooth edge may differ in the last bit). */
    st_uv_map um = { u->uv, NULL, u->cap };
    st_fvar_soup_install(&so, out, st_fvar_soup_uvs(k, c, darts, &um, so.face_uv, so.uv));
    return ST_OK;
}
