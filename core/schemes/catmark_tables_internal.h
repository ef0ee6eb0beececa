/* Catmull-Clark synthesis tables (catmark_fast.c explains them) and the
 * evaluation of one record, shared by the full-level synthesis
 * (catmark_fast.c) and the local one (catmark_local.c), so that both give
 * the same bits. */
#ifndef ST_CATMARK_TABLES_H
#define ST_CATMARK_TABLES_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/schemes/catmark_internal.h"
#include "core/schemes/synth_blocks_internal.h"
#include "core/schemes/synth_tables_internal.h"

#include <stdlib.h>
#include <string.h>

typedef st_synth_table cc_table;

/* The Catmull-Clark tables of level L's coarse level, built now if stale
 * (catmark_fast.c).  Tables that are not irregular prove that level L is
 * the whole polygon split of level L-1. */
const cc_table *st_cc_tables_for(const st_subdiv_view *sv, unsigned L);

static inline uint32_t st_cc_nfaces_general(const cc_table *t) { return st_synth_count(&t->foff); }
static inline uint32_t st_cc_nverts_general(const cc_table *t) { return st_synth_count(&t->voff); }

/* ---- evaluation of a record ---- */

typedef struct cc_eval {
    const st_subdiv_view *sv;
    unsigned L;
    const cc_table *t;
    const double *pbase, *pcol;     /* level-l positions: base, column */
    double *pnew, *pold;            /* level-L positions: base (new vertices), column (old vertices) */
} cc_eval;

static inline const double *st_cc_ref_pos(const cc_eval *x, uint32_t r) { return st_synth_ref_pos(x->pbase, x->pcol, r); }

/* The arithmetic, on positions: every path goes through these, so that all
 * give the same bits. */

/* Face point: f = Σ corners (from the first, f starting at 0), then ... */
static inline void st_cc_face_add(double *f, const double *p) { f[0] += p[0]; f[1] += p[1]; f[2] += p[2]; }
/* ... out = f · (1/k). */
static inline void st_cc_face_finish(const double *f, unsigned k, double *out)
{
    double inv = 1.0 / k;
    out[0] = f[0] * inv; out[1] = f[1] * inv; out[2] = f[2] * inv;
}

/* Edge point of (d, e): 0.25 G(d) + 0.25 G(e), G(d) = P(ve) + F(d). */
static inline void st_cc_edge_mix(const double *pd, const double *pe, const double *fd, const double *fe, double *out)
{
    for (int k = 0; k < 3; k++) {
        double gd = pe[k] + fd[k], ge = pd[k] + fe[k];
        out[k] = 0.25 * gd + 0.25 * ge;
    }
}

/* Vertex point: s = Σ G(y) = Σ (P(vert(β0 y)) + F(y)) around from the
 * smallest dart (s starting at 0), then ... */
static inline void st_cc_vertex_add(double *s, const double *q, const double *f)
{
    double g[3] = { q[0] + f[0], q[1] + f[1], q[2] + f[2] };
    s[0] += g[0]; s[1] += g[1]; s[2] += g[2];
}
/* ... out = (n-2)/n P(v) + (1/n²) s. */
static inline void st_cc_vertex_finish(const double *p, const double *s, unsigned n, double *out)
{
    double wv = (double)(n - 2) / n, wn = 1.0 / ((double)n * n);
    for (int k = 0; k < 3; k++) out[k] = wv * p[k] + wn * s[k];
}

/* ---- the same on table records ---- */

static inline void st_cc_face_value(const cc_eval *x, const uint32_t *r, unsigned k, double *out)
{
    double f[3] = { 0, 0, 0 };
    for (unsigned i = 0; i < k; i++) st_cc_face_add(f, st_cc_ref_pos(x, r[i]));
    st_cc_face_finish(f, k, out);
}

/* Record r: ref vd, ref ve, face point of d's face, of e's. */
static inline void st_cc_edge_value(const cc_eval *x, const uint32_t *r, double *out)
{
    st_cc_edge_mix(st_cc_ref_pos(x, r[0]), st_cc_ref_pos(x, r[1]), x->pnew + 3 * (size_t)r[2], x->pnew + 3 * (size_t)r[3], out);
}

/* Record r: ref v, then n pairs (neighbour ref, face point). */
static inline void st_cc_vertex_value(const cc_eval *x, const uint32_t *r, unsigned n, double *out)
{
    double s[3] = { 0, 0, 0 };
    for (unsigned j = 0; j < n; j++) st_cc_vertex_add(s, st_cc_ref_pos(x, r[1 + 2 * j]), x->pnew + 3 * (size_t)r[2 + 2 * j]);
    st_cc_vertex_finish(st_cc_ref_pos(x, r[0]), s, n, out);
}

#endif
