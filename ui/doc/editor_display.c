/* The interest box's display (editor_display.h), without GL.
 *
 * Decisions (where the requirements leave a choice):
 *   - The display is derived from the model, never the reverse: a copy of
 *     the model's levels 0..base refined by st_adapt inside the box, whose
 *     vertices of levels <= the model's top take the positions of the same
 *     vertices of the model (a walk of both refinement structures pairs
 *     them, pairs_build: quadrisection sub-faces for Catmull-Clark, Loop,
 *     Butterfly and quad/triangle, the same walk on the dual map for
 *     Doo-Sabin, whose vertex ids are the faces of M*, and the three
 *     sub-faces of each triangle after the flips for √3, every scheme with
 *     a box), and whose levels beyond the model's top are synthesised from
 *     there.  After every edit the display follows the model, so box on,
 *     edit, box off, box on always shows the model (no detail is ever lost
 *     or rotated by coarsening: the model never coarsens).
 *   - After a local edit the display copies exactly the positions core
 *     reported writing (core/map/footprint.h) and re-synthesises its
 *     levels beyond the model around them only. */
#include "editor_display.h"
#include "editor_internal.h"
#include "core/io/session.h"
#include "core/progressive/progressive.h"

#include <stdlib.h>
#include <string.h>

void st_box_display_drop(st_box_display *bd)
{
    /* (a progressive model's display: adapt reads the model, hier is the
     * selected mesh; both are freed the same way) */
    if (bd->built) {
        st_adapt_free(&bd->adapt);
        st_hier_free(&bd->hier);
    }
    bd->built = 0;
    bd->ndisp_to_model = 0;
}

static void pairs_push(st_box_display *bd, uint32_t L, uint32_t dv, uint32_t mv)
{
    if (bd->npairs + 3 > bd->cappairs) {
        uint32_t c = bd->cappairs ? 2 * bd->cappairs : 3 * 1024;
        uint32_t *p = realloc(bd->pairs, (size_t)c * sizeof *p);
        if (!p) abort();
        bd->pairs = p;
        bd->cappairs = c;
    }
    bd->pairs[bd->npairs++] = L;
    bd->pairs[bd->npairs++] = dv;
    bd->pairs[bd->npairs++] = mv;
}

static int split_tri(const st_hier *h, unsigned deg)
{
    st_scheme_id id = h->scheme->id;
    return id == ST_SCHEME_LOOP || id == ST_SCHEME_BUTTERFLY || (id == ST_SCHEME_QUADTRI && deg == 3);
}

/* The display's subdivided faces beyond the model, per level, for a full
 * synthesis of those levels (sync_from_model). */
static void collect_subdivided_faces(st_box_display *bd, const st_hier *model)
{
    st_map *dm = &bd->hier.map;
    unsigned N = model->map.top;
    bd->nsubdivided_faces = 0;
    for (unsigned L = 0; L <= ST_MAX_LEVELS; L++) bd->subdivided_faces_at[L] = 0;
    for (unsigned L = N + 1; L <= dm->top; L++) {
        bd->subdivided_faces_at[L] = bd->nsubdivided_faces;
        int fb = st_marker_reserve(dm);
        if (fb < 0) abort();
        st_dart_iter it;
        for (uint32_t x = st_dart_first(dm, L - 1, &it); x != ST_NIL; x = st_dart_next(dm, L - 1, &it)) {
            if (st_is_boundary(dm, x) || st_marked(dm, fb, x)) continue;
            st_mark_face(dm, fb, x, L - 1);
            if (st_face_level(dm, x, L - 1) != L - 1 || !st_face_is_subdivided(dm, x, L - 1)) continue;
            if (bd->nsubdivided_faces == bd->capsubdivided_faces) {
                bd->capsubdivided_faces = bd->capsubdivided_faces ? 2 * bd->capsubdivided_faces : 1024;
                bd->subdivided_faces = realloc(bd->subdivided_faces, (size_t)bd->capsubdivided_faces * sizeof *bd->subdivided_faces);
                if (!bd->subdivided_faces) abort();
            }
            bd->subdivided_faces[bd->nsubdivided_faces++] = x;
        }
        st_marker_release(dm, fb, L - 1);
        bd->subdivided_faces_at[L + 1] = bd->nsubdivided_faces;
    }
    bd->subdivided_faces_ok = 1;
}

static void pair_vertex(st_box_display *bd, unsigned L, uint32_t v, uint32_t V)
{
    bd->disp_to_model_vertex[v] = V;
    bd->model_to_disp_vertex[V] = v;
    bd->levels_of_disp_vertex[v] |= 1u << L;
    pairs_push(bd, L, v, V);
}

/* Pairs the face of display dart y0 at level L with the face of model dart
 * Y0, dart by dart and vertex by vertex (dd: display dart -> model dart). */
static void pair_face(st_box_display *bd, const st_hier *model, uint32_t *dd, unsigned L, uint32_t y0, uint32_t Y0)
{
    const st_map *dm = &bd->hier.map, *mm = &model->map;
    uint32_t y = y0, Y = Y0;
    unsigned guard = 0;
    do {
        dd[y] = Y;
        pair_vertex(bd, L, st_vert(dm, y, L), st_vert(mm, Y, L));
        y = st_phi1(dm, y, L);
        Y = st_phi1(mm, Y, L);
    } while (y != y0 && ++guard < 64);
}

/* √3: the centre of the level-(L-1) triangle of dart x (subdivided toward
 * L), read at level L from x's face (adapt_sqrt3.c): x unflipped (the odd
 * triangle a b c, x from a): c is the origin of x's second successor; x
 * flipped (the edge a b became the centres' edge, thesis fig. 3.46): x's
 * face is (a, c', c) with x from c' to c, or (b, c, c') with x from c. */
static uint32_t sqrt3_centre(const st_map *m, uint32_t x, unsigned L)
{
    uint32_t o = st_vert(m, x, L - 1), x1 = st_phi1(m, x, L), x2 = st_phi1(m, x1, L);
    if (st_vert(m, x, L) == o) return st_vert(m, x2, L);
    if (st_vert(m, x2, L) == o) return st_vert(m, x1, L);
    return st_vert(m, x, L);
}

/* √3: pairs the level-L sub-faces of the display's triangle of x (level
 * L-1, subdivided toward L; its darts paired) with the model's.  Each dart
 * of the triangle holds one sub-face at L: the even triangle of its flipped
 * edge, paired dart by dart with the model's (every edge of the regular
 * model is flipped), or an odd triangle (the edge toward an unsubdivided
 * neighbour, not a face of the model, never subdivided): its corners and
 * the centre are paired.  Even sub-faces go to `next`. */
static void sqrt3_pair_children(st_box_display *bd, const st_hier *model, uint32_t *dd, unsigned L, uint32_t x, st_dart_list *next)
{
    const st_map *dm = &bd->hier.map, *mm = &model->map;
    uint32_t c = x;
    unsigned guard = 0;
    do {
        uint32_t C = dd[c];
        if (C == ST_NIL) break; /* cannot happen: coarser darts are paired first */
        if (c == x) pair_vertex(bd, L, sqrt3_centre(dm, c, L), sqrt3_centre(mm, C, L));
        if (st_vert(dm, c, L) != st_vert(dm, c, L - 1)) {
            pair_face(bd, model, dd, L, c, C);
            st_dart_list_push(next, c);
        } else {
            uint32_t a = st_vert(dm, c, L), b = st_vert(dm, st_phi1(dm, c, L), L);
            if (bd->disp_to_model_vertex[a] != ST_NIL) pair_vertex(bd, L, a, bd->disp_to_model_vertex[a]);
            if (bd->disp_to_model_vertex[b] != ST_NIL) pair_vertex(bd, L, b, bd->disp_to_model_vertex[b]);
        }
        c = st_phi1(dm, c, L - 1);
    } while (c != x && ++guard < 3);
}

/* Pairs the display's darts and vertices with the model's: identical ids up
 * to the base level (the display is a copy), then level by level through
 * the sub-faces of each subdivided face (the corner sub-face of a coarse
 * dart starts at that dart in both maps; a triangle's central sub-face lies
 * across the first corner's inner edge).  Doo-Sabin: the same walk on the
 * dual map M* (Catmull-Clark topology; the darts of a face of M* carry its
 * surface vertex, a fresh id per quad in both maps, so pair_face pairs the
 * Doo-Sabin vertices).  √3: sqrt3_pair_children. */
/* pairs_build after a box move when the display's base is the model's
 * top (HD levels, editor_hd.c): nothing above the base is paired and the
 * levels up to it never change, so only the ids the move added need their
 * entries (a vertex above the base: no model vertex, no level bit, no
 * dart of the model's top).  Ids freed and reused lie above the base and
 * already hold those values.  Returns 0 when the full build is needed. */
static int pairs_extend(st_box_display *bd, const st_hier *model, unsigned b)
{
    st_map *dm = &bd->hier.map;
    if (b != model->map.top || bd->copied_top != b || bd->npairs || bd->nmodel_to_disp != model->map.verts.end ||
        bd->ndisp_to_model != bd->ndisp_vertices || dm->verts.end < bd->ndisp_vertices)
        return 0;
    uint32_t n0 = bd->ndisp_vertices, n = dm->verts.end;
    if (n == n0) return 1;
    uint32_t *dc = realloc(bd->disp_to_model_vertex, (size_t)n * sizeof *dc);
    uint32_t *lv = realloc(bd->levels_of_disp_vertex, (size_t)n * sizeof *lv);
    uint32_t *vd = realloc(bd->dart_of_disp_vertex, (size_t)n * sizeof *vd);
    if (!dc || !lv || !vd) abort();
    for (uint32_t v = n0; v < n; v++) { dc[v] = ST_NIL; lv[v] = 0; vd[v] = ST_NIL; }
    bd->disp_to_model_vertex = dc;
    bd->levels_of_disp_vertex = lv;
    bd->dart_of_disp_vertex = vd;
    bd->ndisp_to_model = bd->ndisp_vertices = n;
    bd->subdivided_faces_ok = 0;
    return 1;
}

static void pairs_build(st_box_display *bd, const st_hier *model, unsigned base_level)
{
    st_map *dm = &bd->hier.map;
    const st_map *mm = &model->map;
    unsigned N = mm->top, b = base_level < N ? base_level : N;
    bd->npairs = 0;
    bd->copied_top = b;
    uint32_t *dd = malloc((size_t)(dm->darts.end ? dm->darts.end : 1) * sizeof *dd);
    uint32_t *dc = realloc(bd->disp_to_model_vertex, (size_t)(dm->verts.end ? dm->verts.end : 1) * sizeof *dc);
    if (!dd || !dc) abort();
    bd->disp_to_model_vertex = dc;
    bd->ndisp_to_model = dm->verts.end;
    for (uint32_t x = 0; x < dm->darts.end; x++) dd[x] = dm->darts.ins[x] != ST_FREE_LEVEL && dm->darts.ins[x] <= b ? x : ST_NIL;
    for (uint32_t v = 0; v < dm->verts.end; v++) dc[v] = dm->verts.ins[v] != ST_FREE_LEVEL && dm->verts.ins[v] <= b ? v : ST_NIL;
    unsigned topL = dm->top < N ? dm->top : N;
    bd->subdivided_faces_ok = 0; /* collected when a full synthesis needs them */
    uint32_t *mc = realloc(bd->model_to_disp_vertex, (size_t)(mm->verts.end ? mm->verts.end : 1) * sizeof *mc);
    uint32_t *lv = realloc(bd->levels_of_disp_vertex, (size_t)(dm->verts.end ? dm->verts.end : 1) * sizeof *lv);
    uint32_t *vd = realloc(bd->dart_of_disp_vertex, (size_t)(dm->verts.end ? dm->verts.end : 1) * sizeof *vd);
    if (!mc || !lv || !vd) abort();
    bd->model_to_disp_vertex = mc;
    bd->nmodel_to_disp = mm->verts.end;
    bd->levels_of_disp_vertex = lv;
    bd->dart_of_disp_vertex = vd;
    bd->ndisp_vertices = dm->verts.end;
    for (uint32_t v = 0; v < mm->verts.end; v++) mc[v] = ST_NIL;
    for (uint32_t v = 0; v < dm->verts.end; v++) { lv[v] = 0; vd[v] = ST_NIL; }
    {
        st_dart_iter it;
        for (uint32_t x = st_dart_first(dm, topL, &it); x != ST_NIL; x = st_dart_next(dm, topL, &it)) {
            uint32_t v = st_vert(dm, x, topL);
            if (vd[v] == ST_NIL || (st_is_boundary(dm, vd[v]) && !st_is_boundary(dm, x))) vd[v] = x;
        }
    }
    /* Down the refinement tree: the faces of level b (all faces of the
     * map at b), then the sub-faces of the subdivided ones, level by level;
     * unrefined regions are not visited again at every level. */
    st_dart_list cur = { 0 }, next = { 0 };
    if (b < topL) {
        int fb = st_marker_reserve(dm);
        if (fb < 0) abort();
        st_dart_iter it;
        for (uint32_t x = st_dart_first(dm, b, &it); x != ST_NIL; x = st_dart_next(dm, b, &it)) {
            if (st_is_boundary(dm, x) || st_marked(dm, fb, x)) continue;
            st_mark_face(dm, fb, x, b);
            st_dart_list_push(&cur, x);
        }
        st_marker_release(dm, fb, b);
    }
    for (unsigned L = b + 1; L <= topL; L++) {
        next.n = 0;
        for (uint32_t k = 0; k < cur.n; k++) {
            uint32_t x = cur.d[k];
            if (!st_face_is_subdivided(dm, x, L - 1)) continue;
            if (bd->hier.scheme->id == ST_SCHEME_SQRT3) {
                sqrt3_pair_children(bd, model, dd, L, x, &next);
                continue;
            }
            unsigned deg = st_face_degree(dm, x, L - 1);
            int tri = split_tri(&bd->hier, deg);
            uint32_t c = x;
            int first = 1;
            do {
                uint32_t C = dd[c];
                if (C == ST_NIL) break; /* cannot happen: coarser darts are paired first */
                pair_face(bd, model, dd, L, c, C);
                st_dart_list_push(&next, c); /* the corner sub-face of c */
                if (tri && first) {
                    uint32_t z0 = st_beta0(dm, st_phi1(dm, c, L), L);
                    pair_face(bd, model, dd, L, z0, st_beta0(mm, st_phi1(mm, C, L), L));
                    st_dart_list_push(&next, z0); /* the central triangle */
                }
                first = 0;
                c = st_phi1(dm, c, L - 1);
            } while (c != x);
        }
        st_dart_list t = cur;
        cur = next;
        next = t;
    }
    st_dart_list_free(&cur);
    st_dart_list_free(&next);
    free(dd);
}

/* A display vertex moved (the document reports it as ST_CHANGE_DISPLAY). */
static void disp_moved(st_box_display *bd, uint32_t v)
{
    if (bd->nmoved == bd->capmoved) {
        uint32_t cap = bd->capmoved ? 2 * bd->capmoved : 1024;
        uint32_t *p = realloc(bd->moved, (size_t)cap * sizeof *p);
        if (!p) abort();
        bd->moved = p;
        bd->capmoved = cap;
    }
    bd->moved[bd->nmoved++] = v;
}

/* ---- progressive hierarchies ---------------------------------------------------
 * Nothing is refined: core selects a mesh of faces of several levels of
 * the model (st_adapt on the model itself, which it only reads), and the
 * display is that mesh as a one-level hierarchy.  Display vertex i is the
 * model's vertex st_adapt's pm->vid[i] at its level pm->lam[i]. */

static int is_progressive(const st_hier *h) { return h->scheme && h->scheme->id == ST_SCHEME_PROGRESSIVE; }

static int pm_build(st_box_display *bd, const st_hier *model, const st_adapt_params *p, st_error *err)
{
    /* (st_adapt takes a mutable hierarchy for the refinement families; on
     * a progressive one it only reads, the topology cache reading the map's
     * generation number) */
    int rc = st_adapt_init(&bd->adapt, (st_hier *)model, err);
    if (rc) return rc;
    rc = st_adapt_update(&bd->adapt, p, err);
    st_mesh c;
    st_mesh_init(&c);
    if (!rc) rc = st_adapt_mesh(&bd->adapt, &c, err);
    if (!rc) rc = st_hier_init(&bd->hier, &c, &st_scheme_progressive, NULL, err);
    st_mesh_free(&c);
    if (rc) {
        st_adapt_free(&bd->adapt);
        return rc;
    }
    bd->built = 1;
    bd->copied_top = 0;
    bd->npairs = 0;
    bd->subdivided_faces_ok = 0;
    const st_pm_select *s = bd->adapt.pm;
    const st_map *mm = &model->map;
    uint32_t n = s->nverts;
    uint32_t *dc = realloc(bd->disp_to_model_vertex, (size_t)(n ? n : 1) * sizeof *dc);
    uint32_t *mc = realloc(bd->model_to_disp_vertex, (size_t)(mm->verts.end ? mm->verts.end : 1) * sizeof *mc);
    uint32_t *lv = realloc(bd->levels_of_disp_vertex, (size_t)(n ? n : 1) * sizeof *lv);
    uint32_t *vd = realloc(bd->dart_of_disp_vertex, (size_t)(n ? n : 1) * sizeof *vd);
    if (!dc || !mc || !lv || !vd) abort();
    bd->disp_to_model_vertex = dc;
    bd->model_to_disp_vertex = mc;
    bd->levels_of_disp_vertex = lv;
    bd->dart_of_disp_vertex = vd;
    bd->ndisp_to_model = bd->ndisp_vertices = n;
    bd->nmodel_to_disp = mm->verts.end;
    for (uint32_t v = 0; v < mm->verts.end; v++) mc[v] = ST_NIL;
    for (uint32_t i = 0; i < n; i++) {
        dc[i] = s->vid[i];
        mc[s->vid[i]] = i;
        lv[i] = 1u << s->lam[i];
        vd[i] = ST_NIL;
    }
    return ST_OK;
}

/* Display vertex i to its model position; reported when it moved. */
static void pm_sync_vertex(st_box_display *bd, const st_hier *model, uint32_t i, int report)
{
    const st_pm_select *s = bd->adapt.pm;
    const double *p = st_pos(&model->map, s->vid[i], s->lam[i]);
    if (!memcmp(st_pos(&bd->hier.map, i, 0), p, 3 * sizeof *p)) return;
    st_set_pos(&bd->hier.map, i, 0, p);
    if (!report) return;
    disp_moved(bd, i);
    st_footprint_add(&bd->written, st_fp_key(0, ST_FP_POS, i));
}

/* After a local edit: the display vertices whose level-and-vertex the edit
 * wrote (keys: core/map/footprint.h). */
static void pm_follow_edit(st_box_display *bd, const st_hier *model, const uint64_t *keys, uint32_t nkeys)
{
    const st_pm_select *s = bd->adapt.pm;
    for (uint32_t k = 0; k < nkeys; k++) {
        if ((keys[k] >> 32) & 1) continue; /* not a position */
        unsigned L = (unsigned)(keys[k] >> 33);
        uint32_t V = (uint32_t)keys[k];
        uint32_t i = V < bd->nmodel_to_disp ? bd->model_to_disp_vertex[V] : ST_NIL;
        if (i == ST_NIL || s->lam[i] != L) continue;
        pm_sync_vertex(bd, model, i, 1);
    }
}

/* The display's levels beyond the model, re-synthesised around the seeds
 * (darts of level min(h.top, disp.top) of vertices whose positions
 * changed) by core (st_hier_resynth_around), which reports what it wrote.
 * Frees the seeds. */
static void resynth_region(st_box_display *bd, const st_hier *model, st_dart_list *seeds)
{
    uint32_t n0 = bd->written.n;
    if (seeds->n) st_hier_resynth_around(&bd->hier, model->map.top, seeds->d, seeds->n, &bd->written);
    for (uint32_t i = n0; i < bd->written.n; i++) disp_moved(bd, st_fp_vid(bd->written.keys[i]));
    st_dart_list_free(seeds);
}

/* Display positions from the model, for levels >= from.  Beyond the model:
 * every subdivided face (after a build), or only around the vertices whose
 * positions changed (after a box move, which leaves the model alone: only
 * new vertices differ). */
static void sync_from_model(st_box_display *bd, const st_hier *model, unsigned from, int box_move)
{
    st_map *dm = &bd->hier.map;
    const st_map *mm = &model->map;
    unsigned N = mm->top, b = bd->copied_top, T = dm->top < N ? dm->top : N;
    int local = box_move && dm->top > N;
    st_dart_list seeds = { 0 };
    for (unsigned L = from; L <= b; L++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(dm, L, &it); v != ST_NIL; v = st_vertex_next(dm, L, &it)) {
            const double *p = st_pos(mm, v, L);
            if (!memcmp(st_pos(dm, v, L), p, 3 * sizeof *p)) continue;
            st_set_pos(dm, v, L, p);
            if (local && L == T && bd->dart_of_disp_vertex[v] != ST_NIL) st_dart_list_push(&seeds, bd->dart_of_disp_vertex[v]);
        }
    }
    for (uint32_t i = 0; i < bd->npairs; i += 3) {
        unsigned L = bd->pairs[i];
        if (L < from) continue;
        uint32_t dv = bd->pairs[i + 1];
        const double *p = st_pos(mm, bd->pairs[i + 2], L);
        if (!memcmp(st_pos(dm, dv, L), p, 3 * sizeof *p)) continue;
        st_set_pos(dm, dv, L, p);
        if (local && L == T && bd->dart_of_disp_vertex[dv] != ST_NIL) st_dart_list_push(&seeds, bd->dart_of_disp_vertex[dv]);
    }
    if (local) {
        resynth_region(bd, model, &seeds);
    } else if (dm->top > N) {
        /* S(P_{L-1}) + frame * detail on every subdivided face
         * (st_adapt_synthesize, with face lists kept until the display's
         * topology changes). */
        if (!bd->subdivided_faces_ok) collect_subdivided_faces(bd, model);
        for (unsigned L = N + 1; L <= dm->top; L++)
            st_hier_resynth_faces(&bd->hier, L, bd->subdivided_faces + bd->subdivided_faces_at[L], bd->subdivided_faces_at[L + 1] - bd->subdivided_faces_at[L]);
    }
    st_dart_list_free(&seeds);
}

/* After an edit of the model that wrote the values of `keys` (core's
 * footprint of it): the display's copies of those positions, then its
 * levels beyond the model around them only. */
void st_box_display_follow_edit(st_box_display *bd, const st_hier *model, const uint64_t *keys, uint32_t nkeys)
{
    if (is_progressive(model)) {
        pm_follow_edit(bd, model, keys, nkeys);
        return;
    }
    st_map *dm = &bd->hier.map;
    const st_map *mm = &model->map;
    unsigned N = mm->top, b = bd->copied_top, T = dm->top < N ? dm->top : N;
    unsigned lo = ST_MAX_LEVELS;
    for (uint32_t i = 0; i < nkeys; i++) {
        unsigned L = (unsigned)(keys[i] >> 33);
        if (L < lo) lo = L;
    }
    st_dart_list seeds = { 0 };
    for (unsigned L = lo; L <= T; L++)
        for (uint32_t i = 0; i < nkeys; i++) {
            if ((unsigned)(keys[i] >> 33) != L || ((keys[i] >> 32) & 1)) continue;
            uint32_t V = (uint32_t)keys[i], dv;
            if (mm->verts.ins[V] <= b) dv = V;
            else dv = V < bd->nmodel_to_disp ? bd->model_to_disp_vertex[V] : ST_NIL;
            if (dv == ST_NIL || dv >= bd->ndisp_vertices) continue;
            if (L > b && !((bd->levels_of_disp_vertex[dv] >> L) & 1)) continue;
            const double *p = st_pos(mm, V, L);
            if (!memcmp(st_pos(dm, dv, L), p, 3 * sizeof *p)) continue;
            st_set_pos(dm, dv, L, p);
            disp_moved(bd, dv);
            st_footprint_add(&bd->written, st_fp_key(L, ST_FP_POS, dv));
            if (L == T && dm->top > N && bd->dart_of_disp_vertex[dv] != ST_NIL) st_dart_list_push(&seeds, bd->dart_of_disp_vertex[dv]);
        }
    resynth_region(bd, model, &seeds);
    /* The model changed: the next box update visits everything. */
    bd->adapt.has_prev = 0;
}

/* V - E + F of the model's level 0 (real faces), which every adaptive
 * refinement of it keeps (st_box_display.euler0). */
static int64_t level0_euler(const st_hier *model)
{
    st_level_stats z;
    st_level_stats_compute((st_map *)&model->map, 0, &z);
    return z.euler;
}

int st_box_display_build(st_box_display *bd, const st_hier *model, const st_adapt_params *p, st_error *err)
{
    st_box_display_drop(bd);
    if (is_progressive(model)) return pm_build(bd, model, p, err);
    unsigned N = model->map.top, b = p->base_level < N ? p->base_level : N;
    /* The display starts as a copy of the model (then cut to the base). */
    if (ed_hier_clone(&bd->hier, model, NULL)) return st_fail(err, ST_ERR_MEMORY, "out of memory for the interest box's display");
    while (bd->hier.map.top > b) st_hier_remove_top(&bd->hier);
    int rc = st_adapt_init(&bd->adapt, &bd->hier, err);
    if (rc) { st_hier_free(&bd->hier); return rc; }
    bd->built = 1;
    rc = st_adapt_update(&bd->adapt, p, err);
    if (rc) { st_box_display_drop(bd); return rc; }
    pairs_build(bd, model, p->base_level);
    bd->euler0 = level0_euler(model);
    sync_from_model(bd, model, 0, 0);
    return ST_OK;
}

int st_box_display_move(st_box_display *bd, const st_hier *model, const st_adapt_params *p, int keep_log,
                        st_error *err)
{
    /* The display map logs what the update touches, so that the renderer
     * re-tessellates only that (ST_CHANGE_PATCH); moves not yet taken by
     * the renderer add up in the one log. */
    if (!keep_log) st_map_log_clear(&bd->patch_log);
    if (is_progressive(model)) {
        /* a new mesh each time (the document rebuilds the display for a
         * progressive model rather than patching it) */
        st_box_display_drop(bd);
        return pm_build(bd, model, p, err);
    }
    bd->hier.map.log = &bd->patch_log;
    int rc = st_adapt_update(&bd->adapt, p, err);
    if (!rc) {
        if (!pairs_extend(bd, model, p->base_level < model->map.top ? p->base_level : model->map.top))
            pairs_build(bd, model, p->base_level);
        /* Box updates never touch the levels up to the base. */
        sync_from_model(bd, model, bd->copied_top + 1, 1);
    }
    bd->hier.map.log = NULL;
    return rc;
}

void st_box_display_follow_model(st_box_display *bd, const st_hier *model, unsigned from)
{
    if (is_progressive(model)) {
        (void)from; /* a vertex shows its position of its own level, which may be any */
        for (uint32_t i = 0; bd->built && i < bd->adapt.pm->nverts; i++) pm_sync_vertex(bd, model, i, 0);
        return;
    }
    sync_from_model(bd, model, from, 0);
    bd->adapt.has_prev = 0; /* the model changed */
}

uint32_t st_box_display_model_vertex(const st_box_display *bd, uint32_t dv)
{
    return bd->built && dv < bd->ndisp_to_model ? bd->disp_to_model_vertex[dv] : ST_NIL;
}

void st_box_display_free(st_box_display *bd)
{
    st_box_display_drop(bd);
    free(bd->disp_to_model_vertex);
    free(bd->pairs);
    free(bd->subdivided_faces);
    free(bd->model_to_disp_vertex);
    free(bd->levels_of_disp_vertex);
    free(bd->dart_of_disp_vertex);
    free(bd->moved);
    st_map_log_free(&bd->patch_log);
    st_footprint_free(&bd->written);
    memset(bd, 0, sizeof *bd);
}

void st_box_display_written(st_box_display *bd, uint32_t from)
{
    for (uint32_t i = from; i < bd->written.n; i++)
        if (st_fp_kind(bd->written.keys[i]) == ST_FP_POS) disp_moved(bd, st_fp_vid(bd->written.keys[i]));
}

int st_box_display_adopt(st_box_display *bd, const st_hier *model, st_hier *hier, st_adapt *adapt, st_error *err)
{
    const st_map *hm = &hier->map, *mm = &model->map;
    unsigned N = mm->top;
    if (is_progressive(model) || hier->scheme != model->scheme || hm->top < N)
        return st_fail(err, ST_ERR_INVALID, "the HD levels do not belong to this model");
    for (unsigned L = 0; L <= N; L++) {
        st_level_stats a, b;
        st_level_stats_compute((st_map *)hm, L, &a);
        st_level_stats_compute((st_map *)mm, L, &b);
        if (a.faces != b.faces || a.vertices != b.vertices)
            return st_fail(err, ST_ERR_INVALID, "the HD levels' level %u differs from the model's", L);
    }
    st_box_display_drop(bd);
    st_session_move_hier(&bd->hier, hier);
    st_session_move_adapt(&bd->adapt, adapt, &bd->hier);
    bd->built = 1;
    pairs_build(bd, model, N);
    bd->euler0 = level0_euler(model);
    sync_from_model(bd, model, 0, 0);
    return ST_OK;
}
