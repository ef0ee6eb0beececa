#ifndef ST_CLI_COMMON_H
#define ST_CLI_COMMON_H

#include "core/multires/hier.h"
#include "core/io/session.h"

typedef struct st_cli_opts {
    const char *in, *out, *scheme;
    unsigned levels;
    int level;          /* -1: not given */
    int boundary;       /* ST_BOUNDARY_UNSET unless --boundary */
    int uv_interp;      /* enum st_uv_interp: --uv-interp, else OpenSubdiv's default (corners-plus1) */
    unsigned read_flags; /* st_mesh_repair_flags: ST_MESH_STRICT with --strict */
} st_cli_opts;

/* Parses the common options (--strict: refuse edges with 3+ faces rather
 * than split them, core/io/mesh.h's ST_MESH_STRICT); prints a message and
 * returns -1 on error. */
int st_cli_parse(int argc, char **argv, st_cli_opts *o, const char *cmd);
/* Loads o->in and builds the hierarchy to o->levels; prints errors. */
int st_cli_load(const st_cli_opts *o, st_hier *h, const char *cmd);
/* Loads o->in as a whole session: a session file with every chunk it
 * holds, or a mesh built as st_cli_load builds it, its control mesh kept as
 * the session's base.  Prints errors; s is empty on failure. */
int st_cli_load_session(const st_cli_opts *o, st_session *s, const char *cmd);
/* --uv-interp NAME into *out (enum st_uv_interp); -1 with a message. */
int st_cli_parse_uv_interp(const char *v, int *out, const char *cmd);

/* The level a command shows or writes once h is loaded: --level, else
 * --levels, else (a session file given without either) its top level.
 * Prints a message and returns -1 when the level does not exist. */
int st_cli_level(const st_cli_opts *o, const st_hier *h, const char *cmd, unsigned *level);

/* Parses "x0,y0,z0,x1,y1,z1" into sorted corners; -1 when malformed. */
int st_cli_parse_box(const char *s, double lo[3], double hi[3]);

#endif
