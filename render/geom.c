/* CPU-side geometry of a displayed level; see geom.h. */
#include "core/map/geometry.h"
#include "geom_internal.h"

#include <math.h>
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
    st_tri_index_init(&g->tix);
}

void st_rgeom_free(st_rgeom *g)
{
    free(g->vdata); free(g->vid); free(g->vdart); free(g->slot);
    free(g->face_dart); free(g->face_off); free(g->corner); free(g->fnormal); free(g->face_case); free(g->face_line);
    free(g->dart_face); free(g->tris); free(g->tri_face); free(g->lines);
    free(g->dstamp_v); free(g->dstamp_f); free(g->vstamp); free(g->fstamp); free(g->reread);
    st_tri_index tix = g->tix;
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
void st_rg_vertex_normal(st_rgeom *g, const st_level_view *V, uint32_t s)
{
    double n[3] = { 0, 0, 0 };
    uint32_t d = g->vdart[s], x = d;
    do {
        uint32_t f = g->dart_face[x];
        if (f < g->nfaces) {
            const float *fn = g->fnormal + 4 * (size_t)f;
            n[0] += fn[0]; n[1] += fn[1]; n[2] += fn[2];
        }
        x = vertex_next(V, g->face_embedded, x);
    } while (x != d);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    float *o = g->vdata + ST_RGEOM_VSTRIDE * (size_t)s + 3;
    if (len > 0 && isfinite(len)) { o[0] = (float)(n[0] / len); o[1] = (float)(n[1] / len); o[2] = (float)(n[2] / len); }
    else { o[0] = 0; o[1] = 0; o[2] = 1; }
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
    free(fs->darts); free(fs->elev); free(fs->vlev); free(fs->loc); free(fs->pos);
}

int st_rg_face_case(st_rgeom *g, const st_level_view *V, st_rg_scratch *fs, unsigned n, const uint32_t *vids)
{
    int oom = 0;
    GROW(fs->elev, fs->celev, n, oom);
    GROW(fs->vlev, fs->cvlev, n, oom);
    GROW(fs->loc, fs->cloc, 3 * (size_t)n, oom);
    if (oom) return -2;
    for (unsigned k = 0; k < n; k++) {
        uint32_t y = fs->darts[k], t = st_v_beta0(V, y);
        uint8_t a = V->ins[y], b = V->ins[t];
        fs->elev[k] = a > b ? a : b;               /* st_edge_level(m, y, l) */
        fs->vlev[k] = V->vins[vids[k]];            /* st_vertex_level(m, v) */
    }
    /* The case tables read the walk only (the dual encoding has no
     * meaningful vertex levels: only edge levels there). */
    int c = st_tri_face(&g->tix, n, fs->elev, g->face_embedded ? NULL : fs->vlev, NULL, fs->loc);
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

    /* Every dart of level l is the corner of exactly one face: the number
     * of darts bounds corners, triangles and polygon edges. */
    size_t ndl = 0;
    for (unsigned i = 0; i <= l && i < ST_MAX_LEVELS; i++) ndl += m->darts.live[i];
    if (!ndl) ndl = 1;
    g->dart_face = malloc((size_t)(g->ndarts_end ? g->ndarts_end : 1) * sizeof *g->dart_face);
    g->slot = malloc((size_t)(g->nvids ? g->nvids : 1) * sizeof *g->slot);
    g->corner = malloc(ndl * sizeof *g->corner);
    g->lines = malloc(2 * ndl * sizeof *g->lines);
    g->tris = malloc(3 * ndl * sizeof *g->tris);
    size_t cfaces = 0, ccase = 0, cline = 0;
    st_rg_scratch fs = { 0 };
    int oom = !g->dart_face || !g->slot || !g->corner || !g->lines || !g->tris;
    if (!oom) {
        for (uint32_t i = 0; i < g->ndarts_end; i++) g->dart_face[i] = ST_NIL;
        for (uint32_t i = 0; i < g->nvids; i++) g->slot[i] = ST_NIL;
    }
    /* Pass 1: walk each face once.  Corners and line ends hold vertex ids,
     * triangles hold corner numbers, slot[v] a dart of v; all become
     * vertex-table indices once the table is known (pass 2). */
    size_t ncorner = 0;
    st_dart_iter it;
    for (uint32_t d = oom ? ST_NIL : st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (g->dart_face[d] != ST_NIL) continue;
        unsigned n = 0;
        int real = 1;
        uint32_t x = d;
        do {
            if (GROW(fs.darts, fs.cdarts, (size_t)n + 1, oom), oom) break;
            fs.darts[n++] = x;
            if (st_is_void(m, x)) real = 0; /* a boundary or a hole face: nothing to draw */
            x = face_next(&V, fe, x);
        } while (x != d);
        if (oom) break;
        if (!real || n < 3) {
            for (unsigned k = 0; k < n; k++) g->dart_face[fs.darts[k]] = UNDRAWN;
            continue;
        }
        GROW(g->face_dart, cfaces, (size_t)g->nfaces + 1, oom);
        GROW(g->face_case, ccase, (size_t)g->nfaces + 1, oom);
        GROW(g->face_line, cline, (size_t)g->nfaces + 2, oom);
        if (oom) break;
        uint32_t f = g->nfaces++;
        g->face_dart[f] = d;
        g->face_line[f] = g->nlines;
        for (unsigned k = 0; k < n; k++) {
            uint32_t y = fs.darts[k], v = st_v_vert(&V, y);
            g->dart_face[y] = f;
            g->corner[ncorner + k] = v;
            if (g->slot[v] == ST_NIL) g->slot[v] = y;
        }
        /* Polygon edges: the side from corner k to k+1 once, from the end
         * with the smaller id (ids and table indices are in the same order),
         * or from this face when the face across is a hole. */
        for (unsigned k = 0; k < n; k++) {
            uint32_t a = g->corner[ncorner + k], b = g->corner[ncorner + (k + 1) % n];
            if (a < b || st_is_void(m, st_v_beta0(&V, fs.darts[k]))) {
                g->lines[2 * (size_t)g->nlines] = a;
                g->lines[2 * (size_t)g->nlines + 1] = b;
                g->nlines++;
            }
        }
        g->face_line[f + 1] = g->nlines;
        int c = st_rg_face_case(g, &V, &fs, n, g->corner + ncorner);
        if (c == -2) { oom = 1; break; }
        g->face_case[f] = (int16_t)c;
        g->ncase[c >= 0 && c < 31 ? c : 31]++;
        for (unsigned t = 0; t < 3 * (n - 2); t++) g->tris[3 * (size_t)g->ntris + t] = (uint32_t)ncorner + fs.loc[t];
        g->ntris += n - 2;
        ncorner += n;
    }
    st_rg_scratch_free(&fs);
    if (!oom) {
        g->face_off = malloc(((size_t)g->nfaces + 1) * sizeof *g->face_off);
        g->fnormal = malloc(4 * ((size_t)g->nfaces + 1) * sizeof *g->fnormal);
        g->tri_face = malloc(((size_t)g->ntris + 1) * sizeof *g->tri_face);
        oom = !g->face_off || !g->fnormal || !g->tri_face;
    }
    uint32_t nv = 0;
    if (!oom) {
        /* Face offsets and triangle owners: n - 2 triangles per face, in
         * walk order (a second, cheap walk gives each face's size). */
        uint32_t k = 0, t = 0;
        for (uint32_t f = 0; f < g->nfaces; f++) {
            g->face_off[f] = k;
            uint32_t d = g->face_dart[f], x = d, n = 0;
            do { n++; x = face_next(&V, fe, x); } while (x != d);
            for (uint32_t i = 0; i + 2 < n; i++) g->tri_face[t++] = f;
            k += n;
        }
        g->face_off[g->nfaces] = k;
        for (uint32_t v = 0; v < g->nvids; v++) if (g->slot[v] != ST_NIL) nv++;
        g->nverts = nv;
        g->vdata = malloc((size_t)(nv ? nv : 1) * ST_RGEOM_VSTRIDE * sizeof *g->vdata);
        g->vid = malloc((size_t)(nv ? nv : 1) * sizeof *g->vid);
        g->vdart = malloc((size_t)(nv ? nv : 1) * sizeof *g->vdart);
        oom = !g->vdata || !g->vid || !g->vdart;
    }
    if (oom) {
        st_rgeom_free(g);
        return st_fail(err, ST_ERR_MEMORY, "render: out of memory building level %u", l);
    }
    /* Pass 2: the vertex table in increasing id order. */
    nv = 0;
    for (uint32_t v = 0; v < g->nvids; v++)
        if (g->slot[v] != ST_NIL) { g->vdart[nv] = g->slot[v]; g->vid[nv] = v; g->slot[v] = nv++; }
    for (size_t k = 0; k < ncorner; k++) g->corner[k] = g->slot[g->corner[k]];
    for (size_t k = 0; k < 2 * (size_t)g->nlines; k++) g->lines[k] = g->slot[g->lines[k]];
    for (size_t k = 0; k < 3 * (size_t)g->ntris; k++) g->tris[k] = g->corner[g->tris[k]];
    if (!g->nfaces && g->face_line) g->face_line[0] = 0;
    /* What st_rgeom_patch may grow in place. */
    g->cap_faces = (size_t)g->nfaces + 1;
    g->cap_corner = ndl;
    g->cap_tris = g->ntris + 1;
    g->cap_lines = ndl;
    g->cap_verts = nv ? nv : 1;
    g->cap_dart_face = g->ndarts_end ? g->ndarts_end : 1;
    g->cap_slot = g->nvids ? g->nvids : 1;
    g->cap_face_case = ccase;
    g->cap_face_dart = cfaces;
    g->cap_face_line = cline;
    st_rgeom_refresh_all(g, m);
    return ST_OK;
}

/* The dart of face f at vertex-table index s: the face's corners are its
 * walk from face_dart[f], in order (st_rgeom_build, st_rgeom_patch). */
static uint32_t face_corner_dart(const st_rgeom *g, const st_level_view *V, uint32_t f, uint32_t s)
{
    uint32_t a = g->face_off[f], n = g->face_off[f + 1] - a, d = g->face_dart[f];
    for (uint32_t k = 0; k < n; k++, d = face_next(V, g->face_embedded, d))
        if (g->corner[a + k] == s) return d;
    return ST_NIL;
}

void st_rgeom_corner_uvs(const st_rgeom *g, const st_map *m, const double *uv, float *out)
{
    st_level_view V;
    st_level_view_init(m, g->level, &V);
    for (uint32_t t = 0; t < g->ntris; t++) {
        uint32_t f = g->tri_face[t];
        int live = f < g->nfaces && g->face_dart[f] != ST_NIL;
        for (int j = 0; j < 3; j++) {
            uint32_t d = live ? face_corner_dart(g, &V, f, g->tris[3 * (size_t)t + j]) : ST_NIL;
            float *o = out + 6 * (size_t)t + 2 * j;
            o[0] = d != ST_NIL ? (float)uv[2 * (size_t)d] : 0.0f;
            o[1] = d != ST_NIL ? (float)uv[2 * (size_t)d + 1] : 0.0f;
        }
    }
}

void st_rgeom_refresh_all(st_rgeom *g, const st_map *m)
{
    st_level_view V;
    st_level_view_init(m, g->level, &V);
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t s = 0; s < g->nverts; s++) {
        st_rg_read_position(g, &V, s);
        const float *p = g->vdata + ST_RGEOM_VSTRIDE * (size_t)s;
        for (int i = 0; i < 3; i++) { if (p[i] < lo[i]) lo[i] = p[i]; if (p[i] > hi[i]) hi[i] = p[i]; }
    }
    if (!g->nverts) for (int i = 0; i < 3; i++) lo[i] = hi[i] = 0;
    memcpy(g->bbox, lo, sizeof lo);
    memcpy(g->bbox + 3, hi, sizeof hi);
    for (uint32_t f = 0; f < g->nfaces; f++) st_rg_face_normal(g, f);
    for (uint32_t s = 0; s < g->nverts; s++) st_rg_vertex_normal(g, &V, s);
}

/* ---- incremental ------------------------------------------------------------ */

/* Scratch marks: per vertex index, per face, and per dart of the current
 * map (the map may have grown finer levels since the build). */
int st_rg_ensure_stamps(st_rgeom *g, const st_map *m)
{
    if (!g->vstamp) {
        g->vstamp = calloc(g->nverts ? g->nverts : 1, sizeof *g->vstamp);
        g->fstamp = calloc(g->nfaces ? g->nfaces : 1, sizeof *g->fstamp);
        if (!g->vstamp || !g->fstamp) return -1;
    }
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
        memset(g->vstamp, 0, (size_t)(g->nverts ? g->nverts : 1) * sizeof *g->vstamp);
        memset(g->fstamp, 0, (size_t)(g->nfaces ? g->nfaces : 1) * sizeof *g->fstamp);
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

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* Sorted indices -> ranges, merging gaps of up to ST_RGEOM_RANGE_GAP. */
int st_rg_to_ranges(u32_list *idx, st_range_list *out)
{
    if (!idx->n) return 0;
    qsort(idx->d, idx->n, sizeof *idx->d, cmp_u32);
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
            x = vertex_next(&V, fe, x);
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
