/* ID-buffer picking; see pick.h. */
#include "pick.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int st_pick_init(st_pick *p, const st_gl *gl, st_error *err)
{
    memset(p, 0, sizeof *p);
    return st_idbuffer_init(&p->ids, gl, err);
}

void st_pick_free(st_pick *p)
{
    st_idbuffer_free(&p->ids);
    free(p->scratch);
    memset(p, 0, sizeof *p);
}

int st_pick_render(st_pick *p, const st_renderer *r, const st_camctl *c, int w, int h, st_error *err)
{
    if (w < 1 || h < 1) return ST_OK;
    if (p->valid && p->ids.w == w && p->ids.h == h) return ST_OK;
    int rc = st_idbuffer_draw(&p->ids, r, &c->cam, w, h, err);
    if (rc) return rc;
    p->valid = 1;
    p->renders++;
    return ST_OK;
}

static unsigned char *scratch(st_pick *p, size_t bytes)
{
    if (bytes > p->scratch_cap) {
        unsigned char *s = realloc(p->scratch, bytes);
        if (!s) return NULL;
        p->scratch = s;
        p->scratch_cap = bytes;
    }
    return p->scratch;
}

/* Reads the ID pixels of the rectangle [x0, x1) x [y0, y1) (top-left
 * origin, clipped); returns the pixels bottom-up with their GL rectangle. */
static unsigned char *read_ids(st_pick *p, int *x0, int *y0, int *x1, int *y1)
{
    if (*x0 < 0) *x0 = 0;
    if (*y0 < 0) *y0 = 0;
    if (*x1 > p->ids.w) *x1 = p->ids.w;
    if (*y1 > p->ids.h) *y1 = p->ids.h;
    if (*x1 <= *x0 || *y1 <= *y0 || !p->ids.target.fbo) return NULL;
    int rw = *x1 - *x0, rh = *y1 - *y0;
    unsigned char *px = scratch(p, (size_t)rw * rh * 4);
    if (!px) return NULL;
    st_idbuffer_read_ids(&p->ids, *x0, p->ids.h - *y1, rw, rh, px);
    return px;
}

static uint32_t decode(const unsigned char *q)
{
    return (uint32_t)q[0] | (uint32_t)q[1] << 8 | (uint32_t)q[2] << 16 | (uint32_t)q[3] << 24;
}

uint32_t st_pick_at(st_pick *p, int x, int y)
{
    int x0 = x - ST_PICK_RADIUS, y0 = y - ST_PICK_RADIUS, x1 = x + ST_PICK_RADIUS + 1, y1 = y + ST_PICK_RADIUS + 1;
    unsigned char *px = read_ids(p, &x0, &y0, &x1, &y1);
    if (!px) return ST_NIL;
    int rw = x1 - x0, rh = y1 - y0;
    uint32_t best = ST_NIL;
    long bestd = (long)ST_PICK_RADIUS * ST_PICK_RADIUS + 1;
    for (int j = 0; j < rh; j++) {
        int sy = y1 - 1 - j;             /* row j of the read is screen row sy */
        for (int i = 0; i < rw; i++) {
            uint32_t id = decode(px + 4 * ((size_t)j * rw + i));
            if (!id) continue;
            long dx = x0 + i - x, dy = sy - y, d = dx * dx + dy * dy;
            if (d < bestd) { bestd = d; best = id - 1; }
        }
    }
    return best;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

int64_t st_pick_rect(st_pick *p, int ax, int ay, int bx, int by, uint32_t **out)
{
    *out = NULL;
    int x0 = ax < bx ? ax : bx, x1 = (ax < bx ? bx : ax) + 1;
    int y0 = ay < by ? ay : by, y1 = (ay < by ? by : ay) + 1;
    unsigned char *px = read_ids(p, &x0, &y0, &x1, &y1);
    if (!px) return 0;
    size_t n = (size_t)(x1 - x0) * (size_t)(y1 - y0), k = 0;
    uint32_t *ids = malloc((n ? n : 1) * sizeof *ids);
    if (!ids) return -1;
    for (size_t i = 0; i < n; i++) {
        uint32_t id = decode(px + 4 * i);
        if (id && (!k || ids[k - 1] != id - 1)) ids[k++] = id - 1;
    }
    qsort(ids, k, sizeof *ids, cmp_u32);
    size_t u = 0;
    for (size_t i = 0; i < k; i++)
        if (!u || ids[u - 1] != ids[i]) ids[u++] = ids[i];
    *out = ids;
    return (int64_t)u;
}

static int read_depth(st_pick *p, int x, int y, float *z)
{
    if (x < 0 || y < 0 || x >= p->ids.w || y >= p->ids.h) return 0;
    *z = st_idbuffer_read_depth(&p->ids, x, p->ids.h - 1 - y);
    return *z < 1.0f;
}

int st_pick_surface(st_pick *p, const st_camctl *c, int x, int y, double pos[3], double nrm[3])
{
    if (!p->ids.target.fbo) return 0;
    float z = 1;
    if (!read_depth(p, x, y, &z)) return 0;
    st_camctl_unproject(c, p->ids.w, p->ids.h, x + 0.5, y + 0.5, z, pos);
    double r[3], u[3], b[3];
    st_camctl_axes(c, r, u, b);
    /* Normal from the depths of two neighbours (central differences where
     * both sides hit the surface). */
    const int k = 2;
    double q[4][3];
    int ok[4];
    const int off[4][2] = { { k, 0 }, { -k, 0 }, { 0, k }, { 0, -k } };
    for (int i = 0; i < 4; i++) {
        float zi = 1;
        ok[i] = read_depth(p, x + off[i][0], y + off[i][1], &zi);
        if (ok[i]) st_camctl_unproject(c, p->ids.w, p->ids.h, x + off[i][0] + 0.5, y + off[i][1] + 0.5, zi, q[i]);
    }
    double dx[3], dy[3];
    for (int i = 0; i < 3; i++) {
        dx[i] = ok[0] && ok[1] ? q[0][i] - q[1][i] : ok[0] ? q[0][i] - pos[i] : ok[1] ? pos[i] - q[1][i] : r[i];
        dy[i] = ok[2] && ok[3] ? q[2][i] - q[3][i] : ok[2] ? q[2][i] - pos[i] : ok[3] ? pos[i] - q[3][i] : -u[i];
    }
    double n[3] = { dy[1] * dx[2] - dy[2] * dx[1], dy[2] * dx[0] - dy[0] * dx[2], dy[0] * dx[1] - dy[1] * dx[0] };
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0)) { for (int i = 0; i < 3; i++) nrm[i] = b[i]; return 1; }
    double s = (n[0] * b[0] + n[1] * b[1] + n[2] * b[2]) < 0 ? -1 : 1;
    for (int i = 0; i < 3; i++) nrm[i] = s * n[i] / len;
    return 1;
}
