/* Higher operators across levels (Kraemer 2008 §2.3.2).  Each acts on
 * the map of level l: it inserts darts at level l and changes level-l
 * relations, so the levels below l are untouched, and the levels above l
 * follow wherever they had not diverged (map.h, "Setting a relation"). */
#include "core/map/map.h"

/* ---- split an edge by a new vertex (fig. 2.4) ------------------------------
 *
 *     before (level l)              after
 *        d: u ---------> w          d: u --> m   a: m --> w
 *        e: u <--------- w          b: u <-- m   e: m <-- w
 *
 * The new vertex m has the β1 cycle (a b); β1 of old darts is untouched. */
uint32_t st_split_edge(st_map *m, uint32_t d, unsigned l, const double p[3])
{
    uint32_t e = st_beta0(m, d, l);
    uint32_t v = st_vertex_new(m, l, p);
    uint32_t a = st_dart_new(m, l, v, m->flags[d]);
    uint32_t b = st_dart_new(m, l, v, m->flags[e]);
    st_set_beta1(m, a, l, b);
    st_set_beta1(m, b, l, a);
    st_sew0(m, d, b, l);
    st_sew0(m, e, a, l);
    return a;
}

/* True when relation values of x stay those of level l on every level above. */
static int unchanged_above(const st_map *m, uint32_t x, unsigned l)
{
    for (unsigned k = l + 1; k <= m->top; k++)
        if (st_beta0(m, x, k) != st_beta0(m, x, l) || st_beta1(m, x, k) != st_beta1(m, x, l))
            return 0;
    return 1;
}

int st_unsplit_edge(st_map *m, uint32_t a, unsigned l, st_error *err)
{
    uint32_t b = st_beta1(m, a, l);
    if (st_dart_level(m, a) != l || st_dart_level(m, b) != l || st_beta1(m, b, l) != a)
        return st_fail(err, ST_ERR_INVALID, "unsplit: dart %u is not on a degree-2 vertex inserted at level %u", a, l);
    if (!unchanged_above(m, a, l) || !unchanged_above(m, b, l))
        return st_fail(err, ST_ERR_INVALID, "unsplit: the vertex of dart %u is refined above level %u", a, l);
    uint32_t v = st_vert(m, a, l);
    uint32_t e = st_beta0(m, a, l), d = st_beta0(m, b, l);
    st_sew0(m, d, e, l);
    st_dart_delete(m, a);
    st_dart_delete(m, b);
    st_vertex_delete(m, v);
    return ST_OK;
}

/* ---- cut a face by a new edge (listing 2.4.3) ------------------------------
 *
 * Face (d1 ... p1 d2 ... p2).  New darts x: vert(d1) -> vert(d2) and
 * y = β0(x).  x is inserted in the β1 cycle of vert(d1) just before d1, so
 * φ1(p1) = x and φ1(x) = d2: faces (x d2 ... p1) and (y d1 ... p2). */
uint32_t st_cut_face(st_map *m, uint32_t d1, uint32_t d2, unsigned l)
{
    uint32_t p1 = st_phi_1(m, d1, l), p2 = st_phi_1(m, d2, l);
    uint32_t q1 = st_beta0(m, p1, l), q2 = st_beta0(m, p2, l);
    uint32_t x = st_dart_new(m, l, st_vert(m, d1, l), m->flags[d1]);
    uint32_t y = st_dart_new(m, l, st_vert(m, d2, l), m->flags[d1]);
    st_sew0(m, x, y, l);
    st_set_beta1(m, q1, l, x);
    st_set_beta1(m, x, l, d1);
    st_set_beta1(m, q2, l, y);
    st_set_beta1(m, y, l, d2);
    return x;
}

int st_uncut_face(st_map *m, uint32_t x, unsigned l, st_error *err)
{
    uint32_t y = st_beta0(m, x, l);
    if (st_dart_level(m, x) != l || st_dart_level(m, y) != l)
        return st_fail(err, ST_ERR_INVALID, "uncut: edge of dart %u was not inserted at level %u", x, l);
    if (st_beta1(m, x, l) == x || st_beta1(m, y, l) == y)
        return st_fail(err, ST_ERR_INVALID, "uncut: edge of dart %u is dangling", x);
    if (!unchanged_above(m, x, l) || !unchanged_above(m, y, l))
        return st_fail(err, ST_ERR_INVALID, "uncut: edge of dart %u changes above level %u", x, l);
    uint32_t q1 = st_beta1_inv(m, x, l), q2 = st_beta1_inv(m, y, l);
    st_set_beta1(m, q1, l, st_beta1(m, x, l));
    st_set_beta1(m, q2, l, st_beta1(m, y, l));
    st_dart_delete(m, x);
    st_dart_delete(m, y);
    return ST_OK;
}

/* ---- flip an edge (√3, thesis §3.4.2) ---------------------------------------
 *
 * Faces A = (d a1 ... ak) and B = (e b1 ... bk') with e = β0(d).  The flip
 * gives A' = (d ak b1 ... b(k'-1)) and B' = (e bk' a1 ... a(k-1)): d now
 * starts at vert(bk'), e at vert(ak).  For two triangles this is the other
 * diagonal of their quad.  Every new φ1 link is written as a β1 link through
 * φ1(z) = β1(β0(z)); all targets are read before anything is written. */
struct rotation {
    uint32_t dart[6], next[6]; /* β1(dart[i]) := next[i] */
    uint32_t vd, ve;           /* new vertices of d and e */
};

static void apply_rotation(st_map *m, uint32_t d, uint32_t e, unsigned l, const struct rotation *r)
{
    for (int i = 0; i < 6; i++) st_set_beta1(m, r->dart[i], l, r->next[i]);
    st_set_vert(m, d, l, r->vd);
    st_set_vert(m, e, l, r->ve);
}

static int flip_precheck(const st_map *m, uint32_t d, unsigned l, st_error *err)
{
    uint32_t e = st_beta0(m, d, l);
    if (st_is_boundary(m, d) || st_is_boundary(m, e))
        return st_fail(err, ST_ERR_INVALID, "flip: edge of dart %u borders a boundary face", d);
    if (st_face_degree(m, d, l) < 3 || st_face_degree(m, e, l) < 3)
        return st_fail(err, ST_ERR_INVALID, "flip: a face of dart %u has fewer than 3 sides", d);
    if (st_vertex_degree(m, d, l) < 2 || st_vertex_degree(m, e, l) < 2)
        return st_fail(err, ST_ERR_INVALID, "flip: an end of dart %u has degree 1", d);
    return ST_OK;
}

int st_flip_edge(st_map *m, uint32_t d, unsigned l, st_error *err)
{
    if (flip_precheck(m, d, l, err)) return err ? err->code : ST_ERR_INVALID;
    uint32_t e = st_beta0(m, d, l);
    uint32_t a1 = st_phi1(m, d, l), ak = st_phi_1(m, d, l);
    uint32_t b1 = st_phi1(m, e, l), bk = st_phi_1(m, e, l);
    uint32_t ak1 = st_phi_1(m, ak, l), bk1 = st_phi_1(m, bk, l); /* a(k-1), b(k'-1) */
    struct rotation r = {
        .dart = { e, d, st_beta0(m, ak, l), st_beta0(m, bk, l), st_beta0(m, bk1, l), st_beta0(m, ak1, l) },
        .next = { ak, bk, b1, a1, d, e },
        .vd = st_vert(m, bk, l), .ve = st_vert(m, ak, l),
    };
    apply_rotation(m, d, e, l, &r);
    return ST_OK;
}

/* Inverse of st_flip_edge: with A' = (d s1 s2 ... sm) and B' = (e t1 t2 ... tn)
 * it restores A = (d t2 ... tn s1) and B = (e s2 ... sm t1). */
int st_flip_edge_back(st_map *m, uint32_t d, unsigned l, st_error *err)
{
    if (flip_precheck(m, d, l, err)) return err ? err->code : ST_ERR_INVALID;
    uint32_t e = st_beta0(m, d, l);
    uint32_t s1 = st_phi1(m, d, l), s2 = st_phi1(m, s1, l), sm = st_phi_1(m, d, l);
    uint32_t t1 = st_phi1(m, e, l), t2 = st_phi1(m, t1, l), tn = st_phi_1(m, e, l);
    struct rotation r = {
        .dart = { e, st_beta0(m, tn, l), st_beta0(m, s1, l), d, st_beta0(m, sm, l), st_beta0(m, t1, l) },
        .next = { t2, s1, d, s2, t1, e },
        .vd = st_vert(m, s2, l), .ve = st_vert(m, t2, l),
    };
    apply_rotation(m, d, e, l, &r);
    return ST_OK;
}
