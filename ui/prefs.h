/* The window's preferences: recent files, window size and UI scale, in
 * $XDG_CONFIG_HOME/strata/prefs (~/.config/strata/prefs without it),
 * written atomically (core/io/atomic_file.h).  A file that does not parse
 * is ignored with a message naming the file and line; the defaults stay.
 *
 * Format, one setting a line ('#' comments):
 *   strata-prefs 1
 *   window W H
 *   ui_scale S            (0: from the monitor's content scale)
 *   recent PATH           (newest first, at most ST_PREFS_RECENT) */
#ifndef ST_PREFS_H
#define ST_PREFS_H

#define ST_PREFS_RECENT 8

/* Where the file is (buf), 0; -1 when neither variable is set. */
int st_prefs_path(char *buf, unsigned long n);
/* Reads the file (a missing one is no error); 0, or -1 with the message
 * printed and the defaults kept. */
int st_prefs_load(void);
/* Writes the file; 0 or -1 (message printed). */
int st_prefs_save(void);

/* NULL-terminated, newest first. */
const char *const *st_prefs_recent(void);
void st_prefs_add_recent(const char *path);
float st_prefs_ui_scale(void);
void st_prefs_window(int *w, int *h);        /* 0 0 when not set */
void st_prefs_set_window(int w, int h);
void st_prefs_free(void);                  /* at exit */

#endif
