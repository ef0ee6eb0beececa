/* Memory accounting per level (strata info). */
#ifndef ST_MAP_MEMORY_H
#define ST_MAP_MEMORY_H

#include "core/map/map.h"

/* Bytes attributable to level l: the darts and vertices inserted at l
 * (their base values, insertion level and flags) plus the level-l columns. */
void st_map_level_memory(const st_map *m, unsigned l, st_map_bytes *b);

#endif
