#include "render/camera.h"

#include <math.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)
#define FIT_MARGIN 1.08f          /* image border left around the framed box */

static const struct { const char *name; float az, el; } presets[ST_VIEW_COUNT] = {
    [ST_VIEW_FRONT] = { "front", 0, 0 },
    [ST_VIEW_BACK] = { "back", 180, 0 },
    [ST_VIEW_LEFT] = { "left", -90, 0 },
    [ST_VIEW_RIGHT] = { "right", 90, 0 },
    [ST_VIEW_TOP] = { "top", 0, 90 },
    [ST_VIEW_ISO] = { "iso", 45, 35.26439f },
};

int st_view_parse(const char *name)
{
    for (int i = 0; i < ST_VIEW_COUNT; i++)
        if (!strcmp(name, presets[i].name)) return i;
    return -1;
}

const char *st_view_name(int p) { return p >= 0 && p < ST_VIEW_COUNT ? presets[p].name : "?"; }

void st_view_angles(int p, float *az, float *el)
{
    if (p < 0 || p >= ST_VIEW_COUNT) p = ST_VIEW_ISO;
    *az = presets[p].az;
    *el = presets[p].el;
}

/* Orthonormal camera frame: dir (target -> eye), right, up. */
static void frame(float az, float el, double dir[3], double right[3], double up[3])
{
    double a = az * DEG, e = el * DEG;
    dir[0] = cos(e) * sin(a); dir[1] = sin(e); dir[2] = cos(e) * cos(a);
    /* d dir / d el: the up vector, well defined even looking straight down. */
    up[0] = -sin(e) * sin(a); up[1] = cos(e); up[2] = -sin(e) * cos(a);
    right[0] = up[1] * dir[2] - up[2] * dir[1];
    right[1] = up[2] * dir[0] - up[0] * dir[2];
    right[2] = up[0] * dir[1] - up[1] * dir[0];
}

void st_camera_frame(st_camera *c, const float b[6], float az, float el, float dist, float aspect)
{
    if (!(aspect > 0)) aspect = 1;
    if (c->fovy <= 0) c->fovy = 30;
    c->az = az;
    c->el = el;
    for (int i = 0; i < 3; i++) c->target[i] = 0.5f * (b[i] + b[i + 3]);
    double dir[3], right[3], up[3];
    frame(az, el, dir, right, up);
    double tv = tan(0.5 * c->fovy * DEG) / FIT_MARGIN, th = tv * aspect;
    double need = 0, zmax = 0, rad = 0, hmax = 0, vmax = 0;
    for (int k = 0; k < 8; k++) {
        double p[3] = { (k & 1 ? b[3] : b[0]) - c->target[0],
                        (k & 2 ? b[4] : b[1]) - c->target[1],
                        (k & 4 ? b[5] : b[2]) - c->target[2] };
        double x = p[0] * right[0] + p[1] * right[1] + p[2] * right[2];
        double y = p[0] * up[0] + p[1] * up[1] + p[2] * up[2];
        double z = p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2];
        /* The corner is in the frustum when its depth from the eye,
         * D - z, is at least |x| / tan(hfov/2) and |y| / tan(vfov/2). */
        double dx = z + fabs(x) / th, dy = z + fabs(y) / tv;
        if (dx > need) need = dx;
        if (dy > need) need = dy;
        if (z > zmax) zmax = z;
        if (fabs(x) > hmax) hmax = fabs(x);
        if (fabs(y) > vmax) vmax = fabs(y);
        double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (r > rad) rad = r;
    }
    if (!(rad > 0)) rad = 1;
    if (!(need > zmax)) need = zmax + rad;
    c->dist = dist > 0 ? dist : (float)need;
    /* Orthographic height that frames the same box. */
    double oh = 2 * (vmax > hmax / aspect ? vmax : hmax / aspect) * FIT_MARGIN;
    c->ortho_height = (float)(oh > 0 ? oh : 2 * rad);
    double nearp = c->dist - rad * 1.05;
    if (nearp < c->dist * 1e-3) nearp = c->dist * 1e-3;
    c->znear = (float)nearp;
    c->zfar = (float)(c->dist + rad * 1.05);
}

void st_camera_eye(const st_camera *c, float eye[3])
{
    double dir[3], right[3], up[3];
    frame(c->az, c->el, dir, right, up);
    for (int i = 0; i < 3; i++) eye[i] = c->target[i] + (float)(c->dist * dir[i]);
}

void st_camera_view(const st_camera *c, float m[16])
{
    double dir[3], r[3], u[3];
    frame(c->az, c->el, dir, r, u);
    double e[3];
    for (int i = 0; i < 3; i++) e[i] = c->target[i] + c->dist * dir[i];
    /* Rows of the rotation: right, up, dir (the eye looks along -dir). */
    const double *rows[3] = { r, u, dir };
    for (int i = 0; i < 3; i++) {
        m[0 + i] = (float)rows[i][0];
        m[4 + i] = (float)rows[i][1];
        m[8 + i] = (float)rows[i][2];
        m[12 + i] = (float)-(rows[i][0] * e[0] + rows[i][1] * e[1] + rows[i][2] * e[2]);
    }
    m[3] = m[7] = m[11] = 0;
    m[15] = 1;
}

void st_camera_proj(const st_camera *c, float aspect, float m[16])
{
    memset(m, 0, 16 * sizeof *m);
    double n = c->znear, f = c->zfar;
    if (!(aspect > 0)) aspect = 1;
    if (c->ortho) {
        double h = 0.5 * c->ortho_height, w = h * aspect;
        m[0] = (float)(1 / w);
        m[5] = (float)(1 / h);
        m[10] = (float)(-2 / (f - n));
        m[14] = (float)(-(f + n) / (f - n));
        m[15] = 1;
    } else {
        double t = 1 / tan(0.5 * c->fovy * DEG);
        m[0] = (float)(t / aspect);
        m[5] = (float)t;
        m[10] = (float)((f + n) / (n - f));
        m[11] = -1;
        m[14] = (float)(2 * f * n / (n - f));
    }
}
