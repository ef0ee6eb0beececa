/* Shared by the steps of core/uv (uv.h): the mesh's adjacency and face
 * geometry, computed once, and the scratch every step reuses. */
#ifndef ST_UV_INTERNAL_H
#define ST_UV_INTERNAL_H

#ifndef STRATA_CORE_INTERNAL
#error "uv_internal.h is internal to core"
#endif

#include "core/uv/uv.h"

#define UV_NIL UINT32_MAX

typedef struct uv_ctx {
    const st_uv_mesh *m;
    st_uv_opts o;                 /* defaults filled in */
    uint32_t nc;                  /* corners: face_off[nfaces] */
    uint32_t *corner_face;        /* nc: the face of each corner */
    uint32_t *twin;               /* nc: the corner starting the opposite half-edge of the half-edge
                                     corner c → next(c), UV_NIL on a border or a non-manifold edge */
    double *fn;                   /* 3 * nfaces: unit Newell normals (0 for a degenerate face) */
    double *farea;                /* nfaces: area (half the Newell vector's length) */
    double *fcent;                /* 3 * nfaces: mean of the corners */
    /* Stamps: mark[x] == stamp means "x is in the set being looked at";
     * bumping the stamp clears every mark at once. */
    uint32_t *fmark;              /* nfaces */
    uint32_t *vmark;              /* nverts */
    uint32_t *vloc;               /* nverts: the chart-local index of a vertex whose vmark is current */
    uint32_t stamp;
    /* Scratch sized by the mesh. */
    uint32_t *vlist;              /* nverts: the chart's vertices by local index */
    uint32_t *vout;               /* nverts: an outgoing border corner per chart vertex */
    uint32_t *fqueue;             /* nfaces */
    uint32_t *border;             /* nc: a chart's border corners */
    double *x, *r, *s, *p, *q;    /* 2 * nverts (x, s, p) and 2 * nc (r, q): the CGLS vectors */
    uint32_t *tv;                 /* 3 * nc: the chart's triangles, local vertex indices */
    double *tw;                   /* 6 * nc: the LSCM coefficients of each triangle */
    uint32_t (*ftris)[3];         /* the largest face degree: one face's triangles */
} uv_ctx;

static inline uint32_t uv_next(const st_uv_mesh *m, const uint32_t *corner_face, uint32_t c)
{
    uint32_t f = corner_face[c];
    return c + 1 < m->face_off[f + 1] ? c + 1 : m->face_off[f];
}

/* The largest face degree of m (at least 3): scratch for
 * st_uv_face_triangles. */
static inline uint32_t uv_max_degree(const st_uv_mesh *m)
{
    uint32_t d = 3;
    for (uint32_t f = 0; f < m->nfaces; f++)
        if (m->face_off[f + 1] - m->face_off[f] > d) d = m->face_off[f + 1] - m->face_off[f];
    return d;
}

/* A new stamp (wrapping: marks are cleared then). */
void uv_new_stamp(uv_ctx *c);

/* uv_charts.c: face_chart for every face (grown charts, numbered from 0);
 * returns the number of charts. */
uint32_t uv_grow_charts(uv_ctx *c, uint32_t *face_chart);

/* uv_charts.c: 1 when the faces (n of them) form a topological disk: one
 * border loop, no vertex with two border edges leaving it, V − E + F = 1. */
int uv_is_disk(uv_ctx *c, const uint32_t *faces, uint32_t n);

/* uv_charts.c: reorders faces[0..n) into edge-connected components;
 * writes the components' sizes to sizes (at most n) and returns their
 * count. */
uint32_t uv_components(uv_ctx *c, uint32_t *faces, uint32_t n, uint32_t *sizes);

/* uv_charts.c: reorders faces[0..n) so that the first n/2 lie on one side
 * of the plane across the principal axis of their centres. */
void uv_bisect(uv_ctx *c, uint32_t *faces, uint32_t n);

/* uv_lscm.c: flattens the chart faces[0..n) into uv (2 per corner, the
 * chart's corners only), UV area equal to the 3D area.  Returns 0 for LSCM,
 * 1 for the projection fallback, -1 when both flip a triangle. */
int uv_flatten(uv_ctx *c, const uint32_t *faces, uint32_t n, double *uv);

/* uv_pack.c: charts (chart_off, chart_faces) rotated and packed into the
 * unit square; uv updated. */
int uv_pack(uv_ctx *c, uint32_t ncharts, const uint32_t *chart_off, const uint32_t *chart_faces, double *uv,
            st_error *err);

#endif
