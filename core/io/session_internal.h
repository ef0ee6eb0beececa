/* What the session reader (session_read.c), writer (session_write.c) and
 * lifetime (session.c) share: the layout's constants and tags
 * (docs/SESSION-FORMAT.md). */
#ifndef ST_SESSION_INTERNAL_H
#define ST_SESSION_INTERNAL_H
#ifndef STRATA_CORE_INTERNAL
#error "internal to core: render/, ui/ and app/ use core's public headers (docs/ARCHITECTURE.md)"
#endif

#include "core/io/session.h"

#define HEADER_BYTES 28u
#define TRAILER_BYTES 4u
#define CHUNK_HEAD 12u

#define TAG(a, b, c, d) ((uint32_t)(a) | (uint32_t)(b) << 8 | (uint32_t)(c) << 16 | (uint32_t)(d) << 24)
#define TAG_HIER TAG('H', 'I', 'E', 'R')
#define TAG_MAP  TAG('M', 'A', 'P', ' ')
#define TAG_SHRP TAG('S', 'H', 'R', 'P')
#define TAG_DETL TAG('D', 'E', 'T', 'L')
#define TAG_ADPT TAG('A', 'D', 'P', 'T')
#define TAG_EDIT TAG('E', 'D', 'I', 'T')
#define TAG_VIEW TAG('V', 'I', 'E', 'W')
#define TAG_BASE TAG('B', 'A', 'S', 'E')
#define TAG_MASK TAG('m', 'a', 's', 'k')
#define TAG_TOOL TAG('t', 'o', 'o', 'l')
#define TAG_LAYR TAG('l', 'a', 'y', 'r')
/* The same payload as layr when a layer is on level 0, which versions
 * before level-0 layers refuse in layr: under this tag they skip it as an
 * unknown ancillary chunk and get the surface with the layers composed. */
#define TAG_LAY0 TAG('l', 'a', 'y', '0')
/* The HD hierarchy (session.h, st_session.hd): u32 hd_from, then a whole
 * nested session image of it, written and read by this writer and reader. */
#define TAG_HDLV TAG('h', 'd', 'l', 'v')
#define TAG_FVAR TAG('F', 'V', 'A', 'R')
#define TAG_BUVS TAG('B', 'U', 'V', 'S')
/* Version 4, a hierarchy whose levels 1..top are the scheme's refinement
 * of level 0 (st_hier_regenerable): LVL0 holds level 0 as a map of its own
 * and the number of levels, POSN the positions of every level, read once
 * the reader has regenerated the levels; they replace MAP. */
#define TAG_LVL0 TAG('L', 'V', 'L', '0')
#define TAG_POSN TAG('P', 'O', 'S', 'N')
/* Version 5, a progressive hierarchy as its build left it
 * (st_progressive_recipe, core/progressive/progressive.h): level 0's darts
 * and the vertex splits of every level, replayed by the reader; then POSN
 * as after LVL0.  It replaces MAP. */
#define TAG_PMRC TAG('P', 'M', 'R', 'C')

/* Version 2 added the UV chunks (FVAR, BUVS); version 3 trims the map's
 * attribute arrays (map_io_internal.h, st_br.trimmed); version 4 adds
 * LVL0 and POSN; version 5 adds PMRC, and is what every session is
 * written as. */
#define SESSION_VERSION_UV 2u
#define SESSION_VERSION_TRIMMED 3u
#define SESSION_VERSION_RECIPE 4u
#define SESSION_VERSION_PMRC 5u

/* Moves src into dst without freeing dst, whose content is garbage or
 * already freed (session.c). */
void st_session_move_raw(st_session *dst, st_session *src);
/* Why a tool chunk cannot be written or read, or NULL (session_read.c). */
const char *st_session_tool_refusal(const st_session_tool *t);

#endif
