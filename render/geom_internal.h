/* Internals shared by geom.c (build, refresh) and geom_patch.c. */
#ifndef ST_GEOM_INTERNAL_H
#define ST_GEOM_INTERNAL_H
#ifndef STRATA_RENDER_INTERNAL
#error "internal to render: ui/, app/ and bench/ use render's public headers (docs/ARCHITECTURE.md)"
#endif

#include "render/geom.h"
#include "render/triangulate.h"

#include <stdlib.h>

#define UNDRAWN (ST_NIL - 1)          /* dart_face of darts of boundary faces */

/* Returns p grown to hold need elements of elem bytes (geometric growth),
 * or p unchanged with *oom set when memory runs out. */
static inline void *st_rg_grow(void *p, size_t *cap, size_t need, size_t elem, int *oom)
{
    if (need <= *cap) return p;
    size_t c = *cap ? *cap : 64;
    while (c < need) c *= 2;
    void *q = realloc(p, c * elem);
    if (!q) { *oom = 1; return p; }
    *cap = c;
    return q;
}
#define GROW(ptr, cap, need, oom) ((ptr) = st_rg_grow((ptr), &(cap), (need), sizeof *(ptr), &(oom)))

typedef struct u32_list { uint32_t *d; size_t n, cap; } u32_list;
int st_rg_push(u32_list *l, uint32_t v);
int st_rg_to_ranges(u32_list *idx, st_range_list *out);   /* sorts idx */

void st_rg_face_normal(st_rgeom *g, uint32_t f);
void st_rg_vertex_normal(st_rgeom *g, const st_level_view *V, uint32_t s);
void st_rg_read_position(st_rgeom *g, const st_level_view *V, uint32_t s);
int st_rg_ensure_stamps(st_rgeom *g, const st_map *m);
uint32_t st_rg_next_gen(st_rgeom *g);

/* Scratch for one face walk: its darts, then what the case lookup needs. */
typedef struct st_rg_scratch {
    uint32_t *darts; size_t cdarts;
    uint32_t *b0; size_t cb0;         /* β0 of each dart (st_rgeom_build's walk) */
    uint8_t *elev, *vlev; size_t celev, cvlev;
    uint32_t *loc; size_t cloc;
    float *pos; size_t cpos;
} st_rg_scratch;
void st_rg_scratch_free(st_rg_scratch *fs);
/* The case of the face whose n darts are fs->darts and vertex ids vids,
 * its triangles as corner numbers in fs->loc; -2 when out of memory.  b0:
 * the β0 of each dart when the caller has them, else NULL. */
int st_rg_face_case(st_rgeom *g, const st_level_view *V, st_rg_scratch *fs, unsigned n, const uint32_t *vids,
                    const uint32_t *b0);

#endif
