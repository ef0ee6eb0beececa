/* glTF 2.0 import and export (.gltf + .bin, .glb) through tinygltf, behind a
 * C API: formats/gltf_io.cc is the one C++ translation unit that compiles
 * tinygltf.  core stays C and knows nothing of it; formats/mesh_any.c picks this
 * reader/writer or core's by extension.
 *
 * Export (st_gltf_save, st_gltf_write_mem): one mesh, one primitive of
 * triangles, POSITION (float, with min/max) + NORMAL + indices (u16, or u32
 * from 65535 vertices on), and TEXCOORD_0 (float; v flipped: glTF's v runs
 * down the image, OBJ's up) when the mesh has UVs: vertices are then split
 * along UV seams (one glTF vertex per vertex and UV index; normals are the
 * unsplit mesh's, smooth across seams).  glTF has only triangles: each polygon is fanned
 * from its first vertex (exact for convex polygons, which is what the
 * schemes produce).  Normals are m->normals, normalised, where given with
 * a length; elsewhere core's smooth area-weighted ones (st_mesh_vertex_normals:
 * a vertex whose faces cancel out takes its first face's normal, then
 * (0,0,1)), as the OBJ and PLY writers have them.  .gltf writes NAME.bin next to it (buffer uri NAME.bin); .glb
 * embeds the buffer.  Files are written to NAME.tmp, then renamed.
 *
 * Import (st_gltf_load, st_gltf_parse): every triangle primitive of every
 * mesh placed in the default scene (scene 0 when none is marked), with node
 * transforms applied (matrix, or translation * rotation * scale; a mirroring
 * transform flips the winding as glTF says).  A file without scenes: every
 * mesh, untransformed.  Modes: TRIANGLES; TRIANGLE_STRIP and TRIANGLE_FAN
 * are converted to triangles; POINTS and LINES* are refused.  Index types
 * u8/u16/u32 and non-indexed primitives.  glTF duplicates vertices (per
 * primitive, and for seams of normals/UVs): vertices with exactly the same
 * transformed position are welded into one so that the result is a connected
 * 2-manifold the schemes can subdivide; triangles that become degenerate
 * (two corners on one vertex) are dropped.  POSITION and TEXCOORD_0 (float
 * VEC2, when every primitive has it; v flipped back) are read: corners of a
 * welded vertex with different UVs are on a UV seam, with equal UVs share
 * one texture coordinate; quads
 * stored as triangle pairs come back as triangles (glTF keeps no polygons).
 * Refused with "file: problem": tinygltf's own errors, accessors or buffer
 * views beyond their buffer, indices out of range, non-finite positions,
 * sparse accessors, accessors without a buffer view, unsupported required
 * extensions, node hierarchies that are not trees, JSON nested deeper than
 * 256 levels.  On failure *out is untouched.
 */
#ifndef ST_GLTF_IO_H
#define ST_GLTF_IO_H

#include <stddef.h>

/* core's headers are C without extern "C" guards: wrap them here. */
#ifdef __cplusplus
extern "C" {
#endif

#include "core/io/mesh.h"
#include "core/multires/hier.h"

/* Reads path (.gltf with external or data: buffers, or .glb: chosen by the
 * file's magic, not its name), then st_mesh_repair() like core's loaders.
 * The _notes variant takes the repair flags (ST_MESH_STRICT) and also
 * returns the repair notes (may be NULL). */
int st_gltf_load(const char *path, st_mesh *out, st_error *err);
int st_gltf_load_notes(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err);

/* Parses glTF from memory (GLB when it starts with "glTF", else JSON) without
 * repairing (call st_mesh_repair next), for fuzzers and tests.  name is used
 * in messages.  Buffers must be embedded (GLB BIN chunk or data: URIs): an
 * external file URI is refused, nothing is read from disk. */
int st_gltf_parse(const char *name, const void *data, size_t size, st_mesh *out, st_error *err);

/* Writes m by extension: .glb binary, .gltf JSON + .bin (case-insensitive). */
int st_gltf_save(const char *path, const st_mesh *m, st_error *err);

/* A normal-mapped export (strata convert --normal-map): per face corner of
 * m, in the order of m->face_idx, the UV (2, OBJ convention: v up), the
 * tangent (4: unit xyz and the bitangent sign w = ±1) and the normal (3, unit)
 * the map was baked with (st_bake_tangents), and the PNG of the map. */
typedef struct st_gltf_material {
    const double *corner_uv;
    const double *corner_tangent;
    const double *corner_normal;
    const char *normal_map;
} st_gltf_material;

/* Writes m like st_gltf_save with TEXCOORD_0, TANGENT and NORMAL from mat,
 * vertices split wherever two corners of a vertex differ in any of them,
 * and a material whose normalTexture is mat->normal_map: embedded in a .glb
 * (bufferView, image/png), referenced by a relative URI from a .gltf (the
 * PNG is not copied).  m's own UVs and normals are not used.
 *
 * UDIM: a normal_map with a literal <UDIM> (NAME.<UDIM>.png, strata bake's
 * tiles) gives one primitive per UV tile that the faces are at home in
 * (core/bake/bake.h: st_bake_face_tile), in UDIM order, all sharing the
 * vertex accessors; each has its own material whose normalTexture is the
 * tile's PNG (NAME.1001.png ...), and each face's UVs are moved by its home
 * tile into [0,1] (an overshoot stays outside and is read with repeat, as
 * the bake wrapped it).  A face in a tile without a UDIM number, or a
 * missing tile image, is refused. */
int st_gltf_save_mapped(const char *path, const st_mesh *m, const st_gltf_material *mat, st_error *err);

/* Level l of h, as the mesh m (st_hier_level_mesh), written by
 * st_gltf_save_mapped with the layout and tangents strata bake used: l's
 * own UVs, or when auto_uv or when l has none the atlas of
 * st_bake_chart_uvs for a map of atlas_size texels with atlas_padding (what
 * the bake used: strata convert --normal-map passes the map's width and
 * bake's default padding, the window its last bake's). */
int st_gltf_save_level_mapped(const char *path, st_hier *h, unsigned l, const st_mesh *m, int auto_uv, uint32_t atlas_size,
                              uint32_t atlas_padding, const char *normal_map, st_error *err);

/* Writes m to memory: binary != 0 gives a GLB, else JSON with the buffer as
 * a data: URI.  index_bytes: 0 picks u16/u32 as st_gltf_save does; 1, 2 or 4
 * force u8/u16/u32 indices (refused when a vertex index does not fit; a u8
 * index may not be 255, glTF's primitive restart value).  *data is malloc'd:
 * free() it. */
int st_gltf_write_mem(const st_mesh *m, int binary, int index_bytes, void **data, size_t *size,
                      st_error *err);

/* 1 when path ends in .gltf or .glb (case-insensitive). */
int st_gltf_is_gltf_path(const char *path);

#ifdef __cplusplus
}
#endif

#endif
