/* st_map storage, allocation, queries and enumeration (map.h). */
#include "core/base/hugepage.h"
#include "core/map/map.h"
#include "core/map/pool_internal.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

static _Atomic uint64_t last_gen;

static uint64_t new_gen(void) { return atomic_fetch_add(&last_gen, 1) + 1; }

uint64_t st_map_generation(st_map *m)
{
    m->gen_seen = 1;
    return m->gen;
}

/* A new number only when the current one was handed out: setters call this
 * millions of times in a refinement, and a plain test costs nothing. */
void st_map_changed(st_map *m)
{
    if (!m->gen_seen) return;
    m->gen = new_gen();
    m->gen_seen = 0;
}

void st_map_init(st_map *m)
{
    memset(m, 0, sizeof *m);
    m->gen = new_gen();
    st_pool_init(&m->darts);
    st_pool_init(&m->verts);
    st_mla_init(&m->beta0, sizeof(uint32_t));
    st_mla_init(&m->beta1, sizeof(uint32_t));
    st_mla_init(&m->vert, sizeof(uint32_t));
    st_mla_init(&m->pos, 3 * sizeof(double));
}

void st_map_free(st_map *m)
{
    st_pool_free(&m->darts);
    st_pool_free(&m->verts);
    st_mla_free(&m->beta0);
    st_mla_free(&m->beta1);
    st_mla_free(&m->vert);
    st_mla_free(&m->pos);
    free(m->flags);
    free(m->marks);
    st_map_init(m);
}

/* ---- allocation ------------------------------------------------------------ */

static int try_grow_dart_arrays(st_map *m, uint32_t cap, int huge)
{
    uint32_t used = m->darts.end;
    if (st_array_grow(&m->flags, 1, used, cap, huge)) return -1;
    st_mla *rel[3] = { &m->beta0, &m->beta1, &m->vert };
    for (int i = 0; i < 3; i++)
        if (st_mla_grow(rel[i], used, cap, huge)) return -1;
    for (uint32_t i = 0; i < m->ndart_attrs; i++)
        if (st_mla_grow(m->dart_attrs[i], used, cap, huge)) return -1;
    if (m->marks) {
        uint32_t *mk = realloc(m->marks, (size_t)cap * sizeof *mk);
        if (!mk) return -1;
        m->marks = mk;
    }
    return 0;
}

static void grow_dart_arrays(st_map *m, uint32_t cap)
{
    if (try_grow_dart_arrays(m, cap, 0))
        abort(); /* out of memory in the middle of an operator: no consistent state to return to */
}

static int grow_vertex_arrays_kind(st_map *m, uint32_t cap, int huge)
{
    uint32_t used = m->verts.end;
    if (st_mla_grow(&m->pos, used, cap, huge)) return -1;
    for (uint32_t i = 0; i < m->nvert_attrs; i++)
        if (st_mla_grow(m->vert_attrs[i], used, cap, huge)) return -1;
    return 0;
}

static int grow_vertex_arrays(st_map *m, uint32_t cap) { return grow_vertex_arrays_kind(m, cap, 0); }

int st_map_reserve(st_map *m, uint64_t darts, uint64_t verts)
{
    uint32_t dc = st_pool_reserve(&m->darts, darts);
    if (!dc || try_grow_dart_arrays(m, dc, 1)) return -1;
    uint32_t vc = st_pool_reserve(&m->verts, verts);
    if (!vc || grow_vertex_arrays_kind(m, vc, 1)) return -1;
    return 0;
}

static void advise_tail(st_mla *a, const st_pool *p)
{
    st_advise_huge(a->base + (size_t)p->end * a->elem, (size_t)(p->cap - p->end) * a->elem);
}

void st_map_advise_reserved(st_map *m)
{
    st_advise_huge(m->flags + m->darts.end, m->darts.cap - m->darts.end);
    st_mla *dart_mla[3] = { &m->beta0, &m->beta1, &m->vert };
    for (int i = 0; i < 3; i++) advise_tail(dart_mla[i], &m->darts);
    for (uint32_t i = 0; i < m->ndart_attrs; i++) advise_tail(m->dart_attrs[i], &m->darts);
    advise_tail(&m->pos, &m->verts);
    for (uint32_t i = 0; i < m->nvert_attrs; i++) advise_tail(m->vert_attrs[i], &m->verts);
}

void st_map_trim(st_map *m)
{
    st_pool_trim(&m->darts);
    st_pool_trim(&m->verts);
    uint32_t dc = m->darts.cap ? m->darts.cap : 1;
    uint8_t *fl = realloc(m->flags, dc);
    if (fl) m->flags = fl;
    if (m->marks) {
        uint32_t *mk = realloc(m->marks, (size_t)dc * sizeof *mk);
        if (mk) m->marks = mk;
    }
    st_mla *dart_mla[3] = { &m->beta0, &m->beta1, &m->vert };
    for (int i = 0; i < 3; i++) st_mla_trim(dart_mla[i], &m->darts);
    for (uint32_t i = 0; i < m->ndart_attrs; i++) st_mla_trim(m->dart_attrs[i], &m->darts);
    st_mla_trim(&m->pos, &m->verts);
    for (uint32_t i = 0; i < m->nvert_attrs; i++) st_mla_trim(m->vert_attrs[i], &m->verts);
}

/* Dense columns again before anything writes the topology (map.h, "Sparse
 * form"): the sparse form is read-only. */
static void thaw_topology(st_map *m)
{
    st_mla_thaw(&m->beta0, &m->darts);
    st_mla_thaw(&m->beta1, &m->darts);
    st_mla_thaw(&m->vert, &m->darts);
}

void st_map_compact(st_map *m)
{
    st_map_trim(m);
    st_mla_freeze(&m->beta0, &m->darts); /* out of memory: stays dense */
    st_mla_freeze(&m->beta1, &m->darts);
    st_mla_freeze(&m->vert, &m->darts);
}

void st_map_sparse_stats_compute(const st_map *m, st_map_sparse_stats *st)
{
    const st_mla *rel[3] = { &m->beta0, &m->beta1, &m->vert };
    memset(st, 0, sizeof *st);
    for (int r = 0; r < 3; r++) {
        const st_mla_sparse *s = rel[r]->sp;
        if (!s) continue;
        st->relations_sparse++;
        st->pairs += s->npairs;
        for (uint32_t i = 0; i < s->n; i++) {
            uint32_t b = s->bbase[i >> ST_POOL_BLOCK_SHIFT] + s->boff[i];
            uint32_t e = s->bbase[(i + 1) >> ST_POOL_BLOCK_SHIFT] + s->boff[i + 1];
            if (e - b > st->longest) st->longest = e - b;
        }
    }
}

/* ---- change log ---------------------------------------------------------------- */

void st_map_log_clear(st_map_log *g)
{
    g->ndarts = g->nverts = 0;
    g->overflow = 0;
}

void st_map_log_free(st_map_log *g)
{
    free(g->darts);
    free(g->verts);
    memset(g, 0, sizeof *g);
}

static void log_id(st_map_log *g, uint32_t **ids, uint32_t *n, uint32_t *cap, uint32_t id)
{
    if (g->overflow) return;
    if (*n == *cap) {
        uint32_t c = *cap ? 2 * *cap : 256;
        uint32_t *a = c > *cap ? realloc(*ids, (size_t)c * sizeof *a) : NULL;
        if (!a) { g->overflow = 1; return; }
        *ids = a;
        *cap = c;
    }
    (*ids)[(*n)++] = id;
}

static inline void log_dart(st_map *m, uint32_t d)
{
    st_map_changed(m);
    if (m->log) log_id(m->log, &m->log->darts, &m->log->ndarts, &m->log->capdarts, d);
}

void st_map_log_vertex(st_map *m, uint32_t v)
{
    if (m->log) log_id(m->log, &m->log->verts, &m->log->nverts, &m->log->capverts, v);
}

uint32_t st_dart_new(st_map *m, unsigned l, uint32_t v, uint8_t flags)
{
    uint32_t grow;
    uint32_t d = st_pool_take(&m->darts, l, &grow);
    if (d == ST_NIL) abort();
    if (grow) grow_dart_arrays(m, grow);
    st_mla_insert(&m->beta0, &m->darts, d, &d);
    st_mla_insert(&m->beta1, &m->darts, d, &d);
    st_mla_insert(&m->vert, &m->darts, d, &v);
    m->flags[d] = flags;
    if (m->marks) m->marks[d] = 0;
    static const unsigned char zero[64];
    for (uint32_t i = 0; i < m->ndart_attrs; i++) st_mla_insert(m->dart_attrs[i], &m->darts, d, zero);
    log_dart(m, d);
    return d;
}

static const unsigned char zero_attr[64];

uint32_t st_dart_take_run(st_map *m, unsigned l, uint32_t want, uint32_t *got)
{
    uint32_t grow;
    thaw_topology(m); /* the caller writes base[] of the new ids directly */
    uint32_t d = st_pool_take_run(&m->darts, l, want, got, &grow);
    if (d == ST_NIL) abort();
    if (grow) grow_dart_arrays(m, grow);
    if (m->marks) memset(m->marks + d, 0, (size_t)*got * sizeof *m->marks);
    for (uint32_t i = 0; i < m->ndart_attrs; i++)
        for (uint32_t k = 0; k < *got; k++) st_mla_insert(m->dart_attrs[i], &m->darts, d + k, zero_attr);
    st_map_changed(m);
    for (uint32_t k = 0; m->log && k < *got; k++) log_dart(m, d + k);
    return d;
}

void st_dart_delete(st_map *m, uint32_t d)
{
    thaw_topology(m); /* a reused id must not find this one's pairs */
    log_dart(m, d);
    st_pool_release(&m->darts, d);
}

static int attach(st_mla *a, st_pool *p, st_mla **list, uint32_t *n)
{
    static const unsigned char zero[64];
    if (*n >= 4 || a->elem > sizeof zero || st_mla_grow(a, p->end, p->cap ? p->cap : 1, 0)) return -1;
    for (uint32_t i = 0; i < p->end; i++)
        if (p->ins[i] != ST_FREE_LEVEL) st_mla_insert(a, p, i, zero);
    list[(*n)++] = a;
    return 0;
}

int st_map_attach_dart_attr(st_map *m, st_mla *a) { return attach(a, &m->darts, m->dart_attrs, &m->ndart_attrs); }
int st_map_attach_vertex_attr(st_map *m, st_mla *a) { return attach(a, &m->verts, m->vert_attrs, &m->nvert_attrs); }

uint32_t st_vertex_new(st_map *m, unsigned l, const double p[3])
{
    uint32_t grow;
    uint32_t v = st_pool_take(&m->verts, l, &grow);
    if (v == ST_NIL) abort();
    if (grow && grow_vertex_arrays(m, grow)) abort();
    st_map_changed(m);
    st_mla_insert(&m->pos, &m->verts, v, p);
    static const unsigned char zero[64];
    for (uint32_t i = 0; i < m->nvert_attrs; i++) st_mla_insert(m->vert_attrs[i], &m->verts, v, zero);
    st_map_log_vertex(m, v);
    return v;
}

uint32_t st_vertex_take_run(st_map *m, unsigned l, uint32_t want, uint32_t *got)
{
    uint32_t grow;
    uint32_t v = st_pool_take_run(&m->verts, l, want, got, &grow);
    if (v == ST_NIL) abort();
    if (grow && grow_vertex_arrays(m, grow)) abort();
    st_map_changed(m);
    for (uint32_t i = 0; i < m->nvert_attrs; i++)
        for (uint32_t k = 0; k < *got; k++) st_mla_insert(m->vert_attrs[i], &m->verts, v + k, zero_attr);
    for (uint32_t k = 0; m->log && k < *got; k++) st_map_log_vertex(m, v + k);
    return v;
}

void st_vertex_delete(st_map *m, uint32_t v)
{
    st_map_changed(m);
    st_map_log_vertex(m, v);
    st_pool_release(&m->verts, v);
}

void st_set_beta0(st_map *m, uint32_t d, unsigned l, uint32_t e) { log_dart(m, d); st_mla_set(&m->beta0, &m->darts, d, l, &e); }
void st_set_beta1(st_map *m, uint32_t d, unsigned l, uint32_t e) { log_dart(m, d); st_mla_set(&m->beta1, &m->darts, d, l, &e); }
void st_set_vert(st_map *m, uint32_t d, unsigned l, uint32_t v) { log_dart(m, d); st_mla_set(&m->vert, &m->darts, d, l, &v); }
void st_set_pos(st_map *m, uint32_t v, unsigned l, const double p[3]) { st_map_log_vertex(m, v); st_mla_set(&m->pos, &m->verts, v, l, p); }

void st_map_write_pos(st_map *m, uint32_t v, unsigned l, const double p[3])
{
    st_mla *a = &m->pos;
    if (m->log) st_map_log_vertex(m, v); /* a call per vertex written otherwise */
    if (m->verts.ins[v] == l) {
        memcpy(a->base + (size_t)v * a->elem, p, 3 * sizeof(double)); /* elem: 3 doubles */
        return;
    }
    if (a->col[l] && v < a->colcap[l]) {
        memcpy(a->col[l] + (size_t)v * a->elem, p, 3 * sizeof(double));
        return;
    }
    if (!a->col[l] && memcmp(st_pos(m, v, l), p, a->elem) == 0) return;
    double *col = st_mla_column(a, &m->verts, l);
    if (!col) abort(); /* out of memory for a level's positions */
    memcpy(col + 3 * (size_t)v, p, a->elem);
}

void st_sew0(st_map *m, uint32_t d, uint32_t e, unsigned l)
{
    st_set_beta0(m, d, l, e);
    st_set_beta0(m, e, l, d);
}

/* ---- levels ---------------------------------------------------------------- */

int st_level_add(st_map *m, st_error *err)
{
    if (m->top + 1 >= ST_MAX_LEVELS)
        return st_fail(err, ST_ERR_RANGE, "cannot add level %u: at most %d levels", m->top + 1, ST_MAX_LEVELS);
    st_map_changed(m);
    m->top++;
    return ST_OK;
}

void st_level_remove_top(st_map *m)
{
    if (m->top == 0) return;
    st_map_changed(m);
    thaw_topology(m);
    unsigned l = m->top;
    st_mla_drop_column(&m->beta0, l);
    st_mla_drop_column(&m->beta1, l);
    st_mla_drop_column(&m->vert, l);
    st_mla_drop_column(&m->pos, l);
    for (uint32_t i = 0; i < m->ndart_attrs; i++) st_mla_drop_column(m->dart_attrs[i], l);
    for (uint32_t i = 0; i < m->nvert_attrs; i++) st_mla_drop_column(m->vert_attrs[i], l);
    st_pool_drop_level(&m->darts, l);
    st_pool_drop_level(&m->verts, l);
    m->top--;
}

void st_level_remove_bottom(st_map *m)
{
    if (m->top == 0) return;
    st_map_changed(m);
    st_mla_drop_bottom(&m->beta0, &m->darts);
    st_mla_drop_bottom(&m->beta1, &m->darts);
    st_mla_drop_bottom(&m->vert, &m->darts);
    for (uint32_t i = 0; i < m->ndart_attrs; i++) st_mla_drop_bottom(m->dart_attrs[i], &m->darts);
    st_mla_drop_bottom(&m->pos, &m->verts);
    for (uint32_t i = 0; i < m->nvert_attrs; i++) st_mla_drop_bottom(m->vert_attrs[i], &m->verts);
    st_pool_drop_bottom(&m->darts);
    st_pool_drop_bottom(&m->verts);
    m->top--;
}

/* ---- enumeration ------------------------------------------------------------- */

/* Advances it over the blocks of levels 0..l of pool p; returns the next live
 * id or ST_NIL.  it->id is the offset inside the current block (blocks of a
 * level are not in id order once blocks of removed levels are reused). */
static uint32_t pool_scan(const st_pool *p, unsigned l, st_dart_iter *it)
{
    l = st_lvl_clamp(l);
    while (it->level <= l) {
        if (it->block < p->nblocks[it->level]) {
            uint32_t first = p->blocks[it->level][it->block] << ST_POOL_BLOCK_SHIFT;
            while (it->id < ST_POOL_BLOCK) {
                uint32_t id = first + it->id++;
                if (p->ins[id] != ST_FREE_LEVEL) return id;
            }
            it->block++;
            it->id = 0;
        } else {
            it->level++;
            it->block = 0;
        }
    }
    return ST_NIL;
}

uint32_t st_dart_first(const st_map *m, unsigned l, st_dart_iter *it)
{
    memset(it, 0, sizeof *it);
    return pool_scan(&m->darts, l, it);
}

uint32_t st_dart_next(const st_map *m, unsigned l, st_dart_iter *it) { return pool_scan(&m->darts, l, it); }

uint32_t st_vertex_first(const st_map *m, unsigned l, st_dart_iter *it)
{
    memset(it, 0, sizeof *it);
    /* In the dual encoding a surface vertex lives at its own level only. */
    if (m->face_embedded) it->level = st_lvl_clamp(l);
    return pool_scan(&m->verts, l, it);
}

uint32_t st_vertex_next(const st_map *m, unsigned l, st_dart_iter *it) { return pool_scan(&m->verts, l, it); }

/* ---- markers ------------------------------------------------------------------ */

int st_marker_reserve(st_map *m)
{
    if (!m->marks) {
        m->marks = calloc(m->darts.cap ? m->darts.cap : 1, sizeof *m->marks);
        if (!m->marks) return -1;
    }
    for (int b = 0; b < 32; b++)
        if (!(m->marks_used & (1u << b))) {
            m->marks_used |= 1u << b;
            return b;
        }
    return -1;
}

void st_marker_release(st_map *m, int bit, unsigned l)
{
    st_dart_iter it;
    for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it))
        st_unmark(m, bit, d);
    m->marks_used &= ~(1u << bit);
}

/* ---- statistics and memory ---------------------------------------------------- */

/* Orbits are counted with two transient bits per dart id rather than the
 * marker bits: no 4-byte-per-dart marks array to allocate, and no pass to
 * clear it afterwards. */
typedef struct orbit_count {
    st_level_view v;
    uint64_t *vseen, *fseen;
} orbit_count;

static int seen_bit(const uint64_t *s, uint32_t d) { return (s[d >> 6] >> (d & 63)) & 1; }
static void see_bit(uint64_t *s, uint32_t d) { s[d >> 6] |= 1ull << (d & 63); }

/* Cells of the surface: in the dual encoding its vertices are the map's
 * φ1 orbits and its faces (and holes) the β1 orbits. */
static inline void count_dart(const st_map *m, orbit_count *c, uint32_t d, st_level_stats *s, int sparse)
{
    s->darts++;
    if (d < st_v_beta0_kind(&c->v, d, sparse)) s->edges++;
    int bd = st_is_boundary(m, d), dual = m->face_embedded;
    if (bd) s->boundary_edges++;
    if (!seen_bit(c->vseen, d)) {
        s->vertices++;
        uint32_t x = d;
        do {
            see_bit(c->vseen, x);
            x = st_v_vertex_step_kind(&c->v, dual, x, sparse);
        } while (x != d);
    }
    if (!seen_bit(c->fseen, d)) {
        if (bd) s->boundary_loops++; else s->faces++;
        uint32_t x = d;
        do {
            see_bit(c->fseen, x);
            x = st_v_face_step_kind(&c->v, dual, x, sparse);
        } while (x != d);
    }
}

/* The darts of levels 0..l, block by block (st_dart_next without a call per
 * dart); one copy per kind of map (map.h, "Two lookup paths"). */
static inline void count_darts(const st_map *m, orbit_count *c, unsigned l, st_level_stats *s, int sparse)
{
    const st_pool *p = &m->darts;
    for (unsigned lv = 0; lv <= st_lvl_clamp(l); lv++)
        for (uint32_t b = 0; b < p->nblocks[lv]; b++) {
            uint32_t first = p->blocks[lv][b] << ST_POOL_BLOCK_SHIFT;
            for (uint32_t d = first; d < first + ST_POOL_BLOCK; d++)
                if (p->ins[d] != ST_FREE_LEVEL) count_dart(m, c, d, s, sparse);
        }
}

void st_level_stats_compute(st_map *m, unsigned l, st_level_stats *s)
{
    memset(s, 0, sizeof *s);
    size_t words = (size_t)m->darts.end / 64 + 1;
    orbit_count c;
    c.vseen = calloc(2 * words, sizeof *c.vseen);
    if (!c.vseen) abort(); /* out of memory for two bits per dart */
    c.fseen = c.vseen + words;
    st_level_view_init(m, l, &c.v);
    if (st_map_is_sparse(m)) count_darts(m, &c, l, s, 1);
    else count_darts(m, &c, l, s, 0);
    free(c.vseen);
    s->euler = (int64_t)s->vertices - (int64_t)s->edges + (int64_t)s->faces;
}

void st_map_memory(const st_map *m, st_map_bytes *b)
{
    uint32_t dc = m->darts.cap, vc = m->verts.cap;
    b->topology = st_mla_bytes(&m->beta0, dc) + st_mla_bytes(&m->beta1, dc) + st_mla_bytes(&m->vert, dc)
                + (size_t)dc * 2; /* ins + flags */
    b->positions = st_mla_bytes(&m->pos, vc) + vc;
}
