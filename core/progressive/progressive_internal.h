/* The flat working copy of a progressive build (progressive.h, design
 * points 1-4): a closed half-edge structure, the grouped collapses and
 * their undo log. */
#ifndef ST_PROGRESSIVE_INTERNAL_H
#define ST_PROGRESSIVE_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/progressive/progressive.h"

enum { PM_HE_BOUNDARY = 1u, PM_HE_DEAD = 2u };

/* One half-edge's state before a collapse changed it. */
typedef struct pm_rec {
    uint32_t he, twin, next, prev, org;
    uint8_t flags;
} pm_rec;

/* One collapse a -> b of half-edge h; c, d opposite (d = ST_NIL on a
 * boundary edge); its undo records are log[rec_beg, rec_end). */
typedef struct pm_collapse {
    uint32_t h, a, b, c, d;
    uint32_t rec_beg, rec_end;
    uint32_t vhe[4];             /* vhe of a, b, c, d before (undo restores them exactly) */
} pm_collapse;

typedef struct pm_work {
    uint32_t nv, nhe;            /* vertices, half-edges (real ones first: 3 per triangle) */
    uint32_t nreal;              /* real half-edges */
    const double *pos;           /* 3 * nv, borrowed */
    uint32_t *twin, *next, *prev, *org;
    uint8_t *hflags;             /* PM_HE_* */
    uint32_t *vhe;               /* per vertex: an outgoing half-edge */
    uint8_t *vdead;
    double *quad;                /* per vertex: 10 coefficients of the quadric */
    /* scratch */
    uint32_t *stamp, stamp_gen;
    uint8_t *indep;              /* per vertex, per group: bit 0 in some W, bit 1 in some R */
    uint8_t *vbound;             /* per vertex: on a boundary (per group) */
    /* result */
    pm_collapse *col;
    uint32_t ncol, capcol;
    uint32_t *group_beg;         /* groups fine to coarse: collapses [group_beg[k], group_beg[k+1]) */
    uint32_t ngroups;
    pm_rec *log;
    uint32_t nlog, caplog;
    uint64_t faces, verts;       /* alive now */
} pm_work;

/* Builds the working copy of a triangle soup (3 indices per face). */
int pm_work_init(pm_work *w, const double *pos, uint32_t nv, const uint32_t *tri, uint32_t nt, st_error *err);
void pm_work_free(pm_work *w);
/* Frees the half-edges, quadrics, scratch and undo log, keeping the
 * collapses, their groups and vdead (all a replay of the groups reads);
 * pm_undo cannot run after it. */
void pm_work_drop_topology(pm_work *w);
/* Level 0's optimal placement (progressive.h, point 8): for every vertex
 * alive in the working copy, in id order, the point minimising its
 * quadric plus a small pull toward pos (a thousandth of the quadric's
 * mean eigenvalue: an ill-conditioned quadric, a flat or straight
 * region, stays put along its free directions), written into pos (3 per
 * vertex, the input positions on entry) unless a face around it would
 * turn by more than 60 degrees or lose almost all its area. */
void pm_work_fit_coarse(const pm_work *w, double *pos);

/* Simplifies by groups of independent collapses down to target faces or
 * max_groups groups; progress as in st_progressive_opts.  Returns ST_OK
 * (note says why it stopped) or ST_ERR_INVALID when cancelled. */
int pm_simplify(pm_work *w, uint64_t target, unsigned max_groups, int (*progress)(void *, double), void *ctx,
                char *note, size_t notesz, st_error *err);

/* Undoes collapse i: collapses are undone in the reverse order of their
 * making, and each restores every array it changed, vhe included. */
void pm_undo(pm_work *w, uint32_t i);

/* The stencil of the vertex of dart d at level L >= 1 of a progressive
 * hierarchy (progressive_scheme.c), built in buf; 0 when the
 * vertex has no dart of level L-1 (a map this scheme did not build). */
int st_progressive_stencil(const st_hier *h, unsigned L, uint32_t d, st_stencil_buf *buf, st_stencil *s);

/* Synthesis of level L of a progressive hierarchy from flat ring tables
 * (progressive_synth.c), to the bits of the stencils: every vertex, or,
 * after the vertices of the seeds (darts of L-1) changed at L-1, exactly
 * the vertices of L whose position then changes (scheme.h predict_around).
 * Both return 0, having written nothing, on a map this scheme did not
 * build. */
struct st_synth_ctx;
int st_progressive_synth_level(st_hier *h, unsigned L);
int st_progressive_resynth_around(st_hier *h, unsigned L, const uint32_t *seeds, uint32_t nseeds, struct st_synth_ctx *out);
/* S(P_{L-1})(v) and v's frame at L-1 from the ring tables of L and L-1
 * (the scheme's predict_vertex), when both are in the cache for the map as
 * it is now and regular, and v is a vertex of L; else 0.  Never builds a
 * table: one edit would pay a whole level for it. */
int st_progressive_predict_vertex(st_hier *h, unsigned L, uint32_t v, double pred[3], double f[3][3]);
/* Bytes the ring tables now held in h->cache take (a transient cache: never
 * saved, rebuilt after a topology change). */
size_t st_progressive_table_bytes(const st_hier *h);
/* Bytes a synthesis of the levels above `from` adds to the process: the
 * ring tables it builds (the levels from..top whose table is not held
 * now) and the position columns it creates (st_estimate_position_columns),
 * from the pools' counts; the memory guard's estimate
 * (core/base/membudget.h) before a filter re-synthesises. */
size_t st_progressive_synth_estimate(const st_hier *h, unsigned from);

/* The build's details (progressive.c): for each vertex v in [begin, end)
 * of level L whose stencil is not v itself, fn gets its prediction
 * S(P_{L-1})(v) and the frame its detail is in, evaluated from the ring
 * tables to the bits of st_stencil_eval and st_hier_frame.  The first call
 * of a level builds the tables of L-1 and L into h->cache (not thread-safe:
 * call it on one thread first, e.g. with an empty range); later calls only
 * read them.  Returns 0, having called nothing, where the tables do not
 * describe the map (the stencils then serve).  st_progressive_drop_table
 * frees the table of level l. */
typedef void (*pm_predicted_fn)(void *ctx, uint32_t v, const double pred[3], const double f[3][3]);
int st_progressive_predict_range(st_hier *h, unsigned L, uint32_t begin, uint32_t end, pm_predicted_fn fn, void *ctx);
void st_progressive_drop_table(st_hier *h, unsigned l);

/* The detail dv of a vertex at p predicted at pred with frame f
 * (progressive.c compute_details): D = F^T (p - pred), then corrected by
 * the residual of the synthesis itself (pred + F D, as st_stencil_apply
 * sums it), with shrinking steps after the second so as not to jump over
 * the target bits, until it gives back p to the bit.  Returns 1 when it
 * does; *nonzero is set when some step's dv was not all zero (a detail
 * array would then have been created). */
static inline int pm_detail_correct(const double p[3], const double pred[3], const double f[3][3], double dv[3], int *nonzero)
{
    double r[3], out[3];
    dv[0] = dv[1] = dv[2] = 0;
    for (int j = 0; j < 3; j++) r[j] = p[j] - pred[j];
    int exact = 0;
    double step = 1.0;
    for (int it = 0; it < 16 && !exact; it++, step = it < 2 ? 1.0 : step * 0.75) {
        for (int j = 0; j < 3; j++) dv[j] += step * (f[j][0] * r[0] + f[j][1] * r[1] + f[j][2] * r[2]);
        for (int j = 0; j < 3; j++) out[j] = pred[j];
        if (dv[0] != 0 || dv[1] != 0 || dv[2] != 0) {
            *nonzero = 1;
            for (int i = 0; i < 3; i++) out[i] += dv[0] * f[0][i] + dv[1] * f[1][i] + dv[2] * f[2][i];
        }
        for (int j = 0; j < 3; j++) r[j] = p[j] - out[j];
        exact = r[0] == 0 && r[1] == 0 && r[2] == 0;
    }
    return exact;
}

/* The weight mu of the relaxation of a split's old neighbours at level L
 * (progressive.h, point 5): P(v) = (1 - mu) v + mu avg(ring).  Graded:
 * 1/2 on the two finest levels (their bands hold the input's noise, which
 * st_progressive_filter removes by relaxing), 1/10 below (a coarse edit
 * crosses many levels, some five per octave, and keeps its amplitude). */
static inline double pm_relax_weight(const st_hier *h, unsigned L)
{
    switch (h->opts.pm_predictor) {
    case ST_PM_LIGHT: return 0.125;
    case ST_PM_GRADED: return L + 2 > h->map.top ? 0.5 : 0.1;
    default: return 0.5;
    }
}

/* The replay of a recipe (progressive_replay.c): st_progressive_regenerate
 * and the build (progressive.c materialise) make a map the same way.
 * begin checks and builds level 0 from rc (its level-0 arrays, top and
 * nsplits; rc->split is not read) into h's map; each pm_replay_level adds
 * level l from its n splits with b, c and d as vertex ids, in order, and
 * pm_replay_new_vertices gives the vertices those splits made; then
 * pm_replay_relations puts the relations' per-level changes in (dense
 * columns, for a reader before compaction, then pm_replay_sparsify; or
 * the form st_map_compact leaves), and pm_replay_finish compacts the map
 * and marks h regenerable.  Refusals name the level and the split. */
typedef struct pm_replay pm_replay;
int pm_replay_begin(pm_replay **out, st_hier *h, const st_pm_recipe *rc, st_error *err);
int pm_replay_level(pm_replay *r, unsigned l, const st_pm_split *resolved, uint32_t n, uint64_t first);
const uint32_t *pm_replay_new_vertices(const pm_replay *r);
/* The build: the splits are also kept as the recipe's ranks, and
 * pm_replay_keep_recipe (level 0 as given to begin) stores the session's
 * bytes of the recipe in h->pm_recipe. */
void pm_replay_record(pm_replay *r);
int pm_replay_keep_recipe(pm_replay *r, const st_pm_recipe *level0);
int pm_replay_relations(pm_replay *r, int dense);
int pm_replay_sparsify(pm_replay *r);
void pm_replay_finish(pm_replay *r);
void pm_replay_free(pm_replay *r);

/* Half-edge helpers. */
static inline uint32_t pm_dest(const pm_work *w, uint32_t h) { return w->org[w->next[h]]; }
static inline uint32_t pm_rot(const pm_work *w, uint32_t h) { return w->next[w->twin[h]]; } /* next around org[h] */

#endif
