/* Stencil scratch buffers and the scheme registry. */
#include "core/schemes/scheme.h"

#include <stdlib.h>
#include <string.h>

void st_stencil_buf_free(st_stencil_buf *b)
{
    free(b->src);
    free(b->w);
    memset(b, 0, sizeof *b);
}

void st_stencil_buf_clear(st_stencil_buf *b) { b->n = 0; }

void st_stencil_buf_add(st_stencil_buf *b, uint32_t v, double w)
{
    if (b->n == b->cap) {
        uint32_t cap = b->cap ? 2 * b->cap : 32;
        uint32_t *s = realloc(b->src, cap * sizeof *s);
        double *ww = realloc(b->w, cap * sizeof *ww);
        if (!s || !ww) abort(); /* stencils are bounded by valence: out of memory here is fatal */
        b->src = s;
        b->w = ww;
        b->cap = cap;
    }
    b->src[b->n] = v;
    b->w[b->n++] = w;
}

void st_stencil_buf_add_scaled(st_stencil_buf *b, const st_stencil_buf *o, double s)
{
    for (uint32_t i = 0; i < o->n; i++) st_stencil_buf_add(b, o->src[i], o->w[i] * s);
}

static const st_scheme *const all_schemes[] = {
    &st_scheme_catmark, &st_scheme_loop, &st_scheme_butterfly,
    &st_scheme_quadtri, &st_scheme_sqrt3, &st_scheme_doosabin,
    &st_scheme_progressive,
};

const st_scheme *st_scheme_get(st_scheme_id id)
{
    for (size_t i = 0; i < sizeof all_schemes / sizeof *all_schemes; i++)
        if (all_schemes[i]->id == id) return all_schemes[i];
    return NULL;
}

const st_scheme *st_scheme_find(const char *name)
{
    for (size_t i = 0; i < sizeof all_schemes / sizeof *all_schemes; i++)
        if (!strcmp(all_schemes[i]->name, name)) return all_schemes[i];
    if (!strcmp(name, "catmark") || !strcmp(name, "cc")) return st_scheme_get(ST_SCHEME_CATMARK);
    return NULL;
}
