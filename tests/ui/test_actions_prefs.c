/* The window's preferences file (ui/prefs.h), without a window: a valid
 * file is read, a corrupt one is ignored (defaults kept, -1), the recent
 * list keeps the newest first without duplicates, the panel layout
 * (width, open and closed sections) and the brush defaults (tool, radius,
 * strength) round-trip, and a save goes through the atomic writer with no
 * temporary left behind.  (Named
 * test_actions_* to link the window's library, tests/CMakeLists.txt.) */
#include "prefs.h"
#include "testlib.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[256], path[512];

static void write_file(const char *text)
{
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (!f) return;
    fputs(text, f);
    fclose(f);
}

static int count_entries(const char *d)
{
    DIR *h = opendir(d);
    int n = 0;
    if (!h) return -1;
    for (struct dirent *e; (e = readdir(h));) n += e->d_name[0] != '.';
    closedir(h);
    return n;
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/strata_prefs_test.%d", (int)getpid());
    setenv("XDG_CONFIG_HOME", dir, 1);
    char got[512];
    CHECK(st_prefs_path(got, sizeof got) == 0);
    snprintf(path, sizeof path, "%s/strata/prefs", dir);
    CHECK(!strcmp(got, path));

    /* No file: defaults, no error. */
    CHECK(st_prefs_load() == 0);
    CHECK(st_prefs_recent()[0] == NULL && st_prefs_ui_scale() == 0);

    /* Save creates the folder; the file reads back. */
    st_prefs_add_recent("/nonexistent/a.obj");
    st_prefs_add_recent("/nonexistent/b.obj");
    st_prefs_add_recent("/nonexistent/a.obj");   /* back to the front, not twice */
    st_prefs_set_window(900, 700);
    CHECK(st_prefs_save() == 0);
    char sdir[600];
    snprintf(sdir, sizeof sdir, "%s/strata", dir);
    CHECK(count_entries(sdir) == 1);              /* no temporary left */
    st_prefs_free();
    st_prefs_set_window(0, 0);
    CHECK(st_prefs_load() == 0);
    const char *const *r = st_prefs_recent();
    CHECK(r[0] && !strcmp(r[0], "/nonexistent/a.obj"));
    CHECK(r[0] && r[1] && !strcmp(r[1], "/nonexistent/b.obj") && r[2] == NULL);
    int w, h;
    st_prefs_window(&w, &h);
    CHECK(w == 900 && h == 700);

    /* More than ST_PREFS_RECENT: the oldest falls off. */
    for (int i = 0; i < ST_PREFS_RECENT + 3; i++) {
        char p[64];
        snprintf(p, sizeof p, "/nonexistent/%d.obj", i);
        st_prefs_add_recent(p);
    }
    int n = 0;
    while (st_prefs_recent()[n]) n++;
    CHECK(n == ST_PREFS_RECENT);
    CHECK(!strcmp(st_prefs_recent()[0], "/nonexistent/10.obj"));

    /* Corrupt files: ignored with the defaults, whatever came before. */
    static const char *const bad[] = {
        "not prefs\n", "strata-prefs 1\nwindow 10\n", "strata-prefs 1\nui_scale banana\n",
        "strata-prefs 1\nrecent /x.obj\nwhatever 3\n", "",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        write_file(bad[i]);
        CHECKF(st_prefs_load() == -1, "case %zu loaded", i);
        st_prefs_window(&w, &h);
        CHECKF(st_prefs_recent()[0] == NULL && w == 0 && h == 0 && st_prefs_ui_scale() == 0, "case %zu kept values", i);
    }
    write_file("strata-prefs 1\n# comment\nui_scale 1.5\nrecent /y.obj\n");
    CHECK(st_prefs_load() == 0 && st_prefs_ui_scale() == 1.5f);
    CHECK(st_prefs_recent()[0] && !strcmp(st_prefs_recent()[0], "/y.obj"));

    /* The Preferences window's settings: the UI scale (clamped; 0 is the
     * monitor's) and clearing the recent files, saved and read back. */
    st_prefs_set_ui_scale(2.25f);
    st_prefs_clear_recent();
    CHECK(st_prefs_ui_scale() == 2.25f && st_prefs_recent()[0] == NULL);
    CHECK(st_prefs_save() == 0);
    st_prefs_set_ui_scale(0);
    st_prefs_add_recent("/nonexistent/z.obj");
    CHECK(st_prefs_load() == 0 && st_prefs_ui_scale() == 2.25f && st_prefs_recent()[0] == NULL);
    st_prefs_set_ui_scale(100);
    CHECK(st_prefs_ui_scale() == 4.0f);
    st_prefs_set_ui_scale(0.1f);
    CHECK(st_prefs_ui_scale() == 0.5f);
    st_prefs_set_ui_scale(-1);
    CHECK(st_prefs_ui_scale() == 0);

    /* Panel layout and brush defaults: unset, then set, saved, read back. */
    write_file("strata-prefs 1\n");
    CHECK(st_prefs_load() == 0);
    CHECK(st_prefs_panel_width() == 0 && st_prefs_brush_tool()[0] == 0);
    CHECK(st_prefs_brush_radius() == 0 && st_prefs_brush_strength() == 0);
    CHECK(st_prefs_section_open("Levels", 1) == 1 && st_prefs_section_open("Levels", 0) == 0);
    st_prefs_set_panel_width(340);
    st_prefs_set_section_open("Levels", 0);
    st_prefs_set_section_open("Interest box", 1);
    st_prefs_set_section_open("Timings", 0);
    st_prefs_set_section_open("Timings", 1);          /* changed again: one entry */
    st_prefs_set_brush("smooth", 0.0625, 0.35);
    CHECK(st_prefs_save() == 0);
    CHECK(count_entries(sdir) == 1);
    st_prefs_set_panel_width(0);
    st_prefs_set_brush(NULL, 0, 0);
    CHECK(st_prefs_load() == 0);
    CHECK(st_prefs_panel_width() == 340.0f);
    CHECK(st_prefs_section_open("Levels", 1) == 0);
    CHECK(st_prefs_section_open("Interest box", 0) == 1);
    CHECK(st_prefs_section_open("Timings", 0) == 1);
    CHECK(st_prefs_section_open("Display", 1) == 1);  /* not listed: the default */
    CHECK(!strcmp(st_prefs_brush_tool(), "smooth"));
    CHECK(st_prefs_brush_radius() == 0.0625 && st_prefs_brush_strength() == 0.35);
    FILE *f = fopen(path, "r");
    char text[2048] = "";
    size_t len = f ? fread(text, 1, sizeof text - 1, f) : 0;
    if (f) fclose(f);
    text[len] = 0;
    CHECKF(strstr(text, "\nsection Timings 1\n") && !strstr(text, "section Timings 0"), "file: %s", text);
    /* Settings out of range or malformed: the whole file is ignored and
     * every setting, the layout and brush included, is back to its default. */
    static const char *const bad2[] = {
        "strata-prefs 1\npanel_width -3\n", "strata-prefs 1\nsection Levels 2\n", "strata-prefs 1\nsection 1\n",
        "strata-prefs 1\nbrush_strength 7\n", "strata-prefs 1\nbrush_radius 0\n", "strata-prefs 1\nbrush_tool draw smooth\n",
        "strata-prefs 1\npanel_width 300\nbrush_tool draw\nsection Tool 0\nwindow 1 2 3\n",
    };
    for (size_t i = 0; i < sizeof bad2 / sizeof bad2[0]; i++) {
        write_file("strata-prefs 1\npanel_width 310\nbrush_tool grab\nsection Tool 0\n");
        CHECK(st_prefs_load() == 0 && st_prefs_panel_width() == 310.0f && st_prefs_section_open("Tool", 1) == 0);
        write_file(bad2[i]);
        CHECKF(st_prefs_load() == -1, "layout case %zu loaded", i);
        CHECKF(st_prefs_panel_width() == 0 && st_prefs_brush_tool()[0] == 0 && st_prefs_brush_radius() == 0 &&
                   st_prefs_brush_strength() == 0 && st_prefs_section_open("Tool", 1) == 1,
               "layout case %zu kept values", i);
    }
    /* Names with spaces, and setters refusing what the file could not hold. */
    st_prefs_set_brush("two words", 5000, 2);
    CHECK(st_prefs_brush_tool()[0] == 0 && st_prefs_brush_radius() == 0 && st_prefs_brush_strength() == 0);

    st_prefs_free();
    unlink(path);
    rmdir(sdir);
    rmdir(dir);
    return TEST_END();
}
