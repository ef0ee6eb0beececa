/* Worker threads for the geometry passes (pthreads).
 *
 * A pass splits its work into parts that write disjoint memory and read
 * nothing another part writes, so its result never depends on the number of
 * threads nor on which thread ran which part: one thread and two give the
 * same bits.  Threads are started per call and joined before it returns (no
 * pool survives a call, so fork() and library unloading need no care).
 *
 * The number of threads is a process-wide setting: the number of online
 * cores unless the environment variable STRATA_THREADS says otherwise, or
 * st_parallel_set_threads(). */
#ifndef ST_PARALLEL_H
#define ST_PARALLEL_H

#include <stdint.h>

#define ST_PARALLEL_MAX 64

unsigned st_parallel_threads(void);
/* n = 0 goes back to the default (STRATA_THREADS, else the online cores). */
void st_parallel_set_threads(unsigned n);

typedef struct st_team st_team;
typedef void (*st_team_fn)(st_team *team, unsigned t, void *ctx);

/* Runs fn(team, t, ctx) on `threads` threads, t = 0 being the caller's
 * thread; returns when all have returned.  If a thread cannot be started its
 * share runs on the others: fn must take its work from st_team_next (or
 * cope with fewer threads than asked for: st_team_size). */
void st_team_run(unsigned threads, st_team_fn fn, void *ctx);
unsigned st_team_size(const st_team *team);
/* Waits until every thread of the team has called it. */
void st_team_sync(st_team *team);
/* Dynamic work sharing: hands out chunks [*begin, *end) of [0, n), at most
 * `chunk` items each, every item to exactly one thread of the team, until it
 * returns 0.  Counter k (0..3) serves one loop per st_team_run; n and chunk
 * must be the same on every thread. */
int st_team_next(st_team *team, unsigned k, uint32_t n, uint32_t chunk, uint32_t *begin, uint32_t *end);

#endif
