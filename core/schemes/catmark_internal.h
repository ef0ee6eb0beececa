/* What scheme_catmark.c (stencils) shares with catmark_fast.c (full-level
 * synthesis by tables). */
#ifndef ST_CATMARK_INTERNAL_H
#define ST_CATMARK_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/schemes/crease_internal.h"
#include "core/schemes/synth_internal.h"

#include <math.h>

/* Scratch of the stencil path, one per thread. */
typedef struct st_catmark_emitter {
    st_stencil_buf buf, tmp;
} st_catmark_emitter;

/* The stencil of the edge point of coarse dart d's edge / of the vertex
 * point of vert(d), level L from L-1, with the crease and boundary rules. */
void st_catmark_emit_edge(const st_subdiv_view *sv, unsigned L, uint32_t d, st_catmark_emitter *e, st_stencil_sink sink, void *ctx);
void st_catmark_emit_vertex(const st_subdiv_view *sv, unsigned L, uint32_t d, st_catmark_emitter *e, st_stencil_sink sink, void *ctx);
/* The stencil of the face point of the face of coarse dart d (its corners
 * from d on, each 1/k). */
void st_catmark_emit_face(const st_subdiv_view *sv, unsigned L, uint32_t d, st_catmark_emitter *e, st_stencil_sink sink, void *ctx);
/* Whether the edge of d (level l) takes the smooth-triangle edge weights
 * (opts.tri_sub smooth, a triangle on either side): such edges leave the
 * tables for the stencil path. */
int st_catmark_tri_edge(const st_subdiv_view *sv, uint32_t d, unsigned l);
/* The scheme's emit (scheme.h). */
void st_catmark_emit(const st_subdiv_view *sv, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx);
/* The scheme's predict_level (catmark_fast.c). */
void st_catmark_predict_level(const st_subdiv_view *sv, unsigned L);
/* The scheme's predict_around (catmark_local.c). */
int st_catmark_predict_around(const st_subdiv_view *sv, unsigned L, const uint32_t *seeds, uint32_t n, st_synth_ctx *out);

#endif
