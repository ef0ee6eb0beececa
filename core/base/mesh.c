/* st_mesh's lifetime and the notes (core/base/mesh.h). */
#include "core/base/mesh.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void st_mesh_init(st_mesh *m)
{
    memset(m, 0, sizeof *m);
    m->boundary_interp = ST_BOUNDARY_UNSET;
}

uint32_t st_mesh_hole_faces(const st_mesh *m)
{
    uint32_t n = 0;
    for (uint32_t f = 0; m->face_hole && f < m->nfaces; f++) n += m->face_hole[f] != 0;
    return n;
}

void st_mesh_free(st_mesh *m)
{
    free(m->pos);
    free(m->face_off);
    free(m->face_idx);
    free(m->normals);
    free(m->crease_v);
    free(m->crease_s);
    free(m->corner_v);
    free(m->corner_s);
    free(m->face_hole);
    free(m->uv);
    free(m->face_uv);
    st_mesh_init(m);
}

void st_mesh_move(st_mesh *dst, st_mesh *src)
{
    if (dst == src) return;
    st_mesh_free(dst);
    *dst = *src;
    st_mesh_init(src);
}

void st_notes_free(st_notes *n)
{
    if (!n) return;
    for (uint32_t i = 0; i < n->count; i++) free(n->lines[i]);
    free(n->lines);
    n->lines = NULL;
    n->count = 0;
}

int st_notes_add(st_notes *notes, const char *fmt, ...)
{
    if (!notes) return 0;
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    char **lines = realloc(notes->lines, (notes->count + 1u) * sizeof *lines);
    if (!lines) return ST_ERR_MEMORY;
    notes->lines = lines;
    size_t len = strlen(buf) + 1;
    char *copy = malloc(len);
    if (!copy) return ST_ERR_MEMORY;
    memcpy(copy, buf, len);
    lines[notes->count++] = copy;
    return 0;
}
