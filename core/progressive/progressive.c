/* Progressive multiresolution meshes: the build (working copy -> st_hier)
 * and multiresolution filtering.  Design: progressive.h. */
#include "core/progressive/progressive_internal.h"
#include "core/base/hugepage.h"
#include "core/base/membudget.h"
#include "core/base/parallel.h"
#include "core/multires/hier_internal.h"
#include "core/map/pool_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Fans every polygon into triangles (3 indices per triangle). */
static int triangulate(const st_mesh *m, uint32_t **tri, uint32_t *nt, int *fanned, st_error *err)
{
    uint64_t n = 0;
    *fanned = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t k = m->face_off[f + 1] - m->face_off[f];
        if (k < 3) return st_fail(err, ST_ERR_TOPOLOGY, "progressive: face %u has %u vertices", f, k);
        if (k > 3) *fanned = 1;
        n += k - 2;
    }
    if (n >= 0x7fffffffu / 6) return st_fail(err, ST_ERR_RANGE, "progressive: %llu triangles are too many", (unsigned long long)n);
    uint32_t *t = malloc(3 * (size_t)(n ? n : 1) * sizeof *t);
    if (!t) return st_fail(err, ST_ERR_MEMORY, "progressive: out of memory for %llu triangles", (unsigned long long)n);
    size_t o = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        const uint32_t *idx = m->face_idx + m->face_off[f];
        uint32_t k = m->face_off[f + 1] - m->face_off[f];
        for (uint32_t i = 1; i + 1 < k; i++) {
            t[o++] = idx[0];
            t[o++] = idx[i];
            t[o++] = idx[i + 1];
        }
    }
    *tri = t;
    *nt = (uint32_t)n;
    return ST_OK;
}

static void hier_empty(st_hier *h)
{
    memset(h, 0, sizeof *h);
    st_map_init(&h->map);
    st_mla_init(&h->edge_sharp, sizeof(float));
    st_mla_init(&h->vertex_sharp, sizeof(float));
    h->scheme = &st_scheme_progressive;
    h->opts.boundary = ST_BOUNDARY_EDGE_ONLY;
    h->opts.crease_method = ST_CREASE_UNIFORM;
}

/* Level 0's records from the coarsest working copy (the recipe's level-0
 * arrays, progressive.h): live vertices and half-edges in index order
 * take the ids 0, 1, ...; vid_of gets each live vertex's id. */
static int level0_recipe(const pm_work *w, uint32_t *vid_of, st_pm_recipe *rc)
{
    uint32_t *dart_of = malloc((size_t)w->nhe * sizeof *dart_of);
    uint32_t nv = 0, nd = 0;
    for (uint32_t v = 0; v < w->nv; v++) vid_of[v] = w->vdead[v] ? ST_NIL : nv++;
    for (uint32_t e = 0; dart_of && e < w->nhe; e++) dart_of[e] = (w->hflags[e] & PM_HE_DEAD) ? ST_NIL : nd++;
    rc->nverts0 = nv;
    if (!dart_of || st_pm_recipe_alloc_level0(rc, nd)) {
        free(dart_of);
        return -1;
    }
    for (uint32_t e = 0; e < w->nhe; e++) {
        uint32_t d = dart_of[e];
        if (d == ST_NIL) continue;
        rc->beta0[d] = dart_of[w->twin[e]];
        rc->beta1[d] = dart_of[pm_rot(w, e)];
        rc->vert[d] = vid_of[w->org[e]];
        rc->boundary[d] = (w->hflags[e] & PM_HE_BOUNDARY) != 0;
    }
    free(dart_of);
    return 0;
}

/* The map from the working copy, as the recipe's replay makes it
 * (progressive_replay.c): level 0 from the coarsest working copy, then
 * one level per group, coarse to fine, each collapse a -> b of the group
 * undone as the vertex split (b, c, d) (point 4 of progressive.h; a
 * session's replay of the same recipe makes the same map, ids included).
 * The relations stay in dense columns for the details; *out is the
 * replay, for pm_replay_sparsify once they are computed.  Each level's
 * faces and vertices go to the report from the working copy's counts:
 * no walk of every level's orbits afterwards. */
static int materialise(pm_work *w, st_hier *h, const st_progressive_opts *o, st_progressive_report *rep,
                       pm_replay **out, st_error *err)
{
    *out = NULL;
    st_pm_recipe rc;
    memset(&rc, 0, sizeof rc);
    rc.top = w->ngroups;
    uint32_t most = 0;
    for (unsigned l = 1; l <= w->ngroups; l++) {
        rc.nsplits[l] = w->group_beg[w->ngroups - l + 1] - w->group_beg[w->ngroups - l];
        if (rc.nsplits[l] > most) most = rc.nsplits[l];
    }
    uint32_t *vid_of = malloc((size_t)(w->nv ? w->nv : 1) * sizeof *vid_of);
    st_pm_split *s = malloc((size_t)(most ? most : 1) * sizeof *s);
    int res = !vid_of || !s || level0_recipe(w, vid_of, &rc) ? st_fail(err, ST_ERR_MEMORY, "progressive: out of memory for the map") : ST_OK;
    /* Level 0's placement (point 8) reads the coarsest working copy and its
     * quadrics, which go next. */
    double *fit = NULL;
    if (!res && o->fit_coarse) {
        fit = malloc(3 * (size_t)(w->nv ? w->nv : 1) * sizeof *fit);
        if (!fit) res = st_fail(err, ST_ERR_MEMORY, "progressive: out of memory for level 0's placement");
        else {
            memcpy(fit, w->pos, 3 * (size_t)w->nv * sizeof *fit);
            pm_work_fit_coarse(w, fit);
        }
    }
    /* The splits name vertices only: the working copy's half-edges, its
     * quadrics and its undo log go before the map grows (a lower peak). */
    pm_work_drop_topology(w);
    pm_replay *r = NULL;
    if (!res) res = pm_replay_begin(&r, h, &rc, err);
    if (!res) pm_replay_record(r);
    rep->faces[0] = w->faces;
    rep->vertices[0] = w->verts;
    uint64_t at = 0;
    for (unsigned l = 1; l <= w->ngroups && !res; l++) {
        uint32_t k = w->ngroups - l, beg = w->group_beg[k], end = w->group_beg[k + 1];
        uint64_t faces = rep->faces[l - 1];
        for (uint32_t i = beg; i < end; i++) {
            const pm_collapse *cl = &w->col[i];
            s[i - beg] = (st_pm_split){ vid_of[cl->b], vid_of[cl->c], cl->d == ST_NIL ? ST_NIL : vid_of[cl->d] };
            faces += cl->d == ST_NIL ? 1 : 2;
        }
        res = pm_replay_level(r, l, s, end - beg, at);
        if (res) break;
        const uint32_t *made = pm_replay_new_vertices(r);
        for (uint32_t i = beg; i < end; i++) vid_of[w->col[i].a] = made[i - beg];
        at += end - beg;
        rep->faces[l] = faces;
        rep->vertices[l] = rep->vertices[l - 1] + (end - beg);
        if (o->progress && o->progress(o->progress_ctx, 0.8 + 0.15 * l / w->ngroups))
            res = st_fail(err, ST_ERR_INVALID, "progressive: cancelled");
    }
    if (!res) res = pm_replay_keep_recipe(r, &rc);
    if (!res) res = pm_replay_relations(r, 1);
    if (!res) {
        /* Every vertex keeps its input position at every level (point 1):
         * its base value, no column. */
        st_map *m = &h->map;
        for (uint32_t v = 0; v < w->nv; v++)
            if (vid_of[v] != ST_NIL) memcpy(m->pos.base + (size_t)vid_of[v] * m->pos.elem, w->pos + 3 * (size_t)v, 3 * sizeof(double));
        /* ...but level 0's own, with the placement: level 1 gets a column
         * holding the input positions of level 0's vertices (the lowest
         * ids), and their base values (level 0) become the fitted ones. */
        if (fit && !st_mla_column(&m->pos, &m->verts, 1))
            res = st_fail(err, ST_ERR_MEMORY, "progressive: out of memory for level 0's positions");
        for (uint32_t v = 0; fit && !res && v < w->nv; v++)
            if (vid_of[v] != ST_NIL && m->verts.ins[vid_of[v]] == 0)
                memcpy(m->pos.base + (size_t)vid_of[v] * m->pos.elem, fit + 3 * (size_t)v, 3 * sizeof(double));
    }
    free(fit);
    st_pm_recipe_free(&rc);
    free(vid_of);
    free(s);
    if (res) pm_replay_free(r);
    else *out = r;
    return res;
}

/* D = F^T (P_l - S(P_{l-1})) for every vertex whose stencil is not itself
 * (the split vertices and their neighbours) or whose position changed from
 * l-1 (level 0's placed vertices at level 1: progressive.h, point 8); every
 * other detail is zero,
 * corrected until synthesis gives back the input to the bit
 * (pm_detail_correct): the stored positions are then also what a full
 * synthesis writes.  Some bits cannot be reached (a coordinate much smaller
 * than the prediction it is the sum of has finer bits than that sum can
 * hold); those vertices are counted, keep the input as stored position,
 * and a synthesis moves them by an ulp or so (koala to 1 %: 1823 details,
 * bench_progressive).
 *
 * The predictions and frames come from the ring tables of synthesis
 * (progressive_synth.c), which evaluate the stencils' sums in their order
 * from flat arrays, to the same bits; the stencils (scheme emit) serve a
 * level the tables do not describe.  A level's detail array is created
 * whole up front (its vertices write their own entries, on several
 * threads), and dropped again if no step of any vertex was non-zero, where
 * st_hier_set_detail would have created none. */
typedef struct detail_ctx {
    st_hier *h;
    unsigned l;
    double *d;           /* level l's detail array */
    uint64_t inexact;
    int nonzero;
} detail_ctx;

static void detail_put(void *ctx, uint32_t v, const double pred[3], const double f[3][3])
{
    detail_ctx *c = ctx;
    c->inexact += !pm_detail_correct(st_pos(&c->h->map, v, c->l), pred, f, c->d + 3 * (size_t)v, &c->nonzero);
}

static void detail_sink(void *ctx, const st_stencil *s)
{
    detail_ctx *c = ctx;
    /* Predicted by itself: zero, unless its position changed from l-1
     * (progressive.h, point 8). */
    if (s->n == 1 && s->src[0] == s->fine && s->w[0] == 1.0 &&
        !memcmp(st_pos(&c->h->map, s->fine, c->l - 1), st_pos(&c->h->map, s->fine, c->l), 3 * sizeof(double)))
        return;
    double pred[3], f[3][3];
    st_stencil_eval(&c->h->map, c->l, s, pred);
    st_hier_frame(c->h, c->l - 1, s->frame_dart, s->frame_cell, f);
    detail_put(c, s->fine, pred, f);
}

/* A level's vertices on the threads of a team (core/base/parallel.h):
 * each vertex writes only its own detail and reads the level's tables and
 * positions, so the bits do not depend on the threads; each thread counts
 * its own inexact and nonzero. */
enum { DETAIL_CHUNK = 4096 };   /* vertex ids per piece of work */

typedef struct detail_job {
    detail_ctx part[ST_PARALLEL_MAX];
    uint32_t n;
} detail_job;

static void detail_part(st_team *team, unsigned t, void *ctx)
{
    detail_job *j = ctx;
    uint32_t b, e;
    while (st_team_next(team, 0, j->n, DETAIL_CHUNK, &b, &e))
        st_progressive_predict_range(j->part[t].h, j->part[t].l, b, e, detail_put, &j->part[t]);
}

/* Level l's details from the ring tables, on `threads` threads, for the
 * vertex ids [0, n); the tables are built already. */
static void details_from_tables(detail_ctx *c, uint32_t n, unsigned threads)
{
    if (threads < 2) {
        st_progressive_predict_range(c->h, c->l, 0, n, detail_put, c);
        return;
    }
    detail_job j;
    j.n = n;
    for (unsigned t = 0; t < threads; t++) j.part[t] = *c;
    st_team_run(threads, detail_part, &j);
    for (unsigned t = 0; t < threads; t++) {
        c->inexact += j.part[t].inexact;
        c->nonzero |= j.part[t].nonzero;
    }
}

static uint64_t compute_details(st_hier *h)
{
    uint64_t inexact = 0;
    uint32_t n = h->map.verts.end ? h->map.verts.end : 1;
    for (unsigned l = 1; l <= h->map.top; l++) {
        /* With the tables, the ids of levels 0..l (st_pool_cover: the
         * levels' vertices are numbered coarse to fine) rather than every
         * id: st_hier_trim_details leaves the same array either way. */
        int tables = st_progressive_predict_range(h, l, 0, 0, detail_put, NULL); /* builds them */
        uint32_t cap = n, cover = st_pool_cover(&h->map.verts, l + 1);
        if (tables && cover && cover < n) cap = cover;
        unsigned threads = st_parallel_threads(), most = cap / (4 * DETAIL_CHUNK);
        if (threads > most) threads = most ? most : 1;
        if (threads > ST_PARALLEL_MAX) threads = ST_PARALLEL_MAX;
        detail_ctx c = { h, l, st_calloc_huge(3 * (size_t)cap, sizeof(double)), 0, 0 };
        if (!c.d) abort(); /* as st_hier_set_detail */
        if (tables) details_from_tables(&c, cap, threads);
        else st_hier_emit(h, l, NULL, 0, detail_sink, &c);
        if (c.nonzero) {
            h->detail[l] = c.d;
            h->detail_cap[l] = cap;
        } else {
            free(c.d);
        }
        inexact += c.inexact;
        st_progressive_drop_table(h, l - 1); /* the next level reads l and l+1 */
    }
    st_progressive_drop_table(h, h->map.top);
    return inexact;
}

/* The rest of the report; faces and vertices per level are in already
 * (materialise).  The finest level's darts are all live darts (a
 * progressive hierarchy removes none going finer). */
static void fill_report(st_hier *h, st_progressive_report *rep, uint64_t target)
{
    st_map *m = &h->map;
    rep->levels = m->top + 1;
    for (unsigned l = 0; l <= m->top; l++)
        rep->kept[l] = l ? (double)rep->vertices[l - 1] / (double)rep->vertices[l] : 1.0;
    uint64_t darts = st_pool_count(&m->darts, m->top);
    st_map_bytes b;
    st_map_memory(m, &b);
    rep->bytes_per_dart = darts ? (double)b.topology / (double)darts : 0;
    size_t det = 0;
    for (unsigned k = 0; k < ST_MAX_LEVELS; k++) det += (size_t)h->detail_cap[k] * 3 * sizeof(double);
    rep->detail_bytes_per_dart = darts ? (double)det / (double)darts : 0;
    rep->target_reached = rep->faces[0] <= target;
}

int st_progressive_build(const st_mesh *fine, const st_progressive_opts *o, st_hier *out,
                         st_progressive_report *rep, st_error *err)
{
    st_progressive_opts def = { 0 };
    st_progressive_report local;
    if (!o) o = &def;
    if (!rep) rep = &local;
    memset(rep, 0, sizeof *rep);
    memset(out, 0, sizeof *out);
    if (o->predictor != ST_PM_RELAXED && o->predictor != ST_PM_LIGHT && o->predictor != ST_PM_GRADED)
        return st_fail(err, ST_ERR_INVALID, "progressive: unknown predictor %d", o->predictor);
    for (uint64_t i = 0; i < 3 * (uint64_t)fine->nverts; i++)
        if (!isfinite(fine->pos[i]))
            return st_fail(err, ST_ERR_GEOMETRY, "progressive: vertex %llu has a non-finite coordinate", (unsigned long long)(i / 3));
    uint32_t *tri = NULL, nt = 0;
    int rc = triangulate(fine, &tri, &nt, &rep->triangulated, err);
    if (rc) return rc;
    pm_work w;
    rc = pm_work_init(&w, fine->pos, fine->nverts, tri, nt, err);
    free(tri);
    if (rc) return rc;
    unsigned max_levels = o->max_levels && o->max_levels < ST_MAX_LEVELS ? o->max_levels : ST_MAX_LEVELS;
    rc = pm_simplify(&w, o->target_faces, max_levels - 1, o->progress, o->progress_ctx, rep->note, sizeof rep->note, err);
    if (!rc) {
        hier_empty(out);
        out->opts.pm_predictor = o->predictor;
        pm_replay *rp = NULL;
        rc = materialise(&w, out, o, rep, &rp, err);
        pm_work_free(&w); /* before the details: a lower peak of memory */
        if (!rc) rep->inexact = compute_details(out);
        /* A level's splits re-set few darts: the sparse form (map.h) from
         * the replay's changes, then the pools trimmed (per-level blocks
         * overflow the reservation); a session may store the recipe of
         * this map until its topology changes. */
        if (!rc) rc = pm_replay_sparsify(rp);
        if (!rc) pm_replay_finish(rp);
        pm_replay_free(rp);
        if (!rc) st_hier_trim_details(out); /* sized to the ids of levels 0..l, per level */
        if (rc) {
            st_hier_free(out);
            memset(rep->faces, 0, sizeof rep->faces); /* materialise's counts of a map that is gone */
            memset(rep->vertices, 0, sizeof rep->vertices);
        }
    }
    if (!rc && o->progress && o->progress(o->progress_ctx, 1.0)) {
        st_hier_free(out);
        rc = st_fail(err, ST_ERR_INVALID, "progressive: cancelled");
    }
    pm_work_free(&w);
    if (!rc) fill_report(out, rep, o->target_faces);
    return rc;
}

int st_progressive_filter(st_hier *h, const double *gains, unsigned n, st_error *err)
{
    if (h->scheme != &st_scheme_progressive)
        return st_fail(err, ST_ERR_INVALID, "filter: the hierarchy is %s, not progressive", h->scheme ? h->scheme->name : "empty");
    for (unsigned k = 0; k < n; k++)
        if (!isfinite(gains[k])) return st_fail(err, ST_ERR_INVALID, "filter: gain %u is not finite", k);
    unsigned first = 0;
    for (unsigned k = 0; k < n && k < h->map.top && !first; k++)
        if (gains[k] != 1.0) first = k + 1;
    /* The memory guard (core/base/membudget.h): the synthesis below builds
     * the ring tables of levels first-1..top. */
    if (first && st_mem_check(st_progressive_synth_estimate(h, first - 1), "the synthesis of the filtered levels", err))
        return ST_ERR_MEMORY;
    for (unsigned k = 0; k < n && k < h->map.top; k++) {
        unsigned l = k + 1;
        if (gains[k] == 1.0) continue;
        double *d = h->detail[l];
        for (uint64_t i = 0; d && i < 3 * (uint64_t)h->detail_cap[l]; i++) d[i] *= gains[k];
    }
    if (first) st_hier_synthesize(h, first - 1);
    return ST_OK;
}
