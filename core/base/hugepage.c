/* See hugepage.h. */
#define _DEFAULT_SOURCE
#include "core/base/hugepage.h"

#include <stdint.h>
#include <stdlib.h>
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
