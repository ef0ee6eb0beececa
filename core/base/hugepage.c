/* See hugepage.h. */
#define _DEFAULT_SOURCE
#include "core/base/hugepage.h"

#include <limits.h>
#include <malloc.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#define HUGE_PAGE ((uintptr_t)2 << 20)

void st_advise_huge(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
    if (!p || bytes < ST_HUGE_MIN_BYTES) return;
    uintptr_t lo = ((uintptr_t)p + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1);
    uintptr_t hi = ((uintptr_t)p + bytes) & ~(HUGE_PAGE - 1);
    if (hi > lo) (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

size_t st_usable_bytes(void *p)
{
#ifdef __GLIBC__
    return p ? malloc_usable_size(p) : 0;
#else
    (void)p;
    return 0;
#endif
}

void st_malloc_keep_freed(void)
{
#if defined(M_MMAP_MAX) && defined(M_TRIM_THRESHOLD)
    /* Blocks over the mmap threshold are unmapped when freed, so the next
     * large array faults its pages in again; the heap's top is trimmed
     * once over the trim threshold. */
    (void)mallopt(M_MMAP_MAX, 0);
    (void)mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
#ifdef M_ARENA_MAX
    /* One heap for every thread: a worker's arrays (a rebuild's UVs,
     * refined beside the positions) reuse what the main thread freed
     * instead of faulting in an arena of their own.  Arrays are flat and
     * allocated a few at a time, not per element, so the shared lock is
     * taken rarely. */
    (void)mallopt(M_ARENA_MAX, 1);
#endif
}

void *st_malloc_huge(size_t bytes)
{
    void *p = malloc(bytes);
    st_advise_huge(p, bytes);
    return p;
}

void *st_calloc_huge(size_t count, size_t size)
{
    /* calloc leaves fresh pages from the system untouched, so the advice
     * still comes before their first touch. */
    void *p = calloc(count, size);
    if (p) st_advise_huge(p, count * size);
    return p;
}

void *st_realloc_huge(void *p, size_t keep, size_t bytes)
{
    if (!p || bytes < ST_HUGE_MIN_BYTES) return realloc(p, bytes);
    size_t held = malloc_usable_size(p);
    if (bytes <= held) return realloc(p, bytes); /* shrinking: in place */
    if (keep > held) keep = held;
    if (keep > bytes) keep = bytes;
    /* Aligned to 2 MiB, so that the advice covers the whole array. */
    void *q = aligned_alloc(HUGE_PAGE, (bytes + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1));
    if (!q) return NULL;
    st_advise_huge(q, bytes);
    memcpy(q, p, keep);
    free(p);
    return q;
}
