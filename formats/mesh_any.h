/* Mesh files of every format the app knows: glTF (.gltf, .glb) through
 * formats/gltf_io.h, everything else through core's st_mesh_load/st_mesh_save
 * (.obj .off .ply).  Same contract as core's loaders: repaired on load,
 * notes returned, *out untouched on failure, err "file: problem"; flags as
 * st_mesh_repair_flags (ST_MESH_STRICT: --strict). */
#ifndef ST_MESH_ANY_H
#define ST_MESH_ANY_H

#include "core/io/mesh.h"

int st_any_mesh_load(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err);
int st_any_mesh_save(const char *path, const st_mesh *m, st_error *err);

#endif
