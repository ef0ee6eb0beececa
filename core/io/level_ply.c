/* A level written as binary PLY straight from the map (level_ply.h).
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

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Level l's faces: the corners' darts face after face (hole faces
 * included, as in the soup), face f spanning off[f]..off[f+1]. */
typedef struct level_faces {
    uint32_t *dart, *off;
    uint32_t ncorners, nfaces;
} level_faces;

static void faces_free(level_faces *lf)
{
    free(lf->dart);
    free(lf->off);
}

/* Words of a bitset with one bit per dart id. */
static size_t seen_words(const st_map *m) { return (size_t)m->darts.end / 64 + 1; }

/* The darts are scanned block by block (st_fvar_scan: st_dart_first/next's
 * order without a call per dart) and faces marked seen in a bit per dart
 * id, which needs no pass to release. */
static int faces_walk(st_map *m, unsigned l, level_faces *lf)
{
    st_fvar_scan it;
    uint32_t nc = 0;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) nc += !st_is_boundary(m, d);
    lf->dart = st_malloc_huge(((size_t)nc + 1) * sizeof *lf->dart);
    lf->off = st_malloc_huge(((size_t)nc + 2) * sizeof *lf->off);
    uint64_t *seen = calloc(seen_words(m), sizeof *seen);
    if (!lf->dart || !lf->off || !seen) {
        free(seen);
        return -1;
    }
    st_level_view lv;
    st_level_view_init(m, l, &lv);
    uint32_t k = 0, nf = 0;
    lf->off[0] = 0;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
        uint32_t x = d;
        do {
            seen[x >> 6] |= 1ull << (x & 63);
            lf->dart[k++] = x;
            x = st_v_phi1(&lv, x);
        } while (x != d);
        lf->off[++nf] = k;
    }
    free(seen);
    lf->ncorners = k;
    lf->nfaces = nf;
    return 0;
}

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

typedef struct uv_groups {
    uint32_t *corner_t;   /* per corner: its PLY vertex */
    uint32_t *first;      /* per PLY vertex: the dart of its first corner */
    uint32_t n;
} uv_groups;

/* Sorts one vertex's corners (ascending ids) by label, ties kept in id
 * order: insertion for the usual few, qsort of (label, id) keys past 32. */
static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static void sort_by_label(uint32_t *c, uint32_t k, const uint32_t *dart, const uint32_t *val, uint64_t *scratch)
{
    if (k > 32) {
        for (uint32_t i = 0; i < k; i++) scratch[i] = (uint64_t)val[dart[c[i]]] << 32 | c[i];
        qsort(scratch, k, sizeof *scratch, cmp_u64);
        for (uint32_t i = 0; i < k; i++) c[i] = (uint32_t)scratch[i];
        return;
    }
    for (uint32_t i = 1; i < k; i++) {
        uint32_t x = c[i], lx = val[dart[x]], j = i;
        for (; j > 0 && val[dart[c[j - 1]]] > lx; j--) c[j] = c[j - 1];
        c[j] = x;
    }
}

static int uv_group(const level_faces *lf, const uint32_t *vindex, uint32_t nverts, const st_map *m, unsigned l,
                    const uint32_t *val, uv_groups *g)
{
    uint32_t nc = lf->ncorners;
    uint32_t *start = st_calloc_huge((size_t)nverts + 1, sizeof *start);
    uint32_t *bucket = st_malloc_huge(((size_t)nc + 1) * sizeof *bucket);
    g->corner_t = st_malloc_huge(((size_t)nc + 1) * sizeof *g->corner_t);
    g->first = st_malloc_huge(((size_t)nc + 1) * sizeof *g->first);
    uint64_t *scratch = NULL;
    int rc = -1;
    if (!start || !bucket || !g->corner_t || !g->first) goto done;
    /* Counting sort of the corners by vertex (corner_t holds the vertex for now). */
    uint32_t kmax = 0;
    st_level_view lv;
    st_level_view_init(m, l, &lv);
    for (uint32_t c = 0; c < nc; c++) start[(g->corner_t[c] = vindex[st_v_vert(&lv, lf->dart[c])]) + 1]++;
    /* start[v + 1]: the beginning of v's bucket, then its end once filled
     * (start[v] being its beginning). */
    for (uint32_t v = 0, s = 0; v < nverts; v++) {
        uint32_t k = start[v + 1];
        start[v + 1] = s;
        s += k;
        if (k > kmax) kmax = k;
    }
    for (uint32_t c = 0; c < nc; c++) bucket[start[g->corner_t[c] + 1]++] = c;
    if (kmax > 32 && !(scratch = malloc((size_t)kmax * sizeof *scratch))) goto done;
    g->n = 0;
    for (uint32_t v = 0; v < nverts; v++) {
        uint32_t *c = bucket + start[v], k = start[v + 1] - start[v];
        sort_by_label(c, k, lf->dart, val, scratch);
        for (uint32_t i = 0; i < k; i++) {
            if (i == 0 || val[lf->dart[c[i]]] != val[lf->dart[c[i - 1]]]) g->first[g->n++] = lf->dart[c[i]];
            g->corner_t[c[i]] = g->n - 1;
        }
    }
    rc = 0;
done:
    free(start);
    free(bucket);
    free(scratch);
    return rc;
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
                                         int fast)
{
    memset(seen, 0, seen_words(m) * sizeof *seen);
    st_fvar_scan it;
    st_fvar_scan_init(&it, m, 0, l);
    for (uint32_t d = st_fvar_scan_next(&it); d != ST_NIL; d = st_fvar_scan_next(&it)) {
        if (st_is_boundary(m, d) || ((seen[d >> 6] >> (d & 63)) & 1)) continue;
        uint32_t k = 0, x = d;
        do {
            seen[x >> 6] |= 1ull << (x & 63);
            k++;
            x = pv_phi1(pv, x, fast);
        } while (x != d);
        count_face(fc, k, st_is_hole(m, d));
    }
}

static void count_faces_walk(st_map *m, unsigned l, const ply_view *pv, face_counts *fc, uint64_t *seen)
{
    if (pv->fast) count_faces_walk_kind(m, l, pv, fc, seen, 1);
    else count_faces_walk_kind(m, l, pv, fc, seen, 0);
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
        for (int k = 0; x < fl->cap && k < 2; k++)
            if (!isfinite(fl->uv[2 * (size_t)x + (size_t)k]))
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

/* Without UVs: the level's real faces walked again. */
static inline void write_plain_faces(ply_out *o, st_map *m, unsigned l, const ply_view *pv, const face_counts *fc,
                                     uint64_t *seen, int fast)
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
            if (real) out_u32(o, pv_index(pv, x, fast));
            x = pv_phi1(pv, x, fast);
        } while (x != d);
    }
}

/* Without UVs, in one walk: the face records of the real faces (a uchar
 * size and the indices, as write_plain_faces writes them) into buf, which
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
    memset(seen, 0, seen_words(m) * sizeof *seen);
    if (pv->fast) write_plain_faces(o, m, l, pv, fc, seen, 1);
    else write_plain_faces(o, m, l, pv, fc, seen, 0);
    fwrite(o->b, 1, o->n, f);
}

/* With UVs: one vertex per group, faces from the corner array. */
static void write_uv(FILE *f, const st_map *m, unsigned l, const level_faces *lf, const face_counts *fc,
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
        out_f64(o, x < fl->cap ? fl->uv[2 * (size_t)x] : 0);
        out_f64(o, x < fl->cap ? fl->uv[2 * (size_t)x + 1] : 0);
    }
    for (uint32_t fi = 0; fi < lf->nfaces; fi++) {
        uint32_t a = lf->off[fi], b = lf->off[fi + 1];
        if (st_is_hole(m, lf->dart[a])) continue;
        write_face_size(o, fc, b - a);
        for (uint32_t c = a; c < b; c++) out_u32(o, g->corner_t[c]);
    }
    fwrite(o->b, 1, o->n, f);
}

int st_hier_level_save_ply_soup(st_hier *h, unsigned l, const char *path, st_error *err)
{
    st_mesh out;
    st_mesh_init(&out);
    int rc = st_hier_level_mesh(h, l, &out, err);
    if (!rc) rc = st_mesh_save_ply(path, &out, err);
    st_mesh_free(&out);
    return rc;
}

int st_hier_level_save_ply(st_hier *h, unsigned l, const char *path, st_error *err)
{
    st_map *m = &h->map;
    if (m->face_embedded) return st_hier_level_save_ply_soup(h, l, path, err);
    const double *uv = st_hier_uv(h, l);
    const st_fvar_level *fl = uv ? &h->fvar->lv[l] : NULL;
    level_faces lf = { 0 };
    uv_groups groups = { 0 };
    uv_groups *g = uv ? &groups : NULL;
    face_counts fc = { 0, 0, UINT32_MAX, 0 };
    uint64_t *seen = NULL; /* without UVs: the faces-walked bits of the walks */
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
    if (!rc && g) {
        rc = faces_walk(m, l, &lf);
        if (!rc) rc = uv_group(&lf, vindex, nverts, m, l, fl->val, g);
        for (uint32_t fi = 0; !rc && fi < lf.nfaces; fi++)
            count_face(&fc, lf.off[fi + 1] - lf.off[fi], st_is_hole(m, lf.dart[lf.off[fi]]));
    } else if (!rc) {
        seen = malloc(seen_words(m) * sizeof *seen);
        if (!seen) rc = -1;
        /* One walk into memory; else (no memory for the records, or a face
         * over 255 corners) one walk that counts and one that writes. */
        uint64_t bound = 5 * darts_up_to(m, l);
        if (!rc && bound <= SIZE_MAX) recs = st_malloc_huge((size_t)bound);
        if (recs && faces_to_memory(m, l, &pv, &fc, seen, recs, &len)) {
            free(recs);
            recs = NULL;
            fc = (face_counts){ 0, 0, UINT32_MAX, 0 };
        }
        if (!rc && !recs) count_faces_walk(m, l, &pv, &fc, seen);
    }
    if (rc) rc = st_fail(err, ST_ERR_MEMORY, "%s: out of memory writing level %u", path, l);
    if (!rc) rc = check_level(path, m, l, &fc, fl, g, err);
    st_afile af;
    if (!rc) rc = st_afile_open(&af, path, err);
    if (!rc) {
        if (g) write_uv(af.f, m, l, &lf, &fc, fl, g);
        else write_plain(af.f, m, l, &pv, nverts, &fc, seen, recs, len);
        rc = st_afile_commit(&af, err);
    }
    faces_free(&lf);
    free(groups.corner_t);
    free(groups.first);
    free(vindex);
    free(seen);
    free(recs);
    ply_view_free(&pv);
    return rc;
}
