#include "testlib.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

int tl_passed, tl_failed, tl_skipped;

void tl_skip(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    printf("skipped: ");
    vprintf(fmt, ap);
    putchar('\n');
    va_end(ap);
    tl_skipped++;
}

#ifndef STRATA_SHARED_DATA
#define STRATA_SHARED_DATA "../shared/data/meshes"
#endif

int tl_load_shared(const char *subdir, const char *name, st_mesh *m)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s/%s", STRATA_SHARED_DATA, subdir, name);
    st_error err;
    st_mesh_init(m);
    if (st_mesh_load(path, m, &err)) {
        tl_skip("%s not loaded (%s)", path, err.msg);
        return -1;
    }
    return 0;
}

int tl_report(const char *file)
{
    if (tl_skipped) printf("%s: %d passed, %d failed, %d skipped\n", file, tl_passed, tl_failed, tl_skipped);
    else printf("%s: %d passed, %d failed\n", file, tl_passed, tl_failed);
    fflush(stdout);
    if (tl_failed) return 1;
    if (!tl_passed && !tl_skipped) {
        fprintf(stderr, "%s: no check ran: a test that checks nothing fails\n", file);
        return 1;
    }
    return tl_skipped ? TL_SKIP_CODE : 0;
}

char *tl_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) { free(buf); buf = NULL; }
    fclose(f);
    if (buf) { buf[n] = 0; if (size) *size = (size_t)n; }
    return buf;
}

int tl_write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t w = fwrite(data, 1, size, f);
    return (fclose(f) == 0 && w == size) ? 0 : -1;
}

#include <math.h>
#include <string.h>

void tl_mesh_make(st_mesh *m, const double *pos, uint32_t nv, const uint32_t *off, const uint32_t *idx, uint32_t nf)
{
    st_mesh_init(m);
    m->nverts = nv;
    m->nfaces = nf;
    m->pos = malloc(3 * (size_t)nv * sizeof *m->pos);
    m->face_off = malloc(((size_t)nf + 1) * sizeof *m->face_off);
    m->face_idx = malloc((size_t)off[nf] * sizeof *m->face_idx);
    memcpy(m->pos, pos, 3 * (size_t)nv * sizeof *pos);
    memcpy(m->face_off, off, ((size_t)nf + 1) * sizeof *off);
    memcpy(m->face_idx, idx, (size_t)off[nf] * sizeof *idx);
}

void tl_mesh_cube(st_mesh *m)
{
    static const double p[] = { 0,0,0, 1,0,0, 1,1,0, 0,1,0, 0,0,1, 1,0,1, 1,1,1, 0,1,1 };
    static const uint32_t off[] = { 0, 4, 8, 12, 16, 20, 24 };
    static const uint32_t idx[] = { 0,3,2,1, 4,5,6,7, 0,1,5,4, 1,2,6,5, 2,3,7,6, 3,0,4,7 };
    tl_mesh_make(m, p, 8, off, idx, 6);
}

void tl_mesh_tetra(st_mesh *m)
{
    static const double p[] = { 1,1,1, -1,-1,1, -1,1,-1, 1,-1,-1 };
    static const uint32_t off[] = { 0, 3, 6, 9, 12 };
    static const uint32_t idx[] = { 0,1,3, 0,2,1, 0,3,2, 1,2,3 };
    tl_mesh_make(m, p, 4, off, idx, 4);
}

void tl_mesh_octa(st_mesh *m)
{
    static const double p[] = { 1,0,0, -1,0,0, 0,1,0, 0,-1,0, 0,0,1, 0,0,-1 };
    static const uint32_t off[] = { 0, 3, 6, 9, 12, 15, 18, 21, 24 };
    static const uint32_t idx[] = { 0,2,4, 2,1,4, 1,3,4, 3,0,4, 2,0,5, 1,2,5, 3,1,5, 0,3,5 };
    tl_mesh_make(m, p, 6, off, idx, 8);
}

void tl_mesh_icosa(st_mesh *m)
{
    const double t = (1 + sqrt(5.0)) / 2;
    const double p[] = { -1,t,0, 1,t,0, -1,-t,0, 1,-t,0, 0,-1,t, 0,1,t, 0,-1,-t, 0,1,-t, t,0,-1, t,0,1, -t,0,-1, -t,0,1 };
    static const uint32_t idx[] = { 0,11,5, 0,5,1, 0,1,7, 0,7,10, 0,10,11, 1,5,9, 5,11,4, 11,10,2, 10,7,6, 7,1,8,
                                    3,9,4, 3,4,2, 3,2,6, 3,6,8, 3,8,9, 4,9,5, 2,4,11, 6,2,10, 8,6,7, 9,8,1 };
    uint32_t off[21];
    for (int i = 0; i <= 20; i++) off[i] = 3 * i;
    tl_mesh_make(m, p, 12, off, idx, 20);
}

void tl_mesh_grid(st_mesh *m, unsigned n)
{
    uint32_t nv = (n + 1) * (n + 1), nf = n * n;
    double *p = malloc(3 * (size_t)nv * sizeof *p);
    uint32_t *off = malloc(((size_t)nf + 1) * sizeof *off), *idx = malloc(4 * (size_t)nf * sizeof *idx);
    for (unsigned j = 0; j <= n; j++)
        for (unsigned i = 0; i <= n; i++) {
            double *q = p + 3 * (j * (n + 1) + i);
            q[0] = i; q[1] = j; q[2] = 0.1 * ((i * 7 + j * 3) % 5);
        }
    for (unsigned j = 0, f = 0; j < n; j++)
        for (unsigned i = 0; i < n; i++, f++) {
            uint32_t a = j * (n + 1) + i;
            off[f] = 4 * f;
            idx[4 * f] = a; idx[4 * f + 1] = a + 1; idx[4 * f + 2] = a + n + 2; idx[4 * f + 3] = a + n + 1;
        }
    off[nf] = 4 * nf;
    tl_mesh_make(m, p, nv, off, idx, nf);
    free(p); free(off); free(idx);
}

void tl_mesh_torus(st_mesh *m, unsigned nu, unsigned nv)
{
    uint32_t nvert = nu * nv, nf = nu * nv;
    double *p = malloc(3 * (size_t)nvert * sizeof *p);
    uint32_t *off = malloc(((size_t)nf + 1) * sizeof *off), *idx = malloc(4 * (size_t)nf * sizeof *idx);
    for (unsigned j = 0; j < nv; j++)
        for (unsigned i = 0; i < nu; i++) {
            double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv, r = 2 + 0.7 * cos(v);
            double *q = p + 3 * (j * nu + i);
            q[0] = r * cos(u); q[1] = r * sin(u); q[2] = 0.7 * sin(v);
        }
    for (unsigned j = 0, f = 0; j < nv; j++)
        for (unsigned i = 0; i < nu; i++, f++) {
            uint32_t i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            off[f] = 4 * f;
            idx[4 * f] = j * nu + i; idx[4 * f + 1] = j * nu + i1;
            idx[4 * f + 2] = j1 * nu + i1; idx[4 * f + 3] = j1 * nu + i;
        }
    off[nf] = 4 * nf;
    tl_mesh_make(m, p, nvert, off, idx, nf);
    free(p); free(off); free(idx);
}

uint32_t tl_rand(uint64_t *s)
{
    uint64_t x = *s;
    x ^= x << 13; x ^= x >> 7; x ^= x << 17;
    *s = x;
    return (uint32_t)(x >> 32);
}

/* ---- multiresolution checks shared by the scheme tests ---- */
#include "core/multires/hier.h"
#include "core/multires/hier_internal.h"
#include "core/io/map_io_internal.h"
#include "core/progressive/scheme_registry.h"

void tl_init_hier(st_hier *h, void (*make)(st_mesh *), st_scheme_id id, unsigned levels)
{
    st_mesh s;
    st_error err;
    make(&s);
    const st_scheme *sc = st_scheme_get(id);
    CHECK(sc != NULL);
    int rc = st_hier_init(h, &s, sc, NULL, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    st_mesh_free(&s);
    rc = st_hier_subdivide_to(h, levels, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    rc = st_map_validate(&h->map, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
}

void tl_snap_pos(const st_hier *h, tl_posnap *s)
{
    s->levels = h->map.top + 1;
    s->n = h->map.verts.end;
    s->p = calloc((size_t)s->levels * s->n * 3 + 1, sizeof *s->p);
    for (unsigned l = 0; l < s->levels; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it))
            memcpy(s->p + ((size_t)l * s->n + v) * 3, st_pos(&h->map, v, l), 3 * sizeof(double));
    }
}

double tl_snap_maxdiff(const tl_posnap *a, const tl_posnap *b)
{
    double m = 0;
    for (size_t i = 0; i < (size_t)a->levels * a->n * 3; i++) m = fmax(m, fabs(a->p[i] - b->p[i]));
    return m;
}

/* Random details at every level >= 1, then a full synthesis. */
void tl_random_details(st_hier *h, uint64_t *rng, double scale)
{
    for (unsigned l = 1; l <= h->map.top; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h->map, l, &it); v != ST_NIL; v = st_vertex_next(&h->map, l, &it)) {
            double d[3];
            for (int i = 0; i < 3; i++) d[i] = scale * ((double)(tl_rand(rng) % 2001) / 1000.0 - 1.0);
            st_hier_set_detail(h, l, v, d);
        }
    }
    st_hier_synthesize(h, 0);
}

/* A dart of some vertex of level l, chosen at random. */
uint32_t tl_random_dart_at(const st_map *m, unsigned l, uint64_t *rng)
{
    for (;;) {
        uint32_t d = tl_rand(rng) % m->darts.end;
        if (st_dart_in_level(m, d, l)) return d;
    }
}

/* Local re-synthesis after moving vertices at level l equals a full
 * synthesis from level l, and recomputes far fewer vertices: with details
 * at every level, and without (the levels above l then have none, and a
 * scheme's predict_around takes them). */
static void check_local_equals_full(st_scheme_id id, void (*make)(st_mesh *), unsigned levels, int details, int counted);

void tl_check_local_equals_full(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    check_local_equals_full(id, make, levels, 1, 1);
    check_local_equals_full(id, make, levels, 0, 1);
}

void tl_check_local_equals_full_small(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    check_local_equals_full(id, make, levels, 1, 0);
    check_local_equals_full(id, make, levels, 0, 0);
}

static void check_local_equals_full(st_scheme_id id, void (*make)(st_mesh *), unsigned levels, int details, int counted)
{
    st_hier h;
    uint64_t rng = 12345 + id;
    tl_init_hier(&h, make, id, levels);
    if (details) tl_random_details(&h, &rng, 0.01);
    for (unsigned l = 0; l < levels; l++) {
        uint32_t darts[3];
        double pos[3][3];
        for (int k = 0; k < 3; k++) {
            darts[k] = tl_random_dart_at(&h.map, l, &rng);
            const double *p = st_dart_pos(&h.map, darts[k], l);
            for (int i = 0; i < 3; i++) pos[k][i] = p[i] + 0.05 * (k + 1) * (i + 1);
        }
        /* Two darts of one vertex would be one vertex moved twice: keep distinct vertices. */
        uint32_t n = 1;
        for (int k = 1; k < 3; k++) {
            int dup = 0;
            for (uint32_t j = 0; j < n; j++) dup |= st_vert(&h.map, darts[j], l) == st_vert(&h.map, darts[k], l);
            if (!dup) { darts[n] = darts[k]; memcpy(pos[n], pos[k], sizeof pos[k]); n++; }
        }
        uint64_t count = st_hier_move(&h, l, darts, (const double (*)[3])pos, n);
        tl_posnap local, full;
        tl_snap_pos(&h, &local);
        st_hier_synthesize(&h, l);
        tl_snap_pos(&h, &full);
        double diff = tl_snap_maxdiff(&local, &full);
        /* Without details, Catmull-Clark's local paths share the full
         * synthesis's arithmetic (catmark_local.c): the same bits. */
        double tol = !details && id == ST_SCHEME_CATMARK ? 0 : 1e-12;
        CHECKF(diff <= tol, "%s%s: edit at level %u: local and full synthesis differ by %g", h.scheme->name,
               details ? "" : " without details", l, diff);
        for (int k = 0; k < (int)n; k++) {
            const double *p = st_dart_pos(&h.map, darts[k], l);
            CHECK(fabs(p[0] - pos[k][0]) < 1e-12 && fabs(p[2] - pos[k][2]) < 1e-12);
        }
        uint64_t total = 0;
        for (unsigned L = l + 1; L <= h.map.top; L++) {
            st_level_stats s;
            st_level_stats_compute(&h.map, L, &s);
            total += s.vertices;
        }
        if (counted && l + 2 <= levels) CHECKF(count < total, "%s: local update recomputed %llu of %llu", h.scheme->name, (unsigned long long)count, (unsigned long long)total);
        free(local.p);
        free(full.p);
    }
    st_hier_free(&h);
}

/* A rigid motion of level 0 moves every finer level rigidly, details
 * included (they live in local frames of the coarser surface). */
void tl_check_rigid_motion(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    st_hier h;
    uint64_t rng = 777 + id;
    tl_init_hier(&h, make, id, levels);
    tl_random_details(&h, &rng, 0.02);
    tl_posnap before;
    tl_snap_pos(&h, &before);
    double c = cos(0.7), s = sin(0.7), t[3] = { 0.3, -1.2, 2.5 };
    st_dart_list darts = { 0 };
    int vb = st_marker_reserve(&h.map);
    st_dart_iter it;
    for (uint32_t d = st_dart_first(&h.map, 0, &it); d != ST_NIL; d = st_dart_next(&h.map, 0, &it))
        if (!st_marked(&h.map, vb, d)) {
            /* Surface vertices: vertex orbits, or faces of a dual-encoded map. */
            if (h.map.face_embedded) st_mark_face(&h.map, vb, d, 0);
            else st_mark_vertex(&h.map, vb, d, 0);
            st_dart_list_push(&darts, d);
        }
    st_marker_release(&h.map, vb, 0);
    double (*pos)[3] = malloc(darts.n * sizeof *pos);
    for (uint32_t i = 0; i < darts.n; i++) {
        const double *p = st_dart_pos(&h.map, darts.d[i], 0);
        pos[i][0] = c * p[0] - s * p[1] + t[0];
        pos[i][1] = s * p[0] + c * p[1] + t[1];
        pos[i][2] = p[2] + t[2];
    }
    st_hier_move(&h, 0, darts.d, (const double (*)[3])pos, darts.n);
    double worst = 0;
    for (unsigned l = 0; l <= h.map.top; l++)
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            const double *p = before.p + ((size_t)l * before.n + v) * 3, *q = st_pos(&h.map, v, l);
            double r[3] = { c * p[0] - s * p[1] + t[0], s * p[0] + c * p[1] + t[1], p[2] + t[2] };
            for (int i = 0; i < 3; i++) worst = fmax(worst, fabs(r[i] - q[i]));
        }
    CHECKF(worst < 1e-12, "%s: rigid motion error %g", h.scheme->name, worst);
    free(pos);
    free(before.p);
    st_dart_list_free(&darts);
    st_hier_free(&h);
}

/* Moving a vertex at level i keeps the details of every finer level. */
void tl_check_details_kept(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    st_hier h;
    uint64_t rng = 99 + id;
    tl_init_hier(&h, make, id, levels);
    tl_random_details(&h, &rng, 0.01);
    double *saved = malloc((size_t)h.detail_cap[levels] * 3 * sizeof *saved);
    memcpy(saved, h.detail[levels], (size_t)h.detail_cap[levels] * 3 * sizeof *saved);
    uint32_t d = tl_random_dart_at(&h.map, 1, &rng);
    double p[1][3];
    memcpy(p[0], st_dart_pos(&h.map, d, 1), sizeof p[0]);
    p[0][2] += 0.3;
    st_hier_move(&h, 1, &d, (const double (*)[3])p, 1);
    CHECK(memcmp(saved, h.detail[levels], (size_t)h.detail_cap[levels] * 3 * sizeof *saved) == 0);
    free(saved);
    st_hier_free(&h);
}


/* Analysis (least squares) then synthesis gives back the finest level with
 * random details; an exact subdivision analyses to zero details. */
void tl_check_analysis(st_scheme_id id, void (*make)(st_mesh *), unsigned levels)
{
    st_hier h;
    uint64_t rng = 31337 + id;
    tl_init_hier(&h, make, id, levels);
    double worst = 0;
    for (unsigned l = 1; l <= levels; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            const double *d = st_hier_detail(&h, l, v);
            worst = fmax(worst, fabs(d[0]) + fabs(d[1]) + fabs(d[2]));
        }
    }
    st_hier_analyze(&h, 0);
    for (unsigned l = 1; l <= levels; l++) {
        st_dart_iter it;
        for (uint32_t v = st_vertex_first(&h.map, l, &it); v != ST_NIL; v = st_vertex_next(&h.map, l, &it)) {
            const double *d = st_hier_detail(&h, l, v);
            worst = fmax(worst, fabs(d[0]) + fabs(d[1]) + fabs(d[2]));
        }
    }
    CHECKF(worst < 1e-9, "%s: exact subdivision analyses to details of %g", h.scheme->name, worst);
    tl_random_details(&h, &rng, 0.01);
    uint32_t n = h.map.verts.end;
    double *fine = malloc(3 * (size_t)n * sizeof *fine);
    st_dart_iter it;
    for (uint32_t v = st_vertex_first(&h.map, levels, &it); v != ST_NIL; v = st_vertex_next(&h.map, levels, &it))
        memcpy(fine + 3 * (size_t)v, st_pos(&h.map, v, levels), 3 * sizeof *fine);
    st_hier_analyze(&h, 0);
    st_hier_synthesize(&h, 0);
    worst = 0;
    for (uint32_t v = st_vertex_first(&h.map, levels, &it); v != ST_NIL; v = st_vertex_next(&h.map, levels, &it))
        for (int i = 0; i < 3; i++) worst = fmax(worst, fabs(st_pos(&h.map, v, levels)[i] - fine[3 * (size_t)v + i]));
    CHECKF(worst < 1e-9, "%s: analysis + synthesis round trip error %g", h.scheme->name, worst);
    free(fine);
    st_hier_free(&h);
}

void *tl_session_bytes(const st_session_ref *r, size_t *n)
{
    void *data = NULL;
    st_error err;
    int rc = st_session_write_mem(r, &data, n, &err);
    CHECKF(rc == ST_OK, "%s", err.msg);
    return data;
}

int tl_session_roundtrip(const st_session_ref *r, const char *name, st_session *s)
{
    void *b1 = NULL, *b2 = NULL;
    size_t n1 = 0, n2 = 0;
    st_error err;
    st_session_init(s);
    int rc = st_session_write_mem(r, &b1, &n1, &err);
    CHECKF(rc == 0, "%s: write: %s", name, err.msg);
    if (!rc) {
        rc = st_session_parse(name, b1, n1, s, &err);
        CHECKF(rc == 0, "%s: %s", name, err.msg);
    }
    if (!rc) {
        st_session_ref r2 = st_session_ref_of(s);
        rc = st_session_write_mem(&r2, &b2, &n2, &err);
        CHECKF(rc == 0, "%s: write the loaded session: %s", name, err.msg);
        if (!rc) {
            int same = n1 == n2 && memcmp(b1, b2, n1) == 0;
            CHECKF(same, "%s: save -> load -> save differs (%zu vs %zu bytes)", name, n1, n2);
            if (!same) rc = -1;
        }
        if (rc) st_session_free(s);
    }
    free(b1);
    free(b2);
    return rc ? -1 : 0;
}

void tl_session_file_roundtrip(const st_session_ref *r, const char *path, const char *path2)
{
    st_error err;
    int rc = st_session_save_ref(path, r, &err);
    CHECKF(rc == 0, "%s: %s", path, err.msg);
    st_session s;
    if (!rc) {
        rc = st_session_load(path, &s, &err);
        CHECKF(rc == 0, "%s: %s", path, err.msg);
    }
    if (rc) return;
    st_session_ref r2 = st_session_ref_of(&s);
    CHECKF(st_session_save_ref(path2, &r2, &err) == 0, "%s: %s", path2, err.msg);
    size_t na = 0, nb = 0;
    char *fa = tl_read_file(path, &na), *fb = tl_read_file(path2, &nb);
    CHECKF(fa && fb && na == nb && !memcmp(fa, fb, na), "save -> load -> save: %s and %s differ", path, path2);
    free(fa);
    free(fb);
    st_session_free(&s);
}

/* Fixes the header size, header CRC and trailer CRC of a session's bytes
 * that a test mutated (docs/SESSION-FORMAT.md), so that the reader gets
 * past the checksums to the mutation. */
void tl_session_fix_crc(unsigned char *c, size_t n)
{
    if (n < 32) return;
    for (int k = 0; k < 8; k++) c[16 + k] = (unsigned char)((uint64_t)n >> (8 * k));
    uint32_t hc = st_crc32(0, c, 24);
    for (int k = 0; k < 4; k++) c[24 + k] = (unsigned char)(hc >> (8 * k));
    uint32_t crc = st_session_checksum(c, n);
    for (int k = 0; k < 4; k++) c[n - 4 + k] = (unsigned char)(crc >> (8 * k));
}
