/* GLSL sources from shaders/NAME.glsl, embedded at build time by
 * cmake/embed_shaders.cmake (the generated shaders_embedded.c). */
#ifndef ST_SHADERS_H
#define ST_SHADERS_H
#ifndef STRATA_RENDER_INTERNAL
#error "internal to render: ui/, app/ and bench/ use render's public headers (docs/ARCHITECTURE.md)"
#endif

/* Source of shaders/NAME.glsl (e.g. "surface.vert"), NULL if unknown. */
const char *st_shader_source(const char *name);
unsigned st_shader_count(void);
const char *st_shader_name(unsigned i);

#endif
