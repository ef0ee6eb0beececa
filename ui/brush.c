/* Brushes at the editing level (editor.h): grab, draw, smooth, flatten.
 *
 * Finding the vertices under a dab: a uniform grid (hashed cells) of the
 * editing level's vertex positions, built at stroke begin with the cell
 * size equal to the brush radius, so a dab visits the 2x2x2 (at most 3x3x3)
 * cells around it, never the whole level.  Positions change during the
 * stroke: every vertex a dab moves is re-inserted into the cell of its new
 * position right after the dab (doubly linked per-cell lists, O(1) per
 * move), so the grid is always exact.  A radius changed during the stroke
 * only widens the range of cells visited.
 *
 * Falloff (1 - (r/R)^2)^2.  Normals: area-weighted vertex normals of the
 * editing level (sum of the Newell normals of the faces around the vertex),
 * computed for the vertices under the dab only.  Per dab, with s the
 * strength and f the falloff:
 *   grab     the vertices under the first dab (and their weights f) are
 *            captured; every dab moves them by f * grab_delta;
 *   draw     along the vertex's own normal by s * f * R / 10 (invert: in);
 *   smooth   towards the average of the one-ring neighbours by s * f;
 *   flatten  towards the plane through the average position of the
 *            vertices under the dab, normal their average normal, by s * f.
 * X-mirror: the dab is repeated with centre, normal and delta mirrored
 * across x = 0; the displacements of both dabs are computed from the same
 * positions and added, so a symmetric mesh stays symmetric.
 */
#include "core/map/geometry.h"
#include "editor_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct st_brush_state {
    unsigned level;
    double cs;                 /* cell size */
    uint64_t *hkey;            /* cell hash: key -> first vertex */
    uint32_t *hhead, hcap, hn;
    uint32_t nv;               /* per-vertex arrays below have nv entries */
    uint32_t *next, *prev;     /* per-cell doubly linked lists */
    uint64_t *vcell;           /* cell key of each vertex, EMPTY when not in the grid */
    uint32_t *mark, gen;       /* dab membership */
    uint32_t *slot;            /* index in list when marked */
    uint32_t *list;            /* vertices moved by this dab */
    double (*disp)[3];
    uint32_t nlist, caplist;
    uint32_t *tmp;             /* query result */
    double *tmpw;
    uint32_t ntmp, captmp;
    /* grab */
    int grabbed;
    uint32_t *gv;
    double *gw;
    uint8_t *gk;               /* which dab (0 direct, 1 mirrored) */
    uint32_t ng, capg;
};

#define EMPTY_KEY UINT64_MAX
#define CELL_LIM (1 << 20)

double st_brush_falloff(double r, double radius)
{
    if (!(radius > 0) || r >= radius) return 0;
    double q = r / radius;
    double t = 1 - q * q;
    return t * t;
}

void ed_brush_state_free(struct st_brush_state *bs)
{
    if (!bs) return;
    free(bs->hkey);
    free(bs->hhead);
    free(bs->next);
    free(bs->prev);
    free(bs->vcell);
    free(bs->mark);
    free(bs->slot);
    free(bs->list);
    free(bs->disp);
    free(bs->tmp);
    free(bs->tmpw);
    free(bs->gv);
    free(bs->gw);
    free(bs->gk);
    free(bs);
}

static void *xrealloc(void *p, size_t n)
{
    void *q = realloc(p, n ? n : 1);
    if (!q) abort();
    return q;
}

/* ---- grid -------------------------------------------------------------------- */

static int64_t cell_coord(double x, double cs)
{
    double c = floor(x / cs);
    if (!(c > -CELL_LIM)) return -CELL_LIM; /* also NaN */
    if (c > CELL_LIM - 1) return CELL_LIM - 1;
    return (int64_t)c;
}

static uint64_t cell_key(int64_t ix, int64_t iy, int64_t iz)
{
    return (uint64_t)(ix + CELL_LIM) << 42 | (uint64_t)(iy + CELL_LIM) << 21 | (uint64_t)(iz + CELL_LIM);
}

static uint32_t hash_slot(uint64_t k, uint32_t cap)
{
    k ^= k >> 31;
    k *= 0x9e3779b97f4a7c15ull;
    k ^= k >> 29;
    return (uint32_t)k & (cap - 1);
}

static void grid_rehash(struct st_brush_state *bs, uint32_t cap)
{
    uint64_t *ok = bs->hkey;
    uint32_t *oh = bs->hhead, ocap = bs->hcap;
    bs->hkey = xrealloc(NULL, (size_t)cap * sizeof *bs->hkey);
    bs->hhead = xrealloc(NULL, (size_t)cap * sizeof *bs->hhead);
    for (uint32_t i = 0; i < cap; i++) bs->hkey[i] = EMPTY_KEY;
    bs->hcap = cap;
    for (uint32_t i = 0; i < ocap; i++) {
        if (ok[i] == EMPTY_KEY) continue;
        uint32_t h = hash_slot(ok[i], cap);
        while (bs->hkey[h] != EMPTY_KEY) h = (h + 1) & (cap - 1);
        bs->hkey[h] = ok[i];
        bs->hhead[h] = oh[i];
    }
    free(ok);
    free(oh);
}

/* Slot of a cell; created (empty list) when absent and create is set. */
static int64_t grid_cell(struct st_brush_state *bs, uint64_t key, int create)
{
    if (create && 2 * (bs->hn + 1) > bs->hcap) grid_rehash(bs, bs->hcap ? 2 * bs->hcap : 1024);
    if (!bs->hcap) return -1;
    uint32_t h = hash_slot(key, bs->hcap);
    while (bs->hkey[h] != EMPTY_KEY) {
        if (bs->hkey[h] == key) return h;
        h = (h + 1) & (bs->hcap - 1);
    }
    if (!create) return -1;
    bs->hkey[h] = key;
    bs->hhead[h] = ST_NIL;
    bs->hn++;
    return h;
}

static uint64_t pos_key(const struct st_brush_state *bs, const double *p)
{
    return cell_key(cell_coord(p[0], bs->cs), cell_coord(p[1], bs->cs), cell_coord(p[2], bs->cs));
}

static void grid_unlink(struct st_brush_state *bs, uint32_t v)
{
    if (bs->vcell[v] == EMPTY_KEY) return;
    int64_t h = grid_cell(bs, bs->vcell[v], 0);
    if (bs->prev[v] != ST_NIL) bs->next[bs->prev[v]] = bs->next[v];
    else if (h >= 0) bs->hhead[h] = bs->next[v];
    if (bs->next[v] != ST_NIL) bs->prev[bs->next[v]] = bs->prev[v];
    bs->vcell[v] = EMPTY_KEY;
}

static void grid_insert(struct st_brush_state *bs, uint32_t v, const double *p)
{
    uint64_t key = pos_key(bs, p);
    if (bs->vcell[v] == key) return;
    grid_unlink(bs, v);
    int64_t h = grid_cell(bs, key, 1);
    bs->prev[v] = ST_NIL;
    bs->next[v] = bs->hhead[h];
    if (bs->next[v] != ST_NIL) bs->prev[bs->next[v]] = v;
    bs->hhead[h] = (uint32_t)v;
    bs->vcell[v] = key;
}

static void tmp_push(struct st_brush_state *bs, uint32_t v, double w)
{
    if (bs->ntmp == bs->captmp) {
        bs->captmp = bs->captmp ? 2 * bs->captmp : 256;
        bs->tmp = xrealloc(bs->tmp, (size_t)bs->captmp * sizeof *bs->tmp);
        bs->tmpw = xrealloc(bs->tmpw, (size_t)bs->captmp * sizeof *bs->tmpw);
    }
    bs->tmp[bs->ntmp] = v;
    bs->tmpw[bs->ntmp++] = w;
}

static void visit_cell(struct st_brush_state *bs, const st_map *m, unsigned l, uint32_t head, const double c[3], double R)
{
    for (uint32_t v = head; v != ST_NIL; v = bs->next[v]) {
        const double *p = st_pos(m, v, l);
        double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
        double r = sqrt(dx * dx + dy * dy + dz * dz);
        double w = st_brush_falloff(r, R);
        if (w > 0) tmp_push(bs, v, w);
    }
}

/* Vertices strictly inside the sphere (c, R), with their falloff, into tmp. */
static void grid_query(struct st_brush_state *bs, const st_map *m, unsigned l, const double c[3], double R)
{
    bs->ntmp = 0;
    int64_t lo[3], hi[3];
    double cells = 1;
    for (int k = 0; k < 3; k++) {
        lo[k] = cell_coord(c[k] - R, bs->cs);
        hi[k] = cell_coord(c[k] + R, bs->cs);
        cells *= (double)(hi[k] - lo[k] + 1);
    }
    if (cells > 2.0 * bs->hn) {
        /* A radius far above the cell size: every occupied cell once. */
        for (uint32_t h = 0; h < bs->hcap; h++)
            if (bs->hkey[h] != EMPTY_KEY) visit_cell(bs, m, l, bs->hhead[h], c, R);
        return;
    }
    for (int64_t x = lo[0]; x <= hi[0]; x++)
        for (int64_t y = lo[1]; y <= hi[1]; y++)
            for (int64_t z = lo[2]; z <= hi[2]; z++) {
                int64_t h = grid_cell(bs, cell_key(x, y, z), 0);
                if (h >= 0) visit_cell(bs, m, l, bs->hhead[h], c, R);
            }
}

/* ---- local geometry --------------------------------------------------------------- */

/* Next dart around the vertex of x at level l: β1 in the primal encoding;
 * in the dual one (Doo-Sabin, map.h: a surface vertex is a map face) φ1. */
static uint32_t around(const st_map *m, uint32_t x, unsigned l)
{
    return m->face_embedded ? st_phi1(m, x, l) : st_beta1(m, x, l);
}

/* Next dart along the surface face of x: φ1, or β1 in the dual encoding. */
static uint32_t along(const st_map *m, uint32_t x, unsigned l)
{
    return m->face_embedded ? st_beta1(m, x, l) : st_phi1(m, x, l);
}

/* Area-weighted normal of the vertex of dart x0 at level l (not normalised):
 * the sum of the Newell normals of the surface faces around it. */
static void vertex_normal(const st_map *m, uint32_t x0, unsigned l, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    uint32_t x = x0;
    unsigned guard = 0;
    do {
        if (!st_is_boundary(m, x)) {
            uint32_t y = x;
            unsigned g2 = 0;
            do {
                uint32_t z = along(m, y, l);
                st_newell_add(n, st_dart_pos(m, y, l), st_dart_pos(m, z, l)); /* one running sum */
                y = z;
            } while (y != x && ++g2 < 1u << 16);
        }
        x = around(m, x, l);
    } while (x != x0 && ++guard < 1u << 16);
}

static int normalize3(double v[3])
{
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0)) return -1;
    v[0] /= len; v[1] /= len; v[2] /= len;
    return 0;
}

/* ---- dab accumulation ----------------------------------------------------------------- */

static void acc(struct st_brush_state *bs, uint32_t v, const double dv[3])
{
    if (bs->mark[v] != bs->gen) {
        bs->mark[v] = bs->gen;
        if (bs->nlist == bs->caplist) {
            bs->caplist = bs->caplist ? 2 * bs->caplist : 256;
            bs->list = xrealloc(bs->list, (size_t)bs->caplist * sizeof *bs->list);
            bs->disp = xrealloc(bs->disp, (size_t)bs->caplist * sizeof *bs->disp);
        }
        bs->slot[v] = bs->nlist;
        bs->list[bs->nlist] = v;
        bs->disp[bs->nlist][0] = bs->disp[bs->nlist][1] = bs->disp[bs->nlist][2] = 0;
        bs->nlist++;
    }
    double *t = bs->disp[bs->slot[v]];
    t[0] += dv[0]; t[1] += dv[1]; t[2] += dv[2];
}

/* One dab's displacements (tools other than grab), from the current
 * positions, added into the accumulator. */
static void dab_displace(st_doc *d, struct st_brush_state *bs, const double c[3], const double nrm[3])
{
    const st_map *m = &d->h.map;
    unsigned l = bs->level;
    double R = d->brush.radius, s = d->brush.strength;
    if (s < 0) s = 0;
    if (s > 1) s = 1;
    grid_query(bs, m, l, c, R);
    if (!bs->ntmp) return;
    double dn[3] = { nrm ? nrm[0] : 0, nrm ? nrm[1] : 0, nrm ? nrm[2] : 1 };
    if (normalize3(dn)) { dn[0] = 0; dn[1] = 0; dn[2] = 1; }
    int tool = d->brush.tool;
    double c0[3] = { 0, 0, 0 }, pn[3] = { 0, 0, 0 };
    if (tool == ST_BRUSH_FLATTEN) {
        for (uint32_t i = 0; i < bs->ntmp; i++) {
            const double *p = st_pos(m, bs->tmp[i], l);
            double vn[3] = { 0, 0, 0 };
            uint32_t x0 = ed_vertex_dart(d, bs->tmp[i]);
            if (x0 != ST_NIL) vertex_normal(m, x0, l, vn);
            for (int k = 0; k < 3; k++) { c0[k] += p[k] / bs->ntmp; pn[k] += vn[k]; }
        }
        if (normalize3(pn)) memcpy(pn, dn, sizeof pn);
    }
    for (uint32_t i = 0; i < bs->ntmp; i++) {
        uint32_t v = bs->tmp[i];
        double f = bs->tmpw[i], dv[3] = { 0, 0, 0 };
        const double *p = st_pos(m, v, l);
        uint32_t x0 = ed_vertex_dart(d, v);
        if (x0 == ST_NIL) continue;
        if (tool == ST_BRUSH_DRAW) {
            double vn[3];
            vertex_normal(m, x0, l, vn);
            if (normalize3(vn)) memcpy(vn, dn, sizeof vn);
            double a = (d->brush.invert ? -1 : 1) * s * f * R * 0.1;
            for (int k = 0; k < 3; k++) dv[k] = a * vn[k];
        } else if (tool == ST_BRUSH_SMOOTH) {
            double avg[3] = { 0, 0, 0 };
            unsigned cnt = 0;
            uint32_t x = x0;
            do {
                const double *q = st_dart_pos(m, st_beta0(m, x, l), l);
                for (int k = 0; k < 3; k++) avg[k] += q[k];
                cnt++;
                x = around(m, x, l);
            } while (x != x0 && cnt < 1u << 16);
            for (int k = 0; k < 3; k++) dv[k] = s * f * (avg[k] / cnt - p[k]);
        } else if (tool == ST_BRUSH_FLATTEN) {
            double h = (p[0] - c0[0]) * pn[0] + (p[1] - c0[1]) * pn[1] + (p[2] - c0[2]) * pn[2];
            for (int k = 0; k < 3; k++) dv[k] = -s * f * h * pn[k];
        }
        acc(bs, v, dv);
    }
}

/* ---- strokes -------------------------------------------------------------------------- */

int st_doc_stroke_begin(st_doc *d)
{
    if (!d->loaded) return -1;
    if (d->active == 1) st_doc_drag_end(d);
    else if (d->active == 2) st_doc_stroke_end(d);
    if (!(d->brush.radius > 0) || d->brush.tool < 0 || d->brush.tool >= ST_BRUSH_COUNT) return -1;
    struct st_brush_state *bs = d->bs;
    if (!bs) {
        bs = calloc(1, sizeof *bs);
        if (!bs) abort();
        d->bs = bs;
    }
    const st_map *m = &d->h.map;
    unsigned l = d->edit_level;
    bs->level = l;
    bs->cs = d->brush.radius;
    /* Per-vertex arrays up to the largest id of the editing level only. */
    uint32_t nv = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        if (v + 1 > nv) nv = v + 1;
    if (bs->nv < nv) {
        bs->next = xrealloc(bs->next, (size_t)nv * sizeof *bs->next);
        bs->prev = xrealloc(bs->prev, (size_t)nv * sizeof *bs->prev);
        bs->vcell = xrealloc(bs->vcell, (size_t)nv * sizeof *bs->vcell);
        bs->mark = xrealloc(bs->mark, (size_t)nv * sizeof *bs->mark);
        bs->slot = xrealloc(bs->slot, (size_t)nv * sizeof *bs->slot);
        bs->nv = nv;
    }
    for (uint32_t v = 0; v < bs->nv; v++) { bs->vcell[v] = EMPTY_KEY; bs->mark[v] = 0; }
    bs->gen = 0;
    for (uint32_t i = 0; i < bs->hcap; i++) bs->hkey[i] = EMPTY_KEY;
    bs->hn = 0;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        grid_insert(bs, v, st_pos(m, v, l));
    bs->grabbed = 0;
    bs->ng = 0;
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->level = l;
    d->pending = s;
    d->active = 2;
    return 0;
}

static void grab_capture(st_doc *d, struct st_brush_state *bs, const double c[3], uint8_t which)
{
    grid_query(bs, &d->h.map, bs->level, c, d->brush.radius);
    for (uint32_t i = 0; i < bs->ntmp; i++) {
        if (bs->ng == bs->capg) {
            bs->capg = bs->capg ? 2 * bs->capg : 256;
            bs->gv = xrealloc(bs->gv, (size_t)bs->capg * sizeof *bs->gv);
            bs->gw = xrealloc(bs->gw, (size_t)bs->capg * sizeof *bs->gw);
            bs->gk = xrealloc(bs->gk, (size_t)bs->capg * sizeof *bs->gk);
        }
        bs->gv[bs->ng] = bs->tmp[i];
        bs->gw[bs->ng] = bs->tmpw[i];
        bs->gk[bs->ng++] = which;
    }
}

int st_doc_stroke_dab(st_doc *d, const double center[3], const double normal[3], const double grab_delta[3])
{
    if (d->active != 2 || !d->pending || !d->bs) return -1;
    struct st_brush_state *bs = d->bs;
    if (!(d->brush.radius > 0)) return -1;
    double t0 = ed_now_ms();
    st_hier *h = &d->h;
    unsigned l = bs->level;
    int mirror = d->brush.mirror_x != 0;
    double mc[3] = { -center[0], center[1], center[2] };
    double nn[3] = { 0, 0, 1 }, mn[3];
    if (normal) memcpy(nn, normal, sizeof nn);
    mn[0] = -nn[0]; mn[1] = nn[1]; mn[2] = nn[2];
    if (++bs->gen == 0) {
        for (uint32_t v = 0; v < bs->nv; v++) bs->mark[v] = 0;
        bs->gen = 1;
    }
    bs->nlist = 0;
    if (d->brush.tool == ST_BRUSH_GRAB) {
        if (!bs->grabbed) {
            grab_capture(d, bs, center, 0);
            if (mirror) grab_capture(d, bs, mc, 1);
            bs->grabbed = 1;
        }
        double g[3] = { 0, 0, 0 };
        if (grab_delta) memcpy(g, grab_delta, sizeof g);
        double mg[3] = { -g[0], g[1], g[2] };
        for (uint32_t i = 0; i < bs->ng; i++) {
            const double *dd = bs->gk[i] ? mg : g;
            double dv[3] = { bs->gw[i] * dd[0], bs->gw[i] * dd[1], bs->gw[i] * dd[2] };
            acc(bs, bs->gv[i], dv);
        }
    } else {
        dab_displace(d, bs, center, nn);
        if (mirror) dab_displace(d, bs, mc, mn);
    }
    if (!bs->nlist) return 0;
    uint32_t *darts = xrealloc(NULL, (size_t)bs->nlist * sizeof *darts);
    double(*pos)[3] = xrealloc(NULL, (size_t)bs->nlist * sizeof *pos);
    uint32_t n = 0;
    for (uint32_t i = 0; i < bs->nlist; i++) {
        uint32_t v = bs->list[i], x = ed_vertex_dart(d, v);
        /* The mask attenuates the dab: displacement times 1 - mask; a fully
         * masked vertex is left out, so it stays the same to the bit. */
        double keep = 1.0 - (double)st_mask_get(&d->mask, v);
        if (x == ST_NIL || !(keep > 0)) continue;
        const double *p = st_pos(&h->map, v, l);
        for (int k = 0; k < 3; k++) pos[n][k] = p[k] + keep * bs->disp[i][k];
        darts[n++] = x;
    }
    /* Old values of what core will write (also the layers'), then the
     * edit, which reports what it wrote for the display and the renderer. */
    uint32_t from = d->fp_model.n;
    ed_model_edit(d, d->pending, l, darts, (const double(*)[3])pos, n);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = st_vert(&h->map, darts[i], l);
        grid_insert(bs, v, st_pos(&h->map, v, l));
    }
    ed_geometry_changed(d, l, darts, n, t0, from);
    free(darts);
    free(pos);
    return 0;
}

uint32_t ed_brush_query(st_doc *d, const double c[3], double R, const uint32_t **vids, const double **w)
{
    struct st_brush_state *bs = d->bs;
    if (!bs || !d->active) return 0;
    grid_query(bs, &d->h.map, bs->level, c, R);
    *vids = bs->tmp;
    *w = bs->tmpw;
    return bs->ntmp;
}

void st_doc_stroke_end(st_doc *d)
{
    st_undo_step *s = ed_take_pending(d, 2);
    if (s) ed_push_edit(d, s);
}
