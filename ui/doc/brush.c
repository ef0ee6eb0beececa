/* Brush strokes at the editing level (editor.h): the document's side of
 * sculpting.  The geometry (the spatial grid, each vertex's weight, ring
 * normals, symmetry, each tool's displacement, auto-smooth, the hold) is
 * core's (core/sculpt/sculpt.h); here are the brush settings (defaults,
 * each tool's own strength, falloff and auto-smooth), the stroke (its
 * radius, the fade-in along the dab centres' path and the fade-out at its
 * end), the undo step, the edit into the model (a sculpt layer's when one
 * is active, ed_model_edit) and the change reported to the display and the
 * renderer.  The spacing of dabs along the cursor's path is in
 * brush_stroke.c. */
#include "editor_internal.h"
#include "core/sculpt/sculpt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct st_brush_state {
    st_sculpt *sc;             /* the kernel's stroke state (grid, rings, accumulators) */
    double path, last_c[3];    /* path length of the dab centres so far, the last centre (fade) */
    double dir[3];             /* unit direction from the last dab's centre to this one's, 0: none yet */
    unsigned ndabs;
    double outk;               /* the fade-out's factor (st_doc_stroke_fade_out), 1 until the stroke's end */
    double edge_mean;          /* mean edge length of edge_level (cache of st_doc_brush_reach) */
    unsigned edge_level;
    uint32_t edge_key;         /* verts.end of the map when edge_mean was taken, 0: none */
};

double st_brush_falloff(double r, double radius)
{
    return st_falloff_eval(ST_FALLOFF_SMOOTH, r, radius);
}

const char *st_brush_name(int tool)
{
    static const char *names[ST_BRUSH_COUNT] = { "grab", "draw", "smooth", "flatten", "crease",
                                                 "pinch", "inflate", "clay strips", "layer", "relax" };
    return tool >= 0 && tool < ST_BRUSH_COUNT ? names[tool] : "?";
}

void st_brush_defaults(st_brush *b, double radius)
{
    memset(b, 0, sizeof *b);
    b->tool = ST_BRUSH_DRAW;
    b->radius = radius;
    b->falloff = ST_FALLOFF_SMOOTH;
    b->front_only = 1;
    b->spacing = 0.1;          /* Blender's default spacing: 10 % of the radius */
    b->space_atten = 1;        /* Blender: "Adjust Strength for Spacing", on by default */
    b->fade = 1.0;             /* strength reaches full after one radius of path */
    b->reach_edges = ST_BRUSH_REACH_EDGES;
    b->area_plane = 1;
    b->hold = 1;
    b->stabilize_dist = 0.5;
    for (int t = 0; t < ST_BRUSH_COUNT; t++) {
        b->tool_strength[t] = t == ST_BRUSH_GRAB ? 1.0 : 0.5;
        b->tool_falloff[t] = ST_FALLOFF_SMOOTH;
    }
    /* Auto-smooth (Blender's per-brush Auto-Smooth, sculpt.c
     * do_brush_action, which ships at 0 and which sculptors raise for
     * crease and pinch): on here for the brushes whose strength-1 strokes
     * pile up sharp ridges and creases without it (test_editor_brush_hold),
     * low enough that a crease stays a crease. */
    b->tool_autosmooth[ST_BRUSH_DRAW] = 0.15;
    b->tool_autosmooth[ST_BRUSH_CLAY_STRIPS] = 0.15;
    b->tool_autosmooth[ST_BRUSH_INFLATE] = 0.15;
    b->tool_autosmooth[ST_BRUSH_CREASE] = 0.2;
    b->tool_autosmooth[ST_BRUSH_PINCH] = 0.2;
    b->tool_autosmooth[ST_BRUSH_FLATTEN] = 0.1;
    b->tool_autosmooth[ST_BRUSH_LAYER] = 0.1;
    b->strength = b->tool_strength[b->tool];
    b->autosmooth = b->tool_autosmooth[b->tool];
}

void st_brush_raw(st_brush *b)
{
    b->space_atten = 0;
    b->fade = 0;
    b->reach_edges = 0;
    b->area_plane = 0;
    b->hold = 0;
    b->autosmooth = 0;
    for (int t = 0; t < ST_BRUSH_COUNT; t++) b->tool_autosmooth[t] = 0;
}

void st_brush_set_tool(st_brush *b, int tool)
{
    if (tool < 0 || tool >= ST_BRUSH_COUNT) return;
    if (b->tool >= 0 && b->tool < ST_BRUSH_COUNT) {
        b->tool_strength[b->tool] = b->strength;
        b->tool_falloff[b->tool] = b->falloff;
        b->tool_autosmooth[b->tool] = b->autosmooth;
    }
    b->tool = tool;
    b->strength = b->tool_strength[tool];
    b->falloff = b->tool_falloff[tool];
    b->autosmooth = b->tool_autosmooth[tool];
}

void ed_brush_state_free(struct st_brush_state *bs)
{
    if (!bs) return;
    st_sculpt_free(bs->sc);
    free(bs);
}

static struct st_brush_state *brush_state(st_doc *d)
{
    if (!d->bs) {
        d->bs = calloc(1, sizeof *d->bs);
        if (!d->bs) abort();
    }
    if (!d->bs->sc && !(d->bs->sc = st_sculpt_new())) abort();
    return d->bs;
}

/* What the kernel reads of the document's brush. */
static void sculpt_brush(const st_brush *b, st_sculpt_brush *o)
{
    memset(o, 0, sizeof *o);
    o->tool = b->tool;
    o->radius = b->radius;
    o->strength = b->strength;
    o->falloff = b->falloff;
    o->mirror_x = b->mirror_x;
    o->mirror_y = b->mirror_y;
    o->mirror_z = b->mirror_z;
    o->invert = b->invert;
    o->front_only = b->front_only;
    o->spacing = b->spacing;
    o->space_atten = b->space_atten;
    o->fade = b->fade;
    o->reach_edges = b->reach_edges;
    o->area_plane = b->area_plane;
    o->hold = b->hold;
    o->autosmooth = b->autosmooth;
}

/* ---- reach at coarse levels ---------------------------------------------------------- */

double st_doc_brush_reach(st_doc *d)
{
    double R = d->brush.radius;
    if (!d->loaded || !(d->brush.reach_edges > 0)) return R;
    struct st_brush_state *bs = brush_state(d);
    /* Taken again when the level or the map's vertex count changes; the
     * lengths drift little under brushes, which do not change topology. */
    uint32_t key = d->h.map.verts.end + 1;
    if (bs->edge_key != key || bs->edge_level != d->edit_level) {
        bs->edge_mean = st_sculpt_edge_mean(&d->h.map, d->edit_level);
        bs->edge_level = d->edit_level;
        bs->edge_key = key;
    }
    st_sculpt_brush b;
    sculpt_brush(&d->brush, &b);
    return st_sculpt_reach(&b, bs->edge_mean);
}

/* ---- strokes -------------------------------------------------------------------------- */

int st_doc_stroke_begin(st_doc *d)
{
    return ed_stroke_begin(d, 1);
}

int ed_stroke_begin(st_doc *d, int moves_geometry)
{
    if (!d->loaded) return -1;
    if (d->active == 1) st_doc_drag_end(d);
    else if (d->active == 2) st_doc_stroke_end(d);
    if (!(d->brush.radius > 0) || d->brush.tool < 0 || d->brush.tool >= ST_BRUSH_COUNT) return -1;
    struct st_brush_state *bs = brush_state(d);
    unsigned l = d->edit_level;
    /* At an HD level the mask brush paints the model's top (edit_level
     * stays there): the HD levels take its subdivision (hd_mask_build). */
    int hd = d->hd_level && moves_geometry;
    if (hd) {
        /* An HD level: the box's display is sculpted (editor_hd.c). */
        if (ed_hd_stroke_begin(d)) return -1;
        l = d->hd_level;
    } else if (moves_geometry && ed_edit_budget(d, l)) {
        return -1;
    }
    st_sculpt_brush b;
    sculpt_brush(&d->brush, &b);
    st_sculpt_stroke st = { 0 };
    st.level = l;
    if (hd) {
        /* At an HD level the brush radius is the reach: the level's mean
         * edge is mostly the coarse faces' outside the HD region. */
        b.reach_edges = 0;
        st.reach = d->brush.radius;
        st.vertex_darts = d->hd_vdart;
        st.nvertex_darts = d->nhd_vdart;
    } else {
        st.reach = st_doc_brush_reach(d);
        st.edge_mean = bs->edge_mean;
        /* The document's vertex -> dart table of the editing level (kept while
         * the topology holds, which a stroke does not change). */
        st.vertex_darts = ed_vertex_darts(d, &st.nvertex_darts);
    }
    st_sculpt_begin(bs->sc, hd ? &d->display.hier.map : &d->h.map, &b, &st);
    bs->path = 0;
    bs->ndabs = 0;
    bs->outk = 1;
    st_undo_step *s = ed_step_new(ED_STEP_EDIT);
    s->level = l;
    s->hd = hd;
    d->pending = s;
    d->active = 2;
    return 0;
}

int st_doc_stroke_dab(st_doc *d, const double center[3], const double normal[3], const double grab_delta[3])
{
    if (d->active != 2 || !d->pending || !d->bs) return -1;
    struct st_brush_state *bs = d->bs;
    if (!(d->brush.radius > 0)) return -1;
    double t0 = ed_now_ms();
    int hd = d->pending->hd;
    st_hier *h = hd ? &d->display.hier : &d->h;
    unsigned l = d->pending->level;
    st_sculpt_brush b;
    sculpt_brush(&d->brush, &b);
    if (hd) b.reach_edges = 0;
    st_sculpt_dab dab = { .normal = { 0, 0, 1 }, .fade = 1 };
    memcpy(dab.center, center, sizeof dab.center);
    if (normal) memcpy(dab.normal, normal, sizeof dab.normal);
    memcpy(dab.view, d->brush.view_dir, sizeof dab.view);
    if (grab_delta) memcpy(dab.grab_delta, grab_delta, sizeof dab.grab_delta);
    double R = st_sculpt_dab_radius(bs->sc, &h->map, &b, center);
    /* Fade-in: the strength rises smoothly over the first fade * R of the
     * dab centres' path, so a crease or draw stroke starts tapered instead
     * of with a full-strength dab (ZBrush's stroke taper, Blender's
     * "stroke" tapering in its curve strokes). */
    if (bs->ndabs++) {
        double step[3] = { center[0] - bs->last_c[0], center[1] - bs->last_c[1], center[2] - bs->last_c[2] };
        double len = sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2]);
        bs->path += len;
        if (len > 0) for (int k = 0; k < 3; k++) bs->dir[k] = step[k] / len;
    } else {
        bs->dir[0] = bs->dir[1] = bs->dir[2] = 0;
    }
    memcpy(bs->last_c, center, sizeof bs->last_c);
    memcpy(dab.dir, bs->dir, sizeof dab.dir);
    if (d->brush.fade > 0 && d->brush.tool != ST_BRUSH_GRAB) {
        double t = bs->path / (d->brush.fade * R);
        if (t < 1) dab.fade = 0.1 + 0.9 * t * t * (3 - 2 * t);
        dab.fade *= bs->outk;
    }
    const uint32_t *darts;
    const double(*pos)[3];
    uint32_t n = st_sculpt_dab_run(bs->sc, &h->map, &b, &dab, hd ? &d->hd_mask : &d->mask, &darts, &pos);
    if (n && hd) {
        ed_hd_dab_write(d, d->pending, darts, pos, n, t0);
        st_sculpt_moved(bs->sc, &h->map, darts, n);
    } else if (n) {
        /* Old values of what core will write (also the layers'), then the
         * edit, which reports what it wrote for the display and the renderer. */
        uint32_t from = d->fp_model.n;
        ed_model_edit(d, d->pending, l, darts, pos, n);
        st_sculpt_moved(bs->sc, &h->map, darts, n);
        ed_geometry_changed(d, l, darts, n, t0, from);
    }
    return 0;
}

uint32_t ed_brush_query(st_doc *d, const double c[3], double R, const uint32_t **vids, const double **w)
{
    struct st_brush_state *bs = d->bs;
    if (!bs || !bs->sc || !d->active) return 0;
    /* The weights are those of every brush (falloff preset, strength,
     * front faces only); R is the stroke's radius the kernel reads. */
    (void)R;
    st_sculpt_brush b;
    sculpt_brush(&d->brush, &b);
    return st_sculpt_query(bs->sc, &d->h.map, &b, c, d->brush.view_dir, vids, w);
}

void st_doc_stroke_fade_out(st_doc *d, double k)
{
    if (d->active == 2 && d->bs) d->bs->outk = k < 0 ? 0 : k > 1 ? 1 : k;
}

void st_doc_stroke_end(st_doc *d)
{
    st_undo_step *s = ed_take_pending(d, 2);
    if (s) ed_push_edit(d, s);
}
