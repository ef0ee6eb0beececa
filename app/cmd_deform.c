/* strata deform IN -o OUT.strata --level L --bump CX,CY,CZ,R,DX,DY,DZ
 *               [--scheme S --levels N] [--mem-budget MIB]
 *
 * A scripted coarse edit: every vertex v of level L moves by
 * D·exp(−|v−C|²/R²), as one edit through the path the window's drag and
 * brushes take (st_hier_edit, core/multires/edit.h; st_layers_edit when the
 * level has sculpt layers, as ui/doc/editor_layers.c does), so the finer levels
 * keep their details exactly as after the same edit in the window.  Not a
 * brush of core/sculpt: the bump's weight is a Gaussian with no edge (every
 * vertex of L moves, by however little), where the brushes' falloffs end at
 * their radius and grab moves what its first dab captured; what it shares
 * with them is the vertex -> dart table (st_sculpt_vertex_darts), so it
 * edits the vertices through the same darts the window's picking gives.  IN is a
 * session, every chunk kept, or a mesh built with --scheme/--levels as
 * `strata info` builds it (app/cli_common.h).  OUT is written atomically
 * (core/io/atomic_file.h) and only after everything was checked, so a
 * refusal leaves an existing OUT as it was.  Exit status: 0 done, 1 a file
 * could not be read or written or the edit is over the memory budget, 2 bad
 * usage.
 *
 * HD levels (core/adapt/adapt.h "HD levels", core/io/session.h).  --level L
 * above the model's top N edits the session's HD hierarchy, as a stroke at
 * an HD level in the window does (ui/doc/editor_hd.c): it needs --box, the
 * region that reaches level L, and a quadrisection scheme.  The HD
 * hierarchy is the session's, or a copy of the model with the same ids
 * (written and parsed back: core offers no other deep copy to app/); it is
 * updated with base level N and the box at max(L, its top), only the
 * vertices st_adapt_vertex_editable accepts move (st_adapt_edit), then the
 * box goes off, as in the window, so only the faces holding detail stay
 * refined (keep_above = N).  The model is not changed.  With --level L <= N
 * the HD hierarchy follows the model's edit: the same edit through
 * st_adapt_edit (the details of level L), the model's positions of levels
 * L..N copied over bit for bit and the levels above N synthesised again
 * from them, so its HD detail rides on the moved surface. */
#include "cli.h"
#include "cli_common.h"
#include "core/adapt/adapt.h"
#include "core/adapt/adapt_estimate.h"
#include "core/base/membudget.h"
#include "core/multires/edit.h"
#include "core/multires/estimate.h"
#include "core/multires/layers.h"
#include "core/sculpt/sculpt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct bump {
    double c[3], r, d[3];
} bump;

static int usage(void)
{
    fprintf(stderr, "usage: strata deform IN -o OUT.strata --level L --bump CX,CY,CZ,R,DX,DY,DZ\n"
                    "                     [--box x0,y0,z0,x1,y1,z1] [--scheme S --levels N] [--mem-budget MIB]\n"
                    "       (--box: needed with a level above the model's top, an HD level)\n");
    return 2;
}

/* "cx,cy,cz,r,dx,dy,dz": exactly seven finite numbers, R > 0.  Prints what
 * is wrong, naming --bump, and returns -1. */
static int parse_bump(const char *s, bump *b)
{
    double v[7];
    const char *p = s;
    int n = 0;
    for (;;) {
        char *end;
        double x = strtod(p, &end);
        if (end == p || (*end && *end != ',')) {
            fprintf(stderr, "strata deform: --bump wants 7 numbers CX,CY,CZ,R,DX,DY,DZ, got '%s' (number %d is not a number)\n",
                    s, n + 1);
            return -1;
        }
        if (!isfinite(x)) {
            fprintf(stderr, "strata deform: --bump: number %d of '%s' is not finite\n", n + 1, s);
            return -1;
        }
        if (n < 7) v[n] = x;
        n++;
        if (!*end) break;
        p = end + 1;
    }
    if (n != 7) {
        fprintf(stderr, "strata deform: --bump wants 7 numbers CX,CY,CZ,R,DX,DY,DZ, got %d in '%s'\n", n, s);
        return -1;
    }
    if (!(v[3] > 0)) {
        fprintf(stderr, "strata deform: --bump: the radius R (number 4) must be > 0, got %g\n", v[3]);
        return -1;
    }
    memcpy(b->c, v, sizeof b->c);
    b->r = v[3];
    memcpy(b->d, v + 4, sizeof b->d);
    return 0;
}

/* Takes --bump VALUE out of argv (the common parser knows the rest).
 * Returns 1 when found, 0 when not, -1 after a message. */
static int take_bump(int *argc, char **argv, bump *b)
{
    int out = 0, found = 0;
    for (int i = 0; i < *argc; i++) {
        if (strcmp(argv[i], "--bump")) { argv[out++] = argv[i]; continue; }
        if (i + 1 >= *argc) { fprintf(stderr, "strata deform: --bump wants CX,CY,CZ,R,DX,DY,DZ\n"); return -1; }
        if (found) { fprintf(stderr, "strata deform: --bump given twice (one edit per run)\n"); return -1; }
        if (parse_bump(argv[++i], b)) return -1;
        found = 1;
    }
    *argc = out;
    return found;
}

/* Takes --box VALUE out of argv.  1 found, 0 not, -1 after a message. */
static int take_box(int *argc, char **argv, st_adapt_params *p)
{
    int out = 0, found = 0;
    for (int i = 0; i < *argc; i++) {
        if (strcmp(argv[i], "--box")) { argv[out++] = argv[i]; continue; }
        if (i + 1 >= *argc) { fprintf(stderr, "strata deform: --box wants x0,y0,z0,x1,y1,z1\n"); return -1; }
        if (found) { fprintf(stderr, "strata deform: --box given twice\n"); return -1; }
        if (st_cli_parse_box(argv[++i], p->box_lo, p->box_hi)) {
            fprintf(stderr, "strata deform: --box wants 6 numbers x0,y0,z0,x1,y1,z1, got '%s'\n", argv[i]);
            return -1;
        }
        found = 1;
    }
    *argc = out;
    return found;
}

/* The slot the edit goes into on a layered level: the active layer when it
 * lives on l and shows (ui/doc/editor_layers.c edit_target), else the level's
 * own details. */
static int layer_target(const st_layers *ls, unsigned l)
{
    int a = ls->active;
    if (a < 0 || (uint32_t)a >= ls->n) return -1;
    const st_layer *y = &ls->v[a];
    return y->level == l && !y->hidden && y->strength != 0 ? a : -1;
}

static int layers_above(const st_layers *ls, unsigned l)
{
    for (uint32_t i = 0; i < ls->n; i++)
        if (ls->v[i].level > l) return 1;
    return 0;
}

/* The bump's targets at level l of m: one dart per vertex and its new
 * position; the vertices it leaves exactly where they were (far from C)
 * are not part of the edit, nor, with hd, those st_adapt_vertex_editable
 * refuses (a vertex on the border of the refined region shows a coarser
 * face's corner).  *n of them; -1 when out of memory. */
static int bump_targets(st_map *m, unsigned l, const bump *b, int hd, uint32_t **darts_out, double (**pos_out)[3],
                        uint32_t *n_out)
{
    uint32_t nv, n = 0;
    uint32_t *vd = st_sculpt_vertex_darts(m, l, &nv);
    uint32_t *darts = malloc((size_t)(nv ? nv : 1) * sizeof *darts);
    double (*pos)[3] = malloc((size_t)(nv ? nv : 1) * sizeof *pos);
    if (!vd || !darts || !pos) { free(vd); free(darts); free(pos); return -1; }
    for (uint32_t v = 0; v < nv; v++) {
        if (vd[v] == ST_NIL || (hd && !st_adapt_vertex_editable(m, vd[v], l))) continue;
        const double *p = st_pos(m, v, l);
        double q2 = 0, np[3];
        for (int k = 0; k < 3; k++) q2 += (p[k] - b->c[k]) * (p[k] - b->c[k]);
        /* (|v-C|/R)², not |v-C|²/R²: a tiny R whose square underflows
         * gives 0/R = 0 at C and +inf elsewhere, never 0/0. */
        double t = sqrt(q2) / b->r, w = exp(-t * t);
        for (int k = 0; k < 3; k++) np[k] = p[k] + b->d[k] * w;
        if (np[0] == p[0] && np[1] == p[1] && np[2] == p[2]) continue;
        darts[n] = vd[v];
        memcpy(pos[n++], np, sizeof np);
    }
    free(vd);
    *darts_out = darts;
    *pos_out = pos;
    *n_out = n;
    return 0;
}

/* The HD hierarchy follows an edit of the model's level l <= N (darts: the
 * moved vertices, same ids in both): the same edit through st_adapt_edit
 * (its details of level l), then the model's positions of levels l..N
 * copied so that those levels stay copies of the model's bit for bit, and
 * the levels above N synthesised again from them (st_adapt_synthesize:
 * every HD vertex gets S(P_{L-1}) + frame · detail, its sculpted detail
 * carried along by the moved surface). */
static void hd_follow(st_session *s, unsigned l, const uint32_t *darts, uint32_t n)
{
    st_map *m = &s->h.map, *hm = &s->hd.map;
    unsigned N = s->hd_from;
    double (*pos)[3] = malloc((size_t)(n ? n : 1) * sizeof *pos);
    if (pos) {
        for (uint32_t i = 0; i < n; i++) memcpy(pos[i], st_pos(m, st_vert(m, darts[i], l), l), sizeof pos[i]);
        st_adapt_edit(&s->hd, l, darts, (const double (*)[3])pos, n, NULL, NULL);
        free(pos);
    }
    for (unsigned k = l; k <= N; k++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(m, k, &it); v != ST_NIL; v = st_vertex_next(m, k, &it))
            st_set_pos(hm, v, k, st_pos(m, v, k));
    }
    st_adapt_synthesize(&s->hd_adapt, N);
}

/* Applies the bump to level l of s as one edit (and the HD hierarchy
 * follows it, when the session has one).  Returns the number of vertices
 * moved, or -1 when out of memory. */
static int64_t apply_bump(st_session *s, unsigned l, const bump *b)
{
    st_hier *h = &s->h;
    uint32_t n = 0, *darts;
    double (*pos)[3];
    if (bump_targets(&h->map, l, b, 0, &darts, &pos, &n)) return -1;
    st_footprint fp = { 0 };
    if (n) {
        if (st_layers_on_level(&s->layers, l))
            st_layers_edit(&s->layers, h, l, layer_target(&s->layers, l), darts, (const double (*)[3])pos, n, &fp, NULL);
        else
            st_hier_edit(h, l, darts, (const double (*)[3])pos, n, &fp);
        if (layers_above(&s->layers, l)) st_layers_follow(&s->layers, h, l, fp.keys, fp.n);
        if (s->has_hd) hd_follow(s, l, darts, n);
    }
    st_footprint_free(&fp);
    free(darts);
    free(pos);
    return n;
}

/* ---- HD levels ------------------------------------------------------------ */


/* What an edit at HD level l (above the model's top) needs before anything
 * is computed: a box, a quadrisection scheme, no adaptive model. */
static int check_hd_input(const st_cli_opts *o, const st_session *s, unsigned l, int has_box)
{
    if (s->has_adapt) {
        fprintf(stderr, "strata deform: %s holds an adaptive hierarchy (interest box); deform edits regular levels\n", o->in);
        return 2;
    }
    if (!has_box) {
        char lv[48];
        fprintf(stderr, "strata deform: --level %u does not exist in %s (%s); above the top it is an HD level: "
                        "give --box x0,y0,z0,x1,y1,z1, the region refined to level %u\n", l, o->in,
                st_levels_phrase(s->h.map.top, lv, sizeof lv), l);
        return 2;
    }
    if (!st_adapt_scheme_has_hd(s->h.scheme)) {
        fprintf(stderr, "strata deform: %s: HD levels (--level %u above the top level %u) need a quadrisection scheme "
                        "(catmull-clark, loop, butterfly, quad-triangle), not %s\n", o->in, l, s->h.map.top, s->h.scheme->name);
        return 2;
    }
    if (l >= ST_MAX_LEVELS) {
        fprintf(stderr, "strata deform: --level %u: levels go up to %d\n", l, ST_MAX_LEVELS - 1);
        return 2;
    }
    return 0;
}

/* A new HD hierarchy for s: a copy of the model with its ids (the session's
 * own bytes parsed back) and a fresh adaptive state on it. */
static int hd_create(st_session *s, st_error *err)
{
    st_session_ref r = { .h = &s->h, .whole_map = 1 };
    void *data = NULL;
    size_t size = 0;
    st_session copy;
    int rc = st_session_write_mem(&r, &data, &size, err);
    if (!rc) rc = st_session_parse("the model's copy", data, size, &copy, err);
    free(data);
    if (rc) return rc;
    st_session_move_hier(&s->hd, &copy.h);
    st_session_free(&copy);
    memset(&s->hd_adapt, 0, sizeof s->hd_adapt);
    rc = st_adapt_init(&s->hd_adapt, &s->hd, err);
    if (rc) { st_hier_free(&s->hd); memset(&s->hd, 0, sizeof s->hd); return rc; }
    s->has_hd = 1;
    s->hd_from = s->h.map.top;
    return ST_OK;
}

/* The bump at HD level l inside the box p (p->box_*: set by --box).  Moves
 * the session's HD hierarchy (made when it has none); *moved gets the
 * vertices moved.  Returns 0, or the exit status after a message. */
static int hd_deform(const st_cli_opts *o, st_session *s, unsigned l, const st_adapt_params *box, const bump *b,
                     int64_t *moved)
{
    unsigned N = s->h.map.top;
    st_adapt_params p = *box;
    p.base_level = N;
    p.max_level = l;
    if (s->has_hd && s->hd.map.top > l) p.max_level = s->hd.map.top;
    p.has_box = 1;
    st_error err;
    /* From level 0 of the model: a bound on the copy and the refinement
     * (an existing HD hierarchy already holds part of it). */
    if (st_mem_check(st_adapt_estimate_bytes(&s->h, &p), "the HD levels' refinement inside the box", &err)) {
        fprintf(stderr, "strata deform: %s: %s\n", o->in, err.msg);
        return 1;
    }
    int rc = s->has_hd ? ST_OK : hd_create(s, &err);
    /* Sculpted faces never coarsen, whatever the box (a loaded session sets
     * it too; a new hierarchy starts at 0). */
    s->hd_adapt.keep_above = N;
    s->hd_adapt.keep_layers = &s->hd_layers; /* (and the faces the HD layers cover) */
    s->hd_adapt.exact = 1;
    if (!rc) rc = st_adapt_update(&s->hd_adapt, &p, &err);
    if (rc) { fprintf(stderr, "strata deform: %s: HD levels: %s\n", o->in, err.msg); return 1; }
    uint32_t n = 0, *darts;
    double (*pos)[3];
    if (bump_targets(&s->hd.map, l, b, 1, &darts, &pos, &n)) {
        fprintf(stderr, "strata deform: %s: out of memory for the edit\n", o->in);
        return 1;
    }
    /* Into the active HD layer when it is on l, as the window's strokes. */
    if (n)
        st_adapt_edit_layered(&s->hd, &s->hd_layers, layer_target(&s->hd_layers, l), l, darts, (const double (*)[3])pos, n,
                              NULL, NULL);
    free(darts);
    free(pos);
    /* The box goes off, as in the window: only the faces holding detail
     * stay refined above N. */
    st_adapt_params off = { .base_level = N, .max_level = N };
    rc = st_adapt_update(&s->hd_adapt, &off, &err);
    if (!rc) rc = st_map_validate(&s->hd.map, &err);
    if (rc) { fprintf(stderr, "strata deform: %s: HD levels: %s\n", o->in, err.msg); return 1; }
    *moved = n;
    return 0;
}

/* Real faces stored above the model's top in the HD hierarchy. */
static uint64_t hd_faces(const st_session *s)
{
    uint64_t faces[ST_MAX_LEVELS], bytes[ST_MAX_LEVELS], n = 0;
    st_adapt_hd_levels(&s->hd.map, s->hd_from, faces, bytes);
    for (unsigned k = s->hd_from + 1; k < ST_MAX_LEVELS; k++) n += faces[k];
    return n;
}

/* What a session input must allow before anything is computed: a regular
 * hierarchy (an adaptive one is edited in the window, whose box display
 * has its own) holding level l. */
static int check_input(const st_cli_opts *o, const st_session *s, unsigned l)
{
    if (s->has_adapt) {
        fprintf(stderr, "strata deform: %s holds an adaptive hierarchy (interest box); deform edits regular levels\n", o->in);
        return 2;
    }
    if (l > s->h.map.top) {
        char lv[48];
        fprintf(stderr, "strata deform: --level %u does not exist in %s (%s)\n", l, o->in,
                st_levels_phrase(s->h.map.top, lv, sizeof lv));
        return 2;
    }
    return 0;
}

int st_cmd_deform(int argc, char **argv)
{
    bump b = { { 0 }, 0, { 0 } };
    st_adapt_params box = { 0 };
    int found = take_bump(&argc, argv, &b);
    if (found < 0) return usage();
    int has_box = take_box(&argc, argv, &box);
    if (has_box < 0) return usage();
    st_cli_opts o;
    if (st_cli_parse(argc, argv, &o, "deform")) return usage();
    if (!found) { fprintf(stderr, "strata deform: --bump CX,CY,CZ,R,DX,DY,DZ is required\n"); return usage(); }
    if (o.level < 0) { fprintf(stderr, "strata deform: --level L is required\n"); return usage(); }
    if (!o.out) { fprintf(stderr, "strata deform: -o OUT.strata is required\n"); return usage(); }
    if (!st_session_is_path(o.out)) {
        fprintf(stderr, "strata deform: -o %s: the output is a session (.strata)\n", o.out);
        return 2;
    }
    st_session s;
    int rc = st_cli_load_session(&o, &s, "deform");
    if (rc) return rc;
    unsigned l = (unsigned)o.level;
    int hd = l > s.h.map.top;
    st_error err;
    int64_t moved = 0;
    if (hd) {
        rc = check_hd_input(&o, &s, l, has_box);
        if (!rc) rc = hd_deform(&o, &s, l, &box, &b, &moved);
    } else {
        rc = check_input(&o, &s, l);
        if (!rc && has_box) fprintf(stderr, "strata deform: note: --box applies to HD levels (above level %u); level %u is edited everywhere\n",
                                    s.h.map.top, l);
        if (!rc && st_mem_check(st_hier_synth_estimate(&s.h, l), "the edit's synthesis of the levels above", &err)) {
            fprintf(stderr, "strata deform: %s: %s\n", o.in, err.msg);
            rc = 1;
        }
        moved = rc ? 0 : apply_bump(&s, l, &b);
        if (moved < 0) { fprintf(stderr, "strata deform: %s: out of memory for the edit\n", o.in); rc = 1; }
    }
    if (!rc) {
        if (!hd) s.edit_level = l;
        if (st_session_save(o.out, &s, &err)) { fprintf(stderr, "strata: %s\n", err.msg); rc = 1; }
        else {
            char lv[48];
            printf("%s: %lld %s of %slevel %u moved, %s", o.out, (long long)moved, moved == 1 ? "vertex" : "vertices",
                   hd ? "HD " : "", l, st_levels_phrase(s.h.map.top, lv, sizeof lv));
            if (s.has_hd)
                printf(", HD levels %u..%u: %llu faces stored", s.hd_from + 1, s.hd.map.top,
                       (unsigned long long)hd_faces(&s));
            printf("\n");
        }
    }
    st_session_free(&s);
    return rc;
}
