/* Multiresolution filtering in the document (editor.h, st_doc_filter): the
 * window's Filter panel.
 *
 * The operation is core's (st_progressive_filter: the details of level k+1
 * scaled by gain k, then the levels above the first changed one
 * re-synthesised; GSS99 §5).  The document adds what an interactive tool
 * needs: one undo step holding every value the filter writes, before and
 * after (the scaled details and every position of the re-synthesised
 * levels), so that undo and redo are exact whatever the gains (a gain of 0
 * cannot be undone by dividing, and re-synthesis would move the vertices
 * whose input bits a synthesis cannot reach by an ulp); the memory budget
 * first; and the display refreshed. */
#include "editor_internal.h"
#include "core/multires/estimate.h"
#include "core/progressive/progressive.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdio.h>

/* The first level whose details change (gain k applies to level k+1), or
 * 0 when every gain up to the top is 1. */
static unsigned first_changed(const double *gains, unsigned n, unsigned top)
{
    for (unsigned k = 0; k < n && k < top; k++)
        if (gains[k] != 1.0) return k + 1;
    return 0;
}

/* Values of every level >= first the step will hold (positions of every
 * vertex there, details of every vertex of a level whose gain is not 1). */
static uint64_t values_written(const st_hier *h, const double *gains, unsigned n, unsigned first)
{
    uint64_t c = 0;
    for (unsigned l = first; l <= h->map.top; l++) {
        uint64_t v = h->map.verts.live[l];
        for (unsigned k = 0; k < l; k++) v += h->map.verts.live[k];
        c += v * (1 + (l - 1 < n && gains[l - 1] != 1.0));
    }
    return c;
}

static void record(st_undo_step *s, const st_hier *h, const double *gains, unsigned n, unsigned first)
{
    const st_map *m = &h->map;
    st_dart_iter it;
    for (unsigned l = first; l <= m->top; l++) {
        int scaled = l - 1 < n && gains[l - 1] != 1.0;
        for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
            ed_step_touch_pos(s, h, l, v);
            if (scaled) ed_step_touch_detail(s, h, l, v);
        }
    }
}

int st_doc_filter(st_doc *d, const double *gains, unsigned n, st_error *err)
{
    if (!d->loaded) return st_fail(err, ST_ERR_INVALID, "no model");
    if (d->scheme != st_scheme_find("progressive"))
        return st_fail(err, ST_ERR_INVALID,
                       "filtering needs a progressive model (Mesh > Rebuild levels on a mesh without subdivision "
                       "connectivity); this one is %s",
                       d->scheme ? d->scheme->name : "empty");
    if (d->layers.n)
        return st_fail(err, ST_ERR_INVALID,
                       "filtering scales the levels' own details: merge or delete the %u sculpt layer%s first",
                       d->layers.n, d->layers.n == 1 ? "" : "s");
    for (unsigned k = 0; k < n; k++)
        if (!isfinite(gains[k])) return st_fail(err, ST_ERR_INVALID, "filter: gain %u is not finite", k);
    ed_finish_active(d);
    unsigned first = first_changed(gains, n, d->h.map.top);
    if (!first) return ST_OK; /* gains of 1 change no bit: no step */
    /* The synthesis's tables and columns, and the step's keys and two
     * values each. */
    size_t need = st_hier_synth_estimate(&d->h, first - 1) +
                  (size_t)values_written(&d->h, gains, n, first) * (sizeof(uint64_t) + 6 * sizeof(double));
    size_t have = st_doc_model_bytes(d);
    if (have + need > d->mem_budget)
        return st_fail(err, ST_ERR_MEMORY,
                       "filter refused: it needs about %.1f MiB more, the model uses %.1f MiB and the memory budget "
                       "is %.1f MiB",
                       st_mib(need), st_mib(have), st_mib(d->mem_budget));
    double t0 = ed_now_ms();
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->name = "filter";
    s->level = first - 1;
    record(s, &d->h, gains, n, first);
    int rc = st_progressive_filter(&d->h, gains, n, err);
    if (rc) {
        ed_step_free(s);
        return rc;
    }
    ed_step_capture_new(s, &d->h);
    ed_step_finish(s);
    ed_push_step(d, s);
    /* Every position above first-1 may have moved: no footprint, a full
     * refresh (from past the footprint's end). */
    ed_geometry_changed(d, first - 1, NULL, 0, t0, d->fp_model.n + 1);
    d->change.bits |= ST_CHANGE_ALL_POSITIONS;
    return ST_OK;
}

const char *st_filter_preset_name(int preset)
{
    static const char *const names[ST_FILTER_NPRESETS] = { "smooth", "sharpen", "keep coarse shape", "keep fine detail" };
    return preset >= 0 && preset < ST_FILTER_NPRESETS ? names[preset] : "?";
}

void st_filter_preset_gains(int preset, unsigned top, double *gains)
{
    /* Band k + 1 (gains[k]) by its place among levels 1..top: a third of
     * the bands at least one, so that a shallow hierarchy still filters. */
    unsigned third = top / 3 ? top / 3 : 1, half = top / 2 ? top / 2 : 1;
    for (unsigned k = 0; k < top; k++) {
        unsigned from_top = top - 1 - k;   /* 0: the finest band */
        double g = 1;
        switch (preset) {
        case ST_FILTER_SMOOTH: g = from_top < third ? 0.0 : from_top < 2 * third ? 0.5 : 1.0; break;
        case ST_FILTER_SHARPEN: g = from_top < half ? 1.5 : 1.0; break;
        case ST_FILTER_KEEP_COARSE: g = k < third ? 1.0 : 0.0; break;
        case ST_FILTER_KEEP_FINE: g = k < third ? 0.0 : 1.0; break;
        default: break;
        }
        gains[k] = g;
    }
}
