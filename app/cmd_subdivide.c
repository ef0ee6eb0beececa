/* strata subdivide IN --scheme S --levels N [--level L] [--boundary B] -o OUT */
#include "cli.h"
#include "cli_common.h"
#include "formats/mesh_any.h"
#include "core/io/level_ply.h"
#include "core/io/session.h"

#include <stdio.h>

/* The synthesis tables (st_hier.cache) serve later syntheses; the command
 * writes one level and exits: their memory goes back before the writer
 * takes its own. */
static void drop_synthesis_caches(st_hier *h)
{
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
        if (h->cache[l].p) {
            h->cache[l].free(h->cache[l].p);
            h->cache[l].p = NULL;
        }
}

int st_cmd_subdivide(int argc, char **argv)
{
    st_cli_opts o;
    if (st_cli_parse(argc, argv, &o, "subdivide")) return 2;
    if (!o.out) { fprintf(stderr, "strata subdivide: -o OUT is required\n"); return 2; }
    if (o.level > (int)o.levels && !st_session_is_path(o.in)) {
        fprintf(stderr, "strata subdivide: --level %d is above --levels %u\n", o.level, o.levels);
        return 2;
    }
    st_hier h;
    int rc = st_cli_load(&o, &h, "subdivide");
    if (rc) return rc;
    unsigned level;
    if (st_cli_level(&o, &h, "subdivide", &level)) { st_hier_free(&h); return 2; }
    st_error err;
    drop_synthesis_caches(&h);
    if (st_path_has_ext(o.out, ".ply")) {
        /* Straight from the map: no copy of the level (core/io/level_ply.h). */
        rc = st_hier_level_save_ply(&h, level, o.out, &err);
    } else if (st_path_has_ext(o.out, ".obj")) {
        rc = st_hier_level_save_obj(&h, level, o.out, &err);
    } else {
        st_mesh out;
        st_mesh_init(&out);
        rc = st_hier_level_mesh(&h, level, &out, &err);
        if (!rc) rc = st_any_mesh_save(o.out, &out, &err);
        st_mesh_free(&out);
    }
    if (rc) fprintf(stderr, "strata: %s\n", err.msg);
    st_hier_free(&h);
    return rc ? 1 : 0;
}
