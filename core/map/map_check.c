/* The map validator (map.h): every level must be a valid closed 2-map whose
 * cells agree with their attributes.  Reports the first failure; never
 * aborts.  Cost O(|B^l|) per level plus one scratch byte per dart and one
 * scratch word per vertex. */
#include "core/map/map.h"

#include <stdlib.h>
#include <string.h>

typedef struct check_ctx {
    st_map *m;
    unsigned l;
    uint8_t *hit;        /* per dart: times it is a β1 image at this level */
    uint32_t *owner;     /* per vertex: first dart of the orbit that carries it */
    st_error *err;
} check_ctx;

static int check_dart(check_ctx *c, uint32_t d)
{
    st_map *m = c->m;
    unsigned l = c->l;
    uint32_t e = st_beta0(m, d, l), f = st_beta1(m, d, l), v = st_vert(m, d, l);
    if (!st_dart_in_level(m, e, l))
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: beta0 = %u is not a dart of the level", l, d, e);
    if (e == d)
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: beta0 has a fixed point", l, d);
    if (st_beta0(m, e, l) != d)
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: beta0 is not an involution (beta0(beta0(d)) = %u)", l, d, st_beta0(m, e, l));
    if (!st_dart_in_level(m, f, l))
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: beta1 = %u is not a dart of the level", l, d, f);
    if (++c->hit[f] > 1)
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: beta1 is not a permutation (%u has two preimages)", l, d, f);
    if (v >= m->verts.end || m->verts.ins[v] == ST_FREE_LEVEL || m->verts.ins[v] > l)
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: vertex %u does not exist at this level", l, d, v);
    uint32_t n = st_phi1(m, d, l);
    /* The embedded cell: vertex orbits, or face orbits in the dual encoding. */
    uint32_t same = m->face_embedded ? n : f;
    if (!(m->face_embedded && st_is_boundary(m, d)) && st_vert(m, same, l) != v)
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: %s orbit carries two vertices (%u and %u)", l, d,
                       m->face_embedded ? "face" : "vertex", v, st_vert(m, same, l));
    /* The hole flag is on the cell that stands for a face: φ1 orbits, or β1
     * orbits in the dual encoding. */
    if (st_is_boundary(m, m->face_embedded ? f : n) != st_is_boundary(m, d))
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: face mixes boundary and real darts", l, d);
    if (st_is_boundary(m, d) && st_is_boundary(m, e))
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: two boundary faces share an edge", l, d);
    /* A hole face (ST_DART_HOLE) is all hole, and never a boundary face. */
    if (st_is_hole(m, m->face_embedded ? f : n) != st_is_hole(m, d) || (st_is_hole(m, d) && st_is_boundary(m, d)))
        return st_fail(c->err, ST_ERR_INVALID, "level %u, dart %u: face mixes hole and other darts", l, d);
    return ST_OK;
}

/* Called once per vertex orbit: each vertex id must be carried by exactly
 * one orbit. */
static int check_vertex_owner(check_ctx *c, uint32_t d)
{
    uint32_t v = st_vert(c->m, d, c->l);
    if (c->owner[v] != ST_NIL)
        return st_fail(c->err, ST_ERR_INVALID, "level %u: vertex %u is carried by two orbits (darts %u and %u)", c->l, v, c->owner[v], d);
    c->owner[v] = d;
    return ST_OK;
}

static int check_level(check_ctx *c)
{
    st_map *m = c->m;
    st_dart_iter it;
    memset(c->hit, 0, m->darts.end);
    for (uint32_t v = 0; v < m->verts.end; v++) c->owner[v] = ST_NIL;
    for (uint32_t d = st_dart_first(m, c->l, &it); d != ST_NIL; d = st_dart_next(m, c->l, &it)) {
        if (m->darts.ins[d] > m->top)
            return st_fail(c->err, ST_ERR_INVALID, "dart %u: insertion level %u above the top level %u", d, m->darts.ins[d], m->top);
        int rc = check_dart(c, d);
        if (rc) return rc;
    }
    /* Only darts of B^l may be β1 images, each exactly once: with the checks
     * above, a dart of B^l that is never hit would mean another one is hit
     * twice, so permutation-ness is complete. */
    int vmark = st_marker_reserve(m);
    int rc = ST_OK;
    for (uint32_t d = st_dart_first(m, c->l, &it); d != ST_NIL && !rc; d = st_dart_next(m, c->l, &it)) {
        if (st_marked(m, vmark, d) || (m->face_embedded && st_is_boundary(m, d))) continue;
        if (m->face_embedded) st_mark_face(m, vmark, d, c->l);
        else st_mark_vertex(m, vmark, d, c->l);
        rc = check_vertex_owner(c, d);
    }
    st_marker_release(m, vmark, c->l);
    if (rc) return rc;
    /* In the dual encoding the surface's vertices of a coarser level are not
     * carried by the finer maps (Doo-Sabin replaces every vertex). */
    if (m->face_embedded) return ST_OK;
    for (uint32_t v = st_vertex_first(m, c->l, &it); v != ST_NIL; v = st_vertex_next(m, c->l, &it))
        if (c->owner[v] == ST_NIL)
            return st_fail(c->err, ST_ERR_INVALID, "level %u: vertex %u exists but no dart carries it", c->l, v);
    return ST_OK;
}

int st_map_validate(st_map *m, st_error *err)
{
    check_ctx c = { .m = m, .err = err };
    c.hit = malloc(m->darts.end ? m->darts.end : 1);
    c.owner = malloc((m->verts.end ? m->verts.end : 1) * sizeof *c.owner);
    int rc = (!c.hit || !c.owner) ? st_fail(err, ST_ERR_MEMORY, "validator: out of memory") : ST_OK;
    for (unsigned l = 0; l <= m->top && !rc; l++) {
        c.l = l;
        rc = check_level(&c);
    }
    free(c.hit);
    free(c.owner);
    if (!rc && err) { err->code = ST_OK; err->msg[0] = 0; }
    return rc;
}
