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
 * usage. */
#include "cli.h"
#include "cli_common.h"
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
                    "                     [--scheme S --levels N] [--mem-budget MIB]\n");
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

/* Applies the bump to level l of s as one edit; the vertices it leaves
 * exactly where they were (far from C) are not part of the edit.  Returns
 * the number moved, or -1 when out of memory. */
static int64_t apply_bump(st_session *s, unsigned l, const bump *b)
{
    st_hier *h = &s->h;
    uint32_t nv, n = 0;
    uint32_t *vd = st_sculpt_vertex_darts(&h->map, l, &nv);
    uint32_t *darts = malloc((size_t)(nv ? nv : 1) * sizeof *darts);
    double (*pos)[3] = malloc((size_t)(nv ? nv : 1) * sizeof *pos);
    if (!vd || !darts || !pos) { free(vd); free(darts); free(pos); return -1; }
    for (uint32_t v = 0; v < nv; v++) {
        if (vd[v] == ST_NIL) continue;
        const double *p = st_pos(&h->map, v, l);
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
    st_footprint fp = { 0 };
    if (n) {
        if (st_layers_on_level(&s->layers, l))
            st_layers_edit(&s->layers, h, l, layer_target(&s->layers, l), darts, (const double (*)[3])pos, n, &fp, NULL);
        else
            st_hier_edit(h, l, darts, (const double (*)[3])pos, n, &fp);
        if (layers_above(&s->layers, l)) st_layers_follow(&s->layers, h, l, fp.keys, fp.n);
    }
    st_footprint_free(&fp);
    free(vd);
    free(darts);
    free(pos);
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
    int found = take_bump(&argc, argv, &b);
    if (found < 0) return usage();
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
    rc = check_input(&o, &s, l);
    st_error err;
    if (!rc && st_mem_check(st_hier_synth_estimate(&s.h, l), "the edit's synthesis of the levels above", &err)) {
        fprintf(stderr, "strata deform: %s: %s\n", o.in, err.msg);
        rc = 1;
    }
    int64_t moved = rc ? 0 : apply_bump(&s, l, &b);
    if (moved < 0) { fprintf(stderr, "strata deform: %s: out of memory for the edit\n", o.in); rc = 1; }
    if (!rc) {
        s.edit_level = l;
        if (st_session_save(o.out, &s, &err)) { fprintf(stderr, "strata: %s\n", err.msg); rc = 1; }
        else {
            char lv[48];
            printf("%s: %lld %s of level %u moved, %s\n", o.out, (long long)moved, moved == 1 ? "vertex" : "vertices", l,
                   st_levels_phrase(s.h.map.top, lv, sizeof lv));
        }
    }
    st_session_free(&s);
    return rc;
}
