#include "render/offscreen.h"

#include <string.h>

st_render_spec st_render_spec_default(void)
{
    st_render_spec s;
    memset(&s, 0, sizeof s);
    s.mode = ST_MODE_SMOOTH;
    s.view = ST_VIEW_ISO;
    return s;
}

/* Multisampling up to 4 Mpixels; larger images (up to 8192x8192) are
 * drawn without it rather than asking llvmpipe for gigabytes. */
static int samples_for(int width, int height)
{
    return (long long)width * height <= ST_OFFSCREEN_MSAA_MAX_PIXELS ? ST_OFFSCREEN_SAMPLES : 1;
}

size_t st_offscreen_bytes(int width, int height)
{
    /* Per pixel: OSMesa's RGBA buffer, the driver's own colour and 32-bit
     * depth surfaces it renders into, 4 bytes each; with multisampling,
     * colour and depth once per sample on top. */
    size_t px = (size_t)width * (size_t)height;
    int s = samples_for(width, height);
    return px * 12 + (s > 1 ? px * 8 * (size_t)s : 0);
}

int st_offscreen_init(st_offscreen *o, int width, int height, st_error *err)
{
    memset(o, 0, sizeof *o);
    int samples = samples_for(width, height);
    int rc = st_headless_init(&o->hl, width, height, samples, err);
    if (rc) return rc;
    rc = st_renderer_init(&o->r, &o->hl.gl, err);
    if (rc) { st_headless_free(&o->hl); return rc; }
    o->has_renderer = 1;
    return ST_OK;
}

int st_offscreen_prepare(st_offscreen *o, const st_map *m, const st_render_spec *s, st_error *err)
{
    st_headless_begin(&o->hl);
    int rc = st_renderer_set_level(&o->r, m, s->level, err);
    if (rc) return rc;
    if (s->mode == ST_MODE_UV) {
        if (!s->uv.uv) return st_fail(err, ST_ERR_INVALID, "render: level %u has no UVs to draw the checker with", s->level);
        rc = st_renderer_set_uvs(&o->r, m, &s->uv, err);
        if (rc) return rc;
    }
    if (s->mode == ST_MODE_CAGE) {
        unsigned cl = s->cage_level < 0 ? 0 : (unsigned)s->cage_level;
        if (cl > m->top) cl = m->top;
        rc = st_renderer_set_cage(&o->r, m, cl, err);
    } else {
        st_renderer_clear_cage(&o->r);
    }
    return rc;
}

static void bbox_union(float b[6], const float c[6])
{
    for (int i = 0; i < 3; i++) {
        if (c[i] < b[i]) b[i] = c[i];
        if (c[i + 3] > b[i + 3]) b[i + 3] = c[i + 3];
    }
}

void st_offscreen_camera(const st_offscreen *o, const st_render_spec *s, st_camera *cam)
{
    float b[6];
    memcpy(b, o->r.surf.bbox, sizeof b);
    if (o->r.has_cage) bbox_union(b, o->r.cage.bbox);
    if (s->has_box) {
        float c[6];
        for (int i = 0; i < 3; i++) {
            c[i] = s->box[i] < s->box[i + 3] ? s->box[i] : s->box[i + 3];
            c[i + 3] = s->box[i] < s->box[i + 3] ? s->box[i + 3] : s->box[i];
        }
        bbox_union(b, c);
    }
    float az = s->az, el = s->el, dist = s->dist;
    if (s->view >= 0) { st_view_angles(s->view, &az, &el); dist = 0; }
    memset(cam, 0, sizeof *cam);
    cam->fovy = 30;
    st_camera_frame(cam, b, az, el, dist, (float)o->hl.width / (float)o->hl.height);
}

int st_offscreen_draw(st_offscreen *o, const st_render_spec *s, unsigned char *rgba, st_error *err)
{
    st_headless_begin(&o->hl);
    st_camera cam;
    st_offscreen_camera(o, s, &cam);
    st_renderer_set_box(&o->r, s->box, s->box + 3, s->has_box);
    st_draw_opts opts;
    st_render_mode_opts(s->mode, &opts);
    /* Lines and points scale gently with the image so that small test
     * images and large screenshots look alike. */
    int mn = o->hl.width < o->hl.height ? o->hl.width : o->hl.height;
    opts.line_width = mn >= 600 ? 1.5f : 1.0f;
    opts.point_size = mn >= 600 ? 7.0f : 4.0f;
    st_renderer_draw(&o->r, &cam, o->hl.width, o->hl.height, &opts);
    return st_headless_read(&o->hl, rgba, err);
}

void st_offscreen_free(st_offscreen *o)
{
    if (o->has_renderer) {
        st_headless_begin(&o->hl);
        st_renderer_free(&o->r);
    }
    st_headless_free(&o->hl);
    memset(o, 0, sizeof *o);
}
