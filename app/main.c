/* strata: one executable, subcommands. */
#include "cli.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

static void usage(FILE *f)
{
    fprintf(f,
        "usage: strata <command> [options]\n"
        "commands:\n"
        "  info FILE [--scheme S --levels N] [--boundary B]\n"
        "                                      per-level counts and memory\n"
        "  subdivide IN --scheme S --levels N [--level L] [--boundary edge-only|edge-and-corner] -o OUT\n"
        "                                      writes level L (default N) as OBJ or PLY\n"
        "  adapt IN --scheme S --base-level B --max-level M --box x0,y0,z0,x1,y1,z1\n"
        "        [--falloff W] [--flatness T] [--no-restriction] [--triangulate] -o OUT\n"
        "                                      writes the adaptive mesh (interest box)\n"
        "  render IN [--scheme S --levels N --level L] [--view front|back|left|right|top|iso | --orbit AZ,EL,DIST]\n"
        "         [--mode smooth|flat|wire|cage] [--size WxH] -o OUT.png\n"
        "                                      draws level L headless (no display, no GPU) into a PNG\n"
        "  convert IN OUT [--scheme S --levels N --level L | --box ...] [--normals | --no-normals]\n"
        "                                      meshes and sessions (.strata) into each other\n"
        "  rebuild IN [--method auto|unsubdivide|progressive] [--scheme S] [--target-faces N]\n"
        "          [--max-levels L] -o OUT.strata\n"
        "                                      a dense mesh into a hierarchy with coarse levels\n"
        "  [--scheme S] [--levels N] [--size WxH] [--replay EVENTS.txt] [--screenshot-dir D]\n"
        "  [--compare-dir D] [--mem-budget MIB] [--bench-interaction] [FILE]\n"
        "                                      the modeller window on FILE (default: assets/torus.obj);\n"
        "                                      F1 in the window lists the keys\n"
        "  help                                this text\n"
        "schemes: catmull-clark, loop, butterfly, quad-triangle, sqrt3, doo-sabin\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) return st_cmd_window(0, argv + 1);
    const char *cmd = argv[1];
    if (!strcmp(cmd, "info")) return st_cmd_info(argc - 2, argv + 2);
    if (!strcmp(cmd, "subdivide")) return st_cmd_subdivide(argc - 2, argv + 2);
    if (!strcmp(cmd, "adapt")) return st_cmd_adapt(argc - 2, argv + 2);
    if (!strcmp(cmd, "render")) return st_cmd_render(argc - 2, argv + 2);
    if (!strcmp(cmd, "convert")) return st_cmd_convert(argc - 2, argv + 2);
    if (!strcmp(cmd, "rebuild")) return st_cmd_rebuild(argc - 2, argv + 2);
    if (!strcmp(cmd, "help") || !strcmp(cmd, "--help") || !strcmp(cmd, "-h")) { usage(stdout); return 0; }
    /* Anything else is the modeller: `strata [options] [FILE]`. */
    if (cmd[0] == '-' || access(cmd, F_OK) == 0) return st_cmd_window(argc - 1, argv + 1);
    fprintf(stderr, "strata: unknown command '%s' (and no such file)\n", cmd);
    usage(stderr);
    return 2;
}
