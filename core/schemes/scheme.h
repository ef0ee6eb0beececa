/* Subdivision schemes: rules kept apart from topology (as OpenSubdiv
 * keeps Sdc apart from Vtr).
 *
 * A scheme is a table of functions over the view of a surface its rules
 * read (view.h: the map, the sharpness, the rule options, scratch), never
 * over the multiresolution hierarchy above it:
 *   - refine(): the topology of level top+1 (a uniform split of the map);
 *   - emit(): the *stencil* of fine vertices: each vertex of level L as a
 *     weighted sum of vertices of level L-1, plus the coarse cell whose local
 *     frame carries the vertex's detail vector.
 * The geometry passes (core/multires/hier_synth.c) apply stencils forwards (synthesis) and
 * transposed (least-squares analysis), everywhere or locally after an edit;
 * schemes never write positions themselves.
 */
#ifndef ST_SCHEME_H
#define ST_SCHEME_H

#include "core/schemes/view.h"

typedef enum st_scheme_id {
    ST_SCHEME_CATMARK,      /* Catmull-Clark, any polygon mesh */
    ST_SCHEME_LOOP,         /* Loop, triangle meshes */
    ST_SCHEME_BUTTERFLY,    /* modified Butterfly (Zorin, Schröder, Sweldens 1996), triangles, interpolating */
    ST_SCHEME_QUADTRI,      /* quad/triangle (Stam, Loop 2003) on mixed meshes */
    ST_SCHEME_SQRT3,        /* √3 (Kobbelt 2000), triangles */
    ST_SCHEME_DOOSABIN,     /* Doo-Sabin, any polygon mesh (dual) */
    ST_SCHEME_PROGRESSIVE,  /* progressive mesh: levels by simplification (core/progressive/progressive.h,
                               its table above core/multires) */
    ST_SCHEME_COUNT
} st_scheme_id;

/* Cell that locates a detail vector's local frame at the coarser level. */
enum st_frame_cell {
    ST_CELL_VERTEX, ST_CELL_EDGE, ST_CELL_FACE,
    ST_CELL_DUAL_FACE   /* face embedding: the β1 orbit of the dart, a face of the surface */
};

typedef struct st_stencil {
    uint32_t fine;          /* vertex id at level L */
    uint32_t n;             /* number of entries */
    const uint32_t *src;    /* vertex ids of level L-1 */
    const double *w;        /* weights, summing to 1 */
    uint32_t frame_dart;    /* dart of level L-1 on the frame cell */
    uint8_t frame_cell;     /* enum st_frame_cell */
} st_stencil;

typedef void (*st_stencil_sink)(void *ctx, const st_stencil *s);

/* Growable scratch for building stencils (valence is unbounded). */
typedef struct st_stencil_buf {
    uint32_t *src;
    double *w;
    uint32_t n, cap;
} st_stencil_buf;
void st_stencil_buf_free(st_stencil_buf *b);
void st_stencil_buf_clear(st_stencil_buf *b);
void st_stencil_buf_add(st_stencil_buf *b, uint32_t v, double w);
/* Adds every entry of o scaled by s (merging is not needed: the geometry
 * passes accept repeated sources). */
void st_stencil_buf_add_scaled(st_stencil_buf *b, const st_stencil_buf *o, double s);

struct st_synth_ctx;

typedef struct st_scheme {
    const char *name;                 /* CLI name: "catmull-clark", "loop", ... */
    st_scheme_id id;
    int interpolating;                /* even vertices keep their positions */
    unsigned support_rings;           /* rings of coarse faces around an edited vertex
                                         whose children can move (stencil + frame) */
    /* Checks the scheme's input requirements on level 0 (NULL: none). */
    int (*check)(const st_subdiv_view *sv, st_error *err);
    /* Adds level top+1 (topology, and sharpness of child edges/vertices). */
    int (*refine)(const st_subdiv_view *sv, st_error *err);
    /* Emits the stencils of level L.  With faces == NULL: every vertex of
     * level L exactly once.  Otherwise only (at least) the fine vertices
     * whose stencil lies on the given coarse faces (darts of level L-1, one
     * per face), possibly several times. */
    void (*emit)(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t nfaces,
                 st_stencil_sink sink, void *ctx);
    /* Optional fast path: writes S(P_{L-1}) for every vertex of level L,
     * equal to applying emit()'s stencils up to rounding.  Used by full
     * synthesis of a level that carries no details. */
    void (*predict_level)(const st_subdiv_view *sv, unsigned L);
    /* Optional fast path of local re-synthesis for a level L without
     * details: every fine vertex of the real faces of level L-1 around the
     * vertices of the seeds (darts of L-1; the faces support_rings = 1
     * gives to emit) whose stamp (sv->stamp) is not out->gen, once, as
     * S(P_{L-1}) through st_synth_put, or through out->sink as a stencil
     * (synth_ctx_internal.h).  Returns 0, having written nothing, when
     * level L is not one it handles (the stamps it set must then be
     * forgotten: a new generation). */
    int (*predict_around)(const st_subdiv_view *sv, unsigned L, const uint32_t *seeds, uint32_t nseeds, struct st_synth_ctx *out);
    /* Non-zero: predict_level and predict_around apply the details too
     * (S(P_{L-1}) + F D, to the bits out->sink writes), so they also
     * run on levels that carry details; predict_around then writes only
     * the vertices whose position changes (the progressive scheme). */
    int fast_paths_apply_details;
    /* Optional: bytes a synthesis of the levels above `from` adds to the
     * process, the caches its fast paths build included (the progressive
     * ring tables); NULL: the position columns alone
     * (st_hier_synth_estimate, core/multires/estimate.h). */
    size_t (*synth_estimate)(const st_subdiv_view *sv, unsigned from);
    /* Optional fast path of an edit's own level (core/multires/
     * hier_synth.c, refresh_detail): S(P_{L-1})(v) in pred and v's frame
     * at L-1 in f, to the bits of emit()'s stencil for v (st_stencil_eval)
     * and st_hier_frame.  Returns 0, having written nothing, when it cannot
     * answer cheaply; the caller then finds v's stencil through emit(). */
    int (*predict_vertex)(const st_subdiv_view *sv, unsigned L, uint32_t v, double pred[3], double f[3][3]);
} st_scheme;

/* Scheme tables, one per file scheme_*.c; the progressive scheme's is
 * core/progressive/progressive.h's, and the lookup by id or name
 * core/progressive/scheme_registry.h's. */
extern const st_scheme st_scheme_catmark;
extern const st_scheme st_scheme_loop;
extern const st_scheme st_scheme_butterfly;
extern const st_scheme st_scheme_quadtri;
extern const st_scheme st_scheme_sqrt3;
extern const st_scheme st_scheme_doosabin;

#endif
