#include "core/map/map_memory.h"

void st_map_level_memory(const st_map *m, unsigned l, st_map_bytes *b)
{
    const st_mla *rel[3] = { &m->beta0, &m->beta1, &m->vert };
    size_t per_dart = 2; /* insertion level + flags */
    b->topology = 0;
    for (int i = 0; i < 3; i++) {
        per_dart += rel[i]->elem;
        b->topology += (size_t)rel[i]->colcap[l] * rel[i]->elem;
        if (rel[i]->sp) b->topology += (size_t)rel[i]->sp->pairs_at[l] * (1 + rel[i]->elem); /* offsets: not per level */
    }
    b->topology += (size_t)m->darts.live[l] * per_dart;
    b->positions = (size_t)m->verts.live[l] * (m->pos.elem + 1) + (size_t)m->pos.colcap[l] * m->pos.elem;
}
