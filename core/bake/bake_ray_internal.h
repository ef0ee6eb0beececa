/* Ray casting for the bake where the faces of level L do not nest in those
 * of level B (√3, Doo-Sabin; core/bake/bake.h): a bounding volume hierarchy
 * over level L's triangles and the nearest hit of a line through a point of
 * B along B's normal, as normal-map bakers do where no exact correspondence
 * exists (a two-sided ray within a cage distance).
 *
 * The hierarchy is flat: per triangle three vertex ids (the fan of each
 * face from its first corner), per node its box, its first child or first
 * triangle and its triangle count; no allocation per node or triangle.  It
 * is built by object-median splits (Wald, Boulos, Shirley 2007 discuss the
 * trade-off with SAH; the levels of a subdivision surface have triangles of
 * nearly one size, where a median split is close to SAH): the triangles of a
 * node sorted by their centroid along the longest axis of the centroids'
 * box, ties by triangle id, split in two halves, down to leaves of at most
 * ST_BAKE_BVH_LEAF triangles.  The node count is then a function of the
 * triangle count alone (st_bake_bvh_nodes), so the memory estimate is exact,
 * and the tree is the same on every run. */
#ifndef ST_BAKE_RAY_INTERNAL_H
#define ST_BAKE_RAY_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "core/bake/bake_ray_internal.h is internal to core"
#endif

#include "core/bake/bake_internal.h"

#define ST_BAKE_BVH_LEAF 4u

typedef struct st_bake_bvh {
    const st_map *m;
    unsigned level;
    uint32_t ntris, nnodes;
    uint32_t *tri_vert;     /* 3 vertex ids per triangle, faces in st_bake_level_faces' order */
    uint32_t *leaf_tri;     /* triangle ids in leaf order */
    uint32_t *node_first;   /* inner node: its first child (the second follows); leaf: its first leaf_tri entry */
    uint32_t *node_count;   /* 0: inner node; else the leaf's triangle count */
    double *node_box;       /* 6 per node: lo xyz, hi xyz (widened by a rounding margin) */
} st_bake_bvh;

/* Triangles of the fans of level l's surface faces (Σ degree - 2). */
uint64_t st_bake_level_triangles(const st_map *m, unsigned l);
/* Nodes of the hierarchy over n triangles (1 + both halves' above the leaf size). */
uint64_t st_bake_bvh_nodes(uint64_t n);
/* Bytes of the hierarchy over n triangles, with its build scratch (centroids). */
size_t st_bake_bvh_bytes(uint64_t n);

int st_bake_bvh_build(st_map *m, unsigned l, st_bake_bvh *b, st_error *err);
void st_bake_bvh_free(st_bake_bvh *b);

typedef struct st_bake_hit {
    uint32_t tri;           /* ST_NIL: no hit */
    double t;               /* hit = o + t d */
    double w[3];            /* barycentric weights of the triangle's corners */
} st_bake_hit;

/* The hit of the line o + t d, |t| <= reach, with the smallest |t| (ties: the
 * smaller triangle id), on triangles facing d's way (their normal e1 × e2
 * has a positive component along d: the near side of a thin part is not
 * mistaken for its far side).  Returns 1 on a hit.  The result depends on
 * the inputs only, not on the traversal order. */
int st_bake_bvh_nearest(const st_bake_bvh *b, const double o[3], const double d[3], double reach, st_bake_hit *hit);

/* The diagonal of the joint bounding box of levels B and L and the largest
 * gap between the faces of their two boxes (the default reach of the
 * rays, core/bake/bake.c, starts from these). */
void st_bake_level_boxes(const st_map *m, unsigned B, unsigned L, double *diag, double *gap);

#endif
