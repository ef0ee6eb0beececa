/* Footprints of local edits and values by key (edit.h, footprint.h).  The
 * region growth of an edit itself is in hier_synth.c, next to the synthesis
 * it drives; the local re-synthesis of adaptive hierarchies is in
 * core/adapt/adapt_resynth.c. */
#include "core/multires/edit.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

/* ---- footprints ---------------------------------------------------------------- */

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

/* ---- values by key ----------------------------------------------------------------- */

void st_hier_value(const st_hier *h, uint64_t key, double out[3])
{
    unsigned l = st_fp_level(key);
    uint32_t v = st_fp_vid(key);
    const double *p = st_fp_kind(key) == ST_FP_DETAIL ? st_hier_detail(h, l, v) : st_pos(&h->map, v, l);
    memcpy(out, p, 3 * sizeof *out);
}

void st_hier_set_value(st_hier *h, uint64_t key, const double v[3])
{
    if (st_fp_kind(key) == ST_FP_DETAIL) st_hier_set_detail(h, st_fp_level(key), st_fp_vid(key), v);
    else st_hier_write_pos(h, st_fp_vid(key), st_fp_level(key), v);
}

void st_hier_restore(st_hier *h, const uint64_t *keys, const double (*values)[3], uint32_t n, st_footprint *fp)
{
    for (uint32_t i = 0; i < n; i++) {
        st_hier_set_value(h, keys[i], values[i]);
        if (fp) st_footprint_add(fp, keys[i]);
    }
}
