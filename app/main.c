/* strata: one executable, subcommands. */
#include "cli.h"

#include <stdio.h>
#include <string.h>

static void usage(FILE *f)
{
    fprintf(f,
        "usage: strata <command> [options]\n"
        "commands:\n"
        "  info FILE [--scheme S --levels N] [--boundary B]\n"
        "                                      per-level counts and memory\n"
        "  subdivide IN --scheme S --levels N [--level L] [--boundary edge-only|edge-and-corner] -o OUT\n"
        "                                      writes level L (default N) as OBJ or PLY\n"
        "schemes: catmull-clark, loop, butterfly, quad-triangle, sqrt3, doo-sabin\n"
        "  help                                this text\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) { usage(stderr); return 2; }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "info")) return st_cmd_info(argc - 2, argv + 2);
    if (!strcmp(cmd, "subdivide")) return st_cmd_subdivide(argc - 2, argv + 2);
    if (!strcmp(cmd, "help") || !strcmp(cmd, "--help") || !strcmp(cmd, "-h")) { usage(stdout); return 0; }
    fprintf(stderr, "strata: unknown command '%s'\n", cmd);
    usage(stderr);
    return 2;
}
