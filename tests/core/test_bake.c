/* Baking (core/bake/bake.h): a fine level that is a known displacement of
 * the base level along its interpolated normal bakes to that displacement
 * (within 1 % of its range) on a per-face atlas (cube) and on a seamed
 * toroidal unwrap (torus); level B baked onto itself gives the flat
 * tangent-space normal; tangents follow the UV derivative; bad UVs,
 * overlapping islands and schemes whose faces do not nest are refused; a
 * face concave in UV is split inside itself (no false overlap). */
#include "testlib.h"

#include "core/bake/bake_ray_internal.h"
#include "core/base/membudget.h"
#include "core/base/parallel.h"
#include "core/io/mesh.h"
#include "core/multires/edit.h"
#include "core/progressive/progressive.h"

#include <malloc.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void normalize3(double *v)
{
    double l = sqrt(dot3(v, v));
    for (int k = 0; k < 3; k++) v[k] /= l;
}

/* The known displacement: a smooth function of the base point. */
static double bump(const double *p)
{
    return 0.04 * sin(3.0 * p[0] + 0.5) * cos(2.0 * p[1]) + 0.03 * sin(2.5 * p[2]);
}

typedef struct base_geo {
    st_hier *h;
    unsigned B;
    const st_bake_uvs *uvs;
    uint32_t *cvert;              /* vertex per corner */
    double *cnormal;              /* normal per corner */
    double *target;               /* per vertex id of level L */
    uint8_t *has_target;
    uint32_t face;
} base_geo;

/* Point and unit interpolated normal of face f of B at UV p (the fan
 * triangle that holds p best, as the bake picks it). */
static void base_at(const base_geo *g, uint32_t f, const double p[2], double pos[3], double n[3])
{
    uint32_t a = g->uvs->corner_off[f], deg = g->uvs->corner_off[f + 1] - a;
    double best = -INFINITY, bw[3] = { 1, 0, 0 };
    uint32_t bi[3] = { a, a, a };
    for (uint32_t t = 0; t + 2 < deg; t++) {
        uint32_t idx[3] = { a, a + t + 1, a + t + 2 };
        double tri[3][2], w[3];
        for (int k = 0; k < 3; k++) memcpy(tri[k], g->uvs->uv + 2 * (size_t)idx[k], sizeof tri[k]);
        if (!st_bake_barycentric(tri, p, w)) continue;
        double lo = fmin(w[0], fmin(w[1], w[2]));
        if (lo > best) { best = lo; memcpy(bw, w, sizeof bw); memcpy(bi, idx, sizeof bi); }
    }
    for (int k = 0; k < 3; k++) pos[k] = n[k] = 0;
    for (int j = 0; j < 3; j++) {
        const double *q = st_pos(&g->h->map, g->cvert[bi[j]], g->B), *cn = g->cnormal + 3 * (size_t)bi[j];
        for (int k = 0; k < 3; k++) { pos[k] += bw[j] * q[k]; n[k] += bw[j] * cn[k]; }
    }
    normalize3(n);
}

static int set_target(void *ctx, const uint32_t *verts, const double *uv, unsigned n)
{
    base_geo *g = ctx;
    for (unsigned c = 0; c < n; c++) {
        double p[3], nn[3];
        base_at(g, g->face, uv + 2 * c, p, nn);
        double h = bump(p), *t = g->target + 3 * (size_t)verts[c];
        for (int k = 0; k < 3; k++) t[k] = p[k] + h * nn[k];
        g->has_target[verts[c]] = 1;
    }
    return ST_OK;
}

static void corner_data(base_geo *g)
{
    st_map *m = &g->h->map;
    uint32_t *darts, nf;
    st_error err;
    CHECK(st_bake_level_faces(m, g->B, &darts, &nf, &err) == ST_OK);
    size_t nc = g->uvs->corner_off[nf];
    g->cvert = malloc(nc * sizeof *g->cvert);
    g->cnormal = malloc(3 * nc * sizeof *g->cnormal);
    double *tan = malloc(4 * nc * sizeof *tan);
    CHECKF(st_bake_tangents(g->h, g->B, g->uvs, tan, g->cnormal, &err) == ST_OK, "%s", err.msg);
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t x = darts[f];
        for (uint32_t k = g->uvs->corner_off[f]; k < g->uvs->corner_off[f + 1]; k++, x = st_face_step(m, x, g->B))
            g->cvert[k] = st_vert(m, x, g->B);
    }
    free(tan);
    free(darts);
}

/* Moves every vertex of level L to base point + bump · base normal, through
 * the editing API (details stay consistent). */
static void displace_level(base_geo *g, unsigned L)
{
    st_map *m = &g->h->map;
    uint32_t *darts, nf;
    st_error err;
    CHECK(st_bake_level_faces(m, g->B, &darts, &nf, &err) == ST_OK);
    g->target = calloc(3 * (size_t)m->verts.end, sizeof *g->target);
    g->has_target = calloc(m->verts.end, 1);
    for (uint32_t f = 0; f < nf; f++) {
        g->face = f;
        uint32_t a = g->uvs->corner_off[f];
        int rc = st_bake_walk(m, darts[f], g->B, L, g->uvs->uv + 2 * (size_t)a, g->uvs->corner_off[f + 1] - a, set_target, g, &err);
        CHECKF(rc == ST_OK, "%s", err.msg);
    }
    uint32_t *vd = malloc(m->verts.end * sizeof *vd), n = 0;
    double (*pos)[3] = malloc(m->verts.end * sizeof *pos);
    uint8_t *seen = calloc(m->verts.end, 1);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
        uint32_t v = st_vert(m, d, L);
        if (seen[v] || !g->has_target[v]) continue;
        seen[v] = 1;
        vd[n] = d;
        memcpy(pos[n], g->target + 3 * (size_t)v, sizeof pos[n]);
        n++;
    }
    st_hier_move(g->h, L, vd, (const double (*)[3])pos, n);
    free(vd);
    free(pos);
    free(seen);
    free(darts);
}

typedef struct expect_ctx {
    base_geo *g;
    const st_bake_maps *maps;
    double max_err, lo, hi;
    uint64_t compared;
} expect_ctx;

static void compare_texel(void *pc, uint32_t x, uint32_t y, const double w[3])
{
    (void)w;
    expect_ctx *e = pc;
    size_t i = (size_t)y * e->maps->size + x;
    if (e->maps->mask[i] != 1) return;
    double p[2] = { (x + 0.5) / e->maps->size, (y + 0.5) / e->maps->size }, pos[3], n[3];
    base_at(e->g, e->g->face, p, pos, n);
    double want = bump(pos);
    e->lo = fmin(e->lo, want);
    e->hi = fmax(e->hi, want);
    e->max_err = fmax(e->max_err, fabs(e->maps->disp[i] - want));
    e->compared++;
}

/* Bakes level L of h (displaced as above) onto B with uvs and compares. */
static void check_analytic(const char *what, st_hier *h, unsigned B, unsigned L, const st_bake_uvs *uvs, uint32_t size)
{
    base_geo g = { .h = h, .B = B, .uvs = uvs };
    corner_data(&g);
    displace_level(&g, L);
    st_bake_opts o = { .base = B, .level = L, .size = size, .space = ST_BAKE_TANGENT, .normal = 1, .displacement = 1, .padding = 4 };
    st_bake_maps maps;
    st_error err;
    int rc = st_bake(h, uvs, &o, &maps, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, err.msg);
    if (rc) return;
    expect_ctx e = { .g = &g, .maps = &maps, .lo = INFINITY, .hi = -INFINITY };
    for (uint32_t f = 0; f < uvs->nfaces; f++) {
        g.face = f;
        uint32_t a = uvs->corner_off[f], deg = uvs->corner_off[f + 1] - a;
        for (uint32_t t = 0; t + 2 < deg; t++) {
            double tri[3][2];
            uint32_t idx[3] = { a, a + t + 1, a + t + 2 };
            for (int k = 0; k < 3; k++) memcpy(tri[k], uvs->uv + 2 * (size_t)idx[k], sizeof tri[k]);
            st_bake_raster_tri(tri, size, compare_texel, &e);
        }
    }
    double range = e.hi - e.lo;
    printf("%s: B=%u L=%u %ux%u: %llu texels baked, %llu padded, %llu compared; displacement range %.5f, "
           "max error %.3g (%.3f %% of the range)\n",
           what, B, L, size, size, (unsigned long long)maps.baked, (unsigned long long)maps.padded,
           (unsigned long long)e.compared, range, e.max_err, 100 * e.max_err / range);
    CHECKF(e.compared > maps.baked * 99 / 100, "%s: %llu of %llu baked texels compared", what,
           (unsigned long long)e.compared, (unsigned long long)maps.baked);
    CHECKF(range > 0.05, "%s: range %g", what, range);
    CHECKF(e.max_err < 0.01 * range, "%s: max error %g >= 1 %% of range %g", what, e.max_err, range);
    CHECK(maps.padded > 0);
    /* The same bake twice gives the same maps, to the bit. */
    st_bake_maps again;
    CHECK(st_bake(h, uvs, &o, &again, &err) == ST_OK);
    size_t tx = (size_t)size * size;
    CHECK(!memcmp(again.disp, maps.disp, tx * sizeof(float)) && !memcmp(again.normal, maps.normal, 3 * tx * sizeof(float)));
    st_bake_maps_free(&again);
    /* --vector: the normal component is the scalar map; the displacement is
     * along the normal, so the tangential ones stay within the
     * discretisation error too. */
    o.displacement = 3;
    CHECK(st_bake(h, uvs, &o, &again, &err) == ST_OK);
    double worst_n = 0, worst_t = 0;
    for (size_t i = 0; i < tx; i++) {
        if (maps.mask[i] != 1) continue;
        worst_n = fmax(worst_n, fabs(again.disp[3 * i + 2] - maps.disp[i]));
        worst_t = fmax(worst_t, fmax(fabs(again.disp[3 * i]), fabs(again.disp[3 * i + 1])));
    }
    printf("%s: vector displacement: normal component off the scalar by %.2g, tangential up to %.2g (%.3f %% of the range)\n",
           what, worst_n, worst_t, 100 * worst_t / range);
    CHECK(worst_n < 1e-6);
    CHECK(worst_t < 0.01 * range);
    st_bake_maps_free(&again);
    st_bake_maps_free(&maps);
    free(g.cvert);
    free(g.cnormal);
    free(g.target);
    free(g.has_target);
}

/* Toroidal unwrap of the test torus (major axis z): u around z, v around the
 * tube, seams where the angles wrap, kept inside [0.02, 0.98]. */
static void torus_uvs(st_hier *h, unsigned l, st_bake_layout *out)
{
    st_map *m = &h->map;
    uint32_t *darts, nf;
    st_error err;
    CHECK(st_bake_level_faces(m, l, &darts, &nf, &err) == ST_OK);
    out->nfaces = nf;
    out->corner_off = malloc(((size_t)nf + 1) * sizeof *out->corner_off);
    out->corner_off[0] = 0;
    for (uint32_t f = 0; f < nf; f++) out->corner_off[f + 1] = out->corner_off[f] + st_face_degree(m, darts[f], l);
    out->uv = malloc(2 * (size_t)out->corner_off[nf] * sizeof *out->uv);
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t a = out->corner_off[f], n = out->corner_off[f + 1] - a, x = darts[f];
        double *uv = out->uv + 2 * (size_t)a;
        for (uint32_t c = 0; c < n; c++, x = st_phi1(m, x, l)) {
            const double *p = st_dart_pos(m, x, l);
            double r = sqrt(p[0] * p[0] + p[1] * p[1]);
            double ang[2] = { atan2(p[1], p[0]), atan2(p[2], r - 2) };
            for (int k = 0; k < 2; k++) {
                double t = ang[k] / (2 * M_PI);
                if (t < -1e-9) t += 1;
                uv[2 * c + k] = t < 0 ? 0 : t;
            }
        }
        for (int k = 0; k < 2; k++) {
            double hi = 0;
            for (uint32_t c = 0; c < n; c++) hi = fmax(hi, uv[2 * c + k]);
            for (uint32_t c = 0; c < n; c++)
                if (hi - uv[2 * c + k] > 0.5) uv[2 * c + k] += 1;
            for (uint32_t c = 0; c < n; c++) uv[2 * c + k] = 0.02 + 0.96 * uv[2 * c + k];
        }
    }
    free(darts);
}

static void make_torus(st_mesh *m) { tl_mesh_torus(m, 12, 8); }

static void test_analytic(void)
{
    st_hier h;
    st_error err;
    tl_init_hier(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 4);
    st_bake_layout lay;
    CHECKF(st_bake_auto_uvs(&h, 1, &lay, &err) == ST_OK, "%s", err.msg);
    st_bake_uvs u = st_bake_layout_uvs(&lay);
    check_analytic("cube catmull-clark, per-face atlas", &h, 1, 4, &u, 256);
    st_bake_layout_free(&lay);
    st_hier_free(&h);

    tl_init_hier(&h, make_torus, ST_SCHEME_CATMARK, 4);
    torus_uvs(&h, 0, &lay);
    u = st_bake_layout_uvs(&lay);
    check_analytic("torus catmull-clark, toroidal unwrap with seams", &h, 0, 4, &u, 256);
    st_bake_layout_free(&lay);
    st_hier_free(&h);

    tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, 4);
    CHECKF(st_bake_auto_uvs(&h, 1, &lay, &err) == ST_OK, "%s", err.msg);
    u = st_bake_layout_uvs(&lay);
    check_analytic("icosahedron loop, per-face atlas", &h, 1, 4, &u, 512);
    st_bake_layout_free(&lay);
    st_hier_free(&h);
}

/* Level B onto itself: the fine normal is B's own, so the tangent-space map
 * is (0, 0, 1) and the displacement 0; tangents are unit, orthogonal to the
 * normal and point along dP/du on the cube's flat faces. */
static void test_identity_and_tangents(void)
{
    st_hier h;
    st_error err;
    tl_init_hier(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 2);
    st_bake_layout lay;
    CHECK(st_bake_auto_uvs(&h, 0, &lay, &err) == ST_OK);
    st_bake_uvs u = st_bake_layout_uvs(&lay);
    size_t nc = lay.corner_off[lay.nfaces];
    CHECK(lay.nfaces == 6 && nc == 24);
    double *tan = malloc(4 * nc * sizeof *tan), *nrm = malloc(3 * nc * sizeof *nrm);
    CHECK(st_bake_tangents(&h, 0, &u, tan, nrm, &err) == ST_OK);
    uint32_t *darts, nf;
    CHECK(st_bake_level_faces(&h.map, 0, &darts, &nf, &err) == ST_OK);
    double worst_orth = 0, worst_dir = 1;
    for (uint32_t f = 0; f < nf; f++) {
        /* dP/du of the face from its first triangle. */
        uint32_t a = lay.corner_off[f];
        const double *p0 = st_dart_pos(&h.map, darts[f], 0), *p1 = st_dart_pos(&h.map, st_phi1(&h.map, darts[f], 0), 0);
        const double *p2 = st_dart_pos(&h.map, st_phi1(&h.map, st_phi1(&h.map, darts[f], 0), 0), 0);
        const double *t0 = lay.uv + 2 * a, *t1 = t0 + 2, *t2 = t0 + 4;
        double du1 = t1[0] - t0[0], dv1 = t1[1] - t0[1], du2 = t2[0] - t0[0], dv2 = t2[1] - t0[1], r = du1 * dv2 - du2 * dv1;
        double dpdu[3];
        for (int k = 0; k < 3; k++) dpdu[k] = ((p1[k] - p0[k]) * dv2 - (p2[k] - p0[k]) * dv1) / r;
        normalize3(dpdu);
        for (uint32_t c = a; c < lay.corner_off[f + 1]; c++) {
            const double *t = tan + 4 * c, *n = nrm + 3 * c;
            worst_orth = fmax(worst_orth, fabs(dot3(t, n)));
            CHECK(fabs(dot3(t, t) - 1) < 1e-12 && (t[3] == 1 || t[3] == -1));
            /* The corner normal is the vertex's (diagonal on the cube), so
             * the tangent is dP/du made orthogonal to it. */
            double d = dot3(dpdu, n), pr[3] = { dpdu[0] - d * n[0], dpdu[1] - d * n[1], dpdu[2] - d * n[2] };
            normalize3(pr);
            worst_dir = fmin(worst_dir, dot3(pr, t));
        }
    }
    CHECKF(worst_orth < 1e-12, "tangent·normal up to %g", worst_orth);
    CHECKF(worst_dir > 1 - 1e-12, "tangent off dP/du: cos %g", worst_dir);
    free(darts);
    free(tan);
    free(nrm);

    st_bake_opts o = { .base = 0, .level = 0, .size = 64, .space = ST_BAKE_TANGENT, .normal = 1, .displacement = 3, .padding = 2 };
    st_bake_maps maps;
    CHECKF(st_bake(&h, &u, &o, &maps, &err) == ST_OK, "%s", err.msg);
    double worst_n = 0, worst_d = 0;
    for (size_t i = 0; i < (size_t)64 * 64; i++) {
        if (maps.mask[i] != 1) continue;
        worst_n = fmax(worst_n, fabs(maps.normal[3 * i]) + fabs(maps.normal[3 * i + 1]) + fabs(maps.normal[3 * i + 2] - 1));
        for (int k = 0; k < 3; k++) worst_d = fmax(worst_d, fabs(maps.disp[3 * i + k]));
    }
    printf("level 0 onto itself: %llu texels, normal off (0,0,1) by %.2g, displacement up to %.2g\n",
           (unsigned long long)maps.baked, worst_n, worst_d);
    CHECK(maps.baked > 1000);
    CHECK(worst_n < 1e-5 && worst_d < 1e-5);
    /* Padding reaches 2 texels beyond the islands and no further. */
    uint64_t pad2 = maps.padded;
    st_bake_maps_free(&maps);
    o.padding = 0;
    CHECK(st_bake(&h, &u, &o, &maps, &err) == ST_OK);
    CHECK(maps.padded == 0 && pad2 > 0);
    st_bake_maps_free(&maps);
    st_bake_layout_free(&lay);
    st_hier_free(&h);
}

static void expect_refusal(st_hier *h, const st_bake_uvs *u, const st_bake_opts *o, const char *pattern)
{
    st_bake_maps maps;
    st_error err;
    int rc = st_bake(h, u, o, &maps, &err);
    CHECKF(rc != ST_OK && strstr(err.msg, pattern), "expected a refusal with '%s', got %d '%s'", pattern, rc, rc ? err.msg : "");
    CHECK(maps.normal == NULL && maps.disp == NULL && maps.mask == NULL);
}

static void test_refusals(void)
{
    st_hier h;
    st_error err;
    tl_init_hier(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 2);
    st_bake_layout lay;
    CHECK(st_bake_auto_uvs(&h, 0, &lay, &err) == ST_OK);
    st_bake_uvs u = st_bake_layout_uvs(&lay);
    st_bake_opts o = { .base = 0, .level = 2, .size = 32, .normal = 1, .padding = 2 };

    expect_refusal(&h, NULL, &o, "has no UVs");
    /* Face 2 laid over face 1. */
    double saved[8];
    memcpy(saved, lay.uv + 8, sizeof saved);
    memcpy(lay.uv + 8, lay.uv, sizeof saved);
    expect_refusal(&h, &u, &o, "UV islands overlap: faces 1 and 2 of level 0");
    memcpy(lay.uv + 8, saved, sizeof saved);
    lay.uv[5] = NAN;
    expect_refusal(&h, &u, &o, "face 1 of level 0: corner 3 has no UV");
    /* A corner beyond the tile is no refusal any more (issue 31; overshoots
     * are baked with wrap-around, test_udim_tiles), but face 1 stretched to
     * v = 1.5 lies across face 4's cell inside its own tile: an overlap. */
    lay.uv[5] = 1.5;
    expect_refusal(&h, &u, &o, "UV islands overlap: faces 1 and 4 of level 0");
    lay.uv[5] = 3e6;
    expect_refusal(&h, &u, &o, "face 1 of level 0: corner 3 has UV (0.");
    lay.uv[5] = 9.5;
    expect_refusal(&h, &u, &o, "face 1 of level 0 spans 1 x 10 UV tiles");
    memcpy(lay.uv + 8, saved, sizeof saved);
    lay.uv[5] = lay.uv[3];
    u.nfaces = 5;
    expect_refusal(&h, &u, &o, "describe 5 faces but level 0 has 6");
    u.nfaces = 6;
    o.base = 1;
    expect_refusal(&h, &u, &o, "describe 6 faces but level 1 has 24");
    o.base = 3;
    expect_refusal(&h, &u, &o, "levels are 0..2");
    st_bake_layout_free(&lay);
    st_hier_free(&h);

    /* Progressive hierarchies (levels by edge collapses) are refused. */
    tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, 2);
    st_mesh fine;
    st_mesh_init(&fine);
    CHECK(st_hier_level_mesh(&h, 2, &fine, &err) == ST_OK);
    st_hier_free(&h);
    st_progressive_opts po = { .target_faces = 40 };
    CHECKF(st_progressive_build(&fine, &po, &h, NULL, &err) == ST_OK, "%s", err.msg);
    CHECK(st_bake_auto_uvs(&h, 0, &lay, &err) == ST_OK);
    u = st_bake_layout_uvs(&lay);
    o.base = 0;
    o.level = h.map.top;
    expect_refusal(&h, &u, &o, "edge collapses");
    st_bake_layout_free(&lay);
    st_hier_free(&h);
    st_mesh_free(&fine);
    /* A reach that is not a distance. */
    tl_init_hier(&h, tl_mesh_octa, ST_SCHEME_SQRT3, 2);
    CHECK(st_bake_auto_uvs(&h, 0, &lay, &err) == ST_OK);
    u = st_bake_layout_uvs(&lay);
    o.level = 2;
    o.ray_reach = -1;
    expect_refusal(&h, &u, &o, "reach");
    o.ray_reach = NAN;
    expect_refusal(&h, &u, &o, "reach");
    st_bake_layout_free(&lay);
    st_hier_free(&h);
}

/* The walk's level-L faces tile their level-B face in UV: their signed
 * areas have the parent's sign and add up to the parent's area, and their
 * count is the split's (n·4^(k-1) quads for the polygon split of an n-gon,
 * 4^k triangles for quadrisection). */
typedef struct tile_ctx { double area; uint32_t faces; int flipped; double parent_sign; } tile_ctx;

static double signed_area(const double *uv, unsigned n)
{
    double a = 0;
    for (unsigned c = 0; c < n; c++) {
        const double *p = uv + 2 * c, *q = uv + 2 * ((c + 1) % n);
        a += p[0] * q[1] - q[0] * p[1];
    }
    return 0.5 * a;
}

static int add_tile(void *pc, const uint32_t *verts, const double *uv, unsigned n)
{
    (void)verts;
    tile_ctx *t = pc;
    double a = signed_area(uv, n);
    if (!(a * t->parent_sign > 0)) t->flipped++;
    t->area += a;
    t->faces++;
    return ST_OK;
}

static void check_tiling(const char *what, st_scheme_id id, void (*make)(st_mesh *), unsigned B, unsigned L)
{
    st_hier h;
    st_error err;
    tl_init_hier(&h, make, id, L);
    st_bake_layout lay;
    CHECK(st_bake_auto_uvs(&h, B, &lay, &err) == ST_OK);
    uint32_t *darts, nf;
    CHECK(st_bake_level_faces(&h.map, B, &darts, &nf, &err) == ST_OK);
    double worst = 0;
    uint64_t total = 0;
    int bad_count = 0, flipped = 0;
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t a = lay.corner_off[f], n = lay.corner_off[f + 1] - a;
        double parent = signed_area(lay.uv + 2 * (size_t)a, n);
        tile_ctx t = { 0, 0, 0, parent > 0 ? 1 : -1 };
        CHECKF(st_bake_walk(&h.map, darts[f], B, L, lay.uv + 2 * (size_t)a, n, add_tile, &t, &err) == ST_OK, "%s", err.msg);
        worst = fmax(worst, fabs(t.area - parent) / fabs(parent));
        unsigned k = L - B;
        uint64_t want = 1;
        for (unsigned i = 0; i < k; i++) want *= 4;
        unsigned child_deg = st_face_degree(&h.map, darts[f], B + (k ? 1 : 0));
        if (k && child_deg == 4) want = want / 4 * n;
        if (t.faces != want) bad_count++;
        flipped += t.flipped;
        total += t.faces;
    }
    printf("%s: %u faces of level %u tile into %llu of level %u; area off by %.2g (relative), %d flipped\n",
           what, nf, B, (unsigned long long)total, L, worst, flipped);
    CHECK(worst < 1e-12 && !bad_count && !flipped);
    st_level_stats st;
    st_level_stats_compute(&h.map, L, &st);
    CHECKF(total == st.faces, "%s: %llu faces walked, level %u has %llu", what, (unsigned long long)total, L, (unsigned long long)st.faces);
    free(darts);
    st_bake_layout_free(&lay);
    st_hier_free(&h);
}

static void mixed_mesh(st_mesh *m)
{
    /* A quad and two triangles around it (an open strip). */
    static const double p[] = { 0, 0, 0, 1, 0, 0, 1, 1, 0.2, 0, 1, 0, 2, 0.5, 0, -1, 0.5, 0.1 };
    static const uint32_t off[] = { 0, 4, 7, 10 }, idx[] = { 0, 1, 2, 3, 1, 4, 2, 3, 5, 0 };
    tl_mesh_make(m, p, 6, off, idx, 3);
}

static void test_walk_tiles(void)
{
    check_tiling("cube catmull-clark", ST_SCHEME_CATMARK, tl_mesh_cube, 0, 3);
    check_tiling("tetrahedron catmull-clark (triangles into quads)", ST_SCHEME_CATMARK, tl_mesh_tetra, 0, 2);
    check_tiling("icosahedron loop", ST_SCHEME_LOOP, tl_mesh_icosa, 1, 3);
    check_tiling("octahedron butterfly", ST_SCHEME_BUTTERFLY, tl_mesh_octa, 0, 3);
    check_tiling("quad and triangles quad-triangle", ST_SCHEME_QUADTRI, mixed_mesh, 0, 3);
    check_tiling("cube onto itself", ST_SCHEME_CATMARK, tl_mesh_cube, 2, 2);
}

/* ---- faces concave in UV -------------------------------------------------- */

/* The split of a UV polygon: n-2 triangles, each in the polygon's
 * orientation (none flipped), their areas adding up to the polygon's (so
 * they cover it once), corner indices in range. */
static void check_split(const char *what, const double *uv, unsigned n, const uint32_t (*want)[3])
{
    uint32_t tri[16][3];
    unsigned k = st_bake_split_polygon(uv, n, tri);
    double area = signed_area(uv, n), sum = 0;
    int flipped = 0, range = 0, differs = 0;
    for (unsigned t = 0; t < k; t++) {
        double c[6];
        for (int j = 0; j < 3; j++) {
            range |= tri[t][j] >= n;
            c[2 * j] = uv[2 * tri[t][j] % (2 * n)];
            c[2 * j + 1] = uv[(2 * tri[t][j] + 1) % (2 * n)];
            if (want) differs |= tri[t][j] != want[t][j];
        }
        double a = signed_area(c, 3);
        flipped += a * area <= 0;
        sum += a;
    }
    CHECKF(k == n - 2 && !range && !flipped && fabs(sum - area) < 1e-15, "%s: %u triangles, %d flipped, areas %.17g of %.17g",
           what, k, flipped, sum, area);
    CHECKF(!differs, "%s: not the expected triangles", what);
}

static void test_split_polygon(void)
{
    /* Convex: the fan from corner 0 (the split every convex face had before). */
    static const double square[] = { 0, 0, 1, 0, 1, 1, 0, 1 };
    static const uint32_t fan4[2][3] = { { 0, 1, 2 }, { 0, 2, 3 } };
    check_split("convex quad", square, 4, fan4);
    /* Reflex corner 1: the diagonal 1-3 through it, not 0-2 across the notch. */
    static const double dart1[] = { 0.1, 0.1, 0.5, 0.25, 0.9, 0.1, 0.5, 0.9 };
    static const uint32_t via1[2][3] = { { 3, 0, 1 }, { 1, 2, 3 } };
    check_split("quad concave at corner 1", dart1, 4, via1);
    static const double dart3[] = { 0.5, 0.9, 0.1, 0.1, 0.5, 0.25, 0.9, 0.1 };  /* same shape, reflex corner 2: fan valid */
    check_split("quad concave at corner 2", dart3, 4, fan4);
    static const double dart3cw[] = { 0.5, 0.9, 0.9, 0.1, 0.5, 0.25, 0.1, 0.1 };  /* clockwise, reflex corner 2 */
    check_split("clockwise quad concave at corner 2", dart3cw, 4, fan4);
    static const double dart_b[] = { 0.9, 0.1, 0.5, 0.9, 0.1, 0.1, 0.5, 0.25 };  /* reflex corner 3 */
    check_split("quad concave at corner 3", dart_b, 4, NULL);
    /* n-gons: an L and a comb, concave at several corners. */
    static const double ell[] = { 0, 0, 1, 0, 1, 0.4, 0.4, 0.4, 0.4, 1, 0, 1 };
    check_split("L hexagon", ell, 6, NULL);
    static const double ell_rot[] = { 0.4, 0.4, 0.4, 1, 0, 1, 0, 0, 1, 0, 1, 0.4 };
    check_split("L hexagon from its reflex corner", ell_rot, 6, NULL);
    static const double comb[] = { 0, 0, 1, 0, 1, 1, 0.8, 1, 0.7, 0.3, 0.6, 1, 0.4, 1, 0.3, 0.3, 0.2, 1, 0, 1 };
    check_split("comb decagon", comb, 10, NULL);
}

/* A quad concave in UV (corner 1 reflex) and the triangle that fills its
 * notch: their UVs tile the triangle A C D without overlap.  Splitting the
 * quad across the notch (the fan from corner 0) made it cover the
 * triangle's texels: a false "UV islands overlap". */
static const char *concave_obj =
    "v 0.1 0.1 0\nv 0.5 0.25 0.1\nv 0.9 0.1 0\nv 0.5 0.9 0.05\n"
    "vt 0.1 0.1\nvt 0.5 0.25\nvt 0.9 0.1\nvt 0.5 0.9\nvt 0.1 0.1\nvt 0.9 0.1\nvt 0.5 0.25\n"
    "f 1/1 2/2 3/3 4/4\nf 1/5 3/6 2/7\n";

static void test_concave_quad_bake(void)
{
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    CHECKF(st_mesh_parse_obj("concave.obj", concave_obj, strlen(concave_obj), &m, &err) == 0 &&
           st_mesh_repair("concave.obj", &m, NULL, &err) == 0, "%s", err.msg);
    st_hier h;
    CHECKF(st_hier_init(&h, &m, &st_scheme_catmark, NULL, &err) == 0 && st_hier_subdivide_to(&h, 2, &err) == 0, "%s", err.msg);
    st_bake_layout lay;
    CHECKF(st_bake_level_uvs(&h, 0, &lay, &err) == ST_OK, "%s", err.msg);
    st_bake_uvs u = st_bake_layout_uvs(&lay);
    const uint32_t size = 64;
    st_bake_opts o = { .base = 0, .level = 0, .size = size, .space = ST_BAKE_TANGENT, .normal = 1, .padding = 0 };
    /* Texel centres inside A C D (0.1,0.1) (0.9,0.1) (0.5,0.9): what the two faces cover. */
    uint64_t inside = 0;
    for (uint32_t y = 0; y < size; y++)
        for (uint32_t x = 0; x < size; x++) {
            double p[2] = { (x + 0.5) / size, (y + 0.5) / size };
            inside += p[1] > 0.1 && p[1] < 0.1 + 2 * (p[0] - 0.1) && p[1] < 0.1 + 2 * (0.9 - p[0]);
        }
    for (unsigned level = 0; level <= 2; level += 2) {
        o.level = level;
        st_bake_maps maps;
        int rc = st_bake(&h, &u, &o, &maps, &err);
        CHECKF(rc == ST_OK, "level %u onto 0: %s", level, rc ? err.msg : "");
        if (rc) continue;
        printf("concave quad and its notch, level %u onto 0: %llu texels baked, %llu centres inside\n",
               level, (unsigned long long)maps.baked, (unsigned long long)inside);
        CHECK(maps.baked + 2 >= inside && maps.baked <= inside + 2);
        st_bake_maps_free(&maps);
    }
    /* A real overlap is still refused: the triangle's corner B moved into the quad. */
    CHECK(lay.nfaces == 2 && lay.corner_off[2] == 7);
    double saved = lay.uv[2 * 6 + 1];
    lay.uv[2 * 6 + 1] = 0.6;
    expect_refusal(&h, &u, &o, "UV islands overlap: faces 1 and 2 of level 0");
    lay.uv[2 * 6 + 1] = saved;
    st_bake_layout_free(&lay);
    st_hier_free(&h);
    st_mesh_free(&m);
}

/* Doo-Sabin's dual encoding: the layout of a level (the one glTF export
 * with a normal map writes) lists st_hier_level_mesh's faces and corner
 * UVs, and its tangents are unit and orthogonal to the normals. */
static void test_dual_layout(void)
{
    st_mesh m;
    st_error err;
    st_mesh_init(&m);
    CHECK(st_mesh_parse_obj("concave.obj", concave_obj, strlen(concave_obj), &m, &err) == 0 &&
          st_mesh_repair("concave.obj", &m, NULL, &err) == 0);
    st_hier h;
    CHECKF(st_hier_init(&h, &m, &st_scheme_doosabin, NULL, &err) == 0 && st_hier_subdivide_to(&h, 2, &err) == 0, "%s", err.msg);
    for (unsigned l = 0; l <= 2; l++) {
        st_mesh lm;
        st_mesh_init(&lm);
        st_bake_layout lay;
        CHECK(st_hier_level_mesh(&h, l, &lm, &err) == 0 && lm.face_uv);
        CHECKF(st_bake_level_uvs(&h, l, &lay, &err) == ST_OK, "%s", err.msg);
        int same = lay.nfaces == lm.nfaces && lm.face_uv;
        for (uint32_t f = 0; same && f < lm.nfaces; f++) same = lay.corner_off[f + 1] == lm.face_off[f + 1];
        for (uint32_t c = 0; same && c < lm.face_off[lm.nfaces]; c++)
            same = lay.uv[2 * c] == lm.uv[2 * lm.face_uv[c]] && lay.uv[2 * c + 1] == lm.uv[2 * lm.face_uv[c] + 1];
        CHECKF(same, "doo-sabin level %u: layout of %u faces against the level's %u", l, lay.nfaces, lm.nfaces);
        size_t nc = lay.corner_off[lay.nfaces];
        double *tan = malloc(4 * (nc + 1) * sizeof *tan), *nrm = malloc(3 * (nc + 1) * sizeof *nrm);
        st_bake_uvs u = st_bake_layout_uvs(&lay);
        CHECKF(st_bake_tangents(&h, l, &u, tan, nrm, &err) == ST_OK, "%s", err.msg);
        double worst = 0;
        for (size_t c = 0; c < nc; c++)
            worst = fmax(worst, fabs(dot3(tan + 4 * c, tan + 4 * c) - 1) + fabs(dot3(tan + 4 * c, nrm + 3 * c)));
        CHECKF(worst < 1e-12, "doo-sabin level %u: tangents off unit/orthogonal by %g", l, worst);
        free(tan);
        free(nrm);
        st_bake_layout_free(&lay);
        st_mesh_free(&lm);
    }
    st_hier_free(&h);
    st_mesh_free(&m);
}

/* ---- by rays (√3, Doo-Sabin; or asked for) -------------------------------- */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* The nearest facing hit by trying every triangle: the plane's crossing,
 * then the point's barycentric weights from areas (another formula than
 * the hierarchy's Möller-Trumbore). */
static uint32_t brute_nearest(const st_bake_bvh *b, const double o[3], const double d[3], double reach, double *t_out)
{
    uint32_t best = ST_NIL;
    double bt = 0;
    for (uint32_t t = 0; t < b->ntris; t++) {
        const double *p[3];
        for (int k = 0; k < 3; k++) p[k] = st_pos(b->m, b->tri_vert[3 * (size_t)t + k], b->level);
        double e1[3], e2[3], ng[3];
        for (int k = 0; k < 3; k++) { e1[k] = p[1][k] - p[0][k]; e2[k] = p[2][k] - p[0][k]; }
        ng[0] = e1[1] * e2[2] - e1[2] * e2[1];
        ng[1] = e1[2] * e2[0] - e1[0] * e2[2];
        ng[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double dn = dot3(d, ng);
        if (!(dn > 0)) continue;
        double r[3] = { p[0][0] - o[0], p[0][1] - o[1], p[0][2] - o[2] };
        double tt = dot3(r, ng) / dn;
        if (fabs(tt) > reach) continue;
        double q[3] = { o[0] + tt * d[0], o[1] + tt * d[1], o[2] + tt * d[2] };
        int inside = 1;
        for (int k = 0; k < 3 && inside; k++) {
            const double *a = p[k], *c = p[(k + 1) % 3];
            double ea[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] }, qa[3] = { q[0] - a[0], q[1] - a[1], q[2] - a[2] }, x[3];
            x[0] = ea[1] * qa[2] - ea[2] * qa[1];
            x[1] = ea[2] * qa[0] - ea[0] * qa[2];
            x[2] = ea[0] * qa[1] - ea[1] * qa[0];
            inside = dot3(x, ng) >= 0;
        }
        if (!inside) continue;
        if (best == ST_NIL || fabs(tt) < fabs(bt)) { best = t; bt = tt; }
    }
    *t_out = bt;
    return best;
}

static uint32_t count_nodes(const st_bake_bvh *b, uint32_t node, uint32_t *leaf_tris)
{
    if (b->node_count[node]) { *leaf_tris += b->node_count[node]; return 1; }
    return 1 + count_nodes(b, b->node_first[node], leaf_tris) + count_nodes(b, b->node_first[node] + 1, leaf_tris);
}

/* The hierarchy finds the hit that trying every triangle finds, for lines
 * through random points in random directions; its node and triangle counts
 * are the formulas the memory estimate uses. */
static void check_bvh(const char *what, st_scheme_id id, void (*make)(st_mesh *), unsigned L)
{
    st_hier h;
    st_error err;
    tl_init_hier(&h, make, id, L);
    st_bake_bvh b;
    CHECKF(st_bake_bvh_build(&h.map, L, &b, &err) == ST_OK, "%s", err.msg);
    uint32_t leaf_tris = 0, nodes = count_nodes(&b, 0, &leaf_tris);
    CHECKF(b.ntris == st_bake_level_triangles(&h.map, L) && nodes == b.nnodes && nodes == st_bake_bvh_nodes(b.ntris) &&
           leaf_tris == b.ntris, "%s: %u triangles (counted %llu), %u nodes reached of %u (formula %llu)", what, b.ntris,
           (unsigned long long)st_bake_level_triangles(&h.map, L), nodes, b.nnodes, (unsigned long long)st_bake_bvh_nodes(b.ntris));
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t t = 0; t < b.ntris; t++)
        for (int k = 0; k < 3; k++) {
            const double *p = st_pos(&h.map, b.tri_vert[3 * (size_t)t + k], L);
            for (int j = 0; j < 3; j++) { lo[j] = fmin(lo[j], p[j]); hi[j] = fmax(hi[j], p[j]); }
        }
    unsigned hits = 0, same = 0, rays = 3000;
    double reach = 0.4 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    for (unsigned r = 0; r < rays; r++) {
        double o[3], d[3];
        for (int k = 0; k < 3; k++) { o[k] = lo[k] + rnd() * (hi[k] - lo[k]); d[k] = 2 * rnd() - 1; }
        normalize3(d);
        st_bake_hit hit;
        double bt;
        int got = st_bake_bvh_nearest(&b, o, d, reach, &hit);
        uint32_t want = brute_nearest(&b, o, d, reach, &bt);
        hits += got;
        same += (!got && want == ST_NIL) || (got && want == hit.tri && fabs(bt - hit.t) < 1e-9);
    }
    printf("%s: %u triangles, %u nodes; %u random lines, %u hits, %u as trying every triangle\n", what, b.ntris, b.nnodes,
           rays, hits, same);
    CHECK(hits > rays / 4 && same == rays);
    st_bake_bvh_free(&b);
    st_hier_free(&h);
}

/* Texels whose 5 × 5 neighbourhood is baked in both maps: away from the
 * islands' borders. */
static int interior(const st_bake_maps *a, uint32_t x, uint32_t y)
{
    int s = (int)a->size;
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++) {
            int xx = (int)x + dx, yy = (int)y + dy;
            if (xx < 0 || yy < 0 || xx >= s || yy >= s || a->mask[(size_t)yy * s + xx] != 1) return 0;
        }
    return 1;
}

/* The same level baked by the exact correspondence and by rays: the
 * displacement within disp_tol of its range and the normals within
 * mean_tol / max_tol per channel (unit vectors) on interior texels; the
 * rays on 1 and 3 threads give the same bits. */
static void compare_paths(const char *what, st_hier *h, unsigned B, unsigned L, const st_bake_uvs *uvs, uint32_t size,
                          double disp_tol, double mean_tol, double max_tol)
{
    st_error err;
    st_bake_opts o = { .base = B, .level = L, .size = size, .space = ST_BAKE_TANGENT, .normal = 1, .displacement = 1, .padding = 4 };
    st_bake_maps exact, rays;
    CHECKF(st_bake(h, uvs, &o, &exact, &err) == ST_OK, "%s", err.msg);
    o.rays = 1;
    CHECKF(st_bake(h, uvs, &o, &rays, &err) == ST_OK, "%s", err.msg);
    CHECK(!exact.by_rays && rays.by_rays && rays.baked == exact.baked);
    double lo = INFINITY, hi = -INFINITY, worst = 0, nsum = 0, nmax = 0;
    uint64_t n = 0;
    for (uint32_t y = 0; y < size; y++)
        for (uint32_t x = 0; x < size; x++) {
            size_t i = (size_t)y * size + x;
            if (!interior(&exact, x, y) || rays.mask[i] != 1) continue;
            lo = fmin(lo, exact.disp[i]);
            hi = fmax(hi, exact.disp[i]);
            worst = fmax(worst, fabs((double)rays.disp[i] - exact.disp[i]));
            for (int k = 0; k < 3; k++) {
                double dn = fabs((double)rays.normal[3 * i + k] - exact.normal[3 * i + k]);
                nsum += dn;
                nmax = fmax(nmax, dn);
            }
            n++;
        }
    double range = hi - lo;
    printf("%s: B=%u L=%u %ux%u, exact vs rays on %llu interior texels of %llu: displacement off by %.3g at most "
           "(%.3f %% of the range %.4f); normals off by %.2g per channel on average, %.2g at most; %llu misses\n",
           what, B, L, size, size, (unsigned long long)n, (unsigned long long)exact.baked, worst, 100 * worst / range, range,
           nsum / (3.0 * (double)n), nmax, (unsigned long long)rays.ray_misses);
    CHECK(n > exact.baked / 2 && range > 0.05);
    CHECKF(worst < disp_tol * range, "%s: displacement off by %g, over %g %% of %g", what, worst, 100 * disp_tol, range);
    CHECKF(nsum / (3.0 * (double)n) < mean_tol && nmax < max_tol, "%s: normals off by %g mean, %g max", what,
           nsum / (3.0 * (double)n), nmax);
    CHECK(rays.ray_misses == 0);
    /* Threads share out rows: 1 and 3 give the bits of the default. */
    size_t tx = (size_t)size * size;
    for (unsigned threads = 1; threads <= 3; threads += 2) {
        st_parallel_set_threads(threads);
        st_bake_maps again;
        CHECK(st_bake(h, uvs, &o, &again, &err) == ST_OK);
        CHECKF(!memcmp(again.disp, rays.disp, tx * sizeof(float)) && !memcmp(again.normal, rays.normal, 3 * tx * sizeof(float)) &&
               !memcmp(again.mask, rays.mask, tx) && again.disp_min == rays.disp_min && again.disp_max == rays.disp_max,
               "%s: rays on %u threads differ", what, threads);
        st_bake_maps_free(&again);
    }
    st_parallel_set_threads(0);
    st_bake_maps_free(&exact);
    st_bake_maps_free(&rays);
}

static void displace_by_bump(st_hier *h, unsigned B, unsigned L, const st_bake_uvs *uvs)
{
    base_geo g = { .h = h, .B = B, .uvs = uvs };
    corner_data(&g);
    displace_level(&g, L);
    free(g.cvert);
    free(g.cnormal);
    free(g.target);
    free(g.has_target);
}

static void test_rays_vs_exact(void)
{
    st_hier h;
    st_error err;
    st_bake_layout lay;
    tl_init_hier(&h, tl_mesh_icosa, ST_SCHEME_LOOP, 4);
    CHECKF(st_bake_auto_uvs(&h, 1, &lay, &err) == ST_OK, "%s", err.msg);
    st_bake_uvs u = st_bake_layout_uvs(&lay);
    displace_by_bump(&h, 1, 4, &u);
    compare_paths("icosahedron loop, bump, per-face atlas", &h, 1, 4, &u, 512, 0.005, 0.001, 0.01);
    st_bake_layout_free(&lay);
    st_hier_free(&h);

    tl_init_hier(&h, make_torus, ST_SCHEME_CATMARK, 4);
    torus_uvs(&h, 0, &lay);
    u = st_bake_layout_uvs(&lay);
    displace_by_bump(&h, 0, 4, &u);
    compare_paths("torus catmull-clark, bump, toroidal unwrap", &h, 0, 4, &u, 256, 0.005, 0.001, 0.01);
    st_bake_layout_free(&lay);
    st_hier_free(&h);
}

/* ---- √3 and Doo-Sabin: a sphere with known bumps ----------------------------- */

/* Level L is moved onto the surface r = ρ (1 + bump(direction)); the
 * displacement at a texel is where the line from B's point along B's
 * normal crosses that surface nearest to B (bisection on a bracket found
 * by stepping out from t = 0). */
static double radial_bump(const double *u)
{
    return 0.06 * (sin(3.0 * u[0] + 0.5) * cos(2.0 * u[1]) + 0.5 * sin(2.5 * u[2]));
}

static double sphere_gap(double rho, const double *q)
{
    double r = sqrt(dot3(q, q)), u[3] = { q[0] / r, q[1] / r, q[2] / r };
    return r - rho * (1 + radial_bump(u));
}

static double move_onto_sphere(st_hier *h, unsigned L)
{
    st_map *m = &h->map;
    uint32_t *vd = malloc(m->verts.end * sizeof *vd), n = 0;
    double (*pos)[3] = malloc(m->verts.end * sizeof *pos), rho = 0;
    uint8_t *seen = calloc(m->verts.end, 1);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, L, &it); d != ST_NIL; d = st_dart_next(m, L, &it)) {
        uint32_t v = st_vert(m, d, L);
        if (seen[v]) continue;
        seen[v] = 1;
        vd[n] = d;
        memcpy(pos[n], st_pos(m, v, L), sizeof pos[n]);
        rho += sqrt(dot3(pos[n], pos[n]));
        n++;
    }
    rho /= n;
    for (uint32_t i = 0; i < n; i++) {
        double u[3];
        memcpy(u, pos[i], sizeof u);
        normalize3(u);
        for (int k = 0; k < 3; k++) pos[i][k] = rho * (1 + radial_bump(u)) * u[k];
    }
    st_hier_move(h, L, vd, (const double (*)[3])pos, n);
    /* Every vertex of the level is now on the surface. */
    double worst = 0;
    for (uint32_t i = 0; i < n; i++) worst = fmax(worst, fabs(sphere_gap(rho, st_pos(m, st_vert(m, vd[i], L), L))));
    CHECKF(worst < 1e-12 * rho, "level %u off the sphere by %g after the move", L, worst);
    free(vd);
    free(pos);
    free(seen);
    return rho;
}

static double crossing(double rho, const double *p, const double *n, double reach)
{
    const unsigned steps = 400;
    double step = reach / steps;
    for (unsigned k = 0; k < steps; k++)
        for (int side = 1; side >= -1; side -= 2) {
            double a = side * step * k, b = side * step * (k + 1);
            double qa[3], qb[3];
            for (int j = 0; j < 3; j++) { qa[j] = p[j] + a * n[j]; qb[j] = p[j] + b * n[j]; }
            double fa = sphere_gap(rho, qa), fb = sphere_gap(rho, qb);
            if ((fa <= 0) == (fb <= 0)) continue;
            for (int it = 0; it < 80; it++) {
                double c = 0.5 * (a + b), qc[3];
                for (int j = 0; j < 3; j++) qc[j] = p[j] + c * n[j];
                if ((sphere_gap(rho, qc) <= 0) == (fa <= 0)) a = c; else b = c;
            }
            return 0.5 * (a + b);
        }
    return NAN;
}

typedef struct sphere_ctx {
    base_geo *g;
    const st_bake_maps *maps;
    double rho, reach, lo, hi, worst;
    uint64_t compared, unsolved;
} sphere_ctx;

static void sphere_texel(void *pc, uint32_t x, uint32_t y, const double w[3])
{
    (void)w;
    sphere_ctx *e = pc;
    size_t i = (size_t)y * e->maps->size + x;
    if (e->maps->mask[i] != 1) return;
    double p[2] = { (x + 0.5) / e->maps->size, (y + 0.5) / e->maps->size }, pos[3], n[3];
    base_at(e->g, e->g->face, p, pos, n);
    double want = crossing(e->rho, pos, n, e->reach);
    if (!isfinite(want)) { e->unsolved++; return; }
    e->lo = fmin(e->lo, want);
    e->hi = fmax(e->hi, want);
    e->worst = fmax(e->worst, fabs(e->maps->disp[i] - want));
    e->compared++;
}

static void check_sphere(const char *what, st_scheme_id id, void (*make)(st_mesh *), unsigned B, unsigned L, uint32_t size,
                         double tol)
{
    st_hier h;
    st_error err;
    tl_init_hier(&h, make, id, L);
    double rho = move_onto_sphere(&h, L);
    st_bake_layout lay;
    CHECKF(st_bake_auto_uvs(&h, B, &lay, &err) == ST_OK, "%s", err.msg);
    st_bake_uvs u = st_bake_layout_uvs(&lay);
    st_bake_opts o = { .base = B, .level = L, .size = size, .space = ST_BAKE_TANGENT, .normal = 1, .displacement = 1, .padding = 4 };
    CHECK(st_bake_by_rays(&h, &o) && st_bake_estimate(&h, &u, &o) > st_bake_bvh_bytes(st_bake_level_triangles(&h.map, L)));
    st_bake_maps maps;
    int rc = st_bake(&h, &u, &o, &maps, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, rc ? err.msg : "");
    if (rc) { st_bake_layout_free(&lay); st_hier_free(&h); return; }
    base_geo g = { .h = &h, .B = B, .uvs = &u };
    corner_data(&g);
    sphere_ctx e = { .g = &g, .maps = &maps, .rho = rho, .reach = maps.ray_reach, .lo = INFINITY, .hi = -INFINITY };
    for (uint32_t f = 0; f < u.nfaces; f++) {
        g.face = f;
        uint32_t a = u.corner_off[f], deg = u.corner_off[f + 1] - a;
        for (uint32_t t = 0; t + 2 < deg; t++) {
            double tri[3][2];
            uint32_t idx[3] = { a, a + t + 1, a + t + 2 };
            for (int k = 0; k < 3; k++) memcpy(tri[k], u.uv + 2 * (size_t)idx[k], sizeof tri[k]);
            st_bake_raster_tri(tri, size, sphere_texel, &e);
        }
    }
    double range = e.hi - e.lo;
    printf("%s: B=%u L=%u %ux%u by rays (reach %.4g, radius %.4g): %llu texels, %llu misses, %llu compared; "
           "displacement range %.5f, max error %.3g (%.3f %% of the range)\n",
           what, B, L, size, size, maps.ray_reach, rho, (unsigned long long)maps.baked, (unsigned long long)maps.ray_misses,
           (unsigned long long)e.compared, range, e.worst, 100 * e.worst / range);
    CHECK(maps.by_rays && maps.ray_misses == 0 && e.unsolved == 0);
    CHECKF(e.compared > maps.baked * 99 / 100, "%s: %llu of %llu compared", what, (unsigned long long)e.compared,
           (unsigned long long)maps.baked);
    CHECKF(range > 0.05 * rho, "%s: range %g", what, range);
    CHECKF(e.worst < tol * range, "%s: max error %g >= %g %% of range %g", what, e.worst, 100 * tol, range);
    st_bake_maps_free(&maps);
    free(g.cvert);
    free(g.cnormal);
    st_bake_layout_free(&lay);
    st_hier_free(&h);
}

static void test_rays(void)
{
    check_bvh("icosahedron sqrt3 level 3", ST_SCHEME_SQRT3, tl_mesh_icosa, 3);
    check_bvh("cube doo-sabin level 3", ST_SCHEME_DOOSABIN, tl_mesh_cube, 3);
    check_bvh("torus catmull-clark level 2", ST_SCHEME_CATMARK, make_torus, 2);
    test_rays_vs_exact();
    check_sphere("icosahedron sqrt3 on a bumpy sphere", ST_SCHEME_SQRT3, tl_mesh_icosa, 1, 6, 512, 0.015);
    check_sphere("icosahedron doo-sabin on a bumpy sphere", ST_SCHEME_DOOSABIN, tl_mesh_icosa, 1, 5, 512, 0.015);
}

/* ---- the memory estimate against the measured peak -------------------------- */

/* In a child: the hierarchy built, the heap trimmed and the peak resident
 * size reset (/proc/self/clear_refs), then the bake; its growth (peak
 * after minus resident before) against st_bake_estimate. */
static size_t status_kib(const char *key)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    size_t v = 0, n = strlen(key);
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, key, n)) v = (size_t)strtoull(line + n, NULL, 10);
    if (f) fclose(f);
    return v;
}

static void check_bake_peak(const char *what, st_scheme_id id, unsigned L, uint32_t size)
{
    int fd[2];
    if (pipe(fd)) { CHECK(!"pipe"); return; }
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        double r[4] = { 0, 0, 0, 0 };
        st_hier h;
        st_error err;
        st_bake_layout lay;
        tl_init_hier(&h, tl_mesh_icosa, id, L);
        if (st_bake_auto_uvs(&h, 1, &lay, &err) == ST_OK) {
            st_bake_uvs u = st_bake_layout_uvs(&lay);
            st_bake_opts o = { .base = 1, .level = L, .size = size, .space = ST_BAKE_TANGENT, .normal = 1, .displacement = 1, .padding = 4 };
            malloc_trim(0);
            FILE *cr = fopen("/proc/self/clear_refs", "w");
            int reset = cr && fputs("5", cr) >= 0;
            if (cr) reset &= fclose(cr) == 0;
            r[0] = (double)st_mem_resident();
            r[1] = (double)st_bake_estimate(&h, &u, &o);
            r[3] = st_bake_by_rays(&h, &o);
            st_bake_maps maps;
            if (reset && st_bake(&h, &u, &o, &maps, &err) == ST_OK) {
                r[2] = 1024.0 * (double)status_kib("VmHWM:");
                st_bake_maps_free(&maps);
            }
            st_bake_layout_free(&lay);
        }
        st_hier_free(&h);
        ssize_t w = write(fd[1], r, sizeof r);
        _exit(w == (ssize_t)sizeof r ? 0 : 1);
    }
    close(fd[1]);
    double r[4] = { 0, 0, 0, 0 };
    ssize_t got = read(fd[0], r, sizeof r);
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    CHECKF(got == (ssize_t)sizeof r && r[2] > 0, "%s: no peak measured (is /proc/self/clear_refs writable?)", what);
    double growth = r[2] - r[0], ratio = r[1] / growth;
    printf("%s (%s): resident before %.1f MiB, bake estimated %.1f MiB, measured growth %.1f MiB (estimate / measured %.2f)\n",
           what, r[3] ? "by rays" : "exact", r[0] / 1048576, r[1] / 1048576, growth / 1048576, ratio);
#if defined(__SANITIZE_ADDRESS__)
    (void)ratio; /* the sanitizer's shadow memory and quarantine are not the program's */
#else
    CHECKF(ratio > 0.75 && ratio < 1.3, "%s: estimate %.1f MiB against a growth of %.1f MiB", what, r[1] / 1048576, growth / 1048576);
#endif
}

static void test_peaks(void)
{
    check_bake_peak("icosahedron sqrt3 level 8 onto level 1, 256x256", ST_SCHEME_SQRT3, 8, 256);
    check_bake_peak("icosahedron doo-sabin level 6 onto level 1, 256x256", ST_SCHEME_DOOSABIN, 6, 256);
    check_bake_peak("icosahedron loop level 5 onto level 1, 1024x1024", ST_SCHEME_LOOP, 5, 1024);
}

/* ---- UV tiles and wrap-around (issue 31) ----------------------------------- */

/* The cube's per-face atlas with faces 1-3 moved one tile right (u + 1):
 * a UDIM layout on tiles 1001 and 1002.  Baked per tile, each tile holds
 * three faces and the two tiles together hold every texel the unmoved
 * atlas bakes; --udim off wraps both tiles into one map, the texels the
 * unmoved atlas bakes.  Moving by whole tiles changes UVs by an ulp at most
 * ((u + 1) - 1), so the texel counts agree exactly and the normals to 1e-6. */
static void test_udim_tiles(void)
{
    st_hier h;
    st_error err;
    tl_init_hier(&h, tl_mesh_cube, ST_SCHEME_CATMARK, 2);
    st_bake_layout lay;
    CHECK(st_bake_auto_uvs(&h, 0, &lay, &err) == ST_OK);
    st_bake_uvs u = st_bake_layout_uvs(&lay);
    st_bake_opts o = { .base = 0, .level = 2, .size = 64, .normal = 1, .padding = 0 };
    st_bake_maps plain, wrapped, tile[2];
    CHECKF(st_bake(&h, &u, &o, &plain, &err) == ST_OK, "%s", err.msg);
    for (uint32_t c = lay.corner_off[0]; c < lay.corner_off[3]; c++) lay.uv[2 * c] += 1;
    st_bake_tiles t;
    CHECK(st_bake_uv_tiles(&u, o.size, &t, &err) == ST_OK);
    CHECKF(t.ntiles == 2 && st_bake_udim(t.tile[0]) == 1001 && st_bake_udim(t.tile[1]) == 1002 && t.faces[0] == 3 &&
           t.faces[1] == 3 && t.corners_outside == 0 && t.faces_crossing == 0 && t.first_non_udim == UINT32_MAX,
           "tiles: %u, corners outside %llu", t.ntiles, (unsigned long long)t.corners_outside);
    CHECKF(st_bake(&h, &u, &o, &wrapped, &err) == ST_OK, "%s", err.msg);
    o.udim = 1;
    for (int k = 0; k < 2; k++) {
        o.tile[0] = t.tile[k][0];
        o.tile[1] = t.tile[k][1];
        CHECKF(st_bake(&h, &u, &o, &tile[k], &err) == ST_OK, "%s", err.msg);
        CHECKF(tile[k].faces == 3 && tile[k].corners_outside == 0, "tile %d: %u faces", k, tile[k].faces);
    }
    uint64_t texels = (uint64_t)o.size * o.size, both = 0;
    double worst = 0;
    for (uint64_t i = 0; i < texels; i++) {
        both += tile[0].mask[i] && tile[1].mask[i];
        const st_bake_maps *from = tile[0].mask[i] ? &tile[0] : &tile[1];
        if (!plain.mask[i]) continue;
        for (int k = 0; k < 3; k++) {
            worst = fmax(worst, fabs(plain.normal[3 * i + k] - wrapped.normal[3 * i + k]));
            worst = fmax(worst, fabs(plain.normal[3 * i + k] - from->normal[3 * i + k]));
        }
    }
    printf("udim: plain %llu texels, wrapped %llu, tiles 1001 %llu + 1002 %llu, normals within %.3g\n",
           (unsigned long long)plain.baked, (unsigned long long)wrapped.baked, (unsigned long long)tile[0].baked,
           (unsigned long long)tile[1].baked, worst);
    CHECK(wrapped.baked == plain.baked && tile[0].baked + tile[1].baked == plain.baked && both == 0);
    CHECKF(worst < 1e-6, "normals differ by %g", worst);
    st_bake_maps_free(&plain);
    st_bake_maps_free(&wrapped);
    st_bake_maps_free(&tile[0]);
    st_bake_maps_free(&tile[1]);
    st_bake_tiles_free(&t);

    /* An overshoot: face 4's corner 3 pulled to u = -0.02 (its cell starts
     * at u >= 0), baked with wrap-around: counted, no overlap, and the
     * texels it wraps onto lie at the map's right edge. */
    o.udim = 0;
    for (uint32_t c = lay.corner_off[0]; c < lay.corner_off[3]; c++) lay.uv[2 * c] -= 1;
    double *p = lay.uv + 2 * ((size_t)lay.corner_off[3] + 2);
    double saved = p[0];
    p[0] = -0.02;
    CHECK(st_bake_uv_tiles(&u, o.size, &t, &err) == ST_OK && t.corners_outside == 1 && t.ntiles == 1);
    CHECKF(st_bake(&h, &u, &o, &wrapped, &err) == ST_OK, "%s", err.msg);
    uint64_t right = 0;
    for (uint32_t y = 0; y < o.size; y++) right += wrapped.mask[(size_t)y * o.size + o.size - 1] == 1;
    printf("udim: overshoot to u = -0.02: %llu corner outside, %llu texels in the map's last column\n",
           (unsigned long long)wrapped.corners_outside, (unsigned long long)right);
    CHECK(wrapped.corners_outside == 1 && right > 0);
    p[0] = saved;
    st_bake_maps_free(&wrapped);
    st_bake_tiles_free(&t);
    st_bake_layout_free(&lay);
    st_hier_free(&h);
}

int main(void)
{
    test_udim_tiles();
    test_peaks();
    test_dual_layout();
    test_split_polygon();
    test_concave_quad_bake();
    test_walk_tiles();
    test_identity_and_tangents();
    test_refusals();
    test_analytic();
    test_rays();
    return TEST_END();
}
