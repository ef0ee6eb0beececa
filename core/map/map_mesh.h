/* Conversion between polygon soups (mesh.h) and the multiresolution map. */
#ifndef ST_MAP_MESH_H
#define ST_MAP_MESH_H

#include "core/map/map.h"
#include "core/base/mesh.h"

/* Builds level 0 of an empty map from a manifold, consistently oriented soup
 * (st_mesh_repair's output).  Holes become boundary faces.  Fails with a
 * message (and leaves m empty) on a soup that is not such a surface. */
int st_map_from_mesh(st_map *m, const st_mesh *mesh, st_error *err);
/* Extracts the real (non-boundary) faces of level l; vertices are numbered
 * in the order of their ids; out is replaced on success. */
int st_map_to_mesh(st_map *m, unsigned l, st_mesh *out, st_error *err);

#endif
