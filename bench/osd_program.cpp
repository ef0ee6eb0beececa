// osd_program: the OpenSubdiv peer of `strata info` and `strata subdivide`
// for bench/whole_process.sh, a whole process doing with OpenSubdiv 3.5 what
// the two commands do with Strata:
//
//   osd_program info MESH.obj catmark|loop DEPTH
//       per-level vertex, edge and face counts and Euler characteristic
//   osd_program ply  MESH.obj catmark|loop DEPTH OUT.ply
//       the finest level as binary little-endian PLY, laid out as Strata's
//       writer lays it out (core/io/mesh_write.c): double x y z, and u v when
//       the mesh has texture coordinates (one PLY vertex per distinct pair of
//       vertex and UV value, in the order of the pairs), then a face list
//       counted by uchar (uint when a face has more than 255 corners)
//   osd_program obj  MESH.obj catmark|loop DEPTH OUT.obj
//       the finest level as OBJ text, as Strata's writer writes it: `v`,
//       `vt` (one per face-varying value) and `f v/vt` lines, %.17g
//
// All read the OBJ themselves with a plain reader (the whole file in one
// buffer; `v`, `vt` and `f` lines with v, v/t, v//n and v/t/n corners,
// negative indices allowed; every other line ignored: no repairs, no tags),
// build Far::TopologyRefinerFactory<TopologyDescriptor> with Strata's
// defaults (boundary edge-only, UV interpolation corners-plus1), run
// RefineUniform(DEPTH) and PrimvarRefiner::Interpolate in double for every
// level (and InterpolateFaceVarying for the UVs), as a user of OpenSubdiv
// would.  No dependency on Strata: a process of its own to compare with.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

using namespace OpenSubdiv;

namespace {

struct Vec3 {
    double p[3];
    void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(Vec3 const &s, float w) { p[0] += w * s.p[0]; p[1] += w * s.p[1]; p[2] += w * s.p[2]; }
};

struct Vec2 {
    double p[2];
    void Clear(void * = nullptr) { p[0] = p[1] = 0; }
    void AddWithWeight(Vec2 const &s, float w) { p[0] += w * s.p[0]; p[1] += w * s.p[1]; }
};

struct Obj {
    std::vector<double> pos, uv;     // 3 and 2 per value
    std::vector<int> counts, idx, uvidx;
    bool all_uv = true;               // every corner has a texture coordinate
};

// One index of a corner: 1-based, or negative (relative to the end).
bool obj_index(const char *&s, size_t n, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || v == 0) return false;
    long i = v > 0 ? v - 1 : (long)n + v;
    if (i < 0 || i >= (long)n) return false;
    *out = (int)i;
    s = end;
    return true;
}

bool read_obj(const char *path, Obj &o)
{
    FILE *f = fopen(path, "rb");
    if (!f) { perror(path); return false; }
    std::vector<char> text;
    char chunk[1 << 16];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) text.insert(text.end(), chunk, chunk + got);
    fclose(f);
    text.push_back('\0');
    unsigned line = 0;
    for (char *s = text.data(); *s;) {
        char *eol = strchr(s, '\n');
        if (eol) *eol = '\0';
        line++;
        while (*s == ' ' || *s == '\t') s++;
        if (s[0] == 'v' && s[1] == ' ') {
            char *p = s + 2;
            for (int k = 0; k < 3; k++) o.pos.push_back(strtod(p, &p));
        } else if (s[0] == 'v' && s[1] == 't' && s[2] == ' ') {
            char *p = s + 3;
            for (int k = 0; k < 2; k++) o.uv.push_back(strtod(p, &p));
        } else if (s[0] == 'f' && s[1] == ' ') {
            const char *p = s + 2;
            int n = 0;
            for (;;) {
                while (*p == ' ' || *p == '\t' || *p == '\r') p++;
                if (!*p) break;
                int v, t = -1;
                if (!obj_index(p, o.pos.size() / 3, &v)) { fprintf(stderr, "%s:%u: bad face\n", path, line); return false; }
                if (*p == '/') {
                    p++;
                    if (*p != '/' && !obj_index(p, o.uv.size() / 2, &t)) { fprintf(stderr, "%s:%u: bad face\n", path, line); return false; }
                    if (*p == '/') { p++; strtol(p, (char **)&p, 10); }
                }
                o.idx.push_back(v);
                o.uvidx.push_back(t);
                o.all_uv = o.all_uv && t >= 0;
                n++;
            }
            if (n < 3) { fprintf(stderr, "%s:%u: face with %d corners\n", path, line, n); return false; }
            o.counts.push_back(n);
        }
        if (!eol) break;
        s = eol + 1;
    }
    if (o.uv.empty()) o.all_uv = false;
    return true;
}

Far::TopologyRefiner *refine(const Obj &o, Sdc::SchemeType type, int depth)
{
    Far::TopologyDescriptor desc;
    desc.numVertices = (int)(o.pos.size() / 3);
    desc.numFaces = (int)o.counts.size();
    desc.numVertsPerFace = o.counts.data();
    desc.vertIndicesPerFace = o.idx.data();
    Far::TopologyDescriptor::FVarChannel uvs;
    if (o.all_uv) {
        uvs.numValues = (int)(o.uv.size() / 2);
        uvs.valueIndices = o.uvidx.data();
        desc.numFVarChannels = 1;
        desc.fvarChannels = &uvs;
    }
    Sdc::Options opts;
    opts.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    opts.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1);
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    Far::TopologyRefiner *r = Factory::Create(desc, Factory::Options(type, opts));
    if (!r) return nullptr;
    r->RefineUniform(Far::TopologyRefiner::UniformOptions(depth));
    return r;
}

// Positions (and UVs) of every level, level after level in one buffer.
void interpolate(const Far::TopologyRefiner &r, const Obj &o, std::vector<Vec3> &pos, std::vector<Vec2> &uv)
{
    Far::PrimvarRefiner pr(r);
    pos.resize(r.GetNumVerticesTotal());
    memcpy(pos.data(), o.pos.data(), o.pos.size() * sizeof(double));
    Vec3 *src = pos.data();
    for (int l = 1; l <= r.GetMaxLevel(); l++) {
        Vec3 *dst = src + r.GetLevel(l - 1).GetNumVertices();
        pr.Interpolate(l, src, dst);
        src = dst;
    }
    if (!o.all_uv) return;
    uv.resize(r.GetNumFVarValuesTotal(0));
    memcpy(uv.data(), o.uv.data(), o.uv.size() * sizeof(double));
    Vec2 *us = uv.data();
    for (int l = 1; l <= r.GetMaxLevel(); l++) {
        Vec2 *ud = us + r.GetLevel(l - 1).GetNumFVarValues(0);
        pr.InterpolateFaceVarying(l, us, ud, 0);
        us = ud;
    }
}

// Little-endian bytes through a 1 MiB buffer.
struct Out {
    FILE *f;
    std::vector<unsigned char> b;
    void bytes(const void *p, size_t n)
    {
        const unsigned char *c = (const unsigned char *)p;
        b.insert(b.end(), c, c + n);
        if (b.size() >= (1u << 20)) flush();
    }
    void u8(unsigned v) { unsigned char c = (unsigned char)v; bytes(&c, 1); }
    void u32(uint32_t v) { unsigned char c[4] = { (unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16), (unsigned char)(v >> 24) }; bytes(c, 4); }
    void f64(double d) { uint64_t v; memcpy(&v, &d, 8); u32((uint32_t)v); u32((uint32_t)(v >> 32)); }
    void flush() { fwrite(b.data(), 1, b.size(), f); b.clear(); }
};

// The finest level of r and where its vertices and face-varying values
// start in the buffers of every level.
struct Finest {
    const Far::TopologyLevel &lv;
    size_t vbase, ubase;
    int nf, nv;
    Finest(const Far::TopologyRefiner &r, bool has_uv)
        : lv(r.GetLevel(r.GetMaxLevel())),
          vbase((size_t)r.GetNumVerticesTotal() - (size_t)lv.GetNumVertices()),
          ubase(has_uv ? (size_t)r.GetNumFVarValuesTotal(0) - (size_t)lv.GetNumFVarValues(0) : 0),
          nf(lv.GetNumFaces()), nv(lv.GetNumVertices())
    {
    }
};

bool write_ply(const char *path, const Far::TopologyRefiner &r, const std::vector<Vec3> &pos, const std::vector<Vec2> &uv,
               bool has_uv)
{
    Finest fl(r, has_uv);
    const Far::TopologyLevel &lv = fl.lv;
    size_t vbase = fl.vbase, ubase = fl.ubase;
    int nf = fl.nf, nv = fl.nv;
    bool wide = false;
    size_t nc = 0;
    for (int f = 0; f < nf; f++) {
        int n = lv.GetFaceVertices(f).size();
        wide = wide || n > 255;
        nc += (size_t)n;
    }
    // With UVs: one PLY vertex per distinct (vertex, UV value) pair, pairs
    // in increasing order: corners bucketed by vertex, each bucket sorted
    // by UV value.
    std::vector<uint32_t> corner_vert;   // PLY vertex of each corner
    std::vector<uint32_t> pair_v, pair_t;
    if (has_uv) {
        std::vector<uint32_t> start(nv + 1, 0), bucket(nc);
        for (int f = 0; f < nf; f++)
            for (int v : lv.GetFaceVertices(f)) start[v + 1]++;
        for (int v = 0; v < nv; v++) start[v + 1] += start[v];
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        std::vector<uint32_t> ctex(nc);
        size_t c = 0;
        for (int f = 0; f < nf; f++) {
            Far::ConstIndexArray fv = lv.GetFaceVertices(f), ft = lv.GetFaceFVarValues(f, 0);
            for (int k = 0; k < fv.size(); k++, c++) { bucket[fill[fv[k]]++] = (uint32_t)c; ctex[c] = (uint32_t)ft[k]; }
        }
        corner_vert.resize(nc);
        for (int v = 0; v < nv; v++) {
            uint32_t *b = bucket.data() + start[v], *e = bucket.data() + start[v + 1];
            std::sort(b, e, [&](uint32_t x, uint32_t y) { return ctex[x] < ctex[y]; });
            for (uint32_t *p = b; p != e; p++) {
                if (p == b || ctex[*p] != ctex[p[-1]]) { pair_v.push_back((uint32_t)v); pair_t.push_back(ctex[*p]); }
                corner_vert[*p] = (uint32_t)pair_v.size() - 1;
            }
        }
    }
    FILE *f = fopen(path, "wb");
    if (!f) { perror(path); return false; }
    size_t nout = has_uv ? pair_v.size() : (size_t)nv;
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment written by Strata\n"
               "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n", nout);
    if (has_uv) fprintf(f, "property double u\nproperty double v\n");
    fprintf(f, "element face %d\nproperty list %s uint vertex_indices\nend_header\n", nf, wide ? "uint" : "uchar");
    Out o{ f, {} };
    for (size_t i = 0; i < nout; i++) {
        const Vec3 &p = pos[vbase + (has_uv ? pair_v[i] : i)];
        for (int k = 0; k < 3; k++) o.f64(p.p[k]);
        if (has_uv)
            for (int k = 0; k < 2; k++) o.f64(uv[ubase + pair_t[i]].p[k]);
    }
    size_t c = 0;
    for (int fi = 0; fi < nf; fi++) {
        Far::ConstIndexArray fv = lv.GetFaceVertices(fi);
        if (wide) o.u32((uint32_t)fv.size()); else o.u8((unsigned)fv.size());
        for (int k = 0; k < fv.size(); k++, c++) o.u32(has_uv ? corner_vert[c] : (uint32_t)fv[k]);
    }
    o.flush();
    return fclose(f) == 0;
}

// The finest level as OBJ text, as `strata subdivide -o X.obj` writes it:
// a comment, `v` lines, with UVs one `vt` per face-varying value and
// `f v/vt` lines, numbers as %.17g.  (OpenSubdiv's own value order: the
// same lines as Strata's up to the order of the `vt` lines.)
bool write_obj(const char *path, const Far::TopologyRefiner &r, const std::vector<Vec3> &pos, const std::vector<Vec2> &uv,
               bool has_uv)
{
    Finest fl(r, has_uv);
    const Far::TopologyLevel &lv = fl.lv;
    size_t vbase = fl.vbase, ubase = fl.ubase;
    int nf = fl.nf, nv = fl.nv;
    FILE *f = fopen(path, "wb");
    if (!f) { perror(path); return false; }
    fprintf(f, "# Strata mesh: %d vertices, %d faces\n", nv, nf);
    Out o{ f, {} };
    char t[96];
    for (int v = 0; v < nv; v++) {
        const Vec3 &p = pos[vbase + (size_t)v];
        o.bytes(t, (size_t)snprintf(t, sizeof t, "v %.17g %.17g %.17g\n", p.p[0], p.p[1], p.p[2]));
    }
    for (int i = 0; has_uv && i < lv.GetNumFVarValues(0); i++) {
        const Vec2 &u = uv[ubase + (size_t)i];
        o.bytes(t, (size_t)snprintf(t, sizeof t, "vt %.17g %.17g\n", u.p[0], u.p[1]));
    }
    for (int fi = 0; fi < nf; fi++) {
        Far::ConstIndexArray fv = lv.GetFaceVertices(fi);
        o.bytes("f", 1);
        for (int k = 0; k < fv.size(); k++) {
            int n = has_uv ? snprintf(t, sizeof t, " %d/%d", fv[k] + 1, lv.GetFaceFVarValues(fi, 0)[k] + 1)
                           : snprintf(t, sizeof t, " %d", fv[k] + 1);
            o.bytes(t, (size_t)n);
        }
        o.bytes("\n", 1);
    }
    o.flush();
    return fclose(f) == 0;
}

}  // namespace

int main(int argc, char **argv)
{
    bool ply = argc == 6 && !strcmp(argv[1], "ply"), obj = argc == 6 && !strcmp(argv[1], "obj");
    if (!(argc == 5 && !strcmp(argv[1], "info")) && !ply && !obj) {
        fprintf(stderr, "usage: osd_program info MESH.obj catmark|loop DEPTH\n"
                        "       osd_program ply|obj MESH.obj catmark|loop DEPTH OUT\n");
        return 2;
    }
    Sdc::SchemeType type = !strcmp(argv[3], "loop") ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    int depth = atoi(argv[4]);
    Obj o;
    if (!read_obj(argv[2], o)) return 1;
    Far::TopologyRefiner *r = refine(o, type, depth);
    if (!r) { fprintf(stderr, "%s: OpenSubdiv refused the mesh\n", argv[2]); return 1; }
    std::vector<Vec3> pos;
    std::vector<Vec2> uv;
    interpolate(*r, o, pos, uv);
    int rc = 0;
    if (ply) {
        rc = write_ply(argv[5], *r, pos, uv, o.all_uv) ? 0 : 1;
    } else if (obj) {
        rc = write_obj(argv[5], *r, pos, uv, o.all_uv) ? 0 : 1;
    } else {
        printf("%s: %s, %d levels\n%5s %10s %10s %10s %6s\n", argv[2], type == Sdc::SCHEME_LOOP ? "loop" : "catmark",
               r->GetMaxLevel(), "level", "vertices", "edges", "faces", "euler");
        for (int l = 0; l <= r->GetMaxLevel(); l++) {
            const Far::TopologyLevel &lv = r->GetLevel(l);
            printf("%5d %10d %10d %10d %6d\n", l, lv.GetNumVertices(), lv.GetNumEdges(), lv.GetNumFaces(),
                   lv.GetNumVertices() - lv.GetNumEdges() + lv.GetNumFaces());
        }
        // The finest positions are used, as `strata info` keeps them.
        double s = 0;
        for (size_t i = pos.size() - (size_t)r->GetLevel(r->GetMaxLevel()).GetNumVertices(); i < pos.size(); i++) s += pos[i].p[0];
        printf("sum of finest x: %.6g\n", s);
    }
    delete r;
    return rc;
}
