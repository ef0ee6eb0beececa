/* The automatic atlas (core/uv/uv.h, strata bake --auto-uv): on literal
 * meshes (a cube: six flat charts cut at its 90° creases, flattened
 * exactly; a flat grid: one chart; a torus, whose rings are annuli and must
 * be split into disks) and on the acceptance meshes (spot's cage, blub's
 * cage, koala's progressive level 0), every chart is checked here without
 * core/uv's own tests: a disk (V − E + F = 1 and one border loop, counted
 * from the faces), no triangle flipped in UV, no texel covered by two
 * charts at 1024², no two texels of different charts nearer than
 * `padding` texels, the
 * distortion under the bounds below, and at least 55 % of a 1024² map's
 * texels written by the bake (st_bake's own count, which also refuses
 * overlapping islands). */
#include "testlib.h"

#include "core/bake/bake.h"
#include "core/io/mesh.h"
#include "core/progressive/progressive.h"
#include "core/uv/uv.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Bounds the acceptance meshes must meet (at their defaults: cone 60°,
 * crease 80°, 1024², padding 8). */
#define MAX_L2_STRETCH 1.05
#define MAX_ANGLE_ERR_DEG 3.0
#define MIN_COVERAGE 0.55

typedef struct ekey { uint64_t key; uint32_t chart; } ekey;

static int ekey_cmp(const void *pa, const void *pb)
{
    const ekey *a = pa, *b = pb;
    if (a->chart != b->chart) return a->chart < b->chart ? -1 : 1;
    return (a->key > b->key) - (a->key < b->key);
}

/* Charts that are not disks, counted from the faces alone: per chart, V
 * distinct vertices, E distinct edges, F faces, border edges (used once)
 * forming one cycle (every border vertex of degree 2, one component). */
static uint32_t non_disks(const st_uv_mesh *m, const uint32_t *face_chart, uint32_t ncharts)
{
    uint32_t nc = m->face_off[m->nfaces];
    ekey *e = malloc((size_t)nc * sizeof *e), *v = malloc((size_t)nc * sizeof *v);
    uint32_t *faces = calloc(ncharts, sizeof *faces);
    for (uint32_t f = 0; f < m->nfaces; f++) {
        faces[face_chart[f]]++;
        for (uint32_t i = m->face_off[f]; i < m->face_off[f + 1]; i++) {
            uint32_t a = m->face_idx[i], b = m->face_idx[i + 1 < m->face_off[f + 1] ? i + 1 : m->face_off[f]];
            e[i] = (ekey){ (uint64_t)(a < b ? a : b) << 32 | (a < b ? b : a), face_chart[f] };
            v[i] = (ekey){ a, face_chart[f] };
        }
    }
    qsort(e, nc, sizeof *e, ekey_cmp);
    qsort(v, nc, sizeof *v, ekey_cmp);
    int64_t *chi = calloc(ncharts, sizeof *chi);
    uint32_t *border = calloc(ncharts, sizeof *border);
    for (uint32_t k = 0; k < ncharts; k++) chi[k] = faces[k];
    for (uint32_t i = 0; i < nc; i++)
        if (i == 0 || v[i].key != v[i - 1].key || v[i].chart != v[i - 1].chart) chi[v[i].chart]++;
    /* Border edges, and a union-find of their vertices per chart. */
    uint32_t nb = 0;
    ekey *be = malloc((size_t)nc * sizeof *be);
    for (uint32_t i = 0; i < nc;) {
        uint32_t j = i;
        while (j < nc && e[j].key == e[i].key && e[j].chart == e[i].chart) j++;
        chi[e[i].chart]--;
        if (j - i == 1) { border[e[i].chart]++; be[nb++] = e[i]; }
        i = j;
    }
    uint32_t bad = 0;
    /* Border vertex degrees: each border vertex must appear in exactly two
     * border edges, and the border edges of a chart must be one cycle:
     * with all degrees 2 that is one component, checked by walking. */
    uint32_t *deg = calloc(m->nverts, sizeof *deg), *nbr = malloc(2 * (size_t)m->nverts * sizeof *nbr);
    uint8_t *seen = calloc(m->nverts, 1);
    for (uint32_t i = 0, s = 0; i <= nb; i++) {
        if (i < nb && be[i].chart == be[s].chart) continue;
        /* edges s..i-1 are one chart's border */
        uint32_t k = nb ? be[s].chart : 0, ok = 1;
        for (uint32_t t = s; t < i; t++) {
            uint32_t a = (uint32_t)(be[t].key >> 32), b = (uint32_t)be[t].key;
            if (deg[a] < 2) nbr[2 * (size_t)a + deg[a]] = b;
            if (deg[b] < 2) nbr[2 * (size_t)b + deg[b]] = a;
            deg[a]++; deg[b]++;
        }
        for (uint32_t t = s; t < i && ok; t++) {
            uint32_t a = (uint32_t)(be[t].key >> 32), b = (uint32_t)be[t].key;
            ok = deg[a] == 2 && deg[b] == 2;
        }
        if (ok && i > s) {
            uint32_t start = (uint32_t)(be[s].key >> 32), prev = UINT32_MAX, cur = start, len = 0;
            do {
                seen[cur] = 1;
                uint32_t nx = nbr[2 * (size_t)cur] != prev ? nbr[2 * (size_t)cur] : nbr[2 * (size_t)cur + 1];
                prev = cur;
                cur = nx;
                len++;
            } while (cur != start && len <= i - s);
            ok = cur == start && len == i - s;
        }
        for (uint32_t t = s; t < i; t++) {
            uint32_t a = (uint32_t)(be[t].key >> 32), b = (uint32_t)be[t].key;
            deg[a] = deg[b] = 0; seen[a] = seen[b] = 0;
        }
        if (i > s && (!ok || chi[k] != 1)) bad++;
        if (i > s) chi[k] = 1000; /* counted */
        s = i;
        if (i == nb) break;
    }
    for (uint32_t k = 0; k < ncharts; k++)
        if (chi[k] != 1000) bad++; /* no border at all: closed */
    free(e); free(v); free(faces); free(chi); free(border); free(be); free(deg); free(nbr); free(seen);
    return bad;
}

/* Flipped triangles of the atlas' own triangulation, and the smallest gap
 * between two charts' UV boxes, in texels of a size × size map (the gap
 * on the farther axis: boxes apart on either axis do not touch). */
static uint32_t flipped(const st_uv_mesh *m, const double *uv)
{
    uint32_t (*tris)[3] = malloc(256 * sizeof *tris), bad = 0;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        if (m->face_off[f + 1] - m->face_off[f] > 256) { bad++; continue; }
        unsigned n = st_uv_face_triangles(m, f, tris);
        for (unsigned t = 0; t < n; t++) {
            const double *p = uv + 2 * (size_t)tris[t][0], *q = uv + 2 * (size_t)tris[t][1], *r = uv + 2 * (size_t)tris[t][2];
            if (!((q[0] - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (q[1] - p[1]) > 0)) bad++;
        }
    }
    free(tris);
    return bad;
}

/* The nearest two texels of different charts, in texels (texel centres
 * inside a chart's triangles, sampled here independently of core/uv): the
 * charts are at least that far apart, up to a texel. */
static double min_gap_texels(const st_uv_mesh *m, const double *uv, const uint32_t *face_chart, uint32_t size, int reach)
{
    uint32_t *own = malloc((size_t)size * size * sizeof *own), (*tris)[3] = malloc(256 * sizeof *tris);
    for (size_t i = 0; i < (size_t)size * size; i++) own[i] = UINT32_MAX;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        unsigned n = st_uv_face_triangles(m, f, tris);
        for (unsigned t = 0; t < n; t++) {
            double P[3][2];
            for (int j = 0; j < 3; j++) { P[j][0] = uv[2 * (size_t)tris[t][j]] * size; P[j][1] = uv[2 * (size_t)tris[t][j] + 1] * size; }
            int x0 = (int)floor(fmin(P[0][0], fmin(P[1][0], P[2][0]))), x1 = (int)ceil(fmax(P[0][0], fmax(P[1][0], P[2][0])));
            int y0 = (int)floor(fmin(P[0][1], fmin(P[1][1], P[2][1]))), y1 = (int)ceil(fmax(P[0][1], fmax(P[1][1], P[2][1])));
            for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < (int)size; y++)
                for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < (int)size; x++) {
                    double px = x + 0.5, py = y + 0.5, e[3];
                    for (int j = 0; j < 3; j++) {
                        const double *a = P[j], *b = P[(j + 1) % 3];
                        e[j] = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
                    }
                    if (e[0] >= 0 && e[1] >= 0 && e[2] >= 0) own[(size_t)y * size + (size_t)x] = face_chart[f];
                }
        }
    }
    double best = INFINITY;
    for (int y = 0; y < (int)size; y++)
        for (int x = 0; x < (int)size; x++) {
            uint32_t k = own[(size_t)y * size + (size_t)x];
            if (k == UINT32_MAX) continue;
            for (int dy = -reach; dy <= reach; dy++)
                for (int dx = -reach; dx <= reach; dx++) {
                    int u = x + dx, v = y + dy;
                    if (u < 0 || v < 0 || u >= (int)size || v >= (int)size) continue;
                    uint32_t o = own[(size_t)v * size + (size_t)u];
                    if (o != UINT32_MAX && o != k) best = fmin(best, sqrt((double)(dx * dx + dy * dy)));
                }
        }
    free(own);
    free(tris);
    return best;
}

/* Everything above on one mesh, its figures printed; with bake_h the
 * coverage of a 1024² bake of level 0 onto itself. */
static void check_mesh(const char *what, const st_mesh *mesh, st_hier *bake_h, int acceptance)
{
    const uint32_t size = 1024, pad = 8;
    st_uv_mesh um = { mesh->nverts, mesh->pos, mesh->nfaces, mesh->face_off, mesh->face_idx };
    st_uv_opts o = { .size = size, .padding = pad };
    st_uv_atlas a;
    st_error err;
    int rc = st_uv_make_atlas(&um, &o, &a, &err);
    CHECKF(rc == ST_OK, "%s: %s", what, rc ? err.msg : "");
    if (rc) return;
    uint32_t nd = non_disks(&um, a.face_chart, a.ncharts), fl = flipped(&um, a.uv);
    uint64_t covered = 0, overlap = 0, folded = 0;
    CHECK(st_uv_texels(&um, a.uv, a.face_chart, size, &covered, &overlap, &folded, &err) == ST_OK);
    double gap = min_gap_texels(&um, a.uv, a.face_chart, size, (int)pad);
    int inside = 1;
    for (size_t i = 0; i < 2 * (size_t)mesh->face_off[mesh->nfaces]; i++) inside &= a.uv[i] >= 0 && a.uv[i] <= 1;
    const st_uv_stats *s = &a.stats;
    printf("%s: %u faces, %u charts (%u by projection, %u splits); %u not disks, %u flipped, %llu texels of two charts, %llu folded, "
           "nearest texels of two charts %.2f apart (inf: none within the padding); L2 stretch %.4f, angle error %.3f deg, area ratio %.3f..%.3f (5th..95th %%); "
           "UV area %.1f %%, texels %.1f %%\n",
           what, mesh->nfaces, a.ncharts, s->fallback_charts, s->splits, nd, fl, (unsigned long long)overlap, (unsigned long long)folded, gap, s->l2_stretch,
           s->angle_err_deg, s->area_p5, s->area_p95, 100 * s->uv_area, 100.0 * (double)covered / ((double)size * size));
    CHECKF(nd == 0, "%s: %u charts are not disks", what, nd);
    CHECKF(fl == 0 && s->flipped == 0, "%s: %u flipped triangles", what, fl);
    CHECKF(overlap == 0, "%s: %llu texels covered by two charts", what, (unsigned long long)overlap);
    CHECKF(folded == 0, "%s: %llu texels covered by two faces of one chart", what, (unsigned long long)folded);
    CHECKF(gap >= pad, "%s: texels of two charts %.3f apart, padding %u", what, gap, pad);
    CHECKF(inside, "%s: UVs outside [0,1]", what);
    if (acceptance) {
        CHECKF(s->l2_stretch <= MAX_L2_STRETCH, "%s: L2 stretch %.4f > %.2f", what, s->l2_stretch, MAX_L2_STRETCH);
        CHECKF(s->angle_err_deg <= MAX_ANGLE_ERR_DEG, "%s: angle error %.3f > %.1f deg", what, s->angle_err_deg, MAX_ANGLE_ERR_DEG);
    }
    if (bake_h) {
        st_bake_layout lay;
        st_uv_stats bs;
        rc = st_bake_chart_uvs(bake_h, 0, size, pad, &lay, &bs, &err);
        CHECKF(rc == ST_OK, "%s: %s", what, rc ? err.msg : "");
        if (!rc) {
            /* The bake's layout is this atlas (same level mesh, same options). */
            CHECKF(lay.nfaces == mesh->nfaces && !memcmp(lay.uv, a.uv, 2 * (size_t)mesh->face_off[mesh->nfaces] * sizeof *a.uv),
                   "%s: the bake's atlas differs", what);
            st_bake_uvs u = st_bake_layout_uvs(&lay);
            st_bake_opts bo = { .base = 0, .level = 0, .size = size, .normal = 1, .padding = pad };
            st_bake_maps maps;
            rc = st_bake(bake_h, &u, &bo, &maps, &err);
            CHECKF(rc == ST_OK, "%s: bake: %s", what, rc ? err.msg : "");
            if (!rc) {
                double cov = (double)maps.baked / ((double)size * size);
                printf("%s: bake at %ux%u writes %llu texels (%.1f %%)\n", what, size, size, (unsigned long long)maps.baked, 100 * cov);
                CHECKF(cov >= MIN_COVERAGE, "%s: %.1f %% of the texels baked, want %.0f %%", what, 100 * cov, 100 * MIN_COVERAGE);
                st_bake_maps_free(&maps);
            }
            st_bake_layout_free(&lay);
        }
    }
    st_uv_atlas_free(&a);
}

static void test_literal(void)
{
    st_mesh m;
    tl_mesh_cube(&m);
    check_mesh("cube", &m, NULL, 0);
    /* Six flat squares cut at the creases, each isometric. */
    st_uv_mesh um = { m.nverts, m.pos, m.nfaces, m.face_off, m.face_idx };
    st_uv_atlas a;
    st_error err;
    CHECK(st_uv_make_atlas(&um, NULL, &a, &err) == ST_OK);
    CHECKF(a.ncharts == 6 && fabs(a.stats.l2_stretch - 1) < 1e-9 && a.stats.angle_err_deg < 1e-6,
           "cube: %u charts, stretch %.6f", a.ncharts, a.stats.l2_stretch);
    st_uv_atlas_free(&a);
    st_mesh_free(&m);

    tl_mesh_grid(&m, 6);
    um = (st_uv_mesh){ m.nverts, m.pos, m.nfaces, m.face_off, m.face_idx };
    CHECK(st_uv_make_atlas(&um, NULL, &a, &err) == ST_OK);
    CHECKF(a.ncharts == 1 && fabs(a.stats.l2_stretch - 1) < 1e-9, "grid: %u charts, stretch %.6f", a.ncharts, a.stats.l2_stretch);
    st_uv_atlas_free(&a);
    check_mesh("grid 6x6", &m, NULL, 0);
    st_mesh_free(&m);

    tl_mesh_torus(&m, 24, 12);
    check_mesh("torus 24x12", &m, NULL, 0);
    st_mesh_free(&m);
}

static int load(const char *path, st_mesh *m)
{
    st_error err;
    st_mesh_init(m);
    if (st_mesh_load(path, m, &err)) { tl_skip("%s: %s", path, err.msg); return -1; }
    return 0;
}

/* A Catmull-Clark hierarchy of no levels above the mesh: what the bake of
 * level 0 onto itself needs. */
static int hier_of(const st_mesh *m, st_hier *h)
{
    st_error err;
    int rc = st_hier_init(h, m, st_scheme_get(ST_SCHEME_CATMARK), NULL, &err);
    CHECKF(rc == ST_OK, "%s", rc ? err.msg : "");
    return rc;
}

static void test_acceptance(void)
{
    const char *cages[2][2] = { { "spot cage", STRATA_SHARED_DATA "/catmull_clark/spot_quadrangulated.obj" },
                                { "blub cage", STRATA_SHARED_DATA "/catmull_clark/blub_control_mesh.obj" } };
    for (int i = 0; i < 2; i++) {
        st_mesh m;
        if (load(cages[i][1], &m)) continue;
        st_hier h;
        if (!hier_of(&m, &h)) {
            check_mesh(cages[i][0], &m, &h, 1);
            st_hier_free(&h);
        }
        st_mesh_free(&m);
    }
    /* Koala's progressive level 0 (strata rebuild --method progressive). */
    st_mesh fine, coarse;
    if (load(STRATA_SHARED_DATA "/large/koala.obj", &fine)) return;
    st_hier p, h;
    st_error err;
    /* strata rebuild --method progressive's default target (core/rebuild/rebuild.c): 1 % of the faces. */
    st_progressive_opts po = { .target_faces = fine.nfaces / 100 > 4 ? fine.nfaces / 100 : 4 };
    int rc = st_progressive_build(&fine, &po, &p, NULL, &err);
    CHECKF(rc == ST_OK, "koala: %s", rc ? err.msg : "");
    st_mesh_free(&fine);
    if (rc) return;
    st_mesh_init(&coarse);
    rc = st_hier_level_mesh(&p, 0, &coarse, &err);
    CHECKF(rc == ST_OK, "koala level 0: %s", rc ? err.msg : "");
    st_hier_free(&p);
    if (!rc && !hier_of(&coarse, &h)) {
        check_mesh("koala progressive level 0", &coarse, &h, 1);
        st_hier_free(&h);
    }
    st_mesh_free(&coarse);
}

int main(void)
{
    test_literal();
    test_acceptance();
    return TEST_END();
}
