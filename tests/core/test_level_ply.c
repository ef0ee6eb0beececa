/* st_hier_level_save_ply and st_hier_level_save_obj (core/io/level_ply.h)
 * write the bytes of the soup path, st_hier_level_mesh + st_mesh_save_ply
 * or st_mesh_save_obj: with and without UVs, with
 * hole faces, on boundaries, at every level, for primal and dual schemes,
 * with a face of more than 255 corners, on progressive hierarchies (whose
 * relations the writer reads through the general lookup path); and refuses
 * a level with a non-finite position as the soup path does, with the same
 * message, leaving no file. */
#include "testlib.h"
#include "core/io/level_ply.h"
#include "core/multires/hier.h"
#include "core/progressive/progressive.h"
#include "core/progressive/scheme_registry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MESHES STRATA_SHARED_DATA "/"

static char direct_path[256], soup_path[256], direct_obj[256], soup_obj[256];

static int same_files(const char *a, const char *b)
{
    size_t na, nb;
    char *x = tl_read_file(a, &na), *y = tl_read_file(b, &nb);
    int same = x && y && na == nb && !memcmp(x, y, na);
    free(x);
    free(y);
    return same;
}

/* Compares both writers at every level of h. */
static void check_levels(st_hier *h, const char *name, const char *scheme)
{
    st_error err;
    for (unsigned l = 0; l <= h->map.top; l++) {
        CHECKF(!st_hier_level_save_ply(h, l, direct_path, &err), "%s level %u: %s", name, l, err.msg);
        CHECKF(!st_hier_level_save_ply_soup(h, l, soup_path, &err), "%s level %u: %s", name, l, err.msg);
        CHECKF(same_files(direct_path, soup_path), "%s %s level %u: the two writers differ", name, scheme, l);
        CHECKF(!st_hier_level_save_obj(h, l, direct_obj, &err), "%s level %u: %s", name, l, err.msg);
        CHECKF(!st_hier_level_save_obj_soup(h, l, soup_obj, &err), "%s level %u: %s", name, l, err.msg);
        CHECKF(same_files(direct_obj, soup_obj), "%s %s level %u: the two OBJ writers differ", name, scheme, l);
    }
}

/* Builds `levels` levels of the mesh at path and compares both writers at
 * every level. */
static void check_mesh(const char *name, const char *path, const char *scheme, unsigned levels)
{
    st_mesh mesh;
    st_error err;
    st_mesh_init(&mesh);
    CHECKF(!st_mesh_load(path, &mesh, &err), "%s: %s", name, err.msg);
    st_hier h;
    st_hier_opts o = { .boundary = ST_BOUNDARY_UNSET, .crease_method = ST_CREASE_UNIFORM, .uv_interp = ST_UV_CORNERS_PLUS1 };
    int rc = st_hier_init(&h, &mesh, st_scheme_find(scheme), &o, &err);
    st_mesh_free(&mesh);
    CHECKF(!rc, "%s: %s", name, err.msg);
    if (rc) return;
    CHECKF(!st_hier_subdivide_to(&h, levels, &err), "%s: %s", name, err.msg);
    check_levels(&h, name, scheme);
    st_hier_free(&h);
}

/* A disc of one 300-gon (face records with a uint size) with a triangle on
 * one of its sides. */
static const char *wide_face(void)
{
    static char path[256];
    snprintf(path, sizeof path, "/tmp/test_level_ply_%d_wide.obj", (int)getpid());
    FILE *f = fopen(path, "wb");
    if (!f) return path;
    for (int i = 0; i < 300; i++) fprintf(f, "v %.17g %.17g 0\n", cos(i * 2 * M_PI / 300), sin(i * 2 * M_PI / 300));
    fprintf(f, "v 0.5 -0.01 -1\nf");
    for (int i = 1; i <= 300; i++) fprintf(f, " %d", i);
    fprintf(f, "\nf 2 1 301\n");
    fclose(f);
    return path;
}

/* Levels made by edge collapses (thesis ch. 4): relations with columns for
 * β1 and vert. */
static void check_progressive(void)
{
    st_mesh fine;
    st_error err;
    st_mesh_init(&fine);
    CHECKF(!st_mesh_load(MESHES "triangle/hemisphere.obj", &fine, &err), "hemisphere: %s", err.msg);
    st_hier h;
    st_progressive_opts po = { .target_faces = 60 };
    int rc = st_progressive_build(&fine, &po, &h, NULL, &err);
    st_mesh_free(&fine);
    CHECKF(rc == ST_OK, "progressive hemisphere: %s", err.msg);
    if (rc) return;
    CHECK(h.map.top >= 2);
    check_levels(&h, "progressive hemisphere", "progressive");
    st_hier_free(&h);
}

/* A hole-tagged copy of a mesh with UVs. */
static const char *with_holes(const char *src)
{
    static char path[256];
    snprintf(path, sizeof path, "/tmp/test_level_ply_%d_holes.obj", (int)getpid());
    size_t n;
    char *text = tl_read_file(src, &n);
    FILE *f = fopen(path, "wb");
    if (!text || !f) { free(text); if (f) fclose(f); return src; }
    fwrite(text, 1, n, f);
    fputs("\nt hole 3/0/0 5 17 200\n", f);
    fclose(f);
    free(text);
    return path;
}

static void check_not_finite(void)
{
    st_mesh mesh;
    st_error e1, e2;
    tl_mesh_cube(&mesh);
    st_hier h;
    int rc = st_hier_init(&h, &mesh, st_scheme_find("catmull-clark"), NULL, &e1);
    st_mesh_free(&mesh);
    CHECK(!rc);
    if (rc) return;
    CHECK(!st_hier_subdivide_to(&h, 1, &e1));
    st_dart_iter it;
    uint32_t v = st_vertex_first(&h.map, 1, &it);
    v = st_vertex_next(&h.map, 1, &it);
    double *p = (double *)st_pos(&h.map, v, 1);
    p[1] = NAN;
    remove(direct_path);
    remove(soup_path);
    CHECK(st_hier_level_save_ply(&h, 1, direct_path, &e1) != 0);
    CHECK(st_hier_level_save_ply_soup(&h, 1, soup_path, &e2) != 0);
    CHECK(e1.code == e2.code);
    CHECKF(!strcmp(e1.msg, e2.msg) || (strstr(e1.msg, "vertex 1 is not finite") && strstr(e2.msg, "vertex 1 is not finite")),
           "messages '%s' and '%s'", e1.msg, e2.msg);
    CHECK(access(direct_path, F_OK) != 0);
    remove(direct_obj);
    CHECK(st_hier_level_save_obj(&h, 1, direct_obj, &e1) != 0);
    CHECK(st_hier_level_save_obj_soup(&h, 1, soup_obj, &e2) != 0);
    CHECKF(e1.code == e2.code && strstr(e1.msg, "vertex 1 is not finite") && strstr(e2.msg, "vertex 1 is not finite"),
           "OBJ messages '%s' and '%s'", e1.msg, e2.msg);
    CHECK(access(direct_obj, F_OK) != 0);
    st_hier_free(&h);
}

int main(void)
{
    snprintf(direct_path, sizeof direct_path, "/tmp/test_level_ply_%d_direct.ply", (int)getpid());
    snprintf(soup_path, sizeof soup_path, "/tmp/test_level_ply_%d_soup.ply", (int)getpid());
    snprintf(direct_obj, sizeof direct_obj, "/tmp/test_level_ply_%d_direct.obj", (int)getpid());
    snprintf(soup_obj, sizeof soup_obj, "/tmp/test_level_ply_%d_soup.obj", (int)getpid());
    check_mesh("spot (UVs)", MESHES "catmull_clark/spot_quadrangulated.obj", "catmull-clark", 2);
    const char *holes = with_holes(MESHES "catmull_clark/spot_quadrangulated.obj");
    check_mesh("spot with holes (UVs)", holes, "catmull-clark", 2);
    check_mesh("grid_holes", MESHES "edge_cases/grid_holes.obj", "catmull-clark", 2);
    check_mesh("plane_holes", MESHES "triangle/plane_holes.obj", "loop", 2);
    const char *tri_holes = with_holes(MESHES "triangle/hemisphere.obj");
    check_mesh("hemisphere with holes", tri_holes, "loop", 2);
    remove(tri_holes);
    const char *wide = wide_face();
    check_mesh("300-gon", wide, "catmull-clark", 1);
    remove(wide);
    check_progressive();
    check_mesh("hemisphere", MESHES "triangle/hemisphere.obj", "butterfly", 2);
    check_mesh("spot_low_resolution", MESHES "triangle/spot_low_resolution.obj", "loop", 2);
    check_mesh("dodecahedron", MESHES "catmull_clark/dodecahedron_poly.obj", "quad-triangle", 2);
    check_mesh("dodecahedron", MESHES "catmull_clark/dodecahedron_poly.obj", "doo-sabin", 2);
    check_mesh("hemisphere", MESHES "triangle/hemisphere.obj", "sqrt3", 2);
    check_not_finite();
    remove(holes);
    remove(direct_path);
    remove(soup_path);
    remove(direct_obj);
    remove(soup_obj);
    return TEST_END();
}
