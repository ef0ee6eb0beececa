// Small mesh reader/writer shared by the oracle programs (test-only C++17).
//
// Reads:
//   OBJ  : v, f (forms i, i/t, i//n, i/t/n; negative = relative indices),
//          OpenSubdiv tags  `t NAME ni/nf/ns ints... floats... strings...`
//          as its regression harness applies them (regression/common/far_utils.h):
//          crease: vertex pairs; corner: vertices; interpolateboundary: 1 int;
//          hole: face indices; creasemethod, smoothtriangles: 1 string.
//          Other records (vt, vn, o, g, s, usemtl, mtllib, l, #) are ignored.
//   OFF  : ASCII, n-gon faces.
//   PLY  : ascii / binary_little_endian / binary_big_endian; vertex x,y,z of any
//          scalar type, face list `vertex_indices` / `vertex_index`.
// Writes OBJ with `%.17g` coordinates (round-trips doubles exactly).
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace oracle {

struct Crease { int v0, v1; float sharpness; };
struct Corner { int v; float sharpness; };

struct Mesh {
    std::vector<double> P;        // 3 * nverts
    std::vector<int>    fsize;    // vertices per face
    std::vector<int>    fidx;     // concatenated face vertex indices (0-based)
    std::vector<Crease> creases;  // from `t crease`
    std::vector<Corner> corners;  // from `t corner`
    int interpolateboundary = -1; // OBJ tag value (0 none, 1 edge-and-corner, 2 edge-only), -1 = absent
    std::vector<int>    holes;    // from `t hole` (0-based face indices)
    std::string creasemethod;     // from `t creasemethod` ("normal" | "chaikin"), empty = absent
    std::string smoothtriangles;  // from `t smoothtriangles` ("catmark" | "smooth"), empty = absent

    int nverts() const { return (int)(P.size() / 3); }
    int nfaces() const { return (int)fsize.size(); }
    bool all_faces_of_size(int n) const {
        for (int s : fsize) if (s != n) return false;
        return true;
    }
    int max_face_size() const {
        int m = 0;
        for (int s : fsize) m = std::max(m, s);
        return m;
    }
};

inline std::string lower_ext(const std::string& path) {
    size_t dot = path.find_last_of('.');
    if (dot == std::string::npos) return "";
    std::string e = path.substr(dot + 1);
    for (auto& c : e) c = (char)std::tolower((unsigned char)c);
    return e;
}

inline std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Resolve an OBJ index token (1-based, negative = relative to current count).
inline int obj_index(long v, int count, const std::string& path, int line) {
    long r = v > 0 ? v - 1 : (v < 0 ? count + v : -1);
    if (v == 0 || r < 0)
        throw std::runtime_error(path + ":" + std::to_string(line) + ": bad vertex index " + std::to_string(v));
    return (int)r;
}

inline void read_obj(const std::string& path, Mesh& m) {
    std::string text = read_all(path);
    std::istringstream in(text);
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        // handle CRLF and line continuations are not supported (not used by the data set)
        if (!line.empty() && line.back() == '\r') line.pop_back();
        size_t p = line.find_first_not_of(" \t");
        if (p == std::string::npos || line[p] == '#') continue;
        std::istringstream ls(line.substr(p));
        std::string kw;
        ls >> kw;
        if (kw == "v") {
            double x = 0, y = 0, z = 0;
            if (!(ls >> x >> y >> z))
                throw std::runtime_error(path + ":" + std::to_string(lineno) + ": bad vertex");
            m.P.push_back(x); m.P.push_back(y); m.P.push_back(z);
        } else if (kw == "f") {
            std::string tok;
            int n = 0;
            while (ls >> tok) {
                long v = std::strtol(tok.c_str(), nullptr, 10); // stops at '/'
                m.fidx.push_back(obj_index(v, m.nverts(), path, lineno));
                ++n;
            }
            if (n < 3) throw std::runtime_error(path + ":" + std::to_string(lineno) + ": face with < 3 vertices");
            m.fsize.push_back(n);
        } else if (kw == "t") {
            std::string name, counts;
            ls >> name >> counts;
            int ni = 0, nf = 0, ns = 0;
            if (std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns) < 2)
                throw std::runtime_error(path + ":" + std::to_string(lineno) + ": bad tag counts");
            std::vector<long> ia(ni);
            std::vector<float> fa(nf);
            std::vector<std::string> sa(ns);
            for (auto& x : ia) ls >> x;
            for (auto& x : fa) ls >> x;
            for (auto& x : sa) ls >> x;
            if (!ls) throw std::runtime_error(path + ":" + std::to_string(lineno) + ": truncated tag");
            if (name == "crease") {
                // OpenSubdiv shape_utils: ints are vertex PAIRS (j += 2); one float applies to all
                // pairs, otherwise one float per pair.
                for (int j = 0; j + 1 < ni; j += 2) {
                    float s = (nf > 1) ? fa[std::min(j / 2, nf - 1)] : (nf ? fa[0] : 0.0f);
                    m.creases.push_back({(int)ia[j], (int)ia[j + 1], std::max(0.0f, s)});
                }
            } else if (name == "corner") {
                for (int j = 0; j < ni; ++j) {
                    float s = (nf > 1) ? fa[std::min(j, nf - 1)] : (nf ? fa[0] : 0.0f);
                    m.corners.push_back({(int)ia[j], std::max(0.0f, s)});
                }
            } else if (name == "interpolateboundary") {
                if (ni >= 1) m.interpolateboundary = (int)ia[0];
            } else if (name == "hole") {
                for (long f : ia) m.holes.push_back((int)f);
            } else if (name == "creasemethod" || name == "smoothtriangles") {
                if (ns < 1) throw std::runtime_error(path + ":" + std::to_string(lineno) + ": " + name + " needs a string");
                (name == "creasemethod" ? m.creasemethod : m.smoothtriangles) = sa[0];
            } else {
                std::fprintf(stderr, "warning: %s:%d: ignoring tag '%s'\n", path.c_str(), lineno, name.c_str());
            }
        }
        // everything else ignored
    }
}

inline void read_off(const std::string& path, Mesh& m) {
    std::string text = read_all(path);
    // strip comments
    std::string clean;
    clean.reserve(text.size());
    bool comment = false;
    for (char c : text) {
        if (c == '#') comment = true;
        if (c == '\n') comment = false;
        if (!comment) clean.push_back(c);
    }
    std::istringstream in(clean);
    std::string head;
    in >> head;
    if (head != "OFF") throw std::runtime_error(path + ": only plain ASCII OFF supported (header '" + head + "')");
    long nv, nf, ne;
    in >> nv >> nf >> ne;
    m.P.resize(3 * nv);
    for (long i = 0; i < 3 * nv; ++i) in >> m.P[i];
    for (long f = 0; f < nf; ++f) {
        int n;
        in >> n;
        for (int k = 0; k < n; ++k) { int v; in >> v; m.fidx.push_back(v); }
        m.fsize.push_back(n);
    }
    if (!in) throw std::runtime_error(path + ": truncated OFF");
}

// ---- PLY ------------------------------------------------------------------
namespace plyd {
enum Type { I8, U8, I16, U16, I32, U32, F32, F64, BAD };
inline Type type_of(const std::string& s) {
    if (s == "char" || s == "int8") return I8;
    if (s == "uchar" || s == "uint8") return U8;
    if (s == "short" || s == "int16") return I16;
    if (s == "ushort" || s == "uint16") return U16;
    if (s == "int" || s == "int32") return I32;
    if (s == "uint" || s == "uint32") return U32;
    if (s == "float" || s == "float32") return F32;
    if (s == "double" || s == "float64") return F64;
    return BAD;
}
inline int size_of(Type t) {
    switch (t) { case I8: case U8: return 1; case I16: case U16: return 2;
                 case I32: case U32: case F32: return 4; case F64: return 8; default: return 0; }
}
struct Prop { std::string name; Type t; bool list = false; Type count_t = BAD; };
struct Elem { std::string name; long count; std::vector<Prop> props; };
} // namespace plyd

inline void read_ply(const std::string& path, Mesh& m) {
    using namespace plyd;
    std::string text = read_all(path);
    size_t hend = text.find("end_header");
    if (text.compare(0, 3, "ply") != 0 || hend == std::string::npos)
        throw std::runtime_error(path + ": not a PLY file");
    size_t body = text.find('\n', hend);
    body = (body == std::string::npos) ? text.size() : body + 1;
    std::istringstream hs(text.substr(0, hend));
    std::string line, fmt;
    std::vector<Elem> elems;
    while (std::getline(hs, line)) {
        std::istringstream ls(line);
        std::string kw;
        ls >> kw;
        if (kw == "format") ls >> fmt;
        else if (kw == "element") { Elem e; ls >> e.name >> e.count; elems.push_back(e); }
        else if (kw == "property") {
            std::string t1; ls >> t1;
            Prop p;
            if (t1 == "list") {
                std::string ct, it; ls >> ct >> it >> p.name;
                p.list = true; p.count_t = type_of(ct); p.t = type_of(it);
            } else { p.t = type_of(t1); ls >> p.name; }
            if (elems.empty()) throw std::runtime_error(path + ": property before element");
            elems.back().props.push_back(p);
        }
    }
    bool ascii = fmt == "ascii";
    bool big = fmt == "binary_big_endian";
    if (!ascii && !big && fmt != "binary_little_endian") throw std::runtime_error(path + ": unknown PLY format " + fmt);
    const unsigned char* data = (const unsigned char*)text.data();
    size_t pos = body, end = text.size();
    std::istringstream as(ascii ? text.substr(body) : std::string());
    auto rd = [&](Type t) -> double {
        if (ascii) { double v; as >> v; if (!as) throw std::runtime_error(path + ": truncated"); return v; }
        int sz = size_of(t);
        if (pos + sz > end) throw std::runtime_error(path + ": truncated binary PLY");
        unsigned char b[8];
        std::memcpy(b, data + pos, sz);
        pos += sz;
        if (big) std::reverse(b, b + sz);
        switch (t) {
            case I8: { int8_t v; std::memcpy(&v, b, 1); return v; }
            case U8: { uint8_t v; std::memcpy(&v, b, 1); return v; }
            case I16: { int16_t v; std::memcpy(&v, b, 2); return v; }
            case U16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
            case I32: { int32_t v; std::memcpy(&v, b, 4); return v; }
            case U32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
            case F32: { float v; std::memcpy(&v, b, 4); return v; }
            case F64: { double v; std::memcpy(&v, b, 8); return v; }
            default: throw std::runtime_error(path + ": bad PLY type");
        }
    };
    for (auto& e : elems) {
        bool isv = e.name == "vertex", isf = e.name == "face";
        for (long i = 0; i < e.count; ++i) {
            double xyz[3] = {0, 0, 0};
            for (auto& p : e.props) {
                if (p.list) {
                    int n = (int)rd(p.count_t);
                    bool idx = isf && (p.name == "vertex_indices" || p.name == "vertex_index");
                    for (int k = 0; k < n; ++k) {
                        double v = rd(p.t);
                        if (idx) m.fidx.push_back((int)v);
                    }
                    if (idx) m.fsize.push_back(n);
                } else {
                    double v = rd(p.t);
                    if (isv) {
                        if (p.name == "x") xyz[0] = v;
                        else if (p.name == "y") xyz[1] = v;
                        else if (p.name == "z") xyz[2] = v;
                    }
                }
            }
            if (isv) { m.P.push_back(xyz[0]); m.P.push_back(xyz[1]); m.P.push_back(xyz[2]); }
        }
    }
}

inline Mesh read_mesh(const std::string& path) {
    Mesh m;
    std::string e = lower_ext(path);
    if (e == "off") read_off(path, m);
    else if (e == "ply") read_ply(path, m);
    else read_obj(path, m);
    for (int v : m.fidx)
        if (v < 0 || v >= m.nverts())
            throw std::runtime_error(path + ": face references vertex " + std::to_string(v) + " out of range");
    return m;
}

// Number of vertices whose incident faces do not form one edge-connected fan
// (pinch / bowtie vertices), and number of edges with more than two faces.
// OpenSubdiv sharpens such features; CGAL's Surface_mesh and OpenMesh either reject
// the faces or accept them with library-specific (and mutually different) results.
inline void nonmanifold_counts(const Mesh& m, int& pinch_vertices, int& nm_edges) {
    std::vector<std::vector<int>> vf(m.nverts());
    std::vector<int> off(m.nfaces() + 1, 0);
    for (int f = 0; f < m.nfaces(); ++f) off[f + 1] = off[f] + m.fsize[f];
    for (int f = 0; f < m.nfaces(); ++f)
        for (int k = off[f]; k < off[f + 1]; ++k) vf[m.fidx[k]].push_back(f);
    // undirected edge -> face count
    std::vector<std::pair<long long, int>> ek;
    for (int f = 0; f < m.nfaces(); ++f)
        for (int k = 0; k < m.fsize[f]; ++k) {
            int a = m.fidx[off[f] + k], b = m.fidx[off[f] + (k + 1) % m.fsize[f]];
            ek.push_back({(long long)std::min(a, b) * m.nverts() + std::max(a, b), f});
        }
    std::sort(ek.begin(), ek.end());
    nm_edges = 0;
    for (size_t i = 0; i < ek.size();) {
        size_t j = i;
        while (j < ek.size() && ek[j].first == ek[i].first) ++j;
        if (j - i > 2) ++nm_edges;
        i = j;
    }
    pinch_vertices = 0;
    for (int v = 0; v < m.nverts(); ++v) {
        const auto& fs = vf[v];
        if (fs.size() < 2) continue;
        // union faces around v that share an edge (v, w)
        std::vector<int> parent(fs.size());
        for (size_t i = 0; i < fs.size(); ++i) parent[i] = (int)i;
        auto find = [&](int x) { while (parent[x] != x) x = parent[x] = parent[parent[x]]; return x; };
        auto nbrs = [&](int f, int out[2]) {
            int n = m.fsize[f];
            for (int k = 0; k < n; ++k)
                if (m.fidx[off[f] + k] == v) {
                    out[0] = m.fidx[off[f] + (k + 1) % n];
                    out[1] = m.fidx[off[f] + (k + n - 1) % n];
                    return;
                }
        };
        for (size_t i = 0; i < fs.size(); ++i) {
            int ni[2] = {-1, -1};
            nbrs(fs[i], ni);
            for (size_t j = i + 1; j < fs.size(); ++j) {
                int nj[2] = {-2, -2};
                nbrs(fs[j], nj);
                if (ni[0] == nj[0] || ni[0] == nj[1] || ni[1] == nj[0] || ni[1] == nj[1])
                    parent[find((int)i)] = find((int)j);
            }
        }
        int comps = 0;
        for (size_t i = 0; i < fs.size(); ++i) comps += find((int)i) == (int)i;
        if (comps > 1) ++pinch_vertices;
    }
}

inline void write_obj(const std::string& path, const double* P, int nverts,
                      const std::vector<int>& fsize, const std::vector<int>& fidx,
                      const std::string& comment = "") {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write " + path);
    if (!comment.empty()) std::fprintf(f, "# %s\n", comment.c_str());
    for (int i = 0; i < nverts; ++i)
        std::fprintf(f, "v %.17g %.17g %.17g\n", P[3 * i], P[3 * i + 1], P[3 * i + 2]);
    size_t k = 0;
    for (int n : fsize) {
        std::fputc('f', f);
        for (int j = 0; j < n; ++j) std::fprintf(f, " %d", fidx[k++] + 1);
        std::fputc('\n', f);
    }
    if (std::fclose(f) != 0) throw std::runtime_error("error writing " + path);
}

// Tiny argv helper.
struct Args {
    std::vector<std::string> pos;
    std::vector<std::pair<std::string, std::string>> opt;
    Args(int argc, char** argv, const std::vector<std::string>& flags_without_value) {
        for (int i = 1; i < argc; ++i) {
            std::string a = argv[i];
            if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
                std::string key = a.substr(2), val;
                size_t eq = key.find('=');
                if (eq != std::string::npos) { val = key.substr(eq + 1); key = key.substr(0, eq); }
                else if (std::find(flags_without_value.begin(), flags_without_value.end(), key) == flags_without_value.end()) {
                    if (i + 1 >= argc) throw std::runtime_error("missing value for --" + key);
                    val = argv[++i];
                }
                opt.push_back({key, val});
            } else pos.push_back(a);
        }
    }
    bool has(const std::string& k) const {
        for (auto& p : opt) if (p.first == k) return true;
        return false;
    }
    std::string get(const std::string& k, const std::string& def = "") const {
        std::string r = def;
        for (auto& p : opt) if (p.first == k) r = p.second;
        return r;
    }
};

inline int parse_levels(const Args& a, int maxlev = 12) {
    std::string s = a.get("levels", "1");
    char* endp = nullptr;
    long v = std::strtol(s.c_str(), &endp, 10);
    if (*endp || v < 1 || v > maxlev) throw std::runtime_error("--levels must be an integer in 1.." + std::to_string(maxlev));
    return (int)v;
}

} // namespace oracle
