/* Case tables of the adaptive-face triangulation (render/triangulate.h):
 * every case on a hand-built face in every rotation, the reading of the
 * case from edge levels (√3 border triangles, the all-split faces, the
 * regular polygons), the fallback on faces outside the tables, and the
 * "no cracks" property on hand-built adaptive polyhedra: a coarse
 * triangle/quad mesh with some faces split once, every other face seeing
 * its split neighbours as hanging vertices; the triangles of all faces,
 * welded by vertex index, must form a closed, consistently oriented
 * 2-manifold. */
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/triangulate.h"

static st_tri_index IX;

/* ---- checks on one triangulated polygon ------------------------------------- */

static double area2(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* tri (n-2 triangles over corners 0..n-1) is a triangulation of the n-gon
 * as a disk: every side used once in the face's direction, every other
 * (directed) edge matched by its reverse exactly once.  With xy (2D
 * positions), every triangle is counter-clockwise with a positive area and
 * the areas add up to the polygon's. */
static int check_triangulation(unsigned n, const uint32_t *tri, const double (*xy)[2], double min_area, const char *what)
{
    int ok = 1;
    unsigned *cnt = calloc((size_t)n * n, sizeof *cnt);
    for (unsigned t = 0; t < n - 2; t++)
        for (unsigned k = 0; k < 3; k++) {
            uint32_t a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
            if (a >= n || b >= n || a == b) { ok = 0; continue; }
            cnt[a * n + b]++;
        }
    for (unsigned a = 0; a < n && ok; a++)
        for (unsigned b = 0; b < n && ok; b++) {
            if (a == b) continue;
            unsigned ab = cnt[a * n + b], ba = cnt[b * n + a];
            if (b == (a + 1) % n) { if (ab != 1 || ba != 0) ok = 0; }        /* a side of the polygon */
            else if (a == (b + 1) % n) { /* checked from the other end */ }
            else if (ab > 1 || ab != ba) ok = 0;                              /* a diagonal: both ways */
        }
    free(cnt);
    CHECKF(ok, "%s: not a triangulation of the %u-gon", what, n);
    if (!xy || !ok) return ok;
    double sum = 0, poly = 0;
    for (unsigned t = 0; t < n - 2; t++) {
        double a = area2(xy[tri[3 * t]], xy[tri[3 * t + 1]], xy[tri[3 * t + 2]]) / 2;
        CHECKF(a > min_area, "%s: triangle %u (%u,%u,%u) area %g", what, t, tri[3 * t], tri[3 * t + 1], tri[3 * t + 2], a);
        sum += a;
    }
    for (unsigned k = 0; k < n; k++) poly += (xy[k][0] * xy[(k + 1) % n][1] - xy[(k + 1) % n][0] * xy[k][1]) / 2;
    CHECKF(fabs(sum - poly) < 1e-9, "%s: triangles cover %g of a polygon of area %g", what, sum, poly);
    return ok;
}

/* ---- every case of the table ------------------------------------------------ */

/* A hand-built face for a pattern: the coarse corners on a regular c-gon,
 * each 'm' on the middle of its coarse edge (exactly collinear: the worst
 * case for a triangulation), coarse sides at level f = 1, half sides at
 * level 2, corners inserted at level 0 or 1, midpoints at level 2.  All-'c'
 * patterns (regular polygons) have every side at level 1 and corners of
 * level 0. */
static void make_face(const char *pat, double (*xy)[2], uint8_t *elev, uint8_t *vlev)
{
    unsigned n = (unsigned)strlen(pat), c = 0;
    for (unsigned k = 0; k < n; k++) c += pat[k] == 'c';
    unsigned ci = 0;
    for (unsigned k = 0; k < n; k++) {
        if (pat[k] == 'c') {
            double a = 2 * M_PI * ci / c + 0.3;
            xy[k][0] = cos(a); xy[k][1] = sin(a);
            vlev[k] = (uint8_t)(c == n ? 0 : ci % 2);   /* regular polygons: an input face */
            ci++;
        }
    }
    for (unsigned k = 0; k < n; k++) {
        if (pat[k] != 'm') continue;
        unsigned p = (k + n - 1) % n, q = (k + 1) % n;
        xy[k][0] = 0.5 * (xy[p][0] + xy[q][0]);
        xy[k][1] = 0.5 * (xy[p][1] + xy[q][1]);
        vlev[k] = 2;
    }
    for (unsigned k = 0; k < n; k++)
        elev[k] = (pat[k] == 'm' || pat[(k + 1) % n] == 'm') ? 2 : 1;
}

static void test_every_case(void)
{
    for (unsigned i = 0; i < st_tri_ncases; i++) {
        const st_tri_case *tc = &st_tri_cases[i];
        unsigned n = (unsigned)strlen(tc->pattern);
        CHECKF(tc->ntri == n - 2, "case %s: %u triangles for %u sides", tc->name, tc->ntri, n);
        double xy0[ST_TRI_TABLE_MAX_SIDES][2], xy[ST_TRI_TABLE_MAX_SIDES][2];
        uint8_t e0[ST_TRI_TABLE_MAX_SIDES], v0[ST_TRI_TABLE_MAX_SIDES], e[ST_TRI_TABLE_MAX_SIDES], v[ST_TRI_TABLE_MAX_SIDES];
        make_face(tc->pattern, xy0, e0, v0);
        /* The table itself, as written. */
        uint32_t raw[3 * (ST_TRI_TABLE_MAX_SIDES - 2)];
        for (unsigned t = 0; t < tc->ntri; t++)
            for (unsigned k = 0; k < 3; k++) raw[3 * t + k] = tc->tri[t][k];
        check_triangulation(n, raw, (const double (*)[2])xy0, 1e-3, tc->name);
        /* Read from the walk, starting at every corner. */
        for (unsigned r = 0; r < n; r++) {
            for (unsigned k = 0; k < n; k++) {
                memcpy(xy[k], xy0[(k + r) % n], sizeof xy[k]);
                e[k] = e0[(k + r) % n];
                v[k] = v0[(k + r) % n];
            }
            uint32_t tri[3 * (ST_TRI_TABLE_MAX_SIDES - 2)];
            int c = st_tri_face(&IX, n, e, v, NULL, tri);
            CHECKF(c == (int)i, "case %s from corner %u: read as case %d (%s)", tc->name, r, c,
                   c >= 0 ? st_tri_cases[c].name : "fallback");
            char what[96];
            snprintf(what, sizeof what, "%s from corner %u", tc->name, r);
            check_triangulation(n, tri, (const double (*)[2])xy, 1e-3, what);
        }
    }
}

/* ---- reading cases from levels ------------------------------------------------ */

static int case_of(unsigned n, const uint8_t *e, const uint8_t *v)
{
    uint32_t tri[3 * 64];
    return st_tri_face(&IX, n, e, v, NULL, tri);
}

static int find_case(const char *pattern)
{
    for (unsigned i = 0; i < st_tri_ncases; i++)
        if (!strcmp(st_tri_cases[i].pattern, pattern)) return (int)i;
    return -2;
}

static void test_sqrt3_border_triangles(void)
{
    /* √3 never splits edges: every face is a triangle whatever its levels.
     *   regular level-n triangle           (n, n, n)
     *   even triangle after its split      (n-1, n, n): the flipped old edge
     *   odd border triangle (not flipped)  (n-1, n-1, n) and rotations     */
    static const uint8_t pats[][3] = { {2,2,2}, {1,2,2}, {2,1,2}, {2,2,1}, {1,1,2}, {2,1,1}, {1,2,1}, {0,2,2}, {0,0,0} };
    static const uint8_t vl[3] = { 0, 1, 2 };
    for (size_t i = 0; i < sizeof pats / sizeof pats[0]; i++) {
        uint32_t tri[3];
        int c = st_tri_face(&IX, 3, pats[i], vl, NULL, tri);
        CHECKF(c == find_case("ccc") && tri[0] == 0 && tri[1] == 1 && tri[2] == 2,
               "sqrt3 triangle with edge levels %u %u %u: case %d", pats[i][0], pats[i][1], pats[i][2], c);
    }
}

static void test_reading(void)
{
    /* Regular quads at any level: corners of levels (<= L-1, L, L, L). */
    static const uint8_t e4[4] = { 3, 3, 3, 3 }, v4[4] = { 2, 3, 3, 3 };
    CHECK(case_of(4, e4, v4) == find_case("cccc"));
    /* An input hexagon (level 0) and Doo-Sabin's hexagons (no vertex levels). */
    static const uint8_t e6[6] = { 0, 0, 0, 0, 0, 0 }, v6[6] = { 0, 0, 0, 0, 0, 0 };
    CHECK(case_of(6, e6, v6) == find_case("cccccc"));
    static const uint8_t e6b[6] = { 2, 2, 2, 2, 2, 2 }, v6b[6] = { 1, 2, 1, 2, 1, 2 }, v6c[6] = { 2, 0, 2, 1, 2, 1 };
    CHECK(case_of(6, e6b, NULL) == find_case("cccccc"));
    /* All three edges split: corners older than the midpoints, either parity. */
    uint32_t tri[12];
    CHECK(st_tri_face(&IX, 6, e6b, v6b, NULL, tri) == find_case("cmcmcm"));
    CHECKF(tri[9] == 1 && tri[10] == 3 && tri[11] == 5, "centre triangle on the midpoints 1 3 5, got %u %u %u", tri[9], tri[10], tri[11]);
    CHECK(st_tri_face(&IX, 6, e6b, v6c, NULL, tri) == find_case("cmcmcm"));
    CHECKF(tri[9] % 2 == 0 && tri[10] % 2 == 0 && tri[11] % 2 == 0, "centre triangle on the midpoints 0 2 4, got %u %u %u", tri[9], tri[10], tri[11]);
    /* Eight sides all split (a quad) vs a regular octagon at level 0. */
    static const uint8_t e8[8] = { 1, 1, 1, 1, 1, 1, 1, 1 }, v8[8] = { 0, 1, 0, 1, 0, 1, 0, 1 };
    static const uint8_t e8b[8] = { 0 }, v8b[8] = { 0 };
    CHECK(case_of(8, e8, v8) == find_case("cmcmcmcm"));
    CHECK(case_of(8, e8b, v8b) == find_case("cccccccc"));
    /* Listing 3.3.1: 5 sides, three of level i and two of level i+1. */
    static const uint8_t e5[5] = { 1, 1, 2, 2, 1 }, v5[5] = { 0, 1, 1, 2, 0 };
    CHECK(case_of(5, e5, v5) == find_case("cmccc"));
    /* A 5-gon with four fine sides is a triangle with two split edges. */
    static const uint8_t e5b[5] = { 2, 2, 2, 2, 1 }, v5b[5] = { 1, 2, 0, 2, 1 };
    CHECK(case_of(5, e5b, v5b) == find_case("cmcmc"));
    /* Outside the tables: */
    static const uint8_t skip[5] = { 1, 1, 3, 3, 1 };                 /* levels two apart: restriction off */
    CHECK(case_of(5, skip, NULL) == ST_TRI_FALLBACK);
    static const uint8_t odd[5] = { 2, 2, 2, 1, 1 };                  /* a fine run of odd length */
    CHECK(case_of(5, odd, NULL) == ST_TRI_FALLBACK);
    static const uint8_t badv[4] = { 2, 2, 1, 1 }, badvl[4] = { 0, 1, 0, 0 }; /* "midpoint" older than its sides */
    CHECK(case_of(4, badv, badvl) == ST_TRI_FALLBACK);
    static const uint8_t e9[9] = { 0 };                               /* a 9-gon */
    CHECK(case_of(9, e9, NULL) == ST_TRI_FALLBACK);
    static const uint8_t e7[7] = { 2, 2, 2, 2, 2, 2, 1 }, v7[7] = { 1, 2, 1, 2, 1, 2, 1 }; /* 6 fine sides + 1: a quad */
    CHECK(case_of(7, e7, v7) == find_case("cmcmcmc"));
    static const uint8_t e7b[7] = { 2, 2, 2, 2, 2, 2, 2 }, v7b[7] = { 1, 2, 1, 2, 1, 2, 2 }; /* 7 fine sides: no such face */
    CHECK(case_of(7, e7b, v7b) == find_case("ccccccc"));
    static const uint8_t e4m[4] = { 2, 2, 2, 2 }, v4m[4] = { 1, 2, 1, 2 };            /* a 2-gon split: never */
    CHECK(case_of(4, e4m, v4m) == find_case("cccc"));
    /* Table-driven: the index knows every rotation of every case. */
    unsigned entries = 0;
    for (unsigned n = 0; n <= ST_TRI_TABLE_MAX_SIDES; n++)
        for (unsigned k = 0; k < (1u << ST_TRI_TABLE_MAX_SIDES); k++) entries += IX.icase[n][k] >= 0;
    /* Distinct rotations: ccc 1, cmcc 4, cmcmc 5, cmcmcm 2, cccc 1, cmccc 5,
     * cmcmcc 6, cmccmc 3, cmcmcmc 7, cmcmcmcm 2, and 1 per regular polygon. */
    CHECKF(entries == 1 + 4 + 5 + 2 + 1 + 5 + 6 + 3 + 7 + 2 + 4, "%u distinct (sides, mask) entries", entries);
}

/* ---- fallback ------------------------------------------------------------------ */

static void test_fallback(void)
{
    /* A concave "L" and a star: ear clipping gives only positive triangles. */
    static const double L[6][2] = { {0,0}, {2,0}, {2,1}, {1,1}, {1,2}, {0,2} };
    double star[10][2];
    for (int k = 0; k < 10; k++) {
        double a = 2 * M_PI * k / 10, r = k % 2 ? 0.4 : 1.0;
        star[k][0] = r * cos(a); star[k][1] = r * sin(a);
    }
    const struct { unsigned n; const double (*xy)[2]; const char *name; } polys[] = {
        { 6, L, "L shape" }, { 10, (const double (*)[2])star, "star" },
    };
    for (size_t i = 0; i < sizeof polys / sizeof polys[0]; i++) {
        float pos[3 * 16];
        for (unsigned k = 0; k < polys[i].n; k++) {
            pos[3 * k] = (float)polys[i].xy[k][0]; pos[3 * k + 1] = (float)polys[i].xy[k][1]; pos[3 * k + 2] = 0;
        }
        uint32_t tri[3 * 16];
        st_tri_fallback(polys[i].n, pos, tri);
        check_triangulation(polys[i].n, tri, polys[i].xy, 1e-6, polys[i].name);
    }
    /* Near-collinear corners (a quad side split twice, restriction off):
     * a valid triangulation with no flat triangle. */
    static const double q[6][2] = { {0,0}, {0.25,0}, {0.5,0}, {1,0}, {1,1}, {0,1} };
    float pq[18];
    for (int k = 0; k < 6; k++) { pq[3 * k] = (float)q[k][0]; pq[3 * k + 1] = (float)q[k][1]; pq[3 * k + 2] = 0; }
    static const uint8_t eq[6] = { 2, 2, 1, 0, 0, 0 };
    uint32_t tri[12];
    CHECK(st_tri_face(&IX, 6, eq, NULL, pq, tri) == ST_TRI_FALLBACK);
    check_triangulation(6, tri, q, 1e-6, "quad with a side split twice");
    /* A non-planar n-gon in 3D, a degenerate one (all corners on a line),
     * and one too big to ear-clip: still n-2 triangles, no hole. */
    float bent[3 * 12], line[3 * 12];
    for (int k = 0; k < 12; k++) {
        double a = 2 * M_PI * k / 12;
        bent[3 * k] = (float)cos(a); bent[3 * k + 1] = (float)sin(a); bent[3 * k + 2] = (float)(0.3 * (k % 2));
        line[3 * k] = (float)k; line[3 * k + 1] = 0; line[3 * k + 2] = 0;
    }
    uint32_t t12[30];
    st_tri_fallback(12, bent, t12);
    check_triangulation(12, t12, NULL, 0, "bent 12-gon");
    st_tri_fallback(12, line, t12);
    check_triangulation(12, t12, NULL, 0, "collinear 12-gon");
    unsigned big = 300;
    float *pb = malloc(3 * (size_t)big * sizeof *pb);
    uint32_t *tb = malloc(3 * (size_t)(big - 2) * sizeof *tb);
    uint8_t *eb = calloc(big, 1);
    for (unsigned k = 0; k < big; k++) {
        double a = 2 * M_PI * k / big;
        pb[3 * k] = (float)cos(a); pb[3 * k + 1] = (float)sin(a); pb[3 * k + 2] = 0;
    }
    CHECK(st_tri_face(&IX, big, eb, NULL, pb, tb) == ST_TRI_FALLBACK);
    check_triangulation(big, tb, NULL, 0, "300-gon");
    free(pb); free(tb); free(eb);
}

/* ---- no cracks on hand-built adaptive polyhedra ---------------------------------- */

typedef struct soup {
    double pos[256][3];
    uint8_t vlev[256];
    unsigned nv;
    /* faces: corners with the level of the side leaving each corner */
    unsigned nf, off[128], idx[512];
    uint8_t elev[512];
} soup;

static unsigned add_vertex(soup *s, const double *p, uint8_t lev)
{
    memcpy(s->pos[s->nv], p, sizeof s->pos[0]);
    s->vlev[s->nv] = lev;
    return s->nv++;
}

static void add_face(soup *s, unsigned n, const unsigned *c, const uint8_t *e)
{
    s->off[s->nf + 1] = s->off[s->nf] + n;
    for (unsigned k = 0; k < n; k++) { s->idx[s->off[s->nf] + k] = c[k]; s->elev[s->off[s->nf] + k] = e[k]; }
    s->nf++;
}

/* Splits the faces flagged in `split` of a coarse polyhedron once (triangle
 * or polygon quadrisection), as an adaptive level-1 map shows it: coarse
 * sides at level 0, split halves and inner edges at level 1, midpoints and
 * centres inserted at level 1. */
static void make_adaptive(soup *s, const double (*p)[3], unsigned nv, const unsigned *off, const unsigned *idx,
                          unsigned nf, const int *split)
{
    memset(s, 0, sizeof *s);
    for (unsigned v = 0; v < nv; v++) add_vertex(s, p[v], 0);
    unsigned mid[64][64];
    for (unsigned a = 0; a < nv; a++) for (unsigned b = 0; b < nv; b++) mid[a][b] = ~0u;
    for (unsigned f = 0; f < nf; f++) {
        if (!split[f]) continue;
        unsigned n = off[f + 1] - off[f];
        for (unsigned k = 0; k < n; k++) {
            unsigned a = idx[off[f] + k], b = idx[off[f] + (k + 1) % n];
            if (mid[a][b] != ~0u) continue;
            double m[3];
            for (int i = 0; i < 3; i++) m[i] = 0.5 * (p[a][i] + p[b][i]);
            mid[a][b] = mid[b][a] = add_vertex(s, m, 1);
        }
    }
    for (unsigned f = 0; f < nf; f++) {
        unsigned n = off[f + 1] - off[f];
        const unsigned *c = idx + off[f];
        if (split[f]) {
            static const uint8_t one[4] = { 1, 1, 1, 1 };
            if (n == 3) {
                unsigned m0 = mid[c[0]][c[1]], m1 = mid[c[1]][c[2]], m2 = mid[c[2]][c[0]];
                unsigned t[4][3] = { { c[0], m0, m2 }, { m0, c[1], m1 }, { m1, c[2], m2 }, { m0, m1, m2 } };
                for (int i = 0; i < 4; i++) add_face(s, 3, t[i], one);
            } else {
                double ctr[3] = { 0, 0, 0 };
                for (unsigned k = 0; k < n; k++) for (int i = 0; i < 3; i++) ctr[i] += p[c[k]][i] / n;
                unsigned z = add_vertex(s, ctr, 1);
                for (unsigned k = 0; k < n; k++) {
                    unsigned q[4] = { c[k], mid[c[k]][c[(k + 1) % n]], z, mid[c[(k + n - 1) % n]][c[k]] };
                    add_face(s, 4, q, one);
                }
            }
        } else {
            unsigned cc[16];
            uint8_t ee[16];
            unsigned m = 0;
            for (unsigned k = 0; k < n; k++) {
                unsigned a = c[k], b = c[(k + 1) % n];
                if (mid[a][b] != ~0u) {
                    cc[m] = a; ee[m++] = 1;
                    cc[m] = mid[a][b]; ee[m++] = 1;
                } else {
                    cc[m] = a; ee[m++] = 0;
                }
            }
            add_face(s, m, cc, ee);
        }
    }
}

/* Triangulates every face by the tables (expecting the given patterns to
 * be used) and checks the welded triangles: each directed edge once, with
 * its reverse once (closed, oriented 2-manifold), V - E + F = 2. */
static void check_no_cracks(const soup *s, const char *name, const char *expect)
{
    unsigned ntri = 0, used[32] = { 0 };
    static uint32_t tris[3 * 1024];
    int fallback = 0;
    for (unsigned f = 0; f < s->nf; f++) {
        unsigned n = s->off[f + 1] - s->off[f];
        uint8_t v[16];
        for (unsigned k = 0; k < n; k++) v[k] = s->vlev[s->idx[s->off[f] + k]];
        uint32_t loc[3 * 16];
        int c = st_tri_face(&IX, n, s->elev + s->off[f], v, NULL, loc);
        if (c < 0) fallback = 1; else used[c]++;
        for (unsigned t = 0; t < 3 * (n - 2); t++) tris[3 * ntri + t] = s->idx[s->off[f] + loc[t]];
        ntri += n - 2;
    }
    CHECKF(!fallback, "%s: a face fell outside the tables", name);
    /* Every expected case (space-separated patterns) was used. */
    char buf[256];
    snprintf(buf, sizeof buf, "%s", expect);
    for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " ")) {
        int c = find_case(tok);
        CHECKF(c >= 0 && used[c] > 0, "%s: case %s not met", name, tok);
    }
    unsigned nv = s->nv;
    unsigned *cnt = calloc((size_t)nv * nv, sizeof *cnt);
    for (unsigned t = 0; t < ntri; t++)
        for (int k = 0; k < 3; k++) cnt[tris[3 * t + k] * nv + tris[3 * t + (k + 1) % 3]]++;
    unsigned bad = 0, edges = 0;
    for (unsigned a = 0; a < nv; a++)
        for (unsigned b = a + 1; b < nv; b++) {
            unsigned ab = cnt[a * nv + b], ba = cnt[b * nv + a];
            if (!ab && !ba) continue;
            edges++;
            if (ab != 1 || ba != 1) bad++;
        }
    free(cnt);
    CHECKF(bad == 0, "%s: %u edges not shared by exactly two triangles in opposite directions", name, bad);
    CHECKF((int)nv - (int)edges + (int)ntri == 2, "%s: V - E + F = %d", name, (int)nv - (int)edges + (int)ntri);
}

static void test_adaptive_polyhedra(void)
{
    static const double cube[8][3] = { {0,0,0}, {1,0,0}, {1,1,0}, {0,1,0}, {0,0,1}, {1,0,1}, {1,1,1}, {0,1,1} };
    static const unsigned coff[7] = { 0, 4, 8, 12, 16, 20, 24 };
    /* bottom, top, front (y=0), right (x=1), back (y=1), left (x=0) */
    static const unsigned cidx[24] = { 0,3,2,1, 4,5,6,7, 0,1,5,4, 1,2,6,5, 2,3,7,6, 3,0,4,7 };
    static const double tet[4][3] = { {1,1,1}, {-1,-1,1}, {-1,1,-1}, {1,-1,-1} };
    static const unsigned toff[5] = { 0, 3, 6, 9, 12 };
    static const unsigned tidx[12] = { 0,1,3, 0,2,1, 0,3,2, 1,2,3 };
    static const double oct[6][3] = { {1,0,0}, {-1,0,0}, {0,1,0}, {0,-1,0}, {0,0,1}, {0,0,-1} };
    static const unsigned ooff[9] = { 0, 3, 6, 9, 12, 15, 18, 21, 24 };
    static const unsigned oidx[24] = { 0,2,4, 2,1,4, 1,3,4, 3,0,4, 2,0,5, 1,2,5, 3,1,5, 0,3,5 };
    static const struct { const char *name; int poly; int split[8]; const char *expect; } cases[] = {
        /* Catmull-Clark quads next to finer quads. */
        { "cube, 1 face split", 0, { 1,0,0,0,0,0 }, "cccc cmccc" },
        { "cube, 2 adjacent faces split", 0, { 1,0,1,0,0,0 }, "cmccc cmcmcc" },
        { "cube, 2 opposite faces split", 0, { 1,1,0,0,0,0 }, "cmccmc" },
        { "cube, 3 faces split", 0, { 1,1,1,0,0,0 }, "cmcmcmc cmccmc" },
        { "cube, 5 faces split", 0, { 1,1,1,1,1,0 }, "cmcmcmcm" },
        /* Loop/Butterfly triangles next to finer triangles. */
        { "tetrahedron, 1 face split", 1, { 1,0,0,0 }, "ccc cmcc" },
        { "tetrahedron, 2 faces split", 1, { 1,1,0,0 }, "cmcmc" },
        { "tetrahedron, 3 faces split", 1, { 1,1,1,0 }, "cmcmcm" },
        { "octahedron, alternate faces split", 2, { 1,0,1,0,0,1,0,1 }, "cmcmcm" },
        { "octahedron, 3 faces split", 2, { 1,1,0,0,1,0,0,0 }, "cmcc cmcmc" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        static soup s;
        if (cases[i].poly == 0) make_adaptive(&s, cube, 8, coff, cidx, 6, cases[i].split);
        else if (cases[i].poly == 1) make_adaptive(&s, tet, 4, toff, tidx, 4, cases[i].split);
        else make_adaptive(&s, oct, 6, ooff, oidx, 8, cases[i].split);
        check_no_cracks(&s, cases[i].name, cases[i].expect);
    }
}

/* Doo-Sabin's border quads (dual encoding: edge levels only).  A surface
 * quad of level 1 whose corners 1 and 2 are Doo-Sabin points of level 2
 * (inside the coarse face, 9/16 toward their corner): the sides around
 * them are of level 2.  Read as "cmcc" from every starting corner, with
 * the diagonal from the first finer corner to the far coarse one, and a
 * valid triangulation of the (convex) quad.  With vertex levels (a primal
 * face) the same edge levels stay outside the tables; so does the
 * pentagon with two finer corners (test_reading). */
static void test_doosabin_border_quads(void)
{
    const double sq[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
    double xy0[4][2];
    for (unsigned k = 0; k < 4; k++) {
        /* corners 1 and 2: the Doo-Sabin point of that corner of the square */
        double w[4] = { 1.0 / 16, 3.0 / 16, 3.0 / 16, 1.0 / 16 };
        if (k == 1 || k == 2) {
            xy0[k][0] = xy0[k][1] = 0;
            for (unsigned j = 0; j < 4; j++) {
                double a = j == k ? 9.0 / 16 : (j + 2) % 4 == k ? w[0] : w[1];
                xy0[k][0] += a * sq[j][0];
                xy0[k][1] += a * sq[j][1];
            }
        } else {
            xy0[k][0] = sq[k][0];
            xy0[k][1] = sq[k][1];
        }
    }
    const uint8_t e0[4] = { 2, 2, 2, 1 };
    for (unsigned r = 0; r < 4; r++) {
        uint8_t e[4];
        double xy[4][2];
        for (unsigned k = 0; k < 4; k++) {
            e[k] = e0[(k + r) % 4];
            memcpy(xy[k], xy0[(k + r) % 4], sizeof xy[k]);
        }
        uint32_t tri[6];
        int c = st_tri_face(&IX, 4, e, NULL, NULL, tri);
        CHECKF(c == find_case("cmcc"), "doo-sabin border quad from corner %u: case %d", r, c);
        char what[64];
        snprintf(what, sizeof what, "doo-sabin border quad from corner %u", r);
        check_triangulation(4, tri, (const double (*)[2])xy, 1e-3, what);
        /* The diagonal joins the first finer corner (1 before rotation)
         * and the far coarse one (3). */
        unsigned a = (1 + 4 - r) % 4, b = (3 + 4 - r) % 4, found = 0;
        for (unsigned t = 0; t < 2; t++)
            for (unsigned k = 0; k < 3; k++) {
                uint32_t p = tri[3 * t + k], q = tri[3 * t + (k + 1) % 3];
                if ((p == a && q == b) || (p == b && q == a)) found++;
            }
        CHECKF(found == 2, "doo-sabin border quad from corner %u: diagonal %u-%u used %u times", r, a, b, found);
    }
    /* One finer corner: "cmcc" from that corner; two opposite or three:
     * every side fine, a regular quad. */
    const uint8_t one[4] = { 2, 2, 1, 1 }, all[4] = { 2, 2, 2, 2 };
    CHECK(case_of(4, one, NULL) == find_case("cmcc"));
    CHECK(case_of(4, all, NULL) == find_case("cccc"));
    /* Primal faces (vertex levels known) with an odd run stay outside. */
    const uint8_t v[4] = { 1, 2, 2, 1 };
    CHECK(case_of(4, e0, v) == ST_TRI_FALLBACK);
}

int main(void)
{
    st_tri_index_init(&IX);
    test_every_case();
    test_sqrt3_border_triangles();
    test_reading();
    test_fallback();
    test_adaptive_polyhedra();
    test_doosabin_border_quads();
    return TEST_END();
}
