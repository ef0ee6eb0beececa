/* A level written as binary PLY or as OBJ straight from the map
 * (level_ply.h).
 *
 * The soup path (st_map_to_mesh, st_fvar_level_mesh, then the PLY writer's
 * split along UV seams) copies the level three times and sorts its corners
 * twice.  This writes through one buffer from the map: without UVs from
 * two walks of the faces (one counting, one writing) and no per-corner
 * array; with UVs from one walk into an array of corners, grouped by
 * vertex with a counting sort.  Its bytes are the soup
 * path's: the same face walk (darts in st_dart_first/next order, each
 * unvisited face along φ1, boundary darts left out, as st_map_to_mesh), the
 * same vertex order, and with UVs the same PLY vertices: the soup numbers a
 * level's texture coordinates by (vertex, value label) and the writer then
 * makes one vertex per (vertex, texture coordinate) pair in that same order,
 * so PLY vertex t is the t-th (vertex, label) pair, with the position of its
 * vertex and the UV of its first corner. */
#include "core/io/mesh.h"
#include "core/io/level_ply.h"
#include "core/io/atomic_file.h"
#include "core/base/hugepage.h"
#include "core/fvar/fvar_internal.h"
#include "core/map/dart_list.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Words of a bitset with one bit per dart id. */
static size_t seen_words(const st_map *m) { return (size_t)m->darts.end / 64 + 1; }

/* ---- lookups of the plain writer's walks -------------------------------------------
 *
 * The walks of a large level are bound by cache misses, three per dart
 * through the level view: ins(x) to choose β0's column, ins(β0 x) for β1's,
 * ins(x) again for vert's, besides the relations themselves and vindex[v].
 * On a quadrisection hierarchy (thesis §3.2.1: β1 and vert of old darts
 * never change, so neither has a column) only β0 has a column to choose,
 * and a dart's insertion level is its block's (map.h: each block is owned
 * by one level), read from a table of one byte per block that stays in
 * cache.  When every vertex block's live ids are consecutive, as refinement
 * leaves them, a vertex's PLY index is its block's first index plus its
 * offset in the block: a table of one word per block instead of vindex[],
 * a word per vertex.  Other maps (sparse, rebuilt or edited ones) take the
 * level view and vindex[]. */
typedef struct ply_view {
    st_level_view lv;             /* the general path */
    const uint32_t *vindex;       /* general path: PLY index per vertex id */
    int fast;
    const uint8_t *block_level;   /* fast path: per dart block, its insertion level */
    const uint32_t *b0base, *b0col, *b1, *vt;
    unsigned b0lvl;
    const uint32_t *vblock;       /* fast path: per vertex block, PLY index of its id 0 */
} ply_view;

static inline uint32_t pv_phi1(const ply_view *v, uint32_t x, int fast)
{
    if (!fast) return st_v_phi1(&v->lv, x);
    uint32_t e = v->block_level[x >> ST_POOL_BLOCK_SHIFT] < v->b0lvl ? v->b0col[x] : v->b0base[x];
    return v->b1[e];
}

static inline uint32_t pv_index(const ply_view *v, uint32_t x, int fast)
{
    if (!fast) return v->vindex[st_v_vert(&v->lv, x)];
    uint32_t w = v->vt[x];
    return v->vblock[w >> ST_POOL_BLOCK_SHIFT] + (w & (ST_POOL_BLOCK - 1));
}

/* Per vertex block of levels 0..l, the PLY index of its id 0, if the live
 * ids of every block are consecutive; NULL otherwise (or out of memory). */
static uint32_t *vertex_blocks(const st_map *m, unsigned l)
{
    uint32_t *vb = st_malloc_huge(((size_t)m->verts.end / ST_POOL_BLOCK + 1) * sizeof *vb);
    if (!vb) return NULL;
    st_fvar_scan it;
    st_fvar_scan_vertices(&it, m, l);
    uint32_t n = 0, prev = ST_NIL;
    for (uint32_t v = st_fvar_scan_next(&it); v != ST_NIL; v = st_fvar_scan_next(&it), n++) {
        uint32_t b = v >> ST_POOL_BLOCK_SHIFT;
        if (prev == ST_NIL || prev >> ST_POOL_BLOCK_SHIFT != b) vb[b] = n - (v & (ST_POOL_BLOCK - 1));
        else if (v != prev + 1) { free(vb); return NULL; }
        prev = v;
    }
    return vb;
}

/* Per dart block, the level that owns it. */
static uint8_t *dart_block_levels(const st_map *m)
{
    const st_pool *p = &m->darts;
    uint8_t *bl = malloc((size_t)p->end / ST_POOL_BLOCK + 1);
    if (!bl) return NULL;
    for (unsigned lv = 0; lv < ST_MAX_LEVELS; lv++)
        for (uint32_t i = 0; i < p->nblocks[lv]; i++) bl[p->blocks[lv][i]] = (uint8_t)lv;
    return bl;
}

/* The fast path's tables when the map allows it (above); pv->fast says. */
static void ply_view_init(ply_view *pv, const st_map *m, unsigned l, const uint32_t *vindex)
{
    memset(pv, 0, sizeof *pv);
    st_level_view_init(m, l, &pv->lv);
    pv->vindex = vindex;
    if (st_map_is_sparse(m) || pv->lv.beta1.lvl || pv->lv.vert.lvl) return;
    uint32_t *vb = vertex_blocks(m, l);
    uint8_t *bl = vb ? dart_block_levels(m) : NULL;
    if (!bl) { free(vb); return; }
    pv->fast = 1;
    pv->block_level = bl;
    pv->vblock = vb;
    pv->b0base = pv->lv.beta0.base;
    pv->b0col = pv->lv.beta0.col;
    pv->b0lvl = pv->lv.beta0.lvl;
    pv->b1 = pv->lv.beta1.base;
    pv->vt = pv->lv.vert.base;
}

static void ply_view_free(ply_view *pv)
{
    free((void *)pv->block_level);
    free((void *)pv->vblock);
}

/* ---- output through one buffer, little-endian ------------------------------------ */

typedef struct ply_out {
    FILE *f;
    size_t n;
    unsigned char b[1 << 16];
} ply_out;

static void out_room(ply_out *o, size_t n)
{
    if (o->n + n <= sizeof o->b) return;
    fwrite(o->b, 1, o->n, o->f);
    o->n = 0;
}

/* n bytes of v, least significant first: one store on a little-endian
 * machine, where those are v's own bytes. */
static void put_le(unsigned char *b, uint64_t v, int n)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    if (n == 8) memcpy(b, &v, 8);
    else { uint32_t w = (uint32_t)v; memcpy(b, &w, 4); }
#else
    for (int k = 0; k < n; k++) b[k] = (unsigned char)(v >> (8 * k));
#endif
}

static void out_u32(ply_out *o, uint32_t v)
{
    out_room(o, 4);
    put_le(o->b + o->n, v, 4);
    o->n += 4;
}

static void out_f64(ply_out *o, double d)
{
    uint64_t v;
    memcpy(&v, &d, sizeof v);
    out_room(o, 8);
    put_le(o->b + o->n, v, 8);
    o->n += 8;
}

static void out_u8(ply_out *o, unsigned v)
{
    out_room(o, 1);
    o->b[o->n++] = (unsigned char)v;
}

/* ---- UV groups: one PLY vertex per (vertex, value label) ------------------------- */

/* The groups are found around each vertex (its β1 ring at level l: the
 * corners of real and hole faces, as the soup has them), not by sorting
 * every corner: the writer then holds a few words per vertex and group
 * instead of four per corner (spot's level 4 with UVs: 34 MiB less at the
 * process's peak).  A vertex's groups are its distinct labels in ascending
 * order, and PLY vertices follow the vertices' order, as in the soup.  A
 * group's UV is the soup's: that of its first corner in the faces' order
 * (the counting walk finds it), since corners of one label may differ in
 * the last bit (each takes the value as its own face's rule sums it). */
typedef struct uv_groups {
    uint32_t *gfirst;     /* per PLY position of a vertex (vindex order): its first group; nverts + 1 */
    uint32_t *first;      /* per group (PLY vertex): the dart of its first corner in the faces' order */
    uint32_t *label;      /* per group: its value label */
    uint32_t n;
} uv_groups;

static void groups_free(uv_groups *g)
{
    free(g->gfirst);
    free(g->first);
    free(g->label);
}

/* The labels of v's corners (d one of them) into r, ascending. */
static void ring_labels(const st_map *m, const st_level_view *lv, uint32_t d, const st_fvar_level *fl, st_dart_list *r)
{
    r->n = 0;
    uint32_t y = d;
    do {
        if (!st_is_boundary(m, y)) st_dart_list_push(r, st_fvar_label_at(fl, y));
        y = st_v_beta1(lv, y);
    } while (y != d);
    for (uint32_t i = 1; i < r->n; i++) { /* (rings are short: insertion) */
        uint32_t x = r->d[i];
        uint32_t j = i;
        for (; j > 0 && r->d[j - 1] > x; j--) r->d[j] = r->d[j - 1];
        r->d[j] = x;
    }
}

/* One scan of the darts finds a corner of each vertex; then each vertex's
 * ring, in PLY order, gives its groups' labels (their first corners:
 * count_faces_walk). */
static int uv_group(const uint32_t *vindex, uint32_t nverts, const st_map *m, unsigned l, const st_fvar_level *fl,
                    uv_groups *g)
{
    st_level_view lv;
    st_level_view_init(m, l, &lv);
    uint32_t *vdart = st_malloc_huge(((size_t)nverts + 1) * sizeof *vdart), cap = nverts + nverts / 4 + 16;
    st_dart_list r = { 0 };
    g->gfirst = st_malloc_huge(((size_t)nverts + 1) * sizeof *g->gfirst);
    g->label = st_malloc_huge((size_t)cap * sizeof *g->label);
    g->n = 0;
    int rc = -1;
    if (!vdart || !g->gfirst || !g->label) goto done;
    memset(vdart, 0xff, ((size_t)nverts + 1) * sizeof *vdart); /* ST_NIL */
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d)) continue;
        uint32_t vi = vindex[st_v_vert(&lv, d)];
        if (vdart[vi] == ST_NIL) vdart[vi] = d;
    }
    for (uint32_t vi = 0; vi < nverts; vi++) {
        g->gfirst[vi] = g->n;
        if (vdart[vi] == ST_NIL) continue; /* (on no face) */
        ring_labels(m, &lv, vdart[vi], fl, &r);
        for (uint32_t i = 0; i < r.n; i++) {
            if (i > 0 && r.d[i] == r.d[i - 1]) continue;
            if (g->n == cap) {
                uint32_t c = cap + cap / 2;
                uint32_t *q = st_realloc_huge(g->label, (size_t)cap * sizeof *q, (size_t)c * sizeof *q);
                if (!q) goto done;
                g->label = q;
                cap = c;
            }
            g->label[g->n++] = r.d[i];
        }
    }
    g->gfirst[nverts] = g->n;
    g->first = st_malloc_huge(((size_t)g->n + 1) * sizeof *g->first);
    if (!g->first) goto done;
    memset(g->first, 0xff, ((size_t)g->n + 1) * sizeof *g->first); /* ST_NIL */
    rc = 0;
done:
    free(vdart);
    st_dart_list_free(&r);
    if (rc) {
        groups_free(g);
        memset(g, 0, sizeof *g);
    }
    return rc;
}

/* The PLY vertex of the corner x of the vertex at PLY position vi. */
static inline uint32_t group_of(const uv_groups *g, uint32_t vi, const st_fvar_level *fl, uint32_t x)
{
    uint32_t t = g->gfirst[vi], end = g->gfirst[vi + 1], lab = st_fvar_label_at(fl, x);
    while (t + 1 < end && g->label[t] != lab) t++;
    return t;
}

/* ---- the writer ------------------------------------------------------------------- */

/* What the header and the checks need of the faces: counts, whether a
 * face has more than 255 corners, the first face under 3 corners. */
typedef struct face_counts {
    uint32_t nfaces, nreal, first_short;
    int wide;
} face_counts;

static void count_face(face_counts *fc, uint32_t k, int hole)
{
    if (k < 3 && fc->first_short == UINT32_MAX) fc->first_short = fc->nfaces;
    fc->nfaces++;
    if (hole) return;
    fc->nreal++;
    fc->wide |= k > 255;
}

/* Without UVs: one walk that counts, and later one that writes (below),
 * instead of an array of every corner. */
/* seen: seen_words(m) words, cleared here; a bit per dart id marks the faces
 * already walked (no marker to reserve and release).  `fast`: a constant,
 * one copy per lookup path (ply_view). */
static inline void count_faces_walk_kind(st_map *m, unsigned l, const ply_view *pv, face_counts *fc, uint64_t *seen,
                                         const st_fvar_level *fl, uv_groups *g, int fast)
{
    memset(seen, 0, seen_words(m) * sizeof *seen);
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
        uint32_t k = 0, x = d;
        do {
            seen[x >> 6] |= 1ull << (x & 63);
            if (g) {
                uint32_t t = group_of(g, pv_index(pv, x, fast), fl, x);
                if (g->first[t] == ST_NIL) g->first[t] = x;
            }
            k++;
            x = pv_phi1(pv, x, fast);
        } while (x != d);
        count_face(fc, k, st_is_hole(m, d));
    }
}

/* With g (and the level's labels fl): each group's first corner too. */
static void count_faces_walk(st_map *m, unsigned l, const ply_view *pv, face_counts *fc, uint64_t *seen,
                             const st_fvar_level *fl, uv_groups *g)
{
    if (pv->fast) count_faces_walk_kind(m, l, pv, fc, seen, fl, g, 1);
    else count_faces_walk_kind(m, l, pv, fc, seen, fl, g, 0);
}

/* The checks of mesh_write.c's check_writable, in its order, with its
 * messages: positions in level order, faces, then texture coordinates. */
static int check_level(const char *path, st_map *m, unsigned l, const face_counts *fc, const st_fvar_level *fl,
                       const uv_groups *g, st_error *err)
{
    st_fvar_scan it;
    st_fvar_scan_vertices(&it, m, l);
    st_level_view lv;
    st_level_view_init(m, l, &lv);
    size_t i = 0;
    for (uint32_t v = st_fvar_scan_next(&it); v != ST_NIL; v = st_fvar_scan_next(&it), i++) {
        const double *p = st_v_pos(&lv, v);
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return st_fail(err, ST_ERR_GEOMETRY, "%s: vertex %zu is not finite", path, i);
    }
    if (fc->first_short != UINT32_MAX)
        return st_fail(err, ST_ERR_INVALID, "%s: face %u has fewer than 3 vertices", path, fc->first_short);
    for (uint32_t t = 0; g && t < g->n; t++) {
        uint32_t x = g->first[t];
        if (x == ST_NIL) /* (every ring corner lies on a walked face: not met on a valid map) */
            return st_fail(err, ST_ERR_INVALID, "%s: texture coordinate %zu has no corner", path, (size_t)t);
        for (int k = 0; x < fl->cap && k < 2; k++)
            if (!isfinite(st_fvar_uv_at(fl, x)[k]))
                return st_fail(err, ST_ERR_GEOMETRY, "%s: texture coordinate %zu is not finite", path, (size_t)t);
    }
    return 0;
}

static void write_header(FILE *f, uint32_t nverts, int uv, const face_counts *fc)
{
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment written by Strata\n"
               "element vertex %u\nproperty double x\nproperty double y\nproperty double z\n", nverts);
    if (uv) fprintf(f, "property double u\nproperty double v\n");
    fprintf(f, "element face %u\nproperty list %s uint vertex_indices\nend_header\n", fc->nreal,
            fc->wide ? "uint" : "uchar");
}

static void write_face_size(ply_out *o, const face_counts *fc, uint32_t k)
{
    if (fc->wide) out_u32(o, k);
    else out_u8(o, k);
}

/* The level's real faces walked again; with g (the UV writer) each
 * corner's PLY vertex is its group (fl: the labels). */
static inline void write_faces_kind(ply_out *o, st_map *m, unsigned l, const ply_view *pv, const face_counts *fc,
                                    uint64_t *seen, const st_fvar_level *fl, const uv_groups *g, int fast)
{
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
        int real = !st_is_hole(m, d);
        uint32_t k = 0, x = d;
        do {
            k++;
            x = pv_phi1(pv, x, fast);
        } while (x != d);
        if (real) write_face_size(o, fc, k);
        do {
            seen[x >> 6] |= 1ull << (x & 63);
            if (real) {
                uint32_t vi = pv_index(pv, x, fast);
                out_u32(o, g ? group_of(g, vi, fl, x) : vi);
            }
            x = pv_phi1(pv, x, fast);
        } while (x != d);
    }
}

static void write_faces(ply_out *o, st_map *m, unsigned l, const ply_view *pv, const face_counts *fc, uint64_t *seen,
                        const st_fvar_level *fl, const uv_groups *g)
{
    memset(seen, 0, seen_words(m) * sizeof *seen);
    if (pv->fast) write_faces_kind(o, m, l, pv, fc, seen, fl, g, 1);
    else write_faces_kind(o, m, l, pv, fc, seen, fl, g, 0);
}

/* Without UVs, in one walk: the face records of the real faces (a uchar
 * size and the indices, as write_faces writes them) into buf, which
 * holds 5 bytes per dart of levels 0..l (the most a face record takes per
 * corner), the counts into fc.  -1 (fc then partial) when a face has more
 * than 255 corners: the records would need a uint size, known only after
 * the walk. */
static inline int faces_to_memory_kind(st_map *m, unsigned l, const ply_view *pv, face_counts *fc, uint64_t *seen,
                                       unsigned char *buf, size_t *len, int fast)
{
    memset(seen, 0, seen_words(m) * sizeof *seen);
    size_t n = 0;
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
        int hole = st_is_hole(m, d);
        unsigned char *idx = buf + n + 1;
        uint32_t k = 0, x = d;
        do {
            seen[x >> 6] |= 1ull << (x & 63);
            if (!hole) put_le(idx + 4 * (size_t)k, pv_index(pv, x, fast), 4);
            k++;
            x = pv_phi1(pv, x, fast);
        } while (x != d);
        count_face(fc, k, hole);
        if (hole) continue;
        if (k > 255) return -1;
        buf[n] = (unsigned char)k;
        n += 1 + 4 * (size_t)k;
    }
    *len = n;
    return 0;
}

static int faces_to_memory(st_map *m, unsigned l, const ply_view *pv, face_counts *fc, uint64_t *seen,
                           unsigned char *buf, size_t *len)
{
    if (pv->fast) return faces_to_memory_kind(m, l, pv, fc, seen, buf, len, 1);
    return faces_to_memory_kind(m, l, pv, fc, seen, buf, len, 0);
}

/* Darts of levels 0..l: the bound faces_to_memory's buffer is sized by. */
static uint64_t darts_up_to(const st_map *m, unsigned l)
{
    uint64_t n = 0;
    for (unsigned k = 0; k <= l && k < ST_MAX_LEVELS; k++) n += m->darts.live[k];
    return n;
}

/* Without UVs: the level's vertices, then its real faces, from recs (len
 * bytes, faces_to_memory) or else walked again. */
static void write_plain(FILE *f, st_map *m, unsigned l, const ply_view *pv, uint32_t nverts, const face_counts *fc,
                        uint64_t *seen, const unsigned char *recs, size_t len)
{
    write_header(f, nverts, 0, fc);
    ply_out buf, *o = &buf;
    o->f = f;
    o->n = 0;
    st_fvar_scan vs;
    st_fvar_scan_vertices(&vs, m, l);
    for (uint32_t v = st_fvar_scan_next(&vs); v != ST_NIL; v = st_fvar_scan_next(&vs)) {
        const double *p = st_v_pos(&pv->lv, v);
        for (int k = 0; k < 3; k++) out_f64(o, p[k]);
    }
    if (recs) {
        fwrite(o->b, 1, o->n, f);
        fwrite(recs, 1, len, f);
        return;
    }
    write_faces(o, m, l, pv, fc, seen, NULL, NULL);
    fwrite(o->b, 1, o->n, f);
}

/* With UVs: one vertex per group, then the faces (write_faces). */
static void write_uv(FILE *f, st_map *m, unsigned l, const ply_view *pv, const face_counts *fc, uint64_t *seen,
                     const st_fvar_level *fl, const uv_groups *g)
{
    write_header(f, g->n, 1, fc);
    ply_out buf, *o = &buf;
    o->f = f;
    o->n = 0;
    st_level_view lv;
    st_level_view_init(m, l, &lv);
    for (uint32_t i = 0; i < g->n; i++) {
        uint32_t x = g->first[i];
        const double *p = st_v_pos(&lv, st_v_vert(&lv, x));
        for (int k = 0; k < 3; k++) out_f64(o, p[k]);
        const double *t = x < fl->cap ? st_fvar_uv_at(fl, x) : NULL;
        out_f64(o, t ? t[0] : 0);
        out_f64(o, t ? t[1] : 0);
    }
    write_faces(o, m, l, pv, fc, seen, fl, g);
    fwrite(o->b, 1, o->n, f);
}

/* ---- OBJ: the text of st_mesh_save_obj (core/io/mesh_write.c) ------------------- */

static void out_text(ply_out *o, const char *t, int n)
{
    if (n <= 0) return;
    out_room(o, (size_t)n);
    memcpy(o->b + o->n, t, (size_t)n);
    o->n += (size_t)n;
}

/* The real faces as `f` lines: a corner's vertex, and its texture
 * coordinate (its group) with g. */
static inline void obj_faces_kind(ply_out *o, st_map *m, unsigned l, const ply_view *pv, uint64_t *seen,
                                  const st_fvar_level *fl, const uv_groups *g, int fast)
{
    memset(seen, 0, seen_words(m) * sizeof *seen);
    char t[32];
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
        int real = !st_is_hole(m, d);
        if (real) out_text(o, "f", 1);
        uint32_t x = d;
        do {
            seen[x >> 6] |= 1ull << (x & 63);
            if (real) {
                uint32_t vi = pv_index(pv, x, fast);
                if (g) out_text(o, t, snprintf(t, sizeof t, " %u/%u", vi + 1, group_of(g, vi, fl, x) + 1));
                else out_text(o, t, snprintf(t, sizeof t, " %u", vi + 1));
            }
            x = pv_phi1(pv, x, fast);
        } while (x != d);
        if (real) out_text(o, "\n", 1);
    }
}

/* The header, the vertices, with g one `vt` per group (the UV of its first
 * corner), then the faces. */
static void write_obj(FILE *f, st_map *m, unsigned l, const ply_view *pv, uint32_t nverts, const face_counts *fc,
                      uint64_t *seen, const st_fvar_level *fl, const uv_groups *g)
{
    fprintf(f, "# Strata mesh: %u vertices, %u faces\n", nverts, fc->nreal);
    ply_out buf, *o = &buf;
    o->f = f;
    o->n = 0;
    char t[96];
    st_fvar_scan vs;
    st_fvar_scan_vertices(&vs, m, l);
    for (uint32_t v = st_fvar_scan_next(&vs); v != ST_NIL; v = st_fvar_scan_next(&vs)) {
        const double *p = st_v_pos(&pv->lv, v);
        out_text(o, t, snprintf(t, sizeof t, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]));
    }
    for (uint32_t i = 0; g && i < g->n; i++) {
        uint32_t x = g->first[i];
        const double *p = x < fl->cap ? st_fvar_uv_at(fl, x) : NULL;
        out_text(o, t, snprintf(t, sizeof t, "vt %.17g %.17g\n", p ? p[0] : 0, p ? p[1] : 0));
    }
    if (pv->fast) obj_faces_kind(o, m, l, pv, seen, fl, g, 1);
    else obj_faces_kind(o, m, l, pv, seen, fl, g, 0);
    fwrite(o->b, 1, o->n, f);
}

/* Level l as a soup (st_hier_level_mesh), written by save. */
static int save_soup(st_hier *h, unsigned l, const char *path,
                     int (*save)(const char *path, const st_mesh *m, st_error *err), st_error *err)
{
    st_mesh out;
    st_mesh_init(&out);
    int rc = st_hier_level_mesh(h, l, &out, err);
    if (!rc) rc = save(path, &out, err);
    st_mesh_free(&out);
    return rc;
}

int st_hier_level_save_ply_soup(st_hier *h, unsigned l, const char *path, st_error *err)
{
    return save_soup(h, l, path, st_mesh_save_ply, err);
}

int st_hier_level_save_obj_soup(st_hier *h, unsigned l, const char *path, st_error *err)
{
    return save_soup(h, l, path, st_mesh_save_obj, err);
}

/* PLY, or OBJ when obj. */
static int save_level(st_hier *h, unsigned l, const char *path, int obj, st_error *err)
{
    st_map *m = &h->map;
    if (m->face_embedded) return obj ? st_hier_level_save_obj_soup(h, l, path, err) : st_hier_level_save_ply_soup(h, l, path, err);
    int uv = st_hier_has_uv(h, l);
    const st_fvar_level *fl = uv ? &h->fvar->lv[l] : NULL;
    uv_groups groups = { 0 };
    uv_groups *g = uv ? &groups : NULL;
    face_counts fc = { 0, 0, UINT32_MAX, 0 };
    uint64_t *seen = NULL; /* the faces-walked bits of the walks */
    unsigned char *recs = NULL; /* without UVs: the face records, when one walk made them */
    size_t len = 0;
    ply_view pv;
    ply_view_init(&pv, m, l, NULL);
    uint32_t *vindex = NULL, nverts = 0;
    int rc = 0;
    if (g || !pv.fast) { /* vindex[]: the UV groups' and the general path's */
        vindex = st_malloc_huge((size_t)(m->verts.end ? m->verts.end : 1) * sizeof *vindex);
        if (!vindex) rc = -1;
        pv.vindex = vindex;
    }
    if (!rc) {
        st_fvar_scan it;  /* not face-embedded (above): st_vertex_first/next's order */
        st_fvar_scan_vertices(&it, m, l);
        for (uint32_t v = st_fvar_scan_next(&it); v != ST_NIL; v = st_fvar_scan_next(&it), nverts++)
            if (vindex) vindex[v] = nverts;
    }
    if (!rc) {
        seen = malloc(seen_words(m) * sizeof *seen);
        if (!seen) rc = -1;
    }
    if (!rc && g) {
        rc = uv_group(vindex, nverts, m, l, fl, g);
        if (!rc) count_faces_walk(m, l, &pv, &fc, seen, fl, g);
    } else if (!rc && obj) {
        count_faces_walk(m, l, &pv, &fc, seen, NULL, NULL);
    } else if (!rc) {
        /* One walk into memory; else (no memory for the records, or a face
         * over 255 corners) one walk that counts and one that writes. */
        uint64_t bound = 5 * darts_up_to(m, l);
        if (bound <= SIZE_MAX) recs = st_malloc_huge((size_t)bound);
        if (recs && faces_to_memory(m, l, &pv, &fc, seen, recs, &len)) {
            free(recs);
            recs = NULL;
            fc = (face_counts){ 0, 0, UINT32_MAX, 0 };
        }
        if (!recs) count_faces_walk(m, l, &pv, &fc, seen, NULL, NULL);
    }
    if (rc) rc = st_fail(err, ST_ERR_MEMORY, "%s: out of memory writing level %u", path, l);
    if (!rc) rc = check_level(path, m, l, &fc, fl, g, err);
    st_afile af;
    if (!rc) rc = st_afile_open(&af, path, err);
    if (!rc) {
        if (obj) write_obj(af.f, m, l, &pv, nverts, &fc, seen, fl, g);
        else if (g) write_uv(af.f, m, l, &pv, &fc, seen, fl, g);
        else write_plain(af.f, m, l, &pv, nverts, &fc, seen, recs, len);
        rc = st_afile_commit(&af, err);
    }
    groups_free(&groups);
    free(vindex);
    free(seen);
    free(recs);
    ply_view_free(&pv);
    return rc;
}

int st_hier_level_save_ply(st_hier *h, unsigned l, const char *path, st_error *err)
{
    return save_level(h, l, path, 0, err);
}

int st_hier_level_save_obj(st_hier *h, unsigned l, const char *path, st_error *err)
{
    return save_level(h, l, path, 1, err);
}
