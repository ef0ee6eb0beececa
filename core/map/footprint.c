/* st_footprint's growth (footprint.h): the keys of the values a local edit
 * wrote, appended by the synthesis passes of core/multires and by the
 * schemes' local predictions (st_synth_put), hence here, below both. */
#include "core/map/footprint.h"

#include <stdlib.h>
#include <string.h>

void st_footprint_add_slow(st_footprint *f, uint64_t key)
{
    if (f->n == f->cap) {
        uint32_t cap = f->cap ? 2 * f->cap : 256;
        uint64_t *k = realloc(f->keys, (size_t)cap * sizeof *k);
        if (!k) abort(); /* out of memory during a synthesis pass */
        f->keys = k;
        f->cap = cap;
    }
    f->keys[f->n++] = key;
}

void st_footprint_free(st_footprint *f)
{
    free(f->keys);
    memset(f, 0, sizeof *f);
}
