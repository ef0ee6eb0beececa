/* The document's interaction benchmark (st_doc_bench_drag, editor.h): the
 * geometry half of `strata --bench-interaction` (bench/interaction.c adds
 * the window's buffer updates); in strata_editor, with no GL, so that the
 * headless tests run it too. */
#include "editor_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int st_doc_bench_drag(st_doc *d, unsigned level, unsigned steps, double *step_ms_median, double *full_synth_ms)
{
    if (!d->loaded || level > d->h.map.top || !steps) return -1;
    ed_finish_active(d);
    st_map *m = &d->h.map;
    uint64_t count = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, level, &it); v != ST_NIL; v = st_vertex_next(m, level, &it)) count++;
    uint64_t k = 0;
    uint32_t pick = ST_NIL;
    for (uint32_t v = st_vertex_first(m, level, &it); v != ST_NIL; v = st_vertex_next(m, level, &it))
        if (k++ == count / 2) { pick = v; break; }
    if (pick == ST_NIL) return -1;
    unsigned el = d->edit_level, dl = d->display_level;
    uint32_t nsel = d->nsel, *sel = malloc((size_t)(nsel ? nsel : 1) * sizeof *sel);
    if (!sel) abort();
    if (nsel) memcpy(sel, d->sel, (size_t)nsel * sizeof *sel);
    d->edit_level = level;
    if (d->display_level < level) d->display_level = level;
    st_doc_select(d, &pick, 1, ST_SELECT_REPLACE);
    double *t = malloc((size_t)steps * sizeof *t);
    if (!t) abort();
    double size = 0;
    for (uint32_t i = 0; i < d->base.nverts; i++)
        for (int c = 0; c < 3; c++) size = fmax(size, fabs(d->base.pos[3 * i + c]));
    if (size == 0) size = 1;
    int rc = st_doc_drag_begin(d);
    if (!rc) {
        for (unsigned i = 0; i < steps; i++) {
            double a = 6.283185307179586 * i / steps;
            double delta[3] = { 0.05 * size * cos(a), 0.05 * size * sin(a), 0.02 * size };
            double t0 = ed_now_ms();
            st_doc_drag_update(d, delta);
            t[i] = ed_now_ms() - t0;
            /* Untimed, as the window takes the change every frame (else
             * the footprints of all the steps pile up). */
            (void)st_doc_take_change(d);
        }
        st_doc_drag_cancel(d);
        qsort(t, steps, sizeof *t, cmp_double);
        if (step_ms_median) *step_ms_median = steps % 2 ? t[steps / 2] : (t[steps / 2 - 1] + t[steps / 2]) / 2;
    }
    free(t);
    d->edit_level = el;
    d->display_level = dl;
    d->vdart_level = -1;
    st_doc_select(d, sel, nsel, ST_SELECT_REPLACE);
    free(sel);
    if (rc) return -1;
    /* The full synthesis runs on a copy: the model keeps its exact bits. */
    st_hier tmp;
    if (ed_hier_clone(&tmp, &d->h, NULL)) return -1;
    double t0 = ed_now_ms();
    st_hier_synthesize(&tmp, 0);
    if (full_synth_ms) *full_synth_ms = ed_now_ms() - t0;
    st_hier_free(&tmp);
    return 0;
}

