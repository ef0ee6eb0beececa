/* The memory budget: every operation that can grow the process by a lot
 * (new levels, adaptive depth, exports, rebuilds, bakes) estimates the bytes
 * it will need from counts it already has, before allocating, and asks
 * st_mem_check() first.  Over the budget it is refused with the estimate and
 * the limit in the message, within the time the estimate takes (counting
 * cells of the current top level), and nothing is written.
 *
 * The budget is process-wide, like the thread count (parallel.h): the bytes
 * given to st_mem_budget_set(), else three quarters of the memory the system
 * reported available (MemAvailable) the first time it was asked.  The check
 * compares the resident size now plus the estimate with the budget. */
#ifndef ST_MEMBUDGET_H
#define ST_MEMBUDGET_H

#include <stddef.h>

#include "core/base/st_error.h"

/* bytes = 0 goes back to the default. */
void st_mem_budget_set(size_t bytes);
size_t st_mem_budget(void);
/* MemAvailable (/proc/meminfo), else the free physical pages; 0 if unknown. */
size_t st_mem_available(void);
/* Resident set size of this process now (/proc/self/statm); 0 if unknown. */
size_t st_mem_resident(void);

/* Reading a file whose bound is smaller than this goes unchecked: the
 * check guards against large allocations, and a process that is over its
 * budget for other reasons (a sanitizer's shadow memory, say) can still
 * read a small file and then be refused the operation that would grow it. */
#define ST_MEM_CHECK_MIN_BYTES ((size_t)16 << 20)

/* ST_OK when the resident size plus `need` fits the budget; else fails
 * with ST_ERR_MEMORY: "WHAT needs about N MiB more (estimate) ...". */
int st_mem_check(size_t need, const char *what, st_error *err);

/* The check before reading a file of file_bytes whose parsed form takes at
 * most `bound` bytes (a bound, not an estimate): skipped under
 * ST_MEM_CHECK_MIN_BYTES; the message names the path and the kind of file. */
int st_mem_check_read(const char *path, const char *kind, size_t file_bytes, size_t bound, st_error *err);

/* Bytes as MiB, for messages. */
static inline double st_mib(size_t bytes) { return (double)bytes / 1048576.0; }

/* Parses a budget in MiB ("512", "1.5"); -1 when not a positive number. */
int st_mem_parse_mib(const char *s, size_t *bytes);

#endif
