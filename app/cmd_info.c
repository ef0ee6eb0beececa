/* strata info FILE [--scheme S --levels N]: the per-level table. */
#include "cli.h"
#include "cli_common.h"
#include "core/map/map_memory.h"
#include "core/multires/estimate.h"
#include "core/io/session.h"

#include <stdio.h>

int st_cmd_info(int argc, char **argv)
{
    st_cli_opts o;
    if (st_cli_parse(argc, argv, &o, "info")) return 2;
    st_hier h;
    int rc = st_cli_load(&o, &h, "info");
    if (rc) return rc;
    st_map *m = &h.map;
    char lv[48];
    printf("%s: scheme %s, %s\n", o.in, h.scheme->name, st_levels_phrase(m->top, lv, sizeof lv));
    printf("%5s %10s %10s %10s %8s %6s %14s %14s\n", "level", "vertices", "edges", "faces", "holes", "euler",
           "topology B", "positions B");
    /* Levels refined here from a mesh are whole refinements of the level
     * below: their counts follow by arithmetic (core/multires/estimate.h,
     * equal to the walked counts on every scheme: tests/core/test_membudget.c),
     * which costs nothing beside refinement.  A session's levels may be
     * adaptive or rebased: walked. */
    int arithmetic = !st_session_is_path(o.in);
    uint64_t triangles = arithmetic ? st_level_triangles(m, 0) : 0;
    st_level_stats s, top;
    for (unsigned l = 0; l <= m->top; l++) {
        if (l == 0 || !arithmetic) st_level_stats_compute(m, l, &s);
        else { st_level_stats prev = s; st_estimate_next_level(h.scheme->id, l, &prev, &triangles, &s); }
        st_map_bytes lb;
        st_map_level_memory(m, l, &lb);
        printf("%5u %10llu %10llu %10llu %8llu %6lld %14zu %14zu\n", l, (unsigned long long)s.vertices,
               (unsigned long long)s.edges, (unsigned long long)s.faces,
               (unsigned long long)s.boundary_loops, (long long)s.euler, lb.topology, lb.positions);
        top = s;
    }
    st_map_bytes b;
    st_map_memory(m, &b);
    printf("memory, all levels (allocated): topology %zu bytes (%.2f per finest dart), positions %zu bytes\n", b.topology,
           top.darts ? (double)b.topology / (double)top.darts : 0.0, b.positions);
    st_hier_free(&h);
    return 0;
}
