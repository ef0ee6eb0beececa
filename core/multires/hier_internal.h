/* Internal helpers shared by hier*.c and the layers above (the schemes below
 * see the hierarchy only through st_subdiv_view, core/schemes/view.h). */
#ifndef ST_HIER_INTERNAL_H
#define ST_HIER_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/multires/hier.h"
#include "core/schemes/synth_internal.h"
#include "core/map/dart_list.h"
#include "core/map/refine_internal.h"

#include <math.h>
#include <string.h>

/* Writable position slot of v at level l (st_map_write_pos, map.h). */
static inline void st_hier_write_pos(st_hier *h, uint32_t v, unsigned l, const double p[3]) { st_map_write_pos(&h->map, v, l, p); }

/* The UVs of levels up to upto (st_fvar_refine_levels, fvar_internal.h,
 * for the threads it may run beside) once the topology reaches it. */
int st_hier_uv_refine_levels(st_hier *h, unsigned upto, st_error *err);

/* Detail of v at level l (zero vector when none stored). */
const double *st_hier_detail(const st_hier *h, unsigned l, uint32_t v);
void st_hier_set_detail(st_hier *h, unsigned l, uint32_t v, const double d[3]);
/* Shrinks each level's detail array to its last vertex whose detail is not
 * all-zero bits (at least one entry is kept: an array stays an array).
 * Reads past the end give zero, so nothing a synthesis computes changes;
 * on a progressive hierarchy, where st_hier_set_detail sized every level's
 * array to all vertex ids, it leaves about the ids of the level's own
 * vertices (they are numbered coarse to fine). */
void st_hier_trim_details(st_hier *h);

/* Predicted position plus frame · detail. */
void st_stencil_apply(const st_hier *h, unsigned L, const st_stencil *s, double out[3]);

/* Faces of level l within `rings` vertex rings of the seed darts' vertices,
 * one dart per face (real faces only), into a growable list. */
void st_region_faces(st_map *m, unsigned l, const uint32_t *seeds, uint32_t nseeds, unsigned rings, st_dart_list *faces);
/* Pushes every dart of the faces (one dart each, of level l) onto list. */
void st_dart_list_push_faces(st_dart_list *list, const st_map *m, unsigned l, const uint32_t *faces, uint32_t n);

/* Local work up the levels (the local synthesis of Kraemer 2008 §3.1 and
 * the passes built like it: re-synthesis, mask propagation): level L is
 * recomputed around the seeds (darts of level L-1), and what changed there
 * seeds level L+1.  For L = from+1 .. top: next is emptied, then
 * step(ctx, L, seeds, next) works on level L and fills next, which becomes
 * the seeds; a non-zero return stops before level L is touched by anything
 * else.  Takes seeds over (frees it). */
typedef int (*st_level_step_fn)(void *ctx, unsigned L, const st_dart_list *seeds, st_dart_list *next);
void st_hier_levels_up(const st_hier *h, unsigned from, st_dart_list *seeds, st_level_step_fn step, void *ctx);

/* A dart of level L carrying fine vertex v, found on the frame cell of its
 * stencil (dart d of level L-1): d itself for a vertex cell; for an edge or
 * a face, the children of a primal split lie on the face of d at level L.
 * ST_NIL if v is not there (hier_synth.c). */
uint32_t st_dart_on_cell(const st_map *m, uint32_t v, uint32_t d, unsigned L);

/* Per-vertex generation stamps for deduplication within one pass. */
static inline uint32_t st_hier_stamp_begin(st_hier *h) { return st_stamps_begin(&h->stamp, h->map.verts.end); }

/* The sink of the synthesis passes (scheme.h emit; st_synth_ctx,
 * core/schemes/synth_internal.h), ctx an st_synth_ctx whose owner is the
 * st_hier: applies the stencil, with the detail, and writes. */
void st_synth_sink(void *ctx, const st_stencil *s);

/* An st_synth_ctx of level L writing into h, full (gen 0, nothing listed):
 * the caller sets gen (after st_hier_stamp_begin), changed and fp for a
 * local pass. */
static inline st_synth_ctx st_hier_synth_ctx(st_hier *h, unsigned L)
{
    return (st_synth_ctx){ .m = &h->map, .stamp = &h->stamp, .L = L, .gen = 0, .count = 0, .changed = NULL, .lost = 0,
                           .fp = NULL, .sink = st_synth_sink, .owner = h };
}

/* What st_hier_analyze_ex did per level l (to+1..top). */
typedef struct st_analysis_report {
    uint8_t streamed[ST_MAX_LEVELS + 1];     /* 1: accepted by the streamed pass, no solve */
    double row_residual[ST_MAX_LEVELS + 1];  /* Catmull-Clark: the streamed pass' largest |f - S x|
                                                component over the level's scale (a lower bound
                                                where it stopped early); 0 where not streamed */
} st_analysis_report;
/* st_hier_analyze, with the streamed pass of an exact level (Catmull-Clark)
 * and the stored rows built on several threads; stored_only: the rows from
 * the scheme's emit on one thread and the solve for every level, the
 * analysis without either, as the reference for tests.  rep may be NULL. */
double st_hier_analyze_ex(st_hier *h, unsigned to, int stored_only, st_analysis_report *rep);

/* Three-vector arithmetic shared by the frames of subdivision synthesis
 * (hier_synth.c) and of progressive synthesis (progressive_synth.c), which
 * must give the same bits, and by the progressive working copy. */
static inline void st_sub3(const double *a, const double *b, double *o) { o[0] = a[0] - b[0]; o[1] = a[1] - b[1]; o[2] = a[2] - b[2]; }
static inline void st_cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static inline double st_dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The local frame F(v) (rows t, b, n) from an unnormalised normal n and a
 * tangent t: Gram-Schmidt, falling back to fixed axes for a degenerate n or
 * a tangent along n, so that the frame is always defined (uses sqrt and
 * fabs: the includer includes math.h). */
static inline void st_frame_orthonormal(double t[3], double n[3], double f[3][3])
{
    double ln = sqrt(st_dot3(n, n));
    if (ln < 1e-300) { n[0] = 0; n[1] = 0; n[2] = 1; ln = 1; }
    for (int i = 0; i < 3; i++) n[i] /= ln;
    double k = st_dot3(t, n);
    for (int i = 0; i < 3; i++) t[i] -= k * n[i];
    double lt = sqrt(st_dot3(t, t));
    if (lt < 1e-12) {
        double ax[3] = { fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0 };
        k = st_dot3(ax, n);
        for (int i = 0; i < 3; i++) t[i] = ax[i] - k * n[i];
        lt = sqrt(st_dot3(t, t));
    }
    for (int i = 0; i < 3; i++) t[i] /= lt;
    double b[3];
    st_cross3(n, t, b);
    for (int i = 0; i < 3; i++) { f[0][i] = t[i]; f[1][i] = b[i]; f[2][i] = n[i]; }
}

#endif
