// glTF 2.0 reader and writer (gltf_io.h): the one C++17 translation unit that
// compiles tinygltf.  Everything crosses the C API with try/catch around it:
// no exception reaches C code.
//
// Images are never needed: tinygltf's stb_image/stb_image_write code is left
// out (render/image.c already compiles stb, a second copy would clash), a
// no-op image loader accepts embedded images and external images are not
// read at all.  File access goes through our own callbacks so that the
// in-memory parser reads nothing from disk and file reads are bounded.
//
// Over 900 lines, one file on purpose: tinygltf's implementation and the
// nlohmann::json templates it pulls in are the slowest code of the build to
// compile (its slowest object, about 48 s under ASan), and every further
// unit including tiny_gltf.h would compile those headers again.  It holds
// the reader, the writer (seams split, UDIM tiles, maps attached) and the
// C API.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "gltf_io.h"

// core's headers are C without extern "C" guards.
extern "C" {
extern "C" {
#include "core/bake/bake.h"
#include "core/fvar/fvar.h"
}
#include "core/base/membudget.h"
#include "core/io/atomic_file.h"
#include "core/io/file_open.h"
}

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <tuple>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

// Files (and external buffers) above this are refused before reading;
// tinygltf takes sizes as unsigned int.
const size_t kMaxFileBytes = (size_t)1 << 31;
// Deeper JSON is refused before tinygltf sees it: its extras/extensions
// copies recurse once per level (a stack overflow on hostile input).
const int kMaxJsonDepth = 256;

const int kModePoints = 0, kModeTriangles = 4, kModeStrip = 5, kModeFan = 6;

// The error type: a message without the file name ("what: problem"), or,
// when named, one that names its file itself (a writer's second file).
struct Failure {
    int code;
    std::string msg;
    bool named;
};

[[noreturn]] void fail(int code, const std::string &msg) { throw Failure{code, msg, false}; }
[[noreturn]] void fail_named(int code, const std::string &msg) { throw Failure{code, msg, true}; }

std::string one_line(std::string s)
{
    // tinygltf's messages are several lines; ours must be one.
    for (char &c : s)
        if (c == '\n' || c == '\r') c = ';';
    while (!s.empty() && (s.back() == ';' || s.back() == ' ')) s.pop_back();
    std::string out;
    for (size_t i = 0; i < s.size(); i++) {
        out += s[i];
        if (s[i] == ';' && i + 1 < s.size() && s[i + 1] != ' ') out += ' ';
    }
    return out;
}

// ---- reading files ---------------------------------------------------------

bool read_file(const std::string &path, std::vector<unsigned char> *out, std::string *why)
{
    st_error e;
    FILE *f = st_open_input(path.c_str(), &e);
    if (!f) {
        // Its message names the path, and says "cannot open", which the
        // caller says too: the reason alone.
        std::string m = e.msg;
        for (const std::string &pre : {path + ": ", std::string("cannot open: ")})
            if (m.compare(0, pre.size(), pre) == 0) m = m.substr(pre.size());
        *why = m;
        return false;
    }
    std::vector<unsigned char> buf;
    unsigned char chunk[65536];
    size_t n;
    bool ok = true;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (buf.size() + n > kMaxFileBytes) {
            *why = "file larger than 2 GiB";
            ok = false;
            break;
        }
        buf.insert(buf.end(), chunk, chunk + n);
    }
    if (ok && ferror(f)) {
        *why = strerror(errno);
        ok = false;
    }
    fclose(f);
    if (ok) out->swap(buf);
    return ok;
}

// Where external buffers may come from: tinygltf's file-system callbacks
// get this as user_data.  Only regular files inside the glTF's own folder
// are read (no absolute URI, no ".." or symlink out of it, no FIFO or
// device, which could hang or never end), after their size was checked
// against the buffer's byteLength and --mem-budget.
struct BufferFs {
    bool in_memory = false;      // parsing from memory: every external URI is refused
    std::string base;            // the folder as handed to tinygltf (the prefix of its paths)
    std::string real_base;       // its realpath
    std::map<std::string, size_t> byte_length;  // decoded URI -> largest byteLength naming it
    std::string refusal;         // the first refusal: "buffer 'URI': problem"
    int code = ST_ERR_PARSE;
};

// A URI as a message shows it: one line (control bytes as '?', a file's
// URI may hold a newline), at most 80 bytes and "..." (a data: URI may be
// megabytes).
std::string uri_for_message(const std::string &uri)
{
    std::string s = uri.substr(0, 80);
    for (char &c : s)
        if ((unsigned char)c < 0x20 || c == 0x7f) c = '?';
    return uri.size() > 80 ? s + "..." : s;
}

bool refuse(BufferFs *fs, std::string *err, const std::string &uri, const std::string &why, int code)
{
    std::string msg = "buffer '" + uri_for_message(uri) + "': " + why;
    if (fs->refusal.empty()) fs->refusal = msg, fs->code = code;
    if (err) *err = msg;
    return false;
}

// The URI tinygltf joined to the folder (tinygltf's JoinPath).
std::string uri_of(const BufferFs *fs, const std::string &path)
{
    if (fs->base.empty()) return path;
    std::string prefix = fs->base.back() == '/' ? fs->base : fs->base + "/";
    return path.compare(0, prefix.size(), prefix) == 0 ? path.substr(prefix.size()) : path;
}

std::string real_path(const std::string &p)
{
    char *r = realpath(p.c_str(), nullptr);
    if (!r) return std::string();
    std::string s = r;
    free(r);
    return s;
}

const char *file_kind(mode_t m)
{
    return S_ISFIFO(m) ? "a FIFO" : S_ISCHR(m) || S_ISBLK(m) ? "a device" : S_ISDIR(m) ? "a folder" : S_ISSOCK(m) ? "a socket" : "not a regular file";
}

// Reads the regular file real (checked by the caller) of `size` bytes:
// opened without blocking and checked again once open, so that a file
// swapped for a FIFO in between is refused, not waited on.
bool read_checked(BufferFs *fs, std::string *err, const std::string &uri, const std::string &real, size_t size,
                  std::vector<unsigned char> *out)
{
    int fd = open(real.c_str(), O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return refuse(fs, err, uri, std::string("cannot open: ") + strerror(errno), ST_ERR_IO);
    struct stat st;
    if (fstat(fd, &st) || !S_ISREG(st.st_mode) || (size_t)st.st_size != size) {
        close(fd);
        return refuse(fs, err, uri, "changed while it was being opened", ST_ERR_IO);
    }
    std::vector<unsigned char> buf(size);
    size_t got = 0;
    while (got < size) {
        ssize_t r = read(fd, buf.data() + got, size - got);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) {
            int e = r < 0 ? errno : 0;
            close(fd);
            return refuse(fs, err, uri, e ? std::string("cannot read: ") + strerror(e) : "shorter than when it was opened", ST_ERR_IO);
        }
        got += (size_t)r;
    }
    close(fd);
    out->swap(buf);
    return true;
}

// Whether a relative URI's '..' segments climb above the folder it starts
// in, read from the text alone: such a URI is refused whether or not the
// place it names exists (realpath() fails on a missing file, and the
// message must not depend on how deep the glTF's folder lies).
bool climbs_above(const std::string &uri)
{
    long depth = 0;
    size_t i = 0;
    while (i <= uri.size()) {
        size_t j = uri.find('/', i);
        if (j == std::string::npos) j = uri.size();
        std::string seg = uri.substr(i, j - i);
        if (seg == "..") {
            if (--depth < 0) return true;
        } else if (!seg.empty() && seg != ".") {
            depth++;
        }
        i = j + 1;
    }
    return false;
}

bool fs_exists(const std::string &, void *) { return true; }  // fs_read decides, with the reason
std::string fs_expand(const std::string &path, void *) { return path; }
bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *user)
{
    BufferFs *fs = static_cast<BufferFs *>(user);
    std::string uri = uri_of(fs, path);
    if (fs->in_memory) return refuse(fs, err, uri, "external URIs cannot be resolved when parsing from memory (only data: URIs)", ST_ERR_PARSE);
    if (uri.empty()) return refuse(fs, err, uri, "an empty URI", ST_ERR_PARSE);
    if (uri[0] == '/') return refuse(fs, err, uri, "an absolute path: external buffers must lie in the glTF's folder", ST_ERR_PARSE);
    if (climbs_above(uri)) return refuse(fs, err, uri, "outside the glTF's folder (its '..' segments climb above it)", ST_ERR_PARSE);
    std::string real = real_path(path);
    if (real.empty()) return refuse(fs, err, uri, std::string("cannot open: ") + strerror(errno), ST_ERR_IO);
    std::string inside = fs->real_base == "/" ? "/" : fs->real_base + "/";
    if (fs->real_base.empty() || real.compare(0, inside.size(), inside) != 0)
        return refuse(fs, err, uri, "outside the glTF's folder (it resolves to " + real + ")", ST_ERR_PARSE);
    struct stat st;
    if (stat(real.c_str(), &st)) return refuse(fs, err, uri, std::string("cannot open: ") + strerror(errno), ST_ERR_IO);
    if (!S_ISREG(st.st_mode)) return refuse(fs, err, uri, std::string(file_kind(st.st_mode)) + ", not a regular file", ST_ERR_PARSE);
    size_t size = (size_t)st.st_size;
    auto bl = fs->byte_length.find(uri);
    if (bl != fs->byte_length.end() && size > bl->second)
        return refuse(fs, err, uri, std::to_string(size) + " bytes, more than the buffer's byteLength " + std::to_string(bl->second), ST_ERR_PARSE);
    if (size > kMaxFileBytes) return refuse(fs, err, uri, "larger than 2 GiB", ST_ERR_MEMORY);
    st_error e;
    if (size >= ST_MEM_CHECK_MIN_BYTES && st_mem_check(size, "reading it", &e)) return refuse(fs, err, uri, e.msg, ST_ERR_MEMORY);
    return read_checked(fs, err, uri, real, size, out);
}

// The byteLength of each buffer with an external URI, from the JSON alone
// (tinygltf checks a file's size only after reading all of it).  Members
// other than "buffers" are dropped while parsing; malformed JSON leaves the
// table empty (tinygltf then says what is wrong).
void collect_byte_lengths(const unsigned char *text, size_t n, BufferFs *fs)
{
    using nlohmann::json;
    json::parser_callback_t keep = [](int depth, json::parse_event_t ev, json &parsed) {
        return !(depth == 1 && ev == json::parse_event_t::key && parsed != "buffers");
    };
    json j = json::parse(text, text + n, keep, false);
    if (!j.is_object() || !j.contains("buffers") || !j["buffers"].is_array()) return;
    for (const json &b : j["buffers"]) {
        if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string() || !b.contains("byteLength") ||
            !b["byteLength"].is_number_unsigned())
            continue;
        std::string uri = b["uri"].get<std::string>();
        if (tinygltf::IsDataURI(uri)) continue;
        size_t len = b["byteLength"].get<size_t>();
        size_t &have = fs->byte_length[tinygltf::dlib::urldecode(uri)];
        if (len > have) have = len;
    }
}
bool fs_write(std::string *err, const std::string &, const std::vector<unsigned char> &, void *)
{
    if (err) *err = "writing through tinygltf is not used";
    return false;
}
bool no_image(tinygltf::Image *, const int, std::string *, std::string *, int, int,
              const unsigned char *, int, void *)
{
    return true;  // images are not needed for geometry
}

// Max nesting of [ and { outside strings.
int json_depth(const unsigned char *s, size_t n)
{
    int depth = 0, max = 0;
    bool in_str = false;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = s[i];
        if (in_str) {
            if (c == '\\') i++;
            else if (c == '"') in_str = false;
        } else if (c == '"') {
            in_str = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max) max = depth;
        } else if (c == ']' || c == '}') {
            depth--;
        }
    }
    return max;
}

bool is_glb(const unsigned char *d, size_t n) { return n >= 4 && memcmp(d, "glTF", 4) == 0; }

// Parses bytes with tinygltf; base_dir is where external buffers are looked
// up, or null for the in-memory parser.
void parse_model(const unsigned char *d, size_t n, const char *base_dir, tinygltf::Model *model)
{
    if (n > kMaxFileBytes) fail(ST_ERR_MEMORY, "larger than 2 GiB");
    const unsigned char *json = d;
    size_t json_n = n;
    if (is_glb(d, n) && n >= 20) {
        // Only the JSON chunk's declared length, clamped to the input.
        uint32_t len;
        memcpy(&len, d + 12, 4);
        json = d + 20;
        json_n = len < n - 20 ? len : n - 20;
    }
    if (!is_glb(d, n)) {
        // Not GLB: must be a JSON object (after blanks and a UTF-8 BOM).
        size_t i = n >= 3 && memcmp(d, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
        while (i < n && (d[i] == ' ' || d[i] == '\t' || d[i] == '\r' || d[i] == '\n')) i++;
        if (i == n || d[i] != '{')
            fail(ST_ERR_PARSE, "not glTF: neither binary (no \"glTF\" magic) nor JSON (no '{')");
    }
    if (json_depth(json, json_n) > kMaxJsonDepth)
        fail(ST_ERR_PARSE, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");

    BufferFs bfs;
    bfs.in_memory = !base_dir;
    if (base_dir) {
        bfs.base = base_dir;
        bfs.real_base = real_path(base_dir);
        collect_byte_lengths(json, json_n, &bfs);
    }
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks fs = {fs_exists, fs_expand, fs_read, fs_write, &bfs};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(no_image, nullptr);
    std::string err, warn;
    bool ok = is_glb(d, n)
                  ? loader.LoadBinaryFromMemory(model, &err, &warn, d, (unsigned)n, base_dir ? base_dir : "")
                  : loader.LoadASCIIFromString(model, &err, &warn, (const char *)d, (unsigned)n,
                                               base_dir ? base_dir : "");
    if (!ok && !bfs.refusal.empty()) fail(bfs.code, bfs.refusal);
    if (!ok) fail(ST_ERR_PARSE, one_line(err.empty() ? "tinygltf could not parse it" : err));
}

// ---- from the model to a triangle soup ----------------------------------

typedef double Mat4[16];  // column-major, as glTF

void mat_identity(Mat4 m)
{
    for (int i = 0; i < 16; i++) m[i] = (i % 5 == 0) ? 1.0 : 0.0;
}

void mat_mul(const Mat4 a, const Mat4 b, Mat4 out)
{
    Mat4 r;
    for (int c = 0; c < 4; c++)
        for (int rr = 0; rr < 4; rr++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    memcpy(out, r, sizeof r);
}

void node_local(const tinygltf::Node &node, int index, Mat4 out)
{
    std::string what = "node " + std::to_string(index);
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) fail(ST_ERR_PARSE, what + ": matrix does not have 16 numbers");
        for (int i = 0; i < 16; i++) out[i] = node.matrix[(size_t)i];
    } else {
        double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
        if (!node.translation.empty()) {
            if (node.translation.size() != 3) fail(ST_ERR_PARSE, what + ": translation does not have 3 numbers");
            for (int i = 0; i < 3; i++) t[i] = node.translation[(size_t)i];
        }
        if (!node.rotation.empty()) {
            if (node.rotation.size() != 4) fail(ST_ERR_PARSE, what + ": rotation does not have 4 numbers");
            for (int i = 0; i < 4; i++) q[i] = node.rotation[(size_t)i];
        }
        if (!node.scale.empty()) {
            if (node.scale.size() != 3) fail(ST_ERR_PARSE, what + ": scale does not have 3 numbers");
            for (int i = 0; i < 3; i++) s[i] = node.scale[(size_t)i];
        }
        // Normalise the quaternion: files store it rounded.
        double ql = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(ql > 0) || !std::isfinite(ql)) fail(ST_ERR_GEOMETRY, what + ": rotation is not a unit quaternion");
        double x = q[0] / ql, y = q[1] / ql, z = q[2] / ql, w = q[3] / ql;
        double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),
                       2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                       2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)};
        mat_identity(out);
        for (int c = 0; c < 3; c++)
            for (int rr = 0; rr < 3; rr++) out[c * 4 + rr] = r[c * 3 + rr] * s[c];
        for (int rr = 0; rr < 3; rr++) out[12 + rr] = t[rr];
    }
    for (int i = 0; i < 16; i++)
        if (!std::isfinite(out[i])) fail(ST_ERR_GEOMETRY, what + ": transform is not finite");
}

double mat_det3(const Mat4 m)
{
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

// The bytes of one accessor, checked against its view and buffer.
struct View {
    const unsigned char *base;
    size_t count, stride;
};

View accessor_view(const tinygltf::Model &model, int index, size_t elem_bytes)
{
    std::string what = "accessor " + std::to_string(index);
    if (index < 0 || (size_t)index >= model.accessors.size())
        fail(ST_ERR_RANGE, what + " does not exist (the file has " + std::to_string(model.accessors.size()) +
                               " accessors)");
    const tinygltf::Accessor &a = model.accessors[(size_t)index];
    if (a.sparse.isSparse) fail(ST_ERR_PARSE, what + ": sparse accessors are not supported");
    if (a.bufferView < 0) fail(ST_ERR_PARSE, what + ": no bufferView (all-zero accessors are not supported)");
    if ((size_t)a.bufferView >= model.bufferViews.size())
        fail(ST_ERR_RANGE, what + ": bufferView " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView &v = model.bufferViews[(size_t)a.bufferView];
    std::string vwhat = "bufferView " + std::to_string(a.bufferView);
    if (v.buffer < 0 || (size_t)v.buffer >= model.buffers.size())
        fail(ST_ERR_RANGE, vwhat + ": buffer " + std::to_string(v.buffer) + " does not exist");
    size_t bsize = model.buffers[(size_t)v.buffer].data.size();
    if (v.byteOffset > bsize || v.byteLength > bsize - v.byteOffset)
        fail(ST_ERR_RANGE, vwhat + ": bytes " + std::to_string(v.byteOffset) + "+" + std::to_string(v.byteLength) +
                               " lie beyond its buffer of " + std::to_string(bsize) + " bytes");
    size_t stride = v.byteStride ? v.byteStride : elem_bytes;
    if (stride < elem_bytes)
        fail(ST_ERR_PARSE, vwhat + ": byteStride " + std::to_string(stride) + " is smaller than an element of " +
                               what);
    // count elements need (count - 1) * stride + elem_bytes bytes after the
    // accessor's offset, all inside the view (checked without overflow).
    size_t avail = a.byteOffset <= v.byteLength ? v.byteLength - a.byteOffset : 0;
    bool fits = a.byteOffset <= v.byteLength &&
                (a.count == 0 || (avail >= elem_bytes && (a.count - 1) <= (avail - elem_bytes) / stride));
    if (!fits)
        fail(ST_ERR_RANGE, what + ": " + std::to_string(a.count) + " elements from byte " +
                               std::to_string(a.byteOffset) + " lie beyond " + vwhat + " (" +
                               std::to_string(v.byteLength) + " bytes)");
    View out;
    out.base = model.buffers[(size_t)v.buffer].data.data() + v.byteOffset + a.byteOffset;
    out.count = a.count;
    out.stride = stride;
    return out;
}

// Welds vertices by exact position (after the transform).
struct Key {
    double x, y, z;
    bool operator==(const Key &o) const { return x == o.x && y == o.y && z == o.z; }
};
struct KeyHash {
    size_t operator()(const Key &k) const
    {
        uint64_t h = 1469598103934665603ull, b[3];
        memcpy(b, &k, sizeof b);
        for (uint64_t v : b) h = (h ^ v) * 1099511628211ull ^ (v >> 29);
        return (size_t)h;
    }
};

struct Soup {
    std::vector<double> pos;
    std::vector<uint32_t> tri;
    // TEXCOORD_0 (OBJ convention, v up) per source vertex, and per corner
    // of tri the index into it; dropped when some primitive has none.
    std::vector<double> uv;
    std::vector<uint32_t> tri_uv;
    bool no_uv = false;
    std::unordered_map<Key, uint32_t, KeyHash> weld;
    size_t dropped = 0;  // triangles that became degenerate
};

void add_primitive(const tinygltf::Model &model, int mesh_i, int prim_i, const Mat4 world, Soup *soup)
{
    const tinygltf::Primitive &p = model.meshes[(size_t)mesh_i].primitives[(size_t)prim_i];
    std::string what = "mesh " + std::to_string(mesh_i) + " primitive " + std::to_string(prim_i);
    if (p.mode >= kModePoints && p.mode < kModeTriangles)
        fail(ST_ERR_PARSE, what + ": mode " + std::to_string(p.mode) +
                               (p.mode == kModePoints ? " (POINTS)" : " (LINES)") +
                               " is not supported: only triangles can be subdivided");
    if (p.mode != kModeTriangles && p.mode != kModeStrip && p.mode != kModeFan)
        fail(ST_ERR_PARSE, what + ": unknown mode " + std::to_string(p.mode));
    auto it = p.attributes.find("POSITION");
    if (it == p.attributes.end()) fail(ST_ERR_PARSE, what + ": no POSITION attribute");
    int pa = it->second;
    View pv = accessor_view(model, pa, 12);
    const tinygltf::Accessor &pacc = model.accessors[(size_t)pa];
    if (pacc.type != TINYGLTF_TYPE_VEC3 || pacc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        fail(ST_ERR_PARSE, what + ": POSITION accessor " + std::to_string(pa) + " is not VEC3 of FLOAT");

    // TEXCOORD_0 as float VEC2 (other encodings, or none: no UVs at all).
    uint32_t uv_base = (uint32_t)(soup->uv.size() / 2);
    auto ti = p.attributes.find("TEXCOORD_0");
    bool has_uv = false;
    if (ti != p.attributes.end() && ti->second >= 0 && (size_t)ti->second < model.accessors.size()) {
        const tinygltf::Accessor &ta = model.accessors[(size_t)ti->second];
        if (ta.type == TINYGLTF_TYPE_VEC2 && ta.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
            View tv = accessor_view(model, ti->second, 8);
            if (tv.count != pv.count)
                fail(ST_ERR_PARSE, what + ": TEXCOORD_0 has " + std::to_string(tv.count) + " entries for " +
                                       std::to_string(pv.count) + " vertices");
            for (size_t i = 0; i < tv.count && !soup->no_uv; i++) {
                float f[2];
                memcpy(f, tv.base + i * tv.stride, sizeof f);
                if (!std::isfinite(f[0]) || !std::isfinite(f[1]))
                    fail(ST_ERR_GEOMETRY, what + ": TEXCOORD_0 entry " + std::to_string(i) + " is not finite");
                // glTF's v runs down the image, OBJ's (and Strata's) up.
                soup->uv.insert(soup->uv.end(), {(double)f[0], 1.0 - (double)f[1]});
            }
            has_uv = true;
        }
    }
    if (!has_uv) soup->no_uv = true;

    // Corner list: the indices, or 0..count-1.
    std::vector<uint32_t> idx;
    if (p.indices >= 0) {
        if ((size_t)p.indices >= model.accessors.size())
            fail(ST_ERR_RANGE, what + ": indices accessor " + std::to_string(p.indices) + " does not exist");
        const tinygltf::Accessor &ia = model.accessors[(size_t)p.indices];
        size_t bytes = ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                       : ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                       : ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                    : 0;
        if (ia.type != TINYGLTF_TYPE_SCALAR || bytes == 0)
            fail(ST_ERR_PARSE, what + ": indices accessor " + std::to_string(p.indices) +
                                   " is not SCALAR of unsigned byte/short/int");
        View iv = accessor_view(model, p.indices, bytes);
        if (iv.count > ST_MESH_MAX_FACES * (size_t)3) fail(ST_ERR_MEMORY, what + ": too many indices");
        idx.resize(iv.count);
        for (size_t i = 0; i < iv.count; i++) {
            const unsigned char *e = iv.base + i * bytes;  // indices are tightly packed
            uint32_t v = bytes == 1 ? e[0] : bytes == 2 ? (uint32_t)(e[0] | e[1] << 8) : 0;
            if (bytes == 4) memcpy(&v, e, 4);
            if (v >= pv.count)
                fail(ST_ERR_RANGE, what + ": index " + std::to_string(i) + " (value " + std::to_string(v) +
                                       ") is out of range: POSITION accessor " + std::to_string(pa) + " has " +
                                       std::to_string(pv.count) + " vertices");
            idx[i] = v;
        }
    } else {
        if (pv.count > ST_MESH_MAX_VERTS) fail(ST_ERR_MEMORY, what + ": too many vertices");
        idx.resize(pv.count);
        for (size_t i = 0; i < pv.count; i++) idx[i] = (uint32_t)i;
    }

    // Triangles as corner triples, converted from strips and fans.
    std::vector<uint32_t> tris;
    if (p.mode == kModeTriangles) {
        if (idx.size() % 3)
            fail(ST_ERR_PARSE, what + ": " + std::to_string(idx.size()) + " corners are not whole triangles");
        tris.swap(idx);
    } else {
        for (size_t i = 2; i < idx.size(); i++) {
            uint32_t a, b, c = idx[i];
            if (p.mode == kModeFan) a = idx[0], b = idx[i - 1];
            else if (i % 2 == 0) a = idx[i - 2], b = idx[i - 1];  // strips alternate winding
            else a = idx[i - 1], b = idx[i - 2];
            tris.insert(tris.end(), {a, b, c});
        }
    }
    if (soup->tri.size() / 3 + tris.size() / 3 > ST_MESH_MAX_FACES)
        fail(ST_ERR_MEMORY, what + ": more than " + std::to_string(ST_MESH_MAX_FACES) + " triangles in all");

    // Transformed, welded vertices of the positions this primitive uses.
    std::vector<uint32_t> map(pv.count, UINT32_MAX);
    bool flip = mat_det3(world) < 0;
    for (size_t t = 0; t < tris.size(); t += 3) {
        uint32_t v[3];
        for (int k = 0; k < 3; k++) {
            uint32_t src = tris[t + (size_t)k];
            if (map[src] == UINT32_MAX) {
                float f[3];
                memcpy(f, pv.base + src * pv.stride, sizeof f);
                if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
                    fail(ST_ERR_GEOMETRY, what + ": POSITION accessor " + std::to_string(pa) + " vertex " +
                                              std::to_string(src) + " is not finite");
                double w[3];
                for (int r = 0; r < 3; r++)
                    w[r] = world[r] * f[0] + world[4 + r] * f[1] + world[8 + r] * f[2] + world[12 + r] + 0.0;
                if (!std::isfinite(w[0]) || !std::isfinite(w[1]) || !std::isfinite(w[2]))
                    fail(ST_ERR_GEOMETRY, what + ": vertex " + std::to_string(src) + " is not finite after its node transform");
                Key key = {w[0], w[1], w[2]};
                auto found = soup->weld.find(key);
                if (found != soup->weld.end()) {
                    map[src] = found->second;
                } else {
                    if (soup->pos.size() / 3 >= ST_MESH_MAX_VERTS)
                        fail(ST_ERR_MEMORY, "more than " + std::to_string(ST_MESH_MAX_VERTS) + " vertices");
                    map[src] = (uint32_t)(soup->pos.size() / 3);
                    soup->weld.emplace(key, map[src]);
                    soup->pos.insert(soup->pos.end(), {w[0], w[1], w[2]});
                }
            }
            v[k] = map[src];
        }
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
            soup->dropped++;
            continue;
        }
        uint32_t u[3] = {uv_base + tris[t], uv_base + tris[t + 1], uv_base + tris[t + 2]};
        if (flip) std::swap(v[1], v[2]), std::swap(u[1], u[2]);
        soup->tri.insert(soup->tri.end(), {v[0], v[1], v[2]});
        if (has_uv) soup->tri_uv.insert(soup->tri_uv.end(), {u[0], u[1], u[2]});
    }
}

// A mesh placed in the scene with its world transform.
struct Instance {
    int mesh;
    Mat4 world;
};

void add_instance(const tinygltf::Model &model, int mesh_i, const Mat4 world, std::vector<Instance> *out)
{
    if (mesh_i < 0 || (size_t)mesh_i >= model.meshes.size())
        fail(ST_ERR_RANGE, "mesh " + std::to_string(mesh_i) + " does not exist");
    Instance in;
    in.mesh = mesh_i;
    memcpy(in.world, world, sizeof in.world);
    out->push_back(in);
}

// Depth-first over a scene's nodes with an explicit stack (no recursion on
// file data); a node reached twice means a cycle or a shared child, which
// glTF forbids and which could multiply the geometry without bound.
void scene_instances(const tinygltf::Model &model, int scene_i, std::vector<Instance> *out)
{
    struct Item {
        int node;
        Mat4 parent;
    };
    std::vector<char> seen(model.nodes.size(), 0);
    std::vector<Item> stack;
    const tinygltf::Scene &scene = model.scenes[(size_t)scene_i];
    for (auto it = scene.nodes.rbegin(); it != scene.nodes.rend(); ++it) {
        Item item;
        item.node = *it;
        mat_identity(item.parent);
        stack.push_back(item);
    }
    while (!stack.empty()) {
        Item item = stack.back();
        stack.pop_back();
        int n = item.node;
        if (n < 0 || (size_t)n >= model.nodes.size())
            fail(ST_ERR_RANGE, "scene " + std::to_string(scene_i) + ": node " + std::to_string(n) + " does not exist");
        if (seen[(size_t)n])
            fail(ST_ERR_PARSE, "node " + std::to_string(n) + " is reached twice: the node hierarchy is not a tree");
        seen[(size_t)n] = 1;
        const tinygltf::Node &node = model.nodes[(size_t)n];
        Mat4 local, world;
        node_local(node, n, local);
        mat_mul(item.parent, local, world);
        if (node.mesh >= 0) add_instance(model, node.mesh, world, out);
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) {
            Item child;
            child.node = *c;
            memcpy(child.parent, world, sizeof world);
            stack.push_back(child);
        }
    }
}

// Triangles an instance asks for, from the accessors' declared counts (not
// yet checked): lets a file that places one mesh many times be refused
// before anything is allocated for it.
size_t declared_triangles(const tinygltf::Model &model, const Instance &in)
{
    size_t n = 0;
    for (const tinygltf::Primitive &p : model.meshes[(size_t)in.mesh].primitives) {
        int a = p.indices;
        if (a < 0) {
            auto it = p.attributes.find("POSITION");
            a = it == p.attributes.end() ? -1 : it->second;
        }
        if (a < 0 || (size_t)a >= model.accessors.size()) continue;
        // Clamped so that the sum below cannot wrap around.
        size_t c = std::min(model.accessors[(size_t)a].count, (size_t)ST_MESH_MAX_FACES * 4);
        n += p.mode == kModeTriangles ? c / 3 : c > 2 ? c - 2 : 0;
        if (n > ST_MESH_MAX_FACES) break;
    }
    return n;
}

void model_to_soup(const tinygltf::Model &model, Soup *soup)
{
    for (const std::string &ext : model.extensionsRequired)
        fail(ST_ERR_PARSE, "requires extension " + ext + ", which is not supported");
    std::vector<Instance> inst;
    if (model.scenes.empty()) {
        // No scene to place the meshes: take every mesh as it is.
        Mat4 id;
        mat_identity(id);
        for (size_t m = 0; m < model.meshes.size(); m++) add_instance(model, (int)m, id, &inst);
    } else {
        int s = model.defaultScene;
        if (s < 0) s = 0;
        if ((size_t)s >= model.scenes.size())
            fail(ST_ERR_RANGE, "scene " + std::to_string(s) + " does not exist");
        scene_instances(model, s, &inst);
    }
    size_t total = 0;
    for (const Instance &in : inst) {
        total += declared_triangles(model, in);
        if (total > ST_MESH_MAX_FACES)
            fail(ST_ERR_MEMORY, "the scene places more than " + std::to_string(ST_MESH_MAX_FACES) + " triangles");
    }
    for (const Instance &in : inst) {
        const tinygltf::Mesh &mesh = model.meshes[(size_t)in.mesh];
        for (size_t p = 0; p < mesh.primitives.size(); p++) add_primitive(model, in.mesh, (int)p, in.world, soup);
    }
    if (soup->tri.empty()) fail(ST_ERR_PARSE, "no triangles found");
}

// Moves the soup into a fresh st_mesh (C allocations, as st_mesh_free wants).
int soup_to_mesh(const Soup &soup, st_mesh *m)
{
    st_mesh_init(m);
    size_t nv = soup.pos.size() / 3, nt = soup.tri.size() / 3;
    m->pos = (double *)malloc(soup.pos.size() * sizeof(double));
    m->face_off = (uint32_t *)malloc((nt + 1) * sizeof(uint32_t));
    m->face_idx = (uint32_t *)malloc(soup.tri.size() * sizeof(uint32_t));
    if (!m->pos || !m->face_off || !m->face_idx) {
        st_mesh_free(m);
        return ST_ERR_MEMORY;
    }
    memcpy(m->pos, soup.pos.data(), soup.pos.size() * sizeof(double));
    memcpy(m->face_idx, soup.tri.data(), soup.tri.size() * sizeof(uint32_t));
    for (size_t f = 0; f <= nt; f++) m->face_off[f] = (uint32_t)(3 * f);
    m->nverts = (uint32_t)nv;
    m->nfaces = (uint32_t)nt;
    if (soup.no_uv || soup.tri_uv.size() != soup.tri.size()) return 0;
    // One texture coordinate per welded vertex and UV value: glTF splits
    // vertices for normals too, and a split with equal UVs is no UV seam.
    std::map<std::tuple<uint32_t, double, double>, uint32_t> id;
    std::vector<double> uv;
    m->face_uv = (uint32_t *)malloc((soup.tri.size() + 1) * sizeof(uint32_t));
    if (!m->face_uv) {
        st_mesh_free(m);
        return ST_ERR_MEMORY;
    }
    for (size_t c = 0; c < soup.tri.size(); c++) {
        const double *p = &soup.uv[2 * (size_t)soup.tri_uv[c]];
        auto key = std::make_tuple(soup.tri[c], p[0], p[1]);
        auto it = id.find(key);
        if (it == id.end()) {
            it = id.emplace(key, (uint32_t)(uv.size() / 2)).first;
            uv.insert(uv.end(), {p[0], p[1]});
        }
        m->face_uv[c] = it->second;
    }
    m->uv = (double *)malloc((uv.size() + 2) * sizeof(double));
    if (!m->uv) {
        st_mesh_free(m);
        return ST_ERR_MEMORY;
    }
    memcpy(m->uv, uv.data(), uv.size() * sizeof(double));
    m->nuvs = (uint32_t)(uv.size() / 2);
    return 0;
}

// Parses into *out (untouched on failure); dropped degenerate triangles
// become a note when notes is given.
int parse_impl(const char *name, const unsigned char *d, size_t n, const char *base_dir, st_mesh *out,
               st_notes *notes, st_error *err)
{
    try {
        tinygltf::Model model;
        parse_model(d, n, base_dir, &model);
        Soup soup;
        model_to_soup(model, &soup);
        st_mesh m;
        if (soup_to_mesh(soup, &m)) return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", name);
        st_mesh_move(out, &m);
        if (soup.dropped)
            st_notes_add(notes, "%s: repaired: dropped %zu triangles that are degenerate after welding equal positions",
                         name, soup.dropped);
        return 0;
    } catch (const Failure &f) {
        return st_fail(err, f.code, "%s: %s", name, f.msg.c_str());
    } catch (const std::bad_alloc &) {
        return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", name);
    } catch (const std::exception &e) {
        return st_fail(err, ST_ERR_PARSE, "%s: %s", name, one_line(e.what()).c_str());
    } catch (...) {
        return st_fail(err, ST_ERR_PARSE, "%s: unexpected error", name);
    }
}

// ---- writing -----------------------------------------------------------

// An accessor of float vectors (type: TINYGLTF_TYPE_VEC2..4) over a whole
// buffer view, one per vertex.
tinygltf::Accessor float_accessor(int view, int type, size_t count)
{
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = type;
    a.count = count;
    return a;
}

void add_view(tinygltf::Model *model, size_t offset, size_t length, int target)
{
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = offset;
    v.byteLength = length;
    v.target = target;
    model->bufferViews.push_back(v);
}

template <class T> void put(std::vector<unsigned char> *buf, const T &v)
{
    const unsigned char *b = (const unsigned char *)&v;
    buf->insert(buf->end(), b, b + sizeof v);
}

// A mesh with UVs as glTF wants it: one vertex per (vertex, UV index) pair,
// so vertices are split along UV seams; normals are those of the unsplit
// mesh (smooth across seams).  texcoord gets TEXCOORD_0 per new vertex.
struct Split {
    st_mesh m;
    std::vector<float> texcoord;
    Split() { st_mesh_init(&m); }
    ~Split() { st_mesh_free(&m); }
};

// Unit vertex normals for glTF: core's area-weighted ones
// (st_mesh_vertex_normals, the one computation every writer uses), replaced
// by the mesh's own where it has them and they have a length.
std::vector<double> unit_normals(const st_mesh *m)
{
    std::vector<double> n(3 * (size_t)m->nverts);
    if (st_mesh_vertex_normals(m, n.data())) fail(ST_ERR_MEMORY, "out of memory for normals");
    for (size_t v = 0; m->normals && v < m->nverts; v++) {
        const double *g = m->normals + 3 * v;
        double len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        if (len > 1e-300 && std::isfinite(len))
            for (int c = 0; c < 3; c++) n[3 * v + (size_t)c] = g[c] / len;
    }
    return n;
}

// A split copy's faces: m's face sizes (face_off), with face_idx to be
// renumbered into the split vertices; `what` names the split in messages.
void split_faces_begin(const st_mesh *m, st_mesh *e, const char *what)
{
    uint32_t nc = m->face_off[m->nfaces];
    e->face_idx = (uint32_t *)malloc(((size_t)nc + 1) * sizeof(uint32_t));
    e->face_off = (uint32_t *)malloc(((size_t)m->nfaces + 1) * sizeof(uint32_t));
    if (!e->face_idx || !e->face_off) fail(ST_ERR_MEMORY, std::string("out of memory ") + what);
    memcpy(e->face_off, m->face_off, ((size_t)m->nfaces + 1) * sizeof(uint32_t));
    e->nfaces = m->nfaces;
}

// The split copy's n vertices: positions and normals, to be filled.
void split_verts_alloc(st_mesh *e, size_t n, const char *what)
{
    e->nverts = (uint32_t)n;
    e->pos = (double *)malloc(3 * (n + 1) * sizeof(double));
    e->normals = (double *)malloc(3 * (n + 1) * sizeof(double));
    if (!e->pos || !e->normals) fail(ST_ERR_MEMORY, std::string("out of memory ") + what);
}

void split_seams(const st_mesh *m, Split *out)
{
    uint32_t nc = m->face_off[m->nfaces];
    for (uint32_t c = 0; c < nc; c++)
        if (m->face_idx[c] >= m->nverts || m->face_uv[c] >= m->nuvs)
            fail(ST_ERR_RANGE, "face corner " + std::to_string(c) + " is out of range");
    std::vector<double> nrm = unit_normals(m);
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> id;
    std::vector<uint32_t> src;  // per new vertex: (vertex, uv) pair's corner
    st_mesh *e = &out->m;
    split_faces_begin(m, e, "splitting UV seams");
    for (uint32_t c = 0; c < nc; c++) {
        auto key = std::make_pair(m->face_idx[c], m->face_uv[c]);
        auto it = id.find(key);
        if (it == id.end()) {
            it = id.emplace(key, (uint32_t)src.size()).first;
            src.push_back(c);
        }
        e->face_idx[c] = it->second;
    }
    split_verts_alloc(e, src.size(), "splitting UV seams");
    out->texcoord.resize(2 * src.size());
    for (size_t i = 0; i < src.size(); i++) {
        uint32_t v = m->face_idx[src[i]], t = m->face_uv[src[i]];
        memcpy(e->pos + 3 * i, m->pos + 3 * (size_t)v, 3 * sizeof(double));
        memcpy(e->normals + 3 * i, nrm.data() + 3 * (size_t)v, 3 * sizeof(double));
        double u = m->uv[2 * (size_t)t], w = m->uv[2 * (size_t)t + 1];
        if (!std::isfinite(u) || !std::isfinite(w) || std::fabs(u) > FLT_MAX || std::fabs(w) > FLT_MAX)
            fail(ST_ERR_GEOMETRY, "texture coordinate " + std::to_string(t) + " is not finite or beyond float range");
        out->texcoord[2 * i] = (float)u;
        out->texcoord[2 * i + 1] = (float)(1.0 - w);  // glTF's v runs down the image
    }
}

// The normal-mapped export (st_gltf_save_mapped): one glTF vertex per
// distinct (vertex, UV, tangent, normal) of the corners, so vertices are
// split wherever two corners of a vertex differ in any of them (UV seams,
// the tangent's sign across mirrored islands).  Keys are the float values
// written, so corners that round to the same floats share a vertex.
void split_mapped(const st_mesh *m, const st_gltf_material *mat, Split *out, std::vector<float> *tangent)
{
    if (!m->nfaces || !m->face_off || !m->face_idx) fail(ST_ERR_INVALID, "the mesh is empty");
    uint32_t nc = m->face_off[m->nfaces];
    const double *uv = mat->corner_uv, *tg = mat->corner_tangent, *nm = mat->corner_normal;
    std::map<std::array<uint32_t, 10>, uint32_t> id;
    std::vector<float> attr;  // 9 per new vertex: u, v, tangent xyzw, normal xyz
    std::vector<uint32_t> vert;
    st_mesh *e = &out->m;
    split_faces_begin(m, e, "splitting vertices");
    if (m->face_hole) {
        e->face_hole = (uint8_t *)malloc((size_t)m->nfaces);
        if (!e->face_hole) fail(ST_ERR_MEMORY, "out of memory splitting vertices");
        memcpy(e->face_hole, m->face_hole, (size_t)m->nfaces);
    }
    for (uint32_t c = 0; c < nc; c++) {
        if (m->face_idx[c] >= m->nverts) fail(ST_ERR_RANGE, "face corner " + std::to_string(c) + " is out of range");
        double v[9] = {uv[2 * (size_t)c], 1.0 - uv[2 * (size_t)c + 1],  // glTF's v runs down the image
                       tg[4 * (size_t)c], tg[4 * (size_t)c + 1], tg[4 * (size_t)c + 2], tg[4 * (size_t)c + 3],
                       nm[3 * (size_t)c], nm[3 * (size_t)c + 1], nm[3 * (size_t)c + 2]};
        std::array<uint32_t, 10> key;
        key[0] = m->face_idx[c];
        float f[9];
        for (int k = 0; k < 9; k++) {
            if (!std::isfinite(v[k]) || std::fabs(v[k]) > FLT_MAX)
                fail(ST_ERR_GEOMETRY, "face corner " + std::to_string(c) + ": UV, tangent or normal is not finite");
            f[k] = (float)v[k];
            memcpy(&key[(size_t)k + 1], &f[k], 4);
        }
        auto it = id.find(key);
        if (it == id.end()) {
            it = id.emplace(key, (uint32_t)vert.size()).first;
            vert.push_back(m->face_idx[c]);
            attr.insert(attr.end(), f, f + 9);
        }
        e->face_idx[c] = it->second;
    }
    split_verts_alloc(e, vert.size(), "splitting vertices");
    out->texcoord.resize(2 * vert.size());
    tangent->resize(4 * vert.size());
    for (size_t i = 0; i < vert.size(); i++) {
        memcpy(e->pos + 3 * i, m->pos + 3 * (size_t)vert[i], 3 * sizeof(double));
        const float *a = attr.data() + 9 * i;
        out->texcoord[2 * i] = a[0];
        out->texcoord[2 * i + 1] = a[1];
        for (int k = 0; k < 4; k++) (*tangent)[4 * i + (size_t)k] = a[2 + k];
        for (int k = 0; k < 3; k++) e->normals[3 * i + (size_t)k] = a[6 + k];
    }
}

// The normal map of a mapped export: for .glb its PNG bytes (embedded), for
// .gltf the URI that reaches it from the .gltf's folder.
struct NormalMap {
    std::vector<unsigned char> png;
    std::string uri;
    std::string name;   // a UDIM tile's number
};

// Builds the tinygltf model of m (checked first); with mat, the tangents,
// UVs and normals of mat and a material whose normalTexture is nmap[0].
// With groups (a UDIM export): face f goes to primitive group[f], whose
// material's normalTexture is nmap[group[f]] (nmap then has one map per group).
void mesh_to_model(const st_mesh *m, int index_bytes, tinygltf::Model *model,
                   const st_gltf_material *mat = nullptr, const std::vector<NormalMap> *nmaps = nullptr,
                   const std::vector<uint32_t> *group = nullptr)
{
    const NormalMap *nmap = nmaps && !nmaps->empty() ? &(*nmaps)[0] : nullptr;
    size_t ngroups = group && nmaps ? nmaps->size() : 1;
    Split split;
    std::vector<float> tan;
    if (mat) {
        split_mapped(m, mat, &split, &tan);
        m = &split.m;
    } else if (m->face_uv && m->uv && m->nfaces && m->face_off && m->face_idx) {
        split_seams(m, &split);
        m = &split.m;
    }
    const std::vector<float> &tex = split.texcoord;
    if (!m->nverts || !m->nfaces || !m->pos || !m->face_off || !m->face_idx)
        fail(ST_ERR_INVALID, "the mesh is empty");
    size_t ntri = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t a = m->face_off[f], b = m->face_off[f + 1];
        if (m->face_hole && m->face_hole[f]) continue;  // a hole face has no surface
        if (b < a + 3) fail(ST_ERR_INVALID, "face " + std::to_string(f) + " has fewer than 3 vertices");
        for (uint32_t k = a; k < b; k++)
            if (m->face_idx[k] >= m->nverts)
                fail(ST_ERR_RANGE, "face " + std::to_string(f) + " uses vertex " + std::to_string(m->face_idx[k]) +
                                       " of " + std::to_string(m->nverts));
        ntri += b - a - 2;
    }
    if (ntri == 0) fail(ST_ERR_INVALID, "every face is a hole: no surface to write");
    if (ntri > (size_t)UINT32_MAX / 3) fail(ST_ERR_MEMORY, "too many triangles for one glTF primitive");
    if (index_bytes == 0) index_bytes = m->nverts < 65535 ? 2 : 4;
    // The largest value of each index type is the primitive restart value.
    uint64_t limit = index_bytes == 1 ? 255 : index_bytes == 2 ? 65535 : 0xffffffffull;
    if ((index_bytes != 1 && index_bytes != 2 && index_bytes != 4) || m->nverts > limit)
        fail(ST_ERR_RANGE, std::to_string(m->nverts) + " vertices do not fit " + std::to_string(index_bytes) +
                               "-byte indices");

    // Positions as float, with their exact float bounds.
    std::vector<float> pos(3 * (size_t)m->nverts);
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (size_t i = 0; i < 3 * (size_t)m->nverts; i++) {
        double v = m->pos[i];
        if (!std::isfinite(v) || std::fabs(v) > FLT_MAX)
            fail(ST_ERR_GEOMETRY, "vertex " + std::to_string(i / 3) + " is not finite or beyond float range");
        pos[i] = (float)v;
        lo[i % 3] = std::min(lo[i % 3], (double)pos[i]);
        hi[i % 3] = std::max(hi[i % 3], (double)pos[i]);
    }

    std::vector<double> acc = unit_normals(m);
    std::vector<float> nrm(acc.size());
    for (size_t i = 0; i < acc.size(); i++) nrm[i] = (float)acc[i];

    // One buffer: positions, normals, [texcoords, [tangents,]] indices (each
    // 4-byte aligned), [the embedded normal map].
    std::vector<unsigned char> buf;
    size_t vbytes = pos.size() * sizeof(float), tbytes = tex.size() * sizeof(float), gbytes = tan.size() * sizeof(float);
    buf.reserve(2 * vbytes + tbytes + gbytes + 3 * ntri * (size_t)index_bytes + 4);
    buf.insert(buf.end(), (const unsigned char *)pos.data(), (const unsigned char *)pos.data() + vbytes);
    buf.insert(buf.end(), (const unsigned char *)nrm.data(), (const unsigned char *)nrm.data() + vbytes);
    if (tbytes) buf.insert(buf.end(), (const unsigned char *)tex.data(), (const unsigned char *)tex.data() + tbytes);
    if (gbytes) buf.insert(buf.end(), (const unsigned char *)tan.data(), (const unsigned char *)tan.data() + gbytes);
    // The indices of group 0, then of group 1 ... (each group's own view,
    // 4-byte aligned).
    std::vector<size_t> g_at(ngroups), g_tri(ngroups);
    for (size_t gi = 0; gi < ngroups; gi++) {
        while (gi && buf.size() % 4) buf.push_back(0);
        g_at[gi] = buf.size();
        for (uint32_t f = 0; f < m->nfaces; f++) {
            uint32_t a = m->face_off[f], b = m->face_off[f + 1];
            if (m->face_hole && m->face_hole[f]) continue;
            if (ngroups > 1 && (*group)[f] != gi) continue;
            for (uint32_t k = a + 1; k + 1 < b; k++) {  // fan from the first corner
                uint32_t c[3] = {m->face_idx[a], m->face_idx[k], m->face_idx[k + 1]};
                g_tri[gi]++;
                for (uint32_t v : c) {
                    if (index_bytes == 1) put(&buf, (uint8_t)v);
                    else if (index_bytes == 2) put(&buf, (uint16_t)v);
                    else put(&buf, (uint32_t)v);
                }
            }
        }
    }
    for (size_t gi = 0; gi < ngroups; gi++)
        if (!g_tri[gi]) fail(ST_ERR_INVALID, "UV tile group " + std::to_string(gi) + " has no triangle");

    size_t ibytes = 3 * g_tri[0] * (size_t)index_bytes;
    std::vector<size_t> png_at(ngroups, 0);
    for (size_t gi = 0; nmaps && gi < ngroups; gi++)
        if (!(*nmaps)[gi].png.empty()) {
            while (buf.size() % 4) buf.push_back(0);
            png_at[gi] = buf.size();
            buf.insert(buf.end(), (*nmaps)[gi].png.begin(), (*nmaps)[gi].png.end());
        }

    model->asset.version = "2.0";
    model->asset.generator = "Strata";
    tinygltf::Buffer b;
    b.data.swap(buf);
    model->buffers.push_back(b);
    add_view(model, 0, vbytes, TINYGLTF_TARGET_ARRAY_BUFFER);
    add_view(model, vbytes, vbytes, TINYGLTF_TARGET_ARRAY_BUFFER);
    if (tbytes) add_view(model, 2 * vbytes, tbytes, TINYGLTF_TARGET_ARRAY_BUFFER);
    add_view(model, 2 * vbytes + tbytes + gbytes, ibytes, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    if (gbytes) add_view(model, 2 * vbytes + tbytes, gbytes, TINYGLTF_TARGET_ARRAY_BUFFER);

    tinygltf::Accessor ap = float_accessor(0, TINYGLTF_TYPE_VEC3, m->nverts);
    ap.minValues.assign(lo, lo + 3);
    ap.maxValues.assign(hi, hi + 3);
    tinygltf::Accessor an = float_accessor(1, TINYGLTF_TYPE_VEC3, m->nverts);
    tinygltf::Accessor ai;
    ai.bufferView = tbytes ? 3 : 2;
    ai.componentType = index_bytes == 1   ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE
                       : index_bytes == 2 ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                          : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    ai.type = TINYGLTF_TYPE_SCALAR;
    ai.count = 3 * g_tri[0];
    model->accessors = {ap, an, ai};
    if (tbytes) model->accessors.push_back(float_accessor(2, TINYGLTF_TYPE_VEC2, m->nverts));
    if (gbytes) model->accessors.push_back(float_accessor(4, TINYGLTF_TYPE_VEC4, m->nverts));

    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = 0;
    prim.attributes["NORMAL"] = 1;
    if (tbytes) prim.attributes["TEXCOORD_0"] = 3;
    if (gbytes) prim.attributes["TANGENT"] = 4;
    prim.indices = 2;
    prim.mode = kModeTriangles;
    // Groups 1.. (UDIM tiles): their own index views and accessors, after
    // everything above, so that a one-group model is laid out as before.
    std::vector<tinygltf::Primitive> prims(1, prim);
    for (size_t gi = 1; gi < ngroups; gi++) {
        add_view(model, g_at[gi], 3 * g_tri[gi] * (size_t)index_bytes, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        tinygltf::Accessor ax = ai;
        ax.bufferView = (int)model->bufferViews.size() - 1;
        ax.count = 3 * g_tri[gi];
        model->accessors.push_back(ax);
        tinygltf::Primitive px = prim;
        px.indices = (int)model->accessors.size() - 1;
        prims.push_back(px);
    }
    for (size_t gi = 0; nmap && gi < ngroups; gi++) {
        const NormalMap *nm = &(*nmaps)[gi];
        // The normal map: image (embedded bytes or a URI), texture, and a
        // material that uses it through TEXCOORD_0 and the TANGENT above.
        tinygltf::Image img;
        img.name = ngroups > 1 ? "normal." + nm->name : "normal";
        if (!nm->png.empty()) {
            add_view(model, png_at[gi], nm->png.size(), 0);
            img.bufferView = (int)model->bufferViews.size() - 1;
            img.mimeType = "image/png";
        } else {
            img.uri = nm->uri;
        }
        model->images.push_back(img);
        if (gi) {
            tinygltf::Texture t;
            t.source = (int)gi;
            t.sampler = 0;
            model->textures.push_back(t);
            tinygltf::Material mt;
            mt.name = "strata." + nm->name;
            mt.normalTexture.index = (int)gi;
            model->materials.push_back(mt);
            prims[gi].material = (int)gi;
            continue;
        }
        // Sampled with repeat, as strata bake wrapped the faces that
        // overshoot their UV tile (core/bake/bake.h: tiles and
        // wrap-around); said explicitly although glTF 2.0 §5.26 makes
        // repeat the default of a texture without a sampler.
        tinygltf::Sampler smp;
        smp.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
        smp.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
        smp.wrapS = TINYGLTF_TEXTURE_WRAP_REPEAT;
        smp.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
        model->samplers.push_back(smp);
        tinygltf::Texture t;
        t.source = 0;
        t.sampler = 0;
        model->textures.push_back(t);
        tinygltf::Material mt;
        mt.name = "strata";
        mt.normalTexture.index = 0;
        if (ngroups > 1) mt.name += "." + nm->name;
        model->materials.push_back(mt);
        prims[0].material = 0;
    }
    tinygltf::Mesh mesh;
    mesh.name = "strata";
    mesh.primitives = prims;
    model->meshes.push_back(mesh);
    tinygltf::Node node;
    node.mesh = 0;
    node.name = "strata";
    model->nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    model->scenes.push_back(scene);
    model->defaultScene = 0;
}

std::string to_bytes(const tinygltf::Model &model, bool binary)
{
    tinygltf::TinyGLTF writer;
    std::ostringstream os;
    if (!writer.WriteGltfSceneToStream(&model, os, !binary, binary)) fail(ST_ERR_IO, "tinygltf could not serialise it");
    return os.str();
}

// A file written atomically (core/io/atomic_file.h): its temporary is
// removed unless it was placed.  Failures name the file (fail_named), so
// that a .gltf's .bin is named as itself.
struct OutFile {
    st_afile af{};
    bool open = false;
    OutFile() = default;
    OutFile(const OutFile &) = delete;
    OutFile &operator=(const OutFile &) = delete;
    ~OutFile()
    {
        if (open) st_afile_abort(&af);
    }
};

void out_open(OutFile *o, const std::string &path)
{
    st_error e;
    if (st_afile_open(&o->af, path.c_str(), &e)) fail_named(ST_ERR_IO, e.msg);
    o->open = true;
}

void out_write(OutFile *o, const std::string &bytes)
{
    if (st_afile_write(&o->af, bytes.data(), bytes.size()))
        fail_named(ST_ERR_IO, std::string(o->af.path) + ": write error: " + strerror(o->af.werr));
}

// Every write that can fail is done once this returns.
void out_finish(OutFile *o)
{
    st_error e;
    if (st_afile_finish(&o->af, &e)) {
        o->open = false;
        fail_named(ST_ERR_IO, e.msg);
    }
}

void out_place(OutFile *o)
{
    st_error e;
    o->open = false;
    if (st_afile_place(&o->af, &e)) fail_named(ST_ERR_IO, e.msg);
}

// Writes bytes to path atomically: a failed write never leaves a half file
// under the real name, and keeps the old one.
void write_file(const std::string &path, const std::string &bytes)
{
    OutFile o;
    out_open(&o, path);
    out_write(&o, bytes);
    out_finish(&o);
    out_place(&o);
}

// Percent-encodes what a URI path segment may not hold.
std::string uri_encode(const std::string &s)
{
    static const char hex[] = "0123456789ABCDEF";
    std::string out;
    for (unsigned char c : s) {
        if (isalnum(c) || strchr("-._~!$&'()*+,;=:@", c)) out += (char)c;
        else out += '%', out += hex[c >> 4], out += hex[c & 15];
    }
    return out;
}

// .gltf: the JSON of the GLB serialisation with the buffer's uri pointing at
// NAME.bin (tinygltf's stream writer would embed it as base64 instead).
void save_gltf_json(const std::string &path, const tinygltf::Model &model)
{
    std::string glb = to_bytes(model, true);
    uint32_t json_len;
    memcpy(&json_len, glb.data() + 12, 4);
    nlohmann::json j = nlohmann::json::parse(glb.substr(20, json_len));
    std::string dir, base = path;
    size_t slash = path.find_last_of('/');
    if (slash != std::string::npos) dir = path.substr(0, slash + 1), base = path.substr(slash + 1);
    size_t dot = base.find_last_of('.');
    std::string bin = (dot == std::string::npos ? base : base.substr(0, dot)) + ".bin";
    j["buffers"][0]["uri"] = uri_encode(bin);
    const std::vector<unsigned char> &data = model.buffers[0].data;
    // Both written and finished before either is placed, the .bin first: a
    // kill leaves the old pair or the new one (but for the window between
    // the two renames, atomic_file.h), and an old .gltf never names a .bin
    // that is not there.
    OutFile fb, fj;
    out_open(&fb, dir + bin);
    out_open(&fj, path);
    out_write(&fb, std::string(data.begin(), data.end()));
    out_write(&fj, j.dump(2) + "\n");
    out_finish(&fb);
    out_finish(&fj);
    out_place(&fb);
    out_place(&fj);
}

// The URI of png as seen from the folder of the .gltf at path: a relative
// reference, each segment percent-encoded.
std::string relative_uri(const std::string &path, const std::string &png)
{
    namespace fs = std::filesystem;
    fs::path from = fs::weakly_canonical(fs::absolute(fs::path(path))).parent_path();
    fs::path to = fs::weakly_canonical(fs::absolute(fs::path(png)));
    fs::path rel = to.lexically_relative(from);
    if (rel.empty()) fail(ST_ERR_INVALID, png + ": no relative path from " + from.string());
    std::string uri;
    for (const fs::path &seg : rel) uri += (uri.empty() ? "" : "/") + uri_encode(seg.string());
    return uri;
}

void load_normal_map(const std::string &path, const std::string &png, bool glb, NormalMap *out)
{
    std::vector<unsigned char> bytes;
    std::string why;
    if (!read_file(png, &bytes, &why)) fail(ST_ERR_IO, png + ": cannot read: " + why);
    if (bytes.size() < 8 || memcmp(bytes.data(), "\x89PNG\r\n\x1a\n", 8) != 0) fail(ST_ERR_PARSE, png + ": not a PNG file");
    if (glb) out->png.swap(bytes);
    else out->uri = relative_uri(path, png);
}

// A UDIM set NAME.<UDIM>.png: each face goes to the group of its home UV
// tile (core/bake/bake.h: st_bake_face_tile), groups in UDIM order, each
// with the tile's PNG; the face's UVs are moved by its home tile into
// [0,1] (give or take its overshoot, read with repeat), as strata bake
// baked the tile's image.
void udim_groups(const char *path, const st_mesh *m, const st_gltf_material *mat, bool glb, std::vector<NormalMap> *nmaps,
                 std::vector<uint32_t> *group, std::vector<double> *shifted)
{
    if (!m->nfaces || !m->face_off) fail(ST_ERR_INVALID, "the mesh is empty");
    uint32_t nc = m->face_off[m->nfaces];
    shifted->assign(mat->corner_uv, mat->corner_uv + 2 * (size_t)nc);
    group->assign(m->nfaces, 0);
    std::vector<unsigned> number(m->nfaces, 0);
    std::map<unsigned, uint32_t> used;   // UDIM number -> group, in UDIM order
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t a = m->face_off[f], n = m->face_off[f + 1] - a;
        if (!n) continue;
        int32_t t[2];
        st_bake_face_tile(mat->corner_uv + 2 * (size_t)a, n, t);
        number[f] = st_bake_udim(t);
        if (!number[f])
            fail(ST_ERR_INVALID, "face " + std::to_string(f + 1) + " lies in UV tile (" + std::to_string(t[0]) + ", " +
                                     std::to_string(t[1]) + "), which has no UDIM number (u tiles 0..9, v tiles 0..99)");
        for (uint32_t k = a; k < a + n; k++) {
            (*shifted)[2 * (size_t)k] -= t[0];
            (*shifted)[2 * (size_t)k + 1] -= t[1];
        }
        if (!(m->face_hole && m->face_hole[f])) used[number[f]] = 0;
    }
    if (used.size() > 64) fail(ST_ERR_INVALID, "the faces use " + std::to_string(used.size()) + " UDIM tiles; at most 64 are written");
    uint32_t gi = 0;
    for (auto &u : used) u.second = gi++;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        auto it = used.find(number[f]);
        (*group)[f] = it == used.end() ? 0 : it->second;   // a hole face is written in no group
    }
    nmaps->assign(used.size(), NormalMap());
    std::string p = mat->normal_map;
    size_t at = p.find("<UDIM>");
    for (const auto &u : used) {
        std::string one = p.substr(0, at) + std::to_string(u.first) + p.substr(at + 6);
        load_normal_map(path, one, glb, &(*nmaps)[u.second]);
        (*nmaps)[u.second].name = std::to_string(u.first);
    }
}

// The frame of every file export: the name's extension picks GLB or JSON,
// build(glb, &model) fills the model, and a failure becomes "PATH: why"
// (or the message alone when it names its file already).
template <class Build> int save_model(const char *path, st_error *err, Build build)
{
    try {
        bool glb = st_path_has_ext(path, ".glb");
        if (!glb && !st_path_has_ext(path, ".gltf"))
            return st_fail(err, ST_ERR_PARSE, "%s: not a glTF file name (expected .gltf or .glb)", path);
        tinygltf::Model model;
        build(glb, &model);
        if (glb) write_file(path, to_bytes(model, true));
        else save_gltf_json(path, model);
        return 0;
    } catch (const Failure &f) {
        if (f.named) return st_fail(err, f.code, "%s", f.msg.c_str());
        return st_fail(err, f.code, "%s: %s", path, f.msg.c_str());
    } catch (const std::exception &e) {
        return st_fail(err, ST_ERR_IO, "%s: %s", path, one_line(e.what()).c_str());
    }
}

}  // namespace

extern "C" {

int st_gltf_save_level_mapped(const char *path, st_hier *h, unsigned l, const st_mesh *m, int auto_uv, uint32_t atlas_size,
                              uint32_t atlas_padding, const char *normal_map, st_error *err)
{
    st_bake_layout lay;
    int rc = !auto_uv && st_hier_has_uv(h, l) ? st_bake_level_uvs(h, l, &lay, err)
                                          : st_bake_chart_uvs(h, l, atlas_size, atlas_padding, &lay, NULL, err);
    if (rc) return rc;
    size_t nc = lay.corner_off[lay.nfaces];
    double *tan = (double *)malloc((nc ? nc : 1) * 4 * sizeof *tan), *nrm = (double *)malloc((nc ? nc : 1) * 3 * sizeof *nrm);
    st_bake_uvs uvs = st_bake_layout_uvs(&lay);
    if (!tan || !nrm) rc = st_fail(err, ST_ERR_MEMORY, "out of memory for the tangents of level %u", l);
    else if (lay.nfaces != m->nfaces || nc != m->face_off[m->nfaces])
        rc = st_fail(err, ST_ERR_INVALID, "level %u: %u faces, %zu corners in its UV layout; the mesh has %u and %u", l, lay.nfaces, nc,
                     m->nfaces, m->face_off[m->nfaces]);
    if (!rc) rc = st_bake_tangents(h, l, &uvs, tan, nrm, err);
    if (!rc) {
        st_gltf_material mat = { lay.uv, tan, nrm, normal_map };
        rc = st_gltf_save_mapped(path, m, &mat, err);
    }
    free(tan);
    free(nrm);
    st_bake_layout_free(&lay);
    return rc;
}

int st_gltf_save_mapped(const char *path, const st_mesh *m, const st_gltf_material *mat, st_error *err)
{
    if (!mat || !mat->corner_uv || !mat->corner_tangent || !mat->corner_normal || !mat->normal_map)
        return st_gltf_is_gltf_path(path)
                   ? st_fail(err, ST_ERR_INVALID, "%s: a normal-mapped export needs UVs, tangents, normals and a map", path)
                   : st_fail(err, ST_ERR_PARSE, "%s: not a glTF file name (expected .gltf or .glb)", path);
    return save_model(path, err, [&](bool glb, tinygltf::Model *model) {
        std::vector<NormalMap> nmaps(1);
        std::vector<uint32_t> group;
        std::vector<double> shifted;
        st_gltf_material one = *mat;
        const char *tok = strstr(mat->normal_map, "<UDIM>");
        if (tok) udim_groups(path, m, mat, glb, &nmaps, &group, &shifted);
        else load_normal_map(path, mat->normal_map, glb, &nmaps[0]);
        if (tok) one.corner_uv = shifted.data();
        mesh_to_model(m, 0, model, &one, &nmaps, tok ? &group : nullptr);
    });
}

int st_gltf_is_gltf_path(const char *path)
{
    return path && (st_path_has_ext(path, ".gltf") || st_path_has_ext(path, ".glb"));
}

int st_gltf_parse(const char *name, const void *data, size_t size, st_mesh *out, st_error *err)
{
    return parse_impl(name, (const unsigned char *)data, size, nullptr, out, nullptr, err);
}

int st_gltf_load_notes(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err)
{
    std::vector<unsigned char> bytes;
    std::string dir;
    try {
        std::string why;
        if (!read_file(path, &bytes, &why)) return st_fail(err, ST_ERR_IO, "%s: cannot read: %s", path, why.c_str());
        std::string p = path;
        size_t slash = p.find_last_of('/');
        dir = slash == std::string::npos ? "." : p.substr(0, slash);
    } catch (...) {
        return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", path);
    }
    st_mesh m;
    st_mesh_init(&m);
    st_notes local = {nullptr, 0};
    int rc = parse_impl(path, bytes.data(), bytes.size(), dir.c_str(), &m, notes ? &local : nullptr, err);
    /* The parser's notes (welded vertices and the like), then the repair's;
     * *notes gets them only on success. */
    if (!rc) rc = st_mesh_finish_load(path, &m, nullptr, flags, out, notes ? &local : nullptr, err);
    else st_mesh_free(&m);
    if (!rc)
        for (uint32_t i = 0; i < local.count; i++) st_notes_add(notes, "%s", local.lines[i]);
    st_notes_free(&local);
    return rc;
}

int st_gltf_load(const char *path, st_mesh *out, st_error *err)
{
    return st_gltf_load_notes(path, out, 0, nullptr, err);
}

int st_gltf_write_mem(const st_mesh *m, int binary, int index_bytes, void **data, size_t *size, st_error *err)
{
    try {
        tinygltf::Model model;
        mesh_to_model(m, index_bytes, &model);
        std::string bytes = to_bytes(model, binary != 0);
        void *p = malloc(bytes.size() ? bytes.size() : 1);
        if (!p) return st_fail(err, ST_ERR_MEMORY, "glTF: out of memory");
        memcpy(p, bytes.data(), bytes.size());
        *data = p;
        *size = bytes.size();
        return 0;
    } catch (const Failure &f) {
        return st_fail(err, f.code, "glTF: %s", f.msg.c_str());
    } catch (const std::exception &e) {
        return st_fail(err, ST_ERR_MEMORY, "glTF: %s", one_line(e.what()).c_str());
    }
}

int st_gltf_save(const char *path, const st_mesh *m, st_error *err)
{
    return save_model(path, err, [&](bool, tinygltf::Model *model) { mesh_to_model(m, 0, model); });
}

}  // extern "C"
