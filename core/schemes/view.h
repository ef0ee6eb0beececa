/* st_subdiv_view: what a scheme's rules read of a subdivision surface, and
 * the little they write (scheme.h).
 *
 * OpenSubdiv keeps its rules (Sdc) below its topology refinement (Vtr) and
 * its tables (Far): a rule asks a small neighbourhood for its valences,
 * boundaries and sharpness, never the whole mesh.  Strata's schemes stand
 * in the same place: below the multiresolution hierarchy (core/multires,
 * st_hier), which holds details, face-varying data and sculpt layers the
 * rules have no business with.  The hierarchy hands its scheme this view
 * (st_hier_view, core/multires/hier.h), built on the stack once per call:
 *   - the 2-map, whose levels the rules walk, refine() splits and the fast
 *     paths write positions into (st_map_write_pos, map.h);
 *   - the semi-sharp creases (DeRose et al. 1998): a float per dart and per
 *     vertex, per level, as multilevel attributes of the map;
 *   - the rule options (OpenSubdiv's Sdc::Options);
 *   - the scratch the fast paths share with the hierarchy's own passes:
 *     per-vertex stamps, and the per-level caches of what a synthesis
 *     derives from the topology alone.
 * owner is the hierarchy that built the view, for a scheme that lives above
 * it (core/progressive: its prediction is the progressive hierarchy's own);
 * the schemes of this folder never read it. */
#ifndef ST_SUBDIV_VIEW_H
#define ST_SUBDIV_VIEW_H

#include "core/map/map.h"
#include "core/base/mesh.h"

enum st_crease_method { ST_CREASE_UNIFORM, ST_CREASE_CHAIKIN };
/* Catmull-Clark's edge points next to triangles (Sdc::Options
 * TriangleSubdivision, OBJ `t smoothtriangles`): its own rule, or the
 * smoother weights of TRI_SUB_SMOOTH. */
enum st_tri_sub { ST_TRI_SUB_CATMARK, ST_TRI_SUB_SMOOTH };

/* The options the rules read (a subset of st_hier_opts). */
typedef struct st_rule_opts {
    int boundary;              /* ST_BOUNDARY_EDGE_ONLY or ST_BOUNDARY_EDGE_AND_CORNER (mesh.h) */
    int crease_method;         /* enum st_crease_method */
    int tri_sub;               /* enum st_tri_sub (Catmull-Clark only) */
} st_rule_opts;

/* Per-vertex generation stamps, for deduplication within one pass. */
typedef struct st_stamps {
    uint32_t *v;               /* per vertex id */
    uint32_t cap, gen;
} st_stamps;

/* A new generation of stamps covering the vertex ids below need (grows and
 * zeroes v as needed; wraps around by clearing). */
uint32_t st_stamps_begin(st_stamps *s, uint32_t need);

typedef struct st_level_cache {
    void *p;                   /* NULL, or owned data ... */
    void (*free)(void *p);     /* ... freed by this */
} st_level_cache;

typedef struct st_subdiv_view {
    st_map *map;
    st_mla *edge_sharp;        /* float per dart (both darts of an edge agree) */
    st_mla *vertex_sharp;      /* float per vertex */
    int has_sharpness;         /* 0: both attributes absent, every sharpness 0 */
    st_rule_opts opts;
    st_stamps *stamp;
    /* Per coarse level, what a full-level synthesis derived from the
     * topology (Catmull-Clark, Loop: their tables), kept between syntheses;
     * the owner of the data checks the map's generation before each use. */
    st_level_cache *cache;     /* ST_MAX_LEVELS of them */
    /* What the last local prediction derived for its region (Catmull-Clark:
     * its records per level), kept for the next edit of the same vertices. */
    st_level_cache *local;
    void *owner;
    /* emit() over a list of faces may leave out the fine vertices listed
     * here (their level-L positions stand: st_hier_emit_except); a scheme
     * that does not read the list emits them too, which the contract of
     * emit() allows.  Empty in every other view. */
    const uint32_t *emit_skip;
    uint32_t emit_nskip;
} st_subdiv_view;

/* Sharpness of the edge of d / of vertex v at level l as stored (0 when
 * none; boundaries are not sharp here: crease_internal.h's rules add them). */
static inline float st_subdiv_edge_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l)
{
    if (!sv->has_sharpness) return 0;
    return *(const float *)st_mla_at(sv->edge_sharp, sv->map->darts.ins, d, l);
}
static inline float st_subdiv_vertex_sharpness(const st_subdiv_view *sv, uint32_t v, unsigned l)
{
    if (!sv->has_sharpness) return 0;
    return *(const float *)st_mla_at(sv->vertex_sharp, sv->map->verts.ins, v, l);
}

/* A new stamp generation over the map's vertex ids (st_stamps_begin). */
static inline uint32_t st_subdiv_stamp_begin(const st_subdiv_view *sv) { return st_stamps_begin(sv->stamp, sv->map->verts.end); }

#endif
