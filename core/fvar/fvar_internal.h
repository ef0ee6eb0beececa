/* The face-varying UV channel of a hierarchy, for core/multires/hier*.c,
 * sessions and tests (core/fvar/fvar.h is the public side).  It sits below
 * the hierarchy, as the scheme rules do: it reads the map and the view its
 * scheme's rules read (core/schemes/view.h), and core/multires/hier_fvar.c
 * keeps the channel of an st_hier (st_hier.fvar) through it. */
#ifndef ST_FVAR_INTERNAL_H
#define ST_FVAR_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/fvar/fvar.h"
#include "core/base/st_error.h"
#include "core/base/mesh.h"
#include "core/map/map.h"
#include "core/schemes/scheme.h"

/* One level.  Labels say which corners of one vertex share a
 * face-varying value (OpenSubdiv's "siblings"); they compare only between
 * corners of the same vertex.  At level 0 they are the file's UV indices.
 *
 * While a level is computed it is dense: per dart id below cap, the
 * corner's UV (uv, 2 * cap) and label (val, cap), idx NULL; the rules write
 * each corner (fvar_rules.c).  Done, it is compact (st_fvar_level_compact):
 * one value per distinct (label, UV bits) among the corners of a vertex,
 * uv (2 * nvals) and val (nvals) per value, idx per dart id below cap.
 * Corners of one label can differ in the last bit (each is computed from
 * its own side), so the bits are part of the key: every dart reads back
 * exactly what it was given.  A value per vertex and seam instead of per
 * corner: a quad level's UVs take 4 + 20 * nvals / cap bytes per dart
 * instead of 20. */
typedef struct st_fvar_level {
    uint32_t cap;
    uint32_t nvals;   /* compact: the values */
    double *uv;       /* compact: 2 * nvals; dense: 2 * cap */
    uint32_t *val;    /* compact: nvals; dense: cap */
    uint32_t *idx;    /* compact: cap; dense: NULL */
} st_fvar_level;

/* Dart d's UV and label (d < cap), the level compact or dense. */
static inline const double *st_fvar_uv_at(const st_fvar_level *lv, uint32_t d)
{
    return lv->uv + 2 * (size_t)(lv->idx ? lv->idx[d] : d);
}
static inline uint32_t st_fvar_label_at(const st_fvar_level *lv, uint32_t d)
{
    return lv->val[lv->idx ? lv->idx[d] : d];
}
/* The bytes its arrays hold. */
static inline size_t st_fvar_level_bytes(const st_fvar_level *lv)
{
    return lv->idx ? 4 * (size_t)lv->cap + 20 * (size_t)lv->nvals : 20 * (size_t)lv->cap;
}
/* The level as core/fvar/fvar.h's st_uv_map (per-dart reads). */
static inline st_uv_map st_fvar_uv_map(const st_fvar_level *lv)
{
    return (st_uv_map){ lv->uv, lv->idx, lv->cap };
}
/* Makes a dense level of the map's level L compact, in place (the UVs
 * moved down, the labels' array becoming the index); -1 when out of
 * memory, the level left dense (still valid). */
int st_fvar_level_compact(st_fvar_level *lv, const st_map *m, unsigned L);

typedef struct st_fvar {
    int interp;                       /* enum st_uv_interp */
    unsigned levels;                  /* levels 0..levels-1 carry UVs */
    st_fvar_level lv[ST_MAX_LEVELS];
} st_fvar;

/* Level 0's UVs from the soup the hierarchy was built from (level 0 of m
 * made by st_map_from_mesh from mesh) into *out; *out NULL when mesh has
 * none, or on failure. */
int st_fvar_init(st_fvar **out, const st_map *m, const st_mesh *mesh, int interp, st_error *err);
void st_fvar_free(st_fvar *f);
/* After level L = top of sv's map was added by the scheme's refine(): its
 * UVs from level L-1 (primal quadrisection schemes; others leave level L
 * without).  Nothing when f is NULL. */
int st_fvar_refine(st_fvar *f, const st_subdiv_view *sv, const st_scheme *scheme, st_error *err);
/* The UVs of levels f->levels..upto, each level from the one below, once
 * the map's topology reaches upto or beyond (the scheme's refine() run
 * first for every level): the same bits as st_fvar_refine after each
 * refine(), and each level's arrays sized by the dart ids of levels
 * 0..L (st_pool_cover), not by the finer map's.  Nothing when f is NULL,
 * the scheme carries none above level 0, or they reach upto already;
 * ST_ERR_INVALID when upto is above the map's top, or for √3 and
 * Doo-Sabin unless upto is the top and the only level missing (their
 * stencils read the top level: st_fvar_refine after each refine()).
 *
 * Threads: for the primal quadrisection schemes it reads the map's
 * relations, flags and id pools, the view's sharpness and options, and
 * writes f only (and memory it allocates): it may run beside
 * readers of the connectivity and a writer of positions and details
 * (st_hier_write_pos, st_hier_set_detail), never beside anything that
 * changes the map's topology or sharpness (refine(), level removal), nor
 * anything that reads h->fvar (st_hier_uv, sessions, level meshes).
 * Returns ST_OK or the error; out of memory leaves the levels done. */
int st_fvar_refine_levels(st_fvar *f, const st_subdiv_view *sv, const st_scheme *scheme, unsigned upto, st_error *err);
/* Level top's UVs and labels for √3 and Doo-Sabin (fvar_stencil.c), from
 * level top-1's, by the scheme's stencils; -1 when out of memory. */
int st_fvar_refine_stencil(const st_subdiv_view *sv, const st_scheme *scheme, const st_fvar_level *coarse,
                           st_fvar_level *fine);
/* The same rules for one step l -> l+1 of an adaptive map (core/adapt/
 * adapt_uv.c), applied to faces[0..n), the faces of level l subdivided
 * toward l+1: uv/val hold level l's values per dart, out_uv/out_val (a copy
 * of them) get level l+1's at every corner of the vertices the step
 * computes (those of the subdivided faces, so faces not subdivided show
 * their kept corners at the finest value), out_level l+1 there; -1 when out
 * of memory.  rank (Doo-Sabin; NULL for √3, whose homes need no order)
 * gives the darts of levels 1..l their places in a regular level's
 * numbering, so that homes are chosen as on a regular level. */
int st_fvar_stencil_step(const st_subdiv_view *sv, const st_scheme *scheme, unsigned l, const double *uv,
                         const uint32_t *val, const uint32_t *faces, uint32_t n, const uint32_t *rank, double *out_uv,
                         uint32_t *out_val, uint8_t *out_level);
/* Whether the next level of a map at top will get UVs (the estimate of its
 * memory counts ST_FVAR_BYTES_PER_DART per dart of the levels added then:
 * a compact level's 4 bytes of index per dart and 20 per value, about one
 * value per 2.7 darts on quad levels and fewer on triangle levels, and the
 * dense form of the level being computed, 20 per dart, gone before the
 * next one's positions). */
int st_fvar_continues(const st_fvar *f, unsigned top, const st_scheme *scheme);
#define ST_FVAR_BYTES_PER_DART 12.0
/* Level bookkeeping mirroring st_hier_remove_top / st_hier_remove_bottom
 * of a map at top (before the removal); the last level gone, *f is freed
 * and NULL. */
void st_fvar_remove_top(st_fvar *f, unsigned top);
void st_fvar_remove_bottom(st_fvar **f, unsigned top);
/* Fills out->nuvs, uv, face_uv for the soup st_map_to_mesh made of level
 * l of m (same face walk): one texture coordinate per (vertex, value
 * label); nothing when f has no UVs at l. */
int st_fvar_level_mesh(const st_fvar *f, st_map *m, unsigned l, st_mesh *out, st_error *err);
/* One corner of a soup: its vertex, the level and label of its value, its
 * face's place in a regular level's scan, and its place in the soup. */
typedef struct st_fvar_corner_key { uint32_t vert, level, label, corner; uint64_t face; } st_fvar_corner_key;
/* A soup's texture coordinates: one per (vertex, level, label), the value
 * of the corner met first in (face, corner) order (darts[corner] its dart,
 * its UV read from uv, 0 past its cap); sorts k[0..c), fills face_uv per
 * corner and out_uv, and returns their count. */
uint32_t st_fvar_soup_uvs(st_fvar_corner_key *k, uint32_t c, const uint32_t *darts, const st_uv_map *uv,
                          uint32_t *face_uv, double *out_uv);
/* The arrays a soup's texture coordinates are made in, for nc corners:
 * keys and darts (scratch), and the result, face_uv per corner and uv.
 * st_fvar_soup_alloc: -1 (nothing kept) when out of memory.
 * st_fvar_soup_install: the result into out (its UVs before freed), the
 * scratch freed. */
typedef struct st_fvar_soup {
    st_fvar_corner_key *k;
    uint32_t *darts, *face_uv;
    double *uv;
} st_fvar_soup;
int st_fvar_soup_alloc(st_fvar_soup *s, uint32_t nc);
void st_fvar_soup_install(st_fvar_soup *s, st_mesh *out, uint32_t nuvs);
/* A deep copy of src (NULL: none) into *dst, for a map with the same dart
 * ids; -1 when out of memory (*dst NULL then). */
int st_fvar_copy(st_fvar **dst, const st_fvar *src);

/* ---- one refinement step of the face-varying rules (fvar_rules.c) ----------- */

/* The rules of docs/SUBDIVISION-RULES.md §7b (OpenSubdiv's face-varying
 * interpolation) carrying level l's values to level L = l+1.  One copy
 * serves both a regular level (st_fvar_refine: every face subdivided) and
 * an adaptive map (core/adapt/adapt_uv.c: only the faces subdivided toward
 * L, in a map whose darts of several levels interleave).  Children are
 * written straight into out_uv/out_val at the fine corners that hold them:
 * the vertex child of coarse corner d at d itself, the edge child of d's
 * edge on d's side at φ1(d) and at the last corner of the child face of
 * the next coarse corner, the face child at φ1²(d) of each child quad. */
enum st_fvar_rules {
    ST_FVAR_CATMARK, ST_FVAR_LOOP, ST_FVAR_LINEAR,
    ST_FVAR_STENCIL     /* √3 and Doo-Sabin: fvar_stencil.c, not st_fvar_step */
};
/* The rules of a scheme, -1 when its levels above 0 carry no UVs. */
int st_fvar_rules_of(const st_scheme *scheme);

typedef struct st_fvar_step {
    st_subdiv_view sv;           /* the hierarchy's, as its scheme's rules read it */
    const st_scheme *scheme;     /* adaptive maps: the scheme whose stencils st_fvar_stencil_step applies */
    st_map *m;
    unsigned l, L;
    int interp;                  /* enum st_uv_interp */
    int rules;                   /* enum st_fvar_rules */
    const double *uv;            /* level l's values: per dart, or per value through idx */
    const uint32_t *val;         /* level l's value labels: the same */
    const uint32_t *idx;         /* level l compact (st_fvar_level): per dart its value; NULL: dense */
    double *out_uv;              /* the children's values, per dart */
    uint32_t *out_val;
    uint8_t *out_level;          /* when not NULL: L at every corner written */
    /* Adaptive maps only; all NULL on a regular level. */
    double *cent;                /* per dart of map l: its face's centroid (the
                                    Catmull-Clark rules read those of faces not
                                    subdivided too); NULL: read the face child */
    uint8_t *sub;                /* per dart of map l: its face is subdivided toward L */
    int (*split_toward)(const st_map *m, uint32_t d, unsigned l); /* fills sub */
    uint32_t *rank;              /* per dart: its place among its level's darts in a
                                    regular level's numbering; NULL: the map is one
                                    regular level, whose scan is that order */
    uint32_t *c, *rot;           /* one vertex's corners in β1 order, and scratch */
    float *sharp;                /* the sharpness of each corner's edge in c */
    uint32_t cap_c, cap_rot;
    /* The relations of levels l and L and the sharpness of level l hoisted
     * out of the per-dart lookups (st_level_view); each pass below takes
     * them afresh (the map may change between steps, never during one). */
    st_level_view vl, vL;
    st_u32_view esharp, vsharp;  /* float bits, when h has sharpness */
    unsigned viewed;             /* l + 1 when the views are level l's */
    uint32_t tri_splits;         /* faces of level l split into triangles toward L */
    uint32_t *fchild, cap_fchild; /* per dart of level l (Catmull-Clark, cent NULL): the corner at L
                                    holding its face's child, for the rules that read it */
    unsigned faced;              /* l + 1 once st_fvar_face_children counted them */
    const uint32_t *fc;          /* fchild once every face child is set (all quads), else NULL */
    int has_sharpness;           /* h's, taken with the views */
    uint8_t *disc;               /* per real dart of level l: its edge is a face-varying
                                    boundary (st_fvar_edge_children), for the vertex pass */
    uint32_t cap_disc;
    unsigned edged;              /* l + 1 once st_fvar_edge_children filled disc */
} st_fvar_step;

/* The darts of levels from..top (a level's darts are in id order inside
 * each of its blocks), in the order of st_dart_first/next over level top
 * when from is 0, without a call per dart. */
typedef struct st_fvar_scan {
    const st_pool *p;
    unsigned lv, top;
    uint32_t b, d, end;
} st_fvar_scan;

static inline void st_fvar_scan_init(st_fvar_scan *s, const st_map *m, unsigned from, unsigned top)
{
    *s = (st_fvar_scan){ &m->darts, st_lvl_clamp(from), st_lvl_clamp(top), 0, 0, 0 };
}

/* The same over the vertex ids of levels 0..top: st_vertex_first/next's
 * order in a map that is not face-embedded. */
static inline void st_fvar_scan_vertices(st_fvar_scan *s, const st_map *m, unsigned top)
{
    *s = (st_fvar_scan){ &m->verts, 0, st_lvl_clamp(top), 0, 0, 0 };
}

static inline uint32_t st_fvar_scan_next(st_fvar_scan *s)
{
    for (;;) {
        while (s->d < s->end) {
            uint32_t d = s->d++;
            if (s->p->ins[d] != ST_FREE_LEVEL) return d;
        }
        while (s->b >= s->p->nblocks[s->lv]) {
            if (s->lv >= s->top) return ST_NIL;
            s->lv++;
            s->b = 0;
        }
        s->d = s->p->blocks[s->lv][s->b++] << ST_POOL_BLOCK_SHIFT;
        s->end = s->d + ST_POOL_BLOCK;
    }
}

/* The face children (centroids) of the faces of level l split into quads,
 * each summed from the corner a regular level's scan meets first; the
 * first pass of a step.  -1 when out of memory. */
int st_fvar_face_children(st_fvar_step *w);
/* The child of the edge of corner d (a real dart of level l) on d's side. */
void st_fvar_edge_child(st_fvar_step *w, uint32_t d);
/* The children of every edge of level l on each real side (a regular level). */
void st_fvar_edge_children(st_fvar_step *w);
/* The vertex children of the vertices of level l that are corners of a
 * subdivided face (all of them on a regular level); -1 when out of memory. */
int st_fvar_vertex_children(st_fvar_step *w);
/* The corners of the inner triangles of the triangle splits toward L. */
void st_fvar_inner_triangles(st_fvar_step *w);
/* x comes before y in the scan of a regular level (level by level, each in
 * the order the level was made; w->rank gives that order above level 0). */
int st_fvar_regular_before(const st_fvar_step *w, uint32_t x, uint32_t y);
/* Frees the step's scratch (c, rot, sharp). */
void st_fvar_step_free(st_fvar_step *w);

#endif
