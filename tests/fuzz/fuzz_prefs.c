/* libFuzzer target for the preferences file (ui/prefs.h): st_prefs_parse
 * from memory.  Whatever the bytes, the parser keeps its limits; a file it
 * accepts is saved (to a private temporary $XDG_CONFIG_HOME) and must load
 * again to the same settings, so that the window never writes preferences
 * it will refuse at the next start.
 *   fuzz_prefs -max_total_time=60 /tmp/corpus_prefs   (a copy of
 *   tests/fuzz/corpus/prefs: the fuzzer writes into its corpus folder) */
#include "prefs.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char dir[] = "/tmp/strata-fuzz-prefs.XXXXXX";

static void cleanup(void)
{
    char path[sizeof dir + 32];
    snprintf(path, sizeof path, "%s/strata/prefs", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/strata", dir);
    rmdir(path);
    rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    if (!mkdtemp(dir)) { perror("mkdtemp"); abort(); }
    setenv("XDG_CONFIG_HOME", dir, 1);
    atexit(cleanup);
    return 0;
}

typedef struct settings {
    int w, h;
    float scale, panel;
    char tool[64];
    double radius, strength;
    char *recent[ST_PREFS_RECENT + 1];
    int open[4];
} settings;

/* Section names the seeds use; their state must survive a save. */
static const char *const names[4] = { "Brush", "Display", "Sculpt layers", "a" };

static void get(settings *s)
{
    memset(s, 0, sizeof *s);
    st_prefs_window(&s->w, &s->h);
    s->scale = st_prefs_ui_scale();
    s->panel = st_prefs_panel_width();
    snprintf(s->tool, sizeof s->tool, "%s", st_prefs_brush_tool());
    s->radius = st_prefs_brush_radius();
    s->strength = st_prefs_brush_strength();
    const char *const *r = st_prefs_recent();
    for (int i = 0; i < ST_PREFS_RECENT && r[i]; i++) s->recent[i] = strdup(r[i]);
    for (int i = 0; i < 4; i++) s->open[i] = st_prefs_section_open(names[i], -1);
}

static void drop(settings *s)
{
    for (int i = 0; i < ST_PREFS_RECENT; i++) free(s->recent[i]);
}

static int differ(const settings *a, const settings *b)
{
    if (a->w != b->w || a->h != b->h || a->scale != b->scale || a->panel != b->panel || strcmp(a->tool, b->tool) ||
        a->radius != b->radius || a->strength != b->strength || memcmp(a->open, b->open, sizeof a->open))
        return 1;
    for (int i = 0; i < ST_PREFS_RECENT; i++)
        if (!a->recent[i] != !b->recent[i] || (a->recent[i] && strcmp(a->recent[i], b->recent[i]))) return 1;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (st_prefs_parse("fuzz.prefs", (const char *)data, size) != 0) {
        /* A refusal keeps the defaults. */
        settings d;
        get(&d);
        if (d.w || d.h || d.scale != 0 || d.panel != 0 || d.tool[0] || d.radius != 0 || d.strength != 0 || d.recent[0]) {
            fprintf(stderr, "a refused file left settings behind\n");
            abort();
        }
        drop(&d);
        return 0;
    }
    settings a, b;
    get(&a);
    if (!(a.scale >= 0 && a.scale <= 8) || !(a.panel >= 0 && a.panel < 100000) || strlen(a.tool) >= 48 ||
        !(a.radius >= 0 && a.radius < 1e3) || !(a.strength >= 0 && a.strength <= 1)) {
        fprintf(stderr, "a setting out of its range was accepted\n");
        abort();
    }
    if (st_prefs_save() != 0) { fprintf(stderr, "cannot save accepted preferences\n"); abort(); }
    char path[4200];
    if (st_prefs_path(path, sizeof path)) abort();
    if (st_prefs_load() != 0) { fprintf(stderr, "saved preferences are refused at the next load\n"); abort(); }
    get(&b);
    if (differ(&a, &b)) { fprintf(stderr, "preferences changed through a save and a load\n"); abort(); }
    drop(&a);
    drop(&b);
    st_prefs_free();
    return 0;
}
