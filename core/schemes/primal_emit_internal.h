/* Stencil emission shared by the primal quadrisection schemes (Loop,
 * Butterfly, quad/triangle; the same pattern as Catmull-Clark's): the
 * vertices of level L are the vertex points of the vertices of level L-1,
 * the edge points of its edges and, for polygon splits, the face points of
 * its faces.  A scheme gives only its masks. */
#ifndef ST_PRIMAL_EMIT_H
#define ST_PRIMAL_EMIT_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/schemes/crease_internal.h"
#include "core/schemes/scheme.h"

enum st_face_points { ST_FACE_POINTS_NONE, ST_FACE_POINTS_NON_TRIANGLES, ST_FACE_POINTS_ALL };

typedef struct st_primal_rules {
    st_vertex_mask_fn vertex;   /* smooth vertex mask; NULL: interpolating (the vertex itself) */
    st_edge_mask_fn edge;       /* smooth edge mask */
    int creases;                /* 1: wrap the masks in OpenSubdiv's sharpness rules (crease.h) */
    int face_points;            /* enum st_face_points */
} st_primal_rules;

/* The scheme's emit(), given its rules (scheme.h for the contract). */
void st_primal_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx,
                    const st_primal_rules *r);

/* Adds w · (centroid of d's face at level l) as vertex weights. */
void st_add_face_centroid(const st_map *m, unsigned l, uint32_t d, double w, st_stencil_buf *out);

/* check() of the triangle-only schemes: names the scheme and the side count
 * of the first other face. */
int st_check_triangles(const st_subdiv_view *sv, const char *scheme, st_error *err);

#endif
