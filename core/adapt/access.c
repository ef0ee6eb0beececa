/* Adaptive access on a regular hierarchy (access.h; thesis §3.3.2). */
#include "core/adapt/access.h"
#include "core/fvar/fvar_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct access_ctx {
    st_map *m;
    const st_adapt_params *p;
    int bit[ST_MAX_LEVELS];    /* B_j: the dart's face of level j is opened */
    unsigned maxl;             /* deepest level shown */
    int restricted;
    uint64_t forced;           /* openings made by the restriction */
} access_ctx;

/* The dart of the face of d (level j >= 1) that is older than j: the side
 * its parent face gave it (every sub-face of a quadrisection has one,
 * except the central triangle of a triangle split, whose parent is reached
 * across any of its sides). */
static uint32_t older_dart(const st_map *m, uint32_t d, unsigned j)
{
    uint32_t x = d;
    do { if (m->darts.ins[x] < j) return x; x = st_phi1(m, x, j); } while (x != d);
    return ST_NIL;
}

static uint32_t parent_dart(const st_map *m, uint32_t d, unsigned j)
{
    uint32_t c = older_dart(m, d, j);
    return c != ST_NIL ? c : older_dart(m, st_beta0(m, d, j), j);
}

/* The face of d at level j is shown or opened (its parent is opened). */
static int present(const access_ctx *c, uint32_t d, unsigned j)
{
    return j == 0 || st_marked(c->m, c->bit[j - 1], parent_dart(c->m, d, j));
}

static int opened(const access_ctx *c, uint32_t d, unsigned j)
{
    return j < c->maxl && st_marked(c->m, c->bit[j], d);
}

/* Opens the face of d at level j (present); with the restriction, the
 * faces of level j sharing a vertex with it are made present first. */
static void open_face(access_ctx *c, uint32_t d, unsigned j)
{
    st_map *m = c->m;
    if (opened(c, d, j)) return;
    if (c->restricted) {
        uint32_t x = d;
        do {
            uint32_t y = x;
            do {
                if (!st_is_boundary(m, y) && !present(c, y, j)) {
                    open_face(c, parent_dart(m, y, j), j - 1);
                    c->forced++;
                }
                y = st_beta1(m, y, j);
            } while (y != x);
            x = st_phi1(m, x, j);
        } while (x != d);
    }
    st_mark_face(m, c->bit[j], d, j);
}

/* Algorithm 5 without the refinement: level by level, every present face
 * the criteria want finer is opened; again while the restriction opened
 * faces of levels already passed. */
static void choose_levels(access_ctx *c)
{
    st_map *m = c->m;
    uint64_t total = 0;
    for (uint64_t forced = 1; forced;) {
        c->forced = 0;
        for (unsigned j = 0; j < c->maxl; j++) {
            int seen = st_marker_reserve(m);
            st_dart_iter it;
            for (uint32_t d = st_dart_first(m, j, &it); d != ST_NIL; d = st_dart_next(m, j, &it)) {
                if (st_is_boundary(m, d) || st_marked(m, seen, d)) continue;
                st_mark_face(m, seen, d, j);
                if (present(c, d, j) && !opened(c, d, j) && st_adapt_wanted_level(m, d, j, c->p) > j) open_face(c, d, j);
            }
            st_marker_release(m, seen, j);
        }
        forced = c->forced;
        total += forced;
    }
    c->forced = total;
}

/* Growable soup under construction. */
typedef struct soup {
    uint32_t *off, *idx;       /* face offsets, corners as (vertex id) */
    uint32_t *dart;            /* per corner: the dart leaving it into its face (its UVs at every finer level) */
    uint8_t *lev;              /* per corner: level of the face or midpoint */
    uint32_t nf, nc, capf, capc;
} soup;

static int soup_corner(soup *s, uint32_t v, uint32_t dart, unsigned level)
{
    if (s->nc == s->capc) {
        uint32_t cap = s->capc ? 2 * s->capc : 1024;
        uint32_t *idx = realloc(s->idx, cap * sizeof *idx);
        if (!idx) return -1;
        s->idx = idx;
        uint32_t *dt = realloc(s->dart, cap * sizeof *dt);
        if (!dt) return -1;
        s->dart = dt;
        uint8_t *lev = realloc(s->lev, cap);
        if (!lev) return -1;
        s->lev = lev;
        s->capc = cap;
    }
    s->idx[s->nc] = v;
    s->dart[s->nc] = dart;
    s->lev[s->nc++] = (uint8_t)level;
    return 0;
}

static int soup_face_end(soup *s)
{
    if (s->nf + 1 >= s->capf) {
        uint32_t cap = s->capf ? 2 * s->capf : 256;
        uint32_t *off = realloc(s->off, (cap + 1) * sizeof *off);
        if (!off) return -1;
        s->off = off;
        s->capf = cap;
        if (s->nf == 0) s->off[0] = 0;
    }
    s->off[++s->nf] = s->nc;
    return 0;
}

/* The vertices inside the side x of level j: where the face across is
 * opened, the side is two sides of level j+1 with a midpoint between them
 * (recursively, so faces more than one level apart still share every
 * vertex of their common border). */
static int side_inner(const access_ctx *c, soup *s, uint32_t x, unsigned j, unsigned face_level)
{
    const st_map *m = c->m;
    uint32_t t = st_beta0(m, x, j);
    if (st_is_boundary(m, t) || !opened(c, t, j)) return 0;
    uint32_t half = st_beta0(m, t, j + 1);  /* midpoint -> next corner, on this side */
    if (side_inner(c, s, x, j + 1, face_level)) return -1;
    if (soup_corner(s, st_vert(m, half, j + 1), half, face_level)) return -1;
    return side_inner(c, s, half, j + 1, face_level);
}

/* The shown face of d at level j. */
static int emit_face(const access_ctx *c, soup *s, uint32_t d, unsigned j)
{
    const st_map *m = c->m;
    uint32_t x = d;
    do {
        if (soup_corner(s, st_vert(m, x, j), x, j) || side_inner(c, s, x, j, j)) return -1;
        x = st_phi1(m, x, j);
    } while (x != d);
    return soup_face_end(s);
}

static int collect_faces(access_ctx *c, soup *s, st_access_stats *stats)
{
    st_map *m = c->m;
    for (unsigned j = 0; j <= c->maxl; j++) {
        int seen = st_marker_reserve(m);
        st_dart_iter it;
        int rc = 0;
        for (uint32_t d = st_dart_first(m, j, &it); d != ST_NIL && !rc; d = st_dart_next(m, j, &it)) {
            if (st_is_boundary(m, d) || st_marked(m, seen, d)) continue;
            st_mark_face(m, seen, d, j);
            if (!present(c, d, j) || opened(c, d, j)) continue;
            if (st_is_hole(m, d)) continue; /* no surface (its children are holes too) */
            rc = emit_face(c, s, d, j);
            if (stats) stats->faces_per_level[j]++;
        }
        st_marker_release(m, seen, j);
        if (rc) return -1;
    }
    return 0;
}

typedef struct uv_key { uint32_t vert, label, corner; } uv_key;

static int cmp_uv_key(const void *pa, const void *pb)
{
    const uv_key *a = pa, *b = pb;
    if (a->vert != b->vert) return a->vert < b->vert ? -1 : 1;
    if (a->label != b->label) return a->label < b->label ? -1 : 1;
    return (a->corner > b->corner) - (a->corner < b->corner);
}

/* The UVs of the soup's corners (r's vertices made, lev the level of each
 * vertex id): each corner at its vertex's level, in its face's chart (the
 * regular level's UV of the corner's dart there: the dart stays in the
 * child face at that corner), one texture coordinate per (vertex, value)
 * as st_hier_level_mesh gives them.  Nothing when a level lacks UVs. */
static int soup_uvs(const st_hier *h, const soup *s, const uint8_t *lev, st_mesh *r)
{
    for (unsigned l = 0; l <= h->map.top; l++)
        if (!st_hier_has_uv(h, l)) return 0;
    uv_key *k = malloc(((size_t)s->nc + 1) * sizeof *k);
    r->uv = malloc(2 * ((size_t)s->nc + 1) * sizeof *r->uv);
    r->face_uv = malloc(((size_t)s->nc + 1) * sizeof *r->face_uv);
    if (!k || !r->uv || !r->face_uv) { free(k); return -1; }
    for (uint32_t c = 0; c < s->nc; c++)
        k[c] = (uv_key){ r->face_idx[c], st_fvar_label_at(&h->fvar->lv[lev[s->idx[c]]], s->dart[c]), c };
    qsort(k, s->nc, sizeof *k, cmp_uv_key);
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->nc; i++) {
        if (i == 0 || k[i].vert != k[i - 1].vert || k[i].label != k[i - 1].label) {
            uint32_t c = k[i].corner;
            const double *uv = st_fvar_uv_at(&h->fvar->lv[lev[s->idx[c]]], s->dart[c]);
            r->uv[2 * (size_t)n] = uv[0];
            r->uv[2 * (size_t)n + 1] = uv[1];
            n++;
        }
        r->face_uv[k[i].corner] = n - 1;
    }
    r->nuvs = n;
    free(k);
    return 0;
}

/* Vertex ids -> 0..n-1, each at the finest level of a shown face around
 * it, with the UVs of that level. */
static int soup_to_mesh(const st_hier *h, const soup *s, st_mesh *out)
{
    const st_map *m = &h->map;
    uint32_t nv = m->verts.end;
    uint32_t *slot = malloc((size_t)nv * sizeof *slot);
    uint8_t *lev = calloc(nv, 1);
    st_mesh r;
    st_mesh_init(&r);
    r.face_idx = malloc((size_t)(s->nc ? s->nc : 1) * sizeof *r.face_idx);
    r.face_off = malloc((size_t)(s->nf + 1) * sizeof *r.face_off);
    int ok = slot && lev && r.face_idx && r.face_off;
    if (ok) {
        memset(slot, 0xff, (size_t)nv * sizeof *slot);
        for (uint32_t k = 0; k < s->nc; k++) {
            uint32_t v = s->idx[k];
            if (slot[v] == ST_NIL) slot[v] = r.nverts++;
            if (s->lev[k] > lev[v]) lev[v] = s->lev[k];
            r.face_idx[k] = slot[v];
        }
        r.pos = malloc((size_t)(r.nverts ? r.nverts : 1) * 3 * sizeof *r.pos);
        ok = r.pos != NULL;
    }
    if (ok) {
        for (uint32_t v = 0; v < nv; v++)
            if (slot[v] != ST_NIL) memcpy(r.pos + 3 * (size_t)slot[v], st_pos(m, v, lev[v]), 3 * sizeof *r.pos);
        r.nfaces = s->nf;
        if (s->nf) memcpy(r.face_off, s->off, (size_t)(s->nf + 1) * sizeof *r.face_off);
        else r.face_off[0] = 0;
        ok = soup_uvs(h, s, lev, &r) == 0;
    }
    if (ok) {
        st_mesh_move(out, &r);
    }
    st_mesh_free(&r);
    free(slot);
    free(lev);
    return ok ? 0 : -1;
}

int st_access_mesh(st_hier *h, const st_adapt_params *p, st_mesh *out, st_access_stats *stats, st_error *err)
{
    st_map *m = &h->map;
    st_scheme_id id = h->scheme->id;
    if (id == ST_SCHEME_SQRT3 || id == ST_SCHEME_DOOSABIN)
        return st_fail(err, ST_ERR_INVALID, "adaptive access of %s is not implemented (primal quadrisection schemes are)",
                       h->scheme->name);
    if (stats) memset(stats, 0, sizeof *stats);
    access_ctx c = { .m = m, .p = p, .restricted = !p->no_restriction };
    c.maxl = p->max_level < m->top ? p->max_level : m->top;
    /* Marker bits: one per opened level, plus one for the face walks. */
    for (unsigned j = 0; j < c.maxl; j++) {
        c.bit[j] = st_marker_reserve(m);
        if (c.bit[j] < 0) {
            for (unsigned k = 0; k < j; k++) st_marker_release(m, c.bit[k], k);
            return st_fail(err, ST_ERR_RANGE, "adaptive access: not enough marker bits for %u levels", c.maxl);
        }
    }
    choose_levels(&c);
    if (stats) stats->forced = c.forced;
    soup s = { 0 };
    int rc = collect_faces(&c, &s, stats) || soup_to_mesh(h, &s, out);
    /* Darts of level j+1 carry no B_j: releasing at j clears every mark. */
    for (unsigned j = 0; j < c.maxl; j++) st_marker_release(m, c.bit[j], j);
    free(s.off);
    free(s.idx);
    free(s.dart);
    free(s.lev);
    return rc ? st_fail(err, ST_ERR_MEMORY, "adaptive access: out of memory") : ST_OK;
}
