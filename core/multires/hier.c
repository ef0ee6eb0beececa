/* st_hier: construction, refinement, sharpness and level extraction.
 * The geometry passes are in hier_synth.c (synthesis, editing) and
 * hier_analysis.c (least-squares analysis). */
#include "core/base/membudget.h"
#include "core/multires/estimate.h"
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/map/map_mesh.h"
#include "core/map/pool_internal.h"
#include "core/schemes/crease_internal.h"
#include "core/fvar/fvar_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Dart from u to w at level 0, ST_NIL if none (walks u's β1 cycle). */
static uint32_t find_edge(const st_map *m, const uint32_t *vdart, uint32_t u, uint32_t w)
{
    uint32_t d = vdart[u];
    if (d == ST_NIL) return ST_NIL;
    uint32_t x = d;
    do {
        if (st_vert(m, st_beta0(m, x, 0), 0) == w) return x;
        x = st_beta1(m, x, 0);
    } while (x != d);
    return ST_NIL;
}

static int load_tags(st_hier *h, const st_mesh *mesh, st_error *err)
{
    if (!mesh->ncreases && !mesh->ncorners) return ST_OK;
    st_map *m = &h->map;
    uint32_t *vdart = malloc((size_t)(m->verts.end ? m->verts.end : 1) * sizeof *vdart);
    if (!vdart) return st_fail(err, ST_ERR_MEMORY, "out of memory reading creases");
    for (uint32_t v = 0; v < m->verts.end; v++) vdart[v] = ST_NIL;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) vdart[st_vert(m, d, 0)] = d;
    int rc = ST_OK;
    for (uint32_t i = 0; i < mesh->ncreases && !rc; i++) {
        uint32_t u = mesh->crease_v[2 * i], w = mesh->crease_v[2 * i + 1];
        uint32_t d = (u < mesh->nverts && w < mesh->nverts) ? find_edge(m, vdart, u, w) : ST_NIL;
        if (d == ST_NIL)
            rc = st_fail(err, ST_ERR_RANGE, "crease tag names %u-%u, which is not an edge of the mesh", u, w);
        else
            st_hier_set_edge_sharpness(h, d, 0, mesh->crease_s[i]);
    }
    for (uint32_t i = 0; i < mesh->ncorners && !rc; i++) {
        if (mesh->corner_v[i] >= mesh->nverts)
            rc = st_fail(err, ST_ERR_RANGE, "corner tag names vertex %u of %u", mesh->corner_v[i], mesh->nverts);
        else
            st_hier_set_vertex_sharpness(h, mesh->corner_v[i], 0, mesh->corner_s[i]);
    }
    free(vdart);
    return rc;
}

/* Hole faces need a scheme that splits every face into children inside it
 * (the children inherit the flag); √3 flips edges across faces and
 * Doo-Sabin and the progressive scheme are not face splits. */
static int holes_supported(const st_scheme *scheme)
{
    static const char *const primal[] = { "catmull-clark", "loop", "butterfly", "quad-triangle" };
    for (size_t i = 0; i < sizeof primal / sizeof primal[0]; i++)
        if (!strcmp(scheme->name, primal[i])) return 1;
    return 0;
}

static int mesh_has_holes(const st_mesh *mesh)
{
    for (uint32_t f = 0; mesh->face_hole && f < mesh->nfaces; f++)
        if (mesh->face_hole[f]) return 1;
    return 0;
}

static int triangles_only(const st_scheme *scheme)
{
    return scheme->id == ST_SCHEME_LOOP || scheme->id == ST_SCHEME_BUTTERFLY || scheme->id == ST_SCHEME_SQRT3 ||
           scheme->id == ST_SCHEME_PROGRESSIVE;
}

int st_scheme_accepts(const st_scheme *scheme, const st_mesh *mesh, st_error *err)
{
    if (triangles_only(scheme))
        for (uint32_t f = 0; f < mesh->nfaces; f++) {
            uint32_t n = mesh->face_off[f + 1] - mesh->face_off[f];
            if (n != 3 && !(mesh->face_hole && mesh->face_hole[f]))
                return st_fail(err, ST_ERR_TOPOLOGY, "the %s scheme needs a triangle mesh, but the mesh has a face with %u sides",
                               scheme->name, n);
        }
    if ((mesh->boundary_interp == ST_BOUNDARY_NONE || mesh_has_holes(mesh)) && !holes_supported(scheme))
        return st_fail(err, ST_ERR_INVALID, "the %s scheme has no hole faces: holes need a face-splitting scheme "
                       "(catmull-clark, loop, butterfly, quad-triangle)", scheme->name);
    return ST_OK;
}

/* Every real face around the vertex of d (level 0) becomes a hole. */
static void hole_faces_around(st_map *m, uint32_t d)
{
    uint32_t x = d;
    do {
        if (!st_is_boundary(m, x)) {
            uint32_t y = x;
            do {
                m->flags[y] |= ST_DART_HOLE;
                y = st_phi1(m, y, 0);
            } while (y != x);
        }
        x = st_beta1(m, x, 0);
    } while (x != d);
}

/* OBJ `t interpolateboundary 0` (Sdc::Options::VTX_BOUNDARY_NONE): the
 * boundary faces are not in the limit surface.  As Far's
 * prepareComponentTagsAndSharpness does, every face at a vertex with a
 * boundary edge that is not infinitely sharp becomes a hole; the rules are
 * then the edge-only ones (boundary edges infinitely sharp, no corners). */
static void boundary_none_holes(st_hier *h)
{
    st_map *m = &h->map;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
        if (!st_is_boundary(m, d) || st_hier_edge_sharpness(h, d, 0) >= ST_SHARP_INFINITE) continue;
        hole_faces_around(m, d);
        hole_faces_around(m, st_beta0(m, d, 0));
    }
}

int st_hier_init(st_hier *h, const st_mesh *mesh, const st_scheme *scheme, const st_hier_opts *opts, st_error *err)
{
    memset(h, 0, sizeof *h);
    st_map_init(&h->map);
    st_mla_init(&h->edge_sharp, sizeof(float));
    st_mla_init(&h->vertex_sharp, sizeof(float));
    h->scheme = scheme;
    h->opts.boundary = mesh->boundary_interp == ST_BOUNDARY_EDGE_AND_CORNER ? ST_BOUNDARY_EDGE_AND_CORNER : ST_BOUNDARY_EDGE_ONLY;
    h->opts.crease_method = mesh->crease_method == ST_CREASE_CHAIKIN ? ST_CREASE_CHAIKIN : ST_CREASE_UNIFORM;
    if (opts && opts->crease_method == ST_CREASE_CHAIKIN) h->opts.crease_method = ST_CREASE_CHAIKIN;
    /* A Catmull-Clark option: other schemes ignore the tag, as OpenSubdiv's
     * regression harness does. */
    h->opts.tri_sub = ST_TRI_SUB_CATMARK;
    if ((mesh->tri_sub == ST_TRI_SUB_SMOOTH || (opts && opts->tri_sub == ST_TRI_SUB_SMOOTH)) &&
        !strcmp(scheme->name, "catmull-clark"))
        h->opts.tri_sub = ST_TRI_SUB_SMOOTH;
    if (opts && opts->boundary != ST_BOUNDARY_UNSET) h->opts.boundary = opts->boundary;
    int none = mesh->boundary_interp == ST_BOUNDARY_NONE && (!opts || opts->boundary == ST_BOUNDARY_UNSET);
    int rc = ST_OK;
    if ((none || mesh_has_holes(mesh)) && !holes_supported(scheme))
        rc = st_fail(err, ST_ERR_INVALID, "%s has no hole faces (OBJ `t hole`, `t interpolateboundary 0`): "
                     "holes need a face-splitting scheme (catmull-clark, loop, butterfly, quad-triangle)",
                     scheme->name);
    if (!rc) rc = st_map_from_mesh(&h->map, mesh, err);
    if (!rc && scheme->check) {
        st_subdiv_view v = st_hier_view(h);
        rc = scheme->check(&v, err);
    }
    if (!rc) rc = load_tags(h, mesh, err);
    if (!rc && none) boundary_none_holes(h);
    h->opts.uv_interp = opts ? opts->uv_interp : ST_UV_CORNERS_PLUS1;
    if (!rc) rc = st_fvar_init(&h->fvar, &h->map, mesh, h->opts.uv_interp, err);
    if (rc) st_hier_free(h);
    else if (scheme->id != ST_SCHEME_PROGRESSIVE) {
        uint32_t end[2] = { h->map.darts.end, h->map.verts.end };
        st_hier_mark_regenerable(h, end);
    }
    return rc;
}

int st_hier_regenerable(const st_hier *h)
{
    /* The generation was handed out when it was marked (st_map_generation),
     * so any later change of the topology replaced it. */
    return h->regen_gen != 0 && h->regen_gen == h->map.gen;
}

void st_hier_mark_regenerable(st_hier *h, const uint32_t end[2])
{
    h->regen_gen = st_map_generation(&h->map);
    h->regen_end[0] = end[0];
    h->regen_end[1] = end[1];
}

/* Drops the caches of levels from..: they describe levels that moved or
 * went away (the generation check would refuse them; this frees them). */
static void drop_caches(st_hier *h, unsigned from)
{
    for (unsigned l = from; l < ST_MAX_LEVELS; l++)
        if (h->cache[l].p) {
            h->cache[l].free(h->cache[l].p);
            h->cache[l].p = NULL;
        }
    if (h->local.p) {
        h->local.free(h->local.p);
        h->local.p = NULL;
    }
}

char *st_levels_phrase(unsigned top, char *buf, size_t n)
{
    if (top == 0) snprintf(buf, n, "1 level (0)");
    else snprintf(buf, n, "%u levels (0..%u)", top + 1, top);
    return buf;
}

void st_hier_free(st_hier *h)
{
    st_map_free(&h->map);
    st_mla_free(&h->edge_sharp);
    st_mla_free(&h->vertex_sharp);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) free(h->detail[l]);
    drop_caches(h, 0);
    free(h->stamp.v);
    st_hier_uv_free(h);
    free(h->pm_recipe);
    memset(h, 0, sizeof *h);
}

st_subdiv_view st_hier_view(st_hier *h)
{
    return (st_subdiv_view){
        .map = &h->map, .edge_sharp = &h->edge_sharp, .vertex_sharp = &h->vertex_sharp,
        .has_sharpness = h->has_sharpness,
        .opts = { .boundary = h->opts.boundary, .crease_method = h->opts.crease_method, .tri_sub = h->opts.tri_sub },
        .stamp = &h->stamp, .cache = h->cache, .local = &h->local, .owner = h,
    };
}

/* ---- sharpness ------------------------------------------------------------- */

/* The sharpness attributes are attached to the map on the first crease, so
 * that every dart and vertex created later starts at zero. */
static void ensure_sharp(st_hier *h)
{
    if (h->has_sharpness) return;
    if (st_map_attach_dart_attr(&h->map, &h->edge_sharp) || st_map_attach_vertex_attr(&h->map, &h->vertex_sharp))
        abort(); /* out of memory attaching two small arrays */
    h->has_sharpness = 1;
}

float st_hier_edge_sharpness(const st_hier *h, uint32_t d, unsigned l)
{
    if (!h->has_sharpness) return 0;
    return *(const float *)st_mla_at(&h->edge_sharp, h->map.darts.ins, d, l);
}

float st_hier_vertex_sharpness(const st_hier *h, uint32_t v, unsigned l)
{
    if (!h->has_sharpness) return 0;
    return *(const float *)st_mla_at(&h->vertex_sharp, h->map.verts.ins, v, l);
}

/* This level only (the attribute's finer levels that had not diverged
 * follow it as they are); st_subdiv_store_* mark the map changed, as
 * sharpness decides which cells take the crease rules. */
static void store_edge_sharpness(st_hier *h, uint32_t d, unsigned l, float s)
{
    ensure_sharp(h);
    st_subdiv_view v = st_hier_view(h);
    st_subdiv_store_edge_sharpness(&v, d, l, s);
}

static void store_vertex_sharpness(st_hier *h, uint32_t v, unsigned l, float s)
{
    ensure_sharp(h);
    st_subdiv_view sv = st_hier_view(h);
    st_subdiv_store_vertex_sharpness(&sv, v, l, s);
}

/* Whether the edge (d, β0(d)) of level k was split at level k+1 into
 * (d, β0(d,k+1)) and (e, β0(e,k+1)) around a new midpoint (primal
 * refinement; an adaptive hierarchy may not have split it). */
static int edge_split_below(const st_hier *h, uint32_t d, unsigned k)
{
    const st_map *m = &h->map;
    uint32_t e = st_beta0(m, d, k);
    uint32_t mid = st_vert(m, st_beta0(m, d, k + 1), k + 1);
    return m->verts.ins[mid] == k + 1 && st_vert(m, st_beta0(m, e, k + 1), k + 1) == mid;
}

/* The child of the half edge of x (at x's vertex) on level k+1 takes the
 * sharpness refinement would have given it (DeRose et al. 1998,
 * OpenSubdiv's Sdc::Crease), from level k.  Returns 0 when that edge was
 * not split. */
static int derive_child_edge(st_hier *h, uint32_t x, unsigned k)
{
    if (!edge_split_below(h, x, k)) return 0;
    st_subdiv_view v = st_hier_view(h);
    float c = st_crease_child_edge_sharpness(&v, x, k);
    if (st_hier_edge_sharpness(h, x, k + 1) != c) store_edge_sharpness(h, x, k + 1, c);
    return 1;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static void push_dart(uint32_t **list, uint32_t *n, uint32_t *cap, uint32_t d)
{
    if (*n == *cap) {
        *cap = *cap ? 2 * *cap : 16;
        *list = realloc(*list, *cap * sizeof **list);
        if (!*list) abort(); /* out of memory on a few darts */
    }
    (*list)[(*n)++] = d;
}

/* A sharpness set below the top changes what refinement gave the finer
 * levels: they are derived again, level by level, as refinement would, for
 * the half edges whose parent may have changed (cur: both darts of each
 * edge).  Chaikin's rule reads every semi-sharp edge at a vertex, so there
 * every half edge at their vertices is derived again. */
static void derive_finer_edge_sharpness(st_hier *h, uint32_t d, unsigned l)
{
    const st_map *m = &h->map;
    int chaikin = h->opts.crease_method == ST_CREASE_CHAIKIN;
    uint32_t *cur = NULL, *next = NULL, ncur = 0, nnext = 0, capcur = 0, capnext = 0;
    push_dart(&cur, &ncur, &capcur, d);
    push_dart(&cur, &ncur, &capcur, st_beta0(m, d, l));
    for (unsigned k = l; k < m->top && ncur; k++) {
        if (chaikin) {
            uint32_t n = ncur;
            for (uint32_t i = 0; i < n; i++)
                for (uint32_t x = st_beta1(m, cur[i], k); x != cur[i]; x = st_beta1(m, x, k)) push_dart(&cur, &ncur, &capcur, x);
        }
        qsort(cur, ncur, sizeof *cur, cmp_u32);
        nnext = 0;
        for (uint32_t i = 0; i < ncur; i++) {
            if (i && cur[i] == cur[i - 1]) continue;
            if (!derive_child_edge(h, cur[i], k)) continue;
            push_dart(&next, &nnext, &capnext, cur[i]);
            push_dart(&next, &nnext, &capnext, st_beta0(m, cur[i], k + 1));
        }
        uint32_t *t = cur; cur = next; next = t;
        uint32_t tc = capcur; capcur = capnext; capnext = tc;
        ncur = nnext;
    }
    free(cur);
    free(next);
}

void st_hier_set_edge_sharpness(st_hier *h, uint32_t d, unsigned l, float s)
{
    store_edge_sharpness(h, d, l, s);
    derive_finer_edge_sharpness(h, d, l);
}

void st_hier_set_vertex_sharpness(st_hier *h, uint32_t v, unsigned l, float s)
{
    store_vertex_sharpness(h, v, l, s);
    for (unsigned k = l; k < h->map.top; k++) {
        s = st_crease_decay(s);
        if (st_hier_vertex_sharpness(h, v, k + 1) != s) store_vertex_sharpness(h, v, k + 1, s);
    }
}

/* ---- levels ---------------------------------------------------------------- */

int st_hier_refine_topology(st_hier *h, st_error *err)
{
    st_subdiv_view v = st_hier_view(h);
    return h->scheme->refine(&v, err);
}

int st_hier_subdivide_to(st_hier *h, unsigned levels, st_error *err)
{
    return st_hier_subdivide_to_progress(h, levels, NULL, NULL, err);
}

/* The progress callback's answer at fraction f (0: go on). */
static int cancelled(int (*progress)(void *, double), void *ctx, double f, st_error *err)
{
    if (!progress || !progress(ctx, f)) return 0;
    st_fail(err, ST_ERR_INVALID, "cancelled");
    return 1;
}

int st_hier_subdivide_to_progress(st_hier *h, unsigned levels, int (*progress)(void *ctx, double fraction),
                                  void *ctx, st_error *err)
{
    /* Level k of the new ones weighs 4^k (quadrisection's growth): a
     * fraction that moves evenly with the work. */
    unsigned from = h->map.top;
    double total = 0;
    for (unsigned l = from + 1; l <= levels; l++) total += ldexp(1.0, 2 * (int)(l - from));
    double done = 0;
    if (levels > h->map.top) {
        /* The memory guard: refused from the counts, before any level. */
        char what[64];
        snprintf(what, sizeof what, "subdividing to level %u", levels);
        int rc = st_mem_check(st_hier_estimate_subdivide(h, levels, NULL), what, err);
        if (rc) return rc;
    }
    int regen = st_hier_regenerable(h);
    while (h->map.top < levels) {
        double w = ldexp(1.0, 2 * (int)(h->map.top + 1 - from));
        if (cancelled(progress, ctx, done / total, err)) return ST_ERR_INVALID;
        int rc = st_hier_refine_topology(h, err);
        if (!rc) {
            st_subdiv_view v = st_hier_view(h);
            rc = st_fvar_refine(h->fvar, &v, h->scheme, err);
        }
        if (rc) return rc;
        drop_caches(h, 0); /* stale now: their memory back before the next level */
        if (cancelled(progress, ctx, (done + w / 2) / total, err)) return ST_ERR_INVALID;
        st_hier_synthesize(h, h->map.top - 1);
        done += w;
        /* A refinement of a regenerable hierarchy is one too. */
        if (regen) st_hier_mark_regenerable(h, h->regen_end);
    }
    if (total > 0 && cancelled(progress, ctx, 1.0, err)) return ST_ERR_INVALID;
    return ST_OK;
}

void st_hier_remove_top(st_hier *h)
{
    unsigned l = h->map.top;
    if (l == 0) return;
    drop_caches(h, l - 1);
    free(h->detail[l]);
    h->detail[l] = NULL;
    h->detail_cap[l] = 0;
    st_fvar_remove_top(h->fvar, l);
    st_level_remove_top(&h->map);
}

void st_hier_remove_bottom(st_hier *h)
{
    if (h->map.top == 0) return;
    drop_caches(h, 0);
    /* Level 1's details are now part of the control mesh's positions. */
    free(h->detail[1]);
    for (unsigned l = 1; l + 1 < ST_MAX_LEVELS; l++) {
        h->detail[l] = h->detail[l + 1];
        h->detail_cap[l] = h->detail_cap[l + 1];
    }
    h->detail[ST_MAX_LEVELS - 1] = NULL;
    h->detail_cap[ST_MAX_LEVELS - 1] = 0;
    if (h->map.face_embedded) {
        /* Dual encoding: the control vertices are not carried by level 1,
         * whose own vertices become the control mesh. */
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, 0, &it); v != ST_NIL; v = st_vertex_next(&h->map, 0, &it))
            st_vertex_delete(&h->map, v);
    }
    st_fvar_remove_bottom(&h->fvar, h->map.top);
    st_level_remove_bottom(&h->map);
}

int st_hier_level_mesh(st_hier *h, unsigned l, st_mesh *out, st_error *err)
{
    int rc = st_map_to_mesh(&h->map, l, out, err);
    if (!rc) rc = st_fvar_level_mesh(h->fvar, &h->map, l, out, err);
    return rc;
}
