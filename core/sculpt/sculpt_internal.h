/* Shared between core/sculpt/sculpt.c (grid, weights, ring normals,
 * accumulation, the dab), sculpt_tools.c (what each tool does under a dab)
 * and sculpt_hold.c (layer, auto-smooth, the hold). */
#ifndef ST_SCULPT_INTERNAL_H
#define ST_SCULPT_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/sculpt/sculpt.h"

#include <stddef.h>

struct st_sculpt {
    unsigned level;
    double R;                  /* this dab's radius (st_sculpt_dab_radius), the stroke's at begin */
    double hscale, fscale;     /* spacing attenuation of heights and of fractions (st_sculpt_begin) */
    double dab_dir[3];         /* the stroke's direction reflected with the mirrored dab being applied */
    double fadek;              /* this dab's fade factor (st_sculpt_dab.fade), 1 at begin */
    double edge_mean;          /* mean edge length of the level (st_sculpt_stroke.edge_mean) */
    const uint32_t *vdart;     /* per vertex id: a dart (st_sculpt_stroke's, or own_vdart) */
    uint32_t nvdart;
    uint32_t *own_vdart;
    double *accw;              /* per list slot: the largest weight a dab gave the vertex (auto-smooth) */
    double (*disp2)[3];        /* auto-smooth's result, per list slot */
    double *tmpa;              /* per tmp entry: the vertex's area (length of its area-weighted normal) */
    double cs;                 /* cell size */
    uint64_t *hkey;            /* cell hash: key -> first vertex */
    uint32_t *hhead, hcap, hn;
    uint32_t nv;               /* per-vertex arrays below have nv entries */
    uint32_t *next, *prev;     /* per-cell doubly linked lists */
    uint64_t *vcell;           /* cell key of each vertex, EMPTY when not in the grid */
    uint32_t *mark, gen;       /* dab membership */
    uint32_t *slot;            /* index in list when marked */
    double *lay_o;             /* layer: displacement along lay_n0 so far this stroke, -1 untouched */
    double (*lay_n0)[3];       /* layer: the vertex's unit normal when the stroke first reached it */
    uint32_t *list;            /* vertices moved by this dab */
    double (*disp)[3];
    double *lay_t;             /* layer: per list slot, the height this dab reaches */
    uint32_t nlist, caplist;
    /* The vertices under one dab: id, weight (sc_weight), unit normal. */
    uint32_t *tmp;
    double *tmpw;
    double (*tmpn)[3];
    uint32_t ntmp, captmp;
    /* Ring records (sculpt.c: ring_of): the corners of the faces around
     * each vertex in the order its normal sums them, kept for the stroke. */
    uint32_t *ring_at;         /* per vertex: 1 + offset in ring, 0: not recorded in this stroke */
    uint32_t *ring, nring, capring;
    double (*fn)[3];           /* per face of a ring record: its Newell normal when recorded (hold) */
    double (*held)[3];         /* the hold: the faces held in this pass (lattice points, mirrored) */
    double *heldr;             /* ... and the distance from each within which their corners lie */
    uint32_t nheld, capheld;
    uint32_t nfn, capfn;
    /* grab */
    int grabbed;
    uint32_t *gv;
    double *gw;
    uint8_t *gk;               /* which mirrored dab (bits: x, y, z flipped) */
    uint32_t ng, capg;
    /* st_sculpt_dab_run's result */
    uint32_t *odarts;
    double (*opos)[3];
    uint32_t capout;
};

/* ---- sculpt.c ---- */
void *sc_xrealloc(void *p, size_t n);
static inline uint32_t sc_vertex_dart(const st_sculpt *s, uint32_t v)
{
    return v < s->nvdart ? s->vdart[v] : ST_NIL;
}
/* The weight of a vertex under a dab: falloff at distance r times the
 * strength times the front-face test (vn: the vertex's unit normal, view:
 * the view direction of this dab, zero when unknown) times the stroke's
 * fade.  Every brush takes its per-vertex weight from here. */
double sc_weight(const st_sculpt *s, const st_sculpt_brush *b, double r, const double vn[3], const double view[3]);
/* Adds a displacement of v into this dab's accumulator. */
void sc_acc(st_sculpt *s, uint32_t v, const double dv[3]);
/* Records the weight w of v under this dab (the largest counts): the
 * strength of auto-smooth there. */
void sc_acc_weight(st_sculpt *s, uint32_t v, double w);
/* Layer: the height h (>= 0) the dab raises v to; the largest over the
 * mirrored dabs counts.  n: v's unit normal now, kept as the direction of
 * the layer at v when the stroke first reaches it. */
void sc_acc_layer(st_sculpt *s, uint32_t v, double h, const double n[3]);
/* The Newell normal of the face record r (terms c, then c + 1 ids) now,
 * with each vertex moved by its displacement in this dab when `moved`. */
void sc_face_normal(const st_sculpt *s, const st_level_view *lv, const uint32_t *r, int moved, double n[3]);
/* v reflected across the planes of the set bits of `which` (1 x, 2 y, 4 z). */
void sc_reflect(uint8_t which, const double v[3], double out[3]);
/* The mirrored dabs of the brush's symmetry: every subset of the enabled
 * planes (0 is the dab itself); returns how many. */
unsigned sc_symmetry_set(const st_sculpt_brush *b, uint8_t which[8]);

/* ---- sculpt_tools.c ---- */
/* One dab of b->tool (not grab) centred at c with unit normal dn on the
 * vertices under it (s->tmp, tmpw, tmpn): displacements computed from the
 * current positions, added into the accumulator. */
void sc_tool_dab(st_sculpt *s, const st_map *m, const st_sculpt_brush *b, const double c[3], const double dn[3]);

/* ---- sculpt_hold.c ---- */
/* Layer: each vertex's step toward the largest height asked of it. */
void sc_layer_finish(st_sculpt *s, const st_sculpt_brush *b);
/* Layer, after auto-smooth and the hold: the height each vertex reached. */
void sc_layer_settle(st_sculpt *s, const st_sculpt_brush *b);
/* Auto-smooth of the dab's vertices by a times their weight. */
void sc_autosmooth(st_sculpt *s, const st_map *m, double a);
/* Damps the dab so that no face around a moved vertex turns or collapses. */
void sc_hold_faces(st_sculpt *s, const st_map *m, const st_sculpt_brush *b);

#endif
