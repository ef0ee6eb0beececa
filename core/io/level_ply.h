/* A level of a hierarchy written as binary PLY straight from the map.
 *
 * The same bytes as st_hier_level_mesh followed by st_mesh_save_ply
 * (core/io/mesh_write.c), without the intermediate soup, its UV soup and
 * the copy split along UV seams: what `strata subdivide -o X.ply` writes
 * after the finest level's synthesis, when the whole hierarchy is still in
 * memory.  Vertices in level order; with UVs, one PLY vertex per vertex and
 * face-varying value, in the order of (vertex, value label); hole faces are
 * not written.  Dual maps (Doo-Sabin, √3) go through the soup. */
#ifndef ST_LEVEL_PLY_H
#define ST_LEVEL_PLY_H

#include "core/multires/hier.h"

int st_hier_level_save_ply(st_hier *h, unsigned l, const char *path, st_error *err);
/* The same as OBJ text: the bytes of st_hier_level_mesh followed by
 * st_mesh_save_obj (vertices, one `vt` per vertex and value, `f` lines). */
int st_hier_level_save_obj(st_hier *h, unsigned l, const char *path, st_error *err);

/* The same file through the soup (st_hier_level_mesh, st_mesh_save_ply): the
 * dual maps' path, and the reference tests/core/test_level_ply.c compares the
 * direct path with. */
int st_hier_level_save_ply_soup(st_hier *h, unsigned l, const char *path, st_error *err);
int st_hier_level_save_obj_soup(st_hier *h, unsigned l, const char *path, st_error *err);

#endif
