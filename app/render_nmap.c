/* `strata render --normal-map` (app/render_nmap.h). */
#include "render_nmap.h"
#include "render/image.h"
#include "render/nmap.h"
#include "core/bake/bake.h"
#include "core/fvar/fvar.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int st_render_normal_mapped(st_offscreen *off, st_hier *h, const st_render_spec *spec, const char *map_path,
                            int object_space, int auto_uv, unsigned char *rgba, uint32_t *faces, st_error *err)
{
    int rc = st_bake_check_scheme(h, err);
    if (rc) return rc;
    int tw = 0, th = 0;
    unsigned char *tex = NULL;
    /* NAME.<UDIM>.png: one image per UV tile (strata bake's UDIM output). */
    const char *tok = strstr(map_path, "<UDIM>");
    if (!tok) rc = st_png_read(map_path, &tw, &th, &tex, err);
    if (rc) return rc;
    /* The layout strata bake used: the level's own UVs, or for a level
     * without UVs the atlas of strata bake --auto-uv, made again for the
     * map's size and bake's default padding (st_bake_chart_uvs). */
    st_bake_layout lay;
    st_nmap_mesh mesh = { 0 };
    st_nmap nm = { 0 };
    rc = !auto_uv && st_hier_has_uv(h, spec->level) ? st_bake_level_uvs(h, spec->level, &lay, err)
                                    : st_bake_chart_uvs(h, spec->level, tw > 0 ? (uint32_t)tw : 2048, ST_BAKE_AUTO_PADDING, &lay, NULL, err);
    if (rc) { free(tex); return rc; }
    st_bake_uvs uvs = st_bake_layout_uvs(&lay);
    *faces = lay.nfaces;
    rc = st_nmap_mesh_build(h, spec->level, &uvs, &mesh, err);
    /* The renderer's own upload of the level frames the camera as a plain
     * render of the level would. */
    if (!rc) rc = st_offscreen_prepare(off, &h->map, spec, err);
    if (!rc) rc = st_nmap_init(&nm, &off->hl.gl, err);
    if (!rc) {
        st_headless_begin(&off->hl);
        st_nmap_set_mesh(&nm, &mesh);
        if (tok) rc = st_nmap_load_map(&nm, &mesh, map_path, err);
        else st_nmap_set_map(&nm, tex, tw, th);
    }
    if (!rc) {
        st_camera cam;
        st_offscreen_camera(off, spec, &cam);
        st_nmap_draw(&nm, &cam, off->hl.width, off->hl.height, object_space ? ST_NMAP_OBJECT : ST_NMAP_TANGENT);
        rc = st_headless_read(&off->hl, rgba, err);
    }
    st_nmap_free(&nm);
    st_nmap_mesh_free(&mesh);
    st_bake_layout_free(&lay);
    free(tex);
    return rc;
}
