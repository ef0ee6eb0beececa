/* Brush strokes at the editing level (editor.h): the spatial grid, the
 * per-vertex weight, symmetry and the stroke itself; what each brush does
 * under a dab is in brush_tools.c, the spacing of dabs along the cursor's
 * path in brush_stroke.c.  Around the brushes, so that full strength holds
 * (issue 30, tests/test_editor_brush_hold.c): the dab's reach at coarse
 * levels (dab_reach), the stroke's fade-in, the spacing attenuation
 * (st_brush_overlap_scale), auto-smooth and the hold (hold_faces).
 *
 * Finding the vertices under a dab: a uniform grid (hashed cells) of the
 * editing level's vertex positions, built at stroke begin with the cell
 * size equal to the brush radius, so a dab visits the 2x2x2 (at most 3x3x3)
 * cells around it, never the whole level.  Positions change during the
 * stroke: every vertex a dab moves is re-inserted into the cell of its new
 * position right after the dab (doubly linked per-cell lists, O(1) per
 * move), so the grid is always exact.  A radius changed during the stroke
 * only widens the range of cells visited.  A dab's cost is thus that of
 * the vertices under it (and their one-rings for normals).
 *
 * Weight of a vertex under a dab (ed_brush_weight, the one place): the
 * falloff preset at its distance, times the strength, times the front-face
 * test: with front_only and a view direction known (brush.view_dir, set by
 * the window at stroke begin), a vertex whose area-weighted normal does not
 * face the viewer (dot with the view direction >= 0) is on the far side of
 * a thin part or of the model and is left alone, as Blender's "front faces
 * only" does.  Mirrored dabs reflect the view direction with the dab.
 *
 * Symmetry: with mirror_x / _y / _z the dab is repeated with centre, normal
 * and grab delta reflected across every combination of the enabled planes
 * of object space (up to 8 dabs).  The displacements of all of them are
 * computed from the same positions and added, and only then applied, so a
 * mesh symmetric about those planes stays symmetric (to the rounding of the
 * additions).
 */
#include "brush_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


#define EMPTY_KEY UINT64_MAX
#define CELL_LIM (1 << 20)

double st_brush_falloff(double r, double radius)
{
    return st_falloff_eval(ST_FALLOFF_SMOOTH, r, radius);
}

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

const char *st_brush_name(int tool)
{
    static const char *names[ST_BRUSH_COUNT] = { "grab", "draw", "smooth", "flatten", "crease",
                                                 "pinch", "inflate", "clay strips", "layer", "relax" };
    return tool >= 0 && tool < ST_BRUSH_COUNT ? names[tool] : "?";
}

void st_brush_defaults(st_brush *b, double radius)
{
    memset(b, 0, sizeof *b);
    b->tool = ST_BRUSH_DRAW;
    b->radius = radius;
    b->falloff = ST_FALLOFF_SMOOTH;
    b->front_only = 1;
    b->spacing = 0.1;          /* Blender's default spacing: 10 % of the radius */
    b->space_atten = 1;        /* Blender: "Adjust Strength for Spacing", on by default */
    b->fade = 1.0;             /* strength reaches full after one radius of path */
    b->reach_edges = ST_BRUSH_REACH_EDGES;
    b->area_plane = 1;
    b->hold = 1;
    b->stabilize_dist = 0.5;
    for (int t = 0; t < ST_BRUSH_COUNT; t++) {
        b->tool_strength[t] = t == ST_BRUSH_GRAB ? 1.0 : 0.5;
        b->tool_falloff[t] = ST_FALLOFF_SMOOTH;
    }
    /* Auto-smooth (Blender's per-brush Auto-Smooth, sculpt.c
     * do_brush_action, which ships at 0 and which sculptors raise for
     * crease and pinch): on here for the brushes whose strength-1 strokes
     * pile up sharp ridges and creases without it (test_editor_brush_hold),
     * low enough that a crease stays a crease. */
    b->tool_autosmooth[ST_BRUSH_DRAW] = 0.15;
    b->tool_autosmooth[ST_BRUSH_CLAY_STRIPS] = 0.15;
    b->tool_autosmooth[ST_BRUSH_INFLATE] = 0.15;
    b->tool_autosmooth[ST_BRUSH_CREASE] = 0.2;
    b->tool_autosmooth[ST_BRUSH_PINCH] = 0.2;
    b->tool_autosmooth[ST_BRUSH_FLATTEN] = 0.1;
    b->tool_autosmooth[ST_BRUSH_LAYER] = 0.1;
    b->strength = b->tool_strength[b->tool];
    b->autosmooth = b->tool_autosmooth[b->tool];
}

void st_brush_raw(st_brush *b)
{
    b->space_atten = 0;
    b->fade = 0;
    b->reach_edges = 0;
    b->area_plane = 0;
    b->hold = 0;
    b->autosmooth = 0;
    for (int t = 0; t < ST_BRUSH_COUNT; t++) b->tool_autosmooth[t] = 0;
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

void st_brush_set_tool(st_brush *b, int tool)
{
    if (tool < 0 || tool >= ST_BRUSH_COUNT) return;
    if (b->tool >= 0 && b->tool < ST_BRUSH_COUNT) {
        b->tool_strength[b->tool] = b->strength;
        b->tool_falloff[b->tool] = b->falloff;
        b->tool_autosmooth[b->tool] = b->autosmooth;
    }
    b->tool = tool;
    b->strength = b->tool_strength[tool];
    b->falloff = b->tool_falloff[tool];
    b->autosmooth = b->tool_autosmooth[tool];
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
    free(bs);
}

void *ed_xrealloc(void *p, size_t n)
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
    bs->hkey = ed_xrealloc(NULL, (size_t)cap * sizeof *bs->hkey);
    bs->hhead = ed_xrealloc(NULL, (size_t)cap * sizeof *bs->hhead);
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

static void tmp_push(struct st_brush_state *bs, uint32_t v, double w, const double n[3], double area)
{
    if (bs->ntmp == bs->captmp) {
        bs->captmp = bs->captmp ? 2 * bs->captmp : 256;
        bs->tmp = ed_xrealloc(bs->tmp, (size_t)bs->captmp * sizeof *bs->tmp);
        bs->tmpw = ed_xrealloc(bs->tmpw, (size_t)bs->captmp * sizeof *bs->tmpw);
        bs->tmpn = ed_xrealloc(bs->tmpn, (size_t)bs->captmp * sizeof *bs->tmpn);
        bs->tmpa = ed_xrealloc(bs->tmpa, (size_t)bs->captmp * sizeof *bs->tmpa);
    }
    bs->tmp[bs->ntmp] = v;
    bs->tmpw[bs->ntmp] = w;
    bs->tmpa[bs->ntmp] = area;
    memcpy(bs->tmpn[bs->ntmp++], n, sizeof bs->tmpn[0]);
}

/* ---- local geometry --------------------------------------------------------------- */

/* Next dart around the vertex of x at level l: β1 in the primal encoding;
 * in the dual one (Doo-Sabin, map.h: a surface vertex is a map face) φ1. */
uint32_t ed_around(const st_map *m, uint32_t x, unsigned l)
{
    return m->face_embedded ? st_phi1(m, x, l) : st_beta1(m, x, l);
}

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
static void ring_push(struct st_brush_state *bs, uint32_t x)
{
    if (bs->nring == bs->capring) {
        bs->capring = bs->capring ? 2 * bs->capring : 4096;
        bs->ring = ed_xrealloc(bs->ring, (size_t)bs->capring * sizeof *bs->ring);
    }
    bs->ring[bs->nring++] = x;
}

/* The Newell normal of the face record r (terms c, then c + 1 ids) now,
 * with each vertex moved by its displacement in this dab when `moved`. */
static void face_normal(const struct st_brush_state *bs, const st_level_view *lv, const uint32_t *r, int moved,
                        double n[3])
{
    uint32_t c = r[0];
    double n0 = 0, n1 = 0, n2 = 0, p[3], q[3];
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

static void fn_push(struct st_brush_state *bs, const st_level_view *lv, const uint32_t *r)
{
    if (bs->nfn == bs->capfn) {
        bs->capfn = bs->capfn ? 2 * bs->capfn : 4096;
        bs->fn = ed_xrealloc(bs->fn, (size_t)bs->capfn * sizeof *bs->fn);
    }
    face_normal(bs, lv, r, 0, bs->fn[bs->nfn++]);
}

static uint32_t ring_of(struct st_brush_state *bs, const st_map *m, const st_level_view *lv, uint32_t v, uint32_t x0)
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
                uint32_t z = dual ? st_v_beta1(lv, y) : st_v_phi1(lv, y);
                ring_push(bs, st_v_vert(lv, z));
                bs->ring[at]++;
                y = z;
            } while (y != x && ++g2 < 1u << 16);
            bs->ring[o]++;
            fn_push(bs, lv, bs->ring + at);
        }
        x = dual ? st_v_phi1(lv, x) : st_v_beta1(lv, x);
    } while (x != x0 && ++guard < 1u << 16);
    bs->ring_at[v] = o + 1;
    return o;
}

/* Area-weighted normal of a vertex (not normalised) from its ring record:
 * the sum of the Newell normals of the surface faces around it, one
 * running sum (st_newell_add's terms) in the order of the walk. */
static void ring_normal(const struct st_brush_state *bs, const st_level_view *lv, uint32_t o, double n[3])
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
static double unit_normal(struct st_brush_state *bs, const st_map *m, const st_level_view *lv, uint32_t v, uint32_t x0,
                          const double fallback[3], double n[3])
{
    ring_normal(bs, lv, ring_of(bs, m, lv, v, x0), n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (normalize3(n)) memcpy(n, fallback, 3 * sizeof *n);
    return len;
}

/* ---- the weight of a vertex under a dab ------------------------------------------------ */

double ed_brush_weight(const st_doc *d, uint32_t v, double r, const double vn[3], const double view[3])
{
    /* v: the mask is not read here but where the dab's summed displacement
     * is applied (st_doc_stroke_dab), so that it scales every mirrored dab
     * together and a vertex masked 1 is left out to the bit. */
    (void)v;
    const st_brush *b = &d->brush;
    /* In a stroke: its radius (st_doc_brush_reach) and fade-in. */
    int stroke = d->bs && d->active;
    double f = st_falloff_eval(b->falloff, r, stroke ? d->bs->R : b->radius);
    if (!(f > 0)) return 0;
    int known = view[0] != 0 || view[1] != 0 || view[2] != 0;
    if (b->front_only && known && !(vn[0] * view[0] + vn[1] * view[1] + vn[2] * view[2] < 0)) return 0;
    double s = b->strength;
    if (!(s > 0)) return 0;
    if (s > 1) s = 1;
    return f * s * (stroke ? d->bs->fadek : 1);
}

static void visit_cell(st_doc *d, struct st_brush_state *bs, const st_level_view *lv, uint32_t head, const double c[3],
                       const double dn[3], const double view[3])
{
    const st_map *m = &d->h.map;
    double R = bs->R;
    for (uint32_t v = head; v != ST_NIL; v = bs->next[v]) {
        const double *p = st_v_pos(lv, v);
        double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
        double r = sqrt(dx * dx + dy * dy + dz * dz);
        if (!(r < R)) continue;
        uint32_t x0 = ed_vertex_dart(d, v);
        if (x0 == ST_NIL) continue;
        double vn[3], area = unit_normal(bs, m, lv, v, x0, dn, vn);
        double w = ed_brush_weight(d, v, r, vn, view);
        if (w > 0) tmp_push(bs, v, w, vn, area);
    }
}

/* Vertices strictly inside the sphere (c, R) with a positive weight, with
 * their weights and unit normals, into tmp. */
static void grid_query(st_doc *d, struct st_brush_state *bs, const double c[3], const double dn[3], const double view[3])
{
    double R = bs->R;
    bs->ntmp = 0;
    st_level_view lv;
    st_level_view_init(&d->h.map, bs->level, &lv);
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
            if (bs->hkey[h] != EMPTY_KEY) visit_cell(d, bs, &lv, bs->hhead[h], c, dn, view);
        return;
    }
    for (int64_t x = lo[0]; x <= hi[0]; x++)
        for (int64_t y = lo[1]; y <= hi[1]; y++)
            for (int64_t z = lo[2]; z <= hi[2]; z++) {
                int64_t h = grid_cell(bs, cell_key(x, y, z), 0);
                if (h >= 0) visit_cell(d, bs, &lv, bs->hhead[h], c, dn, view);
            }
}

/* ---- dab accumulation ----------------------------------------------------------------- */

/* The accumulator slot of v in this dab (created zero). */
static uint32_t acc_slot(struct st_brush_state *bs, uint32_t v)
{
    if (bs->mark[v] != bs->gen) {
        bs->mark[v] = bs->gen;
        if (bs->nlist == bs->caplist) {
            bs->caplist = bs->caplist ? 2 * bs->caplist : 256;
            bs->list = ed_xrealloc(bs->list, (size_t)bs->caplist * sizeof *bs->list);
            bs->disp = ed_xrealloc(bs->disp, (size_t)bs->caplist * sizeof *bs->disp);
            bs->lay_t = ed_xrealloc(bs->lay_t, (size_t)bs->caplist * sizeof *bs->lay_t);
            bs->accw = ed_xrealloc(bs->accw, (size_t)bs->caplist * sizeof *bs->accw);
            bs->disp2 = ed_xrealloc(bs->disp2, (size_t)bs->caplist * sizeof *bs->disp2);
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

void ed_brush_acc_weight(struct st_brush_state *bs, uint32_t v, double w)
{
    uint32_t i = acc_slot(bs, v);
    if (w > bs->accw[i]) bs->accw[i] = w;
}

void ed_brush_acc(struct st_brush_state *bs, uint32_t v, const double dv[3])
{
    uint32_t i = acc_slot(bs, v); /* before reading bs->disp, which it may move */
    double *t = bs->disp[i];
    t[0] += dv[0]; t[1] += dv[1]; t[2] += dv[2];
}

void ed_brush_acc_layer(struct st_brush_state *bs, uint32_t v, double h, const double n[3])
{
    uint32_t i = acc_slot(bs, v);
    if (h > bs->lay_t[i]) bs->lay_t[i] = h;
    if (bs->lay_o[v] < 0) {
        bs->lay_o[v] = 0;
        memcpy(bs->lay_n0[v], n, sizeof bs->lay_n0[v]);
    }
}

/* Layer (Blender's layer brush without "persistent"): a vertex rises to the
 * largest height any dab of the stroke asked of it, never more: each dab
 * moves it by what is left between that height and its displacement so far
 * (lay_o), along its normal when the stroke first reached it (so the
 * heights add up exactly along one direction). */
static void layer_finish(st_doc *d, struct st_brush_state *bs)
{
    double sgn = d->brush.invert ? -1 : 1;
    for (uint32_t i = 0; i < bs->nlist; i++) {
        uint32_t v = bs->list[i];
        double step = bs->lay_t[i] - bs->lay_o[v];
        bs->lay_t[i] = -1; /* from here: the height before this dab, -1 none asked */
        if (!(step > 0)) continue;
        bs->lay_t[i] = bs->lay_o[v];
        bs->lay_o[v] += step;
        for (int k = 0; k < 3; k++) bs->disp[i][k] = sgn * step * bs->lay_n0[v][k];
    }
}

/* After auto-smooth and the hold changed the layer's steps: the height
 * each vertex reached is what moved it along its layer direction, so a
 * held vertex rises the rest of the way in a later dab if it can. */
static void layer_settle(st_doc *d, struct st_brush_state *bs)
{
    double sgn = d->brush.invert ? -1 : 1;
    for (uint32_t i = 0; i < bs->nlist; i++) {
        if (bs->lay_t[i] < 0) continue;
        uint32_t v = bs->list[i];
        const double *n = bs->lay_n0[v], *dv = bs->disp[i];
        double got = sgn * (dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2]);
        bs->lay_o[v] = bs->lay_t[i] + (got > 0 ? fmin(got, bs->lay_o[v] - bs->lay_t[i]) : 0);
    }
}

/* ---- auto-smooth ----------------------------------------------------------------------- */

/* Blender's Auto-Smooth (sculpt.c, do_brush_action: a smooth pass over the
 * brush's vertices after each dab, autosmooth_factor times the falloff):
 * every vertex this dab moves goes toward the average of its one-ring as
 * the dab leaves them (positions plus the dab's displacements), by
 * a * its weight.  The result goes to disp2 and then replaces disp, so the
 * order of the vertices does not matter and a symmetric dab stays
 * symmetric. */
static void autosmooth(st_doc *d, struct st_brush_state *bs, double a)
{
    st_level_view lv;
    st_level_view_init(&d->h.map, bs->level, &lv);
    for (uint32_t i = 0; i < bs->nlist; i++) {
        uint32_t v = bs->list[i];
        double *o = bs->disp2[i];
        memcpy(o, bs->disp[i], sizeof bs->disp2[0]);
        double k = a * bs->accw[i];
        if (!(k > 0)) continue;
        const double *p = st_v_pos(&lv, v);
        double avg[3] = { 0, 0, 0 };
        unsigned cnt = 0;
        if (bs->ring_at[v]) {
            /* The neighbours from v's ring record (every vertex a dab moves
             * has one): the corner after v on each face around it, one per
             * edge at v (the edge of a boundary vertex along the hole is
             * left out); no dart walk. */
            const uint32_t *r = bs->ring + bs->ring_at[v] - 1;
            uint32_t nf = r[0];
            r += 2;
            for (uint32_t f = 0; f < nf; f++, r += r[0] + 2) {
                uint32_t u = r[2];
                const double *q = st_v_pos(&lv, u);
                int moved = bs->mark[u] == bs->gen;
                for (int j = 0; j < 3; j++) avg[j] += q[j] + (moved ? bs->disp[bs->slot[u]][j] : 0);
                cnt++;
            }
        }
        if (!cnt) continue;
        for (int j = 0; j < 3; j++) o[j] += k * (avg[j] / cnt - p[j] - bs->disp[i][j]);
    }
    for (uint32_t i = 0; i < bs->nlist; i++) memcpy(bs->disp[i], bs->disp2[i], sizeof bs->disp[0]);
}

/* v reflected across the planes of the set bits of `which` (1 x, 2 y, 4 z). */
static void reflect(uint8_t which, const double v[3], double out[3])
{
    for (int k = 0; k < 3; k++) out[k] = which >> k & 1 ? -v[k] : v[k];
}

/* The mirrored dabs of the brush's symmetry: every subset of the enabled
 * planes (0 is the dab itself); returns how many. */
static unsigned symmetry_set(const st_brush *b, uint8_t which[8])
{
    unsigned mask = (b->mirror_x ? 1u : 0) | (b->mirror_y ? 2u : 0) | (b->mirror_z ? 4u : 0), n = 0;
    for (unsigned s = 0; s < 8; s++)
        if (!(s & ~mask)) which[n++] = (uint8_t)s;
    return n;
}

/* ---- holding the surface --------------------------------------------------------------- */

/* A face turned by more than acos HOLD_COS from its normal when the stroke
 * first reached it, or (but under crease and pinch) shrunk below HOLD_AREA
 * of its area then, is held:
 * issue 30 asks that no face flip (turn past 90 degrees) under any brush
 * at full strength, and that none collapse. */
#define HOLD_COS 0.719 /* cos 44 degrees: two strokes stay under 90 */
#define HOLD_AREA 0.1

static int face_held(const struct st_brush_state *bs, const st_level_view *lv, const uint32_t *r, const double n0[3],
                     int shrinks)
{
    double n[3];
    face_normal(bs, lv, r, 1, n);
    double a = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), a0 = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
    return !(n[0] * n0[0] + n[1] * n0[1] + n[2] * n0[2] > HOLD_COS * a * a0) || (!shrinks && !(a >= HOLD_AREA * a0));
}

/* The clamp that makes the guarantee: after the brush and its auto-smooth,
 * every face around a vertex the dab moves is checked against its
 * reference.  Around the faces that would be held the dab is damped
 * smoothly: each moved vertex's displacement is scaled by
 * 1 - k K(d / rho), K the smooth falloff, d its distance to the nearest
 * held face (its centroid on a lattice of R/8, hold_push), rho half
 * the dab's radius, k = 1/2, pass after
 * pass (the displacement stays a smooth field: halving the corners of the
 * held faces alone left the surface crumpled, and so did slowing each
 * vertex by its own normal's turn).  After HOLD_SMOOTH passes the corners
 * of faces still held (and their mirror images) are taken back, until
 * none is: a face whose
 * corners all stay where they were is as it was before the dab, which
 * held, so this ends (at worst with the dab taken back). */
#define HOLD_SMOOTH 8

/* Records a held face by its centroid c snapped to the lattice of spacing
 * h, unless that lattice point is recorded already (a held region is a
 * few points, not one per face: hold_damp visits every moved vertex per
 * point).  round() is odd, so the lattice points of mirrored faces are
 * mirrored and a symmetric dab stays symmetric. */
static void hold_point(struct st_brush_state *bs, const double p[3], double reach)
{
    for (uint32_t i = 0; i < bs->nheld; i++)
        if (bs->held[i][0] == p[0] && bs->held[i][1] == p[1] && bs->held[i][2] == p[2]) {
            if (reach > bs->heldr[i]) bs->heldr[i] = reach;
            return;
        }
    if (bs->nheld == bs->capheld) {
        bs->capheld = bs->capheld ? 2 * bs->capheld : 64;
        bs->held = ed_xrealloc(bs->held, (size_t)bs->capheld * sizeof *bs->held);
        bs->heldr = ed_xrealloc(bs->heldr, (size_t)bs->capheld * sizeof *bs->heldr);
    }
    bs->heldr[bs->nheld] = reach;
    memcpy(bs->held[bs->nheld++], p, sizeof bs->held[0]);
}

/* ... with its reflections across the brush's symmetry planes too: a held
 * face and its mirror image damp alike even where rounding held only one
 * of them (their normals are summed in opposite orders). */
static void hold_push(struct st_brush_state *bs, const st_brush *b, const double c[3], double corner, double h)
{
    uint8_t which[8];
    unsigned nsym = symmetry_set(b, which);
    double p[3], q[3], off = 0;
    for (int k = 0; k < 3; k++) {
        p[k] = round(c[k] / h) * h;
        off += (p[k] - c[k]) * (p[k] - c[k]);
    }
    /* reach: every corner of the face is within it of p */
    double reach = corner + sqrt(off) + 1e-9 * h;
    for (unsigned s = 0; s < nsym; s++) {
        reflect(which[s], p, q);
        hold_point(bs, q, reach);
    }
}

/* The hard pass: every moved vertex within a held point's reach (so every
 * corner of every held face, and their mirror images) is taken back. */
static void hold_zero(struct st_brush_state *bs, const st_level_view *lv)
{
    for (uint32_t i = 0; i < bs->nlist; i++) {
        const double *p = st_v_pos(lv, bs->list[i]);
        for (uint32_t h = 0; h < bs->nheld; h++) {
            double dx = p[0] - bs->held[h][0], dy = p[1] - bs->held[h][1], dz = p[2] - bs->held[h][2];
            if (dx * dx + dy * dy + dz * dz <= bs->heldr[h] * bs->heldr[h]) {
                bs->disp[i][0] = bs->disp[i][1] = bs->disp[i][2] = 0;
                break;
            }
        }
    }
}

/* Scales every displacement by 1 - k K(distance to the nearest held point / rho). */
static void hold_damp(struct st_brush_state *bs, const st_level_view *lv, double rho, double k)
{
    for (uint32_t i = 0; i < bs->nlist; i++) {
        const double *p = st_v_pos(lv, bs->list[i]);
        double near = INFINITY;
        for (uint32_t h = 0; h < bs->nheld; h++) {
            double dx = p[0] - bs->held[h][0], dy = p[1] - bs->held[h][1], dz = p[2] - bs->held[h][2];
            double r2 = dx * dx + dy * dy + dz * dz;
            if (r2 < near) near = r2;
        }
        double f = 1 - k * st_falloff_eval(ST_FALLOFF_SMOOTH, sqrt(near), rho);
        for (int j = 0; j < 3; j++) bs->disp[i][j] *= f;
    }
}

static void hold_faces(st_doc *d, struct st_brush_state *bs)
{
    st_level_view lv;
    st_level_view_init(&d->h.map, bs->level, &lv);
    /* Crease and pinch pull vertices together: their faces may shrink. */
    int shrinks = d->brush.tool == ST_BRUSH_CREASE || d->brush.tool == ST_BRUSH_PINCH;
    for (unsigned pass = 0; pass < HOLD_SMOOTH + 64; pass++) {
        int hard = pass >= HOLD_SMOOTH;
        bs->nheld = 0;
        for (uint32_t i = 0; i < bs->nlist; i++) {
            uint32_t v = bs->list[i];
            if (!bs->ring_at[v]) continue;
            const uint32_t *r = bs->ring + bs->ring_at[v] - 1;
            uint32_t nf = r[0], f0 = r[1];
            r += 2;
            for (uint32_t f = 0; f < nf; f++, r += r[0] + 2) {
                /* A face is checked from each moved corner, against the
                 * reference that corner's ring recorded: mirrored faces
                 * then get mirrored decisions (checking it once, from one
                 * corner chosen by id, did not: ids are not mirrored). */
                if (!face_held(bs, &lv, r, bs->fn[f0 + f], shrinks)) continue;
                double c[3] = { 0, 0, 0 }, corner = 0;
                for (uint32_t t = 1; t <= r[0]; t++) {
                    const double *q = st_v_pos(&lv, r[t]);
                    for (int j = 0; j < 3; j++) c[j] += q[j] / r[0];
                }
                for (uint32_t t = 1; t <= r[0]; t++) {
                    const double *q = st_v_pos(&lv, r[t]);
                    double e = sqrt((q[0] - c[0]) * (q[0] - c[0]) + (q[1] - c[1]) * (q[1] - c[1]) + (q[2] - c[2]) * (q[2] - c[2]));
                    if (e > corner) corner = e;
                }
                hold_push(bs, &d->brush, c, corner, 0.125 * bs->R);
            }
        }
        if (!bs->nheld) return;
        if (hard) hold_zero(bs, &lv);
        else hold_damp(bs, &lv, 0.5 * bs->R, 0.5);
    }
    for (uint32_t i = 0; i < bs->nlist; i++) bs->disp[i][0] = bs->disp[i][1] = bs->disp[i][2] = 0;
}

/* ---- reach at coarse levels ---------------------------------------------------------- */

/* Mean length of the edges of level l (each edge once: the dart of the
 * smaller id of its two, β0 the opposite dart).  In the dual encoding
 * (Doo-Sabin) the darts join face centres, a length of the same order. */
static double edge_mean(const st_map *m, unsigned l)
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

double st_doc_brush_reach(st_doc *d)
{
    double R = d->brush.radius;
    if (!d->loaded || !(d->brush.reach_edges > 0)) return R;
    struct st_brush_state *bs = d->bs;
    if (!bs) {
        bs = calloc(1, sizeof *bs);
        if (!bs) abort();
        d->bs = bs;
    }
    /* Taken again when the level or the map's vertex count changes; the
     * lengths drift little under brushes, which do not change topology. */
    uint32_t key = d->h.map.verts.end + 1;
    if (bs->edge_key != key || bs->edge_level != d->edit_level) {
        bs->edge_mean = edge_mean(&d->h.map, d->edit_level);
        bs->edge_level = d->edit_level;
        bs->edge_key = key;
    }
    double e = d->brush.reach_edges * bs->edge_mean;
    return e > R ? e : R;
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
        x = ed_around(m, x, l);
    } while (x != x0 && cnt < 1u << 16);
    return sum / cnt;
}

/* The vertex of the grid nearest to c, searching cubes of cells of growing
 * size (a vertex within k cells of c is inside the cube of k cells around
 * c's cell); ST_NIL when none is within 8 cells. */
static uint32_t grid_nearest(const struct st_brush_state *bs, const st_level_view *lv, const double c[3])
{
    int64_t at[3];
    for (int k = 0; k < 3; k++) at[k] = cell_coord(c[k], bs->cs);
    uint32_t best = ST_NIL;
    double bd = INFINITY;
    for (int64_t g = 1; g <= 8; g++) {
        for (int64_t x = at[0] - g; x <= at[0] + g; x++)
            for (int64_t y = at[1] - g; y <= at[1] + g; y++)
                for (int64_t z = at[2] - g; z <= at[2] + g; z++) {
                    int64_t h = grid_cell((struct st_brush_state *)bs, cell_key(x, y, z), 0);
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
 * length at the editing-level vertex nearest to the centre when that is
 * larger (st_doc_brush_reach: a coarse level takes in the vertices of the
 * faces under the cursor).  The edges there, not the level's mean: a
 * coarse cage's faces differ in size by several times (blub's fins). */
static double dab_reach(st_doc *d, struct st_brush_state *bs, const double c[3])
{
    double R = d->brush.radius;
    if (!(d->brush.reach_edges > 0)) return R;
    /* A fine level (the level's mean edge far below the radius): no search
     * (the grid's cells there hold thousands of vertices each).  Local
     * edges of a cage differ from the mean by a few times, hence 8. */
    if (8 * d->brush.reach_edges * bs->edge_mean < R) return R;
    st_level_view lv;
    st_level_view_init(&d->h.map, bs->level, &lv);
    uint32_t v = grid_nearest(bs, &lv, c), x0 = v == ST_NIL ? ST_NIL : ed_vertex_dart(d, v);
    if (x0 == ST_NIL) return bs->R;
    double e = d->brush.reach_edges * vertex_edge_mean(&d->h.map, x0, bs->level);
    return e > R ? e : R;
}

/* ---- strokes -------------------------------------------------------------------------- */

int st_doc_stroke_begin(st_doc *d)
{
    return ed_stroke_begin(d, 1);
}

int ed_stroke_begin(st_doc *d, int moves_geometry)
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
    if (moves_geometry && ed_edit_budget(d, l)) return -1;
    bs->level = l;
    bs->R = st_doc_brush_reach(d);
    bs->cs = bs->R;
    /* Spacing attenuation (Blender's BRUSH_SPACE_ATTEN): fractions (pinch,
     * flatten, ...) by 1 / overlap, heights (draw, inflate, crease) so that
     * a stroke at the default spacing deposits what it did before. */
    double sp = d->brush.space_atten ? d->brush.spacing : 0;
    bs->fscale = st_brush_overlap_scale(d->brush.falloff, sp);
    bs->hscale = bs->fscale / st_brush_overlap_scale(d->brush.falloff, sp > 0 ? 0.1 : 0);
    bs->path = 0;
    bs->ndabs = 0;
    bs->fadek = 1;
    bs->outk = 1;
    /* Per-vertex arrays up to the largest id of the editing level only. */
    uint32_t nv = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        if (v + 1 > nv) nv = v + 1;
    if (bs->nv < nv) {
        bs->next = ed_xrealloc(bs->next, (size_t)nv * sizeof *bs->next);
        bs->prev = ed_xrealloc(bs->prev, (size_t)nv * sizeof *bs->prev);
        bs->vcell = ed_xrealloc(bs->vcell, (size_t)nv * sizeof *bs->vcell);
        bs->mark = ed_xrealloc(bs->mark, (size_t)nv * sizeof *bs->mark);
        bs->slot = ed_xrealloc(bs->slot, (size_t)nv * sizeof *bs->slot);
        bs->lay_o = ed_xrealloc(bs->lay_o, (size_t)nv * sizeof *bs->lay_o);
        bs->lay_n0 = ed_xrealloc(bs->lay_n0, (size_t)nv * sizeof *bs->lay_n0);
        bs->ring_at = ed_xrealloc(bs->ring_at, (size_t)nv * sizeof *bs->ring_at);
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
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->level = l;
    d->pending = s;
    d->active = 2;
    return 0;
}

static void grab_capture(st_doc *d, struct st_brush_state *bs, const double c[3], const double dn[3],
                         const double view[3], uint8_t which)
{
    grid_query(d, bs, c, dn, view);
    for (uint32_t i = 0; i < bs->ntmp; i++) {
        if (bs->ng == bs->capg) {
            bs->capg = bs->capg ? 2 * bs->capg : 256;
            bs->gv = ed_xrealloc(bs->gv, (size_t)bs->capg * sizeof *bs->gv);
            bs->gw = ed_xrealloc(bs->gw, (size_t)bs->capg * sizeof *bs->gw);
            bs->gk = ed_xrealloc(bs->gk, (size_t)bs->capg * sizeof *bs->gk);
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
    static const double up[3] = { 0, 0, 1 };
    double nn[3] = { 0, 0, 1 };
    if (normal) memcpy(nn, normal, sizeof nn);
    if (normalize3(nn)) memcpy(nn, up, sizeof nn);
    uint8_t which[8];
    unsigned nsym = symmetry_set(&d->brush, which);
    if (d->brush.tool != ST_BRUSH_GRAB || !bs->grabbed) bs->R = dab_reach(d, bs, center);
    /* Fade-in: the strength rises smoothly over the first fade * R of the
     * dab centres' path, so a crease or draw stroke starts tapered instead
     * of with a full-strength dab (ZBrush's stroke taper, Blender's
     * "stroke" tapering in its curve strokes). */
    if (bs->ndabs++) {
        double step[3] = { center[0] - bs->last_c[0], center[1] - bs->last_c[1], center[2] - bs->last_c[2] };
        double len = sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2]);
        bs->path += len;
        if (len > 0) for (int k = 0; k < 3; k++) bs->dir[k] = step[k] / len;
    } else {
        bs->dir[0] = bs->dir[1] = bs->dir[2] = 0;
    }
    memcpy(bs->last_c, center, sizeof bs->last_c);
    bs->fadek = 1;
    if (d->brush.fade > 0 && d->brush.tool != ST_BRUSH_GRAB) {
        double t = bs->path / (d->brush.fade * bs->R);
        if (t < 1) bs->fadek = 0.1 + 0.9 * t * t * (3 - 2 * t);
        bs->fadek *= bs->outk;
    }
    if (++bs->gen == 0) {
        for (uint32_t v = 0; v < bs->nv; v++) bs->mark[v] = 0;
        bs->gen = 1;
    }
    bs->nlist = 0;
    if (d->brush.tool == ST_BRUSH_GRAB) {
        if (!bs->grabbed) {
            for (unsigned s = 0; s < nsym; s++) {
                double mc[3], mn[3], mv[3];
                reflect(which[s], center, mc);
                reflect(which[s], nn, mn);
                reflect(which[s], d->brush.view_dir, mv);
                grab_capture(d, bs, mc, mn, mv, which[s]);
            }
            bs->grabbed = 1;
        }
        double g[3] = { 0, 0, 0 };
        if (grab_delta) memcpy(g, grab_delta, sizeof g);
        for (uint32_t i = 0; i < bs->ng; i++) {
            double dd[3];
            reflect(bs->gk[i], g, dd);
            double dv[3] = { bs->gw[i] * dd[0], bs->gw[i] * dd[1], bs->gw[i] * dd[2] };
            ed_brush_acc(bs, bs->gv[i], dv);
        }
    } else {
        for (unsigned s = 0; s < nsym; s++) {
            double mc[3], mn[3], mv[3];
            reflect(which[s], center, mc);
            reflect(which[s], nn, mn);
            reflect(which[s], d->brush.view_dir, mv);
            reflect(which[s], bs->dir, bs->dab_dir);
            grid_query(d, bs, mc, mn, mv);
            if (bs->ntmp) ed_brush_tool_dab(d, bs, mc, mn);
        }
        if (d->brush.tool == ST_BRUSH_LAYER) layer_finish(d, bs);
        int smoother = d->brush.tool == ST_BRUSH_SMOOTH || d->brush.tool == ST_BRUSH_RELAX;
        if (!smoother && d->brush.autosmooth > 0) autosmooth(d, bs, fmin(d->brush.autosmooth, 1));
        if (d->brush.hold) hold_faces(d, bs);
        if (d->brush.tool == ST_BRUSH_LAYER && (d->brush.hold || d->brush.autosmooth > 0)) layer_settle(d, bs);
    }
    if (!bs->nlist) return 0;
    uint32_t *darts = ed_xrealloc(NULL, (size_t)bs->nlist * sizeof *darts);
    double(*pos)[3] = ed_xrealloc(NULL, (size_t)bs->nlist * sizeof *pos);
    uint32_t n = 0;
    for (uint32_t i = 0; i < bs->nlist; i++) {
        uint32_t v = bs->list[i], x = ed_vertex_dart(d, v);
        /* The mask attenuates the dab: displacement times 1 - mask; a fully
         * masked vertex is left out, so it stays the same to the bit. */
        double keep = 1.0 - (double)st_mask_get(&d->mask, v);
        if (x == ST_NIL || !(keep > 0)) continue;
        if (!bs->disp[i][0] && !bs->disp[i][1] && !bs->disp[i][2]) continue;
        const double *p = st_pos(&h->map, v, l);
        for (int k = 0; k < 3; k++) pos[n][k] = p[k] + keep * bs->disp[i][k];
        darts[n++] = x;
    }
    if (n) {
        /* Old values of what core will write (also the layers'), then the
         * edit, which reports what it wrote for the display and the renderer. */
        uint32_t from = d->fp_model.n;
        ed_model_edit(d, d->pending, l, darts, (const double(*)[3])pos, n);
        for (uint32_t i = 0; i < n; i++) {
            uint32_t v = st_vert(&h->map, darts[i], l);
            grid_insert(bs, v, st_pos(&h->map, v, l));
        }
        ed_geometry_changed(d, l, darts, n, t0, from);
    }
    free(darts);
    free(pos);
    return 0;
}

uint32_t ed_brush_query(st_doc *d, const double c[3], double R, const uint32_t **vids, const double **w)
{
    struct st_brush_state *bs = d->bs;
    if (!bs || !d->active) return 0;
    /* The weights are those of every brush (falloff preset, strength,
     * front faces only); R is the brush radius grid_query reads. */
    (void)R;
    static const double up[3] = { 0, 0, 1 };
    grid_query(d, bs, c, up, d->brush.view_dir);
    *vids = bs->tmp;
    *w = bs->tmpw;
    return bs->ntmp;
}

void st_doc_stroke_fade_out(st_doc *d, double k)
{
    if (d->active == 2 && d->bs) d->bs->outk = k < 0 ? 0 : k > 1 ? 1 : k;
}

void st_doc_stroke_end(st_doc *d)
{
    st_undo_step *s = ed_take_pending(d, 2);
    if (s) ed_push_edit(d, s);
}
