/* What each tool does under one dab (core/sculpt/sculpt.h, sculpt.c).
 *
 * Input: the dab's centre c and unit normal n, and the vertices under it
 * with their weights w (falloff times strength times the front-face test
 * times the stroke's fade, sc_weight), unit normals vn and areas.
 * With st_sculpt_brush.area_plane (the document's default) n is the normal of the area under
 * the dab and the plane of flatten and clay strips goes through its
 * weighted centroid (dab_plane); without, n is the normal given with the
 * dab (the pick's under the cursor) and the plane the plain mean's.
 * R is the dab's radius (st_sculpt_dab_radius), sgn -1 when the stroke is
 * inverted, else 1.  Heights below are times hs and fractions times
 * fs, the spacing attenuation (st_sculpt_begin; both 1 without it).  All
 * displacements are computed from the positions before the dab:
 *
 *   draw         along n by sgn * w * R/10 (Blender's draw: the area normal)
 *   smooth       toward the one-ring average by w
 *   flatten      toward the plane, by w of the distance
 *   crease       into the surface (sgn: out) along n by w * R/10, and toward
 *                the dab's axis in the plane of n by w/2 of the offset (w
 *                with the attenuation, as Blender's pinch): a sharp groove
 *                whose sides are pinched together (Blender's crease, pinch
 *                factor 0.5); within a stroke only across it
 *   pinch        the pinch of crease alone (sgn: away)
 *   inflate      along the vertex's own normal vn by sgn * w * R/10
 *   clay strips  toward the plane of flatten raised by sgn * R/10, only the
 *                vertices below it (sgn: above), by w of the distance: a
 *                flat-bottomed build-up whose top stops at the raised plane
 *   layer        up to the height w * R/10 along vn (as it was when the
 *                stroke reached the vertex), the largest any dab of the
 *                stroke asked, never more (sculpt_hold.c: sc_layer_finish)
 *   relax        by w times the Laplacian (one-ring average minus position)
 *                less its component along vn: the vertices slide along the
 *                surface toward even spacing and the shape stays
 */
#include "core/sculpt/sculpt_internal.h"

#include <math.h>
#include <string.h>

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Average of the one-ring neighbours of the vertex of dart x0, minus p. */
static void laplacian(const st_map *m, uint32_t x0, unsigned l, const double p[3], double lap[3])
{
    double avg[3] = { 0, 0, 0 };
    unsigned cnt = 0;
    uint32_t x = x0;
    do {
        const double *q = st_dart_pos(m, st_beta0(m, x, l), l);
        for (int k = 0; k < 3; k++) avg[k] += q[k];
        cnt++;
        x = st_vertex_step(m, x, l);
    } while (x != x0 && cnt < 1u << 16);
    for (int k = 0; k < 3; k++) lap[k] = avg[k] / cnt - p[k];
}

/* The plane of the area under the dab, as Blender's
 * calc_area_normal_and_center and ZBrush's brushes take it: the centroid of
 * the vertices under the dab weighted by their brush weights, and the sum
 * of their area-weighted normals times those weights, normalised.  One
 * vertex's normal (or the pick's, under the cursor) swings from dab to dab
 * on a bumpy or freshly drawn surface and pushes the surface sideways
 * until it folds; the area's does not.  The dab's normal n when the area's
 * vanishes or faces away from it. */
static void dab_plane(const st_map *m, unsigned l, const st_sculpt *bs, const double n[3], double c0[3],
                      double pn[3])
{
    c0[0] = c0[1] = c0[2] = 0;
    pn[0] = pn[1] = pn[2] = 0;
    double ws = 0;
    for (uint32_t i = 0; i < bs->ntmp; i++) {
        const double *p = st_pos(m, bs->tmp[i], l);
        double w = bs->tmpw[i], wa = w * bs->tmpa[i];
        ws += w;
        for (int k = 0; k < 3; k++) { c0[k] += w * p[k]; pn[k] += wa * bs->tmpn[i][k]; }
    }
    if (ws > 0) for (int k = 0; k < 3; k++) c0[k] /= ws;
    double len = sqrt(dot3(pn, pn));
    if (len > 0 && dot3(pn, n) > 0) for (int k = 0; k < 3; k++) pn[k] /= len;
    else memcpy(pn, n, sizeof *pn * 3);
}

/* Without the area plane (st_sculpt_brush.area_plane 0): flatten's and clay
 * strips' plane through the plain mean of the vertices under the dab, its
 * normal their mean normal (the dab's when it vanishes). */
static void mean_plane(const st_map *m, unsigned l, const st_sculpt *bs, const double n[3], double c0[3],
                       double pn[3])
{
    c0[0] = c0[1] = c0[2] = 0;
    pn[0] = pn[1] = pn[2] = 0;
    for (uint32_t i = 0; i < bs->ntmp; i++) {
        const double *p = st_pos(m, bs->tmp[i], l);
        for (int k = 0; k < 3; k++) { c0[k] += p[k] / bs->ntmp; pn[k] += bs->tmpn[i][k]; }
    }
    double len = sqrt(dot3(pn, pn));
    if (len > 0) for (int k = 0; k < 3; k++) pn[k] /= len;
    else memcpy(pn, n, sizeof *pn * 3);
}

void sc_tool_dab(st_sculpt *bs, const st_map *m, const st_sculpt_brush *b, const double c[3], const double n[3])
{
    unsigned l = bs->level;
    int tool = b->tool;
    double R = bs->R, sgn = b->invert ? -1 : 1;
    /* Spacing attenuation (st_sculpt_begin): heights and fractions per dab. */
    double hs = bs->hscale, fs = bs->fscale;
    double c0[3] = { 0, 0, 0 }, pn[3] = { 0, 0, 0 };
    if (b->area_plane) {
        dab_plane(m, l, bs, n, c0, pn);
        n = pn; /* draw, crease and pinch work in the area's plane too */
    } else if (tool == ST_BRUSH_FLATTEN || tool == ST_BRUSH_CLAY_STRIPS) {
        mean_plane(m, l, bs, n, c0, pn);
    }
    if (tool == ST_BRUSH_CLAY_STRIPS)
        for (int k = 0; k < 3; k++) c0[k] += sgn * 0.1 * R * pn[k];
    /* Crease and pinch in a stroke pull across it only: in the middle of a
     * stroke the pulls along it of the dabs before and after a vertex
     * cancel, so dropping them changes little there; at the ends nothing
     * cancels them, and a crease ended in a star of faces pulled in from
     * every side (issue 30).  The stroke's direction in the dab's plane;
     * none for the first dab or a dab in place (radial, as before).  With
     * the stroke's fade (st_sculpt_brush.fade > 0): both taper a stroke's ends. */
    double along[3] = { 0, 0, 0 };
    const double *stroke_dir = NULL;
    if ((tool == ST_BRUSH_CREASE || tool == ST_BRUSH_PINCH) && b->fade > 0) {
        double dn = dot3(bs->dab_dir, n);
        for (int k = 0; k < 3; k++) along[k] = bs->dab_dir[k] - dn * n[k];
        double len = sqrt(dot3(along, along));
        if (len > 1e-6) {
            for (int k = 0; k < 3; k++) along[k] /= len;
            stroke_dir = along;
        }
    }
    for (uint32_t i = 0; i < bs->ntmp; i++) {
        uint32_t v = bs->tmp[i];
        double w = bs->tmpw[i], dv[3] = { 0, 0, 0 };
        const double *vn = bs->tmpn[i];
        const double *p = st_pos(m, v, l);
        uint32_t x0 = sc_vertex_dart(bs, v);
        if (x0 == ST_NIL) continue;
        sc_acc_weight(bs, v, w);
        switch (tool) {
        case ST_BRUSH_DRAW:
        case ST_BRUSH_INFLATE: {
            const double *dir = tool == ST_BRUSH_DRAW ? n : vn;
            double a = sgn * w * R * 0.1 * hs;
            for (int k = 0; k < 3; k++) dv[k] = a * dir[k];
            break;
        }
        case ST_BRUSH_SMOOTH: {
            double lap[3];
            laplacian(m, x0, l, p, lap);
            for (int k = 0; k < 3; k++) dv[k] = w * lap[k];
            break;
        }
        case ST_BRUSH_RELAX: {
            double lap[3];
            laplacian(m, x0, l, p, lap);
            double ln = dot3(lap, vn);
            for (int k = 0; k < 3; k++) dv[k] = w * (lap[k] - ln * vn[k]);
            break;
        }
        case ST_BRUSH_FLATTEN:
        case ST_BRUSH_CLAY_STRIPS: {
            double hgt = (p[0] - c0[0]) * pn[0] + (p[1] - c0[1]) * pn[1] + (p[2] - c0[2]) * pn[2];
            if (tool == ST_BRUSH_CLAY_STRIPS && !(sgn * hgt < 0)) break;
            for (int k = 0; k < 3; k++) dv[k] = -w * fs * hgt * pn[k];
            break;
        }
        case ST_BRUSH_CREASE:
        case ST_BRUSH_PINCH: {
            double to[3] = { c[0] - p[0], c[1] - p[1], c[2] - p[2] };
            double along_n = dot3(to, n);
            /* Raw: half the offset per dab; attenuated for spacing, the
             * whole offset over the overlap as Blender's pinch (its
             * do_pinch_brush moves by the offset times the fade). */
            double pk = b->space_atten ? 1.0 : 0.5;
            double f = (tool == ST_BRUSH_PINCH ? sgn * pk * w : pk * w) * fs;
            for (int k = 0; k < 3; k++) dv[k] = f * (to[k] - along_n * n[k]);
            if (stroke_dir) {
                /* only across the stroke (see stroke_dir above) */
                double a = dot3(dv, stroke_dir);
                for (int k = 0; k < 3; k++) dv[k] -= a * stroke_dir[k];
            }
            if (tool == ST_BRUSH_CREASE)
                for (int k = 0; k < 3; k++) dv[k] -= sgn * w * R * 0.1 * hs * n[k];
            break;
        }
        case ST_BRUSH_LAYER: sc_acc_layer(bs, v, w * R * 0.1, vn); continue;
        default: continue;
        }
        sc_acc(bs, v, dv);
    }
}
