/* Camera: orbit around a target, framing of a bounding box, and the view
 * and projection matrices (column-major, as OpenGL takes them).
 *
 * Axes: Y up, the front of a model faces +Z (the OBJ habit).  A view is an
 * azimuth (degrees around Y from +Z towards +X) and an elevation (degrees
 * above the XZ plane); the eye sits at target + dist * dir(az, el).
 *
 *   front  az 0,    el 0        back   az 180, el 0
 *   right  az 90,   el 0        left   az -90, el 0
 *   top    az 0,    el 90       iso    az 45,  el 35.264 (the cube diagonal)
 */
#ifndef ST_CAMERA_H
#define ST_CAMERA_H

enum st_view_preset {
    ST_VIEW_FRONT, ST_VIEW_BACK, ST_VIEW_LEFT, ST_VIEW_RIGHT, ST_VIEW_TOP, ST_VIEW_ISO,
    ST_VIEW_COUNT
};

typedef struct st_camera {
    float target[3];
    float az, el;              /* degrees */
    float dist;                /* eye to target */
    float fovy;                /* vertical field of view, degrees (perspective) */
    int ortho;                 /* orthographic: the view height is ortho_height */
    float ortho_height;
    float znear, zfar;
} st_camera;

/* Name -> preset ("front", ...), -1 if unknown; and back. */
int st_view_parse(const char *name);
const char *st_view_name(int preset);
void st_view_angles(int preset, float *az, float *el);

/* Points the camera at the centre of bbox (min xyz, max xyz) from (az, el)
 * and sets the distance so that the whole box fits the image of the given
 * aspect (width / height) with a small margin; dist > 0 keeps that distance
 * instead.  Sets near and far planes around the box. */
void st_camera_frame(st_camera *c, const float bbox[6], float az, float el, float dist, float aspect);

/* Column-major 4x4 matrices. */
void st_camera_view(const st_camera *c, float view[16]);
void st_camera_proj(const st_camera *c, float aspect, float proj[16]);
/* Eye position in world space. */
void st_camera_eye(const st_camera *c, float eye[3]);

#endif
