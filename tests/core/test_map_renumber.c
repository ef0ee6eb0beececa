/* The dense renumbering of a map's ids (core/map/renumber_internal.h) and
 * the map written under it (st_map_write_renumbered): on adaptive maps
 * whose box moved (freed ids on free lists), with the top level removed
 * (its blocks spare), for several kept levels:
 *   - the renumbered pool is packed above `keep` (every block of a level
 *     full but its last, no free list) and the same as before up to it
 *     (ids, blocks, fill pointers, free lists);
 *   - the bytes read back (st_map_read) give a valid map (st_map_validate)
 *     that is the original under the renumbering: insertion levels, flags,
 *     the relations and positions of every level bit for bit, the old
 *     order kept within each level;
 *   - the map read back renumbers to the identity and writes the same
 *     bytes again (what makes a session's save -> load -> save stable). */
#include "core/adapt/adapt.h"
#include "core/io/map_io_internal.h"
#include "core/map/renumber_internal.h"
#include "core/multires/hier_internal.h"
#include "core/progressive/scheme_registry.h"
#include "testlib.h"

#include <stdlib.h>
#include <string.h>

static int box_update(st_adapt *a, unsigned base, unsigned max, double c, double r)
{
    st_adapt_params p = { .base_level = base, .max_level = max, .has_box = 1 };
    for (int k = 0; k < 3; k++) {
        p.box_lo[k] = c - r;
        p.box_hi[k] = c + r;
    }
    st_error err;
    int rc = st_adapt_update(a, &p, &err);
    CHECKF(rc == ST_OK, "box update: %s", err.msg);
    return rc;
}

/* The cube to level 1, refined to level 5 in a box at one corner with
 * details on every fourth vertex of levels 4 and 5 (kept: keep_above),
 * then the box at the opposite corner, then off: the faces without
 * details coarsen, their ids go on free lists. */
static int build(st_hier *h, st_adapt *a)
{
    st_mesh s;
    st_error err;
    tl_mesh_cube(&s);
    int rc = st_hier_init(h, &s, st_scheme_get(ST_SCHEME_CATMARK), NULL, &err);
    st_mesh_free(&s);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (rc) return rc;
    rc = st_hier_subdivide_to(h, 1, &err);
    if (!rc) rc = st_adapt_init(a, h, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    if (rc) { st_hier_free(h); return rc; }
    a->keep_above = 1;
    if (box_update(a, 1, 5, 0.9, 0.3)) goto fail;
    unsigned k = 0;
    for (unsigned l = 4; l <= 5; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
            if (h->map.verts.ins[v] == l && k++ % 4 == 0) {
                double d[3] = { 0.001 * (v % 5), 0.002, -0.001 };
                st_hier_set_detail(h, l, v, d);
            }
    }
    st_adapt_synthesize(a, 1);
    if (box_update(a, 1, 5, 0.1, 0.25)) goto fail;
    /* The box off: the second box's faces (no details) coarsen too. */
    st_adapt_params off = { .base_level = 1, .max_level = 1 };
    if (st_adapt_update(a, &off, &err)) { CHECKF(0, "box off: %s", err.msg); goto fail; }
    return 0;
fail:
    st_adapt_free(a);
    st_hier_free(h);
    return -1;
}

/* The pool q renumbered from p with `keep`: packed above keep, as it was
 * up to keep. */
static int pool_ok(const st_pool *p, const st_pool *q, unsigned keep)
{
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (q->live[l] != p->live[l]) return 0;
        if (l <= keep) {
            if (q->nblocks[l] != p->nblocks[l] || q->fill[l] != p->fill[l] || q->freehead[l] != p->freehead[l]) return 0;
            if (p->nblocks[l] && memcmp(q->blocks[l], p->blocks[l], p->nblocks[l] * sizeof *p->blocks[l])) return 0;
            for (uint32_t id = p->freehead[l]; id != ST_NIL; id = p->next_free[id])
                if (q->next_free[id] != p->next_free[id]) return 0;
            continue;
        }
        if (q->nblocks[l] != (q->live[l] + ST_POOL_BLOCK - 1) / ST_POOL_BLOCK || q->freehead[l] != ST_NIL) return 0;
    }
    return q->end <= p->end;
}

/* b (read back) is a under rn, and rn keeps each level's order. */
static int same_under(const st_map *a, const st_map *b, const st_map_renumber *rn)
{
    const uint32_t *dn = rn->darts.new_of, *vn = rn->verts.new_of;
    uint32_t last[ST_MAX_LEVELS];
    if (a->top != b->top) return 1;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) last[l] = ST_NIL;
    for (uint32_t d = 0; d < a->darts.end; d++) {
        unsigned i = a->darts.ins[d];
        if (i == ST_FREE_LEVEL) continue;
        uint32_t e = dn[d];
        if (e >= b->darts.end || b->darts.ins[e] != i || b->flags[e] != a->flags[d]) return 2;
        if (last[i] != ST_NIL && e <= last[i]) return 3;
        last[i] = e;
        for (unsigned l = i; l <= a->top; l++)
            if (dn[st_beta0(a, d, l)] != st_beta0(b, e, l) || dn[st_beta1(a, d, l)] != st_beta1(b, e, l) ||
                vn[st_vert(a, d, l)] != st_vert(b, e, l))
                return 4;
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) last[l] = ST_NIL;
    for (uint32_t v = 0; v < a->verts.end; v++) {
        unsigned i = a->verts.ins[v];
        if (i == ST_FREE_LEVEL) continue;
        uint32_t w = vn[v];
        if (w >= b->verts.end || b->verts.ins[w] != i) return 5;
        if (last[i] != ST_NIL && w <= last[i]) return 6;
        last[i] = w;
        for (unsigned l = i; l <= a->top; l++)
            if (memcmp(st_pos(a, v, l), st_pos(b, w, l), 3 * sizeof(double))) return 7;
    }
    return 0;
}

/* m written under its renumbering with `keep`, into *out (malloc'ed). */
static int write_renumbered(const st_map *m, unsigned keep, st_map_renumber *rn, unsigned char **out, size_t *n)
{
    if (st_map_renumber_make(m, keep, rn)) return -1;
    st_bw *w = malloc(sizeof *w);
    st_bw_init_mem(w);
    st_map_write_renumbered(w, m, rn);
    st_bw_flush(w);
    int rc = w->failed ? -1 : 0;
    *out = w->out;
    *n = w->outlen;
    st_bw_free(w);
    free(w);
    return rc;
}

static void check_keep(const st_map *m, unsigned keep, const char *label)
{
    st_map_renumber rn;
    unsigned char *b = NULL;
    size_t n = 0;
    if (write_renumbered(m, keep, &rn, &b, &n)) { CHECKF(0, "%s: not written", label); return; }
    CHECKF(pool_ok(&m->darts, &rn.darts.pool, keep) && pool_ok(&m->verts, &rn.verts.pool, keep),
           "%s: the renumbered pools are not packed above %u or not kept up to it", label, keep);
    st_error err;
    st_br r;
    st_br_init(&r, label, b, n, &err);
    r.trimmed = 1;
    st_map back;
    int rc = st_map_read(&r, &back);
    CHECKF(rc == 0 && r.off == n, "%s: read back: %s", label, rc ? err.msg : "bytes left over");
    if (rc) goto done;
    CHECKF(st_map_validate(&back, &err) == ST_OK, "%s: the map read back is not valid: %s", label, err.msg);
    int why = same_under(m, &back, &rn);
    CHECKF(why == 0, "%s: the map read back is not the original renumbered (check %d)", label, why);
    printf("%s: ids %u -> %u darts, %u -> %u vertices; %zu bytes\n", label, m->darts.end, back.darts.end,
           m->verts.end, back.verts.end, n);
    st_map_renumber rn2;
    unsigned char *b2 = NULL;
    size_t n2 = 0;
    if (!write_renumbered(&back, keep, &rn2, &b2, &n2)) {
        CHECKF(st_map_renumber_is_identity(&rn2), "%s: the map read back is renumbered again", label);
        CHECKF(n2 == n && !memcmp(b, b2, n), "%s: the map read back writes other bytes", label);
        st_map_renumber_free(&rn2);
    }
    free(b2);
    st_map_free(&back);
done:
    st_map_renumber_free(&rn);
    free(b);
}

/* Whether a level in [lo, hi] of p has a free list. */
static int has_free(const st_pool *p, unsigned lo, unsigned hi)
{
    for (unsigned l = lo; l <= hi && l < ST_MAX_LEVELS; l++)
        if (p->freehead[l] != ST_NIL) return 1;
    return 0;
}

int main(void)
{
    st_hier h;
    st_adapt a;
    if (build(&h, &a)) return TEST_END();
    st_map *m = &h.map;
    CHECKF(has_free(&m->darts, 4, m->top) && has_free(&m->verts, 4, m->top), "the box freed no id above level 3 (the test needs some)");
    CHECKF(has_free(&m->darts, 2, 3), "no free dart at levels 2..3 (keep 3 would keep no free list)");
    check_keep(m, 1, "box moved, keep 1");
    check_keep(m, 3, "box moved, keep 3");
    check_keep(m, 0, "box moved, keep 0");
    /* The top level removed: its blocks become spare ones. */
    st_hier_remove_top(&h);
    CHECKF(m->darts.nspare > 0, "removing the top level left no spare block");
    check_keep(m, 1, "top removed, keep 1");
    check_keep(m, 3, "top removed, keep 3");
    /* A uniform map: the renumbering is the identity. */
    st_map_renumber rn;
    st_hier u;
    st_mesh s;
    st_error err;
    tl_mesh_cube(&s);
    if (st_hier_init(&u, &s, st_scheme_get(ST_SCHEME_CATMARK), NULL, &err) == ST_OK) {
        if (st_hier_subdivide_to(&u, 3, &err) == ST_OK && st_map_renumber_make(&u.map, 0, &rn) == 0) {
            CHECKF(st_map_renumber_is_identity(&rn), "a uniform map is renumbered");
            st_map_renumber_free(&rn);
        }
        st_hier_free(&u);
    }
    st_mesh_free(&s);
    st_adapt_free(&a);
    st_hier_free(&h);
    return TEST_END();
}
