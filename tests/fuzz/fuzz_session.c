/* libFuzzer target for the session reader (core/io/session.h).
 *
 * Fuzz builds leave the reader's whole-file checksum out
 * (FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, CMakeLists.txt), and the
 * harness makes the header's size and the header CRC match the mutated
 * bytes (when the magic is there), so that mutations reach the structural
 * checks.  A refused input must leave the output untouched and give one
 * line naming the file; an accepted one must pass the validator, extract
 * every level, survive what the window does next, and re-save to bytes that
 * parse and re-save identically.
 *
 * The corpus holds version-3 sessions of small models (a few KB: format 3
 * stores live ids only), version-4 ones in the compact form (LVL0, POSN:
 * the reader regenerates the levels; *_v4.strata), one each of
 * versions 1 and 2, and one with an HD hierarchy (cube_cc1_hd.strata: the
 * chunk 'hdlv' and its nested image; made by tests/core/test_session_hd
 * --seed).
 *   fuzz_session -max_total_time=60 /tmp/corpus_session   (a copy of
 *   tests/fuzz/corpus/session: the fuzzer writes into its corpus folder) */
#include "core/io/map_io_internal.h"
#include "core/base/parallel.h"
#include "core/io/session.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *__asan_default_options(void);

/* ASan records no allocation stacks here: unwinding at every malloc and
 * free was a seventh of the time on these small inputs.  A heap error is
 * still caught and its own stack shown; for the allocation's and the
 * free's stacks, run the artifact again with
 * ASAN_OPTIONS=malloc_context_size=30 (the environment overrides this). */
const char *__asan_default_options(void) { return "malloc_context_size=0"; }

/* One thread: a pass gives the same bits on any number of threads (tested
 * in test_hier, test_progressive and test_unsubdivide), and starting and joining threads at
 * every input cost more than the small models' work. */
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    st_parallel_set_threads(1);
    return 0;
}

static void fix_header(unsigned char *c, size_t n)
{
    if (n < 32 || memcmp(c, ST_SESSION_MAGIC, 8)) return;
    for (int k = 0; k < 8; k++) c[16 + k] = (unsigned char)((uint64_t)n >> (8 * k));
    uint32_t hc = st_crc32(0, c, 24);
    for (int k = 0; k < 4; k++) c[24 + k] = (unsigned char)(hc >> (8 * k));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned char *c = malloc(size ? size : 1);
    if (!c) return 0;
    memcpy(c, data, size);
    fix_header(c, size);
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
    /* The HD hierarchy (chunk 'hdlv'): a valid map, and its adaptive mesh. */
    if (s.has_hd) {
        if (st_map_validate(&s.hd.map, &err) != ST_OK) { fprintf(stderr, "accepted an invalid HD map: %s\n", err.msg); abort(); }
        st_mesh m;
        st_mesh_init(&m);
        if (s.hd.map.darts.end <= 20000 && st_adapt_mesh(&s.hd_adapt, &m, &err) == ST_OK) st_mesh_free(&m);
    }
    for (unsigned l = 0; l <= s.h.map.top; l++) {
        st_mesh m;
        st_mesh_init(&m);
        if (st_hier_level_mesh(&s.h, l, &m, &err) == ST_OK) st_mesh_free(&m);
    }
    /* What the window does next must not crash either: synthesis, an edit,
     * a new level, a box move. */
    st_hier *h = &s.h;
    if (s.has_adapt) {
        st_adapt_params p = s.adapt.has_prev ? s.adapt.prev : s.box;
        for (int k = 0; k < 3; k++) { p.box_lo[k] += 0.25; p.box_hi[k] += 0.25; }
        if (p.max_level > 3) p.max_level = 3;
        if (p.base_level > p.max_level) p.base_level = p.max_level;
        if (h->map.darts.end <= 20000 && st_adapt_update(&s.adapt, &p, &err) == ST_OK &&
            st_map_validate(&h->map, &err) != ST_OK) {
            fprintf(stderr, "box move broke the map: %s\n", err.msg);
            abort();
        }
        /* a progressive hierarchy's selected mesh is a map of its own */
        unsigned shown_level;
        const st_map *shown = st_adapt_display_map(&s.adapt, &shown_level);
        if (shown && shown != &h->map && st_map_validate((st_map *)shown, &err) != ST_OK) {
            fprintf(stderr, "the selected mesh is not a valid map: %s\n", err.msg);
            abort();
        }
    } else {
        st_hier_synthesize(h, 0);
        st_dart_iter it;
        uint32_t d = st_dart_first(&h->map, 0, &it);
        if (d != ST_NIL) {
            double q[1][3];
            const double *pp = st_dart_pos(&h->map, d, 0);
            for (int k = 0; k < 3; k++) q[0][k] = pp[k] + 0.125;
            st_hier_move(h, 0, &d, (const double (*)[3])q, 1);
        }
        /* (not under an HD hierarchy, whose levels start at the model's
         * top: the writer would refuse the session, leaving the re-save
         * below unchecked) */
        if (!s.has_hd && h->map.top < 3 && h->map.darts.end <= 20000 && st_hier_subdivide_to(h, h->map.top + 1, &err) == ST_OK &&
            st_map_validate(&h->map, &err) != ST_OK) {
            fprintf(stderr, "a new level broke the map: %s\n", err.msg);
            abort();
        }
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
