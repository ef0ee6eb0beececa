/* The face-varying UVs of an st_hier (hier.h): its channel h->fvar kept
 * through core/fvar, which knows the map and the view of the scheme's
 * rules, not the hierarchy. */
#include "core/fvar/fvar_internal.h"
#include "core/multires/hier_internal.h"

st_uv_map st_hier_uv(const st_hier *h, unsigned l)
{
    const st_fvar *f = h->fvar;
    if (!f || l >= f->levels || l > h->map.top) return (st_uv_map){ NULL, NULL, 0 };
    return st_fvar_uv_map(&f->lv[l]);
}

int st_hier_has_uv(const st_hier *h, unsigned l)
{
    return st_hier_uv(h, l).uv != NULL;
}

int st_hier_uv_copy(st_hier *dst, const st_hier *src, size_t *bytes)
{
    if (st_fvar_copy(&dst->fvar, src->fvar)) return -1;
    for (unsigned l = 0; bytes && dst->fvar && l < dst->fvar->levels; l++) *bytes += st_fvar_level_bytes(&dst->fvar->lv[l]);
    return 0;
}

void st_hier_uv_free(st_hier *h)
{
    st_fvar_free(h->fvar);
    h->fvar = NULL;
}

int st_hier_uv_refine_levels(st_hier *h, unsigned upto, st_error *err)
{
    st_subdiv_view v = st_hier_view(h);
    return st_fvar_refine_levels(h->fvar, &v, h->scheme, upto, err);
}
