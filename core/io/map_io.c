/* Binary (de)serialization of st_map and st_mla (map_io.h). */
#include "core/io/map_io_internal.h"
#include "core/map/pool_internal.h"

#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <xxhash.h>

/* ---- CRC-32 ------------------------------------------------------------------ */

static uint32_t crc_table[8][256];
static pthread_once_t crc_once = PTHREAD_ONCE_INIT;

static void crc_init(void)
{
    for (uint32_t i = 0; i < 256; i++) {
        uint32_t c = i;
        for (int k = 0; k < 8; k++) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        crc_table[0][i] = c;
    }
    for (uint32_t i = 0; i < 256; i++)
        for (int t = 1; t < 8; t++)
            crc_table[t][i] = (crc_table[t - 1][i] >> 8) ^ crc_table[0][crc_table[t - 1][i] & 0xff];
}

uint32_t st_crc32(uint32_t crc, const void *data, size_t n)
{
    pthread_once(&crc_once, crc_init); /* saves may run on a worker thread (autosave) */
    const unsigned char *p = data;
    uint32_t c = ~crc;
    /* Slicing by 8 (byte order independent: the bytes are combined by hand). */
    while (n >= 8) {
        uint32_t lo = c ^ ((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24);
        uint32_t hi = (uint32_t)p[4] | (uint32_t)p[5] << 8 | (uint32_t)p[6] << 16 | (uint32_t)p[7] << 24;
        c = crc_table[7][lo & 0xff] ^ crc_table[6][(lo >> 8) & 0xff] ^ crc_table[5][(lo >> 16) & 0xff] ^
            crc_table[4][lo >> 24] ^ crc_table[3][hi & 0xff] ^ crc_table[2][(hi >> 8) & 0xff] ^
            crc_table[1][(hi >> 16) & 0xff] ^ crc_table[0][hi >> 24];
        p += 8;
        n -= 8;
    }
    while (n--) c = crc_table[0][(c ^ *p++) & 0xff] ^ (c >> 8);
    return ~c;
}

/* ---- writer -------------------------------------------------------------------- */

uint32_t st_session_checksum(const void *p, size_t n)
{
    const unsigned char *b = p;
    if (n < 16) return 0;
    uint32_t version = (uint32_t)b[8] | (uint32_t)b[9] << 8 | (uint32_t)b[10] << 16 | (uint32_t)b[11] << 24;
    return version >= 4 ? (uint32_t)XXH3_64bits(p, n - 4) : st_crc32(0, p, n - 4);
}

static void bw_reset(st_bw *w)
{
    w->f = NULL;
    w->mem = 0;
    w->out = NULL;
    w->outlen = w->outcap = 0;
    w->total = 0;
    w->xxh = NULL;
    w->failed = 0;
    w->refused_value = 0;
    w->slow_us = 0;
    w->progress = NULL;
    w->progress_ctx = NULL;
    w->progress_total = 0;
    w->cancelled = 0;
    w->n = 0;
}

void st_bw_init_count(st_bw *w) { bw_reset(w); }

static int bw_hash_start(st_bw *w)
{
    w->xxh = XXH3_createState();
    if (!w->xxh || XXH3_64bits_reset(w->xxh) != XXH_OK) w->failed = 1;
    return w->failed ? -1 : 0;
}

int st_bw_init_file(st_bw *w, FILE *f)
{
    bw_reset(w);
    w->f = f;
    return bw_hash_start(w);
}

int st_bw_init_mem(st_bw *w)
{
    bw_reset(w);
    w->mem = 1;
    return bw_hash_start(w);
}

void st_bw_free(st_bw *w)
{
    if (w->xxh) XXH3_freeState(w->xxh);
    w->xxh = NULL;
}

uint32_t st_bw_checksum(const st_bw *w) { return w->xxh ? (uint32_t)XXH3_64bits_digest(w->xxh) : 0; }

int st_bw_flush(st_bw *w)
{
    if (w->n && !w->failed) {
        if (w->xxh) XXH3_64bits_update(w->xxh, w->buf, w->n);
        if (w->f) {
            if (fwrite(w->buf, 1, w->n, w->f) != w->n) w->failed = 1;
            if (w->slow_us > 0) {
                struct timespec ts = { w->slow_us / 1000000, (w->slow_us % 1000000) * 1000 };
                nanosleep(&ts, NULL);
            }
            if (w->progress && !w->failed && w->progress_total &&
                w->progress(w->progress_ctx, (double)w->total / (double)w->progress_total)) {
                w->failed = 1;
                w->cancelled = 1;
            }
        } else if (w->mem) {
            if (w->outlen + w->n > w->outcap) {
                size_t cap = w->outcap ? w->outcap : 1 << 16;
                while (cap < w->outlen + w->n) cap *= 2;
                unsigned char *q = realloc(w->out, cap);
                if (!q) { w->failed = 1; w->n = 0; return -1; }
                w->out = q;
                w->outcap = cap;
            }
            memcpy(w->out + w->outlen, w->buf, w->n);
            w->outlen += w->n;
        }
    }
    w->n = 0;
    return w->failed ? -1 : 0;
}

void st_bw_bytes(st_bw *w, const void *p, size_t n)
{
    const unsigned char *s = p;
    w->total += n;
    while (n) {
        size_t room = sizeof w->buf - w->n, k = n < room ? n : room;
        memcpy(w->buf + w->n, s, k);
        w->n += k;
        s += k;
        n -= k;
        if (w->n == sizeof w->buf) st_bw_flush(w);
    }
}

static inline void bw_le(st_bw *w, uint64_t v, unsigned k)
{
    if (w->n + k > sizeof w->buf) st_bw_flush(w);
    for (unsigned i = 0; i < k; i++) w->buf[w->n + i] = (unsigned char)(v >> (8 * i));
    w->n += k;
    w->total += k;
}

void st_bw_u8(st_bw *w, uint8_t v) { bw_le(w, v, 1); }
void st_bw_u32(st_bw *w, uint32_t v) { bw_le(w, v, 4); }
void st_bw_u64(st_bw *w, uint64_t v) { bw_le(w, v, 8); }
/* Every reader of these formats refuses a non-finite number. */
void st_bw_f32(st_bw *w, float v)
{
    if (!isfinite(v)) w->refused_value = 1;
    uint32_t u;
    memcpy(&u, &v, 4);
    bw_le(w, u, 4);
}

void st_bw_f64(st_bw *w, double v)
{
    if (!isfinite(v)) w->refused_value = 1;
    uint64_t u;
    memcpy(&u, &v, 8);
    bw_le(w, u, 8);
}

/* ---- reader -------------------------------------------------------------------- */

void st_br_init(st_br *r, const char *name, const void *p, size_t size, st_error *err)
{
    r->p = p;
    r->size = size;
    r->off = 0;
    r->name = name;
    r->err = err;
    r->failed = 0;
    r->trimmed = 0;
}

int st_br_fail(st_br *r, const char *fmt, ...)
{
    if (r->failed) return -1;
    r->failed = 1;
    char what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    st_fail(r->err, ST_ERR_PARSE, "%s: byte %zu: %s", r->name, r->off, what);
    return -1;
}

int st_br_need(st_br *r, uint64_t count, uint64_t elem, const char *what)
{
    if (r->failed) return -1;
    uint64_t left = r->size - r->off;
    if (elem && count > left / elem)
        return st_br_fail(r, "%s: %llu entries of %llu bytes do not fit in the %llu bytes left", what,
                          (unsigned long long)count, (unsigned long long)elem, (unsigned long long)left);
    return 0;
}

static uint64_t br_le(st_br *r, unsigned k)
{
    if (r->failed) return 0;
    if (r->size - r->off < k) { st_br_fail(r, "unexpected end of data"); return 0; }
    uint64_t v = 0;
    for (unsigned i = 0; i < k; i++) v |= (uint64_t)r->p[r->off + i] << (8 * i);
    r->off += k;
    return v;
}

uint8_t st_br_u8(st_br *r) { return (uint8_t)br_le(r, 1); }
uint32_t st_br_u32(st_br *r) { return (uint32_t)br_le(r, 4); }
uint64_t st_br_u64(st_br *r) { return br_le(r, 8); }
float st_br_f32(st_br *r) { uint32_t u = (uint32_t)br_le(r, 4); float f; memcpy(&f, &u, 4); return f; }
double st_br_f64(st_br *r) { uint64_t u = br_le(r, 8); double d; memcpy(&d, &u, 8); return d; }

void st_br_bytes(st_br *r, void *out, size_t n)
{
    if (r->failed || r->size - r->off < n) {
        if (!r->failed) st_br_fail(r, "unexpected end of data");
        memset(out, 0, n);
        return;
    }
    memcpy(out, r->p + r->off, n);
    r->off += n;
}

/* ---- value checks -------------------------------------------------------------- */

int st_value_finite_f64x3(const void *v)
{
    double d[3];
    memcpy(d, v, sizeof d);
    return isfinite(d[0]) && isfinite(d[1]) && isfinite(d[2]);
}

int st_value_sharpness_f32(const void *v)
{
    float f;
    memcpy(&f, v, sizeof f);
    return isfinite(f) && f >= 0;
}

/* ---- pools ---------------------------------------------------------------------- */

#define OWNER_NONE 0xfeu
#define OWNER_SPARE 0xfdu

static uint32_t chain_length(const st_pool *p, unsigned l)
{
    uint32_t n = 0;
    for (uint32_t id = p->freehead[l]; id != ST_NIL; id = p->next_free[id]) n++;
    return n;
}

static void pool_write(st_bw *w, const st_pool *p)
{
    st_bw_u32(w, p->end);
    st_bw_bytes(w, p->ins, p->end);
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        st_bw_u32(w, p->nblocks[l]);
        for (uint32_t b = 0; b < p->nblocks[l]; b++) st_bw_u32(w, p->blocks[l][b]);
        st_bw_u32(w, p->fill[l]);
        st_bw_u32(w, p->live[l]);
        uint32_t n = p->freehead[l] == ST_NIL ? 0 : chain_length(p, l);
        st_bw_u32(w, n);
        for (uint32_t id = p->freehead[l]; n && id != ST_NIL; id = p->next_free[id]) st_bw_u32(w, id);
    }
    st_bw_u32(w, p->nspare);
    for (uint32_t i = 0; i < p->nspare; i++) st_bw_u32(w, p->spare[i]);
    st_bw_u8(w, p->next_free != NULL);
}

static uint32_t *read_u32_array(st_br *r, uint32_t n, const char *what)
{
    if (st_br_need(r, n, 4, what)) return NULL;
    uint32_t *a = malloc((size_t)(n ? n : 1) * sizeof *a);
    if (!a) { st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory reading %s", r->name, what); r->failed = 1; return NULL; }
    for (uint32_t i = 0; i < n; i++) a[i] = st_br_u32(r);
    return a;
}

/* Reads and checks a pool of a map whose top level is `top`. */
static int pool_read(st_br *r, st_pool *p, unsigned top, const char *what)
{
    st_pool_init(p);
    uint8_t *owner = NULL, *seen = NULL;
    uint32_t **chains = calloc(ST_MAX_LEVELS, sizeof *chains);
    uint32_t nchain[ST_MAX_LEVELS] = { 0 };
    int rc = -1;
    if (!chains) { st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory", r->name); r->failed = 1; return -1; }
    uint32_t end = st_br_u32(r);
    if (r->failed) goto out;
    if (end & (ST_POOL_BLOCK - 1) || end > UINT32_MAX - 4 * ST_POOL_BLOCK) {
        st_br_fail(r, "%s: %u ids is not a whole number of blocks", what, end);
        goto out;
    }
    if (st_br_need(r, end, 1, what)) goto out;
    uint32_t nb = end >> ST_POOL_BLOCK_SHIFT;
    p->ins = malloc(end ? end : 1);
    owner = malloc(nb ? nb : 1);
    seen = calloc(end ? end : 1, 1);
    if (!p->ins || !owner || !seen) { st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory", r->name); r->failed = 1; goto out; }
    p->end = p->cap = end;
    st_br_bytes(r, p->ins, end);
    for (uint32_t i = 0; i < end; i++)
        if (p->ins[i] != ST_FREE_LEVEL && p->ins[i] > top) {
            st_br_fail(r, "%s: id %u has insertion level %u above the top level %u", what, i, p->ins[i], top);
            goto out;
        }
    memset(owner, OWNER_NONE, nb ? nb : 1);
    for (unsigned l = 0; l < ST_MAX_LEVELS && !r->failed; l++) {
        uint32_t n = st_br_u32(r);
        if (r->failed) break;
        if (n > nb) { st_br_fail(r, "%s: level %u owns %u blocks of %u", what, l, n, nb); break; }
        if (n && l > top) { st_br_fail(r, "%s: level %u above the top level owns blocks", what, l); break; }
        /* a level without blocks keeps NULL, as in a pool made in memory */
        p->blocks[l] = n ? read_u32_array(r, n, what) : NULL;
        if (n && !p->blocks[l]) break;
        p->nblocks[l] = p->capblocks[l] = n;
        for (uint32_t b = 0; b < n; b++) {
            uint32_t k = p->blocks[l][b];
            if (k >= nb || owner[k] != OWNER_NONE) { st_br_fail(r, "%s: block %u of level %u is invalid or owned twice", what, k, l); break; }
            owner[k] = (uint8_t)l;
        }
        p->fill[l] = st_br_u32(r);
        p->live[l] = st_br_u32(r);
        nchain[l] = st_br_u32(r);
        if (r->failed) break;
        if (nchain[l] > end) { st_br_fail(r, "%s: free list of level %u is longer than the pool", what, l); break; }
        chains[l] = nchain[l] ? read_u32_array(r, nchain[l], what) : NULL;
        if (nchain[l] && !chains[l]) break;
    }
    if (r->failed) goto out;
    uint32_t nspare = st_br_u32(r);
    if (r->failed) goto out;
    if (nspare > nb) { st_br_fail(r, "%s: %u spare blocks of %u", what, nspare, nb); goto out; }
    p->spare = nspare ? read_u32_array(r, nspare, what) : NULL;
    if (nspare && !p->spare) goto out;
    p->nspare = p->capspare = nspare;
    for (uint32_t i = 0; i < nspare; i++) {
        uint32_t k = p->spare[i];
        if (k >= nb || owner[k] != OWNER_NONE) { st_br_fail(r, "%s: spare block %u is invalid or owned twice", what, k); goto out; }
        owner[k] = OWNER_SPARE;
    }
    uint8_t has_next = st_br_u8(r);
    if (r->failed) goto out;
    if (has_next > 1) { st_br_fail(r, "%s: bad free-list flag %u", what, has_next); goto out; }
    /* Insertion levels agree with block owners; live counts agree. */
    uint32_t live[ST_MAX_LEVELS] = { 0 };
    for (uint32_t i = 0; i < end; i++) {
        uint8_t o = owner[i >> ST_POOL_BLOCK_SHIFT], v = p->ins[i];
        if (v == ST_FREE_LEVEL) continue;
        if (o != v) { st_br_fail(r, "%s: id %u of level %u lies in a block of %s", what, i, v, o < ST_MAX_LEVELS ? "another level" : "no level"); goto out; }
        live[v]++;
    }
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (live[l] != p->live[l]) { st_br_fail(r, "%s: level %u claims %u live ids, has %u", what, l, p->live[l], live[l]); goto out; }
        uint32_t f = p->fill[l];
        if (f != ST_NIL) {
            if (f >= end || owner[f >> ST_POOL_BLOCK_SHIFT] != l) { st_br_fail(r, "%s: fill pointer %u of level %u is outside its blocks", what, f, l); goto out; }
            for (uint32_t i = f; i < ((f >> ST_POOL_BLOCK_SHIFT) + 1) << ST_POOL_BLOCK_SHIFT; i++)
                if (p->ins[i] != ST_FREE_LEVEL) { st_br_fail(r, "%s: id %u after the fill pointer of level %u is taken", what, i, l); goto out; }
        }
        for (uint32_t k = 0; k < nchain[l]; k++) {
            uint32_t id = chains[l][k];
            if (id >= end || p->ins[id] != ST_FREE_LEVEL || owner[id >> ST_POOL_BLOCK_SHIFT] != l || seen[id] ||
                (f != ST_NIL && (id >> ST_POOL_BLOCK_SHIFT) == (f >> ST_POOL_BLOCK_SHIFT) && id >= f)) {
                st_br_fail(r, "%s: free list of level %u: id %u cannot be free there", what, l, id);
                goto out;
            }
            seen[id] = 1;
        }
        p->freehead[l] = nchain[l] ? chains[l][0] : ST_NIL;
        if (nchain[l] && !has_next) { st_br_fail(r, "%s: free lists without links", what); goto out; }
    }
    if (has_next) {
        p->next_free = calloc(end ? end : 1, sizeof *p->next_free);
        if (!p->next_free) { st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory", r->name); r->failed = 1; goto out; }
        for (unsigned l = 0; l < ST_MAX_LEVELS; l++)
            for (uint32_t k = 0; k < nchain[l]; k++)
                p->next_free[chains[l][k]] = k + 1 < nchain[l] ? chains[l][k + 1] : ST_NIL;
    }
    rc = 0;
out:
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) free(chains[l]);
    free(chains);
    free(owner);
    free(seen);
    if (rc) st_pool_free(p);
    return rc;
}

/* ---- multilevel attributes -------------------------------------------------------- */


/* Whether entry i of column l (l >= 1) can be read: an id inserted below l. */
static inline int col_readable(const st_pool *p, uint32_t i, unsigned l)
{
    return i < p->end && p->ins[i] != ST_FREE_LEVEL && p->ins[i] < l;
}

/* below[l], l = 0..ST_MAX_LEVELS: 1 + the largest id inserted at a level < l
 * (0 when none), non-decreasing in l: the entries column l can be read at. */
static void ids_below(const st_pool *p, uint32_t below[ST_MAX_LEVELS + 1])
{
    memset(below, 0, (ST_MAX_LEVELS + 1) * sizeof *below);
    for (uint32_t i = 0; i < p->end; i++)
        if (p->ins[i] != ST_FREE_LEVEL && i + 1 > below[p->ins[i] + 1]) below[p->ins[i] + 1] = i + 1;
    for (unsigned l = 1; l <= ST_MAX_LEVELS; l++)
        if (below[l - 1] > below[l]) below[l] = below[l - 1];
}

/* Live ids of p (all levels), and ids readable in the column of each level
 * l (inserted below l): how many values format 3 stores. */
static uint32_t live_ids(const st_pool *p)
{
    uint32_t n = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) n += p->live[l];
    return n;
}

static uint32_t ids_readable_at(const st_pool *p, unsigned l)
{
    uint32_t n = 0;
    for (unsigned k = 0; k < l && k < ST_MAX_LEVELS; k++) n += p->live[k];
    return n;
}

/* Which ids an attribute is written for, and where their values are read:
 * id j of q (the pool written) is id old_of[j] of p (the map's pool), the
 * identity when old_of is NULL (q == p).  Under a renumbering (renumber_internal.h)
 * q is the renumbered pool. */
typedef struct ids_view { const st_pool *p, *q; const uint32_t *old_of; } ids_view;

static ids_view ids_same(const st_pool *p)
{
    ids_view x = { p, p, NULL };
    return x;
}

static ids_view ids_renumbered(const st_pool *p, const st_pool_renumber *r)
{
    ids_view x = { p, &r->pool, r->old_of };
    return x;
}

static inline uint32_t old_id(const ids_view *x, uint32_t j) { return x->old_of ? x->old_of[j] : j; }

/* A value as written: elem bytes, or (relations under a renumbering, elem
 * 4) the id it holds translated by new_of, which is defined on every id a
 * readable relation value can hold (live ids). */
static void put_value(st_bw *w, const unsigned char *v, uint32_t elem, const uint32_t *new_of)
{
    if (!new_of) { st_bw_bytes(w, v, elem); return; }
    uint32_t u;
    memcpy(&u, v, 4);
    st_bw_u32(w, new_of[u]);
}

/* Value of old id i at column level l (dense or sparse form). */
static inline const unsigned char *col_value(const st_mla *a, const st_pool *p, uint32_t i, unsigned l)
{
    return a->sp ? st_mla_sparse_at(a, p->ins, i, l) : a->col[l] + (size_t)i * a->elem;
}

/* Format 3: values of live ids only (base) and of ids inserted below the
 * column's level (columns), in id order; the reader knows which from the
 * pool, and everything else is zero.  A column is written whole (mode 0)
 * or, when that is smaller, as the list of the ids whose value differs
 * from their value one level down (mode 1: u32 count, then u32 id and the
 * value each): a progressive hierarchy changes few positions and relations
 * per level, a subdivision level nearly all.  Ids, order and readability
 * are those of x->q; new_of (NULL: none) translates relation values. */
static void mla_write(st_bw *w, const st_mla *a, const ids_view *x, const uint32_t *new_of, st_mla_value_check check)
{
    const st_pool *p = x->p, *q = x->q;
    st_bw_u32(w, a->elem);
    for (uint32_t j = 0; j < q->end; j++) {
        if (q->ins[j] == ST_FREE_LEVEL) continue;
        const unsigned char *v = a->base + (size_t)old_id(x, j) * a->elem;
        if (check && !check(v)) w->refused_value = 1;
        put_value(w, v, a->elem, new_of);
    }
    /* The sparse form (map.h) is written as the dense columns it stands for. */
    const st_mla_sparse *sp = a->sp;
    uint32_t below[ST_MAX_LEVELS + 1];
    ids_below(q, below);
    uint32_t mask = 0;
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++)
        if (sp ? sp->has_col[l] : a->col[l] != NULL) mask |= 1u << l;
    st_bw_u32(w, mask);
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++) {
        if (!(mask >> l & 1u)) continue;
        uint64_t readable = 0, changed = 0;
        for (uint32_t j = 0; j < below[l]; j++) {
            if (!col_readable(q, j, l)) continue;
            uint32_t i = old_id(x, j);
            const unsigned char *v = col_value(a, p, i, l);
            if (check && !check(v)) w->refused_value = 1;
            readable++;
            /* (old values compared: new_of is one-to-one on live ids) */
            changed += memcmp(v, st_mla_at_any(a, p->ins, i, l - 1), a->elem) != 0;
        }
        int delta = changed * (4 + (uint64_t)a->elem) < readable * a->elem;
        st_bw_u8(w, (uint8_t)delta);
        if (delta) st_bw_u32(w, (uint32_t)changed);
        for (uint32_t j = 0; j < below[l]; j++) {
            if (!col_readable(q, j, l)) continue;
            uint32_t i = old_id(x, j);
            const unsigned char *v = col_value(a, p, i, l);
            if (delta) {
                if (!memcmp(v, st_mla_at_any(a, p->ins, i, l - 1), a->elem)) continue;
                st_bw_u32(w, j);
            }
            put_value(w, v, a->elem, new_of);
        }
    }
}

void st_mla_write(st_bw *w, const st_mla *a, const st_pool *p, st_mla_value_check check)
{
    ids_view x = ids_same(p);
    mla_write(w, a, &x, NULL, check);
}

void st_mla_write_renumbered(st_bw *w, const st_mla *a, const st_pool *p, const st_pool_renumber *r,
                             st_mla_value_check check)
{
    ids_view x = ids_renumbered(p, r);
    mla_write(w, a, &x, NULL, check);
}

/* Format 3, a column written as changes (mode 1): every id inserted below l
 * takes its value one level down (the last column below l that exists, else
 * its base value), then the listed ids, strictly increasing and each
 * readable at l, take theirs. */
static int read_column_changes(st_br *r, st_mla *a, const st_pool *p, unsigned l, uint32_t below, uint32_t readable,
                               const char *what)
{
    uint32_t elem = a->elem, n = st_br_u32(r);
    if (r->failed) return -1;
    if (n > readable) return st_br_fail(r, "%s: column %u lists %u changes of %u values", what, l, n, readable);
    if (st_br_need(r, n, 4 + (uint64_t)elem, what)) return -1;
    unsigned prev = 0;
    for (unsigned k = l - 1; k >= 1 && !prev; k--)
        if (a->col[k]) prev = k;
    for (uint32_t i = 0; i < below; i++)
        if (col_readable(p, i, l))
            memcpy(a->col[l] + (size_t)i * elem, (prev > p->ins[i] ? a->col[prev] : a->base) + (size_t)i * elem, elem);
    uint64_t last = UINT64_MAX;
    for (uint32_t k = 0; k < n; k++) {
        uint32_t id = st_br_u32(r);
        if (r->failed) return -1;
        if (id >= below || !col_readable(p, id, l) || (last != UINT64_MAX && id <= last))
            return st_br_fail(r, "%s: column %u: id %u cannot change there", what, l, id);
        last = id;
        st_br_bytes(r, a->col[l] + (size_t)id * elem, elem);
    }
    return r->failed ? -1 : 0;
}

int st_mla_read(st_br *r, st_mla *a, const st_pool *p, unsigned top, uint32_t elem,
                st_mla_value_check check, const char *what)
{
    st_mla_init(a, elem);
    uint32_t e = st_br_u32(r);
    if (r->failed) return -1;
    if (e != elem) return st_br_fail(r, "%s: element size %u, expected %u", what, e, elem);
    /* Format 3 stores live ids only; older formats every id. */
    if (st_br_need(r, r->trimmed ? live_ids(p) : p->end, elem, what)) return -1;
    a->base = calloc(p->end ? p->end : 1, elem);
    if (!a->base) { st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory", r->name); r->failed = 1; return -1; }
    if (!r->trimmed) st_br_bytes(r, a->base, (size_t)p->end * elem);
    else
        for (uint32_t i = 0; i < p->end; i++)
            if (p->ins[i] != ST_FREE_LEVEL) st_br_bytes(r, a->base + (size_t)i * elem, elem);
    for (uint32_t i = 0; check && i < p->end; i++)
        if (p->ins[i] != ST_FREE_LEVEL && !check(a->base + (size_t)i * elem)) {
            st_br_fail(r, "%s: bad value for id %u", what, i);
            goto fail;
        }
    uint32_t below[ST_MAX_LEVELS + 1];
    ids_below(p, below);
    uint32_t mask = st_br_u32(r);
    if (r->failed) goto fail;
    if (mask & 1u || mask >> ST_MAX_LEVELS || (top + 1 < ST_MAX_LEVELS && mask >> (top + 1))) {
        st_br_fail(r, "%s: columns at impossible levels (mask %#x, top %u)", what, mask, top);
        goto fail;
    }
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++) {
        if (!(mask >> l & 1u)) continue;
        /* Format 3: the values of the ids inserted below l, held with the
         * capacity the pool's blocks cover, as a column made in memory
         * (mla.c, materialize); older formats: a stored capacity n >=
         * below[l] (1 + largest id inserted below l), then n entries. */
        uint32_t n, cap;
        if (r->trimmed) {
            n = ids_readable_at(p, l);
            cap = st_pool_cover(p, l);
            if (cap < below[l]) cap = below[l];
        } else {
            n = cap = st_br_u32(r);
            if (r->failed) goto fail;
            if (n < below[l]) { st_br_fail(r, "%s: column %u holds %u entries, needs %u", what, l, n, below[l]); goto fail; }
        }
        uint8_t mode = 0;
        if (r->trimmed) {
            mode = st_br_u8(r);
            if (r->failed) goto fail;
            if (mode > 1) { st_br_fail(r, "%s: column %u: unknown mode %u", what, l, mode); goto fail; }
        }
        if (!mode && st_br_need(r, n, elem, what)) goto fail;
        a->col[l] = calloc(cap ? cap : 1, elem);
        if (!a->col[l]) { st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory", r->name); r->failed = 1; goto fail; }
        a->colcap[l] = cap;
        if (!r->trimmed) st_br_bytes(r, a->col[l], (size_t)n * elem);
        else if (mode) {
            if (read_column_changes(r, a, p, l, below[l], n, what)) goto fail;
        } else
            for (uint32_t i = 0; i < below[l]; i++)
                if (col_readable(p, i, l)) st_br_bytes(r, a->col[l] + (size_t)i * elem, elem);
        /* every readable entry (format 3: below[l] ids; older: n >= below[l]) */
        for (uint32_t i = 0; check && i < (r->trimmed ? below[l] : n); i++)
            if (col_readable(p, i, l) && !check(a->col[l] + (size_t)i * elem)) {
                st_br_fail(r, "%s: bad value for id %u at level %u", what, i, l);
                goto fail;
            }
    }
    /* eff and maxcol follow from which columns exist (mla.c, refresh_eff). */
    unsigned last = 0;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        if (a->col[l]) last = l;
        a->eff[l] = (uint8_t)last;
    }
    a->maxcol = (uint8_t)last;
    if (r->failed) goto fail;
    return 0;
fail:
    st_mla_free(a);
    return -1;
}

/* ---- map ---------------------------------------------------------------------------- */

/* The map with its darts and vertices numbered as dq and vq say (ids_view)
 * and its relations' values translated by dnew / vnew (NULL: as they are). */
static void map_write(st_bw *w, const st_map *m, const ids_view *dq, const ids_view *vq, const uint32_t *dnew,
                      const uint32_t *vnew)
{
    st_bw_u32(w, m->top);
    st_bw_u8(w, m->face_embedded);
    pool_write(w, dq->q);
    pool_write(w, vq->q);
    mla_write(w, &m->beta0, dq, dnew, NULL);
    mla_write(w, &m->beta1, dq, dnew, NULL);
    mla_write(w, &m->vert, dq, vnew, NULL);
    for (uint32_t j = 0; j < dq->q->end; j++)
        if (dq->q->ins[j] != ST_FREE_LEVEL) st_bw_u8(w, m->flags[old_id(dq, j)]);
    mla_write(w, &m->pos, vq, NULL, st_value_finite_f64x3);
}

void st_map_write(st_bw *w, const st_map *m)
{
    ids_view d = ids_same(&m->darts), v = ids_same(&m->verts);
    map_write(w, m, &d, &v, NULL, NULL);
}

void st_map_write_renumbered(st_bw *w, const st_map *m, const st_map_renumber *rn)
{
    ids_view d = ids_renumbered(&m->darts, &rn->darts), v = ids_renumbered(&m->verts, &rn->verts);
    map_write(w, m, &d, &v, rn->darts.new_of, rn->verts.new_of);
}

/* The pool as level 0 left it, when every later level took fresh blocks
 * from `end` on (st_hier_regenerable): level 0's own records, no other
 * level, no spare block.  A view: it shares p's arrays.  -1 when p is not
 * in that state (a block of level 0 at or past end, or one below end
 * owned by another level). */
static int pool_level0_view(const st_pool *p, uint32_t end, st_pool *v)
{
    if (end > p->end || (end & (ST_POOL_BLOCK - 1)) || p->nspare) return -1;
    *v = *p;
    v->end = end;
    for (uint32_t b = 0; b < p->nblocks[0]; b++)
        if (p->blocks[0][b] >= end >> ST_POOL_BLOCK_SHIFT) return -1;
    for (unsigned l = 1; l < ST_MAX_LEVELS; l++) {
        for (uint32_t b = 0; b < p->nblocks[l]; b++)
            if (p->blocks[l][b] < end >> ST_POOL_BLOCK_SHIFT) return -1;
        v->blocks[l] = NULL;
        v->nblocks[l] = v->capblocks[l] = 0;
        v->fill[l] = ST_NIL;
        v->freehead[l] = ST_NIL;
        v->live[l] = 0;
    }
    return 0;
}

/* An attribute's level-0 values: its base values, no column. */
st_mla st_mla_level0_view(const st_mla *a)
{
    st_mla v = *a;
    for (unsigned l = 0; l < ST_MAX_LEVELS; l++) {
        v.col[l] = NULL;
        v.colcap[l] = 0;
        v.eff[l] = 0;
    }
    v.maxcol = 0;
    v.sp = NULL;
    return v;
}

int st_map_level0_view(const st_map *m, const uint32_t end[2], st_map *v)
{
    if (m->beta0.sp || m->beta1.sp || m->vert.sp || m->pos.sp) return -1;
    *v = *m;
    v->top = 0;
    if (pool_level0_view(&m->darts, end[0], &v->darts) || pool_level0_view(&m->verts, end[1], &v->verts)) return -1;
    v->beta0 = st_mla_level0_view(&m->beta0);
    v->beta1 = st_mla_level0_view(&m->beta1);
    v->vert = st_mla_level0_view(&m->vert);
    v->pos = st_mla_level0_view(&m->pos);
    return 0;
}


/* Every relation of every level stays inside the level (what the validator
 * assumes before it follows relations). */
static int check_ranges(st_br *r, const st_map *m)
{
    for (unsigned l = 0; l <= m->top; l++) {
        st_dart_iter it;
        for (uint32_t d = st_dart_first(m, l, &it); d != ST_NIL; d = st_dart_next(m, l, &it)) {
            uint32_t e = st_beta0(m, d, l), f = st_beta1(m, d, l), v = st_vert(m, d, l);
            if (!st_dart_in_level(m, e, l) || !st_dart_in_level(m, f, l))
                return st_br_fail(r, "map: level %u, dart %u: relation leaves the level", l, d);
            if (v >= m->verts.end || m->verts.ins[v] == ST_FREE_LEVEL || m->verts.ins[v] > l)
                return st_br_fail(r, "map: level %u, dart %u: vertex %u does not exist at this level", l, d, v);
        }
    }
    return 0;
}

int st_map_read(st_br *r, st_map *m)
{
    st_map_init(m);
    uint32_t top = st_br_u32(r);
    uint8_t fe = st_br_u8(r);
    if (r->failed) return -1;
    if (top >= ST_MAX_LEVELS) return st_br_fail(r, "map: top level %u (at most %d)", top, ST_MAX_LEVELS - 1);
    if (fe > 1) return st_br_fail(r, "map: bad face-embedding flag %u", fe);
    m->top = top;
    m->face_embedded = fe;
    if (pool_read(r, &m->darts, top, "dart pool")) goto fail;
    if (pool_read(r, &m->verts, top, "vertex pool")) goto fail;
    if (st_mla_read(r, &m->beta0, &m->darts, top, 4, NULL, "beta0") ||
        st_mla_read(r, &m->beta1, &m->darts, top, 4, NULL, "beta1") ||
        st_mla_read(r, &m->vert, &m->darts, top, 4, NULL, "vertex relation"))
        goto fail;
    if (st_br_need(r, r->trimmed ? live_ids(&m->darts) : m->darts.end, 1, "dart flags")) goto fail;
    m->flags = calloc(m->darts.end ? m->darts.end : 1, 1);
    if (!m->flags) { st_fail(r->err, ST_ERR_MEMORY, "%s: out of memory", r->name); r->failed = 1; goto fail; }
    if (!r->trimmed) st_br_bytes(r, m->flags, m->darts.end);
    else
        for (uint32_t i = 0; i < m->darts.end; i++)
            if (m->darts.ins[i] != ST_FREE_LEVEL) m->flags[i] = st_br_u8(r);
    for (uint32_t i = 0; i < m->darts.end; i++)
        if ((m->flags[i] & ~(uint8_t)(ST_DART_BOUNDARY | ST_DART_HOLE)) ||
            m->flags[i] == (uint8_t)(ST_DART_BOUNDARY | ST_DART_HOLE)) {
            st_br_fail(r, "map: dart %u has unknown flags %#x", i, m->flags[i]);
            goto fail;
        }
    if (st_mla_read(r, &m->pos, &m->verts, top, 3 * sizeof(double), st_value_finite_f64x3, "positions")) goto fail;
    if (check_ranges(r, m)) goto fail;
    return 0;
fail:
    st_map_free(m);
    return -1;
}
