/* Helpers shared by the headless document tests (editor_testlib.h). */
#include "editor_testlib.h"
#include "testlib.h"
#include "core/multires/edit.h"
#include "core/adapt/adapt.h"
#include "core/io/session.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ed_test_open(st_doc *d, const char *path, const char *scheme, unsigned levels)
{
    st_error err;
    int rc = st_doc_open(d, path, scheme, levels, &err);
    CHECKF(rc == 0, "open %s: %s", path, err.msg);
    /* The brush tests written for the formulas of one dab run the raw dab
     * (no auto-smooth, spacing attenuation, fade or coarse reach);
     * test_editor_brush_hold and test_editor_coarse_grab run the defaults. */
    st_brush_raw(&d->brush);
}

uint32_t ed_test_level_vertices(const st_doc *d, unsigned l, uint32_t **out)
{
    uint32_t n = 0, cap = 64, *v = malloc(cap * sizeof *v);
    if (!v) abort();
    st_dart_iter it;
    for (uint32_t x = st_vertex_first(&d->h.map, l, &it); x != ST_NIL; x = st_vertex_next(&d->h.map, l, &it)) {
        if (n == cap) {
            v = realloc(v, (cap *= 2) * sizeof *v);
            if (!v) abort();
        }
        v[n++] = x;
    }
    *out = v;
    return n;
}

uint32_t ed_test_extreme_vertex(st_doc *d, const double dir[3])
{
    uint32_t *v, n = ed_test_level_vertices(d, d->edit_level, &v), best = ST_NIL;
    double bd = -INFINITY;
    for (uint32_t i = 0; i < n; i++) {
        double p[3];
        st_doc_vertex_pos(d, v[i], p);
        double s = p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2];
        if (s > bd) { bd = s; best = v[i]; }
    }
    free(v);
    return best;
}

double ed_test_dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

double *ed_test_all_values(const st_hier *h, size_t *n)
{
    const st_map *m = &h->map;
    size_t cap = 0, k = 0;
    st_dart_iter it;
    for (unsigned l = 0; l <= m->top; l++)
        for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) cap += l ? 6 : 3;
    double *p = malloc((cap ? cap : 1) * sizeof *p);
    if (!p) abort();
    for (unsigned l = 0; l <= m->top; l++)
        for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
            st_hier_value(h, st_fp_key(l, ST_FP_POS, v), p + k);
            k += 3;
            if (l) {
                st_hier_value(h, st_fp_key(l, ST_FP_DETAIL, v), p + k);
                k += 3;
            }
        }
    *n = k;
    return p;
}

int ed_test_same_values(const st_hier *h, const double *v, size_t n)
{
    size_t m;
    double *now = ed_test_all_values(h, &m);
    int same = m == n && !memcmp(now, v, n * sizeof *v);
    free(now);
    return same;
}

int ed_hier_clone(st_hier *dst, const st_hier *src, size_t *bytes); /* ui/doc/editor_clone.c */

/* (test_editor_hd*.c) The display equals a full adaptive synthesis of its levels above `from`
 * (core's st_adapt_synthesize on a copy), bit for bit. */
int ed_test_display_is_synthesis(st_doc *d, unsigned from)
{
    st_hier c;
    if (ed_hier_clone(&c, &d->display.hier, NULL)) return 0;
    st_adapt a = d->display.adapt; /* read only: its arrays stay the display's */
    a.h = &c;
    st_adapt_synthesize(&a, from);
    size_t n1, n2;
    double *v1 = ed_test_all_values(&d->display.hier, &n1), *v2 = ed_test_all_values(&c, &n2);
    int same = n1 == n2 && !memcmp(v1, v2, n1 * sizeof *v1);
    free(v1);
    free(v2);
    st_hier_free(&c);
    return same;
}

/* The editable vertex of the display's level L nearest to the centroid of
 * the editable ones (the middle of the HD region), its dart in *dart. */
uint32_t ed_test_hd_middle_vertex(st_doc *d, unsigned L, uint32_t *dart)
{
    st_map *m = &d->display.hier.map;
    double c[3] = { 0, 0, 0 };
    uint32_t n = 0, best = ST_NIL;
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, L, &it); x != ST_NIL; x = st_dart_next(m, L, &it)) {
        if (st_is_boundary(m, x) || !st_adapt_vertex_editable(m, x, L)) continue;
        const double *p = st_pos(m, st_vert(m, x, L), L);
        for (int k = 0; k < 3; k++) c[k] += p[k];
        n++;
    }
    if (!n) return ST_NIL;
    for (int k = 0; k < 3; k++) c[k] /= n;
    double bd = INFINITY;
    for (uint32_t x = st_dart_first(m, L, &it); x != ST_NIL; x = st_dart_next(m, L, &it)) {
        if (st_is_boundary(m, x) || !st_adapt_vertex_editable(m, x, L)) continue;
        double dd = ed_test_dist3(st_pos(m, st_vert(m, x, L), L), c);
        if (dd < bd) { bd = dd; best = st_vert(m, x, L); *dart = x; }
    }
    return best;
}

void ed_test_set_box(st_doc *d, double lo, double hi, int on)
{
    st_adapt_params p = d->box;
    for (int k = 0; k < 3; k++) { p.box_lo[k] = lo; p.box_hi[k] = hi; }
    p.has_box = 1;
    st_error err;
    CHECKF(st_doc_set_box(d, &p, on, &err) == 0, "box: %s", err.msg);
}

void ed_test_open_hd_session(st_doc *e, const char *obj, st_session *s)
{
    st_error err;
    CHECK(s->has_hd);
    st_doc_init(e);
    ed_test_open(e, obj, "catmull-clark", 0);
    st_hier_free(&e->h);
    st_session_move_hier(&e->h, &s->h);
    e->scheme = e->h.scheme;
    st_layers_free(&e->layers);
    e->layers = s->layers;
    st_layers_init(&s->layers);
    if (s->has_hd) CHECKF(st_doc_adopt_hd(e, &s->hd, &s->hd_adapt, &s->hd_layers, &err) == 0, "adopt: %s", err.msg);
}
