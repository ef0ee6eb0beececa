/* Values by key of local edits' footprints (edit.h; the footprint itself is
 * core/map/footprint.h).  The region growth of an edit itself is in hier_synth.c, next to the synthesis
 * it drives; the local re-synthesis of adaptive hierarchies is in
 * core/adapt/adapt_resynth.c. */
#include "core/multires/edit.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

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
