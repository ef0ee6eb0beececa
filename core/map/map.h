/* st_map: a multiresolution combinatorial 2-map (Kraemer 2008, §1.2.2
 * and ch. 2).
 *
 * Darts
 * -----
 * A dart d is a 32-bit index.  It is inserted at a level ins(d) and then
 * belongs to every level l >= ins(d): the dart sets are nested,
 * B^0 ⊂ B^1 ⊂ ... ⊂ B^top.  Each level l is a complete closed 2-map
 * (B^l, β0^l, β1^l):
 *
 *   β0(d, l)  involution without fixed point: the other dart of d's edge.
 *   β1(d, l)  permutation: the next dart around d's vertex.
 *
 * The dual (half-edge) reading of the same map is
 *
 *   φ2 = β0            twin across the edge
 *   φ1 = β1 ∘ β0       next dart around the face (a dart runs along the face
 *                      on its left, starting at its vertex vert(d, l))
 *
 * so vertex orbits are <β1> = <φ1∘φ2>, edge orbits <β0>, face orbits
 * <φ1> = <β1∘β0>.
 *
 * Levels
 * ------
 * Every relation is indexed by level.  A query above the top level answers
 * with the finest relation.  Querying a dart at a level below its insertion
 * level is a programmer error.
 *
 * Storage (why this layout)
 * -------------------------
 * Each relation (β0, β1, and the vertex embedding vert) is an st_mla: a base
 * array holding every dart's value at its insertion level, plus one dense
 * column per level l >= 1 holding the level-l values of darts inserted
 * before l.  A column exists only from the first level at which some value
 * differs from the level below; levels without a column inherit.  A lookup
 * is therefore one comparison and one load, whatever the level (no walk, no
 * hashing):  j = eff[l];  value = (j > ins(d)) ? col[j][d] : base[d].
 *
 * In primal quadrisection (Loop, Catmull-Clark, Butterfly) β1 and vert never
 * change (thesis §3.2.1: old vertices keep their valence), so they have no
 * column; β0 changes for every old dart at every level, and a column of
 * level l has |B^{l-1}| entries.  For a regular hierarchy the topology then
 * costs 4 (β0 base) + 4/3 (β0 columns) + 4 (β1) + 4 (vert) + 2 (ins, flags)
 * = 15.3 bytes per finest dart; st_map_topology_bytes() reports the exact
 * figure.
 *
 * Sparse form.  In a progressive hierarchy (thesis §4.4) a level's vertex
 * splits re-set the relations of the darts around a few vertices only: a
 * dense column per level would mostly copy the level below (the thesis'
 * redundancy problem, §4.4.5).  st_map_compact() then turns β0, β1 and vert
 * each into the thesis' run-length form (§4.4.5): per dart the (level,
 * value) pairs at which its value changes, found by an offset per dart (a
 * 16-bit offset within its block of ST_POOL_BLOCK ids plus a 32-bit one per
 * block).  A lookup scans that dart's pairs from the finest down: at most
 * one pair per level above its insertion level, and on a progressive
 * hierarchy about one or two (st_map_sparse_stats_compute measures it).  An
 * attribute keeps its dense columns when the sparse form would not halve
 * them (quadrisection changes β0 for every old dart at every level), so
 * subdivision hierarchies never take that path.  The sparse form is
 * read-only: the first setter, new dart or level change on it turns it
 * back into dense columns, identical to those it came from; sessions store
 * the dense columns either way.
 *
 * Darts (and vertices) are allocated by an st_pool in blocks of
 * ST_POOL_BLOCK ids, each block owned by one insertion level, so the darts
 * of level l are enumerated by visiting the blocks of levels 0..l: time
 * proportional to |B^l|, not to the finest level.
 *
 * Setting a relation at level l also updates the levels above l that were
 * still equal to the old level-l value (those that had not diverged): that
 * is what inserting darts at level i+1 after level i+2 exists needs, and
 * keeps every level a valid map.  Setters cost O(levels); getters O(1).
 *
 * Boundaries: the map is always closed.  Holes are filled by faces whose
 * darts carry ST_DART_BOUNDARY; geometry and drawing skip them.
 */
#ifndef ST_MAP_H
#define ST_MAP_H

#include <assert.h>
#include <stddef.h>
#include <stdint.h>

#include "core/base/st_error.h"

#define ST_NIL 0xffffffffu
#define ST_MAX_LEVELS 24        /* levels 0..23; 4^23 faces is far beyond memory */
#define ST_POOL_BLOCK_SHIFT 8
#define ST_POOL_BLOCK (1u << ST_POOL_BLOCK_SHIFT)
#define ST_FREE_LEVEL 0xffu     /* ins[] value of a free id */

/* ---- st_pool: ids with an insertion level, allocated in per-level blocks -- */
typedef struct st_pool {
    uint32_t end;                         /* ids in [0, end) have been handed out in blocks */
    uint32_t cap;                         /* capacity of ins[] and of attached arrays */
    uint8_t *ins;                         /* one per id: insertion level, ST_FREE_LEVEL if free */
    uint32_t *blocks[ST_MAX_LEVELS];      /* per level: block numbers owned by that level */
    uint32_t nblocks[ST_MAX_LEVELS];
    uint32_t capblocks[ST_MAX_LEVELS];
    uint32_t fill[ST_MAX_LEVELS];         /* next unused id in the level's last block, ST_NIL if none */
    uint32_t freehead[ST_MAX_LEVELS];     /* per level: free-list of released ids (link in next_free) */
    uint32_t *next_free;                  /* allocated on the first release only */
    uint32_t live[ST_MAX_LEVELS];         /* live ids inserted at each level */
    uint32_t *spare;                      /* blocks of removed levels, reused first */
    uint32_t nspare, capspare;
} st_pool;

/* ---- st_mla: a multilevel attribute (see "Storage" above) ---------------- */
/* Sparse form of an attribute whose levels change few ids (see "Sparse
 * form" above): per id, the list of (level, value) pairs at which its value
 * differs from the level below, in increasing level order. */
typedef struct st_mla_sparse {
    uint32_t n;                           /* ids covered: [0, n), a multiple of ST_POOL_BLOCK */
    uint32_t *bbase;                      /* n/ST_POOL_BLOCK + 1: first pair of each block of ids */
    uint16_t *boff;                       /* n + 1: first pair of each id, from its block's bbase */
    uint8_t *lvl;                         /* per pair: level from which the value holds */
    unsigned char *val;                   /* per pair: elem bytes */
    uint32_t npairs;
    uint32_t pairs_at[ST_MAX_LEVELS];     /* pairs of each level */
    /* The dense form it stands for (thawing and the file format use it). */
    unsigned char has_col[ST_MAX_LEVELS];
    uint32_t colcap[ST_MAX_LEVELS];
} st_mla_sparse;

#define ST_MLA_SPARSE 0x80u               /* flag in st_mla.eff[l]: read level l from sp */

typedef struct st_mla {
    uint32_t elem;                        /* bytes per element */
    unsigned char *base;                  /* pool->cap elements: value at insertion level */
    unsigned char *col[ST_MAX_LEVELS];    /* col[l]: level-l values of ids with ins < l, or NULL */
    uint32_t colcap[ST_MAX_LEVELS];       /* elements allocated in col[l] */
    uint8_t eff[ST_MAX_LEVELS];           /* highest j <= l with col[j] != NULL, 0 if none;
                                             ST_MLA_SPARSE | l when sp holds level l */
    uint8_t maxcol;                       /* highest level with a column, 0 if none */
    st_mla_sparse *sp;                    /* NULL, or the sparse form (then no col[] is allocated) */
} st_mla;

enum st_dart_flags {
    ST_DART_BOUNDARY = 1u << 0,           /* dart of a face that fills a hole */
    /* Dart of a hole face (OBJ `t hole`, OpenSubdiv's Far hole tag): a real
     * face for the subdivision rules of its vertices and edges, but with no
     * surface: extraction marks it, drawing and export leave it out.  The
     * darts a refinement makes inside it inherit the flag, so its children
     * are holes at every level. */
    ST_DART_HOLE = 1u << 1,
};

/* Change log (optional): while st_map.log is set, the primitive setters
 * below record the darts whose relations they set or that they create or
 * delete, and the vertices whose positions they set or that they create or
 * delete (ids may repeat).  A consumer that mirrors the map (the renderer's
 * buffers) then updates only what a local operation touched.  On running
 * out of memory the log stops and sets `overflow`: the consumer must then
 * start again from scratch.  Transient: never saved, never copied along. */
typedef struct st_map_log {
    uint32_t *darts, *verts;
    uint32_t ndarts, nverts, capdarts, capverts;
    int overflow;
} st_map_log;
void st_map_log_clear(st_map_log *g);    /* empties it (keeps the memory) */
void st_map_log_free(st_map_log *g);

typedef struct st_map {
    unsigned top;                         /* finest existing level */
    uint64_t gen;                         /* topology generation (st_map_generation) */
    int gen_seen;                         /* gen was handed out since it last changed */
    st_map_log *log;                      /* NULL, or where changes are recorded (above) */
    st_pool darts;
    st_pool verts;
    st_mla beta0;                         /* per dart, uint32_t */
    st_mla beta1;                         /* per dart, uint32_t */
    st_mla vert;                          /* per dart, uint32_t vertex id (0-embedding) */
    uint8_t *flags;                       /* per dart, enum st_dart_flags (level-independent) */
    st_mla pos;                           /* per vertex, double[3] position at each level */
    uint32_t *marks;                      /* per dart, marker bits (scratch; allocated on demand) */
    st_mla *dart_attrs[4];                /* attached per-dart attributes (st_map_attach) */
    st_mla *vert_attrs[4];                /* attached per-vertex attributes */
    uint32_t ndart_attrs, nvert_attrs;
    uint32_t marks_used;                  /* bit mask of reserved marker bits */
    uint8_t face_embedded;                /* dual encoding (Doo-Sabin, thesis §3.2.1): vert holds the
                                             id of the dart's face, and vertices of the surface are
                                             the map's faces, its faces the map's vertex orbits */
} st_map;

/* ---- lifetime -------------------------------------------------------------- */
void st_map_init(st_map *m);
void st_map_free(st_map *m);

/* Topology generation: a number that changes whenever the map's darts, their
 * relations or flags, its vertex ids or its levels change (positions do
 * not count), unique across all maps of the process.  A cache derived from
 * the topology (the Catmull-Clark synthesis tables) stores it and is stale
 * when it differs.  Code that writes the relation arrays directly instead of
 * through the setters below calls st_map_changed. */
uint64_t st_map_generation(st_map *m);
void st_map_changed(st_map *m);

/* ---- inline queries: O(1) at every level --------------------------------- */
static inline unsigned st_lvl_clamp(unsigned l)
{
    return l < ST_MAX_LEVELS ? l : ST_MAX_LEVELS - 1;
}

/* Level-l value of id i in an attribute in sparse form (ins[i] < l). */
const void *st_mla_sparse_at(const st_mla *a, const uint8_t *ins, uint32_t i, unsigned l);

/* Two lookup paths ("Sparse form" above).  The dense one is the lookup of
 * "Storage": one comparison and one load.  The other also answers the
 * sparse form, at the price of a test on every lookup, which costs
 * subdivision's hot loops 11-35 % more instructions.  So a translation unit
 * whose loops only ever see dense maps (refinement, the subdivision
 * schemes, face-varying refinement) defines ST_MAP_DENSE_ONLY before its
 * first #include: st_mla_at, st_beta0, st_view_get and the others then
 * take the dense path, and assert (in debug builds) that the attribute is
 * not sparse.  Everywhere else they take the path that answers both.  A
 * function that can meet both kinds and is hot on subdivision maps (level
 * statistics) calls the _kind forms with a constant `sparse` argument, once
 * per kind (st_map_is_sparse), so that the compiler makes a dense copy
 * without the test. */
#ifdef ST_MAP_DENSE_ONLY
#define ST_MAP_SPARSE_READS 0
#else
#define ST_MAP_SPARSE_READS 1
#endif

static inline const void *st_mla_at_dense(const st_mla *a, const uint8_t *ins, uint32_t i, unsigned l)
{
    assert(a->sp == NULL);
    unsigned j = a->eff[st_lvl_clamp(l)];
    const unsigned char *p = j > ins[i] ? a->col[j] : a->base;
    return p + (size_t)i * a->elem;
}

static inline const void *st_mla_at_any(const st_mla *a, const uint8_t *ins, uint32_t i, unsigned l)
{
    unsigned j = a->eff[st_lvl_clamp(l)];
    if (j > ins[i]) {
        if (__builtin_expect(j & ST_MLA_SPARSE, 0)) return st_mla_sparse_at(a, ins, i, j & ~ST_MLA_SPARSE);
        return a->col[j] + (size_t)i * a->elem;
    }
    return a->base + (size_t)i * a->elem;
}

static inline const void *st_mla_at_kind(const st_mla *a, const uint8_t *ins, uint32_t i, unsigned l, int sparse)
{
    return sparse ? st_mla_at_any(a, ins, i, l) : st_mla_at_dense(a, ins, i, l);
}

static inline const void *st_mla_at(const st_mla *a, const uint8_t *ins, uint32_t i, unsigned l)
{
    return st_mla_at_kind(a, ins, i, l, ST_MAP_SPARSE_READS);
}

static inline uint32_t st_mla_u32(const st_mla *a, const uint8_t *ins, uint32_t i, unsigned l)
{
    return *(const uint32_t *)st_mla_at(a, ins, i, l);
}

/* Whether one of the relations is in sparse form (st_map_compact). */
static inline int st_map_is_sparse(const st_map *m)
{
    return m->beta0.sp != NULL || m->beta1.sp != NULL || m->vert.sp != NULL;
}

static inline uint32_t st_beta0_kind(const st_map *m, uint32_t d, unsigned l, int sparse)
{
    return *(const uint32_t *)st_mla_at_kind(&m->beta0, m->darts.ins, d, l, sparse);
}
static inline uint32_t st_beta1_kind(const st_map *m, uint32_t d, unsigned l, int sparse)
{
    return *(const uint32_t *)st_mla_at_kind(&m->beta1, m->darts.ins, d, l, sparse);
}
static inline uint32_t st_phi1_kind(const st_map *m, uint32_t d, unsigned l, int sparse)
{
    return st_beta1_kind(m, st_beta0_kind(m, d, l, sparse), l, sparse);
}

static inline uint32_t st_beta0(const st_map *m, uint32_t d, unsigned l) { return st_mla_u32(&m->beta0, m->darts.ins, d, l); }
static inline uint32_t st_beta1(const st_map *m, uint32_t d, unsigned l) { return st_mla_u32(&m->beta1, m->darts.ins, d, l); }
static inline uint32_t st_phi2(const st_map *m, uint32_t d, unsigned l) { return st_beta0(m, d, l); }
static inline uint32_t st_phi1(const st_map *m, uint32_t d, unsigned l) { return st_beta1(m, st_beta0(m, d, l), l); }
static inline uint32_t st_vert(const st_map *m, uint32_t d, unsigned l) { return st_mla_u32(&m->vert, m->darts.ins, d, l); }
static inline unsigned st_dart_level(const st_map *m, uint32_t d) { return m->darts.ins[d]; }
static inline int st_dart_live(const st_map *m, uint32_t d) { return d < m->darts.end && m->darts.ins[d] != ST_FREE_LEVEL; }
static inline int st_dart_in_level(const st_map *m, uint32_t d, unsigned l) { return st_dart_live(m, d) && m->darts.ins[d] <= l; }
static inline int st_is_boundary(const st_map *m, uint32_t d) { return (m->flags[d] & ST_DART_BOUNDARY) != 0; }
static inline int st_is_hole(const st_map *m, uint32_t d) { return (m->flags[d] & ST_DART_HOLE) != 0; }
/* Dart of a face with no surface to draw or export: a boundary or a hole. */
static inline int st_is_void(const st_map *m, uint32_t d) { return (m->flags[d] & (ST_DART_BOUNDARY | ST_DART_HOLE)) != 0; }
static inline unsigned st_vertex_level(const st_map *m, uint32_t v) { return m->verts.ins[v]; }
/* Positions never take the sparse form (st_map_compact leaves them). */
static inline const double *st_pos(const st_map *m, uint32_t v, unsigned l) { return (const double *)st_mla_at_dense(&m->pos, m->verts.ins, v, l); }
/* Position of the vertex of dart d at level l. */
static inline const double *st_dart_pos(const st_map *m, uint32_t d, unsigned l) { return st_pos(m, st_vert(m, d, l), l); }

/* Level views: the column pointers of one level hoisted out of a hot loop.
 * Valid until the map changes.  col is NULL when the attribute is sparse
 * (then lvl carries ST_MLA_SPARSE and mla answers). */
typedef struct st_u32_view { const uint32_t *base, *col; unsigned lvl; const st_mla *mla; } st_u32_view;
typedef struct st_level_view {
    const uint8_t *ins, *vins;
    st_u32_view beta0, beta1, vert;
    const double *pbase, *pcol;
    unsigned plvl;
} st_level_view;

static inline st_u32_view st_u32_view_of(const st_mla *a, unsigned l)
{
    unsigned j = a->eff[st_lvl_clamp(l)];
    st_u32_view v = { (const uint32_t *)a->base, (j & ST_MLA_SPARSE) ? NULL : (const uint32_t *)a->col[j], j, a };
    return v;
}

/* Whether a level view reads a relation in sparse form: the `sparse`
 * argument of the _kind forms below for the loops that take one view. */
static inline int st_level_view_is_sparse(const st_level_view *v)
{
    return ((v->beta0.lvl | v->beta1.lvl | v->vert.lvl) & ST_MLA_SPARSE) != 0;
}

static inline void st_level_view_init(const st_map *m, unsigned l, st_level_view *v)
{
    v->ins = m->darts.ins;
    v->vins = m->verts.ins;
    v->beta0 = st_u32_view_of(&m->beta0, l);
    v->beta1 = st_u32_view_of(&m->beta1, l);
    v->vert = st_u32_view_of(&m->vert, l);
    v->plvl = m->pos.eff[st_lvl_clamp(l)];
    v->pbase = (const double *)m->pos.base;
    v->pcol = (const double *)m->pos.col[v->plvl];
}

static inline uint32_t st_view_get_dense(const st_u32_view *r, const uint8_t *ins, uint32_t d)
{
    assert(!(r->lvl & ST_MLA_SPARSE));
    return ins[d] < r->lvl ? r->col[d] : r->base[d];
}

static inline uint32_t st_view_get_any(const st_u32_view *r, const uint8_t *ins, uint32_t d)
{
    if (ins[d] < r->lvl) {
        if (__builtin_expect(r->lvl & ST_MLA_SPARSE, 0))
            return *(const uint32_t *)st_mla_sparse_at(r->mla, ins, d, r->lvl & ~ST_MLA_SPARSE);
        return r->col[d];
    }
    return r->base[d];
}

static inline uint32_t st_view_get_kind(const st_u32_view *r, const uint8_t *ins, uint32_t d, int sparse)
{
    return sparse ? st_view_get_any(r, ins, d) : st_view_get_dense(r, ins, d);
}

static inline uint32_t st_view_get(const st_u32_view *r, const uint8_t *ins, uint32_t d)
{
    return st_view_get_kind(r, ins, d, ST_MAP_SPARSE_READS);
}
static inline uint32_t st_v_beta0(const st_level_view *v, uint32_t d) { return st_view_get(&v->beta0, v->ins, d); }
static inline uint32_t st_v_beta1(const st_level_view *v, uint32_t d) { return st_view_get(&v->beta1, v->ins, d); }
static inline uint32_t st_v_phi1(const st_level_view *v, uint32_t d) { return st_v_beta1(v, st_v_beta0(v, d)); }
static inline uint32_t st_v_vert(const st_level_view *v, uint32_t d) { return st_view_get(&v->vert, v->ins, d); }
static inline uint32_t st_v_beta0_kind(const st_level_view *v, uint32_t d, int sparse) { return st_view_get_kind(&v->beta0, v->ins, d, sparse); }
static inline uint32_t st_v_beta1_kind(const st_level_view *v, uint32_t d, int sparse) { return st_view_get_kind(&v->beta1, v->ins, d, sparse); }
static inline uint32_t st_v_phi1_kind(const st_level_view *v, uint32_t d, int sparse)
{
    return st_v_beta1_kind(v, st_v_beta0_kind(v, d, sparse), sparse);
}
static inline const double *st_v_pos(const st_level_view *v, uint32_t vid)
{
    return (v->vins[vid] < v->plvl ? v->pcol : v->pbase) + 3 * (size_t)vid;
}

/* Walks of the surface's cells, whichever the encoding.  A surface face is
 * a φ1 orbit and a surface vertex a β1 orbit, except in Doo-Sabin's dual
 * encoding (st_map.face_embedded, Kraemer 2008 §3.2.1; scheme_doosabin.c),
 * where a surface face is a β1 orbit and a surface vertex a φ1 orbit.
 * Either way one dart is one corner: st_face_step gives the next corner of
 * d's face (the next vertex along it), st_vertex_step the next corner
 * around d's vertex (each in another face).  Code that means the surface
 * walks with these; st_phi1 / st_beta1 name the map's own orbits.  The view
 * forms take the encoding as `dual` (m->face_embedded). */
static inline uint32_t st_face_step(const st_map *m, uint32_t d, unsigned l)
{
    return m->face_embedded ? st_beta1(m, d, l) : st_phi1(m, d, l);
}
static inline uint32_t st_vertex_step(const st_map *m, uint32_t d, unsigned l)
{
    return m->face_embedded ? st_phi1(m, d, l) : st_beta1(m, d, l);
}
/* Visiting each real triangle of level l once (triangle meshes: the
 * progressive levels): whether d is its triangle's smallest dart, not a
 * boundary dart; x and y get the triangle's next two darts. */
static inline int st_tri_first_dart(const st_map *m, uint32_t d, unsigned l, uint32_t *x, uint32_t *y)
{
    if (st_is_boundary(m, d)) return 0;
    *x = st_phi1(m, d, l);
    *y = st_phi1(m, *x, l);
    return *x > d && *y > d;
}
static inline uint32_t st_v_face_step_kind(const st_level_view *v, int dual, uint32_t d, int sparse)
{
    return dual ? st_v_beta1_kind(v, d, sparse) : st_v_phi1_kind(v, d, sparse);
}
static inline uint32_t st_v_vertex_step_kind(const st_level_view *v, int dual, uint32_t d, int sparse)
{
    return dual ? st_v_phi1_kind(v, d, sparse) : st_v_beta1_kind(v, d, sparse);
}
static inline uint32_t st_v_face_step(const st_level_view *v, int dual, uint32_t d)
{
    return st_v_face_step_kind(v, dual, d, ST_MAP_SPARSE_READS);
}
static inline uint32_t st_v_vertex_step(const st_level_view *v, int dual, uint32_t d)
{
    return st_v_vertex_step_kind(v, dual, d, ST_MAP_SPARSE_READS);
}

/* φ1⁻¹ and β1⁻¹ are not stored (memory): they walk the face / vertex. */
/* Inline, so that they take the lookup path of the file that calls them
 * ("Two lookup paths"). */
static inline uint32_t st_phi_1(const st_map *m, uint32_t d, unsigned l)
{
    uint32_t x = d, n;
    while ((n = st_phi1(m, x, l)) != d) x = n;
    return x;
}
static inline uint32_t st_beta1_inv(const st_map *m, uint32_t d, unsigned l)
{
    uint32_t x = d, n;
    while ((n = st_beta1(m, x, l)) != d) x = n;
    return x;
}
static inline unsigned st_face_degree(const st_map *m, uint32_t d, unsigned l)
{
    unsigned n = 0;
    uint32_t x = d;
    do { n++; x = st_phi1(m, x, l); } while (x != d);
    return n;
}
static inline unsigned st_vertex_degree(const st_map *m, uint32_t d, unsigned l)
{
    unsigned n = 0;
    uint32_t x = d;
    do { n++; x = st_beta1(m, x, l); } while (x != d);
    return n;
}
/* Edge level (thesis §3.2.6): max insertion level of its two darts at level l. */
static inline unsigned st_edge_level(const st_map *m, uint32_t d, unsigned l)
{
    unsigned a = m->darts.ins[d], b = m->darts.ins[st_beta0(m, d, l)];
    return a > b ? a : b;
}

/* ---- enumeration: time proportional to the size of level l ---------------- */
/* Every live dart of B^l: d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it) */
typedef struct st_dart_iter { unsigned level; uint32_t block; uint32_t id; } st_dart_iter; /* id: offset in block */
uint32_t st_dart_first(const st_map *m, unsigned l, st_dart_iter *it);
uint32_t st_dart_next(const st_map *m, unsigned l, st_dart_iter *it);
/* Same for vertex ids existing at level l. */
uint32_t st_vertex_first(const st_map *m, unsigned l, st_dart_iter *it);
uint32_t st_vertex_next(const st_map *m, unsigned l, st_dart_iter *it);

/* Cell counts of level l; faces and edges exclude nothing, `boundary`
 * counts the hole faces (boundary loops), `faces` excludes them. */
typedef struct st_level_stats {
    uint64_t darts, vertices, edges, faces, boundary_loops, boundary_edges;
    int64_t euler;                        /* V - E + F (real faces only) */
} st_level_stats;
void st_level_stats_compute(st_map *m, unsigned l, st_level_stats *s);

/* ---- marker bits (thesis listing 2.4.5) ----------------------------------- */
/* Reserves one of 32 marker bits; returns -1 when all are taken.  Marks are
 * scratch state, cleared by st_marker_release over the darts of level l. */
int st_marker_reserve(st_map *m);
void st_marker_release(st_map *m, int bit, unsigned l);
static inline int st_marked(const st_map *m, int bit, uint32_t d) { return (m->marks[d] >> bit) & 1u; }
static inline void st_mark(st_map *m, int bit, uint32_t d) { m->marks[d] |= 1u << bit; }
static inline void st_unmark(st_map *m, int bit, uint32_t d) { m->marks[d] &= ~(1u << bit); }
static inline void st_mark_face(st_map *m, int bit, uint32_t d, unsigned l)
{
    uint32_t x = d;
    do { st_mark(m, bit, x); x = st_phi1(m, x, l); } while (x != d);
}
static inline void st_mark_vertex(st_map *m, int bit, uint32_t d, unsigned l)
{
    uint32_t x = d;
    do { st_mark(m, bit, x); x = st_beta1(m, x, l); } while (x != d);
}

/* ---- base operators (thesis §2.3.1), acting at level l and above ---------- */
/* New dart inserted at level l with β0 = β1 = itself and vertex v. */
uint32_t st_dart_new(st_map *m, unsigned l, uint32_t v, uint8_t flags);
/* Frees a dart inserted at level l; the caller has detached it. */
void st_dart_delete(st_map *m, uint32_t d);
void st_set_beta0(st_map *m, uint32_t d, unsigned l, uint32_t e);
void st_set_beta1(st_map *m, uint32_t d, unsigned l, uint32_t e);
void st_set_vert(st_map *m, uint32_t d, unsigned l, uint32_t v);
/* Sews d and e by β0 at level l (both directions). */
void st_sew0(st_map *m, uint32_t d, uint32_t e, unsigned l);

/* Attaches an attribute owned by the caller: it is grown with the pool and
 * every new id gets the value zero (elem bytes of zeros) at all levels.
 * Existing ids are set to zero too.  Returns -1 when out of memory or when
 * four attributes are attached already. */
int st_map_attach_dart_attr(st_map *m, st_mla *a);
int st_map_attach_vertex_attr(st_map *m, st_mla *a);

/* ---- vertices -------------------------------------------------------------- */
uint32_t st_vertex_new(st_map *m, unsigned l, const double p[3]);
void st_vertex_delete(st_map *m, uint32_t v);
/* Sets the position of v at level l (and the levels above that still had the
 * old level-l position).  Positions are stored per level only from the first
 * level at which some vertex differs from the level below. */
void st_set_pos(st_map *m, uint32_t v, unsigned l, const double p[3]);
/* Writable position slot of v at level l, for the synthesis passes: base
 * when v was inserted at l, else the level-l column; the column is created
 * only when p differs from the inherited value ("stored only where it
 * differs"), so that a synthesis writing every vertex of a level leaves
 * no column where the level adds nothing. */
void st_map_write_pos(st_map *m, uint32_t v, unsigned l, const double p[3]);
/* Records v in m->log when one is set (the setters above do it themselves). */
void st_map_log_vertex(st_map *m, uint32_t v);

/* Sizes the arrays for `darts` and `verts` more ids at exact size, so that a
 * known amount of growth does not double the capacity.  -1: out of memory
 * (nothing changed that matters: the map stays valid). */
int st_map_reserve(st_map *m, uint64_t darts, uint64_t verts);
/* Advises huge pages (core/base/hugepage.h) for the ids reserved beyond the
 * pools' ends: for callers that then write every reserved id in order, as
 * uniform refinement does.  Adaptive refinement touches its reservations
 * sparsely and does not call it: a huge page is resident as a whole. */
void st_map_advise_reserved(st_map *m);

/* Gives back spare capacity once a map is built: pools and their arrays to
 * the ids handed out, columns to the ids they can hold.  Growth afterwards
 * works as before (the next insertion regrows). */
void st_map_trim(st_map *m);

/* Trims the map (st_map_trim) and stores β0, β1 and vert in sparse form
 * where that takes less than half their dense columns ("Sparse form"
 * above).  Queries answer the same; the next change to the topology turns
 * them dense again.  Out of memory keeps the dense form. */
void st_map_compact(st_map *m);
/* Pairs of the sparse form: total over β0, β1 and vert, and the longest
 * list of one dart in one relation (the bound on a lookup's scan). */
typedef struct st_map_sparse_stats { uint64_t pairs; unsigned longest; unsigned relations_sparse; } st_map_sparse_stats;
void st_map_sparse_stats_compute(const st_map *m, st_map_sparse_stats *s);

/* For code that copies an st_mla field by field (undo snapshots): copies
 * src's sparse form into dst->sp (NULL when src has none); -1 when out of
 * memory.  *bytes (may be NULL) grows by what was allocated. */
int st_mla_sparse_copy(st_mla *dst, const st_mla *src, size_t *bytes);
void st_mla_sparse_free(st_mla_sparse *s);

/* ---- levels ---------------------------------------------------------------- */
/* Creates level top+1 as a copy of level top, in O(1): nothing is copied,
 * the new level inherits until something changes in it. */
int st_level_add(st_map *m, st_error *err);
/* Deletes the finest level: its darts, vertices and columns. */
void st_level_remove_top(st_map *m);

/* Deletes the coarsest level: level 1 becomes level 0 with its relations
 * and positions, every level above moves one down ("delete lower"). */
void st_level_remove_bottom(st_map *m);

/* ---- higher operators across levels (thesis §2.3.2), at level l ---------- */
/* Splits the edge of d at level l by a new vertex at position p (variant of
 * fig. 2.4: d and β0(d) keep their vertices).  Returns the new dart that
 * starts at the new vertex and follows d along d's face (φ1(d) at level l). */
uint32_t st_split_edge(st_map *m, uint32_t d, unsigned l, const double p[3]);
/* Inverse: x is the dart returned by st_split_edge, inserted at level l, and
 * its vertex has degree 2 at level l.  Fails if that does not hold. */
int st_unsplit_edge(st_map *m, uint32_t x, unsigned l, st_error *err);
/* Cuts the face of d1 and d2 (two distinct darts of one face, not
 * consecutive) at level l by a new edge from vert(d1) to vert(d2).
 * Returns the new dart starting at vert(d1) (it lies in d2's new face). */
uint32_t st_cut_face(st_map *m, uint32_t d1, uint32_t d2, unsigned l);
/* Inverse: removes the edge of x (both darts inserted at level l). */
int st_uncut_face(st_map *m, uint32_t x, unsigned l, st_error *err);
/* Flips the edge of d at level l inside its two faces (both of degree >= 3):
 * each end moves one vertex back along its face (triangles: the other
 * diagonal of the quad).  st_flip_edge_back is its inverse. */
int st_flip_edge(st_map *m, uint32_t d, unsigned l, st_error *err);
int st_flip_edge_back(st_map *m, uint32_t d, unsigned l, st_error *err);

/* ---- validator ------------------------------------------------------------ */
/* Checks every level 0..top: β0 is an involution without fixed point, β1 a
 * permutation, relations stay inside B^l, dart sets are nested, every vertex
 * orbit carries one vertex id that exists at that level and no two orbits
 * share one, face orbits are homogeneous in the boundary flag, and boundary
 * faces never touch each other.  Returns ST_OK or ST_ERR_INVALID with the
 * first failure (level, dart, what) in err. */
int st_map_validate(st_map *m, st_error *err);

/* ---- memory --------------------------------------------------------------- */
typedef struct st_map_bytes {
    size_t topology;       /* β0, β1, vert (base + columns), ins, flags of darts */
    size_t positions;      /* pos base + columns, vertex ins */
} st_map_bytes;
void st_map_memory(const st_map *m, st_map_bytes *b);

#endif
