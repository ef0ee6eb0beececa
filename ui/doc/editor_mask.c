/* The sculpting mask in the document (editor.h; core/multires/mask.h).
 *
 * One value per vertex id of the hierarchy.  Operations act on the
 * vertices of the editing level, then the finer levels take the
 * subdivision of the mask (st_mask_propagate: the whole level for the
 * whole-level operations, the region around the dab for the mask brush).
 * Every operation is one undo step holding the mask before and after
 * (4 bytes per vertex id each).  The interest box's display has vertex ids
 * of its own: st_doc_display_mask carries the mask over to them for
 * drawing. */
#include "core/map/geometry.h"
#include "editor_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

float st_doc_mask(const st_doc *d, uint32_t vid) { return st_mask_get(&d->mask, vid); }

void ed_mask_changed(st_doc *d, const uint32_t *vids, uint32_t n)
{
    st_doc_change *c = &d->change;
    c->bits |= ST_CHANGE_MASK;
    if (!vids) {
        d->mask_all = 1;
        return;
    }
    if (d->mask_all || !n) return;
    if ((uint64_t)c->nmask_vids + n > d->capmaskv) {
        uint64_t cap = d->capmaskv ? d->capmaskv : 256;
        while (cap < (uint64_t)c->nmask_vids + n) cap *= 2;
        uint32_t *p = realloc(c->mask_vids, (size_t)cap * sizeof *p);
        if (!p) abort();
        c->mask_vids = p;
        d->capmaskv = (uint32_t)cap;
    }
    memcpy(c->mask_vids + c->nmask_vids, vids, (size_t)n * sizeof *vids);
    c->nmask_vids += n;
}

void ed_mask_extend(st_doc *d)
{
    if (!d->mask.v || d->h.map.top == 0) return;
    st_mask_propagate(&d->mask, &d->h, d->h.map.top - 1, NULL, 0);
    ed_mask_changed(d, NULL, 0);
}

/* ---- whole-level operations --------------------------------------------------- */

static st_undo_step *mask_step_begin(st_doc *d, const char *name)
{
    ed_finish_active(d);
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->name = name;
    s->level = d->edit_level;
    s->has_mask = 1;
    if (st_mask_copy(&s->mask_old, &d->mask)) abort(); /* out of memory */
    return s;
}

static int same_mask(const st_mask *a, const st_mask *b)
{
    uint32_t n = a->cap > b->cap ? a->cap : b->cap;
    for (uint32_t i = 0; i < n; i++)
        if (st_mask_get(a, i) != st_mask_get(b, i)) return 0;
    return 1;
}

/* The mask after: finer levels re-derived, the step pushed unless nothing
 * changed. */
static void mask_step_end(st_doc *d, st_undo_step *s, int propagate)
{
    if (propagate) st_mask_propagate(&d->mask, &d->h, s->level, NULL, 0);
    if (same_mask(&s->mask_old, &d->mask)) {
        ed_step_free(s);
        return;
    }
    if (st_mask_copy(&s->mask_new, &d->mask)) abort();
    ed_mask_changed(d, NULL, 0);
    ed_step_finish(s);
    ed_push_step(d, s);
}

int st_doc_mask_clear(st_doc *d)
{
    if (!d->loaded) return -1;
    st_undo_step *s = mask_step_begin(d, "clear mask");
    st_mask_free(&d->mask);
    mask_step_end(d, s, 0);
    return 0;
}

/* Every vertex of the editing level, once. */
static uint32_t level_vertices(const st_doc *d, uint32_t **out)
{
    const st_map *m = &d->h.map;
    unsigned l = d->edit_level;
    uint32_t n = 0, cap = 1024;
    uint32_t *v = malloc(cap * sizeof *v);
    if (!v) abort();
    st_dart_iter it;
    for (uint32_t x = st_vertex_first(m, l, &it); x != ST_NIL; x = st_vertex_next(m, l, &it)) {
        if (n == cap) {
            cap *= 2;
            uint32_t *p = realloc(v, cap * sizeof *p);
            if (!p) abort();
            v = p;
        }
        v[n++] = x;
    }
    *out = v;
    return n;
}

int st_doc_mask_invert(st_doc *d)
{
    if (!d->loaded) return -1;
    st_undo_step *s = mask_step_begin(d, "invert mask");
    uint32_t *v, n = level_vertices(d, &v);
    for (uint32_t i = 0; i < n; i++) st_mask_set(&d->mask, v[i], 1.0f - st_mask_get(&d->mask, v[i]));
    free(v);
    mask_step_end(d, s, 1);
    return 0;
}

enum { OP_GROW, OP_SHRINK, OP_SMOOTH };

/* One pass over the darts of the editing level: each dart x gives its
 * vertex the neighbour at the other end of its edge (β0 as the brushes use
 * it, brush.c), combined into a new array by op; then written back. */
static int neighbour_op(st_doc *d, int op, const char *name)
{
    if (!d->loaded) return -1;
    st_undo_step *s = mask_step_begin(d, name);
    const st_map *m = &d->h.map;
    unsigned l = d->edit_level;
    uint32_t nv = m->verts.end;
    float *acc = malloc((size_t)(nv ? nv : 1) * sizeof *acc);
    uint32_t *cnt = calloc(nv ? nv : 1, sizeof *cnt);
    if (!acc || !cnt) abort();
    uint32_t *v, n = level_vertices(d, &v);
    for (uint32_t i = 0; i < n; i++) acc[v[i]] = op == OP_SMOOTH ? 0.0f : st_mask_get(&d->mask, v[i]);
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, l, &it); x != ST_NIL; x = st_dart_next(m, l, &it)) {
        uint32_t a = st_vert(m, x, l), b = st_vert(m, st_beta0(m, x, l), l);
        if (a == b) continue;
        float mb = st_mask_get(&d->mask, b);
        if (op == OP_GROW) acc[a] = acc[a] > mb ? acc[a] : mb;
        else if (op == OP_SHRINK) acc[a] = acc[a] < mb ? acc[a] : mb;
        else acc[a] += mb;
        cnt[a]++;
    }
    for (uint32_t i = 0; i < n; i++) {
        float x = acc[v[i]];
        if (op == OP_SMOOTH) {
            float own = st_mask_get(&d->mask, v[i]);
            x = cnt[v[i]] ? 0.5f * own + 0.5f * (x / (float)cnt[v[i]]) : own;
        }
        st_mask_set(&d->mask, v[i], x < 0 ? 0.0f : x > 1 ? 1.0f : x);
    }
    free(acc);
    free(cnt);
    free(v);
    mask_step_end(d, s, 1);
    return 0;
}

int st_doc_mask_grow(st_doc *d) { return neighbour_op(d, OP_GROW, "grow mask"); }
int st_doc_mask_shrink(st_doc *d) { return neighbour_op(d, OP_SHRINK, "shrink mask"); }
int st_doc_mask_smooth(st_doc *d) { return neighbour_op(d, OP_SMOOTH, "smooth mask"); }

int st_doc_mask_cavity(st_doc *d)
{
    if (!d->loaded) return -1;
    st_undo_step *s = mask_step_begin(d, "mask by cavity");
    const st_map *m = &d->h.map;
    unsigned l = d->edit_level;
    uint32_t nv = m->verts.end;
    /* Per vertex: area-weighted normal (Newell normals of its faces), sum
     * of the neighbours, sum of edge lengths, count. */
    double(*nrm)[3] = calloc(nv ? nv : 1, sizeof *nrm), (*sum)[3] = calloc(nv ? nv : 1, sizeof *sum);
    double *elen = calloc(nv ? nv : 1, sizeof *elen);
    uint32_t *cnt = calloc(nv ? nv : 1, sizeof *cnt);
    if (!nrm || !sum || !elen || !cnt) abort();
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, l, &it); x != ST_NIL; x = st_dart_next(m, l, &it)) {
        uint32_t a = st_vert(m, x, l), b = st_vert(m, st_beta0(m, x, l), l);
        if (!st_is_boundary(m, x) && !m->face_embedded) {
            double fn[3];
            st_face_newell(m, x, l, fn);
            for (int k = 0; k < 3; k++) nrm[a][k] += fn[k];
        }
        if (a == b) continue;
        const double *pa = st_pos(m, a, l), *pb = st_pos(m, b, l);
        double e2 = 0;
        for (int k = 0; k < 3; k++) {
            sum[a][k] += pb[k];
            e2 += (pb[k] - pa[k]) * (pb[k] - pa[k]);
        }
        elen[a] += sqrt(e2);
        cnt[a]++;
    }
    uint32_t *v, n = level_vertices(d, &v);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t a = v[i];
        double ln = sqrt(nrm[a][0] * nrm[a][0] + nrm[a][1] * nrm[a][1] + nrm[a][2] * nrm[a][2]);
        float x = 0;
        if (cnt[a] && ln > 0 && elen[a] > 0) {
            /* Height of the ring's mean above the vertex along its normal:
             * positive in a crevice (the ring rises around it). */
            const double *p = st_pos(m, a, l);
            double depth = 0;
            for (int k = 0; k < 3; k++) depth += (sum[a][k] / cnt[a] - p[k]) * nrm[a][k] / ln;
            double t = 4.0 * depth / (elen[a] / cnt[a]);
            x = t <= 0 ? 0.0f : t >= 1 ? 1.0f : (float)t;
        }
        st_mask_set(&d->mask, a, x);
    }
    free(v);
    free(nrm);
    free(sum);
    free(elen);
    free(cnt);
    mask_step_end(d, s, 1);
    return 0;
}

/* ---- mask brush -------------------------------------------------------------------- */

int st_doc_mask_stroke_begin(st_doc *d, int erase)
{
    /* The stroke's grid and step, whatever tool is chosen (the window's
     * select tool too). */
    int tool = d->brush.tool;
    if (tool < 0 || tool >= ST_BRUSH_COUNT) d->brush.tool = ST_BRUSH_DRAW;
    int rc = ed_stroke_begin(d, 0); /* paints the mask: no synthesis */
    d->brush.tool = tool;
    if (rc) return -1;
    st_undo_step *s = d->pending;
    s->has_mask = 1;
    if (st_mask_copy(&s->mask_old, &d->mask)) abort();
    d->mask_erase = erase != 0;
    d->active = 3;
    return 0;
}

int st_doc_mask_stroke_dab(st_doc *d, const double center[3])
{
    if (d->active != 3 || !d->pending) return -1;
    const uint32_t *vids;
    const double *w;
    uint32_t n = ed_brush_query(d, center, d->brush.radius, &vids, &w);
    if (!n) return 0;
    unsigned l = d->pending->level;
    uint32_t *darts = malloc((size_t)n * sizeof *darts), *changed = malloc((size_t)n * sizeof *changed);
    if (!darts || !changed) abort();
    uint32_t nd = 0, nc = 0, nvd;
    /* (the model's table: at an HD level the mask is painted at the top) */
    const uint32_t *vd = ed_vertex_darts(d, &nvd);
    for (uint32_t i = 0; i < n; i++) {
        float m0 = st_mask_get(&d->mask, vids[i]);
        double f = w[i]; /* falloff times strength (ed_brush_weight) */
        double m1 = d->mask_erase ? m0 - f * m0 : m0 + f * (1.0 - m0);
        float x = m1 <= 0 ? 0.0f : m1 >= 1 ? 1.0f : (float)m1;
        if (x == m0) continue;
        st_mask_set(&d->mask, vids[i], x);
        uint32_t dart = vids[i] < nvd ? vd[vids[i]] : ST_NIL;
        changed[nc++] = vids[i];
        if (dart != ST_NIL) darts[nd++] = dart;
    }
    ed_mask_changed(d, changed, nc);
    /* The finer levels around the changed vertices. */
    uint32_t *fine = NULL, nf = 0, capf = 0;
    if (nd) st_mask_propagate_list(&d->mask, &d->h, l, darts, nd, &fine, &nf, &capf);
    ed_mask_changed(d, fine, nf);
    free(fine);
    free(darts);
    free(changed);
    return 0;
}

void st_doc_mask_stroke_end(st_doc *d)
{
    st_undo_step *s = ed_take_pending(d, 3);
    if (!s) return;
    if (same_mask(&s->mask_old, &d->mask)) {
        ed_step_free(s);
        return;
    }
    if (st_mask_copy(&s->mask_new, &d->mask)) abort();
    ed_step_finish(s);
    ed_push_step(d, s);
}

/* ---- the mask over the box display (st_doc_display_mask) ------------------------ */

typedef struct disp_mask_ctx { st_mask *mk; const st_map *m; unsigned L; } disp_mask_ctx;

/* A vertex inserted at L takes its stencil applied to the values of level
 * L-1, clamped to [0, 1] (the rule of core/multires/mask.h); a vertex that
 * lives on from L-1 keeps its value.  A stencil given twice writes the same
 * value twice. */
static void disp_mask_sink(void *ctx, const st_stencil *s)
{
    disp_mask_ctx *c = ctx;
    if (st_vertex_level(c->m, s->fine) != c->L) return;
    double x = 0;
    for (uint32_t i = 0; i < s->n; i++) x += s->w[i] * st_mask_get(c->mk, s->src[i]);
    c->mk->v[s->fine] = x < 0 ? 0.0f : x > 1 ? 1.0f : (float)x;
}

/* Level L of the display from level L-1: the stencils on the faces of
 * level L-1 subdivided toward L (the faces the display's own synthesis
 * beyond the model uses, ui/doc/editor_display.c). */
static void disp_mask_level(st_mask *mk, st_hier *h, unsigned L, st_dart_list *faces)
{
    st_map *m = &h->map;
    faces->n = 0;
    int fb = st_marker_reserve(m);
    if (fb < 0) abort();
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, L - 1, &it); x != ST_NIL; x = st_dart_next(m, L - 1, &it)) {
        if (st_is_boundary(m, x) || st_marked(m, fb, x)) continue;
        st_mark_face(m, fb, x, L - 1);
        if (st_face_level(m, x, L - 1) == L - 1 && st_face_is_subdivided(m, x, L - 1)) st_dart_list_push(faces, x);
    }
    st_marker_release(m, fb, L - 1);
    if (!faces->n) return; /* (emit with no face means every vertex of level L) */
    disp_mask_ctx c = { mk, m, L };
    st_hier_emit(h, L, faces->d, faces->n, disp_mask_sink, &c);
}

const st_mask *st_doc_display_mask(st_doc *d)
{
    if (st_doc_display_hier(d) == &d->h) return &d->mask;
    st_box_display *bd = &d->display;
    st_hier *h = &bd->hier;
    st_mask *mk = &d->display_mask;
    uint32_t n = h->map.verts.end;
    if (mk->cap < n || !mk->v) {
        float *p = realloc(mk->v, (size_t)(n ? n : 1) * sizeof *p);
        if (!p) abort(); /* out of memory while drawing, as the renderer's buffers */
        mk->v = p;
    }
    mk->cap = n;
    for (uint32_t v = 0; v < n; v++) {
        uint32_t mv = st_box_display_model_vertex(bd, v);
        mk->v[v] = mv == ST_NIL ? 0.0f : st_mask_get(&d->mask, mv);
    }
    st_dart_list faces = { 0 };
    for (unsigned L = d->h.map.top + 1; L <= h->map.top; L++) disp_mask_level(mk, h, L, &faces);
    st_dart_list_free(&faces);
    return mk;
}
