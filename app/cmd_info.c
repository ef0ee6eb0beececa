/* strata info FILE [--scheme S --levels N]: the per-level table, and for
 * a session with an HD hierarchy (core/io/session.h) its levels above the
 * model. */
#include "cli.h"
#include "cli_common.h"
#include "core/adapt/adapt.h"
#include "core/map/map_memory.h"
#include "core/multires/estimate.h"
#include "core/io/session.h"
#include "core/progressive/progressive.h"

#include <stdio.h>
#include <stdlib.h>

/* Faces the adaptive map stores at level l: real faces of the map of
 * level l whose subdivision level there is l, each counted once. */
static uint64_t hd_faces_at(st_map *m, unsigned l)
{
    int fb = st_marker_reserve(m);
    if (fb < 0) return 0;
    uint64_t n = 0;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, l);
        n += st_face_level(m, d, l) == l;
    }
    st_marker_release(m, fb, l);
    return n;
}

/* The HD levels above the model's top N: the faces stored at each level,
 * an estimate of the bytes that level holds (the darts and vertices
 * inserted at it - their relations, flags and positions, and the level's
 * columns, as the table above counts - plus the level's detail array), and
 * the faces the same depth would have uniform: the faces of level N (the
 * model's, which the HD map shares) times g^(L-N), g = 4 (3 for sqrt3) - exact for Catmull-Clark on quads
 * and Loop on triangles, an estimate where faces of another kind split. */
static void print_hd(st_session *s)
{
    st_hier *hd = &s->hd;
    st_map *m = &hd->map;
    unsigned n = s->hd_from;
    uint64_t g = hd->scheme->id == ST_SCHEME_SQRT3 ? 3 : 4;
    char lv[48];
    printf("HD hierarchy: %s, levels 0..%u the model's, %s\n", st_levels_phrase(m->top, lv, sizeof lv), n,
           m->top > n ? "adaptive above" : "nothing above");
    printf("%5s %12s %14s %16s\n", "level", "HD faces", "HD bytes", "uniform faces");
    st_level_stats base;
    st_level_stats_compute(m, n, &base);
    double uniform = (double)base.faces;
    for (unsigned l = n + 1; l <= m->top; l++) {
        uniform *= (double)g;
        st_map_bytes b;
        st_map_level_memory(m, l, &b);
        size_t bytes = b.topology + b.positions + (hd->detail[l] ? (size_t)hd->detail_cap[l] * 3 * sizeof(double) : 0);
        printf("%5u %12llu %14zu %16.0f\n", l, (unsigned long long)hd_faces_at(m, l), bytes, uniform);
    }
    printf("HD bytes: darts and vertices inserted at the level (topology, positions) and its details; uniform faces: "
           "level %u's faces x %llu per level (an estimate, exact for Catmull-Clark on quads)\n", n, (unsigned long long)g);
    for (uint32_t i = 0; i < s->hd_layers.n; i++) {
        const st_layer *y = &s->hd_layers.v[i];
        printf("HD sculpt layer '%s': level %u, strength %.2f%s\n", y->name, y->level, y->strength,
               y->hidden ? ", hidden" : "");
    }
}

int st_cmd_info(int argc, char **argv)
{
    st_cli_opts o;
    if (st_cli_parse(argc, argv, &o, "info")) return 2;
    /* A session keeps its HD hierarchy for the table below; a mesh is
     * loaded without its base copy (st_cli_load), which would add to the
     * levels' peak. */
    st_session sess;
    st_session_init(&sess);
    st_hier h;
    int rc;
    if (st_session_is_path(o.in)) {
        rc = st_cli_load_session(&o, &sess, "info");
        if (rc) return rc;
        st_session_move_hier(&h, &sess.h);
    } else if ((rc = st_cli_load(&o, &h, "info"))) return rc;
    st_map *m = &h.map;
    char lv[48];
    printf("%s: scheme %s, %s\n", o.in, h.scheme->name, st_levels_phrase(m->top, lv, sizeof lv));
    printf("%5s %10s %10s %10s %8s %6s %14s %14s\n", "level", "vertices", "edges", "faces", "holes", "euler",
           "topology B", "positions B");
    /* Levels refined here from a mesh, or regenerated from a session's
     * level 0, are whole refinements of the level below: their counts
     * follow by arithmetic (core/multires/estimate.h, equal to the walked
     * counts on every scheme: tests/core/test_membudget.c), which costs
     * nothing beside refinement; a progressive hierarchy's as its build
     * left it follow from its pools (st_progressive_level_counts).  Other
     * sessions' levels may be adaptive or rebased: walked. */
    st_level_stats *pm = malloc(((size_t)m->top + 1) * sizeof *pm);
    int counted = pm && st_progressive_level_counts(&h, pm) == 0;
    int arithmetic = !counted && (!st_session_is_path(o.in) || st_hier_regenerable(&h));
    uint64_t triangles = arithmetic ? st_level_triangles(m, 0) : 0;
    st_level_stats s, top;
    for (unsigned l = 0; l <= m->top; l++) {
        if (counted) s = pm[l];
        else if (l == 0 || !arithmetic) st_level_stats_compute(m, l, &s);
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
    if (sess.has_hd) print_hd(&sess);
    free(pm);
    st_session_free(&sess);
    st_hier_free(&h);
    return 0;
}
