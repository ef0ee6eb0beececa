/* st_rgeom: the CPU side of what the renderer draws for one level of a map.
 *
 * Data path: map -> st_rgeom -> GL buffers, one way.  st_rgeom_build walks
 * the real (non-boundary) faces of level l once; for each face it reads the
 * corners' vertices, the level of each side and the insertion level of each
 * corner (the case of st_tri_face: no neighbouring face is visited), and
 * writes
 *
 *   - the vertex table: one entry per vertex used by a real face, in
 *     increasing vertex-id order (so vertices created together sit together
 *     and an edit's vertices form few ranges), interleaved position + normal
 *     (what the vertex buffer holds, uploaded as it is);
 *   - the faces (counts and offsets into the corner list), a face normal per
 *     face (Newell vector: area-weighted, for flat shading);
 *   - triangles (n-2 per face, from the case tables) and the face of each;
 *   - polygon edges for the wireframe: each side of a real face once (the
 *     sides of the polygons, never triangulation diagonals).
 *
 * Both encodings are read: primal maps (faces are φ1 orbits, vertices β1
 * orbits) and the dual encoding of Doo-Sabin (st_map.face_embedded: faces
 * are β1 orbits, the vertex of a corner is the id carried by its dart).
 *
 * Smooth normals: vertex normal = normalised sum of the face normals around
 * the vertex, computed by one procedure for the full build and for local
 * refreshes, so an incremental update gives bit-identical buffers.
 *
 * Incremental updates (an edit moves some vertices, topology unchanged):
 * core reports which values the edit wrote (core/map/footprint.h);
 * st_rgeom_footprint_vids() takes the vertices of the drawn level among
 * them, st_rgeom_refresh() re-reads those positions and recomputes the
 * normals that depend on them, and reports the dirty vertex and face ranges
 * for glBufferSubData.
 */
#ifndef ST_RGEOM_H
#define ST_RGEOM_H

#include <stddef.h>
#include <stdint.h>

#include "core/map/map.h"
#include "core/map/footprint.h"
#include "core/base/st_error.h"
#include "core/fvar/fvar.h"

#define ST_RGEOM_VSTRIDE 6            /* floats per vertex: position, normal */

/* The case tables of the triangulation are render's own (triangulate.h). */
struct st_tri_index;

typedef struct st_range { uint32_t first, count; } st_range;

typedef struct st_range_list {
    st_range *r;
    uint32_t n, cap;
} st_range_list;

typedef struct st_rgeom {
    unsigned level;                   /* level of the map this was built from */
    int face_embedded;                /* dual encoding (Doo-Sabin) */
    uint32_t ndarts_end, nvids;       /* map->darts.end, map->verts.end at build time */

    uint32_t nverts;
    float *vdata;                     /* ST_RGEOM_VSTRIDE per vertex: x y z nx ny nz */
    uint32_t *vid;                    /* per vertex: map vertex id */
    uint32_t *vdart;                  /* per vertex: a dart of a real face at this vertex */
    uint32_t *slot;                   /* per map vertex id (nvids): vertex index, ST_NIL if not drawn */

    uint32_t nfaces;
    uint32_t *face_dart;              /* per face: the dart its walk starts from */
    uint32_t *face_off;               /* nfaces + 1 offsets into corner[] */
    uint32_t *corner;                 /* per corner: vertex index */
    float *fnormal;                   /* 4 per face: Newell vector, 0 (RGBA texel for flat shading) */
    int16_t *face_case;               /* per face: st_tri_cases index or ST_TRI_FALLBACK */
    uint32_t *dart_face;              /* per dart id (ndarts_end): face index, or >= nfaces */

    uint32_t ntris;
    uint32_t *tris;                   /* 3 per triangle: vertex indices, counter-clockwise */
    uint32_t *tri_face;               /* per triangle: its face (face f owns triangles
                                         face_off[f] - 2f .. face_off[f+1] - 2(f+1) - 1) */
    uint32_t nlines;
    uint32_t *lines;                  /* 2 per polygon edge: vertex indices */

    float bbox[6];                    /* min xyz, max xyz of the drawn vertices */
    uint32_t ncase[32];               /* faces per case id (index ncase[0..30] = case, [31] = fallback) */
    uint32_t *face_line;              /* nfaces + 1 offsets into lines: the polygon edges each face draws */

    /* st_rgeom_patch: faces it removed keep their slots (face_dart ST_NIL,
     * their triangles and lines made degenerate: index 0 repeated, which
     * draws nothing); faces and vertices it adds are appended. */
    uint32_t ndead;                   /* removed faces among the nfaces */
    size_t cap_faces;                 /* entries allocated in face_off and fnormal (per face, + 1) */
    size_t cap_face_dart, cap_face_case, cap_face_line, cap_corner, cap_tris, cap_lines, cap_verts;
    size_t cap_dart_face, cap_slot;

    /* Scratch for edit regions and refreshes (allocated on first use). */
    uint32_t *dstamp_v, *dstamp_f;    /* per dart: generation marks (vertex orbit, face orbit) */
    uint32_t dstamp_cap;              /* entries in dstamp_v and dstamp_f */
    uint32_t *vstamp;                 /* per vertex index: generation mark */
    uint32_t *fstamp;                 /* per face: generation mark */
    size_t vstamp_cap, fstamp_cap;    /* entries in vstamp and fstamp (grown as patches append) */
    uint32_t gen;
    uint32_t *reread;                 /* vertex indices the last st_rgeom_refresh re-read */
    uint32_t nreread;
    const struct st_tri_index *tix;   /* case lookup (render/triangulate.c: built once, shared) */
} st_rgeom;

void st_rgeom_init(st_rgeom *g);
void st_rgeom_free(st_rgeom *g);

/* Builds g (replacing its content) from level l of m.  The map is read
 * only.  Fails with ST_ERR_MEMORY or ST_ERR_RANGE (level above the top);
 * g is left empty then. */
int st_rgeom_build(st_rgeom *g, const st_map *m, unsigned l, st_error *err);

/* Appends to *vids (growable, *n entries, *cap capacity) the ids of the
 * vertices drawn by g whose position at g->level the footprint fp wrote:
 * its position keys of levels <= g->level (a level without a position of
 * its own shows the coarser one), each vertex once.  Returns 0 or -1 (out
 * of memory). */
int st_rgeom_footprint_vids(st_rgeom *g, const st_map *m, const st_footprint *fp,
                            uint32_t **vids, uint32_t *n, uint32_t *cap);

/* Re-reads the positions of the given vertex ids (ids not drawn are
 * skipped), recomputes the face normals of the faces around them and the
 * vertex normals of those faces' corners.  The vertex and face ranges that
 * changed are appended to vdirty and fdirty (sorted, merged when closer than
 * ST_RGEOM_RANGE_GAP).  The vertex indices it re-read are left in
 * g->reread (what a test compares with the edit's footprint).  Returns 0
 * or -1 (out of memory). */
#define ST_RGEOM_RANGE_GAP 16
int st_rgeom_refresh(st_rgeom *g, const st_map *m, const uint32_t *vids, uint32_t n,
                     st_range_list *vdirty, st_range_list *fdirty);

/* After a local change of the map's topology (an interest-box update of an
 * adaptive hierarchy), recorded in `log` (map.h: st_map_log, the darts and
 * vertices the change touched): re-tessellates only the faces that changed
 * - the old ones holding a logged dart are removed, the current faces of
 * level g->level holding a logged dart (or its β0) are added - and
 * refreshes the positions and normals around them.  The ranges to upload
 * again are appended to the lists (any may be NULL).  Returns 0, -1 (out of
 * memory or an overflowed log: build again) or 1 (more removed faces than
 * live ones: build again, to compact).  The result draws the same
 * triangles and polygon edges (as vertex ids) as st_rgeom_build would. */
/* Whether vertex index s is a corner of a drawn face (after patches, the
 * table may hold vertices no face uses any more). */
int st_rgeom_vertex_drawn(const st_rgeom *g, const st_map *m, uint32_t s);

typedef struct st_rgeom_dirty { st_range_list verts, faces, tris, lines; } st_rgeom_dirty;
int st_rgeom_patch(st_rgeom *g, const st_map *m, const st_map_log *log, st_rgeom_dirty *dirty);
void st_rgeom_dirty_free(st_rgeom_dirty *d);
/* Distinct darts in the log (-1: overflowed, or out of memory): how large a
 * change is, to choose between st_rgeom_patch and a build. */
int64_t st_rgeom_log_darts(st_rgeom *g, const st_map *m, const st_map_log *log);

/* Re-reads every position and recomputes every normal (topology kept). */
void st_rgeom_refresh_all(st_rgeom *g, const st_map *m);

/* Face-varying texture coordinates per triangle corner: out[6 t + 2 j],
 * out[6 t + 2 j + 1] is the UV of corner j of triangle t, read from uv (2
 * doubles per dart id of g's map level, core/fvar/fvar.h: st_hier_uv) at
 * the dart of that corner's face.  Per corner, not per vertex: a vertex on
 * a UV seam has one UV in each face.  Removed faces get (0, 0). */
void st_rgeom_corner_uvs(const st_rgeom *g, const st_map *m, const st_uv_map *uv, float *out);

void st_range_list_free(st_range_list *l);

#endif
