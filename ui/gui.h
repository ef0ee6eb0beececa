/* The window's interface drawn with Dear ImGui (libimgui-dev 1.86, C++):
 * a menu bar generated from the action table (actions.h), a side panel,
 * a file dialog, the scheme question and a progress window for long jobs.
 * Dear ImGui stays in ui/gui*.cc and ui/file_browser.cc; this is their C API.
 *
 * Input: the window's GLFW handlers (window.c, controller.c), which the replay calls too,
 * pass every event here first.  A press, a wheel turn or a key goes to the
 * GUI alone when ImGui wants it (io.WantCaptureMouse / WantCaptureKeyboard:
 * the pointer is over a menu or panel, a text field is active, a dialog is
 * open); releases, cursor moves and modifiers always reach the 3D view as
 * well, so its camera and brush operations end cleanly.  The pointer and
 * buttons ImGui sees are the ones those events carried, not polled from the
 * X server, so that replays are deterministic.
 *
 * Actions chosen in the GUI run after the GUI's frame (st_gui_run_pending),
 * never inside it: a long job draws frames of its own (jobs.c).
 *
 * Tests: with STRATA_GUI_PROBE=DIR each frame writes DIR/gui (frame
 * number, document values, the rectangles of the widgets a test clicks:
 * "rect menu:File/Open x0 y0 x1 y1"), so that tests/cli/cli_gui_xdotool.sh
 * clicks where the widgets are. */
#ifndef ST_GUI_H
#define ST_GUI_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct st_app;

/* After the window's GLFW callbacks are installed.  0, or -1 (the window
 * then works without the GUI; the reason is printed). */
int st_gui_init(struct st_app *a, int shown);
void st_gui_shutdown(void);

/* Whether the GUI is drawn (and takes input); F10 / View > Interface. */
int st_gui_shown(void);
void st_gui_set_shown(int on);

/* Builds and draws the GUI over the frame in the back buffer. */
void st_gui_frame(struct st_app *a);
/* Runs what the GUI chose during its last frame. */
void st_gui_run_pending(struct st_app *a);

/* Events (window coordinates); the _mouse_button, _scroll and _key ones
 * return 1 when the GUI took the event and the 3D view must ignore it. */
void st_gui_cursor(double x, double y);
int st_gui_mouse_button(struct st_app *a, int button, int action, int mods);
/* During a job (jobs.c) the buttons go to the GUI whatever it wants: its
 * progress window is the only thing that takes input then. */
void st_gui_job_mouse_button(int button, int action);
int st_gui_scroll(double dx, double dy);
/* Input the GUI has not shown the effect of yet (a wheel, a press held
 * for the frame after a wheel): the window draws on. */
int st_gui_wants_frames(void);
/* Width of the side panel on the right, in window coordinates (0 when the
 * GUI is hidden): framing centres the model in what it leaves free. */
float st_gui_panel_pixels(int win_w);
/* The file dialog's folder, its last component ("" when none): replays. */
const char *st_gui_dialog_dir(void);
int st_gui_key(int key, int scancode, int action, int mods);
void st_gui_char(unsigned c);

/* The file dialog (Ctrl+O, Ctrl+Shift+S, Ctrl+E). */
enum st_gui_dialog { ST_DIALOG_OPEN, ST_DIALOG_SAVE_AS, ST_DIALOG_EXPORT, ST_DIALOG_IMPORT };
void st_gui_open_dialog(struct st_app *a, int kind);

/* Help > About. */
void st_gui_show_about(void);
/* Edit > Preferences: the preferences window (ui/prefs.h). */
void st_gui_show_prefs(void);
/* Bake > Bake maps...: the Bake dialog (ui/bake_ui.c holds its settings);
 * whether it is up. */
void st_gui_show_bake(struct st_app *a);
int st_gui_bake_shown(void);
/* The replay's `bake SETTING VALUE`: a field of the Bake dialog (base,
 * level, size, padding N; normal, disp PATH|none; vector, bits16, auto_uv
 * on|off; space tangent|object; udim auto|on|off), the export dialog's
 * "attach" on|off, or `bake run`: its Bake button.  0, or -1 with the
 * reason in msg. */
int st_gui_bake_set(struct st_app *a, const char *what, const char *value, char *msg, size_t n);

/* Writes the displayed mesh (the displayed level, or the adaptive mesh
 * while the interest box is on) by extension: .obj .ply .gltf .glb. */
int st_app_export(struct st_app *a, const char *path);

/* The replay's `menu PATH [ARG]`: activates the menu item PATH
 * ("File/Export/glTF", "View/Wireframe") as a click would; ARG is the file
 * name a dialog would ask for.  0, or -1 with the reason in msg. */
int st_gui_menu_activate(struct st_app *a, const char *path, const char *arg, char *msg, size_t n);

#ifdef __cplusplus
}
#endif

#endif
