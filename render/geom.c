/* CPU-side geometry of a displayed level; see geom.h. */
#include "core/base/hugepage.h"
#include "core/base/parallel.h"
#include "core/map/geometry.h"
#include "render/geom_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void st_range_list_free(st_range_list *l)
{
    free(l->r);
    memset(l, 0, sizeof *l);
}

void st_rgeom_init(st_rgeom *g)
{
    memset(g, 0, sizeof *g);
    g->tix = st_tri_index_shared();
}

void st_rgeom_free(st_rgeom *g)
{
    free(g->vdata); free(g->vid); free(g->vdart); free(g->slot);
    free(g->face_dart); free(g->face_off); free(g->corner); free(g->fnormal); free(g->face_case); free(g->face_line);
    free(g->dart_face); free(g->tris); free(g->tri_face); free(g->lines);
    free(g->dstamp_v); free(g->dstamp_f); free(g->vstamp); free(g->fstamp); free(g->reread);
    const st_tri_index *tix = g->tix;
    memset(g, 0, sizeof *g);
    g->tix = tix;
}

/* Newell vector of face f from the vertex table's float positions. */
void st_rg_face_normal(st_rgeom *g, uint32_t f)
{
    double n[3] = { 0, 0, 0 };
    uint32_t a = g->face_off[f], b = g->face_off[f + 1];
    for (uint32_t k = a; k < b; k++) {
        const float *p = g->vdata + ST_RGEOM_VSTRIDE * (size_t)g->corner[k];
        const float *q = g->vdata + ST_RGEOM_VSTRIDE * (size_t)g->corner[k + 1 < b ? k + 1 : a];
        st_newell_add_f(n, p, q);
    }
    float *o = g->fnormal + 4 * (size_t)f;
    o[0] = (float)(0.5 * n[0]);
    o[1] = (float)(0.5 * n[1]);
    o[2] = (float)(0.5 * n[2]);
    o[3] = 0;
}

/* Normal of vertex s: sum of the face normals around it, in walk order. */
/* One copy per lookup path (core/map/map.h, "Two lookup paths"): the copy
 * for subdivision maps has no test for the sparse form in its ring walk. */
static inline void vertex_normal_kind(st_rgeom *g, const st_level_view *V, uint32_t s, int sparse)
{
    double n[3] = { 0, 0, 0 };
    uint32_t d = g->vdart[s], x = d;
    do {
        uint32_t f = g->dart_face[x];
        if (f < g->nfaces) {
            const float *fn = g->fnormal + 4 * (size_t)f;
            n[0] += fn[0]; n[1] += fn[1]; n[2] += fn[2];
        }
        x = st_v_vertex_step_kind(V, g->face_embedded, x, sparse);
    } while (x != d);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    float *o = g->vdata + ST_RGEOM_VSTRIDE * (size_t)s + 3;
    if (len > 0 && isfinite(len)) { o[0] = (float)(n[0] / len); o[1] = (float)(n[1] / len); o[2] = (float)(n[2] / len); }
    else { o[0] = 0; o[1] = 0; o[2] = 1; }
}

void st_rg_vertex_normal(st_rgeom *g, const st_level_view *V, uint32_t s)
{
    if (st_level_view_is_sparse(V)) vertex_normal_kind(g, V, s, 1);
    else vertex_normal_kind(g, V, s, 0);
}

void st_rg_read_position(st_rgeom *g, const st_level_view *V, uint32_t s)
{
    const double *p = st_v_pos(V, g->vid[s]);
    float *o = g->vdata + ST_RGEOM_VSTRIDE * (size_t)s;
    o[0] = (float)p[0]; o[1] = (float)p[1]; o[2] = (float)p[2];
}

/* ---- build ------------------------------------------------------------------ */

void st_rg_scratch_free(st_rg_scratch *fs)
{
    free(fs->darts); free(fs->b0); free(fs->elev); free(fs->vlev); free(fs->loc); free(fs->pos);
}

int st_rg_face_case(st_rgeom *g, const st_level_view *V, st_rg_scratch *fs, unsigned n, const uint32_t *vids,
                    const uint32_t *b0)
{
    int oom = 0;
    GROW(fs->elev, fs->celev, n, oom);
    GROW(fs->vlev, fs->cvlev, n, oom);
    GROW(fs->loc, fs->cloc, 3 * (size_t)n, oom);
    if (oom) return -2;
    if (n == 3) {
        /* A triangle is always "ccc" (st_tri_face), whatever its levels:
         * the levels are not read (the common face of Loop, Butterfly and
         * √3). */
        fs->loc[0] = 0; fs->loc[1] = 1; fs->loc[2] = 2;
        return 0;
    }
    for (unsigned k = 0; k < n; k++) {
        uint32_t y = fs->darts[k], t = b0 ? b0[k] : st_v_beta0(V, y);
        uint8_t a = V->ins[y], b = V->ins[t];
        fs->elev[k] = a > b ? a : b;               /* st_edge_level(m, y, l) */
        fs->vlev[k] = V->vins[vids[k]];            /* st_vertex_level(m, v) */
    }
    /* The case tables read the walk only (the dual encoding has no
     * meaningful vertex levels: only edge levels there). */
    int c = st_tri_face(g->tix, n, fs->elev, g->face_embedded ? NULL : fs->vlev, NULL, fs->loc);
    if (c == ST_TRI_FALLBACK) {
        if (GROW(fs->pos, fs->cpos, 3 * (size_t)n, oom), oom) return -2;
        for (unsigned k = 0; k < n; k++) {
            const double *p = st_v_pos(V, vids[k]);
            fs->pos[3 * k] = (float)p[0]; fs->pos[3 * k + 1] = (float)p[1]; fs->pos[3 * k + 2] = (float)p[2];
        }
        st_tri_fallback(n, fs->pos, fs->loc);
    }
    return c;
}

/* Large arrays of the build go through st_malloc_huge (core/base/
 * hugepage.h): at 25 M faces the build writes about 3 GB of fresh memory.
 * (Koala, Loop level 3, one thread: 5.6-6.3 s of CPU per build without huge
 * pages, 3.0-5.0 s with, on the same loaded machine.) */
static void *big_alloc(size_t bytes) { return st_malloc_huge(bytes ? bytes : 1); }

/* Worker threads for the passes over whole arrays (core/base/parallel.h):
 * each item is computed by the same code whatever the thread, so the
 * buffers are the same bits with any number of threads.  Small meshes stay
 * on the calling thread. */
#define PAR_MIN_ITEMS (1u << 16)
#define PAR_CHUNK 4096u

static unsigned build_threads(size_t items)
{
    unsigned t = st_parallel_threads();
    if (t > ST_PARALLEL_MAX) t = ST_PARALLEL_MAX;
    return items < PAR_MIN_ITEMS || t < 1 ? 1 : t;
}

/* st_team_next over n items counted in size_t (3 per triangle may pass
 * 2^32 on the largest maps): hands out chunks of PAR_CHUNK items. */
static int next_chunk(st_team *team, unsigned k, size_t n, size_t *begin, size_t *end)
{
    uint32_t c0, c1;
    if (!st_team_next(team, k, (uint32_t)((n + PAR_CHUNK - 1) / PAR_CHUNK), 1, &c0, &c1)) return 0;
    *begin = (size_t)c0 * PAR_CHUNK;
    *end = n - *begin < PAR_CHUNK ? n : *begin + PAR_CHUNK;
    return 1;
}

/* Pass 2 of the build: vertex ids -> vertex-table indices in the corners and
 * line ends, then corner numbers -> vertex-table indices in the triangles. */
typedef struct remap_job { st_rgeom *g; size_t ncorner; } remap_job;

static void remap_part(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    remap_job *j = ctx;
    st_rgeom *g = j->g;
    const uint32_t *slot = g->slot;
    size_t b, e;
    while (next_chunk(team, 0, j->ncorner, &b, &e))
        for (size_t k = b; k < e; k++) g->corner[k] = slot[g->corner[k]];
    while (next_chunk(team, 1, 2 * (size_t)g->nlines, &b, &e))
        for (size_t k = b; k < e; k++) g->lines[k] = slot[g->lines[k]];
    st_team_sync(team);
    while (next_chunk(team, 2, 3 * (size_t)g->ntris, &b, &e))
        for (size_t k = b; k < e; k++) g->tris[k] = g->corner[g->tris[k]];
}

/* The walk of the face of d: its darts and their β0 in fs (β0 is read by
 * the walk itself in the primal encoding, and by the polygon edges and the
 * case lookup after it); whether a dart of it is void.  Returns the number
 * of darts, 0 when out of memory. */
static inline unsigned walk_face_kind(const st_map *m, const st_level_view *V, int fe, st_rg_scratch *fs, uint32_t d,
                                      int *real, int sparse)
{
    unsigned n = 0;
    uint32_t x = d;
    int oom = 0, r = 1;
    do {
        if (n == fs->cdarts || n == fs->cb0) {
            GROW(fs->darts, fs->cdarts, (size_t)n + 1, oom);
            GROW(fs->b0, fs->cb0, (size_t)n + 1, oom);
            if (oom) return 0;
        }
        uint32_t b = st_v_beta0_kind(V, x, sparse);
        fs->darts[n] = x;
        fs->b0[n] = b;
        n++;
        r &= !st_is_void(m, x); /* a boundary or a hole face: nothing to draw */
        x = st_v_beta1_kind(V, fe ? x : b, sparse);
    } while (x != d);
    *real = r;
    return n;
}

/* One copy per lookup path (core/map/map.h, "Two lookup paths"): the
 * subdivision maps' walk has no test for the sparse form. */
static unsigned walk_face_dense(const st_map *m, const st_level_view *V, int fe, st_rg_scratch *fs, uint32_t d, int *real)
{
    return walk_face_kind(m, V, fe, fs, d, real, 0);
}
static unsigned walk_face_any(const st_map *m, const st_level_view *V, int fe, st_rg_scratch *fs, uint32_t d, int *real)
{
    return walk_face_kind(m, V, fe, fs, d, real, 1);
}

int st_rgeom_build(st_rgeom *g, const st_map *m, unsigned l, st_error *err)
{
    st_rgeom_free(g);
    if (l > m->top) return st_fail(err, ST_ERR_RANGE, "render: level %u does not exist (finest is %u)", l, m->top);
    g->level = l;
    g->face_embedded = m->face_embedded != 0;
    g->ndarts_end = m->darts.end;
    g->nvids = m->verts.end;
    const int fe = g->face_embedded;
    st_level_view V;
    st_level_view_init(m, l, &V);
    const int sparse = st_level_view_is_sparse(&V);

    /* Every dart of level l is the corner of exactly one face: the number
     * of darts bounds corners, triangles and polygon edges, and a third of
     * it the faces (of 3 corners or more).  The arrays are allocated at
     * these bounds once (pages never written cost nothing), so the walk
     * below never reallocates. */
    size_t ndl = 0;
    for (unsigned i = 0; i <= l && i < ST_MAX_LEVELS; i++) ndl += m->darts.live[i];
    if (!ndl) ndl = 1;
    size_t nfmax = ndl / 3 + 1;
    size_t nd = g->ndarts_end ? g->ndarts_end : 1, nvid = g->nvids ? g->nvids : 1;
    g->dart_face = big_alloc(nd * sizeof *g->dart_face);
    g->slot = big_alloc(nvid * sizeof *g->slot);
    g->corner = big_alloc(ndl * sizeof *g->corner);
    g->lines = big_alloc(2 * ndl * sizeof *g->lines);
    g->tris = big_alloc(3 * ndl * sizeof *g->tris);
    g->tri_face = big_alloc((ndl + 1) * sizeof *g->tri_face);
    g->face_dart = big_alloc(nfmax * sizeof *g->face_dart);
    g->face_case = big_alloc(nfmax * sizeof *g->face_case);
    g->face_line = big_alloc((nfmax + 1) * sizeof *g->face_line);
    g->face_off = big_alloc((nfmax + 1) * sizeof *g->face_off);
    st_rg_scratch fs = { 0 };
    int oom = !g->dart_face || !g->slot || !g->corner || !g->lines || !g->tris || !g->tri_face || !g->face_dart ||
              !g->face_case || !g->face_line || !g->face_off;
    if (!oom) {
        memset(g->dart_face, 0xff, nd * sizeof *g->dart_face); /* ST_NIL */
        memset(g->slot, 0xff, nvid * sizeof *g->slot);
    }
    /* Pass 1: walk each face once, writing every per-face array in face
     * order.  Corners and line ends hold vertex ids, triangles hold corner
     * numbers, slot[v] a dart of v; all become vertex-table indices once
     * the table is known (pass 2). */
    size_t ncorner = 0;
    uint32_t nf = 0, nl = 0, nt = 0;
    st_dart_iter it;
    for (uint32_t d = oom ? ST_NIL : st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (g->dart_face[d] != ST_NIL) continue;
        int real;
        unsigned n = sparse ? walk_face_any(m, &V, fe, &fs, d, &real) : walk_face_dense(m, &V, fe, &fs, d, &real);
        if (!n) { oom = 1; break; }
        if (!real || n < 3) {
            for (unsigned k = 0; k < n; k++) g->dart_face[fs.darts[k]] = UNDRAWN;
            continue;
        }
        uint32_t f = nf++;
        uint32_t *cn = g->corner + ncorner;
        g->face_dart[f] = d;
        g->face_off[f] = (uint32_t)ncorner;
        g->face_line[f] = nl;
        for (unsigned k = 0; k < n; k++) {
            uint32_t y = fs.darts[k], v = st_view_get_kind(&V.vert, V.ins, y, sparse);
            g->dart_face[y] = f;
            cn[k] = v;
            if (g->slot[v] == ST_NIL) g->slot[v] = y;
        }
        /* Polygon edges: the side from corner k to k+1 once, from the end
         * with the smaller id (ids and table indices are in the same order),
         * or from this face when the face across is a hole. */
        for (unsigned k = 0; k < n; k++) {
            uint32_t a = cn[k], b = cn[k + 1 < n ? k + 1 : 0];
            if (a < b || st_is_void(m, fs.b0[k])) {
                g->lines[2 * (size_t)nl] = a;
                g->lines[2 * (size_t)nl + 1] = b;
                nl++;
            }
        }
        int c = st_rg_face_case(g, &V, &fs, n, cn, fs.b0);
        if (c == -2) { oom = 1; break; }
        g->face_case[f] = (int16_t)c;
        g->ncase[c >= 0 && c < 31 ? c : 31]++;
        uint32_t *tr = g->tris + 3 * (size_t)nt;
        for (unsigned t = 0; t < 3 * (n - 2); t++) tr[t] = (uint32_t)ncorner + fs.loc[t];
        for (unsigned t = 0; t < n - 2; t++) g->tri_face[nt + t] = f;
        nt += n - 2;
        ncorner += n;
    }
    st_rg_scratch_free(&fs);
    g->nfaces = nf;
    g->nlines = nl;
    g->ntris = nt;
    if (!oom) {
        g->face_off[nf] = (uint32_t)ncorner;
        g->face_line[nf] = nl;
        g->fnormal = big_alloc(4 * ((size_t)nf + 1) * sizeof *g->fnormal);
        oom = !g->fnormal;
    }
    uint32_t nv = 0;
    if (!oom) {
        for (uint32_t v = 0; v < g->nvids; v++) nv += g->slot[v] != ST_NIL;
        g->nverts = nv;
        g->vdata = big_alloc((size_t)(nv ? nv : 1) * ST_RGEOM_VSTRIDE * sizeof *g->vdata);
        g->vid = big_alloc((size_t)(nv ? nv : 1) * sizeof *g->vid);
        g->vdart = big_alloc((size_t)(nv ? nv : 1) * sizeof *g->vdart);
        oom = !g->vdata || !g->vid || !g->vdart;
    }
    if (oom) {
        st_rgeom_free(g);
        return st_fail(err, ST_ERR_MEMORY, "render: out of memory building level %u", l);
    }
    /* Pass 2: the vertex table in increasing id order, then the indices. */
    nv = 0;
    for (uint32_t v = 0; v < g->nvids; v++)
        if (g->slot[v] != ST_NIL) { g->vdart[nv] = g->slot[v]; g->vid[nv] = v; g->slot[v] = nv++; }
    remap_job rj = { g, ncorner };
    st_team_run(build_threads(ncorner), remap_part, &rj);
    /* What st_rgeom_patch may grow in place. */
    g->cap_faces = (size_t)nf + 1;
    g->cap_corner = ndl;
    g->cap_tris = ndl;
    g->cap_lines = ndl;
    g->cap_verts = nv ? nv : 1;
    g->cap_dart_face = nd;
    g->cap_slot = nvid;
    g->cap_face_case = nfmax;
    g->cap_face_dart = nfmax;
    g->cap_face_line = nfmax + 1;
    st_rgeom_refresh_all(g, m);
    return ST_OK;
}

/* The dart of face f at vertex-table index s: the face's corners are its
 * walk from face_dart[f], in order (st_rgeom_build, st_rgeom_patch). */
static uint32_t face_corner_dart(const st_rgeom *g, const st_level_view *V, uint32_t f, uint32_t s)
{
    uint32_t a = g->face_off[f], n = g->face_off[f + 1] - a, d = g->face_dart[f];
    for (uint32_t k = 0; k < n; k++, d = st_v_face_step(V, g->face_embedded, d))
        if (g->corner[a + k] == s) return d;
    return ST_NIL;
}

void st_rgeom_corner_uvs(const st_rgeom *g, const st_map *m, const st_uv_map *uv, float *out)
{
    st_level_view V;
    st_level_view_init(m, g->level, &V);
    for (uint32_t t = 0; t < g->ntris; t++) {
        uint32_t f = g->tri_face[t];
        int live = f < g->nfaces && g->face_dart[f] != ST_NIL;
        for (int j = 0; j < 3; j++) {
            uint32_t d = live ? face_corner_dart(g, &V, f, g->tris[3 * (size_t)t + j]) : ST_NIL;
            float *o = out + 6 * (size_t)t + 2 * j;
            const double *p = d != ST_NIL ? st_uv_map_at(uv, d) : NULL;
            o[0] = p ? (float)p[0] : 0.0f;
            o[1] = p ? (float)p[1] : 0.0f;
        }
    }
}

/* st_rgeom_refresh_all in three passes over whole arrays, each item
 * computed as the incremental refresh computes it (st_rg_read_position,
 * st_rg_face_normal, st_rg_vertex_normal): positions and the bounding box
 * (each thread its own box, joined after: min and max do not depend on the
 * order), face normals, vertex normals. */
typedef struct refresh_job {
    st_rgeom *g;
    st_level_view V;
    float lo[ST_PARALLEL_MAX][3], hi[ST_PARALLEL_MAX][3];
} refresh_job;

static void refresh_part(st_team *team, unsigned t, void *ctx)
{
    refresh_job *j = ctx;
    st_rgeom *g = j->g;
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    uint32_t b, e;
    while (st_team_next(team, 0, g->nverts, PAR_CHUNK, &b, &e))
        for (uint32_t s = b; s < e; s++) {
            st_rg_read_position(g, &j->V, s);
            const float *p = g->vdata + ST_RGEOM_VSTRIDE * (size_t)s;
            for (int i = 0; i < 3; i++) { if (p[i] < lo[i]) lo[i] = p[i]; if (p[i] > hi[i]) hi[i] = p[i]; }
        }
    memcpy(j->lo[t], lo, sizeof lo);
    memcpy(j->hi[t], hi, sizeof hi);
    st_team_sync(team);
    while (st_team_next(team, 1, g->nfaces, PAR_CHUNK, &b, &e))
        for (uint32_t f = b; f < e; f++) st_rg_face_normal(g, f);
    st_team_sync(team);
    while (st_team_next(team, 2, g->nverts, PAR_CHUNK, &b, &e))
        for (uint32_t s = b; s < e; s++) st_rg_vertex_normal(g, &j->V, s);
}

void st_rgeom_refresh_all(st_rgeom *g, const st_map *m)
{
    refresh_job *j = malloc(sizeof *j);
    unsigned threads = j ? build_threads((size_t)g->nverts + g->nfaces) : 1;
    refresh_job local;
    if (!j) { j = &local; threads = 1; } /* one thread needs one box */
    j->g = g;
    st_level_view_init(m, g->level, &j->V);
    for (unsigned t = 0; t < threads; t++)
        for (int i = 0; i < 3; i++) { j->lo[t][i] = INFINITY; j->hi[t][i] = -INFINITY; }
    st_team_run(threads, refresh_part, j);
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (unsigned t = 0; t < threads; t++)
        for (int i = 0; i < 3; i++) {
            if (j->lo[t][i] < lo[i]) lo[i] = j->lo[t][i];
            if (j->hi[t][i] > hi[i]) hi[i] = j->hi[t][i];
        }
    if (!g->nverts) for (int i = 0; i < 3; i++) lo[i] = hi[i] = 0;
    memcpy(g->bbox, lo, sizeof lo);
    memcpy(g->bbox + 3, hi, sizeof hi);
    if (j != &local) free(j);
}

/* ---- incremental ------------------------------------------------------------ */

/* Makes *a hold at least n marks (GROW), the new tail cleared: a mark of
 * an older generation never equals a later one. */
static int grow_marks(uint32_t **a, size_t *cap, size_t n)
{
    size_t old = *cap;
    int oom = 0;
    GROW(*a, *cap, n, oom);
    if (oom) return -1;
    if (*cap > old) memset(*a + old, 0, (*cap - old) * sizeof **a);
    return 0;
}

/* Scratch marks: per vertex index, per face, and per dart of the current
 * map (the map may have grown finer levels since the build).  The vertex
 * and face marks grow with the patches' appends instead of being made
 * anew after each (a calloc of every vertex and face was 7 % of a patch at
 * base level 3: bench_render). */
int st_rg_ensure_stamps(st_rgeom *g, const st_map *m)
{
    if (grow_marks(&g->vstamp, &g->vstamp_cap, g->nverts ? g->nverts : 1) ||
        grow_marks(&g->fstamp, &g->fstamp_cap, g->nfaces ? g->nfaces : 1))
        return -1;
    uint32_t nd = m->darts.end ? m->darts.end : 1;
    if (g->dstamp_cap < nd) {
        uint32_t *a = calloc(nd, sizeof *a), *b = calloc(nd, sizeof *b);
        if (!a || !b) { free(a); free(b); return -1; }
        free(g->dstamp_v); free(g->dstamp_f);
        g->dstamp_v = a; g->dstamp_f = b;
        g->dstamp_cap = nd;
    }
    return 0;
}

/* A fresh generation for all stamp arrays. */
uint32_t st_rg_next_gen(st_rgeom *g)
{
    if (++g->gen == 0) {
        memset(g->vstamp, 0, g->vstamp_cap * sizeof *g->vstamp);
        memset(g->fstamp, 0, g->fstamp_cap * sizeof *g->fstamp);
        memset(g->dstamp_v, 0, (size_t)g->dstamp_cap * sizeof *g->dstamp_v);
        memset(g->dstamp_f, 0, (size_t)g->dstamp_cap * sizeof *g->dstamp_f);
        g->gen = 1;
    }
    return g->gen;
}

int st_rg_push(u32_list *l, uint32_t v)
{
    int oom = 0;
    if (GROW(l->d, l->cap, l->n + 1, oom), oom) return -1;
    l->d[l->n++] = v;
    return 0;
}

int st_rgeom_footprint_vids(st_rgeom *g, const st_map *m, const st_footprint *fp,
                            uint32_t **vids, uint32_t *n, uint32_t *cap)
{
    if (!fp || !fp->n) return 0;
    if (st_rg_ensure_stamps(g, m)) return -1;
    u32_list out = { *vids, *n, *cap };
    uint32_t gen = st_rg_next_gen(g);
    int rc = 0;
    for (uint32_t i = 0; i < fp->n && !rc; i++) {
        uint64_t k = fp->keys[i];
        /* A position at level L <= g->level is what the drawn level shows
         * where it stores none of its own (hier.h: stored only where it
         * differs). */
        if (st_fp_kind(k) != ST_FP_POS || st_fp_level(k) > g->level) continue;
        uint32_t v = st_fp_vid(k);
        if (v >= g->nvids || g->slot[v] == ST_NIL || g->vstamp[g->slot[v]] == gen) continue;
        g->vstamp[g->slot[v]] = gen;
        rc = st_rg_push(&out, v);
    }
    *vids = out.d;
    *n = (uint32_t)out.n;
    *cap = (uint32_t)(out.cap > UINT32_MAX ? UINT32_MAX : out.cap);
    return rc ? -1 : 0;
}

/* Vertex s still has a real face at its dart (st_rgeom_patch may leave
 * vertices that no face uses any more: their dart can be gone). */
int st_rgeom_vertex_drawn(const st_rgeom *g, const st_map *m, uint32_t s)
{
    uint32_t d = g->vdart[s];
    if (!st_dart_in_level(m, d, g->level) || d >= g->cap_dart_face || st_is_void(m, d)) return 0;
    uint32_t f = g->dart_face[d];
    return f < g->nfaces && g->face_dart[f] != ST_NIL && st_vert(m, d, g->level) == g->vid[s];
}

/* Sorts l ascending: a least-significant-digit radix sort by bytes
 * (Knuth, TAOCP vol. 3, §5.2.5), skipping the bytes that all values share
 * (a region's slots are close).  Linear: qsort's comparisons were half of
 * a drag step's buffer refresh (2.5 M of 5.3 M instructions for 4,157
 * vertices).  -1: out of memory. */
static int sort_u32(u32_list *l)
{
    size_t n = l->n;
    uint32_t *v = l->d;
    if (n < 64) {
        for (size_t i = 1; i < n; i++) {
            uint32_t x = v[i];
            size_t j = i;
            for (; j > 0 && v[j - 1] > x; j--) v[j] = v[j - 1];
            v[j] = x;
        }
        return 0;
    }
    size_t count[4][256] = { { 0 } };
    for (size_t i = 0; i < n; i++)
        for (unsigned b = 0; b < 4; b++) count[b][(v[i] >> (8 * b)) & 255]++;
    uint32_t *tmp = malloc(n * sizeof *tmp);
    if (!tmp) return -1;
    uint32_t *src = v, *dst = tmp;
    for (unsigned b = 0; b < 4; b++) {
        size_t *c = count[b];
        if (c[(src[0] >> (8 * b)) & 255] == n) continue; /* one value of this byte: order kept */
        size_t at = 0;
        for (unsigned k = 0; k < 256; k++) {
            size_t m = c[k];
            c[k] = at;
            at += m;
        }
        for (size_t i = 0; i < n; i++) dst[c[(src[i] >> (8 * b)) & 255]++] = src[i];
        uint32_t *t = src;
        src = dst;
        dst = t;
    }
    if (src == v) {
        free(tmp);
    } else {
        free(v);
        l->d = src;
        l->cap = n;
    }
    return 0;
}

/* Sorted indices -> ranges, merging gaps of up to ST_RGEOM_RANGE_GAP. */
int st_rg_to_ranges(u32_list *idx, st_range_list *out)
{
    if (!idx->n) return 0;
    if (sort_u32(idx)) return -1;
    uint32_t first = idx->d[0], last = idx->d[0];
    for (size_t i = 1; i <= idx->n; i++) {
        if (i < idx->n && idx->d[i] <= last + ST_RGEOM_RANGE_GAP) { last = idx->d[i]; continue; }
        size_t c = out->cap;
        int oom = 0;
        if (GROW(out->r, c, (size_t)out->n + 1, oom), oom) return -1;
        out->cap = (uint32_t)c;
        out->r[out->n].first = first;
        out->r[out->n].count = last - first + 1;
        out->n++;
        if (i < idx->n) first = last = idx->d[i];
    }
    return 0;
}

int st_rgeom_refresh(st_rgeom *g, const st_map *m, const uint32_t *vids, uint32_t n,
                     st_range_list *vdirty, st_range_list *fdirty)
{
    if (st_rg_ensure_stamps(g, m)) return -1;
    st_level_view V;
    st_level_view_init(m, g->level, &V);
    const int fe = g->face_embedded;
    u32_list moved = { 0 }, faces = { 0 }, verts = { 0 };
    int rc = 0;
    uint32_t gen = st_rg_next_gen(g);
    for (uint32_t i = 0; i < n && !rc; i++) {
        uint32_t v = vids[i];
        if (v >= g->nvids || g->slot[v] == ST_NIL) continue;
        uint32_t s = g->slot[v];
        if (g->vstamp[s] == gen || !st_rgeom_vertex_drawn(g, m, s)) continue;
        g->vstamp[s] = gen;
        st_rg_read_position(g, &V, s);
        rc = st_rg_push(&moved, s);
    }
    /* Faces around moved vertices get new normals... */
    for (size_t i = 0; i < moved.n && !rc; i++) {
        uint32_t d = g->vdart[moved.d[i]], x = d;
        do {
            uint32_t f = g->dart_face[x];
            if (f < g->nfaces && g->fstamp[f] != gen) {
                g->fstamp[f] = gen;
                st_rg_face_normal(g, f);
                rc |= st_rg_push(&faces, f);
            }
            x = st_v_vertex_step(&V, fe, x);
        } while (x != d);
    }
    /* ...and so do all the corners of those faces. */
    gen = st_rg_next_gen(g);
    for (size_t i = 0; i < faces.n && !rc; i++) {
        uint32_t f = faces.d[i];
        for (uint32_t k = g->face_off[f]; k < g->face_off[f + 1] && !rc; k++) {
            uint32_t s = g->corner[k];
            if (g->vstamp[s] == gen) continue;
            g->vstamp[s] = gen;
            st_rg_vertex_normal(g, &V, s);
            rc |= st_rg_push(&verts, s);
        }
    }
    if (!rc && vdirty) rc = st_rg_to_ranges(&verts, vdirty);
    if (!rc && fdirty) rc = st_rg_to_ranges(&faces, fdirty);
    free(g->reread);
    g->reread = moved.d;
    g->nreread = (uint32_t)moved.n;
    free(faces.d);
    free(verts.d);
    return rc ? -1 : 0;
}
