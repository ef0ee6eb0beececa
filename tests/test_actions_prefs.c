/* The window's preferences file (ui/prefs.h), without a window: a valid
 * file is read, a corrupt one is ignored (defaults kept, -1), the recent
 * list keeps the newest first without duplicates, and a save round-trips
 * through the atomic writer with no temporary left behind.  (Named
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

    st_prefs_free();
    unlink(path);
    rmdir(sdir);
    rmdir(dir);
    return TEST_END();
}
