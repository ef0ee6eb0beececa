/* What an operation on a hierarchy will cost, from counts alone: the memory
 * guard (core/base/membudget.h) asks these before allocating.
 *
 * The cell counts of a new level follow from the previous level's by the
 * scheme's refinement, exactly (Euler's relation on each split):
 *   polygon split (Catmull-Clark):  V' = V + E + F,  E' = 2E + Σdeg,  F' = Σdeg
 *   triangle quadrisection (Loop, Butterfly):  V' = V + E,  E' = 2E + 3F,  F' = 4F
 *   quad/triangle (T triangles):  V' = V + E + F - T,  E' = 2E + Σdeg,  F' = T + Σdeg
 *   √3:  V' = V + F + B',  E' = E + 3F + B',  F' = 3F,  B' = B on even levels
 *        (boundary edges trisected, no centre in their triangles), else 0
 *   Doo-Sabin (surface cells, B boundary edges):  V' = 2E + B,  E' = 4E + B,  F' = F + E + V
 * and darts are 2E'.  Bytes come from the map's measured costs per dart and
 * per vertex of a level (topology: relations, vertex ids, insertion levels
 * and columns; positions: a new point per vertex of the level), and a factor
 * for what the passes keep besides the map (synthesis tables, scratch),
 * measured on the shared meshes and tested against the peak resident size
 * (tests/core/test_membudget.c). */
#ifndef ST_ESTIMATE_H
#define ST_ESTIMATE_H

#include <stddef.h>

#include "core/multires/hier.h"

/* Cell counts of level next_level from those of the level below under the scheme.
 * *triangles: the number of triangles of level l, read by quad/triangle
 * only (st_level_triangles), and updated to level l+1's. */
void st_estimate_next_level(st_scheme_id scheme, unsigned next_level, const st_level_stats *l, uint64_t *triangles,
                            st_level_stats *next);
/* Faces of level l with three sides. */
uint64_t st_level_triangles(const st_map *m, unsigned l);

/* Bytes that st_hier_subdivide_to(h, levels) will add to the process at its
 * peak (0 when levels <= top); `finest` (may be NULL) gets the predicted
 * counts of level `levels`. */
size_t st_hier_estimate_subdivide(st_hier *h, unsigned levels, st_level_stats *finest);

/* Bytes of the position columns that a synthesis of levels from+1..top
 * creates, on the levels that have none yet: a vertex of a coarser level
 * that moves there gets the level a column (map.h, "Storage"), as long as
 * the ids of the levels below.  A progressive hierarchy as rebuilt keeps
 * its vertices' input positions at every level but 0, so has no column to
 * begin with besides level 1's over level 0's ids (progressive.h, point 8). */
size_t st_estimate_position_columns(const st_map *m, unsigned from);

/* Bytes a synthesis of the levels above `from` (a full one, or a local
 * edit's at level `from`, which may write any of them) adds to the
 * process: the scheme's own estimate where it builds caches for it
 * (st_scheme.synth_estimate), else the position columns. */
size_t st_hier_synth_estimate(const st_hier *h, unsigned from);

/* Bytes of an exported soup of nverts vertices and ncorners corners in
 * nfaces faces (positions, normals, indices, the writer's buffers). */
size_t st_estimate_mesh_bytes(uint64_t nverts, uint64_t nfaces, uint64_t ncorners);

#endif
