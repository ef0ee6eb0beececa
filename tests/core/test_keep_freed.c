/* st_malloc_keep_freed (core/base/hugepage.h): after it, memory the process
 * frees is reused by its next allocations, on the same thread and on
 * another, without faulting fresh pages in again.  Counted with the
 * process's minor page faults around a second allocation as large as the
 * first: without the setting, glibc maps a 64 MiB block afresh (16384 pages
 * of 4 KiB) and, on another thread, in an arena of its own. */
#define _GNU_SOURCE
#include "testlib.h"
#include "core/base/hugepage.h"

#include <pthread.h>
#include <stdlib.h>
#include <sys/resource.h>

#define BLOCK ((size_t)64 << 20)

#if !defined(__SANITIZE_ADDRESS__)

static long minor_faults(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) ? -1 : ru.ru_minflt;
}

/* Faults taken by allocating `bytes` and writing them all. */
static long fill(size_t bytes)
{
    long before = minor_faults();
    char *p = malloc(bytes);
    /* Volatile: a block written and freed unread is otherwise no block. */
    for (size_t i = 0; p && i < bytes; i += 4096) ((volatile char *)p)[i] = 1;
    long faults = p ? minor_faults() - before : -1;
    free(p);
    return faults;
}

static void *fill_block(void *out)
{
    *(long *)out = fill(BLOCK);
    return NULL;
}

/* A quarter block: small enough for a thread's own arena (64 MiB heaps). */
static void *fill_quarter(void *out)
{
    *(long *)out = fill(BLOCK / 4);
    return NULL;
}

#endif

int main(void)
{
#if defined(__SANITIZE_ADDRESS__)
    /* ASan's allocator quarantines what is freed: nothing to reuse. */
    fprintf(stderr, "test_keep_freed: not under AddressSanitizer\n");
#else
    /* glibc's default, first: the block is mapped afresh each time, so the
     * count below sees a reuse that would not happen without the setting. */
    long fresh = 0, fresh_again = 0;
    fill_block(&fresh);
    fill_block(&fresh_again);
    CHECKF(fresh_again >= (long)(BLOCK >> 21), "without the setting, the block again: %ld faults", fresh_again);
    st_malloc_keep_freed();
    long first = 0, again = 0, other = 0;
    fill_block(&first);
    fill_block(&again);
    pthread_t t;
    CHECK(pthread_create(&t, NULL, fill_quarter, &other) == 0);
    CHECK(pthread_join(t, NULL) == 0);
    /* A fresh block faults at least once per 2 MiB; a reused one not at
     * all (a few for malloc's own bookkeeping). */
    CHECKF(first >= (long)(BLOCK >> 21), "first block: %ld faults", first);
    CHECKF(again >= 0 && again < 64, "the block again: %ld faults", again);
    CHECKF(other >= 0 && other < 64, "the block on another thread: %ld faults", other);
#endif
    return TEST_END();
}
