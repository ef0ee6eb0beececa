/* Deep copy of an st_hier (editor_internal.h): undo snapshots of level and
 * scheme changes, and the interest box's display hierarchy.  The copy is
 * bit-exact, id allocation state included (pools, free lists, spare
 * blocks), so later operations give the same ids on the copy as on the
 * original. */
#include "editor_internal.h"

#include <stdlib.h>
#include <string.h>

static int dup_bytes(void **dst, const void *src, size_t n, size_t *bytes)
{
    *dst = NULL;
    if (!src) return 0;
    void *p = malloc(n ? n : 1);
    if (!p) return -1;
    if (n) memcpy(p, src, n);
    *dst = p;
    *bytes += n;
    return 0;
}

static int dup_pool(st_pool *d, const st_pool *s, size_t *bytes)
{
    *d = *s;
    d->ins = NULL;
    d->next_free = NULL;
    d->spare = NULL;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) d->blocks[l] = NULL;
    int rc = dup_bytes((void **)&d->ins, s->ins, s->cap, bytes);
    rc |= dup_bytes((void **)&d->next_free, s->next_free, (size_t)s->cap * sizeof(uint32_t), bytes);
    rc |= dup_bytes((void **)&d->spare, s->spare, (size_t)s->capspare * sizeof(uint32_t), bytes);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
        rc |= dup_bytes((void **)&d->blocks[l], s->blocks[l], (size_t)s->capblocks[l] * sizeof(uint32_t), bytes);
    return rc ? -1 : 0;
}

static void free_pool(st_pool *p)
{
    free(p->ins);
    free(p->next_free);
    free(p->spare);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) free(p->blocks[l]);
    memset(p, 0, sizeof *p);
}

static int dup_mla(st_mla *d, const st_mla *s, uint32_t cap, size_t *bytes)
{
    *d = *s;
    d->base = NULL;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) d->col[l] = NULL;
    int rc = dup_bytes((void **)&d->base, s->base, (size_t)cap * s->elem, bytes);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
        rc |= dup_bytes((void **)&d->col[l], s->col[l], (size_t)s->colcap[l] * s->elem, bytes);
    rc |= st_mla_sparse_copy(d, s, bytes);
    return rc ? -1 : 0;
}

static void free_mla(st_mla *a)
{
    free(a->base);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) free(a->col[l]);
    st_mla_sparse_free(a->sp);
    memset(a, 0, sizeof *a);
}

/* Frees what a partial copy holds (fields not yet copied are NULL). */
static void free_partial(st_hier *h)
{
    st_map *m = &h->map;
    free_pool(&m->darts);
    free_pool(&m->verts);
    free_mla(&m->beta0);
    free_mla(&m->beta1);
    free_mla(&m->vert);
    free_mla(&m->pos);
    free(m->flags);
    free(m->marks);
    free_mla(&h->edge_sharp);
    free_mla(&h->vertex_sharp);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) free(h->detail[l]);
    free(h->stamp.v);
    st_hier_uv_free(h);
    memset(h, 0, sizeof *h);
}

int ed_hier_clone(st_hier *dst, const st_hier *src, size_t *bytes_out)
{
    size_t bytes = 0;
    const st_map *sm = &src->map;
    memset(dst, 0, sizeof *dst);
    *dst = *src;
    st_map *dm = &dst->map;
    /* Null every owned pointer first so that a failure can free the rest. */
    memset(&dm->darts, 0, sizeof dm->darts);
    memset(&dm->verts, 0, sizeof dm->verts);
    memset(&dm->beta0, 0, sizeof dm->beta0);
    memset(&dm->beta1, 0, sizeof dm->beta1);
    memset(&dm->vert, 0, sizeof dm->vert);
    memset(&dm->pos, 0, sizeof dm->pos);
    dm->flags = NULL;
    dm->marks = NULL;
    memset(&dst->edge_sharp, 0, sizeof dst->edge_sharp);
    memset(&dst->vertex_sharp, 0, sizeof dst->vertex_sharp);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) dst->detail[l] = NULL;
    dst->stamp = (st_stamps){ 0 };
    memset(dst->cache, 0, sizeof dst->cache); /* the copy builds its own */
    memset(&dst->local, 0, sizeof dst->local);
    dst->fvar = NULL;                         /* UVs: copied below */
    dst->pm_recipe = NULL;                    /* the copy's map has a generation of its own: not regenerable */
    dst->pm_recipe_len = 0;
    dm->gen_seen = 1;
    st_map_changed(dm); /* a generation of its own */
    int rc = dup_pool(&dm->darts, &sm->darts, &bytes);
    rc |= dup_pool(&dm->verts, &sm->verts, &bytes);
    rc |= dup_mla(&dm->beta0, &sm->beta0, sm->darts.cap, &bytes);
    rc |= dup_mla(&dm->beta1, &sm->beta1, sm->darts.cap, &bytes);
    rc |= dup_mla(&dm->vert, &sm->vert, sm->darts.cap, &bytes);
    rc |= dup_mla(&dm->pos, &sm->pos, sm->verts.cap, &bytes);
    rc |= dup_bytes((void **)&dm->flags, sm->flags, sm->darts.cap, &bytes);
    rc |= dup_bytes((void **)&dm->marks, sm->marks, (size_t)sm->darts.cap * sizeof(uint32_t), &bytes);
    if (src->has_sharpness) {
        rc |= dup_mla(&dst->edge_sharp, &src->edge_sharp, sm->darts.cap, &bytes);
        rc |= dup_mla(&dst->vertex_sharp, &src->vertex_sharp, sm->verts.cap, &bytes);
    } else {
        dst->edge_sharp = src->edge_sharp; /* element size only: nothing allocated */
        dst->vertex_sharp = src->vertex_sharp;
        dst->edge_sharp.base = NULL;
        dst->vertex_sharp.base = NULL;
        for (unsigned l = 0; l < ST_MAX_LEVELS; l++) dst->edge_sharp.col[l] = dst->vertex_sharp.col[l] = NULL;
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
        rc |= dup_bytes((void **)&dst->detail[l], src->detail[l], (size_t)src->detail_cap[l] * 3 * sizeof(double), &bytes);
    rc |= st_hier_uv_copy(dst, src, &bytes);
    if (rc) {
        free_partial(dst);
        return -1;
    }
    ed_hier_fix(dst);
    if (bytes_out) *bytes_out = bytes;
    return 0;
}

void ed_hier_fix(st_hier *h)
{
    /* The only attributes a hierarchy attaches are its sharpness arrays,
     * which live inside the st_hier itself: re-point them after a move. */
    st_map *m = &h->map;
    if (!h->has_sharpness) return;
    m->ndart_attrs = 1;
    m->dart_attrs[0] = &h->edge_sharp;
    m->nvert_attrs = 1;
    m->vert_attrs[0] = &h->vertex_sharp;
}

void ed_hier_swap(st_hier *a, st_hier *b)
{
    st_hier t = *a;
    *a = *b;
    *b = t;
    ed_hier_fix(a);
    ed_hier_fix(b);
}

size_t ed_hier_bytes(const st_hier *h)
{
    st_map_bytes b;
    st_map_memory(&h->map, &b);
    size_t n = b.topology + b.positions;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) n += (size_t)h->detail_cap[l] * 3 * sizeof(double);
    return n;
}
