/* Case tables for the triangulation of adaptive faces; see triangulate.h
 * for how a face's case is read from its edge levels. */
#include "render/triangulate.h"

#include "core/map/geometry.h"

#include <math.h>
#include <pthread.h>
#include <string.h>

/* The table.  Corner numbers follow the face walk (counter-clockwise seen
 * from outside); each triangle is counter-clockwise too.  Rule for the
 * split faces (Loop, Butterfly, quad/triangle, Catmull-Clark): a hanging
 * vertex 'm' is never joined only to the two ends of its own coarse edge
 * (that triangle would be flat: the three points are nearly collinear,
 * thesis §3.3.3); it fans out to the far corners, as listing 3.3.1 does for
 * the 5-gon, and a corner between two split edges is cut off by the triangle
 * of the two midpoints, as triangle quadrisection does.  Regular polygons
 * (Doo-Sabin's faces, input n-gons) cut off every second corner and fill the
 * middle, which keeps the triangles of a regular polygon fat. */
const st_tri_case st_tri_cases[] = {
    /* ---- any 3-sided face: plain triangles, and √3 border triangles --------
     *        2
     *       / \
     *      0---1      (0,1,2)                                              */
    { "triangle", "ccc", 1, { {0,1,2} } },

    /* ---- triangles with split edges (Loop, Butterfly, quad/triangle) ------
     * 4 sides, edge levels f+1 f+1 f f:
     *        3
     *       /|\
     *      / | \
     *     0--1--2     (0,1,3) (1,2,3)                                      */
    { "triangle, 1 split edge", "cmcc", 2, { {0,1,3}, {1,2,3} } },
    /* 5 sides, edge levels f+1 f+1 f+1 f+1 f:
     *        4
     *       /|\
     *      / | 3
     *     /  |/ \
     *    0---1---2    (1,2,3) (0,1,4) (1,3,4)                              */
    { "triangle, 2 split edges", "cmcmc", 3, { {1,2,3}, {0,1,4}, {1,3,4} } },
    /* 6 sides, all edge levels f+1 (corners inserted <= f, midpoints at f+1):
     *        4
     *       / \
     *      5---3
     *     / \ / \
     *    0---1---2    (0,1,5) (1,2,3) (3,4,5) (1,3,5)                      */
    { "triangle, 3 split edges", "cmcmcm", 4, { {0,1,5}, {1,2,3}, {3,4,5}, {1,3,5} } },

    /* ---- quads with split edges (Catmull-Clark, quad/triangle) -------------
     * 4 sides, one level:
     *    3-----2
     *    |   / |
     *    | /   |
     *    0-----1      (0,1,2) (0,2,3)                                      */
    { "quad", "cccc", 2, { {0,1,2}, {0,2,3} } },
    /* 5 sides, edge levels f+1 f+1 f f f (listing 3.3.1, from b = corner 4):
     *    4-------3
     *    | \   / |
     *    |  \ /  |
     *    0---1---2    (0,1,4) (1,2,3) (1,3,4)                              */
    { "quad, 1 split edge", "cmccc", 3, { {0,1,4}, {1,2,3}, {1,3,4} } },
    /* 6 sides, two adjacent split edges, levels f+1 f+1 f+1 f+1 f f:
     *    5-------4
     *    |\`-._  |
     *    | \   `-3
     *    |  \  / |
     *    0---1---2    (1,2,3) (0,1,5) (1,3,5) (3,4,5)                      */
    { "quad, 2 adjacent split edges", "cmcmcc", 4, { {1,2,3}, {0,1,5}, {1,3,5}, {3,4,5} } },
    /* 6 sides, two opposite split edges, levels f+1 f+1 f f+1 f+1 f:
     *    5---4---3
     *    |  /|  /|
     *    | / | / |
     *    |/  |/  |
     *    0---1---2    (0,1,4) (0,4,5) (1,2,3) (1,3,4)                      */
    { "quad, 2 opposite split edges", "cmccmc", 4, { {0,1,4}, {0,4,5}, {1,2,3}, {1,3,4} } },
    /* 7 sides, three split edges, levels f+1 x6 then f:
     *    6---5---4
     *    |\  |`. |
     *    | \ |  `3
     *    |  \| / |
     *    0---1---2    (1,2,3) (3,4,5) (1,3,5) (1,5,6) (0,1,6)              */
    { "quad, 3 split edges", "cmcmcmc", 5, { {1,2,3}, {3,4,5}, {1,3,5}, {1,5,6}, {0,1,6} } },
    /* 8 sides, all four edges split (all levels f+1):
     *    6---5---4
     *    | / | \ |
     *    7   |   3
     *    | \ | / |
     *    0---1---2    (7,0,1) (1,2,3) (3,4,5) (5,6,7) (1,3,5) (1,5,7)      */
    { "quad, 4 split edges", "cmcmcmcm", 6, { {7,0,1}, {1,2,3}, {3,4,5}, {5,6,7}, {1,3,5}, {1,5,7} } },

    /* ---- regular polygons: Doo-Sabin's faces (valence-n and n-sided faces),
     * input n-gons at their own level -------------------------------------
     *      3
     *    4   2
     *    0---1        (0,1,2) (0,2,3) (0,3,4)                              */
    { "pentagon", "ccccc", 3, { {0,1,2}, {0,2,3}, {0,3,4} } },
    /*     4---3
     *    5     2
     *     0---1       (0,1,2) (2,3,4) (4,5,0) (0,2,4)                      */
    { "hexagon", "cccccc", 4, { {0,1,2}, {2,3,4}, {4,5,0}, {0,2,4} } },
    /*      4
     *    5   3
     *   6     2
     *    0---1        (0,1,2) (2,3,4) (4,5,6) (0,2,4) (0,4,6)              */
    { "heptagon", "ccccccc", 5, { {0,1,2}, {2,3,4}, {4,5,6}, {0,2,4}, {0,4,6} } },
    /*    5---4
     *   6     3
     *   7     2
     *    0---1        (0,1,2) (2,3,4) (4,5,6) (6,7,0) (0,2,4) (0,4,6)      */
    { "octagon", "cccccccc", 6, { {0,1,2}, {2,3,4}, {4,5,6}, {6,7,0}, {0,2,4}, {0,4,6} } },
};
const unsigned st_tri_ncases = sizeof st_tri_cases / sizeof st_tri_cases[0];

void st_tri_index_init(st_tri_index *ix)
{
    for (unsigned n = 0; n <= ST_TRI_TABLE_MAX_SIDES; n++)
        for (unsigned k = 0; k < (1u << ST_TRI_TABLE_MAX_SIDES); k++) { ix->icase[n][k] = -1; ix->rot[n][k] = 0; }
    for (unsigned i = 0; i < st_tri_ncases; i++) {
        const char *p = st_tri_cases[i].pattern;
        unsigned n = (unsigned)strlen(p);
        for (unsigned r = 0; r < n; r++) {
            uint32_t mask = 0;
            for (unsigned k = 0; k < n; k++)
                if (p[(k + n - r) % n] == 'm') mask |= 1u << k;
            if (ix->icase[n][mask] < 0) { ix->icase[n][mask] = (int16_t)i; ix->rot[n][mask] = (uint8_t)r; }
        }
    }
}

static st_tri_index shared_index;
static pthread_once_t shared_once = PTHREAD_ONCE_INIT;
static void shared_index_init(void) { st_tri_index_init(&shared_index); }

const st_tri_index *st_tri_index_shared(void)
{
    pthread_once(&shared_once, shared_index_init);
    return &shared_index;
}

int st_tri_classify(unsigned n, const uint8_t *e, const uint8_t *v, uint32_t *mmask)
{
    *mmask = 0;
    if (n < 3 || n > ST_TRI_TABLE_MAX_SIDES) return -1;
    if (n == 3) return 0;
    unsigned lo = e[0], hi = e[0], s0 = 0;
    for (unsigned k = 1; k < n; k++) {
        if (e[k] < lo) { lo = e[k]; s0 = k; }
        if (e[k] > hi) hi = e[k];
    }
    uint32_t mask = 0;
    if (hi == lo) {
        /* All sides alike: a regular polygon, or (when every second corner
         * is a vertex of level lo and the others older) a face of level
         * lo-1 whose every edge was split. */
        if (!v || lo == 0 || n % 2 || n < 6) return 0;
        for (unsigned p = 0; p < 2 && !mask; p++) {
            int ok = 1;
            for (unsigned k = 0; k < n && ok; k++)
                ok = (k % 2 == p) ? v[k] == lo : v[k] < lo;
            if (ok)
                for (unsigned k = p; k < n; k += 2) mask |= 1u << k;
        }
        *mmask = mask;
        return 0;
    }
    if (hi != lo + 1) return -1;
    /* Runs of fine sides start after the coarse side s0; inside a run the
     * sides pair up and the corner ending a pair's first half is 'm'. */
    unsigned run = 0;
    for (unsigned i = 1; i <= n; i++) {
        unsigned k = (s0 + i) % n;
        if (e[k] == hi) {
            run++;
            if (run % 2) mask |= 1u << ((k + 1) % n);
        } else {
            if (run % 2) {
                /* Dual encoding (no vertex levels): Doo-Sabin's border quad
                 * with two adjacent corners one level finer (their three
                 * sides are fine).  The first of them is read as 'm' and
                 * the face as "cmcc": the diagonal from that corner to the
                 * far coarse one (the finer corners lie inside the coarse
                 * surface face, which keeps it on the inside). */
                if (v || n != 4 || run != 3) return -1;
                mask &= ~(1u << k); /* the coarse corner ending the run */
            }
            run = 0;
        }
    }
    if (v)
        for (unsigned k = 0; k < n; k++) {
            int m = (mask >> k) & 1u;
            if (m ? v[k] != hi : v[k] > lo) return -1;
        }
    unsigned nm = 0;
    for (unsigned k = 0; k < n; k++) nm += (mask >> k) & 1u;
    if (n - nm < 3) return -1;
    *mmask = mask;
    return 0;
}

/* ---- fallback ---------------------------------------------------------------- */

static void fan(unsigned n, uint32_t *tri)
{
    for (unsigned i = 0; i + 2 < n; i++) { tri[3 * i] = 0; tri[3 * i + 1] = i + 1; tri[3 * i + 2] = i + 2; }
}

static double cross2(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* p inside or on triangle abc (counter-clockwise), up to eps: a corner on
 * the new diagonal would leave a flat triangle behind. */
static int inside(const double *a, const double *b, const double *c, const double *p, double eps)
{
    return cross2(a, b, p) >= -eps && cross2(b, c, p) >= -eps && cross2(c, a, p) >= -eps;
}

void st_tri_fallback(unsigned n, const float *pos, uint32_t *tri)
{
    if (n < 3) return;
    if (n == 3 || !pos || n > ST_TRI_EAR_MAX) { fan(n, tri); return; }
    /* Newell normal and a plane basis. */
    double nv[3];
    st_newell_points_f(pos, n, nv);
    double nx = nv[0], ny = nv[1], nz = nv[2];
    double len = sqrt(nx * nx + ny * ny + nz * nz);
    if (!(len > 0) || !isfinite(len)) { fan(n, tri); return; }
    nx /= len; ny /= len; nz /= len;
    double ux, uy, uz;                       /* any unit vector orthogonal to n */
    if (fabs(nx) < 0.9) { ux = 0; uy = nz; uz = -ny; } else { ux = -nz; uy = 0; uz = nx; }
    double ul = sqrt(ux * ux + uy * uy + uz * uz);
    ux /= ul; uy /= ul; uz /= ul;
    double vx = ny * uz - nz * uy, vy = nz * ux - nx * uz, vz = nx * uy - ny * ux;
    double p[ST_TRI_EAR_MAX][2];
    unsigned next[ST_TRI_EAR_MAX], prev[ST_TRI_EAR_MAX];
    double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
    for (unsigned i = 0; i < n; i++) {
        const float *a = pos + 3 * i;
        p[i][0] = a[0] * ux + a[1] * uy + a[2] * uz;
        p[i][1] = a[0] * vx + a[1] * vy + a[2] * vz;
        next[i] = (i + 1) % n;
        prev[i] = (i + n - 1) % n;
        for (int k = 0; k < 2; k++) { if (p[i][k] < lo[k]) lo[k] = p[i][k]; if (p[i][k] > hi[k]) hi[k] = p[i][k]; }
    }
    /* Areas below eps (relative to the polygon's extent) count as flat. */
    double ext = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    double eps = 1e-9 * ext * ext;
    unsigned left = n, start = 0, t = 0;
    while (left > 3) {
        /* Best ear: convex, no other corner inside or on it, largest
         * area / sum of squared sides; else the best convex corner; else
         * the least concave one (a degenerate polygon: any ear closes it). */
        unsigned best = n, best_convex = n, least_bad = start;
        double bq = -1, bqc = -1, bc = -INFINITY;
        unsigned i = start;
        do {
            const double *a = p[prev[i]], *b = p[i], *c = p[next[i]];
            double cr = cross2(a, b, c);
            double s = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1])
                     + (c[0] - b[0]) * (c[0] - b[0]) + (c[1] - b[1]) * (c[1] - b[1])
                     + (a[0] - c[0]) * (a[0] - c[0]) + (a[1] - c[1]) * (a[1] - c[1]);
            double q = s > 0 ? cr / s : 0;
            if (cr > bc) { bc = cr; least_bad = i; }
            if (cr > eps) {
                if (q > bqc) { bqc = q; best_convex = i; }
                int empty = 1;
                for (unsigned j = next[next[i]]; j != prev[i] && empty; j = next[j])
                    if (inside(a, b, c, p[j], eps)) empty = 0;
                if (empty && q > bq) { bq = q; best = i; }
            }
            i = next[i];
        } while (i != start);
        unsigned e = best < n ? best : best_convex < n ? best_convex : least_bad;
        tri[3 * t] = prev[e]; tri[3 * t + 1] = e; tri[3 * t + 2] = next[e];
        t++;
        next[prev[e]] = next[e];
        prev[next[e]] = prev[e];
        start = next[e];
        left--;
    }
    tri[3 * t] = prev[start]; tri[3 * t + 1] = start; tri[3 * t + 2] = next[start];
}

int st_tri_face(const st_tri_index *ix, unsigned n, const uint8_t *elev, const uint8_t *vlev,
                const float *pos, uint32_t *tri)
{
    if (n == 3) { tri[0] = 0; tri[1] = 1; tri[2] = 2; return 0; }
    uint32_t mask;
    if (n <= ST_TRI_TABLE_MAX_SIDES && st_tri_classify(n, elev, vlev, &mask) == 0) {
        int c = ix->icase[n][mask];
        if (c >= 0) {
            const st_tri_case *tc = &st_tri_cases[c];
            unsigned r = ix->rot[n][mask];
            for (unsigned t = 0; t < tc->ntri; t++)
                for (unsigned k = 0; k < 3; k++) tri[3 * t + k] = (tc->tri[t][k] + r) % n;
            return c;
        }
    }
    st_tri_fallback(n, pos, tri);
    return ST_TRI_FALLBACK;
}
