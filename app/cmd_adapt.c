/* strata adapt IN --scheme S --base-level B --max-level M --box x0,y0,z0,x1,y1,z1
 *              [--falloff W] [--flatness T] [--no-restriction] [--triangulate | --access] -o OUT
 * Writes the adaptive polygon mesh (or its triangulation by the renderer's
 * case tables).  --access builds the regular hierarchy to the maximum level
 * instead and reads the same mesh off it with marker bits (core/adapt/access.h,
 * thesis §3.3.2): the structure is not changed. */
#include "core/adapt/access.h"
#include "core/adapt/adapt.h"
#include "cli.h"
#include "core/adapt/adapt_estimate.h"
#include "core/base/membudget.h"
#include "cli_common.h"
#include "formats/mesh_any.h"
#include "render/geom.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int parse_box(const char *s, st_adapt_params *p)
{
    if (st_cli_parse_box(s, p->box_lo, p->box_hi)) return -1;
    p->has_box = 1;
    return 0;
}

static int parse_number(const char *s, double *out)
{
    char *end;
    *out = strtod(s, &end);
    return end == s || *end ? -1 : 0;
}

/* Adapt-only options out of argv; the rest goes to the common parser. */
static int parse_adapt(int argc, char **argv, st_adapt_params *p, int *tri, int *access, char **rest, int *nrest)
{
    memset(p, 0, sizeof *p);
    p->max_level = 3;
    *tri = 0;
    *access = 0;
    *nrest = 0;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double x;
        if (!strcmp(a, "--base-level") && v && !parse_number(v, &x) && x >= 0 && x < ST_MAX_LEVELS) { p->base_level = (unsigned)x; i++; }
        else if (!strcmp(a, "--max-level") && v && !parse_number(v, &x) && x >= 0 && x < ST_MAX_LEVELS) { p->max_level = (unsigned)x; i++; }
        else if (!strcmp(a, "--box") && v && !parse_box(v, p)) i++;
        else if (!strcmp(a, "--falloff") && v && !parse_number(v, &p->falloff) && p->falloff >= 0) i++;
        else if (!strcmp(a, "--flatness") && v && !parse_number(v, &p->flatness) && p->flatness >= 0) i++;
        else if (!strcmp(a, "--no-restriction")) p->no_restriction = 1;
        else if (!strcmp(a, "--triangulate")) *tri = 1;
        else if (!strcmp(a, "--access")) *access = 1;
        else if (!strcmp(a, "--base-level") || !strcmp(a, "--max-level") || !strcmp(a, "--box") ||
                 !strcmp(a, "--falloff") || !strcmp(a, "--flatness")) {
            fprintf(stderr, "strata adapt: bad or missing value for %s%s%s\n", a, v ? ": " : "", v ? v : "");
            return -1;
        } else rest[(*nrest)++] = argv[i];
    }
    if (p->base_level > p->max_level) { fprintf(stderr, "strata adapt: --base-level is above --max-level\n"); return -1; }
    if (*tri && *access) { fprintf(stderr, "strata adapt: --triangulate and --access do not go together\n"); return -1; }
    return 0;
}

/* The renderer's corner UVs (single precision, as it draws them) of the
 * triangles, one texture coordinate per corner. */
static int triangle_uvs(const st_rgeom *g, const st_map *m, const st_uv_map *uv, st_mesh *r)
{
    size_t nc = 3 * (size_t)g->ntris;
    float *f = malloc((2 * nc + 1) * sizeof *f);
    r->uv = malloc((2 * nc + 1) * sizeof *r->uv);
    r->face_uv = malloc((nc + 1) * sizeof *r->face_uv);
    if (!f || !r->uv || !r->face_uv) { free(f); return -1; }
    st_rgeom_corner_uvs(g, m, uv, f);
    for (size_t i = 0; i < 2 * nc; i++) r->uv[i] = f[i];
    for (size_t i = 0; i < nc; i++) r->face_uv[i] = (uint32_t)i;
    r->nuvs = (uint32_t)nc;
    free(f);
    return 0;
}

/* The triangles the renderer would draw, as a soup (map positions), with
 * the adaptive mesh's UVs when uv is not NULL. */
static int triangulated(const st_map *m, unsigned level, const double *uv, st_mesh *out, st_error *err)
{
    st_rgeom g;
    st_rgeom_init(&g);
    int rc = st_rgeom_build(&g, m, level, err);
    if (rc) return rc;
    st_mesh r;
    st_mesh_init(&r);
    r.nverts = g.nverts;
    r.nfaces = g.ntris;
    r.pos = malloc((size_t)(g.nverts ? g.nverts : 1) * 3 * sizeof *r.pos);
    r.face_off = malloc(((size_t)g.ntris + 1) * sizeof *r.face_off);
    r.face_idx = malloc((size_t)(g.ntris ? g.ntris : 1) * 3 * sizeof *r.face_idx);
    if (!r.pos || !r.face_off || !r.face_idx) { st_mesh_free(&r); st_rgeom_free(&g); return st_fail(err, ST_ERR_MEMORY, "out of memory"); }
    for (uint32_t v = 0; v < g.nverts; v++) memcpy(r.pos + 3 * (size_t)v, st_pos(m, g.vid[v], level), 3 * sizeof(double));
    for (uint32_t t = 0; t <= g.ntris; t++) r.face_off[t] = 3 * t;
    memcpy(r.face_idx, g.tris, (size_t)g.ntris * 3 * sizeof *r.face_idx);
    st_uv_map um = { uv, NULL, m->darts.end };
    if (uv && triangle_uvs(&g, m, &um, &r)) { st_mesh_free(&r); st_rgeom_free(&g); return st_fail(err, ST_ERR_MEMORY, "out of memory"); }
    st_rgeom_free(&g);
    st_mesh_move(out, &r);
    return ST_OK;
}

/* --access: the regular hierarchy to max_level, read adaptively. */
static int access_mesh(st_hier *h, const st_adapt_params *p, st_mesh *out, st_error *err)
{
    int rc = st_hier_subdivide_to(h, p->max_level, err);
    st_access_stats st;
    if (!rc) rc = st_access_mesh(h, p, out, &st, err);
    if (!rc) {
        printf("adaptive access (marker bits) of the regular levels 0..%u: faces shown per level:", h->map.top);
        for (unsigned l = 0; l <= h->map.top; l++) printf(" %llu", (unsigned long long)st.faces_per_level[l]);
        printf("; %llu opened by the restriction\n", (unsigned long long)st.forced);
    }
    return rc;
}

int st_cmd_adapt(int argc, char **argv)
{
    st_adapt_params p;
    int tri, access, nrest;
    char **rest = malloc((size_t)(argc + 1) * sizeof *rest);
    if (!rest || parse_adapt(argc, argv, &p, &tri, &access, rest, &nrest)) { free(rest); return 2; }
    st_cli_opts o;
    int bad = st_cli_parse(nrest, rest, &o, "adapt");
    free(rest);
    if (bad) return 2;
    if (!o.out) { fprintf(stderr, "strata adapt: -o OUT is required\n"); return 2; }
    if (!p.has_box && p.flatness <= 0 && p.base_level == 0)
        fprintf(stderr, "strata adapt: no --box and no --flatness: the result is level %u everywhere\n", p.base_level);
    o.levels = 0;
    st_hier h;
    int rc = st_cli_load(&o, &h, "adapt");
    if (rc) return rc;
    st_adapt a;
    st_error err;
    st_mesh out;
    st_mesh_init(&out);
    memset(&a, 0, sizeof a);
    if (access) {
        rc = access_mesh(&h, &p, &out, &err);
    } else {
        /* the memory guard, from level 0, before anything is built */
        rc = st_mem_check(st_adapt_estimate_bytes(&h, &p), "the adaptive refinement", &err);
        if (!rc) rc = st_adapt_init(&a, &h, &err);
        if (!rc) rc = st_adapt_update(&a, &p, &err);
        if (!rc) rc = st_map_validate(&h.map, &err);
        unsigned shown = 0;
        const st_map *sm = rc ? NULL : st_adapt_display_map(&a, &shown); /* a progressive hierarchy's: its own map */
        if (!rc && !sm) rc = st_fail(&err, ST_ERR_MEMORY, "out of memory for the adaptive mesh");
        if (!rc && sm != &h.map) rc = st_map_validate((st_map *)sm, &err);
        st_adapt_uv u = { 0 };
        if (!rc && tri) rc = st_adapt_uv_build(&a, &u, &err);
        /* the second check, from the adaptive map's counts, before the mesh is made */
        if (!rc) rc = st_mem_check(st_adapt_estimate_mesh_bytes(&a), "the adaptive mesh", &err);
        if (!rc) rc = tri ? triangulated(sm, shown, u.uv, &out, &err) : st_adapt_mesh(&a, &out, &err);
        st_adapt_uv_free(&u);
    }
    if (!rc && st_hier_has_uv(&h, 0) && !out.face_uv) {
        const char *why = access ? "a level of the regular hierarchy has none" : st_adapt_uv_absent(&a);
        fprintf(stderr, "strata adapt: note: %s has UVs; %s: %s is written without\n", o.in, why ? why : "?", o.out);
    }
    if (!rc) rc = st_any_mesh_save(o.out, &out, &err);
    if (rc) fprintf(stderr, "strata: %s: %s\n", o.in, err.msg);
    else {
        char lv[48];
        printf("%s: %u %s, %u vertices, %s\n", o.out, out.nfaces - st_mesh_hole_faces(&out),
               tri ? "triangles" : "faces", out.nverts, st_levels_phrase(h.map.top, lv, sizeof lv));
    }
    st_mesh_free(&out);
    st_adapt_free(&a);
    st_hier_free(&h);
    return rc ? 1 : 0;
}
