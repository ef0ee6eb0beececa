// pointset_diff: compare two meshes as point sets (vertex order differs between libraries).
//
//   pointset_diff A.{obj,off,ply} B.{obj,off,ply} [--tol T]
//
// Prints one line:
//   verts A=.. B=.. faces A=.. B=.. facesizes=same|differ diag=.. max_nn=.. max_nn_rel=.. (A->B .., B->A ..)
// max_nn is the symmetric (Hausdorff) distance between the two vertex sets:
//   max( max_a min_b |a-b|, max_b min_a |a-b| ),
// and max_nn_rel = max_nn / (bounding-box diagonal of A).  Only vertices referenced by a
// face are used (isolated vertices are ignored).  `facesizes` compares the face-size
// histograms.  Exit status: 0; with --tol T: 0 if the vertex and face counts match, the
// face-size histograms match and max_nn_rel <= T, else 1.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "mesh_io.h"

namespace {

struct Grid {
    double lo[3], cell;
    int n[3];
    std::unordered_map<long long, std::vector<int>> cells;
    const std::vector<double>* P;

    long long key(int i, int j, int k) const { return ((long long)i * n[1] + j) * n[2] + k; }
    void cell_of(const double* p, int c[3]) const {
        for (int d = 0; d < 3; ++d) {
            int v = (int)std::floor((p[d] - lo[d]) / cell);
            c[d] = std::min(std::max(v, 0), n[d] - 1);
        }
    }
    void build(const std::vector<double>& pts) {
        P = &pts;
        size_t np = pts.size() / 3;
        double hi[3];
        for (int d = 0; d < 3; ++d) { lo[d] = 1e300; hi[d] = -1e300; }
        for (size_t i = 0; i < np; ++i)
            for (int d = 0; d < 3; ++d) { lo[d] = std::min(lo[d], pts[3 * i + d]); hi[d] = std::max(hi[d], pts[3 * i + d]); }
        double ext = 0;
        for (int d = 0; d < 3; ++d) ext = std::max(ext, hi[d] - lo[d]);
        if (ext <= 0) ext = 1;
        // ~2 points per occupied cell for surface-like sets: cell ~ ext / sqrt(np/2)
        double target = std::max(1.0, std::sqrt((double)np / 2.0));
        cell = ext / target;
        for (int d = 0; d < 3; ++d) n[d] = std::max(1, (int)std::ceil((hi[d] - lo[d]) / cell) + 1);
        for (size_t i = 0; i < np; ++i) {
            int c[3];
            cell_of(&pts[3 * i], c);
            cells[key(c[0], c[1], c[2])].push_back((int)i);
        }
    }
    // nearest distance from q to the point set
    double nearest(const double* q) const {
        int c[3];
        cell_of(q, c);
        double best = 1e300;
        int maxr = std::max(n[0], std::max(n[1], n[2]));
        for (int r = 0; r <= maxr; ++r) {
            // visit shell at Chebyshev radius r
            for (int i = c[0] - r; i <= c[0] + r; ++i) {
                if (i < 0 || i >= n[0]) continue;
                for (int j = c[1] - r; j <= c[1] + r; ++j) {
                    if (j < 0 || j >= n[1]) continue;
                    for (int k = c[2] - r; k <= c[2] + r; ++k) {
                        if (k < 0 || k >= n[2]) continue;
                        if (std::max(std::abs(i - c[0]), std::max(std::abs(j - c[1]), std::abs(k - c[2]))) != r) continue;
                        auto it = cells.find(key(i, j, k));
                        if (it == cells.end()) continue;
                        for (int idx : it->second) {
                            const double* p = &(*P)[3 * idx];
                            double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
                            best = std::min(best, dx * dx + dy * dy + dz * dz);
                        }
                    }
                }
            }
            // any point outside the visited cube is at least r*cell away from q
            double safe = r * cell;
            if (best < 1e300 && best <= safe * safe) break;
        }
        return std::sqrt(best);
    }
};

std::vector<double> used_points(const oracle::Mesh& m) {
    std::vector<char> used(m.nverts(), 0);
    for (int v : m.fidx) used[v] = 1;
    std::vector<double> P;
    for (int i = 0; i < m.nverts(); ++i)
        if (used[i]) { P.push_back(m.P[3 * i]); P.push_back(m.P[3 * i + 1]); P.push_back(m.P[3 * i + 2]); }
    return P;
}

double directed(const std::vector<double>& A, const Grid& gB) {
    double mx = 0;
    for (size_t i = 0; i < A.size() / 3; ++i) mx = std::max(mx, gB.nearest(&A[3 * i]));
    return mx;
}

} // namespace

int main(int argc, char** argv) {
    try {
        oracle::Args a(argc, argv, {});
        if (a.pos.size() != 2) {
            std::fprintf(stderr, "usage: pointset_diff A.obj B.obj [--tol T]\n");
            return 2;
        }
        oracle::Mesh A = oracle::read_mesh(a.pos[0]), B = oracle::read_mesh(a.pos[1]);
        std::vector<double> PA = used_points(A), PB = used_points(B);
        double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
        for (size_t i = 0; i < PA.size() / 3; ++i)
            for (int d = 0; d < 3; ++d) { lo[d] = std::min(lo[d], PA[3 * i + d]); hi[d] = std::max(hi[d], PA[3 * i + d]); }
        double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
        if (!(diag > 0)) diag = 1;
        double ab = 0, ba = 0;
        if (!PA.empty() && !PB.empty()) {
            Grid gA, gB;
            gA.build(PA);
            gB.build(PB);
            ab = directed(PA, gB);
            ba = directed(PB, gA);
        }
        std::map<int, int> ha, hb;
        for (int s : A.fsize) ha[s]++;
        for (int s : B.fsize) hb[s]++;
        bool same_sizes = ha == hb;
        double mx = std::max(ab, ba);
        std::printf("verts A=%zu B=%zu faces A=%d B=%d facesizes=%s diag=%.6g max_nn=%.3e max_nn_rel=%.3e (A->B %.3e, B->A %.3e)\n",
                    PA.size() / 3, PB.size() / 3, A.nfaces(), B.nfaces(), same_sizes ? "same" : "differ", diag, mx,
                    mx / diag, ab / diag, ba / diag);
        if (a.has("tol")) {
            double tol = std::atof(a.get("tol").c_str());
            bool ok = PA.size() == PB.size() && A.nfaces() == B.nfaces() && same_sizes && mx / diag <= tol;
            return ok ? 0 : 1;
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pointset_diff: %s\n", e.what());
        return 2;
    }
}
