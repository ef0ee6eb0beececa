/* libFuzzer target for the session reader (core/session.h).
 *
 * The checksum would turn almost every mutation into "damaged file", so the
 * harness first makes the header's size, the header CRC and the trailing CRC
 * match the mutated bytes (when the magic is there), then parses, so that
 * the fuzzer reaches the structural checks behind the checksum.  A refused
 * input must leave the output untouched and give one line naming the file;
 * an accepted one must pass
 * the validator, extract every level, and re-save to bytes that parse and
 * re-save identically.
 *   fuzz_session -max_total_time=60 /tmp/corpus_session   (a copy of
 *   tests/fuzz/corpus/session: the fuzzer writes into its corpus folder) */
#include "map_io.h"
#include "session.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void fix_checksums(unsigned char *c, size_t n)
{
    if (n < 32 || memcmp(c, ST_SESSION_MAGIC, 8)) return;
    for (int k = 0; k < 8; k++) c[16 + k] = (unsigned char)((uint64_t)n >> (8 * k));
    uint32_t hc = st_crc32(0, c, 24);
    for (int k = 0; k < 4; k++) c[24 + k] = (unsigned char)(hc >> (8 * k));
    uint32_t crc = st_crc32(0, c, n - 4);
    for (int k = 0; k < 4; k++) c[n - 4 + k] = (unsigned char)(crc >> (8 * k));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned char *c = malloc(size ? size : 1);
    if (!c) return 0;
    memcpy(c, data, size);
    fix_checksums(c, size);
    st_session s;
    st_error err = { 0 };
    memset(&s, 0x5a, sizeof s);
    if (st_session_parse("fuzz.strata", c, size, &s, &err) != ST_OK) {
        unsigned char probe[sizeof s];
        memset(probe, 0x5a, sizeof probe);
        if (memcmp(&s, probe, sizeof s) || strchr(err.msg, '\n') || !strstr(err.msg, "fuzz.strata")) {
            fprintf(stderr, "bad failure: %s\n", err.msg);
            abort();
        }
        free(c);
        return 0;
    }
    if (st_map_validate(&s.h.map, &err) != ST_OK) { fprintf(stderr, "accepted an invalid map: %s\n", err.msg); abort(); }
    for (unsigned l = 0; l <= s.h.map.top; l++) {
        st_mesh m;
        st_mesh_init(&m);
        if (st_hier_level_mesh(&s.h, l, &m, &err) == ST_OK) st_mesh_free(&m);
    }
    st_session_ref r = st_session_ref_of(&s);
    void *b1 = NULL, *b2 = NULL;
    size_t n1 = 0, n2 = 0;
    if (st_session_write_mem(&r, &b1, &n1, &err) == ST_OK) {
        st_session t;
        if (st_session_parse("resaved.strata", b1, n1, &t, &err) != ST_OK) { fprintf(stderr, "re-saved session refused: %s\n", err.msg); abort(); }
        st_session_ref r2 = st_session_ref_of(&t);
        if (st_session_write_mem(&r2, &b2, &n2, &err) != ST_OK || n1 != n2 || memcmp(b1, b2, n1)) { fprintf(stderr, "save -> load -> save differs\n"); abort(); }
        st_session_free(&t);
    }
    free(b1);
    free(b2);
    st_session_free(&s);
    free(c);
    return 0;
}
