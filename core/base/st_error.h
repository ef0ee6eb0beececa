/* Error reporting shared by every loader and operator of Strata's core.
 *
 * A failing call fills an st_error and returns a non-zero code; it never
 * aborts on bad input (asserts are for programmer errors only).  Messages
 * name the file, the line (or byte offset) and the problem, e.g.
 *   "bunny.obj:1043: face references vertex 9001 but the file has 8000 vertices"
 */
#ifndef ST_ERROR_H
#define ST_ERROR_H

#include <stdarg.h>

enum st_status {
    ST_OK = 0,
    ST_ERR_IO,          /* cannot open / read / write a file */
    ST_ERR_PARSE,       /* syntax error, bad number, unknown format */
    ST_ERR_RANGE,       /* index out of range, absurd count */
    ST_ERR_TOPOLOGY,    /* non-manifold, non-orientable, degenerate faces */
    ST_ERR_GEOMETRY,    /* non-finite coordinates */
    ST_ERR_MEMORY,      /* allocation failed or would exceed a limit */
    ST_ERR_INVALID,     /* operator precondition not met / validator failure */
};

typedef struct st_error {
    int code;           /* enum st_status, ST_OK when nothing failed */
    char msg[1024];     /* human-readable, one line, no trailing newline */
} st_error;

/* Sets err (if not NULL) and returns code; printf-style message. */
int st_fail(st_error *err, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#endif
