#include "testlib.h"

#include <stdlib.h>

int tl_passed, tl_failed;

int tl_report(const char *file)
{
    printf("%s: %d passed, %d failed\n", file, tl_passed, tl_failed);
    return tl_failed ? 1 : 0;
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
