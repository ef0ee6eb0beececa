/* Rebuild levels by unsubdivide or the progressive method (rebuild.h), for
 * the CLI and the window alike. */
#include "core/rebuild/rebuild.h"
#include "core/base/hugepage.h"
#include "core/base/membudget.h"
#include "core/fvar/fvar.h"
#include "core/progressive/progressive.h"
#include "core/rebuild/unsubdivide.h"
#include "core/progressive/scheme_registry.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void st_rebuild_report_free(st_rebuild_report *rep)
{
    if (rep) st_notes_free(&rep->notes);
}

static const char *plural(uint32_t n) { return n == 1 ? "" : "s"; }

/* err's message behind "name: " (a failure inside a step that does not
 * name the file). */
static int named(st_error *err, const char *name, int rc)
{
    if (!err) return rc;
    char msg[sizeof err->msg];
    snprintf(msg, sizeof msg, "%s", err->msg);
    return st_fail(err, rc, "%s: %s", name, msg);
}

/* The progressive method builds levels by edge collapses, which have no
 * rule for OBJ tags or UVs (a collapse merges a crease or a seam with its
 * neighbours): what the input had and the hierarchy lacks, one line. */
static void progressive_dropped(const st_mesh *mesh, st_notes *notes)
{
    char buf[512];
    size_t n = 0;
    uint32_t holes = st_mesh_hole_faces(mesh);
    if (mesh->ncreases) n += (size_t)snprintf(buf + n, sizeof buf - n, "%s%u crease tag%s", n ? ", " : "", mesh->ncreases, plural(mesh->ncreases));
    if (mesh->ncorners && n < sizeof buf) n += (size_t)snprintf(buf + n, sizeof buf - n, "%s%u corner tag%s", n ? ", " : "", mesh->ncorners, plural(mesh->ncorners));
    if (holes && n < sizeof buf) n += (size_t)snprintf(buf + n, sizeof buf - n, "%s%u hole face%s (they are ordinary faces now)", n ? ", " : "", holes, plural(holes));
    if (mesh->face_uv && n < sizeof buf) n += (size_t)snprintf(buf + n, sizeof buf - n, "%sthe UVs", n ? ", " : "");
    if (n) st_notes_add(notes, "note: the progressive method keeps no tags or UVs; dropped %s", buf);
}

/* Any manifold mesh (core/progressive/: grouped independent edge
 * collapses, Kraemer 2008 §4.4).  Default target: 1 % of the input's faces
 * (at least 4), as far as the collapses allow. */
static int build_progressive(const char *name, const st_mesh *mesh, const st_rebuild_opts *o, st_hier *h,
                             st_rebuild_report *rep, st_error *err)
{
    rep->method = ST_REBUILD_PROGRESSIVE;
    if (o->scheme && strcmp(o->scheme, "progressive"))
        snprintf(rep->warning, sizeof rep->warning, "--scheme %s applies to unsubdivide; the progressive method has "
                 "its own prediction (scheme progressive)", o->scheme);
    uint64_t corners = mesh->nfaces ? mesh->face_off[mesh->nfaces] : 0;
    /* about 160 bytes per finest dart at the peak (koala: 47 MiB for 300k darts) */
    if (st_mem_check((size_t)corners * 200u, "the progressive rebuild", err)) return named(err, name, ST_ERR_MEMORY);
    st_progressive_opts po = { .target_faces = o->target_faces, .max_levels = o->max_levels ? o->max_levels + 1 : 0,
                               .predictor = ST_PM_DEFAULT, .fit_coarse = 1, .progress = o->progress,
                               .progress_ctx = o->progress_ctx };
    if (!po.target_faces) po.target_faces = mesh->nfaces / 100 > 4 ? mesh->nfaces / 100 : 4;
    st_progressive_report pr;
    int rc = st_progressive_build(mesh, &po, h, &pr, err);
    if (rc) return named(err, name, rc);
    rep->levels = pr.levels;
    rep->cage_faces = (uint32_t)pr.faces[0];
    char lv[48];
    st_levels_phrase(pr.levels - 1, lv, sizeof lv);
    size_t n = (size_t)snprintf(rep->summary, sizeof rep->summary, "progressive, %s, faces", lv);
    for (unsigned l = 0; l < pr.levels && n < sizeof rep->summary; l++)
        n += (size_t)snprintf(rep->summary + n, sizeof rep->summary - n, " %llu", (unsigned long long)pr.faces[l]);
    if (n < sizeof rep->summary) n += (size_t)snprintf(rep->summary + n, sizeof rep->summary - n, ", kept per level t =");
    for (unsigned l = 1; l < pr.levels && n < sizeof rep->summary; l++)
        n += (size_t)snprintf(rep->summary + n, sizeof rep->summary - n, " %.2f", pr.kept[l]);
    if (n < sizeof rep->summary)
        snprintf(rep->summary + n, sizeof rep->summary - n, ", %.1f topology bytes per finest dart, %.1f of details", pr.bytes_per_dart,
                 pr.detail_bytes_per_dart);
    snprintf(rep->brief, sizeof rep->brief, "rebuilt by the progressive method: %s, coarsest %llu faces", lv,
             (unsigned long long)pr.faces[0]);
    if (pr.triangulated) st_notes_add(&rep->notes, "polygons were split into triangles (fans) first");
    if (pr.note[0]) st_notes_add(&rep->notes, "%s", pr.note);
    progressive_dropped(mesh, &rep->notes);
    return ST_OK;
}

/* The hierarchy of a recovered cage: the scheme (given, or the one the
 * pattern implies), the cage refined, the input's positions analysed; the
 * report says what was recovered and what of the tags and UVs was kept. */
static int build_unsubdivided(const char *name, const st_mesh *mesh, st_unsub *u, const st_rebuild_opts *o,
                              st_hier *h, st_rebuild_report *rep, int *cancelled, st_error *err)
{
    rep->method = ST_REBUILD_UNSUBDIVIDE;
    int split = u->pattern == ST_UNSUB_POLY_SPLIT;
    const char *scheme = o->scheme ? o->scheme : split ? "catmull-clark" : "loop";
    const st_scheme *sc = st_scheme_find(scheme);
    if (!sc) return st_fail(err, ST_ERR_INVALID, "unknown scheme '%s'", scheme);
    if (!st_unsub_scheme_fits(u, sc)) {
        rep->wrong_scheme = 1;
        return st_fail(err, ST_ERR_INVALID, "%s is a %s; --scheme %s refines differently (use %s)", name,
                       split ? "polygon split (Catmull-Clark)" : "triangle quadrisection", scheme,
                       split ? "catmull-clark, or quad-triangle on a cage without triangles" : "loop, butterfly or quad-triangle");
    }
    st_hier_opts ho = { .boundary = ST_BOUNDARY_UNSET, .crease_method = ST_CREASE_UNIFORM, .uv_interp = o->uv_interp };
    double uv_residual = 0;
    int rc = st_unsub_build_hier_corners(mesh, u, sc, &ho, h, NULL, NULL, NULL, mesh->face_uv ? &uv_residual : NULL, err);
    if (rc) return named(err, name, rc);
    if (o->progress && o->progress(o->progress_ctx, 1.0)) {
        st_hier_free(h);
        *cancelled = 1;
        return st_fail(err, ST_ERR_INVALID, "cancelled");
    }
    const st_mesh *c = &u->step[0].coarse;
    char lv[48];
    rep->levels = h->map.top + 1;
    rep->cage_faces = c->nfaces;
    snprintf(rep->summary, sizeof rep->summary,
             "unsubdivide, %s, scheme %s: %s, cage %u faces and %u vertices, finest %u faces, longest detail %.3g",
             split ? "polygon split" : "triangle quadrisection", sc->name, st_levels_phrase(h->map.top, lv, sizeof lv),
             c->nfaces, c->nverts, mesh->nfaces, st_unsub_max_detail(h));
    snprintf(rep->brief, sizeof rep->brief, "rebuilt by unsubdivide (%s): %s, cage %u faces", sc->name, lv, c->nfaces);
    snprintf(rep->stop, sizeof rep->stop, "%s", u->stop);
    if (mesh->ncreases || mesh->ncorners || mesh->face_hole) {
        uint32_t holes = st_mesh_hole_faces(c);
        st_notes_add(&rep->notes, "tags kept: cage %u crease edge%s, %u corner%s, %u hole face%s; finest level as the input's",
                     c->ncreases, plural(c->ncreases), c->ncorners, plural(c->ncorners), holes, plural(holes));
    }
    if (mesh->face_uv)
        st_notes_add(&rep->notes, "UVs: cage corners from the input's; refined with --uv-interp %s, the finest level's UVs "
                     "differ from the input's by at most %.3g (UVs have no details)",
                     st_uv_interp_name(o->uv_interp), uv_residual);
    return ST_OK;
}

/* ---- the input's vertices in order of first use --------------------------------------------- */

/* Whether the vertices of consecutive faces lie near each other in the
 * vertex arrays: for the corners of a sample of faces, whether the nearest
 * vertex id of the face before (a shared vertex counts) is within
 * nverts / 64 (at most 2048, about the L1 cache's worth of positions).
 * Strata's own numbering (a level's vertices, edge points and face points
 * each in their parents' order, faces in their parents' order) and
 * first-use order pass with 94 % and more on the shared meshes subdivided;
 * a shuffled numbering (another program's) meets mostly the shared
 * vertices: 30 to 55 %. */
#define SAMPLE_FACES 8192u
static int vertices_coherent(const st_mesh *m)
{
    uint32_t near_ids = m->nverts / 64 < 16 ? 16 : m->nverts / 64 > 2048 ? 2048 : m->nverts / 64;
    if (m->nfaces < 2) return 1;
    uint32_t step = m->nfaces / SAMPLE_FACES > 1 ? m->nfaces / SAMPLE_FACES : 1;
    uint64_t near = 0, all = 0;
    for (uint32_t f = 1; f < m->nfaces; f += step) {
        uint32_t pb = m->face_off[f - 1], pe = m->face_off[f], e = m->face_off[f + 1];
        for (uint32_t c = pe; c < e; c++) {
            uint32_t v = m->face_idx[c], best = UINT32_MAX;
            for (uint32_t x = pb; x < pe; x++) {
                uint32_t u = m->face_idx[x], d = u > v ? u - v : v - u;
                if (d < best) best = d;
            }
            near += best < near_ids;
            all++;
        }
    }
    return near * 10 >= all * 8;
}

/* The arrays renumbered made (none while copy->face_idx is the input's). */
static void free_renumbered(st_mesh *copy, const st_mesh *in)
{
    if (copy->face_idx == in->face_idx) return;
    free(copy->pos); free(copy->face_idx); free(copy->normals); free(copy->crease_v); free(copy->corner_v);
    *copy = *in;
}

/* A working copy of `in` with its vertices numbered in order of first use
 * by the faces (meshoptimizer's optimizeVertexFetchRemap): every pass of
 * the rebuild walks the faces in order and then finds each vertex's data
 * near the last one's (st_unsubdivide on spot x4, 750k quads: 500 ms in a
 * shuffled order, 250 ms in Strata's).  Per-vertex fields are gathered
 * (positions, normals) or remapped (crease and corner tags); per-face and
 * per-corner fields (holes, face-varying UV indices) are unchanged and
 * shared with `in`, as are face_off and the tags' sharpness: free the copy
 * with free_renumbered only.  0, or -1 when out of memory or when a vertex
 * is unused (then the input is used as it is). */
static int renumbered(const st_mesh *in, st_mesh *out)
{
    *out = *in;
    uint32_t nv = in->nverts, nc = in->face_off[in->nfaces];
    uint32_t *new_of = st_malloc_huge(((size_t)nv + 1) * sizeof *new_of);
    out->pos = st_malloc_huge(((size_t)nv + 1) * 3 * sizeof *out->pos);
    out->face_idx = st_malloc_huge(((size_t)nc + 1) * sizeof *out->face_idx);
    out->normals = in->normals ? malloc(((size_t)nv + 1) * 3 * sizeof *out->normals) : NULL;
    out->crease_v = in->ncreases ? malloc((size_t)in->ncreases * 2 * sizeof *out->crease_v) : NULL;
    out->corner_v = in->ncorners ? malloc((size_t)in->ncorners * sizeof *out->corner_v) : NULL;
    int ok = new_of && out->pos && out->face_idx && (!in->normals || out->normals) && (!in->ncreases || out->crease_v) &&
             (!in->ncorners || out->corner_v);
    uint32_t n = 0;
    if (ok) {
        memset(new_of, 0xff, (size_t)nv * sizeof *new_of);
        for (uint32_t c = 0; c < nc; c++) {
            uint32_t v = in->face_idx[c];
            if (new_of[v] == ST_NIL) {
                memcpy(out->pos + 3 * (size_t)n, in->pos + 3 * (size_t)v, 3 * sizeof *out->pos);
                if (in->normals) memcpy(out->normals + 3 * (size_t)n, in->normals + 3 * (size_t)v, 3 * sizeof *out->normals);
                new_of[v] = n++;
            }
            out->face_idx[c] = new_of[v];
        }
        ok = n == nv;
    }
    for (uint32_t i = 0; ok && i < 2 * in->ncreases; i++) out->crease_v[i] = new_of[in->crease_v[i]];
    for (uint32_t i = 0; ok && i < in->ncorners; i++) out->corner_v[i] = new_of[in->corner_v[i]];
    free(new_of);
    if (!ok) {
        free_renumbered(out, in);
        return -1;
    }
    return 0;
}

/* Unsubdivide and the hierarchy of its cage.  *found: whether a cage was
 * found (a failure after that is final; before it, auto goes on to the
 * progressive method). */
static int unsubdivided(const char *name, const st_mesh *in, const st_rebuild_opts *o, st_hier *h, st_rebuild_report *rep,
                        int *found, int *cancelled, st_error *err)
{
    st_unsub u;
    st_unsub_opts uo = { .max_levels = o->max_levels, .target_faces = o->target_faces };
    int rc = st_unsubdivide(name, in, &uo, &u, err);
    *found = rc == ST_OK;
    if (rc) return rc;
    rc = build_unsubdivided(name, in, &u, o, h, rep, cancelled, err);
    st_unsub_free(&u);
    return rc;
}

int st_rebuild(const char *name, const st_mesh *in, const st_rebuild_opts *o, st_hier *h, st_rebuild_report *rep,
               st_error *err)
{
    memset(rep, 0, sizeof *rep);
    memset(h, 0, sizeof *h);
    if (o->method == ST_REBUILD_PROGRESSIVE) return build_progressive(name, in, o, h, rep, err);
    /* Unsubdivide on the renumbered copy when the input's order is not
     * coherent.  The levels are then numbered from the copy: every such
     * vertex order of the same faces gives the same hierarchy, whose least-squares
     * levels differ in the last bits from those the input's own order would
     * give (sums in another order); the finest level is the input's
     * positions bit for bit either way.  A failure there (but a cancel) is
     * tried again on the input itself, so that refusals name the input's
     * vertices as before, and a memory refusal counts the process without
     * the copy: failure is the rare path. */
    st_mesh work = *in;
    int copied = !vertices_coherent(in) && renumbered(in, &work) == 0, found = 0, cancelled = 0;
    int rc = unsubdivided(name, &work, o, h, rep, &found, &cancelled, err);
    free_renumbered(&work, in);
    if (rc && copied && !cancelled) {
        st_rebuild_report_free(rep);
        memset(rep, 0, sizeof *rep);
        memset(h, 0, sizeof *h);
        rc = unsubdivided(name, in, o, h, rep, &found, &cancelled, err);
    }
    if (rc == ST_OK || found) return rc;
    if (o->method == ST_REBUILD_UNSUBDIVIDE) {
        rep->method = ST_REBUILD_UNSUBDIVIDE;
        return rc;
    }
    snprintf(rep->refusal, sizeof rep->refusal, "%s", err ? err->msg : "no subdivision connectivity");
    if (err) *err = (st_error){ 0 };
    return build_progressive(name, in, o, h, rep, err);
}

/* ---- a hierarchy's level as the input ------------------------------------------------------ */

/* Edge sharpness as crease tags, each edge once (its dart with a real face
 * whose partner is a boundary dart or has a larger id), and vertex
 * sharpness as corner tags; index: vertex id -> mesh index. */
static int level_tags(const st_hier *h, unsigned l, const uint32_t *index, st_mesh *out, st_error *err)
{
    const st_map *m = &h->map;
    st_dart_iter it;
    uint32_t nc = 0, nk = 0;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t e = st_beta0(m, d, l);
        if (!st_is_boundary(m, d) && (st_is_boundary(m, e) || d < e) && st_hier_edge_sharpness(h, d, l) > 0) nc++;
    }
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        if (st_hier_vertex_sharpness(h, v, l) > 0) nk++;
    if (!nc && !nk) return ST_OK;
    out->crease_v = malloc(((size_t)nc + 1) * 2 * sizeof *out->crease_v);
    out->crease_s = malloc(((size_t)nc + 1) * sizeof *out->crease_s);
    out->corner_v = malloc(((size_t)nk + 1) * sizeof *out->corner_v);
    out->corner_s = malloc(((size_t)nk + 1) * sizeof *out->corner_s);
    if (!out->crease_v || !out->crease_s || !out->corner_v || !out->corner_s)
        return st_fail(err, ST_ERR_MEMORY, "out of memory reading the tags of level %u", l);
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t e = st_beta0(m, d, l);
        float s = st_hier_edge_sharpness(h, d, l);
        if (st_is_boundary(m, d) || (!st_is_boundary(m, e) && e < d) || s <= 0) continue;
        out->crease_v[2 * out->ncreases] = index[st_vert(m, d, l)];
        out->crease_v[2 * out->ncreases + 1] = index[st_vert(m, st_phi1(m, d, l), l)];
        out->crease_s[out->ncreases++] = s;
    }
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
        float s = st_hier_vertex_sharpness(h, v, l);
        if (s <= 0) continue;
        out->corner_v[out->ncorners] = index[v];
        out->corner_s[out->ncorners++] = s;
    }
    return ST_OK;
}

int st_rebuild_level_input(st_hier *h, unsigned l, st_mesh *out, st_error *err)
{
    st_mesh_init(out);
    if (l > h->map.top) return st_fail(err, ST_ERR_RANGE, "level %u of a hierarchy of levels 0..%u", l, h->map.top);
    int rc = st_hier_level_mesh(h, l, out, err);
    if (rc) return rc;
    out->boundary_interp = h->opts.boundary;
    out->crease_method = h->opts.crease_method;
    out->tri_sub = h->opts.tri_sub;
    /* A dual encoding (Doo-Sabin) carries no sharpness. */
    const st_map *m = &h->map;
    if (!h->has_sharpness || m->face_embedded) return ST_OK;
    /* st_map_to_mesh numbers the level's vertices in iteration order. */
    uint32_t *index = malloc(((size_t)m->verts.end + 1) * sizeof *index), n = 0;
    if (!index) { st_mesh_free(out); return st_fail(err, ST_ERR_MEMORY, "out of memory reading the tags of level %u", l); }
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) index[v] = n++;
    rc = level_tags(h, l, index, out, err);
    free(index);
    if (rc) st_mesh_free(out);
    return rc;
}
