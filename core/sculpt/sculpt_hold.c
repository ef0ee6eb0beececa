/* What a dab does after its tools (core/sculpt/sculpt.h): the layer
 * brush's heights, auto-smooth and the hold that keeps faces from flipping
 * or collapsing (issue 30: full strength must hold on any brush,
 * tests/ui/test_editor_brush_hold.c). */
#include "core/sculpt/sculpt_internal.h"

#include <math.h>
#include <string.h>

/* Layer (Blender's layer brush without "persistent"): a vertex rises to the
 * largest height any dab of the stroke asked of it, never more: each dab
 * moves it by what is left between that height and its displacement so far
 * (lay_o), along its normal when the stroke first reached it (so the
 * heights add up exactly along one direction). */
void sc_layer_finish(st_sculpt *bs, const st_sculpt_brush *b)
{
    double sgn = b->invert ? -1 : 1;
    for (uint32_t i = 0; i < bs->nlist; i++) {
        uint32_t v = bs->list[i];
        double step = bs->lay_t[i] - bs->lay_o[v];
        bs->lay_t[i] = -1; /* from here: the height before this dab, -1 none asked */
        if (!(step > 0)) continue;
        bs->lay_t[i] = bs->lay_o[v];
        bs->lay_o[v] += step;
        for (int k = 0; k < 3; k++) bs->disp[i][k] = sgn * step * bs->lay_n0[v][k];
    }
}

/* After auto-smooth and the hold changed the layer's steps: the height
 * each vertex reached is what moved it along its layer direction, so a
 * held vertex rises the rest of the way in a later dab if it can. */
void sc_layer_settle(st_sculpt *bs, const st_sculpt_brush *b)
{
    double sgn = b->invert ? -1 : 1;
    for (uint32_t i = 0; i < bs->nlist; i++) {
        if (bs->lay_t[i] < 0) continue;
        uint32_t v = bs->list[i];
        const double *n = bs->lay_n0[v], *dv = bs->disp[i];
        double got = sgn * (dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2]);
        bs->lay_o[v] = bs->lay_t[i] + (got > 0 ? fmin(got, bs->lay_o[v] - bs->lay_t[i]) : 0);
    }
}

/* ---- auto-smooth ----------------------------------------------------------------------- */

/* Blender's Auto-Smooth (sculpt.c, do_brush_action: a smooth pass over the
 * brush's vertices after each dab, autosmooth_factor times the falloff):
 * every vertex this dab moves goes toward the average of its one-ring as
 * the dab leaves them (positions plus the dab's displacements), by
 * a * its weight.  The result goes to disp2 and then replaces disp, so the
 * order of the vertices does not matter and a symmetric dab stays
 * symmetric. */
void sc_autosmooth(st_sculpt *bs, const st_map *m, double a)
{
    st_level_view lv;
    st_level_view_init(m, bs->level, &lv);
    for (uint32_t i = 0; i < bs->nlist; i++) {
        uint32_t v = bs->list[i];
        double *o = bs->disp2[i];
        memcpy(o, bs->disp[i], sizeof bs->disp2[0]);
        double k = a * bs->accw[i];
        if (!(k > 0)) continue;
        const double *p = st_v_pos(&lv, v);
        double avg[3] = { 0, 0, 0 };
        unsigned cnt = 0;
        if (bs->ring_at[v]) {
            /* The neighbours from v's ring record (every vertex a dab moves
             * has one): the corner after v on each face around it, one per
             * edge at v (the edge of a boundary vertex along the hole is
             * left out); no dart walk. */
            const uint32_t *r = bs->ring + bs->ring_at[v] - 1;
            uint32_t nf = r[0];
            r += 2;
            for (uint32_t f = 0; f < nf; f++, r += r[0] + 2) {
                uint32_t u = r[2];
                const double *q = st_v_pos(&lv, u);
                int moved = bs->mark[u] == bs->gen;
                for (int j = 0; j < 3; j++) avg[j] += q[j] + (moved ? bs->disp[bs->slot[u]][j] : 0);
                cnt++;
            }
        }
        if (!cnt) continue;
        for (int j = 0; j < 3; j++) o[j] += k * (avg[j] / cnt - p[j] - bs->disp[i][j]);
    }
    for (uint32_t i = 0; i < bs->nlist; i++) memcpy(bs->disp[i], bs->disp2[i], sizeof bs->disp[0]);
}

/* ---- holding the surface --------------------------------------------------------------- */

/* A face turned by more than acos HOLD_COS from its normal when the stroke
 * first reached it, or (but under crease and pinch) shrunk below HOLD_AREA
 * of its area then, is held:
 * issue 30 asks that no face flip (turn past 90 degrees) under any brush
 * at full strength, and that none collapse. */
#define HOLD_COS 0.719 /* cos 44 degrees: two strokes stay under 90 */
#define HOLD_AREA 0.1

static int face_held(const st_sculpt *bs, const st_level_view *lv, const uint32_t *r, const double n0[3],
                     int shrinks)
{
    double n[3];
    sc_face_normal(bs, lv, r, 1, n);
    double a = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), a0 = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
    return !(n[0] * n0[0] + n[1] * n0[1] + n[2] * n0[2] > HOLD_COS * a * a0) || (!shrinks && !(a >= HOLD_AREA * a0));
}

/* The clamp that makes the guarantee: after the brush and its auto-smooth,
 * every face around a vertex the dab moves is checked against its
 * reference.  Around the faces that would be held the dab is damped
 * smoothly: each moved vertex's displacement is scaled by
 * 1 - k K(d / rho), K the smooth falloff, d its distance to the nearest
 * held face (its centroid on a lattice of R/8, hold_push), rho half
 * the dab's radius, k = 1/2, pass after
 * pass (the displacement stays a smooth field: halving the corners of the
 * held faces alone left the surface crumpled, and so did slowing each
 * vertex by its own normal's turn).  After HOLD_SMOOTH passes the corners
 * of faces still held (and their mirror images) are taken back, until
 * none is: a face whose
 * corners all stay where they were is as it was before the dab, which
 * held, so this ends (at worst with the dab taken back). */
#define HOLD_SMOOTH 8

/* Records a held face by its centroid c snapped to the lattice of spacing
 * h, unless that lattice point is recorded already (a held region is a
 * few points, not one per face: hold_damp visits every moved vertex per
 * point).  round() is odd, so the lattice points of mirrored faces are
 * mirrored and a symmetric dab stays symmetric. */
static void hold_point(st_sculpt *bs, const double p[3], double reach)
{
    for (uint32_t i = 0; i < bs->nheld; i++)
        if (bs->held[i][0] == p[0] && bs->held[i][1] == p[1] && bs->held[i][2] == p[2]) {
            if (reach > bs->heldr[i]) bs->heldr[i] = reach;
            return;
        }
    if (bs->nheld == bs->capheld) {
        bs->capheld = bs->capheld ? 2 * bs->capheld : 64;
        bs->held = sc_xrealloc(bs->held, (size_t)bs->capheld * sizeof *bs->held);
        bs->heldr = sc_xrealloc(bs->heldr, (size_t)bs->capheld * sizeof *bs->heldr);
    }
    bs->heldr[bs->nheld] = reach;
    memcpy(bs->held[bs->nheld++], p, sizeof bs->held[0]);
}

/* ... with its reflections across the brush's symmetry planes too: a held
 * face and its mirror image damp alike even where rounding held only one
 * of them (their normals are summed in opposite orders). */
static void hold_push(st_sculpt *bs, const st_sculpt_brush *b, const double c[3], double corner, double h)
{
    uint8_t which[8];
    unsigned nsym = sc_symmetry_set(b, which);
    double p[3], q[3], off = 0;
    for (int k = 0; k < 3; k++) {
        p[k] = round(c[k] / h) * h;
        off += (p[k] - c[k]) * (p[k] - c[k]);
    }
    /* reach: every corner of the face is within it of p */
    double reach = corner + sqrt(off) + 1e-9 * h;
    for (unsigned s = 0; s < nsym; s++) {
        sc_reflect(which[s], p, q);
        hold_point(bs, q, reach);
    }
}

/* The hard pass: every moved vertex within a held point's reach (so every
 * corner of every held face, and their mirror images) is taken back. */
static void hold_zero(st_sculpt *bs, const st_level_view *lv)
{
    for (uint32_t i = 0; i < bs->nlist; i++) {
        const double *p = st_v_pos(lv, bs->list[i]);
        for (uint32_t h = 0; h < bs->nheld; h++) {
            double dx = p[0] - bs->held[h][0], dy = p[1] - bs->held[h][1], dz = p[2] - bs->held[h][2];
            if (dx * dx + dy * dy + dz * dz <= bs->heldr[h] * bs->heldr[h]) {
                bs->disp[i][0] = bs->disp[i][1] = bs->disp[i][2] = 0;
                break;
            }
        }
    }
}

/* Scales every displacement by 1 - k K(distance to the nearest held point / rho). */
static void hold_damp(st_sculpt *bs, const st_level_view *lv, double rho, double k)
{
    for (uint32_t i = 0; i < bs->nlist; i++) {
        const double *p = st_v_pos(lv, bs->list[i]);
        double near = INFINITY;
        for (uint32_t h = 0; h < bs->nheld; h++) {
            double dx = p[0] - bs->held[h][0], dy = p[1] - bs->held[h][1], dz = p[2] - bs->held[h][2];
            double r2 = dx * dx + dy * dy + dz * dz;
            if (r2 < near) near = r2;
        }
        double f = 1 - k * st_falloff_eval(ST_FALLOFF_SMOOTH, sqrt(near), rho);
        for (int j = 0; j < 3; j++) bs->disp[i][j] *= f;
    }
}

void sc_hold_faces(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b)
{
    st_level_view lv;
    st_level_view_init(m, bs->level, &lv);
    /* Crease and pinch pull vertices together: their faces may shrink. */
    int shrinks = b->tool == ST_BRUSH_CREASE || b->tool == ST_BRUSH_PINCH;
    for (unsigned pass = 0; pass < HOLD_SMOOTH + 64; pass++) {
        int hard = pass >= HOLD_SMOOTH;
        bs->nheld = 0;
        for (uint32_t i = 0; i < bs->nlist; i++) {
            uint32_t v = bs->list[i];
            if (!bs->ring_at[v]) continue;
            const uint32_t *r = bs->ring + bs->ring_at[v] - 1;
            uint32_t nf = r[0], f0 = r[1];
            r += 2;
            for (uint32_t f = 0; f < nf; f++, r += r[0] + 2) {
                /* A face is checked from each moved corner, against the
                 * reference that corner's ring recorded: mirrored faces
                 * then get mirrored decisions (checking it once, from one
                 * corner chosen by id, did not: ids are not mirrored). */
                if (!face_held(bs, &lv, r, bs->fn[f0 + f], shrinks)) continue;
                double c[3] = { 0, 0, 0 }, corner = 0;
                for (uint32_t t = 1; t <= r[0]; t++) {
                    const double *q = st_v_pos(&lv, r[t]);
                    for (int j = 0; j < 3; j++) c[j] += q[j] / r[0];
                }
                for (uint32_t t = 1; t <= r[0]; t++) {
                    const double *q = st_v_pos(&lv, r[t]);
                    double e = sqrt((q[0] - c[0]) * (q[0] - c[0]) + (q[1] - c[1]) * (q[1] - c[1]) + (q[2] - c[2]) * (q[2] - c[2]));
                    if (e > corner) corner = e;
                }
                hold_push(bs, b, c, corner, 0.125 * bs->R);
            }
        }
        if (!bs->nheld) return;
        if (hard) hold_zero(bs, &lv);
        else hold_damp(bs, &lv, 0.5 * bs->R, 0.5);
    }
    for (uint32_t i = 0; i < bs->nlist; i++) bs->disp[i][0] = bs->disp[i][1] = bs->disp[i][2] = 0;
}
