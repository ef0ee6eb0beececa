// osd_oracle: reference uniform subdivision with OpenSubdiv 3.5 (Far/Sdc), test-only.
//
//   osd_oracle IN.obj --scheme catmark|loop --levels N
//              [--boundary none|edge-only|edge-and-corner]
//              [--creasing uniform|chaikin] [--tri-sub catmark|smooth]
//              [--out-prefix P]            -> writes P_1.obj .. P_N.obj
//   osd_oracle IN.obj --scheme catmark --levels N --time [--repeat 5]
//              -> prints one line:
//   osd scheme=catmark levels=4 refine_ms=.. interp_ms=.. bytes=.. refiner_bytes=.. verts=.. faces=..
//
// Options actually passed to OpenSubdiv (printed on stderr):
//   * boundary: --boundary, else the OBJ `t interpolateboundary` tag
//     (OBJ tag values: 0 = none, 1 = edge-and-corner, 2 = edge-only; the reverse of
//     Sdc::Options' enum order), else edge-only.
//   * creasing: --creasing, else the OBJ `t creasemethod` tag (normal = uniform,
//     chaikin), else UNIFORM.  Sdc::Options() defaults to CREASE_UNIFORM (not Chaikin).
//   * triangle subdivision (Catmark only): --tri-sub, else the OBJ `t smoothtriangles`
//     tag, else TRI_SUB_CATMARK (Sdc default).
//   * holes: the OBJ `t hole` faces are holes (TopologyDescriptor::holeIndices): they
//     stay in the rules of their vertices, and the faces they leave at each level are
//     not written.
//   * face-varying: untouched (no face-varying data is refined).
// Positions are refined in double precision (Far::PrimvarRefinerReal<double>); the
// mask weights are computed by Sdc in double as well.
//
// Memory in --time mode: the global operator new/delete are replaced by counting
// versions (malloc_usable_size of each block).  `bytes` = peak live C++ heap bytes
// above the baseline during one factory+RefineUniform+buffer allocation+interpolation
// run (this includes the primvar buffers for all levels, sizeof(double)*3 per vertex);
// `refiner_bytes` = live bytes held by the TopologyRefiner after RefineUniform.
// Allocations made with malloc() directly by libraries are not counted (OpenSubdiv's
// Far/Vtr use std::vector / new throughout).
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "mesh_io.h"

// ---- counting allocator ------------------------------------------------------
static std::atomic<long long> g_live{0}, g_peak{0};
static void note_alloc(void* p) {
    if (!p) return;
    long long now = g_live.fetch_add((long long)malloc_usable_size(p)) + (long long)malloc_usable_size(p);
    long long pk = g_peak.load();
    while (now > pk && !g_peak.compare_exchange_weak(pk, now)) {}
}
void* operator new(std::size_t n) {
    void* p = std::malloc(n ? n : 1);
    if (!p) throw std::bad_alloc();
    note_alloc(p);
    return p;
}
void* operator new[](std::size_t n) { return ::operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    void* p = std::malloc(n ? n : 1);
    note_alloc(p);
    return p;
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return ::operator new(n, t); }
void operator delete(void* p) noexcept {
    if (!p) return;
    g_live.fetch_sub((long long)malloc_usable_size(p));
    std::free(p);
}
void operator delete[](void* p) noexcept { ::operator delete(p); }
void operator delete(void* p, std::size_t) noexcept { ::operator delete(p); }
void operator delete[](void* p, std::size_t) noexcept { ::operator delete(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { ::operator delete(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { ::operator delete(p); }

using namespace OpenSubdiv;

namespace {

struct Vertex {
    double p[3];
    void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(const Vertex& s, double w) {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

void load_base(const oracle::Mesh& m, std::vector<Vertex>& buf) {
    for (int i = 0; i < m.nverts(); ++i)
        for (int k = 0; k < 3; ++k) buf[i].p[k] = m.P[3 * i + k];
}

static_assert(sizeof(Vertex) == 3 * sizeof(double), "Vertex must be 3 packed doubles");

using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;

struct Setup {
    Sdc::SchemeType scheme;
    Sdc::Options opts;
};

Far::TopologyRefiner* build_refiner(const oracle::Mesh& m, const Setup& s,
                                    std::vector<int>& creasePairs, std::vector<float>& creaseW,
                                    std::vector<int>& cornerIdx, std::vector<float>& cornerW) {
    Far::TopologyDescriptor d;
    d.numVertices = m.nverts();
    d.numFaces = m.nfaces();
    d.numVertsPerFace = m.fsize.data();
    d.vertIndicesPerFace = m.fidx.data();
    creasePairs.clear(); creaseW.clear(); cornerIdx.clear(); cornerW.clear();
    for (auto& c : m.creases) { creasePairs.push_back(c.v0); creasePairs.push_back(c.v1); creaseW.push_back(c.sharpness); }
    for (auto& c : m.corners) { cornerIdx.push_back(c.v); cornerW.push_back(c.sharpness); }
    d.numCreases = (int)creaseW.size();
    d.creaseVertexIndexPairs = creasePairs.empty() ? nullptr : creasePairs.data();
    d.creaseWeights = creaseW.empty() ? nullptr : creaseW.data();
    d.numCorners = (int)cornerW.size();
    d.cornerVertexIndices = cornerIdx.empty() ? nullptr : cornerIdx.data();
    d.cornerWeights = cornerW.empty() ? nullptr : cornerW.data();
    d.numHoles = (int)m.holes.size();
    d.holeIndices = m.holes.empty() ? nullptr : m.holes.data();
    return Factory::Create(d, Factory::Options(s.scheme, s.opts));
}

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

const char* boundary_name(Sdc::Options::VtxBoundaryInterpolation b) {
    switch (b) {
        case Sdc::Options::VTX_BOUNDARY_NONE: return "none";
        case Sdc::Options::VTX_BOUNDARY_EDGE_ONLY: return "edge-only";
        default: return "edge-and-corner";
    }
}

int usage() {
    std::fprintf(stderr,
        "usage: osd_oracle IN.{obj,off,ply} --scheme catmark|loop --levels N\n"
        "         [--boundary none|edge-only|edge-and-corner] [--creasing uniform|chaikin]\n"
        "         [--tri-sub catmark|smooth] [--out-prefix P | --time [--repeat K]]\n");
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    try {
        oracle::Args a(argc, argv, {"time"});
        if (a.pos.size() != 1 || !a.has("scheme")) return usage();
        const std::string in = a.pos[0];
        const int levels = oracle::parse_levels(a);
        oracle::Mesh m = oracle::read_mesh(in);

        Setup s;
        std::string scheme = a.get("scheme");
        if (scheme == "catmark" || scheme == "catmull-clark") s.scheme = Sdc::SCHEME_CATMARK, scheme = "catmark";
        else if (scheme == "loop") s.scheme = Sdc::SCHEME_LOOP;
        else return usage();
        if (s.scheme == Sdc::SCHEME_LOOP && !m.all_faces_of_size(3)) {
            std::fprintf(stderr, "osd_oracle: Loop needs an all-triangle mesh\n");
            return 1;
        }

        // boundary: option > OBJ tag > edge-only
        Sdc::Options::VtxBoundaryInterpolation b = Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
        if (m.interpolateboundary == 0) b = Sdc::Options::VTX_BOUNDARY_NONE;
        else if (m.interpolateboundary == 1) b = Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER;
        else if (m.interpolateboundary == 2) b = Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
        if (a.has("boundary")) {
            std::string bs = a.get("boundary");
            if (bs == "none") b = Sdc::Options::VTX_BOUNDARY_NONE;
            else if (bs == "edge-only") b = Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
            else if (bs == "edge-and-corner") b = Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER;
            else return usage();
        }
        s.opts.SetVtxBoundaryInterpolation(b);
        std::string cr = a.get("creasing", m.creasemethod == "chaikin" ? "chaikin" : "uniform");
        if (cr == "uniform") s.opts.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
        else if (cr == "chaikin") s.opts.SetCreasingMethod(Sdc::Options::CREASE_CHAIKIN);
        else return usage();
        std::string ts = a.get("tri-sub", m.smoothtriangles.empty() ? "catmark" : m.smoothtriangles);
        if (ts == "catmark") s.opts.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);
        else if (ts == "smooth") s.opts.SetTriangleSubdivision(Sdc::Options::TRI_SUB_SMOOTH);
        else return usage();
        std::fprintf(stderr, "osd_oracle: %s scheme=%s levels=%d boundary=%s creasing=%s tri-sub=%s creases=%zu corners=%zu\n",
                     in.c_str(), scheme.c_str(), levels, boundary_name(b), cr.c_str(), ts.c_str(),
                     m.creases.size(), m.corners.size());

        std::vector<int> cp, ci;
        std::vector<float> cw, cow;

        if (a.has("time")) {
            int repeat = std::max(1, std::atoi(a.get("repeat", "5").c_str()));
            std::vector<double> tref, tint;
            long long peak = 0, refbytes = 0;
            int nv = 0, nf = 0;
            for (int r = 0; r < repeat; ++r) {
                long long base = g_live.load();
                g_peak.store(base);
                auto t0 = std::chrono::steady_clock::now();
                Far::TopologyRefiner* R = build_refiner(m, s, cp, cw, ci, cow);
                if (!R) { std::fprintf(stderr, "osd_oracle: factory failed\n"); return 1; }
                R->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
                tref.push_back(ms_since(t0));
                refbytes = g_live.load() - base;
                // buffers for all levels (allocation not timed)
                std::vector<Vertex> buf(R->GetNumVerticesTotal());
                load_base(m, buf);
                Far::PrimvarRefinerReal<double> pr(*R);
                auto t1 = std::chrono::steady_clock::now();
                Vertex* src = buf.data();
                for (int L = 1; L <= levels; ++L) {
                    Vertex* dst = src + R->GetLevel(L - 1).GetNumVertices();
                    pr.Interpolate(L, src, dst);
                    src = dst;
                }
                tint.push_back(ms_since(t1));
                peak = std::max(peak, g_peak.load() - base);
                nv = R->GetLevel(levels).GetNumVertices();
                nf = R->GetLevel(levels).GetNumFaces();
                // keep the result alive until here so the optimiser cannot drop it
                volatile double sink = src[0].p[0];
                (void)sink;
                delete R;
            }
            std::printf("osd scheme=%s levels=%d refine_ms=%.3f interp_ms=%.3f bytes=%lld refiner_bytes=%lld verts=%d faces=%d repeat=%d\n",
                        scheme.c_str(), levels, median(tref), median(tint), peak, refbytes, nv, nf, repeat);
            return 0;
        }

        std::string prefix = a.get("out-prefix", "");
        if (prefix.empty()) return usage();
        Far::TopologyRefiner* R = build_refiner(m, s, cp, cw, ci, cow);
        if (!R) { std::fprintf(stderr, "osd_oracle: factory failed (invalid topology?)\n"); return 1; }
        R->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
        std::vector<Vertex> buf(R->GetNumVerticesTotal());
        load_base(m, buf);
        Far::PrimvarRefinerReal<double> pr(*R);
        Vertex* src = buf.data();
        for (int L = 1; L <= levels; ++L) {
            Vertex* dst = src + R->GetLevel(L - 1).GetNumVertices();
            pr.Interpolate(L, src, dst);
            const Far::TopologyLevel& lev = R->GetLevel(L);
            std::vector<int> fs, fi;
            fs.reserve(lev.GetNumFaces());
            for (int f = 0; f < lev.GetNumFaces(); ++f) {
                if (lev.IsFaceHole(f)) continue;
                Far::ConstIndexArray fv = lev.GetFaceVertices(f);
                fs.push_back(fv.size());
                for (int k = 0; k < fv.size(); ++k) fi.push_back(fv[k]);
            }
            std::string out = prefix + "_" + std::to_string(L) + ".obj";
            oracle::write_obj(out, &dst[0].p[0], lev.GetNumVertices(), fs, fi,
                              "osd_oracle " + scheme + " level " + std::to_string(L) + " boundary=" + boundary_name(b) +
                              " creasing=" + cr + " tri-sub=" + ts);
            std::fprintf(stderr, "  level %d: %d verts %d faces -> %s\n", L, lev.GetNumVertices(), lev.GetNumFaces(), out.c_str());
            src = dst;
        }
        delete R;
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "osd_oracle: %s\n", e.what());
        return 1;
    }
}
