/* Preferences file (prefs.h). */
#include "prefs.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/io/atomic_file.h"

#define MAX_SECTIONS 32
#define NAME_LEN 48

static char *recent[ST_PREFS_RECENT + 1];
static float ui_scale;
static int win_w, win_h;
static float panel_w;
static struct { char name[NAME_LEN]; int open; } sections[MAX_SECTIONS];
static int nsections;
static char brush_tool[NAME_LEN];
static double brush_radius, brush_strength;

/* Every setting back to its default (before a load, after a bad one). */
static void clear_settings(void)
{
    ui_scale = 0;
    win_w = win_h = 0;
    panel_w = 0;
    nsections = 0;
    brush_tool[0] = 0;
    brush_radius = brush_strength = 0;
}

float st_prefs_panel_width(void) { return panel_w; }
void st_prefs_set_panel_width(float w) { panel_w = w > 0 && w < 100000 ? w : 0; }

int st_prefs_section_open(const char *name, int dflt)
{
    for (int i = 0; i < nsections; i++)
        if (!strcmp(sections[i].name, name)) return sections[i].open;
    return dflt;
}

void st_prefs_set_section_open(const char *name, int open)
{
    for (int i = 0; i < nsections; i++)
        if (!strcmp(sections[i].name, name)) { sections[i].open = open != 0; return; }
    if (nsections == MAX_SECTIONS || strlen(name) >= NAME_LEN || !name[0]) return;
    snprintf(sections[nsections].name, NAME_LEN, "%s", name);
    sections[nsections++].open = open != 0;
}

const char *st_prefs_brush_tool(void) { return brush_tool; }
double st_prefs_brush_radius(void) { return brush_radius; }
double st_prefs_brush_strength(void) { return brush_strength; }

void st_prefs_set_brush(const char *tool, double radius, double strength)
{
    snprintf(brush_tool, sizeof brush_tool, "%s", tool && strlen(tool) < NAME_LEN && !strchr(tool, ' ') ? tool : "");
    brush_radius = radius > 0 && radius < 1e3 ? radius : 0;
    brush_strength = strength > 0 && strength <= 1 ? strength : 0;
}

int st_prefs_path(char *buf, unsigned long n)
{
    const char *x = getenv("XDG_CONFIG_HOME"), *home = getenv("HOME");
    int k;
    if (x && x[0]) k = snprintf(buf, n, "%s/strata/prefs", x);
    else if (home && home[0]) k = snprintf(buf, n, "%s/.config/strata/prefs", home);
    else return -1;
    return k > 0 && (unsigned long)k < n ? 0 : -1;
}

static void clear_recent(void)
{
    for (int i = 0; i < ST_PREFS_RECENT; i++) { free(recent[i]); recent[i] = NULL; }
}

void st_prefs_free(void) { clear_recent(); }
void st_prefs_clear_recent(void) { clear_recent(); }

void st_prefs_set_ui_scale(float s)
{
    ui_scale = !(s > 0) ? 0 : s < 0.5f ? 0.5f : s > 4 ? 4 : s;
}

const char *const *st_prefs_recent(void) { return (const char *const *)recent; }
float st_prefs_ui_scale(void) { return ui_scale; }
void st_prefs_window(int *w, int *h) { *w = win_w; *h = win_h; }
void st_prefs_set_window(int w, int h) { win_w = w; win_h = h; }

void st_prefs_add_recent(const char *path)
{
    char full[PATH_MAX];
    const char *p = realpath(path, full) ? full : path;
    char *dup = strdup(p);
    if (!dup) return;
    /* Moved to the front if already listed; the oldest falls off. */
    int at = ST_PREFS_RECENT - 1;
    for (int i = 0; i < ST_PREFS_RECENT; i++)
        if (recent[i] && !strcmp(recent[i], p)) { at = i; break; }
    free(recent[at]);
    memmove(recent + 1, recent, (size_t)at * sizeof recent[0]);
    recent[0] = dup;
}

static int load_file(FILE *f, const char *path)
{
    char line[4200];
    unsigned no = 0;
    int nrec = 0;
    while (fgets(line, sizeof line, f)) {
        no++;
        size_t len = strlen(line);
        if (len && line[len - 1] == '\n') line[--len] = 0;
        else if (!feof(f)) { fprintf(stderr, "strata: %s:%u: line too long; preferences ignored\n", path, no); return -1; }
        if (!line[0] || line[0] == '#') continue;
        if (no == 1) {
            if (strcmp(line, "strata-prefs 1")) { fprintf(stderr, "strata: %s:1: not a strata-prefs 1 file; preferences ignored\n", path); return -1; }
            continue;
        }
        int w, h, open, used = 0;
        float s;
        double v;
        char name[NAME_LEN];
        if (sscanf(line, "window %d %d%n", &w, &h, &used) == 2 && !line[used] && w > 0 && h > 0 && w < 100000 && h < 100000) {
            win_w = w;
            win_h = h;
        } else if (sscanf(line, "ui_scale %f%n", &s, &used) == 1 && !line[used] && s >= 0 && s <= 8) {
            ui_scale = s;
        } else if (sscanf(line, "panel_width %f%n", &s, &used) == 1 && !line[used] && s >= 0 && s < 100000) {
            panel_w = s;
        } else if (!strncmp(line, "section ", 8) && len > 10 && (line[len - 1] == '0' || line[len - 1] == '1') &&
                   line[len - 2] == ' ' && len - 10 < NAME_LEN) {
            /* The name is everything between "section " and the last field. */
            open = line[len - 1] == '1';
            memcpy(name, line + 8, len - 10);
            name[len - 10] = 0;
            st_prefs_set_section_open(name, open);
        } else if (sscanf(line, "brush_tool %47s%n", name, &used) == 1 && !line[used]) {
            snprintf(brush_tool, sizeof brush_tool, "%s", name);
        } else if (sscanf(line, "brush_radius %lf%n", &v, &used) == 1 && !line[used] && v > 0 && v < 1e3) {
            brush_radius = v;
        } else if (sscanf(line, "brush_strength %lf%n", &v, &used) == 1 && !line[used] && v > 0 && v <= 1) {
            brush_strength = v;
        } else if (!strncmp(line, "recent ", 7) && line[7]) {
            if (nrec < ST_PREFS_RECENT && (recent[nrec] = strdup(line + 7))) nrec++;
        } else {
            fprintf(stderr, "strata: %s:%u: cannot read \"%.60s\"; preferences ignored\n", path, no, line);
            return -1;
        }
    }
    if (no == 0) { fprintf(stderr, "strata: %s: empty; preferences ignored\n", path); return -1; }
    return 0;
}

int st_prefs_load(void)
{
    char path[PATH_MAX];
    if (st_prefs_path(path, sizeof path)) return 0;
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    clear_recent();
    clear_settings();
    int rc = load_file(f, path);
    fclose(f);
    if (rc) { clear_recent(); clear_settings(); }
    return rc;
}

int st_prefs_parse(const char *name, const char *data, size_t size)
{
    clear_recent();
    clear_settings();
    FILE *f = size ? fmemopen((void *)data, size, "r") : NULL;
    int rc = f ? load_file(f, name) : -1;
    if (f) fclose(f);
    else fprintf(stderr, "strata: %s: %s; preferences ignored\n", name, size ? "cannot read it" : "empty");
    if (rc) { clear_recent(); clear_settings(); }
    return rc;
}

int st_prefs_save(void)
{
    char path[PATH_MAX];
    if (st_prefs_path(path, sizeof path)) return -1;
    st_error err;
    st_afile af;
    if (st_mkdir_parents(path) || st_afile_open(&af, path, &err)) {
        fprintf(stderr, "strata: cannot write the preferences %s: %s\n", path, strerror(errno));
        return -1;
    }
    /* Exact digits (9 for a float, 17 for a double): a value near a limit
     * (panel_width 99999.99) must not round onto it and be refused at the
     * next start (fuzz_prefs). */
    fprintf(af.f, "strata-prefs 1\n");
    if (win_w > 0 && win_h > 0) fprintf(af.f, "window %d %d\n", win_w, win_h);
    fprintf(af.f, "ui_scale %.9g\n", ui_scale);
    if (panel_w > 0) fprintf(af.f, "panel_width %.9g\n", panel_w);
    for (int i = 0; i < nsections; i++) fprintf(af.f, "section %s %d\n", sections[i].name, sections[i].open);
    if (brush_tool[0]) fprintf(af.f, "brush_tool %s\n", brush_tool);
    if (brush_radius > 0) fprintf(af.f, "brush_radius %.17g\n", brush_radius);
    if (brush_strength > 0) fprintf(af.f, "brush_strength %.17g\n", brush_strength);
    for (int i = 0; i < ST_PREFS_RECENT && recent[i]; i++) fprintf(af.f, "recent %s\n", recent[i]);
    if (st_afile_commit(&af, &err)) { fprintf(stderr, "strata: cannot write the preferences %s: %s\n", path, err.msg); return -1; }
    return 0;
}
