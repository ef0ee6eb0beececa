/* Index tables of a scheme's full-level synthesis, cached per coarse level
 * in the view's cache (st_subdiv_view.cache: the hierarchy's; the design:
 * catmark_fast.c).  They depend on the topology (and sharpness) only, and
 * are stale when the map's generation (map.h) or, as a second guard, the
 * pools, the top level or the column of the coarse positions changed since
 * they were built. */
#ifndef ST_SYNTH_TABLES_H
#define ST_SYNTH_TABLES_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/schemes/scheme.h"
#include "core/base/hugepage.h"
#include "core/base/parallel.h"
#include "core/schemes/synth_blocks_internal.h"

#include <stdint.h>
#include <stdlib.h>

/* A position ref: a vertex id, with REF_COL when its coarse position is in
 * the level's column rather than the base. */
#define REF_COL 0x80000000u
#define REF_ID 0x7fffffffu

/* The ref of coarse vertex v at the level of view c: the choice of
 * st_v_pos, read from block bits (synth_blocks.h) when vnew is given. */
static inline uint32_t st_synth_ref(const st_level_view *c, const uint64_t *vnew, uint32_t v)
{
    int use_col = vnew ? !st_block_bit(vnew, v) : c->vins[v] < c->plvl;
    return v | (use_col ? REF_COL : 0);
}

/* The position a ref names: base or column by a select (which one varies
 * without pattern). */
static inline const double *st_synth_ref_pos(const double *pbase, const double *pcol, uint32_t r)
{
    return (const double *)st_pick(pbase, pcol, (r & REF_COL) != 0) + 3 * (size_t)(r & REF_ID);
}

/* Evaluation shares records out in chunks of this many; a level with fewer
 * than ST_SYNTH_MIN_PER_THREAD records per thread runs on fewer threads. */
#define ST_SYNTH_CHUNK 2048u
#define ST_SYNTH_MIN_PER_THREAD 8192u

static inline void st_synth_run(uint64_t records, st_team_fn fn, void *ctx)
{
    unsigned threads = st_parallel_threads();
    if (records < (uint64_t)ST_SYNTH_MIN_PER_THREAD * threads) threads = (unsigned)(records / ST_SYNTH_MIN_PER_THREAD);
    st_team_run(threads ? threads : 1, fn, ctx);
}

/* ---- growable arrays of 32-bit indices ---- */

typedef struct u32vec { uint32_t *a; size_t n, cap; } u32vec;

static inline void vec_reserve(u32vec *v, size_t cap)
{
    if (cap <= v->cap) return;
    uint32_t *a = realloc(v->a, cap * sizeof *a);
    if (!a) abort(); /* out of memory for the synthesis tables */
    st_advise_huge(a, cap * sizeof *a);
    v->a = a;
    v->cap = cap;
}

static inline void vec_push(u32vec *v, uint32_t x)
{
    if (v->n == v->cap) vec_reserve(v, v->cap ? 2 * v->cap : 64);
    v->a[v->n++] = x;
}

static inline void vec_shrink(u32vec *v)
{
    if (v->n == v->cap || !v->n) return;
    uint32_t *a = realloc(v->a, v->n * sizeof *a);
    if (a) { v->a = a; v->cap = v->n; }
}

/* ---- the tables of one coarse level ---- */

/* Records as each scheme defines them (Catmull-Clark: catmark_fast.c;
 * Loop: loop_fast.c); a scheme uses the arrays it needs. */
typedef struct st_synth_table {
    int scheme;                      /* st_scheme_id of the scheme that built them */
    uint64_t gen;                    /* map generation they were built for ... */
    uint32_t dend, vend;             /* ... and, as a second guard, the pools' ends, */
    unsigned top, plvl;              /* the top level and the coarse positions' column */
    int irregular;                   /* the level is not the split the scheme assumes: stencils */
    int deferred;                    /* a mark without records: the last synthesis went without tables
                                        (st_synth_tables_defer), the next builds them */
    u32vec quad, foff, fdata, edge, sedge, v4, voff, vdata, svert, copy;
} st_synth_table;

/* Builds t's records for level L from L-1; returns 1 if the level is
 * irregular (t's records are then unused). */
typedef int (*st_synth_build)(const st_subdiv_view *sv, unsigned L, st_synth_table *t);

/* The tables of coarse level l built by `scheme` for the map as it is now,
 * else NULL. */
const st_synth_table *st_synth_tables_if_fresh(const st_subdiv_view *sv, unsigned l, int scheme);
/* The same, built now (and cached) when there are none or they are stale. */
const st_synth_table *st_synth_tables_for(const st_subdiv_view *sv, unsigned L, int scheme, st_synth_build build);
/* Whether this full synthesis of level L goes without tables: true when
 * nothing fresh is cached for the coarse level (the first synthesis after a
 * change), which leaves a mark so that the next synthesis builds them
 * (st_synth_tables_for).  For a scheme whose walk of the level costs less
 * than building the tables: a one-shot synthesis (a command that subdivides
 * and writes) builds no tables it would never read. */
int st_synth_tables_defer(const st_subdiv_view *sv, unsigned L, int scheme);

static inline uint32_t st_synth_count(const u32vec *off) { return off->n ? (uint32_t)off->n - 1 : 0; }

#endif
