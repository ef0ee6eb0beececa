/* Cache of synthesis tables per level (synth_tables.h). */
/* Only subdivision hierarchies (dense maps) reach this file: the dense
 * lookup path, without the sparse test (map.h, "Two lookup paths"). */
#define ST_MAP_DENSE_ONLY
#include "core/schemes/synth_tables_internal.h"

#include <string.h>

#define TABLE_ARRAYS(t) { &(t)->quad, &(t)->foff, &(t)->fdata, &(t)->edge, &(t)->sedge, &(t)->v4, &(t)->voff, &(t)->vdata, &(t)->svert, &(t)->copy }

static void table_free(void *p)
{
    st_synth_table *t = p;
    u32vec *v[] = TABLE_ARRAYS(t);
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) free(v[i]->a);
    free(t);
}

/* To their sizes; an irregular table keeps no records (the build may have
 * filled some before it found out). */
static void table_shrink(st_synth_table *t)
{
    u32vec *v[] = TABLE_ARRAYS(t);
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        if (t->irregular) {
            free(v[i]->a);
            *v[i] = (u32vec){ 0 };
        } else {
            vec_shrink(v[i]);
        }
    }
}

const st_synth_table *st_synth_tables_if_fresh(const st_subdiv_view *sv, unsigned l, int scheme)
{
    const st_map *m = sv->map;
    const st_synth_table *t = sv->cache[l].p;
    if (t && sv->cache[l].free == table_free && t->scheme == scheme && t->gen == m->gen && t->dend == m->darts.end &&
        t->vend == m->verts.end && t->top == m->top && t->plvl == m->pos.eff[l])
        return t;
    return NULL;
}

/* An empty table of coarse level l, stamped with the map's state, in the
 * cache (what it held is freed first: stale). */
static st_synth_table *table_new(const st_subdiv_view *sv, unsigned l, int scheme)
{
    st_map *m = sv->map;
    st_level_cache *cache = &sv->cache[l];
    if (cache->p) cache->free(cache->p); /* stale: freed before the new one grows */
    cache->p = NULL;
    st_synth_table *t = calloc(1, sizeof *t);
    if (!t) abort(); /* out of memory for the synthesis tables */
    *t = (st_synth_table){ .scheme = scheme, .gen = st_map_generation(m), .dend = m->darts.end, .vend = m->verts.end,
                           .top = m->top, .plvl = m->pos.eff[l] };
    cache->p = t;
    cache->free = table_free;
    return t;
}

const st_synth_table *st_synth_tables_for(const st_subdiv_view *sv, unsigned L, int scheme, st_synth_build build)
{
    st_map *m = sv->map;
    unsigned l = L - 1;
    const st_synth_table *fresh = st_synth_tables_if_fresh(sv, l, scheme);
    if (fresh && !fresh->deferred) return fresh;
    st_synth_table *t = table_new(sv, l, scheme);
    /* Refs keep one bit for the column: ids past 2^31 (never in memory
     * today) take the stencils. */
    t->irregular = m->verts.end > REF_ID || build(sv, L, t);
    table_shrink(t);
    return t;
}

int st_synth_tables_defer(const st_subdiv_view *sv, unsigned L, int scheme)
{
    if (st_synth_tables_if_fresh(sv, L - 1, scheme)) return 0; /* built, or marked by the last synthesis */
    table_new(sv, L - 1, scheme)->deferred = 1;
    return 1;
}
