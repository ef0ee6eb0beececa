/* The sculpting kernels through their public API (core/sculpt/sculpt.h),
 * with no document: one dab of each tool on a small hierarchy.
 *
 *   - only vertices strictly inside the dab's radius move (raw brush: no
 *     auto-smooth, no hold, so nothing reaches past the weights);
 *   - strength 0 moves nothing, to the bit;
 *   - a mask of 1 blocks a vertex, to the bit, and 0 leaves it free;
 *   - with mirror_x on a mesh symmetric about x = 0, the displacement of
 *     each vertex's mirror partner is the mirror of its own;
 *   - on a sphere-like mesh (Loop on an icosahedron), a stroke of each tool
 *     at strength 1 with the hold flips no face: every face's normal after
 *     the stroke has a positive dot with its normal before.
 *
 * The mesh: the icosahedron of testlib (centred, symmetric about the three
 * coordinate planes), Loop, level 2 (162 vertices) or 3 (642), edited at
 * the top level. */
#include "core/multires/hier.h"
#include "core/multires/mask.h"
#include "core/sculpt/sculpt.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct snap {
    uint32_t nv;               /* largest vertex id of the level + 1 */
    uint8_t *in;               /* per id: a vertex of the level */
    double (*p)[3];            /* per id: its position */
} snap;

static void snap_take(const st_hier *h, unsigned l, snap *s)
{
    const st_map *m = &h->map;
    st_dart_iter it;
    s->nv = 0;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it))
        if (v + 1 > s->nv) s->nv = v + 1;
    s->in = calloc(s->nv, 1);
    s->p = calloc(s->nv, sizeof *s->p);
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
        s->in[v] = 1;
        memcpy(s->p[v], st_pos(m, v, l), sizeof s->p[v]);
    }
}

static void snap_free(snap *s)
{
    free(s->in);
    free(s->p);
}

static double dist3(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static int moved(const st_hier *h, unsigned l, const snap *s, uint32_t v)
{
    return memcmp(st_pos(&h->map, v, l), s->p[v], sizeof s->p[v]) != 0;
}

/* The vertex of level l that maximises dot(p, dir). */
static uint32_t extreme(const st_hier *h, unsigned l, const double dir[3])
{
    st_dart_iter it;
    uint32_t best = ST_NIL;
    double bd = -INFINITY;
    for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
        const double *p = st_pos(&h->map, v, l);
        double d = p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2];
        if (d > bd) { bd = d; best = v; }
    }
    return best;
}

/* A raw brush (st_sculpt_brush all zero but these). */
static st_sculpt_brush raw_brush(int tool, double radius, double strength)
{
    st_sculpt_brush b;
    memset(&b, 0, sizeof b);
    b.tool = tool;
    b.radius = radius;
    b.strength = strength;
    b.falloff = ST_FALLOFF_SMOOTH;
    return b;
}

/* A dab at vertex v of level l, its normal the direction from the centre. */
static st_sculpt_dab dab_at(const st_hier *h, unsigned l, uint32_t v)
{
    st_sculpt_dab d;
    memset(&d, 0, sizeof d);
    memcpy(d.center, st_pos(&h->map, v, l), sizeof d.center);
    memcpy(d.normal, d.center, sizeof d.normal); /* normalised by the kernel */
    d.fade = 1;
    d.grab_delta[0] = 0.05;
    d.grab_delta[1] = 0.1;
    d.grab_delta[2] = -0.02;
    return d;
}

static void one_dab(st_hier *h, unsigned l, const st_sculpt_brush *b, const st_sculpt_dab *d, const st_mask *mask,
                    uint32_t *n)
{
    st_sculpt *s = st_sculpt_new();
    st_sculpt_stroke st = { .level = l };
    st_sculpt_begin(s, &h->map, b, &st);
    CHECK(st_sculpt_dab_radius(s, &h->map, b, d->center) == b->radius);
    *n = st_sculpt_dab_apply(s, h, b, d, mask, NULL);
    st_sculpt_free(s);
}

/* Only vertices inside the radius move; each tool moves some; strength 0
 * moves none. */
static void test_radius_and_strength(void)
{
    unsigned l = 2;
    static const double up[3] = { 0.3, 1, 0.2 };
    for (int t = 0; t < ST_BRUSH_COUNT; t++) {
        for (int zero = 0; zero < 2; zero++) {
            st_hier h;
            tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, l);
            snap s;
            snap_take(&h, l, &s);
            uint32_t c = extreme(&h, l, up);
            st_sculpt_brush b = raw_brush(t, 0.9, zero ? 0 : 0.5);
            st_sculpt_dab d = dab_at(&h, l, c);
            uint32_t n;
            one_dab(&h, l, &b, &d, NULL, &n);
            unsigned nmoved = 0, outside = 0;
            for (uint32_t v = 0; v < s.nv; v++) {
                if (!s.in[v] || !moved(&h, l, &s, v)) continue;
                nmoved++;
                if (!(dist3(s.p[v], d.center) < b.radius)) outside++;
            }
            if (zero) {
                CHECKF(n == 0 && nmoved == 0, "%d at strength 0: %u reported, %u moved", t, n, nmoved);
            } else {
                /* reported: a non-zero displacement; relax's on this
                 * near-regular mesh can be below the positions' rounding */
                CHECKF(nmoved > 0 && nmoved <= n, "%d: %u reported, %u moved", t, n, nmoved);
                CHECKF(outside == 0, "%d: %u vertices outside the radius moved", t, outside);
            }
            snap_free(&s);
            st_hier_free(&h);
        }
    }
}

/* A mask of 1 on the vertices with x > 0 keeps them to the bit; the others
 * under the dab move. */
static void test_mask(void)
{
    unsigned l = 2;
    static const double up[3] = { 0, 1, 0 };
    for (int t = 0; t < ST_BRUSH_COUNT; t++) {
        st_hier h;
        tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, l);
        snap s;
        snap_take(&h, l, &s);
        st_mask mask = { 0 };
        for (uint32_t v = 0; v < s.nv; v++)
            if (s.in[v] && s.p[v][0] > 0) st_mask_set(&mask, v, 1.0f);
        uint32_t c = extreme(&h, l, up);
        st_sculpt_brush b = raw_brush(t, 1.2, 0.5);
        st_sculpt_dab d = dab_at(&h, l, c);
        uint32_t n;
        one_dab(&h, l, &b, &d, &mask, &n);
        unsigned masked_moved = 0, free_moved = 0;
        for (uint32_t v = 0; v < s.nv; v++) {
            if (!s.in[v] || !moved(&h, l, &s, v)) continue;
            if (s.p[v][0] > 0) masked_moved++;
            else free_moved++;
        }
        CHECKF(masked_moved == 0, "%d: %u masked vertices moved", t, masked_moved);
        CHECKF(free_moved > 0 && free_moved <= n, "%d: %u unmasked moved, %u reported", t, free_moved, n);
        st_mask_free(&mask);
        snap_free(&s);
        st_hier_free(&h);
    }
}

/* Mirror across x = 0: the partner of each vertex (its reflection, found
 * by position) gets the reflected displacement. */
static void test_symmetry(void)
{
    unsigned l = 2;
    static const double at[3] = { 0.6, 1, 0.3 };
    for (int t = 0; t < ST_BRUSH_COUNT; t++) {
        st_hier h;
        tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, l);
        snap s;
        snap_take(&h, l, &s);
        uint32_t c = extreme(&h, l, at);
        st_sculpt_brush b = raw_brush(t, 0.9, 0.5);
        b.mirror_x = 1;
        st_sculpt_dab d = dab_at(&h, l, c);
        uint32_t n;
        one_dab(&h, l, &b, &d, NULL, &n);
        unsigned pos = 0, neg = 0, nopartner = 0;
        double worst = 0;
        for (uint32_t v = 0; v < s.nv; v++) {
            if (!s.in[v]) continue;
            double q[3] = { -s.p[v][0], s.p[v][1], s.p[v][2] };
            uint32_t w = ST_NIL;
            double wd = INFINITY;
            for (uint32_t u = 0; u < s.nv; u++)
                if (s.in[u] && dist3(s.p[u], q) < wd) { wd = dist3(s.p[u], q); w = u; }
            if (!(wd < 1e-9)) { nopartner++; continue; }
            const double *pv = st_pos(&h.map, v, l), *pw = st_pos(&h.map, w, l);
            double dv[3], dw[3];
            for (int k = 0; k < 3; k++) { dv[k] = pv[k] - s.p[v][k]; dw[k] = pw[k] - s.p[w][k]; }
            dw[0] = -dw[0];
            worst = fmax(worst, dist3(dv, dw));
            /* moved by more than rounding (relax's tangential steps are tiny here) */
            if (sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]) > 1e-12) {
                if (s.p[v][0] > 1e-12) pos++;
                else if (s.p[v][0] < -1e-12) neg++;
            }
        }
        CHECKF(nopartner == 0, "%d: %u vertices without a mirror partner", t, nopartner);
        CHECKF(pos > 0 && pos == neg, "%d: %u moved at x > 0, %u at x < 0", t, pos, neg);
        CHECKF(worst < 1e-12, "%d: mirrored displacements differ by %g", t, worst);
        snap_free(&s);
        st_hier_free(&h);
    }
}

/* Newell normals of the surface faces of level l, one per face (its dart of
 * least id), in dart order. */
static uint32_t face_normals(const st_hier *h, unsigned l, double (**out)[3])
{
    const st_map *m = &h->map;
    uint32_t n = 0, cap = 256;
    double (*nr)[3] = malloc(cap * sizeof *nr);
    st_dart_iter it;
    for (uint32_t x = st_dart_first(m, l, &it); x != ST_NIL; x = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, x)) continue;
        int least = 1;
        for (uint32_t y = st_phi1(m, x, l); y != x; y = st_phi1(m, y, l))
            if (y < x) { least = 0; break; }
        if (!least) continue;
        if (n == cap) nr = realloc(nr, (cap *= 2) * sizeof *nr);
        double *f = nr[n++];
        f[0] = f[1] = f[2] = 0;
        uint32_t y = x;
        do {
            uint32_t z = st_phi1(m, y, l);
            const double *p = st_dart_pos(m, y, l), *q = st_dart_pos(m, z, l);
            f[0] += (p[1] - q[1]) * (p[2] + q[2]);
            f[1] += (p[2] - q[2]) * (p[0] + q[0]);
            f[2] += (p[0] - q[0]) * (p[1] + q[1]);
            y = z;
        } while (y != x);
    }
    *out = nr;
    return n;
}

/* A stroke of 30 dabs along an arc over the top of the sphere, every tool
 * but grab at strength 1, the options the window has on by default (area
 * plane, auto-smooth, the hold, mirror in x): no face flips. */
static void test_no_flip(void)
{
    unsigned l = 3;
    for (int t = 0; t < ST_BRUSH_COUNT; t++) {
        if (t == ST_BRUSH_GRAB) continue;
        for (int inv = 0; inv < 2; inv++) {
            st_hier h;
            tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, l);
            double (*n0)[3];
            uint32_t nf = face_normals(&h, l, &n0);
            st_sculpt_brush b = raw_brush(t, 0.7, 1.0);
            b.invert = inv;
            b.area_plane = 1;
            b.hold = 1;
            b.autosmooth = 0.15;
            b.mirror_x = 1;
            b.fade = 1;
            st_sculpt *s = st_sculpt_new();
            st_sculpt_stroke st = { .level = l };
            st_sculpt_begin(s, &h.map, &b, &st);
            double last[3] = { 0, 0, 0 };
            for (int i = 0; i < 30; i++) {
                double a = -0.8 + 1.6 * i / 29, dir[3] = { sin(a) * 0.7, cos(a), 0.4 };
                st_sculpt_dab d = dab_at(&h, l, extreme(&h, l, dir));
                st_sculpt_dab_radius(s, &h.map, &b, d.center);
                double step = dist3(d.center, last);
                if (i && step > 0)
                    for (int k = 0; k < 3; k++) d.dir[k] = (d.center[k] - last[k]) / step;
                memcpy(last, d.center, sizeof last);
                st_sculpt_dab_apply(s, &h, &b, &d, NULL, NULL);
            }
            st_sculpt_free(s);
            double (*n1)[3];
            uint32_t nf1 = face_normals(&h, l, &n1);
            CHECK(nf1 == nf);
            unsigned flipped = 0;
            for (uint32_t f = 0; f < nf && f < nf1; f++)
                if (!(n0[f][0] * n1[f][0] + n0[f][1] * n1[f][1] + n0[f][2] * n1[f][2] > 0)) flipped++;
            CHECKF(flipped == 0, "%d%s: %u of %u faces flipped", t, inv ? " inverted" : "", flipped, nf);
            free(n0);
            free(n1);
            st_hier_free(&h);
        }
    }
}

/* The falloff presets and the query: what a dab takes in is exactly the
 * vertices inside the radius, weighted by falloff times strength. */
static void test_query(void)
{
    unsigned l = 2;
    st_hier h;
    tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, l);
    static const double up[3] = { 0, 1, 0 };
    uint32_t c = extreme(&h, l, up);
    st_sculpt_brush b = raw_brush(ST_BRUSH_DRAW, 1.1, 0.5);
    b.falloff = ST_FALLOFF_LINEAR;
    st_sculpt *s = st_sculpt_new();
    st_sculpt_stroke st = { .level = l };
    st_sculpt_begin(s, &h.map, &b, &st);
    const double *cp = st_pos(&h.map, c, l), view[3] = { 0, 0, 0 };
    const uint32_t *vids;
    const double *w;
    uint32_t n = st_sculpt_query(s, &h.map, &b, cp, view, &vids, &w);
    unsigned inside = 0, bad = 0;
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it))
        if (dist3(st_pos(&h.map, v, l), cp) < b.radius) inside++;
    for (uint32_t i = 0; i < n; i++) {
        double r = dist3(st_pos(&h.map, vids[i], l), cp);
        if (!(fabs(w[i] - 0.5 * st_falloff_eval(ST_FALLOFF_LINEAR, r, b.radius)) < 1e-15)) bad++;
    }
    CHECKF(n == inside && n > 0, "query: %u, inside: %u", n, inside);
    CHECK(bad == 0);
    st_sculpt_free(s);
    st_hier_free(&h);
}

int main(void)
{
    test_radius_and_strength();
    test_mask();
    test_symmetry();
    test_no_flip();
    test_query();
    return tl_report(__FILE__);
}
