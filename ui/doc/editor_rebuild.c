/* Rebuild levels (editor.h, st_doc_rebuild_levels): the document's finest
 * level made into a hierarchy with coarse levels by core's st_rebuild
 * (core/rebuild/rebuild.h), the path `strata rebuild --method auto` takes
 * (app/cmd_rebuild.c): unsubdivide when the mesh has subdivision
 * connectivity, keeping its crease, corner and hole tags and its UVs, else
 * the progressive method (Kraemer 2008 §4.4), which says what it dropped.
 *
 * The rebuild works on a copy of the finest level; the document changes
 * only when it succeeds, and the old hierarchy moves into the undo step as
 * a scheme change's does (editor.c, undo.c). */
#include "editor_internal.h"

#include "core/rebuild/rebuild.h"

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
    if (rp->d->progress) rp->d->progress(rp->d->progress_ctx, "rebuilding levels", (unsigned)(f * 100 + 0.5), 100);
    return rp->fraction ? rp->fraction(rp->ctx, f) : 0;
}

/* The window's message: what was built, then the report's notes (tags
 * and UVs kept, or what the progressive method dropped), as the CLI prints
 * them. */
static void report_message(const st_rebuild_report *rep, char *msg, size_t msgcap)
{
    size_t n = (size_t)snprintf(msg, msgcap, "%s", rep->brief);
    for (uint32_t i = 0; i < rep->notes.count && n < msgcap; i++)
        n += (size_t)snprintf(msg + n, msgcap - n, "; %s", rep->notes.lines[i]);
}

int st_doc_rebuild_levels(st_doc *d, int (*progress)(void *, double), void *ctx, char *msg, size_t msgcap,
                          st_error *err)
{
    char scratch[256];
    if (!msg || !msgcap) { msg = scratch; msgcap = sizeof scratch; }
    msg[0] = 0;
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    ed_finish_active(d);
    /* A copy of the finest level (with the edits made and its tags): the
     * model stays as it is until the new hierarchy is complete. */
    st_mesh fine;
    int rc = st_rebuild_level_input(&d->h, d->h.map.top, &fine, err);
    if (rc) return rc;
    const char *name = d->path[0] ? d->path : "model";
    rebuild_progress rp = { d, progress, ctx };
    if (d->progress) d->progress(d->progress_ctx, "rebuilding levels", 0, 0);
    /* As `strata rebuild` with its defaults, the UVs refined by the
     * document's face-varying option. */
    st_rebuild_opts ro = { .method = ST_REBUILD_AUTO, .uv_interp = d->h.opts.uv_interp,
                           .progress = report, .progress_ctx = &rp };
    st_rebuild_report rep;
    st_hier h;
    rc = st_rebuild(name, &fine, &ro, &h, &rep, err);
    st_mesh_free(&fine);
    if (!rc) report_message(&rep, msg, msgcap);
    st_rebuild_report_free(&rep);
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
