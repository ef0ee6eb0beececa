// openmesh_oracle: reference subdivision with OpenMesh 9 Subdivider::Uniform (test-only).
//
//   openmesh_oracle IN.{obj,off,ply} --scheme butterfly|sqrt3|loop|catmull-clark --levels N --out-prefix P
//     -> writes P_1.obj .. P_N.obj
//
//   butterfly     = ModifiedButterflyT (TriMesh)      sqrt3 = Sqrt3T (TriMesh)
//   loop          = LoopT (TriMesh)                   catmull-clark = CatmullClarkT (PolyMesh)
//
// Meshes use double points (Vec3d) -- OpenMesh's default traits are float.
// The subdivider is attach()ed once and then called with n=1 per level, so state kept
// in the subdivider across steps is preserved: Sqrt3T's generation counter (boundary
// 1-to-3 split on every second step) survives between levels exactly as in one call
// with n=N.  (Calling sub(mesh, 1) repeatedly would re-run prepare() and restart it.)
// LoopT and Sqrt3T weight tables hold 50 entries (valence 0..49); init_weights() is
// called with max valence + 1 when needed so high-valence vertices are not read past
// the end.  ModifiedButterflyT grows its own table.
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/ModifiedButterFlyT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/Sqrt3T.hh>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "mesh_io.h"

struct DTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<DTraits> TriMesh;
typedef OpenMesh::PolyMesh_ArrayKernelT<DTraits> PolyMesh;

static int usage() {
    std::fprintf(stderr, "usage: openmesh_oracle IN.{obj,off,ply} --scheme butterfly|sqrt3|loop|catmull-clark --levels N --out-prefix P\n");
    return 2;
}

template <class M>
static int build(const oracle::Mesh& m, M& om) {
    std::vector<typename M::VertexHandle> vh(m.nverts());
    for (int i = 0; i < m.nverts(); ++i)
        vh[i] = om.add_vertex(typename M::Point(m.P[3 * i], m.P[3 * i + 1], m.P[3 * i + 2]));
    int rejected = 0;
    size_t k = 0;
    std::vector<typename M::VertexHandle> f;
    for (int n : m.fsize) {
        f.clear();
        for (int j = 0; j < n; ++j) f.push_back(vh[m.fidx[k++]]);
        if (!om.add_face(f).is_valid()) ++rejected;
    }
    return rejected;
}

template <class M>
static unsigned max_valence(const M& om) {
    unsigned v = 0;
    for (auto vh : om.vertices()) v = std::max(v, om.valence(vh));
    return v;
}

template <class M>
static void write(const M& om, const std::string& path, const std::string& comment) {
    std::vector<int> map(om.n_vertices(), -1);
    std::vector<double> P;
    std::vector<int> fs, fi;
    int nv = 0;
    for (auto fh : om.faces()) {
        int n = 0;
        for (auto v : om.fv_range(fh)) {
            int& id = map[v.idx()];
            if (id < 0) {
                id = nv++;
                auto p = om.point(v);
                P.push_back(p[0]); P.push_back(p[1]); P.push_back(p[2]);
            }
            fi.push_back(id);
            ++n;
        }
        fs.push_back(n);
    }
    int isolated = (int)om.n_vertices() - nv;
    if (isolated > 0) std::fprintf(stderr, "  (dropped %d unreferenced vertices)\n", isolated);
    oracle::write_obj(path, P.data(), nv, fs, fi, comment);
}

template <class M, bool TABLE50, class SUB>
static int run(const oracle::Mesh& m, SUB& sub, const std::string& scheme, int levels, const std::string& prefix) {
    M om;
    int rejected = build(m, om);
    if (rejected) {
        std::fprintf(stderr, "openmesh_oracle: %d faces rejected by add_face (complex vertex/edge); refusing\n", rejected);
        return 1;
    }
    if constexpr (TABLE50) {
        unsigned mv = max_valence(om);
        if (mv + 1 > 50) sub.init_weights(mv + 1); // valence does not grow under Loop/sqrt3 refinement
    }
    if (!sub.attach(om)) { std::fprintf(stderr, "openmesh_oracle: attach failed\n"); return 1; }
    for (int L = 1; L <= levels; ++L) {
        if (!sub(1)) { std::fprintf(stderr, "openmesh_oracle: subdivision failed at level %d\n", L); return 1; }
        std::string out = prefix + "_" + std::to_string(L) + ".obj";
        std::fprintf(stderr, "  level %d: %zu verts %zu faces -> %s\n", L, (size_t)om.n_vertices(), (size_t)om.n_faces(), out.c_str());
        write(om, out, "openmesh_oracle " + scheme + " level " + std::to_string(L));
    }
    sub.detach();
    return 0;
}

int main(int argc, char** argv) {
    try {
        oracle::Args a(argc, argv, {});
        if (a.pos.size() != 1 || !a.has("scheme") || !a.has("out-prefix")) return usage();
        const std::string scheme = a.get("scheme"), prefix = a.get("out-prefix");
        const int levels = oracle::parse_levels(a);
        oracle::Mesh m = oracle::read_mesh(a.pos[0]);
        {
            int pinch = 0, nme = 0;
            oracle::nonmanifold_counts(m, pinch, nme);
            if (pinch || nme)
                std::fprintf(stderr, "%s: warning: %d pinch vertices, %d non-manifold edges: results there are "
                             "library-specific (OpenSubdiv makes them sharp); compare on manifold input only\n",
                             "openmesh_oracle", pinch, nme);
        }
        if (!m.creases.empty() || !m.corners.empty())
            std::fprintf(stderr, "openmesh_oracle: warning: crease/corner tags ignored\n");
        std::fprintf(stderr, "openmesh_oracle: %s scheme=%s levels=%d (%d verts, %d faces)\n", a.pos[0].c_str(),
                     scheme.c_str(), levels, m.nverts(), m.nfaces());
        if (scheme == "catmull-clark") {
            OpenMesh::Subdivider::Uniform::CatmullClarkT<PolyMesh, double> sub;
            return run<PolyMesh, false>(m, sub, scheme, levels, prefix);
        }
        if (!m.all_faces_of_size(3)) {
            std::fprintf(stderr, "openmesh_oracle: %s needs an all-triangle mesh\n", scheme.c_str());
            return 1;
        }
        if (scheme == "loop") {
            OpenMesh::Subdivider::Uniform::LoopT<TriMesh, double> sub;
            return run<TriMesh, true>(m, sub, scheme, levels, prefix);
        }
        if (scheme == "sqrt3") {
            OpenMesh::Subdivider::Uniform::Sqrt3T<TriMesh, double> sub;
            return run<TriMesh, true>(m, sub, scheme, levels, prefix);
        }
        if (scheme == "butterfly") {
            OpenMesh::Subdivider::Uniform::ModifiedButterflyT<TriMesh, double> sub;
            return run<TriMesh, false>(m, sub, scheme, levels, prefix);
        }
        return usage();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "openmesh_oracle: %s\n", e.what());
        return 1;
    }
}
