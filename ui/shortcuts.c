/* Shortcuts of the action table: matching a key press, printable names, and
 * the F1 rows and the key table of docs/MODELLER.md generated from st_actions; see actions.h.
 * Reads the table only: nothing here needs a window. */
#include "actions.h"

#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

int st_shortcut_matches(const st_shortcut *s, int key, int mods)
{
    if (!s->key || s->key != key) return 0;
    mods &= ST_MODS;
    return (mods & s->mods) == s->mods && (mods & ~(s->mods | s->tolerate)) == 0;
}

/* Both match the press holding the union of their needed modifiers, unless
 * one forbids a modifier the other needs. */
int st_shortcuts_overlap(const st_shortcut *a, const st_shortcut *b)
{
    if (!a->key || a->key != b->key) return 0;
    int need = a->mods | b->mods;
    int forbid = (ST_MODS & ~(a->mods | a->tolerate)) | (ST_MODS & ~(b->mods | b->tolerate));
    return (need & forbid) == 0;
}

const st_action *st_action_for_key(int context, int key, int mods)
{
    for (unsigned i = 0; i < ST_NACTIONS; i++) {
        const st_action *act = &st_actions[i];
        if (act->context != context) continue;
        for (int k = 0; k < ST_ACTION_KEYS; k++)
            if (st_shortcut_matches(&act->keys[k], key, mods)) return act;
    }
    return NULL;
}

const char *st_key_name(int key)
{
    static const struct { int key; const char *name; } named[] = {
        { GLFW_KEY_PAGE_UP, "PageUp" }, { GLFW_KEY_PAGE_DOWN, "PageDown" }, { GLFW_KEY_HOME, "Home" },
        { GLFW_KEY_LEFT, "Left" }, { GLFW_KEY_RIGHT, "Right" }, { GLFW_KEY_UP, "Up" }, { GLFW_KEY_DOWN, "Down" },
        { GLFW_KEY_ESCAPE, "Esc" }, { GLFW_KEY_ENTER, "Enter" }, { GLFW_KEY_KP_ENTER, "Numpad Enter" },
        { GLFW_KEY_KP_ADD, "Numpad +" }, { GLFW_KEY_KP_SUBTRACT, "Numpad -" },
        { GLFW_KEY_EQUAL, "=" }, { GLFW_KEY_MINUS, "-" }, { GLFW_KEY_LEFT_BRACKET, "[" },
        { GLFW_KEY_RIGHT_BRACKET, "]" }, { GLFW_KEY_PERIOD, "." }, { GLFW_KEY_COMMA, "," },
    };
    static const char *const kp[10] = { "Numpad 0", "Numpad 1", "Numpad 2", "Numpad 3", "Numpad 4",
                                         "Numpad 5", "Numpad 6", "Numpad 7", "Numpad 8", "Numpad 9" };
    static const char *const fkeys[12] = { "F1", "F2", "F3", "F4", "F5", "F6", "F7", "F8", "F9", "F10", "F11", "F12" };
    /* GLFW's codes of letters and digits are their ASCII characters. */
    static const char letters[] = "A\0B\0C\0D\0E\0F\0G\0H\0I\0J\0K\0L\0M\0N\0O\0P\0Q\0R\0S\0T\0U\0V\0W\0X\0Y\0Z";
    static const char digits[] = "0\0001\0002\0003\0004\0005\0006\0007\0008\0009";
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return letters + 2 * (key - GLFW_KEY_A);
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return digits + 2 * (key - GLFW_KEY_0);
    if (key >= GLFW_KEY_KP_0 && key <= GLFW_KEY_KP_9) return kp[key - GLFW_KEY_KP_0];
    if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12) return fkeys[key - GLFW_KEY_F1];
    for (size_t i = 0; i < sizeof named / sizeof named[0]; i++)
        if (named[i].key == key) return named[i].name;
    return NULL;
}

/* Appends text to buf[*len..n), keeping it terminated and *len its length
 * (stopping at the end of the buffer). */
static void put(char *buf, size_t n, size_t *len, const char *text)
{
    size_t k = strlen(text);
    if (*len + 1 >= n) return;
    if (k > n - 1 - *len) k = n - 1 - *len;
    memcpy(buf + *len, text, k);
    *len += k;
    buf[*len] = 0;
}

int st_shortcut_format(const st_shortcut *s, char *buf, size_t n)
{
    size_t len = 0;
    if (n) buf[0] = 0;
    const char *name = st_key_name(s->key);
    if (!name || !n) return -1;
    if (s->mods & ST_MOD_CTRL) put(buf, n, &len, "Ctrl+");
    if (s->mods & ST_MOD_ALT) put(buf, n, &len, "Alt+");
    if (s->mods & ST_MOD_SHIFT) put(buf, n, &len, "Shift+");
    put(buf, n, &len, name);
    return (int)len;
}

const char *st_category_name(int category)
{
    static const char *const names[ST_NCATEGORIES] = { "File", "Edit", "Tools", "Mesh", "Box", "Bake", "View", "Help" };
    return category >= 0 && category < ST_NCATEGORIES ? names[category] : NULL;
}

const char *st_context_name(int context)
{
    static const char *const names[ST_NKEY_CONTEXTS] = { "Window", "Scheme question (after K)",
                                                                 "Quit question (quitting with unsaved changes)" };
    return context >= 0 && context < ST_NKEY_CONTEXTS ? names[context] : NULL;
}

static void put_key(char *buf, size_t n, size_t *len, const st_shortcut *s, int quote)
{
    char name[64];
    if (st_shortcut_format(s, name, sizeof name) < 0) snprintf(name, sizeof name, "key %d", s->key);
    if (quote) put(buf, n, len, "`");
    put(buf, n, len, name);
    if (quote) put(buf, n, len, "`");
}

/* The first shortcuts of the actions joined by " / ", then their other
 * shortcuts in parentheses, one group per position: "PageUp / PageDown
 * (or Numpad + / Numpad -, = / -)". */
void st_help_row_keys(const st_action *first, int count, int quote, char *buf, size_t n)
{
    size_t len = 0;
    int paren = 0;
    if (n) buf[0] = 0;
    for (int k = 0; k < ST_ACTION_KEYS; k++) {
        int any = 0;
        for (int i = 0; i < count; i++) {
            const st_shortcut *s = &first[i].keys[k];
            if (!s->key) continue;
            if (any) put(buf, n, &len, " / ");
            else if (k > 0 && !paren) { put(buf, n, &len, " (or "); paren = 1; }
            else if (k > 0) put(buf, n, &len, ", ");
            put_key(buf, n, &len, s, quote);
            any = 1;
        }
    }
    if (paren) put(buf, n, &len, ")");
}

static unsigned add_row(st_help_row *rows, unsigned max, unsigned n, const char *heading, const char *what)
{
    if (n < max) {
        memset(&rows[n], 0, sizeof rows[n]);
        rows[n].heading = heading;
        rows[n].what = what;
    }
    return n + 1;
}

/* Rows of one section: the actions of (context, category) in table order,
 * neighbours with the same help text merged. */
static unsigned action_rows(st_help_row *rows, unsigned max, unsigned n, int context, int category)
{
    for (unsigned i = 0; i < ST_NACTIONS;) {
        const st_action *act = &st_actions[i];
        if (act->context != context || (category >= 0 && act->category != category)) { i++; continue; }
        unsigned j = i + 1;
        while (j < ST_NACTIONS && st_actions[j].context == context && st_actions[j].category == act->category &&
               !strcmp(st_actions[j].help, act->help))
            j++;
        if (n < max) {
            memset(&rows[n], 0, sizeof rows[n]);
            rows[n].what = act->help;
            rows[n].first = (int)i;
            rows[n].count = (int)(j - i);
            st_help_row_keys(act, (int)(j - i), 0, rows[n].keys, sizeof rows[n].keys);
        }
        n++;
        i = j;
    }
    return n;
}

unsigned st_help_rows(st_help_row *rows, unsigned max)
{
    unsigned n = add_row(rows, max, 0, "Mouse", NULL);
    for (unsigned g = 0; g < st_ngestures; g++) {
        if (n < max) {
            memset(&rows[n], 0, sizeof rows[n]);
            snprintf(rows[n].keys, sizeof rows[n].keys, "%s", st_gestures[g].input);
            rows[n].what = st_gestures[g].help;
        }
        n++;
    }
    for (int c = 0; c < ST_NCATEGORIES; c++) {
        n = add_row(rows, max, n, st_category_name(c), NULL);
        n = action_rows(rows, max, n, ST_KEYS_WINDOW, c);
    }
    for (int ctx = ST_KEYS_WINDOW + 1; ctx < ST_NKEY_CONTEXTS; ctx++) {
        n = add_row(rows, max, n, st_context_name(ctx), NULL);
        n = action_rows(rows, max, n, ctx, -1);
    }
    return n;
}

void st_actions_markdown(FILE *f)
{
    static st_help_row rows[ST_HELP_MAX_ROWS];
    unsigned n = st_help_rows(rows, ST_HELP_MAX_ROWS);
    if (n > ST_HELP_MAX_ROWS) n = ST_HELP_MAX_ROWS;
    fprintf(f, "%s\n\n| | keys | what |\n| --- | --- | --- |\n", ST_KEYS_BEGIN);
    const char *section = "";
    for (unsigned i = 0; i < n; i++) {
        if (rows[i].heading) { section = rows[i].heading; continue; }
        char keys[400];
        if (rows[i].count) st_help_row_keys(&st_actions[rows[i].first], rows[i].count, 1, keys, sizeof keys);
        else snprintf(keys, sizeof keys, "%s", rows[i].keys);
        fprintf(f, "| %s | %s | %s |\n", section, keys, rows[i].what);
        section = "";
    }
    fprintf(f, "\n%s\n", ST_KEYS_END);
}
