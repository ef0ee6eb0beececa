/* The modeller's action table (ui/actions.h), without opening a window:
 * every action complete, no two shortcuts of a context matching the same
 * press, every shortcut reaching its action, the bindings of the former
 * if-chain (key, modifiers -> what ran) unchanged, the F1 rows covering
 * every action and gesture, docs/MODELLER.md's key table equal to the generated
 * one, and the key dispatch of a window state (contexts, enabled-when). */
#include "actions.h"
#include "window.h"
#include "testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#define C ST_MOD_CTRL
#define S ST_MOD_SHIFT
#define A ST_MOD_ALT
#define SUPER 0x8   /* GLFW_MOD_SUPER: never considered */

static void test_entries(void)
{
    for (unsigned i = 0; i < ST_NACTIONS; i++) {
        const st_action *act = &st_actions[i];
        CHECKF(act->id == (int)i, "entry %u has id %d", i, act->id);
        CHECKF(act->name && act->name[0], "action %u has no name", i);
        CHECKF(act->help && act->help[0], "action %u (%s) has no help text", i, act->name ? act->name : "?");
        CHECKF(act->run != NULL, "action %u (%s) has no handler", i, act->name ? act->name : "?");
        CHECKF(st_category_name(act->category) != NULL, "action %u: category %d", i, act->category);
        CHECKF(st_context_name(act->context) != NULL, "action %u: context %d", i, act->context);
        CHECKF(act->keys[0].key != 0, "action %u (%s) has no shortcut", i, act->name ? act->name : "?");
        int ended = 0;
        for (int k = 0; k < ST_ACTION_KEYS; k++) {
            const st_shortcut *s = &act->keys[k];
            if (!s->key) { ended = 1; continue; }
            CHECKF(!ended, "action %s: shortcut %d after the end of its list", act->name, k);
            CHECKF((s->mods & ~ST_MODS) == 0 && (s->tolerate & ~ST_MODS) == 0 && (s->mods & s->tolerate) == 0,
                   "action %s: shortcut %d modifiers %x tolerate %x", act->name, k, s->mods, s->tolerate);
            char name[64];
            CHECKF(st_shortcut_format(s, name, sizeof name) > 0, "action %s: key %d has no printable name", act->name, s->key);
        }
        /* Menus show names: no two alike. */
        for (unsigned j = 0; j < i; j++)
            CHECKF(strcmp(st_actions[j].name, act->name) != 0, "two actions named '%s'", act->name);
    }
}

/* No press matches two shortcuts of one context: every key in use, every
 * combination of modifiers (Super included), counted by brute force; and
 * st_shortcuts_overlap says the same for every pair. */
static void test_no_conflicts(void)
{
    for (unsigned i = 0; i < ST_NACTIONS; i++)
        for (int k = 0; k < ST_ACTION_KEYS && st_actions[i].keys[k].key; k++) {
            const st_shortcut *s = &st_actions[i].keys[k];
            for (int m = 0; m < 16; m++) {
                unsigned n = 0;
                const char *other = NULL;
                for (unsigned j = 0; j < ST_NACTIONS; j++) {
                    if (st_actions[j].context != st_actions[i].context) continue;
                    for (int q = 0; q < ST_ACTION_KEYS && st_actions[j].keys[q].key; q++)
                        if (st_shortcut_matches(&st_actions[j].keys[q], s->key, m)) {
                            n++;
                            if (j != i) other = st_actions[j].name;
                        }
                }
                CHECKF(n <= 1, "key %d with modifiers %x: %s and %s both match", s->key, m, st_actions[i].name,
                       other ? other : "itself twice");
            }
            for (unsigned j = 0; j < ST_NACTIONS; j++) {
                if (st_actions[j].context != st_actions[i].context) continue;
                for (int q = 0; q < ST_ACTION_KEYS && st_actions[j].keys[q].key; q++) {
                    const st_shortcut *t = &st_actions[j].keys[q];
                    if (t == s) continue;
                    int both = 0;
                    for (int m = 0; m < 16; m++)
                        both |= st_shortcut_matches(s, t->key, m) && st_shortcut_matches(t, t->key, m);
                    CHECKF(st_shortcuts_overlap(s, t) == both, "%s / %s: overlap %d, brute force %d",
                           st_actions[i].name, st_actions[j].name, st_shortcuts_overlap(s, t), both);
                }
            }
        }
}

/* Every shortcut reaches its own action (none is shadowed). */
static void test_reachable(void)
{
    for (unsigned i = 0; i < ST_NACTIONS; i++)
        for (int k = 0; k < ST_ACTION_KEYS && st_actions[i].keys[k].key; k++) {
            const st_shortcut *s = &st_actions[i].keys[k];
            const st_action *got = st_action_for_key(st_actions[i].context, s->key, s->mods);
            CHECKF(got == &st_actions[i], "shortcut %d of %s reaches %s", k, st_actions[i].name, got ? got->name : "nothing");
            got = st_action_for_key(st_actions[i].context, s->key, s->mods | s->tolerate | SUPER);
            CHECKF(got == &st_actions[i], "shortcut %d of %s with its tolerated modifiers reaches %s", k,
                   st_actions[i].name, got ? got->name : "nothing");
        }
}

/* The window's bindings as the if-chain of ui/window.c's key_press handled
 * them before the table (key, modifiers -> action, -1: nothing). */
static const struct { int key, mods, id; } window_keys[] = {
    { GLFW_KEY_F1, 0, ST_ACT_HELP }, { GLFW_KEY_F1, C | S | A, ST_ACT_HELP },
    { GLFW_KEY_Q, C, ST_ACT_QUIT }, { GLFW_KEY_Q, C | S, ST_ACT_QUIT }, { GLFW_KEY_Q, 0, -1 }, { GLFW_KEY_Q, S, -1 },
    { GLFW_KEY_ESCAPE, 0, ST_ACT_CANCEL }, { GLFW_KEY_ESCAPE, S, ST_ACT_CANCEL },
    { GLFW_KEY_ENTER, 0, ST_ACT_GRAB_CONFIRM }, { GLFW_KEY_KP_ENTER, C, ST_ACT_GRAB_CONFIRM },
    { GLFW_KEY_HOME, 0, ST_ACT_FRAME_ALL }, { GLFW_KEY_HOME, C, ST_ACT_FRAME_ALL },
    { GLFW_KEY_1, 0, ST_ACT_VIEW_FRONT }, { GLFW_KEY_1, S, ST_ACT_VIEW_FRONT }, { GLFW_KEY_KP_1, A, ST_ACT_VIEW_FRONT },
    { GLFW_KEY_1, C, ST_ACT_VIEW_BACK }, { GLFW_KEY_KP_1, C | S, ST_ACT_VIEW_BACK },
    { GLFW_KEY_3, 0, ST_ACT_VIEW_RIGHT }, { GLFW_KEY_KP_3, C, ST_ACT_VIEW_LEFT },
    { GLFW_KEY_KP_7, 0, ST_ACT_VIEW_TOP }, { GLFW_KEY_7, C | A, ST_ACT_VIEW_BOTTOM },
    { GLFW_KEY_5, C, ST_ACT_PROJECTION }, { GLFW_KEY_KP_5, 0, ST_ACT_PROJECTION },
    { GLFW_KEY_KP_4, 0, ST_ACT_ORBIT_LEFT }, { GLFW_KEY_KP_6, C, ST_ACT_ORBIT_RIGHT },
    { GLFW_KEY_KP_8, S, ST_ACT_ORBIT_UP }, { GLFW_KEY_KP_2, 0, ST_ACT_ORBIT_DOWN },
    { GLFW_KEY_PAGE_UP, 0, ST_ACT_EDIT_LEVEL_UP }, { GLFW_KEY_KP_ADD, 0, ST_ACT_EDIT_LEVEL_UP },
    { GLFW_KEY_EQUAL, 0, ST_ACT_EDIT_LEVEL_UP }, { GLFW_KEY_PAGE_DOWN, 0, ST_ACT_EDIT_LEVEL_DOWN },
    { GLFW_KEY_KP_SUBTRACT, 0, ST_ACT_EDIT_LEVEL_DOWN }, { GLFW_KEY_MINUS, 0, ST_ACT_EDIT_LEVEL_DOWN },
    { GLFW_KEY_PAGE_UP, S, ST_ACT_DISPLAY_LEVEL_UP }, { GLFW_KEY_MINUS, S, ST_ACT_DISPLAY_LEVEL_DOWN },
    { GLFW_KEY_PAGE_UP, C, -1 }, { GLFW_KEY_PAGE_UP, A, -1 }, { GLFW_KEY_PAGE_DOWN, C | S, -1 },
    { GLFW_KEY_D, C, ST_ACT_ADD_LEVEL }, { GLFW_KEY_D, C | SUPER, ST_ACT_ADD_LEVEL },
    { GLFW_KEY_D, C | S, ST_ACT_DELETE_FINEST }, { GLFW_KEY_D, C | S | A, ST_ACT_DELETE_FINEST },
    { GLFW_KEY_D, C | A, ST_ACT_DELETE_COARSEST },
    { GLFW_KEY_D, 0, ST_ACT_BRUSH_DRAW }, { GLFW_KEY_D, S, ST_ACT_BRUSH_DRAW }, { GLFW_KEY_D, A, ST_ACT_BRUSH_DRAW },
    { GLFW_KEY_Z, C, ST_ACT_UNDO }, { GLFW_KEY_Z, C | A, ST_ACT_UNDO },
    { GLFW_KEY_Z, C | S, ST_ACT_REDO }, { GLFW_KEY_Z, C | S | A, ST_ACT_REDO },
    { GLFW_KEY_Y, C, ST_ACT_REDO }, { GLFW_KEY_Y, C | S, ST_ACT_REDO }, { GLFW_KEY_Y, 0, -1 },
    { GLFW_KEY_Z, 0, ST_ACT_SHADING }, { GLFW_KEY_Z, A, ST_ACT_SHADING },
    { GLFW_KEY_Z, S, ST_ACT_WIREFRAME }, { GLFW_KEY_Z, S | A, ST_ACT_WIREFRAME },
    { GLFW_KEY_S, C, ST_ACT_SAVE }, { GLFW_KEY_S, C | S, ST_ACT_SAVE }, { GLFW_KEY_S, 0, ST_ACT_BRUSH_SMOOTH },
    { GLFW_KEY_R, C, ST_ACT_RESTORE_RECOVERY }, { GLFW_KEY_R, 0, -1 },
    { GLFW_KEY_W, 0, ST_ACT_TOOL_SELECT }, { GLFW_KEY_W, S, ST_ACT_TOOL_SELECT }, { GLFW_KEY_W, C, -1 },
    { GLFW_KEY_B, A, ST_ACT_BRUSH_GRAB }, { GLFW_KEY_F, 0, ST_ACT_BRUSH_FLATTEN }, { GLFW_KEY_F, C, -1 },
    { GLFW_KEY_X, 0, ST_ACT_MIRROR_X }, { GLFW_KEY_X, S, ST_ACT_MIRROR_X }, { GLFW_KEY_X, C, -1 },
    { GLFW_KEY_LEFT_BRACKET, 0, ST_ACT_RADIUS_DOWN }, { GLFW_KEY_LEFT_BRACKET, A, ST_ACT_RADIUS_DOWN },
    { GLFW_KEY_LEFT_BRACKET, S, ST_ACT_STRENGTH_DOWN }, { GLFW_KEY_RIGHT_BRACKET, 0, ST_ACT_RADIUS_UP },
    { GLFW_KEY_RIGHT_BRACKET, S | A, ST_ACT_STRENGTH_UP }, { GLFW_KEY_RIGHT_BRACKET, C, -1 },
    { GLFW_KEY_G, 0, ST_ACT_GRAB }, { GLFW_KEY_G, S, ST_ACT_GRAB }, { GLFW_KEY_G, C, -1 },
    { GLFW_KEY_A, 0, ST_ACT_SELECT_ALL }, { GLFW_KEY_A, S, ST_ACT_SELECT_ALL },
    { GLFW_KEY_A, A, ST_ACT_SELECT_NONE }, { GLFW_KEY_A, A | S, ST_ACT_SELECT_NONE }, { GLFW_KEY_A, C, -1 },
    { GLFW_KEY_C, 0, ST_ACT_CAGE }, { GLFW_KEY_C, A, ST_ACT_CAGE }, { GLFW_KEY_C, C, -1 },
    { GLFW_KEY_K, 0, ST_ACT_CHANGE_SCHEME }, { GLFW_KEY_K, S, ST_ACT_CHANGE_SCHEME }, { GLFW_KEY_K, C, -1 },
    { GLFW_KEY_I, 0, ST_ACT_BOX_TOGGLE }, { GLFW_KEY_I, C, -1 },
    { GLFW_KEY_LEFT, 0, ST_ACT_BOX_MOVE_XN }, { GLFW_KEY_LEFT, A, ST_ACT_BOX_MOVE_XN },
    { GLFW_KEY_LEFT, S, ST_ACT_BOX_SHRINK_X }, { GLFW_KEY_RIGHT, S | A, ST_ACT_BOX_GROW_X },
    { GLFW_KEY_RIGHT, 0, ST_ACT_BOX_MOVE_XP }, { GLFW_KEY_UP, 0, ST_ACT_BOX_MOVE_YP },
    { GLFW_KEY_UP, A, ST_ACT_BOX_MOVE_ZP }, { GLFW_KEY_UP, S, ST_ACT_BOX_GROW_Y }, { GLFW_KEY_UP, S | A, ST_ACT_BOX_GROW_Z },
    { GLFW_KEY_DOWN, 0, ST_ACT_BOX_MOVE_YN }, { GLFW_KEY_DOWN, A, ST_ACT_BOX_MOVE_ZN },
    { GLFW_KEY_DOWN, S, ST_ACT_BOX_SHRINK_Y }, { GLFW_KEY_DOWN, A | S, ST_ACT_BOX_SHRINK_Z }, { GLFW_KEY_DOWN, C, -1 },
    { GLFW_KEY_PERIOD, 0, ST_ACT_BOX_MAX_UP }, { GLFW_KEY_PERIOD, A, ST_ACT_BOX_MAX_UP },
    { GLFW_KEY_PERIOD, S, ST_ACT_BOX_BASE_UP }, { GLFW_KEY_COMMA, 0, ST_ACT_BOX_MAX_DOWN },
    { GLFW_KEY_COMMA, S, ST_ACT_BOX_BASE_DOWN }, { GLFW_KEY_COMMA, C, -1 }, { GLFW_KEY_U, C | A, ST_ACT_PREFERENCES },
    { GLFW_KEY_N, 0, -1 }, { GLFW_KEY_E, 0, -1 }, { GLFW_KEY_TAB, 0, -1 },
};

/* The scheme question, as before: K proposes the next, Y or Enter rebuilds
 * (any modifiers), anything else keeps the scheme. */
static const struct { int key, mods, id; } question_keys[] = {
    { GLFW_KEY_K, 0, ST_ACT_SCHEME_NEXT }, { GLFW_KEY_K, C | S, ST_ACT_SCHEME_NEXT },
    { GLFW_KEY_Y, 0, ST_ACT_SCHEME_CONFIRM }, { GLFW_KEY_Y, C, ST_ACT_SCHEME_CONFIRM },
    { GLFW_KEY_ENTER, 0, ST_ACT_SCHEME_CONFIRM }, { GLFW_KEY_N, 0, ST_ACT_SCHEME_KEEP },
    { GLFW_KEY_KP_ENTER, 0, -1 }, { GLFW_KEY_D, C, -1 }, { GLFW_KEY_F1, 0, -1 },
};

static void test_former_bindings(void)
{
    for (size_t i = 0; i < sizeof window_keys / sizeof window_keys[0]; i++) {
        const st_action *got = st_action_for_key(ST_KEYS_WINDOW, window_keys[i].key, window_keys[i].mods);
        int id = got ? got->id : -1;
        CHECKF(id == window_keys[i].id, "window key %d mods %x: %s, expected %s", window_keys[i].key, window_keys[i].mods,
               got ? got->name : "nothing", window_keys[i].id >= 0 ? st_actions[window_keys[i].id].name : "nothing");
    }
    for (size_t i = 0; i < sizeof question_keys / sizeof question_keys[0]; i++) {
        const st_action *got = st_action_for_key(ST_KEYS_SCHEME_QUESTION, question_keys[i].key, question_keys[i].mods);
        CHECKF((got ? got->id : -1) == question_keys[i].id, "question key %d mods %x: %s", question_keys[i].key,
               question_keys[i].mods, got ? got->name : "nothing");
    }
}

static void test_names(void)
{
    static const struct { st_shortcut s; const char *name; } cases[] = {
        { { GLFW_KEY_D, C | S, 0 }, "Ctrl+Shift+D" }, { { GLFW_KEY_D, C | A, 0 }, "Ctrl+Alt+D" },
        { { GLFW_KEY_UP, A | S, 0 }, "Alt+Shift+Up" }, { { GLFW_KEY_KP_1, C, S | A }, "Ctrl+Numpad 1" },
        { { GLFW_KEY_LEFT_BRACKET, S, A }, "Shift+[" }, { { GLFW_KEY_PAGE_DOWN, 0, 0 }, "PageDown" },
        { { GLFW_KEY_F1, 0, ST_MODS }, "F1" }, { { GLFW_KEY_7, 0, 0 }, "7" }, { { GLFW_KEY_ESCAPE, 0, 0 }, "Esc" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char buf[64];
        int n = st_shortcut_format(&cases[i].s, buf, sizeof buf);
        CHECKF(n == (int)strlen(cases[i].name) && !strcmp(buf, cases[i].name), "'%s', expected '%s'", buf, cases[i].name);
    }
    char small[6];
    const st_shortcut cs = { GLFW_KEY_D, C | S, 0 };
    st_shortcut_format(&cs, small, sizeof small);
    CHECK(!strcmp(small, "Ctrl+"));   /* cut, terminated */
    const st_shortcut unnamed = { GLFW_KEY_WORLD_1, 0, 0 };
    CHECK(st_shortcut_format(&unnamed, small, sizeof small) == -1);
}

/* F1: every action in exactly one row whose keys name all its shortcuts,
 * every gesture in a row, and everything fits the row buffer. */
static void test_help_rows(void)
{
    static st_help_row rows[ST_HELP_MAX_ROWS];
    unsigned n = st_help_rows(rows, ST_HELP_MAX_ROWS);
    CHECKF(n <= ST_HELP_MAX_ROWS, "%u help rows, room for %d", n, ST_HELP_MAX_ROWS);
    if (n > ST_HELP_MAX_ROWS) n = ST_HELP_MAX_ROWS;
    unsigned seen[ST_NACTIONS] = { 0 }, gestures = 0, headings = 0;
    for (unsigned r = 0; r < n; r++) {
        if (rows[r].heading) { headings++; continue; }
        CHECK(rows[r].what && rows[r].what[0] && rows[r].keys[0]);
        if (!rows[r].count) {
            for (unsigned g = 0; g < st_ngestures; g++)
                if (!strcmp(rows[r].keys, st_gestures[g].input) && rows[r].what == st_gestures[g].help) gestures++;
            continue;
        }
        CHECK(strlen(rows[r].keys) + 1 < sizeof rows[r].keys);   /* not cut */
        for (int i = rows[r].first; i < rows[r].first + rows[r].count; i++) {
            seen[i]++;
            CHECKF(!strcmp(st_actions[i].help, rows[r].what), "row %u: %s", r, st_actions[i].name);
            for (int k = 0; k < ST_ACTION_KEYS && st_actions[i].keys[k].key; k++) {
                char name[64];
                st_shortcut_format(&st_actions[i].keys[k], name, sizeof name);
                CHECKF(strstr(rows[r].keys, name) != NULL, "F1 row '%s' lacks %s of %s", rows[r].keys, name, st_actions[i].name);
            }
        }
    }
    for (unsigned i = 0; i < ST_NACTIONS; i++) CHECKF(seen[i] == 1, "%s in %u F1 rows", st_actions[i].name, seen[i]);
    CHECK(gestures == st_ngestures);
    CHECK(headings == 1 + ST_NCATEGORIES + (ST_NKEY_CONTEXTS - 1));
    /* Neighbours with the same help share a row: the brushes' keys. */
    char keys[160];
    st_help_row_keys(&st_actions[ST_ACT_BRUSH_GRAB], 4, 0, keys, sizeof keys);
    CHECKF(!strcmp(keys, "B / D / S / F"), "'%s'", keys);
    st_help_row_keys(&st_actions[ST_ACT_UNDO], 2, 1, keys, sizeof keys);
    CHECKF(!strcmp(keys, "`Ctrl+Z` / `Ctrl+Shift+Z` (or `Ctrl+Y`)"), "'%s'", keys);
}

/* docs/MODELLER.md's key table is what `strata --keys` prints. */
static void test_readme(void)
{
    const char *path = STRATA_ASSETS "/../docs/MODELLER.md";
    char *readme = tl_read_file(path, NULL);
    CHECKF(readme != NULL, "cannot read %s", path);
    if (!readme) return;
    FILE *f = tmpfile();
    CHECK(f != NULL);
    if (!f) { free(readme); return; }
    st_actions_markdown(f);
    long size = ftell(f);
    rewind(f);
    char *want = calloc((size_t)size + 1, 1);
    CHECK(want && fread(want, 1, (size_t)size, f) == (size_t)size);
    fclose(f);
    char *begin = strstr(readme, ST_KEYS_BEGIN), *end = begin ? strstr(begin, ST_KEYS_END) : NULL;
    CHECKF(begin && end, "%s has no key table between '%s' and '%s'", path, ST_KEYS_BEGIN, ST_KEYS_END);
    if (begin && end && want) {
        end += strlen(ST_KEYS_END);
        size_t len = (size_t)(end - begin);
        int same = len + 1 == strlen(want) && !memcmp(begin, want, len) && want[len] == '\n';
        if (!same) {
            /* The first line that differs. */
            const char *p = begin, *q = want;
            while (p < end && *q && *p == *q) p++, q++;
            while (p > begin && p[-1] != '\n') p--, q--;
            fprintf(stderr, "docs/MODELLER.md: %.*s\nexpected:  %.*s\n", (int)strcspn(p, "\n"), p, (int)strcspn(q, "\n"), q);
        }
        CHECKF(same, "docs/MODELLER.md's key table differs from ui/actions.c: "
                     "replace it by the output of `strata --keys`");
    }
    free(want);
    free(readme);
}

/* The dispatch on a window state without a window: the context (scheme
 * question or not) and enabled-when (no model, a drag under way).  Only
 * handlers that touch no GL run here; the replays of tests/cli/cli_window.sh
 * run the others through the real window. */
static void test_dispatch(void)
{
    st_app *a = calloc(1, sizeof *a);
    CHECK(a != NULL);
    if (!a) return;
    a->doc.brush.radius = 1.0;
    a->doc.brush.strength = 0.5;
    /* No model: model actions are disabled, help and quit are not. */
    CHECK(st_app_key(a, GLFW_KEY_X, 0) == NULL && !a->doc.brush.mirror_x);
    CHECK(st_app_key(a, GLFW_KEY_F1, 0) == &st_actions[ST_ACT_HELP] && a->help == 1);
    CHECK(st_app_key(a, GLFW_KEY_ESCAPE, 0) == &st_actions[ST_ACT_CANCEL] && a->help == 0);
    a->doc.loaded = 1;
    CHECK(st_app_key(a, GLFW_KEY_X, S) == &st_actions[ST_ACT_MIRROR_X] && a->doc.brush.mirror_x);
    CHECK(st_app_key(a, GLFW_KEY_RIGHT_BRACKET, 0) == &st_actions[ST_ACT_RADIUS_UP] && a->doc.brush.radius == 1.15);
    CHECK(st_app_key(a, GLFW_KEY_LEFT_BRACKET, S) == &st_actions[ST_ACT_STRENGTH_DOWN] && fabs(a->doc.brush.strength - 0.45) < 1e-12);
    CHECK(st_app_key(a, GLFW_KEY_ENTER, 0) == NULL);          /* no grab under way */
    /* Keys wait for the mouse during a drag, except help and quit. */
    a->op = ST_OP_DRAG;
    CHECK(st_app_key(a, GLFW_KEY_X, 0) == NULL && a->doc.brush.mirror_x);
    CHECK(st_app_key(a, GLFW_KEY_F1, 0) == &st_actions[ST_ACT_HELP] && a->help == 1);
    a->op = ST_OP_ORBIT;
    CHECK(st_app_key(a, GLFW_KEY_X, 0) == &st_actions[ST_ACT_MIRROR_X] && !a->doc.brush.mirror_x);
    a->op = ST_OP_NONE;
    /* The scheme question takes every key: K cycles, any other says no. */
    a->pending_scheme = "loop";
    CHECK(st_app_key(a, GLFW_KEY_K, C) == &st_actions[ST_ACT_SCHEME_NEXT] && !strcmp(a->pending_scheme, "butterfly"));
    CHECK(st_app_key(a, GLFW_KEY_X, 0) == &st_actions[ST_ACT_SCHEME_KEEP] && a->pending_scheme == NULL);
    CHECK(!a->doc.brush.mirror_x);   /* X answered the question, the mirror is unchanged */
    a->pending_scheme = "doo-sabin";
    CHECK(st_app_key(a, GLFW_KEY_K, 0) == &st_actions[ST_ACT_SCHEME_NEXT] && !strcmp(a->pending_scheme, "catmull-clark"));
    CHECK(st_app_key(a, GLFW_KEY_N, 0) == &st_actions[ST_ACT_SCHEME_KEEP] && a->pending_scheme == NULL);
    CHECK(strstr(a->msg, "scheme unchanged") != NULL);
    CHECK(st_app_key(a, GLFW_KEY_Q, C) == &st_actions[ST_ACT_QUIT] && a->quit == 1);
    /* K asked the empty model which schemes it takes (st_doc_scheme_accepts),
     * which reserved a marker array on its map. */
    st_hier_free(&a->doc.h);
    free(a);
}

int main(void)
{
    test_entries();
    test_no_conflicts();
    test_reachable();
    test_former_bindings();
    test_names();
    test_help_rows();
    test_readme();
    test_dispatch();
    return TEST_END();
}
