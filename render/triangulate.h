/* Triangulation of the faces of a displayed level by case tables
 * (Kraemer 2008 §3.3.3, Algorithm 7, figs 3.38-3.39, listing 3.3.1).
 *
 * With the one-level restriction, a face of level f of an adaptive mesh is a
 * *coarse* polygon (a triangle for Loop/Butterfly, a quad for Catmull-Clark,
 * either for quad/triangle, any n-gon at level 0 or for Doo-Sabin) some of
 * whose edges were split once because the neighbour across them is finer.
 * Its corners are then of two kinds:
 *
 *     'c'  a corner of the coarse polygon,
 *     'm'  the midpoint (hanging vertex) of a split coarse edge,
 *
 * and its edges of two levels: coarse edges (c-c, level f) and half edges
 * (c-m and m-c, level f+1).  The case of a face is its pattern of corner
 * kinds read while walking the face once, e.g. "cmccc" (a quad with one
 * split edge, 5 sides).  Only the walk is needed: the edge level of each
 * side (st_edge_level: the insertion levels of the side's two darts) and the
 * insertion level of each corner vertex; no neighbouring face is visited.
 *
 * Reading the pattern from the levels (st_tri_classify):
 *   - 3 sides: always "ccc" (one triangle); this covers √3, whose faces are
 *     always triangles whatever the levels of their edges (a border triangle
 *     next to a finer one has an unflipped edge one level coarser).
 *   - two edge levels e and e+1: the fine sides form runs between coarse
 *     sides; each run pairs up from its start (first half, second half), and
 *     the corner between the two halves of a pair is 'm'.  A run of odd
 *     length, or an 'm' whose vertex is not one level e+1 vertex, is not a
 *     restricted face: fallback.
 *   - one edge level e: a regular polygon ("ccc…"), unless every second
 *     corner is a vertex inserted at level e and the others are older (and
 *     e >= 1): then every edge was split ("cmcm…").  Regular faces at levels
 *     >= 1 are triangles and quads whose vertices never alternate like this.
 *   - Doo-Sabin (dual encoding, no vertex levels): a quad whose sides are
 *     fine, fine, fine, coarse is a surface face with two adjacent corners
 *     one level finer (Doo-Sabin points of subdivided cells) and two
 *     coarser ones; it is read as "cmcc" with the first finer corner as
 *     'm' (the diagonal from it to the far coarse corner).  The other
 *     Doo-Sabin border polygons read as they are: a quad with one finer
 *     corner has two fine sides around it ("cmcc", the diagonal from that
 *     corner), three finer corners or two opposite ones make every side
 *     fine (a regular quad), the triangle at an edge split on one side is
 *     a triangle; larger polygons at depth borders (level 0 n-gons)
 *     mostly take the fallback.
 *   - levels further apart (restriction off), fewer than 3 'c' corners, or a
 *     pattern not in the table: fallback.
 *
 * Fallback (faces outside the tables: restriction off, input n-gons with
 * split edges, polygons of more than 8 sides): ear clipping in the plane of
 * the face's Newell normal, taking the best-shaped valid ear each time; with
 * more than ST_TRI_EAR_MAX sides, or a degenerate polygon, a fan from corner
 * 0.  Every triangulation written (table or fallback) has exactly n-2
 * triangles on the face's own corners, uses each side of the face once in
 * the face's orientation and each diagonal twice in opposite directions, so
 * it never leaves a hole and never changes the welded topology.
 */
#ifndef ST_TRIANGULATE_H
#define ST_TRIANGULATE_H
#ifndef STRATA_RENDER_INTERNAL
#error "internal to render: ui/, app/ and bench/ use render's public headers (docs/ARCHITECTURE.md)"
#endif

#include <stdint.h>

#define ST_TRI_TABLE_MAX_SIDES 8      /* largest polygon in the tables */
#define ST_TRI_EAR_MAX 64             /* largest polygon ear-clipped by the fallback */
#define ST_TRI_FALLBACK (-1)          /* case id of faces outside the tables */

typedef struct st_tri_case {
    const char *name;                 /* e.g. "quad, 1 split edge" */
    const char *pattern;              /* corner kinds from corner 0: 'c' or 'm' */
    uint8_t ntri;                     /* strlen(pattern) - 2 */
    uint8_t tri[ST_TRI_TABLE_MAX_SIDES - 2][3]; /* counter-clockwise, corner indices */
} st_tri_case;

extern const st_tri_case st_tri_cases[];
extern const unsigned st_tri_ncases;

/* Lookup from (sides, mask of 'm' corners) to (case, rotation): built once
 * from the table; 'rot' r means corner i of the case is corner (i + r) % n
 * of the face. */
typedef struct st_tri_index {
    int16_t icase[ST_TRI_TABLE_MAX_SIDES + 1][1u << ST_TRI_TABLE_MAX_SIDES];
    uint8_t rot[ST_TRI_TABLE_MAX_SIDES + 1][1u << ST_TRI_TABLE_MAX_SIDES];
} st_tri_index;
void st_tri_index_init(st_tri_index *ix);
/* One index for the whole process, built on first use (thread-safe): what
 * every st_rgeom reads. */
const st_tri_index *st_tri_index_shared(void);

/* Corner kinds of a face of n <= ST_TRI_TABLE_MAX_SIDES sides: elev[k] is
 * the level of side k (corner k to corner k+1), vlev[k] the insertion level
 * of corner k's vertex (NULL when unknown, e.g. the dual encoding: then the
 * all-split reading is not tried).  Sets bit k of *mmask when corner k is
 * 'm'.  Returns 0, or -1 when the face is not a restricted face. */
int st_tri_classify(unsigned n, const uint8_t *elev, const uint8_t *vlev, uint32_t *mmask);

/* Triangulates one face of n >= 3 corners.  pos holds the corners'
 * positions (3n floats; used by the fallback only, may be NULL for table
 * faces).  Writes n-2 triangles as corner indices into tri (3(n-2)
 * entries).  Returns the case id (index in st_tri_cases) or ST_TRI_FALLBACK. */
int st_tri_face(const st_tri_index *ix, unsigned n, const uint8_t *elev, const uint8_t *vlev,
                const float *pos, uint32_t *tri);

/* The fallback alone (ear clipping / fan), for tests. */
void st_tri_fallback(unsigned n, const float *pos, uint32_t *tri);

#endif
