/* libFuzzer target for the PLY reader: parse, repair what parses, then
 * hold the repair to its promise (st_mesh_check) and free.  A failed parse
 * must leave the output mesh untouched and give a one-line message.
 *   cmake -DSTRATA_FUZZ=ON -DCMAKE_C_COMPILER=clang ...
 *   fuzz_ply -max_total_time=60 tests/fuzz/corpus/ply */
#include "mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    st_mesh m;
    st_error err = {0};
    st_notes notes = {0};
    st_mesh_init(&m);
    m.nverts = 7;   /* a marker: a failed parse must not touch the output */
    if (st_mesh_parse_ply("fuzz.ply", (const char *)data, size, &m, &err) != 0) {
        if (m.nverts != 7 || m.pos || m.face_off || strchr(err.msg, '\n') || !strstr(err.msg, "fuzz.ply")) {
            fprintf(stderr, "bad failure: %s\n", err.msg);
            abort();
        }
        return 0;
    }
    if (st_mesh_repair("fuzz.ply", &m, &notes, &err) == 0 && st_mesh_check("fuzz.ply", &m, &err) != 0) {
        fprintf(stderr, "repair broke its promise: %s\n", err.msg);
        abort();
    }
    st_notes_free(&notes);
    st_mesh_free(&m);
    return 0;
}
