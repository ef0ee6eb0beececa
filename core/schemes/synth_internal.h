/* What a scheme's fast paths write into, shared with the synthesis passes of
 * core/multires (hier_synth.c) and core/progressive.  Defined here, below
 * the hierarchy, so that the rules never see it: a prediction writes
 * positions into the map and hands anything that needs the hierarchy (a
 * stencil applied with its detail in its local frame) to the owner's sink. */
#ifndef ST_SYNTH_INTERNAL_H
#define ST_SYNTH_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/schemes/scheme.h"
#include "core/map/dart_list.h"
#include "core/map/footprint.h"

#include <string.h>

/* Stencil evaluation: Σ w P_{L-1}(src), the level-(L-1) positions of m. */
void st_stencil_eval(const st_map *m, unsigned L, const st_stencil *s, double out[3]);

/* The output of a synthesis pass of level L: positions are written at L; a
 * local pass (gen != 0) writes each vertex once (stamp) and lists a dart of
 * level L of each, which seeds level L+1. */
typedef struct st_synth_ctx {
    st_map *m;             /* the positions written */
    st_stamps *stamp;      /* per vertex id: written in this pass when == gen */
    unsigned L;
    uint32_t gen;          /* stamp generation for local passes, 0 for full */
    uint64_t count;        /* vertices written */
    st_dart_list *changed; /* local passes: a dart of level L of each vertex written */
    int lost;              /* some written vertex had no dart found on its frame cell */
    st_footprint *fp;      /* NULL, or where (L, position, vertex) of each vertex written goes */
    /* The owner's stencil sink (ctx: this st_synth_ctx): applies a stencil
     * with the vertex's detail in its frame and writes it, stamps and lists
     * included (core/multires: st_synth_sink, owner the st_hier). */
    st_stencil_sink sink;
    void *owner;
} st_synth_ctx;

/* The same for a point a scheme computed itself (predict_around), whose
 * dart at L is known and whose stamp it checked; inline, as it runs once
 * per vertex of a local edit. */
static inline void st_synth_put(st_synth_ctx *c, uint32_t v, uint32_t d, const double p[3])
{
    st_map *m = c->m;
    st_mla *a = &m->pos;
    c->stamp->v[v] = c->gen;
    if (m->verts.ins[v] != c->L && !(a->col[c->L] && v < a->colcap[c->L])) {
        st_map_write_pos(m, v, c->L, p); /* no column yet */
    } else {
        if (m->log) st_map_log_vertex(m, v);
        unsigned char *slot = m->verts.ins[v] == c->L ? a->base : a->col[c->L];
        memcpy(slot + (size_t)v * 3 * sizeof(double), p, 3 * sizeof(double));
    }
    c->count++;
    if (c->fp) st_footprint_add(c->fp, st_fp_key(c->L, ST_FP_POS, v));
    st_dart_list *l = c->changed;
    if (!l) return;
    if (l->n < l->cap) l->d[l->n++] = d; /* no call while there is room */
    else st_dart_list_push(l, d);
}

#endif
