/* Saving the document as a session (editor.h, st_doc_save_session): what
 * core/io/session.h stores, taken from the document by reference. */
#include "editor_internal.h"

#include "core/io/session.h"

#include <stdlib.h>

/* A view of the layers of levels <= top (hd 0) or above it (hd 1), sharing
 * the document's arrays: free only its v (layers_view_free).  The model's
 * layers go into the file's layr chunk, the HD levels' into the hdlv
 * image (core/io/session.h). */
static int layers_view(const st_layers *all, unsigned top, int hd, st_layers *out)
{
    st_layers_init(out);
    out->v = malloc((size_t)(all->n ? all->n : 1) * sizeof *out->v);
    if (!out->v) return -1;
    out->cap = all->n;
    for (uint32_t i = 0; i < all->n; i++) {
        if ((all->v[i].level > top) != hd) continue;
        if ((int)i == all->active) out->active = (int)out->n;
        out->v[out->n++] = all->v[i];
    }
    for (unsigned l = hd ? top + 1 : 0; l < ST_MAX_LEVELS && (hd || l <= top); l++) {
        out->base[l] = all->base[l];
        out->base_cap[l] = all->base_cap[l];
        out->bpos[l] = all->bpos[l];
        out->bpos_cap[l] = all->bpos_cap[l];
    }
    return 0;
}

int st_doc_save_session(const st_doc *d, const char *path, const st_session_view *view, const st_session_tool *tool,
                        int (*progress)(void *ctx, double fraction), void *ctx, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    /* With the box on, the adaptive state belongs to the display copy, not
     * to the model: the box and its levels are saved and the display is
     * rebuilt from them on load. */
    unsigned top = d->h.map.top;
    st_layers model_layers, hd_layers;
    if (layers_view(&d->layers, top, 0, &model_layers)) return st_fail(err, ST_ERR_MEMORY, "out of memory");
    if (layers_view(&d->layers, top, 1, &hd_layers)) {
        free(model_layers.v);
        return st_fail(err, ST_ERR_MEMORY, "out of memory");
    }
    st_session_ref r = {
        .h = &d->h,
        .adapt = NULL,
        .box = &d->box,
        .box_on = d->box_on,
        .edit_level = d->edit_level,
        .display_level = d->display_level,
        .view = view,
        .base = d->base.nverts ? &d->base : NULL,
        .layers = &model_layers,
        .mask = &d->mask,
        .tool = tool,
    };
    /* HD levels with sculpted detail: the display itself, in chunk hdlv
     * (older readers skip it and get the uniform model). */
    if (ed_hd_detail_present(d)) {
        r.hd = &d->display.hier;
        r.hd_adapt = &d->display.adapt;
        r.hd_from = top;
        r.hd_layers = &hd_layers;
    }
    /* The first report before anything is written (core's come after each
     * buffer). */
    int rc;
    if (progress && progress(ctx, 0)) rc = st_fail(err, ST_ERR_INVALID, "%s: cancelled (the file is as it was)", path);
    else rc = st_session_save_ref_progress(path, &r, progress, ctx, err);
    free(model_layers.v);
    free(hd_layers.v);
    return rc;
}
