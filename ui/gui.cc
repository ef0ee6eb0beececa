/* The window's interface with Dear ImGui 1.86, behind gui.h (with
 * file_browser.cc, the file dialog; gui_internal.h is what they share).  Menus are generated from the action table
 * (actions.h), so a menu item, its shortcut text and the F1 row come from
 * one entry; the items that open a dialog or pick a scheme are the same
 * actions with a submenu.  See gui.h for the input routing. */
#include "gui_internal.h"

extern "C" {
#include "actions.h"
#include "prefs.h"
#include "window.h"
#include "core/io/mesh.h"
#include "core/io/session.h"
#include "core/multires/hier.h"
#include "core/fvar/fvar.h"
#include "formats/gltf_io.h"
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

namespace stgui {

const char *const read_exts[6] = { ".obj", ".off", ".ply", ".gltf", ".glb", ".strata" };
const char *const export_exts[4] = { ".obj", ".ply", ".gltf", ".glb" };
const char *const export_labels[4] = { "OBJ...", "PLY...", "glTF...", "GLB..." };
const char *const schemes[6] = { "catmull-clark", "loop", "butterfly", "quad-triangle", "sqrt3", "doo-sabin" };

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
 * so that tests/cli/cli_gui_xdotool.sh computes where to click instead of
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

/* Messages (st_app_message: "saved ...", errors) as notifications at the
 * bottom left that take no input and fade: 4 s, errors 8 s, the last 3
 * stacked.  With times masked (replays, tests) they stay until newer ones
 * push them out, so that screenshots do not depend on the clock. */
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

}  // namespace stgui

using namespace stgui;

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
    if (!rc && mapped) rc = st_gltf_save_level_mapped(path, h, l, &m, a->bake.have_auto_uv, a->bake.have_size, a->bake.have_padding,
                                                         a->bake.have_map, &err);
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
