/* The hierarchy of an unsubdivided mesh (unsubdivide.h): cage, regular
 * refinement, the input's positions written at the finest level through
 * the combinatorial correspondence, analysis down to level 0. */
#include "core/rebuild/unsubdivide.h"
#include "core/rebuild/unsub_topo_internal.h"
#include "core/base/membudget.h"
#include "core/base/parallel.h"
#include "core/fvar/fvar_internal.h"
#include "core/map/pool_internal.h"
#include "core/multires/estimate.h"
#include "core/multires/hier_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The live ids of a pool at level l in the order of st_dart_next and
 * st_vertex_next (levels 0..l, block by block), inline: on the finest
 * level, a call per id cost more than the loops' own work. */
typedef struct pool_walk { const st_pool *p; unsigned lv, top; uint32_t b, id, first; } pool_walk;

static inline uint32_t walk_next(pool_walk *w)
{
    for (;;) {
        if (w->id < ST_POOL_BLOCK) {
            uint32_t i = w->first + w->id++;
            if (w->p->ins[i] != ST_FREE_LEVEL) return i;
            continue;
        }
        while (w->lv <= w->top && w->b >= w->p->nblocks[w->lv]) { w->lv++; w->b = 0; }
        if (w->lv > w->top) return ST_NIL;
        w->first = w->p->blocks[w->lv][w->b++] << ST_POOL_BLOCK_SHIFT;
        w->id = 0;
    }
}

static inline uint32_t walk_first(pool_walk *w, const st_pool *p, unsigned l, unsigned from)
{
    *w = (pool_walk){ .p = p, .lv = from, .top = st_lvl_clamp(l), .id = ST_POOL_BLOCK };
    return walk_next(w);
}

static inline uint32_t dart_first(const st_map *m, unsigned l, pool_walk *w) { return walk_first(w, &m->darts, l, 0); }
/* In the dual encoding a surface vertex lives at its own level only (st_vertex_first). */
static inline uint32_t vertex_first(const st_map *m, unsigned l, pool_walk *w)
{
    return walk_first(w, &m->verts, l, m->face_embedded ? st_lvl_clamp(l) : 0);
}

/* u's adjacency of level l (st_unsubdivide keeps them) when it is that of
 * mesh m, else NULL (a caller's own st_unsub, or one out of memory). */
static const st_unsub_topo *kept_topo(const st_unsub *u, unsigned l, const st_mesh *m)
{
    const st_unsub_topo *t = u->topo[l];
    return t && t->foff == m->face_off && t->fidx == m->face_idx && t->nv == m->nverts && t->nf == m->nfaces ? t : NULL;
}

/* u's adjacencies, read: freed before the analysis. */
static void release_topologies(st_unsub *u)
{
    for (unsigned j = 0; j <= ST_MAX_LEVELS; j++) {
        if (u->topo[j]) st_unsub_topo_free(u->topo[j]);
        free(u->topo[j]);
        u->topo[j] = NULL;
    }
}

/* map[v] for the vertices of level j (an index of level j's mesh) becomes
 * that of level j+1, and the vertices new at j+1 get theirs: after a primal
 * split the face of an old dart d at level j+1 runs corner, the edge point
 * of d's edge, then (polygon split) the face point (thesis §3.2.1: old darts
 * keep their vertex, refine_internal.h). */
static int map_level(st_hier *h, const st_unsub *u, unsigned j, uint32_t *map, st_error *err)
{
    st_map *m = &h->map;
    const st_unsub_step *st = &u->step[j];
    st_unsub_topo own;
    memset(&own, 0, sizeof own);
    const st_unsub_topo *kept = kept_topo(u, j, &st->coarse);
    if (!kept && st_unsub_topo_build(&own, &st->coarse)) return st_fail(err, ST_ERR_MEMORY, "out of memory");
    const st_unsub_topo ct = kept ? *kept : own;
    int rc = ST_OK;
    st_level_view cv, fv_;   /* levels j and j + 1 */
    st_level_view_init(m, j, &cv);
    st_level_view_init(m, j + 1, &fv_);
    pool_walk it;
    for (uint32_t d = dart_first(m, j, &it); d != ST_NIL && !rc; d = walk_next(&it)) {
        if (st_is_boundary(m, d)) continue;
        uint32_t a = map[st_v_vert(&cv, d)], b = map[st_v_vert(&cv, st_v_phi1(&cv, d))];
        uint32_t c = a < ct.nv && b < ct.nv ? st_unsub_find(&ct, a, b) : ST_NIL;
        uint32_t x = st_v_phi1(&fv_, d), ev = st_v_vert(&fv_, x);
        if (c == ST_NIL || st_vertex_level(m, ev) != j + 1) {
            rc = st_fail(err, ST_ERR_INVALID, "level %u: dart %u has no counterpart in the recovered mesh", j, d);
            break;
        }
        map[ev] = st->e_fine[c];
        if (st->f_fine) {
            uint32_t fv = st_v_vert(&fv_, st_v_phi1(&fv_, x));
            if (st_vertex_level(m, fv) != j + 1) { rc = st_fail(err, ST_ERR_INVALID, "level %u: no face point after dart %u", j + 1, d); break; }
            map[fv] = st->f_fine[ct.face_of[c]];
        }
    }
    for (uint32_t v = vertex_first(m, j, &it); v != ST_NIL && !rc; v = walk_next(&it))
        map[v] = st->v_fine[map[v]];
    st_unsub_topo_free(&own);
    return rc;
}

/* The analysis' starting point at level j (0 < j < k): the positions
 * unsubdivide estimated for level j's mesh by inverting the Catmull-Clark
 * rules on level j+1 (unsubdivide.c), rather than the cage refined j times.
 * Where level j+1 is an exact subdivision they are the least-squares
 * solution up to rounding and the conjugate gradients take 0 or 1 steps,
 * even when the recovered cage itself is no exact subdivision (spot x3,
 * whose cage recovers two levels below spot's own: the top three levels
 * took 66, 69 and 74 steps from the refined cage, 0, 0 and 2 from these).
 * Noisy input (spot x3 moved by up to 1e-4 of its diagonal) takes about
 * 100 steps a level either way.  map[v]: v's index in level j's mesh. */
static void start_level(st_hier *h, const st_mesh *mj, unsigned j, const uint32_t *map)
{
    pool_walk it;
    for (uint32_t v = vertex_first(&h->map, j, &it); v != ST_NIL; v = walk_next(&it))
        st_hier_write_pos(h, v, j, mj->pos + 3 * (size_t)map[v]);
}

/* The faces of the finest level against the input's, on several threads:
 * each face is taken from its smallest dart id, so that every face is
 * checked once and each writes corner_of of its own darts only; chunk i of
 * the blocks notes its first failure in enumeration order, and the first
 * chunk's failure is reported, so the message is the same on any number
 * of threads. */
#define CORR_CHUNK 16u

typedef struct corr_job {
    const st_map *m;
    const st_unsub_topo *t;
    const uint32_t *map;
    uint32_t *corner_of;
    st_level_view lv;
    uint32_t *first, nblocks;      /* the finest level's dart blocks, in enumeration order */
    uint32_t *fail;                /* per chunk: the first dart that fails, ST_NIL if none */
    uint8_t *no_edge;              /* per chunk: it failed as no edge of the input (else as a face) */
    uint64_t *nd;                  /* per chunk: real darts */
} corr_job;

static int smallest_of_face(const st_level_view *lv, uint32_t d)
{
    for (uint32_t x = st_v_phi1(lv, d); x != d; x = st_v_phi1(lv, x))
        if (x < d) return 0;
    return 1;
}

/* 0, or 1 if dart d's half-edge is no input half-edge, 2 if its face is no
 * face of the input; corner_of of the face's darts written on the way. */
static int check_face(const corr_job *j, uint32_t d)
{
    const st_unsub_topo *t = j->t;
    const st_level_view *lv = &j->lv;
    uint32_t c = st_unsub_find(t, j->map[st_v_vert(lv, d)], j->map[st_v_vert(lv, st_v_phi1(lv, d))]);
    if (c == ST_NIL) return 1;
    uint32_t x = d, cx = c, n = t->foff[t->face_of[c] + 1] - t->foff[t->face_of[c]], i = 0;
    do {
        if (j->map[st_v_vert(lv, x)] != t->fidx[cx] || i++ == n) break;
        j->corner_of[x] = cx;
        x = st_v_phi1(lv, x);
        cx = st_unsub_next(t, cx);
    } while (x != d);
    return x != d || cx != c || i != n ? 2 : 0;
}

static void corr_chunks(st_team *team, unsigned tid, void *ctx)
{
    (void)tid;
    corr_job *j = ctx;
    uint32_t b, e, nchunks = (j->nblocks + CORR_CHUNK - 1) / CORR_CHUNK;
    while (st_team_next(team, 0, nchunks, 1, &b, &e)) {
        uint32_t hi = (b + 1) * CORR_CHUNK < j->nblocks ? (b + 1) * CORR_CHUNK : j->nblocks;
        uint64_t nd = 0;
        for (uint32_t i = b * CORR_CHUNK; i < hi && j->fail[b] == ST_NIL; i++)
            for (uint32_t d = j->first[i]; d < j->first[i] + ST_POOL_BLOCK; d++) {
                if (j->m->darts.ins[d] == ST_FREE_LEVEL || st_is_boundary(j->m, d)) continue;
                nd++;
                if (!smallest_of_face(&j->lv, d)) continue;
                int why = check_face(j, d);
                if (why) { j->fail[b] = d; j->no_edge[b] = why == 1; break; }
            }
        j->nd[b] = nd;
    }
}

/* Every finest vertex has a distinct input vertex, and every real half-edge
 * of the finest level is one of the input's: corner_of[d] (by dart id)
 * receives the input corner of dart d, so that the passes after this one
 * read it instead of looking the half-edge up again.  One half-edge of
 * each face is looked up; the face's other darts are then its input face's
 * next corners, each checked by its vertex (the faces of both run
 * counter-clockwise), and the two faces must close together.  Faces are
 * independent: the lookups (one cache miss or more each) share the
 * threads. */
static int check_correspondence(st_hier *h, const st_mesh *in, const st_unsub_topo *t, const uint32_t *map,
                                uint32_t *corner_of, st_error *err)
{
    st_map *m = &h->map;
    unsigned k = m->top;
    uint8_t *seen = calloc((size_t)in->nverts + 1, 1);
    if (!seen) return st_fail(err, ST_ERR_MEMORY, "out of memory");
    int rc = ST_OK;
    uint32_t nv = 0;
    pool_walk it;
    for (uint32_t v = vertex_first(m, k, &it); v != ST_NIL; v = walk_next(&it), nv++)
        if (map[v] >= in->nverts || seen[map[v]]++) { rc = st_fail(err, ST_ERR_INVALID, "vertex %u of level %u has no input vertex of its own", v, k); break; }
    free(seen);
    if (!rc && nv != in->nverts) rc = st_fail(err, ST_ERR_INVALID, "level %u has %u vertices, the input %u", k, nv, in->nverts);
    if (rc) return rc;
    memset(corner_of, 0xff, (size_t)m->darts.end * sizeof *corner_of);   /* ST_NIL */
    corr_job j = { .m = m, .t = t, .map = map, .corner_of = corner_of };
    st_level_view_init(m, k, &j.lv);
    j.nblocks = st_pool_block_list(&m->darts, k, NULL);
    uint32_t nchunks = (j.nblocks + CORR_CHUNK - 1) / CORR_CHUNK;
    j.first = malloc(((size_t)j.nblocks + 1) * sizeof *j.first);
    j.fail = malloc(((size_t)nchunks + 1) * sizeof *j.fail);
    j.no_edge = calloc((size_t)nchunks + 1, 1);
    j.nd = calloc((size_t)nchunks + 1, sizeof *j.nd);
    if (!j.first || !j.fail || !j.no_edge || !j.nd) rc = st_fail(err, ST_ERR_MEMORY, "out of memory");
    if (!rc) {
        st_pool_block_list(&m->darts, k, j.first);
        for (uint32_t i = 0; i < nchunks; i++) j.fail[i] = ST_NIL;
        unsigned threads = st_parallel_threads(), most = nchunks / 4;   /* at least 4 chunks a thread */
        st_team_run(threads < most ? threads : most ? most : 1, corr_chunks, &j);
        uint64_t nd = 0;
        for (uint32_t i = 0; i < nchunks && !rc; i++) {
            if (j.fail[i] != ST_NIL && j.no_edge[i])
                rc = st_fail(err, ST_ERR_INVALID, "level %u: dart %u is no edge of the input", k, j.fail[i]);
            else if (j.fail[i] != ST_NIL)
                rc = st_fail(err, ST_ERR_INVALID, "level %u: the face of dart %u is no face of the input", k, j.fail[i]);
            nd += j.nd[i];
        }
        if (!rc && nd != t->nc) rc = st_fail(err, ST_ERR_INVALID, "level %u has %llu face corners, the input %u", k, (unsigned long long)nd, t->nc);
    }
    free(j.first);
    free(j.fail);
    free(j.no_edge);
    free(j.nd);
    return rc;
}

/* The finest level's tags against the input's.  Sharpness: the cage's
 * tags (s + k, unsubdivide.c) decay by one per level, exact in float
 * except for the rounding of s + k, so the refined finest values agree with
 * the input's to a few ulps; they are then set to the input's exactly, so
 * that the finest level is the input, tags included.  Holes: the finest
 * face of every dart must be a hole exactly when its input face is.  The
 * values to set are listed in *fix (beside the UV refinement, which reads
 * the sharpness) and set by apply_tag_fixes once that is done. */
typedef struct tag_fixes {
    uint32_t *id;                 /* darts, then vertices */
    float *s;
    uint32_t nedges, n;
} tag_fixes;

static int finest_tags(st_hier *h, const st_mesh *in, const st_unsub_topo *tp, const uint32_t *map,
                       const uint32_t *corner_of, tag_fixes *fix, st_error *err)
{
    /* Each input crease edge is at most two darts of the finest level. */
    size_t most = 2 * (size_t)in->ncreases + in->ncorners + 1;
    fix->id = malloc(most * sizeof *fix->id);
    fix->s = malloc(most * sizeof *fix->s);
    if (!fix->id || !fix->s) return st_fail(err, ST_ERR_MEMORY, "out of memory");
    st_map *m = &h->map;
    unsigned k = m->top;
    const st_unsub_topo t = *tp;
    float *esharp = calloc((size_t)t.nc + 1, sizeof *esharp), *vsharp = calloc((size_t)in->nverts + 1, sizeof *vsharp);
    int rc = ST_OK;
    if (!esharp || !vsharp) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory"); goto done; }
    for (uint32_t i = 0; i < in->ncreases; i++) {
        uint32_t a = in->crease_v[2 * i], b = in->crease_v[2 * i + 1], c;
        if ((c = st_unsub_find(&t, a, b)) != ST_NIL) esharp[c] = in->crease_s[i];
        if ((c = st_unsub_find(&t, b, a)) != ST_NIL) esharp[c] = in->crease_s[i];
    }
    for (uint32_t i = 0; i < in->ncorners; i++) vsharp[in->corner_v[i]] = in->corner_s[i];
    pool_walk it;
    for (uint32_t d = dart_first(m, k, &it); d != ST_NIL && !rc; d = walk_next(&it)) {
        if (st_is_boundary(m, d)) continue;
        uint32_t c = corner_of[d];   /* check_correspondence found it */
        if (!st_is_hole(m, d) != !(in->face_hole && in->face_hole[t.face_of[c]]))
            rc = st_fail(err, ST_ERR_INVALID, "level %u: face of dart %u is%s a hole, input face %u is%s", k, d,
                         st_is_hole(m, d) ? "" : " not", t.face_of[c] + 1, st_is_hole(m, d) ? " not" : "");
        if (!in->ncreases) continue;
        float got = st_hier_edge_sharpness(h, d, k), want = esharp[c];
        if (fabsf(got - want) > 1e-5f * (1.0f + want))
            rc = st_fail(err, ST_ERR_INVALID, "level %u: edge %u-%u has sharpness %g after refinement, the input %g",
                         k, map[st_vert(m, d, k)] + 1, map[st_vert(m, st_phi1(m, d, k), k)] + 1, (double)got, (double)want);
        else if (got != want && fix->n < most)
            fix->id[fix->n] = d, fix->s[fix->n++] = want;
    }
    fix->nedges = fix->n;
    for (uint32_t v = vertex_first(m, k, &it); v != ST_NIL && !rc && in->ncorners; v = walk_next(&it)) {
        float got = st_hier_vertex_sharpness(h, v, k), want = vsharp[map[v]];
        if (fabsf(got - want) > 1e-5f * (1.0f + want))
            rc = st_fail(err, ST_ERR_INVALID, "level %u: vertex %u has sharpness %g after refinement, the input %g",
                         k, map[v] + 1, (double)got, (double)want);
        else if (got != want && fix->n < most)
            fix->id[fix->n] = v, fix->s[fix->n++] = want;
    }
done:
    free(esharp);
    free(vsharp);
    return rc;
}

static void apply_tag_fixes(st_hier *h, tag_fixes *fix)
{
    unsigned k = h->map.top;
    for (uint32_t i = 0; i < fix->n; i++) {
        if (i < fix->nedges) st_hier_set_edge_sharpness(h, fix->id[i], k, fix->s[i]);
        else st_hier_set_vertex_sharpness(h, fix->id[i], k, fix->s[i]);
    }
    free(fix->id);
    free(fix->s);
    *fix = (tag_fixes){ 0 };
}

/* The levels' connectivity without positions or UVs: with
 * Catmull-Clark every position of levels 1..k is written before anything
 * reads it (start_level for 0 < j < k, the input at k), so the synthesis
 * st_hier_subdivide_to would run per level is skipped (0.19 G of the
 * refinement's 1.0 G instructions for spot x4).  The session is the same: a
 * position column covers the same ids whichever write creates it
 * (st_pool_cover). */
static int refine_topology(st_hier *h, unsigned levels, st_error *err)
{
    char what[64];
    snprintf(what, sizeof what, "subdividing to level %u", levels);
    int rc = levels > h->map.top ? st_mem_check(st_hier_estimate_subdivide(h, levels, NULL), what, err) : ST_OK;
    /* The UVs come later, beside the positions (positions_task), by
     * st_fvar_refine_levels: what a session's reader does too. */
    int regen = st_hier_regenerable(h);
    while (!rc && h->map.top < levels) rc = st_hier_refine_topology(h, err);
    /* The levels are the cage's refinement, as st_hier_subdivide_to's. */
    if (!rc && regen) st_hier_mark_regenerable(h, h->regen_end);
    return rc;
}

/* The cage's hierarchy refined to the finest level, and the input's
 * adjacency (for the correspondence): independent, so two threads run
 * them side by side; each writes only its own results, so the outcome is
 * the same on one thread or two. */
typedef struct refine_job {
    st_hier *h;
    const st_mesh *in;
    const st_unsub *u;
    const st_scheme *sc;
    const st_hier_opts *ho;
    st_error *err;
    int rc_hier, rc_topo;
    st_unsub_topo topo;           /* the input's adjacency: u's, or built here (own_topo) */
    int own_topo;
} refine_job;

static void refine_task(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    refine_job *j = ctx;
    uint32_t b, e;
    while (st_team_next(team, 0, 2, 1, &b, &e)) {
        if (b == 1) {
            const st_unsub_topo *kept = kept_topo(j->u, j->u->levels, j->in);
            if (kept) j->topo = *kept;
            else j->rc_topo = st_unsub_topo_build(&j->topo, j->in);
            j->own_topo = !kept;
            continue;
        }
        j->rc_hier = st_hier_init(j->h, &j->u->step[0].coarse, j->sc, j->ho, j->err);
        if (!j->rc_hier) {
            j->rc_hier = j->sc->id == ST_SCHEME_CATMARK ? refine_topology(j->h, j->u->levels, j->err)
                                                        : st_hier_subdivide_to(j->h, j->u->levels, j->err);
            if (j->rc_hier) st_hier_free(j->h);
        }
    }
}

/* The input's vertex for every vertex of the hierarchy (map), level by
 * level, with Catmull-Clark's starting points written on the way; the
 * correspondence of the finest level with the input, checked (on several
 * threads), and the input's positions written there; then the tags checked
 * and the analysis.  The analysis needs no stencils built beforehand: an
 * exact level is checked by a streamed pass (hier_analysis.c). */
typedef struct positions_job {
    st_hier *h;
    st_unsub *u;
    const st_mesh *in;
    const st_scheme *sc;
    refine_job *rj;               /* the input's adjacency, freed once read */
    uint32_t *map, *corner_of;
    st_error *err;
    int rc;                       /* in: the level-0 check's */
    double residual;              /* the analysis' */
    tag_fixes fix;                /* finest_tags' */
    int rc_uv;                    /* the UV refinement's, with its own error */
    st_error uv_err;
} positions_job;

static void write_positions(positions_job *j)
{
    st_hier *h = j->h;
    const st_unsub *u = j->u;
    int rc = j->rc;
    for (unsigned l = 0; l < u->levels && !rc; l++) {
        if (l > 0 && j->sc->id == ST_SCHEME_CATMARK) start_level(h, &u->step[l].coarse, l, j->map);
        rc = map_level(h, u, l, j->map, j->err);
    }
    if (!rc) rc = check_correspondence(h, j->in, &j->rj->topo, j->map, j->corner_of, j->err);
    if (!rc) {
        pool_walk it;
        for (uint32_t v = vertex_first(&h->map, u->levels, &it); v != ST_NIL; v = walk_next(&it))
            st_hier_write_pos(h, v, u->levels, j->in->pos + 3 * (size_t)j->map[v]);
    }
    j->rc = rc;
}

/* The positions, tags checked and analysis, then the finest level made
 * the input's again (the analysis writes it back as given; the finest
 * level must reproduce the input bit for bit). */
static void positions_and_analysis(positions_job *j)
{
    st_hier *h = j->h;
    write_positions(j);
    if (!j->rc) j->rc = finest_tags(h, j->in, &j->rj->topo, j->map, j->corner_of, &j->fix, j->err);
    if (j->rj->own_topo) st_unsub_topo_free(&j->rj->topo);
    j->rj->own_topo = 0;
    release_topologies(j->u);
    if (j->rc) return;
    j->residual = st_hier_analyze(h, 0);
    unsigned k = j->u->levels;
    pool_walk it;
    for (uint32_t v = vertex_first(&h->map, k, &it); v != ST_NIL; v = walk_next(&it))
        if (memcmp(st_pos(&h->map, v, k), j->in->pos + 3 * (size_t)j->map[v], 3 * sizeof(double)))
            st_hier_write_pos(h, v, k, j->in->pos + 3 * (size_t)j->map[v]);
}

/* The above beside the UVs of levels 1..k (Catmull-Clark's refinement left
 * them out): st_fvar_refine_levels reads the connectivity, sharpness
 * included, and writes h->fvar only, while the other side writes
 * positions and details (the sharpness only after both: finest_tags), so
 * the two run side by side with the same results on one thread or two
 * (the analysis starts threads of its own). */
static void positions_task(st_team *team, unsigned t, void *ctx)
{
    (void)t;
    positions_job *j = ctx;
    uint32_t b, e;
    while (st_team_next(team, 0, 2, 1, &b, &e)) {
        if (b == 0) positions_and_analysis(j);
        else j->rc_uv = st_hier_uv_refine_levels(j->h, j->u->levels, &j->uv_err);
    }
}

int st_unsub_build_hier(const st_mesh *in, st_unsub *u, const st_scheme *sc, const st_hier_opts *ho,
                        st_hier *h, uint32_t **fine_of, double *residual, st_error *err)
{
    return st_unsub_build_hier_corners(in, u, sc, ho, h, fine_of, NULL, residual, NULL, err);
}

int st_unsub_build_hier_corners(const st_mesh *in, st_unsub *u, const st_scheme *sc, const st_hier_opts *ho,
                                st_hier *h, uint32_t **fine_of, uint32_t **corner_of_out, double *residual,
                                double *uv_residual, st_error *err)
{
    if (fine_of) *fine_of = NULL;
    if (corner_of_out) *corner_of_out = NULL;
    if (residual) *residual = 0;
    if (uv_residual) *uv_residual = 0;
    if (!u->levels) return st_fail(err, ST_ERR_INVALID, "nothing to rebuild: no level was recovered");
    refine_job job = { .h = h, .in = in, .u = u, .sc = sc, .ho = ho, .err = err };
    /* With the input's adjacency kept by st_unsubdivide, the second task
     * is a copy of a struct: no thread for it. */
    int kept = kept_topo(u, u->levels, in) != NULL;
    st_team_run(st_parallel_threads() < 2 || kept ? 1 : 2, refine_task, &job);
    if (job.rc_hier) { if (job.own_topo) st_unsub_topo_free(&job.topo); return job.rc_hier; }
    if (job.rc_topo) { st_hier_free(h); return st_fail(err, ST_ERR_MEMORY, "out of memory"); }
    int rc = ST_OK;
    st_map *m = &h->map;
    uint32_t *map = malloc(((size_t)m->verts.end + 1) * sizeof *map);
    uint32_t *corner_of = malloc(((size_t)m->darts.end + 1) * sizeof *corner_of);
    if (!map || !corner_of) {
        free(map);
        free(corner_of);
        if (job.own_topo) st_unsub_topo_free(&job.topo);
        st_hier_free(h);
        return st_fail(err, ST_ERR_MEMORY, "out of memory");
    }
    for (uint32_t v = 0; v < m->verts.end; v++) map[v] = ST_NIL;
    /* Level 0 was built from the cage in its vertex order. */
    pool_walk it;
    uint32_t i = 0;
    for (uint32_t v = vertex_first(m, 0, &it); v != ST_NIL; v = walk_next(&it)) map[v] = i++;
    if (i != u->step[0].coarse.nverts) rc = st_fail(err, ST_ERR_INVALID, "level 0 has %u vertices, the cage %u", i, u->step[0].coarse.nverts);
    positions_job pj = { .h = h, .u = u, .in = in, .sc = sc, .rj = &job, .map = map, .corner_of = corner_of, .err = err, .rc = rc };
    st_team_run(st_parallel_threads() < 2 ? 1 : 2, positions_task, &pj);
    rc = pj.rc;
    if (!rc && pj.rc_uv) {
        if (err) *err = pj.uv_err;
        rc = pj.rc_uv;
    }
    apply_tag_fixes(h, &pj.fix);
    if (!rc && uv_residual && in->face_uv) *uv_residual = st_unsub_uv_residual_corners(h, in, corner_of);
    if (rc) { free(map); free(corner_of); st_hier_free(h); return rc; }
    if (corner_of_out) *corner_of_out = corner_of;
    else free(corner_of);
    if (residual) *residual = pj.residual;
    if (fine_of) {
        for (uint32_t v = 0; v < m->verts.end; v++)
            if (m->verts.ins[v] == ST_FREE_LEVEL) map[v] = ST_NIL;
        *fine_of = map;
    } else {
        free(map);
    }
    return ST_OK;
}

double st_unsub_max_detail(const st_hier *h)
{
    const st_map *m = &h->map;
    double worst = 0;
    for (unsigned l = 1; l <= m->top; l++) {
        pool_walk it;
        for (uint32_t v = vertex_first(m, l, &it); v != ST_NIL; v = walk_next(&it)) {
            const double *d = st_hier_detail(h, l, v);
            double n = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            if (n > worst) worst = n;
        }
    }
    return sqrt(worst);   /* of the largest square: the same as the largest root (sqrt is monotonic) */
}

double st_unsub_uv_residual_corners(const st_hier *h, const st_mesh *in, const uint32_t *corner_of)
{
    const st_map *m = &h->map;
    unsigned k = m->top;
    st_uv_map u = st_hier_uv(h, k);
    if (!in->face_uv) return 0;
    if (!u.uv || !corner_of) return INFINITY;
    double worst = 0;
    pool_walk it;
    for (uint32_t d = dart_first(m, k, &it); d != ST_NIL; d = walk_next(&it)) {
        if (st_is_boundary(m, d) || st_is_hole(m, d)) continue;
        uint32_t c = corner_of[d];
        if (c == ST_NIL) return INFINITY;
        const double *w = in->uv + 2 * (size_t)in->face_uv[c];
        const double *uv = st_uv_map_at(&u, d);
        double e = fmax(fabs(uv[0] - w[0]), fabs(uv[1] - w[1]));
        if (e > worst) worst = e;
    }
    return worst;
}

double st_unsub_uv_residual(const st_hier *h, const st_mesh *in, const uint32_t *fine_of)
{
    const st_map *m = &h->map;
    unsigned k = m->top;
    st_uv_map u = st_hier_uv(h, k);
    if (!in->face_uv) return 0;
    if (!u.uv || !fine_of) return INFINITY;
    st_unsub_topo t;
    if (st_unsub_topo_build(&t, in)) return INFINITY;
    double worst = 0;
    pool_walk it;
    for (uint32_t d = dart_first(m, k, &it); d != ST_NIL; d = walk_next(&it)) {
        if (st_is_boundary(m, d) || st_is_hole(m, d)) continue;
        uint32_t c = st_unsub_find(&t, fine_of[st_vert(m, d, k)], fine_of[st_vert(m, st_phi1(m, d, k), k)]);
        if (c == ST_NIL) { worst = INFINITY; break; }
        const double *w = in->uv + 2 * (size_t)in->face_uv[c];
        const double *uv = st_uv_map_at(&u, d);
        double e = fmax(fabs(uv[0] - w[0]), fabs(uv[1] - w[1]));
        if (e > worst) worst = e;
    }
    st_unsub_topo_free(&t);
    return worst;
}
