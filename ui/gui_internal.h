/* Shared by the files of the window's Dear ImGui interface (C++): gui.cc
 * (menus, notifications, the probe, the C API of gui.h), gui_panel.cc (the
 * side panel), gui_windows.cc (the other windows) and file_browser.cc (the
 * file dialog).  Not part of gui.h's API. */
#ifndef ST_GUI_INTERNAL_H
#define ST_GUI_INTERNAL_H

extern "C" {
#include "gui.h"
#include "window.h"
}

#include <cfloat>
#include <cstdint>
#include <string>
#include <vector>

#include <imgui.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace stgui {

struct file_entry {
    std::string name;
    bool dir;
    long long size;
};

/* The formats Strata reads (core/io/mesh.h, formats/gltf_io.h, sessions) and
 * writes (sessions, and the exporters). */
extern const char *const read_exts[6];
extern const char *const export_exts[4];
extern const char *const export_labels[4];
extern const char *const schemes[6];

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

extern gui_state g;

/* ---- gui.cc ---- */
/* Widget rectangles for tests (STRATA_GUI_PROBE): the item just submitted. */
void probe_item(const char *name);
void probe_item(const std::string &name);
/* A widget's name for the probe: prefix + label without "##..." or a
 * trailing "...", spaces as '_'. */
std::string probe_name(const std::string &prefix, const char *label);
/* A rectangle (window coordinates) under a name. */
void probe_rect_at(const std::string &name, ImVec2 lo, ImVec2 hi);
/* Height of the menu bar (the last frame's). */
extern float menu_height;

/* ---- gui_panel.cc ---- */
/* The side panel's width now (window units). */
float panel_width(void);
void side_panel(st_app *a);

/* ---- gui_windows.cc ---- */
void quit_window(st_app *a);       /* unsaved changes on quit */
void scheme_window(st_app *a);     /* the scheme question of an open */
void about_window(void);
void prefs_window(st_app *a);
void bake_window(st_app *a);       /* Bake > Bake maps... */
void keys_window(st_app *a);       /* the key list (F1) */
void progress_window(st_app *a);   /* a job's stage, fraction and Cancel */
/* p made absolute against the working directory, in place (n bytes). */
void absolute_path(char *p, size_t n);

/* ---- file_browser.cc ---- */
/* Opens the file dialog of `kind` (ST_DIALOG_*; export: format, an index
 * in export_exts) in the open document's folder. */
void open_dialog(st_app *a, int kind, int format);
/* Draws it (in the ImGui frame); a choice sets g.dlg_accept. */
void file_dialog(st_app *a);
/* The dialog's path completed with the extension its kind writes. */
std::string completed_path(int kind, const char *p);
/* Runs the dialog's choice (outside the ImGui frame: opening is a job). */
void dialog_accept(st_app *a, int kind, const std::string &path);

}  // namespace stgui

#endif
