/* Synthesis (thesis Algorithm 3), local frames, and local re-synthesis after
 * an edit.  Stencils come from the scheme; this file only applies them. */
#include "core/base/hugepage.h"
#include "core/map/geometry.h"
#include "core/multires/edit.h"
#include "core/multires/hier_internal.h"
#include "core/map/pool_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- positions and details -------------------------------------------------- */

static const double zero3[3];

const double *st_hier_detail(const st_hier *h, unsigned l, uint32_t v)
{
    if (!h->detail[l] || v >= h->detail_cap[l]) return zero3;
    return h->detail[l] + 3 * (size_t)v;
}

void st_hier_set_detail(st_hier *h, unsigned l, uint32_t v, const double d[3])
{
    if (v >= h->detail_cap[l]) {
        if (!h->detail[l] && d[0] == 0 && d[1] == 0 && d[2] == 0) return;
        uint32_t cap = h->map.verts.end > v ? h->map.verts.end : v + 1;
        /* The array covers the ids up to the map's end, which an adaptive
         * refinement moves a pool block at a time: when the block must
         * move it takes half again as much room, so that it is not copied
         * once per pool block (a quadratic copy that took three quarters
         * of an HD box jump where realloc could not grow in place).  The
         * room past detail_cap is neither read nor zeroed before the cap
         * reaches it. */
        size_t room = st_usable_bytes(h->detail[l]) / (3 * sizeof(double));
        if (cap > room) {
            size_t want = (size_t)cap + cap / 2;
            if (want > UINT32_MAX) want = UINT32_MAX;
            double *p = realloc(h->detail[l], 3 * want * sizeof *p);
            if (!p) abort();
            st_advise_huge(p, 3 * want * sizeof *p);
            h->detail[l] = p;
        }
        memset(h->detail[l] + 3 * (size_t)h->detail_cap[l], 0, 3 * (size_t)(cap - h->detail_cap[l]) * sizeof(double));
        h->detail_cap[l] = cap;
    }
    memcpy(h->detail[l] + 3 * (size_t)v, d, 3 * sizeof *d);
}

void st_hier_trim_details(st_hier *h)
{
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (!h->detail[l]) continue;
        uint32_t n = h->detail_cap[l];
        while (n > 1 && memcmp(h->detail[l] + 3 * (size_t)(n - 1), zero3, sizeof zero3) == 0) n--;
        if (n == h->detail_cap[l]) continue;
        double *p = realloc(h->detail[l], 3 * (size_t)n * sizeof *p);
        if (p) h->detail[l] = p; /* a failed shrink keeps the larger block */
        h->detail_cap[l] = n;
    }
}

/* ---- local frames ------------------------------------------------------------ */

static void add3(double *a, const double *b) { a[0] += b[0]; a[1] += b[1]; a[2] += b[2]; }

/* Newell normal of the face of d (unnormalised; zero for boundary faces). */
static void face_normal(const st_map *m, uint32_t d, unsigned l, double n[3])
{
    if (st_is_boundary(m, d)) { n[0] = n[1] = n[2] = 0; return; }
    st_face_newell(m, d, l, n);
}

static uint32_t min_in_orbit(const st_map *m, uint32_t d, unsigned l, int face)
{
    uint32_t best = d, x = d;
    do {
        if (x < best) best = x;
        x = face ? st_phi1(m, x, l) : st_beta1(m, x, l);
    } while (x != d);
    return best;
}

void st_hier_frame(const st_hier *h, unsigned l, uint32_t d, int cell, double f[3][3])
{
    const st_map *m = &h->map;
    double n[3] = { 0, 0, 0 }, t[3], fn[3];
    uint32_t c;
    if (cell == ST_CELL_DUAL_FACE) {
        /* Face of a dual-encoded surface: the vertex orbit of the map,
         * whose faces carry the surface's vertices (Newell normal). */
        c = min_in_orbit(m, d, l, 0);
        st_face_newell(m, c, l, n);
        st_sub3(st_pos(m, st_vert(m, st_beta1(m, c, l), l), l), st_pos(m, st_vert(m, c, l), l), t);
        st_frame_orthonormal(t, n, f);
        return;
    }
    if (cell == ST_CELL_FACE) {
        c = min_in_orbit(m, d, l, 1);
        face_normal(m, c, l, n);
    } else if (cell == ST_CELL_EDGE) {
        uint32_t e = st_beta0(m, d, l);
        c = d < e ? d : e;
        face_normal(m, c, l, n);
        face_normal(m, st_beta0(m, c, l), l, fn);
        add3(n, fn);
    } else {
        /* Vertex: sum of the corner normals of its real faces. */
        c = min_in_orbit(m, d, l, 0);
        const double *p = st_dart_pos(m, c, l);
        uint32_t x = c;
        do {
            uint32_t y = st_beta1(m, x, l);
            if (!st_is_boundary(m, st_beta0(m, x, l))) {
                double a[3], b[3], cr[3];
                st_sub3(p, st_dart_pos(m, st_beta0(m, x, l), l), a);
                st_sub3(st_dart_pos(m, st_beta0(m, y, l), l), p, b);
                st_cross3(a, b, cr);
                add3(n, cr);
            }
            x = y;
        } while (x != c);
    }
    st_sub3(st_dart_pos(m, st_beta0(m, c, l), l), st_dart_pos(m, c, l), t);
    st_frame_orthonormal(t, n, f);
}

/* ---- stencil application ----------------------------------------------------- */

void st_stencil_apply(const st_hier *h, unsigned L, const st_stencil *s, double out[3])
{
    st_stencil_eval(&h->map, L, s, out);
    const double *d = st_hier_detail(h, L, s->fine);
    if (d[0] == 0 && d[1] == 0 && d[2] == 0) return;
    double f[3][3];
    st_hier_frame(h, L - 1, s->frame_dart, s->frame_cell, f);
    for (int i = 0; i < 3; i++) out[i] += d[0] * f[0][i] + d[1] * f[1][i] + d[2] * f[2][i];
}

typedef st_synth_ctx synth_ctx;

/* A dart of level L carrying fine vertex v, found on the frame cell of its
 * stencil (dart d of level L-1): d itself for a vertex cell; for an edge or
 * a face, the children of a primal split lie on the face of d at level L.
 * ST_NIL if v is not there (a scheme that puts it elsewhere). */
uint32_t st_dart_on_cell(const st_map *m, uint32_t v, uint32_t d, unsigned L)
{
    uint32_t x = d;
    do {
        if (st_vert(m, x, L) == v) return x;
        x = st_phi1(m, x, L);
    } while (x != d);
    return ST_NIL;
}

void st_synth_sink(void *ctx, const st_stencil *s)
{
    synth_ctx *c = ctx;
    if (c->gen) {
        if (c->stamp->v[s->fine] == c->gen) return;
        c->stamp->v[s->fine] = c->gen;
    }
    double p[3];
    st_stencil_apply(c->owner, c->L, s, p);
    st_map_write_pos(c->m, s->fine, c->L, p);
    c->count++;
    if (c->fp) st_footprint_add(c->fp, st_fp_key(c->L, ST_FP_POS, s->fine));
    if (c->changed) {
        uint32_t d = st_dart_on_cell(c->m, s->fine, s->frame_dart, c->L);
        if (d == ST_NIL) c->lost = 1;
        else st_dart_list_push(c->changed, d);
    }
}

void st_hier_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t nfaces, st_stencil_sink sink, void *ctx)
{
    st_hier_emit_except(h, L, faces, nfaces, NULL, 0, sink, ctx);
}

void st_hier_emit_except(st_hier *h, unsigned L, const uint32_t *faces, uint32_t nfaces, const uint32_t *skip,
                         uint32_t nskip, st_stencil_sink sink, void *ctx)
{
    st_subdiv_view v = st_hier_view(h);
    v.emit_skip = skip;
    v.emit_nskip = nskip;
    h->scheme->emit(&v, L, faces, nfaces, sink, ctx);
}

void st_hier_synthesize(st_hier *h, unsigned from)
{
    st_subdiv_view v = st_hier_view(h);
    for (unsigned L = from + 1; L <= h->map.top; L++) {
        if (h->scheme->predict_level && (!h->detail[L] || h->scheme->fast_paths_apply_details)) {
            h->scheme->predict_level(&v, L);
            continue;
        }
        synth_ctx c = st_hier_synth_ctx(h, L);
        h->scheme->emit(&v, L, NULL, 0, st_synth_sink, &c);
    }
}

/* ---- regions ------------------------------------------------------------------ */

void st_dart_list_push_faces(st_dart_list *list, const st_map *m, unsigned l, const uint32_t *faces, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++) {
        uint32_t x = faces[i];
        do { st_dart_list_push(list, x); x = st_phi1(m, x, l); } while (x != faces[i]);
    }
}

void st_hier_levels_up(const st_hier *h, unsigned from, st_dart_list *seeds, st_level_step_fn step, void *ctx)
{
    st_dart_list next = { 0 };
    for (unsigned L = from + 1; L <= h->map.top; L++) {
        next.n = 0;
        if (step(ctx, L, seeds, &next)) break;
        st_dart_list t = *seeds;
        *seeds = next;
        next = t;
    }
    st_dart_list_free(seeds);
    st_dart_list_free(&next);
}

/* Breadth-first over vertex rings with two marker bits; the marks are
 * cleared from the lists afterwards, so the cost is proportional to the
 * region, not to the level. */
void st_region_faces(st_map *m, unsigned l, const uint32_t *seeds, uint32_t nseeds, unsigned rings, st_dart_list *faces)
{
    int fb = st_marker_reserve(m), vb = st_marker_reserve(m);
    if (fb < 0 || vb < 0) abort();
    st_dart_list verts = { 0 };
    for (uint32_t i = 0; i < nseeds; i++)
        if (!st_marked(m, vb, seeds[i])) { st_mark_vertex(m, vb, seeds[i], l); st_dart_list_push(&verts, seeds[i]); }
    uint32_t begin = 0;
    for (unsigned r = 0; r < rings; r++) {
        uint32_t end = verts.n;
        for (uint32_t i = begin; i < end; i++) {
            uint32_t x = verts.d[i];
            do {
                if (!st_is_boundary(m, x) && !st_marked(m, fb, x)) {
                    st_mark_face(m, fb, x, l);
                    st_dart_list_push(faces, x);
                    uint32_t y = x;
                    do {
                        if (!st_marked(m, vb, y)) { st_mark_vertex(m, vb, y, l); st_dart_list_push(&verts, y); }
                        y = st_phi1(m, y, l);
                    } while (y != x);
                }
                x = st_beta1(m, x, l);
            } while (x != verts.d[i]);
        }
        begin = end;
    }
    for (uint32_t i = 0; i < verts.n; i++) {
        uint32_t x = verts.d[i];
        do { st_unmark(m, vb, x); x = st_beta1(m, x, l); } while (x != verts.d[i]);
    }
    for (uint32_t i = 0; i < faces->n; i++) {
        uint32_t x = faces->d[i];
        do { st_unmark(m, fb, x); x = st_phi1(m, x, l); } while (x != faces->d[i]);
    }
    m->marks_used &= ~((1u << fb) | (1u << vb));
    st_dart_list_free(&verts);
}

/* ---- editing ------------------------------------------------------------------ */

/* A seed on a hole leads nowhere in the dual encoding (Doo-Sabin), where
 * the region walk starts from the seed's β1 orbit, a surface face: take a
 * dart of the same surface vertex (φ1 orbit) on a real face. */
static uint32_t real_seed(const st_map *m, uint32_t d, unsigned l)
{
    if (d == ST_NIL || !m->face_embedded || !st_is_boundary(m, d)) return d;
    uint32_t x = d;
    do {
        if (!st_is_boundary(m, x)) return x;
        x = st_phi1(m, x, l);
    } while (x != d);
    return d;
}

/* A dart of level l-1 near the vertex of d (level l): walk the faces around
 * the vertex until a dart that existed at level l-1 is found. */
static uint32_t coarse_seed(const st_map *m, uint32_t d, unsigned l)
{
    uint32_t x = d;
    do {
        uint32_t y = x;
        do {
            if (m->darts.ins[y] < l) return y;
            y = st_phi1(m, y, l);
        } while (y != x);
        x = st_beta1(m, x, l);
    } while (x != d);
    return ST_NIL;
}

typedef struct find_ctx { uint32_t v; st_stencil_buf buf; uint32_t frame_dart; uint8_t frame_cell; int found; } find_ctx;

static void find_sink(void *ctx, const st_stencil *s)
{
    find_ctx *c = ctx;
    if (s->fine != c->v || c->found) return;
    st_stencil_buf_clear(&c->buf);
    for (uint32_t i = 0; i < s->n; i++) st_stencil_buf_add(&c->buf, s->src[i], s->w[i]);
    c->frame_dart = s->frame_dart;
    c->frame_cell = s->frame_cell;
    c->found = 1;
}

/* ---- prediction cache of an edit sequence (edit.h) ---------------------------- */

struct st_edit_cache {
    unsigned level;
    /* Per vertex id: entry + 1 (0: none).  A dense index rather than a
     * hash: a dab looks up thousands of neighbouring vertices, whose ids
     * share cache lines here, where hashed slots missed the cache for
     * each (a fifth of a level-6 dab). */
    uint32_t *at, cap;
    double (*pf)[12];          /* per entry: S(P_{l-1})(v), frame rows */
    uint32_t *vid;             /* per entry: its vertex id (clearing resets only those) */
    uint8_t *fixed;            /* per entry: the prediction was replaced (st_edit_cache_set_pred) */
    uint32_t nent, capent;
};

st_edit_cache *st_edit_cache_new(void)
{
    st_edit_cache *c = calloc(1, sizeof *c);
    if (!c) abort();
    return c;
}

void st_edit_cache_clear(st_edit_cache *c)
{
    if (!c) return;
    for (uint32_t i = 0; i < c->nent; i++) c->at[c->vid[i]] = 0;
    c->nent = 0;
}

void st_edit_cache_free(st_edit_cache *c)
{
    if (!c) return;
    free(c->at);
    free(c->pf);
    free(c->vid);
    free(c->fixed);
    free(c);
}

static double *cache_find(st_edit_cache *c, unsigned l, uint32_t v)
{
    if (!c || !c->nent || c->level != l || v >= c->cap || !c->at[v]) return NULL;
    return c->pf[c->at[v] - 1];
}

static void cache_put(st_edit_cache *c, unsigned l, uint32_t v, const double pred[3], const double f[3][3])
{
    if (!c) return;
    if (c->level != l) { st_edit_cache_clear(c); c->level = l; }
    if (v >= c->cap) {
        uint32_t cap = c->cap ? 2 * c->cap : 4096;
        if (cap <= v) cap = v + 1;
        uint32_t *p = realloc(c->at, (size_t)cap * sizeof *p);
        if (!p) abort();
        memset(p + c->cap, 0, (size_t)(cap - c->cap) * sizeof *p);
        c->at = p;
        c->cap = cap;
    }
    if (c->nent == c->capent) {
        c->capent = c->capent ? 2 * c->capent : 4096;
        double(*p)[12] = realloc(c->pf, (size_t)c->capent * sizeof *p);
        uint32_t *q = realloc(c->vid, (size_t)c->capent * sizeof *q);
        uint8_t *f = realloc(c->fixed, (size_t)c->capent * sizeof *f);
        if (!p || !q || !f) abort();
        c->pf = p;
        c->vid = q;
        c->fixed = f;
    }
    c->fixed[c->nent] = 0;
    c->vid[c->nent] = v;
    memcpy(c->pf[c->nent], pred, 3 * sizeof(double));
    memcpy(c->pf[c->nent] + 3, f, 9 * sizeof(double));
    c->at[v] = ++c->nent;
}

int st_edit_cache_pred_fixed(const st_edit_cache *c, unsigned l, uint32_t v)
{
    if (!c || !c->nent || c->level != l || v >= c->cap || !c->at[v]) return 0;
    return c->fixed[c->at[v] - 1];
}

void st_edit_cache_set_pred(st_edit_cache *c, unsigned l, uint32_t v, const double pred[3])
{
    double *e = cache_find(c, l, v);
    if (!e) return;
    memcpy(e, pred, 3 * sizeof *e);
    c->fixed[c->at[v] - 1] = 1;
}

/* S(P_{l-1})(v) and the frame of v's stencil, found from dart d of v. */
static int predict_vertex(st_hier *h, unsigned l, uint32_t d, uint32_t v, double pred[3], double f[3][3])
{
    st_map *m = &h->map;
    if (h->scheme->predict_vertex) {
        st_subdiv_view sv = st_hier_view(h);
        if (h->scheme->predict_vertex(&sv, l, v, pred, f)) return 1;
    }
    uint32_t seed = real_seed(m, coarse_seed(m, d, l), l - 1);
    if (seed == ST_NIL) return 0;
    /* The seed's face first, alone: v is one of its children, and a region
     * lists the seed's face first, so the stencil found is the one the
     * ring below would give first, at a ninth of the cost; the ring of
     * faces around the seed when a scheme puts v elsewhere. */
    find_ctx c = { .v = v };
    if (!st_is_boundary(m, seed)) st_hier_emit(h, l, &seed, 1, find_sink, &c);
    if (!c.found) {
        st_dart_list faces = { 0 };
        st_region_faces(m, l - 1, &seed, 1, 1, &faces);
        st_hier_emit(h, l, faces.d, faces.n, find_sink, &c);
        st_dart_list_free(&faces);
    }
    if (c.found) {
        st_stencil s = { v, c.buf.n, c.buf.src, c.buf.w, c.frame_dart, c.frame_cell };
        st_stencil_eval(&h->map, l, &s, pred);
        st_hier_frame(h, l - 1, s.frame_dart, s.frame_cell, f);
    }
    st_stencil_buf_free(&c.buf);
    return c.found;
}

/* Re-expresses the detail of the vertex of d at level l >= 1 so that its
 * position is P_l(v): D = F^T (P_l - S(P_{l-1})).  With a hook (edit.h:
 * st_hier_edit_with) the hook decides the detail and the position.  The
 * cache (may be NULL) keeps S(P_{l-1})(v) and the frame, which only depend
 * on level l-1. */
static void refresh_detail(st_hier *h, unsigned l, uint32_t d, st_detail_hook hook, void *hctx, st_edit_cache *cache)
{
    st_map *m = &h->map;
    if (hook) d = real_seed(m, min_in_orbit(m, d, l, m->face_embedded), l);
    uint32_t v = st_vert(m, d, l);
    double pred[3], f[3][3], r[3], dv[3];
    const double *pc = cache_find(cache, l, v);
    if (pc) {
        memcpy(pred, pc, sizeof pred);
        memcpy(f, pc + 3, sizeof f);
    } else {
        if (!predict_vertex(h, l, d, v, pred, f)) return;
        cache_put(cache, l, v, pred, (const double(*)[3])f);
    }
    st_sub3(st_pos(m, v, l), pred, r);
    for (int i = 0; i < 3; i++) dv[i] = st_dot3(f[i], r);
    if (hook) {
        double p[3];
        hook(hctx, l, v, dv, pred, (const double(*)[3])f, p);
        st_hier_write_pos(h, v, l, p);
    }
    st_hier_set_detail(h, l, v, dv);
}

/* Footprint query (st_hier_edit_footprint): the stamps and the seeds of
 * st_synth_sink, the write left out. */
static void dry_sink(void *ctx, const st_stencil *s)
{
    synth_ctx *c = ctx;
    if (c->stamp->v[s->fine] == c->gen) return;
    c->stamp->v[s->fine] = c->gen;
    c->count++;
    if (c->fp) st_footprint_add(c->fp, st_fp_key(c->L, ST_FP_POS, s->fine));
    uint32_t d = st_dart_on_cell(c->m, s->fine, s->frame_dart, c->L);
    if (d == ST_NIL) c->lost = 1;
    else st_dart_list_push(c->changed, d);
}

/* The levels above l after the vertices of `darts` changed at l, written
 * (write != 0) or only recorded in fp: one walk for the edit and for its
 * footprint query, so that both give the same set. */
/* Level L is recomputed on the faces of level L-1 whose children can see a
 * vertex that changed at L-1 (support_rings rings around it); the vertices
 * written at L seed level L+1.  Should a written vertex not be found on its
 * frame cell, the next level takes every dart of the region as seed, with
 * one more ring (the children of the region lie within it). */
typedef struct above_ctx {
    st_hier *h;
    int write;
    st_footprint *fp;
    unsigned extra;            /* more rings: a vertex was lost at the level below */
    uint64_t count;
    st_dart_list faces;
} above_ctx;

static int above_step(void *ctx, unsigned L, const st_dart_list *seeds, st_dart_list *next)
{
    above_ctx *a = ctx;
    st_hier *h = a->h;
    st_subdiv_view v = st_hier_view(h);
    synth_ctx c = st_hier_synth_ctx(h, L);
    c.gen = st_hier_stamp_begin(h);
    c.changed = next;
    c.fp = a->fp;
    if (!a->write) c.sink = dry_sink;
    if (a->write && h->scheme->predict_around && (!h->detail[L] || h->scheme->fast_paths_apply_details) && !a->extra &&
        h->scheme->predict_around(&v, L, seeds->d, seeds->n, &c)) {
        a->count += c.count;
        return 0;
    }
    a->faces.n = 0;
    st_region_faces(&h->map, L - 1, seeds->d, seeds->n, h->scheme->support_rings + a->extra, &a->faces);
    c.gen = st_hier_stamp_begin(h);
    h->scheme->emit(&v, L, a->faces.d, a->faces.n, c.sink, &c);
    a->count += c.count;
    a->extra = c.lost;
    if (c.lost) {
        next->n = 0;
        st_dart_list_push_faces(next, &h->map, L - 1, a->faces.d, a->faces.n);
    }
    return 0;
}

static uint64_t resynth_above(st_hier *h, unsigned l, const uint32_t *darts, uint32_t n, int write, st_footprint *fp)
{
    st_dart_list seeds = { 0 };
    for (uint32_t i = 0; i < n; i++) st_dart_list_push(&seeds, real_seed(&h->map, darts[i], l));
    above_ctx a = { .h = h, .write = write, .fp = fp };
    st_hier_levels_up(h, l, &seeds, above_step, &a);
    st_dart_list_free(&a.faces);
    return a.count;
}

/* The level-l values of an edit: positions, and details for l >= 1. */
static void edit_level_keys(const st_map *m, unsigned l, const uint32_t *darts, uint32_t n, st_footprint *fp)
{
    if (!fp) return;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = st_vert(m, darts[i], l);
        st_footprint_add(fp, st_fp_key(l, ST_FP_POS, v));
        if (l > 0) st_footprint_add(fp, st_fp_key(l, ST_FP_DETAIL, v));
    }
}

uint64_t st_hier_edit_with(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                           st_footprint *fp, st_detail_hook hook, void *hctx)
{
    return st_hier_edit_cached(h, l, darts, pos, n, fp, hook, hctx, NULL);
}

uint64_t st_hier_edit_level(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                            st_footprint *fp, st_detail_hook hook, void *hctx, st_edit_cache *cache)
{
    st_map *m = &h->map;
    if (pos)
        for (uint32_t i = 0; i < n; i++) st_hier_write_pos(h, st_vert(m, darts[i], l), l, pos[i]);
    if (l > 0)
        for (uint32_t i = 0; i < n; i++) refresh_detail(h, l, real_seed(m, darts[i], l), hook, hctx, cache);
    edit_level_keys(m, l, darts, n, fp);
    return l > 0 ? 2 * (uint64_t)n : n;
}

uint64_t st_hier_edit_cached(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                             st_footprint *fp, st_detail_hook hook, void *hctx, st_edit_cache *cache)
{
    st_hier_edit_level(h, l, darts, pos, n, fp, hook, hctx, cache);
    return resynth_above(h, l, darts, n, 1, fp);
}

uint64_t st_hier_edit(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n,
                      st_footprint *fp)
{
    return st_hier_edit_with(h, l, darts, pos, n, fp, NULL, NULL);
}

uint64_t st_hier_move(st_hier *h, unsigned l, const uint32_t *darts, const double (*pos)[3], uint32_t n)
{
    return st_hier_edit(h, l, darts, pos, n, NULL);
}

void st_hier_edit_footprint(st_hier *h, unsigned l, const uint32_t *darts, uint32_t n, st_footprint *fp)
{
    edit_level_keys(&h->map, l, darts, n, fp);
    resynth_above(h, l, darts, n, 0, fp);
}
