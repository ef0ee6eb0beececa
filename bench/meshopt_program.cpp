// meshopt_program: the meshoptimizer peer of `strata rebuild --method
// progressive` for bench/progressive_process.sh, a whole process:
//
//   meshopt_program MESH.obj OUT.obj [PERCENT]
//
// reads the OBJ with a plain reader (the whole file in one buffer; `v` and
// `f` lines, v, v/t, v//n and v/t/n corners, negative indices; polygons
// fanned into triangles as Strata fans them; nothing repaired), runs
// meshopt_simplify down to PERCENT (default 1) % of the triangles with no
// error limit, as bench_progressive does in process, and writes the
// coarse mesh as OBJ (its vertices in first-use order).  Strata's side
// builds every level and its details and writes a session: not like for
// like, the whole-process comparison all the same.
#include <meshoptimizer.h>

#include <cfloat>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

bool corner(const char *&s, size_t n, unsigned *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || v == 0) return false;
    long i = v > 0 ? v - 1 : (long)n + v;
    if (i < 0 || i >= (long)n) return false;
    *out = (unsigned)i;
    s = end;
    while (*s == '/' || (*s >= '0' && *s <= '9') || *s == '-') s++;   // the t and n parts
    return true;
}

bool read_obj(const char *path, std::vector<float> &pos, std::vector<unsigned> &tri)
{
    FILE *f = fopen(path, "rb");
    if (!f) { perror(path); return false; }
    std::vector<char> text;
    char chunk[1 << 16];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) text.insert(text.end(), chunk, chunk + got);
    fclose(f);
    text.push_back('\0');
    std::vector<unsigned> face;
    for (char *s = text.data(); *s;) {
        char *eol = strchr(s, '\n');
        if (eol) *eol = '\0';
        while (*s == ' ' || *s == '\t') s++;
        if (s[0] == 'v' && s[1] == ' ') {
            char *p = s + 2;
            for (int k = 0; k < 3; k++) pos.push_back((float)strtod(p, &p));
        } else if (s[0] == 'f' && s[1] == ' ') {
            const char *p = s + 2;
            face.clear();
            for (;;) {
                while (*p == ' ' || *p == '\t' || *p == '\r') p++;
                if (!*p) break;
                unsigned v;
                if (!corner(p, pos.size() / 3, &v)) { fprintf(stderr, "%s: bad face\n", path); return false; }
                face.push_back(v);
            }
            for (size_t i = 1; i + 1 < face.size(); i++) {
                tri.push_back(face[0]);
                tri.push_back(face[i]);
                tri.push_back(face[i + 1]);
            }
        }
        if (!eol) break;
        s = eol + 1;
    }
    return true;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 3) { fprintf(stderr, "usage: meshopt_program MESH.obj OUT.obj [PERCENT]\n"); return 2; }
    double percent = argc > 3 ? atof(argv[3]) : 1.0;
    std::vector<float> pos;
    std::vector<unsigned> tri;
    if (!read_obj(argv[1], pos, tri)) return 1;
    size_t nv = pos.size() / 3, target = (size_t)(tri.size() / 3 * percent / 100.0);
    std::vector<unsigned> out(tri.size());
    size_t n = meshopt_simplify(out.data(), tri.data(), tri.size(), pos.data(), nv, 3 * sizeof(float), 3 * target, FLT_MAX,
                                0, nullptr);
    std::vector<unsigned> remap(nv, ~0u);
    unsigned used = 0;
    FILE *f = fopen(argv[2], "wb");
    if (!f) { perror(argv[2]); return 1; }
    for (size_t i = 0; i < n; i++)
        if (remap[out[i]] == ~0u) {
            remap[out[i]] = used++;
            const float *p = &pos[3 * (size_t)out[i]];
            fprintf(f, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
    for (size_t i = 0; i < n; i += 3) fprintf(f, "f %u %u %u\n", remap[out[i]] + 1, remap[out[i + 1]] + 1, remap[out[i + 2]] + 1);
    if (fclose(f)) { perror(argv[2]); return 1; }
    printf("%s: %zu triangles -> %zu (target %zu), %u vertices\n", argv[1], tri.size() / 3, n / 3, target, used);
    return 0;
}
