/* Stencil scratch buffers, their evaluation, and the stamps of the passes. */
#include "core/schemes/synth_internal.h"

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

void st_stencil_eval(const st_map *m, unsigned L, const st_stencil *s, double out[3])
{
    st_level_view v;
    st_level_view_init(m, L - 1, &v);
    double x = 0, y = 0, z = 0;
    for (uint32_t i = 0; i < s->n; i++) {
        const double *p = st_v_pos(&v, s->src[i]);
        x += s->w[i] * p[0];
        y += s->w[i] * p[1];
        z += s->w[i] * p[2];
    }
    out[0] = x; out[1] = y; out[2] = z;
}

uint32_t st_stamps_begin(st_stamps *s, uint32_t need)
{
    if (s->cap < need) {
        uint32_t *p = realloc(s->v, (size_t)need * sizeof *p);
        if (!p) abort();
        memset(p + s->cap, 0, (size_t)(need - s->cap) * sizeof *p);
        s->v = p;
        s->cap = need;
    }
    if (++s->gen == 0) {
        memset(s->v, 0, (size_t)s->cap * sizeof *s->v);
        s->gen = 1;
    }
    return s->gen;
}
