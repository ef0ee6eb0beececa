/* bench_transfer: how far a coarse edit reaches the finest level (issue 30,
 * point 2), on subdivision and progressive hierarchies.
 *
 *   bench_transfer [--centres N] [--koala PATH] [--no-cc] [--predictor P] [--no-koala]
 *
 * A bump applied at level L through st_hier_edit (the core path of the
 * window's drag and brushes): every vertex v of level L moves by
 * D exp(-|v - C|^2 / R^2), C a vertex of level L, D along the level-L
 * normal at C with |D| one mean edge length of level L.  Two bumps:
 *   smooth: R = 3 mean edge lengths of level L;
 *   single: R = 0.2 mean edge lengths (C alone moves).
 * Printed per bump, averaged over N centres (vertices of level L spread
 * over the id range, none on a hole):
 *   peak: the largest displacement of a finest-level vertex over |D|;
 *   rms:  the RMS, over the finest vertices w where the field at w's
 *         original position exceeds 5 % of |D|, of |disp(w) - field(w)|/|D|.
 * Surfaces: the Catmull-Clark hierarchy of spot_quadrangulated.obj
 * subdivided 3 times and then unsubdivided 3 steps (st_unsubdivide), the
 * progressive hierarchy of the same dense surface (fanned into triangles by
 * the build), and koala's progressive hierarchy, both simplified to 1 % of
 * their faces (17 levels, as issue 30 measured).
 * Levels: 0, the middle one and the one below the top.  Each edit is undone
 * from its footprint (st_hier_restore) before the next. */
#include "bench_common.h"
#include "core/io/mesh.h"
#include "core/map/map.h"
#include "core/multires/edit.h"
#include "core/multires/hier.h"
#include "core/progressive/progressive.h"
#include "core/rebuild/unsubdivide.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct bump_result { double peak, rms; } bump_result;

static void *xcalloc(size_t n, size_t s)
{
    void *p = calloc(n ? n : 1, s);
    if (!p) { fprintf(stderr, "bench_transfer: out of memory\n"); exit(1); }
    return p;
}

static double dist2(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return x * x + y * y + z * z;
}

/* Mean length of the edges of level l (each edge seen from both darts;
 * hole darts left out). */
static double mean_edge(const st_map *m, unsigned l)
{
    double s = 0;
    uint64_t n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d)) continue;
        s += sqrt(dist2(st_dart_pos(m, d, l), st_dart_pos(m, st_beta0(m, d, l), l)));
        n++;
    }
    return n ? s / (double)n : 0;
}

/* A dart per vertex of level l (the smallest), ST_NIL elsewhere; vertices
 * touching a hole get ST_NIL too (centres are chosen inside). */
static uint32_t *vertex_darts(const st_map *m, unsigned l, int skip_border)
{
    uint32_t *vd = xcalloc(m->verts.end, sizeof *vd);
    uint8_t *border = xcalloc(m->verts.end, 1);
    for (uint32_t v = 0; v < m->verts.end; v++) vd[v] = ST_NIL;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        uint32_t v = st_vert(m, d, l);
        if (d < vd[v]) vd[v] = d;
        if (st_is_boundary(m, d)) border[v] = 1;
    }
    for (uint32_t v = 0; skip_border && v < m->verts.end; v++)
        if (border[v]) vd[v] = ST_NIL;
    free(border);
    return vd;
}

/* One bump at level l centred on vertex c, measured at the top level and
 * undone. */
static bump_result bump(st_hier *h, unsigned l, uint32_t c, const uint32_t *vd, double edge, double rfac)
{
    st_map *m = &h->map;
    unsigned top = m->top;
    double C[3], f[3][3], D[3], R2 = (rfac * edge) * (rfac * edge);
    memcpy(C, st_pos(m, c, l), sizeof C);
    st_hier_frame(h, l, vd[c], ST_CELL_VERTEX, f);
    for (int i = 0; i < 3; i++) D[i] = edge * f[2][i];
    /* the moved vertices of level l */
    uint32_t n = 0, cap = 1024;
    uint32_t *darts = xcalloc(cap, sizeof *darts);
    double (*pos)[3] = xcalloc(cap, sizeof *pos);
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(m, l, &it); v != ST_NIL; v = st_vertex_next(m, l, &it)) {
        const double *p = st_pos(m, v, l);
        double w = exp(-dist2(p, C) / R2);
        if (w < 1e-12 || vd[v] == ST_NIL) continue;
        if (n == cap) {
            cap *= 2;
            darts = realloc(darts, cap * sizeof *darts);
            pos = realloc(pos, cap * sizeof *pos);
            if (!darts || !pos) { fprintf(stderr, "bench_transfer: out of memory\n"); exit(1); }
        }
        darts[n] = vd[v];
        for (int i = 0; i < 3; i++) pos[n][i] = p[i] + w * D[i];
        n++;
    }
    /* the finest positions before, and the old values of the footprint */
    double *before = xcalloc(3 * (size_t)m->verts.end, sizeof *before);
    for (uint32_t v = st_vertex_first(m, top, &it); v != ST_NIL; v = st_vertex_next(m, top, &it))
        memcpy(before + 3 * (size_t)v, st_pos(m, v, top), 3 * sizeof(double));
    st_footprint fp = { 0 };
    st_hier_edit_footprint(h, l, darts, n, &fp);
    double (*old)[3] = xcalloc(fp.n, sizeof *old);
    for (uint32_t k = 0; k < fp.n; k++) st_hier_value(h, fp.keys[k], old[k]);
    st_hier_edit(h, l, darts, (const double(*)[3])pos, n, NULL);
    double amp = edge, peak = 0, se = 0;
    uint64_t ne = 0;
    for (uint32_t v = st_vertex_first(m, top, &it); v != ST_NIL; v = st_vertex_next(m, top, &it)) {
        const double *b = before + 3 * (size_t)v, *a = st_pos(m, v, top);
        double disp[3] = { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
        double len = sqrt(disp[0] * disp[0] + disp[1] * disp[1] + disp[2] * disp[2]);
        if (len > peak) peak = len;
        double w = exp(-dist2(b, C) / R2);
        if (w <= 0.05) continue;
        double e2 = 0;
        for (int i = 0; i < 3; i++) e2 += (disp[i] - w * D[i]) * (disp[i] - w * D[i]);
        se += e2;
        ne++;
    }
    st_hier_restore(h, fp.keys, (const double(*)[3])old, fp.n, NULL);
    st_footprint_free(&fp);
    free(old);
    free(before);
    free(darts);
    free(pos);
    return (bump_result){ peak / amp, ne ? sqrt(se / (double)ne) / amp : 0 };
}

/* Mean over ncentres vertices of level l spread over the id range. */
static void measure_level(st_hier *h, const char *name, unsigned l, unsigned ncentres)
{
    st_map *m = &h->map;
    uint32_t *vd = vertex_darts(m, l, 0), *inner = vertex_darts(m, l, 1);
    uint32_t nv = 0;
    for (uint32_t v = 0; v < m->verts.end; v++) nv += inner[v] != ST_NIL;
    double edge = mean_edge(m, l);
    bump_result smooth = { 0, 0 }, single = { 0, 0 };
    double single_min = INFINITY;
    unsigned k = 0;
    uint32_t seen = 0, stride = nv / ncentres ? nv / ncentres : 1;
    for (uint32_t v = 0; v < m->verts.end && k < ncentres; v++) {
        if (inner[v] == ST_NIL) continue;
        if (seen++ % stride != stride / 2) continue;
        bump_result a = bump(h, l, v, vd, edge, 3.0), b = bump(h, l, v, vd, edge, 0.2);
        smooth.peak += a.peak;
        smooth.rms += a.rms;
        single.peak += b.peak;
        if (b.peak < single_min) single_min = b.peak;
        k++;
    }
    if (k) {
        smooth.peak /= k;
        smooth.rms /= k;
        single.peak /= k;
    }
    printf("%-26s L=%2u/%-2u %8u verts  smooth: peak %.3f rms %.4f   single: peak %.3f (min %.3f)  [%u centres]\n", name, l,
           m->top, nv, smooth.peak, smooth.rms, single.peak, single_min, k);
    fflush(stdout);
    free(vd);
    free(inner);
}

static void measure(st_hier *h, const char *name, unsigned ncentres)
{
    unsigned top = h->map.top;
    unsigned levels[3] = { 0, top / 2, top - 1 };
    for (unsigned i = 0; i < 3; i++) {
        if (i && levels[i] == levels[i - 1]) continue;
        measure_level(h, name, levels[i], ncentres);
    }
}

static int load(const char *path, st_mesh *m)
{
    st_error err;
    if (st_mesh_load(path, m, &err) || st_mesh_repair(path, m, NULL, &err)) {
        fprintf(stderr, "bench_transfer: %s: %s\n", path, err.msg);
        return 1;
    }
    return 0;
}

static int progressive(const st_mesh *fine, st_hier *h, const char *name, int predictor)
{
    st_error err;
    st_progressive_opts o = { .target_faces = fine->nfaces / 100, .predictor = predictor };
    st_progressive_report rep;
    double t0 = bench_now();
    if (st_progressive_build(fine, &o, h, &rep, &err)) {
        fprintf(stderr, "bench_transfer: %s: %s\n", name, err.msg);
        return 1;
    }
    printf("%s, predictor %s: progressive build %.2f s, %u levels, %llu -> %llu vertices\n", name,
           predictor == ST_PM_LIGHT ? "light (1/8)" : predictor == ST_PM_GRADED ? "graded (1/2 on the 2 finest, 1/10 below)" : "relaxed (1/2)", bench_now() - t0, rep.levels,
           (unsigned long long)rep.vertices[0], (unsigned long long)rep.vertices[rep.levels - 1]);
    return 0;
}

int main(int argc, char **argv)
{
    unsigned ncentres = 4;
    int cc_too = 1, only = -1, koala_too = 1;
    char koala[1024];
    snprintf(koala, sizeof koala, "%s/large/koala.obj", STRATA_SHARED_DATA);
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--centres") && i + 1 < argc) ncentres = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--koala") && i + 1 < argc) snprintf(koala, sizeof koala, "%s", argv[++i]);
        else if (!strcmp(argv[i], "--no-cc")) cc_too = 0; /* the progressive hierarchies only */
        else if (!strcmp(argv[i], "--no-koala")) koala_too = 0;
        else if (!strcmp(argv[i], "--predictor") && i + 1 < argc) only = atoi(argv[++i]); /* that one only */
        else {
            fprintf(stderr, "usage: bench_transfer [--centres N] [--koala PATH] [--no-cc] [--predictor P] [--no-koala]\n");
            return 2;
        }
    }
    if (ncentres == 0) ncentres = 1;
    char spot[1024];
    snprintf(spot, sizeof spot, "%s/catmull_clark/spot_quadrangulated.obj", STRATA_SHARED_DATA);
    st_error err;
    st_mesh cage, fine;
    st_mesh_init(&fine);
    if (load(spot, &cage)) return 1;
    /* the dense surface: the cage subdivided three times */
    st_hier sub;
    if (st_hier_init(&sub, &cage, st_scheme_find("catmull-clark"), NULL, &err) || st_hier_subdivide_to(&sub, 3, &err) ||
        st_hier_level_mesh(&sub, 3, &fine, &err)) {
        fprintf(stderr, "bench_transfer: spot: %s\n", err.msg);
        return 1;
    }
    st_hier_free(&sub);
    if (st_mesh_repair("spot x3", &fine, NULL, &err)) { fprintf(stderr, "bench_transfer: %s\n", err.msg); return 1; }
    /* its Catmull-Clark hierarchy, found back by unsubdivision */
    st_unsub u;
    st_hier cc, pm;
    st_unsub_opts uo = { .max_levels = 3 };
    if (cc_too && (st_unsubdivide("spot x3", &fine, &uo, &u, &err) ||
        st_unsub_build_hier(&fine, &u, st_scheme_find("catmull-clark"), NULL, &cc, NULL, NULL, &err))) {
        fprintf(stderr, "bench_transfer: spot x3: %s\n", err.msg);
        return 1;
    }
    if (cc_too) {
        st_unsub_free(&u);
        printf("spot x3: %u faces, Catmull-Clark hierarchy of %u levels\n", fine.nfaces, cc.map.top + 1);
        measure(&cc, "spot x3 catmull-clark", ncentres);
        st_hier_free(&cc);
    }
    static const char *const spot_names[] = { "spot x3 progressive", "spot x3 progressive light", "spot x3 progressive graded" };
    static const char *const koala_names[] = { "koala progressive", "koala progressive light", "koala progressive graded" };
    for (int p = 0; p < 3; p++) {
        if (only >= 0 && p != only) continue;
        if (progressive(&fine, &pm, "spot x3 triangulated", p)) return 1;
        measure(&pm, spot_names[p], ncentres);
        st_hier_free(&pm);
    }
    st_mesh_free(&fine);
    st_mesh_free(&cage);
    if (!koala_too) return 0;
    st_mesh k;
    if (load(koala, &k)) return 1;
    for (int p = 0; p < 3; p++) {
        if (only >= 0 && p != only) continue;
        if (progressive(&k, &pm, "koala", p)) return 1;
        measure(&pm, koala_names[p], ncentres);
        st_hier_free(&pm);
    }
    st_mesh_free(&k);
    return 0;
}
