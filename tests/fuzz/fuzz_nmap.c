/* libFuzzer target for the PNG normal-map input (`strata render
 * --normal-map`, `strata convert --normal-map`): render/image.h's
 * st_png_decode, the decoder st_png_read and app/render_nmap.c use, from
 * memory.  A refusal gives one line naming the input; a decoded map is
 * w*h RGBA pixels, each of them readable, and no larger than the reader's
 * limit.
 *   fuzz_nmap -max_total_time=60 /tmp/corpus_nmap   (a copy of
 *   tests/fuzz/corpus/nmap: the fuzzer writes into its corpus folder) */
#include "render/image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

volatile unsigned fuzz_nmap_sink;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    int w = -1, h = -1;
    unsigned char *px = NULL;
    st_error err = { 0 };
    if (st_png_decode("fuzz.png", data, size, &w, &h, &px, &err) != ST_OK) {
        if (px || strchr(err.msg, '\n') || !strstr(err.msg, "fuzz.png")) {
            fprintf(stderr, "bad failure: %s\n", err.msg);
            abort();
        }
        return 0;
    }
    if (!px || w < 1 || h < 1 || w > ST_PNG_MAX_SIDE || h > ST_PNG_MAX_SIDE) {
        fprintf(stderr, "decoded %dx%d\n", w, h);
        abort();
    }
    /* Every pixel is there (ASan reports a short buffer); alpha is opaque
     * or whatever the file said, never read uninitialised by the caller. */
    size_t n = (size_t)w * (size_t)h * 4;
    for (size_t i = 0; i < n; i += 4093) fuzz_nmap_sink += px[i];
    fuzz_nmap_sink += px[n - 1];
    free(px);
    return 0;
}
