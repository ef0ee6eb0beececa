/* Rebuild levels (editor.h, st_doc_rebuild_levels): the document's finest
 * level made into a hierarchy with coarse levels, as `strata rebuild
 * --method auto` does (app/cmd_rebuild.c): unsubdivide when the mesh has
 * subdivision connectivity (core/rebuild/unsubdivide.h), else the
 * progressive method (core/progressive/progressive.h; Kraemer 2008 §4.4).
 *
 * The rebuild works on a copy of the finest level; the document changes
 * only when it succeeds, and the old hierarchy moves into the undo step as
 * a scheme change's does (editor.c, undo.c). */
#include "editor_internal.h"

#include "core/base/membudget.h"
#include "core/progressive/progressive.h"
#include "core/rebuild/unsubdivide.h"

#include <stdio.h>
#include <string.h>

/* The stage for the window's "working" panel (d->progress), then the
 * caller's fraction callback, whose non-zero return cancels. */
typedef struct rebuild_progress {
    st_doc *d;
    int (*fraction)(void *, double);
    void *ctx;
} rebuild_progress;

static int report(void *p, double f)
{
    rebuild_progress *rp = p;
    if (rp->d->progress) rp->d->progress(rp->d->progress_ctx, "progressive rebuild", (unsigned)(f * 100 + 0.5), 100);
    return rp->fraction ? rp->fraction(rp->ctx, f) : 0;
}

/* Unsubdivide: the cage, and the scheme its pattern implies (Catmull-Clark
 * for the polygon split, Loop for quadrisection, as the CLI's default).
 * Returns 1 when the mesh has no subdivision connectivity (*h untouched),
 * 0 when *h was built, < 0 on a failure (err). */
static int try_unsubdivide(const char *name, const st_mesh *fine, st_hier *h, char *msg, size_t msgcap,
                           st_error *err)
{
    st_unsub u;
    st_error refusal;
    st_unsub_opts uo = { 0 };
    if (st_unsubdivide(name, fine, &uo, &u, &refusal) != ST_OK) return 1;
    const st_scheme *sc = st_scheme_find(u.pattern == ST_UNSUB_POLY_SPLIT ? "catmull-clark" : "loop");
    st_hier_opts ho = { .boundary = ST_BOUNDARY_UNSET, .crease_method = ST_CREASE_UNIFORM };
    int rc = st_unsub_build_hier(fine, &u, sc, &ho, h, NULL, NULL, err);
    if (!rc)
        snprintf(msg, msgcap, "rebuilt by unsubdivide (%s): %u levels, cage %u faces", sc->name, h->map.top + 1,
                 u.step[0].coarse.nfaces);
    st_unsub_free(&u);
    return rc ? -1 : 0;
}

/* The progressive method, with the CLI's default target: 1 % of the faces,
 * at least 4. */
static int build_progressive(const st_mesh *fine, rebuild_progress *rp, st_hier *h, char *msg,
                             size_t msgcap, st_error *err)
{
    uint64_t corners = fine->nfaces ? fine->face_off[fine->nfaces] : 0;
    /* about 160 bytes per finest dart at the peak (app/cmd_rebuild.c) */
    if (st_mem_check((size_t)corners * 200u, "the progressive rebuild", err)) return -1;
    st_progressive_opts po = { .target_faces = fine->nfaces / 100 > 4 ? fine->nfaces / 100 : 4,
                               .progress = report, .progress_ctx = rp };
    st_progressive_report rep;
    if (st_progressive_build(fine, &po, h, &rep, err)) return -1;
    snprintf(msg, msgcap, "rebuilt by the progressive method: %u levels, coarsest %llu faces%s", rep.levels,
             (unsigned long long)rep.faces[0], rep.triangulated ? " (polygons split into triangles)" : "");
    return 0;
}

int st_doc_rebuild_levels(st_doc *d, int (*progress)(void *, double), void *ctx, char *msg, size_t msgcap,
                          st_error *err)
{
    char scratch[256];
    if (!msg || !msgcap) { msg = scratch; msgcap = sizeof scratch; }
    msg[0] = 0;
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    ed_finish_active(d);
    /* A copy of the finest level (with the edits made): the model stays as
     * it is until the new hierarchy is complete. */
    st_mesh fine;
    st_mesh_init(&fine);
    int rc = st_hier_level_mesh(&d->h, d->h.map.top, &fine, err);
    if (rc) return rc;
    const char *name = d->path[0] ? d->path : "model";
    rebuild_progress rp = { d, progress, ctx };
    if (d->progress) d->progress(d->progress_ctx, "unsubdivide", 0, 0);
    st_hier h;
    rc = try_unsubdivide(name, &fine, &h, msg, msgcap, err);
    if (rc == 1) rc = build_progressive(&fine, &rp, &h, msg, msgcap, err);
    else if (!rc && progress && progress(ctx, 1.0)) {
        st_hier_free(&h);
        rc = st_fail(err, ST_ERR_INVALID, "cancelled");
    }
    st_mesh_free(&fine);
    if (rc) return err && err->code ? err->code : ST_ERR_INVALID;
    /* The old hierarchy moves into the undo step (as a scheme change). */
    st_undo_step *s = ed_swap_hier(d, &h);
    s->name = "rebuild levels";
    /* Level 0 is no longer the loaded mesh: a scheme change must not take
     * the file's crease tags. */
    d->rebased = 1;
    d->edit_level = 0;
    d->display_level = d->h.map.top;
    double t0 = ed_now_ms();
    ed_topology_done(d, t0);
    ed_step_finish(s);
    ed_push_step(d, s);
    return ST_OK;
}
