/* The window's interface with Dear ImGui 1.86: the one C++ translation unit
 * of ui/, behind gui.h.  Menus are generated from the action table
 * (actions.h), so a menu item, its shortcut text and the F1 row come from
 * one entry; the items that open a dialog or pick a scheme are the same
 * actions with a submenu.  See gui.h for the input routing. */
extern "C" {
#include "gui.h"
#include "actions.h"
#include "prefs.h"
#include "window.h"
#include "core/io/mesh.h"
#include "core/io/session.h"
#include "core/multires/hier.h"
#include "core/fvar/fvar.h"
#include "gltf_io.h"
}

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#ifndef STRATA_VERSION
#define STRATA_VERSION "?"
#endif

namespace {

struct file_entry {
    std::string name;
    bool dir;
    long long size;
};

/* The formats Strata reads (core/io/mesh.h, app/gltf_io.h, sessions) and
 * writes (sessions, and the exporters). */
const char *const read_exts[] = { ".obj", ".off", ".ply", ".gltf", ".glb", ".strata" };
const char *const export_exts[] = { ".obj", ".ply", ".gltf", ".glb" };
const char *const export_labels[] = { "OBJ...", "PLY...", "glTF...", "GLB..." };
const char *const schemes[] = { "catmull-clark", "loop", "butterfly", "quad-triangle", "sqrt3", "doo-sabin" };

struct gui_state {
    bool init = false, shown = true, in_frame = false;
    GLFWwindow *win = nullptr;
    float scale = 1;
    /* The pointer as the window's events carried it (window coordinates). */
    float mx = -FLT_MAX, my = -FLT_MAX;
    bool down[3] = {}, pressed[3] = {};
    bool fed_down[3] = {};     /* io.MouseDown as the last frame had it */
    float held_wheel[2] = {};  /* a wheel that waits for the frame after a click (st_gui_frame) */
    std::string scheme_refusal[sizeof schemes / sizeof schemes[0]];   /* why not, "" when it can */
    uint64_t scheme_refusal_rev = 0; /* st_doc.revision + 1 they were computed for (0: never) */
    std::string scheme_refusal_path;
    bool box_pending = false;        /* a level slider moved: applied after the frame that shows it */
    st_adapt_params box_next = {};
    st_adapt_params box_allowed_for = {};
    uint64_t box_allowed_rev = 0;
    unsigned box_allowed = 0;        /* st_doc_box_max_level_allowed of box_allowed_for */
    /* Keys pressed since the last frame, and releases held back until a
     * frame has seen them down (ImGui 1.86 reads key states, not events: a
     * press and release between two frames, such as a fast typist's Enter
     * or Backspace, would otherwise be lost). */
    struct key_event { int key, scancode, mods; };
    std::vector<int> keys_pressed;
    std::vector<key_event> held_releases;
    int pending_action = -1;
    /* The file dialog. */
    bool dlg_open = false, dlg_popup = false, dlg_confirm = false, dlg_accept = false;
    int dlg_kind = ST_DIALOG_OPEN;
    int dlg_format = 0;                 /* export: index in export_exts */
    std::string cwd;
    char path[4096] = "";
    std::vector<file_entry> entries;
    std::string dlg_error;
    bool about = false;
    bool prefs = false;
    /* Bake > Bake maps...: the dialog (its settings are st_app.bake), its
     * Bake button (run after the frame: a job), its last refusal. */
    bool bake = false, bake_go = false;
    std::string bake_error;
    int box_dragging = 0;
    /* Side panel width (window units; a preference, the left edge drags it). */
    float panel_w = 0;
    /* STRATA_GUI_PROBE (tests): the folder the widget rectangles go to. */
    std::string probe_dir, probe;
    std::vector<std::string> menu_path;   /* drawn menus open around the current item */
    unsigned long long frames = 0;
    /* Notifications: the window's messages (st_app_message) as toasts. */
    double msg_time = -1;
    struct toast { std::string text; bool error; double t0; };
    std::vector<toast> toasts;
};

gui_state g;

/* After a frame (or with the GUI hidden): the releases held back go to ImGui. */
void release_held_keys(void)
{
    g.keys_pressed.clear();
    for (const gui_state::key_event &e : g.held_releases) ImGui_ImplGlfw_KeyCallback(g.win, e.key, e.scancode, GLFW_RELEASE, e.mods);
    g.held_releases.clear();
}

/* ---- widget rectangles for tests ---------------------------------------------------
 * With STRATA_GUI_PROBE=DIR, every frame writes DIR/gui (atomically: a
 * temporary renamed over it) with the frame number, a few document values
 * and the rectangles (window coordinates) of the widgets a test clicks,
 * so that tests/cli_gui_xdotool.sh computes where to click instead of
 * guessing pixels.  Names have '_' for spaces and no trailing "...". */

std::string probe_name(const std::string &prefix, const char *label)
{
    std::string n = label;
    size_t hash = n.find("##");
    if (hash != std::string::npos) n.resize(hash);
    while (!n.empty() && (n.back() == '.' || n.back() == ' ')) n.pop_back();
    std::replace(n.begin(), n.end(), ' ', '_');
    return prefix + n;
}

void probe_rect_at(const std::string &name, ImVec2 lo, ImVec2 hi)
{
    if (g.probe_dir.empty()) return;
    char b[96];
    snprintf(b, sizeof b, " %.0f %.0f %.0f %.0f\n", lo.x, lo.y, hi.x, hi.y);
    g.probe += "rect " + name + b;
}

/* The item just submitted. */
void probe_item(const char *name)
{
    if (!g.probe_dir.empty()) probe_rect_at(name, ImGui::GetItemRectMin(), ImGui::GetItemRectMax());
}

void probe_item(const std::string &name)
{
    if (!g.probe_dir.empty()) probe_rect_at(name, ImGui::GetItemRectMin(), ImGui::GetItemRectMax());
}

std::string menu_prefix(void)
{
    std::string p = "menu:";
    for (const std::string &m : g.menu_path) p += m + "/";
    return p;
}

void probe_write(st_app *a)
{
    if (g.probe_dir.empty()) return;
    const st_doc *d = &a->doc;
    char b[512];
    snprintf(b, sizeof b, "frame %llu\nbusy %d\n", g.frames, a->busy);
    std::string text = b;
    /* The document's values as of the last frame without a job: a job's
     * worker thread owns the document meanwhile (jobs.c). */
    static std::string doc_values;
    if (!a->busy) {
        snprintf(b, sizeof b, "loaded %d\ntop %u\nbox_on %d\nundo %u\nradius %.6g\nbox_size %.6g %.6g %.6g\n", d->loaded,
                 d->loaded ? d->h.map.top : 0, d->box_on, d->undo_pos, d->brush.radius, d->box.box_hi[0] - d->box.box_lo[0],
                 d->box.box_hi[1] - d->box.box_lo[1], d->box.box_hi[2] - d->box.box_lo[2]);
        doc_values = b;
        doc_values += "file " + std::string(d->loaded ? st_path_base(d->path) : "-") + "\n";
        doc_values += "tool " + std::string(a->tool == ST_TOOL_SELECT ? "select" : st_brush_name(a->tool)) + "\n";
        snprintf(b, sizeof b, "strength %.6g\n", d->brush.strength);
        doc_values += b;
    }
    text += doc_values;
    snprintf(b, sizeof b, "scale %g\n", g.scale);
    text += b;
    text += "message " + std::string(a->msg) + "\n";   /* the last notification (st_app_message) */
    text += "dialog " + std::string(g.dlg_open ? "1" : "0") + "\n";
    text += g.probe;
    std::string path = g.probe_dir + "/gui", tmp = path + ".tmp";
    FILE *f = fopen(tmp.c_str(), "w");
    if (!f) return;
    fwrite(text.data(), 1, text.size(), f);
    if (fclose(f) == 0) rename(tmp.c_str(), path.c_str());
}

bool ends_with_ci(const char *s, const char *ext)
{
    size_t n = strlen(s), m = strlen(ext);
    return n >= m && !strcasecmp(s + n - m, ext);
}

bool wanted_file(int kind, const char *name)
{
    if (kind == ST_DIALOG_OPEN || kind == ST_DIALOG_IMPORT) {
        /* Import: the mesh formats, not sessions. */
        for (const char *e : read_exts)
            if (ends_with_ci(name, e) && (kind == ST_DIALOG_OPEN || strcmp(e, ".strata"))) return true;
        return false;
    }
    if (kind == ST_DIALOG_SAVE_AS) return ends_with_ci(name, ".strata");
    return ends_with_ci(name, export_exts[g.dlg_format]);
}

/* Folders first, then files of the dialog's formats, each by name. */
void list_dir(void)
{
    g.entries.clear();
    DIR *d = opendir(g.cwd.c_str());
    if (!d) { g.dlg_error = "cannot read the folder " + g.cwd + ": " + strerror(errno); return; }
    while (struct dirent *e = readdir(d)) {
        if (e->d_name[0] == '.') continue;   /* hidden files and . / .. (Parent goes up) */
        std::string full = g.cwd + "/" + e->d_name;
        struct stat st;
        if (stat(full.c_str(), &st)) continue;
        bool dir = S_ISDIR(st.st_mode);
        if (!dir && !wanted_file(g.dlg_kind, e->d_name)) continue;
        g.entries.push_back({ e->d_name, dir, (long long)st.st_size });
    }
    closedir(d);
    std::sort(g.entries.begin(), g.entries.end(), [](const file_entry &a, const file_entry &b) {
        if (a.dir != b.dir) return a.dir;
        return a.name < b.name;
    });
}

void set_cwd(const std::string &dir)
{
    char buf[4096];
    g.cwd = realpath(dir.c_str(), buf) ? buf : dir;
    list_dir();
}

std::string dir_of(const char *path)
{
    const char *s = strrchr(path, '/');
    if (!s) return ".";
    if (s == path) return "/";
    return std::string(path, (size_t)(s - path));
}

std::string format_size(long long n)
{
    char b[32];
    if (n >= 1 << 20) snprintf(b, sizeof b, "%.1f MB", n / 1048576.0);
    else if (n >= 1 << 10) snprintf(b, sizeof b, "%.1f KB", n / 1024.0);
    else snprintf(b, sizeof b, "%lld B", n);
    return b;
}

/* The dialog's path completed with the extension its kind writes. */
std::string completed_path(int kind, const char *p)
{
    std::string s = p;
    if (kind == ST_DIALOG_SAVE_AS && !ends_with_ci(p, ".strata")) s += ".strata";
    if (kind == ST_DIALOG_EXPORT) {
        bool known = false;
        for (const char *e : export_exts) known = known || ends_with_ci(p, e);
        if (!known) s += export_exts[g.dlg_format];
    }
    if (!s.empty() && s[0] != '/') s = g.cwd + "/" + s;
    return s;
}

/* Runs the dialog's choice (outside the ImGui frame: opening is a job).
 * A failure keeps the dialog open with the message and the current model. */
void dialog_accept(st_app *a, int kind, const std::string &path)
{
    int rc;
    if (kind == ST_DIALOG_OPEN) {
        rc = st_app_open(a, path.c_str());
    } else if (kind == ST_DIALOG_IMPORT) {
        rc = st_app_import(a, path.c_str());
    } else if (kind == ST_DIALOG_SAVE_AS) {
        rc = st_app_save_session(a, path.c_str(), 0);
        if (!rc && path.size() < sizeof a->doc.path) {
            memcpy(a->doc.path, path.c_str(), path.size() + 1);
            st_app_saved(a);
            a->untitled = 0;
            if (a->quit_after_save) a->quit = 1;
        }
    } else {
        rc = st_app_export(a, path.c_str());
    }
    if (rc) {
        g.dlg_error = a->msg;
        return;
    }
    if (kind != ST_DIALOG_EXPORT && kind != ST_DIALOG_IMPORT) st_prefs_add_recent(path.c_str());   /* imports are not documents */
    g.dlg_open = false;
    g.dlg_error.clear();
}

void open_dialog(st_app *a, int kind, int format)
{
    a->quit_after_save = 0;
    g.dlg_open = true;
    g.dlg_popup = true;
    g.dlg_confirm = false;
    g.dlg_kind = kind;
    g.dlg_format = format;
    g.dlg_error.clear();
    g.path[0] = 0;
    const char *doc = a->doc.loaded ? a->doc.path : "";
    /* The open document's folder, or the working directory: not the
     * folder of the default model shown at start (assets/), which is not
     * the user's. */
    bool own = doc[0] && !a->showing_default;
    std::string start = own ? dir_of(doc) : ".";
    if (kind != ST_DIALOG_OPEN && kind != ST_DIALOG_IMPORT && doc[0]) {
        /* The model's name with the extension of what is written. */
        const char *base = st_path_base(doc);
        const char *dot = strrchr(base, '.');
        int n = dot ? (int)(dot - base) : (int)strlen(base);
        snprintf(g.path, sizeof g.path, "%.*s%s", n, base, kind == ST_DIALOG_SAVE_AS ? ".strata" : export_exts[format]);
    }
    set_cwd(start);
    g.shown = true;
}

/* ---- menus: drawn, or searched by the replay's `menu PATH` -------------------------- */

struct menu_pass {
    st_app *a = nullptr;
    bool draw = true;
    std::vector<std::string> path;   /* search: the labels to follow */
    size_t depth = 0;
    const char *arg = nullptr;
    bool found = false;
    std::string error;
};

bool same_label(const std::string &want, const char *label)
{
    std::string l = label;
    while (!l.empty() && (l.back() == '.' || l.back() == ' ')) l.pop_back();
    std::string w = want;
    std::replace(w.begin(), w.end(), '_', ' ');   /* the replay's tokens have no spaces */
    while (!w.empty() && (w.back() == '.' || w.back() == ' ')) w.pop_back();
    return !strcasecmp(l.c_str(), w.c_str());
}

bool m_begin(menu_pass &m, const char *label, bool enabled = true)
{
    if (m.draw) {
        /* Where the label starts: after BeginMenu the last item is the
         * open menu's window. */
        if (g.probe_dir.empty()) return ImGui::BeginMenu(label, enabled);
        ImVec2 p = ImGui::GetCursorScreenPos(), t = ImGui::CalcTextSize(label);
        std::string name = probe_name(menu_prefix(), label);
        bool open = ImGui::BeginMenu(label, enabled);
        probe_rect_at(name, p, ImVec2(p.x + t.x + ImGui::GetStyle().ItemSpacing.x, p.y + t.y));
        if (open) g.menu_path.push_back(probe_name("", label));
        return open;
    }
    if (m.found || m.depth + 1 >= m.path.size() || !same_label(m.path[m.depth], label)) return false;
    if (!enabled) { m.error = std::string("menu ") + label + " is disabled"; return false; }
    m.depth++;
    return true;
}

void m_end(menu_pass &m)
{
    if (m.draw) {
        ImGui::EndMenu();
        if (!g.menu_path.empty()) g.menu_path.pop_back();
    }
    else m.depth--;
}

bool m_item(menu_pass &m, const char *label, const char *shortcut, bool checked, bool enabled)
{
    if (m.draw) {
        bool chosen = ImGui::MenuItem(label, shortcut, checked, enabled);
        if (!g.probe_dir.empty()) probe_item(probe_name(menu_prefix(), label));
        return chosen;
    }
    if (m.found || m.depth + 1 != m.path.size() || !same_label(m.path[m.depth], label)) return false;
    if (!enabled) { m.error = std::string("menu item ") + label + " is disabled"; return false; }
    m.found = true;
    return true;
}

/* A drawn click waits for the end of the frame; a replay's runs now. */
void choose_action(menu_pass &m, int id)
{
    if (m.draw) g.pending_action = id;
    else st_actions[id].run(m.a);
}

void choose_dialog(menu_pass &m, int kind, int format)
{
    if (!m.draw && m.arg) {
        g.dlg_format = format;
        g.dlg_kind = kind;
        char cwd[4096];
        g.cwd = getcwd(cwd, sizeof cwd) ? cwd : ".";
        /* A failure is the status line's error, as in the dialog, not
         * the replay's: `expect error 1` checks it. */
        dialog_accept(m.a, kind, completed_path(kind, m.arg));
        g.dlg_error.clear();
        return;
    }
    open_dialog(m.a, kind, format);
}

void action_item(menu_pass &m, const st_action *act)
{
    char sc[64] = "";
    if (act->keys[0].key) st_shortcut_format(&act->keys[0], sc, sizeof sc);
    int checked = st_action_checked(act, m.a);
    const char *label = act->name;
    char named[160];
    if (act->id == ST_ACT_UNDO || act->id == ST_ACT_REDO) {
        /* What the step was: "Undo brush stroke", "Redo add level". */
        const st_doc *d = &m.a->doc;
        const char *step = act->id == ST_ACT_UNDO ? st_doc_undo_name(d) : st_doc_redo_name(d);
        if (step) snprintf(named, sizeof named, "%s %s", act->name, step);
        else snprintf(named, sizeof named, "%s", act->name);
        /* The replay names the item by the table's name. */
        if (!m.draw) label = act->name; else label = named;
    }
    bool enabled = st_action_enabled(act, m.a) != 0;
    if (!m_item(m, label, sc[0] ? sc : nullptr, checked > 0, enabled)) return;
    if (act->id == ST_ACT_OPEN) choose_dialog(m, ST_DIALOG_OPEN, 0);
    else if (act->id == ST_ACT_IMPORT) choose_dialog(m, ST_DIALOG_IMPORT, 0);
    else if (act->id == ST_ACT_SAVE_AS) choose_dialog(m, ST_DIALOG_SAVE_AS, 0);
    else choose_action(m, act->id);
}

void export_menu(menu_pass &m, const st_action *act)
{
    bool enabled = st_action_enabled(act, m.a) != 0;
    if (!m_begin(m, "Export", enabled)) return;
    for (int f = 0; f < 4; f++) {
        char sc[64] = "";
        if (f == 0 && act->keys[0].key) st_shortcut_format(&act->keys[0], sc, sizeof sc);
        if (m_item(m, export_labels[f], sc[0] ? sc : nullptr, false, true)) choose_dialog(m, ST_DIALOG_EXPORT, f);
    }
    m_end(m);
}

/* Which schemes the control mesh cannot take, and why (greyed out in the
 * Scheme menu, the reason as a tooltip): asked of the document again only
 * when the model changed. */
void scheme_refusals_update(st_app *a)
{
    if (g.scheme_refusal_rev == a->doc.revision + 1 && g.scheme_refusal_path == a->doc.path) return;
    g.scheme_refusal_rev = a->doc.revision + 1;
    g.scheme_refusal_path = a->doc.path;
    const unsigned n = sizeof schemes / sizeof schemes[0];
    int rc[n];
    st_error err[n];
    st_doc_schemes_accepted(&a->doc, schemes, n, rc, err);
    for (unsigned i = 0; i < n; i++) g.scheme_refusal[i] = rc[i] ? err[i].msg : "";
}

/* The scheme submenu proposes a scheme; the question (scheme_window)
 * confirms it, as K then Y do. */
void scheme_menu(menu_pass &m, const st_action *act)
{
    bool enabled = st_action_enabled(act, m.a) != 0;
    if (!m_begin(m, "Scheme", enabled)) return;
    const char *cur = m.a->doc.scheme ? m.a->doc.scheme->name : "";
    scheme_refusals_update(m.a);
    for (size_t i = 0; i < sizeof schemes / sizeof schemes[0]; i++) {
        const char *s = schemes[i];
        bool takes = g.scheme_refusal[i].empty();
        bool clicked = m_item(m, s, nullptr, !strcmp(cur, s), strcmp(cur, s) != 0 && takes);
        if (m.draw && !takes && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("%s", g.scheme_refusal[i].c_str());
        if (clicked) {
            m.a->pending_scheme = s;
            if (!m.draw && m.arg && !strcmp(m.arg, "confirm")) st_actions[ST_ACT_SCHEME_CONFIRM].run(m.a);
        }
    }
    m_end(m);
}

void menus(menu_pass &m)
{
    for (int c = 0; c < ST_NCATEGORIES; c++) {
        if (!m_begin(m, st_category_name(c))) continue;
        int last = -1;
        for (int i = 0; i < ST_NACTIONS; i++) {
            const st_action *act = &st_actions[i];
            if (act->category != c || act->context != ST_KEYS_WINDOW || !st_action_in_menu(act)) continue;
            /* A separator between groups of different help text. */
            if (m.draw && last >= 0 && strcmp(st_actions[last].help, act->help) &&
                (st_actions[last].id + 1 != act->id || act->id == ST_ACT_QUIT))
                ImGui::Separator();
            last = i;
            if (act->id == ST_ACT_EXPORT) export_menu(m, act);
            else if (act->id == ST_ACT_CHANGE_SCHEME) scheme_menu(m, act);
            else action_item(m, act);
            if (act->id == ST_ACT_OPEN) {
                const char *const *recent = st_prefs_recent();
                if (m_begin(m, "Open Recent", recent[0] != nullptr)) {
                    for (int r = 0; recent[r]; r++)
                        if (m_item(m, recent[r], nullptr, false, true)) {
                            g.dlg_kind = ST_DIALOG_OPEN;
                            g.path[0] = 0;
                            snprintf(g.path, sizeof g.path, "%s", recent[r]);
                            g.dlg_accept = true;
                            if (!m.draw) { g.dlg_accept = false; dialog_accept(m.a, ST_DIALOG_OPEN, recent[r]); }
                        }
                    m_end(m);
                }
            }
        }
        m_end(m);
    }
}

/* ---- windows --------------------------------------------------------------------------- */

float menu_height = 0;

void file_dialog(st_app *a)
{
    const char *title = g.dlg_kind == ST_DIALOG_OPEN     ? "Open###filedialog"
                        : g.dlg_kind == ST_DIALOG_IMPORT ? "Import a mesh###filedialog"
                        : g.dlg_kind == ST_DIALOG_SAVE_AS ? "Save session as###filedialog"
                                                          : "Export the displayed mesh###filedialog";
    /* (Again after a job: its frames drew no dialog.) */
    if (g.dlg_popup || !ImGui::IsPopupOpen("###filedialog")) { ImGui::OpenPopup("###filedialog"); g.dlg_popup = false; }
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowSize(ImVec2(560 * g.scale, 420 * g.scale), ImGuiCond_Appearing);
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    bool open = true;
    if (!ImGui::BeginPopupModal(title, &open)) {
        if (!open || g.dlg_open) g.dlg_open = g.dlg_open && open;
        return;
    }
    ImGui::TextUnformatted(g.cwd.c_str());
    if (ImGui::Button("Parent")) set_cwd(dir_of(g.cwd.c_str()));
    ImGui::SameLine();
    if (ImGui::Button("Refresh")) list_dir();
    ImGui::SameLine();
    if (g.dlg_kind == ST_DIALOG_OPEN) ImGui::TextDisabled(".obj .off .ply .gltf .glb .strata");
    else if (g.dlg_kind == ST_DIALOG_IMPORT) ImGui::TextDisabled(".obj .off .ply .gltf .glb (a new untitled document)");
    else if (g.dlg_kind == ST_DIALOG_SAVE_AS) ImGui::TextDisabled(".strata");
    else ImGui::TextDisabled("%s of the displayed %s", export_exts[g.dlg_format], a->doc.box_on ? "adaptive mesh" : "level");
    /* A row of options under the list (the list's top and the path row
     * stay where they were: replays click there). */
    bool options = (g.dlg_kind == ST_DIALOG_EXPORT && g.dlg_format >= 2) || g.dlg_kind == ST_DIALOG_OPEN || g.dlg_kind == ST_DIALOG_IMPORT;
    float footer = ImGui::GetFrameHeightWithSpacing() * (options ? 3 : 2) +
                   (g.dlg_error.empty() ? 0 : ImGui::GetTextLineHeightWithSpacing() * 2);
    ImGui::BeginChild("entries", ImVec2(0, -footer), true);
    std::string go;
    for (const file_entry &e : g.entries) {
        std::string label = e.dir ? "[dir] " + e.name : e.name;
        bool sel = !e.dir && !strcmp(g.path, e.name.c_str());
        if (ImGui::Selectable(label.c_str(), sel, ImGuiSelectableFlags_AllowDoubleClick)) {
            if (e.dir) go = e.name;
            else {
                snprintf(g.path, sizeof g.path, "%s", e.name.c_str());
                g.dlg_confirm = false;
                if (ImGui::IsMouseDoubleClicked(0)) g.dlg_accept = true;
            }
        }
        if (!e.dir) {
            ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 90 * g.scale);
            ImGui::TextDisabled("%s", format_size(e.size).c_str());
        }
    }
    ImGui::EndChild();
    if (!go.empty()) set_cwd(g.cwd + "/" + go);
    /* glTF can carry the last baked normal map (normalTexture, TANGENT);
     * a mesh file cannot.  Opening can refuse non-manifold edges. */
    if (g.dlg_kind == ST_DIALOG_EXPORT && g.dlg_format >= 2) {
        bool can = st_app_can_show_baked(a) != 0, on = can && a->bake.attach;
        if (!can) ImGui::BeginDisabled();
        if (ImGui::Checkbox("Attach the baked normal map", &on)) a->bake.attach = on;
        if (!can) ImGui::EndDisabled();
        probe_item("dialog:attach");
        ImGui::SameLine();
        if (can) ImGui::TextDisabled("(writes level %u with %s)", a->bake.have_base, st_path_base(a->bake.have_map));
        else ImGui::TextDisabled("(Bake > Bake maps... makes one)");
    }
    if (g.dlg_kind == ST_DIALOG_OPEN || g.dlg_kind == ST_DIALOG_IMPORT) {
        bool strict = (a->doc.read_flags & ST_MESH_STRICT) != 0;
        if (ImGui::Checkbox("Refuse non-manifold edges (--strict; else they are split)", &strict))
            a->doc.read_flags = strict ? a->doc.read_flags | ST_MESH_STRICT : a->doc.read_flags & ~ST_MESH_STRICT;
        probe_item("dialog:strict");
    }
    if (!g.dlg_error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
        ImGui::TextWrapped("%s", g.dlg_error.c_str());
        ImGui::PopStyleColor();
    }
    ImGui::SetNextItemWidth(-160 * g.scale);
    /* A click in the field selects what it holds, so that a typed path
     * replaces the proposed name. */
    if (ImGui::InputText("##path", g.path, sizeof g.path, ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll))
        g.dlg_accept = true;
    probe_item("dialog:path");
    ImGui::SameLine();
    const char *ok = g.dlg_kind == ST_DIALOG_OPEN      ? "Open"
                     : g.dlg_kind == ST_DIALOG_IMPORT  ? "Import"
                     : g.dlg_kind == ST_DIALOG_SAVE_AS ? "Save"
                                                       : "Export";
    if (ImGui::Button(ok, ImVec2(70 * g.scale, 0)) && g.path[0]) g.dlg_accept = true;
    probe_item("dialog:ok");
    ImGui::SameLine();
    bool cancel = ImGui::Button("Cancel", ImVec2(70 * g.scale, 0));
    probe_item("dialog:cancel");
    if (cancel || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) {
        g.dlg_open = false;
        g.dlg_accept = false;
    }
    if (g.dlg_accept) {
        std::string full = completed_path(g.dlg_kind, g.path);
        struct stat st;
        if (!g.path[0]) g.dlg_accept = false;
        else if (!stat(full.c_str(), &st) && S_ISDIR(st.st_mode)) { set_cwd(full); g.path[0] = 0; g.dlg_accept = false; }
        else if (g.dlg_kind != ST_DIALOG_OPEN && g.dlg_kind != ST_DIALOG_IMPORT && !g.dlg_confirm && !stat(full.c_str(), &st)) {
            g.dlg_confirm = true;   /* asks below; the choice runs on "Overwrite" */
            g.dlg_accept = false;
        }
    }
    if (g.dlg_confirm) {
        ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "%s exists.", g.path);
        ImGui::SameLine();
        if (ImGui::Button("Overwrite")) { g.dlg_accept = true; }
        probe_item("dialog:Overwrite");
        ImGui::SameLine();
        if (ImGui::Button("Keep it")) g.dlg_confirm = false;
    }
    if (!open) a->quit_after_save = 0;   /* closed without saving: no quit */
    if (!g.dlg_open || !open) { g.dlg_open = false; ImGui::CloseCurrentPopup(); }
    ImGui::EndPopup();
}

/* Quitting with unsaved changes (st_app_request_quit): S, D and any other
 * key answer it too (actions.c). */
void quit_window(st_app *a)
{
    if (!a->quit_asking) return;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Quit Strata?", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
    probe_item("quit:window");
    ImGui::Text("Save the changes to %s before quitting?", a->untitled ? "the untitled model" : st_path_base(a->doc.path));
    ImGui::TextDisabled("Without saving, the last changes stay only in the recovery file.");
    if (ImGui::Button("Save")) g.pending_action = ST_ACT_QUIT_SAVE;
    probe_item("quit:Save");
    ImGui::SameLine();
    if (ImGui::Button("Don't save")) g.pending_action = ST_ACT_QUIT_DISCARD;
    probe_item("quit:Don't save");
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) g.pending_action = ST_ACT_QUIT_CANCEL;
    probe_item("quit:Cancel");
    ImGui::End();
}

/* The scheme question of K (or the Scheme menu): Y / Enter, K, N still work. */
void scheme_window(st_app *a)
{
    if (!a->pending_scheme) return;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Change the scheme?", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::Text("Rebuild the hierarchy with %s?", a->pending_scheme);
    ImGui::TextDisabled("The details of the current levels are lost.");
    char b[96];
    snprintf(b, sizeof b, "Rebuild with %s", a->pending_scheme);
    if (ImGui::Button(b)) g.pending_action = ST_ACT_SCHEME_CONFIRM;
    ImGui::SameLine();
    if (ImGui::Button("Next scheme")) g.pending_action = ST_ACT_SCHEME_NEXT;
    ImGui::SameLine();
    if (ImGui::Button("Keep")) g.pending_action = ST_ACT_SCHEME_KEEP;
    ImGui::End();
}

void about_window(void)
{
    if (!g.about) return;
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.4f), ImGuiCond_Appearing,
                            ImVec2(0.5f, 0.5f));
    if (ImGui::Begin("About Strata", &g.about, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
        ImGui::Text("Strata %s", STRATA_VERSION);
        ImGui::TextDisabled("interactive multiresolution subdivision modelling");
        ImGui::Separator();
        ImGui::Text("Dear ImGui %s", IMGUI_VERSION);
        ImGui::Text("GLFW %s", glfwGetVersionString());
    }
    ImGui::End();
}

/* Edit > Preferences: what the user sets by hand (prefs.h); the rest
 * (window size, panel layout, brush defaults, recent files) is kept as the
 * window is used and saved at exit.  "Save now" writes the file at once. */
void prefs_window(st_app *a)
{
    if (!g.prefs) return;
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.4f), ImGuiCond_Appearing,
                            ImVec2(0.5f, 0.5f));
    if (ImGui::Begin("Preferences", &g.prefs, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
        char path[4096];
        ImGui::Text("kept in %s", st_prefs_path(path, sizeof path) ? "(no $XDG_CONFIG_HOME or $HOME: not kept)" : path);
        ImGui::Separator();
        float s = st_prefs_ui_scale();
        if (ImGui::SliderFloat("UI scale", &s, 0.0f, 4.0f, s > 0 ? "%.2f" : "auto (monitor)")) st_prefs_set_ui_scale(s);
        probe_item("prefs:ui_scale");
        ImGui::TextDisabled("now %.2f; a new scale applies at the next start (--ui-scale overrides it)", g.scale);
        const char *const *recent = st_prefs_recent();
        int nrecent = 0;
        while (recent[nrecent]) nrecent++;
        ImGui::Text("%d recent file%s", nrecent, nrecent == 1 ? "" : "s");
        ImGui::SameLine();
        if (ImGui::Button("Clear")) st_prefs_clear_recent();
        probe_item("prefs:clear_recent");
        const char *tool = st_prefs_brush_tool();
        ImGui::Text("brush at start: %s, radius %.3g of the model, strength %.2g", tool[0] ? tool : "(default)",
                    st_prefs_brush_radius(), st_prefs_brush_strength());
        ImGui::TextDisabled("(the brush in use when the window closes)");
        if (ImGui::Button("Save now")) {
            if (st_prefs_save()) st_app_message(a, 1, "preferences not saved (see the terminal)");
            else st_app_message(a, 0, "preferences saved");
        }
        probe_item("prefs:save");
    }
    ImGui::End();
}

/* A path the user typed, relative to the working directory, made absolute
 * (the job's messages and the view read it later). */
void absolute_path(char *p, size_t n)
{
    if (!p[0] || p[0] == '/') return;
    char cwd[4096];
    if (!getcwd(cwd, sizeof cwd)) return;
    std::string full = std::string(cwd) + "/" + p;
    if (full.size() < n) memcpy(p, full.c_str(), full.size() + 1);
}

/* Bake > Bake maps...: strata bake's options (bakeio/bake_run.h); Bake
 * runs the job (progress, Esc or Cancel) after this frame. */
void bake_window(st_app *a)
{
    if (!g.bake) return;
    if (!a->doc.loaded) { g.bake = false; return; }
    st_app_bake *b = &a->bake;
    st_app_bake_defaults(a);
    int top = (int)a->doc.h.map.top;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.4f, io.DisplaySize.y * 0.45f), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (!ImGui::Begin("Bake maps", &g.bake, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) { ImGui::End(); return; }
    ImGui::TextDisabled("level %d's surface onto level %d's UVs (strata bake)", b->level, b->base);
    float w = 260 * g.scale;
    ImGui::SetNextItemWidth(w);
    ImGui::SliderInt("Base level (gets the maps)", &b->base, 0, top);
    probe_item("bake:base");
    if (b->level < b->base) b->level = b->base;
    ImGui::SetNextItemWidth(w);
    ImGui::SliderInt("Detail level", &b->level, b->base, top);
    probe_item("bake:level");
    static const int sizes[] = { 256, 512, 1024, 2048, 4096, 8192 };
    static const char *const size_names[] = { "256", "512", "1024", "2048", "4096", "8192" };
    int si = 2;
    for (int i = 0; i < 6; i++) if (sizes[i] == b->size) si = i;
    ImGui::SetNextItemWidth(w);
    if (ImGui::Combo("Resolution", &si, size_names, 6)) b->size = sizes[si];
    probe_item("bake:size");
    ImGui::Separator();
    bool on = b->want_normal != 0;
    if (ImGui::Checkbox("Normal map", &on)) b->want_normal = on;
    probe_item("bake:normal");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(w + 40 * g.scale);
    ImGui::InputText("##normal_path", b->normal, sizeof b->normal, ImGuiInputTextFlags_AutoSelectAll);
    probe_item("bake:normal_path");
    ImGui::RadioButton("Tangent space", &b->space, ST_BAKE_TANGENT);
    ImGui::SameLine();
    ImGui::RadioButton("Object space", &b->space, ST_BAKE_OBJECT);
    ImGui::SameLine();
    on = b->bits16 != 0;
    if (ImGui::Checkbox("16-bit", &on)) b->bits16 = on;
    on = b->want_disp != 0;
    if (ImGui::Checkbox("Displacement", &on)) b->want_disp = on;
    probe_item("bake:disp");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(w + 40 * g.scale);
    ImGui::InputText("##disp_path", b->disp, sizeof b->disp, ImGuiInputTextFlags_AutoSelectAll);
    ImGui::TextDisabled(".exr (float) or .png (16-bit, scale in NAME.json)");
    on = b->vector != 0;
    if (ImGui::Checkbox("Vector displacement", &on)) b->vector = on;
    ImGui::Separator();
    static const char *const udims[] = { "auto", "off (one map)", "on (one map per tile)" };
    int ui = b->udim < 0 ? 0 : b->udim == 0 ? 1 : 2;
    ImGui::SetNextItemWidth(w);
    if (ImGui::Combo("UDIM tiles", &ui, udims, 3)) b->udim = ui == 0 ? -1 : ui == 1 ? 0 : 1;
    probe_item("bake:udim");
    ImGui::SetNextItemWidth(w);
    ImGui::SliderInt("Padding (texels)", &b->padding, 0, 64);
    bool has_uv = st_hier_uv(&a->doc.h, (unsigned)b->base) != nullptr;
    on = b->auto_uv != 0 || !has_uv;
    if (!has_uv) ImGui::BeginDisabled();
    if (ImGui::Checkbox("Auto UVs (a per-face atlas)", &on)) b->auto_uv = on;
    if (!has_uv) { ImGui::EndDisabled(); ImGui::SameLine(); ImGui::TextDisabled("level %d has no UVs", b->base); }
    probe_item("bake:auto_uv");
    if (!g.bake_error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 520 * g.scale);
        ImGui::TextWrapped("%s", g.bake_error.c_str());
        ImGui::PopTextWrapPos();
        ImGui::PopStyleColor();
    }
    if (ImGui::Button("Bake", ImVec2(90 * g.scale, 0))) g.bake_go = true;
    probe_item("bake:run");
    ImGui::SameLine();
    if (ImGui::Button("Close", ImVec2(90 * g.scale, 0))) g.bake = false;
    probe_item("bake:close");
    ImGui::End();
}

/* Help > Key bindings (F1): the same rows as the HUD's F1 list and the
 * README's table (st_help_rows). */
void keys_window(st_app *a)
{
    if (!a->help) return;
    static st_help_row rows[ST_HELP_MAX_ROWS];
    unsigned n = st_help_rows(rows, ST_HELP_MAX_ROWS);
    if (n > ST_HELP_MAX_ROWS) n = ST_HELP_MAX_ROWS;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(20 * g.scale, menu_height + 10 * g.scale), ImGuiCond_Appearing);
    ImGui::SetNextWindowSize(ImVec2(std::min(760 * g.scale, io.DisplaySize.x - 40 * g.scale), io.DisplaySize.y * 0.8f),
                             ImGuiCond_Appearing);
    bool open = true;
    if (ImGui::Begin("Key bindings (F1)", &open) && ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_Resizable)) {
        ImGui::TableSetupColumn("keys", ImGuiTableColumnFlags_WidthFixed, 300 * g.scale);
        ImGui::TableSetupColumn("what", ImGuiTableColumnFlags_WidthStretch);
        for (unsigned i = 0; i < n; i++) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            if (rows[i].heading) { ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1), "%s", rows[i].heading); continue; }
            ImGui::TextUnformatted(rows[i].keys);
            ImGui::TableSetColumnIndex(1);
            ImGui::TextWrapped("%s", rows[i].what);
        }
        ImGui::EndTable();
    }
    ImGui::End();
    if (!open) a->help = 0;
}

/* What the window is doing on its worker thread (jobs.c): the stage and
 * how far it is (the fraction the editor reports, else its steps, "step 3
 * of 6").  Jobs (opening, adding a level, a scheme change, saving,
 * rebuilding the levels) have a Cancel button, as Esc: the worker stops at
 * its next progress report and the model stays as it was (editor.h,
 * st_doc_*_progress). */
void progress_window(st_app *a)
{
    if (!a->working[0]) return;
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(420 * g.scale, 0));
    ImGui::Begin("Working", nullptr, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove);
    ImGui::TextWrapped("%s", a->working);
    unsigned step = 0, steps = 0;
    const char *s = strstr(a->working, "step ");
    if (s) sscanf(s, "step %u of %u", &step, &steps);
    char over[32];
    if (steps) snprintf(over, sizeof over, "step %u of %u", step, steps);
    else snprintf(over, sizeof over, "working...");
    double fraction = st_app_job_fraction();
    if (fraction >= 0) snprintf(over, sizeof over, "%.0f %%", 100 * fraction);
    ImGui::ProgressBar(fraction >= 0 ? (float)fraction : steps ? (float)step / (float)steps : 0.0f, ImVec2(-1, 0), over);
    if (st_app_job_cancellable()) {
        bool asked = st_app_job_cancelling();
        if (asked) ImGui::BeginDisabled();
        if (ImGui::Button(asked ? "Cancelling..." : "Cancel", ImVec2(100 * g.scale, 0))) st_app_cancel_job();
        probe_item("progress:Cancel");
        if (asked) ImGui::EndDisabled();
    }
    ImGui::End();
}

/* Messages (st_app_message: "saved ...", errors) as notifications at the
 * bottom left that take no input and fade: 4 s, errors 8 s, the last 3
 * stacked.  With times masked (replays, tests) they stay until newer ones
 * push them out, so that screenshots do not depend on the clock. */
float panel_width(void);

void note_message(st_app *a)
{
    if (!a->msg[0] || a->msg_time == g.msg_time) return;
    g.msg_time = a->msg_time;
    g.toasts.push_back({ a->msg, a->msg_error != 0, glfwGetTime() });
    if (g.toasts.size() > 3) g.toasts.erase(g.toasts.begin());
}

void toasts(st_app *a)
{
    note_message(a);
    ImGuiIO &io = ImGui::GetIO();
    double now = glfwGetTime();
    float y = io.DisplaySize.y - 8 * g.scale;
    float wmax = std::max(120 * g.scale, io.DisplaySize.x - panel_width() - 24 * g.scale);
    for (size_t i = g.toasts.size(); i-- > 0;) {
        const gui_state::toast &t = g.toasts[i];
        double life = t.error ? 8 : 4, age = a->masked_times ? 0 : now - t.t0;
        if (age > life) { g.toasts.erase(g.toasts.begin() + (long)i); continue; }
        float alpha = (float)std::min(1.0, (life - age) / 0.5);
        char id[32];
        snprintf(id, sizeof id, "##toast%zu", i);
        ImGui::SetNextWindowPos(ImVec2(8 * g.scale, y), ImGuiCond_Always, ImVec2(0, 1));
        ImGui::SetNextWindowBgAlpha(0.85f * alpha);
        ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(wmax, FLT_MAX));
        ImGui::PushStyleVar(ImGuiStyleVar_Alpha, alpha);
        ImGui::Begin(id, nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                                      ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoSavedSettings);
        ImGui::PushTextWrapPos(wmax - 16 * g.scale);
        ImGui::TextColored(t.error ? ImVec4(1, 0.45f, 0.4f, 1) : ImVec4(0.6f, 0.95f, 0.6f, 1), "%s", t.text.c_str());
        ImGui::PopTextWrapPos();
        y -= ImGui::GetWindowHeight() + 4 * g.scale;
        ImGui::End();
        ImGui::PopStyleVar();
    }
}

void slider_level(st_app *a, const char *label, int display)
{
    st_doc *d = &a->doc;
    int top = (int)d->h.map.top;
    int v = display ? (int)d->display_level : (int)d->edit_level;
    int lo = display ? (int)d->edit_level : 0;
    bool off = display && d->box_on;
    if (off) ImGui::BeginDisabled();
    if (ImGui::SliderInt(label, &v, lo, top) && a->op == ST_OP_NONE) {
        if (display) st_doc_set_display_level(d, (unsigned)v);
        else st_doc_set_edit_level(d, (unsigned)v);
        st_app_sync(a);
    }
    if (off) ImGui::EndDisabled();
}

void action_button(st_app *a, int id, const char *label)
{
    bool on = st_action_enabled(&st_actions[id], a) != 0;
    if (!on) ImGui::BeginDisabled();
    if (ImGui::Button(label)) g.pending_action = id;
    if (!g.probe_dir.empty()) probe_item(probe_name("panel:", label));
    if (!on) ImGui::EndDisabled();
}

void box_section(st_app *a)
{
    st_doc *d = &a->doc;
    bool on = d->box_on != 0;
    if (ImGui::Checkbox("interest box", &on)) g.pending_action = ST_ACT_BOX_TOGGLE;
    probe_item("panel:interest_box");
    if (!d->box_on) return;
    st_adapt_params b = d->box;
    double c[3], s[3];
    for (int k = 0; k < 3; k++) { c[k] = 0.5 * (b.box_lo[k] + b.box_hi[k]); s[k] = b.box_hi[k] - b.box_lo[k]; }
    float speed = 0.005f * (float)a->cc.radius;
    bool changed = ImGui::DragScalarN("centre", ImGuiDataType_Double, c, 3, speed, nullptr, nullptr, "%.3f");
    bool active = ImGui::IsItemActive();
    double smin = 1e-4 * a->cc.radius;
    changed |= ImGui::DragScalarN("size", ImGuiDataType_Double, s, 3, speed, &smin, nullptr, "%.3f");
    probe_item("panel:size");
    active |= ImGui::IsItemActive();
    int base = (int)b.base_level, mx = (int)b.max_level, top = (int)d->h.map.top + 3;
    if (g.box_pending) { base = (int)g.box_next.base_level; mx = (int)g.box_next.max_level; }
    /* The maximum level stops where the memory budget does (the display's
     * estimate, as st_doc_set_box checks it), asked again only when the
     * box or the model changed. */
    if (g.box_allowed_rev != d->revision + 1 || memcmp(&g.box_allowed_for, &b, sizeof b)) {
        g.box_allowed_for = b;
        g.box_allowed_rev = d->revision + 1;
        g.box_allowed = st_doc_box_max_level_allowed(d, &b);
    }
    int allowed = std::max((int)g.box_allowed, mx);
    bool lv = ImGui::SliderInt("base level", &base, 0, top);
    lv |= ImGui::SliderInt("max level", &mx, 0, std::min(top, allowed));
    if (allowed < top && ImGui::IsItemHovered())
        ImGui::SetTooltip("levels above %d would go over the memory budget (--mem-budget)", allowed);
    /* A drag of the fields is one box operation, as a handle drag. */
    if (active && !g.box_dragging) { st_doc_box_begin(d); g.box_dragging = 1; }
    if ((changed || lv) && a->op == ST_OP_NONE) {
        for (int k = 0; k < 3; k++) { b.box_lo[k] = c[k] - 0.5 * s[k]; b.box_hi[k] = c[k] + 0.5 * s[k]; }
        if (base > mx) { if (lv && base != (int)d->box.base_level) mx = base; else base = mx; }
        b.base_level = (unsigned)base;
        b.max_level = (unsigned)mx;
        if (lv) {
            /* A level change can take seconds: the frame that shows the
             * slider's new value is presented first, and the display is
             * computed before the next one (st_gui_run_pending). */
            g.box_next = b;
            g.box_pending = true;
        } else {
            st_error err;
            if (st_doc_set_box(d, &b, 1, &err)) st_app_message(a, 1, "cannot change the box: %s", err.msg);
            st_app_sync(a);
        }
    }
    if (!active && g.box_dragging) { st_doc_box_end(d); g.box_dragging = 0; st_app_sync(a); }
}

/* A collapsible section of the panel, open or closed as the preferences
 * say (open by default); a click that changes it changes them. */
bool section(const char *name, bool open_by_default = true)
{
    bool was = st_prefs_section_open(name, open_by_default ? 1 : 0) != 0;
    ImGui::SetNextItemOpen(was, ImGuiCond_Once);
    bool open = ImGui::CollapsingHeader(name);
    if (!g.probe_dir.empty()) probe_item(probe_name("panel:section:", name));
    if (open != was) st_prefs_set_section_open(name, open);
    return open;
}

/* The panel's width: the preference (in unscaled units), within
 * [200, 60 % of the window] scaled. */
float panel_width(void)
{
    float lo = 200 * g.scale, hi = std::max(lo, ImGui::GetIO().DisplaySize.x * 0.6f);
    return std::min(hi, std::max(lo, g.panel_w));
}

/* The Mask section: the mask brush and the whole-level operations
 * (ui/doc/editor_mask.c), as actions so that keys, menus and this agree. */
void mask_section(st_app *a)
{
    bool on = a->mask_brush != 0;
    if (ImGui::Checkbox("mask brush (Ctrl+stroke erases)", &on)) g.pending_action = ST_ACT_MASK_BRUSH;
    action_button(a, ST_ACT_MASK_CLEAR, "Clear");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_INVERT, "Invert");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_GROW, "Grow");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_SHRINK, "Shrink");
    action_button(a, ST_ACT_MASK_SMOOTH, "Smooth");
    ImGui::SameLine();
    action_button(a, ST_ACT_MASK_CAVITY, "Mask cavities");
}

/* The Layers section (ui/doc/editor_layers.c): the stack top first; a click
 * makes a layer active (and its level the editing level); visibility,
 * strength (one undo step when the slider is released) and the active
 * layer's name. */
void layers_section(st_app *a)
{
    st_doc *d = &a->doc;
    st_layers *ls = &d->layers;
    static float strength[ST_LAYER_MAX];
    static char name[ST_LAYER_NAME];
    static int name_of = -2;
    st_error err;
    if (ImGui::Selectable("(none: the level's own details)", ls->active < 0)) st_doc_layer_set_active(d, -1, &err);
    for (int k = (int)ls->n - 1; k >= 0; k--) {
        st_layer *y = &ls->v[k];
        ImGui::PushID(k);
        bool vis = !y->hidden;
        if (ImGui::Checkbox("##vis", &vis)) {
            if (st_doc_layer_set_hidden(d, k, !vis, &err)) st_app_message(a, 1, "%s", err.msg);
            st_app_sync(a);
        }
        ImGui::SameLine();
        char label[ST_LAYER_NAME + 32];
        snprintf(label, sizeof label, "%s  (level %u)", y->name, y->level);
        if (ImGui::Selectable(label, ls->active == k, 0, ImVec2(120 * g.scale, 0))) {
            st_doc_layer_set_active(d, k, &err);
            st_app_sync(a);
        }
        ImGui::SameLine();
        if (!ImGui::IsAnyItemActive() || !strength[k]) strength[k] = (float)y->strength;
        ImGui::SetNextItemWidth(80 * g.scale);
        ImGui::SliderFloat("##s", &strength[k], 0.0f, (float)ST_LAYER_STRENGTH_MAX, "%.2f");
        if (ImGui::IsItemDeactivatedAfterEdit()) {
            if (st_doc_layer_set_strength(d, k, strength[k], &err)) st_app_message(a, 1, "%s", err.msg);
            st_app_sync(a);
        }
        ImGui::PopID();
    }
    action_button(a, ST_ACT_LAYER_ADD, "New");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_UP, "Up");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_DOWN, "Down");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_MERGE, "Merge");
    ImGui::SameLine();
    action_button(a, ST_ACT_LAYER_DELETE, "Delete");
    int k = ls->active;
    if (k >= 0 && (uint32_t)k < ls->n) {
        if (name_of != k || !ImGui::IsAnyItemActive()) {
            snprintf(name, sizeof name, "%s", ls->v[k].name);
            name_of = k;
        }
        ImGui::InputText("name", name, sizeof name);
        if (ImGui::IsItemDeactivatedAfterEdit() && strcmp(name, ls->v[k].name)) {
            if (st_doc_layer_rename(d, k, name, &err)) st_app_message(a, 1, "%s", err.msg);
        }
    }
}

/* The Filter section of a progressive model (ui/doc/editor_filter.c): a gain
 * per band of details, level 1 (coarsest) to the top, and Apply, which
 * scales the details and re-synthesises as one undo step; the gains then
 * go back to 1, since the details now carry the change. */
void filter_section(st_app *a)
{
    st_doc *d = &a->doc;
    static float gains[ST_MAX_LEVELS];
    static unsigned shown_top = ~0u;
    unsigned top = d->h.map.top;
    if (shown_top != top) {
        for (float &x : gains) x = 1.0f;
        shown_top = top;
    }
    /* Presets first (what most users want), Apply and Reset next to them,
     * the per-level gains below for whoever wants them. */
    for (int p = 0; p < ST_FILTER_NPRESETS; p++) {
        if (p % 2) ImGui::SameLine();
        char label[48];
        snprintf(label, sizeof label, "%s", st_filter_preset_name(p));
        if (ImGui::Button(label)) {
            double gd[ST_MAX_LEVELS];
            st_filter_preset_gains(p, top, gd);
            for (unsigned k = 0; k < top; k++) gains[k] = (float)gd[k];
        }
        if (!g.probe_dir.empty()) probe_item(probe_name("panel:filter:", label));
    }
    bool any = false;
    for (unsigned l = 1; l <= top; l++) any |= gains[l - 1] != 1.0f;
    if (!any) ImGui::BeginDisabled();
    bool apply = ImGui::Button("Apply");
    if (!g.probe_dir.empty()) probe_item("panel:filter:apply");
    ImGui::SameLine();
    bool reset = ImGui::Button("Reset");
    if (!any) ImGui::EndDisabled();
    if (ImGui::TreeNode("gains per level")) {
        ImGui::TextWrapped("details of each level: 0 removes them (smoother), 1 keeps them, 2 doubles them");
        for (unsigned l = 1; l <= top; l++) {
            char label[32];
            snprintf(label, sizeof label, "level %u", l);
            ImGui::SliderFloat(label, &gains[l - 1], 0.0f, 2.0f, "%.2f");
            if (!g.probe_dir.empty()) probe_item(probe_name("panel:filter:", label));
        }
        ImGui::TreePop();
    }
    if (apply && a->op == ST_OP_NONE) {
        double gd[ST_MAX_LEVELS];
        for (unsigned k = 0; k < top; k++) gd[k] = gains[k];
        if (!st_app_filter(a, gd, top)) reset = true;
    }
    if (reset)
        for (float &x : gains) x = 1.0f;
}

void side_panel(st_app *a)
{
    ImGuiIO &io = ImGui::GetIO();
    float w = panel_width();
    /* Its width follows a drag of the left edge (and is remembered); the
     * height fits the content (a 0 size axis is fitted each frame).  The
     * corner grips are not drawn: only the edge resizes. */
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - w, menu_height), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(w, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(200 * g.scale, 0), ImVec2(std::max(200 * g.scale, io.DisplaySize.x * 0.6f), io.DisplaySize.y - menu_height));
    ImGui::PushStyleColor(ImGuiCol_ResizeGrip, ImVec4(0, 0, 0, 0));
    ImGui::PushStyleColor(ImGuiCol_ResizeGripHovered, ImVec4(0, 0, 0, 0));
    ImGui::PushStyleColor(ImGuiCol_ResizeGripActive, ImVec4(0, 0, 0, 0));
    ImGui::Begin("Strata", nullptr, ImGuiWindowFlags_NoMove);
    ImGui::PopStyleColor(3);
    probe_rect_at("window:panel", ImGui::GetWindowPos(),
                  ImVec2(ImGui::GetWindowPos().x + ImGui::GetWindowWidth(), ImGui::GetWindowPos().y + ImGui::GetWindowHeight()));
    if (std::fabs(ImGui::GetWindowWidth() - w) >= 1) {
        g.panel_w = ImGui::GetWindowWidth();
        st_prefs_set_panel_width(g.panel_w / g.scale);
    }
    st_doc *d = &a->doc;
    ImGui::PushItemWidth(150 * g.scale);
    if (!d->loaded) {
        ImGui::TextUnformatted("No model: File > Open, or drop a file");
    } else {
        uint64_t faces = 0, verts = 0;
        st_doc_display_counts(d, &faces, &verts);
        ImGui::Text("%s  (%s)", st_path_base(d->path), d->scheme ? d->scheme->name : "?");
        if (section("Levels")) {
            slider_level(a, "editing", 0);
            slider_level(a, "displayed", 1);
            ImGui::Text("%llu faces, %llu vertices", (unsigned long long)faces, (unsigned long long)verts);
            ImGui::Text("editing level: %u vertices", a->r.has_cage ? a->r.cage.nverts : 0);
            action_button(a, ST_ACT_ADD_LEVEL, "Add level");
            ImGui::SameLine();
            action_button(a, ST_ACT_DELETE_FINEST, "Delete finest");
            ImGui::SameLine();
            action_button(a, ST_ACT_DELETE_COARSEST, "Rebase");
        }
        if (section("Tool")) {
            /* Three tools a row (clay strips, the longest name, in the middle column). */
            static const int tools[] = { ST_ACT_TOOL_SELECT, ST_ACT_BRUSH_GRAB,    ST_ACT_BRUSH_DRAW,
                                         ST_ACT_BRUSH_SMOOTH, ST_ACT_BRUSH_FLATTEN, ST_ACT_BRUSH_CREASE,
                                         ST_ACT_BRUSH_PINCH,  ST_ACT_BRUSH_INFLATE, ST_ACT_BRUSH_LAYER,
                                         ST_ACT_BRUSH_RELAX,  ST_ACT_BRUSH_CLAY_STRIPS };
            static const int brush_of[] = { ST_TOOL_SELECT, ST_BRUSH_GRAB, ST_BRUSH_DRAW, ST_BRUSH_SMOOTH,
                                            ST_BRUSH_FLATTEN, ST_BRUSH_CREASE, ST_BRUSH_PINCH, ST_BRUSH_INFLATE,
                                            ST_BRUSH_LAYER, ST_BRUSH_RELAX, ST_BRUSH_CLAY_STRIPS };
            const int ntools = (int)(sizeof tools / sizeof tools[0]);
            for (int i = 0; i < ntools; i++) {
                if (i % 3) ImGui::SameLine((float)(i % 3) * 88 * g.scale);
                const char *name = brush_of[i] == ST_TOOL_SELECT ? "select" : st_brush_name(brush_of[i]);
                if (ImGui::RadioButton(name, st_action_checked(&st_actions[tools[i]], a) > 0)) g.pending_action = tools[i];
                if (!g.probe_dir.empty()) probe_item(probe_name("panel:", name));
            }
            float r = (float)d->brush.radius, s = (float)d->brush.strength;
            float rmax = (float)a->cc.radius;
            /* At a coarse level a dab takes in at least the faces under the
             * cursor (st_doc_brush_reach): the slider says so when that is
             * more (in its text, so that the panel's rows stay put). */
            double reach = a->tool != ST_TOOL_SELECT && d->loaded ? st_doc_brush_reach(d) : d->brush.radius;
            char rfmt[48] = "%.4g";
            if (reach > d->brush.radius) snprintf(rfmt, sizeof rfmt, "%%.4g (reach %.3g)", reach);
            if (ImGui::SliderFloat("radius", &r, 0.002f * rmax, rmax, rfmt, ImGuiSliderFlags_Logarithmic)) d->brush.radius = r;
            probe_item("panel:radius");
            if (ImGui::SliderFloat("strength", &s, 0.02f, 1.0f, "%.2f")) d->brush.strength = s;
            /* Symmetry in the model's axes (brush.c). */
            bool mx = d->brush.mirror_x != 0, my = d->brush.mirror_y != 0, mz = d->brush.mirror_z != 0;
            if (ImGui::Checkbox("X", &mx)) d->brush.mirror_x = mx;
            ImGui::SameLine();
            if (ImGui::Checkbox("Y", &my)) d->brush.mirror_y = my;
            ImGui::SameLine();
            if (ImGui::Checkbox("Z mirror", &mz)) d->brush.mirror_z = mz;
            ImGui::SameLine();
            ImGui::Text(" selected %u", d->nsel);
            if (ImGui::TreeNode("falloff, spacing, stabiliser")) {
                if (ImGui::BeginCombo("falloff", st_falloff_name(d->brush.falloff))) {
                    for (int k = 0; k < ST_FALLOFF_COUNT; k++)
                        if (ImGui::Selectable(st_falloff_name(k), d->brush.falloff == k)) d->brush.falloff = k;
                    ImGui::EndCombo();
                }
                float sp = (float)d->brush.spacing;
                if (ImGui::SliderFloat("spacing", &sp, 0.0f, 1.0f, "%.2f radius")) d->brush.spacing = sp;
                /* Per brush (brush.c: autosmooth); the stroke's fade (in and out),
                 * spacing attenuation and hold for every brush. */
                float as = (float)d->brush.autosmooth, fade = (float)d->brush.fade;
                if (ImGui::SliderFloat("auto-smooth", &as, 0.0f, 1.0f, "%.2f")) d->brush.autosmooth = as;
                if (ImGui::SliderFloat("fade", &fade, 0.0f, 4.0f, "%.2f radius each end")) d->brush.fade = fade;
                bool atten = d->brush.space_atten != 0, hold = d->brush.hold != 0;
                if (ImGui::Checkbox("strength for spacing", &atten)) d->brush.space_atten = atten;
                ImGui::SameLine();
                if (ImGui::Checkbox("hold the surface", &hold)) d->brush.hold = hold;
                bool lazy = d->brush.stabilize != 0;
                if (ImGui::Checkbox("stabiliser", &lazy)) d->brush.stabilize = lazy;
                ImGui::SameLine();
                bool front = d->brush.front_only != 0;
                if (ImGui::Checkbox("front faces only", &front)) d->brush.front_only = front;
                ImGui::TreePop();
            }
        }
        if (section("Interest box")) box_section(a);
        if (section("Display")) {
            int sh = a->shading;
            if (ImGui::RadioButton("smooth", sh == ST_SHADE_SMOOTH)) a->shading = ST_SHADE_SMOOTH;
            ImGui::SameLine();
            if (ImGui::RadioButton("flat", sh == ST_SHADE_FLAT)) a->shading = ST_SHADE_FLAT;
            ImGui::SameLine();
            bool cage = a->cage != 0, wire = a->wire != 0;
            if (ImGui::Checkbox("cage", &cage)) g.pending_action = ST_ACT_CAGE;
            ImGui::SameLine();
            if (ImGui::Checkbox("wire", &wire)) a->wire = wire;
        }
        /* Last, so that the sections above keep their places. */
        if (section("Mask", false)) mask_section(a);
        if (section("Layers", false)) layers_section(a);
        if (d->scheme == st_scheme_find("progressive") && section("Filter", false)) filter_section(a);
    }
    if (section("Timings")) {
        char t1[32], t2[32], t3[32];
        ImGui::Text("frame %s", st_app_fmt_ms(a, a->frame_ms, t1, sizeof t1));
        ImGui::Text("update: geometry %s, buffers %s", st_app_fmt_ms(a, d->loaded ? d->last_update_ms : 0, t2, sizeof t2),
                    st_app_fmt_ms(a, a->update_ms, t3, sizeof t3));
        ImGui::Text("undo %u/%u   %s", d->undo_pos, d->nundo, a->cc.cam.ortho ? "ortho" : "persp");
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

}  // namespace

/* ---- the C API ---------------------------------------------------------------------------- */

extern "C" {

int st_gui_init(st_app *a, int shown)
{
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO &io = ImGui::GetIO();
    io.IniFilename = nullptr;   /* preferences are ours (prefs.c), no imgui.ini in the working directory */
    ImGui::StyleColorsDark();
    /* The window's callbacks stay the window's: they pass events on (gui.h). */
    if (!ImGui_ImplGlfw_InitForOpenGL(a->win, false) || !ImGui_ImplOpenGL3_Init("#version 330")) {
        fprintf(stderr, "strata: the interface (Dear ImGui) did not start; the window works without it\n");
        ImGui::DestroyContext();
        return -1;
    }
    float xs = 1, ys = 1;
    glfwGetWindowContentScale(a->win, &xs, &ys);
    /* --ui-scale, else the preference, else the monitor's content scale. */
    g.scale = a->opts.ui_scale > 0 ? a->opts.ui_scale
              : st_prefs_ui_scale() > 0 ? st_prefs_ui_scale() : std::max(1.0f, std::max(xs, ys));
    g.panel_w = (st_prefs_panel_width() > 0 ? st_prefs_panel_width() : 290) * g.scale;
    const char *probe = getenv("STRATA_GUI_PROBE");
    if (probe && probe[0]) g.probe_dir = probe;
    if (g.scale != 1) {
        ImGui::GetStyle().ScaleAllSizes(g.scale);
        io.FontGlobalScale = g.scale;
    }
    ImGui::GetStyle().WindowRounding = 0;
    ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 0.85f;
    g.win = a->win;
    g.shown = shown != 0;
    g.init = true;
    return 0;
}

void st_gui_shutdown(void)
{
    if (!g.init) return;
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    g = gui_state();
}

int st_gui_shown(void) { return g.init && g.shown; }
void st_gui_set_shown(int on) { g.shown = on != 0; }

void st_gui_frame(st_app *a)
{
    if (!st_gui_shown() || g.in_frame) return;
    g.in_frame = true;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGuiIO &io = ImGui::GetIO();
    io.MousePos = ImVec2(g.mx, g.my);
    /* What you click is what you see: ImGui applies a wheel's scroll in
     * the frame that reads it, so a press read in the same frame would hit
     * the item under the pointer after the scroll, which no frame has shown
     * (the list drawn at the old position, the click on another folder).
     * The user clicked what the last frame showed: while a button is down,
     * and in the frame of its release (ImGui's click is a press and a
     * release on the same item), a wheel waits, and scrolls the frame after. */
    io.MouseWheel += g.held_wheel[0];
    io.MouseWheelH += g.held_wheel[1];
    g.held_wheel[0] = g.held_wheel[1] = 0;
    bool clicking = false;
    for (int i = 0; i < 5; i++) {
        bool want = i < 3 && (g.down[i] || g.pressed[i]);
        clicking = clicking || want || (i < 3 && g.fed_down[i]);
        io.MouseDown[i] = want;
        if (i < 3) { g.fed_down[i] = want; g.pressed[i] = false; }
    }
    if (clicking && (io.MouseWheel != 0 || io.MouseWheelH != 0)) {
        g.held_wheel[0] = io.MouseWheel;
        g.held_wheel[1] = io.MouseWheelH;
        io.MouseWheel = io.MouseWheelH = 0;
    }
    if (a->masked_times) io.DeltaTime = 1.0f / 60;   /* replays: the same frames whatever the clock */
    ImGui::NewFrame();
    g.probe.clear();
    g.menu_path.clear();
    if (a->busy || a->working[0]) {
        progress_window(a);
    } else {
        if (ImGui::BeginMainMenuBar()) {
            menu_pass m;
            m.a = a;
            menus(m);
            menu_height = ImGui::GetWindowSize().y;
            ImGui::EndMainMenuBar();
        }
        side_panel(a);
        scheme_window(a);
        quit_window(a);
        about_window();
        prefs_window(a);
        bake_window(a);
        keys_window(a);
        if (g.dlg_open) file_dialog(a);
        toasts(a);
    }
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    g.frames++;
    probe_write(a);
    release_held_keys();
    g.in_frame = false;
}

void st_gui_run_pending(st_app *a)
{
    if (g.box_pending) {
        g.box_pending = false;
        st_error err;
        if (a->doc.loaded && st_doc_set_box(&a->doc, &g.box_next, 1, &err))
            st_app_message(a, 1, "cannot change the box: %s", err.msg);
        st_app_sync(a);
    }
    if (g.pending_action >= 0) {
        int id = g.pending_action;
        g.pending_action = -1;
        if (st_action_enabled(&st_actions[id], a)) st_actions[id].run(a);
    }
    st_app_run_requested(a);
    if (g.bake_go) {
        g.bake_go = false;
        absolute_path(a->bake.normal, sizeof a->bake.normal);
        absolute_path(a->bake.disp, sizeof a->bake.disp);
        int rc = st_app_bake_maps(a);
        if (rc == 0) { g.bake = false; g.bake_error.clear(); }
        else g.bake_error = rc == ST_APP_CANCELLED ? "" : a->msg;
    }
    if (g.dlg_accept) {
        g.dlg_accept = false;
        g.dlg_confirm = false;
        dialog_accept(a, g.dlg_kind, completed_path(g.dlg_kind, g.path));
    }
}

void st_gui_cursor(double x, double y)
{
    g.mx = (float)x;
    g.my = (float)y;
}

int st_gui_mouse_button(st_app *a, int button, int action, int mods)
{
    (void)mods;
    if (!st_gui_shown() || button < 0 || button >= 3) return 0;
    if (action == GLFW_RELEASE) { g.down[button] = false; return 0; }
    if (a->op != ST_OP_NONE || !ImGui::GetIO().WantCaptureMouse) return 0;
    g.down[button] = g.pressed[button] = true;
    return 1;
}

void st_gui_job_mouse_button(int button, int action)
{
    if (!st_gui_shown() || button < 0 || button >= 3) return;
    if (action == GLFW_RELEASE) g.down[button] = false;
    else g.down[button] = g.pressed[button] = true;
}

const char *st_gui_dialog_dir(void)
{
    size_t k = g.cwd.find_last_of('/');
    return k == std::string::npos ? g.cwd.c_str() : g.cwd.c_str() + k + 1;
}

float st_gui_panel_pixels(int win_w)
{
    if (!g.init || !g.shown) return 0;
    float lo = 200 * g.scale, hi = std::max(lo, (float)win_w * 0.6f);   /* panel_width() before the first frame */
    return std::min(hi, std::max(lo, g.panel_w));
}

int st_gui_wants_frames(void)
{
    if (!g.init || !g.shown) return 0;
    ImGuiIO &io = ImGui::GetIO();
    return g.box_pending || g.held_wheel[0] != 0 || g.held_wheel[1] != 0 || io.MouseWheel != 0 || io.MouseWheelH != 0;
}

int st_gui_scroll(double dx, double dy)
{
    if (!st_gui_shown() || !ImGui::GetIO().WantCaptureMouse) return 0;
    ImGuiIO &io = ImGui::GetIO();
    io.MouseWheelH += (float)dx;
    io.MouseWheel += (float)dy;
    return 1;
}

int st_gui_key(int key, int scancode, int action, int mods)
{
    if (!g.init) return 0;
    if (!g.shown) release_held_keys();   /* no frame will see them */
    bool seen = std::find(g.keys_pressed.begin(), g.keys_pressed.end(), key) != g.keys_pressed.end();
    if (action == GLFW_RELEASE && seen) g.held_releases.push_back({ key, scancode, mods });
    else ImGui_ImplGlfw_KeyCallback(g.win, key, scancode, action, mods);
    if (action == GLFW_PRESS && !seen) g.keys_pressed.push_back(key);
    if (!g.shown || action == GLFW_RELEASE) return 0;
    switch (key) {
    case GLFW_KEY_LEFT_SHIFT: case GLFW_KEY_RIGHT_SHIFT: case GLFW_KEY_LEFT_CONTROL: case GLFW_KEY_RIGHT_CONTROL:
    case GLFW_KEY_LEFT_ALT: case GLFW_KEY_RIGHT_ALT: case GLFW_KEY_LEFT_SUPER: case GLFW_KEY_RIGHT_SUPER: return 0;
    default: break;
    }
    return ImGui::GetIO().WantCaptureKeyboard ? 1 : 0;
}

void st_gui_char(unsigned c)
{
    if (st_gui_shown()) ImGui::GetIO().AddInputCharacter(c);
}

void st_gui_open_dialog(st_app *a, int kind) { open_dialog(a, kind, 0); }
void st_gui_show_about(void) { g.about = true; }
void st_gui_show_prefs(void) { g.prefs = true; }
void st_gui_show_bake(st_app *a)
{
    st_app_bake_defaults(a);
    g.bake = true;
    g.bake_error.clear();
    g.shown = true;
}
int st_gui_bake_shown(void) { return g.bake; }

int st_gui_bake_set(st_app *a, const char *what, const char *value, char *msg, size_t n)
{
    st_app_bake *b = &a->bake;
    if (!a->doc.loaded) { snprintf(msg, n, "no model"); return -1; }
    st_app_bake_defaults(a);
    auto flag = [&](int *f) {
        if (!value || (strcmp(value, "on") && strcmp(value, "off"))) { snprintf(msg, n, "bake %s on|off", what); return -1; }
        *f = !strcmp(value, "on");
        return 0;
    };
    auto number = [&](int *f, long lo, long hi) {
        char *end = nullptr;
        long v = value ? strtol(value, &end, 10) : -1;
        if (!value || !*value || *end || v < lo || v > hi) { snprintf(msg, n, "bake %s: a number in %ld..%ld", what, lo, hi); return -1; }
        *f = (int)v;
        return 0;
    };
    auto path = [&](char *p, size_t pn, int *want) {
        if (!value) { snprintf(msg, n, "bake %s PATH|none", what); return -1; }
        *want = strcmp(value, "none") != 0;
        if (*want) {
            if (strlen(value) >= pn) { snprintf(msg, n, "bake %s: path too long", what); return -1; }
            snprintf(p, pn, "%s", value);
            absolute_path(p, pn);
        }
        return 0;
    };
    int top = (int)a->doc.h.map.top;
    if (!strcmp(what, "base")) return number(&b->base, 0, top);
    if (!strcmp(what, "level")) return number(&b->level, 0, top);
    if (!strcmp(what, "size")) return number(&b->size, 1, 16384);
    if (!strcmp(what, "padding")) return number(&b->padding, 0, 254);
    if (!strcmp(what, "normal")) return path(b->normal, sizeof b->normal, &b->want_normal);
    if (!strcmp(what, "disp")) return path(b->disp, sizeof b->disp, &b->want_disp);
    if (!strcmp(what, "vector")) return flag(&b->vector);
    if (!strcmp(what, "bits16")) return flag(&b->bits16);
    if (!strcmp(what, "auto_uv")) return flag(&b->auto_uv);
    if (!strcmp(what, "attach")) return flag(&b->attach);
    if (!strcmp(what, "space")) {
        if (!value || (strcmp(value, "tangent") && strcmp(value, "object"))) { snprintf(msg, n, "bake space tangent|object"); return -1; }
        b->space = !strcmp(value, "object") ? ST_BAKE_OBJECT : ST_BAKE_TANGENT;
        return 0;
    }
    if (!strcmp(what, "udim")) {
        if (!value || (strcmp(value, "auto") && strcmp(value, "on") && strcmp(value, "off"))) { snprintf(msg, n, "bake udim auto|on|off"); return -1; }
        b->udim = !strcmp(value, "auto") ? -1 : !strcmp(value, "on");
        return 0;
    }
    if (!strcmp(what, "run")) {
        /* The dialog's Bake button: a refusal is the status line's error
         * (expect error 1), as in the dialog. */
        g.bake_go = false;
        int rc = st_app_bake_maps(a);
        if (rc == 0) { g.bake = false; g.bake_error.clear(); }
        else g.bake_error = rc == ST_APP_CANCELLED ? "" : a->msg;
        return 0;
    }
    snprintf(msg, n, "bake %s: not one of base, level, size, padding, normal, disp, vector, bits16, auto_uv, space, udim, attach, run", what);
    return -1;
}

int st_app_export(st_app *a, const char *path)
{
    st_doc *d = &a->doc;
    if (!d->loaded) { st_app_message(a, 1, "nothing to export"); return -1; }
    st_mesh m;
    st_mesh_init(&m);
    st_error err;
    /* The displayed hierarchy: the model's, or the adaptive one with the box on. */
    st_hier *h = (st_hier *)st_doc_display_hier(d);
    unsigned l = st_doc_display_map_level(d);
    /* With the baked normal map: the bake's base level of the model, its
     * UVs (or the bake's atlas) and tangents (strata convert --normal-map). */
    int mapped = st_gltf_is_gltf_path(path) && a->bake.attach && st_app_can_show_baked(a);
    if (mapped) { h = &d->h; l = a->bake.have_base; }
    int rc = st_hier_level_mesh(h, l, &m, &err);
    if (!rc && mapped) rc = st_gltf_save_level_mapped(path, h, l, &m, a->bake.have_auto_uv, a->bake.have_map, &err);
    else if (!rc) rc = st_gltf_is_gltf_path(path) ? st_gltf_save(path, &m, &err) : st_mesh_save(path, &m, &err);
    if (rc) st_app_message(a, 1, "cannot export %s: %s", st_path_base(path), err.msg);
    else if (mapped) st_app_message(a, 0, "exported %s (level %u, %u faces) with the baked normal map %s", st_path_base(path), l,
                                    (unsigned)m.nfaces, st_path_base(a->bake.have_map));
    else st_app_message(a, 0, "exported %s (%s %u, %u faces)", st_path_base(path), d->box_on ? "adaptive mesh at level" : "level", l,
                        (unsigned)m.nfaces);
    st_mesh_free(&m);
    return rc;
}

int st_gui_menu_activate(st_app *a, const char *path, const char *arg, char *msg, size_t n)
{
    menu_pass m;
    m.a = a;
    m.draw = false;
    m.arg = arg;
    std::string p = path;
    size_t s = 0;
    for (size_t i = 0; i <= p.size(); i++)
        if (i == p.size() || p[i] == '/') { m.path.push_back(p.substr(s, i - s)); s = i + 1; }
    menus(m);
    if (m.found && m.error.empty()) return 0;
    snprintf(msg, n, "%s", !m.error.empty() ? m.error.c_str() : "no such menu item");
    return -1;
}

}  // extern "C"
