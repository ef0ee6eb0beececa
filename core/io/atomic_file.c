/* Crash-safe file replacement (atomic_file.h). */
#include "core/io/atomic_file.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *p = malloc(n);
    if (p) memcpy(p, s, n);
    return p;
}

/* The folder part of path ("." when none, "/" for the root); NULL when out
 * of memory. */
static char *dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash) return dup_str(".");
    if (slash == path) return dup_str("/");
    char *dir = malloc((size_t)(slash - path) + 1);
    if (dir) { memcpy(dir, path, (size_t)(slash - path)); dir[slash - path] = 0; }
    return dir;
}

/* The PID of a temporary's name "NAME.tmp-PID", or 0 when the name is not
 * one (NAME non-empty, PID decimal without a leading zero, > 0). */
static long temp_pid(const char *name)
{
    const char *t = strstr(name, ".tmp-");
    if (!t || t == name) return 0;
    for (const char *n; (n = strstr(t + 1, ".tmp-")); ) t = n;
    const char *d = t + 5;
    if (*d < '1' || *d > '9') return 0;
    long pid = 0;
    for (; *d; d++) {
        if (*d < '0' || *d > '9' || pid > 99999999) return 0;
        pid = pid * 10 + (*d - '0');
    }
    return pid;
}

void st_afile_sweep(const char *path)
{
    char *dir = dir_of(path);
    DIR *dp = dir ? opendir(dir) : NULL;
    if (!dp) { free(dir); return; }
    int dfd = dirfd(dp);
    struct dirent *e;
    while ((e = readdir(dp))) {
        long pid = temp_pid(e->d_name);
        if (!pid || pid == (long)getpid()) continue;
        struct stat st;
        if (fstatat(dfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) || !S_ISREG(st.st_mode) || st.st_uid != geteuid()) continue;
        if (kill((pid_t)pid, 0) == -1 && errno == ESRCH) unlinkat(dfd, e->d_name, 0);
    }
    closedir(dp);
    free(dir);
}

int st_afile_open(st_afile *af, const char *path, st_error *err)
{
    memset(af, 0, sizeof *af);
    st_afile_sweep(path);
    size_t n = strlen(path) + 32;
    af->path = dup_str(path);
    af->tmp = malloc(n);
    if (!af->path || !af->tmp) {
        free(af->path);
        free(af->tmp);
        memset(af, 0, sizeof *af);
        return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", path);
    }
    snprintf(af->tmp, n, "%s.tmp-%ld", path, (long)getpid());
    af->f = fopen(af->tmp, "wb");
    if (!af->f) {
        int e = errno;
        free(af->path);
        free(af->tmp);
        memset(af, 0, sizeof *af);
        return st_fail(err, ST_ERR_IO, "%s: cannot write: %s", path, strerror(e));
    }
    return ST_OK;
}

int st_afile_write(st_afile *af, const void *data, size_t n)
{
    if (!n || fwrite(data, 1, n, af->f) == n) return 0;
    if (!af->werr) af->werr = errno ? errno : EIO;
    return -1;
}

static void reset(st_afile *af)
{
    free(af->path);
    free(af->tmp);
    memset(af, 0, sizeof *af);
}

void st_afile_abort(st_afile *af)
{
    if (af->f) fclose(af->f);
    if (af->tmp) remove(af->tmp);
    reset(af);
}

/* fsync of the directory holding path, so that a rename into it is durable.
 * Some file systems refuse fsync on directories (EINVAL): not an error. */
static int sync_dir(const char *path)
{
    char *dir = dir_of(path);
    if (!dir) return -1;
    int fd = open(dir, O_RDONLY | O_DIRECTORY);
    free(dir);
    if (fd < 0) return -1;
    int rc = fsync(fd);
    if (rc && (errno == EINVAL || errno == EROFS)) rc = 0;
    close(fd);
    return rc;
}

int st_afile_finish(st_afile *af, st_error *err)
{
    if (!af->f) return st_fail(err, ST_ERR_INVALID, "commit of a file that is not open");
    /* The reason: the first failed st_afile_write's errno, else the
     * flush's (it repeats a write that failed into stdio's buffer), else,
     * for a stream whose error flag an earlier fwrite set, the errno it
     * left. */
    int bad = fflush(af->f) != 0 || ferror(af->f);
    int e = af->werr ? af->werr : errno;
    if (!bad && fsync(fileno(af->f)) != 0 && errno != EINVAL) { bad = 1; e = errno; }
    if (fclose(af->f) != 0 && !bad) { bad = 1; e = errno; }
    af->f = NULL;
    if (!bad) return ST_OK;
    remove(af->tmp);
    int rc = st_fail(err, ST_ERR_IO, "%s: write error: %s", af->path, strerror(e ? e : EIO));
    reset(af);
    return rc;
}

int st_afile_place(st_afile *af, st_error *err)
{
    if (!af->tmp || af->f) { st_afile_abort(af); return st_fail(err, ST_ERR_INVALID, "placing a file that is not finished"); }
    int rc = ST_OK;
    if (rename(af->tmp, af->path) != 0) {
        rc = st_fail(err, ST_ERR_IO, "%s: cannot replace the file: %s", af->path, strerror(errno));
        remove(af->tmp);
    } else if (sync_dir(af->path) != 0) {
        /* The new content is in place; only its durability across a power
         * cut is not guaranteed.  Not worth failing the save. */
    }
    reset(af);
    return rc;
}

int st_afile_commit(st_afile *af, st_error *err)
{
    int rc = st_afile_finish(af, err);
    return rc ? rc : st_afile_place(af, err);
}

int st_mkdir_parents(const char *path)
{
    char *p = dup_str(path);
    if (!p) return -1;
    char *slash = strrchr(p, '/');
    if (!slash || slash == p) { free(p); return 0; }
    *slash = 0;
    for (char *q = p + 1; ; q++) {
        if (*q == '/' || *q == 0) {
            char c = *q;
            *q = 0;
            if (mkdir(p, 0700) != 0 && errno != EEXIST) { free(p); return -1; }
            *q = c;
            if (!c) break;
        }
    }
    struct stat st;
    int rc = stat(p, &st) == 0 && S_ISDIR(st.st_mode) ? 0 : -1;
    free(p);
    return rc;
}
