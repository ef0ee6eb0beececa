/* Session files, the reader (session.h, docs/SESSION-FORMAT.md): every
 * chunk checked before anything is kept. */
#include "core/io/session_internal.h"
#include "core/base/membudget.h"
#include "core/base/parallel.h"
#include "core/io/atomic_file.h"
#include "core/io/file_open.h"
#include "core/io/map_io_internal.h"
#include "core/map/pool_internal.h"
#include "core/progressive/progressive.h"
#include "core/multires/estimate.h"
#include "core/multires/hier_internal.h"
#include "core/fvar/fvar_internal.h"
#include "core/progressive/scheme_registry.h"

#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- chunk readers ------------------------------------------------------------------ */

typedef struct load_ctx {
    st_session *s;
    const char *name;
    st_error *err;
    unsigned seen;         /* bit per chunk kind */
    int has_sharpness;
    unsigned regen_top;    /* LVL0: the levels to regenerate */
    int uv_pending;        /* FVAR read before POSN: level 0's UVs, the rest to refine */
    uint32_t regen_end[2]; /* LVL0: its pools' ends */
    int nested;            /* reading the image inside an hdlv chunk */
} load_ctx;

static int parse_image(const char *name, const void *data, size_t size, st_session *out, st_error *err, int nested);

/* SEEN_MAP: the whole map is there (MAP, or LVL0 then POSN). */
enum { SEEN_HIER = 1, SEEN_MAP = 2, SEEN_SHRP = 4, SEEN_DETL = 8, SEEN_ADPT = 16, SEEN_EDIT = 32, SEEN_VIEW = 64, SEEN_BASE = 128,
       SEEN_MASK = 256, SEEN_LAYR = 512,
       SEEN_FVAR = 1024, SEEN_BUVS = 2048, SEEN_TOOL = 4096, SEEN_LVL0 = 8192, SEEN_POSN = 16384, SEEN_HDLV = 32768,
       SEEN_PMRC = 65536 };

/* A failure that is not the file's bytes (memory, the budget, a
 * regeneration): "FILE: what", the chunk's reader stopped. */
static int load_fail(load_ctx *c, st_br *r, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static int load_fail(load_ctx *c, st_br *r, int code, const char *fmt, ...)
{
    char what[sizeof c->err->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    st_fail(c->err, code, "%s: %s", c->name, what);
    r->failed = 1;
    return -1;
}

static int r_hier(load_ctx *c, st_br *r)
{
    uint32_t n = st_br_u32(r);
    if (r->failed) return -1;
    if (n == 0 || n > 64) return st_br_fail(r, "scheme name of %u bytes", n);
    char name[65];
    st_br_bytes(r, name, n);
    name[n] = 0;
    uint32_t boundary = st_br_u32(r), crease = st_br_u32(r), tri_sub = (crease >> 8) & 0xff, predictor = crease >> 16;
    crease &= 0xff;
    uint8_t sharp = st_br_u8(r);
    if (r->failed) return -1;
    const st_scheme *sc = st_scheme_find(name);
    if (!sc || strlen(name) != n) {
        for (uint32_t k = 0; k < n; k++)
            if (name[k] < 0x20 || name[k] > 0x7e) name[k] = '?'; /* messages are one printable line */
        return st_br_fail(r, "unknown scheme '%s'", name);
    }
    if (boundary != ST_BOUNDARY_EDGE_ONLY && boundary != ST_BOUNDARY_EDGE_AND_CORNER)
        return st_br_fail(r, "bad boundary option %u", boundary);
    if (crease != ST_CREASE_UNIFORM && crease != ST_CREASE_CHAIKIN) return st_br_fail(r, "bad crease method %u", crease);
    if (tri_sub != ST_TRI_SUB_CATMARK && tri_sub != ST_TRI_SUB_SMOOTH) return st_br_fail(r, "bad triangle rule %u", tri_sub);
    if (predictor > ST_PM_GRADED || (predictor && sc->id != ST_SCHEME_PROGRESSIVE))
        return st_br_fail(r, "bad progressive predictor %u for the %s scheme", predictor, sc->name);
    if (sharp > 1) return st_br_fail(r, "bad sharpness flag %u", sharp);
    c->s->h.scheme = sc;
    c->s->h.opts.boundary = (int)boundary;
    c->s->h.opts.crease_method = (int)crease;
    c->s->h.opts.tri_sub = (int)tri_sub;
    c->s->h.opts.pm_predictor = (int)predictor;
    c->has_sharpness = sharp;
    return 0;
}

static int faces_are_triangles(st_map *m, unsigned l)
{
    int fb = st_marker_reserve(m);
    if (fb < 0) return 0;
    int ok = 1;
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL && ok; d = st_dart_next(m, l, &it)) {
        if (st_is_boundary(m, d) || st_marked(m, fb, d)) continue;
        st_mark_face(m, fb, d, l);
        ok = st_face_degree(m, d, l) == 3;
    }
    st_marker_release(m, fb, l);
    return ok;
}

static int r_map(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    if (c->seen & (SEEN_POSN | SEEN_PMRC)) return st_br_fail(r, "a map in a session that regenerates its levels");
    st_map_free(&h->map);
    if (st_map_read(r, &h->map)) return -1;
    int dual = h->scheme->id == ST_SCHEME_DOOSABIN;
    if (h->map.face_embedded != dual)
        return st_br_fail(r, "map: the %s scheme needs %s", h->scheme->name,
                          dual ? "the dual (face) embedding" : "the vertex embedding");
    /* Few darts change per level: the sparse form, as the build leaves it. */
    if (h->scheme->id == ST_SCHEME_PROGRESSIVE) st_map_compact(&h->map);
    return 0;
}

/* Sharpness comes after MAP, or between LVL0 and POSN: level 0's, which
 * the regeneration refines with the levels. */
static int r_level0(load_ctx *c, st_br *r)
{
    if (c->seen & SEEN_MAP) return st_br_fail(r, "level 0 in a session that has its map");
    uint32_t top = st_br_u32(r);
    if (r->failed) return -1;
    if (top >= ST_MAX_LEVELS) return st_br_fail(r, "%u levels to regenerate (at most %d)", top, ST_MAX_LEVELS - 1);
    if (r_map(c, r)) return -1;
    st_map *m = &c->s->h.map;
    if (m->top != 0) return st_br_fail(r, "level 0 is a map of %u levels", m->top);
    if (c->s->h.scheme->id == ST_SCHEME_PROGRESSIVE) return st_br_fail(r, "progressive levels cannot be regenerated");
    c->regen_top = top;
    c->regen_end[0] = m->darts.end;
    c->regen_end[1] = m->verts.end;
    return 0;
}

/* An unsigned LEB128 number of at most 32 bits (session_write.c w_varint). */
static uint32_t r_varint(st_br *r)
{
    uint32_t v = 0;
    for (unsigned shift = 0; shift < 35; shift += 7) {
        uint8_t b = st_br_u8(r);
        if (r->failed) return 0;
        if (shift == 28 && b > 0x0f) break;
        v |= (uint32_t)(b & 0x7f) << shift;
        if (!(b & 0x80)) return v;
    }
    st_br_fail(r, "a number of more than 32 bits");
    return 0;
}

/* A progressive hierarchy's recipe (version 5, session_write.c w_recipe):
 * replayed at once (st_progressive_regenerate checks every record), so
 * POSN finds the levels there, as after LVL0's regeneration.  The map the
 * replay makes grows with the splits, about 250 bytes for each 6 of the
 * file: the memory guard is asked first. */
static int r_recipe(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    if (c->seen & SEEN_MAP) return st_br_fail(r, "progressive levels in a session that has its map");
    if (h->scheme->id != ST_SCHEME_PROGRESSIVE) return st_br_fail(r, "progressive levels for the %s scheme", h->scheme->name);
    if (c->has_sharpness) return st_br_fail(r, "progressive levels with sharpness");
    size_t start = r->off;
    st_pm_recipe pm;
    memset(&pm, 0, sizeof pm);
    pm.top = st_br_u32(r);
    pm.nverts0 = st_br_u32(r);
    pm.ndarts0 = st_br_u32(r);
    if (r->failed) return -1;
    if (pm.top >= ST_MAX_LEVELS) return st_br_fail(r, "%u progressive levels (at most %d)", pm.top + 1, ST_MAX_LEVELS);
    if (st_br_need(r, pm.ndarts0, 13, "level 0's darts")) return -1;
    if (pm.nverts0 > pm.ndarts0) return st_br_fail(r, "level 0: %u vertices for %u darts", pm.nverts0, pm.ndarts0);
    int rc = 0;
    if (st_pm_recipe_alloc_level0(&pm, pm.ndarts0)) { rc = load_fail(c, r, ST_ERR_MEMORY, "out of memory"); goto done; }
    for (uint32_t d = 0; d < pm.ndarts0; d++) {
        pm.beta0[d] = st_br_u32(r);
        pm.beta1[d] = st_br_u32(r);
        pm.vert[d] = st_br_u32(r);
        pm.boundary[d] = st_br_u8(r);
    }
    /* Each level's count, checked against the bytes left, then its splits. */
    uint64_t total = 0;
    size_t cap = 0;
    for (unsigned l = 1; l <= pm.top && !r->failed; l++) {
        pm.nsplits[l] = st_br_u32(r);
        if (r->failed || st_br_need(r, pm.nsplits[l], 6, "splits")) { rc = -1; goto done; }
        if (total + pm.nsplits[l] > cap) {
            size_t want = (size_t)(total + pm.nsplits[l]) * 2;
            st_pm_split *p = realloc(pm.split, want * sizeof *p);
            if (!p) { rc = load_fail(c, r, ST_ERR_MEMORY, "out of memory"); goto done; }
            pm.split = p;
            cap = want;
        }
        for (uint32_t i = 0; i < pm.nsplits[l]; i++) {
            st_pm_split *s = &pm.split[total + i];
            s->b = st_br_u32(r);
            s->c = r_varint(r);
            uint32_t d = r_varint(r);
            s->d = d ? d - 1 : ST_NIL;
        }
        total += pm.nsplits[l];
    }
    if (r->failed) { rc = -1; goto done; }
    st_error e2;
    size_t need = ((size_t)pm.ndarts0 + 6 * (size_t)total) * 64 + ((size_t)pm.nverts0 + (size_t)total) * 64;
    if (need >= ST_MEM_CHECK_MIN_BYTES && st_mem_check(need, "regenerating the progressive levels", &e2)) {
        rc = load_fail(c, r, e2.code, "%s", e2.msg);
        goto done;
    }
    if (st_progressive_regenerate(h, &pm, &e2)) { rc = load_fail(c, r, e2.code, "progressive levels: %s", e2.msg); goto done; }
    /* The payload kept: the next save writes it again as it is. */
    h->pm_recipe = malloc(r->off - start);
    if (!h->pm_recipe) { rc = load_fail(c, r, ST_ERR_MEMORY, "out of memory"); goto done; }
    memcpy(h->pm_recipe, r->p + start, r->off - start);
    h->pm_recipe_len = r->off - start;
    c->regen_top = pm.top;
    c->regen_end[0] = pm.ndarts0;
    c->regen_end[1] = pm.nverts0;
    c->seen |= SEEN_LVL0;   /* POSN follows, as after LVL0 */
done:
    st_pm_recipe_free(&pm);
    return rc;
}

/* The sharpness read, as the map's attached attributes. */
static void attach_sharpness(load_ctx *c)
{
    st_hier *h = &c->s->h;
    if (!c->has_sharpness) return;
    h->map.dart_attrs[0] = &h->edge_sharp;
    h->map.vert_attrs[0] = &h->vertex_sharp;
    h->map.ndart_attrs = h->map.nvert_attrs = 1;
    h->has_sharpness = 1;
}

/* The map's checks before anything works on it: the validator (when
 * `validate`) and the scheme's need of triangles at level 0. */
static int check_map(load_ctx *c, int validate, st_error *e)
{
    st_hier *h = &c->s->h;
    st_error e2;
    if (validate && st_map_validate(&h->map, &e2)) return st_fail(e, ST_ERR_INVALID, "invalid map: %s", e2.msg);
    st_scheme_id id = h->scheme->id;
    if ((id == ST_SCHEME_LOOP || id == ST_SCHEME_BUTTERFLY || id == ST_SCHEME_SQRT3) && !faces_are_triangles(&h->map, 0))
        return st_fail(e, ST_ERR_INVALID, "the %s scheme needs a triangle control mesh", h->scheme->name);
    return 0;
}

/* Live ids of a pool, all levels. */
static uint64_t live_ids_of(const st_pool *p)
{
    uint64_t n = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) n += p->live[l];
    return n;
}

/* Levels 1..regen_top from level 0, by the scheme's refinement, as they
 * were built.  Level 0 is checked first as finish() checks a whole map.
 * The work is bounded by the file: POSN stores 24 bytes for each vertex
 * the levels have, so a level is refined only while the vertices so far
 * fit in what is left of the chunk (and the memory guard allows it). */
static int regenerate(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    st_map *m = &h->map;
    if (c->seen & SEEN_PMRC) return 0;   /* replayed by r_recipe, every split checked */
    attach_sharpness(c);
    st_error e2;
    if (check_map(c, 1, &e2)) return st_br_fail(r, "level 0: %s", e2.msg);
    st_subdiv_view sv = st_hier_view(h);
    if (h->scheme->check && h->scheme->check(&sv, &e2)) return st_br_fail(r, "level 0: %s", e2.msg);
    /* The budget's check, as for the file read (st_mem_check_read): a small
     * model is read even by a process over its budget for other reasons
     * (a sanitizer's shadow memory), which is refused what would grow it. */
    size_t need = c->regen_top ? st_hier_estimate_subdivide(h, c->regen_top, NULL) : 0;
    if (need >= ST_MEM_CHECK_MIN_BYTES) {
        char what[64];
        snprintf(what, sizeof what, "regenerating %u levels", c->regen_top);
        if (st_mem_check(need, what, &e2))
            return load_fail(c, r, e2.code, "%s", e2.msg);
    }
    while (m->top < c->regen_top) {
        if (live_ids_of(&m->verts) * 24 > r->size - r->off)
            return st_br_fail(r, "positions: %u vertices at level %u, more than the chunk holds", (unsigned)live_ids_of(&m->verts), m->top);
        if (st_hier_refine_topology(h, &e2))
            return load_fail(c, r, e2.code, "regenerating level %u: %s", m->top + 1, e2.msg);
    }
    return 0;
}

/* The UVs of levels 1..top refined from level 0's, on a thread of their
 * own while the positions are read: they read the regenerated topology
 * and sharpness only, and the positions go to an attribute of their own
 * until both are done. */
typedef struct uv_job {
    st_hier *h;
    int rc;
    st_error err;
} uv_job;

static void *uv_job_run(void *p)
{
    uv_job *j = p;
    j->rc = st_hier_uv_refine_levels(j->h, j->h->map.top, &j->err);
    return NULL;
}

static int r_positions(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    st_map *m = &h->map;
    if (c->has_sharpness && !(c->seen & SEEN_SHRP)) return st_br_fail(r, "positions before the sharpness of level 0");
    if (regenerate(c, r)) return -1;
    uv_job job = { .h = h };
    pthread_t th;
    int threaded = 0;
    if (c->uv_pending) {
        threaded = st_parallel_threads() > 1 && pthread_create(&th, NULL, uv_job_run, &job) == 0;
        if (!threaded) uv_job_run(&job);
    }
    st_mla pos;
    int rc = st_mla_read(r, &pos, &m->verts, m->top, 3 * sizeof(double), st_value_finite_f64x3, "positions");
    if (threaded) pthread_join(th, NULL);
    if (rc) return -1;
    if (c->uv_pending && job.rc) {
        st_mla_free(&pos);
        return load_fail(c, r, job.err.code, "regenerating the UVs: %s", job.err.msg);
    }
    c->uv_pending = 0;
    /* The refinement grew the pool past its end: the attached arrays have
     * its capacity. */
    if (m->verts.cap > m->verts.end) {
        unsigned char *b = realloc(pos.base, (size_t)m->verts.cap * pos.elem);
        if (!b) { st_mla_free(&pos); return load_fail(c, r, ST_ERR_MEMORY, "out of memory"); }
        memset(b + (size_t)m->verts.end * pos.elem, 0, (size_t)(m->verts.cap - m->verts.end) * pos.elem);
        pos.base = b;
    }
    st_mla_free(&m->pos);
    m->pos = pos;
    c->seen |= SEEN_MAP;
    return 0;
}

static int r_sharp(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    if (!c->has_sharpness) return st_br_fail(r, "sharpness chunk in a session without sharpness");
    if (!(c->seen & (SEEN_MAP | SEEN_LVL0))) return st_br_fail(r, "sharpness before the map");
    if (c->seen & SEEN_POSN) return st_br_fail(r, "sharpness after the positions of the regenerated levels");
    if (st_mla_read(r, &h->edge_sharp, &h->map.darts, h->map.top, sizeof(float), st_value_sharpness_f32, "edge sharpness") ||
        st_mla_read(r, &h->vertex_sharp, &h->map.verts, h->map.top, sizeof(float), st_value_sharpness_f32, "vertex sharpness"))
        return -1;
    return 0;
}

static int r_detail(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        uint8_t present = st_br_u8(r);
        if (r->failed) return -1;
        if (present > 1) return st_br_fail(r, "details of level %u: bad flag %u", l, present);
        if (!present) continue;
        if (l == 0 || l > h->map.top) return st_br_fail(r, "details at level %u (levels 1..%u have details)", l, h->map.top);
        uint32_t cap = st_br_u32(r);
        uint8_t list = 0;
        if (r->trimmed) list = st_br_u8(r);   /* version 3 (w_detail) */
        if (r->failed) return -1;
        if (list > 1) return st_br_fail(r, "details of level %u: unknown mode %u", l, list);
        if (!list && st_br_need(r, cap, 24, "details")) return -1;
        if (cap == 0) return st_br_fail(r, "details of level %u: empty array", l);
        /* a list names ids below cap, and cap is what its bytes allow */
        if (list && cap > c->s->h.map.verts.end) return st_br_fail(r, "details of level %u: %u of %u vertex ids", l, cap, c->s->h.map.verts.end);
        h->detail[l] = calloc((size_t)cap, 24);
        if (!h->detail[l]) return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
        h->detail_cap[l] = cap;
        if (!list) {
            for (size_t i = 0; i < 3 * (size_t)cap; i++) {
                h->detail[l][i] = st_br_f64(r);
                if (!isfinite(h->detail[l][i])) return st_br_fail(r, "details of level %u: vertex %zu is not finite", l, i / 3);
            }
            continue;
        }
        uint32_t n = st_br_u32(r);
        if (r->failed) return -1;
        if (n > cap || st_br_need(r, n, 28, "details")) return n > cap ? st_br_fail(r, "details of level %u: %u listed of %u", l, n, cap) : -1;
        uint64_t last = UINT64_MAX;
        for (uint32_t k = 0; k < n; k++) {
            uint32_t id = st_br_u32(r);
            if (id >= cap || (last != UINT64_MAX && id <= last))
                return st_br_fail(r, "details of level %u: vertex %u out of order or range", l, id);
            last = id;
            for (int j = 0; j < 3; j++) {
                double v = st_br_f64(r);
                if (!isfinite(v)) return st_br_fail(r, "details of level %u: vertex %u is not finite", l, id);
                h->detail[l][3 * (size_t)id + j] = v;
            }
        }
    }
    return r->failed ? -1 : 0;
}

static int r_params(st_br *r, st_adapt_params *p, const char *what)
{
    memset(p, 0, sizeof *p);
    p->base_level = st_br_u32(r);
    p->max_level = st_br_u32(r);
    for (int k = 0; k < 3; k++) p->box_lo[k] = st_br_f64(r);
    for (int k = 0; k < 3; k++) p->box_hi[k] = st_br_f64(r);
    uint8_t hb = st_br_u8(r);
    p->falloff = st_br_f64(r);
    p->flatness = st_br_f64(r);
    uint8_t nr = st_br_u8(r);
    if (r->failed) return -1;
    p->has_box = hb;
    p->no_restriction = nr;
    if (hb > 1 || nr > 1) return st_br_fail(r, "%s: bad flag", what);
    if (p->base_level >= ST_MAX_LEVELS || p->max_level >= ST_MAX_LEVELS)
        return st_br_fail(r, "%s: levels %u..%u (at most %d)", what, p->base_level, p->max_level, ST_MAX_LEVELS - 1);
    int ok = isfinite(p->falloff) && p->falloff >= 0 && isfinite(p->flatness) && p->flatness >= 0;
    for (int k = 0; k < 3; k++) ok &= isfinite(p->box_lo[k]) && isfinite(p->box_hi[k]);
    if (!ok) return st_br_fail(r, "%s: non-finite or negative value", what);
    return 0;
}

/* A sorted store of details (st_adapt saved / parked). */
static int r_store(load_ctx *c, st_br *r, st_adapt_saved **out, uint32_t *nout, uint32_t *cap, const char *what)
{
    uint32_t n = st_br_u32(r);
    if (st_br_need(r, n, 36, what)) return -1;
    st_adapt_saved *a = malloc((size_t)(n ? n : 1) * sizeof *a);
    if (!a) return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
    *out = a;
    *cap = n ? n : 1;
    for (uint32_t i = 0; i < n; i++) {
        st_adapt_saved *e = &a[i];
        e->path = st_br_u64(r);
        e->meta = st_br_u32(r);
        for (int k = 0; k < 3; k++) e->d[k] = st_br_f64(r);
        *nout = i + 1;
        if (r->failed) return -1;
        if (!isfinite(e->d[0]) || !isfinite(e->d[1]) || !isfinite(e->d[2]))
            return st_br_fail(r, "%s: entry %u is not finite", what, i);
        if (i && !(a[i - 1].path < e->path || (a[i - 1].path == e->path && a[i - 1].meta < e->meta)))
            return st_br_fail(r, "%s: entries not sorted (entry %u)", what, i);
    }
    return 0;
}

static int r_adapt(load_ctx *c, st_br *r)
{
    st_session *s = &c->s[0];
    st_adapt *a = &s->adapt;
    memset(a, 0, sizeof *a);
    a->h = &s->h;
    s->has_adapt = 1;
    if (r_store(c, r, &a->saved, &a->nsaved, &a->capsaved, "saved details") ||
        r_store(c, r, &a->parked, &a->nparked, &a->capparked, "parked details"))
        return -1;
    /* A progressive hierarchy's selective display removes no vertex and
     * keeps no detail: only its criteria are saved (core/adapt/adapt.h). */
    if (s->h.scheme && s->h.scheme->id == ST_SCHEME_PROGRESSIVE && (a->nsaved || a->nparked))
        return st_br_fail(r, "a progressive hierarchy's adaptive state keeps no details (%u saved, %u parked)", a->nsaved, a->nparked);
    uint32_t nb = st_br_u32(r);
    if (st_br_need(r, nb, 4, "base faces")) return -1;
    for (uint32_t i = 0; i < nb; i++) {
        uint32_t d = st_br_u32(r);
        if (r->failed) return -1;
        if (!st_dart_in_level(&s->h.map, d, 0) || st_is_boundary(&s->h.map, d))
            return st_br_fail(r, "base face %u: dart %u is not a real dart of level 0", i, d);
        st_dart_list_push(&a->base_faces, d);
    }
    if (r_params(r, &a->prev, "adaptive criteria")) return -1;
    uint8_t hp = st_br_u8(r);
    a->touched = st_br_u64(r);
    a->forced = st_br_u64(r);
    if (r->failed) return -1;
    if (hp > 1) return st_br_fail(r, "bad flag %u", hp);
    a->has_prev = hp;
    return 0;
}

static int r_edit(load_ctx *c, st_br *r)
{
    st_session *s = c->s;
    if (r_params(r, &s->box, "interest box")) return -1;
    uint8_t on = st_br_u8(r);
    uint32_t e = st_br_u32(r), d = st_br_u32(r);
    if (r->failed) return -1;
    if (on > 1) return st_br_fail(r, "bad box flag %u", on);
    if (e > s->h.map.top || d > s->h.map.top)
        return st_br_fail(r, "editing level %u / displayed level %u above the top level %u", e, d, s->h.map.top);
    s->box_on = on;
    s->edit_level = e;
    s->display_level = d;
    return 0;
}

static int r_view(load_ctx *c, st_br *r)
{
    st_session_view *v = &c->s->view;
    for (int k = 0; k < 3; k++) v->target[k] = st_br_f32(r);
    v->az = st_br_f32(r);
    v->el = st_br_f32(r);
    v->dist = st_br_f32(r);
    v->fovy = st_br_f32(r);
    v->ortho = (int)st_br_u32(r);
    v->ortho_height = st_br_f32(r);
    if (r->failed) return -1;
    int ok = v->ortho == 0 || v->ortho == 1;
    float f[8] = { v->target[0], v->target[1], v->target[2], v->az, v->el, v->dist, v->fovy, v->ortho_height };
    for (int k = 0; k < 8; k++) ok &= isfinite(f[k]) != 0;
    if (!ok) return st_br_fail(r, "view: bad value");
    c->s->has_view = 1;
    return 0;
}

/* The one rule for the `tool` chunk's values, for the writer (which
 * writes nothing the reader would refuse) and the reader. */
const char *st_session_tool_refusal(const st_session_tool *t)
{
    if (t->tool != ST_SESSION_NO_TOOL && t->tool > 255) return "tool index";
    if (!(isfinite(t->radius) && t->radius > 0)) return "radius";
    if (!(t->strength >= 0 && t->strength <= 1)) return "strength";
    if (t->falloff > 255) return "falloff";
    if (t->mirror > 7) return "mirror axes";
    if (t->show > 15) return "display toggles";
    return NULL;
}

static int r_tool(load_ctx *c, st_br *r)
{
    st_session_tool *t = &c->s->tool;
    t->tool = st_br_u32(r);
    t->radius = st_br_f64(r);
    t->strength = st_br_f64(r);
    t->falloff = st_br_u32(r);
    t->mirror = st_br_u32(r);
    t->show = st_br_u32(r);
    if (r->failed) return -1;
    const char *bad = st_session_tool_refusal(t);
    if (bad) return st_br_fail(r, "tool settings: bad %s", bad);
    c->s->has_tool = 1;
    return 0;
}

static int r_base(load_ctx *c, st_br *r)
{
    st_mesh *m = &c->s->base;
    c->s->has_base = 1;
    uint32_t nv = st_br_u32(r);
    if (r->failed) return -1;
    if (nv > ST_MESH_MAX_VERTS || st_br_need(r, nv, 24, "base mesh vertices")) return st_br_fail(r, "base mesh: %u vertices", nv);
    m->pos = malloc((size_t)(nv ? nv : 1) * 24);
    if (!m->pos) goto oom;
    m->nverts = nv;
    for (size_t i = 0; i < 3 * (size_t)nv; i++) m->pos[i] = st_br_f64(r);
    uint32_t nf = st_br_u32(r);
    if (r->failed) return -1;
    if (nf > ST_MESH_MAX_FACES || st_br_need(r, nf, 4, "base mesh faces")) return st_br_fail(r, "base mesh: %u faces", nf);
    m->face_off = malloc(((size_t)nf + 1) * sizeof *m->face_off);
    if (!m->face_off) goto oom;
    m->face_off[0] = 0;
    uint64_t total = 0;
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t k = st_br_u32(r);
        total += k;
        if (r->failed) return -1;
        if (k < 3 || k > ST_MESH_MAX_DEGREE || total > UINT32_MAX) return st_br_fail(r, "base mesh: face %u has %u vertices", f, k);
        m->face_off[f + 1] = (uint32_t)total;
    }
    m->nfaces = nf;
    if (st_br_need(r, total, 4, "base mesh corners")) return -1;
    m->face_idx = malloc((size_t)(total ? total : 1) * sizeof *m->face_idx);
    if (!m->face_idx) goto oom;
    for (uint64_t i = 0; i < total; i++) m->face_idx[i] = st_br_u32(r);
    uint32_t nc = st_br_u32(r);
    if (r->failed || st_br_need(r, nc, 12, "crease tags")) return -1;
    m->crease_v = malloc((size_t)(nc ? nc : 1) * 2 * sizeof *m->crease_v);
    m->crease_s = malloc((size_t)(nc ? nc : 1) * sizeof *m->crease_s);
    if (!m->crease_v || !m->crease_s) goto oom;
    m->ncreases = nc;
    for (uint32_t i = 0; i < nc; i++) {
        m->crease_v[2 * i] = st_br_u32(r);
        m->crease_v[2 * i + 1] = st_br_u32(r);
        m->crease_s[i] = st_br_f32(r);
    }
    uint32_t nk = st_br_u32(r);
    if (r->failed || st_br_need(r, nk, 8, "corner tags")) return -1;
    m->corner_v = malloc((size_t)(nk ? nk : 1) * sizeof *m->corner_v);
    m->corner_s = malloc((size_t)(nk ? nk : 1) * sizeof *m->corner_s);
    if (!m->corner_v || !m->corner_s) goto oom;
    m->ncorners = nk;
    for (uint32_t i = 0; i < nk; i++) {
        m->corner_v[i] = st_br_u32(r);
        m->corner_s[i] = st_br_f32(r);
    }
    int32_t bi = (int32_t)st_br_u32(r);
    if (r->failed) return -1;
    if (bi < ST_BOUNDARY_UNSET || bi > ST_BOUNDARY_EDGE_ONLY) return st_br_fail(r, "base mesh: bad boundary tag %d", bi);
    m->boundary_interp = bi;
    for (uint32_t i = 0; i < nc; i++)
        if (!isfinite(m->crease_s[i]) || m->crease_s[i] < 0) return st_br_fail(r, "base mesh: bad crease sharpness");
    for (uint32_t i = 0; i < nk; i++)
        if (!isfinite(m->corner_s[i]) || m->corner_s[i] < 0) return st_br_fail(r, "base mesh: bad corner sharpness");
    st_error e2;
    if (st_mesh_check("base mesh", m, &e2)) return st_br_fail(r, "%s", e2.msg);
    return 0;
oom:
    return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
}

static int r_mask(load_ctx *c, st_br *r)
{
    st_mask *mk = &c->s->mask;
    uint32_t n = st_br_u32(r);
    if (r->failed || st_br_need(r, n, 4, "mask")) return -1;
    if (n > c->s->h.map.verts.end) return st_br_fail(r, "mask of %u vertices; the map has %u vertex ids", n, c->s->h.map.verts.end);
    if (!n) return st_br_fail(r, "empty mask");
    mk->v = malloc((size_t)n * sizeof *mk->v);
    if (!mk->v) return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
    mk->cap = n;
    for (uint32_t i = 0; i < n; i++) {
        float x = st_br_f32(r);
        if (!(x >= 0 && x <= 1)) return st_br_fail(r, "mask of vertex %u is %g, not in [0, 1]", i, (double)x);
        mk->v[i] = x;
    }
    if (mk->v[n - 1] == 0) return st_br_fail(r, "mask: trailing zero values");
    return r->failed ? -1 : 0;
}

static int r_offsets(load_ctx *c, st_br *r, double **out, uint32_t *cap, const char *what, int nan_ok)
{
    uint32_t n = st_br_u32(r);
    if (r->failed || st_br_need(r, n, 24, what)) return -1;
    if (n > c->s->h.map.verts.end) return st_br_fail(r, "%s: %u vertices; the map has %u vertex ids", what, n, c->s->h.map.verts.end);
    if (!n) return 0;
    double *a = malloc((size_t)n * 24);
    if (!a) return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
    *out = a;
    *cap = n;
    for (size_t i = 0; i < 3 * (size_t)n; i++) {
        a[i] = st_br_f64(r);
        if (nan_ok && isnan(a[i]) && (i % 3 == 0 || isnan(a[i - i % 3]))) continue;
        if (!isfinite(a[i]) || (nan_ok && i % 3 && isnan(a[i - i % 3])))
            return st_br_fail(r, "%s: vertex %zu is not finite", what, i / 3);
    }
    if (nan_ok ? isnan(a[3 * (size_t)n - 3])
               : a[3 * (size_t)n - 1] == 0 && a[3 * (size_t)n - 2] == 0 && a[3 * (size_t)n - 3] == 0)
        return st_br_fail(r, "%s: trailing empty entries", what);
    return r->failed ? -1 : 0;
}

/* layr (lowest level 1) or lay0 (0, with a layer there). */
static int r_layers_from(load_ctx *c, st_br *r, unsigned lowest)
{
    st_layers *ls = &c->s->layers;
    unsigned top = c->s->h.map.top;
    uint32_t active = st_br_u32(r), n = st_br_u32(r);
    if (r->failed || st_br_need(r, n, 21, "layers")) return -1;
    if (n > ST_LAYER_MAX) return st_br_fail(r, "%u sculpt layers (at most %d)", n, ST_LAYER_MAX);
    if (active != UINT32_MAX && active >= n) return st_br_fail(r, "active layer %u of %u", active, n);
    ls->v = calloc(n ? n : 1, sizeof *ls->v);
    if (!ls->v) return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
    ls->cap = n;
    ls->active = active == UINT32_MAX ? -1 : (int)active;
    for (uint32_t i = 0; i < n; i++) {
        st_layer *y = &ls->v[i];
        ls->n = i + 1;
        uint32_t len = st_br_u32(r);
        if (r->failed) return -1;
        if (len == 0 || len >= ST_LAYER_NAME) return st_br_fail(r, "layer %u: name of %u bytes (1..%d)", i, len, ST_LAYER_NAME - 1);
        st_br_bytes(r, y->name, len);
        if (r->failed) return -1;
        y->name[len] = 0;
        if (strlen(y->name) != len) return st_br_fail(r, "layer %u: NUL in its name", i);
        y->level = st_br_u32(r);
        y->strength = st_br_f64(r);
        uint8_t hidden = st_br_u8(r);
        if (r->failed) return -1;
        if (y->level < lowest || y->level > top)
            return st_br_fail(r, "layer '%s' at level %u (levels %u..%u%s)", y->name, y->level, lowest, top,
                              lowest ? "; level 0 in chunk 'lay0'" : "");
        if (!(y->strength >= 0 && y->strength <= ST_LAYER_STRENGTH_MAX))
            return st_br_fail(r, "layer '%s': strength %g not in [0, %g]", y->name, y->strength, ST_LAYER_STRENGTH_MAX);
        if (hidden > 1) return st_br_fail(r, "layer '%s': bad hidden flag %u", y->name, hidden);
        y->hidden = hidden;
        if (r_offsets(c, r, &y->off, &y->cap, "layer offsets", 0)) return -1;
    }
    /* The details without layers, one array per level with layers, in
     * increasing level order. */
    if (!lowest && !st_layers_on_level(ls, 0)) return st_br_fail(r, "chunk 'lay0' without a layer at level 0");
    for (unsigned l = lowest; l < ST_MAX_LEVELS; l++) {
        if (!st_layers_on_level(ls, l)) continue;
        uint32_t lev = st_br_u32(r);
        if (r->failed) return -1;
        if (lev != l) return st_br_fail(r, "layers: base details of level %u where level %u was expected", lev, l);
        if (r_offsets(c, r, &ls->base[l], &ls->base_cap[l], "layer base details", 0)) return -1;
        if (r_offsets(c, r, &ls->bpos[l], &ls->bpos_cap[l], "layer base positions", 1)) return -1;
        if (l == 0 && ls->bpos[0]) return st_br_fail(r, "layers: base positions at level 0 (its base details are its positions)");
    }
    return r->failed ? -1 : 0;
}

static int r_layers(load_ctx *c, st_br *r) { return r_layers_from(c, r, 1); }
static int r_layers0(load_ctx *c, st_br *r) { return r_layers_from(c, r, 0); }

/* A session with regenerated levels stores level 0's UVs alone when the
 * rest refine after the topology (session_write.c, w_fvar): they are
 * refined again here, as they were built. */
static int regenerate_uvs(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    if (!(c->seen & SEEN_LVL0) || h->map.top == 0) return 0;
    int rules = st_fvar_rules_of(h->scheme);
    if (rules < 0 || rules == ST_FVAR_STENCIL) return st_br_fail(r, "UVs: level 0 alone for the %s scheme", h->scheme->name);
    st_error e2;
    if (st_hier_uv_refine_levels(h, h->map.top, &e2)) return load_fail(c, r, e2.code, "regenerating the UVs: %s", e2.msg);
    return 0;
}

/* The levels read whole (r_fvar) made compact once the map is checked: the
 * compaction walks each vertex's corners. */
static int compact_uvs(st_hier *h)
{
    st_fvar *f = h->fvar;
    for (unsigned l = 0; f && l < f->levels; l++)
        if (st_fvar_level_compact(&f->lv[l], &h->map, l)) return -1;
    return 0;
}

static int r_fvar(load_ctx *c, st_br *r)
{
    st_hier *h = &c->s->h;
    /* After the map, or (compact, level 0 alone) between LVL0 and POSN. */
    int early = (c->seen & SEEN_LVL0) && !(c->seen & SEEN_POSN);
    if (!(c->seen & SEEN_MAP) && !early) return st_br_fail(r, "UVs before the map");
    uint32_t interp = st_br_u32(r), levels = st_br_u32(r);
    if (r->failed) return -1;
    if (interp >= ST_UV_INTERP_COUNT) return st_br_fail(r, "UVs: bad interpolation option %u", interp);
    if (levels == 0 || levels > h->map.top + 1) return st_br_fail(r, "UVs: %u levels in a hierarchy of %u", levels, h->map.top + 1);
    st_fvar *f = calloc(1, sizeof *f);
    if (!f) goto oom;
    h->fvar = f;
    f->interp = (int)interp;
    for (unsigned l = 0; l < levels; l++) {
        st_fvar_level *lv = &f->lv[l];   /* dense while read, compact after */
        lv->cap = h->map.darts.end;
        lv->uv = calloc(2 * (size_t)lv->cap + 2, sizeof *lv->uv);
        lv->val = calloc((size_t)lv->cap + 1, sizeof *lv->val);
        if (!lv->uv || !lv->val) goto oom;
        f->levels = l + 1;
        st_dart_iter it;
        uint64_t n = 0;
        for (uint32_t d = st_dart_first(&h->map, l, &it); d != ST_NIL; d = st_dart_next(&h->map, l, &it)) n += !st_is_boundary(&h->map, d);
        if (st_br_need(r, n, 20, "UVs")) return -1;
        for (uint32_t d = st_dart_first(&h->map, l, &it); d != ST_NIL; d = st_dart_next(&h->map, l, &it)) {
            if (st_is_boundary(&h->map, d)) continue;
            lv->uv[2 * (size_t)d] = st_br_f64(r);
            lv->uv[2 * (size_t)d + 1] = st_br_f64(r);
            lv->val[d] = st_br_u32(r);
            if (!isfinite(lv->uv[2 * (size_t)d]) || !isfinite(lv->uv[2 * (size_t)d + 1]))
                return st_br_fail(r, "UVs: a texture coordinate of level %u is not finite", l);
        }
        /* Compact once the map is checked: here when level 0 was (LVL0),
         * else after the whole map's check (compact_uvs). */
        if (!r->failed && early && st_fvar_level_compact(lv, &h->map, l)) goto oom;
    }
    if (r->failed) return -1;
    if (early) {
        c->uv_pending = 1;   /* refined beside the positions (r_positions) */
        return 0;
    }
    return levels == 1 ? regenerate_uvs(c, r) : 0;
oom:
    return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
}

static int r_base_uv(load_ctx *c, st_br *r)
{
    st_mesh *m = &c->s->base;
    uint32_t n = st_br_u32(r);
    if (r->failed) return -1;
    if (n == 0 || n > ST_MESH_MAX_VERTS || st_br_need(r, n, 16, "base mesh UVs")) return st_br_fail(r, "base mesh: %u UVs", n);
    uint32_t nidx = m->nfaces ? m->face_off[m->nfaces] : 0;
    m->uv = malloc(2 * (size_t)n * sizeof *m->uv);
    m->face_uv = malloc(((size_t)nidx + 1) * sizeof *m->face_uv);
    if (!m->uv || !m->face_uv) return load_fail(c, r, ST_ERR_MEMORY, "out of memory");
    m->nuvs = n;
    for (size_t i = 0; i < 2 * (size_t)n; i++) m->uv[i] = st_br_f64(r);
    if (st_br_need(r, nidx, 4, "base mesh UV corners")) return -1;
    for (uint32_t i = 0; i < nidx; i++) m->face_uv[i] = st_br_u32(r);
    if (r->failed) return -1;
    st_error e2;
    if (st_mesh_check("base mesh", m, &e2)) return st_br_fail(r, "%s", e2.msg);
    return 0;
}

/* ---- hdlv: the HD hierarchy ----------------------------------------------- */

/* Why a parsed HD image does not go with the model h, or NULL.  The
 * comparison of the shared levels is a cheap consistency check, not a proof
 * that they are copies: the number of live darts and vertices inserted at
 * each level 0..hd_from (O(levels), not a walk over the map). */
static const char *hd_mismatch(const st_hier *h, const st_session *in, unsigned hd_from, char *why, size_t n)
{
    static const st_adapt_params none;
    if (!in->has_adapt) return "it has no adaptive state";
    if (in->h.scheme != h->scheme) {
        snprintf(why, n, "its scheme is %s, the model's %s", in->h.scheme->name, h->scheme->name);
        return why;
    }
    if (hd_from != h->map.top) {
        snprintf(why, n, "hd_from is %u, the model's top is %u", hd_from, h->map.top);
        return why;
    }
    if (in->h.map.top < hd_from) {
        snprintf(why, n, "its top level %u is below the model's %u", in->h.map.top, hd_from);
        return why;
    }
    for (unsigned l = 0; l <= hd_from; l++) {
        const st_map *a = &h->map, *b = &in->h.map;
        if (a->darts.live[l] != b->darts.live[l] || a->verts.live[l] != b->verts.live[l]) {
            snprintf(why, n, "level %u has %u darts and %u vertices, the model's %u and %u", l, b->darts.live[l],
                     b->verts.live[l], a->darts.live[l], a->verts.live[l]);
            return why;
        }
    }
    /* The writer stores the hierarchy and its adaptive state alone: anything
     * else would not be written back (load -> save would change the bytes). */
    if (in->has_view || in->has_base || in->has_tool || in->mask.v || in->box_on || in->edit_level ||
        in->display_level || memcmp(&in->box, &none, sizeof none))
        return "its image holds more than a hierarchy, its adaptive state and its layers";
    /* Its layers are the HD levels' (the model's are in the outer file). */
    for (uint32_t i = 0; i < in->layers.n; i++)
        if (in->layers.v[i].level <= hd_from) {
            snprintf(why, n, "its layer '%s' is on level %u, not above the model's top %u", in->layers.v[i].name,
                     in->layers.v[i].level, hd_from);
            return why;
        }
    return NULL;
}

static int r_hd(load_ctx *c, st_br *r)
{
    st_session *s = c->s;
    /* The writer never nests them; a crafted file could, as deep as its
     * bytes allow, and each level is a reader's frame on the stack. */
    if (c->nested) return st_br_fail(r, "an HD hierarchy inside an HD hierarchy");
    uint32_t from = st_br_u32(r);
    if (r->failed) return -1;
    char name[512], why[160];
    snprintf(name, sizeof name, "%s: chunk 'hdlv'", c->name);
    st_session *in = malloc(sizeof *in);
    if (!in) return load_fail(c, r, ST_ERR_MEMORY, "chunk 'hdlv': out of memory");
    /* The nested image's messages name the file and the chunk, and give
     * offsets inside the image. */
    if (parse_image(name, r->p + r->off, r->size - r->off, in, c->err, 1)) {
        free(in);
        r->failed = 1;
        return -1;
    }
    const char *bad = hd_mismatch(&s->h, in, from, why, sizeof why);
    if (bad) {
        st_session_free(in);
        free(in);
        st_fail(c->err, ST_ERR_PARSE, "%s: %s", name, bad);
        r->failed = 1;
        return -1;
    }
    st_session_move_hier(&s->hd, &in->h);
    st_session_move_adapt(&s->hd_adapt, &in->adapt, &s->hd);
    in->has_adapt = 0;
    s->hd_layers = in->layers;
    st_layers_init(&in->layers);
    s->has_hd = 1;
    s->hd_from = from;
    /* keep_above is not stored: sculpted HD faces must never coarsen after
     * a load, whatever the next update's box says. */
    s->hd_adapt.keep_above = from;
    s->hd_adapt.exact = 1; /* saved from an exact state (adapt.h): updates keep it */
    st_session_free(in);
    free(in);
    r->off = r->size;
    return 0;
}

/* After every chunk: attributes attached, whole-map checks. */
static int finish(load_ctx *c)
{
    st_session *s = c->s;
    st_hier *h = &s->h;
    st_map *m = &h->map;
    const char *name = c->name;
    unsigned need = SEEN_HIER | SEEN_MAP | SEEN_DETL | SEEN_EDIT;
    if ((c->seen & need) != need) return st_fail(c->err, ST_ERR_PARSE, "%s: a required part of the session is missing", name);
    if (c->has_sharpness && !(c->seen & SEEN_SHRP)) return st_fail(c->err, ST_ERR_PARSE, "%s: the sharpness is missing", name);
    attach_sharpness(c);
    st_error e2;
    /* Regenerated levels are the refinement of a level 0 checked before
     * it ran (regenerate()); a map read whole is checked here. */
    if (check_map(c, !(c->seen & SEEN_LVL0), &e2)) return st_fail(c->err, ST_ERR_INVALID, "%s: %s", name, e2.msg);
    if (compact_uvs(h)) return st_fail(c->err, ST_ERR_MEMORY, "%s: out of memory", name);
    if (s->has_adapt) {
        /* The scheme must have adaptive refinement in this build. */
        st_adapt probe;
        if (st_adapt_init(&probe, h, &e2)) return st_fail(c->err, ST_ERR_INVALID, "%s: adaptive state: %s", name, e2.msg);
        st_adapt_free(&probe);
        /* One base dart per face of level 0. */
        int fb = st_marker_reserve(m);
        int rc = fb < 0 ? -1 : 0;
        for (uint32_t i = 0; !rc && i < s->adapt.base_faces.n; i++) {
            uint32_t d = s->adapt.base_faces.d[i];
            if (st_marked(m, fb, d)) rc = -1;
            else st_mark_face(m, fb, d, 0);
        }
        if (fb >= 0) st_marker_release(m, fb, 0);
        if (rc) return st_fail(c->err, ST_ERR_INVALID, "%s: adaptive state: two base darts on one face", name);
    }
    return ST_OK;
}

int st_session_parse(const char *name, const void *data, size_t size, st_session *out, st_error *err)
{
    return parse_image(name, data, size, out, err, 0);
}

/* st_session_parse; nested: the image inside an hdlv chunk (r_hd). */
static int parse_image(const char *name, const void *data, size_t size, st_session *out, st_error *err, int nested)
{
    const unsigned char *p = data;
    if (size < HEADER_BYTES + TRAILER_BYTES)
        return st_fail(err, ST_ERR_PARSE, "%s: %s (%zu bytes)", name,
                       size >= 8 && !memcmp(p, ST_SESSION_MAGIC, 8) ? "truncated session file" : "too short to be a Strata session", size);
    if (memcmp(p, ST_SESSION_MAGIC, 8))
        return st_fail(err, ST_ERR_PARSE, "%s: not a Strata session file (bad magic)", name);
    uint32_t hc = 0, version = 0;
    uint64_t total = 0;
    for (int k = 0; k < 4; k++) version |= (uint32_t)p[8 + k] << (8 * k);
    for (int k = 0; k < 8; k++) total |= (uint64_t)p[16 + k] << (8 * k);
    for (int k = 0; k < 4; k++) hc |= (uint32_t)p[24 + k] << (8 * k);
    if (st_crc32(0, p, 24) != hc)
        return st_fail(err, ST_ERR_PARSE, "%s: damaged session file (header checksum mismatch)", name);
    if (version < 1 || version > ST_SESSION_VERSION)
        return st_fail(err, ST_ERR_PARSE, "%s: session format version %u is %s than this strata (%u)", name, version,
                       version > ST_SESSION_VERSION ? "newer" : "older", ST_SESSION_VERSION);
    if (p[12] | p[13] | p[14] | p[15]) return st_fail(err, ST_ERR_PARSE, "%s: unknown header flags", name);
    if (total != size)
        return st_fail(err, ST_ERR_PARSE, "%s: %s: %zu bytes, the header says %llu", name,
                       size < total ? "truncated session file" : "session file with trailing data", size,
                       (unsigned long long)total);
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
    /* Fuzz builds (CMakeLists.txt, STRATA_FUZZ) leave the whole-file
     * checksum out, as the usual libFuzzer convention does, so that every
     * mutation reaches the structural checks (test_session checks this one). */
    uint32_t crc = 0;
    for (int k = 0; k < 4; k++) crc |= (uint32_t)p[size - 4 + k] << (8 * k);
    if (st_session_checksum(p, size) != crc)
        return st_fail(err, ST_ERR_PARSE, "%s: damaged session file (checksum mismatch)", name);
#endif

    st_session *s = malloc(sizeof *s);
    if (!s) return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", name);
    st_session_init(s);
    load_ctx c = { .s = s, .name = name, .err = err, .nested = nested };
    size_t off = HEADER_BYTES, end = size - TRAILER_BYTES;
    int rc = 0;
    while (off < end && !rc) {
        st_br hr;
        st_br_init(&hr, name, p, end, err);
        hr.off = off;
        uint32_t tag = st_br_u32(&hr);
        uint64_t len = st_br_u64(&hr);
        if (hr.failed) { rc = -1; break; }
        if (len > end - hr.off) { rc = st_br_fail(&hr, "chunk of %llu bytes runs past the end", (unsigned long long)len); break; }
        /* The tag as text for messages (hex when not printable ASCII). */
        char t[16] = { (char)(tag & 0xff), (char)(tag >> 8 & 0xff), (char)(tag >> 16 & 0xff), (char)(tag >> 24), 0 };
        for (int k = 0; k < 4; k++)
            if (t[k] < 0x20 || t[k] > 0x7e) { snprintf(t, sizeof t, "0x%08x", (unsigned)tag); break; }
        /* The chunk's reader sees only its payload; offsets stay file offsets. */
        st_br r;
        st_br_init(&r, name, p, hr.off + (size_t)len, err);
        r.off = hr.off;
        r.trimmed = version >= SESSION_VERSION_TRIMMED;
        unsigned bit = 0;
        int (*fn)(load_ctx *, st_br *) = NULL;
        unsigned after = 0;   /* chunks that must come first */
        switch (tag) {
        case TAG_HIER: bit = SEEN_HIER; fn = r_hier; break;
        case TAG_MAP:  bit = SEEN_MAP;  fn = r_map;  after = SEEN_HIER; break;
        case TAG_SHRP: bit = SEEN_SHRP; fn = r_sharp; after = SEEN_HIER; break;
        case TAG_LVL0: if (version >= SESSION_VERSION_RECIPE) { bit = SEEN_LVL0; fn = r_level0; after = SEEN_HIER; } break;
        case TAG_POSN: if (version >= SESSION_VERSION_RECIPE) { bit = SEEN_POSN; fn = r_positions; after = SEEN_LVL0; } break;
        case TAG_PMRC: if (version >= SESSION_VERSION_PMRC) { bit = SEEN_PMRC; fn = r_recipe; after = SEEN_HIER; } break;
        case TAG_DETL: bit = SEEN_DETL; fn = r_detail; after = SEEN_MAP; break;
        case TAG_ADPT: bit = SEEN_ADPT; fn = r_adapt; after = SEEN_MAP; break;
        case TAG_EDIT: bit = SEEN_EDIT; fn = r_edit; after = SEEN_MAP; break;
        case TAG_VIEW: bit = SEEN_VIEW; fn = r_view; break;
        case TAG_BASE: bit = SEEN_BASE; fn = r_base; break;
        case TAG_MASK: bit = SEEN_MASK; fn = r_mask; after = SEEN_MAP; break;
        case TAG_TOOL: bit = SEEN_TOOL; fn = r_tool; break;
        case TAG_LAYR: bit = SEEN_LAYR; fn = r_layers; after = SEEN_MAP; break;
        case TAG_LAY0: bit = SEEN_LAYR; fn = r_layers0; after = SEEN_MAP; break;
        case TAG_FVAR: if (version >= SESSION_VERSION_UV) { bit = SEEN_FVAR; fn = r_fvar; after = SEEN_HIER; } break;
        case TAG_BUVS: if (version >= SESSION_VERSION_UV) { bit = SEEN_BUVS; fn = r_base_uv; after = SEEN_BASE; } break;
        case TAG_HDLV: bit = SEEN_HDLV; fn = r_hd; after = SEEN_MAP | SEEN_DETL; break;
        default: break;
        }
        if (!fn) {
            /* Unknown chunk: ancillary ones (first letter lower case) are skipped. */
            if (t[0] >= 'a' && t[0] <= 'z') { off = hr.off + (size_t)len; continue; }
            rc = st_br_fail(&hr, "unknown chunk '%s'", t);
            break;
        }
        if (c.seen & bit) { rc = st_br_fail(&hr, "chunk '%s' appears twice", t); break; }
        if ((c.seen & after) != after) { rc = st_br_fail(&hr, "chunk '%s' comes before the chunks it depends on", t); break; }
        c.seen |= bit;
        rc = fn(&c, &r);
        if (!rc && r.failed) rc = -1;
        if (!rc && r.off != r.size) rc = st_br_fail(&r, "chunk '%s': %zu bytes left over", t, r.size - r.off);
        off = hr.off + (size_t)len;
    }
    if (!rc) rc = finish(&c);
    /* Regenerated from level 0 as it was built: the next save can store
     * level 0 alone again. */
    if (!rc && (c.seen & SEEN_LVL0)) st_hier_mark_regenerable(&s->h, c.regen_end);
    if (rc) {
        if (err && !err->code) st_fail(err, ST_ERR_PARSE, "%s: invalid session", name);
        st_session_free(s);
        free(s);
        return err ? (err->code ? err->code : ST_ERR_PARSE) : ST_ERR_PARSE;
    }
    st_session_move_raw(out, s);
    free(s);
    if (err) { err->code = ST_OK; err->msg[0] = 0; }
    return ST_OK;
}

#define SESSION_BYTES_PER_FILE_BYTE 3u

int st_session_load(const char *path, st_session *out, st_error *err)
{
    FILE *f = st_open_input(path, err);
    if (!f) return err ? err->code : ST_ERR_IO;
    /* The memory guard (core/base/membudget.h): the file, then the
     * hierarchy parsed from it, a bound of SESSION_BYTES_PER_FILE_BYTE
     * times the file (measured at 2.0 to 2.8 on sessions of koala's
     * progressive hierarchy and of blub's Catmull-Clark levels, stored
     * whole); a compact file regenerates more than that, and checks the
     * estimate of the levels it regenerates before it does (regenerate()). */
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
        size_t n = (size_t)st.st_size;
        int rc = st_mem_check_read(path, "session", n, n + SESSION_BYTES_PER_FILE_BYTE * n, err);
        if (rc) {
            fclose(f);
            return rc;
        }
    }
    unsigned char *buf = NULL;
    size_t n = 0, cap = 0;
    int bad = 0;
    for (;;) {
        if (n == cap) {
            size_t nc = cap ? cap * 2 : 1 << 20;
            unsigned char *q = realloc(buf, nc);
            if (!q) { bad = ENOMEM; break; }
            buf = q;
            cap = nc;
        }
        size_t k = fread(buf + n, 1, cap - n, f);
        n += k;
        if (k == 0) {
            if (ferror(f)) bad = errno ? errno : EIO;
            break;
        }
    }
    fclose(f);
    if (bad) {
        free(buf);
        return st_fail(err, bad == ENOMEM ? ST_ERR_MEMORY : ST_ERR_IO, "%s: cannot read: %s", path, strerror(bad));
    }
    int rc = st_session_parse(path, buf ? buf : (const unsigned char *)"", n, out, err);
    free(buf);
    return rc;
}
