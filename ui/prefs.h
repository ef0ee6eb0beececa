/* The window's preferences: recent files, window size, UI scale, the side
 * panel's layout and the brush defaults, in
 * $XDG_CONFIG_HOME/strata/prefs (~/.config/strata/prefs without it),
 * written atomically (core/io/atomic_file.h).  A file that does not parse
 * is ignored with a message naming the file and line; the defaults stay.
 *
 * Format, one setting a line ('#' comments):
 *   strata-prefs 1
 *   window W H
 *   ui_scale S            (0: from the monitor's content scale)
 *   recent PATH           (newest first, at most ST_PREFS_RECENT)
 *   panel_width W         (side panel, unscaled pixels; 0: the default)
 *   section NAME 0|1      (a panel section closed / open; NAME may have spaces)
 *   brush_tool NAME       (select, or a brush's name: draw, smooth, ...)
 *   brush_radius F        (a fraction of the model's half-diagonal)
 *   brush_strength S */
#ifndef ST_PREFS_H
#define ST_PREFS_H

#include <stddef.h>

#define ST_PREFS_RECENT 8

/* Where the file is (buf), 0; -1 when neither variable is set. */
int st_prefs_path(char *buf, unsigned long n);
/* Reads the file (a missing one is no error); 0, or -1 with the message
 * printed and the defaults kept. */
int st_prefs_load(void);
/* The same from memory (fuzz_prefs): name stands for the file in messages. */
int st_prefs_parse(const char *name, const char *data, size_t size);
/* Writes the file; 0 or -1 (message printed). */
int st_prefs_save(void);

/* NULL-terminated, newest first. */
const char *const *st_prefs_recent(void);
void st_prefs_add_recent(const char *path);
float st_prefs_ui_scale(void);
/* 0: from the monitor's content scale; else clamped to [0.5, 4].  Applies
 * at the next start (fonts are built once). */
void st_prefs_set_ui_scale(float s);
/* Forgets every recent file (File > Open Recent). */
void st_prefs_clear_recent(void);
void st_prefs_window(int *w, int *h);        /* 0 0 when not set */
void st_prefs_set_window(int w, int h);
void st_prefs_free(void);                  /* at exit */

/* Side panel: width (0 when not set) and which sections are open. */
float st_prefs_panel_width(void);
void st_prefs_set_panel_width(float w);
int st_prefs_section_open(const char *name, int dflt);
void st_prefs_set_section_open(const char *name, int open);

/* Brush defaults: the tool's name ("" when not set), the radius as a
 * fraction of the model's size and the strength (0 when not set). */
const char *st_prefs_brush_tool(void);
double st_prefs_brush_radius(void);
double st_prefs_brush_strength(void);
void st_prefs_set_brush(const char *tool, double radius, double strength);

#endif
