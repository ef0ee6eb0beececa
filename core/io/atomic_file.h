/* Crash-safe file replacement.
 *
 * st_afile_open() creates "<path>.tmp-<pid>" next to path; the caller writes
 * through af.f; st_afile_commit() flushes the stdio buffer, fsyncs the file,
 * closes it, renames it over path (atomic on POSIX file systems) and fsyncs
 * the directory so that the rename itself is durable.  Killing the process
 * at any moment leaves either the old file or the new one at path, never a
 * mixture or a truncated file (at worst a stray temporary, which the next
 * save of the same process id replaces).  st_afile_abort() removes the
 * temporary.  On any failure path keeps its previous content. */
#ifndef ST_ATOMIC_FILE_H
#define ST_ATOMIC_FILE_H

#include <stdio.h>

#include "core/base/st_error.h"

typedef struct st_afile {
    FILE *f;
    char *path;                /* copies, owned */
    char *tmp;
} st_afile;

int st_afile_open(st_afile *af, const char *path, st_error *err);
/* Commits (see above); af is closed and reset in every case.  A write error
 * seen on af->f (ferror) fails the commit and removes the temporary. */
int st_afile_commit(st_afile *af, st_error *err);
void st_afile_abort(st_afile *af);

/* Creates the directories of path's parent ("mkdir -p" of dirname(path));
 * 0 when they exist afterwards. */
int st_mkdir_parents(const char *path);

#endif
