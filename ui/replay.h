/* Scripted input for the modeller window (`strata --replay EVENTS.txt`).
 *
 * The file is a list of events, one per line, '#' starts a comment.  Each
 * primitive event is delivered through the window's real GLFW callbacks
 * (window.h) with the arguments GLFW would pass, one per frame, with a
 * frame rendered in between:
 *
 *   wait N                      N frames without input
 *   key SPEC                    press and release, e.g. key ctrl+d, key shift+pageup, key kp_1, key [
 *   press SPEC / release SPEC   one key event (e.g. press ctrl: hold a modifier)
 *   mouse_move X Y              cursor in window coordinates (top left origin)
 *   mouse_down BUTTON [MODS]    left|middle|right, MODS like ctrl+shift
 *   mouse_up BUTTON [MODS]
 *   drag BUTTON X0 Y0 X1 Y1 STEPS [MODS]
 *                               move to X0 Y0, press, STEPS moves to X1 Y1, release
 *   scroll DY [MODS]            wheel (MODS held around it through key events)
 *   scroll_click DY             a wheel turn, then a left press and release, in one
 *                               frame (a click right after a scroll on a slow frame)
 *   drop PATH                   a file dropped on the window (relative: to the events file)
 *   level edit N | level display N
 *                               set a level directly (document call); edit N above
 *                               the top is an HD level when the interest box is on
 *   snapshot                    remember the displayed positions (also taken after loading)
 *   screenshot NAME.png         read the next frame from the framebuffer
 *   expect WHAT [VALUE]         assertion; WHAT: edit_level, display_level, top,
 *                               selected, undo_depth, redo_depth, box_on, tool
 *                               ('_' for a space: clay_strips), falloff NAME,
 *                               symmetry xyz|none, stabilize 0/1, front 0/1,
 *                               scheme, hover (0/1), faces, moved, unchanged,
 *                               synced (the renderer's incrementally updated
 *                               buffers equal a fresh build),
 *                               patched N (at least N box moves were drawn by
 *                               re-tessellating only the touched faces),
 *                               error (0/1: status line is an error),
 *                               message TEXT (status line contains TEXT),
 *                               dialog quit|scheme|bake|none (the question or dialog that is up),
 *                               baked 0/1 (a normal map was baked for this model),
 *                               baked_view 0/1 (View > Show baked map draws it),
 *                               dialog_dir NAME (the file dialog's folder, last component),
 *                               box_max N (the document's box maximum level),
 *                               unsaved 0/1 (changes since the last open or save),
 *                               recovery 0/1 (the recovery file holds the last step),
 *                               wire 0/1, cage 0/1 (display toggles),
 *                               brush_strength N (hundredths),
 *                               centred (the model's centre projects to the middle
 *                               of the part of the window the side panel leaves free),
 *                               gui (0/1: the GUI is shown), checker (0/1: the UV
 *                               checker is drawn), file PATH (exists,
 *                               not empty), undo_name / redo_name NAME (what the
 *                               Edit menu's Undo / Redo names, '_' for a space,
 *                               "-" for none: expect undo_name brush_stroke)
 *                               layers N (sculpt layers), active_layer K (-1: none),
 *                               layer_strength S (the active layer's, in hundredths),
 *                               masked N (editing-level vertices with a mask above 0;
 *                               "masked +": at least one),
 *                               hd_faces N (faces stored at the HD levels, above the
 *                               model's top; "hd_faces +": at least one)
 *   brush SETTING VALUE         the brush settings of the panel's tool section:
 *                               falloff smooth|sphere|root|sharp|linear|constant,
 *                               spacing F (dabs every F radii; 0: one per event),
 *                               stabilize on|off [F] (lazy mouse, F radii behind),
 *                               symmetry none|x|y|z|xy|xz|yz|xyz, front on|off
 *                               (front faces only), strength S, radius R
 *   filter G0,G1,...            the Filter panel's Apply with these gains (details
 *                               of level k+1 times Gk; st_doc_filter)
 *   gui on | off                show / hide the GUI (menus, side panel; gui.h);
 *                               replays start with it hidden
 *   menu PATH [ARG]             activate a menu item by its labels, as a click
 *                               does ('_' for a space, case and a trailing "..."
 *                               ignored): menu View/Wireframe, menu Mesh/Add_a_level,
 *                               menu Mesh/Scheme/loop
 *                               (then the question; ARG confirm rebuilds at
 *                               once); for items that open the file dialog ARG
 *                               is the file (relative: to the working directory):
 *                               menu File/Export/glTF out.gltf, menu File/Open x.obj
 *   bake SETTING VALUE          the Bake dialog's fields (Bake > Bake maps...): base N,
 *                               level N, size N, padding N, normal PATH|none,
 *                               disp PATH|none, vector / bits16 / auto_uv on|off,
 *                               space tangent|object, udim auto|on|off; attach
 *                               on|off (the export dialog's "Attach the baked
 *                               normal map"); bake run: the Bake button (the job;
 *                               a refusal is the status line's error)
 *   time_frames N               print the median and mean of the next N frames'
 *                               times (drawing + presenting, a->frame_ms)
 *   echo TEXT                   print
 *   quit                        end (success); the end of the file too
 *
 * A failing expect prints the line and the actual value and the process
 * exits 1.  During a replay the window ignores real input (an X server's
 * stray pointer would change the run) unless STRATA_REPLAY_LIVE=1. */
#ifndef ST_REPLAY_H
#define ST_REPLAY_H

#include "core/base/st_error.h"

#include <stddef.h>

typedef struct st_replay st_replay;
struct st_app;

int st_replay_load(st_replay **out, const char *path, st_error *err);
/* The same from memory (fuzz_replay); name stands for the file in messages
 * and relative dropped paths. */
int st_replay_parse(st_replay **out, const char *name, const char *data, size_t size, st_error *err);
void st_replay_free(st_replay *rp);
/* Delivers the next event: 0 continue, 1 finished, -1 an expect failed. */
int st_replay_step(st_replay *rp, struct st_app *a);

#endif
