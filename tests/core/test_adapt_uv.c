/* Face-varying UVs of adaptive meshes (core/adapt/adapt_uv.c, adapt.h "UVs")
 * on shared meshes with UV seams, for every scheme that has UVs above
 * level 0: an empty box gives the base level's UVs, a box over everything
 * the maximum level's (bit for bit), and with a box in part of the mesh
 * every face whose vertices all have level L holds the regular level-L UVs
 * (bit for bit but for the last bit of Catmull-Clark's edge points, whose
 * two sides differ there on the regular level too); the corners of
 * one vertex all hold values of one level (so faces sharing an edge inside
 * an island share its ends' values: no new seams), and the seams are those
 * of the regular level where everything is refined.  √3 (the stencil
 * rules of core/fvar/fvar_stencil.c) is checked the same way, but for its
 * odd triangles, which no regular level has, and so is Doo-Sabin (the same
 * rules through its dual encoding: a face is a β1 orbit there, a vertex a
 * φ1 orbit), whose border polygons mix levels and every other face is a
 * regular level's.  Both also give, after the box moved (refined,
 * simplified, refined again), the UVs of the final box applied at once. */
#include "testlib.h"

#include "core/adapt/adapt.h"
#include "core/fvar/fvar_internal.h"
#include "core/io/mesh.h"
#include "core/multires/hier.h"
#include "core/schemes/scheme.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MESHES STRATA_SHARED_DATA "/"

static int load_hier(st_hier *h, const char *path, st_scheme_id id, int interp, unsigned levels)
{
    st_mesh m;
    st_error err = { 0 };
    st_mesh_init(&m);
    int rc = st_mesh_load(path, &m, &err);
    CHECKF(rc == ST_OK, "%s: %s", path, err.msg);
    if (rc) return rc;
    st_hier_opts o = { .boundary = ST_BOUNDARY_UNSET, .uv_interp = interp };
    rc = st_hier_init(h, &m, st_scheme_get(id), &o, &err);
    CHECKF(rc == ST_OK, "%s: %s", path, err.msg);
    st_mesh_free(&m);
    if (!rc) rc = st_hier_subdivide_to(h, levels, &err);
    CHECKF(rc == ST_OK, "%s: subdividing: %s", path, err.msg);
    return rc;
}

/* ---- corners of two meshes matched by place ------------------------------- */

typedef struct face_key { double c[3]; uint32_t f; } face_key;

static int cmp_fx(const void *a, const void *b)
{
    double x = ((const face_key *)a)->c[0], y = ((const face_key *)b)->c[0];
    return (x > y) - (x < y);
}

static void centroid(const st_mesh *m, uint32_t f, double c[3])
{
    uint32_t a = m->face_off[f], n = m->face_off[f + 1] - a;
    c[0] = c[1] = c[2] = 0;
    for (uint32_t j = 0; j < n; j++)
        for (int k = 0; k < 3; k++) c[k] += m->pos[3 * (size_t)m->face_idx[a + j] + k] / n;
}

typedef struct index { face_key *k; uint32_t n; } index;

static index index_faces(const st_mesh *m)
{
    index ix = { malloc(((size_t)m->nfaces + 1) * sizeof *ix.k), m->nfaces };
    for (uint32_t f = 0; f < m->nfaces; f++) {
        centroid(m, f, ix.k[f].c);
        ix.k[f].f = f;
    }
    qsort(ix.k, ix.n, sizeof *ix.k, cmp_fx);
    return ix;
}

/* The face of ref whose centroid is c (within tol), or UINT32_MAX. */
static uint32_t find_face(const index *ix, const double c[3], double tol)
{
    uint32_t lo = 0, hi = ix->n;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (ix->k[mid].c[0] < c[0] - tol) lo = mid + 1; else hi = mid;
    }
    for (uint32_t i = lo; i < ix->n && ix->k[i].c[0] <= c[0] + tol; i++)
        if (fabs(ix->k[i].c[1] - c[1]) <= tol && fabs(ix->k[i].c[2] - c[2]) <= tol) return ix->k[i].f;
    return UINT32_MAX;
}

/* The UV of the corner of face f of ref at position p, or NULL. */
static const double *corner_uv(const st_mesh *ref, uint32_t f, const double *p, double tol)
{
    for (uint32_t j = ref->face_off[f]; j < ref->face_off[f + 1]; j++) {
        const double *q = ref->pos + 3 * (size_t)ref->face_idx[j];
        if (fabs(p[0] - q[0]) <= tol && fabs(p[1] - q[1]) <= tol && fabs(p[2] - q[2]) <= tol)
            return ref->uv + 2 * (size_t)ref->face_uv[j];
    }
    return NULL;
}

typedef struct cmp_stats { uint32_t corners, exact, unmatched; double worst; } cmp_stats;

static void compare_corner(cmp_stats *s, const double *got, const double *want)
{
    s->corners++;
    if (!want) { s->unmatched++; return; }
    double d = fmax(fabs(got[0] - want[0]), fabs(got[1] - want[1]));
    s->worst = fmax(s->worst, d);
    s->exact += got[0] == want[0] && got[1] == want[1];
}

/* Every corner of mesh a against the corner of b at the same place. */
static cmp_stats compare_meshes(const st_mesh *a, const st_mesh *b, double tol)
{
    cmp_stats s = { 0 };
    index ix = index_faces(b);
    for (uint32_t f = 0; f < a->nfaces; f++) {
        double c[3];
        centroid(a, f, c);
        uint32_t g = find_face(&ix, c, tol);
        for (uint32_t j = a->face_off[f]; j < a->face_off[f + 1]; j++) {
            const double *want = g == UINT32_MAX ? NULL : corner_uv(b, g, a->pos + 3 * (size_t)a->face_idx[j], tol);
            compare_corner(&s, a->uv + 2 * (size_t)a->face_uv[j], want);
        }
    }
    free(ix.k);
    return s;
}

/* Edges whose two faces name different texture coordinates at an end. */
static uint32_t seam_edges(const st_mesh *m)
{
    typedef struct he { uint32_t a, b, ta, tb; } he;
    uint32_t nc = m->face_off[m->nfaces], n = 0;
    he *e = malloc(((size_t)nc + 1) * sizeof *e);
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t a = m->face_off[f], k = m->face_off[f + 1] - a;
        for (uint32_t j = 0; j < k; j++) {
            uint32_t u = m->face_idx[a + j], v = m->face_idx[a + (j + 1) % k];
            e[n++] = (he){ u, v, m->face_uv[a + j], m->face_uv[a + (j + 1) % k] };
        }
    }
    uint32_t seams = 0;
    for (uint32_t i = 0; i < n; i++)   /* each interior edge once: from its half with a < b */
        for (uint32_t j = 0; j < n && e[i].a < e[i].b; j++)
            if (e[j].a == e[i].b && e[j].b == e[i].a) {
                seams += e[j].ta != e[i].tb || e[j].tb != e[i].ta;
                break;
            }
    free(e);
    return seams;
}

/* ---- the cases ---------------------------------------------------------------- */

typedef struct uv_case {
    const char *file;
    st_scheme_id id;
    int interp;
    unsigned max;
} uv_case;

static void adapt_mesh(st_hier *h, const st_adapt_params *p, st_mesh *out, st_adapt *a)
{
    st_error err = { 0 };
    CHECK(st_adapt_init(a, h, &err) == ST_OK);
    CHECKF(st_adapt_update(a, p, &err) == ST_OK, "%s", err.msg);
    st_mesh_init(out);
    CHECKF(st_adapt_mesh(a, out, &err) == ST_OK, "%s", err.msg);
}

static void check_against_level(const uv_case *c, const st_adapt_params *p, unsigned level, const char *what)
{
    st_hier h, r;
    st_adapt a;
    st_mesh got, want;
    st_error err = { 0 };
    if (load_hier(&h, c->file, c->id, c->interp, 0) || load_hier(&r, c->file, c->id, c->interp, level)) return;
    adapt_mesh(&h, p, &got, &a);
    st_mesh_init(&want);
    CHECK(st_hier_level_mesh(&r, level, &want, &err) == ST_OK);
    CHECKF(got.face_uv && want.face_uv, "%s %s: UVs (adaptive %p, regular %p)", c->file, what, (void *)got.face_uv,
           (void *)want.face_uv);
    if (got.face_uv && want.face_uv) {
        CHECKF(got.nfaces == want.nfaces, "%s %s: %u faces, level %u has %u", c->file, what, got.nfaces, level, want.nfaces);
        cmp_stats s = compare_meshes(&got, &want, 1e-7);
        printf("%s %s %s (level %u): %u corners, %u bit-exact, worst %.3g, %u unmatched; %u seam edges (regular %u)\n",
               c->file, st_scheme_get(c->id)->name, what, level, s.corners, s.exact, s.worst, s.unmatched,
               seam_edges(&got), seam_edges(&want));
        CHECKF(s.corners > 0 && s.unmatched == 0, "%s %s: %u corners unmatched", c->file, what, s.unmatched);
        CHECKF(s.worst <= 1e-12, "%s %s: adaptive vs regular level %u UVs differ by %g", c->file, what, level, s.worst);
        CHECKF(s.exact == s.corners, "%s %s: level %u: %u of %u corners bit-exact", c->file, what, level, s.exact, s.corners);
        CHECKF(got.nuvs == want.nuvs, "%s %s: %u texture coordinates, regular %u", c->file, what, got.nuvs, want.nuvs);
        CHECKF(seam_edges(&got) == seam_edges(&want), "%s %s: seams differ", c->file, what);
    }
    st_mesh_free(&got);
    st_mesh_free(&want);
    st_adapt_free(&a);
    st_hier_free(&h);
    st_hier_free(&r);
}

/* A box over part of the mesh: faces whose corners all hold values of
 * their own level L against regular level L, one level per vertex. */
/* Vertices of the adaptive map whose (non-boundary) corners hold values of
 * more than one level: 0 when faces sharing an edge inside an island hold one
 * value at its ends. */
static uint32_t mixed_level_vertices(st_map *m, unsigned top, const uint8_t *level)
{
    uint32_t mixed = 0;
    st_dart_iter it;
    int vb = st_marker_reserve(m);
    for (uint32_t d = st_dart_first(m, top, &it); d != ST_NIL; d = st_dart_next(m, top, &it)) {
        if (st_marked(m, vb, d)) continue;
        int lev = -1, counted = 0;
        uint32_t x = d;
        do {
            st_mark(m, vb, x);
            if (!st_is_boundary(m, x) && !counted) {
                if (lev >= 0 && lev != level[x]) { mixed++; counted = 1; }
                lev = level[x];
            }
            x = st_vertex_step(m, x, top);
        } while (x != d);
    }
    st_marker_release(m, vb, top);
    return mixed;
}

static void check_partial(const uv_case *c)
{
    st_hier h, r;
    st_adapt a;
    st_mesh shown;
    st_error err = { 0 };
    if (load_hier(&h, c->file, c->id, c->interp, 0) || load_hier(&r, c->file, c->id, c->interp, c->max)) return;
    /* the box: around the first vertex of level 0, a fifth of the extent */
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    st_dart_iter it;
    uint32_t v0 = st_vertex_first(&h.map, 0, &it);
    for (uint32_t v = v0; v != ST_NIL; v = st_vertex_next(&h.map, 0, &it))
        for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], st_pos(&h.map, v, 0)[k]); hi[k] = fmax(hi[k], st_pos(&h.map, v, 0)[k]); }
    st_adapt_params p = { .base_level = 0, .max_level = c->max, .has_box = 1 };
    for (int k = 0; k < 3; k++) {
        double mid = st_pos(&h.map, v0, 0)[k], half = 0.2 * (hi[k] - lo[k]);
        p.box_lo[k] = mid - half;
        p.box_hi[k] = mid + half;
    }
    adapt_mesh(&h, &p, &shown, &a);
    st_adapt_uv u;
    CHECK(st_adapt_uv_build(&a, &u, &err) == ST_OK);
    st_mesh want[ST_MAX_LEVELS];
    index ix[ST_MAX_LEVELS];
    for (unsigned l = 0; l <= c->max; l++) {
        st_mesh_init(&want[l]);
        CHECK(st_hier_level_mesh(&r, l, &want[l], &err) == ST_OK);
        ix[l] = index_faces(&want[l]);
    }
    st_map *m = &h.map;
    unsigned top = m->top;
    cmp_stats s = { 0 };
    uint32_t per_level[ST_MAX_LEVELS] = { 0 }, mixed = 0, corner = 0;
    int fb = st_marker_reserve(m);
    /* the faces in st_adapt_mesh's order: corner counts its corners */
    for (uint32_t d = st_dart_first(m, top, &it); u.uv && shown.face_uv && d != ST_NIL; d = st_dart_next(m, top, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, top);
        uint32_t first = corner;
        corner += st_face_degree(m, d, top);
        unsigned L = u.level[d];
        int whole = st_face_level(m, d, top) == L;
        double cen[3] = { 0, 0, 0 };
        unsigned n = 0;
        uint32_t x = d;
        do { whole &= u.level[x] == L; n++; x = st_phi1(m, x, top); } while (x != d);
        do {
            whole &= m->darts.ins[x] <= L;  /* no split point of a finer level */
            for (int k = 0; k < 3; k++) cen[k] += st_dart_pos(m, x, top)[k] / n;
            x = st_phi1(m, x, top);
        } while (x != d);
        if (!whole || L > c->max) continue;
        per_level[L]++;
        uint32_t g = find_face(&ix[L], cen, 1e-7);
        uint32_t j = first;
        do {
            const double *got = shown.uv + 2 * (size_t)shown.face_uv[j++];
            CHECKF(fabs(got[0] - u.uv[2 * (size_t)x]) < 1e-15 && fabs(got[1] - u.uv[2 * (size_t)x + 1]) < 1e-15,
                   "%s: the mesh's corner and st_adapt_uv differ", c->file);
            compare_corner(&s, got, g == UINT32_MAX ? NULL : corner_uv(&want[L], g, st_dart_pos(m, x, top), 1e-7));
            x = st_phi1(m, x, top);
        } while (x != d);
    }
    st_marker_release(m, fb, top);
    /* one level per vertex: faces sharing an edge inside an island hold
     * one value at its ends */
    if (u.uv) mixed += mixed_level_vertices(m, top, u.level);
    printf("%s %s partial box: faces whole at levels 0..%u:", c->file, st_scheme_get(c->id)->name, c->max);
    for (unsigned l = 0; l <= c->max; l++) printf(" %u", per_level[l]);
    printf("; %u corners, %u bit-exact, worst %.3g, %u unmatched; %u seam edges; %u vertices of mixed levels\n", s.corners,
           s.exact, s.worst, s.unmatched, shown.face_uv ? seam_edges(&shown) : 0, mixed);
    CHECKF(u.uv != NULL && shown.face_uv != NULL, "%s: no UVs", c->file);
    for (unsigned l = 0; l <= c->max; l++) CHECKF(per_level[l] > 0, "%s: no whole face of level %u", c->file, l);
    /* bit for bit but where the regular level's two sides of a smooth
     * edge differ in the last bit and the regular walk takes the side of a
     * face the partial mesh does not show */
    CHECKF(s.unmatched == 0 && s.worst <= 4e-16, "%s: whole faces vs regular: worst %g, %u unmatched", c->file, s.worst,
           s.unmatched);
    CHECKF(c->id == ST_SCHEME_CATMARK || s.exact == s.corners, "%s: whole faces: %u of %u bit-exact", c->file, s.exact, s.corners);
    CHECKF(mixed == 0, "%s: %u vertices hold values of several levels", c->file, mixed);
    for (unsigned l = 0; l <= c->max; l++) { st_mesh_free(&want[l]); free(ix[l].k); }
    st_adapt_uv_free(&u);
    st_mesh_free(&shown);
    st_adapt_free(&a);
    st_hier_free(&h);
    st_hier_free(&r);
}

/* Without the one-level restriction stencils read whatever the
 * neighbourhood is (as the positions do): UVs still on every corner, finite,
 * inside the range of level 0's. */
static void check_unrestricted(const uv_case *c)
{
    st_hier h;
    st_adapt a;
    st_mesh out;
    if (load_hier(&h, c->file, c->id, c->interp, 0)) return;
    st_uv_map uv0 = st_hier_uv(&h, 0);
    double lo = INFINITY, hi = -INFINITY;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&h.map, 0, &it); d != ST_NIL; d = st_dart_next(&h.map, 0, &it))
        if (!st_is_boundary(&h.map, d)) {
            const double *t = st_uv_map_at(&uv0, d);
            lo = fmin(lo, fmin(t[0], t[1]));
            hi = fmax(hi, fmax(t[0], t[1]));
        }
    st_adapt_params p = { .base_level = 0, .max_level = c->max, .has_box = 1, .no_restriction = 1,
                          .box_lo = { -1e9, -1e9, -1e9 }, .box_hi = { 0, 1e9, 1e9 } };
    adapt_mesh(&h, &p, &out, &a);
    uint32_t bad = 0;
    for (uint32_t i = 0; out.uv && i < 2 * out.nuvs; i++) bad += !(out.uv[i] >= lo && out.uv[i] <= hi);
    CHECKF(out.face_uv && out.nuvs > 0 && bad == 0, "%s unrestricted: %u of %u UVs out of [%g, %g]", c->file, bad, out.nuvs, lo, hi);
    st_mesh_free(&out);
    st_adapt_free(&a);
    st_hier_free(&h);
}

static void check_case(const uv_case *c)
{
    st_adapt_params none = { .base_level = 0, .max_level = c->max };
    check_against_level(c, &none, 0, "empty box, base 0");
    st_adapt_params base1 = { .base_level = 1, .max_level = c->max };
    check_against_level(c, &base1, 1, "empty box, base 1");
    st_adapt_params all = { .base_level = 0, .max_level = c->max, .has_box = 1,
                            .box_lo = { -1e9, -1e9, -1e9 }, .box_hi = { 1e9, 1e9, 1e9 } };
    check_against_level(c, &all, c->max, "box over everything");
    check_partial(c);
    check_unrestricted(c);
}

/* √3 (fvar_stencil.c's rules on the faces subdivided toward each level):
 * with a box over part of the mesh every corner holds a UV inside level
 * 0's range, every level has faces, and no vertex holds values of several
 * levels.  Odd triangles are no faces of a regular level; the faces that
 * are one hold its UVs. */
static void check_partial_stencil(const uv_case *c)
{
    st_hier h, r;
    st_adapt a;
    st_mesh shown;
    st_error err = { 0 };
    if (load_hier(&h, c->file, c->id, c->interp, 0) || load_hier(&r, c->file, c->id, c->interp, c->max)) return;
    st_uv_map uv0 = st_hier_uv(&h, 0);
    double lo_uv = INFINITY, hi_uv = -INFINITY;
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&h.map, 0, &it); d != ST_NIL; d = st_dart_next(&h.map, 0, &it))
        if (!st_is_boundary(&h.map, d))
            for (int k = 0; k < 2; k++) { lo_uv = fmin(lo_uv, st_uv_map_at(&uv0, d)[k]); hi_uv = fmax(hi_uv, st_uv_map_at(&uv0, d)[k]); }
    uint32_t v0 = st_vertex_first(&h.map, 0, &it);
    for (uint32_t v = v0; v != ST_NIL; v = st_vertex_next(&h.map, 0, &it))
        for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], st_pos(&h.map, v, 0)[k]); hi[k] = fmax(hi[k], st_pos(&h.map, v, 0)[k]); }
    st_adapt_params p = { .base_level = 0, .max_level = c->max, .has_box = 1 };
    for (int k = 0; k < 3; k++) {
        double mid = st_pos(&h.map, v0, 0)[k], half = 0.2 * (hi[k] - lo[k]);
        p.box_lo[k] = mid - half;
        p.box_hi[k] = mid + half;
    }
    adapt_mesh(&h, &p, &shown, &a);
    st_adapt_uv u;
    CHECK(st_adapt_uv_build(&a, &u, &err) == ST_OK);
    st_mesh want[ST_MAX_LEVELS];
    index ix[ST_MAX_LEVELS];
    for (unsigned l = 0; l <= c->max; l++) {
        st_mesh_init(&want[l]);
        CHECK(st_hier_level_mesh(&r, l, &want[l], &err) == ST_OK);
        ix[l] = index_faces(&want[l]);
    }
    st_map *m = &h.map;
    unsigned top = m->top;
    cmp_stats s = { 0 };
    uint32_t per_level[ST_MAX_LEVELS] = { 0 }, mixed = 0, outside = 0, corners = 0, stray = 0;
    int fb = st_marker_reserve(m);
    for (uint32_t d = st_dart_first(m, top, &it); u.uv && shown.face_uv && d != ST_NIL; d = st_dart_next(m, top, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        unsigned L = u.level[d], n = 0;
        int whole = 1;
        double cen[3] = { 0, 0, 0 };
        uint32_t x = d;
        do { st_mark(m, fb, x); n++; x = st_face_step(m, x, top); } while (x != d);
        do {
            whole &= u.level[x] == L;
            for (int k = 0; k < 2; k++) outside += !(u.uv[2 * (size_t)x + k] >= lo_uv - 1e-12 && u.uv[2 * (size_t)x + k] <= hi_uv + 1e-12);
            for (int k = 0; k < 3; k++) cen[k] += st_dart_pos(m, x, top)[k] / n;
            corners++;
            x = st_face_step(m, x, top);
        } while (x != d);
        if (!whole || L > c->max) continue;
        per_level[L]++;
        uint32_t g = find_face(&ix[L], cen, 1e-7);
        if (g == UINT32_MAX) { stray++; continue; }
        do {
            const double *w = corner_uv(&want[L], g, st_dart_pos(m, x, top), 1e-7);
            if (w) compare_corner(&s, u.uv + 2 * (size_t)x, w);
            x = st_face_step(m, x, top);
        } while (x != d);
    }
    st_marker_release(m, fb, top);
    if (u.uv) mixed += mixed_level_vertices(m, top, u.level);
    printf("%s %s partial box: faces whole at levels 0..%u:", c->file, st_scheme_get(c->id)->name, c->max);
    for (unsigned l = 0; l <= c->max; l++) printf(" %u", per_level[l]);
    printf("; %u corners, %u outside level 0's UV range [%g, %g]; %u corners on faces of a regular level, %u bit-exact, "
           "worst %.3g; %u whole faces of no regular level; %u seam edges; %u vertices of mixed levels\n", corners, outside,
           lo_uv, hi_uv, s.corners, s.exact, s.worst, stray, shown.face_uv ? seam_edges(&shown) : 0, mixed);
    CHECKF(u.uv != NULL && shown.face_uv != NULL, "%s: no UVs", c->file);
    CHECKF(corners > 0 && outside == 0, "%s: %u UVs outside level 0's range", c->file, outside);
    for (unsigned l = 0; l <= c->max; l++) CHECKF(per_level[l] > 0, "%s: no whole face of level %u", c->file, l);
    CHECKF(mixed == 0, "%s: %u vertices hold values of several levels", c->file, mixed);
    /* the even triangles whose corners all hold level L's values are the
     * regular level L's, bit for bit (the stencils read complete rings) */
    CHECKF(s.corners > 0 && s.exact == s.corners, "%s: faces of a regular level: %u of %u corners bit-exact", c->file,
           s.exact, s.corners);
    /* Doo-Sabin has no odd faces: its border polygons mix levels, and every
     * face whose corners hold one level's values is a face of that level */
    CHECKF(!m->face_embedded || stray == 0, "%s: %u whole faces match no face of their level", c->file, stray);
    for (unsigned l = 0; l <= c->max; l++) { st_mesh_free(&want[l]); free(ix[l].k); }
    st_adapt_uv_free(&u);
    st_mesh_free(&shown);
    st_adapt_free(&a);
    st_hier_free(&h);
    st_hier_free(&r);
}

/* A box moved: refined over everything, then updated to a box over part of
 * the mesh (simplifications free darts that later refinements reuse, so
 * the map's numbering is not a fresh one's) gives the UVs of that box
 * applied at once, bit for bit. */
static void check_moved(const uv_case *c)
{
    st_hier h, f;
    st_adapt a, b;
    st_mesh moved, fresh;
    st_error err = { 0 };
    if (load_hier(&h, c->file, c->id, c->interp, 0) || load_hier(&f, c->file, c->id, c->interp, 0)) return;
    st_adapt_params all = { .base_level = 0, .max_level = c->max, .has_box = 1,
                            .box_lo = { -1e9, -1e9, -1e9 }, .box_hi = { 1e9, 1e9, 1e9 } };
    st_adapt_params part = all;
    part.box_hi[0] = 0;
    CHECK(st_adapt_init(&a, &h, &err) == ST_OK);
    CHECKF(st_adapt_update(&a, &all, &err) == ST_OK, "%s", err.msg);
    CHECKF(st_adapt_update(&a, &part, &err) == ST_OK, "%s", err.msg);
    part.box_lo[1] = 0;
    CHECKF(st_adapt_update(&a, &all, &err) == ST_OK, "%s", err.msg);
    CHECKF(st_adapt_update(&a, &part, &err) == ST_OK, "%s", err.msg);
    st_mesh_init(&moved);
    CHECKF(st_adapt_mesh(&a, &moved, &err) == ST_OK, "%s", err.msg);
    adapt_mesh(&f, &part, &fresh, &b);
    CHECKF(moved.face_uv && fresh.face_uv, "%s: moved box: no UVs", c->file);
    if (moved.face_uv && fresh.face_uv) {
        cmp_stats s = compare_meshes(&moved, &fresh, 1e-9);
        printf("%s %s moved box vs the same box at once: %u faces (%u), %u corners, %u bit-exact, worst %.3g, %u unmatched\n",
               c->file, st_scheme_get(c->id)->name, moved.nfaces, fresh.nfaces, s.corners, s.exact, s.worst, s.unmatched);
        CHECKF(moved.nfaces == fresh.nfaces && s.unmatched == 0 && s.exact == s.corners && s.corners > 0,
               "%s: moved box: %u of %u corners bit-exact, %u unmatched", c->file, s.exact, s.corners, s.unmatched);
        CHECKF(seam_edges(&moved) == seam_edges(&fresh), "%s: moved box: seams differ", c->file);
    }
    st_mesh_free(&moved);
    st_mesh_free(&fresh);
    st_adapt_free(&a);
    st_adapt_free(&b);
    st_hier_free(&h);
    st_hier_free(&f);
}

static void check_stencil_case(const uv_case *c)
{
    st_adapt_params none = { .base_level = 0, .max_level = c->max };
    check_against_level(c, &none, 0, "empty box, base 0");
    st_adapt_params base1 = { .base_level = 1, .max_level = c->max };
    check_against_level(c, &base1, 1, "empty box, base 1");
    st_adapt_params all = { .base_level = 0, .max_level = c->max, .has_box = 1,
                            .box_lo = { -1e9, -1e9, -1e9 }, .box_hi = { 1e9, 1e9, 1e9 } };
    check_against_level(c, &all, c->max, "box over everything");
    check_partial_stencil(c);
    check_moved(c);
}

int main(void)
{
    static const uv_case cases[] = {
        { MESHES "catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, ST_UV_CORNERS_PLUS1, 3 },
        { MESHES "catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, ST_UV_NONE, 2 },
        { MESHES "catmull_clark/blub_control_mesh.obj", ST_SCHEME_CATMARK, ST_UV_BOUNDARIES, 2 },
        { MESHES "catmull_clark/blub_control_mesh.obj", ST_SCHEME_QUADTRI, ST_UV_CORNERS_PLUS1, 2 },
        { MESHES "triangle/sphere_ico.obj", ST_SCHEME_LOOP, ST_UV_CORNERS_PLUS1, 2 },
        { MESHES "triangle/sphere_ico.obj", ST_SCHEME_LOOP, ST_UV_CORNERS_PLUS2, 2 },
        { MESHES "triangle/sphere_ico.obj", ST_SCHEME_BUTTERFLY, ST_UV_CORNERS_PLUS1, 2 },
        /* open: boundary rules, edge-only corners */
        { MESHES "triangle/cube_no_bottom.obj", ST_SCHEME_LOOP, ST_UV_CORNERS_PLUS1, 3 },
        { MESHES "triangle/cube_no_bottom.obj", ST_SCHEME_CATMARK, ST_UV_CORNERS_ONLY, 3 },
        { MESHES "triangle/cube_no_bottom.obj", ST_SCHEME_QUADTRI, ST_UV_ALL, 2 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) check_case(&cases[i]);
    static const uv_case sqrt3[] = {
        { MESHES "triangle/sphere_ico.obj", ST_SCHEME_SQRT3, ST_UV_CORNERS_PLUS1, 2 },
        { MESHES "triangle/sphere_ico.obj", ST_SCHEME_SQRT3, ST_UV_CORNERS_PLUS1, 4 },
    };
    for (size_t i = 0; i < sizeof sqrt3 / sizeof *sqrt3; i++) check_stencil_case(&sqrt3[i]);
    /* Doo-Sabin (fvar_stencil.c's rules through the dual encoding; homes
     * of E- and V-faces chosen in a regular level's order) */
    static const uv_case doosabin[] = {
        { MESHES "catmull_clark/blub_control_mesh.obj", ST_SCHEME_DOOSABIN, ST_UV_CORNERS_PLUS1, 3 },
        { MESHES "triangle/sphere_ico.obj", ST_SCHEME_DOOSABIN, ST_UV_CORNERS_PLUS1, 3 },
    };
    for (size_t i = 0; i < sizeof doosabin / sizeof *doosabin; i++) check_stencil_case(&doosabin[i]);
    return TEST_END();
}
