// bench_osd: Strata vs OpenSubdiv 3.5 side by side, in one run, on the same
// input and depth.  C++ only because OpenSubdiv
// is C++; Strata is called through its C API.
//
//   bench_osd [--quick] [spot|koala]   (one case alone: no local edit)
//   bench_osd --profile strata|osd catmark|loop DEPTH [THREADS [REPEAT]]
//       one side's synthesis alone, REPEAT times (wall and processor medians),
//       for callgrind --toggle-collect / perf; with BENCH_CHECK=1 in the
//       environment, also a hash of every level's positions and a comparison
//       of each with its stencil (bit-identity checks across changes)
//   bench_osd --profile-e2e strata|osd catmark|loop DEPTH [THREADS [REPEAT]]
//       one side's end to end alone (read, topology, first synthesis)
//   bench_osd --profile-edit REPEAT
//       the local edit case alone, with REPEAT more edits before the timed ones
//
// Prints, per case: topology refinement time (Strata refine vs
// Far::TopologyRefinerFactory + RefineUniform), synthesis of all levels
// (st_hier_synthesize vs Far::PrimvarRefiner::Interpolate), peak memory of
// each (VmHWM growth of a forked child that builds and synthesises, its
// high-water mark reset first; and each side's whole-process peak end to
// end in a fresh process, ru_maxrss), and the
// ratios.  Synthesis is timed on one thread and on two (parallel.h; OpenSubdiv
// on one thread in both lines), the three runs interleaved, medians of 9;
// other figures medians of 5 runs.  End to end (each side from the OBJ file
// to every level's positions: Strata's st_mesh_load, OpenSubdiv's factory
// after a plain OBJ reader, osd_read_obj) likewise interleaved, wall and
// processor time.  Then a local edit: one vertex moved at level 2
// of a depth-6 Catmull-Clark hierarchy, local re-synthesis vs full synthesis.
extern "C" {
#include "bench_common.h"
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/base/parallel.h"
#include "core/map/pool_internal.h"
#include "core/io/mesh.h"
#include "core/progressive/scheme_registry.h"
}
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <malloc.h>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace OpenSubdiv;

namespace {

const int RUNS = 5;
const int SYNTH_RUNS = 9;   // synthesis is short: more runs for its medians

struct Vec3 {
    double p[3];
    void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(Vec3 const &s, float w) { p[0] += w * s.p[0]; p[1] += w * s.p[1]; p[2] += w * s.p[2]; }
};

// OpenSubdiv has no mesh reader in its library: its side of the end-to-end
// line reads the OBJ with this plain reader (whole file in one read, `v`
// and `f` records, corner indices `v`, `v/t`, `v//n`, `v/t/n`, negative
// ones counting back; no checks beyond the index range), as a program using
// OpenSubdiv would.
struct osd_obj {
    std::vector<double> pos;
    std::vector<int> counts, idx;
};

bool osd_read_obj(const char *path, osd_obj &o)
{
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    std::string text;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    text.resize((size_t)size);
    bool ok = fread(&text[0], 1, (size_t)size, f) == (size_t)size;
    fclose(f);
    if (!ok) return false;
    const char *p = text.c_str(), *end = p + text.size();
    while (p < end) {
        const char *le = (const char *)memchr(p, '\n', (size_t)(end - p));
        if (!le) le = end;
        if (p[0] == 'v' && (p[1] == ' ' || p[1] == '\t')) {
            char *q = (char *)p + 1;
            for (int k = 0; k < 3; k++) o.pos.push_back(strtod(q, &q));
        } else if (p[0] == 'f' && (p[1] == ' ' || p[1] == '\t')) {
            const char *q = p + 1;
            int n = 0;
            for (;;) {
                while (q < le && (*q == ' ' || *q == '\t' || *q == '\r')) q++;
                if (q >= le || *q == '#') break;
                char *e;
                long v = strtol(q, &e, 10);
                if (e == q) return false;
                long nv = (long)(o.pos.size() / 3);
                v = v < 0 ? nv + v : v - 1;
                if (v < 0 || v >= nv) return false;
                o.idx.push_back((int)v);
                n++;
                q = e;
                while (q < le && *q != ' ' && *q != '\t' && *q != '\r') q++; // skip /t/n
            }
            o.counts.push_back(n);
        }
        p = le + 1;
    }
    return true;
}

Far::TopologyRefiner *osd_refine_desc(int nverts, const std::vector<int> &counts, const int *idx, Sdc::SchemeType type,
                                      int levels)
{
    Far::TopologyDescriptor desc;
    desc.numVertices = nverts;
    desc.numFaces = (int)counts.size();
    desc.numVertsPerFace = counts.data();
    desc.vertIndicesPerFace = idx;
    Sdc::Options opts;
    opts.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    Far::TopologyRefiner *r = Factory::Create(desc, Factory::Options(type, opts));
    r->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    return r;
}

// Interpolates every level from the coarse positions `pos`.
std::vector<Vec3> osd_interpolate_from(const Far::TopologyRefiner &r, const double *pos)
{
    std::vector<Vec3> buf(r.GetNumVerticesTotal());
    memcpy(buf.data(), pos, sizeof(Vec3) * (size_t)r.GetLevel(0).GetNumVertices());
    Far::PrimvarRefiner pr(r);
    Vec3 *src = buf.data();
    for (int l = 1; l <= r.GetMaxLevel(); l++) {
        Vec3 *dst = src + r.GetLevel(l - 1).GetNumVertices();
        pr.Interpolate(l, src, dst);
        src = dst;
    }
    return buf;
}

Far::TopologyRefiner *osd_refine(const st_mesh &m, Sdc::SchemeType type, int levels)
{
    std::vector<int> counts(m.nfaces);
    for (uint32_t f = 0; f < m.nfaces; f++) counts[f] = (int)(m.face_off[f + 1] - m.face_off[f]);
    return osd_refine_desc((int)m.nverts, counts, (const int *)m.face_idx, type, levels);
}

// Interpolates every level; returns the buffer of all levels.
std::vector<Vec3> osd_interpolate(const Far::TopologyRefiner &r, const st_mesh &m)
{
    return osd_interpolate_from(r, m.pos);
}

int strata_build(st_hier *h, const st_mesh &m, const st_scheme *sc, int levels)
{
    st_error err;
    st_hier_opts o = {};
    o.boundary = ST_BOUNDARY_EDGE_ONLY;
    o.crease_method = ST_CREASE_UNIFORM;
    o.tri_sub = ST_TRI_SUB_CATMARK;
    o.uv_interp = ST_UV_CORNERS_PLUS1;
    if (st_hier_init(h, &m, sc, &o, &err)) { fprintf(stderr, "bench_osd: %s\n", err.msg); return -1; }
    for (int l = 0; l < levels; l++)
        if (st_hier_refine_topology(h, &err)) { fprintf(stderr, "bench_osd: %s\n", err.msg); return -1; }
    return 0;
}

// Processor time of the whole process (all threads, user and system).
double cpu_now()
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// End to end, each side from the file to every level's positions: wall and
// processor time up to the result (freeing comes after the clocks stop).
struct e2e_time { double wall, cpu; };

e2e_time osd_e2e(const char *path, Sdc::SchemeType type, int levels)
{
    double t0 = bench_now(), c0 = cpu_now();
    osd_obj o;
    if (!osd_read_obj(path, o)) { fprintf(stderr, "bench_osd: cannot read %s\n", path); exit(1); }
    Far::TopologyRefiner *r = osd_refine_desc((int)(o.pos.size() / 3), o.counts, o.idx.data(), type, levels);
    std::vector<Vec3> buf = osd_interpolate_from(*r, o.pos.data());
    e2e_time t = { bench_now() - t0, cpu_now() - c0 };
    delete r;
    return t;
}

e2e_time strata_e2e(const char *path, const st_scheme *sc, int levels)
{
    double t0 = bench_now(), c0 = cpu_now();
    st_mesh m;
    st_error err;
    st_hier h;
    st_mesh_init(&m);
    if (st_mesh_load(path, &m, &err) || strata_build(&h, m, sc, levels)) { fprintf(stderr, "bench_osd: %s\n", err.msg); exit(1); }
    st_hier_synthesize(&h, 0);
    e2e_time t = { bench_now() - t0, cpu_now() - c0 };
    st_hier_free(&h);
    st_mesh_free(&m);
    return t;
}

long rss_kb(const char *field)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long v = -1;
    size_t n = strlen(field);
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, field, n)) v = atol(line + n + 1);
    if (f) fclose(f);
    return v;
}

// Runs fn in a forked child; returns its peak RSS growth in bytes.
template <class F> long peak_bytes(F fn)
{
    int fd[2];
    if (pipe(fd)) return -1;
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        // Heap the parent freed but glibc kept (its mmap threshold grows
        // with the blocks freed) would be reused without growing the
        // resident set: give it back first, so the growth is all counted.
        malloc_trim(0);
        // A forked child inherits its parent's high-water mark (VmHWM):
        // without a reset both sides printed the parent's peak, the same
        // figure (spot: 299.8 / 299.8 MB).  Writing 5 to clear_refs sets
        // it to the current resident size (proc(5)).
        if (FILE *cr = fopen("/proc/self/clear_refs", "w")) {
            fputs("5", cr);
            fclose(cr);
        }
        long base = rss_kb("VmRSS:");
        fn();
        long peak = rss_kb("VmHWM:");
        long d = (peak - base) * 1024;
        if (write(fd[1], &d, sizeof d) != (ssize_t)sizeof d) _exit(1);
        _exit(0);
    }
    close(fd[1]);
    long d = -1;
    if (read(fd[0], &d, sizeof d) != (ssize_t)sizeof d) d = -1;
    close(fd[0]);
    waitpid(pid, nullptr, 0);
    return d;
}

template <class F> double median_time(F fn)
{
    double t[RUNS];
    for (int r = 0; r < RUNS; r++) {
        double t0 = bench_now();
        fn();
        t[r] = bench_now() - t0;
    }
    return bench_median(t, RUNS);
}

// End to end in a fresh process (this program's --profile-e2e, one run), as
// a user's command meets it: every page of the heap faulted in for the first
// time.  Returns wall and processor time and the page faults of the process.
struct e2e_fresh { double wall, cpu, faults, peak; };

e2e_fresh e2e_in_process(bool osd, bool loop, int levels, int threads)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "/proc/%d/exe --profile-e2e %s %s %d %d 1", (int)getpid(), osd ? "osd" : "strata",
             loop ? "loop" : "catmark", levels, threads);
    e2e_fresh r = { -1, -1, -1, -1 };
    FILE *f = popen(cmd, "r");
    char line[256];
    double wall, cpu;
    long faults, kib;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(strstr(line, "end to end") ? strstr(line, "end to end") : line,
                   "end to end %lf ms, cpu %lf ms (medians of 1), %ld page faults, peak %ld KiB", &wall, &cpu, &faults, &kib) == 4)
            r = { 1e-3 * wall, 1e-3 * cpu, (double)faults, 1024.0 * (double)kib };
    if (f) pclose(f);
    if (r.wall < 0) { fprintf(stderr, "bench_osd: %s failed\n", cmd); exit(1); }
    return r;
}

void compare(const char *path, const st_scheme *sc, Sdc::SchemeType type, int levels)
{
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    if (st_mesh_load(path, &m, &err)) { fprintf(stderr, "bench_osd: %s\n", err.msg); return; }
    printf("\n%s, %s, depth %d\n", path, sc->name, levels);
    double t_osd_topo = median_time([&] { delete osd_refine(m, type, levels); });
    double t_st_topo = median_time([&] { st_hier h; if (!strata_build(&h, m, sc, levels)) st_hier_free(&h); });
    Far::TopologyRefiner *r = osd_refine(m, type, levels);
    st_hier h;
    if (strata_build(&h, m, sc, levels)) return;
    // The first synthesis after a refinement walks the levels, the second
    // builds the tables (synth_tables.h) that the later ones reuse
    // (st_synth_tables_defer): the first is timed apart, and added to the
    // topology's time in a second ratio (OpenSubdiv's RefineUniform builds
    // its own tables); the second falls in the synthesis runs below, whose
    // median it does not move.
    st_parallel_set_threads(1);
    double t_first0 = bench_now();
    st_hier_synthesize(&h, 0);
    double t_first = bench_now() - t_first0;
    // Synthesis runs interleaved (OpenSubdiv, Strata on 1 thread, on 2), so
    // that a change in the machine's load falls on all three alike.
    double ti[3][SYNTH_RUNS];
    for (int k = 0; k < SYNTH_RUNS; k++) {
        double t0 = bench_now();
        osd_interpolate(*r, m);
        double t1 = bench_now();
        st_parallel_set_threads(1);
        st_hier_synthesize(&h, 0);
        double t2 = bench_now();
        st_parallel_set_threads(2);
        st_hier_synthesize(&h, 0);
        double t3 = bench_now();
        ti[0][k] = t1 - t0;
        ti[1][k] = t2 - t1;
        ti[2][k] = t3 - t2;
    }
    st_parallel_set_threads(1);
    double t_osd_interp = bench_median(ti[0], SYNTH_RUNS), t_st_synth = bench_median(ti[1], SYNTH_RUNS),
           t_st_synth2 = bench_median(ti[2], SYNTH_RUNS);
    printf("  finest level: OpenSubdiv %d vertices, Strata %llu vertices\n", r->GetLevel(levels).GetNumVertices(),
           (unsigned long long)st_pool_count(&h.map.verts, levels));
    delete r;
    st_hier_free(&h);
    // End to end, the three interleaved: OpenSubdiv, Strata on 1 thread, on 2.
    double ew[3][RUNS], ec[3][RUNS];
    for (int k = 0; k < RUNS; k++) {
        e2e_time a = osd_e2e(path, type, levels);
        st_parallel_set_threads(1);
        e2e_time b = strata_e2e(path, sc, levels);
        st_parallel_set_threads(2);
        e2e_time c = strata_e2e(path, sc, levels);
        st_parallel_set_threads(1);
        ew[0][k] = a.wall, ec[0][k] = a.cpu;
        ew[1][k] = b.wall, ec[1][k] = b.cpu;
        ew[2][k] = c.wall, ec[2][k] = c.cpu;
    }
    double e_osd = bench_median(ew[0], RUNS), e_st = bench_median(ew[1], RUNS), e_st2 = bench_median(ew[2], RUNS);
    double ec_osd = bench_median(ec[0], RUNS), ec_st = bench_median(ec[1], RUNS);
    // The same, each run in a fresh process, interleaved.
    bool loop = type == Sdc::SCHEME_LOOP;
    double fw[3][RUNS], fc[3][RUNS], ff[3][RUNS], fp[2][RUNS];
    for (int k = 0; k < RUNS; k++) {
        e2e_fresh a = e2e_in_process(true, loop, levels, 1), b = e2e_in_process(false, loop, levels, 1),
                  c = e2e_in_process(false, loop, levels, 2);
        fw[0][k] = a.wall, fc[0][k] = a.cpu, ff[0][k] = a.faults, fp[0][k] = a.peak;
        fw[1][k] = b.wall, fc[1][k] = b.cpu, ff[1][k] = b.faults, fp[1][k] = b.peak;
        fw[2][k] = c.wall, fc[2][k] = c.cpu, ff[2][k] = c.faults;
    }
    double f_osd = bench_median(fw[0], RUNS), f_st = bench_median(fw[1], RUNS), f_st2 = bench_median(fw[2], RUNS);
    double fc_osd = bench_median(fc[0], RUNS), fc_st = bench_median(fc[1], RUNS);
    double ff_osd = bench_median(ff[0], RUNS), ff_st = bench_median(ff[1], RUNS);
    double fp_osd = bench_median(fp[0], RUNS), fp_st = bench_median(fp[1], RUNS);
    long mem_osd = peak_bytes([&] { Far::TopologyRefiner *q = osd_refine(m, type, levels); osd_interpolate(*q, m); delete q; });
    long mem_st = peak_bytes([&] { st_hier g; if (!strata_build(&g, m, sc, levels)) { st_hier_synthesize(&g, 0); st_hier_free(&g); } });
    printf("  topology refinement: Strata %.1f ms, OpenSubdiv %.1f ms, ratio %.2f (target <= 1.5)\n",
           1e3 * t_st_topo, 1e3 * t_osd_topo, t_st_topo / t_osd_topo);
    printf("  first synthesis after refinement (1 thread, walks the levels): Strata %.1f ms; topology + it %.1f ms, "
           "ratio %.2f to OpenSubdiv's topology\n",
           1e3 * t_first, 1e3 * (t_st_topo + t_first), (t_st_topo + t_first) / t_osd_topo);
    printf("  end to end (read OBJ + topology + first synthesis of all levels), fresh process, 1 thread: Strata %.1f ms "
           "(cpu %.1f, %.0f page faults), OpenSubdiv %.1f ms (cpu %.1f, %.0f page faults), ratio %.2f (cpu %.2f; target <= 0.8)\n",
           1e3 * f_st, 1e3 * fc_st, ff_st, 1e3 * f_osd, 1e3 * fc_osd, ff_osd, f_st / f_osd, fc_st / fc_osd);
    printf("  end to end, fresh process, Strata 2 threads: %.1f ms, OpenSubdiv (1 thread) %.1f ms, ratio %.2f\n", 1e3 * f_st2,
           1e3 * f_osd, f_st2 / f_osd);
    printf("  end to end in this process (heap reused), 1 thread: Strata %.1f ms (cpu %.1f), OpenSubdiv %.1f ms (cpu %.1f), "
           "ratio %.2f (cpu %.2f); Strata 2 threads %.1f ms, ratio %.2f\n",
           1e3 * e_st, 1e3 * ec_st, 1e3 * e_osd, 1e3 * ec_osd, e_st / e_osd, ec_st / ec_osd, 1e3 * e_st2, e_st2 / e_osd);
    printf("  synthesis, all levels, 1 thread: Strata %.1f ms, OpenSubdiv %.1f ms, ratio %.2f (target <= 1.0)\n",
           1e3 * t_st_synth, 1e3 * t_osd_interp, t_st_synth / t_osd_interp);
    printf("  synthesis, all levels, 2 threads: Strata %.1f ms, OpenSubdiv (1 thread) %.1f ms, ratio %.2f (target <= 0.6)\n",
           1e3 * t_st_synth2, 1e3 * t_osd_interp, t_st_synth2 / t_osd_interp);
    printf("  peak memory (refine + synthesis, growth in a forked child): Strata %.1f MB, OpenSubdiv %.1f MB, ratio %.2f "
           "(target <= 1.0)\n",
           mem_st / 1e6, mem_osd / 1e6, (double)mem_st / (double)mem_osd);
    printf("  peak memory, end to end in a fresh process (its own ru_maxrss, as /usr/bin/time reads it), 1 thread: "
           "Strata %.1f MB, OpenSubdiv %.1f MB, ratio %.2f\n",
           fp_st / 1e6, fp_osd / 1e6, fp_st / fp_osd);
    st_mesh_free(&m);
}

// FNV-1a of the positions of levels from+1..top: the local edit against a
// full synthesis, to the bit.
uint64_t levels_hash(const st_hier *h, unsigned from)
{
    uint64_t hash = 1469598103934665603ull;
    for (unsigned L = from + 1; L <= h->map.top; L++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, L, &it); v != ST_NIL; v = st_vertex_next(&h->map, L, &it)) {
            const unsigned char *b = (const unsigned char *)st_pos(&h->map, v, L);
            for (size_t k = 0; k < 3 * sizeof(double); k++) hash = (hash ^ b[k]) * 1099511628211ull;
        }
    }
    return hash;
}

void local_edit(const char *path, int repeat = 0)
{
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    if (st_mesh_load(path, &m, &err)) { fprintf(stderr, "bench_osd: %s\n", err.msg); return; }
    st_hier h;
    if (strata_build(&h, m, &st_scheme_catmark, 6)) return;
    st_hier_synthesize(&h, 0);
    st_dart_iter it;
    uint32_t d = st_dart_first(&h.map, 2, &it);
    for (int i = 0; i < 1000; i++) d = st_dart_next(&h.map, 2, &it);
    double p0[3];
    memcpy(p0, st_dart_pos(&h.map, d, 2), sizeof p0);
    int flip = 0;
    uint64_t count = 0;
    auto move = [&] {
        double p[1][3] = { { p0[0], p0[1], p0[2] + (flip ^= 1) * 0.01 } };
        count = st_hier_move(&h, 2, &d, p, 1);
    };
    for (int i = 0; i < repeat; i++) move(); // --profile-edit: for profilers
    // Successive edits, as in a drag (the region stays in the caches), and
    // successive full syntheses; then the two interleaved, each edit after a
    // full synthesis has streamed through memory (cold caches).  Wall clock
    // and process CPU time (less disturbed on a loaded machine; the
    // synthesis threads count too).
    double tl[SYNTH_RUNS], tf[SYNTH_RUNS], cl[SYNTH_RUNS], cf[SYNTH_RUNS];
    double ptl[SYNTH_RUNS], ptf[SYNTH_RUNS], pcl[SYNTH_RUNS], pcf[SYNTH_RUNS];
    for (int k = 0; k < SYNTH_RUNS; k++) {
        double t0 = bench_now(), c0 = cpu_now();
        move();
        tl[k] = bench_now() - t0;
        ptl[k] = cpu_now() - c0;
    }
    for (int k = 0; k < SYNTH_RUNS; k++) {
        double t0 = bench_now(), c0 = cpu_now();
        st_hier_synthesize(&h, 2);
        tf[k] = bench_now() - t0;
        ptf[k] = cpu_now() - c0;
    }
    for (int k = 0; k < SYNTH_RUNS; k++) {
        double t0 = bench_now(), c0 = cpu_now();
        move();
        double t1 = bench_now(), c1 = cpu_now();
        st_hier_synthesize(&h, 2);
        cl[k] = t1 - t0;
        pcl[k] = c1 - c0;
        cf[k] = bench_now() - t1;
        pcf[k] = cpu_now() - c1;
    }
    // One more edit, then the full synthesis it must equal to the bit.
    move();
    uint64_t h_local = levels_hash(&h, 2);
    st_hier_synthesize(&h, 2);
    uint64_t h_full = levels_hash(&h, 2);
    double t_local = bench_median(tl, SYNTH_RUNS), t_full = bench_median(tf, SYNTH_RUNS);
    double c_local = bench_median(cl, SYNTH_RUNS), c_full = bench_median(cf, SYNTH_RUNS);
    double pt_local = bench_median(ptl, SYNTH_RUNS), pt_full = bench_median(ptf, SYNTH_RUNS);
    double pc_local = bench_median(pcl, SYNTH_RUNS), pc_full = bench_median(pcf, SYNTH_RUNS);
    printf("\nlocal edit: %s, Catmull-Clark depth 6, one vertex moved at level 2, synthesis threads: %u\n", path,
           st_parallel_threads());
    printf("  successive edits: local re-synthesis %.3f ms (%llu vertices), full synthesis from level 2 %.1f ms, ratio %.4f (target <= 0.015)\n",
           1e3 * t_local, (unsigned long long)count, 1e3 * t_full, t_local / t_full);
    printf("    in process CPU time: local %.3f ms, full %.1f ms, ratio %.4f (target <= 0.015)\n", 1e3 * pt_local,
           1e3 * pt_full, pt_local / pt_full);
    printf("  each edit after a full synthesis (cold caches): local %.3f ms, full %.1f ms, ratio %.4f; CPU time ratio %.4f\n",
           1e3 * c_local, 1e3 * c_full, c_local / c_full, pc_local / pc_full);
    printf("  local edit and full synthesis: %s (FNV-1a of levels 3..6 %016llx, %016llx)\n",
           h_local == h_full ? "the same bits" : "DIFFERENT BITS", (unsigned long long)h_local, (unsigned long long)h_full);
    st_hier_free(&h);
    st_mesh_free(&m);
}

} // namespace

// Compares every position of levels 1..top (after a synthesis) with its
// stencil evaluated on the level below: prints the count of exact matches
// and the largest difference relative to the coordinates' magnitude.
struct check_ctx { st_hier *h; unsigned L; uint64_t n, exact; double worst; };

void check_sink(void *ctx, const st_stencil *s)
{
    check_ctx *c = (check_ctx *)ctx;
    double p[3];
    st_stencil_eval(&c->h->map, c->L, s, p);
    const double *q = st_pos(&c->h->map, s->fine, c->L);
    c->n++;
    c->exact += !memcmp(p, q, sizeof p);
    for (int k = 0; k < 3; k++) {
        double scale = fabs(p[k]) > 1 ? fabs(p[k]) : 1;
        if (fabs(p[k] - q[k]) / scale > c->worst) c->worst = fabs(p[k] - q[k]) / scale;
    }
}

void check_stencils(st_hier *h)
{
    uint64_t hash = 1469598103934665603ull;
    for (unsigned L = 0; L <= h->map.top; L++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, L, &it); v != ST_NIL; v = st_vertex_next(&h->map, L, &it)) {
            const unsigned char *b = (const unsigned char *)st_pos(&h->map, v, L);
            for (size_t k = 0; k < 3 * sizeof(double); k++) hash = (hash ^ b[k]) * 1099511628211ull;
        }
    }
    printf("  positions of all levels: FNV-1a %016llx\n", (unsigned long long)hash);
    for (unsigned L = 1; L <= h->map.top; L++) {
        check_ctx c = { h, L, 0, 0, 0 };
        st_hier_emit(h, L, nullptr, 0, check_sink, &c);
        printf("  level %u: %llu stencils, %llu exact, worst relative difference %.3g\n", L, (unsigned long long)c.n,
               (unsigned long long)c.exact, c.worst);
    }
}

// One synthesis on one side, for profilers (callgrind --toggle-collect):
//   bench_osd --profile strata|osd catmark|loop DEPTH [THREADS [REPEAT]]
// REPEAT synthesis runs (default 1); prints the median time.
int profile(int argc, char **argv)
{
    if (argc < 5) { fprintf(stderr, "usage: bench_osd --profile strata|osd catmark|loop DEPTH [THREADS [REPEAT]]\n"); return 2; }
    bool osd = !strcmp(argv[2], "osd"), loop = !strcmp(argv[3], "loop");
    int levels = atoi(argv[4]), repeat = argc > 6 ? atoi(argv[6]) : 1;
    if (repeat < 1) repeat = 1;
    std::vector<double> t(repeat), c(repeat);
    std::string dir = STRATA_SHARED_DATA;
    std::string path = dir + (loop ? "/large/koala.obj" : "/catmull_clark/spot_quadrangulated.obj");
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    if (st_mesh_load(path.c_str(), &m, &err)) { fprintf(stderr, "bench_osd: %s\n", err.msg); return 1; }
    if (osd) {
        Far::TopologyRefiner *r = osd_refine(m, loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, levels);
        size_t n = 0;
        for (int i = 0; i < repeat; i++) {
            double t0 = bench_now(), c0 = cpu_now();
            n = osd_interpolate(*r, m).size();
            t[i] = bench_now() - t0;
            c[i] = cpu_now() - c0;
        }
        printf("osd synthesis %.2f ms, cpu %.2f ms (medians of %d), %zu vertices\n", 1e3 * bench_median(t.data(), repeat),
               1e3 * bench_median(c.data(), repeat), repeat, n);
        delete r;
    } else {
        st_hier h;
        if (strata_build(&h, m, loop ? st_scheme_find("loop") : &st_scheme_catmark, levels)) return 1;
        st_parallel_set_threads(argc > 5 ? (unsigned)atoi(argv[5]) : 1);
        for (int i = 0; i < repeat; i++) {
            double t0 = bench_now(), c0 = cpu_now();
            st_hier_synthesize(&h, 0);
            t[i] = bench_now() - t0;
            c[i] = cpu_now() - c0;
        }
        printf("strata synthesis %.2f ms, cpu %.2f ms (medians of %d)\n", 1e3 * bench_median(t.data(), repeat),
               1e3 * bench_median(c.data(), repeat), repeat);
        if (getenv("BENCH_CHECK")) check_stencils(&h);
        st_hier_free(&h);
    }
    st_mesh_free(&m);
    return 0;
}

// End to end on one side, for profilers:
//   bench_osd --profile-e2e strata|osd catmark|loop DEPTH [THREADS [REPEAT]]
int profile_e2e(int argc, char **argv)
{
    if (argc < 5) { fprintf(stderr, "usage: bench_osd --profile-e2e strata|osd catmark|loop DEPTH [THREADS [REPEAT]]\n"); return 2; }
    bool osd = !strcmp(argv[2], "osd"), loop = !strcmp(argv[3], "loop");
    int levels = atoi(argv[4]), repeat = argc > 6 ? atoi(argv[6]) : 1;
    if (repeat < 1) repeat = 1;
    st_parallel_set_threads(argc > 5 ? (unsigned)atoi(argv[5]) : 1);
    std::string path = std::string(STRATA_SHARED_DATA) + (loop ? "/large/koala.obj" : "/catmull_clark/spot_quadrangulated.obj");
    std::vector<double> t(repeat), c(repeat);
    for (int i = 0; i < repeat; i++) {
        e2e_time e = osd ? osd_e2e(path.c_str(), loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, levels)
                         : strata_e2e(path.c_str(), loop ? st_scheme_find("loop") : &st_scheme_catmark, levels);
        t[i] = e.wall;
        c[i] = e.cpu;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("%s end to end %.2f ms, cpu %.2f ms (medians of %d), %ld page faults, peak %ld KiB\n", osd ? "osd" : "strata",
           1e3 * bench_median(t.data(), repeat), 1e3 * bench_median(c.data(), repeat), repeat, ru.ru_minflt + ru.ru_majflt,
           ru.ru_maxrss);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "--profile-e2e")) return profile_e2e(argc, argv);
    if (argc > 1 && !strcmp(argv[1], "--profile")) return profile(argc, argv);
    if (argc > 2 && !strcmp(argv[1], "--profile-edit")) {
        local_edit((std::string(STRATA_SHARED_DATA) + "/catmull_clark/blub_control_mesh.obj").c_str(), atoi(argv[2]));
        return 0;
    }
    bool quick = false, spot = true, koala = true, edit = true;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) quick = true;
        else if (!strcmp(argv[i], "spot")) koala = edit = false;
        else if (!strcmp(argv[i], "koala")) spot = edit = false;
    }
    std::string dir = STRATA_SHARED_DATA;
    if (spot) compare((dir + "/catmull_clark/spot_quadrangulated.obj").c_str(), &st_scheme_catmark, Sdc::SCHEME_CATMARK, quick ? 2 : 4);
    const st_scheme *loop = st_scheme_find("loop");
    if (koala && loop && loop->check) compare((dir + "/large/koala.obj").c_str(), loop, Sdc::SCHEME_LOOP, quick ? 1 : 3);
    if (!edit) return 0;
    local_edit((dir + "/catmull_clark/blub_control_mesh.obj").c_str());
    return 0;
}
