/* Sculpting kernels (core/sculpt/sculpt.h): the spatial grid, the
 * per-vertex weight, ring normals, symmetry, the dab's reach at coarse
 * levels and the dab itself; what each tool does under a dab is in
 * sculpt_tools.c, the layer's heights, auto-smooth and the hold in
 * sculpt_hold.c.  Around the tools, so that full strength holds (issue 30,
 * tests/ui/test_editor_brush_hold.c): the dab's reach at coarse levels
 * (st_sculpt_dab_radius), the stroke's fade (a factor given with each dab
 * by the document, ui/doc/brush.c), the spacing attenuation
 * (st_brush_overlap_scale), auto-smooth and the hold (sc_hold_faces).
 *
 * Finding the vertices under a dab: a uniform grid (hashed cells) of the
 * level's vertex positions, built at stroke begin with the cell size equal
 * to the stroke's radius, so a dab visits the 2x2x2 (at most 3x3x3) cells
 * around it, never the whole level.  Positions change during the stroke:
 * every vertex a dab moves is re-inserted into the cell of its new
 * position right after the dab (st_sculpt_moved; doubly linked per-cell
 * lists, O(1) per move), so the grid is always exact.  A radius changed
 * during the stroke only widens the range of cells visited.  A dab's cost
 * is thus that of the vertices under it (and their one-rings for normals).
 *
 * Weight of a vertex under a dab (sc_weight, the one place): the falloff
 * preset at its distance, times the strength, times the front-face test:
 * with front_only and a view direction known (st_sculpt_dab.view), a
 * vertex whose area-weighted normal does not face the viewer (dot with the
 * view direction >= 0) is on the far side of a thin part or of the model
 * and is left alone, as Blender's "front faces only" does; times the
 * stroke's fade.  Mirrored dabs reflect the view direction with the dab.
 *
 * Symmetry: with mirror_x / _y / _z the dab is repeated with centre, normal
 * and grab delta reflected across every combination of the enabled planes
 * of object space (up to 8 dabs).  The displacements of all of them are
 * computed from the same positions and added, and only then applied, so a
 * mesh symmetric about those planes stays symmetric (to the rounding of the
 * additions).
 */
#include "core/sculpt/sculpt_internal.h"
#include "core/multires/edit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EMPTY_KEY UINT64_MAX
#define CELL_LIM (1 << 20)

/* ---- falloff ---------------------------------------------------------------------- */

double st_falloff_eval(int kind, double r, double radius)
{
    if (!(radius > 0) || !(r < radius)) return 0;
    double q = r > 0 ? r / radius : 0, t = 1 - q;
    switch (kind) {
    case ST_FALLOFF_SPHERE: return sqrt(2 * t - t * t);
    case ST_FALLOFF_ROOT: return sqrt(t);
    case ST_FALLOFF_SHARP: return t * t;
    case ST_FALLOFF_LINEAR: return t;
    case ST_FALLOFF_CONSTANT: return 1;
    default: {
        double u = 1 - q * q;
        return u * u;
    }
    }
}

static const char *const falloff_names[ST_FALLOFF_COUNT] = { "smooth", "sphere", "root", "sharp", "linear", "constant" };

const char *st_falloff_name(int falloff)
{
    return falloff >= 0 && falloff < ST_FALLOFF_COUNT ? falloff_names[falloff] : "?";
}

int st_falloff_by_name(const char *name)
{
    for (int k = 0; k < ST_FALLOFF_COUNT; k++)
        if (name && !strcmp(name, falloff_names[k])) return k;
    return -1;
}

/* Blender's integrate_overlap (paint_stroke / sculpt.c): the largest sum,
 * over a point of the path, of the falloffs of the dabs `spacing` radii
 * apart that cover it. */
double st_brush_overlap_scale(int falloff, double spacing)
{
    if (!(spacing > 0)) return 1;
    if (spacing < 0.01) spacing = 0.01;
    double most = 0;
    for (int i = 0; i < 10; i++) {
        double x = spacing * i / 10, sum = 0;
        for (double p = x - floor((x + 1) / spacing) * spacing; p < 1; p += spacing) sum += st_falloff_eval(falloff, fabs(p), 1);
        if (sum > most) most = sum;
    }
    return most > 1 ? 1 / most : 1;
}

st_sculpt *st_sculpt_new(void)
{
    return calloc(1, sizeof(st_sculpt));
}

void st_sculpt_free(st_sculpt *bs)
{
    if (!bs) return;
    free(bs->hkey);
    free(bs->hhead);
    free(bs->next);
    free(bs->prev);
    free(bs->vcell);
    free(bs->mark);
    free(bs->slot);
    free(bs->lay_o);
    free(bs->lay_n0);
    free(bs->held);
    free(bs->heldr);
    free(bs->list);
    free(bs->disp);
    free(bs->lay_t);
    free(bs->tmp);
    free(bs->tmpw);
    free(bs->tmpn);
    free(bs->gv);
    free(bs->gw);
    free(bs->gk);
    free(bs->ring_at);
    free(bs->ring);
    free(bs->accw);
    free(bs->disp2);
    free(bs->tmpa);
    free(bs->fn);
    free(bs->own_vdart);
    free(bs->odarts);
    free(bs->opos);
    free(bs);
}

void *sc_xrealloc(void *p, size_t n)
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

static void grid_rehash(st_sculpt *bs, uint32_t cap)
{
    uint64_t *ok = bs->hkey;
    uint32_t *oh = bs->hhead, ocap = bs->hcap;
    bs->hkey = sc_xrealloc(NULL, (size_t)cap * sizeof *bs->hkey);
    bs->hhead = sc_xrealloc(NULL, (size_t)cap * sizeof *bs->hhead);
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
static int64_t grid_cell(st_sculpt *bs, uint64_t key, int create)
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

static uint64_t pos_key(const st_sculpt *bs, const double *p)
{
    return cell_key(cell_coord(p[0], bs->cs), cell_coord(p[1], bs->cs), cell_coord(p[2], bs->cs));
}

static void grid_unlink(st_sculpt *bs, uint32_t v)
{
    if (bs->vcell[v] == EMPTY_KEY) return;
    int64_t h = grid_cell(bs, bs->vcell[v], 0);
    if (bs->prev[v] != ST_NIL) bs->next[bs->prev[v]] = bs->next[v];
    else if (h >= 0) bs->hhead[h] = bs->next[v];
    if (bs->next[v] != ST_NIL) bs->prev[bs->next[v]] = bs->prev[v];
    bs->vcell[v] = EMPTY_KEY;
}

static void grid_insert(st_sculpt *bs, uint32_t v, const double *p)
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

static void tmp_push(st_sculpt *bs, uint32_t v, double w, const double n[3], double area)
{
    if (bs->ntmp == bs->captmp) {
        bs->captmp = bs->captmp ? 2 * bs->captmp : 256;
        bs->tmp = sc_xrealloc(bs->tmp, (size_t)bs->captmp * sizeof *bs->tmp);
        bs->tmpw = sc_xrealloc(bs->tmpw, (size_t)bs->captmp * sizeof *bs->tmpw);
        bs->tmpn = sc_xrealloc(bs->tmpn, (size_t)bs->captmp * sizeof *bs->tmpn);
        bs->tmpa = sc_xrealloc(bs->tmpa, (size_t)bs->captmp * sizeof *bs->tmpa);
    }
    bs->tmp[bs->ntmp] = v;
    bs->tmpw[bs->ntmp] = w;
    bs->tmpa[bs->ntmp] = area;
    memcpy(bs->tmpn[bs->ntmp++], n, sizeof bs->tmpn[0]);
}

/* ---- local geometry --------------------------------------------------------------- */


/* The faces around the vertex v of dart x0, as its normal walks them:
 * around the vertex (β1; φ1 in the dual encoding, map.h), and along each
 * surface face from the dart at the vertex (φ1; β1 in the dual), the
 * corners' vertex ids recorded in bs->ring as [faces, index of the first
 * face's normal in bs->fn, then per face: terms c, the c + 1 ids of the
 * walk p0 .. pc (pc the start again)], and each face's Newell normal as it
 * is then in bs->fn (the reference hold_faces keeps faces near).  Recorded
 * the first time a dab of the stroke needs v's normal: the topology does
 * not change during a stroke, so later dabs read ids and positions only
 * instead of walking the darts again (the walk was a quarter of a dab).
 * Returns the record's offset. */
static void ring_push(st_sculpt *bs, uint32_t x)
{
    if (bs->nring == bs->capring) {
        bs->capring = bs->capring ? 2 * bs->capring : 4096;
        bs->ring = sc_xrealloc(bs->ring, (size_t)bs->capring * sizeof *bs->ring);
    }
    bs->ring[bs->nring++] = x;
}

/* The Newell normal of the face record r (terms c, then c + 1 ids) now,
 * with each vertex moved by its displacement in this dab when `moved`. */
void sc_face_normal(const st_sculpt *bs, const st_level_view *lv, const uint32_t *r, int moved,
                        double n[3])
{
    uint32_t c = r[0];
    double n0 = 0, n1 = 0, n2 = 0, p[3] = { 0, 0, 0 }, q[3]; /* p: the previous corner, set at t = 0 */
    const uint32_t *id = r + 1;
    for (uint32_t t = 0; t <= c; t++) {
        const double *a = st_v_pos(lv, id[t]);
        int in = moved && bs->mark[id[t]] == bs->gen;
        for (int k = 0; k < 3; k++) q[k] = a[k] + (in ? bs->disp[bs->slot[id[t]]][k] : 0);
        if (t) {
            n0 += (p[1] - q[1]) * (p[2] + q[2]);
            n1 += (p[2] - q[2]) * (p[0] + q[0]);
            n2 += (p[0] - q[0]) * (p[1] + q[1]);
        }
        memcpy(p, q, sizeof p);
    }
    n[0] = n0; n[1] = n1; n[2] = n2;
}

static void fn_push(st_sculpt *bs, const st_level_view *lv, const uint32_t *r)
{
    if (bs->nfn == bs->capfn) {
        bs->capfn = bs->capfn ? 2 * bs->capfn : 4096;
        bs->fn = sc_xrealloc(bs->fn, (size_t)bs->capfn * sizeof *bs->fn);
    }
    sc_face_normal(bs, lv, r, 0, bs->fn[bs->nfn++]);
}

static uint32_t ring_of(st_sculpt *bs, const st_map *m, const st_level_view *lv, uint32_t v, uint32_t x0)
{
    if (bs->ring_at[v]) return bs->ring_at[v] - 1;
    int dual = m->face_embedded;
    uint32_t o = bs->nring;
    ring_push(bs, 0);
    ring_push(bs, bs->nfn);
    uint32_t x = x0;
    unsigned guard = 0;
    do {
        if (!st_is_boundary(m, x)) {
            uint32_t at = bs->nring;
            ring_push(bs, 0);
            ring_push(bs, st_v_vert(lv, x));
            uint32_t y = x;
            unsigned g2 = 0;
            do {
                uint32_t z = st_v_face_step(lv, dual, y);
                ring_push(bs, st_v_vert(lv, z));
                bs->ring[at]++;
                y = z;
            } while (y != x && ++g2 < 1u << 16);
            bs->ring[o]++;
            fn_push(bs, lv, bs->ring + at);
        }
        x = st_v_vertex_step(lv, dual, x);
    } while (x != x0 && ++guard < 1u << 16);
    bs->ring_at[v] = o + 1;
    return o;
}

/* Area-weighted normal of a vertex (not normalised) from its ring record:
 * the sum of the Newell normals of the surface faces around it, one
 * running sum (st_newell_add's terms) in the order of the walk. */
static void ring_normal(const st_sculpt *bs, const st_level_view *lv, uint32_t o, double n[3])
{
    const uint32_t *r = bs->ring + o;
    uint32_t nf = *r++;
    r++; /* the faces' normals */
    /* The sum in locals: stores through n would not be hoisted. */
    double n0 = 0, n1 = 0, n2 = 0;
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t c = *r++;
        const double *p = st_v_pos(lv, r[0]);
        for (uint32_t t = 1; t <= c; t++) {
            const double *q = st_v_pos(lv, r[t]);
            n0 += (p[1] - q[1]) * (p[2] + q[2]);
            n1 += (p[2] - q[2]) * (p[0] + q[0]);
            n2 += (p[0] - q[0]) * (p[1] + q[1]);
            p = q;
        }
        r += c + 1;
    }
    n[0] = n0;
    n[1] = n1;
    n[2] = n2;
}

static int normalize3(double v[3])
{
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0)) return -1;
    v[0] /= len; v[1] /= len; v[2] /= len;
    return 0;
}

/* Unit normal of vertex v (dart x0) now; `fallback` when it vanishes.
 * Returns the length of the area-weighted normal (twice the area around v). */
static double unit_normal(st_sculpt *bs, const st_map *m, const st_level_view *lv, uint32_t v, uint32_t x0,
                          const double fallback[3], double n[3])
{
    ring_normal(bs, lv, ring_of(bs, m, lv, v, x0), n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (normalize3(n)) memcpy(n, fallback, 3 * sizeof *n);
    return len;
}

/* ---- the weight of a vertex under a dab ------------------------------------------------ */

double sc_weight(const st_sculpt *bs, const st_sculpt_brush *b, double r, const double vn[3], const double view[3])
{
    /* The mask is not read here but where the dab's summed displacement is
     * applied (st_sculpt_dab_run), so that it scales every mirrored dab
     * together and a vertex masked 1 is left out to the bit. */
    double f = st_falloff_eval(b->falloff, r, bs->R);
    if (!(f > 0)) return 0;
    int known = view[0] != 0 || view[1] != 0 || view[2] != 0;
    if (b->front_only && known && !(vn[0] * view[0] + vn[1] * view[1] + vn[2] * view[2] < 0)) return 0;
    double s = b->strength;
    if (!(s > 0)) return 0;
    if (s > 1) s = 1;
    return f * s * bs->fadek;
}

static void visit_cell(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const st_level_view *lv,
                       uint32_t head, const double c[3], const double dn[3], const double view[3])
{
    double R = bs->R;
    for (uint32_t v = head; v != ST_NIL; v = bs->next[v]) {
        const double *p = st_v_pos(lv, v);
        double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
        double r = sqrt(dx * dx + dy * dy + dz * dz);
        if (!(r < R)) continue;
        uint32_t x0 = sc_vertex_dart(bs, v);
        if (x0 == ST_NIL) continue;
        double vn[3], area = unit_normal(bs, m, lv, v, x0, dn, vn);
        double w = sc_weight(bs, b, r, vn, view);
        if (w > 0) tmp_push(bs, v, w, vn, area);
    }
}

/* Vertices strictly inside the sphere (c, R) with a positive weight, with
 * their weights and unit normals, into tmp. */
static void grid_query(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const double c[3], const double dn[3],
                       const double view[3])
{
    double R = bs->R;
    bs->ntmp = 0;
    st_level_view lv;
    st_level_view_init(m, bs->level, &lv);
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
            if (bs->hkey[h] != EMPTY_KEY) visit_cell(bs, m, b, &lv, bs->hhead[h], c, dn, view);
        return;
    }
    for (int64_t x = lo[0]; x <= hi[0]; x++)
        for (int64_t y = lo[1]; y <= hi[1]; y++)
            for (int64_t z = lo[2]; z <= hi[2]; z++) {
                int64_t h = grid_cell(bs, cell_key(x, y, z), 0);
                if (h >= 0) visit_cell(bs, m, b, &lv, bs->hhead[h], c, dn, view);
            }
}

/* ---- dab accumulation ----------------------------------------------------------------- */

/* The accumulator slot of v in this dab (created zero). */
static uint32_t acc_slot(st_sculpt *bs, uint32_t v)
{
    if (bs->mark[v] != bs->gen) {
        bs->mark[v] = bs->gen;
        if (bs->nlist == bs->caplist) {
            bs->caplist = bs->caplist ? 2 * bs->caplist : 256;
            bs->list = sc_xrealloc(bs->list, (size_t)bs->caplist * sizeof *bs->list);
            bs->disp = sc_xrealloc(bs->disp, (size_t)bs->caplist * sizeof *bs->disp);
            bs->lay_t = sc_xrealloc(bs->lay_t, (size_t)bs->caplist * sizeof *bs->lay_t);
            bs->accw = sc_xrealloc(bs->accw, (size_t)bs->caplist * sizeof *bs->accw);
            bs->disp2 = sc_xrealloc(bs->disp2, (size_t)bs->caplist * sizeof *bs->disp2);
        }
        uint32_t i = bs->nlist++;
        bs->slot[v] = i;
        bs->list[i] = v;
        bs->disp[i][0] = bs->disp[i][1] = bs->disp[i][2] = 0;
        bs->lay_t[i] = 0;
        bs->accw[i] = 0;
    }
    return bs->slot[v];
}

void sc_acc_weight(st_sculpt *bs, uint32_t v, double w)
{
    uint32_t i = acc_slot(bs, v);
    if (w > bs->accw[i]) bs->accw[i] = w;
}

void sc_acc(st_sculpt *bs, uint32_t v, const double dv[3])
{
    uint32_t i = acc_slot(bs, v); /* before reading bs->disp, which it may move */
    double *t = bs->disp[i];
    t[0] += dv[0]; t[1] += dv[1]; t[2] += dv[2];
}

void sc_acc_layer(st_sculpt *bs, uint32_t v, double h, const double n[3])
{
    uint32_t i = acc_slot(bs, v);
    if (h > bs->lay_t[i]) bs->lay_t[i] = h;
    if (bs->lay_o[v] < 0) {
        bs->lay_o[v] = 0;
        memcpy(bs->lay_n0[v], n, sizeof bs->lay_n0[v]);
    }
}

/* v reflected across the planes of the set bits of `which` (1 x, 2 y, 4 z). */
void sc_reflect(uint8_t which, const double v[3], double out[3])
{
    for (int k = 0; k < 3; k++) out[k] = which >> k & 1 ? -v[k] : v[k];
}

/* The mirrored dabs of the brush's symmetry: every subset of the enabled
 * planes (0 is the dab itself); returns how many. */
unsigned sc_symmetry_set(const st_sculpt_brush *b, uint8_t which[8])
{
    unsigned mask = (b->mirror_x ? 1u : 0) | (b->mirror_y ? 2u : 0) | (b->mirror_z ? 4u : 0), n = 0;
    for (unsigned s = 0; s < 8; s++)
        if (!(s & ~mask)) which[n++] = (uint8_t)s;
    return n;
}

/* ---- reach at coarse levels ---------------------------------------------------------- */

/* Mean length of the edges of level l (each edge once: the dart of the
 * smaller id of its two, β0 the opposite dart).  In the dual encoding
 * (Doo-Sabin) the darts join face centres, a length of the same order. */
double st_sculpt_edge_mean(const st_map *m, unsigned l)
{
    double sum = 0;
    uint64_t n = 0;
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, l, &it); x != ST_NIL; x = st_dart_next(m, l, &it)) {
        uint32_t y = st_beta0(m, x, l);
        if (y < x) continue;
        const double *p = st_dart_pos(m, x, l), *q = st_dart_pos(m, y, l);
        double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        sum += sqrt(dx * dx + dy * dy + dz * dz);
        n++;
    }
    return n ? sum / (double)n : 0;
}

double st_sculpt_reach(const st_sculpt_brush *b, double edge_mean)
{
    double R = b->radius;
    if (!(b->reach_edges > 0)) return R;
    double e = b->reach_edges * edge_mean;
    return e > R ? e : R;
}

uint32_t *st_sculpt_vertex_darts(const st_map *m, unsigned l, uint32_t *nv)
{
    st_dart_iter it;
    *nv = 0;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        if (v + 1 > *nv) *nv = v + 1;
    uint32_t *vd = malloc((size_t)(*nv ? *nv : 1) * sizeof *vd);
    if (!vd) return NULL;
    for (uint32_t v = 0; v < *nv; v++) vd[v] = ST_NIL;
    for (uint32_t x = st_dart_first(m, l, &it); x != ST_NIL; x = st_dart_next(m, l, &it)) {
        uint32_t v = st_vert(m, x, l), cur = vd[v];
        if (cur == ST_NIL || (st_is_boundary(m, cur) && !st_is_boundary(m, x))) vd[v] = x;
    }
    return vd;
}

/* Mean length of the edges at vertex v (dart x0) of level l. */
static double vertex_edge_mean(const st_map *m, uint32_t x0, unsigned l)
{
    const double *p = st_dart_pos(m, x0, l);
    double sum = 0;
    unsigned cnt = 0;
    uint32_t x = x0;
    do {
        const double *q = st_dart_pos(m, st_beta0(m, x, l), l);
        double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        sum += sqrt(dx * dx + dy * dy + dz * dz);
        cnt++;
        x = st_vertex_step(m, x, l);
    } while (x != x0 && cnt < 1u << 16);
    return sum / cnt;
}

/* The vertex of the grid nearest to c, searching cubes of cells of growing
 * size (a vertex within k cells of c is inside the cube of k cells around
 * c's cell); ST_NIL when none is within 8 cells. */
static uint32_t grid_nearest(const st_sculpt *bs, const st_level_view *lv, const double c[3])
{
    int64_t at[3];
    for (int k = 0; k < 3; k++) at[k] = cell_coord(c[k], bs->cs);
    uint32_t best = ST_NIL;
    double bd = INFINITY;
    for (int64_t g = 1; g <= 8; g++) {
        for (int64_t x = at[0] - g; x <= at[0] + g; x++)
            for (int64_t y = at[1] - g; y <= at[1] + g; y++)
                for (int64_t z = at[2] - g; z <= at[2] + g; z++) {
                    int64_t h = grid_cell((st_sculpt *)bs, cell_key(x, y, z), 0);
                    if (h < 0) continue;
                    for (uint32_t v = bs->hhead[h]; v != ST_NIL; v = bs->next[v]) {
                        const double *p = st_v_pos(lv, v);
                        double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2], r = dx * dx + dy * dy + dz * dz;
                        if (r < bd) { bd = r; best = v; }
                    }
                }
        if (best != ST_NIL && sqrt(bd) < (double)g * bs->cs) break;
    }
    return best;
}

/* This dab's radius: the brush radius, or reach_edges times the mean edge
 * length at the level's vertex nearest to the centre when that is larger
 * (st_sculpt_reach: a coarse level takes in the vertices of the faces
 * under the cursor).  The edges there, not the level's mean: a coarse
 * cage's faces differ in size by several times (blub's fins). */
static double dab_reach(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const double c[3])
{
    double R = b->radius;
    if (!(b->reach_edges > 0)) return R;
    /* A fine level (the level's mean edge far below the radius): no search
     * (the grid's cells there hold thousands of vertices each).  Local
     * edges of a cage differ from the mean by a few times, hence 8. */
    if (8 * b->reach_edges * bs->edge_mean < R) return R;
    st_level_view lv;
    st_level_view_init(m, bs->level, &lv);
    uint32_t v = grid_nearest(bs, &lv, c), x0 = v == ST_NIL ? ST_NIL : sc_vertex_dart(bs, v);
    if (x0 == ST_NIL) return bs->R;
    double e = b->reach_edges * vertex_edge_mean(m, x0, bs->level);
    return e > R ? e : R;
}

double st_sculpt_dab_radius(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const double c[3])
{
    if (b->tool == ST_BRUSH_GRAB && bs->grabbed) return bs->R;
    bs->R = dab_reach(bs, m, b, c);
    return bs->R;
}

/* ---- strokes -------------------------------------------------------------------------- */

void st_sculpt_begin(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const st_sculpt_stroke *st)
{
    unsigned l = st->level;
    bs->level = l;
    bs->edge_mean = st->edge_mean;
    bs->R = st->reach > 0 ? st->reach : st_sculpt_reach(b, st->edge_mean);
    bs->cs = bs->R;
    /* Spacing attenuation (Blender's BRUSH_SPACE_ATTEN): fractions (pinch,
     * flatten, ...) by 1 / overlap, heights (draw, inflate, crease) so that
     * a stroke at the default spacing deposits what it did before. */
    double sp = b->space_atten ? b->spacing : 0;
    bs->fscale = st_brush_overlap_scale(b->falloff, sp);
    bs->hscale = bs->fscale / st_brush_overlap_scale(b->falloff, sp > 0 ? 0.1 : 0);
    bs->fadek = 1;
    free(bs->own_vdart);
    bs->own_vdart = NULL;
    if (st->vertex_darts) {
        bs->vdart = st->vertex_darts;
        bs->nvdart = st->nvertex_darts;
    } else {
        bs->own_vdart = st_sculpt_vertex_darts(m, l, &bs->nvdart);
        if (!bs->own_vdart) abort();
        bs->vdart = bs->own_vdart;
    }
    /* Per-vertex arrays up to the largest id of the level only. */
    uint32_t nv = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        if (v + 1 > nv) nv = v + 1;
    if (bs->nv < nv) {
        bs->next = sc_xrealloc(bs->next, (size_t)nv * sizeof *bs->next);
        bs->prev = sc_xrealloc(bs->prev, (size_t)nv * sizeof *bs->prev);
        bs->vcell = sc_xrealloc(bs->vcell, (size_t)nv * sizeof *bs->vcell);
        bs->mark = sc_xrealloc(bs->mark, (size_t)nv * sizeof *bs->mark);
        bs->slot = sc_xrealloc(bs->slot, (size_t)nv * sizeof *bs->slot);
        bs->lay_o = sc_xrealloc(bs->lay_o, (size_t)nv * sizeof *bs->lay_o);
        bs->lay_n0 = sc_xrealloc(bs->lay_n0, (size_t)nv * sizeof *bs->lay_n0);
        bs->ring_at = sc_xrealloc(bs->ring_at, (size_t)nv * sizeof *bs->ring_at);
        bs->nv = nv;
    }
    for (uint32_t v = 0; v < bs->nv; v++) { bs->vcell[v] = EMPTY_KEY; bs->mark[v] = 0; bs->lay_o[v] = -1; }
    memset(bs->ring_at, 0, (size_t)bs->nv * sizeof *bs->ring_at);
    bs->nring = 0;
    bs->nfn = 0;
    bs->gen = 0;
    for (uint32_t i = 0; i < bs->hcap; i++) bs->hkey[i] = EMPTY_KEY;
    bs->hn = 0;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        grid_insert(bs, v, st_pos(m, v, l));
    bs->grabbed = 0;
    bs->ng = 0;
}

static void grab_capture(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const double c[3],
                         const double dn[3], const double view[3], uint8_t which)
{
    grid_query(bs, m, b, c, dn, view);
    for (uint32_t i = 0; i < bs->ntmp; i++) {
        if (bs->ng == bs->capg) {
            bs->capg = bs->capg ? 2 * bs->capg : 256;
            bs->gv = sc_xrealloc(bs->gv, (size_t)bs->capg * sizeof *bs->gv);
            bs->gw = sc_xrealloc(bs->gw, (size_t)bs->capg * sizeof *bs->gw);
            bs->gk = sc_xrealloc(bs->gk, (size_t)bs->capg * sizeof *bs->gk);
        }
        bs->gv[bs->ng] = bs->tmp[i];
        bs->gw[bs->ng] = bs->tmpw[i];
        bs->gk[bs->ng++] = which;
    }
}

uint32_t st_sculpt_dab_run(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const st_sculpt_dab *dab,
                           const st_mask *mask, const uint32_t **darts, const double (**pos)[3])
{
    unsigned l = bs->level;
    static const double up[3] = { 0, 0, 1 };
    double nn[3];
    memcpy(nn, dab->normal, sizeof nn);
    if (normalize3(nn)) memcpy(nn, up, sizeof nn);
    uint8_t which[8];
    unsigned nsym = sc_symmetry_set(b, which);
    const double *center = dab->center;
    bs->fadek = dab->fade;
    if (++bs->gen == 0) {
        for (uint32_t v = 0; v < bs->nv; v++) bs->mark[v] = 0;
        bs->gen = 1;
    }
    bs->nlist = 0;
    if (b->tool == ST_BRUSH_GRAB) {
        if (!bs->grabbed) {
            for (unsigned s = 0; s < nsym; s++) {
                double mc[3], mn[3], mv[3];
                sc_reflect(which[s], center, mc);
                sc_reflect(which[s], nn, mn);
                sc_reflect(which[s], dab->view, mv);
                grab_capture(bs, m, b, mc, mn, mv, which[s]);
            }
            bs->grabbed = 1;
        }
        for (uint32_t i = 0; i < bs->ng; i++) {
            double dd[3];
            sc_reflect(bs->gk[i], dab->grab_delta, dd);
            double dv[3] = { bs->gw[i] * dd[0], bs->gw[i] * dd[1], bs->gw[i] * dd[2] };
            sc_acc(bs, bs->gv[i], dv);
        }
    } else {
        for (unsigned s = 0; s < nsym; s++) {
            double mc[3], mn[3], mv[3];
            sc_reflect(which[s], center, mc);
            sc_reflect(which[s], nn, mn);
            sc_reflect(which[s], dab->view, mv);
            sc_reflect(which[s], dab->dir, bs->dab_dir);
            grid_query(bs, m, b, mc, mn, mv);
            if (bs->ntmp) sc_tool_dab(bs, m, b, mc, mn);
        }
        if (b->tool == ST_BRUSH_LAYER) sc_layer_finish(bs, b);
        int smoother = b->tool == ST_BRUSH_SMOOTH || b->tool == ST_BRUSH_RELAX;
        if (!smoother && b->autosmooth > 0) sc_autosmooth(bs, m, fmin(b->autosmooth, 1));
        if (b->hold) sc_hold_faces(bs, m, b);
        if (b->tool == ST_BRUSH_LAYER && (b->hold || b->autosmooth > 0)) sc_layer_settle(bs, b);
    }
    if (bs->nlist > bs->capout) {
        bs->capout = bs->nlist;
        bs->odarts = sc_xrealloc(bs->odarts, (size_t)bs->capout * sizeof *bs->odarts);
        bs->opos = sc_xrealloc(bs->opos, (size_t)bs->capout * sizeof *bs->opos);
    }
    uint32_t n = 0;
    for (uint32_t i = 0; i < bs->nlist; i++) {
        uint32_t v = bs->list[i], x = sc_vertex_dart(bs, v);
        /* The mask attenuates the dab: displacement times 1 - mask; a fully
         * masked vertex is left out, so it stays the same to the bit. */
        double keep = 1.0 - (double)(mask ? st_mask_get(mask, v) : 0.0f);
        if (x == ST_NIL || !(keep > 0)) continue;
        if (!bs->disp[i][0] && !bs->disp[i][1] && !bs->disp[i][2]) continue;
        const double *p = st_pos(m, v, l);
        for (int k = 0; k < 3; k++) bs->opos[n][k] = p[k] + keep * bs->disp[i][k];
        bs->odarts[n++] = x;
    }
    *darts = bs->odarts;
    *pos = (const double(*)[3])bs->opos;
    return n;
}

void st_sculpt_moved(st_sculpt *bs, const st_map *m, const uint32_t *darts, uint32_t n)
{
    unsigned l = bs->level;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v = st_vert(m, darts[i], l);
        grid_insert(bs, v, st_pos(m, v, l));
    }
}

uint32_t st_sculpt_dab_apply(st_sculpt *s, st_hier *h, const st_sculpt_brush *b, const st_sculpt_dab *dab,
                             const st_mask *mask, st_footprint *fp)
{
    const uint32_t *darts;
    const double(*pos)[3];
    uint32_t n = st_sculpt_dab_run(s, &h->map, b, dab, mask, &darts, &pos);
    if (!n) return 0;
    st_hier_edit(h, s->level, darts, pos, n, fp);
    st_sculpt_moved(s, &h->map, darts, n);
    return n;
}

uint32_t st_sculpt_query(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const double c[3],
                         const double view[3], const uint32_t **vids, const double **w)
{
    static const double up[3] = { 0, 0, 1 };
    grid_query(bs, m, b, c, up, view);
    *vids = bs->tmp;
    *w = bs->tmpw;
    return bs->ntmp;
}
