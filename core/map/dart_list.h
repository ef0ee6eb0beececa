/* st_dart_list: a growable array of darts (or any 32-bit ids), the one list
 * type the passes hand each other (faces of a region, seeds of a local
 * synthesis, the darts a change touched).  Zero-initialised is empty. */
#ifndef ST_DART_LIST_H
#define ST_DART_LIST_H

#include <stdint.h>

typedef struct st_dart_list { uint32_t *d; uint32_t n, cap; } st_dart_list;
void st_dart_list_push(st_dart_list *l, uint32_t d);
void st_dart_list_free(st_dart_list *l);

#endif
