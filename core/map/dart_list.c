/* st_dart_list (dart_list.h): the growable list the passes of every layer
 * hand each other, the schemes' local predictions included. */
#include "core/map/dart_list.h"

#include <stdlib.h>
#include <string.h>

void st_dart_list_push(st_dart_list *l, uint32_t d)
{
    if (l->n == l->cap) {
        uint32_t cap = l->cap ? 2 * l->cap : 64;
        uint32_t *p = realloc(l->d, cap * sizeof *p);
        if (!p) abort();
        l->d = p;
        l->cap = cap;
    }
    l->d[l->n++] = d;
}

void st_dart_list_free(st_dart_list *l) { free(l->d); memset(l, 0, sizeof *l); }
