/* libFuzzer target for the PLY reader (fuzz_harness.h). */
#include "fuzz_harness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_one(st_mesh_parse_ply, "fuzz.ply", data, size);
}
