/* libFuzzer target for the OFF reader (fuzz_harness.h). */
#include "fuzz_harness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_one(st_mesh_parse_off, "fuzz.off", data, size);
}
