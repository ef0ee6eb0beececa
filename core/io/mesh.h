/* Mesh files: st_mesh (core/base/mesh.h), a polygon soup, read from and
 * written to OBJ, OFF and PLY.
 *
 * Loaders fill it, the repair/check pass makes it a consistently oriented
 * 2-manifold (or refuses it with a message), st_map_from_mesh() builds the
 * level-0 map from it, and st_map_to_mesh() extracts any level back into it
 * for the writers.
 */
#ifndef ST_MESH_H
#define ST_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "core/base/mesh.h"
#include "core/base/st_error.h"

/* Whether path ends in ext (".obj", ...), ignoring ASCII case: the one
 * extension test every loader, writer and command uses. */
int st_path_has_ext(const char *path, const char *ext);

/* Loaders: read, parse, then st_mesh_repair().  On failure *out is
 * untouched and err names file:line: problem (binary PLY: "file: byte N:");
 * on success *out's previous content is freed and replaced.
 * Format chosen by extension (.obj .off .ply), case-insensitive.
 * OBJ face indices count from 1 (negative: relative); OFF and PLY from 0;
 * OBJ `t` tag indices from 0 (OpenSubdiv).  Messages number vertices as
 * the file does. */
int st_mesh_load(const char *path, st_mesh *out, st_error *err);
int st_mesh_load_obj(const char *path, st_mesh *out, st_error *err);
int st_mesh_load_off(const char *path, st_mesh *out, st_error *err);
int st_mesh_load_ply(const char *path, st_mesh *out, st_error *err);
/* In-memory variants (fuzzers); name is used in messages.  They parse and
 * reject malformed records (bad numbers, indices out of range, faces of < 3
 * or repeated vertices, non-finite coordinates, lying counts) but do not
 * repair: call st_mesh_repair() next. */
int st_mesh_parse_obj(const char *name, const char *data, size_t size, st_mesh *out, st_error *err);
int st_mesh_parse_off(const char *name, const char *data, size_t size, st_mesh *out, st_error *err);
int st_mesh_parse_ply(const char *name, const char *data, size_t size, st_mesh *out, st_error *err);

/* Length of the diagonal of the vertices' bounding box (0 for no vertex):
 * the scale of a mesh's tolerances. */
double st_mesh_diagonal(const st_mesh *m);

/* Area-weighted smooth unit vertex normals (core/io/mesh_normals.c): into
 * n (3 * m->nverts doubles), or into m->normals (replaced).  -1 when out of
 * memory.  The one normal computation of every writer, glTF's included. */
int st_mesh_vertex_normals(const st_mesh *m, double *n);
int st_mesh_compute_normals(st_mesh *m);

/* Writers: by extension (.obj .ply); PLY written binary little-endian. */
int st_mesh_save(const char *path, const st_mesh *m, st_error *err);
int st_mesh_save_obj(const char *path, const st_mesh *m, st_error *err);
int st_mesh_save_ply(const char *path, const st_mesh *m, st_error *err);

/* Topological check and repair, run by st_mesh_load() after parsing.
 * Makes the soup an oriented 2-manifold (possibly with boundary) or fails.
 * Repairs it performs are appended to *notes (one line each, may be NULL).
 * Repaired: edges with 3+ faces (two faces keep the edge, every further
 * face gets its own copies of its two vertices, as OpenMesh's importer
 * detaches such faces), inconsistent winding (faces flipped), bow-tie
 * vertices (one copy per fan), unreferenced vertices (dropped; tags follow
 * their vertices).  Faces keep their order and count; a flipped face's UV
 * indices are flipped with its vertices, so face_uv stays parallel to
 * face_idx.
 * Refused: non-orientable surfaces, degenerate faces, and with
 * ST_MESH_STRICT edges with 3+ faces (as before the split existed).
 * On failure m is unchanged.  See core/io/mesh_repair.c for the rules. */
int st_mesh_repair(const char *name, st_mesh *m, st_notes *notes, st_error *err);
/* Flags of the _flags variants (0: st_mesh_repair's behaviour).
 * ST_MESH_STRICT refuses an edge with 3+ faces ("non-manifold edge between
 * vertices A and B: N faces share it (lines ...)") instead of splitting it:
 * the commands' --strict. */
#define ST_MESH_STRICT 1u
int st_mesh_repair_flags(const char *name, st_mesh *m, unsigned flags, st_notes *notes, st_error *err);

/* st_mesh_load() that also returns the repair notes ("file: repaired: ...",
 * one per line; notes may be NULL).  st_mesh_load() drops them. */
int st_mesh_load_notes(const char *path, st_mesh *out, st_notes *notes, st_error *err);
/* st_mesh_load_notes() with repair flags (ST_MESH_STRICT). */
int st_mesh_load_flags(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err);

/* Checks what st_mesh_repair() promises, without changing m: indices in
 * range, faces of 3+ distinct vertices, finite positions, every vertex used,
 * every undirected edge used by 1 or 2 faces (in opposite directions when 2),
 * every vertex's faces one fan, tags on existing vertices and edges, UV
 * indices in range and UV values finite.
 * Returns 0 or fills err (ST_ERR_INVALID / ST_ERR_TOPOLOGY). */
int st_mesh_check(const char *name, const st_mesh *m, st_error *err);

/* ---- For loaders outside core (the glTF reader in formats/gltf_io.cc). */

/* Where each face of a parsed mesh came from (core/io/mesh_internal.h). */
typedef struct st_mesh_src st_mesh_src;
/* The end of every loader: repairs the freshly parsed mesh (src may be
 * NULL; flags as st_mesh_repair_flags), then moves it into *out and appends
 * the repair notes to *notes (may be NULL).  On failure *out and *notes are
 * untouched; *parsed is freed either way. */
int st_mesh_finish_load(const char *name, st_mesh *parsed, const st_mesh_src *src, unsigned flags,
                        st_mesh *out, st_notes *notes, st_error *err);

#endif
