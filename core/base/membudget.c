/* Memory budget (membudget.h). */
#include "core/base/membudget.h"

#include <math.h>
#include <stdint.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static _Atomic size_t budget_setting; /* 0: the default, computed on first use */

size_t st_mem_available(void)
{
    FILE *f = fopen("/proc/meminfo", "r");
    if (f) {
        char line[256];
        unsigned long long kb = 0;
        int found = 0;
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "MemAvailable: %llu kB", &kb) == 1) { found = 1; break; }
        fclose(f);
        if (found) return (size_t)kb * 1024u;
    }
    long pages = sysconf(_SC_AVPHYS_PAGES), psize = sysconf(_SC_PAGESIZE);
    return pages > 0 && psize > 0 ? (size_t)pages * (size_t)psize : 0;
}

size_t st_mem_resident(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long long size = 0, resident = 0;
    int n = fscanf(f, "%llu %llu", &size, &resident);
    fclose(f);
    long psize = sysconf(_SC_PAGESIZE);
    return n == 2 && psize > 0 ? (size_t)resident * (size_t)psize : 0;
}

void st_mem_budget_set(size_t bytes) { atomic_store(&budget_setting, bytes); }

size_t st_mem_budget(void)
{
    size_t b = atomic_load(&budget_setting);
    if (!b) {
        size_t avail = st_mem_available();
        b = avail ? avail / 4 * 3 : (size_t)4 << 30;
        atomic_store(&budget_setting, b);
    }
    return b;
}

int st_mem_check(size_t need, const char *what, st_error *err)
{
    size_t have = st_mem_resident(), limit = st_mem_budget();
    if (need <= limit && have <= limit - need) return ST_OK;
    return st_fail(err, ST_ERR_MEMORY,
                   "%s needs about %.1f MiB more (estimate); the process uses %.1f MiB and the memory budget is "
                   "%.1f MiB (--mem-budget MIB; default: 3/4 of the memory available at start)",
                   what, st_mib(need), st_mib(have), st_mib(limit));
}

int st_mem_check_read(const char *path, const char *kind, size_t file_bytes, size_t bound, st_error *err)
{
    if (bound < ST_MEM_CHECK_MIN_BYTES) return ST_OK;
    char what[96];
    snprintf(what, sizeof what, "reading a %s of %.1f MiB", kind, st_mib(file_bytes));
    int rc = st_mem_check(bound, what, err);
    if (!rc) return ST_OK;
    char msg[sizeof err->msg];
    snprintf(msg, sizeof msg, "%s", err->msg);
    return st_fail(err, rc, "%s: %s", path, msg);
}

int st_mem_parse_mib(const char *s, size_t *bytes)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end || !isfinite(v) || !(v > 0) || v * 1048576.0 > (double)SIZE_MAX / 2) return -1;
    *bytes = (size_t)(v * 1048576.0);
    return *bytes ? 0 : -1;
}
