/* Worker threads (parallel.h). */
#include "core/base/parallel.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

static atomic_uint threads_setting; /* 0: not read from the environment yet */

/* STRATA_THREADS when set, else every online core: a pass gives the same
 * bits on any number of threads, so using the machine costs nothing in
 * reproducibility. */
static unsigned default_threads(void)
{
    const char *s = getenv("STRATA_THREADS");
    long n = s && *s ? strtol(s, NULL, 10) : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > ST_PARALLEL_MAX ? ST_PARALLEL_MAX : (unsigned)n;
}

unsigned st_parallel_threads(void)
{
    unsigned n = atomic_load(&threads_setting);
    if (!n) {
        n = default_threads();
        atomic_store(&threads_setting, n);
    }
    return n;
}

void st_parallel_set_threads(unsigned n)
{
    atomic_store(&threads_setting, n > ST_PARALLEL_MAX ? ST_PARALLEL_MAX : n);
}

/* The members wait at a start gate until the team's size is known (a thread
 * that cannot be started just makes the team smaller); st_team_sync is a
 * counting barrier on the same mutex. */
struct st_team {
    unsigned size;
    st_team_fn fn;
    void *ctx;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int go;                     /* start gate open */
    unsigned arrived, phase;    /* barrier */
    _Atomic uint32_t next[4];   /* st_team_next counters */
};

typedef struct member { st_team *team; unsigned t; } member;

static void *member_main(void *arg)
{
    member *w = arg;
    st_team *team = w->team;
    pthread_mutex_lock(&team->mu);
    while (!team->go) pthread_cond_wait(&team->cv, &team->mu);
    pthread_mutex_unlock(&team->mu);
    team->fn(team, w->t, team->ctx);
    return NULL;
}

unsigned st_team_size(const st_team *team) { return team->size; }

void st_team_sync(st_team *team)
{
    if (team->size < 2) return;
    pthread_mutex_lock(&team->mu);
    unsigned phase = team->phase;
    if (++team->arrived == team->size) {
        team->arrived = 0;
        team->phase++;
        pthread_cond_broadcast(&team->cv);
    } else {
        while (phase == team->phase) pthread_cond_wait(&team->cv, &team->mu);
    }
    pthread_mutex_unlock(&team->mu);
}

int st_team_next(st_team *team, unsigned k, uint32_t n, uint32_t chunk, uint32_t *begin, uint32_t *end)
{
    /* A counter only grows: once past n it stays past n (chunk <= 2^31 and
     * n < 2^32 - 2^31 keep it from wrapping around within one loop). */
    uint32_t b = atomic_fetch_add_explicit(&team->next[k], chunk, memory_order_relaxed);
    if (b >= n) return 0;
    *begin = b;
    *end = n - b < chunk ? n : b + chunk;
    return 1;
}

void st_team_run(unsigned threads, st_team_fn fn, void *ctx)
{
    st_team team = { .size = 1, .fn = fn, .ctx = ctx };
    for (unsigned k = 0; k < 4; k++) atomic_init(&team.next[k], 0);
    if (threads > ST_PARALLEL_MAX) threads = ST_PARALLEL_MAX;
    pthread_t tid[ST_PARALLEL_MAX];
    member mem[ST_PARALLEL_MAX];
    unsigned started = 1;
    if (threads > 1 && pthread_mutex_init(&team.mu, NULL) == 0) {
        if (pthread_cond_init(&team.cv, NULL) == 0) {
            for (unsigned t = 1; t < threads; t++) {
                mem[t] = (member){ &team, t };
                if (pthread_create(&tid[t], NULL, member_main, &mem[t]) != 0) break;
                started++;
            }
            pthread_mutex_lock(&team.mu);
            team.size = started;
            team.go = 1;
            pthread_cond_broadcast(&team.cv);
            pthread_mutex_unlock(&team.mu);
            fn(&team, 0, ctx);
            for (unsigned t = 1; t < started; t++) pthread_join(tid[t], NULL);
            pthread_cond_destroy(&team.cv);
            pthread_mutex_destroy(&team.mu);
            return;
        }
        pthread_mutex_destroy(&team.mu);
    }
    fn(&team, 0, ctx);
}
