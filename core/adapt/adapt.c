/* Adaptive refinement (adapt.h): the lifetime of an st_adapt, the choice of
 * its refinement family's operations, and the public entry points, which
 * go through them (Kraemer 2008 §3.2.2-3.2.6).
 *
 * Invariant: the family's table (adapt_internal.h) is chosen here once, from
 * the scheme, when the st_adapt is created; nothing else in core/adapt looks
 * at the scheme.  Level 0 never changes while adapting, so the base faces
 * listed here stay valid for the st_adapt's life. */
#include "core/adapt/adapt_internal.h"
#include "core/map/map_mesh.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

static const st_adapt_ops *ops_for(const st_scheme *s)
{
    switch (s->id) {
    case ST_SCHEME_CATMARK: return &st_adapt_ops_quads;
    case ST_SCHEME_LOOP:
    case ST_SCHEME_BUTTERFLY: return &st_adapt_ops_triangles;
    case ST_SCHEME_SQRT3: return &st_adapt_ops_sqrt3;
    case ST_SCHEME_DOOSABIN: return &st_adapt_ops_doosabin;
    case ST_SCHEME_QUADTRI:
    default: return &st_adapt_ops_quadtri;
    }
}

const st_adapt_ops *st_adapt_choose_ops(st_adapt *a)
{
    a->ops = ops_for(a->h->scheme);
    return a->ops;
}

int st_adapt_init(st_adapt *a, st_hier *h, st_error *err)
{
    memset(a, 0, sizeof *a);
    a->h = h;
    /* A progressive hierarchy's levels come from collapses, not from a
     * refinement of faces: its selective display reads a mesh off the
     * levels (adapt_progressive.c) and no family's operations apply. */
    const st_adapt_ops *ops = st_adapt_is_progressive(a) ? NULL : st_adapt_choose_ops(a);
    if (ops && ops->check) {
        int rc = ops->check(h, err);
        if (rc) return rc;
    }
    /* The base faces: one dart each. */
    st_map *m = &h->map;
    int fb = st_marker_reserve(m);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, 0, &it); d != ST_NIL; d = st_dart_next(m, 0, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, 0);
        st_dart_list_push(&a->base_faces, d);
    }
    st_marker_release(m, fb, 0);
    return ST_OK;
}

void st_adapt_free(st_adapt *a)
{
    st_adapt_pm_free(a);
    free(a->saved);
    free(a->parked);
    st_dart_list_free(&a->base_faces);
    st_adapt_grid_free(a->grid);
    st_dart_list_free(&a->forced_faces);
    memset(a, 0, sizeof *a);
}

int st_adapt_subdivide_face(st_adapt *a, uint32_t d, unsigned i, int restricted, st_error *err)
{
    st_map *m = &a->h->map;
    unsigned L = i + 1;
    if (st_is_boundary(m, d)) return st_fail(err, ST_ERR_INVALID, "adapt: dart %u is on a hole", d);
    if (L >= ST_MAX_LEVELS) return st_fail(err, ST_ERR_RANGE, "adapt: level %u is beyond the limit", L);
    if (st_adapt_is_progressive(a)) return st_fail(err, ST_ERR_INVALID, "adapt: a progressive hierarchy has no face subdivision");
    return st_adapt_ops_of(a)->subdivide(a, d, i, restricted, err);
}

int st_adapt_can_simplify(st_adapt *a, uint32_t d, unsigned i, int restricted)
{
    if (st_adapt_is_progressive(a)) return 0;
    return st_adapt_ops_of(a)->can_simplify(a, d, i, restricted);
}

int st_adapt_simplify_face(st_adapt *a, uint32_t d, unsigned i, st_error *err)
{
    if (st_adapt_is_progressive(a)) return st_fail(err, ST_ERR_INVALID, "adapt: a progressive hierarchy has no face simplification");
    return st_adapt_ops_of(a)->simplify(a, d, i, err);
}

const st_map *st_adapt_display_map(st_adapt *a, unsigned *level)
{
    if (st_adapt_is_progressive(a)) {
        st_error e;
        *level = 0;
        return st_adapt_pm_ensure(a, &e) ? NULL : a->pm_view;
    }
    *level = a->h->map.top;
    return &a->h->map;
}

/* ---- geometry ------------------------------------------------------------------ */

typedef struct resynth_ctx { st_hier *h; unsigned L; uint32_t gen; } resynth_ctx;

static void resynth_sink(void *ctx, const st_stencil *s)
{
    resynth_ctx *c = ctx;
    if (c->h->stamp.v[s->fine] == c->gen) return;
    c->h->stamp.v[s->fine] = c->gen;
    double p[3];
    st_stencil_apply(c->h, c->L, s, p);
    st_set_pos(&c->h->map, s->fine, c->L, p);
}

void st_adapt_synthesize(st_adapt *a, unsigned from)
{
    a->has_prev = 0; /* the geometry changed: the next update visits everything */
    st_hier *h = a->h;
    if (st_adapt_is_progressive(a)) {
        /* every level exists: the regular synthesis, then the shown
         * positions follow */
        st_hier_synthesize(h, from);
        a->has_prev = 1;
        st_error e;
        (void)st_adapt_pm_refresh(a, &e); /* only an update after a failed one can fail: it leaves no view */
        return;
    }
    st_map *m = &h->map;
    st_dart_list faces = { 0 }, sub = { 0 };
    for (unsigned L = from + 1; L <= m->top; L++) {
        st_adapt_faces_of_level(m, L - 1, &faces);
        sub.n = 0;
        for (uint32_t k = 0; k < faces.n; k++)
            if (st_face_is_subdivided(m, faces.d[k], L - 1)) st_dart_list_push(&sub, faces.d[k]);
        if (!sub.n) continue; /* (emit with no face means every vertex of level L) */
        st_adapt_canonical_faces(h, L - 1, &sub); /* the same stencils as a local pass (adapt_resynth.c) */
        resynth_ctx c = { h, L, st_hier_stamp_begin(h) };
        st_hier_emit(h, L, sub.d, sub.n, resynth_sink, &c);
    }
    st_dart_list_free(&faces);
    st_dart_list_free(&sub);
}

int st_adapt_mesh(st_adapt *a, st_mesh *out, st_error *err)
{
    if (st_adapt_is_progressive(a)) {
        /* (a session loaded field by field has the criteria, not the mesh) */
        int rc = st_adapt_pm_ensure(a, err);
        if (rc) return rc;
        return st_pm_select_mesh(a->pm, a->h, out, err);
    }
    int rc = st_map_to_mesh(&a->h->map, a->h->map.top, out, err);
    if (rc || st_adapt_uv_absent(a)) return rc;
    st_adapt_uv u;
    rc = st_adapt_uv_build(a, &u, err);
    if (!rc) rc = st_adapt_uv_mesh(a, &u, out, err);
    st_adapt_uv_free(&u);
    return rc;
}
