/* strata_example: Strata's kernel (libstrata_core) through its installed
 * public API alone (README.md, "Install").  Build it against an installed
 * strata with pkg-config:
 *
 *   cc strata_example.c $(pkg-config --cflags --libs strata) -o strata_example
 *   ./strata_example IN.obj OUT.obj
 *
 * It loads IN, adds three levels of Catmull-Clark, lifts one vertex of
 * level 1 (the first dart's) by a tenth of the model's diagonal along +z as
 * the modeller's drag does (st_hier_edit: levels 2 and 3 are re-synthesised
 * around it and keep their details; level 0 does not change), and writes
 * level 3 (OBJ, or PLY by OUT's extension).  Exit status 0, or 1 with a
 * message naming the file and the problem. */
#include "core/io/mesh.h"
#include "core/multires/edit.h"
#include "core/multires/hier.h"
#include "core/progressive/scheme_registry.h"

#include <stdio.h>
#include <string.h>

static int fail(const char *what, const st_error *err)
{
    fprintf(stderr, "strata_example: %s: %s\n", what, err->msg);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: strata_example IN OUT.obj\n");
        return 2;
    }
    st_error err;
    st_mesh mesh;
    st_mesh_init(&mesh);
    if (st_mesh_load(argv[1], &mesh, &err)) return fail(argv[1], &err);
    double lift = 0.1 * st_mesh_diagonal(&mesh);

    /* Level 0 from the mesh (boundary rule from its tags), then levels 1..3. */
    st_hier h;
    st_hier_opts opts = { .boundary = ST_BOUNDARY_UNSET };
    int rc = st_hier_init(&h, &mesh, st_scheme_find("catmull-clark"), &opts, &err);
    st_mesh_free(&mesh);
    if (rc) return fail(argv[1], &err);
    if (st_hier_subdivide_to(&h, 3, &err)) {
        st_hier_free(&h);
        return fail(argv[1], &err);
    }

    /* Vertex ids live on every level: v is the same vertex at levels 1..3. */
    uint32_t dart = 0, v = st_vert(&h.map, dart, 1);
    double pos[1][3], before[3];
    memcpy(pos[0], st_pos(&h.map, v, 1), sizeof pos[0]);
    memcpy(before, st_pos(&h.map, v, 3), sizeof before);
    pos[0][2] += lift;
    uint64_t resynth = st_hier_edit(&h, 1, &dart, (const double (*)[3])pos, 1, NULL);
    const double *after = st_pos(&h.map, v, 3);
    printf("edit: vertex %u of level 1 lifted by %g; %llu positions re-synthesised above\n", v, lift,
           (unsigned long long)resynth);
    printf("vertex %u at level 3: %g %g %g -> %g %g %g\n", v, before[0], before[1], before[2], after[0], after[1],
           after[2]);

    st_mesh out;
    st_mesh_init(&out);
    rc = st_hier_level_mesh(&h, 3, &out, &err);
    if (!rc) rc = st_mesh_save(argv[2], &out, &err);
    if (!rc) printf("level 3: %u vertices, %u faces written to %s\n", out.nverts, out.nfaces, argv[2]);
    st_mesh_free(&out);
    st_hier_free(&h);
    return rc ? fail(argv[2], &err) : 0;
}
