/* Shared body of the loader fuzz targets: parse, repair what parses, then
 * hold the repair to its promise (st_mesh_check) and free.  A failed parse
 * must leave the output mesh untouched and give a one-line message naming
 * the input.
 *   cmake -DSTRATA_FUZZ=ON -DCMAKE_C_COMPILER=clang ...
 *   fuzz_obj -max_total_time=60 tests/fuzz/corpus/obj */
#ifndef ST_FUZZ_HARNESS_H
#define ST_FUZZ_HARNESS_H

#include "core/io/mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef int (*fuzz_parse_fn)(const char *name, const char *data, size_t size, st_mesh *out, st_error *err);

static int fuzz_one(fuzz_parse_fn parse, const char *name, const uint8_t *data, size_t size)
{
    st_mesh m;
    st_error err = {0};
    st_notes notes = {0};
    st_mesh_init(&m);
    m.nverts = 7; /* a marker: a failed parse must not touch the output */
    if (parse(name, (const char *)data, size, &m, &err) != 0) {
        if (m.nverts != 7 || m.pos || m.face_off || strchr(err.msg, '\n') || !strstr(err.msg, name)) {
            fprintf(stderr, "bad failure: %s\n", err.msg);
            abort();
        }
        return 0;
    }
    if (st_mesh_repair(name, &m, &notes, &err) == 0 && st_mesh_check(name, &m, &err) != 0) {
        fprintf(stderr, "repair broke its promise: %s\n", err.msg);
        abort();
    }
    st_notes_free(&notes);
    st_mesh_free(&m);
    return 0;
}

#endif
