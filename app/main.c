/* strata: one executable, subcommands. */
#include "cli.h"
#include "core/base/membudget.h"

#include <signal.h>
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
        "        [--falloff W] [--flatness T] [--no-restriction] [--triangulate | --access] -o OUT\n"
        "                                      writes the adaptive mesh (interest box)\n"
        "  render IN [--scheme S --levels N --level L | --box x0,y0,z0,x1,y1,z1 --base-level B --max-level M]\n"
        "         [--view front|back|left|right|top|iso | --orbit AZ,EL,DIST] [--mode smooth|flat|wire|cage|uv]\n"
        "         [--size WxH] [--normal-map N.png [--normal-space tangent|object]] [--auto-uv] -o OUT.png\n"
        "                                      draws level L (or the interest box's adaptive mesh) headless\n"
        "                                      (no display, no GPU) into a PNG\n"
        "  convert IN OUT [--scheme S --levels N --level L | --box x0,y0,z0,x1,y1,z1 --base-level B --max-level M]\n"
        "          [--falloff W] [--no-restriction] [--boundary B] [--normals | --no-normals] [--normal-map N.png [--auto-uv]]\n"
        "                                      meshes and sessions (.strata) into each other\n"
        "  (info, subdivide, render, convert, adapt: [--uv-interp none|corners-only|corners-plus1|\n"
        "   corners-plus2|boundaries|all], how UVs are subdivided; default corners-plus1)\n"
        "  rebuild IN [--method auto|unsubdivide|progressive] [--scheme S] [--target-faces N]\n"
        "          [--max-levels L] [--uv-interp I] -o OUT.strata\n"
        "                                      a dense mesh into a hierarchy with coarse levels\n"
        "  [--scheme S] [--levels N] [--size WxH] [--replay EVENTS.txt] [--screenshot-dir D]\n"
        "  [--compare-dir D] [--mem-budget MIB] [--no-gui] [--ui-scale S] [--bench-interaction] [FILE]\n"
        "                                      the modeller window on FILE (default: assets/torus.obj);\n"
        "                                      F1 in the window lists the keys, as strata --keys does\n"
        "  deform IN --level L --bump CX,CY,CZ,R,DX,DY,DZ [--box x0,y0,z0,x1,y1,z1] [--scheme S --levels N] -o OUT.strata\n"
        "                                      moves each vertex v of level L by D*exp(-|v-C|^2/R^2), one edit\n"
        "                                      as in the window (finer levels keep their details); L above the\n"
        "                                      top: an HD level, refined inside --box\n"
        "  filter IN.strata --gains g0,g1,... -o OUT\n"
        "                                      scales the details of each level of a progressive hierarchy\n"
        "  bake IN --base-level B [--level L] --normal-map N.png [--displacement-map D.exr|D.png]\n"
        "       [--size 2048] [--space tangent|object] [--vector] [--padding 8] [--bits 8|16] [--auto-uv] [--ray-reach D]\n"
        "       [--udim auto|on|off]\n"
        "                                      bakes level L onto level B's UV layout as maps (a session with\n"
        "                                      HD levels: from its HD top by default)\n"
        "  help                                this text\n"
        "every command that reads a mesh takes --strict: refuse an edge shared by 3 or more faces (by default\n"
        "it is split: the faces beyond the first two get their own copies of its vertices, with a note)\n"
        "every command takes --mem-budget MIB: operations whose estimated memory would exceed it are refused\n"
        "(default: 3/4 of the memory available at start)\n"
        "schemes: catmull-clark, loop, butterfly, quad-triangle, sqrt3, doo-sabin\n");
}

/* --mem-budget MIB anywhere on a subcommand's line sets the process-wide
 * budget (core/base/membudget.h) and is taken out of argv.  The window keeps
 * the option: its document counts the model's own bytes against it (ui/),
 * while the process budget stays at its default there.  Returns -1 after a
 * message when the value is not a positive number. */
static int take_mem_budget(int *argc, char **argv, int keep)
{
    int out = 0;
    for (int i = 0; i < *argc; i++) {
        if (!strcmp(argv[i], "--mem-budget") && i + 1 < *argc) {
            size_t bytes;
            if (st_mem_parse_mib(argv[i + 1], &bytes)) {
                fprintf(stderr, "strata: --mem-budget wants MiB > 0, got '%s'\n", argv[i + 1]);
                return -1;
            }
            if (!keep) { st_mem_budget_set(bytes); i++; continue; }
        }
        argv[out++] = argv[i];
    }
    *argc = out;
    return 0;
}

int main(int argc, char **argv)
{
    /* A write past the file-size limit (ulimit -f) fails with EFBIG and is
     * reported, the old file kept (core/io/atomic_file.h), instead of the
     * signal killing the process with a half-written temporary. */
    signal(SIGXFSZ, SIG_IGN);
    if (argc < 2) return st_cmd_window(0, argv + 1);
    const char *cmd = argv[1];
    static const char *const subcommands[] = { "info", "subdivide", "adapt", "render", "convert", "filter", "rebuild", "bake", "deform", "help" };
    int window = 1;
    for (size_t i = 0; i < sizeof subcommands / sizeof subcommands[0]; i++)
        if (!strcmp(cmd, subcommands[i])) window = 0;
    if (take_mem_budget(&argc, argv, window)) return 2;
    if (!strcmp(cmd, "info")) return st_cmd_info(argc - 2, argv + 2);
    if (!strcmp(cmd, "subdivide")) return st_cmd_subdivide(argc - 2, argv + 2);
    if (!strcmp(cmd, "adapt")) return st_cmd_adapt(argc - 2, argv + 2);
    if (!strcmp(cmd, "render")) return st_cmd_render(argc - 2, argv + 2);
    if (!strcmp(cmd, "convert")) return st_cmd_convert(argc - 2, argv + 2);
    if (!strcmp(cmd, "filter")) return st_cmd_filter(argc - 2, argv + 2);
    if (!strcmp(cmd, "rebuild")) return st_cmd_rebuild(argc - 2, argv + 2);
    if (!strcmp(cmd, "bake")) return st_cmd_bake(argc - 2, argv + 2);
    if (!strcmp(cmd, "deform")) return st_cmd_deform(argc - 2, argv + 2);
    if (!strcmp(cmd, "help") || !strcmp(cmd, "--help") || !strcmp(cmd, "-h")) { usage(stdout); return 0; }
    /* Anything else is the modeller: `strata [options] [FILE]`. */
    if (cmd[0] == '-' || access(cmd, F_OK) == 0) return st_cmd_window(argc - 1, argv + 1);
    fprintf(stderr, "strata: unknown command '%s' (and no such file)\n", cmd);
    usage(stderr);
    return 2;
}
