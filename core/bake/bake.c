/* The bake: level L's surface rasterised in level B's UV layout
 * (core/bake/bake.h). */
#include "core/bake/bake_ray_internal.h"
#include "core/base/membudget.h"
#include "core/base/parallel.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void st_bake_maps_free(st_bake_maps *m)
{
    free(m->normal);
    free(m->disp);
    free(m->mask);
    memset(m, 0, sizeof *m);
}

size_t st_bake_estimate(const st_hier *h, const st_bake_uvs *uvs, const st_bake_opts *o)
{
    size_t texels = (size_t)o->size * o->size;
    size_t per_texel = sizeof(uint32_t) + 3 * sizeof(uint8_t)                 /* owner, mask, ring, edge */
                     + (o->normal ? 3 * sizeof(float) : 0)
                     + (size_t)o->displacement * sizeof(float);
    size_t corners = uvs && uvs->corner_off ? uvs->corner_off[uvs->nfaces] : 0;
    size_t per_corner = 7 * sizeof(double) + 4 * sizeof(uint32_t);             /* tangent, normal, vertex, triangles */
    /* Tangents' scratch: keys, groups, sums. */
    size_t tangent_scratch = corners * (sizeof(double) * 9 + 2 * sizeof(uint32_t));
    size_t normals = 2 * 3 * sizeof(double) * (size_t)h->map.verts.end;        /* levels B and L */
    /* By rays: the hierarchy over level L's triangles (bake_ray_internal.h). */
    size_t rays = st_bake_by_rays(h, o) ? st_bake_bvh_bytes(st_bake_level_triangles(&h->map, o->level)) : 0;
    return texels * per_texel + corners * per_corner + tangent_scratch + normals + rays;
}

int st_bake_faces_nest(const st_hier *h)
{
    switch (h->scheme->id) {
    case ST_SCHEME_CATMARK: case ST_SCHEME_LOOP: case ST_SCHEME_BUTTERFLY: case ST_SCHEME_QUADTRI:
        return !h->map.face_embedded;
    default:
        return 0;
    }
}

int st_bake_by_rays(const st_hier *h, const st_bake_opts *o)
{
    return o->rays || !st_bake_faces_nest(h);
}

typedef struct bake_ctx {
    st_map *m;
    const st_bake_opts *o;
    const st_bake_uvs *uvs;
    uint32_t face;                /* level-B face being baked */
    int32_t shift[2];             /* the tile being rasterised: texel centre q serves UV q + shift */
    int32_t k0[2], k1[2];         /* the tiles face `face` touches: [k0, k1) per axis */
    uint32_t *owner;              /* per texel: the level-B face covering it, ST_NIL */
    uint8_t *edge;                /* per texel, while claiming: 1 when its owner holds it only on an edge */
    uint32_t conflict[2];         /* faces found overlapping, ST_NIL */
    uint32_t conflict_texel[2];
    int32_t conflict_shift[2];
    const double *corner_tangent; /* 4 per corner of B */
    const double *corner_normal;  /* 3 per corner of B */
    const uint32_t *corner_vert;  /* vertex id per corner of B */
    const uint32_t (*tris)[3];    /* B's faces split in UV: face f's from corner_off[f] - 2 f, absolute corners */
    const double *normal_L;       /* per vertex id of level L */
    /* The level-L triangle being rasterised. */
    const double *tri_pos[3], *tri_nrm[3];
    st_bake_maps *out;
    st_error *err;
} bake_ctx;

/* ---- the faces of B split into triangles that do not overlap in UV ------- */

static uint32_t first_tri(const st_bake_uvs *u, uint32_t f) { return u->corner_off[f] - 2 * f; }

/* Each face of B split by st_bake_split_polygon, the corners made absolute:
 * a concave quad in UV is split along the diagonal through its reflex
 * corner, not across the outside. */
static uint32_t (*split_base_faces(const st_bake_uvs *u))[3]
{
    uint32_t nf = u->nfaces, nt = u->corner_off[nf] >= 2 * nf ? u->corner_off[nf] - 2 * nf : 0;
    uint32_t (*tris)[3] = malloc(((size_t)nt + 1) * sizeof *tris);
    if (!tris) return NULL;
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t a = u->corner_off[f], n = u->corner_off[f + 1] - a, t0 = first_tri(u, f);
        unsigned k = st_bake_split_polygon(u->uv + 2 * (size_t)a, n, tris + t0);
        for (unsigned t = 0; t < k; t++)
            for (int j = 0; j < 3; j++) tris[t0 + t][j] += a;
    }
    return tris;
}

/* ---- tiles (bake.h: tiles and wrap-around) --------------------------------- */

/* Widest face, in tiles per axis: a layout that repeats one face more often
 * is not a tiling. */
#define MAX_FACE_TILES 4

/* The tiles face f touches, [k0, k1) per axis. */
static void face_tiles(const st_bake_uvs *u, uint32_t f, int32_t k0[2], int32_t k1[2])
{
    double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
    for (uint32_t c = u->corner_off[f]; c < u->corner_off[f + 1]; c++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], u->uv[2 * (size_t)c + k]);
            hi[k] = fmax(hi[k], u->uv[2 * (size_t)c + k]);
        }
    for (int k = 0; k < 2; k++) {
        k0[k] = (int32_t)floor(lo[k]);
        k1[k] = (int32_t)ceil(hi[k]);
        if (k1[k] <= k0[k]) k1[k] = k0[k] + 1;
    }
}

static void face_home(const st_bake_uvs *u, uint32_t f, int32_t t[2])
{
    st_bake_face_tile(u->uv + 2 * (size_t)u->corner_off[f], u->corner_off[f + 1] - u->corner_off[f], t);
}

/* Face f is baked into this map: every face, or in a UDIM bake those at
 * home in the tile. */
static int face_on(const bake_ctx *c, uint32_t f)
{
    if (!c->o->udim) return 1;
    int32_t t[2];
    face_home(c->uvs, f, t);
    return t[0] == c->o->tile[0] && t[1] == c->o->tile[1];
}

/* Triangle tri (global UVs) rasterised at tile k: moved by -k into the map. */
static void raster_at(bake_ctx *c, const double tri[3][2], const int32_t k[2], st_bake_texel_fn fn)
{
    double s[3][2];
    for (int j = 0; j < 3; j++) {
        s[j][0] = tri[j][0] - k[0];
        s[j][1] = tri[j][1] - k[1];
    }
    c->shift[0] = k[0];
    c->shift[1] = k[1];
    st_bake_raster_tri(s, c->o->size, fn, c);
}

/* ---- pass 1: which face of B covers each texel, overlaps ------------------ */

/* A texel centre this close to a face's edge (in barycentric weight) is on
 * the edge: islands meeting there touch, they do not overlap.  Layouts
 * moved by whole tiles round their shared edges apart by an ulp or so
 * ((u + 1) − 1 ≠ u in doubles), which must not read as an overlap. */
#define EDGE_WEIGHT 1e-9

static void claim_texel(void *pc, uint32_t x, uint32_t y, const double w[3])
{
    bake_ctx *c = pc;
    size_t i = (size_t)y * c->o->size + x;
    uint32_t f = c->owner[i];
    int on_edge = fmin(w[0], fmin(w[1], w[2])) < EDGE_WEIGHT;
    if (f == ST_NIL) { c->owner[i] = c->face; c->edge[i] = (uint8_t)on_edge; return; }
    if (f == c->face || on_edge) return;
    if (c->edge[i]) { c->owner[i] = c->face; c->edge[i] = 0; return; }
    if (c->conflict[0] == ST_NIL) {
        c->conflict[0] = f;
        c->conflict[1] = c->face;
        c->conflict_texel[0] = x;
        c->conflict_texel[1] = y;
        c->conflict_shift[0] = c->shift[0];
        c->conflict_shift[1] = c->shift[1];
    }
}

/* An overshoot (a face's part outside its home tile, wrapped) takes only
 * texels no home part holds. */
static void claim_free_texel(void *pc, uint32_t x, uint32_t y, const double w[3])
{
    (void)w;
    bake_ctx *c = pc;
    size_t i = (size_t)y * c->o->size + x;
    if (c->owner[i] == ST_NIL) c->owner[i] = c->face;
}

/* Home parts first, checked for overlaps; then the overshoots. */
static int claim_faces(bake_ctx *c, st_error *err)
{
    const st_bake_uvs *u = c->uvs;
    for (int pass = 0; pass < 2 && c->conflict[0] == ST_NIL; pass++)
        for (uint32_t f = 0; f < u->nfaces && c->conflict[0] == ST_NIL; f++) {
            if (!face_on(c, f)) continue;
            c->face = f;
            int32_t home[2], k0[2], k1[2], k[2];
            face_home(u, f, home);
            face_tiles(u, f, k0, k1);
            for (k[1] = k0[1]; k[1] < k1[1]; k[1]++)
                for (k[0] = k0[0]; k[0] < k1[0]; k[0]++) {
                    int at_home = k[0] == home[0] && k[1] == home[1];
                    if (at_home != (pass == 0)) continue;
                    for (uint32_t t = first_tri(u, f); t < first_tri(u, f + 1); t++) {
                        double tri[3][2];
                        for (int j = 0; j < 3; j++) memcpy(tri[j], u->uv + 2 * (size_t)c->tris[t][j], sizeof tri[j]);
                        raster_at(c, tri, k, pass == 0 ? claim_texel : claim_free_texel);
                    }
                }
        }
    if (c->conflict[0] == ST_NIL) return ST_OK;
    double s = c->o->size;
    return st_fail(err, ST_ERR_INVALID,
                   "UV islands overlap: faces %u and %u of level %u both cover texel (%u, %u) at UV (%.4f, %.4f) of a %ux%u map",
                   c->conflict[0] + 1, c->conflict[1] + 1, c->o->base, c->conflict_texel[0], c->conflict_texel[1],
                   (c->conflict_texel[0] + 0.5) / s + c->conflict_shift[0], (c->conflict_texel[1] + 0.5) / s + c->conflict_shift[1],
                   c->o->size, c->o->size);
}

/* ---- pass 2: level-L faces ------------------------------------------------- */

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void normalize3(double *v)
{
    double len = sqrt(dot3(v, v));
    if (len > 1e-300 && isfinite(len))
        for (int k = 0; k < 3; k++) v[k] /= len;
}

/* B's point and frame (t, b, n) at UV p inside face c->face: the
 * triangle of the face's split that holds p best (largest smallest weight), its
 * corners' positions, normals and tangents interpolated, the tangent made
 * orthogonal to the normal again and b = w · n × t, as a shader does. */
static double base_point(const bake_ctx *c, uint32_t face, const double p[2], double pos[3], double frame[3][3])
{
    const st_bake_uvs *u = c->uvs;
    uint32_t a = u->corner_off[face];
    double best = -INFINITY, bw[3] = { 1, 0, 0 };
    uint32_t bi[3] = { a, a, a };
    for (uint32_t t = first_tri(u, face); t < first_tri(u, face + 1); t++) {
        const uint32_t *idx = c->tris[t];
        double tri[3][2], w[3];
        for (int k = 0; k < 3; k++) memcpy(tri[k], u->uv + 2 * (size_t)idx[k], sizeof tri[k]);
        if (!st_bake_barycentric(tri, p, w)) continue;
        double lo = fmin(w[0], fmin(w[1], w[2]));
        if (lo > best) { best = lo; memcpy(bw, w, sizeof bw); memcpy(bi, idx, sizeof bi); }
    }
    double t[3] = { 0, 0, 0 }, *nn = frame[2];
    for (int k = 0; k < 3; k++) pos[k] = nn[k] = 0;
    for (int j = 0; j < 3; j++) {
        const double *q = st_pos(c->m, c->corner_vert[bi[j]], c->o->base);
        const double *cn = c->corner_normal + 3 * (size_t)bi[j], *ct = c->corner_tangent + 4 * (size_t)bi[j];
        for (int k = 0; k < 3; k++) {
            pos[k] += bw[j] * q[k];
            nn[k] += bw[j] * cn[k];
            t[k] += bw[j] * ct[k];
        }
    }
    normalize3(nn);
    double d = dot3(t, nn);
    for (int k = 0; k < 3; k++) t[k] -= d * nn[k];
    normalize3(t);
    double w = c->corner_tangent[4 * (size_t)bi[0] + 3];
    memcpy(frame[0], t, sizeof t);
    frame[1][0] = w * (nn[1] * t[2] - nn[2] * t[1]);
    frame[1][1] = w * (nn[2] * t[0] - nn[0] * t[2]);
    frame[1][2] = w * (nn[0] * t[1] - nn[1] * t[0]);
    return best;
}

/* base_point at texel centre q of a map, for a face that may touch several
 * tiles: the tile whose copy of q lies best inside the face (a face inside
 * one tile has one candidate, so the result is base_point's). */
static void base_point_wrapped(const bake_ctx *c, uint32_t face, const double q[2], double pos[3], double frame[3][3])
{
    int32_t k0[2], k1[2], k[2];
    face_tiles(c->uvs, face, k0, k1);
    double best = -INFINITY;
    for (k[1] = k0[1]; k[1] < k1[1]; k[1]++)
        for (k[0] = k0[0]; k[0] < k1[0]; k[0]++) {
            double p[2] = { q[0] + k[0], q[1] + k[1] }, tp[3], tf[3][3];
            double b = base_point(c, face, p, tp, tf);
            if (b > best || best == -INFINITY) {
                best = b;
                memcpy(pos, tp, sizeof tp);
                memcpy(frame, tf, sizeof tf);
            }
        }
}

/* Writes texel i from level L's point pl and unit normal nl and B's point
 * pb and frame f; widens [*lo, *hi] by the displacement written. */
static void write_texel(const bake_ctx *c, size_t i, const double pl[3], const double nl[3], const double pb[3],
                        const double f[3][3], double *lo, double *hi)
{
    int tangent = c->o->space == ST_BAKE_TANGENT;
    st_bake_maps *out = c->out;
    if (out->normal) {
        float *o = out->normal + 3 * i;
        for (int k = 0; k < 3; k++) o[k] = (float)(tangent ? dot3(nl, f[k]) : nl[k]);
    }
    if (out->disp) {
        double d[3] = { pl[0] - pb[0], pl[1] - pb[1], pl[2] - pb[2] };
        float *o = out->disp + (size_t)out->disp_channels * i;
        if (out->disp_channels == 1) o[0] = (float)dot3(d, f[2]);
        else
            for (int k = 0; k < 3; k++) o[k] = (float)(tangent ? dot3(d, f[k]) : d[k]);
        for (unsigned k = 0; k < out->disp_channels; k++) {
            *lo = fmin(*lo, o[k]);
            *hi = fmax(*hi, o[k]);
        }
    }
    out->mask[i] = 1;
}

static void bake_texel(void *pc, uint32_t x, uint32_t y, const double w[3])
{
    bake_ctx *c = pc;
    uint32_t size = c->o->size;
    size_t i = (size_t)y * size + x;
    if (c->owner[i] != c->face) return;
    double pl[3] = { 0, 0, 0 }, nl[3] = { 0, 0, 0 };
    for (int j = 0; j < 3; j++)
        for (int k = 0; k < 3; k++) {
            pl[k] += w[j] * c->tri_pos[j][k];
            nl[k] += w[j] * c->tri_nrm[j][k];
        }
    normalize3(nl);
    double p[2] = { (x + 0.5) / size + c->shift[0], (y + 0.5) / size + c->shift[1] }, pb[3], f[3][3];
    base_point(c, c->face, p, pb, f);
    st_bake_maps *out = c->out;
    if (!out->mask[i]) out->baked++;
    write_texel(c, i, pl, nl, pb, f, &out->disp_min, &out->disp_max);
}

/* A level-L face split as B's faces are (its children of a concave base
 * face can be concave in UV too). */
static int bake_fine_face(void *pc, const uint32_t *verts, const double *uv, unsigned n)
{
    bake_ctx *c = pc;
    unsigned L = c->o->level;
    uint32_t local[16][3], (*tris)[3] = n <= 18 ? local : malloc((size_t)n * sizeof *tris);
    if (!tris) return st_fail(c->err, ST_ERR_MEMORY, "out of memory splitting a %u-gon of level %u", n, L);
    unsigned nt = st_bake_split_polygon(uv, n, tris);
    for (unsigned t = 0; t < nt; t++) {
        const uint32_t *idx = tris[t];
        double tri[3][2];
        for (int k = 0; k < 3; k++) {
            tri[k][0] = uv[2 * idx[k]];
            tri[k][1] = uv[2 * idx[k] + 1];
            c->tri_pos[k] = st_pos(c->m, verts[idx[k]], L);
            c->tri_nrm[k] = c->normal_L + 3 * (size_t)verts[idx[k]];
        }
        int32_t k[2];
        for (k[1] = c->k0[1]; k[1] < c->k1[1]; k[1]++)
            for (k[0] = c->k0[0]; k[0] < c->k1[0]; k[0]++) raster_at(c, tri, k, bake_texel);
    }
    if (tris != local) free(tris);
    return ST_OK;
}

/* ---- by rays: where the faces do not nest --------------------------------- */

typedef struct ray_pass {
    const bake_ctx *c;
    const st_bake_bvh *bvh;
    const double *normal_L;
    double reach;
    uint32_t row0, row1;          /* the rows of this pass (the progress reports between passes) */
    double lo[ST_PARALLEL_MAX], hi[ST_PARALLEL_MAX];
    uint64_t misses[ST_PARALLEL_MAX];
} ray_pass;

/* Texel i of face f: B's point and frame at the texel centre, the line
 * through it along B's normal, level L's nearest point on it (either side,
 * within the reach) and L's normal interpolated there.  A miss takes B's
 * own point and normal (a flat texel) and is counted. */
static void ray_texel(ray_pass *r, unsigned t, uint32_t x, uint32_t y, uint32_t f)
{
    const bake_ctx *c = r->c;
    uint32_t size = c->o->size;
    size_t i = (size_t)y * size + x;
    double p[2] = { (x + 0.5) / size, (y + 0.5) / size }, pb[3], fr[3][3], pl[3], nl[3] = { 0, 0, 0 };
    base_point_wrapped(c, f, p, pb, fr);
    st_bake_hit hit;
    if (st_bake_bvh_nearest(r->bvh, pb, fr[2], r->reach, &hit)) {
        const uint32_t *tv = r->bvh->tri_vert + 3 * (size_t)hit.tri;
        for (int k = 0; k < 3; k++) pl[k] = pb[k] + hit.t * fr[2][k];
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) nl[k] += hit.w[j] * r->normal_L[3 * (size_t)tv[j] + k];
        normalize3(nl);
    } else {
        memcpy(pl, pb, sizeof pl);
        memcpy(nl, fr[2], sizeof nl);
        r->misses[t]++;
    }
    write_texel(c, i, pl, nl, pb, fr, &r->lo[t], &r->hi[t]);
}

/* Rows of the map shared out among the threads: each texel is written by
 * one thread from inputs no thread writes, and the sums (misses) and
 * extremes (displacement range) are the same in any order, so one thread
 * and many give the same bits. */
static void ray_rows(st_team *team, unsigned t, void *ctx)
{
    ray_pass *r = ctx;
    const bake_ctx *c = r->c;
    uint32_t size = c->o->size, y0, y1;
    while (st_team_next(team, 0, r->row1 - r->row0, 4, &y0, &y1))
        for (uint32_t y = r->row0 + y0; y < r->row0 + y1; y++)
            for (uint32_t x = 0; x < size; x++) {
                uint32_t f = c->owner[(size_t)y * size + x];
                if (f != ST_NIL) ray_texel(r, t, x, y, f);
            }
}

/* How far the lines look for level L when not told: 5 % of the joint
 * bounding-box diagonal plus the largest gap between the two levels' boxes
 * (an approximating scheme shrinks a coarse cage: √3's level 4 of an
 * octahedron lies up to 0.3 of its radius inside level 0).  Farther
 * searches trade misses for hits on other parts of the surface (a ray from
 * a fin of blub's Doo-Sabin level 1 meets its body); --ray-reach chooses. */
static double default_reach(const bake_ctx *c)
{
    double diag, gap;
    st_bake_level_boxes(c->m, c->o->base, c->o->level, &diag, &gap);
    double r = 0.05 * diag + gap;
    return r > 0 && isfinite(r) ? r : 1.0;
}

static int bake_by_rays(bake_ctx *c, st_hier *h, st_error *err)
{
    const st_bake_opts *o = c->o;
    st_bake_maps *out = c->out;
    st_bake_bvh bvh;
    int rc = st_bake_bvh_build(&h->map, o->level, &bvh, err);
    if (rc) return rc;
    ray_pass *r = malloc(sizeof *r);
    if (!r) { st_bake_bvh_free(&bvh); return st_fail(err, ST_ERR_MEMORY, "out of memory casting rays"); }
    r->c = c;
    r->bvh = &bvh;
    r->normal_L = c->normal_L;
    r->reach = o->ray_reach > 0 ? o->ray_reach : default_reach(c);
    unsigned threads = st_parallel_threads();
    if (threads > ST_PARALLEL_MAX) threads = ST_PARALLEL_MAX;
    if (threads < 1) threads = 1;
    for (unsigned t = 0; t < ST_PARALLEL_MAX; t++) { r->lo[t] = INFINITY; r->hi[t] = -INFINITY; r->misses[t] = 0; }
    /* Passes of 64 rows: the progress callback (main thread) between them. */
    rc = ST_OK;
    for (uint32_t y = 0; y < o->size && !rc; y += 64) {
        r->row0 = y;
        r->row1 = o->size - y < 64 ? o->size : y + 64;
        st_team_run(threads, ray_rows, r);
        if (o->progress && o->progress(o->progress_ctx, (double)r->row1 / o->size))
            rc = st_fail(err, ST_ERR_INVALID, "cancelled");
    }
    if (rc) { free(r); st_bake_bvh_free(&bvh); return rc; }
    out->by_rays = 1;
    out->ray_reach = r->reach;
    for (unsigned t = 0; t < ST_PARALLEL_MAX; t++) {
        out->disp_min = fmin(out->disp_min, r->lo[t]);
        out->disp_max = fmax(out->disp_max, r->hi[t]);
        out->ray_misses += r->misses[t];
    }
    size_t texels = (size_t)o->size * o->size;
    for (size_t i = 0; i < texels; i++) out->baked += out->mask[i] == 1;
    free(r);
    st_bake_bvh_free(&bvh);
    return ST_OK;
}

/* ---- padding ------------------------------------------------------------- */

/* Dilation: each pass gives every empty texel next to a filled one (8
 * neighbours, filled before this pass) the mean of those neighbours, so
 * mip-maps and bilinear filtering near island borders do not mix in the
 * background. */
static void pad(st_bake_maps *out, uint32_t passes, uint8_t *ring)
{
    uint32_t s = out->size;
    size_t texels = (size_t)s * s;
    for (size_t i = 0; i < texels; i++) ring[i] = out->mask[i] ? 1 : 0;
    for (uint32_t pass = 1; pass <= passes && pass < 255; pass++) {
        uint64_t added = 0;
        for (uint32_t y = 0; y < s; y++)
            for (uint32_t x = 0; x < s; x++) {
                size_t i = (size_t)y * s + x;
                if (ring[i]) continue;
                double nsum[3] = { 0, 0, 0 }, dsum[3] = { 0, 0, 0 };
                unsigned cnt = 0;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int64_t xx = (int64_t)x + dx, yy = (int64_t)y + dy;
                        if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= s || yy >= s) continue;
                        size_t j = (size_t)yy * s + (size_t)xx;
                        if (!ring[j] || ring[j] > pass) continue;
                        cnt++;
                        for (int k = 0; out->normal && k < 3; k++) nsum[k] += out->normal[3 * j + k];
                        for (unsigned k = 0; out->disp && k < out->disp_channels; k++)
                            dsum[k] += out->disp[out->disp_channels * j + k];
                    }
                if (!cnt) continue;
                ring[i] = (uint8_t)(pass + 1);
                out->mask[i] = 2;
                added++;
                if (out->normal) {
                    normalize3(nsum);
                    for (int k = 0; k < 3; k++) out->normal[3 * i + k] = (float)nsum[k];
                }
                for (unsigned k = 0; out->disp && k < out->disp_channels; k++)
                    out->disp[out->disp_channels * i + k] = (float)(dsum[k] / cnt);
            }
        out->padded += added;
        if (!added) break;
    }
}

/* ---- the bake ------------------------------------------------------------ */

/* Refuses a face wider than MAX_FACE_TILES tiles (not a tiling: its copies
 * would cover the map several times over). */
static int check_tiles(bake_ctx *c, uint32_t nf)
{
    for (uint32_t f = 0; f < nf; f++) {
        int32_t k0[2], k1[2];
        face_tiles(c->uvs, f, k0, k1);
        if (k1[0] - k0[0] > MAX_FACE_TILES || k1[1] - k0[1] > MAX_FACE_TILES)
            return st_fail(c->err, ST_ERR_INVALID, "face %u of level %u spans %d x %d UV tiles (at most %d a side: not a tiled layout)",
                           f + 1, c->o->base, k1[0] - k0[0], k1[1] - k0[1], MAX_FACE_TILES);
    }
    return ST_OK;
}

/* The faces baked into this map and their corners outside its tile. */
static void count_faces(bake_ctx *c, uint32_t nf)
{
    const st_bake_uvs *u = c->uvs;
    double t[2] = { c->o->udim ? c->o->tile[0] : 0, c->o->udim ? c->o->tile[1] : 0 };
    for (uint32_t f = 0; f < nf; f++) {
        if (!face_on(c, f)) continue;
        c->out->faces++;
        for (uint32_t k = u->corner_off[f]; k < u->corner_off[f + 1]; k++) {
            const double *p = u->uv + 2 * (size_t)k;
            c->out->corners_outside += p[0] < t[0] || p[0] > t[0] + 1 || p[1] < t[1] || p[1] > t[1] + 1;
        }
    }
}

static int alloc_maps(const st_bake_opts *o, st_bake_maps *out, st_error *err)
{
    size_t texels = (size_t)o->size * o->size;
    memset(out, 0, sizeof *out);
    out->size = o->size;
    out->mask = calloc(texels, 1);
    if (o->normal) out->normal = malloc(3 * texels * sizeof *out->normal);
    if (o->displacement) {
        out->disp_channels = (unsigned)o->displacement;
        out->disp = calloc(out->disp_channels * texels, sizeof *out->disp);
    }
    if (!out->mask || (o->normal && !out->normal) || (o->displacement && !out->disp)) {
        st_bake_maps_free(out);
        return st_fail(err, ST_ERR_MEMORY, "out of memory allocating %ux%u maps", o->size, o->size);
    }
    for (size_t i = 0; out->normal && i < texels; i++) {
        out->normal[3 * i] = out->normal[3 * i + 1] = 0;
        out->normal[3 * i + 2] = 1;
    }
    out->disp_min = INFINITY;
    out->disp_max = -INFINITY;
    return ST_OK;
}

static int check_opts(const st_hier *h, const st_bake_opts *o, st_error *err)
{
    if (o->base > o->level || o->level > h->map.top)
        return st_fail(err, ST_ERR_RANGE, "cannot bake level %u onto level %u: levels are 0..%u and the base must not be finer",
                       o->level, o->base, h->map.top);
    if (o->size < 1 || o->size > 16384)
        return st_fail(err, ST_ERR_RANGE, "map size %u is outside 1..16384", o->size);
    if (o->displacement != 0 && o->displacement != 1 && o->displacement != 3)
        return st_fail(err, ST_ERR_INVALID, "a displacement map has 1 or 3 channels, not %d", o->displacement);
    if (!o->normal && !o->displacement) return st_fail(err, ST_ERR_INVALID, "nothing to bake");
    if (!(o->ray_reach >= 0) || !isfinite(o->ray_reach))
        return st_fail(err, ST_ERR_RANGE, "the rays' reach %g is not a distance >= 0", o->ray_reach);
    return ST_OK;
}

int st_bake(st_hier *h, const st_bake_uvs *uvs, const st_bake_opts *o, st_bake_maps *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    st_map *m = &h->map;
    int rc = st_bake_check_scheme(h, err);
    if (!rc) rc = check_opts(h, o, err);
    if (rc) return rc;
    uint32_t *darts = NULL, nf = 0;
    rc = st_bake_level_faces(m, o->base, &darts, &nf, err);
    if (!rc) rc = st_bake_check_uvs(m, o->base, darts, nf, uvs, err);
    if (!rc) rc = st_mem_check(st_bake_estimate(h, uvs, o), "baking the maps", err);
    if (rc) { free(darts); return rc; }

    size_t texels = (size_t)o->size * o->size, nc = uvs->corner_off[nf];
    bake_ctx c = { .m = m, .o = o, .uvs = uvs, .out = out, .err = err };
    c.conflict[0] = c.conflict[1] = ST_NIL;
    uint32_t *owner = malloc(texels * sizeof *owner), *cvert = malloc((nc ? nc : 1) * sizeof *cvert);
    double *ctan = malloc((nc ? nc : 1) * 4 * sizeof *ctan), *cnrm = malloc((nc ? nc : 1) * 3 * sizeof *cnrm);
    double *nL = NULL;
    uint32_t (*tris)[3] = split_base_faces(uvs);
    c.tris = (const uint32_t (*)[3])tris;
    if (!owner || !cvert || !ctan || !cnrm || !tris) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory baking %ux%u maps", o->size, o->size); goto done; }
    for (size_t i = 0; i < texels; i++) owner[i] = ST_NIL;
    c.owner = owner;
    rc = check_tiles(&c, nf);
    if (rc) goto done;
    if (!(c.edge = calloc(texels, 1))) { rc = st_fail(err, ST_ERR_MEMORY, "out of memory baking %ux%u maps", o->size, o->size); goto done; }
    rc = claim_faces(&c, err);
    free(c.edge);
    c.edge = NULL;
    if (!rc) rc = st_bake_tangents(h, o->base, uvs, ctan, cnrm, err);
    if (!rc) rc = st_bake_vertex_normals(m, o->level, &nL, err);
    if (!rc) rc = alloc_maps(o, out, err);
    if (rc) goto done;
    count_faces(&c, nf);
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t x = darts[f];
        for (uint32_t k = uvs->corner_off[f]; k < uvs->corner_off[f + 1]; k++, x = st_face_step(m, x, o->base))
            cvert[k] = st_vert(m, x, o->base);
    }
    c.corner_tangent = ctan;
    c.corner_normal = cnrm;
    c.corner_vert = cvert;
    c.normal_L = nL;
    if (st_bake_by_rays(h, o)) rc = bake_by_rays(&c, h, err);
    for (uint32_t f = 0; f < nf && !rc && !out->by_rays; f++) {
        if (!face_on(&c, f)) continue;
        if (o->progress && (f & 255) == 0 && o->progress(o->progress_ctx, (double)f / nf)) {
            rc = st_fail(err, ST_ERR_INVALID, "cancelled");
            break;
        }
        c.face = f;
        face_tiles(uvs, f, c.k0, c.k1);
        uint32_t a = uvs->corner_off[f];
        rc = st_bake_walk(m, darts[f], o->base, o->level, uvs->uv + 2 * (size_t)a, uvs->corner_off[f + 1] - a,
                          bake_fine_face, &c, err);
    }
    if (rc) { st_bake_maps_free(out); goto done; }
    if (!out->baked) {
        st_bake_maps_free(out);
        rc = st_fail(err, ST_ERR_INVALID, "the UVs of level %u cover no texel centre of a %ux%u map", o->base, o->size, o->size);
        goto done;
    }
    /* The owner array is free again: its bytes hold the dilation rings. */
    pad(out, o->padding, (uint8_t *)owner);
done:
    free(darts);
    free(owner);
    free(cvert);
    free(ctan);
    free(cnrm);
    free(nL);
    free(tris);
    return rc;
}
