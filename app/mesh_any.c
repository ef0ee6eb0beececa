/* Extension dispatch between the glTF reader/writer (C++, app/gltf_io.cc)
 * and core's mesh files; core cannot call glTF itself (it is C only). */
#include "mesh_any.h"

#include <string.h>

#if defined(STRATA_GLTF_BUILT)
#include "gltf_io.h"
#endif

static int is_gltf(const char *path)
{
    return st_path_has_ext(path, ".gltf") || st_path_has_ext(path, ".glb");
}

int st_any_mesh_load(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err)
{
    if (!is_gltf(path)) return st_mesh_load_flags(path, out, flags, notes, err);
#if defined(STRATA_GLTF_BUILT)
    return st_gltf_load_notes(path, out, flags, notes, err);
#else
    return st_fail(err, ST_ERR_PARSE, "%s: glTF support was not built (needs libtinygltf-dev)", path);
#endif
}

int st_any_mesh_save(const char *path, const st_mesh *m, st_error *err)
{
    if (!is_gltf(path)) return st_mesh_save(path, m, err);
#if defined(STRATA_GLTF_BUILT)
    return st_gltf_save(path, m, err);
#else
    return st_fail(err, ST_ERR_PARSE, "%s: glTF support was not built (needs libtinygltf-dev)", path);
#endif
}
