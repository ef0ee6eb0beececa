/* Shared between ui/brush.c (spatial grid, per-vertex weight, strokes and
 * symmetry) and ui/brush_tools.c (what each brush does under a dab); not
 * part of the window's API. */
#ifndef ST_BRUSH_INTERNAL_H
#define ST_BRUSH_INTERNAL_H

#include "editor_internal.h"

struct st_brush_state {
    unsigned level;
    double R;                  /* this stroke's radius: st_doc_brush_reach at stroke begin */
    double hscale, fscale;     /* spacing attenuation of heights and of fractions (brush.c) */
    double path, last_c[3];    /* path length of the dab centres so far, the last centre (fade) */
    double dir[3];             /* unit direction from the last dab's centre to this one's, 0: none yet */
    double dab_dir[3];         /* dir reflected with the mirrored dab being applied */
    unsigned ndabs;
    double fadek;              /* this dab's fade factor: the fade-in times outk */
    double outk;               /* the fade-out's factor (st_doc_stroke_fade_out), 1 until the stroke's end */
    double edge_mean;          /* mean edge length of edge_level (cache of st_doc_brush_reach) */
    unsigned edge_level;
    uint32_t edge_key;         /* verts.end of the map when edge_mean was taken, 0: none */
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
    /* The vertices under one dab: id, weight (ed_brush_weight), unit normal. */
    uint32_t *tmp;
    double *tmpw;
    double (*tmpn)[3];
    uint32_t ntmp, captmp;
    /* Ring records (brush.c: ring_of): the corners of the faces around
     * each vertex in the order its normal sums them, kept for the stroke. */
    uint32_t *ring_at;         /* per vertex: 1 + offset in ring, 0: not recorded in this stroke */
    uint32_t *ring, nring, capring;
    double (*fn)[3];           /* per face of a ring record: its Newell normal when recorded (hold_faces) */
    double (*held)[3];         /* hold_faces: the faces held in this pass (lattice points, mirrored) */
    double *heldr;             /* ... and the distance from each within which their corners lie */
    uint32_t nheld, capheld;
    uint32_t nfn, capfn;
    /* grab */
    int grabbed;
    uint32_t *gv;
    double *gw;
    uint8_t *gk;               /* which mirrored dab (bits: x, y, z flipped) */
    uint32_t ng, capg;
};

/* ---- brush.c ---- */
void *ed_xrealloc(void *p, size_t n);
/* Next dart around the vertex of x at level l (β1; φ1 in the dual encoding). */
uint32_t ed_around(const st_map *m, uint32_t x, unsigned l);
/* The weight of a vertex under a dab: falloff at distance r times the
 * strength times the front-face test (vn: the vertex's unit normal, view:
 * the view direction of this dab, zero when unknown).  Every brush takes
 * its per-vertex weight from here. */
double ed_brush_weight(const st_doc *d, uint32_t v, double r, const double vn[3], const double view[3]);
/* Adds a displacement of v into this dab's accumulator. */
void ed_brush_acc(struct st_brush_state *bs, uint32_t v, const double dv[3]);
/* Records the weight w of v under this dab (the largest counts): the
 * strength of auto-smooth there. */
void ed_brush_acc_weight(struct st_brush_state *bs, uint32_t v, double w);
/* Layer: the height h (>= 0) the dab raises v to; the largest over the
 * mirrored dabs counts.  n: v's unit normal now, kept as the direction of
 * the layer at v when the stroke first reaches it. */
void ed_brush_acc_layer(struct st_brush_state *bs, uint32_t v, double h, const double n[3]);

/* ---- brush_tools.c ---- */
/* One dab of d->brush.tool (not grab) centred at c with unit normal dn on
 * the vertices under it (bs->tmp, tmpw, tmpn): displacements computed from
 * the current positions, added into the accumulator. */
void ed_brush_tool_dab(st_doc *d, struct st_brush_state *bs, const double c[3], const double dn[3]);

#endif
