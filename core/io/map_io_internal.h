/* Binary (de)serialization of an st_map and its multilevel attributes, for
 * session files (core/io/session.h, docs/SESSION-FORMAT.md).
 *
 * The map is written as it is in memory: both id pools (insertion levels,
 * per-level block lists, fill pointers, free lists, spare blocks) and every
 * st_mla (base values and per-level columns), so that a loaded map has the
 * same dart and vertex ids, the same columns and the same free lists as the
 * one saved: every later operation (refinement, adaptive updates, frames,
 * which depend on dart ids) behaves exactly as it would have on the
 * original.  Entries nothing can read (values of free ids, column slots of
 * ids inserted at or above the column's level, capacity beyond the last id)
 * are written as zeros, so equal maps give equal bytes.  (A map can also
 * be written under a renumbering of its ids, st_map_write_renumbered: the
 * same format, the ids then those of core/map/renumber_internal.h.)
 *
 * Everything is little-endian.  Readers are bounded: every count is checked
 * against the bytes that remain before anything is allocated, and a map
 * that is read back is checked (pool consistency, relation ranges at every
 * level, finite positions, then st_map_validate) before it is returned. */
#ifndef ST_MAP_IO_H
#define ST_MAP_IO_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include <stdint.h>
#include <stdio.h>

#include "core/map/map.h"
#include "core/map/renumber_internal.h"

/* ---- byte writer: to a FILE, to memory, or counting only ----------------- */
typedef struct st_bw {
    FILE *f;                   /* file mode when not NULL */
    int mem;                   /* memory mode: appends to out/outlen */
    unsigned char *out;
    size_t outlen, outcap;
    uint64_t total;            /* bytes written so far (all modes) */
    struct XXH3_state_s *xxh;  /* file and memory modes: the running checksum (st_bw_checksum) */
    int failed;                /* a write or an allocation failed */
    /* A value its reader would refuse was written: a non-finite number
     * through st_bw_f32/st_bw_f64, or a value failing st_mla_write's check.
     * Set in every mode; the session writer measures its chunks in count
     * mode first and refuses the save when this is set, so that it never
     * writes a file it would not read back. */
    int refused_value;
    long slow_us;              /* test hook: sleep per flushed buffer (file mode) */
    /* File mode: called after each flushed buffer with total / progress_total;
     * a non-zero return stops the writing (failed and cancelled set). */
    int (*progress)(void *ctx, double fraction);
    void *progress_ctx;
    uint64_t progress_total;
    int cancelled;
    size_t n;                  /* bytes in buf */
    unsigned char buf[1 << 16];
} st_bw;

/* Counting writer: nothing stored or hashed, only total advances. */
void st_bw_init_count(st_bw *w);
/* File and memory writers hash what they write; -1 (and w->failed) when
 * the checksum's state cannot be allocated.  st_bw_free releases it. */
int st_bw_init_file(st_bw *w, FILE *f);
int st_bw_init_mem(st_bw *w);
void st_bw_free(st_bw *w);
/* The checksum of everything written and flushed so far: the low 32 bits
 * of XXH3-64 (the session trailer of version 4, st_session_checksum). */
uint32_t st_bw_checksum(const st_bw *w);
/* Flushes buf (CRC, then file or memory).  Returns -1 once anything failed. */
int st_bw_flush(st_bw *w);
void st_bw_bytes(st_bw *w, const void *p, size_t n);
void st_bw_u8(st_bw *w, uint8_t v);
void st_bw_u32(st_bw *w, uint32_t v);
void st_bw_u64(st_bw *w, uint64_t v);
void st_bw_f32(st_bw *w, float v);
void st_bw_f64(st_bw *w, double v);

/* CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320), as zlib's crc32():
 * st_crc32(0, p, n) is the CRC of n bytes; chains across calls.  The
 * session header's checksum, and the whole file's up to version 3. */
uint32_t st_crc32(uint32_t crc, const void *p, size_t n);
/* The trailer checksum of a session file of n bytes (trailer included:
 * the bytes before the last 4), by its version (bytes 8..11): CRC-32 up to
 * version 3, the low 32 bits of XXH3-64 from version 4 (a tenth of
 * CRC-32's time). */
uint32_t st_session_checksum(const void *p, size_t n);

/* ---- bounded reader over a buffer ----------------------------------------- */
typedef struct st_br {
    const unsigned char *p;
    size_t size, off;
    const char *name;          /* file name for messages */
    st_error *err;
    int failed;                /* first failure recorded in err */
    /* Session format 3 and later: attribute arrays stop at the last live id
     * and columns at the last id inserted below their level (the rest are
     * zeros, not stored).  Set by the session reader from the version. */
    int trimmed;
} st_br;

void st_br_init(st_br *r, const char *name, const void *p, size_t size, st_error *err);
/* Records "name: byte OFF: what" (first failure only) and returns -1. */
int st_br_fail(st_br *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* 0 when count elements of elem bytes remain, else fails naming `what`. */
int st_br_need(st_br *r, uint64_t count, uint64_t elem, const char *what);
uint8_t st_br_u8(st_br *r);
uint32_t st_br_u32(st_br *r);
uint64_t st_br_u64(st_br *r);
float st_br_f32(st_br *r);
double st_br_f64(st_br *r);
/* Reads n bytes into out (zeros on failure). */
void st_br_bytes(st_br *r, void *out, size_t n);

/* ---- map and attributes ----------------------------------------------------- */
/* Writes the map (pools, β0, β1, vertex, flags, positions; not the attached
 * attributes, which their owner writes with st_mla_write). */
void st_map_write(st_bw *w, const st_map *m);
/* The same map under a renumbering of its ids (core/map/renumber_internal.h): the
 * renumbered pools, every value in the new ids' order and every relation
 * value translated, so that the bytes are those of the map the
 * renumbering describes (st_map_read gives it back; its ids are then the
 * new ones).  Reads m only. */
void st_map_write_renumbered(st_bw *w, const st_map *m, const st_map_renumber *rn);
/* Reads a map into m (initialised here; freed again on failure).  Checks
 * pools, relation ranges and positions; does not run st_map_validate (the
 * caller does, once the attributes are attached).  0 or -1 with r->err set. */
int st_map_read(st_br *r, st_map *m);

/* One multilevel attribute over pool p (darts or vertices of m); values of
 * readable entries failing check (NULL: any) set w->refused_value, the
 * check st_mla_read applies to them. */
typedef int (*st_mla_value_check)(const void *value);
void st_mla_write(st_bw *w, const st_mla *a, const st_pool *p, st_mla_value_check check);
/* The same under the renumbering r of p (an attribute of values, not of
 * ids: nothing translated). */
void st_mla_write_renumbered(st_bw *w, const st_mla *a, const st_pool *p, const st_pool_renumber *r,
                             st_mla_value_check check);
/* Reads an attribute of elem bytes per element over pool p of a map of top
 * level `top`; values of readable entries must pass check (NULL: any); the
 * result has the pool's capacity, ready to be attached. */
int st_mla_read(st_br *r, st_mla *a, const st_pool *p, unsigned top, uint32_t elem,
                st_mla_value_check check, const char *what);

/* Level 0 of m as a map of its own, for writing (st_map_write, then
 * st_mla_write of the attributes over its pools): m as level 0 left it,
 * its pools ending at end[0] (darts) and end[1] (vertices), no column.  A
 * view sharing m's arrays, valid while m is unchanged.  -1 when m's pools
 * are not in the state a regeneration of levels 1..top from level 0 would
 * start from (st_hier_regenerable, core/multires/hier.h), or it is sparse. */
int st_map_level0_view(const st_map *m, const uint32_t end[2], st_map *v);
/* An attribute's level-0 values (base values, no column), as a view. */
st_mla st_mla_level0_view(const st_mla *a);

/* Value checks for st_mla_read and st_mla_write. */
int st_value_finite_f64x3(const void *v);
int st_value_sharpness_f32(const void *v);

#endif
