/* Sculpting kernels: what a brush dab does to one level of a hierarchy.
 *
 * A stroke is begin, dabs, end on one level l of a hierarchy whose
 * topology does not change meanwhile.  Each dab finds the vertices of l
 * inside its radius (a spatial grid of the level built at begin and kept
 * exact as vertices move), weighs each one (falloff preset at its
 * distance, times the strength, times the front-face test, times the
 * stroke's fade given with the dab), computes every tool's displacement
 * from the positions before the dab (sculpt_tools.c), repeated across the
 * enabled symmetry planes and summed, then auto-smooth and the hold that
 * keeps faces from flipping or collapsing (sculpt_hold.c), and finally the
 * mask (the displacement times 1 - mask; a vertex masked 1 is left out).
 * What it returns is the changed vertices: one dart each and its new
 * position.  The caller writes them (st_hier_edit, or a sculpt layer's
 * edit, or st_sculpt_apply here) and tells the kernel they moved
 * (st_sculpt_moved), so the next dab sees them.
 *
 * The window's document (ui/doc/brush.c) keeps what belongs to the input:
 * the stroke's path and spacing, its fade (a factor per dab), the undo
 * step and the renderer's refresh.  Units are object space; R, the dab's
 * radius, is st_sculpt_dab_radius's. */
#ifndef ST_SCULPT_H
#define ST_SCULPT_H

#include "core/map/map.h"
#include "core/map/footprint.h"
#include "core/multires/hier.h"
#include "core/multires/mask.h"

#include <stdint.h>

/* The tools.  The order is the order of the window panel's buttons; a
 * mask brush (the document's) takes the next slot. */
enum st_brush_tool {
    ST_BRUSH_GRAB, ST_BRUSH_DRAW, ST_BRUSH_SMOOTH, ST_BRUSH_FLATTEN,
    ST_BRUSH_CREASE, ST_BRUSH_PINCH, ST_BRUSH_INFLATE, ST_BRUSH_CLAY_STRIPS, ST_BRUSH_LAYER, ST_BRUSH_RELAX,
    ST_BRUSH_COUNT
};

/* Falloff presets, with t = 1 - r/R (Blender's BKE_brush_curve_strength,
 * except smooth, which is Strata's (1 - (r/R)^2)^2 as before). */
enum st_falloff {
    ST_FALLOFF_SMOOTH,         /* (1 - q^2)^2, q = r/R */
    ST_FALLOFF_SPHERE,         /* sqrt(2t - t^2) = sqrt(1 - q^2) */
    ST_FALLOFF_ROOT,           /* sqrt(t) */
    ST_FALLOFF_SHARP,          /* t^2 */
    ST_FALLOFF_LINEAR,         /* t */
    ST_FALLOFF_CONSTANT,       /* 1 */
    ST_FALLOFF_COUNT
};
const char *st_falloff_name(int falloff);
/* The preset whose name is `name`, -1 if none. */
int st_falloff_by_name(const char *name);
/* Falloff `kind` at distance r of a brush of radius R: in [0, 1], 0 for
 * r >= R. */
double st_falloff_eval(int kind, double r, double radius);
/* Multiplier of a dab's strength for dabs `spacing` radii apart with the
 * falloff preset `falloff`: 1 / the largest sum of overlapping falloffs
 * (Blender's integrate_overlap); 1 for spacing <= 0. */
double st_brush_overlap_scale(int falloff, double spacing);

/* What the kernel reads of a brush, read again at every dab (a setting
 * changed during a stroke takes effect at the next dab).  All zero is a
 * raw dab: no symmetry, no spacing attenuation, no area plane, no
 * auto-smooth, no hold. */
typedef struct st_sculpt_brush {
    int tool;                  /* enum st_brush_tool */
    double radius;             /* object units */
    double strength;           /* 0..1 (above 1 counts as 1) */
    int falloff;               /* enum st_falloff */
    int mirror_x, mirror_y, mirror_z; /* symmetry across the planes x, y, z = 0 of object space */
    int invert;                /* the opposite direction: in instead of out */
    int front_only;            /* vertices whose normal faces away from the view direction are left alone */
    double spacing;            /* dabs every spacing * radius (for the spacing attenuation) */
    int space_atten;           /* each dab's strength divided by how many dabs overlap at `spacing` */
    double fade;               /* > 0: the stroke fades (crease and pinch then pull across it only) */
    double reach_edges;        /* a dab takes in at least this many edge lengths of the level (0: none) */
    int area_plane;            /* draw, crease, pinch, flatten, clay strips in the plane of the area under the dab */
    int hold;                  /* no face turns more than 44 degrees or shrinks below 10 % in a stroke */
    double autosmooth;         /* 0..1: after each dab, a smooth by autosmooth * weight */
} st_sculpt_brush;

/* The stroke: zero fields take their defaults. */
typedef struct st_sculpt_stroke {
    unsigned level;            /* the level sculpted */
    double reach;              /* the stroke's radius; 0: st_sculpt_reach(brush, edge_mean) */
    double edge_mean;          /* mean edge length of the level (st_sculpt_edge_mean); 0: unknown */
    /* One dart per vertex id of the level (st_sculpt_vertex_darts), read
     * until the stroke ends; NULL: the kernel builds its own. */
    const uint32_t *vertex_darts;
    uint32_t nvertex_darts;
} st_sculpt_stroke;

/* One dab. */
typedef struct st_sculpt_dab {
    double center[3];          /* on the surface */
    double normal[3];          /* the surface normal there (normalised here; zero: +z) */
    double view[3];            /* direction the view looks in; zero: unknown (no front-face test) */
    double dir[3];             /* unit direction of the stroke from the last dab; zero: none */
    double fade;               /* the stroke's strength factor at this dab (1: none) */
    double grab_delta[3];      /* grab: the translation since the last dab */
} st_sculpt_dab;

/* The state of a stroke (grid, normals' ring records, accumulators),
 * reusable across strokes; one per document. */
typedef struct st_sculpt st_sculpt;
st_sculpt *st_sculpt_new(void);   /* NULL when out of memory */
void st_sculpt_free(st_sculpt *s);

/* Mean length of the edges of level l (each edge once).  In the dual
 * encoding (Doo-Sabin) the darts join face centres, a length of the same
 * order. */
double st_sculpt_edge_mean(const st_map *m, unsigned l);
/* The radius a stroke takes in: the brush radius, or reach_edges times
 * the mean edge length when that is larger (a coarse level then takes in
 * at least the vertices of the faces under the cursor). */
double st_sculpt_reach(const st_sculpt_brush *b, double edge_mean);
/* One dart per vertex of level l, indexed by vertex id (ST_NIL: none), a
 * dart of a real face preferred; *nv: the largest id + 1.  NULL when out
 * of memory; the caller frees it. */
uint32_t *st_sculpt_vertex_darts(const st_map *m, unsigned l, uint32_t *nv);

/* Starts a stroke on st->level of m: the grid of the level's vertices (cell
 * size the stroke's radius), the accumulators cleared.  Aborts when out of
 * memory, as the document does. */
void st_sculpt_begin(st_sculpt *s, const st_map *m, const st_sculpt_brush *b, const st_sculpt_stroke *st);
/* This dab's radius around `center`, kept for the next st_sculpt_dab and
 * returned: the brush radius, or reach_edges times the mean edge length at
 * the level's vertex nearest to the centre when that is larger (the edges
 * there, not the level's mean: a coarse cage's faces differ in size by
 * several times).  Grab keeps the radius of its first dab. */
double st_sculpt_dab_radius(st_sculpt *s, const st_map *m, const st_sculpt_brush *b, const double center[3]);
/* One dab: returns how many vertices it changes, with one dart each (at
 * the stroke's level) in *darts and its new position in *pos, valid until
 * the next call.  mask: NULL or per vertex id (core/multires/mask.h).
 * Positions are read from m, not written. */
uint32_t st_sculpt_dab_run(st_sculpt *s, const st_map *m, const st_sculpt_brush *b, const st_sculpt_dab *dab,
                           const st_mask *mask, const uint32_t **darts, const double (**pos)[3]);
/* After the caller wrote the positions of these darts' vertices: the grid
 * follows them. */
void st_sculpt_moved(st_sculpt *s, const st_map *m, const uint32_t *darts, uint32_t n);
/* st_sculpt_dab_run written through st_hier_edit (fp: NULL or what it
 * wrote, appended), then st_sculpt_moved.  Returns the vertices moved. */
uint32_t st_sculpt_dab_apply(st_sculpt *s, st_hier *h, const st_sculpt_brush *b, const st_sculpt_dab *dab,
                             const st_mask *mask, st_footprint *fp);
/* The vertices of the level strictly inside the sphere (c, the stroke's
 * radius) with a positive weight (st_sculpt_brush's falloff, strength,
 * front_only with view), valid until the next call: what a dab would
 * take in, for brushes that paint values instead of moving vertices. */
uint32_t st_sculpt_query(st_sculpt *s, const st_map *m, const st_sculpt_brush *b, const double c[3],
                         const double view[3], const uint32_t **vids, const double **w);

#endif
