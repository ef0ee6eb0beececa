/* Unsubdivide (unsubdivide.h): one step labels the vertices of the fine
 * mesh by propagation over its faces, checks the labelling, and reads the
 * coarse mesh off it; steps repeat while the pattern holds.
 *
 * Over 900 lines, one file on purpose: the labelling, its check and the
 * coarse mesh read off it share the step's context (step_ctx) and its
 * invariants (a label per vertex, a phase per face, the component being
 * labelled), which are this file's private state; the recognition of the
 * topology alone (unsub_topo.c) and the hierarchy (unsub_hier.c) are apart. */
#include "core/rebuild/unsubdivide.h"
#include "core/rebuild/unsub_topo_internal.h"
#include "core/base/hugepage.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { LAB_NONE = 0, LAB_V, LAB_E, LAB_F };
static const char *const lab_name[] = { "unlabelled", "a coarse vertex", "an edge point", "a face point" };
#define NO_PHASE 0xffu
#define CENTRAL 3u   /* quadrisection phase of a central triangle */

/* The labelling of one step.  phase[f]: polygon split, the corner of f that
 * is the coarse vertex (the face point is opposite); quadrisection, the
 * corner that is the coarse vertex (0..2) or CENTRAL. */
typedef struct step_ctx {
    const st_unsub_topo *t;
    const double *pos;
    int pattern;
    int boundary_interp;
    uint8_t *lab;              /* per vertex */
    uint8_t *phase;            /* per face */
    uint32_t *queue, nq;       /* faces of the component being labelled, in visiting order */
    uint32_t *best_queue, best_nq;   /* the best labelling of the component so far: its faces */
    uint8_t *best_phase;       /* ... and their phases (per face) */
    double *acc;               /* 3 per vertex: scratch of the geometric score */
    uint8_t *mark;             /* per vertex: scratch */
    int crease_chaikin;        /* `t creasemethod chaikin` */
    float *esharp;             /* per corner: the crease sharpness of its edge; NULL when no creases */
    float *vsharp;             /* per vertex: its corner sharpness; NULL when no corners */
    char fail[400];            /* why the current attempt failed */
} step_ctx;

static void failf(step_ctx *s, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void failf(step_ctx *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->fail, sizeof s->fail, fmt, ap);
    va_end(ap);
}

static unsigned face_deg(const step_ctx *s, uint32_t f) { return s->t->foff[f + 1] - s->t->foff[f]; }

/* The label corner i of a face of phase p must carry. */
static int wanted(const step_ctx *s, unsigned i, unsigned p)
{
    if (s->pattern == ST_UNSUB_POLY_SPLIT) {
        static const uint8_t cycle[4] = { LAB_V, LAB_E, LAB_F, LAB_E };
        return cycle[(i + 4 - p) & 3];
    }
    return p != CENTRAL && i == p ? LAB_V : LAB_E;
}

/* Checks a vertex can carry its new label, as soon as it gets it, so that
 * a local re-meshing is reported where it is rather than where the
 * propagation runs into its consequences: an edge point has valence 4 (3
 * on the boundary) after a polygon split, 6 (4) after quadrisection.  (That
 * face points are interior is checked per candidate, label_all.) */
static int local_check(step_ctx *s, uint32_t v)
{
    const st_unsub_topo *t = s->t;
    int poly = s->pattern == ST_UNSUB_POLY_SPLIT;
    unsigned inner = poly ? 4 : 6, outer = poly ? 3 : 4;
    if (s->lab[v] == LAB_E && t->valence[v] != (t->bnd[v] ? outer : inner)) {
        failf(s, "vertex %u would be an edge point but has %u neighbours; expected %u (%u on the boundary)",
              v + 1, t->valence[v], inner, outer);
        return -1;
    }
    return 0;
}

/* (The arrays are read into locals first: a store through uint8_t * may
 * alias anything, and would make the compiler read them again per corner.) */
static int assign(step_ctx *s, uint32_t f, unsigned p)
{
    s->phase[f] = (uint8_t)p;
    s->queue[s->nq++] = f;
    const st_unsub_topo *t = s->t;
    const uint32_t *fidx = t->fidx, *valence = t->valence;
    const uint8_t *bnd = t->bnd;
    uint8_t *lab = s->lab;
    int poly = s->pattern == ST_UNSUB_POLY_SPLIT;
    unsigned inner = poly ? 4 : 6, outer = poly ? 3 : 4;
    uint32_t b = t->foff[f], n = t->foff[f + 1] - b;
    for (unsigned i = 0; i < n; i++) {
        uint32_t v = fidx[b + i];
        int w = wanted(s, i, p);
        if (lab[v] == LAB_NONE) {
            lab[v] = (uint8_t)w;
            /* local_check's test, here with the arrays at hand; it says why. */
            if (w == LAB_E && valence[v] != (bnd[v] ? outer : inner) && local_check(s, v)) return -1;
        } else if (lab[v] != w) {
            failf(s, "vertex %u (in face %u): this face makes it %s but its other faces make it %s",
                  v + 1, f + 1, lab_name[w], lab_name[lab[v]]);
            return -1;
        }
    }
    return 0;
}

/* Phase of face g reached through corner tw (the twin of a labelled face
 * f's half-edge): its two shared vertices carry labels already. */
static int derive_phase(step_ctx *s, uint32_t f, uint32_t tw, unsigned *p)
{
    const st_unsub_topo *t = s->t;
    uint32_t g = t->face_of[tw];
    unsigned n = face_deg(s, g), jt = tw - t->foff[g], jn = jt + 1 == n ? 0 : jt + 1;
    int lw = s->lab[t->fidx[tw]], lv = s->lab[t->fidx[t->foff[g] + jn]];
    if (s->pattern == ST_UNSUB_POLY_SPLIT) {
        if (lw == LAB_V) *p = jt;
        else if (lw == LAB_F) *p = (jt + 2) & 3;
        else if (lv == LAB_V) *p = jn;
        else if (lv == LAB_F) *p = (jn + 2) & 3;
        else { failf(s, "face %u: its edge %u-%u joins two edge points", g + 1, t->fidx[tw] + 1, t->fidx[t->foff[g] + jn] + 1); return -1; }
        return 0;
    }
    if (lw == LAB_V && lv == LAB_V) {
        failf(s, "face %u: its edge %u-%u joins two coarse vertices", g + 1, t->fidx[tw] + 1, t->fidx[t->foff[g] + jn] + 1);
        return -1;
    }
    if (lw == LAB_V) *p = jt;
    else if (lv == LAB_V) *p = jn;
    else *p = s->phase[f] == CENTRAL ? (jt + 2) % 3 : CENTRAL;
    return 0;
}

/* Labels the component of `seed` from phase p0 by breadth-first
 * propagation over the faces.  0 when done, -1 with s->fail at the first
 * conflict, 1 when `budget` faces are labelled without a conflict (a
 * probe). */
static int propagate(step_ctx *s, uint32_t seed, unsigned p0, uint32_t budget)
{
    const st_unsub_topo *t = s->t;
    s->nq = 0;
    if (assign(s, seed, p0)) return -1;
    const uint32_t *foff = t->foff, *twin = t->twin, *face_of = t->face_of;
    const uint8_t *phase = s->phase;
    for (uint32_t head = 0; head < s->nq; head++) {
        uint32_t f = s->queue[head];
        for (uint32_t c = foff[f], end = foff[f + 1]; c < end; c++) {
            uint32_t tw = twin[c];
            if (tw == ST_NIL || phase[face_of[tw]] != NO_PHASE) continue;
            unsigned p;
            if (derive_phase(s, f, tw, &p) || assign(s, t->face_of[tw], p)) return -1;
            if (s->nq >= budget) return 1;
        }
    }
    return 0;
}

static void unlabel(step_ctx *s)
{
    const uint32_t *foff = s->t->foff, *fidx = s->t->fidx, *queue = s->queue;
    uint8_t *lab = s->lab, *phase = s->phase;
    for (uint32_t i = 0; i < s->nq; i++) {
        uint32_t f = queue[i];
        phase[f] = NO_PHASE;
        for (uint32_t c = foff[f], end = foff[f + 1]; c < end; c++) lab[fidx[c]] = LAB_NONE;
    }
    s->nq = 0;
}

/* Coarse-vertex neighbours of v (boundary fans: the one neighbour reached
 * only by an incoming half-edge counts too). */
static unsigned coarse_neighbours(const step_ctx *s, uint32_t v)
{
    const st_unsub_topo *t = s->t;
    unsigned n = 0;
    for (uint32_t k = t->out_off[v]; k < t->out_off[v + 1]; k++) {
        uint32_t c = t->out_c[k], pc = st_unsub_prev(t, c);
        n += s->lab[st_unsub_target(t, c)] == LAB_V;
        if (t->twin[pc] == ST_NIL) n += s->lab[t->fidx[pc]] == LAB_V;
    }
    return n;
}

/* What a labelled component must satisfy beyond face-by-face consistency
 * and local_check, for quadrisection: each edge point has two coarse
 * neighbours.  (After a polygon split this follows: the neighbours of an
 * edge point of valence 4 alternate coarse vertex, face point around it,
 * and on the boundary its two boundary neighbours cannot be face points.)
 * s->mark visits each vertex once. */
static int check_component(step_ctx *s)
{
    const st_unsub_topo *t = s->t;
    int rc = 0;
    for (uint32_t i = 0; i < s->nq && !rc; i++) {
        uint32_t f = s->queue[i];
        for (uint32_t c = t->foff[f]; c < t->foff[f + 1]; c++) {
            uint32_t v = t->fidx[c];
            if (s->lab[v] != LAB_E || s->mark[v]) continue;
            s->mark[v] = 1;
            unsigned nb = coarse_neighbours(s, v);
            if (nb != 2) {
                failf(s, "vertex %u would be an edge point but has %u coarse vertices among its neighbours; expected 2", v + 1, nb);
                rc = -1;
                break;
            }
        }
    }
    for (uint32_t i = 0; i < s->nq; i++) {
        uint32_t f = s->queue[i];
        for (uint32_t c = t->foff[f]; c < t->foff[f + 1]; c++) s->mark[t->fidx[c]] = 0;
    }
    return rc;
}

/* Polygon split, for the labelling of the current phases (swap 0) or the
 * one with coarse vertices and face points exchanged (swap 1): the corner
 * of face q that is the coarse vertex. */
static unsigned vcorner(const step_ctx *s, uint32_t q, unsigned swap) { return (s->phase[q] + 2u * swap) & 3u; }

/* The face point across the edge point that follows the coarse vertex of
 * face q (ST_NIL on the boundary). */
static uint32_t face_point_across(const step_ctx *s, uint32_t q, unsigned swap)
{
    const st_unsub_topo *t = s->t;
    uint32_t tw = t->twin[t->foff[q] + vcorner(s, q, swap)];
    if (tw == ST_NIL) return ST_NIL;
    uint32_t g = t->face_of[tw];
    return t->fidx[t->foff[g] + ((vcorner(s, g, swap) + 2u) & 3u)];
}

/* Root mean square, over the interior coarse faces met by the first
 * SCORE_FACES fine faces in propagation order (a deterministic sample: a
 * wrong labelling breaks the identity everywhere, so a sample tells as
 * well as the whole and keeps the cost flat), of the identity
 * 4 ΣE_i - 3 m F - Σ F'_i = 0 (unsubdivide.h), which an exact polygon split
 * satisfies and a wrong labelling generally does not.  Faces the sample's
 * end cuts (or of more than 253 sides) are left out. */
#define SCORE_FACES 65536u
#define SCORE_SKIP 255u
static double poly_score(step_ctx *s, unsigned swap)
{
    const st_unsub_topo *t = s->t;
    uint32_t nq = s->nq < SCORE_FACES ? s->nq : SCORE_FACES;
    /* mark[F]: 0 not met, 1 + the terms summed so far, SCORE_SKIP when F
     * has a boundary edge point (the identity is for interior faces). */
    for (uint32_t i = 0; i < nq; i++) {
        uint32_t q = s->queue[i], b = t->foff[q], p = vcorner(s, q, swap);
        uint32_t F = t->fidx[b + ((p + 2) & 3)], E = t->fidx[b + ((p + 1) & 3)], G = face_point_across(s, q, swap);
        double *a = s->acc + 3 * (size_t)F;
        if (s->mark[F] == 0) { a[0] = a[1] = a[2] = 0; s->mark[F] = 1; }
        if (s->mark[F] == SCORE_SKIP) continue;
        /* A sharp coarse edge's edge point is its midpoint, not the smooth
         * rule the identity rests on: such faces are left out too. */
        if (G == ST_NIL || s->mark[F] == SCORE_SKIP - 1 || (s->esharp && s->esharp[b + p] > 0)) { s->mark[F] = SCORE_SKIP; continue; }
        s->mark[F]++;
        for (int k = 0; k < 3; k++) a[k] += 4 * s->pos[3 * (size_t)E + k] - 3 * s->pos[3 * (size_t)F + k] - s->pos[3 * (size_t)G + k];
    }
    double sum = 0;
    uint64_t n = 0;
    for (uint32_t i = 0; i < nq; i++) {
        uint32_t q = s->queue[i], F = t->fidx[t->foff[q] + ((vcorner(s, q, swap) + 2) & 3)];
        /* Only faces whose every term is in the sample. */
        if (s->mark[F] != 0 && s->mark[F] != SCORE_SKIP && s->mark[F] - 1u == t->valence[F]) {
            const double *a = s->acc + 3 * (size_t)F;
            sum += a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
            n++;
        }
        s->mark[F] = 0;
    }
    return n ? sqrt(sum / (double)n) : 0;
}

/* A face point of the labelling (swap as above) on the boundary, or ST_NIL:
 * face points are interior.  When none, *quads: the quadrilateral coarse
 * faces, counted once per fine face around them.  (One pass for both: the
 * face points' valence and boundary flag are cache misses in an arbitrary
 * vertex order.) */
static uint32_t face_points(const step_ctx *s, unsigned swap, uint64_t *quads)
{
    uint64_t n = 0;
    for (uint32_t i = 0; i < s->nq; i++) {
        uint32_t q = s->queue[i], F = s->t->fidx[s->t->foff[q] + ((vcorner(s, q, swap) + 2) & 3)];
        if (s->t->bnd[F]) return F;
        n += s->t->valence[F] == 4;
    }
    *quads = n;
    return ST_NIL;
}

/* The labelling just found is the best so far: keep it, rather than
 * propagate it again at the end. */
static void keep_best(step_ctx *s, unsigned swap)
{
    memcpy(s->best_queue, s->queue, (size_t)s->nq * sizeof *s->queue);
    s->best_nq = s->nq;
    for (uint32_t i = 0; i < s->nq; i++) s->best_phase[s->queue[i]] = (uint8_t)vcorner(s, s->queue[i], swap);
}

static void restore_best(step_ctx *s)
{
    const uint32_t *foff = s->t->foff, *fidx = s->t->fidx;
    uint8_t *lab = s->lab, *phase = s->phase;
    for (uint32_t i = 0; i < s->best_nq; i++) {
        uint32_t f = s->best_queue[i], b = foff[f], n = foff[f + 1] - b;
        unsigned p = phase[f] = s->best_phase[f];
        for (unsigned k = 0; k < n; k++) lab[fidx[b + k]] = (uint8_t)wanted(s, k, p);
    }
}

/* The best candidate labelling of a component so far, and the failure
 * that got furthest. */
typedef struct cand {
    int seed;                  /* -1: none yet */
    double r;
    uint64_t q;
    uint32_t far;
    char msg[sizeof ((step_ctx *)0)->fail];
} cand;

static void note_fail(const step_ctx *s, cand *c)
{
    if (s->nq > c->far || !c->msg[0]) {
        c->far = s->nq;
        memcpy(c->msg, s->fail, sizeof c->msg);
    }
}

/* Scores the labelling just propagated from seed phase p and, for the
 * polygon split, the same with coarse vertices and face points exchanged
 * (seed p + 2: consistency and edge points are the same; it is valid when
 * its face points are interior too).  Returns the exchange (0 or 1) of the
 * candidate that became the best, or -1 when none did. */
static int evaluate(step_ctx *s, unsigned p, double tie, cand *c)
{
    int poly = s->pattern == ST_UNSUB_POLY_SPLIT, win = -1;
    if (!poly && check_component(s)) { note_fail(s, c); return -1; }
    for (unsigned swap = 0; swap <= (unsigned)poly; swap++) {
        double r = 0;
        uint64_t q = 0;
        if (poly) {
            uint32_t fb = face_points(s, swap, &q);
            if (fb != ST_NIL) {
                failf(s, "vertex %u would be a face point but lies on the boundary", fb + 1);
                note_fail(s, c);
                continue;
            }
            r = poly_score(s, swap);
        }
        if (c->seed < 0 || r < c->r - tie || (fabs(r - c->r) <= tie && q > c->q)) {
            c->seed = (int)(p + 2 * swap); c->r = r; c->q = q;
            win = (int)swap;
        }
    }
    return win;
}

/* Coarse vertices and face points exchanged over the labelled component. */
static void exchange_in_place(step_ctx *s)
{
    const uint32_t *foff = s->t->foff, *fidx = s->t->fidx;
    uint8_t *lab = s->lab, *phase = s->phase;
    for (uint32_t i = 0; i < s->nq; i++) {
        uint32_t f = s->queue[i], b = foff[f], n = foff[f + 1] - b;
        unsigned p = phase[f] = (uint8_t)((phase[f] + 2u) & 3u);
        for (unsigned k = 0; k < n; k++) lab[fidx[b + k]] = (uint8_t)wanted(s, k, p);
    }
}

/* Faces a probe labels before a seed phase counts as surviving: wrong
 * phases meet a conflict within a few rings of an extraordinary vertex. */
#define PROBE_FACES 4096u

/* Labels every component, choosing among the consistent labellings
 * (unsubdivide.h: residual, then quadrilaterals, then order).  Each seed
 * phase is first probed; when one survives on a large component (the usual
 * case) it is propagated once, in place; otherwise every survivor is
 * propagated in full, scored, the best kept and restored.  On failure the
 * message of the attempt that got furthest. */
static int label_all(step_ctx *s, double tie)
{
    const st_unsub_topo *t = s->t;
    int poly = s->pattern == ST_UNSUB_POLY_SPLIT;
    unsigned nseeds = poly ? 2 : 4;
    for (uint32_t f0 = 0; f0 < t->nf; f0++) {
        if (s->phase[f0] != NO_PHASE) continue;
        cand c = { .seed = -1 };
        unsigned alive = 0, nalive = 0;
        for (unsigned p = 0; p < nseeds; p++) {
            int r = propagate(s, f0, p, PROBE_FACES);
            if (r == 0) {
                int w = evaluate(s, p, tie, &c);
                if (w >= 0) keep_best(s, (unsigned)w);
            } else if (r > 0) {
                alive |= 1u << p;
                nalive++;
            } else {
                note_fail(s, &c);
            }
            unlabel(s);
        }
        /* Several seed phases survive the probe where extraordinary
         * vertices are far apart (spot x4: the shifted phase lives 8064
         * faces): probe the survivors again, 4 times longer each round,
         * while that stays under a quarter of the faces, rather than label
         * the whole component once per survivor and restore the best.  A
         * probe is a prefix of the full propagation, so a phase that dies
         * in a longer probe would have died in full, and one that completes
         * in it completes in the same round as every other survivor (in
         * seed order, as below): the choice and the failure kept are the
         * same. */
        for (uint32_t budget = 4 * PROBE_FACES; nalive > 1 && budget <= t->nf / 4; budget *= 4) {
            for (unsigned p = 0; p < nseeds; p++) {
                if (!(alive >> p & 1u)) continue;
                int r = propagate(s, f0, p, budget);
                if (r <= 0) {
                    alive &= ~(1u << p);
                    nalive--;
                    if (r == 0) {
                        int w = evaluate(s, p, tie, &c);
                        if (w >= 0) keep_best(s, (unsigned)w);
                    } else {
                        note_fail(s, &c);
                    }
                }
                unlabel(s);
            }
        }
        if (nalive == 1 && c.seed < 0) {
            unsigned p = 0;
            while (!(alive >> p & 1u)) p++;
            if (propagate(s, f0, p, UINT32_MAX) == 0) {
                int w = evaluate(s, p, tie, &c);
                if (w == 1) exchange_in_place(s);
                if (w >= 0) continue;
            } else {
                note_fail(s, &c);
            }
            unlabel(s);
        } else {
            for (unsigned p = 0; p < nseeds; p++) {
                if (!(alive >> p & 1u)) continue;
                if (propagate(s, f0, p, UINT32_MAX) == 0) {
                    int w = evaluate(s, p, tie, &c);
                    if (w >= 0) keep_best(s, (unsigned)w);
                } else {
                    note_fail(s, &c);
                }
                unlabel(s);
            }
        }
        if (c.seed < 0) {
            /* No labelling fits this component.  The seed may lie in the
             * broken region itself, where every attempt fails at once: the
             * message comes from the attempt that labelled the most faces,
             * seeds spread over the mesh included, which runs from a sound
             * region into the break and names it. */
            for (unsigned j = 1; j < 8; j++) {
                uint32_t g = (uint32_t)(f0 + (uint64_t)(t->nf - f0) * j / 8);
                if (g >= t->nf || s->phase[g] != NO_PHASE) continue;
                for (unsigned p = 0; p < nseeds; p++) {
                    if (propagate(s, g, p, UINT32_MAX) < 0 && s->nq > c.far) note_fail(s, &c);
                    unlabel(s);
                }
            }
            memcpy(s->fail, c.msg, sizeof s->fail);
            return -1;
        }
        restore_best(s);
    }
    return 0;
}

/* ---- the coarse mesh ------------------------------------------------------- */

static int alloc_step(st_unsub_step *st, uint32_t nv, uint32_t nf, uint32_t nc, int faces_pts)
{
    st_mesh *m = &st->coarse;
    m->nverts = nv;
    m->nfaces = nf;
    m->pos = st_malloc_huge(((size_t)nv + 1) * 3 * sizeof *m->pos);
    m->face_off = st_malloc_huge(((size_t)nf + 1) * sizeof *m->face_off);
    m->face_idx = st_malloc_huge(((size_t)nc + 1) * sizeof *m->face_idx);
    st->v_fine = st_malloc_huge(((size_t)nv + 1) * sizeof *st->v_fine);
    st->e_fine = st_malloc_huge(((size_t)nc + 1) * sizeof *st->e_fine);
    st->f_fine = faces_pts ? st_malloc_huge(((size_t)nf + 1) * sizeof *st->f_fine) : NULL;
    return m->pos && m->face_off && m->face_idx && st->v_fine && st->e_fine && (!faces_pts || st->f_fine) ? 0 : -1;
}

static void free_step(st_unsub_step *st)
{
    st_mesh_free(&st->coarse);
    free(st->v_fine); free(st->e_fine); free(st->f_fine);
    memset(st, 0, sizeof *st);
    st_mesh_init(&st->coarse);
}

/* Coarse faces of the polygon split: one per face point, in vertex order,
 * its corners read around it (each fine quad is (V, E_next, F, E_prev))
 * from its first fine quad.  The offsets come first (a face point's coarse
 * face has one corner per neighbour), then the faces are read in fine-face
 * order: the quads around a face point lie near each other in that order,
 * where face points in vertex order (another program's) jump about.
 * rank: scratch, per fine vertex.  A face point whose quads do not close
 * around it is reported, the first in vertex order. */
static int build_poly_faces(step_ctx *s, st_unsub_step *st, const uint32_t *vmap, uint32_t *first_face, uint32_t *rank,
                            uint32_t *corner_fine, uint32_t *coarse_of)
{
    const st_unsub_topo *t = s->t;
    st_mesh *m = &st->coarse;
    uint32_t nf = 0, nc = 0;
    for (uint32_t v = 0; v < t->nv; v++) first_face[v] = ST_NIL;
    for (uint32_t q = 0; q < t->nf; q++) {
        uint32_t F = t->fidx[t->foff[q] + ((s->phase[q] + 2) & 3)];
        if (first_face[F] == ST_NIL) first_face[F] = q;
    }
    for (uint32_t F = 0; F < t->nv; F++) {
        if (s->lab[F] != LAB_F) continue;
        rank[F] = nf;
        st->f_fine[nf] = F;
        m->face_off[nf++] = nc;
        nc += t->valence[F];
    }
    m->face_off[nf] = nc;
    /* Interior face points (face_points): one corner per quad around them,
     * every quad around one; else the faces would overrun. */
    if (nc != t->nf) {
        failf(s, "the coarse faces do not cover the fine quads");
        return -1;
    }
    uint32_t open = ST_NIL;       /* the first face point (vertex order) whose quads do not close */
    int short_cycle = 0;
    for (uint32_t q0 = 0; q0 < t->nf; q0++) {
        uint32_t F = t->fidx[t->foff[q0] + ((s->phase[q0] + 2) & 3)];
        if (first_face[F] != q0 || (open != ST_NIL && F > open)) continue;
        uint32_t r = rank[F], c = m->face_off[r], end = m->face_off[r + 1], q = q0, n = 0;
        do {
            uint32_t b = t->foff[q], p = s->phase[q];
            uint32_t tw = t->twin[b + ((p + 1) & 3)];
            if (tw == ST_NIL || ++n > t->valence[F]) { open = F; break; }
            m->face_idx[c] = vmap[t->fidx[b + p]];
            corner_fine[c] = b + p;
            coarse_of[q] = r;
            st->e_fine[c++] = t->fidx[b + ((p + 1) & 3)];
            q = t->face_of[tw];
        } while (q != q0);
        if (open != F && c != end) short_cycle = 1;
    }
    if (open != ST_NIL) {
        failf(s, "vertex %u: the faces around this face point do not close", open + 1);
        return -1;
    }
    if (short_cycle) {
        failf(s, "the coarse faces do not cover the fine quads");
        return -1;
    }
    return 0;
}

/* Coarse faces of quadrisection: one per central triangle (x0 x1 x2); the
 * corner triangle across x_i -> x_(i+1) holds coarse vertex i, and the edge
 * from coarse vertex i to i+1 has edge point x_(i+1). */
static int build_tri_faces(step_ctx *s, st_unsub_step *st, const uint32_t *vmap, uint32_t *corner_fine, uint32_t *coarse_of)
{
    const st_unsub_topo *t = s->t;
    st_mesh *m = &st->coarse;
    uint32_t nf = 0, nc = 0;
    for (uint32_t f = 0; f < t->nf; f++) {
        if (s->phase[f] != CENTRAL) continue;
        uint32_t b = t->foff[f];
        m->face_off[nf] = nc;
        coarse_of[f] = nf;
        for (unsigned i = 0; i < 3; i++) {
            uint32_t tw = t->twin[b + i];
            uint32_t g = tw == ST_NIL ? ST_NIL : t->face_of[tw];
            if (g == ST_NIL || s->phase[g] == CENTRAL) {
                failf(s, "face %u: a central triangle must have a corner triangle across each edge", f + 1);
                return -1;
            }
            m->face_idx[nc] = vmap[t->fidx[t->foff[g] + s->phase[g]]];
            corner_fine[nc] = t->foff[g] + s->phase[g];
            coarse_of[g] = nf;
            st->e_fine[nc++] = t->fidx[b + (i + 1) % 3];
        }
        nf++;
    }
    m->face_off[nf] = nc;
    return 0;
}

/* Estimated coarse positions (polygon split): the inverted Catmull-Clark
 * rules, exact for an exact subdivision.  Interior vertex of valence n != 3:
 * V' = (n-3)/n v + 4/n² ΣE_i - 1/n² ΣF_i (the vertex rule with Σv_i taken
 * from the edge rule).  Boundary (edge-only rule V' = (a + 6v + b)/8 with
 * E = (v + a)/2): v = 2V' - (E_a + E_b)/2.  Valence 3, interior: from an
 * exact neighbour u across edge point E, v = 4E - F - F' - u.  Otherwise
 * the fine position. */
static void poly_positions(step_ctx *s, st_unsub_step *st, const uint32_t *vmap)
{
    const st_unsub_topo *t = s->t;
    st_mesh *m = &st->coarse;
    uint32_t nv = m->nverts;
    /* ΣE and ΣF (in m->pos) per coarse vertex: indexed by the coarse
     * vertex, not the fine one, so that a quarter or so of the scratch is
     * touched (the first touch of fresh memory is a page fault). */
    double *sum = s->acc;
    memset(sum, 0, 3 * (size_t)nv * sizeof *sum);
    memset(m->pos, 0, 3 * (size_t)nv * sizeof *m->pos);
    for (uint32_t q = 0; q < t->nf; q++) {
        uint32_t b = t->foff[q], p = s->phase[q];
        uint32_t V = t->fidx[b + p], E = t->fidx[b + ((p + 1) & 3)], F = t->fidx[b + ((p + 2) & 3)];
        for (int k = 0; k < 3; k++) {
            sum[3 * (size_t)vmap[V] + k] += s->pos[3 * (size_t)E + k];
            m->pos[3 * (size_t)vmap[V] + k] += s->pos[3 * (size_t)F + k];
        }
    }
    uint8_t *exact = s->mark;             /* per fine vertex */
    for (uint32_t cv = 0; cv < nv; cv++) {
        uint32_t V = st->v_fine[cv], n = t->valence[V];
        const double *pv = s->pos + 3 * (size_t)V;
        double *out = m->pos + 3 * (size_t)cv, *se = sum + 3 * (size_t)cv;
        exact[V] = 0;
        /* Crease rules (DeRose et al. 1998; the coarse edges and vertex of
         * a sharp fine chain are at least 1 sharp, unsubdivide.h, so the
         * rules are the full sharp ones): a corner (a sharp vertex, 3+
         * sharp edges, or a sharp edge at a boundary vertex) stays, V' = v;
         * a crease vertex V' = (a + 6v + b)/8 with its sharp edges' edge
         * points E = (v + a)/2 gives v = 2V' - (E_a + E_b)/2; one sharp
         * edge (a dart) keeps the fine position as its estimate. */
        unsigned ns = 0;
        uint32_t sa = ST_NIL, sb = ST_NIL;
        for (uint32_t k = t->out_off[V]; s->esharp && k < t->out_off[V + 1]; k++) {
            uint32_t c = t->out_c[k];
            if (s->esharp[c] <= 0 || t->twin[c] == ST_NIL) continue;
            ns++;
            if (sa == ST_NIL) sa = st_unsub_target(t, c);
            else sb = st_unsub_target(t, c);
        }
        int sharp_v = s->vsharp && s->vsharp[V] > 0;
        if (sharp_v || ns >= 3 || (ns && t->bnd[V])) {
            for (int k = 0; k < 3; k++) out[k] = pv[k];
            exact[V] = 1;
        } else if (ns == 2) {
            for (int k = 0; k < 3; k++) out[k] = 2 * pv[k] - 0.5 * (s->pos[3 * (size_t)sa + k] + s->pos[3 * (size_t)sb + k]);
            exact[V] = 1;
        } else if (ns == 1) {
            for (int k = 0; k < 3; k++) out[k] = pv[k];
        } else if (t->bnd[V]) {
            uint32_t ea = ST_NIL, eb = ST_NIL;
            for (uint32_t k = t->out_off[V]; k < t->out_off[V + 1]; k++) {
                uint32_t c = t->out_c[k], pc = st_unsub_prev(t, c);
                if (t->twin[c] == ST_NIL) ea = st_unsub_target(t, c);
                if (t->twin[pc] == ST_NIL) eb = t->fidx[pc];
            }
            int corner = n == 2 && s->boundary_interp == ST_BOUNDARY_EDGE_AND_CORNER;
            for (int k = 0; k < 3; k++)
                out[k] = corner || ea == ST_NIL || eb == ST_NIL ? pv[k]
                       : 2 * pv[k] - 0.5 * (s->pos[3 * (size_t)ea + k] + s->pos[3 * (size_t)eb + k]);
            exact[V] = !corner;
        } else if (n != 3) {
            double nn = (double)n;
            for (int k = 0; k < 3; k++)
                out[k] = (nn * pv[k] - 4 * se[k] / nn + out[k] / nn) / (nn - 3);
            exact[V] = 1;
        } else {
            for (int k = 0; k < 3; k++) out[k] = pv[k];
        }
    }
    /* Valence 3: one pass over the fine quads, from an exact neighbour. */
    for (uint32_t q = 0; q < t->nf; q++) {
        uint32_t b = t->foff[q], p = s->phase[q];
        uint32_t V = t->fidx[b + p];
        if (exact[V] || t->bnd[V] || (s->esharp && s->esharp[b + p] > 0)) continue;
        uint32_t E = t->fidx[b + ((p + 1) & 3)], F = t->fidx[b + ((p + 2) & 3)], G = face_point_across(s, q, 0);
        uint32_t tw = t->twin[b + ((p + 1) & 3)];
        if (G == ST_NIL || tw == ST_NIL) continue;
        uint32_t h = t->face_of[tw], U = t->fidx[t->foff[h] + s->phase[h]];
        if (!exact[U]) continue;
        const double *pu = m->pos + 3 * (size_t)vmap[U];
        double *out = m->pos + 3 * (size_t)vmap[V];
        for (int k = 0; k < 3; k++)
            out[k] = 4 * s->pos[3 * (size_t)E + k] - s->pos[3 * (size_t)F + k] - s->pos[3 * (size_t)G + k] - pu[k];
        exact[V] = 1;
    }
    for (uint32_t cv = 0; cv < nv; cv++) exact[st->v_fine[cv]] = 0;
}

/* The coarse mesh must be a manifold whose every edge has one edge point,
 * adjacent to both its ends in the fine mesh.  Its adjacency goes to *out
 * (the next step's). */
static int check_coarse(step_ctx *s, const st_unsub_step *st, st_unsub_topo *out)
{
    st_unsub_topo ct;
    if (st_unsub_topo_build(&ct, &st->coarse)) { failf(s, "out of memory"); return -1; }
    int rc = 0;
    uint32_t bad;
    if (st_unsub_topo_manifold(&ct, &bad)) {
        failf(s, "the coarse mesh read off the pattern is not a manifold around vertex %u", st->v_fine[bad] + 1);
        rc = -1;
    }
    for (uint32_t c = 0; c < ct.nc && !rc; c++) {
        uint32_t E = st->e_fine[c], tw = ct.twin[c];
        uint32_t a = st->v_fine[ct.fidx[c]], b = st->v_fine[st_unsub_target(&ct, c)];
        if ((tw != ST_NIL && st->e_fine[tw] != E) ||
            (st_unsub_find(s->t, a, E) == ST_NIL && st_unsub_find(s->t, E, a) == ST_NIL) ||
            (st_unsub_find(s->t, b, E) == ST_NIL && st_unsub_find(s->t, E, b) == ST_NIL)) {
            failf(s, "vertex %u: edge point of coarse vertices %u and %u that are not its neighbours", E + 1, a + 1, b + 1);
            rc = -1;
        }
    }
    if (rc) st_unsub_topo_free(&ct);
    else *out = ct;
    return rc;
}

/* ---- tags and UVs of the coarse mesh ---------------------------------------- */

/* The sharpness one level coarser whose child is s under OpenSubdiv's
 * uniform rule (a child edge or vertex has its parent's sharpness less one;
 * at or above ST_SHARP_INF it stays; DeRose et al. 1998): s + 1, or s when
 * infinitely sharp, or 0 when not sharp (a parent of sharpness at most 1
 * also gives 0: the smooth parent is the one chosen, the details carry the
 * difference).  -1 when no parent gives s: one more than s would be
 * infinitely sharp, whose children stay infinite. */
#define ST_SHARP_INF 10.0f
static float parent_sharpness(float s)
{
    if (s <= 0.0f) return 0.0f;
    if (s >= ST_SHARP_INF) return s;
    float p = s + 1.0f;
    return p >= ST_SHARP_INF ? -1.0f : p;
}

/* Sharpness of the fine edge a-b (0 when untagged), from per-corner values. */
static float fine_edge_sharpness(const st_unsub_topo *t, const float *esharp, uint32_t a, uint32_t b)
{
    uint32_t c = st_unsub_find(t, a, b);
    if (c == ST_NIL) c = st_unsub_find(t, b, a);
    return c == ST_NIL ? 0.0f : esharp[c];
}

/* Crease tags of the coarse mesh: each coarse edge a-b with edge point E is
 * the fine chain a-E-b, so both halves must carry one sharpness s, and the
 * coarse edge gets parent_sharpness(s); a sharp fine edge that is no half
 * of a coarse edge (inside a coarse face) has no coarse counterpart. */
static int carry_creases(step_ctx *s, const st_mesh *fine, st_unsub_step *st, const st_unsub_topo *ct)
{
    const st_unsub_topo *t = s->t;
    st_mesh *m = &st->coarse;
    const float *esharp = s->esharp;
    uint8_t *used = calloc((size_t)t->nc + 1, 1);
    m->crease_v = malloc(((size_t)ct->nc + 1) * 2 * sizeof *m->crease_v);
    m->crease_s = malloc(((size_t)ct->nc + 1) * sizeof *m->crease_s);
    int rc = 0;
    (void)fine;
    if (!esharp || !used || !m->crease_v || !m->crease_s) { failf(s, "out of memory"); rc = -1; goto done; }
    for (uint32_t c = 0; c < ct->nc && !rc; c++) {
        if (ct->twin[c] != ST_NIL && ct->twin[c] < c) continue;   /* each edge once */
        uint32_t a = st->v_fine[ct->fidx[c]], b = st->v_fine[st_unsub_target(ct, c)], E = st->e_fine[c];
        float sa = fine_edge_sharpness(t, esharp, a, E), sb = fine_edge_sharpness(t, esharp, E, b);
        uint32_t x;
        if ((x = st_unsub_find(t, a, E)) != ST_NIL) used[x] = 1;
        if ((x = st_unsub_find(t, E, a)) != ST_NIL) used[x] = 1;
        if ((x = st_unsub_find(t, E, b)) != ST_NIL) used[x] = 1;
        if ((x = st_unsub_find(t, b, E)) != ST_NIL) used[x] = 1;
        if (sa != sb && !(sa >= ST_SHARP_INF && sb >= ST_SHARP_INF)) {
            failf(s, "crease: edge %u-%u has sharpness %g but edge %u-%u, the other half of the same coarse edge, has %g",
                  a + 1, E + 1, (double)sa, E + 1, b + 1, (double)sb);
            rc = -1;
            break;
        }
        float p = parent_sharpness(sa);
        if (p < 0) {
            failf(s, "crease: edges %u-%u-%u have sharpness %g; one level coarser it would be %g, infinitely sharp, "
                  "whose children stay infinite", a + 1, E + 1, b + 1, (double)sa, (double)(sa + 1.0f));
            rc = -1;
            break;
        }
        if (p > 0 && s->crease_chaikin && p < ST_SHARP_INF) {
            failf(s, "crease: edges %u-%u-%u have sharpness %g under `t creasemethod chaikin`, whose parent sharpness "
                  "is not one value per edge", a + 1, E + 1, b + 1, (double)sa);
            rc = -1;
            break;
        }
        if (p > 0) {
            m->crease_v[2 * m->ncreases] = ct->fidx[c];
            m->crease_v[2 * m->ncreases + 1] = st_unsub_target(ct, c);
            m->crease_s[m->ncreases++] = p;
        }
    }
    for (uint32_t c = 0; c < t->nc && !rc; c++)
        if (esharp[c] > 0 && !used[c]) {
            failf(s, "crease: edge %u-%u (sharpness %g) lies inside a coarse face: no coarse edge refines into it",
                  t->fidx[c] + 1, st_unsub_target(t, c) + 1, (double)esharp[c]);
            rc = -1;
        }
done:
    free(used);
    return rc;
}

/* Corner tags: coarse vertices persist and take parent_sharpness; edge and
 * face points are new vertices, never sharp (their children of a smooth
 * rule), so a sharp one has no coarse counterpart. */
static int carry_corners(step_ctx *s, const st_mesh *fine, st_unsub_step *st, const uint32_t *vmap)
{
    st_mesh *m = &st->coarse;
    if (!fine->ncorners) return 0;
    m->corner_v = malloc((size_t)fine->ncorners * sizeof *m->corner_v);
    m->corner_s = malloc((size_t)fine->ncorners * sizeof *m->corner_s);
    if (!m->corner_v || !m->corner_s) { failf(s, "out of memory"); return -1; }
    for (uint32_t i = 0; i < fine->ncorners; i++) {
        uint32_t v = fine->corner_v[i];
        float sv = fine->corner_s[i], p = parent_sharpness(sv);
        if (sv <= 0) continue;
        if (vmap[v] == ST_NIL) {
            failf(s, "corner: vertex %u has sharpness %g but is %s, a vertex no coarse vertex refines into",
                  v + 1, (double)sv, lab_name[s->lab[v]]);
            return -1;
        }
        if (p < 0) {
            failf(s, "corner: vertex %u has sharpness %g; one level coarser it would be %g, infinitely sharp, "
                  "whose children stay infinite", v + 1, (double)sv, (double)(sv + 1.0f));
            return -1;
        }
        m->corner_v[m->ncorners] = vmap[v];
        m->corner_s[m->ncorners++] = p;
    }
    return 0;
}

/* Hole tags: a coarse face is a hole when all its fine faces are (its
 * children are holes at every level, and only those). */
static int carry_holes(step_ctx *s, const st_mesh *fine, st_unsub_step *st, const uint32_t *coarse_of)
{
    st_mesh *m = &st->coarse;
    if (!fine->face_hole) return 0;
    uint32_t *holes = calloc((size_t)m->nfaces + 1, sizeof *holes), *seen = calloc((size_t)m->nfaces + 1, sizeof *seen);
    m->face_hole = calloc((size_t)m->nfaces + 1, 1);
    int rc = 0;
    if (!holes || !seen || !m->face_hole) { failf(s, "out of memory"); rc = -1; goto done; }
    for (uint32_t f = 0; f < fine->nfaces; f++) {
        seen[coarse_of[f]]++;
        holes[coarse_of[f]] += fine->face_hole[f] != 0;
    }
    for (uint32_t f = 0; f < fine->nfaces && !rc; f++) {
        uint32_t cf = coarse_of[f];
        if (holes[cf] && holes[cf] != seen[cf]) {
            uint32_t g = f;
            while (g < fine->nfaces && (coarse_of[g] != cf || (fine->face_hole[g] != 0) == (fine->face_hole[f] != 0))) g++;
            uint32_t h = fine->face_hole[f] ? f : g, n = fine->face_hole[f] ? g : f;
            failf(s, "hole: face %u is a hole but face %u, a child of the same coarse face, is not", h + 1, n + 1);
            rc = -1;
        }
        m->face_hole[cf] = holes[cf] == seen[cf];
    }
done:
    free(holes);
    free(seen);
    return rc;
}

/* UVs: the coarse corner at coarse vertex v of a coarse face takes the UV
 * of v's corner in the fine face at that corner (coarse vertices persist;
 * their face-varying values with them).  The UV values used are renumbered
 * in order of first use. */
static int carry_uvs(step_ctx *s, const st_mesh *fine, st_unsub_step *st, const uint32_t *corner_fine)
{
    st_mesh *m = &st->coarse;
    if (!fine->face_uv) return 0;
    uint32_t nc = m->face_off[m->nfaces];
    uint32_t *renum = malloc(((size_t)fine->nuvs + 1) * sizeof *renum);
    m->face_uv = malloc(((size_t)nc + 1) * sizeof *m->face_uv);
    m->uv = malloc(((size_t)nc + 1) * 2 * sizeof *m->uv);
    if (!renum || !m->face_uv || !m->uv) { free(renum); failf(s, "out of memory"); return -1; }
    for (uint32_t i = 0; i < fine->nuvs; i++) renum[i] = ST_NIL;
    for (uint32_t c = 0; c < nc; c++) {
        uint32_t u = fine->face_uv[corner_fine[c]];
        if (renum[u] == ST_NIL) {
            renum[u] = m->nuvs;
            memcpy(m->uv + 2 * (size_t)m->nuvs++, fine->uv + 2 * (size_t)u, 2 * sizeof(double));
        }
        m->face_uv[c] = renum[u];
    }
    free(renum);
    return 0;
}

static int carry_tags(step_ctx *s, const st_mesh *fine, st_unsub_step *st, const st_unsub_topo *ct,
                      const uint32_t *vmap, const uint32_t *corner_fine, const uint32_t *coarse_of)
{
    st_mesh *m = &st->coarse;
    m->crease_method = fine->crease_method;
    m->tri_sub = fine->tri_sub;
    s->crease_chaikin = fine->crease_method == ST_CREASE_CHAIKIN;
    if (fine->ncreases && carry_creases(s, fine, st, ct)) return -1;
    if (carry_corners(s, fine, st, vmap) || carry_holes(s, fine, st, coarse_of)) return -1;
    return carry_uvs(s, fine, st, corner_fine);
}

/* Which pattern the face degrees allow; -1 with the face that breaks it. */
static int pick_pattern(step_ctx *s, const st_mesh *m)
{
    uint32_t quads = 0, tris = 0, q1 = ST_NIL, t1 = ST_NIL, o1 = ST_NIL;
    for (uint32_t f = 0; f < m->nfaces; f++) {
        uint32_t n = m->face_off[f + 1] - m->face_off[f];
        if (n == 4) { quads++; if (q1 == ST_NIL) q1 = f; }
        else if (n == 3) { tris++; if (t1 == ST_NIL) t1 = f; }
        else if (o1 == ST_NIL) o1 = f;
    }
    if (m->nfaces && quads == m->nfaces) return ST_UNSUB_POLY_SPLIT;
    if (m->nfaces && tris == m->nfaces) return ST_UNSUB_QUADRISECTION;
    if (!m->nfaces) { failf(s, "the mesh has no faces"); return -1; }
    if (quads >= tris) {
        uint32_t f = t1 != ST_NIL ? t1 : o1;
        failf(s, "face %u has %u sides: a polygon split gives quads only (as face %u)", f + 1, m->face_off[f + 1] - m->face_off[f], q1 + 1);
    } else {
        uint32_t f = q1 != ST_NIL ? q1 : o1;
        failf(s, "face %u has %u sides: a triangle quadrisection gives triangles only (as face %u)", f + 1, m->face_off[f + 1] - m->face_off[f], t1 + 1);
    }
    return -1;
}

/* The fine mesh's tags by corner and vertex (NULL when it has none). */
static int fine_tags(step_ctx *s, const st_mesh *fine)
{
    const st_unsub_topo *t = s->t;
    if (fine->ncreases) {
        if (!(s->esharp = calloc((size_t)t->nc + 1, sizeof *s->esharp))) { failf(s, "out of memory"); return -1; }
        for (uint32_t i = 0; i < fine->ncreases; i++) {
            uint32_t a = fine->crease_v[2 * i], b = fine->crease_v[2 * i + 1];
            uint32_t c = st_unsub_find(t, a, b), d = st_unsub_find(t, b, a);
            if (c != ST_NIL) s->esharp[c] = fine->crease_s[i];
            if (d != ST_NIL) s->esharp[d] = fine->crease_s[i];
        }
    }
    if (fine->ncorners) {
        if (!(s->vsharp = calloc((size_t)t->nv + 1, sizeof *s->vsharp))) { failf(s, "out of memory"); return -1; }
        for (uint32_t i = 0; i < fine->ncorners; i++) s->vsharp[fine->corner_v[i]] = fine->corner_s[i];
    }
    return 0;
}

/* One step from `fine` (pattern fixed, or chosen when ST_UNSUB_NONE). */
/* t: the adjacency of `fine` (built here when empty); on success it is
 * replaced by the coarse mesh's. */
/* One step on `fine`, whose adjacency is *topo (built here on the first
 * step); afterwards *topo is the coarse mesh's (empty on failure) and
 * *used the fine mesh's, which the caller keeps or frees. */
static int unsub_step(step_ctx *s, const st_mesh *fine, int *pattern, st_unsub_step *st, st_unsub_topo *topo, double diag,
                      st_unsub_topo *used)
{
    memset(used, 0, sizeof *used);
    if (*pattern == ST_UNSUB_NONE) {
        int p = pick_pattern(s, fine);
        if (p < 0) return -1;
        *pattern = p;
    } else {
        unsigned want = *pattern == ST_UNSUB_POLY_SPLIT ? 4 : 3;
        for (uint32_t f = 0; f < fine->nfaces; f++)
            if (fine->face_off[f + 1] - fine->face_off[f] != want) {
                failf(s, "face %u has %u sides", f + 1, fine->face_off[f + 1] - fine->face_off[f]);
                return -1;
            }
    }
    s->pattern = *pattern;
    s->pos = fine->pos;
    s->boundary_interp = fine->boundary_interp;
    if (!topo->face_of && st_unsub_topo_build(topo, fine)) { failf(s, "out of memory"); return -1; }
    st_unsub_topo t = *topo, next;
    memset(&next, 0, sizeof next);
    s->t = &t;
    size_t nv = (size_t)t.nv + 1, nf = (size_t)t.nf + 1;
    /* Large scratch on huge pages (hugepage.h): one fault per 2 MiB. */
    s->lab = st_calloc_huge(nv, 1);
    s->phase = st_malloc_huge(nf);
    s->queue = st_malloc_huge(nf * sizeof *s->queue);
    s->best_queue = malloc(nf * sizeof *s->best_queue);
    s->best_phase = malloc(nf);
    s->acc = st_malloc_huge(3 * nv * sizeof *s->acc);
    s->mark = st_calloc_huge(nv, 1);
    uint32_t *vmap = st_malloc_huge(nv * sizeof *vmap);
    /* Per coarse corner: the fine corner at its coarse vertex; per fine
     * face: its coarse face (tags and UVs, carry_tags). */
    uint32_t *corner_fine = st_malloc_huge(((size_t)t.nc + 1) * sizeof *corner_fine);
    uint32_t *coarse_of = st_malloc_huge(nf * sizeof *coarse_of);
    int rc = -1;
    if (!s->lab || !s->phase || !s->queue || !s->best_queue || !s->best_phase || !s->acc || !s->mark || !vmap ||
        !corner_fine || !coarse_of) { failf(s, "out of memory"); goto done; }
    memset(s->phase, NO_PHASE, nf);
    /* `t interpolateboundary 0` makes the faces at boundary vertices holes
     * (hier.c); at a coarser level those are coarser faces, whose children
     * are more faces than the input's: no cage gives the input's holes. */
    for (uint32_t v = 0; v < t.nv && fine->boundary_interp == ST_BOUNDARY_NONE; v++)
        if (t.bnd[v]) {
            failf(s, "`t interpolateboundary 0` with a boundary (vertex %u): a coarser mesh's boundary holes cover other faces", v + 1);
            goto done;
        }
    if (fine_tags(s, fine)) goto done;
    if (label_all(s, 1e-12 * (diag > 0 ? diag : 1))) goto done;
    uint32_t ncv = 0, ncf = 0;
    for (uint32_t v = 0; v < t.nv; v++) {
        vmap[v] = s->lab[v] == LAB_V ? ncv++ : ST_NIL;
        ncf += s->pattern == ST_UNSUB_POLY_SPLIT ? s->lab[v] == LAB_F : 0;
    }
    uint32_t ncc = t.nf;                  /* polygon split: one coarse corner per fine quad */
    if (s->pattern == ST_UNSUB_QUADRISECTION) {
        ncf = 0;
        for (uint32_t f = 0; f < t.nf; f++) ncf += s->phase[f] == CENTRAL;
        ncc = 3 * ncf;
        if (4 * ncf != t.nf) { failf(s, "%u central triangles for %u faces: expected a quarter", ncf, t.nf); goto done; }
    }
    if (alloc_step(st, ncv, ncf, ncc, s->pattern == ST_UNSUB_POLY_SPLIT)) { failf(s, "out of memory"); goto done; }
    st->coarse.boundary_interp = fine->boundary_interp;
    for (uint32_t v = 0; v < t.nv; v++)
        if (vmap[v] != ST_NIL) st->v_fine[vmap[v]] = v;
    if (s->pattern == ST_UNSUB_POLY_SPLIT) {
        uint32_t *first = st_malloc_huge(nv * sizeof *first), *rank = st_malloc_huge(nv * sizeof *rank);
        if (!first || !rank) { free(first); free(rank); failf(s, "out of memory"); goto done; }
        int b = build_poly_faces(s, st, vmap, first, rank, corner_fine, coarse_of);
        free(first);
        free(rank);
        if (b) goto done;
        if (st->coarse.face_off[ncf] != ncc) { failf(s, "the coarse faces do not cover the fine quads"); goto done; }
        poly_positions(s, st, vmap);
    } else {
        if (build_tri_faces(s, st, vmap, corner_fine, coarse_of)) goto done;
        for (uint32_t cv = 0; cv < ncv; cv++)
            memcpy(st->coarse.pos + 3 * (size_t)cv, fine->pos + 3 * (size_t)st->v_fine[cv], 3 * sizeof(double));
    }
    if (check_coarse(s, st, &next)) goto done;
    if (carry_tags(s, fine, st, &next, vmap, corner_fine, coarse_of)) { st_unsub_topo_free(&next); memset(&next, 0, sizeof next); goto done; }
    rc = 0;
done:
    free(corner_fine); free(coarse_of);
    if (rc) free_step(st);
    free(s->lab); free(s->phase); free(s->queue); free(s->acc); free(s->mark); free(vmap);
    free(s->best_queue); free(s->best_phase);
    free(s->esharp); free(s->vsharp);
    s->esharp = s->vsharp = NULL;
    s->lab = s->phase = s->mark = s->best_phase = NULL;
    s->queue = s->best_queue = NULL;
    s->acc = NULL;
    *used = t;
    *topo = next;
    return rc;
}

void st_unsub_free(st_unsub *u)
{
    for (unsigned j = 0; j < ST_MAX_LEVELS; j++) free_step(&u->step[j]);
    for (unsigned j = 0; j <= ST_MAX_LEVELS; j++) {
        if (u->topo[j]) st_unsub_topo_free(u->topo[j]);
        free(u->topo[j]);
        u->topo[j] = NULL;
    }
    u->levels = 0;
    u->pattern = ST_UNSUB_NONE;
}

static const char *pattern_name(int p)
{
    return p == ST_UNSUB_POLY_SPLIT ? "polygon split (Catmull-Clark)" : p == ST_UNSUB_QUADRISECTION ? "triangle quadrisection (Loop, Butterfly)" : "polygon split (Catmull-Clark) or triangle quadrisection (Loop, Butterfly)";
}

/* adj[i] (the adjacency of step i's fine mesh: level k - i) into
 * out->topo[k - i], each in its own allocation so that st_unsub stays
 * a plain struct; one that cannot be allocated is freed (rebuilt later). */
static void keep_topologies(st_unsub *out, st_unsub_topo *adj, unsigned k)
{
    for (unsigned i = 0; i <= k; i++) {
        st_unsub_topo *t = adj[i].face_of ? malloc(sizeof *t) : NULL;
        if (t) *t = adj[i];
        else st_unsub_topo_free(&adj[i]);
        out->topo[k - i] = t;
    }
}

int st_unsubdivide(const char *name, const st_mesh *in, const st_unsub_opts *o, st_unsub *out, st_error *err)
{
    memset(out, 0, sizeof *out);
    for (unsigned j = 0; j < ST_MAX_LEVELS; j++) st_mesh_init(&out->step[j].coarse);
    st_unsub_step found[ST_MAX_LEVELS];
    memset(found, 0, sizeof found);
    /* adj[i]: the adjacency of step i's fine mesh (adj[k]: the cage's). */
    st_unsub_topo adj[ST_MAX_LEVELS + 1];
    memset(adj, 0, sizeof adj);
    step_ctx s = { 0 };
    int pattern = ST_UNSUB_NONE;
    unsigned k = 0;
    const st_mesh *cur = in;
    st_unsub_topo topo;
    memset(&topo, 0, sizeof topo);
    /* One scale for the tie tolerance of every step: the input's. */
    double diag = st_mesh_diagonal(in);
    unsigned max = o && o->max_levels ? o->max_levels : ST_MAX_LEVELS - 1;
    if (max > ST_MAX_LEVELS - 1) max = ST_MAX_LEVELS - 1;
    for (;;) {
        if (k == max) {
            snprintf(out->stop, sizeof out->stop, "stopped after %u step%s (the most allowed)", k, k == 1 ? "" : "s");
            adj[k] = topo;   /* the cage's, from the last step */
            memset(&topo, 0, sizeof topo);
            break;
        }
        st_unsub_step st;
        memset(&st, 0, sizeof st);
        st_mesh_init(&st.coarse);
        if (unsub_step(&s, cur, &pattern, &st, &topo, diag, &adj[k])) {
            if (k == 0) {
                st_unsub_topo_free(&topo);
                st_unsub_topo_free(&adj[0]);
                int code = strncmp(s.fail, "out of memory", 13) ? ST_ERR_TOPOLOGY : ST_ERR_MEMORY;
                return st_fail(err, code, "%s: not a %s of a coarser mesh: %s", name,
                               pattern_name(pattern), s.fail);
            }
            snprintf(out->stop, sizeof out->stop, "level 0 (%u faces) is no %s of a coarser mesh: %s",
                     cur->nfaces, pattern_name(pattern), s.fail);
            if (!adj[k].face_of) {   /* refused before the step took the cage's adjacency */
                adj[k] = topo;
                memset(&topo, 0, sizeof topo);
            }
            break;
        }
        if (o && o->target_faces && st.coarse.nfaces < o->target_faces && k > 0) {
            snprintf(out->stop, sizeof out->stop, "one more step would leave %u faces, fewer than the %u asked for",
                     st.coarse.nfaces, o->target_faces);
            free_step(&st);
            break;
        }
        if (o && o->target_faces && st.coarse.nfaces < o->target_faces && k == 0) {
            /* Not even one step fits the target: a refusal like any other. */
            free_step(&st);
            st_unsub_topo_free(&topo);
            st_unsub_topo_free(&adj[0]);
            return st_fail(err, ST_ERR_INVALID, "%s: one step would leave %u faces, fewer than --target-faces %u",
                           name, st.coarse.nfaces, o->target_faces);
        }
        found[k++] = st;
        cur = &found[k - 1].coarse;
    }
    st_unsub_topo_free(&topo);
    out->pattern = pattern;
    out->levels = k;
    for (unsigned i = 0; i < k; i++) out->step[k - 1 - i] = found[i];
    keep_topologies(out, adj, k);
    return ST_OK;
}

int st_unsub_scheme_fits(const st_unsub *u, const st_scheme *sc)
{
    if (u->pattern == ST_UNSUB_QUADRISECTION)
        return sc->id == ST_SCHEME_LOOP || sc->id == ST_SCHEME_BUTTERFLY || sc->id == ST_SCHEME_QUADTRI;
    if (u->pattern != ST_UNSUB_POLY_SPLIT || !u->levels) return 0;
    if (sc->id == ST_SCHEME_CATMARK) return 1;
    if (sc->id != ST_SCHEME_QUADTRI) return 0;
    /* Quad/triangle splits triangles by quadrisection: a cage with none. */
    const st_mesh *c = &u->step[0].coarse;
    for (uint32_t f = 0; f < c->nfaces; f++)
        if (c->face_off[f + 1] - c->face_off[f] == 3) return 0;
    return 1;
}
