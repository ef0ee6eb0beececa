/* Extension dispatch between the glTF reader/writer (C++, app/gltf_io.cc)
 * and core's mesh files; core cannot call glTF itself (it is C only). */
#include "mesh_any.h"

#include <string.h>

#if defined(STRATA_GLTF_BUILT)
#include "gltf_io.h"
#endif

static int is_gltf(const char *path)
{
    static const char *const ext[] = { ".gltf", ".glb" };
    size_t n = strlen(path);
    for (size_t e = 0; e < sizeof ext / sizeof ext[0]; e++) {
        size_t k = strlen(ext[e]);
        if (n < k) continue;
        int same = 1;
        for (size_t i = 0; i < k && same; i++) {
            char c = path[n - k + i];
            if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
            same = c == ext[e][i];
        }
        if (same) return 1;
    }
    return 0;
}

int st_any_mesh_load(const char *path, st_mesh *out, st_notes *notes, st_error *err)
{
    if (!is_gltf(path)) return st_mesh_load_notes(path, out, notes, err);
#if defined(STRATA_GLTF_BUILT)
    return st_gltf_load_notes(path, out, notes, err);
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
