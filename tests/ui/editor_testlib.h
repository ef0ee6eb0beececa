/* Helpers shared by the headless document tests (test_editor*.c). */
#ifndef ST_EDITOR_TESTLIB_H
#define ST_EDITOR_TESTLIB_H

#include <stdint.h>

#include "editor.h"

/* st_doc_open, a failed check (with the editor's message) when it fails;
 * the brush set to the raw dab (st_brush_raw). */
void ed_test_open(st_doc *d, const char *path, const char *scheme, unsigned levels);
/* The vertices of level l in enumeration order (one dart each), into a
 * malloc'ed *out; returns their number. */
uint32_t ed_test_level_vertices(const st_doc *d, unsigned l, uint32_t **out);
/* The editing-level vertex that maximises dot(p, dir). */
uint32_t ed_test_extreme_vertex(st_doc *d, const double dir[3]);
double ed_test_dist3(const double *a, const double *b);
/* Every value of h: for each level, for each of its vertices in
 * enumeration order, its position and (above level 0) its detail, 3
 * doubles each, into a malloc'ed array; *n gets the number of doubles.
 * Two hierarchies of the same topology compare with memcmp. */
double *ed_test_all_values(const st_hier *h, size_t *n);
/* h's values now are the n doubles of v (ed_test_all_values), bit for bit. */
int ed_test_same_values(const st_hier *h, const double *v, size_t n);

/* HD levels (editor_hd.c): the display equals a full adaptive synthesis of
 * its levels above `from` (st_adapt_synthesize on a copy), bit for bit;
 * the editable vertex of the display's level L nearest to the centroid of
 * the editable ones (the middle of the HD region), its dart in *dart. */
int ed_test_display_is_synthesis(st_doc *d, unsigned from);
uint32_t ed_test_hd_middle_vertex(st_doc *d, unsigned L, uint32_t *dart);
/* The interest box set to the cube [lo, hi]^3 (its levels as they are),
 * shown (on 1) or not; a failed check when refused. */
void ed_test_set_box(st_doc *d, double lo, double hi, int on);
/* A document of the session s as the window opens one (ui/session_io.c):
 * s's model and its layers taken, its HD levels adopted (a failed check
 * when it has none or they are refused); obj: any mesh, to open first. */
struct st_session;
void ed_test_open_hd_session(st_doc *e, const char *obj, struct st_session *s);

#endif
