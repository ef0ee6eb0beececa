/* Crash-safe file replacement (atomic_file.h). */
#include "core/io/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
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

int st_afile_open(st_afile *af, const char *path, st_error *err)
{
    memset(af, 0, sizeof *af);
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
    const char *slash = strrchr(path, '/');
    char *dir;
    if (!slash) dir = dup_str(".");
    else if (slash == path) dir = dup_str("/");
    else {
        dir = malloc((size_t)(slash - path) + 1);
        if (dir) { memcpy(dir, path, (size_t)(slash - path)); dir[slash - path] = 0; }
    }
    if (!dir) return -1;
    int fd = open(dir, O_RDONLY | O_DIRECTORY);
    free(dir);
    if (fd < 0) return -1;
    int rc = fsync(fd);
    if (rc && (errno == EINVAL || errno == EROFS)) rc = 0;
    close(fd);
    return rc;
}

int st_afile_commit(st_afile *af, st_error *err)
{
    if (!af->f) return st_fail(err, ST_ERR_INVALID, "commit of a file that is not open");
    int rc = ST_OK;
    int bad = fflush(af->f) != 0 || ferror(af->f);
    int e = errno;
    if (!bad && fsync(fileno(af->f)) != 0 && errno != EINVAL) { bad = 1; e = errno; }
    if (fclose(af->f) != 0 && !bad) { bad = 1; e = errno; }
    af->f = NULL;
    if (bad) rc = st_fail(err, ST_ERR_IO, "%s: write error: %s", af->path, strerror(e ? e : EIO));
    if (!rc && rename(af->tmp, af->path) != 0)
        rc = st_fail(err, ST_ERR_IO, "%s: cannot replace the file: %s", af->path, strerror(errno));
    if (rc) remove(af->tmp);
    else if (sync_dir(af->path) != 0) {
        /* The new content is in place; only its durability across a power
         * cut is not guaranteed.  Not worth failing the save. */
    }
    reset(af);
    return rc;
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
