/* Masks (mask.h): values per vertex id, subdivided by the scheme's
 * stencils from the painting level up. */
#include "core/multires/mask.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

void st_mask_set(st_mask *mk, uint32_t vid, float x)
{
    if (vid >= mk->cap) {
        if (!mk->v && x == 0) return;
        uint32_t cap = mk->cap ? mk->cap : 1024;
        while (cap <= vid) cap *= 2;
        float *p = realloc(mk->v, (size_t)cap * sizeof *p);
        if (!p) abort(); /* out of memory while painting */
        memset(p + mk->cap, 0, (size_t)(cap - mk->cap) * sizeof *p);
        mk->v = p;
        mk->cap = cap;
    }
    mk->v[vid] = x;
}

void st_mask_free(st_mask *mk)
{
    free(mk->v);
    mk->v = NULL;
    mk->cap = 0;
}

int st_mask_copy(st_mask *dst, const st_mask *src)
{
    dst->v = NULL;
    dst->cap = 0;
    if (!src->v) return 0;
    dst->v = malloc((size_t)src->cap * sizeof *dst->v);
    if (!dst->v) return -1;
    memcpy(dst->v, src->v, (size_t)src->cap * sizeof *dst->v);
    dst->cap = src->cap;
    return 0;
}

int st_mask_any(const st_mask *mk)
{
    for (uint32_t i = 0; mk->v && i < mk->cap; i++)
        if (mk->v[i] != 0) return 1;
    return 0;
}

typedef struct prop_ctx {
    st_hier *h;
    st_mask *mk;
    unsigned L;
    uint32_t gen;              /* 0: full level */
    st_dart_list *next;        /* local: darts of level L of the vertices written */
    uint32_t **out, *nout, *cap;   /* NULL, or where the ids written go */
} prop_ctx;

static void prop_sink(void *ctx, const st_stencil *s)
{
    prop_ctx *c = ctx;
    const st_map *m = &c->h->map;
    if (m->verts.ins[s->fine] != c->L) return; /* a coinciding vertex keeps its value */
    if (c->gen) {
        if (c->h->stamp.v[s->fine] == c->gen) return;
        c->h->stamp.v[s->fine] = c->gen;
    }
    double x = 0;
    for (uint32_t i = 0; i < s->n; i++) x += s->w[i] * st_mask_get(c->mk, s->src[i]);
    float f = x < 0 ? 0.0f : x > 1 ? 1.0f : (float)x;
    st_mask_set(c->mk, s->fine, f);
    if (c->out) {
        if (*c->nout == *c->cap) {
            uint32_t nc = *c->cap ? 2 * *c->cap : 256;
            uint32_t *p = realloc(*c->out, (size_t)nc * sizeof *p);
            if (!p) abort();
            *c->out = p;
            *c->cap = nc;
        }
        (*c->out)[(*c->nout)++] = s->fine;
    }
    if (c->next) {
        uint32_t d = st_dart_on_cell(m, s->fine, s->frame_dart, c->L);
        if (d != ST_NIL) st_dart_list_push(c->next, d);
    }
}

/* One level of the local propagation (propagate below). */
typedef struct up_ctx {
    prop_ctx c;                /* L, gen and next set per level */
    st_dart_list faces;
} up_ctx;

static int up_step(void *ctx, unsigned L, const st_dart_list *seeds, st_dart_list *next)
{
    up_ctx *u = ctx;
    st_hier *h = u->c.h;
    u->faces.n = 0;
    st_region_faces(&h->map, L - 1, seeds->d, seeds->n, 1, &u->faces);
    u->c.L = L;
    u->c.gen = st_hier_stamp_begin(h);
    u->c.next = next;
    st_hier_emit(h, L, u->faces.d, u->faces.n, prop_sink, &u->c);
    /* Old seeds stay seeds where their vertex lives on at L. */
    for (uint32_t i = 0; i < seeds->n; i++) st_dart_list_push(next, seeds->d[i]);
    return 0;
}

static void propagate(st_mask *mk, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n, uint32_t **out,
                      uint32_t *nout, uint32_t *cap)
{
    st_map *m = &h->map;
    if (!darts) {
        for (unsigned L = l + 1; L <= m->top; L++) {
            prop_ctx c = { h, mk, L, 0, NULL, NULL, NULL, NULL };
            st_hier_emit(h, L, NULL, 0, prop_sink, &c);
        }
        return;
    }
    /* Local: the vertices of level L whose stencils lie on the faces of
     * level L-1 around the seeds; a vertex that keeps its id from L-1 to L
     * seeds level L+1 too (its neighbours at L+1 may have changed). */
    st_dart_list seeds = { 0 };
    for (uint32_t i = 0; i < n; i++) st_dart_list_push(&seeds, darts[i]);
    up_ctx u = { { h, mk, 0, 0, NULL, out, nout, cap }, { 0 } };
    st_hier_levels_up(h, l, &seeds, up_step, &u);
    st_dart_list_free(&u.faces);
}

void st_mask_propagate(st_mask *mk, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n)
{
    propagate(mk, h, l, darts, n, NULL, NULL, NULL);
}

void st_mask_propagate_list(st_mask *mk, st_hier *h, unsigned l, const uint32_t *darts, uint32_t n, uint32_t **out,
                            uint32_t *nout, uint32_t *cap)
{
    propagate(mk, h, l, darts, n, out, nout, cap);
}
