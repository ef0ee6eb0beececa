/* Extension dispatch between the glTF reader/writer (C++, formats/gltf_io.cc)
 * and core's mesh files; core cannot call glTF itself (it is C only). */
#include "mesh_any.h"

#include <string.h>

#include "gltf_io.h"

int st_any_mesh_load(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err)
{
    if (!st_gltf_is_gltf_path(path)) return st_mesh_load_flags(path, out, flags, notes, err);
    return st_gltf_load_notes(path, out, flags, notes, err);
}

int st_any_mesh_save(const char *path, const st_mesh *m, st_error *err)
{
    if (!st_gltf_is_gltf_path(path)) return st_mesh_save(path, m, err);
    return st_gltf_save(path, m, err);
}
