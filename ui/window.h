/* The modeller window: one GLFW window with an OpenGL 3.3 core
 * context, the document (editor.h), the renderer, picking, the HUD and the
 * scripted input (replay.h).
 *
 * Every input goes through the GLFW callbacks below; the replay calls the
 * same functions with the arguments GLFW would pass, one event per frame,
 * so scripted runs exercise the real handlers.  After each handler the
 * window reads st_doc_take_change() and updates the renderer incrementally
 * (st_renderer_refresh with core's footprint for moved vertices, set_level / set_cage for topology).
 */
#ifndef ST_WINDOW_H
#define ST_WINDOW_H

#include <stddef.h>
#include <stdint.h>

#include "camera_ctl.h"
#include "editor.h"
#include "hud.h"
#include "render/nmap.h"
#include "pick.h"
#include "render/renderer.h"
#include "render/scene_sync.h"

typedef struct GLFWwindow GLFWwindow;

typedef struct st_win_opts {
    const char *file;          /* NULL: the default asset */
    const char *scheme;        /* NULL: catmull-clark */
    int levels;                /* -1: default */
    int width, height;         /* window size */
    const char *replay;        /* events file, NULL: interactive */
    const char *screenshot_dir;/* where `screenshot NAME` writes (default ".") */
    const char *compare_dir;   /* replay screenshots compared with DIR/NAME */
    int bench;                 /* --bench-interaction */
    int bench_steps;           /* drag steps of the benchmark */
    double mem_budget_mb;      /* > 0: the document's memory budget (MiB) */
    int no_gui;                /* start with the GUI (gui.h) hidden */
    int size_given;            /* --size: the preferences' window size does not apply */
    float ui_scale;            /* --ui-scale: > 0 overrides the preference and the monitor's */
    int strict;                /* --strict: refuse non-manifold meshes instead of splitting them (ST_MESH_STRICT) */
    /* The document's mesh reader (st_doc.load_mesh): the program's, which
     * reads glTF as well; NULL: core's OBJ/OFF/PLY readers. */
    int (*load_mesh)(const char *path, st_mesh *out, unsigned flags, st_notes *notes, st_error *err);
} st_win_opts;

enum st_tool { ST_TOOL_SELECT = -1 };   /* else an st_brush_tool */

enum st_mouse_op {
    ST_OP_NONE, ST_OP_ORBIT, ST_OP_PAN, ST_OP_CLICK, ST_OP_RECT, ST_OP_DRAG, ST_OP_STROKE, ST_OP_GRAB, ST_OP_BOX,
    ST_OP_STROKE_WAIT          /* a brush pressed off the surface: the stroke starts where the pointer reaches it */
};

#define ST_MSG_LEN 512

/* Baking from the window (ui/bake_ui.c): the Bake dialog's settings, the
 * last bake's normal map, and the view that draws the base level with it. */
typedef struct st_app_bake {
    /* The dialog (what strata bake takes; formats/bake_run.h). */
    int base, level;           /* -1: not chosen yet (0 and the finest level) */
    int size, padding;
    int bits16, space, vector, auto_uv, udim;   /* udim: -1 auto, 0 off, 1 on */
    int want_normal, want_disp;
    char normal[4096], disp[4096];
    /* The last bake that wrote a normal map. */
    int have;
    unsigned have_base;
    int have_auto_uv, have_space;
    uint32_t have_size, have_padding;   /* the atlas's, for auto UVs */
    char have_map[4096];       /* the map, or its UDIM set NAME.<UDIM>.png */
    unsigned serial;           /* bakes done: the view rebuilds when it changes */
    int show;                  /* View > Show baked map */
    int attach;                /* the export dialog's "attach the baked normal map" */
    /* The view's GL state (built on demand, for serial and the document's revision). */
    st_nmap nm;
    int nm_init, nm_ok;
    unsigned nm_serial;
    uint64_t nm_revision;
} st_app_bake;

typedef struct st_app {
    st_win_opts opts;
    GLFWwindow *win;
    st_gl gl;
    st_renderer r;
    st_pick pick;
    st_hud hud;
    st_camctl cc;
    st_doc doc;
    int fb_w, fb_h, win_w, win_h;

    /* What the renderer shows (to know when to rebuild). */
    st_scene_shown shown;      /* what the renderer's buffers were built from (render/scene_sync.h) */
    int shading;               /* enum st_shading */
    int wire, cage;
    int checker, shown_checker;  /* UV checker asked for / uploaded (st_renderer_set_uvs) */

    int tool;                  /* ST_TOOL_SELECT or enum st_brush_tool */
    int mask_brush;            /* brush strokes paint the mask (Ctrl: erase), ui/doc/editor_mask.c */
    int mods;                  /* GLFW_MOD_* held, from the key events */
    double mx, my;             /* cursor, framebuffer pixels */
    int op;                    /* enum st_mouse_op */
    int op_button, op_mods;
    double op_x0, op_y0;       /* where the operation started */
    double op_lx, op_ly;       /* last cursor position seen by the operation */
    double drag_anchor[3];     /* scene point that follows the cursor */
    double drag_normal[3];     /* average normal of the selection */
    double stroke_pos[3];      /* grab brush: current centre */
    st_stroke_path stroke_path;/* other brushes: dab spacing and stabiliser (pixels) */
    uint32_t hover_vid;        /* hovered editing-level vertex id, ST_NIL */
    int hover_dirty;
    int brush_hit;             /* brush circle: the cursor is over the surface */
    double brush_pos[3], brush_nrm[3];

    int box_handle;            /* interest-box handle under the cursor or dragged: -1 none,
                                  0..5 the face centres (-x +x -y +y -z +z), 6 the centre */
    st_adapt_params box_start; /* the box when its drag started */

    int help;                  /* F1 */
    int untitled;              /* an imported mesh not saved yet: Save asks for a name (st_app_import) */
    const char *pending_scheme;/* scheme change waiting for Y */
    char msg[ST_MSG_LEN];      /* status line (errors in red) */
    int msg_error;
    double msg_time;
    char default_path[4096];
    char working[256];         /* drawn over the frame during a long operation */
    int busy;                  /* a worker thread owns the document: draw nothing of it */
    int masked_times;          /* replay, STRATA_GUI_PROBE: times shown as "--" (screenshots stay comparable) */
    double brush_radius_frac;  /* brush radius at open, times the model's half-diagonal (preference) */
    int autosave_dirty;        /* edits since the last recovery save */
    /* st_doc.revision when the document was last opened or saved, and when
     * the recovery file was last written: a completed step writes the
     * recovery file at once (session_io.c), and quitting with
     * revision != saved_revision asks first (st_app_request_quit). */
    uint64_t saved_revision, recovery_revision;
    int showing_default;       /* the model shown is the default one, opened because no file was given */
    int box_placed;            /* the interest box was placed (by the user, a session, or its first I) */
    int quit_asking;           /* the question "save before quitting?" is up */
    int quit_after_save;       /* its Save opened Save As (untitled): quit once that saves */
    double autosave_t;

    double frame_ms;           /* drawing + presenting the last frame */
    double update_ms;          /* last renderer update */
    uint64_t patches;          /* box moves drawn by re-tessellating only the touched faces */
    uint64_t frames;
    int frames_owed;           /* frames still to draw after the last input or change (window.c, the main loop) */
    int quit;
    int exit_code;

    /* Screenshot requested by the replay for the next rendered frame. */
    char shot[4096];
    int shot_pending;
    int shot_probe;            /* asked by SIGUSR1 (STRATA_GUI_PROBE, window.c) */

    void *replay;              /* st_replay */
    st_app_bake bake;          /* ui/bake_ui.c */
} st_app;

/* Entry points (app/cmd_window.c). */
int st_window_main(const st_win_opts *o);
int st_window_bench(const st_win_opts *o);

/* The window's input handlers, as GLFW takes them (a job swaps in its own
 * while it runs: jobs.c). */
typedef struct st_win_input {
    void (*key)(GLFWwindow *w, int key, int scancode, int action, int mods);
    void (*button)(GLFWwindow *w, int button, int action, int mods);
    void (*cursor)(GLFWwindow *w, double x, double y);
    void (*scroll)(GLFWwindow *w, double dx, double dy);
    void (*drop)(GLFWwindow *w, int count, const char **paths);
    void (*chr)(GLFWwindow *w, unsigned codepoint);
} st_win_input;
/* Installs in's handlers on w; returns the ones they replace. */
st_win_input st_win_swap_input(GLFWwindow *w, st_win_input in);

/* The GLFW callbacks (also called by the replay). */
void st_win_on_key(GLFWwindow *w, int key, int scancode, int action, int mods);
void st_win_on_mouse_button(GLFWwindow *w, int button, int action, int mods);
void st_win_on_cursor(GLFWwindow *w, double x, double y);
void st_win_on_scroll(GLFWwindow *w, double dx, double dy);
void st_win_on_drop(GLFWwindow *w, int count, const char **paths);
void st_win_on_resize(GLFWwindow *w, int width, int height);

/* Status line. */
void st_app_message(st_app *a, int error, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* Brings the renderer up to date with the document. */
int st_app_sync(st_app *a);               /* nonzero: something on screen changed */
void st_app_want_frames(st_app *a);        /* input or a change: draw the next few frames */
/* Renders one frame into the back buffer (no swap). */
void st_app_draw(st_app *a);
/* Opens a file (errors keep the current model and show a message). */
int st_app_open(st_app *a, const char *path);
/* File > Import...: a mesh (not a session) as a new, untitled document:
 * not added to Open Recent, and Save asks for a name (ui/jobs.c). */
int st_app_import(st_app *a, const char *path);

/* Sessions (ui/session_io.c). */
int st_app_save_session(st_app *a, const char *path, int quiet);
int st_app_save(st_app *a);                        /* Ctrl+S; 0 saved */
/* Quit (Ctrl+Q, File > Quit, the window's close button): at once when
 * nothing is unsaved, else the question Save / Don't save / Cancel. */
void st_app_request_quit(st_app *a);
void st_app_saved(st_app *a);                       /* after a save the user asked for */
int st_app_unsaved(const st_app *a);
/* Home and the numbered views: the model fitted and centred in the part of
 * the window the side panel leaves free (view: ST_CV_*). */
void st_app_view(st_app *a, int view);
/* The displayed surface's point under the cursor (picking); 0: none. */
int st_app_surface_at_cursor(st_app *a, double pos[3]);
int st_app_restore(st_app *a, const char *path);   /* opens a .strata session */
void st_app_autosave_tick(st_app *a, int force);    /* recovery file after edits */
void st_app_check_recovery(st_app *a);              /* at start: offer it */
void st_app_restore_recovery(st_app *a);            /* Ctrl+R */

/* Long operations on a worker thread with a "working..." panel and a
 * Cancel button, Esc cancelling; a cancelled one leaves the model as it
 * was (ui/jobs.c; st_app_open above is one and returns ST_APP_CANCELLED
 * then).  They run from the main loop only (events are polled for the
 * Cancel): an action, which may run inside a GLFW callback, asks with
 * st_app_request_*, and the main loop runs the job next
 * (st_app_run_requested, called by st_gui_run_pending). */
#define ST_APP_CANCELLED (-2)
void st_app_add_level(st_app *a);                   /* Ctrl+D */
void st_app_change_scheme(st_app *a, const char *scheme);
/* A save as a job (st_doc_save_session): 0, ST_APP_CANCELLED (the file as
 * it was), or the editor's error code with err filled. */
int st_app_job_save(st_app *a, const char *path, const st_session_view *view, const st_session_tool *tool, st_error *err);
/* st_session_load as a job (0, ST_APP_CANCELLED: nothing loaded, or the
 * error code with err filled); the document is not touched. */
int st_app_job_load_session(st_app *a, const char *path, st_session *s, st_error *err);
void st_app_request_rebuild(st_app *a);             /* Ctrl+U: st_doc_rebuild_levels */
void st_app_request_add_level(st_app *a);
void st_app_request_scheme(st_app *a, const char *scheme);   /* scheme: a static name */
void st_app_request_save(st_app *a);                /* st_app_save */
void st_app_request_recovery(st_app *a);            /* st_app_restore_recovery */
void st_app_request_open(st_app *a, const char *path);       /* path copied */
void st_app_run_requested(st_app *a);
/* While a job runs with events polled: whether one does, whether its
 * cancellation was asked, asking it (the progress window's Cancel button,
 * as Esc), and the fraction done it last reported (-1: none yet). */
int st_app_job_cancellable(void);
int st_app_job_cancelling(void);
void st_app_cancel_job(void);
double st_app_job_fraction(void);

/* Keys are looked up in the action table (ui/actions.h). */

/* ---- shared by the window's files (window.c, controller.c, actions.c, jobs.c, hud_panels.c) ---- */

double st_now_ms(void);
const char *st_path_base(const char *path);        /* the file name of a path */
/* A duration for the HUD and messages ("-- ms" in replays, so that their
 * screenshots are the same pixels). */
const char *st_app_fmt_ms(const st_app *a, double ms, char *buf, size_t n);
float st_app_aspect(const st_app *a);
void st_app_frame_model(st_app *a);                 /* Home */
void st_app_update_hover(st_app *a);                /* hovered vertex or brush point */
void st_app_select_all(st_app *a, int none);
void st_app_drag_start(st_app *a, int op);          /* ST_OP_DRAG or ST_OP_GRAB of the selection */
/* The Filter panel's Apply (st_doc_filter): the result or the refusal in
 * the status line; 0 when applied. */
int st_app_filter(st_app *a, const double *gains, unsigned n);
void st_app_drag_finish(st_app *a, int cancel);
/* The drag follows the cursor and the modifiers (ui/controller.c). */
void st_app_drag_update(st_app *a);
/* Handle k of the interest box: 0..5 the face centres (-x +x -y +y -z +z), 6 the centre. */
void st_box_handle_pos(const st_adapt_params *b, int k, double p[3]);

/* Baking (ui/bake_ui.c; the job in ui/jobs.c). */
void st_app_bake_defaults(st_app *a);              /* the dialog's settings for the open model */
void st_app_request_bake(st_app *a);               /* the Bake dialog's Bake: a job */
/* The bake job (st_bake_run on the model): 0, ST_APP_CANCELLED (the old
 * maps kept), or an error with the message in the status line. */
int st_app_bake_maps(st_app *a);
/* Draws the base level with the last baked normal map instead of the
 * surface; 0 when it cannot (nothing baked, or the map unreadable: the
 * message says why and the view goes back to the surface). */
int st_app_draw_baked(st_app *a);
int st_app_can_show_baked(const st_app *a);
void st_app_bake_forget(st_app *a);                /* another model: no baked map */
void st_app_bake_free(st_app *a);                  /* GL objects, before the context goes */

/* The overlay (ui/hud_panels.c). */
void st_app_draw_hud(st_app *a);                    /* panel, status line, F1 help */
void st_app_draw_overlays(st_app *a);               /* selection rectangle, brush circle */
void st_app_draw_handles(st_app *a);                /* interest-box handles */
void st_app_draw_working(st_app *a);                /* "working..." of a long operation */

#endif
