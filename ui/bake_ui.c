/* Baking from the window (docs/MODELLER.md, docs/BAKING.md; window.h st_app_bake): the Bake
 * dialog's settings (ui/gui.cc draws them), what the last bake wrote, and
 * View > Show baked map, which draws the bake's base level with its normal
 * map (render/nmap.h, as `strata render --normal-map`) instead of the
 * surface.  The bake itself runs as a job (ui/jobs.c, st_app_bake_maps)
 * through formats/bake_run.h, the driver strata bake uses. */
#include "window.h"

#include <stdio.h>
#include <string.h>

#include "core/fvar/fvar.h"

void st_app_bake_defaults(st_app *a)
{
    st_app_bake *b = &a->bake;
    unsigned top = a->doc.loaded ? a->doc.h.map.top : 0;
    if (!b->size) {
        b->size = 1024;
        b->padding = 8;
        b->udim = -1;
        b->want_normal = 1;
    }
    if (b->base < 0 || (unsigned)b->base > top) b->base = 0;
    if (b->level < 0 || (unsigned)b->level > top) b->level = (int)top;
    if (b->level < b->base) b->level = b->base;
    /* A level without UVs bakes onto an atlas of charts. */
    if (a->doc.loaded && !st_hier_has_uv(&a->doc.h, (unsigned)b->base)) b->auto_uv = 1;
    if (!b->normal[0] || !b->disp[0]) {
        /* STEM_normal.png and STEM_disp.exr beside the document. */
        const char *doc = a->doc.loaded && !a->showing_default ? a->doc.path : "";
        const char *base = st_path_base(doc), *dot = strrchr(base, '.');
        int dir = (int)(base - doc), stem = dot ? (int)(dot - base) : (int)strlen(base);
        if (!doc[0]) { base = "model"; stem = 5; }
        if (!b->normal[0]) snprintf(b->normal, sizeof b->normal, "%.*s%.*s_normal.png", dir, doc, stem, base);
        if (!b->disp[0]) snprintf(b->disp, sizeof b->disp, "%.*s%.*s_disp.exr", dir, doc, stem, base);
    }
}

void st_app_bake_forget(st_app *a)
{
    st_app_bake *b = &a->bake;
    b->have = 0;
    b->show = 0;
    b->attach = 0;
    b->base = b->level = -1;
    b->normal[0] = b->disp[0] = 0;
}

int st_app_can_show_baked(const st_app *a)
{
    return a->bake.have && a->doc.loaded && a->bake.have_base <= a->doc.h.map.top;
}

/* The base level's triangles with the layout the bake used, and the map. */
static int build_view(st_app *a, st_error *err)
{
    st_app_bake *b = &a->bake;
    st_hier *h = &a->doc.h;
    st_bake_layout lay;
    int rc = !b->have_auto_uv && st_hier_has_uv(h, b->have_base) ? st_bake_level_uvs(h, b->have_base, &lay, err)
                                                              : st_bake_chart_uvs(h, b->have_base, b->have_size, b->have_padding,
                                                                                  &lay, NULL, err);
    if (rc) return rc;
    st_bake_uvs uvs = st_bake_layout_uvs(&lay);
    st_nmap_mesh mesh = { 0 };
    rc = st_nmap_mesh_build(h, b->have_base, &uvs, &mesh, err);
    if (!rc) {
        /* A fresh program and buffers: the old tiles' textures go with them. */
        if (b->nm_init) st_nmap_free(&b->nm);
        b->nm_init = 0;
        rc = st_nmap_init(&b->nm, &a->gl, err);
        if (!rc) {
            b->nm_init = 1;
            st_nmap_set_mesh(&b->nm, &mesh);
            rc = st_nmap_load_map(&b->nm, &mesh, b->have_map, err);
        }
    }
    st_nmap_mesh_free(&mesh);
    st_bake_layout_free(&lay);
    return rc;
}

int st_app_draw_baked(st_app *a)
{
    st_app_bake *b = &a->bake;
    if (!b->show || !st_app_can_show_baked(a)) return 0;
    if (!b->nm_ok || b->nm_serial != b->serial || b->nm_revision != a->doc.revision) {
        st_error err;
        b->nm_serial = b->serial;
        b->nm_revision = a->doc.revision;
        b->nm_ok = !build_view(a, &err);
        if (!b->nm_ok) {
            b->show = 0;
            st_app_message(a, 1, "cannot show the baked map: %s", err.msg);
            return 0;
        }
    }
    st_nmap_draw(&b->nm, &a->cc.cam, a->fb_w, a->fb_h, b->have_space == ST_BAKE_OBJECT ? ST_NMAP_OBJECT : ST_NMAP_TANGENT);
    return 1;
}

void st_app_bake_free(st_app *a)
{
    if (a->bake.nm_init) st_nmap_free(&a->bake.nm);
    a->bake.nm_init = a->bake.nm_ok = 0;
}
