/* `strata render --normal-map N.png`: level L drawn with a baked normal map
 * (render/nmap.h) on the UV layout strata bake used: the level's own UVs,
 * or the atlas of strata bake --auto-uv for a level without UVs or when
 * auto_uv is set (a map baked with --auto-uv on a level that has UVs). */
#ifndef ST_RENDER_NMAP_H
#define ST_RENDER_NMAP_H

#include "render/offscreen.h"
#include "core/multires/hier.h"

/* Draws level `level` of h with the map in map_path (PNG, any size, row 0 =
 * v = 0; tangent space unless object_space) into rgba, framed as
 * st_offscreen_draw frames spec.  *faces receives the level's face count. */
int st_render_normal_mapped(st_offscreen *off, st_hier *h, const st_render_spec *spec, const char *map_path,
                            int object_space, int auto_uv, unsigned char *rgba, uint32_t *faces, st_error *err);

#endif
