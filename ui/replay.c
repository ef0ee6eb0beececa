/* Scripted input; see replay.h. */
#include "replay.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h> /* key and button codes; ST_REPLAY_PARSE_ONLY (fuzz_replay) links no GLFW */

#include "core/io/session.h"
#include "gui.h"
#include "window.h"

enum ev_type {
    EV_WAIT, EV_KEY, EV_MOVE, EV_BUTTON, EV_SCROLL, EV_DROP, EV_LEVEL, EV_SNAPSHOT, EV_SHOT, EV_EXPECT, EV_ECHO, EV_QUIT,
    EV_GUI, EV_MENU, EV_FRAMES, EV_BRUSH, EV_FILTER, EV_SCROLL_CLICK, EV_BAKE
};

/* `brush SETTING VALUE`: what the panel's tool section sets. */
enum brush_setting { BR_FALLOFF, BR_SPACING, BR_STABILIZE, BR_SYMMETRY, BR_FRONT, BR_STRENGTH, BR_RADIUS };

typedef struct ev {
    int type, line;
    int key, action, mods, button, which;
    double x, y;
    char *text, *arg;
} ev;

struct st_replay {
    char path[1024];
    ev *e;
    size_t n, cap, pos;
    float *snap;               /* displayed positions at the last snapshot */
    uint32_t nsnap;
    int has_snap;
    /* `time_frames N`: frame times still to collect, and those collected. */
    int timing_left, ntimes;
    double *times;
};

/* `filter G0,G1,...`: the gains the Filter panel applies; their number,
 * or -1 when one is not a finite number or there are too many. */
static int parse_gains(const char *s, double g[ST_MAX_LEVELS])
{
    int n = 0;
    for (;;) {
        char *end;
        if (n == ST_MAX_LEVELS) return -1;
        g[n] = strtod(s, &end);
        if (end == s || !isfinite(g[n])) return -1;
        n++;
        if (!*end) return n;
        if (*end != ',') return -1;
        s = end + 1;
    }
}

/* Events a replay may hold: ~64 MB, hours of frames. */
#define MAX_EVENTS (1u << 20)

static ev *push(st_replay *rp, int type, int line)
{
    if (rp->n >= MAX_EVENTS) return NULL;
    if (rp->n == rp->cap) {
        size_t cap = rp->cap ? 2 * rp->cap : 64;
        ev *e = realloc(rp->e, cap * sizeof *e);
        if (!e) return NULL;
        rp->e = e;
        rp->cap = cap;
    }
    ev *e = &rp->e[rp->n++];
    memset(e, 0, sizeof *e);
    e->type = type;
    e->line = line;
    return e;
}

static const struct { const char *name; int key; } key_names[] = {
    { "pageup", GLFW_KEY_PAGE_UP }, { "pagedown", GLFW_KEY_PAGE_DOWN }, { "home", GLFW_KEY_HOME },
    { "end", GLFW_KEY_END }, { "left", GLFW_KEY_LEFT }, { "right", GLFW_KEY_RIGHT }, { "up", GLFW_KEY_UP },
    { "down", GLFW_KEY_DOWN }, { "escape", GLFW_KEY_ESCAPE }, { "esc", GLFW_KEY_ESCAPE },
    { "enter", GLFW_KEY_ENTER }, { "return", GLFW_KEY_ENTER }, { "tab", GLFW_KEY_TAB },
    { "space", GLFW_KEY_SPACE }, { "delete", GLFW_KEY_DELETE }, { "backspace", GLFW_KEY_BACKSPACE },
    { "kp_add", GLFW_KEY_KP_ADD }, { "kp_subtract", GLFW_KEY_KP_SUBTRACT }, { "kp_enter", GLFW_KEY_KP_ENTER },
    { "plus", GLFW_KEY_EQUAL }, { "minus", GLFW_KEY_MINUS },
    { "[", GLFW_KEY_LEFT_BRACKET }, { "]", GLFW_KEY_RIGHT_BRACKET }, { ",", GLFW_KEY_COMMA },
    { ".", GLFW_KEY_PERIOD }, { "-", GLFW_KEY_MINUS }, { "=", GLFW_KEY_EQUAL }, { "/", GLFW_KEY_SLASH },
    { ";", GLFW_KEY_SEMICOLON }, { "'", GLFW_KEY_APOSTROPHE },
    { "shift", GLFW_KEY_LEFT_SHIFT }, { "ctrl", GLFW_KEY_LEFT_CONTROL }, { "control", GLFW_KEY_LEFT_CONTROL },
    { "alt", GLFW_KEY_LEFT_ALT }, { "super", GLFW_KEY_LEFT_SUPER },
};

static int key_code(const char *s)
{
    for (size_t i = 0; i < sizeof key_names / sizeof key_names[0]; i++)
        if (!strcasecmp(s, key_names[i].name)) return key_names[i].key;
    if (strlen(s) == 1 && isalpha((unsigned char)s[0])) return GLFW_KEY_A + (toupper((unsigned char)s[0]) - 'A');
    if (strlen(s) == 1 && isdigit((unsigned char)s[0])) return GLFW_KEY_0 + (s[0] - '0');
    if ((s[0] == 'f' || s[0] == 'F') && isdigit((unsigned char)s[1])) {
        int n = atoi(s + 1);
        if (n >= 1 && n <= 25) return GLFW_KEY_F1 + n - 1;
    }
    if (!strncasecmp(s, "kp_", 3) && isdigit((unsigned char)s[3]) && !s[4]) return GLFW_KEY_KP_0 + (s[3] - '0');
    return -1;
}

static int mod_bit(const char *s)
{
    if (!strcasecmp(s, "ctrl") || !strcasecmp(s, "control")) return GLFW_MOD_CONTROL;
    if (!strcasecmp(s, "shift")) return GLFW_MOD_SHIFT;
    if (!strcasecmp(s, "alt")) return GLFW_MOD_ALT;
    if (!strcasecmp(s, "super")) return GLFW_MOD_SUPER;
    return 0;
}

static int mod_key(int bit)
{
    switch (bit) {
    case GLFW_MOD_CONTROL: return GLFW_KEY_LEFT_CONTROL;
    case GLFW_MOD_SHIFT: return GLFW_KEY_LEFT_SHIFT;
    case GLFW_MOD_ALT: return GLFW_KEY_LEFT_ALT;
    default: return GLFW_KEY_LEFT_SUPER;
    }
}

/* "ctrl+shift+d" -> key and mods; a lone modifier ("ctrl") is a key. */
static int parse_key(const char *spec, int *key, int *mods)
{
    char buf[128];
    snprintf(buf, sizeof buf, "%s", spec);
    *mods = 0;
    *key = -1;
    char *parts[8];
    int np = 0;
    char *s = buf;
    while (np < 8) {
        parts[np++] = s;
        /* '+' separates, except a trailing "+" meaning the key itself. */
        char *p = strchr(s, '+');
        if (!p || !p[1]) break;
        *p = 0;
        s = p + 1;
    }
    for (int i = 0; i < np - 1; i++) {
        int b = mod_bit(parts[i]);
        if (!b) return -1;
        *mods |= b;
    }
    *key = key_code(parts[np - 1]);
    return *key < 0 ? -1 : 0;
}

static int parse_mods(const char *s, int *mods)
{
    *mods = 0;
    if (!s || !*s) return 0;
    char buf[128];
    snprintf(buf, sizeof buf, "%s", s);
    for (char *t = strtok(buf, "+"); t; t = strtok(NULL, "+")) {
        int b = mod_bit(t);
        if (!b) return -1;
        *mods |= b;
    }
    return 0;
}

static int parse_button(const char *s)
{
    if (!s) return -1;
    if (!strcasecmp(s, "left")) return GLFW_MOUSE_BUTTON_LEFT;
    if (!strcasecmp(s, "right")) return GLFW_MOUSE_BUTTON_RIGHT;
    if (!strcasecmp(s, "middle")) return GLFW_MOUSE_BUTTON_MIDDLE;
    return -1;
}

/* Key events holding (action PRESS) or letting go (RELEASE) of the
 * modifiers in mods, with the mods GLFW would report. */
static int push_mods(st_replay *rp, int line, int mods, int action)
{
    static const int order[4] = { GLFW_MOD_CONTROL, GLFW_MOD_SHIFT, GLFW_MOD_ALT, GLFW_MOD_SUPER };
    int held = action == GLFW_PRESS ? 0 : mods;
    for (int i = 0; i < 4; i++) {
        if (!(mods & order[i])) continue;
        ev *e = push(rp, EV_KEY, line);
        if (!e) return -1;
        e->key = mod_key(order[i]);
        e->action = action;
        if (action == GLFW_PRESS) held |= order[i];
        else held &= ~order[i];
        e->mods = held;
    }
    return 0;
}

static int parse_line(st_replay *rp, char *s, int line, st_error *err)
{
    char *tok[10];
    int nt = 0;
    for (char *t = strtok(s, " \t\r\n"); t && nt < 10; t = strtok(NULL, " \t\r\n")) tok[nt++] = t;
    if (!nt) return 0;
    const char *c = tok[0];
    ev *e;
#define BAD(...) return st_fail(err, ST_ERR_PARSE, __VA_ARGS__)
#define NOMEM() return st_fail(err, ST_ERR_MEMORY, "%s:%d: out of memory or more than %u events", rp->path, line, MAX_EVENTS)
    if (!strcmp(c, "wait")) {
        int n = nt > 1 ? atoi(tok[1]) : 1;
        if (n < 0 || n > 100000) BAD("%s:%d: wait wants a frame count", rp->path, line);
        for (int i = 0; i < n; i++) if (!push(rp, EV_WAIT, line)) NOMEM();
    } else if (!strcmp(c, "key") || !strcmp(c, "press") || !strcmp(c, "release")) {
        int key, mods;
        if (nt < 2 || parse_key(tok[1], &key, &mods)) BAD("%s:%d: unknown key '%s'", rp->path, line, nt > 1 ? tok[1] : "");
        int full = !strcmp(c, "key");
        if (full && push_mods(rp, line, mods, GLFW_PRESS)) NOMEM();
        if (full || !strcmp(c, "press")) {
            if (!(e = push(rp, EV_KEY, line))) NOMEM();
            e->key = key; e->action = GLFW_PRESS; e->mods = mods;
        }
        if (full || !strcmp(c, "release")) {
            if (!(e = push(rp, EV_KEY, line))) NOMEM();
            e->key = key; e->action = GLFW_RELEASE; e->mods = mods;
        }
        if (full && push_mods(rp, line, mods, GLFW_RELEASE)) NOMEM();
    } else if (!strcmp(c, "mouse_move")) {
        if (nt < 3) BAD("%s:%d: mouse_move X Y", rp->path, line);
        if (!(e = push(rp, EV_MOVE, line))) NOMEM();
        e->x = atof(tok[1]); e->y = atof(tok[2]);
    } else if (!strcmp(c, "mouse_down") || !strcmp(c, "mouse_up")) {
        int b = parse_button(nt > 1 ? tok[1] : NULL), mods;
        if (b < 0 || parse_mods(nt > 2 ? tok[2] : NULL, &mods)) BAD("%s:%d: %s left|middle|right [MODS]", rp->path, line, c);
        if (!(e = push(rp, EV_BUTTON, line))) NOMEM();
        e->button = b; e->mods = mods; e->action = !strcmp(c, "mouse_down") ? GLFW_PRESS : GLFW_RELEASE;
    } else if (!strcmp(c, "drag")) {
        int b = parse_button(nt > 1 ? tok[1] : NULL), mods;
        if (b < 0 || nt < 7 || parse_mods(nt > 7 ? tok[7] : NULL, &mods))
            BAD("%s:%d: drag BUTTON X0 Y0 X1 Y1 STEPS [MODS]", rp->path, line);
        double x0 = atof(tok[2]), y0 = atof(tok[3]), x1 = atof(tok[4]), y1 = atof(tok[5]);
        int steps = atoi(tok[6]);
        if (steps < 1) steps = 1;
        if (steps > 100000) BAD("%s:%d: drag: STEPS 1..100000", rp->path, line);
        if (!(e = push(rp, EV_MOVE, line))) NOMEM();
        e->x = x0; e->y = y0;
        if (push_mods(rp, line, mods, GLFW_PRESS)) NOMEM();
        if (!(e = push(rp, EV_BUTTON, line))) NOMEM();
        e->button = b; e->mods = mods; e->action = GLFW_PRESS;
        for (int i = 1; i <= steps; i++) {
            if (!(e = push(rp, EV_MOVE, line))) NOMEM();
            e->x = x0 + (x1 - x0) * i / steps;
            e->y = y0 + (y1 - y0) * i / steps;
        }
        if (!(e = push(rp, EV_BUTTON, line))) NOMEM();
        e->button = b; e->mods = mods; e->action = GLFW_RELEASE;
        if (push_mods(rp, line, mods, GLFW_RELEASE)) NOMEM();
    } else if (!strcmp(c, "scroll")) {
        int mods;
        if (nt < 2 || parse_mods(nt > 2 ? tok[2] : NULL, &mods)) BAD("%s:%d: scroll DY [MODS]", rp->path, line);
        if (push_mods(rp, line, mods, GLFW_PRESS)) NOMEM();
        if (!(e = push(rp, EV_SCROLL, line))) NOMEM();
        e->y = atof(tok[1]);
        if (push_mods(rp, line, mods, GLFW_RELEASE)) NOMEM();
    } else if (!strcmp(c, "scroll_click")) {
        if (nt != 2) BAD("%s:%d: scroll_click DY", rp->path, line);
        if (!(e = push(rp, EV_SCROLL_CLICK, line))) NOMEM();
        e->y = atof(tok[1]);
    } else if (!strcmp(c, "drop") || !strcmp(c, "screenshot") || !strcmp(c, "echo")) {
        if (nt < 2) BAD("%s:%d: %s needs an argument", rp->path, line, c);
        if (!(e = push(rp, !strcmp(c, "drop") ? EV_DROP : !strcmp(c, "echo") ? EV_ECHO : EV_SHOT, line))) NOMEM();
        if (e->type == EV_DROP && tok[1][0] != '/') {
            /* Relative dropped paths are relative to the events file. */
            const char *slash = strrchr(rp->path, '/');
            size_t dl = slash ? (size_t)(slash - rp->path) + 1 : 0, n = dl + strlen(tok[1]) + 1;
            e->text = malloc(n);
            if (e->text) { memcpy(e->text, rp->path, dl); strcpy(e->text + dl, tok[1]); }
        } else {
            e->text = strdup(tok[1]);
        }
        if (!e->text) NOMEM();
    } else if (!strcmp(c, "level")) {
        if (nt < 3 || (strcmp(tok[1], "edit") && strcmp(tok[1], "display"))) BAD("%s:%d: level edit|display N", rp->path, line);
        if (!(e = push(rp, EV_LEVEL, line))) NOMEM();
        e->which = !strcmp(tok[1], "display");
        e->x = atof(tok[2]);
    } else if (!strcmp(c, "snapshot")) {
        if (!push(rp, EV_SNAPSHOT, line)) NOMEM();
    } else if (!strcmp(c, "expect")) {
        if (nt < 2) BAD("%s:%d: expect WHAT [VALUE]", rp->path, line);
        if (!(e = push(rp, EV_EXPECT, line))) NOMEM();
        e->text = strdup(tok[1]);
        e->arg = nt > 2 ? strdup(tok[2]) : NULL;
    } else if (!strcmp(c, "time_frames")) {
        if (nt < 2 || atoi(tok[1]) < 1 || atoi(tok[1]) > 100000) BAD("%s:%d: time_frames N (1..100000)", rp->path, line);
        if (!(e = push(rp, EV_FRAMES, line))) NOMEM();
        e->which = atoi(tok[1]);
    } else if (!strcmp(c, "gui")) {
        if (nt < 2 || (strcmp(tok[1], "on") && strcmp(tok[1], "off"))) BAD("%s:%d: gui on|off", rp->path, line);
        if (!(e = push(rp, EV_GUI, line))) NOMEM();
        e->which = !strcmp(tok[1], "on");
    } else if (!strcmp(c, "menu")) {
        if (nt < 2) BAD("%s:%d: menu PATH [ARG] (e.g. menu File/Export/glTF out.gltf)", rp->path, line);
        if (!(e = push(rp, EV_MENU, line))) NOMEM();
        e->text = strdup(tok[1]);
        e->arg = nt > 2 ? strdup(tok[2]) : NULL;
        if (!e->text || (nt > 2 && !e->arg)) NOMEM();
    } else if (!strcmp(c, "brush")) {
        static const char *const what[] = { "falloff", "spacing", "stabilize", "symmetry", "front", "strength", "radius" };
        int k = -1;
        for (int i = 0; nt >= 3 && i < (int)(sizeof what / sizeof what[0]); i++)
            if (!strcmp(tok[1], what[i])) k = i;
        if (k < 0)
            BAD("%s:%d: brush falloff NAME | spacing F | stabilize on|off [F] | symmetry none|x|y|z|xy|xz|yz|xyz | "
                "front on|off | strength S | radius R", rp->path, line);
        if (!(e = push(rp, EV_BRUSH, line))) NOMEM();
        e->which = k;
        char *end = NULL;
        if (k == BR_FALLOFF) {
            if ((e->key = st_falloff_by_name(tok[2])) < 0)
                BAD("%s:%d: brush falloff %s: not one of smooth, sphere, root, sharp, linear, constant", rp->path, line, tok[2]);
        } else if (k == BR_STABILIZE || k == BR_FRONT) {
            if (strcmp(tok[2], "on") && strcmp(tok[2], "off")) BAD("%s:%d: brush %s on|off", rp->path, line, what[k]);
            e->key = !strcmp(tok[2], "on");
            e->x = nt > 3 ? strtod(tok[3], &end) : -1;
            if (nt > 3 && (!end || *end || !(e->x > 0) || e->x > 10)) BAD("%s:%d: brush %s: distance 0..10 radii", rp->path, line, what[k]);
        } else if (k == BR_SYMMETRY) {
            if (strcmp(tok[2], "none")) {
                for (const char *q = tok[2]; *q; q++) {
                    if (*q < 'x' || *q > 'z') BAD("%s:%d: brush symmetry %s: letters x, y, z or none", rp->path, line, tok[2]);
                    e->key |= 1 << (*q - 'x');
                }
            }
        } else {
            e->x = strtod(tok[2], &end);
            double hi = k == BR_STRENGTH ? 1 : k == BR_SPACING ? 10 : 1e9;
            if (!end || *end || !(e->x >= 0) || e->x > hi || (k == BR_RADIUS && !(e->x > 0)))
                BAD("%s:%d: brush %s %s: a number in 0..%g", rp->path, line, what[k], tok[2], hi);
        }
    } else if (!strcmp(c, "bake")) {
        if (nt < 2) BAD("%s:%d: bake SETTING VALUE | bake run (see ui/gui.h st_gui_bake_set)", rp->path, line);
        if (!(e = push(rp, EV_BAKE, line))) NOMEM();
        e->text = strdup(tok[1]);
        e->arg = nt > 2 ? strdup(tok[2]) : NULL;
        if (!e->text || (nt > 2 && !e->arg)) NOMEM();
    } else if (!strcmp(c, "filter")) {
        double g[ST_MAX_LEVELS];
        if (nt < 2 || parse_gains(tok[1], g) < 0)
            BAD("%s:%d: filter G0,G1,... (finite gains, at most %d)", rp->path, line, ST_MAX_LEVELS);
        if (!(e = push(rp, EV_FILTER, line)) || !(e->text = strdup(tok[1]))) NOMEM();
    } else if (!strcmp(c, "quit")) {
        if (!push(rp, EV_QUIT, line)) NOMEM();
    } else {
        BAD("%s:%d: unknown event '%s'", rp->path, line, c);
    }
#undef BAD
#undef NOMEM
    return 0;
}

void st_replay_free(st_replay *rp)
{
    if (!rp) return;
    for (size_t i = 0; i < rp->n; i++) { free(rp->e[i].text); free(rp->e[i].arg); }
    free(rp->e);
    free(rp->snap);
    free(rp->times);
    free(rp);
}

int st_replay_parse(st_replay **out, const char *name, const char *data, size_t size, st_error *err)
{
    *out = NULL;
    st_replay *rp = calloc(1, sizeof *rp);
    if (!rp) return st_fail(err, ST_ERR_MEMORY, "%s: out of memory", name);
    snprintf(rp->path, sizeof rp->path, "%s", name);
    char line[2048];
    int ln = 0, rc = 0;
    for (size_t at = 0; !rc && at < size;) {
        const char *nl = memchr(data + at, '\n', size - at);
        size_t len = nl ? (size_t)(nl - (data + at)) : size - at;
        ln++;
        if (len >= sizeof line) {
            rc = st_fail(err, ST_ERR_PARSE, "%s:%d: line longer than %zu characters", name, ln, sizeof line - 1);
            break;
        }
        memcpy(line, data + at, len);
        line[len] = 0;
        at += len + 1;
        char *h = strchr(line, '#');
        if (h) *h = 0;
        rc = parse_line(rp, line, ln, err);
    }
    if (rc) { st_replay_free(rp); return rc; }
    *out = rp;
    return 0;
}

int st_replay_load(st_replay **out, const char *path, st_error *err)
{
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) return st_fail(err, ST_ERR_IO, "cannot open %s", path);
    char *buf = NULL;
    size_t n = 0, cap = 0, r;
    do {
        if (n == cap) {
            char *q = cap < (64u << 20) ? realloc(buf, cap = cap ? 2 * cap : 65536) : NULL;
            if (!q) { free(buf); fclose(f); return st_fail(err, ST_ERR_MEMORY, "%s: out of memory or larger than 64 MB", path); }
            buf = q;
        }
        r = fread(buf + n, 1, cap - n, f);
        n += r;
    } while (r);
    int bad = ferror(f);
    fclose(f);
    int rc = bad ? st_fail(err, ST_ERR_IO, "cannot read %s", path) : st_replay_parse(out, path, buf, n, err);
    free(buf);
    return rc;
}

#ifndef ST_REPLAY_PARSE_ONLY
/* ---- running ------------------------------------------------------------------ */

static void snapshot(st_replay *rp, const st_app *a)
{
    const st_rgeom *g = &a->r.surf;
    free(rp->snap);
    rp->snap = malloc((size_t)(g->nverts ? g->nverts : 1) * 3 * sizeof *rp->snap);
    rp->nsnap = 0;
    rp->has_snap = rp->snap != NULL;
    if (!rp->snap) return;
    for (uint32_t i = 0; i < g->nverts; i++)
        memcpy(rp->snap + 3 * (size_t)i, g->vdata + (size_t)i * ST_RGEOM_VSTRIDE, 3 * sizeof(float));
    rp->nsnap = g->nverts;
}

/* 1: the displayed positions differ from the snapshot; 0: same; -1: the
 * vertex count changed. */
static int moved(const st_replay *rp, const st_app *a)
{
    const st_rgeom *g = &a->r.surf;
    if (!rp->has_snap || g->nverts != rp->nsnap) return -1;
    for (uint32_t i = 0; i < g->nverts; i++)
        for (int k = 0; k < 3; k++)
            if (fabsf(rp->snap[3 * (size_t)i + k] - g->vdata[(size_t)i * ST_RGEOM_VSTRIDE + k]) > 1e-7f) return 1;
    return 0;
}

/* Largest difference between what the renderer holds for g (built from
 * level l of m, then updated incrementally) and a fresh build; -1 when the
 * vertex sets differ or memory runs out. */
static double rgeom_drift(const st_rgeom *g, const st_map *m, unsigned l)
{
    st_rgeom f;
    st_rgeom_init(&f);
    st_error err;
    if (st_rgeom_build(&f, m, l, &err)) return -1;
    /* (After box moves, g may keep vertices no face draws any more.) */
    uint32_t drawn = 0;
    for (uint32_t i = 0; i < g->nverts; i++) drawn += (uint32_t)st_rgeom_vertex_drawn(g, m, i);
    double worst = f.nverts == drawn ? 0 : -1;
    for (uint32_t i = 0; worst >= 0 && i < g->nverts; i++) {
        uint32_t v = g->vid[i];
        if (!st_rgeom_vertex_drawn(g, m, i)) continue;
        if (v >= f.nvids || f.slot[v] == ST_NIL) { worst = -1; break; }
        const float *p = g->vdata + (size_t)i * ST_RGEOM_VSTRIDE, *q = f.vdata + (size_t)f.slot[v] * ST_RGEOM_VSTRIDE;
        for (int k = 0; k < ST_RGEOM_VSTRIDE; k++) {
            double dd = fabs((double)p[k] - q[k]);
            if (dd > worst) worst = dd;
        }
    }
    st_rgeom_free(&f);
    return worst;
}

static int expect(st_replay *rp, st_app *a, const ev *e)
{
    const st_doc *d = &a->doc;
    const char *w = e->text;
    char actual[768] = "";
    int ok;
    long want = e->arg ? strtol(e->arg, NULL, 10) : 0;
    uint64_t faces = 0, verts = 0;
    if (d->loaded) st_doc_display_counts(d, &faces, &verts);
    if (!strcmp(w, "edit_level")) { snprintf(actual, sizeof actual, "%u", st_doc_sculpt_level(d)); ok = (long)st_doc_sculpt_level(d) == want; }
    else if (!strcmp(w, "hd_faces")) {
        /* faces stored at the HD levels; "+": at least one */
        uint64_t hf = d->loaded ? st_doc_hd_faces(d) : 0;
        snprintf(actual, sizeof actual, "%llu", (unsigned long long)hf);
        ok = e->arg && !strcmp(e->arg, "+") ? hf > 0 : (long)hf == want;
    }
    else if (!strcmp(w, "display_level")) { snprintf(actual, sizeof actual, "%u", d->display_level); ok = (long)d->display_level == want; }
    else if (!strcmp(w, "top") || !strcmp(w, "levels")) { snprintf(actual, sizeof actual, "%u", d->h.map.top); ok = (long)d->h.map.top == want; }
    else if (!strcmp(w, "selected")) { snprintf(actual, sizeof actual, "%u", d->nsel); ok = (long)d->nsel == want; }
    else if (!strcmp(w, "undo_depth")) { snprintf(actual, sizeof actual, "%u", d->undo_pos); ok = (long)d->undo_pos == want; }
    else if (!strcmp(w, "redo_depth")) { snprintf(actual, sizeof actual, "%u", d->nundo - d->undo_pos); ok = (long)(d->nundo - d->undo_pos) == want; }
    else if (!strcmp(w, "box_on")) { snprintf(actual, sizeof actual, "%d", d->box_on); ok = d->box_on == want; }
    else if (!strcmp(w, "hover")) { snprintf(actual, sizeof actual, "%d", a->hover_vid != ST_NIL); ok = (a->hover_vid != ST_NIL) == (want != 0); }
    else if (!strcmp(w, "faces")) { snprintf(actual, sizeof actual, "%llu", (unsigned long long)faces); ok = (long)faces == want; }
    else if (!strcmp(w, "tool")) {
        /* '_' for a space: expect tool clay_strips */
        snprintf(actual, sizeof actual, "%s", a->tool == ST_TOOL_SELECT ? "select" : st_brush_name(a->tool));
        for (char *q = actual; *q; q++) if (*q == ' ') *q = '_';
        ok = e->arg && !strcasecmp(actual, e->arg);
    } else if (!strcmp(w, "wire") || !strcmp(w, "cage")) {
        int on = !strcmp(w, "wire") ? a->wire : a->cage;
        snprintf(actual, sizeof actual, "%d", on);
        ok = on == (want != 0);
    } else if (!strcmp(w, "brush_strength")) {
        /* In hundredths: expect brush_strength 30 */
        long got = lround(100 * d->brush.strength);
        snprintf(actual, sizeof actual, "%ld", got);
        ok = got == want;
    } else if (!strcmp(w, "falloff")) {
        snprintf(actual, sizeof actual, "%s", st_falloff_name(d->brush.falloff));
        ok = e->arg && !strcmp(actual, e->arg);
    } else if (!strcmp(w, "symmetry")) {
        snprintf(actual, sizeof actual, "%s%s%s", d->brush.mirror_x ? "x" : "", d->brush.mirror_y ? "y" : "",
                 d->brush.mirror_z ? "z" : "");
        if (!actual[0]) snprintf(actual, sizeof actual, "none");
        ok = e->arg && !strcmp(actual, e->arg);
    } else if (!strcmp(w, "stabilize") || !strcmp(w, "front")) {
        int on = !strcmp(w, "front") ? d->brush.front_only : d->brush.stabilize;
        snprintf(actual, sizeof actual, "%d", on != 0);
        ok = (on != 0) == (want != 0);
    } else if (!strcmp(w, "scheme")) {
        snprintf(actual, sizeof actual, "%s", d->scheme ? d->scheme->name : "none");
        ok = e->arg && !strcmp(actual, e->arg);
    } else if (!strcmp(w, "moved") || !strcmp(w, "unchanged")) {
        int m = moved(rp, a);
        snprintf(actual, sizeof actual, "%s", m < 0 ? "vertex count changed since the snapshot" : m ? "moved" : "unchanged");
        ok = !strcmp(w, "moved") ? m == 1 : m == 0;
    } else if (!strcmp(w, "synced")) {
        /* The renderer's incrementally updated buffers equal a fresh build
         * of the displayed and editing levels (positions and normals). */
        double ds = a->r.has_surf ? rgeom_drift(&a->r.surf, &st_doc_display_hier(d)->map, st_doc_display_map_level(d)) : 0;
        unsigned cl;
        const st_map *cm = st_doc_cage_map(d, &cl);
        double dc = a->r.has_cage ? rgeom_drift(&a->r.cage, cm, cl) : 0;
        snprintf(actual, sizeof actual, "surface off by %g, cage off by %g", ds, dc);
        ok = ds >= 0 && dc >= 0 && ds < 1e-5 && dc < 1e-5;
    } else if (!strcmp(w, "patched")) {
        /* At least N box moves were drawn by st_renderer_patch. */
        snprintf(actual, sizeof actual, "%llu", (unsigned long long)a->patches);
        ok = a->patches >= (uint64_t)want;
    } else if (!strcmp(w, "error")) {
        snprintf(actual, sizeof actual, "%d (%s)", a->msg_error, a->msg);
        ok = a->msg_error == (want != 0);
    } else if (!strcmp(w, "checker")) {
        /* The UV checker is drawn: switched on and UVs uploaded. */
        int on = a->checker && a->r.has_uv;
        snprintf(actual, sizeof actual, "%d (asked %d)", on, a->checker);
        ok = on == (want != 0);
    } else if (!strcmp(w, "box_max")) {
        /* The document's box maximum level (what is computed, not what a
         * slider shows). */
        snprintf(actual, sizeof actual, "%u", d->box.max_level);
        ok = (long)d->box.max_level == want;
    } else if (!strcmp(w, "dialog_dir")) {
        /* The file dialog's folder (its last component). */
        snprintf(actual, sizeof actual, "%s", st_gui_dialog_dir());
        ok = e->arg && !strcmp(actual, e->arg);
    } else if (!strcmp(w, "dialog")) {
        /* The question up: quit (save before quitting?), scheme, or none. */
        const char *up = a->quit_asking ? "quit" : a->pending_scheme ? "scheme" : st_gui_bake_shown() ? "bake" : "none";
        snprintf(actual, sizeof actual, "%s", up);
        ok = e->arg && !strcmp(e->arg, up);
    } else if (!strcmp(w, "baked") || !strcmp(w, "baked_view")) {
        /* A normal map baked for this model / the view showing it. */
        int on = !strcmp(w, "baked") ? st_app_can_show_baked(a) : a->bake.show && st_app_can_show_baked(a);
        snprintf(actual, sizeof actual, "%d", on);
        ok = on == (want != 0);
    } else if (!strcmp(w, "centred")) {
        /* The model's bounding-box centre projects to the middle of the part
         * of the window the side panel leaves free (within 2 % of its width). */
        const float *bb = a->r.surf.bbox;
        double c[3] = { 0.5 * (bb[0] + bb[3]), 0.5 * (bb[1] + bb[4]), 0.5 * (bb[2] + bb[5]) }, s[2];
        double panel = a->win_w > 0 ? st_gui_panel_pixels(a->win_w) * a->fb_w / a->win_w : 0;
        double free_w = a->fb_w - panel;
        int in = st_camctl_project(&a->cc, a->fb_w, a->fb_h, c, s, NULL) != 0;
        snprintf(actual, sizeof actual, "centre at x %.1f of a free part 0..%.1f", in ? s[0] : -1, free_w);
        ok = in && fabs(s[0] - 0.5 * free_w) <= 0.02 * free_w;
    } else if (!strcmp(w, "recovery")) {
        /* The recovery file holds every completed step (session_io.c). */
        char rec[4096];
        struct stat st;
        int held = !st_session_recovery_path(rec, sizeof rec) && !stat(rec, &st) && a->recovery_revision == d->revision;
        snprintf(actual, sizeof actual, "%d", held);
        ok = held == (want != 0);
    } else if (!strcmp(w, "unsaved")) {
        snprintf(actual, sizeof actual, "%d", st_app_unsaved(a));
        ok = st_app_unsaved(a) == (want != 0);
    } else if (!strcmp(w, "gui")) {
        snprintf(actual, sizeof actual, "%d", st_gui_shown());
        ok = st_gui_shown() == (want != 0);
    } else if (!strcmp(w, "file")) {
        struct stat st;
        int there = e->arg && !stat(e->arg, &st) && st.st_size > 0;
        snprintf(actual, sizeof actual, "%s", there ? "a non-empty file" : "missing or empty");
        ok = there;
    } else if (!strcmp(w, "undo_name") || !strcmp(w, "redo_name")) {
        /* What the Edit menu's Undo / Redo names ('_' for a space; none: "-"). */
        const char *n = !strcmp(w, "undo_name") ? st_doc_undo_name(d) : st_doc_redo_name(d);
        snprintf(actual, sizeof actual, "%s", n ? n : "-");
        for (char *c = actual; *c; c++) if (*c == ' ') *c = '_';
        ok = e->arg && !strcmp(actual, e->arg);
    } else if (!strcmp(w, "layers")) {
        snprintf(actual, sizeof actual, "%u", d->layers.n);
        ok = (long)d->layers.n == want;
    } else if (!strcmp(w, "active_layer")) {
        snprintf(actual, sizeof actual, "%d", d->layers.active);
        ok = d->layers.active == want;
    } else if (!strcmp(w, "layer_strength")) {
        /* The active layer's strength, in hundredths. */
        int k = d->layers.active;
        long s100 = k >= 0 && (uint32_t)k < d->layers.n ? lround(100 * d->layers.v[k].strength) : -1;
        snprintf(actual, sizeof actual, "%ld", s100);
        ok = s100 == want;
    } else if (!strcmp(w, "masked")) {
        /* Vertices of the editing level with a mask above 0; "masked +"
         * asks for at least one. */
        long n = 0;
        st_dart_iter it;
        if (d->loaded)
            for (uint32_t v = st_vertex_first(&d->h.map, d->edit_level, &it); v != ST_NIL;
                 v = st_vertex_next(&d->h.map, d->edit_level, &it))
                n += st_doc_mask(d, v) > 0;
        snprintf(actual, sizeof actual, "%ld", n);
        ok = e->arg && !strcmp(e->arg, "+") ? n > 0 : n == want;
    } else if (!strcmp(w, "message")) {
        snprintf(actual, sizeof actual, "'%s'", a->msg);
        ok = e->arg && strstr(a->msg, e->arg) != NULL;
    } else {
        fprintf(stderr, "strata: %s:%d: unknown expectation '%s'\n", rp->path, e->line, w);
        return -1;
    }
    if (!ok) {
        fprintf(stderr, "strata: %s:%d: expect %s %s failed: actual %s\n", rp->path, e->line, w, e->arg ? e->arg : "", actual);
        return -1;
    }
    return 0;
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* One sample of `time_frames` (the frame just drawn); the median and the
 * mean at the last. */
static void time_frame(st_replay *rp, const st_app *a)
{
    rp->times[rp->ntimes++] = a->frame_ms;
    if (--rp->timing_left) return;
    double sum = 0;
    for (int i = 0; i < rp->ntimes; i++) sum += rp->times[i];
    qsort(rp->times, (size_t)rp->ntimes, sizeof *rp->times, cmp_double);
    fprintf(stderr, "strata: replay: %d frames (GUI %s): median %.3f ms, mean %.3f ms\n", rp->ntimes,
            st_gui_shown() ? "shown" : "hidden", rp->times[rp->ntimes / 2], sum / rp->ntimes);
    free(rp->times);
    rp->times = NULL;
}

int st_replay_step(st_replay *rp, st_app *a)
{
    if (rp->timing_left) { time_frame(rp, a); return 0; }
    if (!rp->has_snap && a->doc.loaded) snapshot(rp, a);
    if (rp->pos >= rp->n) return 1;
    const ev *e = &rp->e[rp->pos++];
    GLFWwindow *w = a->win;
    switch (e->type) {
    case EV_WAIT: break;
    case EV_KEY: st_win_on_key(w, e->key, 0, e->action, e->mods); break;
    case EV_MOVE: st_win_on_cursor(w, e->x, e->y); break;
    case EV_BUTTON: st_win_on_mouse_button(w, e->button, e->action, e->mods); break;
    case EV_SCROLL: st_win_on_scroll(w, 0, e->y); break;
    case EV_SCROLL_CLICK:
        /* What a slow frame receives when a click follows a wheel at once. */
        st_win_on_scroll(w, 0, e->y);
        st_win_on_mouse_button(w, GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
        st_win_on_mouse_button(w, GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
        break;
    case EV_DROP: { const char *p[1] = { e->text }; st_win_on_drop(w, 1, p); break; }
    case EV_LEVEL:
        if (e->which) st_doc_set_display_level(&a->doc, (unsigned)e->x);
        else st_doc_set_edit_level(&a->doc, (unsigned)e->x);
        st_app_sync(a);
        break;
    case EV_SNAPSHOT: st_app_sync(a); snapshot(rp, a); break;
    case EV_SHOT:
        snprintf(a->shot, sizeof a->shot, "%s", e->text);
        a->shot_pending = 1;
        break;
    case EV_EXPECT:
        st_app_sync(a);
        if (expect(rp, a, e)) return -1;
        break;
    case EV_ECHO: fprintf(stderr, "strata: replay: %s\n", e->text); break;
    case EV_QUIT: return 1;
    case EV_BRUSH: {
        st_brush *b = &a->doc.brush;
        switch (e->which) {
        case BR_FALLOFF: b->falloff = e->key; break;
        case BR_SPACING: b->spacing = e->x; break;
        case BR_STABILIZE: b->stabilize = e->key; if (e->x > 0) b->stabilize_dist = e->x; break;
        case BR_SYMMETRY: b->mirror_x = e->key & 1; b->mirror_y = e->key >> 1 & 1; b->mirror_z = e->key >> 2 & 1; break;
        case BR_FRONT: b->front_only = e->key; break;
        case BR_STRENGTH: b->strength = e->x; break;
        case BR_RADIUS: b->radius = e->x; break;
        default: break;
        }
        break;
    }
    case EV_GUI: st_gui_set_shown(e->which); break;
    case EV_FILTER: {
        double g[ST_MAX_LEVELS];
        int n = parse_gains(e->text, g);
        st_app_filter(a, g, n > 0 ? (unsigned)n : 0); /* a refusal is the status line's */
        break;
    }
    case EV_FRAMES:
        free(rp->times);
        if (!(rp->times = malloc((size_t)e->which * sizeof *rp->times))) return -1;
        rp->ntimes = 0;
        rp->timing_left = e->which;
        break;
    case EV_BAKE: {
        char msg[512];
        if (st_gui_bake_set(a, e->text, e->arg, msg, sizeof msg)) {
            fprintf(stderr, "strata: %s:%d: bake %s: %s\n", rp->path, e->line, e->text, msg);
            return -1;
        }
        break;
    }
    case EV_MENU: {
        char msg[512];
        if (st_gui_menu_activate(a, e->text, e->arg, msg, sizeof msg)) {
            fprintf(stderr, "strata: %s:%d: menu %s: %s\n", rp->path, e->line, e->text, msg);
            return -1;
        }
        break;
    }
    default: break;
    }
    return 0;
}

#endif /* ST_REPLAY_PARSE_ONLY */
