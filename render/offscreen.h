/* One-shot headless pictures of a map level: the renderer on an OSMesa
 * context, framed by the camera, read back as an RGBA image.  Used by
 * `strata render`, the image tests and the benchmark.
 *
 *     st_offscreen o;
 *     st_offscreen_init(&o, 640, 480, &err);
 *     st_render_spec s = st_render_spec_default();
 *     s.level = 3;
 *     st_offscreen_prepare(&o, &h.map, &s, &err);  // buffers for the levels
 *     st_offscreen_draw(&o, &s, rgba, &err);        // 640*480*4 bytes
 *     st_offscreen_free(&o);
 */
#ifndef ST_OFFSCREEN_H
#define ST_OFFSCREEN_H

#include "render/headless.h"
#include "render/renderer.h"

typedef struct st_render_spec {
    unsigned level;           /* displayed level */
    int cage_level;           /* level of the control mesh drawn in ST_MODE_CAGE (default 0) */
    int mode;                 /* enum st_render_mode */
    int view;                 /* enum st_view_preset, or -1: the orbit below */
    float az, el, dist;       /* orbit (degrees, degrees, model units; dist <= 0: fit) */
    int has_box;              /* draw the interest box box[0..2] - box[3..5] */
    st_uv_map uv;             /* ST_MODE_UV: the displayed level's UVs (core/fvar/fvar.h; st_hier_uv); uv.uv NULL: none */
    float box[6];
} st_render_spec;

st_render_spec st_render_spec_default(void);

typedef struct st_offscreen {
    st_headless hl;
    st_renderer r;
    int has_renderer;
} st_offscreen;

#define ST_OFFSCREEN_SAMPLES 4
#define ST_OFFSCREEN_MSAA_MAX_PIXELS (2048 * 2048)

int st_offscreen_init(st_offscreen *o, int width, int height, st_error *err);
/* Bytes st_offscreen_init(o, width, height) takes for its framebuffers, at
 * most (an estimate for --mem-budget, before anything is allocated). */
size_t st_offscreen_bytes(int width, int height);
/* Builds and uploads the displayed level (and the cage level for
 * ST_MODE_CAGE, the UVs s->uv for ST_MODE_UV: ST_ERR_INVALID when NULL)
 * of m. */
int st_offscreen_prepare(st_offscreen *o, const st_map *m, const st_render_spec *s, st_error *err);
/* Frames the camera on what is shown, draws, and reads the image back
 * (width*height*4 bytes, top row first). */
int st_offscreen_draw(st_offscreen *o, const st_render_spec *s, unsigned char *rgba, st_error *err);
/* The camera st_offscreen_draw uses for s. */
void st_offscreen_camera(const st_offscreen *o, const st_render_spec *s, st_camera *cam);
void st_offscreen_free(st_offscreen *o);

#endif
