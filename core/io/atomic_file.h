/* Crash-safe file replacement.
 *
 * st_afile_open() creates "<path>.tmp-<pid>" next to path; the caller writes
 * through af.f; st_afile_commit() flushes the stdio buffer, fsyncs the file,
 * closes it, renames it over path (atomic on POSIX file systems) and fsyncs
 * the directory so that the rename itself is durable.  Killing the process
 * at any moment leaves either the old file or the new one at path, never a
 * mixture or a truncated file (at worst a stray temporary).  Stray
 * temporaries do not pile up: st_afile_open() first removes, in path's
 * folder, the temporaries of processes that no longer exist
 * (st_afile_sweep).  st_afile_abort() removes the temporary.  On any
 * failure path keeps its previous content, and the message names path and
 * the reason (strerror), never the temporary. */
#ifndef ST_ATOMIC_FILE_H
#define ST_ATOMIC_FILE_H

#include <stdio.h>

#include "core/base/st_error.h"

typedef struct st_afile {
    FILE *f;
    char *path;                /* copies, owned */
    char *tmp;
    int werr;                  /* errno of the first failed st_afile_write, 0: none */
} st_afile;

int st_afile_open(st_afile *af, const char *path, st_error *err);
/* fwrite of n bytes to af->f that keeps the errno of a short write for the
 * commit's message (stdio's error flag keeps no reason).  0 when all were
 * written. */
int st_afile_write(st_afile *af, const void *data, size_t n);
/* Commits (see above); af is closed and reset in every case.  A write error
 * seen on af->f (ferror) fails the commit and removes the temporary. */
int st_afile_commit(st_afile *af, st_error *err);
void st_afile_abort(st_afile *af);

/* The two halves of st_afile_commit, for files that must appear together
 * (bake's maps, a .gltf and its .bin): finish every file first, so that
 * every write that can fail has been done, then place them all.  A kill
 * between two placements leaves the first one new and the next old: the
 * window is that of a rename() (no data is written in it).
 * st_afile_finish: flushes, fsyncs and closes the temporary; on failure
 * removes it and resets af.  st_afile_place: renames a finished temporary
 * over path; af is reset in every case. */
int st_afile_finish(st_afile *af, st_error *err);
int st_afile_place(st_afile *af, st_error *err);

/* Removes from path's folder the temporaries st_afile_open names
 * ("NAME.tmp-PID", PID decimal) whose process no longer exists
 * (kill(PID, 0) fails with ESRCH), owned by this user and regular files;
 * nothing else is touched.  A process in another PID namespace writing
 * into the same folder would look dead: its save then fails cleanly
 * (the rename finds no temporary), its old file stays. */
void st_afile_sweep(const char *path);

/* Creates the directories of path's parent ("mkdir -p" of dirname(path));
 * 0 when they exist afterwards. */
int st_mkdir_parents(const char *path);

#endif
