/* st_mesh: a polygon soup, the interchange form between files and the map
 * (core/io/mesh.h reads and writes it, core/map/map_mesh.h builds the
 * level-0 map from it and extracts levels back into it).  Here, at the
 * bottom of core, so that every folder above uses the type without
 * reaching the file readers: flat arrays, counts-and-offsets for faces
 * (OpenSubdiv's vtr layout), 0-based indices; the notes a pass leaves for
 * the user. */
#ifndef ST_BASE_MESH_H
#define ST_BASE_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "core/base/st_error.h"

/* OBJ `t interpolateboundary` values as written in files (OpenSubdiv's
 * regression/common/far_utils.h: 0 none, 1 edge-and-corner, 2 edge-only; no tag means edge-only). */
enum st_boundary_interp {
    ST_BOUNDARY_UNSET = -1,
    ST_BOUNDARY_NONE = 0,
    ST_BOUNDARY_EDGE_AND_CORNER = 1,
    ST_BOUNDARY_EDGE_ONLY = 2,
};

typedef struct st_mesh {
    uint32_t nverts;
    double *pos;            /* 3 * nverts */
    uint32_t nfaces;
    uint32_t *face_off;     /* nfaces + 1 offsets into face_idx */
    uint32_t *face_idx;     /* face_off[nfaces] vertex indices, counter-clockwise */
    /* Optional per-vertex normals (writers only; NULL when absent). */
    double *normals;        /* 3 * nverts or NULL */
    /* OpenSubdiv tags from OBJ `t` lines, kept for the schemes. */
    uint32_t ncreases;
    uint32_t *crease_v;     /* 2 * ncreases vertex indices (an edge) */
    float *crease_s;        /* ncreases sharpness values */
    uint32_t ncorners;
    uint32_t *corner_v;     /* ncorners vertex indices */
    float *corner_s;        /* ncorners sharpness values */
    int boundary_interp;    /* enum st_boundary_interp */
    int crease_method;      /* `t creasemethod`: 0 uniform ("normal"), 1 chaikin (enum st_crease_method) */
    int tri_sub;            /* `t smoothtriangles`: 0 catmark, 1 smooth (enum st_tri_sub) */
    /* Hole faces (OBJ `t hole`): nfaces flags, 1 for a hole, or NULL when
     * none.  A hole is a face for the rules of its vertices, with no surface:
     * the writers leave it out. */
    uint8_t *face_hole;
    /* Optional face-varying texture coordinates (OBJ vt, PLY u v, glTF
     * TEXCOORD_0): face_uv is parallel to face_idx and names, per face
     * corner, one of the nuvs values in uv.  Two corners of one vertex with
     * different indices are on a UV seam, even when their values are equal
     * (OpenSubdiv's face-varying topology is by index).  NULL when absent. */
    uint32_t nuvs;
    double *uv;             /* 2 * nuvs */
    uint32_t *face_uv;      /* face_off[nfaces] indices into uv, or NULL */
} st_mesh;

void st_mesh_init(st_mesh *m);
/* Hole faces in m (face_hole set): the writers leave them out. */
uint32_t st_mesh_hole_faces(const st_mesh *m);
void st_mesh_free(st_mesh *m);
/* Moves src into dst (dst freed first); src is left empty. */
void st_mesh_move(st_mesh *dst, st_mesh *src);

/* Limits that keep an unchecked count in a file from driving an allocation. */
#define ST_MESH_MAX_VERTS   (1u << 27)
#define ST_MESH_MAX_FACES   (1u << 27)
#define ST_MESH_MAX_DEGREE  (1u << 16)

/* Lines for the user (repairs made, values clamped), one per note. */
typedef struct st_notes {
    char **lines;
    uint32_t count;
} st_notes;
void st_notes_free(st_notes *n);
/* Appends one formatted line (notes may be NULL: nothing, 0). */
int st_notes_add(st_notes *notes, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#endif
