/* Camera controls of the modeller window (Blender conventions), on top of
 * render/camera.h: orbit, pan, zoom, framing, view presets, projection of
 * points to the screen and of screen motions back into the scene.
 *
 * Screen coordinates are framebuffer pixels with the origin at the top left
 * (as GLFW reports the cursor), width w and height h. */
#ifndef ST_CAMERA_CTL_H
#define ST_CAMERA_CTL_H

#include "render/camera.h"

typedef struct st_camctl {
    st_camera cam;
    float bbox[6];             /* what "frame all" frames (min xyz, max xyz) */
    float radius;              /* half the bbox diagonal */
} st_camctl;

/* Presets of the numpad keys: 1 front, 3 right, 7 top; with Ctrl the
 * opposite view (back, left, bottom). */
enum st_camctl_view { ST_CV_FRONT, ST_CV_BACK, ST_CV_RIGHT, ST_CV_LEFT, ST_CV_TOP, ST_CV_BOTTOM };

void st_camctl_init(st_camctl *c, const float bbox[6], float aspect);
/* Keeps the view direction, refits the distance to bbox. */
void st_camctl_frame_all(st_camctl *c, const float bbox[6], float aspect);
void st_camctl_view(st_camctl *c, int view, float aspect);
void st_camctl_toggle_ortho(st_camctl *c);

/* Mouse motions in pixels (dx right, dy down). */
void st_camctl_orbit(st_camctl *c, float dx, float dy);
void st_camctl_pan(st_camctl *c, float dx, float dy, int w, int h);
/* Wheel steps (positive: closer). */
void st_camctl_zoom(st_camctl *c, float steps);

/* Projects p to screen pixels; returns 0 when p is behind the eye.  ndc_z
 * (may be NULL) receives the window depth in 0..1. */
int st_camctl_project(const st_camctl *c, int w, int h, const double p[3], double s[2], double *depth);
/* The scene point at screen (x, y) and window depth z (0..1). */
void st_camctl_unproject(const st_camctl *c, int w, int h, double x, double y, double z, double p[3]);
/* Scene translation, parallel to the view plane, that follows a screen
 * motion (dx, dy) at the depth of point p. */
void st_camctl_screen_delta(const st_camctl *c, int w, int h, const double p[3], double dx, double dy, double out[3]);
/* World length of one pixel at the depth of p. */
double st_camctl_pixel_size(const st_camctl *c, int w, int h, const double p[3]);
/* Camera axes: right, up, and towards the eye. */
void st_camctl_axes(const st_camctl *c, double right[3], double up[3], double back[3]);

#endif
