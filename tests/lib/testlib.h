/* Minimal test harness: CHECK records a failure and continues; every test
 * program ends with TEST_END, which prints "N passed, N failed" and returns
 * non-zero on any failure, on no check at all, or (77) on a skipped part. */
#ifndef ST_TESTLIB_H
#define ST_TESTLIB_H

#include <stdio.h>

extern int tl_passed, tl_failed, tl_skipped;

#define CHECK(cond) do { if (cond) tl_passed++; else { tl_failed++; \
    fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); } } while (0)
#define CHECKF(cond, ...) do { if (cond) tl_passed++; else { tl_failed++; \
    fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond); \
    fprintf(stderr, __VA_ARGS__); fputc('\n', stderr); } } while (0)
#define TEST_END() tl_report(__FILE__)

/* A part of the test that cannot run here (its data in ../shared/data or
 * OSMesa is missing): prints "skipped: WHY" and counts it. */
void tl_skip(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;
/* Prints "N passed, N failed" (", N skipped" when some part was skipped)
 * and returns the exit status: 1 on a failure or when nothing was checked
 * at all, else 77 (TL_SKIP_CODE: ctest's SKIP_RETURN_CODE) when a part was
 * skipped, else 0. */
#define TL_SKIP_CODE 77
int tl_report(const char *file);
/* Reads a whole file into a malloc'ed NUL-terminated buffer; NULL on error. */
char *tl_read_file(const char *path, size_t *size);
/* Writes data to path; returns 0 on success. */
int tl_write_file(const char *path, const void *data, size_t size);



/* Literal fixtures (counter-clockwise, outward). */
#include "core/io/mesh.h"
/* Loads the shared test mesh STRATA_SHARED_DATA/SUBDIR/NAME into m
 * (st_mesh_load); when it is missing or unreadable, counts a skip
 * (tl_skip) and returns -1, m left empty. */
int tl_load_shared(const char *subdir, const char *name, st_mesh *m);
void tl_mesh_cube(st_mesh *m);              /* 8 v, 6 quads */
void tl_mesh_tetra(st_mesh *m);             /* 4 v, 4 triangles */
void tl_mesh_octa(st_mesh *m);              /* 6 v, 8 triangles, valence 4 */
void tl_mesh_icosa(st_mesh *m);             /* 12 v, 20 triangles, valence 5 */
void tl_mesh_grid(st_mesh *m, unsigned n);  /* open n x n quad grid in z=0 */
void tl_mesh_torus(st_mesh *m, unsigned nu, unsigned nv); /* closed quad torus */
/* Builds a soup from literal arrays (copied). */
void tl_mesh_make(st_mesh *m, const double *pos, uint32_t nv, const uint32_t *off, const uint32_t *idx, uint32_t nf);
/* Deterministic xorshift generator for randomized tests. */
uint32_t tl_rand(uint64_t *state);
/* Multiresolution checks, for any scheme (tests/lib/testlib.c):
 * builds `levels` levels on the fixture, validates the map. */
#include "core/multires/hier.h"
void tl_init_hier(st_hier *h, void (*make)(st_mesh *), st_scheme_id id, unsigned levels);
/* Random details (uniform in ±scale per component) at every level >= 1. */
void tl_random_details(st_hier *h, uint64_t *rng, double scale);
uint32_t tl_random_dart_at(const st_map *m, unsigned l, uint64_t *rng);
/* Moving vertices at each level: local re-synthesis == full synthesis. */
void tl_check_local_equals_full(st_scheme_id id, void (*make)(st_mesh *), unsigned levels);
/* The same without "far fewer vertices": for a mesh so small that an edit's
 * support can be all of it. */
void tl_check_local_equals_full_small(st_scheme_id id, void (*make)(st_mesh *), unsigned levels);
/* A rigid motion of level 0 moves every level rigidly, details included. */
void tl_check_rigid_motion(st_scheme_id id, void (*make)(st_mesh *), unsigned levels);
/* An edit at level 1 keeps the finest level's details bit for bit. */
void tl_check_details_kept(st_scheme_id id, void (*make)(st_mesh *), unsigned levels);
/* An exact subdivision analyses to zero details; analysis then synthesis
 * gives back the finest level with random details (1e-9). */
void tl_check_analysis(st_scheme_id id, void (*make)(st_mesh *), unsigned levels);
/* Positions of every vertex at every level, indexed [level][vertex id];
 * free p when done. */
typedef struct tl_posnap { unsigned levels; uint32_t n; double *p; } tl_posnap;
void tl_snap_pos(const st_hier *h, tl_posnap *s);
double tl_snap_maxdiff(const tl_posnap *a, const tl_posnap *b);
/* Save -> load -> save in memory: writes r, parses it into *s (named name
 * in messages), writes the loaded session again and checks that the two
 * byte strings are equal.  0 with *s loaded (the caller frees it), or -1
 * after a failed check (*s freed). */
#include "core/io/session.h"
int tl_session_roundtrip(const st_session_ref *r, const char *name, st_session *s);
/* st_session_write_mem's bytes (a failed check when it fails: NULL). */
void *tl_session_bytes(const st_session_ref *r, size_t *n);
/* The same through files: saves r to path, loads it, saves the loaded
 * session to path2 and checks that the two files have the same bytes. */
void tl_session_file_roundtrip(const st_session_ref *r, const char *path, const char *path2);
/* Header size and CRCs of mutated session bytes made right again. */
void tl_session_fix_crc(unsigned char *c, size_t n);

#endif
