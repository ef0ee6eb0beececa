/* The schemes by id and by CLI name: the subdivision schemes of
 * core/schemes and the progressive scheme of this folder.  It sits here, the
 * lowest folder above every scheme table, so that core/schemes depends on
 * nothing above it, not even at link time (docs/ARCHITECTURE.md). */
#ifndef ST_SCHEME_REGISTRY_H
#define ST_SCHEME_REGISTRY_H

#include "core/schemes/scheme.h"

/* Lookup by id or CLI name (NULL if unknown; "catmark" and "cc" name
 * Catmull-Clark too). */
const st_scheme *st_scheme_get(st_scheme_id id);
const st_scheme *st_scheme_find(const char *name);

#endif
