/* libFuzzer target for the glTF reader (formats/gltf_io.h, fuzz_harness.h):
 * GLB or JSON glTF from memory, repaired and checked when it parses.
 * Inputs above 1 MiB are skipped: the reader's own limits (2 GiB files,
 * buffers no larger than the input) would let libFuzzer spend its time on
 * copying, not on finding bugs. */
#include "fuzz_harness.h"
#include "formats/gltf_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int parse_gltf(const char *name, const char *data, size_t size, st_mesh *out, st_error *err)
{
    return st_gltf_parse(name, data, size, out, err);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > ((size_t)1 << 20)) return 0;
    return fuzz_one(parse_gltf, "fuzz.glb", data, size);
}
