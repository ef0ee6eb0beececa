/* Opening an input file without hanging on it.
 *
 * fopen() of a FIFO waits for a writer, forever if none comes, and a
 * device such as /dev/zero never ends: a reader that takes a path from the
 * user opens it with st_open_input(), which opens without blocking, refuses
 * anything but a regular file with the path named, and only then hands
 * back an ordinary blocking stream. */
#ifndef ST_FILE_OPEN_H
#define ST_FILE_OPEN_H

#include <stdio.h>

#include "core/base/st_error.h"

/* path opened for reading ("rb"), or NULL with err "PATH: cannot open:
 * REASON" or "PATH: a FIFO (a device, a folder, ...), not a regular file". */
FILE *st_open_input(const char *path, st_error *err);

#endif
