/* Camera controls; see camera_ctl.h. */
#include "camera_ctl.h"

#include <math.h>
#include <string.h>

#define ORBIT_DEG_PER_PIXEL 0.4f
#define ZOOM_STEP 0.88f

static void update_clip(st_camctl *c)
{
    float eye[3];
    st_camera_eye(&c->cam, eye);
    double dc = 0;
    for (int i = 0; i < 3; i++) {
        double d = eye[i] - 0.5 * (c->bbox[i] + c->bbox[i + 3]);
        dc += d * d;
    }
    dc = sqrt(dc);
    double r = c->radius > 0 ? c->radius : 1;
    /* Room for edits that pull the model out of its framed box. */
    double n = dc - 2 * r, f = dc + 2 * r;
    if (!c->cam.ortho && n < 0.002 * r) n = 0.002 * r;
    if (f <= n) f = n + r;
    c->cam.znear = (float)n;
    c->cam.zfar = (float)f;
}

static void set_bbox(st_camctl *c, const float bbox[6])
{
    memcpy(c->bbox, bbox, sizeof c->bbox);
    double d = 0;
    for (int i = 0; i < 3; i++) d += (double)(bbox[i + 3] - bbox[i]) * (bbox[i + 3] - bbox[i]);
    c->radius = (float)(0.5 * sqrt(d));
    if (!(c->radius > 0)) c->radius = 1;
}

void st_camctl_init(st_camctl *c, const float bbox[6], float aspect)
{
    memset(c, 0, sizeof *c);
    c->cam.fovy = 30;
    set_bbox(c, bbox);
    float az, el;
    st_view_angles(ST_VIEW_ISO, &az, &el);
    st_camera_frame(&c->cam, bbox, az, el, 0, aspect);
    update_clip(c);
}

void st_camctl_frame_all(st_camctl *c, const float bbox[6], float aspect)
{
    int ortho = c->cam.ortho;
    set_bbox(c, bbox);
    st_camera_frame(&c->cam, bbox, c->cam.az, c->cam.el, 0, aspect);
    c->cam.ortho = ortho;
    update_clip(c);
}

void st_camctl_view(st_camctl *c, int view, float aspect)
{
    static const float ang[6][2] = { { 0, 0 }, { 180, 0 }, { 90, 0 }, { -90, 0 }, { 0, 90 }, { 0, -90 } };
    if (view < 0 || view > 5) return;
    int ortho = c->cam.ortho;
    st_camera_frame(&c->cam, c->bbox, ang[view][0], ang[view][1], 0, aspect);
    c->cam.ortho = ortho;
    update_clip(c);
}

void st_camctl_toggle_ortho(st_camctl *c)
{
    /* Keep the apparent size at the target: ortho height = the
     * perspective view's height at the target's distance. */
    if (!c->cam.ortho)
        c->cam.ortho_height = (float)(2 * c->cam.dist * tan(0.5 * c->cam.fovy * 3.14159265358979323846 / 180));
    else
        c->cam.dist = (float)(0.5 * c->cam.ortho_height / tan(0.5 * c->cam.fovy * 3.14159265358979323846 / 180));
    c->cam.ortho = !c->cam.ortho;
    update_clip(c);
}

void st_camctl_orbit(st_camctl *c, float dx, float dy)
{
    c->cam.az -= dx * ORBIT_DEG_PER_PIXEL;
    c->cam.el += dy * ORBIT_DEG_PER_PIXEL;
    while (c->cam.az > 180) c->cam.az -= 360;
    while (c->cam.az < -180) c->cam.az += 360;
    while (c->cam.el > 180) c->cam.el -= 360;
    while (c->cam.el < -180) c->cam.el += 360;
    update_clip(c);
}

void st_camctl_axes(const st_camctl *c, double right[3], double up[3], double back[3])
{
    float m[16];
    st_camera_view(&c->cam, m);
    for (int i = 0; i < 3; i++) {
        right[i] = m[4 * i];
        up[i] = m[4 * i + 1];
        back[i] = m[4 * i + 2];
    }
}

static double target_pixel(const st_camctl *c, int h, double depth)
{
    if (h < 1) h = 1;
    if (c->cam.ortho) return c->cam.ortho_height / h;
    return 2 * depth * tan(0.5 * c->cam.fovy * 3.14159265358979323846 / 180) / h;
}

void st_camctl_pan(st_camctl *c, float dx, float dy, int w, int h)
{
    (void)w;
    double r[3], u[3], b[3];
    st_camctl_axes(c, r, u, b);
    double px = target_pixel(c, h, c->cam.dist);
    for (int i = 0; i < 3; i++) c->cam.target[i] += (float)(px * (-dx * r[i] + dy * u[i]));
    update_clip(c);
}

void st_camctl_zoom(st_camctl *c, float steps)
{
    float f = powf(ZOOM_STEP, steps);
    if (c->cam.ortho) c->cam.ortho_height *= f;
    else {
        c->cam.dist *= f;
        if (c->cam.dist < 1e-4f * c->radius) c->cam.dist = 1e-4f * c->radius;
    }
    update_clip(c);
}

/* ---- projection --------------------------------------------------------------- */

static void mvp(const st_camctl *c, int w, int h, double m[16])
{
    float v[16], p[16];
    st_camera_view(&c->cam, v);
    st_camera_proj(&c->cam, h > 0 ? (float)w / (float)h : 1, p);
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += (double)p[4 * k + row] * v[4 * col + k];
            m[4 * col + row] = s;
        }
}

static int invert4(const double m[16], double inv[16])
{
    double a[4][8];
    for (int r = 0; r < 4; r++)
        for (int k = 0; k < 8; k++) a[r][k] = k < 4 ? m[4 * k + r] : (k - 4 == r);
    for (int col = 0; col < 4; col++) {
        int piv = col;
        for (int r = col + 1; r < 4; r++) if (fabs(a[r][col]) > fabs(a[piv][col])) piv = r;
        if (fabs(a[piv][col]) < 1e-300) return -1;
        if (piv != col) for (int k = 0; k < 8; k++) { double t = a[col][k]; a[col][k] = a[piv][k]; a[piv][k] = t; }
        double d = a[col][col];
        for (int k = 0; k < 8; k++) a[col][k] /= d;
        for (int r = 0; r < 4; r++) {
            if (r == col) continue;
            double f = a[r][col];
            if (f != 0) for (int k = 0; k < 8; k++) a[r][k] -= f * a[col][k];
        }
    }
    for (int r = 0; r < 4; r++)
        for (int k = 0; k < 4; k++) inv[4 * k + r] = a[r][k + 4];
    return 0;
}

int st_camctl_project(const st_camctl *c, int w, int h, const double p[3], double s[2], double *depth)
{
    double m[16], q[4];
    mvp(c, w, h, m);
    for (int r = 0; r < 4; r++) q[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    if (q[3] <= 1e-12) return 0;
    s[0] = (q[0] / q[3] * 0.5 + 0.5) * w;
    s[1] = (0.5 - q[1] / q[3] * 0.5) * h;
    if (depth) *depth = q[2] / q[3] * 0.5 + 0.5;
    return 1;
}

void st_camctl_unproject(const st_camctl *c, int w, int h, double x, double y, double z, double p[3])
{
    double m[16], inv[16];
    mvp(c, w, h, m);
    if (invert4(m, inv)) { p[0] = p[1] = p[2] = 0; return; }
    double n[4] = { 2 * x / (w > 0 ? w : 1) - 1, 1 - 2 * y / (h > 0 ? h : 1), 2 * z - 1, 1 };
    double q[4];
    for (int r = 0; r < 4; r++) q[r] = inv[r] * n[0] + inv[4 + r] * n[1] + inv[8 + r] * n[2] + inv[12 + r] * n[3];
    double iw = fabs(q[3]) > 1e-300 ? 1 / q[3] : 0;
    for (int i = 0; i < 3; i++) p[i] = q[i] * iw;
}

double st_camctl_pixel_size(const st_camctl *c, int w, int h, const double p[3])
{
    (void)w;
    if (c->cam.ortho) return target_pixel(c, h, 0);
    float eye[3];
    st_camera_eye(&c->cam, eye);
    double r[3], u[3], b[3];
    st_camctl_axes(c, r, u, b);
    double depth = 0;
    for (int i = 0; i < 3; i++) depth += (eye[i] - p[i]) * b[i];
    if (depth < 1e-9) depth = 1e-9;
    return target_pixel(c, h, depth);
}

void st_camctl_screen_delta(const st_camctl *c, int w, int h, const double p[3], double dx, double dy, double out[3])
{
    double r[3], u[3], b[3];
    st_camctl_axes(c, r, u, b);
    double px = st_camctl_pixel_size(c, w, h, p);
    for (int i = 0; i < 3; i++) out[i] = px * (dx * r[i] - dy * u[i]);
}
