/* Local re-synthesis of adaptive hierarchies (adapt.h): the region growth
 * of an edit (core/multires/hier_synth.c) restricted to the faces that are
 * subdivided toward the next level, for the interest box's display, which
 * copies the model's edited positions and re-synthesises its own finer
 * adaptive levels around them.  Kept in core/adapt because it reads the
 * cells' subdivision levels (Kraemer 2008 §3.3.1). */
#include "core/adapt/adapt.h"
#include "core/multires/edit.h"
#include "core/multires/hier_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct resynth_ctx {
    st_hier *h;
    unsigned L;
    uint32_t gen;
    st_dart_list *changed;   /* NULL: no seeds for a next level */
    int lost;
    st_footprint *fp;
} resynth_ctx;

/* Applies stencil s at level L unless its fine vertex was already written
 * in this pass (stamp gen); st_set_pos writes the level's column as
 * st_adapt_synthesize does. */
static void resynth_sink(void *ctx, const st_stencil *s)
{
    resynth_ctx *c = ctx;
    st_hier *h = c->h;
    if (h->stamp.v[s->fine] == c->gen) return;
    h->stamp.v[s->fine] = c->gen;
    double p[3];
    st_stencil_apply(h, c->L, s, p);
    st_set_pos(&h->map, s->fine, c->L, p);
    if (c->fp) st_footprint_add(c->fp, st_fp_key(c->L, ST_FP_POS, s->fine));
    if (!c->changed) return;
    uint32_t x = st_dart_on_cell(&h->map, s->fine, s->frame_dart, c->L);
    if (x == ST_NIL) c->lost = 1;
    else st_dart_list_push(c->changed, x);
}

void st_hier_resynth_faces(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n)
{
    if (!n) return;
    resynth_ctx c = { .h = h, .L = L, .gen = st_hier_stamp_begin(h) };
    st_hier_emit(h, L, faces, n, resynth_sink, &c);
}

typedef struct around_ctx {
    st_hier *h;
    st_footprint *fp;
    unsigned extra;            /* more rings: a vertex was lost at the level below */
    st_dart_list faces, kept;
} around_ctx;

static int around_step(void *ctx, unsigned L, const st_dart_list *seeds, st_dart_list *next)
{
    around_ctx *a = ctx;
    st_hier *h = a->h;
    st_map *m = &h->map;
    if (!seeds->n) return 1;
    a->faces.n = 0;
    st_region_faces(m, L - 1, seeds->d, seeds->n, h->scheme->support_rings + 1 + a->extra, &a->faces);
    a->kept.n = 0;
    for (uint32_t i = 0; i < a->faces.n; i++)
        if (st_face_level(m, a->faces.d[i], L - 1) == L - 1 && st_face_is_subdivided(m, a->faces.d[i], L - 1))
            st_dart_list_push(&a->kept, a->faces.d[i]);
    resynth_ctx c = { .h = h, .L = L, .gen = st_hier_stamp_begin(h), .changed = next, .fp = a->fp };
    if (a->kept.n) st_hier_emit(h, L, a->kept.d, a->kept.n, resynth_sink, &c);
    a->extra = c.lost;
    /* A vertex not found on its frame cell: every dart of the kept faces
     * seeds the next level, with one more ring. */
    if (c.lost) {
        next->n = 0;
        st_dart_list_push_faces(next, m, L - 1, a->kept.d, a->kept.n);
    }
    return 0;
}

void st_hier_resynth_around(st_hier *h, unsigned from, const uint32_t *seeds0, uint32_t n, st_footprint *fp)
{
    st_dart_list seeds = { 0 };
    for (uint32_t i = 0; i < n; i++) st_dart_list_push(&seeds, seeds0[i]);
    around_ctx a = { .h = h, .fp = fp };
    st_hier_levels_up(h, from, &seeds, around_step, &a);
    st_dart_list_free(&a.faces);
    st_dart_list_free(&a.kept);
}
