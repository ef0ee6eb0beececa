/* libFuzzer target for the replay parser (`strata --replay EVENTS.txt`,
 * ui/replay.h): st_replay_parse from memory, built from ui/replay.c with
 * ST_REPLAY_PARSE_ONLY, so that it links the GL-free document library and
 * no GLFW or GL.  A refusal gives one line naming the input and hands back
 * no replay; the parser keeps its own limits on what it builds.
 *   fuzz_replay -max_total_time=60 /tmp/corpus_replay   (a copy of
 *   tests/fuzz/corpus/replay: the fuzzer writes into its corpus folder) */
#include "replay.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    st_replay *rp = (st_replay *)&rp;
    st_error err = { 0 };
    if (st_replay_parse(&rp, "fuzz.replay", (const char *)data, size, &err) != 0) {
        if (rp || strchr(err.msg, '\n') || !strstr(err.msg, "fuzz.replay")) {
            fprintf(stderr, "bad failure: %s\n", err.msg);
            abort();
        }
        return 0;
    }
    if (!rp) { fprintf(stderr, "accepted without a replay\n"); abort(); }
    st_replay_free(rp);
    return 0;
}
