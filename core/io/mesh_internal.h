/* Plumbing shared by the mesh readers (core/io/mesh_obj.c, mesh_off.c,
 * mesh_ply.c) and the repair pass (mesh_repair.c): face locations for
 * messages, number and token parsers, quoting, failures naming file and line.
 * Tests and fuzzers reach it too; render/, ui/ and app/ use core/io/mesh.h. */
#ifndef ST_MESH_INTERNAL_H
#define ST_MESH_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include <stddef.h>
#include <stdint.h>

#include "core/io/mesh.h"

/* Where each face came from, so that problems found after parsing (by the
 * repair pass) can still name a line or byte offset. */
struct st_mesh_src {
    uint64_t *face_loc;     /* nfaces entries: line (text) or byte offset (binary) */
    int binary;             /* 1: face_loc holds byte offsets, 0: line numbers */
    int index_base;         /* how the file numbers vertices: 1 (OBJ) or 0 */
};
void st_mesh_src_free(st_mesh_src *src);

/* The parse_* functions with face locations (src may be NULL). */
int st_mesh_parse_obj_src(const char *name, const char *data, size_t size,
                          st_mesh *out, st_mesh_src *src, st_error *err);
int st_mesh_parse_off_src(const char *name, const char *data, size_t size,
                          st_mesh *out, st_mesh_src *src, st_error *err);
int st_mesh_parse_ply_src(const char *name, const char *data, size_t size,
                          st_mesh *out, st_mesh_src *src, st_error *err);
/* st_mesh_repair_flags() naming lines/offsets from src (may be NULL). */
int st_mesh_repair_src(const char *name, st_mesh *m, const st_mesh_src *src, unsigned flags,
                       st_notes *notes, st_error *err);

/* A vertex that occurs twice in idx[0..n), or UINT32_MAX when all differ.
 * scratch holds n entries (used for long faces, sorted there: O(n log n)). */
uint32_t st_mesh_face_repeat(const uint32_t *idx, uint32_t n, uint32_t *scratch);
/* Whole-token number parsers for text formats (C syntax, '.' decimal point):
 * 0 on success, -1 if [s, s+len) is not entirely one number. */
int st_mesh_parse_double(const char *s, size_t len, double *out);
int st_mesh_parse_int(const char *s, size_t len, int64_t *out);
/* Text readers (OBJ, OFF): blanks are space, tab, CR, VT, FF.  Next token of
 * the line [*q, le): skips blanks; 0 at the line's end or at a '#' comment;
 * a '#' also ends a token. */
int st_text_is_blank(char c);
int st_text_token(const char **q, const char *le, const char **tok, size_t *len);
/* A token quoted for a message into buf (size bytes, at least 1): cut to
 * size - 1 characters, anything but printable ASCII shown as '?', so that
 * binary junk stays short and harmless on a terminal.  Returns buf. */
const char *st_text_quote(char *buf, size_t size, const char *tok, size_t len);
/* Fails with "name:LOC: problem" (LOC a line number) or, for binary files,
 * "name: byte LOC: problem"; returns code. */
int st_mesh_fail_at(st_error *err, int code, const char *name, int binary, uint64_t loc,
                    const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;
/* Makes room for need elements of elem bytes in p (capacity *cap), growing
 * geometrically; returns the (new) array, or NULL with p still valid. */
void *st_mesh_grow(void *p, size_t *cap, size_t need, size_t elem);

/* What every reader (OBJ, OFF, PLY) builds: the mesh, where its faces came
 * from, and one face's corners while they are checked. */
typedef struct st_mesh_build {
    st_mesh m;              /* result under construction */
    size_t cap_idx;         /* capacity of m.face_idx */
    uint64_t *face_loc;     /* per face: line (text) or byte offset (binary); OBJ: NULL unless asked */
    uint32_t *tmp;          /* one face's corners (OBJ: or one tag's integers) */
    uint32_t *scratch;      /* for st_mesh_face_repeat, same capacity as tmp */
    size_t cap_tmp;
} st_mesh_build;
/* Room for need values in tmp and scratch: ST_OK, or ST_ERR_MEMORY (the
 * caller words the message). */
int st_mesh_build_reserve(st_mesh_build *b, size_t need);
/* Appends tmp[0..n) as the corners of face f (face_off[f] set already),
 * sets face_off[f + 1] and, when face_loc is kept, face_loc[f] = loc.
 * ST_OK, ST_ERR_RANGE (more than 2^32 corners) or ST_ERR_MEMORY (nothing
 * appended); the caller words the message. */
int st_mesh_build_face(st_mesh_build *b, uint32_t f, uint32_t n, uint64_t loc);
/* Ends a parse that returned rc: when rc is ST_OK, moves the mesh into out
 * and the face locations into src (may be NULL) as binary / index_base
 * describe them; frees the rest either way.  Returns rc. */
int st_mesh_build_end(st_mesh_build *b, int rc, st_mesh *out, st_mesh_src *src, int binary, int index_base);

#endif
