/* Session files (session.h, docs/SESSION-FORMAT.md): a session's lifetime
 * and the recovery file's place; the writer is session_write.c, the reader
 * session_read.c. */
#include "core/io/session_internal.h"
#include "core/base/membudget.h"
#include "core/io/atomic_file.h"
#include "core/io/file_open.h"
#include "core/io/map_io_internal.h"
#include "core/map/pool_internal.h"
#include "core/progressive/progressive.h"
#include "core/fvar/fvar_internal.h"

#include <errno.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* ---- lifetime ----------------------------------------------------------------- */

void st_session_init(st_session *s)
{
    memset(s, 0, sizeof *s);
    st_layers_init(&s->layers);
    st_layers_init(&s->hd_layers);
    st_map_init(&s->h.map);
    st_mla_init(&s->h.edge_sharp, sizeof(float));
    st_mla_init(&s->h.vertex_sharp, sizeof(float));
    st_map_init(&s->hd.map);
    st_mla_init(&s->hd.edge_sharp, sizeof(float));
    st_mla_init(&s->hd.vertex_sharp, sizeof(float));
    st_mesh_init(&s->base);
}

void st_session_free(st_session *s)
{
    if (s->has_adapt) st_adapt_free(&s->adapt);
    st_hier_free(&s->h);
    if (s->has_hd) st_adapt_free(&s->hd_adapt);
    st_hier_free(&s->hd);
    st_mesh_free(&s->base);
    st_layers_free(&s->layers);
    st_layers_free(&s->hd_layers);
    st_mask_free(&s->mask);
    st_session_init(s);
}

void st_session_move_hier(st_hier *dst, st_hier *src)
{
    *dst = *src;
    st_map *m = &dst->map;
    for (uint32_t i = 0; i < m->ndart_attrs && i < 4; i++)
        if (m->dart_attrs[i] == &src->edge_sharp) m->dart_attrs[i] = &dst->edge_sharp;
    for (uint32_t i = 0; i < m->nvert_attrs && i < 4; i++)
        if (m->vert_attrs[i] == &src->vertex_sharp) m->vert_attrs[i] = &dst->vertex_sharp;
    memset(src, 0, sizeof *src);
    st_map_init(&src->map);
    st_mla_init(&src->edge_sharp, sizeof(float));
    st_mla_init(&src->vertex_sharp, sizeof(float));
}

void st_session_move_adapt(st_adapt *dst, st_adapt *src, st_hier *h)
{
    *dst = *src;
    dst->h = h;
    memset(src, 0, sizeof *src);
}

/* Moves without freeing dst (dst's content is garbage or already freed). */
void st_session_move_raw(st_session *dst, st_session *src)
{
    st_session_move_hier(&dst->h, &src->h);
    dst->has_adapt = src->has_adapt;
    if (src->has_adapt) st_session_move_adapt(&dst->adapt, &src->adapt, &dst->h);
    else memset(&dst->adapt, 0, sizeof dst->adapt);
    dst->box = src->box;
    dst->box_on = src->box_on;
    dst->edit_level = src->edit_level;
    dst->display_level = src->display_level;
    dst->has_view = src->has_view;
    dst->view = src->view;
    dst->has_base = src->has_base;
    dst->base = src->base;
    dst->layers = src->layers;
    dst->mask = src->mask;
    dst->has_tool = src->has_tool;
    dst->tool = src->tool;
    st_session_move_hier(&dst->hd, &src->hd);
    dst->has_hd = src->has_hd;
    dst->hd_from = src->hd_from;
    dst->hd_layers = src->hd_layers;
    if (src->has_hd) st_session_move_adapt(&dst->hd_adapt, &src->hd_adapt, &dst->hd);
    else memset(&dst->hd_adapt, 0, sizeof dst->hd_adapt);
    st_mesh_init(&src->base);
    st_session_init(src);
}

void st_session_move(st_session *dst, st_session *src)
{
    if (dst == src) return;
    st_session_free(dst);
    st_session_move_raw(dst, src);
}

st_session_ref st_session_ref_of(const st_session *s)
{
    st_session_ref r = { 0 };
    r.h = &s->h;
    r.adapt = s->has_adapt ? &s->adapt : NULL;
    r.box = &s->box;
    r.box_on = s->box_on;
    r.edit_level = s->edit_level;
    r.display_level = s->display_level;
    r.view = s->has_view ? &s->view : NULL;
    r.base = s->has_base ? &s->base : NULL;
    r.layers = &s->layers;
    r.mask = &s->mask;
    r.tool = s->has_tool ? &s->tool : NULL;
    if (s->has_hd) {
        r.hd = &s->hd;
        r.hd_adapt = &s->hd_adapt;
        r.hd_from = s->hd_from;
        r.hd_layers = &s->hd_layers;
    }
    return r;
}

int st_session_is_path(const char *path)
{
    return path && st_path_has_ext(path, ".strata");
}

/* ---- recovery file ------------------------------------------------------------------- */

int st_session_recovery_path(char *buf, size_t n)
{
    const char *env = getenv("STRATA_RECOVERY");
    int k;
    if (env && *env) k = snprintf(buf, n, "%s", env);
    else {
        const char *xdg = getenv("XDG_STATE_HOME"), *home = getenv("HOME");
        if (xdg && *xdg == '/') k = snprintf(buf, n, "%s/strata/recovery.strata", xdg);
        else if (home && *home) k = snprintf(buf, n, "%s/.local/state/strata/recovery.strata", home);
        else return -1;
    }
    if (k < 0 || (size_t)k >= n) return -1;
    return st_mkdir_parents(buf);
}
