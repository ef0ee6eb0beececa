// bench_progressive: Strata's progressive hierarchy (core/progressive) against
// OpenMesh's Decimater (quadric module) and meshoptimizer's meshopt_simplify,
// in one process, on the same input down to the same face count.
//
//   bench_progressive [MESH...] [--percent P] [--repeat N] [--edits-only]
//
// Default meshes: large/koala.obj (100k triangles) and
// large/sword_quad_dominant.obj (22k faces, 98 % quads, fanned into 44.6k
// triangles for all three).  After the comparison, on Strata's hierarchy:
// a one-vertex edit of levels 0, 2, 4, 6, 8, 10 and 12 (local re-synthesis,
// st_hier_move: positions written, changed, and changed by more than 1e-6
// of the edit's move) against the full synthesis of the levels above, with
// the lower bound of any local edit that keeps the full synthesis's bits:
// the fraction of the positions above the level that change (it must write
// them all; the GSS99 relaxation widens the support by two rings a level),
// beside the fraction it writes, and the ratio local / full / bound both
// after a full synthesis (cold cache: the timed edit) and right after another
// edit of the same vertex (warm); and the interest box's selective display
// (update time, faces shown).
//
// Prints, for each: time (median of N), peak memory (each run once more in a
// forked child: its peak RSS above the RSS it started with), the face count
// reached, and the two-sided Hausdorff and RMS distances between the result
// and the input relative to the bounding-box diagonal (points: every vertex
// and centroid of the input, and 16 barycentric samples per triangle of
// the result, each to the closest point of the other surface).
extern "C" {
#include "bench_common.h"
#include "core/io/mesh.h"
#include "core/progressive/progressive_internal.h"
#include "core/map/map.h"
#include "core/adapt/adapt.h"
#include "core/multires/edit.h"
}

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <meshoptimizer.h>

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

typedef OpenMesh::TriMesh_ArrayKernelT<> OMesh;

struct Tri { std::vector<double> pos; std::vector<uint32_t> idx; };

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static long rss_kib(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = 0, res = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &pages, &res) != 2) res = 0;
        fclose(f);
    }
    return res * (sysconf(_SC_PAGESIZE) / 1024);
}

// ---- the three simplifiers ---------------------------------------------------------

static Tri run_strata(const st_mesh *m, uint64_t target, st_progressive_report *rep)
{
    st_hier h;
    st_error err;
    st_progressive_opts o = {};
    o.target_faces = target;
    o.predictor = ST_PM_DEFAULT; /* what new builds use (progressive.h, point 5) */
    o.fit_coarse = 1;            /* and level 0 placed (point 8), as st_rebuild builds */
    Tri t;
    if (st_progressive_build(m, &o, &h, rep, &err)) {
        fprintf(stderr, "strata: %s\n", err.msg);
        return t;
    }
    st_mesh c;
    st_mesh_init(&c);
    if (st_hier_level_mesh(&h, 0, &c, &err) == ST_OK) {
        t.pos.assign(c.pos, c.pos + 3 * (size_t)c.nverts);
        t.idx.assign(c.face_idx, c.face_idx + c.face_off[c.nfaces]);
    }
    st_mesh_free(&c);
    st_hier_free(&h);
    return t;
}

static Tri run_openmesh(const st_mesh *m, uint64_t target)
{
    OMesh mesh;
    std::vector<OMesh::VertexHandle> vh(m->nverts);
    for (uint32_t v = 0; v < m->nverts; v++)
        vh[v] = mesh.add_vertex(OMesh::Point((float)m->pos[3 * v], (float)m->pos[3 * v + 1], (float)m->pos[3 * v + 2]));
    for (uint32_t f = 0; f < m->nfaces; f++) {
        const uint32_t *i = m->face_idx + m->face_off[f];
        mesh.add_face(vh[i[0]], vh[i[1]], vh[i[2]]);
    }
    OpenMesh::Decimater::DecimaterT<OMesh> dec(mesh);
    OpenMesh::Decimater::ModQuadricT<OMesh>::Handle hq;
    dec.add(hq);
    dec.module(hq).unset_max_err();
    dec.initialize();
    dec.decimate_to_faces(0, target);
    mesh.garbage_collection();
    Tri t;
    for (auto v : mesh.vertices()) {
        OMesh::Point p = mesh.point(v);
        t.pos.push_back(p[0]); t.pos.push_back(p[1]); t.pos.push_back(p[2]);
    }
    for (auto f : mesh.faces())
        for (auto v : mesh.fv_range(f)) t.idx.push_back((uint32_t)v.idx());
    return t;
}

static Tri run_meshopt(const st_mesh *m, uint64_t target)
{
    std::vector<float> p(3 * (size_t)m->nverts);
    for (size_t i = 0; i < p.size(); i++) p[i] = (float)m->pos[i];
    std::vector<unsigned> in(m->face_idx, m->face_idx + m->face_off[m->nfaces]), out(in.size());
    size_t n = meshopt_simplify(out.data(), in.data(), in.size(), p.data(), m->nverts, 3 * sizeof(float),
                                3 * (size_t)target, FLT_MAX, 0, nullptr);
    Tri t;
    t.pos.assign(m->pos, m->pos + 3 * (size_t)m->nverts);
    t.idx.assign(out.begin(), out.begin() + (long)n);
    return t;
}

// ---- distances: closest point on a triangle set through a uniform grid --------------

static void closest_on_tri(const double *p, const double *a, const double *b, const double *c, double *q)
{
    // Ericson, Real-Time Collision Detection §5.1.5.
    double ab[3], ac[3], ap[3];
    for (int i = 0; i < 3; i++) { ab[i] = b[i] - a[i]; ac[i] = c[i] - a[i]; ap[i] = p[i] - a[i]; }
    auto dot = [](const double *x, const double *y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) { memcpy(q, a, 24); return; }
    double bp[3];
    for (int i = 0; i < 3; i++) bp[i] = p[i] - b[i];
    double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) { memcpy(q, b, 24); return; }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { double v = d1 / (d1 - d3); for (int i = 0; i < 3; i++) q[i] = a[i] + v * ab[i]; return; }
    double cp[3];
    for (int i = 0; i < 3; i++) cp[i] = p[i] - c[i];
    double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) { memcpy(q, c, 24); return; }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { double w = d2 / (d2 - d6); for (int i = 0; i < 3; i++) q[i] = a[i] + w * ac[i]; return; }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int i = 0; i < 3; i++) q[i] = b[i] + w * (c[i] - b[i]);
        return;
    }
    double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den;
    for (int i = 0; i < 3; i++) q[i] = a[i] + ab[i] * v + ac[i] * w;
}

struct Grid {
    const Tri *t;
    double lo[3], cell;
    int n[3];
    std::vector<uint32_t> start, items;
    explicit Grid(const Tri *tri) : t(tri)
    {
        size_t nt = t->idx.size() / 3;
        double hi[3];
        for (int k = 0; k < 3; k++) { lo[k] = DBL_MAX; hi[k] = -DBL_MAX; }
        for (size_t v = 0; v < t->pos.size() / 3; v++)
            for (int k = 0; k < 3; k++) { lo[k] = std::min(lo[k], t->pos[3 * v + k]); hi[k] = std::max(hi[k], t->pos[3 * v + k]); }
        double vol = 1;
        for (int k = 0; k < 3; k++) vol *= std::max(hi[k] - lo[k], 1e-9);
        cell = std::cbrt(vol / std::max<double>(1, (double)nt)) * 1.5;
        for (int k = 0; k < 3; k++) n[k] = std::max(1, (int)std::ceil((hi[k] - lo[k]) / cell) + 1);
        size_t ncell = (size_t)n[0] * n[1] * n[2];
        start.assign(ncell + 1, 0);
        for (int pass = 0; pass < 2; pass++) {
            if (pass) {
                for (size_t c = 0; c < ncell; c++) start[c + 1] += start[c];
                items.resize(start[ncell]);
            }
            std::vector<uint32_t> fill(pass ? start : std::vector<uint32_t>());
            for (size_t f = 0; f < nt; f++) {
                int a[3], b[3];
                box(f, a, b);
                for (int z = a[2]; z <= b[2]; z++)
                    for (int y = a[1]; y <= b[1]; y++)
                        for (int x = a[0]; x <= b[0]; x++) {
                            size_t c = ((size_t)z * n[1] + y) * n[0] + x;
                            if (pass) items[fill[c]++] = (uint32_t)f;
                            else start[c + 1]++;
                        }
            }
        }
    }
    int coord(double x, int k) const { return std::min(n[k] - 1, std::max(0, (int)((x - lo[k]) / cell))); }
    void box(size_t f, int *a, int *b) const
    {
        for (int k = 0; k < 3; k++) { a[k] = n[k]; b[k] = -1; }
        for (int j = 0; j < 3; j++) {
            const double *p = &t->pos[3 * (size_t)t->idx[3 * f + j]];
            for (int k = 0; k < 3; k++) { a[k] = std::min(a[k], coord(p[k], k)); b[k] = std::max(b[k], coord(p[k], k)); }
        }
    }
    // Distance from p to the closest triangle: rings of cells until the
    // best distance found is within the ring's reach.
    double dist(const double *p) const
    {
        int c[3] = { coord(p[0], 0), coord(p[1], 1), coord(p[2], 2) };
        double best = DBL_MAX;
        int maxr = std::max(n[0], std::max(n[1], n[2]));
        for (int r = 0; r <= maxr; r++) {
            for (int z = c[2] - r; z <= c[2] + r; z++)
                for (int y = c[1] - r; y <= c[1] + r; y++)
                    for (int x = c[0] - r; x <= c[0] + r; x++) {
                        if (std::max(std::abs(x - c[0]), std::max(std::abs(y - c[1]), std::abs(z - c[2]))) != r) continue;
                        if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2]) continue;
                        size_t cc = ((size_t)z * n[1] + y) * n[0] + x;
                        for (uint32_t i = start[cc]; i < start[cc + 1]; i++) {
                            size_t f = items[i];
                            double q[3];
                            closest_on_tri(p, &t->pos[3 * (size_t)t->idx[3 * f]], &t->pos[3 * (size_t)t->idx[3 * f + 1]],
                                           &t->pos[3 * (size_t)t->idx[3 * f + 2]], q);
                            double d = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]);
                            best = std::min(best, d);
                        }
                    }
            if (best < DBL_MAX && std::sqrt(best) <= r * cell) break;
        }
        return std::sqrt(best);
    }
};

struct Dist { double hausdorff, rms; };

static void one_side(const std::vector<double> &pts, const Grid &g, double &mx, double &sum2, size_t &cnt)
{
    for (size_t i = 0; i < pts.size(); i += 3) {
        double d = g.dist(&pts[i]);
        mx = std::max(mx, d);
        sum2 += d * d;
        cnt++;
    }
}

static Dist distance(const Tri &in, const Grid &gin, const Tri &out, double diag)
{
    std::vector<double> pin(in.pos), pout;
    for (size_t f = 0; f < in.idx.size(); f += 3)
        for (int k = 0; k < 3; k++)
            pin.push_back((in.pos[3 * in.idx[f] + k] + in.pos[3 * in.idx[f + 1] + k] + in.pos[3 * in.idx[f + 2] + k]) / 3);
    for (size_t f = 0; f < out.idx.size(); f += 3)
        for (int i = 0; i <= 4; i++)
            for (int j = 0; i + j <= 4; j++) {
                double u = (i + 0.25) / 5.5, v = (j + 0.25) / 5.5, w = 1 - u - v;
                for (int k = 0; k < 3; k++)
                    pout.push_back(u * out.pos[3 * out.idx[f] + k] + v * out.pos[3 * out.idx[f + 1] + k] + w * out.pos[3 * out.idx[f + 2] + k]);
            }
    Grid gout(&out);
    double mx = 0, s2 = 0;
    size_t n = 0;
    one_side(pin, gout, mx, s2, n);
    one_side(pout, gin, mx, s2, n);
    return { mx / diag, std::sqrt(s2 / (double)n) / diag };
}

// ---- driver -----------------------------------------------------------------------

static long peak_in_child(int which, const st_mesh *m, uint64_t target)
{
    int fd[2];
    if (pipe(fd)) return -1;
    pid_t pid = fork();
    if (pid == 0) {
        malloc_trim(0); /* so that the run's heap is new resident memory */
        /* The peak is the child's own from here: a child starts with its
         * parent's high-water mark (the earlier meshes' runs), which
         * writing 5 to clear_refs resets to the current resident size. */
        FILE *cr = fopen("/proc/self/clear_refs", "w");
        if (cr) { fputs("5", cr); fclose(cr); }
        long before = rss_kib();
        st_progressive_report rep;
        if (which == 0) run_strata(m, target, &rep);
        else if (which == 1) run_openmesh(m, target);
        else run_meshopt(m, target);
        long hwm = -1;
        FILE *st = fopen("/proc/self/status", "r");
        char line[256];
        while (st && fgets(line, sizeof line, st))
            if (!strncmp(line, "VmHWM:", 6)) hwm = atol(line + 6);
        if (st) fclose(st);
        if (hwm < 0) { /* no /proc: the process's peak (includes the parent's before the fork) */
            struct rusage ru;
            getrusage(RUSAGE_SELF, &ru);
            hwm = ru.ru_maxrss;
        }
        long peak = hwm - before;
        if (write(fd[1], &peak, sizeof peak) != (ssize_t)sizeof peak) _exit(1);
        _exit(0);
    }
    long peak = -1;
    close(fd[1]);
    if (read(fd[0], &peak, sizeof peak) != (ssize_t)sizeof peak) peak = -1;
    close(fd[0]);
    waitpid(pid, nullptr, 0);
    return peak;
}

/* Fans every polygon into triangles, so that the three simplifiers get the
 * same triangles (Strata would fan them itself). */
static void fan_polygons(st_mesh *m)
{
    uint32_t nt = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) nt += m->face_off[f + 1] - m->face_off[f] - 2;
    if (nt == m->nfaces) return;
    uint32_t *off = (uint32_t *)malloc(((size_t)nt + 1) * sizeof *off), *idx = (uint32_t *)malloc(3 * (size_t)nt * sizeof *idx);
    if (!off || !idx) abort();
    uint32_t t = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        const uint32_t *i = m->face_idx + m->face_off[f];
        for (uint32_t k = 1; k + 1 < m->face_off[f + 1] - m->face_off[f]; k++, t++) {
            off[t] = 3 * t;
            idx[3 * t] = i[0];
            idx[3 * t + 1] = i[k];
            idx[3 * t + 2] = i[k + 1];
        }
    }
    off[t] = 3 * t;
    free(m->face_off);
    free(m->face_idx);
    m->face_off = off;
    m->face_idx = idx;
    m->nfaces = nt;
}

/* One dart per vertex of level l, in vertex id order. */
static std::vector<uint32_t> vertex_darts(const st_map *m, unsigned l)
{
    std::vector<uint32_t> vd(m->verts.end, ST_NIL), out;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it))
        if (!st_is_boundary(m, d)) vd[st_vert(m, d, l)] = d;
    for (uint32_t d : vd)
        if (d != ST_NIL) out.push_back(d);
    return out;
}

/* Coarse-level edits on the hierarchy (thesis §4.4.6: a local edit
 * re-synthesises the support of the moved vertex only) against the full
 * synthesis of the levels above, and the selective display of a box
 * (core/adapt/adapt_progressive.c): update time and faces shown. */
static void edits_and_display(const st_mesh *m, uint64_t target, double diag, int repeat)
{
    st_hier h;
    st_error err;
    st_progressive_opts o = {};
    o.target_faces = target;
    o.predictor = ST_PM_DEFAULT; /* what new builds use (progressive.h, point 5) */
    o.fit_coarse = 1;            /* and level 0 placed (point 8), as st_rebuild builds */
    if (st_progressive_build(m, &o, &h, nullptr, &err)) { fprintf(stderr, "strata: %s\n", err.msg); return; }
    st_map *mp = &h.map;
    st_hier_synthesize(&h, 0); /* (as after any first edit) */
    unsigned top = mp->top;
    for (unsigned l : { 0u, 2u, 4u, 6u, 8u, 10u, 12u }) {
        if (l >= top) continue;
        std::vector<uint32_t> vd = vertex_darts(mp, l);
        uint32_t d = vd[vd.size() / 3];
        std::vector<double> tl, tf, tw;
        uint64_t written = 0, changed = 0, visible = 0;
        for (int r = 0; r < std::max(repeat, 3); r++) {
            const double *p = st_dart_pos(mp, d, l);
            double q[1][3] = { { p[0] + 1e-3 * diag * (r & 1 ? -1 : 1), p[1], p[2] + 5e-4 * diag } };
            std::vector<double> before;
            if (r == 0) /* the support: positions above l that the edit changes */
                for (unsigned L = l + 1; L <= top; L++) {
                    st_dart_iter it;
                    for (uint32_t v = st_vertex_first(mp, L, &it); v != ST_NIL; v = st_vertex_next(mp, L, &it))
                        before.insert(before.end(), st_pos(mp, v, L), st_pos(mp, v, L) + 3);
                }
            double t0 = cpu_now();
            uint64_t w = st_hier_move(&h, l, &d, q, 1);
            tl.push_back(cpu_now() - t0);
            if (r == 0) written = w; /* the edit whose changes are counted */
            if (r == 0) {
                size_t i = 0;
                for (unsigned L = l + 1; L <= top; L++) {
                    st_dart_iter it;
                    for (uint32_t v = st_vertex_first(mp, L, &it); v != ST_NIL; v = st_vertex_next(mp, L, &it), i += 3)
                    {
                        const double *a = &before[i], *b = st_pos(mp, v, L);
                        changed += memcmp(a, b, 3 * sizeof(double)) != 0;
                        /* moved by more than 1e-6 of the edit's own move */
                        double dd = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
                        visible += dd > 1e-6 * std::sqrt(1.25) * 1e-3 * diag;
                    }
                }
            }
            /* The same vertex again at once, the edit's data still in the
             * cache (the timed edit above follows a full synthesis, which
             * streams every level through it). */
            double qw[1][3] = { { q[0][0], q[0][1] + 2.5e-4 * diag, q[0][2] } };
            t0 = cpu_now();
            st_hier_move(&h, l, &d, qw, 1);
            tw.push_back(cpu_now() - t0);
            t0 = cpu_now();
            st_hier_synthesize(&h, l);
            tf.push_back(cpu_now() - t0);
        }
        uint64_t above = 0;
        for (unsigned L = l + 1; L <= top; L++) {
            st_level_stats s;
            st_level_stats_compute(mp, L, &s);
            above += s.vertices;
        }
        double ml = bench_median(tl.data(), (int)tl.size()), mf = bench_median(tf.data(), (int)tf.size());
        double mw = bench_median(tw.data(), (int)tw.size());
        printf("  edit of one vertex of level %2u: local %8.3f ms (%llu positions written, %llu changed, %llu by more than 1e-6 of "
               "the edit's move, of %llu above), full synthesis of levels %u..%u %7.2f ms: local / full %.4fx (goal <= 0.05x); "
               "lower bound of a bit-exact local edit: changed / above %.4f (written / above %.4f)\n",
               l, 1e3 * ml, (unsigned long long)written, (unsigned long long)changed, (unsigned long long)visible,
               (unsigned long long)above, l + 1, top, 1e3 * mf, ml / mf, (double)changed / (double)above,
               (double)written / (double)above);
        double bound = (double)changed / (double)above;
        printf("    against the bound: local / full / bound %.2fx after a full synthesis (cold cache), %.2fx right after "
               "another edit of the vertex (%.3f ms: the edit's data in the cache)\n",
               ml / mf / bound, mw / mf / bound, 1e3 * mw);
    }
    {
        st_level_stats s;
        st_level_stats_compute(mp, top, &s);
        size_t tb = st_progressive_table_bytes(&h);
        printf("  synthesis tables (core/progressive/progressive_synth.c): %.1f MB, %.1f bytes per finest dart\n", tb / 1048576.0,
               s.darts ? (double)tb / (double)s.darts : 0.0);
    }
    /* the interest box: half-size 2 % of the diagonal around a vertex */
    std::vector<uint32_t> vt = vertex_darts(mp, top);
    const double *c = st_dart_pos(mp, vt[vt.size() / 2], top);
    for (unsigned base : { 0u, top > 6 ? top - 6 : 0u }) {
        st_adapt_params p = {};
        p.base_level = base;
        p.max_level = top;
        p.has_box = 1;
        for (int k = 0; k < 3; k++) { p.box_lo[k] = c[k] - 0.02 * diag; p.box_hi[k] = c[k] + 0.02 * diag; }
        st_adapt a;
        if (st_adapt_init(&a, &h, &err)) { fprintf(stderr, "strata: %s\n", err.msg); break; }
        std::vector<double> tu;
        for (int r = 0; r < std::max(repeat, 3); r++) {
            double t0 = cpu_now();
            if (st_adapt_update(&a, &p, &err)) { fprintf(stderr, "strata: %s\n", err.msg); break; }
            tu.push_back(cpu_now() - t0);
        }
        st_level_stats sb, st;
        st_level_stats_compute(mp, base, &sb);
        st_level_stats_compute(mp, top, &st);
        printf("  interest box (2 %% of the diagonal), levels %u..%u: %u faces shown (level %u: %llu, level %u: %llu), "
               "update %.2f ms (selection and its one-level map)\n",
               base, top, a.pm ? a.pm->nfaces : 0, base, (unsigned long long)sb.faces, top, (unsigned long long)st.faces,
               1e3 * bench_median(tu.data(), (int)tu.size()));
        st_adapt_free(&a);
    }
    st_hier_free(&h);
}

static int g_edits_only;

static int bench_mesh(const char *path, double percent, int repeat)
{
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    if (st_mesh_load(path, &m, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    uint32_t nin = m.nfaces;
    fan_polygons(&m);
    uint64_t target = (uint64_t)std::floor(m.nfaces * percent / 100.0);
    Tri in;
    in.pos.assign(m.pos, m.pos + 3 * (size_t)m.nverts);
    in.idx.assign(m.face_idx, m.face_idx + m.face_off[m.nfaces]);
    double lo[3] = { DBL_MAX, DBL_MAX, DBL_MAX }, hi[3] = { -DBL_MAX, -DBL_MAX, -DBL_MAX };
    for (uint32_t v = 0; v < m.nverts; v++)
        for (int k = 0; k < 3; k++) { lo[k] = std::min(lo[k], m.pos[3 * v + k]); hi[k] = std::max(hi[k], m.pos[3 * v + k]); }
    double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    printf("bench_progressive: %s, %u vertices, %u faces%s, target %llu faces (%.2f %%), median of %d runs\n", path, m.nverts,
           m.nfaces, nin != m.nfaces ? " (polygons fanned into triangles for all three)" : "", (unsigned long long)target, percent,
           repeat);
    if (g_edits_only) {
        edits_and_display(&m, target, diag, repeat);
        st_mesh_free(&m);
        return 0;
    }
    const char *names[3] = { "strata (whole hierarchy)", "openmesh decimater+quadric", "meshopt_simplify" };
    long peak[3];
    for (int which = 0; which < 3; which++) peak[which] = peak_in_child(which, &m, target);
    double med[3], cpu[3];
    Tri res[3];
    st_progressive_report rep;
    for (int which = 0; which < 3; which++) {
        std::vector<double> t, c;
        for (int r = 0; r < repeat; r++) {
            double t0 = bench_now(), c0 = cpu_now();
            if (which == 0) res[0] = run_strata(&m, target, &rep);
            else if (which == 1) res[1] = run_openmesh(&m, target);
            else res[2] = run_meshopt(&m, target);
            t.push_back(bench_now() - t0);
            c.push_back(cpu_now() - c0);
        }
        med[which] = bench_median(t.data(), (int)t.size());
        cpu[which] = bench_median(c.data(), (int)c.size());
    }
    {
        /* Strata's phases: the working copy, the grouped simplification, the rest (map, details). */
        std::vector<uint32_t> tri(m.face_idx, m.face_idx + m.face_off[m.nfaces]);
        pm_work w;
        char note[256];
        double c0 = cpu_now();
        if (pm_work_init(&w, m.pos, m.nverts, tri.data(), m.nfaces, &err) == ST_OK) {
            double c1 = cpu_now();
            pm_simplify(&w, target, ST_MAX_LEVELS - 1, nullptr, nullptr, note, sizeof note, &err);
            double c2 = cpu_now();
            printf("  strata phases (CPU): working copy %.1f ms, grouped collapses %.1f ms, map + details %.1f ms\n",
                   1e3 * (c1 - c0), 1e3 * (c2 - c1), 1e3 * (cpu[0] - (c2 - c0)));
            pm_work_free(&w);
        }
    }
    Grid gin(&in);
    double h0 = 0, r0 = 0;
    for (int which = 0; which < 3; which++) {
        Dist d = distance(in, gin, res[which], diag);
        printf("  %-28s %8.1f ms (CPU %8.1f ms)  peak %7.1f MiB  faces %6zu  Hausdorff %.5f  RMS %.6f (of the diagonal)\n",
               names[which], 1e3 * med[which], 1e3 * cpu[which], peak[which] / 1024.0, res[which].idx.size() / 3, d.hausdorff, d.rms);
        if (which == 0) { h0 = d.hausdorff; r0 = d.rms; }
        else printf("    strata / this: wall %.2fx, CPU %.2fx, peak memory %.2fx, Hausdorff %.2fx, RMS %.2fx\n", med[0] / med[which],
                    cpu[0] / cpu[which], (double)peak[0] / (double)std::max(1L, peak[which]), h0 / d.hausdorff, r0 / d.rms);
    }
    printf("  strata: %u levels, faces per level:", rep.levels);
    for (unsigned l = 0; l < rep.levels; l++) printf(" %llu", (unsigned long long)rep.faces[l]);
    printf("\n  kept fraction t per level (vertices l-1 / l):");
    for (unsigned l = 1; l < rep.levels; l++) printf(" %.3f", rep.kept[l]);
    double tmean = rep.levels > 1 ? std::pow((double)rep.vertices[0] / (double)rep.vertices[rep.levels - 1], 1.0 / (rep.levels - 1)) : 1;
    printf("\n  geometric mean t %.3f; topology %.1f bytes per finest dart (details %.1f more); thesis §4.4.8 full arrays: 24/(1-t) = %.1f bytes per "
           "fine vertex = %.1f per dart (6 darts per vertex), classic [Hop98] structure 68 bytes per vertex = 11.3 per dart\n",
           tmean, rep.bytes_per_dart, rep.detail_bytes_per_dart, 24 / (1 - tmean), 4 / (1 - tmean));
    printf("  %s; %llu (level, vertex) details miss the input's bits by an ulp or so\n", rep.note,
           (unsigned long long)rep.inexact);
    edits_and_display(&m, target, diag, repeat);
    st_mesh_free(&m);
    return 0;
}

int main(int argc, char **argv)
{
    double percent = 1.0;
    int repeat = 3;
    std::vector<std::string> paths;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--percent") && i + 1 < argc) percent = atof(argv[++i]);
        else if (!strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, atoi(argv[++i]));
        else if (!strcmp(argv[i], "--edits-only")) g_edits_only = 1;
        else paths.push_back(argv[i]);
    }
    if (paths.empty()) { /* the two large meshes of the shared data (SOURCES.md) */
        paths.push_back(std::string(STRATA_SHARED_DATA) + "/large/koala.obj");
        paths.push_back(std::string(STRATA_SHARED_DATA) + "/large/sword_quad_dominant.obj");
    }
    int rc = 0;
    for (const std::string &p : paths) rc |= bench_mesh(p.c_str(), percent, repeat);
    return rc;
}
