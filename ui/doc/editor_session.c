/* Saving the document as a session (editor.h, st_doc_save_session): what
 * core/io/session.h stores, taken from the document by reference. */
#include "editor_internal.h"

#include "core/io/session.h"

int st_doc_save_session(const st_doc *d, const char *path, const st_session_view *view, const st_session_tool *tool,
                        int (*progress)(void *ctx, double fraction), void *ctx, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    /* With the box on, the adaptive state belongs to the display copy, not
     * to the model: the box and its levels are saved and the display is
     * rebuilt from them on load. */
    st_session_ref r = {
        .h = &d->h,
        .adapt = NULL,
        .box = &d->box,
        .box_on = d->box_on,
        .edit_level = d->edit_level,
        .display_level = d->display_level,
        .view = view,
        .base = d->base.nverts ? &d->base : NULL,
        .layers = &d->layers,
        .mask = &d->mask,
        .tool = tool,
    };
    /* HD levels with sculpted detail: the display itself, in chunk hdlv
     * (older readers skip it and get the uniform model). */
    if (ed_hd_detail_present(d)) {
        r.hd = &d->display.hier;
        r.hd_adapt = &d->display.adapt;
        r.hd_from = d->h.map.top;
    }
    /* The first report before anything is written (core's come after each
     * buffer). */
    if (progress && progress(ctx, 0)) return st_fail(err, ST_ERR_INVALID, "%s: cancelled (the file is as it was)", path);
    return st_session_save_ref_progress(path, &r, progress, ctx, err);
}
