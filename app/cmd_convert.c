/* strata convert IN OUT [--scheme S] [--levels N] [--level L] [--boundary B]
 *                       [--box x0,y0,z0,x1,y1,z1 [--base-level B] [--max-level M]
 *                        [--falloff W] [--no-restriction]]
 *                       [--normals | --no-normals] [--normal-map N.png [--auto-uv]] [--strict]
 *
 * IN: a mesh (.obj .off .ply .gltf .glb, formats/mesh_any.h) or a session
 * (.strata).  OUT: a mesh (.obj .ply .gltf .glb) or a session (.strata).
 *   - mesh -> session: builds the hierarchy (--scheme, default catmull-clark;
 *     --levels, default 0) or, with --box, the adaptive hierarchy, and saves
 *     it with the base mesh; the displayed level is the top.
 *   - session -> mesh: writes level --level, by default the top level, or
 *     the adaptive mesh when the session's interest box is on (or --box is
 *     given, which re-runs the adaptive refinement with that box).  A
 *     session with an HD hierarchy (core/io/session.h) gives, without
 *     --level, the HD adaptive mesh (the model's top level plus the HD
 *     faces, crack-free, with UVs when the model has them); with --level L
 *     above the model's top and at most the HD top, the uniform level L with
 *     the HD detail (the HD hierarchy refined everywhere to L, when the
 *     memory budget allows); with --level L up to the model's top, the
 *     model's level L.  --box works on the model, as for any session.
 *     Session output keeps the HD hierarchy; --levels above the model's top
 *     and --box are refused there (the HD levels start at the model's top).
 *   - session -> session: re-saves it (the same bytes unless options change
 *     it); --levels N adds regular levels up to N.
 *   - mesh -> mesh: subdivision to --levels and export, like `strata
 *     subdivide`, or the adaptive mesh with --box.
 * Mesh output carries smooth vertex normals (OBJ `vn` with `f v//vn`, PLY nx
 * ny nz) unless --no-normals; glTF files always have them (formats/gltf_io.h).
 * --normal-map N.png (glTF output of a level): TEXCOORD_0, TANGENT and
 * NORMAL exactly as strata bake used them (core/bake/bake.h: the level's own
 * UVs, or the --auto-uv atlas for a level without UVs or with --auto-uv,
 * for a map baked with it; st_bake_tangents) and
 * a material whose normalTexture is N.png (formats/gltf_io.h st_gltf_save_mapped).
 * Exit status: 0 done, 1 a file could not be read or written, 2 bad usage. */
#include "core/adapt/adapt.h"
#include "cli.h"
#include "core/adapt/adapt_estimate.h"
#include "core/base/membudget.h"
#include "cli_common.h"
#include "formats/mesh_any.h"
#include "core/io/session.h"
#include "core/bake/bake.h"
#include "core/fvar/fvar.h"
#include "core/progressive/scheme_registry.h"
#include "formats/gltf_io.h"
#include "render/image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct conv_opts {
    const char *in, *out, *scheme;
    int levels;                /* -1: not given */
    int level;                 /* -1: not given */
    int boundary;
    int uv_interp;     /* enum st_uv_interp (--uv-interp) */
    unsigned read_flags; /* ST_MESH_STRICT with --strict */
    int normals;
    const char *normal_map;    /* --normal-map N.png: NULL when not given */
    int auto_uv;               /* --auto-uv: the map was baked on the --auto-uv atlas */
    st_adapt_params box;
    int has_box, has_adapt_opt;
} conv_opts;

static int parse_level(const char *s, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (!*s || *end || v < 0 || v >= ST_MAX_LEVELS) return -1;
    *out = (int)v;
    return 0;
}

static int parse_double(const char *s, double *out)
{
    char *end;
    *out = strtod(s, &end);
    return end == s || *end ? -1 : 0;
}

static int usage(void)
{
    fprintf(stderr, "usage: strata convert IN OUT [--scheme S] [--levels N] [--level L] [--boundary edge-only|edge-and-corner]\n"
                    "                      [--uv-interp none|corners-only|corners-plus1|corners-plus2|boundaries|all]\n"
                    "                      [--box x0,y0,z0,x1,y1,z1 [--base-level B] [--max-level M] [--falloff W] [--no-restriction]]\n"
                    "                      [--normals | --no-normals] [--normal-map N.png [--auto-uv] (glTF output)] [--strict]\n"
                    "  IN: .obj .off .ply .gltf .glb or .strata; OUT: .obj .ply .gltf .glb or .strata\n");
    return 2;
}

static int parse(int argc, char **argv, conv_opts *o)
{
    memset(o, 0, sizeof *o);
    o->levels = o->level = -1;
    o->boundary = ST_BOUNDARY_UNSET;
    o->normals = 1;
    o->box.max_level = 3;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int lv;
        double x;
        if (!strcmp(a, "--scheme") && v) { o->scheme = v; i++; }
        else if (!strcmp(a, "--levels") && v) {
            if (parse_level(v, &o->levels)) { fprintf(stderr, "strata convert: --levels wants 0..%d, got '%s'\n", ST_MAX_LEVELS - 1, v); return -1; }
            i++;
        } else if (!strcmp(a, "--level") && v) {
            if (parse_level(v, &o->level)) { fprintf(stderr, "strata convert: --level wants a level number, got '%s'\n", v); return -1; }
            i++;
        } else if (!strcmp(a, "--boundary") && v) {
            if (!strcmp(v, "edge-only")) o->boundary = ST_BOUNDARY_EDGE_ONLY;
            else if (!strcmp(v, "edge-and-corner")) o->boundary = ST_BOUNDARY_EDGE_AND_CORNER;
            else { fprintf(stderr, "strata convert: --boundary wants edge-only or edge-and-corner, got '%s'\n", v); return -1; }
            i++;
        } else if (!strcmp(a, "--uv-interp") && v) {
            if (st_cli_parse_uv_interp(v, &o->uv_interp, "convert")) return -1;
            i++;
        } else if (!strcmp(a, "--box") && v) {
            if (st_cli_parse_box(v, o->box.box_lo, o->box.box_hi)) { fprintf(stderr, "strata convert: --box wants x0,y0,z0,x1,y1,z1, got '%s'\n", v); return -1; }
            o->box.has_box = o->has_box = 1;
            i++;
        } else if (!strcmp(a, "--base-level") && v) {
            if (parse_level(v, &lv)) { fprintf(stderr, "strata convert: bad --base-level '%s'\n", v); return -1; }
            o->box.base_level = (unsigned)lv;
            o->has_adapt_opt = 1;
            i++;
        } else if (!strcmp(a, "--max-level") && v) {
            if (parse_level(v, &lv)) { fprintf(stderr, "strata convert: bad --max-level '%s'\n", v); return -1; }
            o->box.max_level = (unsigned)lv;
            o->has_adapt_opt = 1;
            i++;
        } else if (!strcmp(a, "--falloff") && v) {
            if (parse_double(v, &x) || !(x >= 0)) { fprintf(stderr, "strata convert: bad --falloff '%s'\n", v); return -1; }
            o->box.falloff = x;
            o->has_adapt_opt = 1;
            i++;
        } else if (!strcmp(a, "--no-restriction")) { o->box.no_restriction = 1; o->has_adapt_opt = 1; }
        else if (!strcmp(a, "--normals")) o->normals = 1;
        else if (!strcmp(a, "--no-normals")) o->normals = 0;
        else if (!strcmp(a, "--strict")) o->read_flags |= ST_MESH_STRICT;
        else if (!strcmp(a, "--normal-map") && v) { o->normal_map = v; i++; }
        else if (!strcmp(a, "--auto-uv")) o->auto_uv = 1;
        else if (a[0] == '-' && a[1]) { fprintf(stderr, "strata convert: unknown or incomplete option '%s'\n", a); return -1; }
        else if (!o->in) o->in = a;
        else if (!o->out) o->out = a;
        else { fprintf(stderr, "strata convert: unexpected argument '%s'\n", a); return -1; }
    }
    if (!o->in || !o->out) { fprintf(stderr, "strata convert: needs an input and an output file\n"); return -1; }
    if (o->has_adapt_opt && !o->has_box) { fprintf(stderr, "strata convert: --base-level, --max-level, --falloff and --no-restriction go with --box\n"); return -1; }
    if (o->has_box && (o->levels >= 0 || o->level >= 0)) { fprintf(stderr, "strata convert: --box is an alternative to --levels / --level\n"); return -1; }
    if (o->box.base_level > o->box.max_level) { fprintf(stderr, "strata convert: --base-level is above --max-level\n"); return -1; }
    if (o->auto_uv && !o->normal_map) { fprintf(stderr, "strata convert: --auto-uv goes with --normal-map (the map's layout)\n"); return -1; }
    if (o->normal_map) {
        if (!st_path_has_ext(o->out, ".gltf") && !st_path_has_ext(o->out, ".glb")) { fprintf(stderr, "strata convert: --normal-map writes a material into glTF output (.gltf or .glb), not %s\n", o->out); return -1; }
        if (o->has_box) { fprintf(stderr, "strata convert: --normal-map applies to a level (--level), not to --box\n"); return -1; }
        if (!st_path_has_ext(o->normal_map, ".png")) { fprintf(stderr, "strata convert: %s: the normal map must be a .png\n", o->normal_map); return -1; }
    }
    return 0;
}

static int is_mesh_out(const char *path)
{
    return st_path_has_ext(path, ".obj") || st_path_has_ext(path, ".ply") || st_path_has_ext(path, ".gltf") || st_path_has_ext(path, ".glb");
}

/* Loads a mesh input into s: base mesh and hierarchy to `levels`. */
static int load_mesh(const conv_opts *o, st_session *s)
{
    const char *name = o->scheme ? o->scheme : "catmull-clark";
    const st_scheme *sc = st_scheme_find(name);
    if (!sc) {
        fprintf(stderr, "strata convert: unknown scheme '%s' (catmull-clark, loop, butterfly, quad-triangle, sqrt3, doo-sabin)\n", name);
        return 2;
    }
    st_error err;
    st_notes notes = { 0 };
    st_mesh mesh;
    st_mesh_init(&mesh);
    if (st_any_mesh_load(o->in, &mesh, o->read_flags, &notes, &err)) {
        fprintf(stderr, "strata: %s\n", err.msg);
        st_notes_free(&notes);
        return 1;
    }
    for (uint32_t i = 0; i < notes.count; i++) fprintf(stderr, "strata: %s\n", notes.lines[i]);
    st_notes_free(&notes);
    st_hier_opts ho = { .boundary = o->boundary, .crease_method = ST_CREASE_UNIFORM, .uv_interp = o->uv_interp };
    st_session_init(s);
    if (st_hier_init(&s->h, &mesh, sc, &ho, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        st_mesh_free(&mesh);
        st_session_init(s);
        return 1;
    }
    st_mesh_move(&s->base, &mesh);
    s->has_base = 1;
    if (st_hier_subdivide_to(&s->h, o->levels > 0 ? (unsigned)o->levels : 0, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o->in, err.msg);
        st_session_free(s);
        return 1;
    }
    s->display_level = s->h.map.top;
    return 0;
}

/* Level l as glTF with the normal map: the layout and tangents strata bake
 * used for l (see the header comment). */
static int save_mapped(st_hier *h, unsigned l, const st_mesh *m, const conv_opts *o, st_error *err)
{
    /* A level without UVs: strata bake --auto-uv's atlas, made again for
     * the map's size and bake's default padding (a map that cannot be
     * read, or a UDIM set: bake's default size, 2048). */
    int w = 0, hh = 0;
    unsigned char *px = NULL;
    st_error ignored;
    if ((!o->auto_uv && st_hier_has_uv(h, l)) || strstr(o->normal_map, "<UDIM>") || st_png_read(o->normal_map, &w, &hh, &px, &ignored))
        w = 0;
    free(px);
    return st_gltf_save_level_mapped(o->out, h, l, m, o->auto_uv, w > 0 ? (uint32_t)w : 2048, ST_BAKE_AUTO_PADDING, o->normal_map, err);
}

/* What a session with an HD hierarchy cannot do: the HD levels start at
 * the model's top level, so neither new regular levels nor an adaptive
 * model may be saved beside them (nor --levels given for a mesh: --level
 * reads the HD levels).  Says why and returns -1. */
static int hd_refusal(const conv_opts *o, const st_session *s)
{
    if (!s->has_hd) return 0;
    if (o->levels >= 0 && (unsigned)o->levels > s->h.map.top) {
        fprintf(stderr, "strata convert: %s holds an HD hierarchy above level %u; --levels cannot add levels to the model "
                        "(--level L up to %u writes an HD level)\n", o->in, s->h.map.top, s->hd.map.top);
        return -1;
    }
    if (o->has_box && st_session_is_path(o->out)) {
        fprintf(stderr, "strata convert: %s holds an HD hierarchy; --box would refine the model it starts from\n", o->in);
        return -1;
    }
    return 0;
}

/* The uniform level l of the HD hierarchy (above the model's top): every
 * face refined to l, the HD details kept where they are, when the memory
 * budget allows it (the estimate of st_adapt_update, from level 0, given in
 * the refusal).  The session's HD hierarchy is refined in place: a mesh is
 * written from it, the session is not saved. */
static int hd_uniform_level(st_session *s, unsigned l, st_error *err)
{
    st_adapt_params p = { .base_level = l, .max_level = l };
    char what[96];
    snprintf(what, sizeof what, "HD level %u everywhere", l);
    /* (from the model, whose level 0 is the HD hierarchy's: the estimate
     * counts the regular levels a hierarchy lacks above its top, and the
     * HD hierarchy's top already is l, so from it the estimate was 0) */
    if (st_mem_check(st_adapt_estimate_bytes(&s->h, &p), what, err)) return -1;
    if (st_adapt_update(&s->hd_adapt, &p, err)) return -1;
    st_adapt_synthesize(&s->hd_adapt, s->hd_from);
    return 0;
}

int st_cmd_convert(int argc, char **argv)
{
    conv_opts o;
    if (parse(argc, argv, &o)) return usage();
    int in_session = st_session_is_path(o.in), out_session = st_session_is_path(o.out);
    if (!out_session && !is_mesh_out(o.out)) {
        fprintf(stderr, "strata convert: %s: unknown output format (expected .obj, .ply, .gltf, .glb or .strata)\n", o.out);
        return 2;
    }
    st_session s;
    st_error err;
    int rc;
    if (in_session) {
        if (o.scheme || o.boundary != ST_BOUNDARY_UNSET) {
            fprintf(stderr, "strata convert: --scheme and --boundary apply to mesh input; %s is a session\n", o.in);
            return 2;
        }
        if (st_session_load(o.in, &s, &err)) { fprintf(stderr, "strata: %s\n", err.msg); return 1; }
        if (hd_refusal(&o, &s)) {
            st_session_free(&s);
            return 2;
        }
        if (o.levels >= 0 && (unsigned)o.levels > s.h.map.top) {
            if (s.has_adapt) {
                fprintf(stderr, "strata convert: %s holds an adaptive hierarchy; --levels applies to regular ones\n", o.in);
                st_session_free(&s);
                return 2;
            }
            if (st_hier_subdivide_to(&s.h, (unsigned)o.levels, &err)) {
                fprintf(stderr, "strata: %s: %s\n", o.in, err.msg);
                st_session_free(&s);
                return 1;
            }
        }
    } else {
        rc = load_mesh(&o, &s);
        if (rc) return rc;
    }
    rc = 0;
    if (o.has_box) {
        if (st_mem_check(st_adapt_estimate_bytes(&s.h, &o.box), "the adaptive refinement", &err)) rc = 1;
        else if (!s.has_adapt) {
            if (st_adapt_init(&s.adapt, &s.h, &err)) rc = 1;
            else s.has_adapt = 1;
        }
        if (!rc && st_adapt_update(&s.adapt, &o.box, &err)) rc = 1;
        if (!rc && st_map_validate(&s.h.map, &err)) rc = 1;
        if (rc) {
            fprintf(stderr, "strata: %s: %s\n", o.in, err.msg);
            st_session_free(&s);
            return 1;
        }
        s.box = o.box;
        s.box_on = 1;
        s.display_level = s.h.map.top;
    }
    if (out_session) {
        if (o.level >= 0) {
            if ((unsigned)o.level > s.h.map.top) {
                fprintf(stderr, "strata convert: --level %d: %s has levels 0..%u\n", o.level, o.in, s.h.map.top);
                st_session_free(&s);
                return 2;
            }
            s.display_level = (unsigned)o.level;
            if (s.edit_level > s.display_level) s.edit_level = s.display_level;
        }
        if (st_session_save(o.out, &s, &err)) {
            fprintf(stderr, "strata: %s\n", err.msg);
            rc = 1;
        } else {
            FILE *f = fopen(o.out, "rb");
            long size = -1;
            if (f && fseek(f, 0, SEEK_END) == 0) size = ftell(f);
            if (f) fclose(f);
            char lv[48];
            char hd[48] = "";
            if (s.has_hd) snprintf(hd, sizeof hd, ", HD levels up to %u", s.hd.map.top);
            printf("%s: session, scheme %s, %s%s%s, %ld bytes\n", o.out, s.h.scheme->name,
                   st_levels_phrase(s.h.map.top, lv, sizeof lv), s.has_adapt ? " (adaptive)" : "", hd, size);
        }
        st_session_free(&s);
        return rc;
    }
    /* Mesh output: the model's level or adaptive mesh, or the HD
     * hierarchy's (see the header comment). */
    int hd_mesh = s.has_hd && o.level < 0 && !o.has_box;
    int hd_level = s.has_hd && o.level >= 0 && (unsigned)o.level > s.h.map.top && (unsigned)o.level <= s.hd.map.top;
    int adaptive = o.level < 0 && s.has_adapt && s.box_on && !hd_mesh;
    if (o.level >= 0 && (unsigned)o.level > s.h.map.top && !hd_level) {
        if (s.has_hd) fprintf(stderr, "strata convert: --level %d: %s has levels 0..%u (HD levels up to %u)\n", o.level, o.in, s.h.map.top, s.hd.map.top);
        else fprintf(stderr, "strata convert: --level %d: %s has levels 0..%u\n", o.level, o.in, s.h.map.top);
        st_session_free(&s);
        return 2;
    }
    unsigned l = o.level >= 0 ? (unsigned)o.level : hd_mesh ? s.hd.map.top : s.h.map.top;
    st_hier *src = hd_level ? &s.hd : &s.h;   /* the hierarchy level l is taken from */
    st_adapt *shown = hd_mesh ? &s.hd_adapt : &s.adapt;
    st_mesh out;
    st_mesh_init(&out);
    rc = adaptive || hd_mesh ? st_mem_check(st_adapt_estimate_mesh_bytes(shown), hd_mesh ? "the HD mesh" : "the adaptive mesh", &err) : 0;
    if (!rc && hd_level) rc = hd_uniform_level(&s, l, &err);
    if (!rc) rc = adaptive || hd_mesh ? st_adapt_mesh(shown, &out, &err) : st_hier_level_mesh(src, l, &out, &err);
    if (rc) fprintf(stderr, "strata: %s: %s\n", o.in, err.msg);
    if (!rc && o.normals && st_mesh_compute_normals(&out)) {
        fprintf(stderr, "strata: %s: out of memory computing normals\n", o.out);
        rc = 1;
    }
    if (!rc && o.normal_map && (adaptive || hd_mesh)) {
        fprintf(stderr, "strata convert: %s shows an adaptive mesh; --normal-map applies to a level: give --level\n", o.in);
        rc = 1;
    } else if (!rc && o.normal_map && save_mapped(src, l, &out, &o, &err)) {
        fprintf(stderr, "strata: %s: %s\n", o.in, err.msg);
        rc = 1;
    } else if (!rc && !o.normal_map && st_any_mesh_save(o.out, &out, &err)) {
        fprintf(stderr, "strata: %s\n", err.msg);
        rc = 1;
    }
    if (!rc)
        printf("%s: %u faces, %u vertices, %s %u%s%s%s\n", o.out, out.nfaces - st_mesh_hole_faces(&out), out.nverts,
               hd_mesh ? "HD adaptive, levels 0.." : adaptive ? "adaptive, levels 0.." : hd_level ? "HD level" : "level", l,
               o.normals || st_path_has_ext(o.out, ".gltf") || st_path_has_ext(o.out, ".glb") ? ", with normals" : "",
               o.normal_map ? ", UVs, tangents and a material with normal map " : "", o.normal_map ? o.normal_map : "");
    st_mesh_free(&out);
    st_session_free(&s);
    return rc ? 1 : 0;
}
