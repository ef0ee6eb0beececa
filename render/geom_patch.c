/* st_rgeom_patch: re-tessellates only the faces a local change of the map
 * touched (a box move of the adaptive display changes a few faces; the rest
 * of the buffers stay).  See geom.h and docs/ARCHITECTURE.md.
 *
 * Which faces changed.  Every primitive that changes a face's cycle sets a
 * relation of one of its darts (map.c logs it): a new or deleted dart, β0
 * (the face of that dart: φ1 = β1 ∘ β0), β1 (the face of its β0 twin, whose
 * φ1 it changes; in the dual encoding faces are β1 orbits: its own), or the
 * vertex a dart carries.  So the current faces holding a logged dart or its
 * β0 are all the new ones, and an old face changed exactly when it holds a
 * logged dart or shares a dart with a new face.  Old faces are removed in
 * place (degenerate triangles and lines, so nothing else moves), new faces
 * are appended, vertices new to the display are appended.
 *
 * Then normals: the moved vertices (logged positions) and every corner of a
 * removed or added face go through st_rgeom_refresh, which re-reads their
 * positions, recomputes the face normals around them and the vertex normals
 * of those faces' corners. */
#include "render/geom_internal.h"

#include <math.h>
#include <string.h>

void st_rgeom_dirty_free(st_rgeom_dirty *d)
{
    st_range_list_free(&d->verts);
    st_range_list_free(&d->faces);
    st_range_list_free(&d->tris);
    st_range_list_free(&d->lines);
}

typedef struct patch {
    st_rgeom *g;
    const st_map *m;
    st_level_view V;
    uint32_t *block_rank;         /* per dart block: its place in its level's list (dart_rank) */
    uint32_t nfaces0;             /* faces before the patch: only those are removed */
    uint32_t ntris0, nlines0;     /* triangles and lines before the patch */
    u32_list refresh;             /* vertex ids whose position or normal may have changed */
    u32_list tri_r, line_r, face_r;   /* dirty triangle / line / face slots: (first, count) pairs */
    st_rg_scratch fs;
    uint32_t *tmp;                /* per face walked: vertex ids, or the walk rotated */
    size_t ctmp;
    int oom;
} patch;

/* Per-dart and per-id tables cover the map as it is now. */
static int grow_id_tables(st_rgeom *g, const st_map *m)
{
    int oom = 0;
    size_t nd = m->darts.end, nv = m->verts.end, od = g->cap_dart_face, ov = g->cap_slot;
    GROW(g->dart_face, g->cap_dart_face, nd ? nd : 1, oom);
    GROW(g->slot, g->cap_slot, nv ? nv : 1, oom);
    if (oom) return -1;
    for (size_t i = od; i < g->cap_dart_face; i++) g->dart_face[i] = ST_NIL;
    for (size_t i = ov; i < g->cap_slot; i++) g->slot[i] = ST_NIL;
    g->ndarts_end = m->darts.end;
    g->nvids = m->verts.end;
    return 0;
}

static void push_corners(patch *p, uint32_t f)
{
    st_rgeom *g = p->g;
    for (uint32_t k = g->face_off[f]; k < g->face_off[f + 1]; k++) p->oom |= st_rg_push(&p->refresh, g->vid[g->corner[k]]);
}

static void push_range(patch *p, u32_list *l, uint32_t first, uint32_t end)
{
    if (end <= first) return;
    p->oom |= st_rg_push(l, first);
    p->oom |= st_rg_push(l, end - first);
}

/* Removes face f (one that existed before the patch), if not done yet. */
static void kill_face(patch *p, uint32_t f)
{
    st_rgeom *g = p->g;
    if (f >= p->nfaces0 || g->face_dart[f] == ST_NIL) return;
    g->face_dart[f] = ST_NIL;
    g->ndead++;
    int c = g->face_case[f];
    g->ncase[c >= 0 && c < 31 ? c : 31]--;
    memset(g->fnormal + 4 * (size_t)f, 0, 4 * sizeof *g->fnormal);
    push_range(p, &p->face_r, f, f + 1);
    uint32_t t0 = g->face_off[f] - 2 * f, t1 = g->face_off[f + 1] - 2 * (f + 1);
    memset(g->tris + 3 * (size_t)t0, 0, 3 * (size_t)(t1 - t0) * sizeof *g->tris);
    push_range(p, &p->tri_r, t0, t1);
    uint32_t l0 = g->face_line[f], l1 = g->face_line[f + 1];
    memset(g->lines + 2 * (size_t)l0, 0, 2 * (size_t)(l1 - l0) * sizeof *g->lines);
    push_range(p, &p->line_r, l0, l1);
    push_corners(p, f);
}

/* The vertex-table index of map vertex v, appending it when new. */
static uint32_t vertex_index(patch *p, uint32_t v, uint32_t dart)
{
    st_rgeom *g = p->g;
    uint32_t s = g->slot[v];
    if (s == ST_NIL) {
        size_t cv = g->cap_verts, cd = g->cap_verts, cf = g->cap_verts * ST_RGEOM_VSTRIDE;
        size_t need = (size_t)g->nverts + 1;
        GROW(g->vid, cv, need, p->oom);
        GROW(g->vdart, cd, need, p->oom);
        GROW(g->vdata, cf, need * ST_RGEOM_VSTRIDE, p->oom);
        if (p->oom) return 0;
        g->cap_verts = cv < cd ? cv : cd;
        if (cf / ST_RGEOM_VSTRIDE < g->cap_verts) g->cap_verts = cf / ST_RGEOM_VSTRIDE;
        s = g->nverts++;
        g->vid[s] = v;
        g->slot[v] = s;
        st_rg_read_position(g, &p->V, s);
        float *n = g->vdata + ST_RGEOM_VSTRIDE * (size_t)s + 3;
        n[0] = 0; n[1] = 0; n[2] = 1;
    }
    g->vdart[s] = dart; /* a dart of a live real face: the normal walks from it */
    return s;
}

static int grow_face_arrays(patch *p, unsigned n)
{
    st_rgeom *g = p->g;
    size_t f = g->nfaces, cf = g->cap_faces, cn = g->cap_faces * 4;
    GROW(g->face_dart, g->cap_face_dart, f + 1, p->oom);
    GROW(g->face_case, g->cap_face_case, f + 1, p->oom);
    GROW(g->face_line, g->cap_face_line, f + 2, p->oom);
    GROW(g->face_off, cf, f + 2, p->oom);
    GROW(g->fnormal, cn, 4 * (f + 2), p->oom);
    GROW(g->corner, g->cap_corner, (size_t)g->face_off[f] + n, p->oom);
    size_t t = (size_t)g->ntris + n - 2, ct = g->cap_tris, ct3 = 3 * g->cap_tris;
    GROW(g->tri_face, ct, t + 1, p->oom);
    GROW(g->tris, ct3, 3 * (t + 1), p->oom);
    size_t cl2 = 2 * g->cap_lines;
    GROW(g->lines, cl2, 2 * ((size_t)g->nlines + n), p->oom);
    if (p->oom) return -1;
    g->cap_faces = cf < cn / 4 ? cf : cn / 4;
    g->cap_tris = ct < ct3 / 3 ? ct : ct3 / 3;
    g->cap_lines = cl2 / 2;
    return 0;
}

/* Appends the face whose n darts are in p->fs.darts. */
static void add_face(patch *p, unsigned n)
{
    st_rgeom *g = p->g;
    const st_map *m = p->m;
    if (grow_face_arrays(p, n)) return;
    uint32_t f = g->nfaces, c0 = g->face_off[f];
    if (GROW(p->tmp, p->ctmp, n, p->oom), p->oom) return;
    uint32_t *vids = p->tmp;
    for (unsigned k = 0; k < n; k++) {
        uint32_t y = p->fs.darts[k];
        vids[k] = st_v_vert(&p->V, y);
        g->corner[c0 + k] = vertex_index(p, vids[k], y);
        g->dart_face[y] = f;
    }
    int c = p->oom ? -2 : st_rg_face_case(g, &p->V, &p->fs, n, vids, NULL);
    if (c == -2) { p->oom = 1; return; }
    g->face_dart[f] = p->fs.darts[0];
    g->face_case[f] = (int16_t)c;
    g->ncase[c >= 0 && c < 31 ? c : 31]++;
    g->face_off[f + 1] = c0 + n;
    g->face_line[f] = g->nlines;
    /* The same polygon edges as the build draws: each side once, from the
     * end with the smaller vertex id, or from this face across a hole. */
    for (unsigned k = 0; k < n; k++) {
        uint32_t a = vids[k], b = vids[(k + 1) % n];
        if (a < b || st_is_void(m, st_v_beta0(&p->V, p->fs.darts[k]))) {
            g->lines[2 * (size_t)g->nlines] = g->slot[a];
            g->lines[2 * (size_t)g->nlines + 1] = g->slot[b];
            g->nlines++;
        }
    }
    g->face_line[f + 1] = g->nlines;
    for (unsigned t = 0; t < n - 2; t++) {
        for (int i = 0; i < 3; i++) g->tris[3 * (size_t)g->ntris + i] = g->corner[c0 + p->fs.loc[3 * t + i]];
        g->tri_face[g->ntris] = f;
        g->ntris++;
    }
    g->nfaces++;
    st_rg_face_normal(g, f);
    push_corners(p, f);
}

/* Where st_rgeom_build's scan (st_dart_first / st_dart_next: level by
 * level, each level's blocks in list order) meets dart d: a face is walked
 * from its first dart in that order, so that the case tables read the same
 * walk, and pick the same triangles, as a fresh build. */
static uint64_t dart_rank(const patch *p, uint32_t d)
{
    return (uint64_t)p->m->darts.ins[d] << 48 | (uint64_t)p->block_rank[d >> ST_POOL_BLOCK_SHIFT] << 20 |
           (d & (ST_POOL_BLOCK - 1));
}

static uint32_t *block_ranks(const st_map *m, unsigned l)
{
    uint32_t *r = malloc((((size_t)m->darts.end >> ST_POOL_BLOCK_SHIFT) + 1) * sizeof *r);
    if (!r) return NULL;
    for (unsigned i = 0; i <= l && i < ST_MAX_LEVELS; i++)
        for (uint32_t k = 0; k < m->darts.nblocks[i]; k++) r[m->darts.blocks[i][k]] = k;
    return r;
}

/* The current face of x (a live dart of the displayed level), unless
 * already visited in this patch: the old faces sharing its darts go, then
 * it is added (or its darts marked undrawn: a hole, a degenerate face). */
static void visit_face(patch *p, uint32_t x, uint32_t gen)
{
    st_rgeom *g = p->g;
    const st_map *m = p->m;
    if (g->dstamp_f[x] == gen) return;
    unsigned n = 0;
    int real = 1;
    uint32_t y = x;
    do {
        if (GROW(p->fs.darts, p->fs.cdarts, (size_t)n + 1, p->oom), p->oom) return;
        p->fs.darts[n++] = y;
        g->dstamp_f[y] = gen;
        if (st_is_void(m, y)) real = 0;
        uint32_t f = g->dart_face[y];
        if (f < p->nfaces0) kill_face(p, f);
        y = st_v_face_step(&p->V, g->face_embedded, y);
    } while (y != x && n <= m->darts.end);
    if (!real || n < 3) {
        for (unsigned k = 0; k < n; k++) g->dart_face[p->fs.darts[k]] = UNDRAWN;
        return;
    }
    unsigned first = 0;
    for (unsigned k = 1; k < n; k++)
        if (dart_rank(p, p->fs.darts[k]) < dart_rank(p, p->fs.darts[first])) first = k;
    if (GROW(p->tmp, p->ctmp, n, p->oom), p->oom) return;
    for (unsigned k = 0; k < n; k++) p->tmp[k] = p->fs.darts[(first + k) % n];
    memcpy(p->fs.darts, p->tmp, n * sizeof *p->tmp);
    add_face(p, n);
}

static int cmp_pair(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* (first, count) pairs -> sorted ranges appended to out, those closer than
 * ST_RGEOM_RANGE_GAP merged. */
static int ranges_out(u32_list *pairs, st_range_list *out)
{
    size_t n = pairs->n / 2;
    if (!n) return 0;
    qsort(pairs->d, n, 2 * sizeof *pairs->d, cmp_pair);
    uint32_t first = pairs->d[0], end = pairs->d[0] + pairs->d[1];
    for (size_t i = 1; i <= n; i++) {
        uint32_t f = i < n ? pairs->d[2 * i] : 0, e = i < n ? f + pairs->d[2 * i + 1] : 0;
        if (i < n && f <= end + ST_RGEOM_RANGE_GAP) { if (e > end) end = e; continue; }
        if (out->n == out->cap) {
            uint32_t c = out->cap ? 2 * out->cap : 16;
            st_range *r = realloc(out->r, (size_t)c * sizeof *r);
            if (!r) return -1;
            out->r = r;
            out->cap = c;
        }
        out->r[out->n].first = first;
        out->r[out->n].count = end - first;
        out->n++;
        first = f;
        end = e;
    }
    return 0;
}

/* Dirty slots -> ranges; the bounding box grows to the refreshed vertices
 * (st_rgeom_refresh's reread: the drawn ones among p->refresh, each once,
 * where this loop tested each of the list's repeats again). */
static int finish(patch *p, st_rgeom_dirty *dirty)
{
    st_rgeom *g = p->g;
    for (uint32_t i = 0; i < g->nreread; i++) {
        const float *q = g->vdata + ST_RGEOM_VSTRIDE * (size_t)g->reread[i];
        for (int k = 0; k < 3; k++) {
            if (q[k] < g->bbox[k]) g->bbox[k] = q[k];
            if (q[k] > g->bbox[3 + k]) g->bbox[3 + k] = q[k];
        }
    }
    if (!dirty) return 0;
    /* The appended slots, then every list sorted and merged. */
    push_range(p, &p->tri_r, p->ntris0, g->ntris);
    push_range(p, &p->line_r, p->nlines0, g->nlines);
    push_range(p, &p->face_r, p->nfaces0, g->nfaces);
    if (p->oom) return -1;
    int rc = ranges_out(&p->tri_r, &dirty->tris);
    rc |= ranges_out(&p->line_r, &dirty->lines);
    rc |= ranges_out(&p->face_r, &dirty->faces);
    return rc;
}

int64_t st_rgeom_log_darts(st_rgeom *g, const st_map *m, const st_map_log *log)
{
    if (!log || log->overflow || st_rg_ensure_stamps(g, m)) return -1;
    uint32_t gen = st_rg_next_gen(g);
    int64_t n = 0;
    for (uint32_t i = 0; i < log->ndarts; i++) {
        uint32_t d = log->darts[i];
        if (d >= g->dstamp_cap || g->dstamp_v[d] == gen) continue;
        g->dstamp_v[d] = gen;
        n++;
    }
    return n;
}

int st_rgeom_patch(st_rgeom *g, const st_map *m, const st_map_log *log, st_rgeom_dirty *dirty)
{
    if (!log || log->overflow || g->level > m->top) return -1;
    if (grow_id_tables(g, m) || st_rg_ensure_stamps(g, m)) return -1;
    patch p = { .g = g, .m = m, .nfaces0 = g->nfaces, .ntris0 = g->ntris, .nlines0 = g->nlines,
                .block_rank = block_ranks(m, g->level) };
    if (!p.block_rank) return -1;
    st_level_view_init(m, g->level, &p.V);
    uint32_t gen = st_rg_next_gen(g);
    for (uint32_t i = 0; i < log->ndarts && !p.oom; i++) {
        uint32_t d = log->darts[i];
        /* A dart logged again (the log holds one entry per relation set:
         * 27,440 for about 9,000 darts in bench_render's base-level-0
         * move) finds its old face dead, its new faces visited: skipped
         * at one read instead of five. */
        if (d < g->dstamp_cap) {
            if (g->dstamp_v[d] == gen) continue;
            g->dstamp_v[d] = gen;
        }
        if (d < g->cap_dart_face && g->dart_face[d] < p.nfaces0) kill_face(&p, g->dart_face[d]);
        if (!st_dart_in_level(m, d, g->level)) continue;
        visit_face(&p, d, gen);
        uint32_t e = st_v_beta0(&p.V, d);
        if (st_dart_in_level(m, e, g->level)) visit_face(&p, e, gen);
    }
    for (uint32_t i = 0; i < log->nverts && !p.oom; i++) p.oom |= st_rg_push(&p.refresh, log->verts[i]);
    int rc = p.oom ? -1 : 0;
    if (!rc && 2 * g->ndead > g->nfaces) rc = 1;
    if (!rc) {
        /* (st_rgeom_refresh grows the vertex and face marks to the new counts) */
        rc = st_rgeom_refresh(g, m, p.refresh.d, (uint32_t)p.refresh.n, dirty ? &dirty->verts : NULL,
                              dirty ? &dirty->faces : NULL);
        if (!rc) rc = finish(&p, dirty) ? -1 : 0;
    }
    free(p.block_rank);
    free(p.tmp);
    free(p.refresh.d);
    free(p.tri_r.d);
    free(p.line_r.d);
    free(p.face_r.d);
    st_rg_scratch_free(&p.fs);
    return rc;
}
