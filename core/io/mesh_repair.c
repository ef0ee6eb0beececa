/* Topological check and repair of a polygon soup (st_mesh_repair, st_mesh_check).
 * (Just over 900 lines, one file on purpose: each repair below leaves the
 * soup in the state the next one assumes, in this order, and the check at
 * the end restates all of them.)
 *
 * Goal: an oriented 2-manifold, possibly with boundary.  Every undirected
 * edge is used by one face (boundary) or two faces that traverse it in
 * opposite directions, and the faces around every vertex form one fan (a
 * disk, or a half-disk at the boundary).
 *
 * Decisions, one per defect, in the order they are handled:
 *   structural garbage (index out of range, face of < 3 or repeated
 *     vertices, non-finite position)       refuse (parsers already refuse
 *                                          these with the line)
 *   edge used by 3+ faces                  repair (refuse with ST_MESH_STRICT):
 *                                          the first face on the edge (file
 *                                          order) and the first later one
 *                                          running the other way (else the
 *                                          second) keep it; every further face
 *                                          gets its own copies of the edge's
 *                                          two vertices, which detaches it
 *                                          there (split_crowded_edges)
 *   inconsistent winding                   repair: breadth-first search over
 *                                          faces across manifold edges, flip
 *                                          the faces whose winding disagrees
 *                                          (per component, the smaller side)
 *   non-orientable (Moebius)               refuse: no winding exists
 *   vertex with 2+ fans (bow-tie, pinch)   repair: one copy of the vertex
 *                                          per fan, positions duplicated
 *   unreferenced vertex                    repair: dropped, indices remapped
 *   crease/corner tag on a changed vertex  follows its vertex (creases to the
 *                                          copies that form the edge, corners
 *                                          to every copy); a tag left with no
 *                                          edge or vertex is dropped
 * Every repair adds one note line "file: repaired: ...".
 *
 * Edges are found by sorting the half-edge keys (min, max vertex), so the
 * whole pass is O(n log n) in the number of face corners, and the fan
 * search is a union-find over corners: no recursion, no per-vertex scans.
 * The input is modified only after every check has passed, so a refused
 * mesh is left as it was.
 */
#include "core/io/mesh_internal.h"
#include "core/base/hugepage.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NONE UINT32_MAX
#define MAX_LISTED 8        /* vertices or faces named in one message */

typedef struct ctx {
    const char *name;
    const st_mesh_src *src; /* face locations, or NULL */
    st_notes *notes;
    st_error *err;
    uint32_t base;          /* vertex numbering of the file in messages: 0 or 1 */
    int strict;             /* ST_MESH_STRICT: refuse edges with 3+ faces instead of splitting */
} ctx;

/* The corner (half-edge) view of the faces: corner c of face f sits at
 * vertex idx[c]; its half-edge runs from idx[c] to idx[next(c)]. */
typedef struct soup {
    uint32_t nv, nf, nc;
    const uint32_t *off;    /* nf + 1 face offsets */
    uint32_t *idx;          /* nc vertex per corner (a working copy in repair) */
    uint32_t *face_of;      /* nc face of each corner */
    uint32_t *partner;      /* nc other corner on the same undirected edge, or NONE */
    uint32_t *uv;           /* nc UV index per corner (a working copy in repair), or NULL */
    uint32_t nv_in;         /* vertices of the input; nv - nv_in are copies made by edge splits */
    uint32_t *ecopy_of;     /* nv - nv_in: the input vertex of each edge-split copy */
    uint8_t *ecopied;       /* nv_in flags: the vertex has edge-split copies (NULL: no split) */
} soup;

typedef struct edge_rec {
    uint64_t key;           /* (min vertex << 32) | max vertex */
    uint32_t c;             /* the corner whose half-edge this is */
} edge_rec;

/* ---- messages -------------------------------------------------------------- */

/* "line 12" / "byte 345" / "face 7" for a face, as the file locates it. */
static void face_where(const ctx *x, uint32_t f, char *buf, size_t size)
{
    if (x->src && x->src->face_loc)
        snprintf(buf, size, "%s %llu", x->src->binary ? "byte" : "line",
                 (unsigned long long)x->src->face_loc[f]);
    else
        snprintf(buf, size, "face %u", f);
}

/* Fails at face f: "name:LINE: ..." or "name: byte N: ...", or "name: ..."
 * when locations are unknown (the messages then name the 0-based face). */
static int fail_face(const ctx *x, int code, uint32_t f, const char *fmt, ...)
{
    char what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (x->src && x->src->face_loc)
        return st_mesh_fail_at(x->err, code, x->name, x->src->binary, x->src->face_loc[f], "%s", what);
    return st_fail(x->err, code, "%s: %s", x->name, what);
}

static int out_of_memory(const ctx *x)
{
    return st_fail(x->err, ST_ERR_MEMORY, "%s: out of memory checking the mesh", x->name);
}

/* ---- structural validation ---------------------------------------------------- */

/* Offsets first (so that the degree bound sizes the scratch), then indices. */
static int validate_faces(const ctx *x, const st_mesh *m)
{
    if (!m->face_off || m->face_off[0] != 0)
        return st_fail(x->err, ST_ERR_INVALID, "%s: malformed face offsets", x->name);
    uint32_t maxdeg = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t a = m->face_off[f], b = m->face_off[f + 1];
        if (b < a || b - a < 3 || b - a > ST_MESH_MAX_DEGREE)
            return fail_face(x, ST_ERR_TOPOLOGY, f, "face %u has %lld vertices; a face needs 3 to %u",
                             f, (long long)b - (long long)a, ST_MESH_MAX_DEGREE);
        if (b - a > maxdeg) maxdeg = b - a;
    }
    if (!m->face_idx) return st_fail(x->err, ST_ERR_INVALID, "%s: no face indices", x->name);
    uint32_t *scratch = malloc((size_t)maxdeg * sizeof *scratch);
    if (!scratch) return out_of_memory(x);
    int rc = 0;
    for (uint32_t f = 0; f < m->nfaces && !rc; f++) {
        uint32_t a = m->face_off[f], b = m->face_off[f + 1];
        for (uint32_t c = a; c < b && !rc; c++)
            if (m->face_idx[c] >= m->nverts)
                rc = fail_face(x, ST_ERR_RANGE, f, "face %u references vertex %u but the mesh has %u",
                               f, m->face_idx[c] + x->base, m->nverts);
        uint32_t dup = rc ? NONE : st_mesh_face_repeat(m->face_idx + a, b - a, scratch);
        if (dup != NONE)
            rc = fail_face(x, ST_ERR_TOPOLOGY, f, "face %u uses vertex %u more than once", f, dup + x->base);
    }
    free(scratch);
    return rc;
}

static int validate_tags(const ctx *x, const st_mesh *m)
{
    if ((m->ncreases && (!m->crease_v || !m->crease_s)) || (m->ncorners && (!m->corner_v || !m->corner_s)))
        return st_fail(x->err, ST_ERR_INVALID, "%s: malformed tag arrays", x->name);
    for (uint32_t i = 0; i < m->ncreases; i++) {
        uint32_t a = m->crease_v[2 * i], b = m->crease_v[2 * i + 1];
        if (a >= m->nverts || b >= m->nverts || a == b || !isfinite(m->crease_s[i]))
            return st_fail(x->err, ST_ERR_INVALID, "%s: crease tag %u (%u-%u) is not an edge of "
                           "two existing vertices", x->name, i, a, b);
    }
    for (uint32_t i = 0; i < m->ncorners; i++)
        if (m->corner_v[i] >= m->nverts || !isfinite(m->corner_s[i]))
            return st_fail(x->err, ST_ERR_INVALID, "%s: corner tag %u names vertex %u of %u",
                           x->name, i, m->corner_v[i], m->nverts);
    return 0;
}

/* The face-varying UV channel: all three fields or none, indices in range,
 * values finite. */
static int validate_uvs(const ctx *x, const st_mesh *m)
{
    if (!m->face_uv && !m->uv && !m->nuvs) return 0;
    if (!m->face_uv || !m->uv || !m->nuvs)
        return st_fail(x->err, ST_ERR_INVALID, "%s: malformed texture coordinate arrays", x->name);
    for (size_t i = 0; i < 2 * (size_t)m->nuvs; i++)
        if (!isfinite(m->uv[i]))
            return st_fail(x->err, ST_ERR_GEOMETRY, "%s: texture coordinate %zu is not finite",
                           x->name, i / 2 + x->base);
    for (uint32_t f = 0; f < m->nfaces; f++)
        for (uint32_t c = m->face_off[f]; c < m->face_off[f + 1]; c++)
            if (m->face_uv[c] >= m->nuvs)
                return fail_face(x, ST_ERR_RANGE, f, "face %u references texture coordinate %u but the mesh has %u",
                                 f, m->face_uv[c] + x->base, m->nuvs);
    return 0;
}

/* Everything the parsers guarantee, re-checked for meshes built elsewhere. */
static int validate(const ctx *x, const st_mesh *m)
{
    if (m->nfaces == 0) return st_fail(x->err, ST_ERR_TOPOLOGY, "%s: no faces", x->name);
    if (m->nverts > ST_MESH_MAX_VERTS || m->nfaces > ST_MESH_MAX_FACES)
        return st_fail(x->err, ST_ERR_RANGE, "%s: %u vertices and %u faces exceed the limits",
                       x->name, m->nverts, m->nfaces);
    if (m->nverts && !m->pos) return st_fail(x->err, ST_ERR_INVALID, "%s: no positions", x->name);
    for (size_t i = 0; i < 3 * (size_t)m->nverts; i++)
        if (!isfinite(m->pos[i]))
            return st_fail(x->err, ST_ERR_GEOMETRY, "%s: vertex %zu has a non-finite coordinate",
                           x->name, i / 3 + x->base);
    int rc = validate_faces(x, m);
    if (!rc) rc = validate_uvs(x, m);
    return rc ? rc : validate_tags(x, m);
}

/* ---- corners and edges ---------------------------------------------------- */

static uint32_t next_corner(const soup *s, uint32_t c)
{
    return c + 1 == s->off[s->face_of[c] + 1] ? s->off[s->face_of[c]] : c + 1;
}

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

static int cmp_edge(const void *pa, const void *pb)
{
    const edge_rec *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->c > b->c) - (a->c < b->c);
}

static void soup_free(soup *s)
{
    free(s->face_of);
    free(s->partner);
    free(s->ecopy_of);
    free(s->ecopied);
    s->face_of = s->partner = s->ecopy_of = NULL;
    s->ecopied = NULL;
}

static int soup_init(const ctx *x, soup *s, const st_mesh *m, uint32_t *idx)
{
    s->nv = s->nv_in = m->nverts;
    s->nf = m->nfaces;
    s->nc = m->face_off[m->nfaces];
    s->off = m->face_off;
    s->idx = idx;
    s->face_of = malloc((size_t)s->nc * sizeof *s->face_of);
    s->partner = malloc((size_t)s->nc * sizeof *s->partner);
    if (!s->face_of || !s->partner) {
        soup_free(s);
        return out_of_memory(x);
    }
    for (uint32_t f = 0; f < s->nf; f++)
        for (uint32_t c = s->off[f]; c < s->off[f + 1]; c++) s->face_of[c] = f;
    return 0;
}

/* Names the faces of a sorted edge group as the file locates them:
 * "lines 6, 7, 8", "bytes 120, 134, 148" or "faces 0, 1, 2". */
static void list_faces(const ctx *x, const soup *s, const edge_rec *e, uint32_t n, char *buf, size_t size)
{
    int located = x->src && x->src->face_loc;
    size_t len = (size_t)snprintf(buf, size, "%s", !located ? "faces" : x->src->binary ? "bytes" : "lines");
    for (uint32_t k = 0; k < n && k < MAX_LISTED && len < size; k++) {
        uint32_t f = s->face_of[e[k].c];
        unsigned long long w = located ? (unsigned long long)x->src->face_loc[f] : f;
        len += (size_t)snprintf(buf + len, size - len, "%s %llu", k ? "," : "", w);
    }
    if (n > MAX_LISTED && len < size) snprintf(buf + len, size - len, ", ...");
}

/* e[0..n) made in corner order (c ascending) into (key, c) order, the order
 * qsort with cmp_edge gives (a total order: the same array): a stable
 * least-significant-digit radix sort of the key, 16 bits a pass, skipping
 * the passes whose digit every key shares.  About a fifth of qsort's
 * instructions on koala's 300k half-edges.  Small inputs, or no memory for
 * the scratch, take qsort. */
static void sort_edges(edge_rec *e, uint32_t n)
{
    edge_rec *tmp = n >= 1024 ? st_malloc_huge((size_t)n * sizeof *tmp) : NULL;  /* written in full: hugepage.h */
    uint32_t *count = tmp ? malloc(65536 * sizeof *count) : NULL;
    if (!count) {
        free(tmp);
        qsort(e, n, sizeof *e, cmp_edge);
        return;
    }
    edge_rec *src = e, *dst = tmp;
    for (unsigned shift = 0; shift < 64; shift += 16) {
        memset(count, 0, 65536 * sizeof *count);
        for (uint32_t i = 0; i < n; i++) count[(src[i].key >> shift) & 0xffff]++;
        if (count[(src[0].key >> shift) & 0xffff] == n) continue;
        for (uint32_t b = 0, sum = 0; b < 65536; b++) {
            uint32_t k = count[b];
            count[b] = sum;
            sum += k;
        }
        for (uint32_t i = 0; i < n; i++) dst[count[(src[i].key >> shift) & 0xffff]++] = src[i];
        edge_rec *t = src;
        src = dst;
        dst = t;
    }
    if (src != e) memcpy(e, src, (size_t)n * sizeof *e);
    free(tmp);
    free(count);
}

/* The half-edges sorted by undirected key; vertices are first relabelled
 * through relabel when it is not NULL. */
static edge_rec *sorted_edges(const ctx *x, const soup *s, const uint32_t *relabel)
{
    edge_rec *e = st_malloc_huge(((size_t)s->nc + 1) * sizeof *e);  /* written in full: hugepage.h */
    if (!e) {
        out_of_memory(x);
        return NULL;
    }
    for (uint32_t c = 0; c < s->nc; c++) {
        uint32_t a = s->idx[c], b = s->idx[next_corner(s, c)];
        e[c].key = relabel ? edge_key(relabel[a], relabel[b]) : edge_key(a, b);
        e[c].c = c;
    }
    sort_edges(e, s->nc);
    return e;
}

/* First record with the given key, or NULL. */
static const edge_rec *find_edge(const edge_rec *e, uint32_t n, uint64_t key)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (e[mid].key < key) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && e[lo].key == key ? &e[lo] : NULL;
}

static const char *vertices_word(uint32_t n)
{
    return n == 1 ? "vertex" : "vertices";
}

/* Of the half-edges e[0..n) of one crowded edge (sorted by corner, i.e. in
 * file order of their faces), the second that keeps the edge: the first
 * that runs against e[0] (the two then agree in orientation), else e[1]
 * (the orientation pass flips one of the two). */
static uint32_t second_keeper(const soup *s, const edge_rec *e, uint32_t n)
{
    for (uint32_t k = 1; k < n; k++)
        if (s->idx[e[k].c] != s->idx[e[0].c]) return k;
    return 1;
}

/* The note for the crowded edges split: a summary, then the first few
 * edges with their faces ("lines 20, 21, 22") and the two that kept it. */
static void note_edge_splits(const ctx *x, const soup *s, const edge_rec *e, uint32_t nedges,
                             uint32_t nmoved, uint32_t nverts, uint32_t ncopies)
{
    st_notes_add(x->notes, "%s: repaired: split %u non-manifold %s (3 or more faces on one edge): "
                 "%u further %s given %s own copies of the edge's vertices (%u %s split into %u copies)",
                 x->name, nedges, nedges == 1 ? "edge" : "edges", nmoved, nmoved == 1 ? "face" : "faces",
                 nmoved == 1 ? "its" : "their", nverts, vertices_word(nverts), ncopies);
    uint32_t listed = 0;
    for (uint32_t i = 0, j; i < s->nc && listed < MAX_LISTED; i = j) {
        for (j = i + 1; j < s->nc && e[j].key == e[i].key; j++) {}
        if (j - i < 3) continue;
        char faces[512], a[48], b[48];
        list_faces(x, s, e + i, j - i, faces, sizeof faces);
        face_where(x, s->face_of[e[i].c], a, sizeof a);
        face_where(x, s->face_of[e[i + second_keeper(s, e + i, j - i)].c], b, sizeof b);
        st_notes_add(x->notes, "%s: repaired: edge between vertices %u and %u split into %u (%s; %s and %s keep it)",
                     x->name, (uint32_t)(e[i].key >> 32) + x->base, (uint32_t)e[i].key + x->base, j - i - 1,
                     faces, a, b);
        listed++;
    }
    if (nedges > listed)
        st_notes_add(x->notes, "%s: repaired: ... and %u more split edges", x->name, nedges - listed);
}

/* Splits every edge that 3+ faces share (e: the sorted half-edges) into
 * manifold pieces.  OpenMesh's importer (OpenMesh/Core/IO/importer/
 * ImporterT.hh, add_face) meets a face it cannot add without a complex edge
 * by adding it on fresh copies of all its vertices; here only the corners
 * on the crowded edge are copied, so the further face stays attached to
 * the rest of the mesh everywhere else.  Two faces keep the edge: the first
 * in file order and the first after it that runs the other way (else the
 * second), so that a consistently oriented pair keeps it when there is one.
 * Each further face gets its own copy of each end (one per corner: a face
 * further on two crowded edges through one vertex copies that corner once),
 * numbered from s->nv up; afterwards no edge has more than two faces,
 * because every copy belongs to one corner.  The vertex a copy leaves may
 * now form several fans: split_vertices splits it as any pinch.  A face
 * that keeps one crowded edge may still lose a corner to another one; the
 * edge it kept is then a boundary of the other keeper, still manifold.
 * (OpenSubdiv instead keeps such an edge and tags it and its vertices
 * non-manifold, opensubdiv/vtr/level.h ETag/VTag _nonManifold, refining
 * them like sharp features; the map here needs a 2-manifold, hence the
 * split.)  Positions, normals and corner tags follow the copies (renumber:
 * orig). */
static int split_crowded_edges(const ctx *x, soup *s, const edge_rec *e, uint32_t nedges)
{
    uint32_t *copy = malloc(((size_t)s->nc + 1) * sizeof *copy);     /* per corner: its copy, or NONE */
    uint8_t *split = calloc((size_t)s->nv + 1, 1);                    /* per input vertex: copied */
    uint32_t *of = malloc(((size_t)s->nc + 1) * sizeof *of);          /* per copy: its input vertex */
    uint8_t *moved = calloc((size_t)s->nf + 1, 1);                    /* per face: detached somewhere */
    if (!copy || !split || !of || !moved) {
        free(copy);
        free(split);
        free(of);
        free(moved);
        return out_of_memory(x);
    }
    for (uint32_t c = 0; c < s->nc; c++) copy[c] = NONE;
    uint32_t ncopies = 0, nmoved = 0, nverts = 0;
    int rc = 0;
    for (uint32_t i = 0, j; i < s->nc && !rc; i = j) {
        for (j = i + 1; j < s->nc && e[j].key == e[i].key; j++) {}
        if (j - i < 3) continue;
        uint32_t keep = second_keeper(s, e + i, j - i);
        for (uint32_t k = 1; k < j - i && !rc; k++) {
            if (k == keep) continue;
            uint32_t ends[2] = {e[i + k].c, next_corner(s, e[i + k].c)};
            nmoved += !moved[s->face_of[ends[0]]];
            moved[s->face_of[ends[0]]] = 1;
            for (int t = 0; t < 2 && !rc; t++) {
                uint32_t c = ends[t];
                if (copy[c] != NONE) continue;
                if ((uint64_t)s->nv + ncopies >= ST_MESH_MAX_VERTS) {
                    rc = st_fail(x->err, ST_ERR_RANGE, "%s: splitting non-manifold edges would exceed "
                                 "%u vertices", x->name, ST_MESH_MAX_VERTS);
                    break;
                }
                of[ncopies] = s->idx[c];
                copy[c] = s->nv + ncopies++;
                nverts += !split[s->idx[c]];
                split[s->idx[c]] = 1;
            }
        }
    }
    if (!rc) {
        note_edge_splits(x, s, e, nedges, nmoved, nverts, ncopies);
        for (uint32_t c = 0; c < s->nc; c++)
            if (copy[c] != NONE) s->idx[c] = copy[c];
        s->nv += ncopies;
        s->ecopy_of = of;
        s->ecopied = split;
        of = NULL;
        split = NULL;
    }
    free(copy);
    free(split);
    free(of);
    free(moved);
    return rc;
}

/* Pairs up the half-edges of each undirected edge.  An edge with 3+
 * half-edges is split when may_split (then paired again: none is left with
 * 3+), else refused, naming its vertices and its faces. */
static int pair_edges(const ctx *x, soup *s, int may_split)
{
    edge_rec *e = sorted_edges(x, s, NULL);
    if (!e) return ST_ERR_MEMORY;
    int rc = 0;
    uint32_t crowded = 0;
    for (uint32_t i = 0, j; i < s->nc && !rc; i = j) {
        for (j = i + 1; j < s->nc && e[j].key == e[i].key; j++) {}
        s->partner[e[i].c] = j - i == 2 ? e[i + 1].c : NONE;
        if (j - i == 2) s->partner[e[i + 1].c] = e[i].c;
        if (j - i >= 3 && may_split) {
            crowded++;
        } else if (j - i >= 3) {
            char faces[512];
            list_faces(x, s, e + i, j - i, faces, sizeof faces);
            rc = fail_face(x, ST_ERR_TOPOLOGY, s->face_of[e[i + 2].c],
                           "non-manifold edge between vertices %u and %u: %u faces share it (%s)",
                           (uint32_t)(e[i].key >> 32) + x->base, (uint32_t)e[i].key + x->base, j - i, faces);
        }
    }
    if (!rc && crowded) rc = split_crowded_edges(x, s, e, crowded);
    free(e);
    if (!rc && crowded) rc = pair_edges(x, s, 0);
    return rc;
}

/* ---- orientation ------------------------------------------------------------ */

enum { UNSEEN = 0, KEEP = 1, FLIP = 2 };

/* Two faces sharing an edge agree when they run along it in opposite
 * directions, i.e. when the two half-edges start at different vertices. */
static int conflict(const ctx *x, const soup *s, uint32_t c, uint32_t g)
{
    return fail_face(x, ST_ERR_TOPOLOGY, g, "non-orientable surface: cannot orient consistently "
                     "(face %u, at the edge between vertices %u and %u)", g, s->idx[c] + x->base,
                     s->idx[next_corner(s, c)] + x->base);
}

/* Breadth-first over the faces of the component of root, giving each the
 * winding its neighbour across an edge implies.  queue[*tail..] receives
 * the component.  Fails on a contradiction: the surface is non-orientable. */
static int orient_component(const ctx *x, const soup *s, uint32_t root, uint8_t *state,
                            uint32_t *queue, uint32_t *tail)
{
    uint32_t head = *tail;
    queue[(*tail)++] = root;
    state[root] = KEEP;
    while (head < *tail) {
        uint32_t f = queue[head++];
        for (uint32_t c = s->off[f]; c < s->off[f + 1]; c++) {
            uint32_t p = s->partner[c];
            if (p == NONE) continue;
            uint32_t g = s->face_of[p];
            uint8_t want = s->idx[p] == s->idx[c] ? (uint8_t)(KEEP + FLIP - state[f]) : state[f];
            if (state[g] == UNSEEN) {
                state[g] = want;
                queue[(*tail)++] = g;
            } else if (state[g] != want) {
                return conflict(x, s, c, g);
            }
        }
    }
    return 0;
}

/* Decides per face whether to flip it; within each component the smaller
 * set is flipped, so one stray face costs one flip whatever its index. */
static int orient(const ctx *x, const soup *s, uint8_t *state, uint32_t *nflip)
{
    uint32_t *queue = malloc((size_t)s->nf * sizeof *queue);
    if (!queue) return out_of_memory(x);
    uint32_t tail = 0;
    int rc = 0;
    *nflip = 0;
    for (uint32_t f = 0; f < s->nf && !rc; f++) {
        if (state[f] != UNSEEN) continue;
        uint32_t start = tail, flips = 0;
        rc = orient_component(x, s, f, state, queue, &tail);
        for (uint32_t k = start; k < tail; k++) flips += state[queue[k]] == FLIP;
        if (2 * (uint64_t)flips > tail - start) {
            for (uint32_t k = start; k < tail; k++) state[queue[k]] = (uint8_t)(KEEP + FLIP - state[queue[k]]);
            flips = tail - start - flips;
        }
        *nflip += flips;
    }
    free(queue);
    return rc;
}

static void reverse_corners(uint32_t *c, uint32_t a, uint32_t b)
{
    for (; a < b; a++, b--) {
        uint32_t t = c[a];
        c[a] = c[b];
        c[b] = t;
    }
}

/* Reverses the flagged faces in place, keeping each face's first corner;
 * UV indices are corners too and turn with them. */
static uint32_t apply_flips(soup *s, const uint8_t *state)
{
    uint32_t first = NONE;
    for (uint32_t f = 0; f < s->nf; f++) {
        if (state[f] != FLIP) continue;
        if (first == NONE) first = f;
        reverse_corners(s->idx, s->off[f] + 1, s->off[f + 1] - 1);
        if (s->uv) reverse_corners(s->uv, s->off[f] + 1, s->off[f + 1] - 1);
    }
    return first;
}

static int repair_orientation(const ctx *x, soup *s)
{
    uint8_t *state = calloc(s->nf, 1);
    if (!state) return out_of_memory(x);
    uint32_t nflip = 0;
    int rc = orient(x, s, state, &nflip);
    if (!rc && nflip) {
        uint32_t first = apply_flips(s, state);
        char w[48];
        face_where(x, first, w, sizeof w);
        st_notes_add(x->notes, "%s: repaired: flipped %u of %u faces to orient the surface "
                     "consistently (first: %s)", x->name, nflip, s->nf, w);
        rc = pair_edges(x, s, 0);  /* corners moved: pair them again */
    }
    free(state);
    return rc;
}

/* ---- fans -------------------------------------------------------------------- */

static uint32_t uf_find(uint32_t *parent, uint32_t c)
{
    while (parent[c] != c) {
        parent[c] = parent[parent[c]];  /* path halving: no recursion, near-constant depth */
        c = parent[c];
    }
    return c;
}

static void uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a < b) parent[b] = a;
    else if (b < a) parent[a] = b;
}

/* Groups the corners at each vertex into fans: corner c (half-edge v->w)
 * and the corner at v of the face across that edge are neighbours in the
 * fan of v.  Needs a consistent orientation (the partner runs w->v). */
static uint32_t *fan_roots(const ctx *x, const soup *s)
{
    uint32_t *parent = malloc((size_t)s->nc * sizeof *parent);
    if (!parent) {
        out_of_memory(x);
        return NULL;
    }
    for (uint32_t c = 0; c < s->nc; c++) parent[c] = c;
    for (uint32_t c = 0; c < s->nc; c++)
        if (s->partner[c] != NONE) uf_union(parent, c, next_corner(s, s->partner[c]));
    for (uint32_t c = 0; c < s->nc; c++) parent[c] = uf_find(parent, c);
    return parent;
}

/* Fans per original vertex, and the copies made for the extra fans. */
typedef struct vmap {
    uint32_t nv;            /* vertices before splitting */
    uint32_t next;          /* vertices after splitting: nv + copies */
    uint32_t *nfans;        /* nv: fans of each vertex (0: unreferenced) */
    uint32_t *copy_of;      /* next - nv: the original vertex of each copy */
} vmap;

static void vmap_free(vmap *vm)
{
    free(vm->nfans);
    free(vm->copy_of);
    vm->nfans = vm->copy_of = NULL;
}

static void note_splits(const ctx *x, const vmap *vm)
{
    uint32_t nsplit = 0, listed = 0;
    for (uint32_t v = 0; v < vm->nv; v++) nsplit += vm->nfans[v] > 1;
    if (!nsplit) return;
    st_notes_add(x->notes, "%s: repaired: split %u non-manifold %s (faces meeting only at a vertex) "
                 "into %u copies, one per fan of faces", x->name, nsplit, vertices_word(nsplit),
                 nsplit + (vm->next - vm->nv));
    for (uint32_t v = 0; v < vm->nv && listed < MAX_LISTED; v++)
        if (vm->nfans[v] > 1) {
            st_notes_add(x->notes, "%s: repaired: vertex %u split into %u", x->name, v + x->base, vm->nfans[v]);
            listed++;
        }
    if (nsplit > listed)
        st_notes_add(x->notes, "%s: repaired: ... and %u more split vertices", x->name, nsplit - listed);
}

/* Gives every fan but the first of each vertex a new vertex (numbered from
 * nv up), rewriting the corners of that fan. */
static int split_vertices(const ctx *x, soup *s, vmap *vm)
{
    uint32_t *root = fan_roots(x, s);
    uint32_t *vert = malloc(((size_t)s->nc + 1) * sizeof *vert);  /* per root corner: its vertex */
    vm->nv = vm->next = s->nv;
    vm->nfans = calloc((size_t)s->nv + 1, sizeof *vm->nfans);
    vm->copy_of = malloc(((size_t)s->nc + 1) * sizeof *vm->copy_of);
    int rc = (!root || !vert || !vm->nfans || !vm->copy_of) ? out_of_memory(x) : 0;
    for (uint32_t c = 0; c < s->nc && !rc; c++) {
        uint32_t r = root[c], v = s->idx[c];
        if (r == c) {   /* the first corner of a fan, in corner order */
            if (vm->nfans[v]++ == 0) {
                vert[r] = v;
            } else if (vm->next == ST_MESH_MAX_VERTS) {
                rc = st_fail(x->err, ST_ERR_RANGE, "%s: splitting non-manifold vertices would exceed "
                             "%u vertices", x->name, ST_MESH_MAX_VERTS);
            } else {
                vm->copy_of[vm->next - vm->nv] = v;
                vert[r] = vm->next++;
            }
        }
        s->idx[c] = vert[r];
    }
    free(root);
    free(vert);
    if (!rc) note_splits(x, vm);
    return rc;
}

/* ---- renumbering, positions, tags --------------------------------------------- */

/* The result of a repair, built aside and committed only on success. */
typedef struct fixed {
    uint32_t nverts;
    uint32_t *orig;         /* nverts: the input vertex each output vertex comes from */
    double *pos, *normals;
    uint32_t ncreases, ncorners;
    uint32_t *crease_v, *corner_v;
    float *crease_s, *corner_s;
} fixed;

static void fixed_free(fixed *r)
{
    free(r->orig);
    free(r->pos);
    free(r->normals);
    free(r->crease_v);
    free(r->crease_s);
    free(r->corner_v);
    free(r->corner_s);
}

/* An input vertex no corner uses any more and that was unreferenced in the
 * file: one whose corners all moved to edge-split copies was used, and is
 * dropped without a note (its copies carry it on). */
static int dropped_unused(const soup *s, const vmap *vm, uint32_t v)
{
    return v < s->nv_in && vm->nfans[v] == 0 && !(s->ecopied && s->ecopied[v]);
}

static void note_dropped(const ctx *x, const soup *s, const vmap *vm, uint32_t ndropped)
{
    char list[256];
    size_t len = 0;
    uint32_t listed = 0;
    list[0] = 0;
    for (uint32_t v = 0; v < s->nv_in && listed < MAX_LISTED; v++)
        if (dropped_unused(s, vm, v))
            len += (size_t)snprintf(list + len, sizeof list - len, "%s%u", listed++ ? ", " : "", v + x->base);
    st_notes_add(x->notes, "%s: repaired: dropped %u unreferenced %s (%s%s)", x->name, ndropped,
                 vertices_word(ndropped), list, ndropped > listed ? ", ..." : "");
}

/* The input vertex of vertex v of the soup (v itself or an edge copy's). */
static uint32_t input_vertex(const soup *s, uint32_t v)
{
    return v < s->nv_in ? v : s->ecopy_of[v - s->nv_in];
}

/* Numbers the used vertices in order (copies after the originals), drops
 * the unreferenced ones and rewrites the corners. */
static int renumber(const ctx *x, soup *s, const vmap *vm, fixed *out)
{
    uint32_t *newid = malloc(((size_t)vm->next + 1) * sizeof *newid);
    out->orig = malloc(((size_t)vm->next + 1) * sizeof *out->orig);
    if (!newid || !out->orig) {
        free(newid);
        return out_of_memory(x);
    }
    uint32_t n = 0;
    for (uint32_t e = 0; e < vm->next; e++) {
        int used = e >= vm->nv || vm->nfans[e] > 0;
        newid[e] = used ? n : NONE;
        if (used) out->orig[n++] = input_vertex(s, e < vm->nv ? e : vm->copy_of[e - vm->nv]);
    }
    for (uint32_t c = 0; c < s->nc; c++) s->idx[c] = newid[s->idx[c]];
    out->nverts = n;
    uint32_t ndropped = 0;
    if (n < vm->next)
        for (uint32_t v = 0; v < s->nv_in; v++) ndropped += dropped_unused(s, vm, v);
    if (ndropped) note_dropped(x, s, vm, ndropped);
    free(newid);
    return 0;
}

static double *gather3(const double *src, const uint32_t *orig, uint32_t n)
{
    double *dst = malloc(3 * (size_t)n * sizeof *dst + 1);
    if (!dst) return NULL;
    for (uint32_t v = 0; v < n; v++) memcpy(dst + 3 * (size_t)v, src + 3 * (size_t)orig[v], 3 * sizeof *dst);
    return dst;
}

static int gather_vertices(const ctx *x, const st_mesh *m, fixed *out)
{
    out->pos = gather3(m->pos, out->orig, out->nverts);
    if (!out->pos) return out_of_memory(x);
    if (m->normals && !(out->normals = gather3(m->normals, out->orig, out->nverts))) return out_of_memory(x);
    return 0;
}

/* A crease names an input edge; it goes to the output edge whose ends come
 * from the same input vertices (unique: both faces of an edge lie in the
 * same fan of each end; of a split crowded edge, the first record in
 * (key, corner) order is the first face's, one of the two that keep the
 * edge, so the crease stays there and the detached faces' copies go
 * without).  Creases on no edge of the mesh are dropped. */
static int remap_creases(const ctx *x, const soup *s, const st_mesh *m, fixed *out)
{
    if (!m->ncreases) return 0;
    edge_rec *e = sorted_edges(x, s, out->orig);
    out->crease_v = malloc(2 * (size_t)m->ncreases * sizeof *out->crease_v);
    out->crease_s = malloc((size_t)m->ncreases * sizeof *out->crease_s);
    if (!e || !out->crease_v || !out->crease_s) {
        free(e);
        return out_of_memory(x);
    }
    uint32_t dropped = 0, first = NONE;
    for (uint32_t i = 0; i < m->ncreases; i++) {
        uint32_t u = m->crease_v[2 * i], w = m->crease_v[2 * i + 1];
        const edge_rec *r = find_edge(e, s->nc, edge_key(u, w));
        if (!r) {
            dropped++;
            if (first == NONE) first = i;
            continue;
        }
        uint32_t a = s->idx[r->c], b = s->idx[next_corner(s, r->c)];
        if (out->orig[a] != u) { uint32_t t = a; a = b; b = t; }
        out->crease_v[2 * out->ncreases] = a;
        out->crease_v[2 * out->ncreases + 1] = b;
        out->crease_s[out->ncreases++] = m->crease_s[i];
    }
    free(e);
    if (dropped)
        st_notes_add(x->notes, "%s: repaired: dropped %u crease tags that name no edge of the mesh "
                     "(first: vertices %u %u, 0-based as in tags)", x->name, dropped,
                     m->crease_v[2 * first], m->crease_v[2 * first + 1]);
    return 0;
}

/* A corner tag goes to every copy of its vertex; one on a dropped vertex is
 * dropped.  Copies are looked up through a per-input-vertex list (CSR). */
static int remap_corners(const ctx *x, const st_mesh *m, fixed *out)
{
    if (!m->ncorners) return 0;
    uint32_t *start = calloc((size_t)m->nverts + 2, sizeof *start);
    uint32_t *list = malloc(((size_t)out->nverts + 1) * sizeof *list);
    int rc = (!start || !list) ? out_of_memory(x) : 0;
    uint64_t total = 0;
    if (!rc) {
        for (uint32_t v = 0; v < out->nverts; v++) start[out->orig[v] + 2]++;
        for (uint32_t v = 0; v <= m->nverts; v++) start[v + 1] += start[v];
        for (uint32_t v = 0; v < out->nverts; v++) list[start[out->orig[v] + 1]++] = v;
        for (uint32_t i = 0; i < m->ncorners; i++)
            total += start[m->corner_v[i] + 1] - start[m->corner_v[i]];
        if (total > ST_MESH_MAX_VERTS)
            rc = st_fail(x->err, ST_ERR_RANGE, "%s: too many corner tags after splitting vertices", x->name);
    }
    if (!rc && total) {
        out->corner_v = malloc((size_t)total * sizeof *out->corner_v);
        out->corner_s = malloc((size_t)total * sizeof *out->corner_s);
        if (!out->corner_v || !out->corner_s) rc = out_of_memory(x);
    }
    for (uint32_t i = 0; i < m->ncorners && !rc; i++)
        for (uint32_t k = start[m->corner_v[i]]; k < start[m->corner_v[i] + 1]; k++) {
            out->corner_v[out->ncorners] = list[k];
            out->corner_s[out->ncorners++] = m->corner_s[i];
        }
    if (!rc && total != m->ncorners)
        st_notes_add(x->notes, "%s: repaired: %u corner tags became %u (tags follow split vertices; "
                     "those on dropped vertices are dropped)", x->name, m->ncorners, (uint32_t)total);
    free(start);
    free(list);
    return rc;
}

/* ---- drivers ----------------------------------------------------------------- */

static void commit(st_mesh *m, uint32_t *idx, uint32_t *uvidx, fixed *r)
{
    free(m->face_idx);
    if (uvidx) {
        free(m->face_uv);
        m->face_uv = uvidx;
    }
    free(m->pos);
    free(m->normals);
    free(m->crease_v);
    free(m->crease_s);
    free(m->corner_v);
    free(m->corner_s);
    m->face_idx = idx;
    m->nverts = r->nverts;
    m->pos = r->pos;
    m->normals = r->normals;
    m->ncreases = r->ncreases;
    m->crease_v = r->crease_v;
    m->crease_s = r->crease_s;
    m->ncorners = r->ncorners;
    m->corner_v = r->corner_v;
    m->corner_s = r->corner_s;
    free(r->orig);
    memset(r, 0, sizeof *r);
}

/* The repair pipeline on a working copy of the corners (s->idx). */
static int repair_steps(const ctx *x, const st_mesh *m, soup *s, fixed *out)
{
    vmap vm = {0};
    int rc = pair_edges(x, s, !x->strict);
    if (!rc) rc = repair_orientation(x, s);
    if (!rc) rc = split_vertices(x, s, &vm);
    if (!rc) rc = renumber(x, s, &vm, out);
    if (!rc) rc = gather_vertices(x, m, out);
    if (!rc) rc = remap_creases(x, s, m, out);
    if (!rc) rc = remap_corners(x, m, out);
    vmap_free(&vm);
    return rc;
}

int st_mesh_repair_src(const char *name, st_mesh *m, const st_mesh_src *src, unsigned flags,
                       st_notes *notes, st_error *err)
{
    st_notes local = {0};
    ctx x = {name, src, notes ? &local : NULL, err, src ? (uint32_t)src->index_base : 0,
             (flags & ST_MESH_STRICT) != 0};
    int rc = validate(&x, m);
    if (rc) return rc;
    size_t nc = m->face_off[m->nfaces];
    uint32_t *idx = malloc((nc + 1) * sizeof *idx);
    if (!idx) return out_of_memory(&x);
    memcpy(idx, m->face_idx, nc * sizeof *idx);
    uint32_t *uvidx = NULL;
    if (m->face_uv) {
        uvidx = malloc((nc + 1) * sizeof *uvidx);
        if (!uvidx) { free(idx); return out_of_memory(&x); }
        memcpy(uvidx, m->face_uv, nc * sizeof *uvidx);
    }
    soup s = {0};
    fixed out = {0};
    rc = soup_init(&x, &s, m, idx);
    s.uv = uvidx;
    if (!rc) rc = repair_steps(&x, m, &s, &out);
    soup_free(&s);
    if (rc) {
        free(idx);
        free(uvidx);
        fixed_free(&out);
        st_notes_free(&local);
        return rc;
    }
    commit(m, idx, uvidx, &out);
    for (uint32_t i = 0; i < local.count; i++) st_notes_add(notes, "%s", local.lines[i]);
    st_notes_free(&local);
    return 0;
}

/* ---- check ------------------------------------------------------------------- */

static int check_orientation(const ctx *x, const soup *s)
{
    for (uint32_t c = 0; c < s->nc; c++) {
        uint32_t p = s->partner[c];
        if (p != NONE && s->idx[p] == s->idx[c])
            return st_fail(x->err, ST_ERR_TOPOLOGY, "%s: faces %u and %u run along the edge between "
                           "vertices %u and %u in the same direction", x->name, s->face_of[c],
                           s->face_of[p], s->idx[c], s->idx[next_corner(s, c)]);
    }
    return 0;
}

static int check_fans(const ctx *x, const soup *s)
{
    uint32_t *root = fan_roots(x, s);
    uint32_t *fans = calloc((size_t)s->nv + 1, sizeof *fans);
    int rc = (!root || !fans) ? out_of_memory(x) : 0;
    for (uint32_t c = 0; c < s->nc && !rc; c++) fans[s->idx[c]] += root[c] == c;
    for (uint32_t v = 0; v < s->nv && !rc; v++)
        if (fans[v] == 0)
            rc = st_fail(x->err, ST_ERR_TOPOLOGY, "%s: vertex %u is not used by any face", x->name, v);
        else if (fans[v] > 1)
            rc = st_fail(x->err, ST_ERR_TOPOLOGY, "%s: vertex %u is non-manifold (%u fans of faces)",
                         x->name, v, fans[v]);
    free(root);
    free(fans);
    return rc;
}

static int check_creases(const ctx *x, const soup *s, const st_mesh *m)
{
    if (!m->ncreases) return 0;
    edge_rec *e = sorted_edges(x, s, NULL);
    if (!e) return ST_ERR_MEMORY;
    int rc = 0;
    for (uint32_t i = 0; i < m->ncreases && !rc; i++)
        if (!find_edge(e, s->nc, edge_key(m->crease_v[2 * i], m->crease_v[2 * i + 1])))
            rc = st_fail(x->err, ST_ERR_INVALID, "%s: crease %u (vertices %u %u) is not an edge",
                         x->name, i, m->crease_v[2 * i], m->crease_v[2 * i + 1]);
    free(e);
    return rc;
}

int st_mesh_check(const char *name, const st_mesh *m, st_error *err)
{
    ctx x = {name, NULL, NULL, err, 0, 1};
    int rc = validate(&x, m);
    if (rc) return rc;
    soup s = {0};
    rc = soup_init(&x, &s, m, m->face_idx);
    if (!rc) rc = pair_edges(&x, &s, 0);
    if (!rc) rc = check_orientation(&x, &s);
    if (!rc) rc = check_fans(&x, &s);
    if (!rc) rc = check_creases(&x, &s, m);
    soup_free(&s);
    return rc;
}
