/* st_uv_make_atlas (core/uv/uv.h): adjacency and face geometry once, then
 * charts, their flattening (split until every chart is a disk that
 * flattens without a flip) and the packing. */
#include "core/uv/uv_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void uv_new_stamp(uv_ctx *c)
{
    if (++c->stamp == 0) {
        memset(c->fmark, 0, (size_t)c->m->nfaces * sizeof *c->fmark);
        memset(c->vmark, 0, (size_t)c->m->nverts * sizeof *c->vmark);
        c->stamp = 1;
    }
}

static void newell(const st_uv_mesh *m, uint32_t f, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    uint32_t a = m->face_off[f], b = m->face_off[f + 1];
    for (uint32_t i = a; i < b; i++) {
        const double *p = m->pos + 3 * (size_t)m->face_idx[i];
        const double *q = m->pos + 3 * (size_t)m->face_idx[i + 1 < b ? i + 1 : a];
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
}

unsigned st_uv_face_triangles(const st_uv_mesh *m, uint32_t f, uint32_t (*tris)[3])
{
    uint32_t a = m->face_off[f], n = m->face_off[f + 1] - a;
    if (n < 3) return 0;
    double fn[3];
    newell(m, f, fn);
    uint32_t start = 0;
    /* The first corner whose fan turns the face's way throughout (a
     * concave quad has one, at its reflex corner). */
    for (uint32_t s = 0; s < n && n > 3; s++) {
        int good = 1;
        const double *p0 = m->pos + 3 * (size_t)m->face_idx[a + s];
        for (uint32_t t = 1; t + 1 < n && good; t++) {
            const double *p1 = m->pos + 3 * (size_t)m->face_idx[a + (s + t) % n];
            const double *p2 = m->pos + 3 * (size_t)m->face_idx[a + (s + t + 1) % n];
            double e1[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
            double e2[3] = { p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2] };
            double c[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0] };
            good = c[0] * fn[0] + c[1] * fn[1] + c[2] * fn[2] > 0;
        }
        if (good) { start = s; break; }
    }
    for (uint32_t t = 1; t + 1 < n; t++) {
        tris[t - 1][0] = a + start;
        tris[t - 1][1] = a + (start + t) % n;
        tris[t - 1][2] = a + (start + t + 1) % n;
    }
    return n - 2;
}

typedef struct edge_key {
    uint64_t key;                 /* (min vertex << 32) | max vertex */
    uint32_t corner;
} edge_key;

static int edge_cmp(const void *pa, const void *pb)
{
    const edge_key *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return a->corner < b->corner ? -1 : a->corner > b->corner;
}

/* Twins by sorting the half-edges by their vertex pair; an edge with other
 * than two half-edges, or two of one direction, is a border for the atlas. */
static int build_twins(uv_ctx *c)
{
    const st_uv_mesh *m = c->m;
    edge_key *k = malloc((size_t)(c->nc ? c->nc : 1) * sizeof *k);
    if (!k) return -1;
    for (uint32_t i = 0; i < c->nc; i++) {
        uint32_t a = m->face_idx[i], b = m->face_idx[uv_next(m, c->corner_face, i)];
        uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        k[i].key = (uint64_t)lo << 32 | hi;
        k[i].corner = i;
        c->twin[i] = UV_NIL;
    }
    qsort(k, c->nc, sizeof *k, edge_cmp);
    for (uint32_t i = 0; i < c->nc;) {
        uint32_t j = i;
        while (j < c->nc && k[j].key == k[i].key) j++;
        if (j - i == 2) {
            uint32_t x = k[i].corner, y = k[i + 1].corner;
            if (m->face_idx[x] != m->face_idx[y]) { c->twin[x] = y; c->twin[y] = x; }
        }
        i = j;
    }
    free(k);
    return 0;
}

static void ctx_free(uv_ctx *c)
{
    free(c->corner_face); free(c->twin); free(c->fn); free(c->farea); free(c->fcent);
    free(c->fmark); free(c->vmark); free(c->vloc); free(c->vlist); free(c->vout); free(c->fqueue); free(c->border);
    free(c->x); free(c->r); free(c->s); free(c->p); free(c->q); free(c->tv); free(c->tw); free(c->ftris);
}

void st_uv_atlas_free(st_uv_atlas *a)
{
    free(a->face_chart);
    free(a->uv);
    memset(a, 0, sizeof *a);
}

/* Charts that are disks and flatten: a chart that is not a disk is split
 * into its halves' components; one that flips under LSCM and under the
 * projection too, likewise.  Charts are ranges of `faces` (reordered in
 * place); a stack of ranges replaces recursion. */
typedef struct range { uint32_t a, n; } range;

int st_uv_make_atlas(const st_uv_mesh *m, const st_uv_opts *o, st_uv_atlas *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    uv_ctx c = { .m = m };
    if (o) c.o = *o;
    if (!c.o.size) c.o.size = 1024;
    if (!(c.o.cone_deg > 0)) c.o.cone_deg = 60;
    if (!(c.o.crease_deg > 0)) c.o.crease_deg = 80;
    for (size_t i = 0; i < 3 * (size_t)m->nverts; i++)
        if (!isfinite(m->pos[i])) return st_fail(err, ST_ERR_GEOMETRY, "vertex %zu has a non-finite coordinate", i / 3 + 1);
    uint32_t nf = m->nfaces, nv = m->nverts;
    c.nc = m->face_off[nf];
    size_t nc1 = c.nc ? c.nc : 1, nf1 = nf ? nf : 1, nv1 = nv ? nv : 1;
    c.corner_face = malloc(nc1 * sizeof *c.corner_face);
    c.twin = malloc(nc1 * sizeof *c.twin);
    c.fn = malloc(3 * nf1 * sizeof *c.fn);
    c.farea = malloc(nf1 * sizeof *c.farea);
    c.fcent = malloc(3 * nf1 * sizeof *c.fcent);
    c.fmark = calloc(nf1, sizeof *c.fmark);
    c.vmark = calloc(nv1, sizeof *c.vmark);
    c.vloc = malloc(nv1 * sizeof *c.vloc);
    c.vlist = malloc(nv1 * sizeof *c.vlist);
    c.vout = malloc(nv1 * sizeof *c.vout);
    c.fqueue = malloc(nf1 * sizeof *c.fqueue);
    c.border = malloc(nc1 * sizeof *c.border);
    c.x = malloc(2 * nv1 * sizeof *c.x);
    c.s = malloc(2 * nv1 * sizeof *c.s);
    c.p = malloc(2 * nv1 * sizeof *c.p);
    c.r = malloc(2 * nc1 * sizeof *c.r);
    c.q = malloc(2 * nc1 * sizeof *c.q);
    c.tv = malloc(3 * nc1 * sizeof *c.tv);
    c.tw = malloc(6 * nc1 * sizeof *c.tw);
    c.ftris = malloc((size_t)uv_max_degree(m) * sizeof *c.ftris);
    out->face_chart = malloc(nf1 * sizeof *out->face_chart);
    out->uv = calloc(2 * nc1, sizeof *out->uv);
    uint32_t *faces = malloc(nf1 * sizeof *faces), *sizes = malloc(nf1 * sizeof *sizes);
    uint32_t *chart_off = malloc((nf1 + 1) * sizeof *chart_off);
    range *stack = malloc(nf1 * sizeof *stack);
    range *done = malloc(nf1 * sizeof *done);
    int rc = ST_OK;
    if (!c.corner_face || !c.twin || !c.fn || !c.farea || !c.fcent || !c.fmark || !c.vmark || !c.vloc || !c.vlist ||
        !c.vout || !c.fqueue || !c.border || !c.x || !c.s || !c.p || !c.r || !c.q || !c.tv || !c.tw || !c.ftris || !out->face_chart ||
        !out->uv || !faces || !sizes || !chart_off || !stack || !done) {
        rc = st_fail(err, ST_ERR_MEMORY, "out of memory making a UV atlas of %u faces", nf);
        goto fail;
    }
    for (uint32_t f = 0; f < nf; f++) {
        for (uint32_t i = m->face_off[f]; i < m->face_off[f + 1]; i++) c.corner_face[i] = f;
        double *n = c.fn + 3 * (size_t)f, *ce = c.fcent + 3 * (size_t)f;
        newell(m, f, n);
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        c.farea[f] = 0.5 * len;
        for (int k = 0; k < 3; k++) n[k] = len > 0 ? n[k] / len : 0;
        uint32_t deg = m->face_off[f + 1] - m->face_off[f];
        ce[0] = ce[1] = ce[2] = 0;
        for (uint32_t i = m->face_off[f]; i < m->face_off[f + 1]; i++)
            for (int k = 0; k < 3; k++) ce[k] += m->pos[3 * (size_t)m->face_idx[i] + k] / deg;
    }
    if (build_twins(&c)) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory making a UV atlas of %u faces", nf); goto fail; }

    /* 1. Grown charts, as ranges of faces sorted by chart. */
    uint32_t grown = uv_grow_charts(&c, out->face_chart);
    memset(chart_off, 0, (nf1 + 1) * sizeof *chart_off);
    for (uint32_t f = 0; f < nf; f++) chart_off[out->face_chart[f] + 1]++;
    for (uint32_t k = 0; k < grown; k++) chart_off[k + 1] += chart_off[k];
    for (uint32_t f = 0; f < nf; f++) faces[chart_off[out->face_chart[f]]++] = f;
    uint32_t nstack = 0, ndone = 0, start = 0;
    for (uint32_t k = 0; k < grown; k++) {
        uint32_t end = chart_off[k];
        stack[nstack++] = (range){ start, end - start };
        start = end;
    }
    /* 2. Disks that flatten. */
    while (nstack) {
        range g = stack[--nstack];
        uint32_t *fs = faces + g.a;
        int split = 0;
        if (g.n > 1 && !uv_is_disk(&c, fs, g.n)) split = 1;
        else {
            int how = uv_flatten(&c, fs, g.n, out->uv);
            if (how < 0 && g.n > 1) split = 1;
            else {
                out->stats.fallback_charts += how != 0;
                done[ndone++] = g;
            }
        }
        if (split) {
            out->stats.splits++;
            uv_bisect(&c, fs, g.n);
            uint32_t half[2] = { g.n / 2, g.n - g.n / 2 }, off = g.a;
            for (int h = 0; h < 2; h++) {
                uint32_t nb = uv_components(&c, faces + off, half[h], sizes), o2 = off;
                for (uint32_t b = 0; b < nb; b++) { stack[nstack++] = (range){ o2, sizes[b] }; o2 += sizes[b]; }
                off += half[h];
            }
        }
    }
    /* Charts numbered in the order they are done; their faces in ranges. */
    uint32_t *chart_faces = sizes; /* reused: nf entries */
    chart_off[0] = 0;
    for (uint32_t k = 0; k < ndone; k++) {
        chart_off[k + 1] = chart_off[k] + done[k].n;
        for (uint32_t i = 0; i < done[k].n; i++) {
            uint32_t f = faces[done[k].a + i];
            chart_faces[chart_off[k] + i] = f;
            out->face_chart[f] = k;
        }
    }
    out->ncharts = ndone;
    out->nfaces = nf;
    /* 3. Packing. */
    rc = uv_pack(&c, ndone, chart_off, chart_faces, out->uv, err);
    if (rc) goto fail;
    /* 4. Figures. */
    st_uv_stats keep = out->stats;
    rc = st_uv_measure(m, out->uv, &out->stats, err);
    if (rc) goto fail;
    out->stats.ncharts = ndone;
    out->stats.fallback_charts = keep.fallback_charts;
    out->stats.splits = keep.splits;
    goto done;
fail:
    st_uv_atlas_free(out);
done:
    free(faces); free(sizes); free(chart_off); free(stack); free(done);
    ctx_free(&c);
    return rc;
}
