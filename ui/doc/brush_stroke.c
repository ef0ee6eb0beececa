/* The dabs of a stroke along the cursor's path (editor.h: st_stroke_path).
 *
 * Spacing as Blender's "space" stroke method: a dab every `spacing` of path
 * length, the positions interpolated linearly between the events, so that
 * the dabs depend on the path and not on how often the events came.  The
 * stabiliser is Blender's "lazy mouse" (smooth stroke): the brush point
 * stays at distance `lazy` behind the cursor, pulled along the line to it
 * when the cursor gets further, and does not move while the cursor is
 * within that distance. */
#include "editor.h"

#include <math.h>
#include <string.h>

void st_stroke_path_begin(st_stroke_path *sp, const double cursor[3])
{
    memcpy(sp->brush, cursor, sizeof sp->brush);
    sp->since = 0;
}

unsigned st_stroke_path_move(st_stroke_path *sp, const double cursor[3], double spacing, double lazy,
                             void (*dab)(void *ctx, const double p[3]), void *ctx)
{
    double to[3], dir[3];
    for (int k = 0; k < 3; k++) dir[k] = cursor[k] - sp->brush[k];
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (lazy > 0) {
        /* The brush point moves only by what the cursor is beyond `lazy`. */
        if (!(len > lazy)) return 0;
        double go = len - lazy;
        for (int k = 0; k < 3; k++) to[k] = sp->brush[k] + dir[k] * (go / len);
        len = go;
    } else {
        memcpy(to, cursor, sizeof to);
    }
    if (!(len > 0)) return 0;
    unsigned n = 0;
    if (!(spacing > 0)) {
        memcpy(sp->brush, to, sizeof sp->brush);
        dab(ctx, sp->brush);
        return 1;
    }
    /* Dabs at path length spacing - since, 2 spacing - since, ... along the
     * segment brush -> to, each placed from the segment's start. */
    double from[3];
    memcpy(from, sp->brush, sizeof from);
    double at = spacing - sp->since;
    while (at <= len) {
        double t = at / len, p[3];
        for (int k = 0; k < 3; k++) p[k] = from[k] + (to[k] - from[k]) * t;
        dab(ctx, p);
        n++;
        at += spacing;
    }
    sp->since = len - (at - spacing);
    memcpy(sp->brush, to, sizeof sp->brush);
    return n;
}

unsigned st_stroke_path_end(st_stroke_path *sp, const double cursor[3], double spacing,
                            void (*dab)(void *ctx, const double p[3], double k), void *ctx)
{
    double dir[3], from[3];
    for (int k = 0; k < 3; k++) dir[k] = cursor[k] - sp->brush[k];
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(len > 0) || !(spacing > 0)) return 0;
    memcpy(from, sp->brush, sizeof from);
    unsigned n = 0;
    double at = spacing - sp->since;
    for (; at <= len; at += spacing) {
        double t = at / len, p[3];
        for (int k = 0; k < 3; k++) p[k] = from[k] + dir[k] * t;
        double u = 1 - t;   /* 1 at the brush point, 0 at the cursor */
        dab(ctx, p, 0.1 + 0.9 * u * u * (3 - 2 * u));
        n++;
    }
    sp->since = len - (at - spacing);
    memcpy(sp->brush, cursor, sizeof sp->brush);
    return n;
}
