/* The scheme registry (scheme_registry.h). */
#include "core/progressive/progressive.h"
#include "core/progressive/scheme_registry.h"

#include <string.h>

static const st_scheme *const all_schemes[] = {
    &st_scheme_catmark, &st_scheme_loop, &st_scheme_butterfly,
    &st_scheme_quadtri, &st_scheme_sqrt3, &st_scheme_doosabin,
    &st_scheme_progressive,
};

const st_scheme *st_scheme_get(st_scheme_id id)
{
    for (size_t i = 0; i < sizeof all_schemes / sizeof *all_schemes; i++)
        if (all_schemes[i]->id == id) return all_schemes[i];
    return NULL;
}

const st_scheme *st_scheme_find(const char *name)
{
    for (size_t i = 0; i < sizeof all_schemes / sizeof *all_schemes; i++)
        if (!strcmp(all_schemes[i]->name, name)) return all_schemes[i];
    if (!strcmp(name, "catmark") || !strcmp(name, "cc")) return st_scheme_get(ST_SCHEME_CATMARK);
    return NULL;
}
