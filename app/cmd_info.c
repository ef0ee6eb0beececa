/* strata info FILE [--scheme S --levels N]: the per-level table. */
#include "cli.h"
#include "map.h"
#include "map_mesh.h"
#include "mesh.h"
#include "refine.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void print_level(st_map *m, unsigned l)
{
    st_level_stats s;
    st_level_stats_compute(m, l, &s);
    printf("%5u %10llu %10llu %10llu %8llu %6lld\n", l, (unsigned long long)s.vertices,
           (unsigned long long)s.edges, (unsigned long long)s.faces,
           (unsigned long long)s.boundary_loops, (long long)s.euler);
}

int st_cmd_info(int argc, char **argv)
{
    const char *path = NULL, *scheme = NULL;
    unsigned levels = 0;
    for (int i = 0; i < argc; i++) {
        if (!strcmp(argv[i], "--scheme") && i + 1 < argc) scheme = argv[++i];
        else if (!strcmp(argv[i], "--levels") && i + 1 < argc) levels = (unsigned)atoi(argv[++i]);
        else if (argv[i][0] == '-') { fprintf(stderr, "strata info: unknown option '%s'\n", argv[i]); return 2; }
        else path = argv[i];
    }
    if (!path) { fprintf(stderr, "usage: strata info FILE [--scheme S --levels N]\n"); return 2; }
    st_mesh mesh;
    st_error err;
    st_mesh_init(&mesh);
    if (st_mesh_load(path, &mesh, &err)) { fprintf(stderr, "strata: %s\n", err.msg); return 1; }
    st_map m;
    st_map_init(&m);
    int rc = st_map_from_mesh(&m, &mesh, &err);
    st_mesh_free(&mesh);
    if (rc) { fprintf(stderr, "strata: %s: %s\n", path, err.msg); return 1; }
    enum st_split_mode mode = ST_SPLIT_POLY;
    if (scheme && !strcmp(scheme, "loop")) mode = ST_SPLIT_TRI;
    for (unsigned k = 0; k < levels; k++)
        if (st_refine_uniform(&m, mode, &err)) { fprintf(stderr, "strata: %s: %s\n", path, err.msg); st_map_free(&m); return 1; }
    printf("%s\n%5s %10s %10s %10s %8s %6s\n", path, "level", "vertices", "edges", "faces", "holes", "euler");
    for (unsigned l = 0; l <= m.top; l++) print_level(&m, l);
    st_map_bytes b;
    st_map_memory(&m, &b);
    printf("memory: topology %zu bytes, positions %zu bytes\n", b.topology, b.positions);
    st_map_free(&m);
    return 0;
}
