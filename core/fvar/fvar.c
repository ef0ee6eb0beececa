/* Face-varying UVs at every level (fvar.h).
 *
 * Each level stores a UV and a value label per dart (a face corner).  A
 * level L made by primal quadrisection (core/map/refine.c) keeps every dart
 * of level L-1: an old dart d of a coarse face f runs at L from its corner
 * to the midpoint of its edge, inside the child face of f at that corner
 * (quad n(d_{i-1}), d_i, in_i, out_{i-1}, or triangle n(d_{i-1}), d_i, t_{i-1}).
 * So a fine corner is found from the one old dart of its face: at offset 0
 * the child of the coarse vertex, 1 the child of d's edge, 2 in a quad the
 * child of f, last the child of the previous edge of f; the inner triangle
 * of a triangle split has no old dart and takes its corners from the corner
 * triangles across its edges.  Each child value is written straight to the
 * fine corners that hold it (face children first: the edge and vertex
 * rules of Catmull-Clark read them back from there).
 *
 * The rules are OpenSubdiv's (Far::PrimvarRefiner::InterpolateFaceVarying,
 * the tags of Vtr::FVarLevel), evaluated on each level afresh rather than
 * inherited from level 0 (the same classification for the rules below):
 *   - an edge is a face-varying boundary (discontinuous) when the values at
 *     either end differ between its two faces (value labels, not UV
 *     coordinates: OpenSubdiv compares indices); its child takes the
 *     midpoint on each side, like a mesh boundary edge;
 *   - a vertex all of whose corners share one value and whose edges are
 *     continuous takes the vertex rule of the scheme (smooth, dart, crease,
 *     corner, semi-sharp blends) applied to the face-varying values;
 *   - otherwise each value is a corner (kept) or a crease (3/4 v + 1/8 of the
 *     two ends of its boundary edges) as FVarLinearInterpolation decides:
 *     see docs/SUBDIVISION-RULES.md §7b.
 * Semi-sharp creases inside a face-varying boundary take the plain crease
 * rule (OpenSubdiv blends toward a corner there).
 *
 * A level's values depend on the relations of levels L-1 and L only, so
 * they may come with each level (st_fvar_refine after the scheme's
 * refine()) or once the topology is complete (st_fvar_refine_levels, as a
 * task of its own beside the positions): the same bits either way.
 */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/base/hugepage.h"
#include "core/fvar/fvar_internal.h"
#include "core/map/pool_internal.h"
#include "core/schemes/scheme.h"

#include <stdlib.h>
#include <string.h>

static const char *const interp_names[ST_UV_INTERP_COUNT] = {
    "corners-plus1", "none", "corners-only", "corners-plus2", "boundaries", "all",
};

int st_uv_interp_find(const char *name)
{
    for (int i = 0; name && i < ST_UV_INTERP_COUNT; i++)
        if (strcmp(name, interp_names[i]) == 0) return i;
    return -1;
}

const char *st_uv_interp_name(int interp)
{
    return interp >= 0 && interp < ST_UV_INTERP_COUNT ? interp_names[interp] : "?";
}

static void level_free(st_fvar_level *lv)
{
    free(lv->uv);
    free(lv->val);
    free(lv->idx);
    memset(lv, 0, sizeof *lv);
}

/* A dense level of cap dart ids, zeroed. */
static int level_alloc(st_fvar_level *lv, uint32_t cap)
{
    memset(lv, 0, sizeof *lv);
    lv->cap = cap;
    lv->uv = calloc(2 * (size_t)cap + 2, sizeof *lv->uv);
    lv->val = calloc((size_t)cap + 1, sizeof *lv->val);
    st_advise_huge(lv->uv, (2 * (size_t)cap + 2) * sizeof *lv->uv);
    st_advise_huge(lv->val, ((size_t)cap + 1) * sizeof *lv->val);
    if (lv->uv && lv->val) return 0;
    level_free(lv);
    return -1;
}

void st_fvar_free(st_fvar *f)
{
    if (!f) return;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) level_free(&f->lv[l]);
    free(f);
}

/* ---- level 0 ---------------------------------------------------------------- */

/* The dart of level 0 leaving u along the real face whose next vertex is w.
 * In Doo-Sabin's dual encoding a surface face is a β1 orbit and a surface
 * vertex a φ1 orbit (scheme_doosabin.c): the corner is still one dart. */
static uint32_t corner_dart(const st_map *m, uint32_t start, uint32_t w)
{
    uint32_t x = start;
    do {
        if (!st_is_boundary(m, x) && st_vert(m, st_face_step(m, x, 0), 0) == w) return x;
        x = st_vertex_step(m, x, 0);
    } while (x != start);
    return ST_NIL;
}

int st_fvar_init(st_fvar **out, const st_map *m, const st_mesh *mesh, int interp, st_error *err)
{
    *out = NULL;
    if (!mesh->face_uv) return ST_OK;
    st_fvar *f = calloc(1, sizeof *f);
    uint32_t *vdart = malloc((size_t)(m->verts.end ? m->verts.end : 1) * sizeof *vdart);
    if (!f || !vdart || level_alloc(&f->lv[0], m->darts.end)) {
        if (f) level_free(&f->lv[0]);
        free(f);
        free(vdart);
        return st_fail(err, ST_ERR_MEMORY, "out of memory for texture coordinates");
    }
    f->interp = interp;
    for (uint32_t v = 0; v < m->verts.end; v++) vdart[v] = ST_NIL;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) vdart[st_vert(m, d, 0)] = d;
    int rc = ST_OK;
    for (uint32_t fi = 0; fi < mesh->nfaces && !rc; fi++) {
        uint32_t a = mesh->face_off[fi], n = mesh->face_off[fi + 1] - a;
        for (uint32_t j = 0; j < n && !rc; j++) {
            uint32_t u = mesh->face_idx[a + j], w = mesh->face_idx[a + (j + 1) % n], t = mesh->face_uv[a + j];
            uint32_t d = u < m->verts.end && vdart[u] != ST_NIL ? corner_dart(m, vdart[u], w) : ST_NIL;
            if (d == ST_NIL || t >= mesh->nuvs) {
                rc = st_fail(err, ST_ERR_INVALID, "face %u corner %u: no such corner in the map, or a bad texture coordinate", fi, j);
                break;
            }
            f->lv[0].uv[2 * (size_t)d] = mesh->uv[2 * (size_t)t];
            f->lv[0].uv[2 * (size_t)d + 1] = mesh->uv[2 * (size_t)t + 1];
            f->lv[0].val[d] = t;
        }
    }
    free(vdart);
    f->levels = 1;
    if (!rc && st_fvar_level_compact(&f->lv[0], m, 0))
        rc = st_fail(err, ST_ERR_MEMORY, "out of memory for texture coordinates");
    if (rc) st_fvar_free(f);
    else *out = f;
    return rc;
}

/* ---- the children of level l, written into level L ----------------------- */

/* Primal quadrisection schemes take the rules of fvar_rules.c; √3 and
 * Doo-Sabin those of fvar_stencil.c. */
int st_fvar_rules_of(const st_scheme *scheme)
{
    switch (scheme->id) {
    case ST_SCHEME_CATMARK: return ST_FVAR_CATMARK;
    case ST_SCHEME_LOOP: return ST_FVAR_LOOP;
    case ST_SCHEME_BUTTERFLY:
    case ST_SCHEME_QUADTRI: return ST_FVAR_LINEAR;
    case ST_SCHEME_SQRT3:
    case ST_SCHEME_DOOSABIN: return ST_FVAR_STENCIL;
    default: return -1;
    }
}

int st_fvar_continues(const st_fvar *f, unsigned top, const st_scheme *scheme)
{
    return f && f->levels == top + 1 && st_fvar_rules_of(scheme) >= 0;
}

/* The dart ids of levels 0..L: a level's arrays need no room for the
 * darts of finer levels the map may already hold (the same as the map's
 * ids when L is its top, short of spare blocks). */
static uint32_t level_darts(const st_map *m, unsigned L)
{
    uint32_t c = st_pool_cover(&m->darts, L + 1);
    return c < m->darts.end ? c : m->darts.end;
}

static int refine_failed(st_error *err, unsigned L)
{
    return st_fail(err, ST_ERR_MEMORY, "out of memory subdividing texture coordinates to level %u", L);
}

/* Level L's values from level L-1's (f->levels == L, the map at level L
 * or finer).  Every pass reads the relations of levels L-1 and L only
 * (st_fvar_step's views), so it gives the same bits whether the map's top
 * is L or finer. */
static int refine_level(st_fvar *f, const st_subdiv_view *sv, const st_scheme *scheme, unsigned L, st_error *err)
{
    st_map *m = sv->map;
    int rules = st_fvar_rules_of(scheme);
    if (level_alloc(&f->lv[L], level_darts(m, L))) return refine_failed(err, L);
    if (rules == ST_FVAR_STENCIL) {
        if (st_fvar_refine_stencil(sv, scheme, &f->lv[L - 1], &f->lv[L]) || st_fvar_level_compact(&f->lv[L], m, L)) {
            level_free(&f->lv[L]);
            return refine_failed(err, L);
        }
        f->levels = L + 1;
        return ST_OK;
    }
    st_fvar_step w = { .sv = *sv, .m = m, .l = L - 1, .L = L, .interp = f->interp, .rules = rules };
    w.uv = f->lv[L - 1].uv;
    w.val = f->lv[L - 1].val;
    w.idx = f->lv[L - 1].idx;
    w.out_uv = f->lv[L].uv;
    w.out_val = f->lv[L].val;
    int rc = st_fvar_face_children(&w);
    if (!rc) st_fvar_edge_children(&w);
    if (!rc) rc = st_fvar_vertex_children(&w);
    if (!rc) st_fvar_inner_triangles(&w);
    st_fvar_step_free(&w);
    if (!rc) rc = st_fvar_level_compact(&f->lv[L], m, L);
    if (rc) {
        level_free(&f->lv[L]);
        return refine_failed(err, L);
    }
    f->levels = L + 1;
    return ST_OK;
}

int st_fvar_refine(st_fvar *f, const st_subdiv_view *sv, const st_scheme *scheme, st_error *err)
{
    unsigned L = sv->map->top;
    if (L == 0 || !f || f->levels != L || st_fvar_rules_of(scheme) < 0) return ST_OK;
    return refine_level(f, sv, scheme, L, err);
}

int st_fvar_refine_levels(st_fvar *f, const st_subdiv_view *sv, const st_scheme *scheme, unsigned upto, st_error *err)
{
    int rules = st_fvar_rules_of(scheme);
    unsigned top = sv->map->top;
    if (!f || rules < 0 || f->levels > upto) return ST_OK;
    if (upto > top)
        return st_fail(err, ST_ERR_INVALID, "texture coordinates to level %u of a hierarchy of %u levels", upto, top + 1);
    /* √3's and Doo-Sabin's stencils come from the scheme's emit(), which
     * reads the top level, and mark the map's darts: level by level with
     * the topology only (st_fvar_refine). */
    if (rules == ST_FVAR_STENCIL && (f->levels != upto || upto != top))
        return st_fail(err, ST_ERR_INVALID, "texture coordinates of %s refine with each level, not after", scheme->name);
    int rc = ST_OK;
    for (unsigned L = f->levels; L <= upto && !rc; L++) rc = refine_level(f, sv, scheme, L, err);
    return rc;
}

/* ---- levels removed, copies, soups ---------------------------------------------- */

void st_fvar_remove_top(st_fvar *f, unsigned top)
{
    if (!f || top == 0 || f->levels <= top) return;
    level_free(&f->lv[top]);
    f->levels = top;
}

void st_fvar_remove_bottom(st_fvar **fp, unsigned top)
{
    st_fvar *f = *fp;
    if (!f || top == 0) return;
    level_free(&f->lv[0]);
    memmove(&f->lv[0], &f->lv[1], (ST_MAX_LEVELS - 1) * sizeof f->lv[0]);
    memset(&f->lv[ST_MAX_LEVELS - 1], 0, sizeof f->lv[0]);
    if (f->levels) f->levels--;
    if (!f->levels) {
        st_fvar_free(f);
        *fp = NULL;
    }
}

static int level_copy(st_fvar_level *dst, const st_fvar_level *src)
{
    size_t n = src->idx ? src->nvals : src->cap;
    *dst = (st_fvar_level){ src->cap, src->nvals, malloc(2 * n * sizeof *dst->uv + 1), malloc(n * sizeof *dst->val + 1),
                            src->idx ? malloc((size_t)src->cap * sizeof *dst->idx + 1) : NULL };
    if (!dst->uv || !dst->val || (src->idx && !dst->idx)) {
        level_free(dst);
        return -1;
    }
    memcpy(dst->uv, src->uv, 2 * n * sizeof *dst->uv);
    memcpy(dst->val, src->val, n * sizeof *dst->val);
    if (src->idx) memcpy(dst->idx, src->idx, (size_t)src->cap * sizeof *dst->idx);
    return 0;
}

int st_fvar_copy(st_fvar **dst, const st_fvar *f)
{
    *dst = NULL;
    if (!f) return 0;
    st_fvar *g = calloc(1, sizeof *g);
    if (!g) return -1;
    g->interp = f->interp;
    g->levels = f->levels;
    for (unsigned l = 0; l < f->levels; l++)
        if (level_copy(&g->lv[l], &f->lv[l])) { st_fvar_free(g); return -1; }
    *dst = g;
    return 0;
}

static int cmp_corner_key(const void *pa, const void *pb)
{
    const st_fvar_corner_key *a = pa, *b = pb;
    if (a->vert != b->vert) return a->vert < b->vert ? -1 : 1;
    if (a->level != b->level) return a->level < b->level ? -1 : 1;
    if (a->label != b->label) return a->label < b->label ? -1 : 1;
    if (a->face != b->face) return a->face < b->face ? -1 : 1;
    return (a->corner > b->corner) - (a->corner < b->corner);
}

uint32_t st_fvar_soup_uvs(st_fvar_corner_key *k, uint32_t c, const uint32_t *darts, const st_uv_map *uv,
                          uint32_t *face_uv, double *out_uv)
{
    /* One texture coordinate per (vertex, level, value): seams stay seams. */
    qsort(k, c, sizeof *k, cmp_corner_key);
    uint32_t nuv = 0;
    for (uint32_t i = 0; i < c; i++) {
        if (i == 0 || k[i].vert != k[i - 1].vert || k[i].level != k[i - 1].level || k[i].label != k[i - 1].label) {
            uint32_t x = darts[k[i].corner];
            const double *p = x < uv->cap ? st_uv_map_at(uv, x) : NULL;
            out_uv[2 * (size_t)nuv] = p ? p[0] : 0;
            out_uv[2 * (size_t)nuv + 1] = p ? p[1] : 0;
            nuv++;
        }
        face_uv[k[i].corner] = nuv - 1;
    }
    return nuv;
}

/* The corners of level l in the face walk of st_map_to_mesh
 * (core/map/map_mesh.c): φ1 orbits, or in the dual encoding β1 orbits,
 * faces with a hole dart or under 3 corners left out. */
static uint32_t level_corners(st_map *m, unsigned l, uint32_t *darts, uint32_t nc)
{
    int dual = m->face_embedded, fbit = st_marker_reserve(m);
    uint32_t c = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL && c < nc; d = st_dart_next(m, l, &it)) {
        if ((!dual && st_is_boundary(m, d)) || st_marked(m, fbit, d)) continue;
        uint32_t x = d, start = c;
        int real = 1;
        do {
            st_mark(m, fbit, x);
            if (st_is_boundary(m, x)) real = 0;
            else if (c < nc) darts[c++] = x;
            x = st_face_step(m, x, l);
        } while (x != d);
        if (dual && (!real || c - start < 3)) c = start;
    }
    st_marker_release(m, fbit, l);
    return c;
}

int st_fvar_soup_alloc(st_fvar_soup *s, uint32_t nc)
{
    s->k = malloc(((size_t)nc + 1) * sizeof *s->k);
    s->darts = malloc(((size_t)nc + 1) * sizeof *s->darts);
    s->face_uv = malloc(((size_t)nc + 1) * sizeof *s->face_uv);
    s->uv = malloc(2 * ((size_t)nc + 1) * sizeof *s->uv);
    if (s->k && s->darts && s->face_uv && s->uv) return 0;
    free(s->k);
    free(s->darts);
    free(s->face_uv);
    free(s->uv);
    *s = (st_fvar_soup){ 0 };
    return -1;
}

void st_fvar_soup_install(st_fvar_soup *s, st_mesh *out, uint32_t nuvs)
{
    free(s->k);
    free(s->darts);
    free(out->face_uv);
    free(out->uv);
    out->face_uv = s->face_uv;
    out->uv = s->uv;
    out->nuvs = nuvs;
    *s = (st_fvar_soup){ 0 };
}

/* The corners of one vertex (perm[0..n), in corner order) by label, then
 * corner: insertion sort, the rings being short; a long one (a pole) by
 * qsort on (label, corner) keys. */
typedef struct label_corner { uint32_t label, corner; } label_corner;

static int cmp_label_corner(const void *pa, const void *pb)
{
    const label_corner *a = pa, *b = pb;
    if (a->label != b->label) return a->label < b->label ? -1 : 1;
    return (a->corner > b->corner) - (a->corner < b->corner);
}

static int sort_ring(uint32_t *perm, uint32_t n, const uint32_t *label)
{
    if (n <= 32) {
        for (uint32_t i = 1; i < n; i++) {
            uint32_t c = perm[i], j = i;
            for (; j > 0 && label[perm[j - 1]] > label[c]; j--) perm[j] = perm[j - 1];
            perm[j] = c;
        }
        return 0;
    }
    label_corner *k = malloc((size_t)n * sizeof *k);
    if (!k) return -1;
    for (uint32_t i = 0; i < n; i++) k[i] = (label_corner){ label[perm[i]], perm[i] };
    qsort(k, n, sizeof *k, cmp_label_corner);
    for (uint32_t i = 0; i < n; i++) perm[i] = k[i].corner;
    free(k);
    return 0;
}

/* The same texture coordinates as st_fvar_soup_uvs gives for keys
 * (vertex, 0, label, corner, 0), without sorting every corner: the
 * corners bucketed by vertex (a counting sort, corner order kept), each
 * bucket by label.  One coordinate per (vertex, label), the value of its
 * first corner; labels[] (per corner, then reused) and the buckets take
 * 8 bytes per corner where the sort took 64. */
static int level_soup_uvs(const st_fvar_level *lv, const st_mesh *out, const uint32_t *darts, uint32_t c,
                          uint32_t *face_uv, double *out_uv, uint32_t *nuvs)
{
    uint32_t nv = out->nverts;
    uint32_t *off = calloc((size_t)nv + 2, sizeof *off), *perm = malloc(((size_t)c + 1) * sizeof *perm);
    uint32_t *label = malloc(((size_t)c + 1) * sizeof *label);
    int rc = off && perm && label ? 0 : -1;
    for (uint32_t i = 0; !rc && i < c; i++) {
        uint32_t d = darts[i];
        label[i] = d < lv->cap ? st_fvar_label_at(lv, d) : 0;
        off[out->face_idx[i] + 2]++;
    }
    for (uint32_t v = 0; !rc && v < nv; v++) off[v + 2] += off[v + 1];
    for (uint32_t i = 0; !rc && i < c; i++) perm[off[out->face_idx[i] + 1]++] = i;
    uint32_t n = 0;
    for (uint32_t v = 0; !rc && v < nv; v++) {
        uint32_t a = off[v], b = off[v + 1];
        rc = sort_ring(perm + a, b - a, label);
        for (uint32_t j = a; !rc && j < b; j++) {
            uint32_t k = perm[j];
            if (j == a || label[k] != label[perm[j - 1]]) {
                uint32_t d = darts[k];
                const double *p = d < lv->cap ? st_fvar_uv_at(lv, d) : NULL;
                out_uv[2 * (size_t)n] = p ? p[0] : 0;
                out_uv[2 * (size_t)n + 1] = p ? p[1] : 0;
                n++;
            }
            face_uv[k] = n - 1;
        }
    }
    free(off);
    free(perm);
    free(label);
    *nuvs = n;
    return rc;
}

int st_fvar_level_mesh(const st_fvar *f, st_map *m, unsigned l, st_mesh *out, st_error *err)
{
    if (!f || l >= f->levels) return ST_OK;
    const st_fvar_level *lv = &f->lv[l];
    uint32_t nc = out->nfaces ? out->face_off[out->nfaces] : 0, nuvs = 0;
    uint32_t *darts = malloc(((size_t)nc + 1) * sizeof *darts), *face_uv = malloc(((size_t)nc + 1) * sizeof *face_uv);
    double *uv = malloc(2 * ((size_t)nc + 1) * sizeof *uv);
    int rc = darts && face_uv && uv ? 0 : -1;
    if (!rc) rc = level_soup_uvs(lv, out, darts, level_corners(m, l, darts, nc), face_uv, uv, &nuvs);
    free(darts);
    if (rc) {
        free(face_uv);
        free(uv);
        return st_fail(err, ST_ERR_MEMORY, "out of memory extracting the texture coordinates of level %u", l);
    }
    double *shrunk = realloc(uv, 2 * ((size_t)nuvs + 1) * sizeof *uv);
    free(out->face_uv);
    free(out->uv);
    out->face_uv = face_uv;
    out->uv = shrunk ? shrunk : uv;
    out->nuvs = nuvs;
    return ST_OK;
}
