/* strata [--scheme S] [--levels N] [--size WxH] [--replay EVENTS.txt]
 *        [--screenshot-dir DIR] [--compare-dir DIR] [--mem-budget MIB]
 *        [--bench-interaction [--bench-steps N]] [FILE]
 * strata --keys
 *
 * Opens the modeller window (ui/window.h) on FILE, or on the default asset
 * (assets/torus.obj).  Exit status: 0, 1 (a replay expectation or a
 * screenshot comparison failed, or a runtime error), 2 (usage), 3 (no
 * display / no OpenGL 3.3 context). */
#include "cli.h"
#include "formats/mesh_any.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef STRATA_UI_BUILT
#include "actions.h"
#include "window.h"
#endif

static void usage(FILE *f)
{
    fprintf(f,
        "usage: strata [--scheme S] [--levels N] [--size WxH] [--strict] [--replay EVENTS.txt]\n"
        "              [--screenshot-dir DIR] [--compare-dir DIR] [--mem-budget MIB] [--no-gui] [--ui-scale S]\n"
        "              [--bench-interaction [--bench-steps N]] [FILE]\n"
        "       strata --keys\n"
        "  opens the modeller window on FILE (default: the torus asset); F1 in the window lists the keys\n"
        "  --no-gui            start with the menus and side panel hidden (F10 shows them)\n"
        "  --strict            refuse meshes with non-manifold edges instead of splitting them (as the commands' --strict)\n"
        "  --ui-scale S        size of the menus and panel (0.5..4; default: the preference, else the monitor's scale)\n"
        "  --replay F          drive the window by the scripted events of F (see ui/replay.h), exit 1 if an expect fails\n"
        "  --screenshot-dir D  where the replay's screenshots go (default .)\n"
        "  --compare-dir D     compare each screenshot with D/NAME.png (exit 1 on a mismatch)\n"
        "  --mem-budget MIB    refuse operations that would make the model larger (default: half the physical memory)\n"
        "  --bench-interaction time a drag of one level-2 vertex on a depth-6 hierarchy (default --levels 6)\n"
        "  --keys              print the key table (docs/MODELLER.md's, from ui/actions.c) as markdown\n");
}

int st_cmd_window(int argc, char **argv)
{
#ifndef STRATA_UI_BUILT
    (void)argc; (void)argv; (void)usage;
    fprintf(stderr, "strata: built without the modeller window (GLFW was not found)\n");
    return 2;
#else
    st_win_opts o;
    memset(&o, 0, sizeof o);
    o.levels = -1;
    o.width = 1100;
    o.height = 750;
    o.bench_steps = 40;
    o.load_mesh = st_any_mesh_load;   /* .gltf and .glb as well as .obj .off .ply */
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { usage(stdout); return 0; }
        if (!strcmp(a, "--bench-interaction")) { o.bench = 1; continue; }
        if (!strcmp(a, "--no-gui")) { o.no_gui = 1; continue; }
        if (!strcmp(a, "--strict")) { o.strict = 1; continue; }
        if (!strcmp(a, "--keys")) { st_actions_markdown(stdout); return 0; }
        if (a[0] != '-') {
            if (o.file) { fprintf(stderr, "strata: one file at a time ('%s' and '%s')\n", o.file, a); return 2; }
            o.file = a;
            continue;
        }
        if (!v) { fprintf(stderr, "strata: %s needs a value\n", a); usage(stderr); return 2; }
        i++;
        if (!strcmp(a, "--scheme")) o.scheme = v;
        else if (!strcmp(a, "--levels")) {
            char *end;
            long n = strtol(v, &end, 10);
            if (end == v || *end || n < 0 || n > 12) { fprintf(stderr, "strata: --levels wants 0..12, got '%s'\n", v); return 2; }
            o.levels = (int)n;
        } else if (!strcmp(a, "--size")) {
            int w = 0, h = 0;
            if (sscanf(v, "%dx%d", &w, &h) != 2 || w < 64 || h < 64 || w > 8192 || h > 8192) {
                fprintf(stderr, "strata: --size wants WxH (64..8192), got '%s'\n", v);
                return 2;
            }
            o.width = w;
            o.height = h;
            o.size_given = 1;
        } else if (!strcmp(a, "--replay")) o.replay = v;
        else if (!strcmp(a, "--screenshot-dir")) o.screenshot_dir = v;
        else if (!strcmp(a, "--compare-dir")) o.compare_dir = v;
        else if (!strcmp(a, "--ui-scale")) {
            char *end;
            double s = strtod(v, &end);
            if (end == v || *end || !(s >= 0.5 && s <= 4)) { fprintf(stderr, "strata: --ui-scale wants 0.5..4, got '%s'\n", v); return 2; }
            o.ui_scale = (float)s;
        }
        else if (!strcmp(a, "--mem-budget")) {
            char *end;
            o.mem_budget_mb = strtod(v, &end);
            if (end == v || *end || !(o.mem_budget_mb > 0)) { fprintf(stderr, "strata: --mem-budget wants MiB > 0, got '%s'\n", v); return 2; }
        } else if (!strcmp(a, "--bench-steps")) {
            o.bench_steps = atoi(v);
            if (o.bench_steps < 1 || o.bench_steps > 100000) { fprintf(stderr, "strata: --bench-steps wants 1..100000\n"); return 2; }
        } else {
            fprintf(stderr, "strata: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
    }
    if (o.bench) return st_window_bench(&o);
    return st_window_main(&o);
#endif
}
