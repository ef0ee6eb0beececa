// osd_fvar_oracle: OpenSubdiv's face-varying refinement of UVs, test-only.
//
//   osd_fvar_oracle IN.obj --scheme catmark|loop --levels N --uv-interp NAME
//                   [--boundary edge-only|edge-and-corner] --out-prefix P
//       -> P_1.obj .. P_N.obj: positions (Far::PrimvarRefinerReal<double>::
//          Interpolate), UVs (InterpolateFaceVarying, channel 0) as vt, faces
//          as f v/t.  NAME: none corners-only corners-plus1 corners-plus2
//          boundaries all (Sdc::Options::FVarLinearInterpolation).
//   osd_fvar_oracle --compare A.obj B.obj [--tol 1e-6]
//       -> per face corner: the corner of B at the same vertex (nearest
//          position) leading to the same next vertex has the same UV within
//          tol (absolute).  Prints "corners=N max_uv_err=E"; exit 1 when
//          counts differ, a corner has no match, or an error exceeds tol.
//
// Reads `v`, `vt` and `f` (v, v/t, v/t/n, v//n) only; indices from 1.
// OpenSubdiv's creases and other tags are not read: the meshes given here
// carry none.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

struct Obj {
    std::vector<double> pos;      // 3 per vertex
    std::vector<double> uv;       // 2 per texture coordinate
    std::vector<int> counts;      // per face
    std::vector<int> verts, uvs;  // per corner (0-based)
};

bool read_obj(const char* path, Obj& m) {
    std::ifstream in(path);
    if (!in) { std::fprintf(stderr, "%s: cannot open\n", path); return false; }
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ss(line);
        std::string kw;
        ss >> kw;
        if (kw == "v") {
            double x, y, z;
            ss >> x >> y >> z;
            m.pos.insert(m.pos.end(), {x, y, z});
        } else if (kw == "vt") {
            double u, v = 0;
            ss >> u;
            if (!(ss >> v)) v = 0;
            m.uv.insert(m.uv.end(), {u, v});
        } else if (kw == "f") {
            std::string c;
            int n = 0;
            while (ss >> c) {
                int v = std::atoi(c.c_str()), t = 0;
                size_t s = c.find('/');
                if (s != std::string::npos && s + 1 < c.size() && c[s + 1] != '/') t = std::atoi(c.c_str() + s + 1);
                m.verts.push_back(v - 1);
                m.uvs.push_back(t - 1);
                n++;
            }
            m.counts.push_back(n);
        }
    }
    return true;
}

bool write_obj(const std::string& path, const Obj& m) {
    FILE* f = std::fopen(path.c_str(), "w");
    if (!f) return false;
    for (size_t i = 0; i < m.pos.size(); i += 3) std::fprintf(f, "v %.17g %.17g %.17g\n", m.pos[i], m.pos[i + 1], m.pos[i + 2]);
    for (size_t i = 0; i < m.uv.size(); i += 2) std::fprintf(f, "vt %.17g %.17g\n", m.uv[i], m.uv[i + 1]);
    size_t c = 0;
    for (int n : m.counts) {
        std::fputc('f', f);
        for (int k = 0; k < n; k++, c++) std::fprintf(f, " %d/%d", m.verts[c] + 1, m.uvs[c] + 1);
        std::fputc('\n', f);
    }
    return std::fclose(f) == 0;
}

struct P3 { double x, y, z; };
struct P2 { double u, v; };

int refine(int argc, char** argv) {
    const char* in = argv[1];
    std::string scheme = "catmark", interp = "corners-plus1", boundary = "edge-only", prefix = "osd_fvar";
    int levels = 1;
    for (int i = 2; i + 1 < argc; i += 2) {
        std::string a = argv[i];
        if (a == "--scheme") scheme = argv[i + 1];
        else if (a == "--levels") levels = std::atoi(argv[i + 1]);
        else if (a == "--uv-interp") interp = argv[i + 1];
        else if (a == "--boundary") boundary = argv[i + 1];
        else if (a == "--out-prefix") prefix = argv[i + 1];
        else { std::fprintf(stderr, "unknown option %s\n", argv[i]); return 2; }
    }
    Obj m;
    if (!read_obj(in, m)) return 1;
    if (m.uv.empty() || std::count(m.uvs.begin(), m.uvs.end(), -1)) { std::fprintf(stderr, "%s: no UVs on every corner\n", in); return 1; }
    static const std::map<std::string, Sdc::Options::FVarLinearInterpolation> fvar = {
        {"none", Sdc::Options::FVAR_LINEAR_NONE},
        {"corners-only", Sdc::Options::FVAR_LINEAR_CORNERS_ONLY},
        {"corners-plus1", Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1},
        {"corners-plus2", Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2},
        {"boundaries", Sdc::Options::FVAR_LINEAR_BOUNDARIES},
        {"all", Sdc::Options::FVAR_LINEAR_ALL},
    };
    if (!fvar.count(interp)) { std::fprintf(stderr, "unknown --uv-interp %s\n", interp.c_str()); return 2; }
    Sdc::Options opts;
    opts.SetVtxBoundaryInterpolation(boundary == "edge-and-corner" ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                                                   : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    opts.SetFVarLinearInterpolation(fvar.at(interp));
    std::fprintf(stderr, "osd_fvar_oracle: scheme=%s uv-interp=%s boundary=%s levels=%d\n", scheme.c_str(), interp.c_str(),
                 boundary.c_str(), levels);

    typedef Far::TopologyDescriptor Descriptor;
    Descriptor desc;
    desc.numVertices = (int)(m.pos.size() / 3);
    desc.numFaces = (int)m.counts.size();
    desc.numVertsPerFace = m.counts.data();
    desc.vertIndicesPerFace = m.verts.data();
    Descriptor::FVarChannel channel;
    channel.numValues = (int)(m.uv.size() / 2);
    channel.valueIndices = m.uvs.data();
    desc.numFVarChannels = 1;
    desc.fvarChannels = &channel;
    Far::TopologyRefinerFactory<Descriptor>::Options fo(scheme == "loop" ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, opts);
    Far::TopologyRefiner* r = Far::TopologyRefinerFactory<Descriptor>::Create(desc, fo);
    if (!r) { std::fprintf(stderr, "%s: OpenSubdiv refused the topology\n", in); return 1; }
    Far::TopologyRefiner::UniformOptions uo(levels);
    uo.fullTopologyInLastLevel = true;
    r->RefineUniform(uo);

    struct V3 { double p[3]; void Clear() { p[0] = p[1] = p[2] = 0; }
                void AddWithWeight(const V3& s, double w) { for (int k = 0; k < 3; k++) p[k] += w * s.p[k]; } };
    struct V2 { double p[2]; void Clear() { p[0] = p[1] = 0; }
                void AddWithWeight(const V2& s, double w) { for (int k = 0; k < 2; k++) p[k] += w * s.p[k]; } };
    std::vector<V3> pos(r->GetNumVerticesTotal());
    std::vector<V2> uv(r->GetNumFVarValuesTotal(0));
    for (size_t i = 0; i < m.pos.size() / 3; i++) for (int k = 0; k < 3; k++) pos[i].p[k] = m.pos[3 * i + k];
    for (size_t i = 0; i < m.uv.size() / 2; i++) for (int k = 0; k < 2; k++) uv[i].p[k] = m.uv[2 * i + k];
    Far::PrimvarRefinerReal<double> pr(*r);
    V3* ps = pos.data();
    V2* us = uv.data();
    for (int l = 1; l <= levels; l++) {
        V3* pd = ps + r->GetLevel(l - 1).GetNumVertices();
        V2* ud = us + r->GetLevel(l - 1).GetNumFVarValues(0);
        pr.Interpolate(l, ps, pd);
        pr.InterpolateFaceVarying(l, us, ud, 0);
        Far::TopologyLevel const& lv = r->GetLevel(l);
        Obj o;
        for (int v = 0; v < lv.GetNumVertices(); v++) o.pos.insert(o.pos.end(), {pd[v].p[0], pd[v].p[1], pd[v].p[2]});
        for (int t = 0; t < lv.GetNumFVarValues(0); t++) o.uv.insert(o.uv.end(), {ud[t].p[0], ud[t].p[1]});
        for (int f = 0; f < lv.GetNumFaces(); f++) {
            Far::ConstIndexArray fv = lv.GetFaceVertices(f), ft = lv.GetFaceFVarValues(f, 0);
            o.counts.push_back(fv.size());
            for (int k = 0; k < fv.size(); k++) { o.verts.push_back(fv[k]); o.uvs.push_back(ft[k]); }
        }
        if (!write_obj(prefix + "_" + std::to_string(l) + ".obj", o)) { std::fprintf(stderr, "cannot write level %d\n", l); return 1; }
        ps = pd;
        us = ud;
    }
    delete r;
    return 0;
}

// Vertex of b nearest to each vertex of a (sorted by x, scanning a window).
std::vector<int> match_vertices(const Obj& a, const Obj& b, double tol) {
    size_t nb = b.pos.size() / 3;
    std::vector<int> order(nb);
    for (size_t i = 0; i < nb; i++) order[i] = (int)i;
    std::sort(order.begin(), order.end(), [&](int i, int j) { return b.pos[3 * i] < b.pos[3 * j]; });
    std::vector<double> xs(nb);
    for (size_t i = 0; i < nb; i++) xs[i] = b.pos[3 * order[i]];
    std::vector<int> to(a.pos.size() / 3, -1);
    for (size_t v = 0; v < to.size(); v++) {
        const double* p = &a.pos[3 * v];
        size_t i = std::lower_bound(xs.begin(), xs.end(), p[0] - tol) - xs.begin();
        double best = tol * tol;
        for (; i < nb && xs[i] <= p[0] + tol; i++) {
            const double* q = &b.pos[3 * order[i]];
            double d = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
            if (d <= best) { best = d; to[v] = order[i]; }
        }
    }
    return to;
}

int compare(int argc, char** argv) {
    if (argc < 4) return 2;
    double tol = 1e-6;
    for (int i = 4; i + 1 < argc; i += 2) if (!std::strcmp(argv[i], "--tol")) tol = std::atof(argv[i + 1]);
    Obj a, b;
    if (!read_obj(argv[2], a) || !read_obj(argv[3], b)) return 1;
    if (a.counts.size() != b.counts.size() || a.verts.size() != b.verts.size() || a.pos.size() != b.pos.size()) {
        std::printf("counts differ: faces %zu/%zu corners %zu/%zu vertices %zu/%zu\n", a.counts.size(), b.counts.size(),
                    a.verts.size(), b.verts.size(), a.pos.size() / 3, b.pos.size() / 3);
        return 1;
    }
    if (std::count(a.uvs.begin(), a.uvs.end(), -1) || std::count(b.uvs.begin(), b.uvs.end(), -1)) {
        std::printf("a corner has no UV\n");
        return 1;
    }
    // Positions match to the subdivision's rounding: a window relative to the size.
    double ext = 0;
    for (double x : b.pos) ext = std::max(ext, std::fabs(x));
    std::vector<int> to = match_vertices(a, b, 1e-7 * (ext > 1 ? ext : 1));
    std::map<std::pair<int, int>, int> corner_b;  // (vertex, next vertex) -> uv index
    for (size_t f = 0, c = 0; f < b.counts.size(); c += b.counts[f], f++)
        for (int k = 0; k < b.counts[f]; k++) corner_b[{b.verts[c + k], b.verts[c + (k + 1) % b.counts[f]]}] = b.uvs[c + k];
    double worst = 0;
    size_t unmatched = 0, bad = 0;
    for (size_t f = 0, c = 0; f < a.counts.size(); c += a.counts[f], f++)
        for (int k = 0; k < a.counts[f]; k++) {
            int u = to[a.verts[c + k]], w = to[a.verts[c + (k + 1) % a.counts[f]]];
            auto it = corner_b.find({u, w});
            if (u < 0 || w < 0 || it == corner_b.end()) { unmatched++; continue; }
            const double* p = &a.uv[2 * a.uvs[c + k]];
            const double* q = &b.uv[2 * it->second];
            double e = std::max(std::fabs(p[0] - q[0]), std::fabs(p[1] - q[1]));
            worst = std::max(worst, e);
            if (!(e <= tol)) {
                if (bad++ < 5)
                    std::printf("corner %zu (face %zu, vertex at %.6g %.6g %.6g): uv %.9g %.9g vs %.9g %.9g\n", c + k, f,
                                a.pos[3 * a.verts[c + k]], a.pos[3 * a.verts[c + k] + 1], a.pos[3 * a.verts[c + k] + 2],
                                p[0], p[1], q[0], q[1]);
            }
        }
    std::printf("corners=%zu unmatched=%zu bad=%zu max_uv_err=%.3g\n", a.verts.size(), unmatched, bad, worst);
    return unmatched || bad ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 2 && !std::strcmp(argv[1], "--compare")) return compare(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: osd_fvar_oracle IN.obj --scheme catmark|loop --levels N --uv-interp NAME --out-prefix P\n"
                             "       osd_fvar_oracle --compare A.obj B.obj [--tol T]\n");
        return 2;
    }
    return refine(argc, argv);
}
