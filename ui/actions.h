/* The modeller's actions: one table (actions.c) of everything a key does,
 * with its name and category for menus, its shortcuts, its help text, the
 * function that runs it and when it is enabled.  Key presses are looked up
 * in it (st_app_key), and the F1 help and docs/MODELLER.md's key table are
 * generated from it (st_help_rows, st_actions_markdown; `strata --keys`).
 *
 * Pointer input (orbit, pan, zoom, clicks, drags, brush strokes, box
 * handles, dropped files) is continuous, not a discrete action: it stays in
 * the window's pointer handlers (controller.c) and is listed, for F1 and the
 * key table, in st_gestures (actions.c).
 *
 * Shortcuts and modifiers.  A shortcut is a key, the modifiers it needs and
 * the modifiers it tolerates: it matches a press when every needed modifier
 * is held and no other modifier is, except tolerated ones (Super is never
 * considered).  So Ctrl+Z (tolerating Alt) and Ctrl+Shift+Z are different
 * shortcuts, and W selects the select tool with or without Shift.  In one
 * context no two shortcuts may match the same press (tests/ui/test_actions.c). */
#ifndef ST_ACTIONS_H
#define ST_ACTIONS_H

#include <stddef.h>
#include <stdio.h>

struct st_app;

/* Modifier bits, GLFW's values (GLFW_MOD_SHIFT, _CONTROL, _ALT). */
enum { ST_MOD_SHIFT = 0x1, ST_MOD_CTRL = 0x2, ST_MOD_ALT = 0x4, ST_MODS = 0x7 };

/* Where a shortcut applies: the window, the question a pending scheme
 * change asks (K cycles, Y rebuilds, any other key keeps the scheme), or
 * the question quitting with unsaved changes asks (S saves, D discards,
 * any other key cancels). */
enum st_key_context { ST_KEYS_WINDOW, ST_KEYS_SCHEME_QUESTION, ST_KEYS_QUIT_QUESTION, ST_NKEY_CONTEXTS };

/* Menu categories, in menu order. */
enum st_action_category {
    ST_CAT_FILE, ST_CAT_EDIT, ST_CAT_TOOLS, ST_CAT_MESH, ST_CAT_BOX, ST_CAT_BAKE, ST_CAT_VIEW, ST_CAT_HELP, ST_NCATEGORIES
};

typedef struct st_shortcut {
    int key;                   /* GLFW_KEY_*; 0 ends an action's list */
    int mods;                  /* ST_MOD_* that must be held */
    int tolerate;              /* ST_MOD_* that may be held as well */
} st_shortcut;

#define ST_ACTION_KEYS 3

typedef struct st_action {
    int id;                    /* enum st_action_id: its index in st_actions */
    const char *name;          /* menu item ("Add level") */
    int category;              /* enum st_action_category */
    int context;               /* enum st_key_context */
    st_shortcut keys[ST_ACTION_KEYS];   /* keys[0]: the one a menu shows */
    /* What it does, for F1 and the key table.  Actions next to each other in
     * the table with the same help text share one row there ("front /
     * back view"). */
    const char *help;
    void (*run)(struct st_app *a);
    int (*enabled)(const struct st_app *a);   /* NULL: always */
} st_action;

enum st_action_id {
    ST_ACT_OPEN, ST_ACT_IMPORT, ST_ACT_SAVE, ST_ACT_SAVE_AS, ST_ACT_EXPORT, ST_ACT_RESTORE_RECOVERY, ST_ACT_QUIT,
    ST_ACT_UNDO, ST_ACT_REDO, ST_ACT_SELECT_ALL, ST_ACT_SELECT_NONE, ST_ACT_GRAB, ST_ACT_GRAB_CONFIRM,
    ST_ACT_TOOL_SELECT, ST_ACT_BRUSH_GRAB, ST_ACT_BRUSH_DRAW, ST_ACT_BRUSH_SMOOTH, ST_ACT_BRUSH_FLATTEN,
    ST_ACT_BRUSH_CREASE, ST_ACT_BRUSH_PINCH, ST_ACT_BRUSH_INFLATE, ST_ACT_BRUSH_CLAY_STRIPS, ST_ACT_BRUSH_LAYER,
    ST_ACT_BRUSH_RELAX,
    ST_ACT_RADIUS_DOWN, ST_ACT_RADIUS_UP, ST_ACT_STRENGTH_DOWN, ST_ACT_STRENGTH_UP, ST_ACT_FALLOFF_NEXT,
    ST_ACT_FALLOFF_PREV, ST_ACT_MIRROR_X, ST_ACT_MIRROR_Y, ST_ACT_MIRROR_Z, ST_ACT_STABILIZE, ST_ACT_FRONT_ONLY,
        ST_ACT_MASK_BRUSH, ST_ACT_MASK_CLEAR, ST_ACT_MASK_INVERT, ST_ACT_MASK_GROW, ST_ACT_MASK_SHRINK, ST_ACT_MASK_SMOOTH,
    ST_ACT_MASK_CAVITY,
    ST_ACT_LAYER_ADD, ST_ACT_LAYER_NEXT, ST_ACT_LAYER_HIDE, ST_ACT_LAYER_WEAKER, ST_ACT_LAYER_STRONGER,
    ST_ACT_LAYER_UP, ST_ACT_LAYER_DOWN, ST_ACT_LAYER_MERGE, ST_ACT_LAYER_DELETE,
    ST_ACT_EDIT_LEVEL_UP, ST_ACT_EDIT_LEVEL_DOWN, ST_ACT_DISPLAY_LEVEL_UP, ST_ACT_DISPLAY_LEVEL_DOWN,
    ST_ACT_ADD_LEVEL, ST_ACT_DELETE_FINEST, ST_ACT_DELETE_COARSEST, ST_ACT_CHANGE_SCHEME, ST_ACT_REBUILD_LEVELS,
    ST_ACT_BOX_TOGGLE,
    ST_ACT_BOX_MOVE_XN, ST_ACT_BOX_MOVE_XP, ST_ACT_BOX_MOVE_YN, ST_ACT_BOX_MOVE_YP, ST_ACT_BOX_MOVE_ZN, ST_ACT_BOX_MOVE_ZP,
    ST_ACT_BOX_SHRINK_X, ST_ACT_BOX_GROW_X, ST_ACT_BOX_SHRINK_Y, ST_ACT_BOX_GROW_Y, ST_ACT_BOX_SHRINK_Z, ST_ACT_BOX_GROW_Z,
    ST_ACT_BOX_MAX_UP, ST_ACT_BOX_MAX_DOWN, ST_ACT_BOX_BASE_UP, ST_ACT_BOX_BASE_DOWN,
    ST_ACT_BAKE_MAPS,
    ST_ACT_FRAME_ALL, ST_ACT_VIEW_FRONT, ST_ACT_VIEW_BACK, ST_ACT_VIEW_RIGHT, ST_ACT_VIEW_LEFT, ST_ACT_VIEW_TOP,
    ST_ACT_VIEW_BOTTOM, ST_ACT_PROJECTION, ST_ACT_ORBIT_LEFT, ST_ACT_ORBIT_RIGHT, ST_ACT_ORBIT_UP, ST_ACT_ORBIT_DOWN,
    ST_ACT_SHADING, ST_ACT_WIREFRAME, ST_ACT_CAGE, ST_ACT_UV_CHECKER, ST_ACT_SHOW_BAKED, ST_ACT_GUI,
    ST_ACT_HELP, ST_ACT_ABOUT, ST_ACT_PREFERENCES, ST_ACT_CANCEL,
    ST_ACT_SCHEME_NEXT, ST_ACT_SCHEME_CONFIRM, ST_ACT_SCHEME_KEEP,
    ST_ACT_QUIT_SAVE, ST_ACT_QUIT_DISCARD, ST_ACT_QUIT_CANCEL,
    ST_NACTIONS
};

extern const st_action st_actions[ST_NACTIONS];

/* Pointer gestures, listed with the keys (not actions: see above). */
typedef struct st_gesture { const char *input, *help; } st_gesture;
extern const st_gesture st_gestures[];
extern const unsigned st_ngestures;

/* ---- running actions (actions.c) ---- */

/* The key press (GLFW key and mods) in the window's current context: runs
 * the action it is the shortcut of, if that is enabled.  Returns the
 * action, or NULL when the key does nothing. */
const st_action *st_app_key(struct st_app *a, int key, int mods);
int st_action_enabled(const st_action *act, const struct st_app *a);
/* Whether the menus (ui/gui.cc) list it: every window action but those
 * that only make sense as a key (confirm a grab, Esc, the 15-degree orbit
 * steps). */
int st_action_in_menu(const st_action *act);
/* For a menu's check mark: 1 on, 0 off, -1 not an on/off action. */
int st_action_checked(const st_action *act, const struct st_app *a);

/* ---- shortcuts, help and the key table (shortcuts.c; no window needed) ---- */

int st_shortcut_matches(const st_shortcut *s, int key, int mods);
/* Whether some press matches both (same key, modifiers compatible). */
int st_shortcuts_overlap(const st_shortcut *a, const st_shortcut *b);
/* The action of CONTEXT whose shortcut matches the press, NULL if none. */
const st_action *st_action_for_key(int context, int key, int mods);

/* Printable names: "Ctrl+Shift+Z", "Numpad 1", "PageUp", "[".  NULL for
 * a key without a name (tests/ui/test_actions.c checks that every shortcut
 * has one). */
const char *st_key_name(int key);
/* Writes the shortcut's name into buf (always terminated); returns its
 * length, -1 when the key has no name. */
int st_shortcut_format(const st_shortcut *s, char *buf, size_t n);

const char *st_category_name(int category);
const char *st_context_name(int context);

/* F1 and the key table: sections (the gestures, then each category, then the
 * scheme question), each a heading row and rows of keys and what they do. */
typedef struct st_help_row {
    const char *heading;       /* non-NULL: a section heading, keys and what unused */
    char keys[160];
    const char *what;
    int first, count;          /* actions st_actions[first .. first+count-1]; count 0 for a gesture */
} st_help_row;

#define ST_HELP_MAX_ROWS 128
/* Fills rows (at most max); returns the number of rows of the whole help. */
unsigned st_help_rows(st_help_row *rows, unsigned max);
/* The keys of a row, with each key name between backticks when quote. */
void st_help_row_keys(const st_action *first, int count, int quote, char *buf, size_t n);
/* docs/MODELLER.md's key table, between its markers (the lines included). */
void st_actions_markdown(FILE *f);
#define ST_KEYS_BEGIN "<!-- keys: generated by `strata --keys` from ui/actions.c; tests/ui/test_actions.c compares -->"
#define ST_KEYS_END "<!-- end of keys -->"

#endif
