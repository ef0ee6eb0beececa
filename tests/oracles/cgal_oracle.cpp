// cgal_oracle: reference subdivision with CGAL 5.5 Subdivision_method_3 (test-only).
//
//   cgal_oracle IN.{obj,off,ply} --scheme doo-sabin|sqrt3|catmull-clark|loop --levels N --out-prefix P
//     -> writes P_1.obj .. P_N.obj
//
// Mesh type: CGAL::Surface_mesh<Simple_cartesian<double>::Point_3> (plain doubles, so the
// arithmetic is the same as the masks in <CGAL/Subdivision_method_3/subdivision_masks_3.h>).
//
// Levels: catmull-clark, loop and doo-sabin are run one call per level with
// number_of_iterations(1) on the growing mesh.  sqrt3 is different: CGAL's
// Sqrt3_subdivision(np) refines boundaries only on every SECOND iteration *of one call*
// (internal::Sqrt3_1step(..., refine_border = (i%2==1))), so depth-1 calls would never
// touch the boundary.  For sqrt3 each level L is therefore computed from the input with a
// single call of number_of_iterations(L); on closed meshes both ways are identical.
//
// Output: only vertices referenced by at least one face are written (isolated vertices,
// if any, are dropped and counted on stderr).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include <cstdio>
#include <string>
#include <vector>

#include "mesh_io.h"

typedef CGAL::Simple_cartesian<double> K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> SM;
namespace SMeth = CGAL::Subdivision_method_3;

static int usage() {
    std::fprintf(stderr, "usage: cgal_oracle IN.{obj,off,ply} --scheme doo-sabin|sqrt3|catmull-clark|loop --levels N --out-prefix P\n");
    return 2;
}

static SM build(const oracle::Mesh& m, int& rejected) {
    SM sm;
    std::vector<SM::Vertex_index> vh(m.nverts());
    for (int i = 0; i < m.nverts(); ++i) vh[i] = sm.add_vertex(Point(m.P[3 * i], m.P[3 * i + 1], m.P[3 * i + 2]));
    rejected = 0;
    size_t k = 0;
    std::vector<SM::Vertex_index> f;
    for (int n : m.fsize) {
        f.clear();
        for (int j = 0; j < n; ++j) f.push_back(vh[m.fidx[k++]]);
        if (sm.add_face(f) == SM::null_face()) ++rejected;
    }
    return sm;
}

static void write(const SM& sm, const std::string& path, const std::string& comment) {
    std::vector<int> map(sm.num_vertices(), -1); // num_vertices() counts removed ones too
    std::vector<double> P;
    std::vector<int> fs, fi;
    int nv = 0;
    for (SM::Face_index f : sm.faces()) {
        int n = 0;
        for (SM::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
            int& id = map[(size_t)v];
            if (id < 0) {
                id = nv++;
                const Point& p = sm.point(v);
                P.push_back(p.x()); P.push_back(p.y()); P.push_back(p.z());
            }
            fi.push_back(id);
            ++n;
        }
        fs.push_back(n);
    }
    int isolated = (int)sm.number_of_vertices() - nv;
    if (isolated > 0) std::fprintf(stderr, "  (dropped %d unreferenced vertices)\n", isolated);
    oracle::write_obj(path, P.data(), nv, fs, fi, comment);
}

int main(int argc, char** argv) {
    try {
        oracle::Args a(argc, argv, {});
        if (a.pos.size() != 1 || !a.has("scheme") || !a.has("out-prefix")) return usage();
        const std::string scheme = a.get("scheme"), prefix = a.get("out-prefix");
        const int levels = oracle::parse_levels(a);
        if (scheme != "doo-sabin" && scheme != "sqrt3" && scheme != "catmull-clark" && scheme != "loop") return usage();
        oracle::Mesh m = oracle::read_mesh(a.pos[0]);
        if ((scheme == "sqrt3" || scheme == "loop") && !m.all_faces_of_size(3)) {
            std::fprintf(stderr, "cgal_oracle: %s needs an all-triangle mesh\n", scheme.c_str());
            return 1;
        }
        {
            int pinch = 0, nme = 0;
            oracle::nonmanifold_counts(m, pinch, nme);
            if (pinch || nme)
                std::fprintf(stderr, "%s: warning: %d pinch vertices, %d non-manifold edges: results there are "
                             "library-specific (OpenSubdiv makes them sharp); compare on manifold input only\n",
                             "cgal_oracle", pinch, nme);
        }
        if (!m.creases.empty() || !m.corners.empty())
            std::fprintf(stderr, "cgal_oracle: warning: crease/corner tags ignored (CGAL has no creases)\n");
        int rejected = 0;
        SM base = build(m, rejected);
        if (rejected) {
            std::fprintf(stderr, "cgal_oracle: %d faces rejected by Surface_mesh::add_face (non-manifold input); refusing\n", rejected);
            return 1;
        }
        std::fprintf(stderr, "cgal_oracle: %s scheme=%s levels=%d (%zu verts, %zu faces)\n", a.pos[0].c_str(),
                     scheme.c_str(), levels, (size_t)base.number_of_vertices(), (size_t)base.number_of_faces());
        SM sm = base;
        for (int L = 1; L <= levels; ++L) {
            if (scheme == "catmull-clark")
                SMeth::CatmullClark_subdivision(sm, CGAL::parameters::number_of_iterations(1));
            else if (scheme == "loop")
                SMeth::Loop_subdivision(sm, CGAL::parameters::number_of_iterations(1));
            else if (scheme == "doo-sabin")
                SMeth::DooSabin_subdivision(sm, CGAL::parameters::number_of_iterations(1));
            else {
                sm = base;
                SMeth::Sqrt3_subdivision(sm, CGAL::parameters::number_of_iterations(L));
            }
            std::string out = prefix + "_" + std::to_string(L) + ".obj";
            std::fprintf(stderr, "  level %d: %zu verts %zu faces -> %s\n", L, (size_t)sm.number_of_vertices(),
                         (size_t)sm.number_of_faces(), out.c_str());
            write(sm, out, "cgal_oracle " + scheme + " level " + std::to_string(L));
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cgal_oracle: %s\n", e.what());
        return 1;
    }
}
