/* Transparent huge pages for large flat arrays.
 *
 * The kernel's big arrays (dart relations, positions, detail vectors, UVs,
 * synthesis tables) are mostly written once, in order, soon after they are
 * allocated.  With 4 KiB pages that first touch costs one page fault per
 * 4 KiB; on a virtual machine a fault costs microseconds, and a fresh
 * `strata info` of a 750k-face level took 47 thousand of them.  Advising
 * transparent huge pages on an array makes it one fault per 2 MiB where the
 * system allows it (THP in "madvise" or "always" mode).
 *
 * It is an advice only: nothing changes where THP is off or the call fails,
 * contents are untouched, and the advice follows the memory through
 * realloc's mremap.  The cost is resident memory rounded up to 2 MiB for the
 * parts of an array that are touched; only arrays of 2 MiB or more are
 * advised, and only their whole aligned 2 MiB ranges. */
#ifndef ST_HUGEPAGE_H
#define ST_HUGEPAGE_H

#include <stddef.h>

/* Arrays smaller than this are left alone. */
#define ST_HUGE_MIN_BYTES ((size_t)2 << 20)

/* Advises huge pages for the 2 MiB-aligned part of [p, p + bytes); p may be
 * NULL (nothing done). */
void st_advise_huge(void *p, size_t bytes);

/* malloc and calloc of an array that is then advised as above. */
void *st_malloc_huge(size_t bytes);
void *st_calloc_huge(size_t count, size_t size);

/* realloc of an array to `bytes` that keeps only its first `keep` bytes (at
 * most what p holds).  A large array moves into fresh memory advised as
 * above before the copy touches it: realloc moves an array that lies in the
 * heap (under glibc's mmap threshold, which rises to 32 MiB once a large
 * block is freed) by a copy that faults its new block in 4 KiB pages, which
 * was half of a Loop refinement's page faults.  Shrinking is realloc's.
 * NULL when out of memory (p then unchanged). */
void *st_realloc_huge(void *p, size_t keep, size_t bytes);

/* The bytes the block p (from malloc, calloc, realloc or the functions
 * above; NULL: 0) can hold: at least what was asked for, so that an array
 * grown by half again can fill that room before it moves.  Where the C
 * library cannot tell, what was asked for is unknown and 0 is returned. */
size_t st_usable_bytes(void *p);

/* Keeps the memory the process frees for its own later allocations instead
 * of handing it back to the system (glibc: no mmap'd blocks, no trimming of
 * the heap).  For a command that runs large stages one after another in a
 * fresh process (read a mesh, rebuild its levels, save a session): a stage
 * then reuses pages the one before touched, where fresh pages cost a fault
 * each (microseconds on a virtual machine) and a huge page's zeroing.  The
 * cost is resident memory: what was freed stays resident until it is
 * reused, so peak memory can grow by what fragmentation leaves unused.
 * Nothing where the C library has no such settings. */
void st_malloc_keep_freed(void);

#endif
