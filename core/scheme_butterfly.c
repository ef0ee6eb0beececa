/* PLACEHOLDER: scheme not implemented yet; refine() refuses with a message. */
#include "hier_internal.h"

static int not_yet(st_hier *h, st_error *err)
{
    (void)h;
    return st_fail(err, ST_ERR_INVALID, "the butterfly scheme is not implemented yet");
}

static void no_emit(st_hier *h, unsigned L, const uint32_t *faces, uint32_t n, st_stencil_sink sink, void *ctx)
{
    (void)h; (void)L; (void)faces; (void)n; (void)sink; (void)ctx;
}

const st_scheme st_scheme_butterfly = {
    .name = "butterfly",
    .id = ST_SCHEME_BUTTERFLY,
    .check = not_yet,
    .refine = not_yet,
    .emit = no_emit,
};
