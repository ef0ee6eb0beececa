#!/usr/bin/env bash
# The interface used as a person would, on the real window under Xvfb:
# xdotool moves the pointer, clicks and types (X events, no replay).
#   1. File > Open... clicked, a path typed into the dialog, Enter;
#      Mesh > Add a level; the draw tool and the radius slider in the panel,
#      a stroke on the model; the interest box switched on in the panel and
#      its size field dragged; File > Export > glTF... and File > Save
#      session as... through the dialog; File > Quit.  A screenshot after
#      each step is compared with tests/window_ref/2*_xdo_*.png (the metric
#      of render/image.h, as tests/cli/cli_window.sh).  Then the glTF passes the
#      Khronos validator (tests/cli/gltf_validate.js), the session opens again
#      with its levels, and the preferences written at exit keep the brush
#      and the recent file.
#   2. The progress window's Cancel button, clicked during a rebuild of the
#      levels, stops it and keeps the model; clicked while Mesh > Add a
#      level works, the level count and the undo history stay; clicked
#      during File > Save session as..., no file is written; clicked during
#      a bake (Bake > Bake maps...), no map is written.  Then a bake by
#      mouse, View > Show baked map, and a GLB exported with the map
#      attached, which passes the validator.
# Where to click comes from the window itself: STRATA_GUI_PROBE=DIR makes
# it write DIR/gui every frame (frame number, document values, widget
# rectangles; ui/gui.cc), and SIGUSR1 takes the screenshot named in
# DIR/shot (ui/window.c).  The window has a fixed size and UI scale
# (--size, --ui-scale 1).  Every wait has a deadline (STEP_TIMEOUT s).
#
#   cli_gui_xdotool.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Runs itself under its own xvfb-run even when $DISPLAY is set: the pointer
# and the keyboard are the X server's, and other tests on the same server
# (ctest -j, cli_window.sh's Esc presses) would take or send them.  To
# accept new references: STRATA_UPDATE_REFS=1 bash tests/cli/cli_gui_xdotool.sh ...
set -u
if [ -z "${STRATA_CLI_XDO_XVFB:-}" ]; then
    if command -v xvfb-run > /dev/null 2>&1; then
        export STRATA_CLI_XDO_XVFB=1
        exec xvfb-run -a -n $((100 + RANDOM % 800)) -s "-screen 0 1280x800x24" bash "$0" "$@"
    fi
    if [ -z "${DISPLAY:-}" ]; then
        echo "FAIL: no \$DISPLAY and no xvfb-run: the window cannot be tested (install xvfb)"
        exit 1
    fi
    echo "cli_gui_xdotool: no xvfb-run: on \$DISPLAY, where other windows may take the pointer"
fi
if ! command -v xdotool > /dev/null 2>&1; then
    echo "FAIL: xdotool is not installed (bash scripts/setup.sh installs it)"
    exit 1
fi
EXE=$1 MESHES=$2 ASSETS=$3 BIN=$4
abs() { (cd "$(dirname "$1")" && printf '%s/%s' "$(pwd)" "$(basename "$1")"); }
EXE=$(abs "$EXE") ASSETS=$(abs "$ASSETS") BIN=$(abs "$BIN")
SRC=$(abs "$ASSETS/../tests")
REF="$SRC/window_ref"
OUT="$BIN/xdotool_out"
STEP_TIMEOUT=${STEP_TIMEOUT:-60}
rm -rf "$OUT"
mkdir -p "$OUT"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_xdo.XXXXXX")
pid=
cleanup() { [ -n "$pid" ] && kill "$pid" 2> /dev/null; rm -rf "$TMP"; }
trap cleanup EXIT
# Leak checks off for the window process (Mesa's GLX leaks; see cli_window.sh).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
export XDG_CONFIG_HOME="$TMP/config" STRATA_RECOVERY="$TMP/recovery.strata" STRATA_GUI_PROBE="$TMP/probe"
mkdir -p "$XDG_CONFIG_HOME" "$STRATA_GUI_PROBE"
P="$STRATA_GUI_PROBE"
passed=0 failed=0
ok() { passed=$((passed + 1)); echo "ok   $*"; }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }
# A step that cannot go on ends the run (the rest depends on it).
die() {
    bad "$*"
    [ -f "$TMP/strata.log" ] && tail -15 "$TMP/strata.log"
    [ -f "$P/gui" ] && { echo "the window's last probe:"; grep -v '^rect' "$P/gui"; grep '^rect dialog' "$P/gui"; }
    echo "cli_gui_xdotool: $passed passed, $failed failed"
    exit 1
}

# ---- the probe ----------------------------------------------------------------
value() { awk -v k="$1" '$1 == k { $1 = ""; sub(/^ /, ""); print; exit }' "$P/gui" 2> /dev/null; }
frame() { value frame; }
# rect NAME: "x0 y0 x1 y1" of a widget drawn in the last frame.
rect() { awk -v n="$1" '$1 == "rect" && $2 == n { print $3, $4, $5, $6; exit }' "$P/gui" 2> /dev/null; }
# until_true WHAT CMD...: waits (polling) until CMD succeeds.
until_true() {
    local what=$1 t0=$SECONDS
    shift
    until "$@"; do
        kill -0 "$pid" 2> /dev/null || die "$what: strata exited"
        [ $((SECONDS - t0)) -ge "$STEP_TIMEOUT" ] && die "$what: not after ${STEP_TIMEOUT}s"
        sleep 0.05
    done
}
is() { [ "$(value "$1")" = "$2" ]; }
has_rect() { [ -n "$(rect "$1")" ]; }
# Two more frames drawn: what the last input changed is on screen and in
# the probe (a press is seen by the GUI one frame, its release the next).
frames_after() { local f0; f0=$(frame); until_true "frames" frame_above "${f0:-0}" 2; }
frame_above() { local f; f=$(frame); [ -n "$f" ] && [ "$f" -ge $(($1 + $2)) ]; }
# point NAME FX FY: the point at fractions FX, FY of a widget's rectangle,
# once it is the same in two frames (a window that fits its content is
# placed from its size, known from its second frame).
stable_rect() {
    local r1 f1
    r1=$(rect "$1") f1=$(frame)
    [ -n "$r1" ] || return 1
    until_true "frames" frame_above "${f1:-0}" 1
    [ "$(rect "$1")" = "$r1" ]
}
point() {
    until_true "widget $1 shown and still" stable_rect "$1"
    rect "$1" | awk -v fx="$2" -v fy="$3" '{ printf "%d %d\n", $1 + fx * ($3 - $1), $2 + fy * ($4 - $2) }'
}
move() { xdotool mousemove --window "$W" "$1" "$2"; frames_after; }
# click NAME [FX]: a left click on a widget (at FX of its width; centre).
click() {
    local xy
    xy=$(point "$1" "${2:-0.5}" 0.5)
    move $xy
    xdotool click 1
    frames_after
}
# type_path TEXT: the dialog's path field: clicked (which selects what it
# holds), typed over, Enter.
type_path() {
    click dialog:path
    xdotool type --window "$W" --delay 5 "$1"
    frames_after
    xdotool key --window "$W" Return
    frames_after
}
# shot NAME: the window's own screenshot, compared with the reference.
nshots=0
shot() {
    echo "$1" > "$P/shot"
    kill -USR1 "$pid"
    nshots=$((nshots + 1))
    until_true "screenshot $1" grep -q "^$1 " "$P/shots"
    if grep -q "^$1 ok" "$P/shots"; then ok "screenshot $1"
    else bad "screenshot $1: $(grep "screenshot $1" "$TMP/strata.log" | tail -1)"; fi
}
start() {
    rm -f "$P/gui" "$P/shots"
    touch "$P/shots"
    "$EXE" "$@" > "$TMP/strata.log" 2>&1 &
    pid=$!
    W=$(timeout "$STEP_TIMEOUT" xdotool search --sync --onlyvisible --name '^Strata' | head -1)
    [ -n "$W" ] || die "the window did not appear: $(tail -5 "$TMP/strata.log")"
    until_true "first frame" test -s "$P/gui"
}
finish() {
    local what=$1 rc=0 t0=$SECONDS
    while kill -0 "$pid" 2> /dev/null; do
        [ $((SECONDS - t0)) -ge "$STEP_TIMEOUT" ] && die "$what: strata did not exit"
        sleep 0.1
    done
    wait "$pid" || rc=$?
    pid=
    return $rc
}

# ---- 1. a session with the mouse and the keyboard ------------------------------
CMP=(--compare-dir "$REF")
[ "${STRATA_UPDATE_REFS:-0}" = 1 ] && CMP=()
mkdir -p "$TMP/work"
cd "$TMP/work" || exit 1
start --size 1000x700 --ui-scale 1 --levels 1 --screenshot-dir "$OUT" "${CMP[@]}" "$ASSETS/cube.obj"
until_true "cube.obj loaded" is file cube.obj
shot 20_xdo_start.png

# File > Open..., the path typed (on an empty field).
click menu:File
click menu:File/Open
until_true "the Open dialog" is dialog 1
type_path "$ASSETS/torus.obj"
until_true "torus.obj opened" is file torus.obj
until_true "the dialog closed" is dialog 0
[ "$(value top)" = 1 ] && ok "File > Open: torus.obj with 1 level" || bad "File > Open: top $(value top)"
shot 21_xdo_opened.png

# Mesh > Add a level.
click menu:Mesh
click menu:Mesh/Add_a_level
until_true "level 2 built" is top 2
ok "Mesh > Add a level: 2 levels"
shot 22_xdo_level.png

# The draw tool, the radius slider at a quarter, a stroke across the model.
click panel:draw
r0=$(value radius)
click panel:radius 0.6
r1=$(value radius)
if [ -n "$r1" ] && [ "$r0" != "$r1" ]; then ok "radius slider: $r0 -> $r1"
else bad "radius slider: $r0 -> $r1 (expected a change)"; fi
u0=$(value undo)
move 420 190
xdotool mousedown 1
for x in 435 450 465 480 495 510 525 540; do xdotool mousemove --window "$W" "$x" 190; sleep 0.02; done
xdotool mouseup 1
frames_after
[ "$(value undo)" = $((u0 + 1)) ] && ok "brush stroke: one undo step" || bad "brush stroke: undo $u0 -> $(value undo)"
move 480 640   # off the model: no brush circle in the screenshot
shot 23_xdo_stroke.png

# The interest box from the panel, then its size field dragged (x).
click panel:interest_box
until_true "box on" is box_on 1
s0=$(value box_size)
xy=$(point panel:size 0.16 0.5)
move $xy
frames_after   # ImGui has seen the pointer over the field
xdotool mousedown 1
frames_after   # ...and the press there, so no motion is folded into it
set -- $xy
# One frame per step: ImGui adds each frame's motion once past its drag
# threshold, so folded steps under load would give a different size.
for d in 5 10 15 20 25 30 35 40; do xdotool mousemove --window "$W" $(($1 + d)) "$2"; frames_after; done
frames_after
xdotool mouseup 1
frames_after
s1=$(value box_size)
if [ "${s0%% *}" != "${s1%% *}" ] && [ "${s0#* }" = "${s1#* }" ]; then ok "box size dragged: $s0 -> $s1"
else bad "box size drag: $s0 -> $s1 (expected x larger, y z the same)"; fi
move 480 640
shot 24_xdo_box.png

# File > Export > glTF..., a path typed.
click menu:File
click menu:File/Export
click menu:File/Export/glTF
until_true "the Export dialog" is dialog 1
type_path "$TMP/work/exported.gltf"
until_true "the export written" test -s "$TMP/work/exported.gltf"
until_true "the dialog closed" is dialog 0
ok "File > Export > glTF"
shot 25_xdo_exported.png

# File > Save session as..., a path typed.  (Its notification names the
# scratch folder, whose random letters differ from the reference's in a
# few glyphs: well under the 0.3 % of pixels allowed.)
click menu:File
click menu:File/Save_session_as
until_true "the Save dialog" is dialog 1
type_path "$TMP/work/saved.strata"
until_true "the session written" test -s "$TMP/work/saved.strata"
until_true "the dialog closed" is dialog 0
ok "File > Save session as"
shot 26_xdo_saved.png

# File > Quit.
click menu:File
xy=$(point menu:File/Quit 0.5 0.5)
move $xy
xdotool click 1   # (no frame to wait for: the window closes)
if finish "File > Quit"; then ok "File > Quit: exit 0"; else bad "File > Quit: exit $? ($(tail -3 "$TMP/strata.log"))"; fi

# The files: the glTF validates, the session opens with its levels and box.
VALIDATOR="${GLTF_VALIDATOR:-${GLTF_VALIDATOR_DIR:+$GLTF_VALIDATOR_DIR/node_modules/gltf-validator}}"
VALIDATOR="${VALIDATOR:-$SRC/../build/node/node_modules/gltf-validator}"
if ! command -v node > /dev/null 2>&1; then bad "node is not installed: the glTF cannot be validated (bash scripts/setup_node.sh)"
elif GLTF_VALIDATOR="$VALIDATOR" node "$SRC/cli/gltf_validate.js" "$TMP/work/exported.gltf" > "$TMP/validator.txt" 2>&1; then
    ok "exported.gltf passes the glTF validator"
else
    bad "exported.gltf: $(cat "$TMP/validator.txt")"
fi
printf 'wait 1\nexpect top 2\nexpect box_on 1\nexpect scheme catmull-clark\nquit\n' > "$TMP/reload.txt"
if out=$("$EXE" --size 320x240 --replay "$TMP/reload.txt" "$TMP/work/saved.strata" 2>&1); then ok "saved.strata reopens (2 levels, box on)"
else bad "saved.strata: $(tail -3 <<< "$out")"; fi
prefs="$XDG_CONFIG_HOME/strata/prefs"
if grep -qx "brush_tool draw" "$prefs" && grep -q "^brush_radius " "$prefs" && grep -qx "recent $TMP/work/saved.strata" "$prefs" &&
   grep -qx "recent $(abs "$ASSETS/torus.obj")" "$prefs"; then ok "preferences: the brush and the recent files kept"
else bad "preferences: $(cat "$prefs" 2>&1)"; fi

# ---- 2. Cancel in the progress window ------------------------------------------
# A progressive rebuild of a 40k-face mesh, asked by the replay's Ctrl+U;
# real clicks are let through (STRATA_REPLAY_LIVE=1).  STRATA_JOB_HOLD_S
# makes the rebuild's progress reports wait for a cancellation (60 s at
# most; ui/jobs.c), so that the click cannot come too late on a fast
# machine: a Cancel that does not work lets it finish and this fails.
printf 'gui on\nwait 1\nexpect top 0\nkey ctrl+u\nwait 1\nexpect message cancelled\nexpect top 0\nexpect undo_depth 0\nquit\n' > "$TMP/cancel.txt"
STRATA_REPLAY_LIVE=1 STRATA_JOB_HOLD_S=60 start --size 640x480 --ui-scale 1 --scheme loop --levels 0 --replay "$TMP/cancel.txt" "$MESHES/triangle/boot.obj"
until_true "the progress window's Cancel" has_rect progress:Cancel
xy=$(point progress:Cancel 0.5 0.5)
move $xy
xdotool click 1
if finish "cancelled rebuild" && grep -q "rebuild cancelled: the model is unchanged" "$TMP/strata.log"; then
    ok "Cancel button: rebuild cancelled, model unchanged"
else
    bad "Cancel button: $(tail -5 "$TMP/strata.log")"
fi

# ---- 2b. Cancel of a level added from the Mesh menu and of a save ----------
# Clicked in the window, no replay.  STRATA_JOB_HOLD_S as above: the job
# waits at its first progress report until the Cancel arrives.
STRATA_JOB_HOLD_S=60 start --size 1000x700 --ui-scale 1 --levels 1 "$ASSETS/cube.obj"
until_true "cube.obj loaded" is file cube.obj
u0=$(value undo)
click menu:Mesh
click menu:Mesh/Add_a_level
until_true "the progress window's Cancel (add a level)" has_rect progress:Cancel
click progress:Cancel
until_true "the level job ended" is busy 0
says() { value message | grep -q "$1"; }
until_true "the cancel reported" says "adding a level cancelled: the model is unchanged"
frames_after
if [ "$(value top)" = 1 ] && [ "$(value undo)" = "$u0" ]; then ok "Cancel of Mesh > Add a level: still 1 level, undo $u0"
else bad "Cancel of Mesh > Add a level: top $(value top), undo $(value undo) (expected 1, $u0)"; fi
click menu:File
click menu:File/Save_session_as
until_true "the Save dialog" is dialog 1
type_path "$TMP/work/cancelled.strata"
until_true "the progress window's Cancel (save)" has_rect progress:Cancel
click progress:Cancel
until_true "the save cancelled" says "save cancelled: .*cancelled.strata is as it was"
frames_after
if [ ! -e "$TMP/work/cancelled.strata" ] && [ -z "$(ls "$TMP/work" | grep 'cancelled.strata.tmp')" ]; then
    ok "Cancel of a save: no file, no temporary"
else bad "Cancel of a save: $(ls "$TMP/work")"; fi
xdotool key --window "$W" Escape   # the dialog (it stays open after a failed or cancelled save)
frames_after
xdotool key --window "$W" ctrl+q
finish "Ctrl+Q after the cancels" || bad "Ctrl+Q after the cancels: $(tail -3 "$TMP/strata.log")"

# ---- 2c. Baking from the window (Bake > Bake maps...) --------------------------
# The torus has no UVs: the dialog bakes onto the per-face atlas (its Auto
# UVs box ticked and greyed).  First with STRATA_JOB_HOLD_S: the progress
# window's Cancel stops the bake and no map (nor temporary) is written.
# Then a bake to its end, View > Show baked map, and File > Export > GLB...
# with "Attach the baked normal map" ticked: the GLB passes the validator.
# A pause of 0.3 s between a move and its click (ImGui 1.86 folds a move
# and a click that arrive in one frame).  Screenshots: 3*_xdo_bake_*.png.
mkdir -p "$TMP/bake"
cd "$TMP/bake" || exit 1
bake_click() { local xy; xy=$(point "$1" "${2:-0.5}" 0.5); move $xy; sleep 0.3; xdotool click 1; frames_after; }
# bake_path NAME TEXT: a path field of the Bake dialog clicked (selects it), typed over.
# Frames pass between Ctrl+A and the typing: ImGui drops a character that
# arrives in the frame where Ctrl still reads as held (under ASan a frame is
# slow enough for the release and the first character to share one, and
# the path lost its leading '/').
bake_path() {
    bake_click "$1" 0.5
    xdotool key --window "$W" ctrl+a
    frames_after
    xdotool type --window "$W" --delay 5 "$2"
    frames_after
}
STRATA_JOB_HOLD_S=60 start --size 1000x700 --ui-scale 1 --levels 2 "$ASSETS/torus.obj"
until_true "torus.obj loaded" is file torus.obj
bake_click menu:Bake
bake_click menu:Bake/Bake_maps
until_true "the Bake dialog" has_rect bake:run
bake_path bake:normal_path "$TMP/bake/cancelled_n.png"
bake_click bake:run
until_true "the progress window's Cancel (bake)" has_rect progress:Cancel
bake_click progress:Cancel
until_true "the bake ended" is busy 0
until_true "the bake cancel reported" says "bake cancelled: the maps on disk are as they were"
if [ -z "$(ls "$TMP/bake")" ]; then ok "Cancel of a bake: no map, no temporary"; else bad "Cancel of a bake left: $(ls "$TMP/bake")"; fi
xdotool key --window "$W" ctrl+q
finish "Ctrl+Q after the bake cancel" || bad "Ctrl+Q after the bake cancel: $(tail -3 "$TMP/strata.log")"

start --size 1000x700 --ui-scale 1 --levels 2 --screenshot-dir "$OUT" "$ASSETS/torus.obj"
until_true "torus.obj loaded" is file torus.obj
bake_click menu:Bake
bake_click menu:Bake/Bake_maps
until_true "the Bake dialog" has_rect bake:run
bake_path bake:normal_path "$TMP/bake/torus_n.png"
move 300 650
sleep 0.3
shot 30_xdo_bake_dialog.png
bake_click bake:run
until_true "the bake done" says "baked level 2 onto level 0: torus_n.png"
no_rect() { ! has_rect "$1"; }
until_true "the Bake dialog closed" no_rect bake:run
[ -s "$TMP/bake/torus_n.png" ] && ok "Bake > Bake maps...: torus_n.png written" || bad "the bake wrote no torus_n.png: $(ls "$TMP/bake")"
bake_click menu:View
bake_click menu:View/Show_baked_map
until_true "the baked map shown" says "showing level 0 with the baked map torus_n.png"
move 300 650
sleep 0.3
shot 31_xdo_bake_view.png
bake_click menu:File
bake_click menu:File/Export
bake_click menu:File/Export/GLB
until_true "the Export dialog" is dialog 1
bake_click dialog:attach 0.05
shot 32_xdo_bake_export.png
type_path "$TMP/bake/torus_mapped.glb"
until_true "the GLB exported with the map" says "exported torus_mapped.glb (level 0, .*) with the baked normal map torus_n.png"
if GLTF_VALIDATOR="$VALIDATOR" node "$SRC/cli/gltf_validate.js" "$TMP/bake/torus_mapped.glb" > "$TMP/val_bake.txt" 2>&1 && grep -q ': 0 errors' "$TMP/val_bake.txt"; then
    ok "the GLB with the baked map: $(cat "$TMP/val_bake.txt")"
else bad "validator on torus_mapped.glb: $(cat "$TMP/val_bake.txt")"; fi
xdotool key --window "$W" ctrl+q
finish "Ctrl+Q after the bake" || bad "Ctrl+Q after the bake: $(tail -3 "$TMP/strata.log")"
cd "$TMP/work" || exit 1

# ---- 3. preferences applied at start, a section closed by a click kept ----------
# The panel 360 wide with Tool closed, the smooth brush at strength 0.3 and
# a radius of a quarter of the model's half-diagonal, UI scale 1.25.
printf 'strata-prefs 1\nui_scale 1.25\npanel_width 360\nsection Tool 0\nbrush_tool smooth\nbrush_radius 0.25\nbrush_strength 0.3\n' \
    > "$XDG_CONFIG_HOME/strata/prefs"
start --size 1000x700 --levels 1 "$ASSETS/cube.obj"
until_true "cube.obj loaded" is file cube.obj
frames_after
set -- $(rect window:panel)
if [ "$(value scale)" = 1.25 ] && [ $(($3 - $1)) = 450 ] && has_rect panel:section:Tool && ! has_rect panel:radius &&
   [ "$(value tool)" = smooth ] && [ "$(value strength)" = 0.3 ] &&
   awk -v r="$(value radius)" 'BEGIN { exit !(r > 0.4329 && r < 0.4331) }'; then   # 0.25 of 1.732 (0.2165 at 1/8 in part 1)
    ok "preferences applied: scale 1.25, panel 360 (450 px), Tool closed, smooth brush, strength 0.3, radius $(value radius)"
else
    bad "preferences not applied: $(grep -v '^rect' "$P/gui" | tr '\n' ' ') panel $*"
fi
click panel:section:Levels
until_true "Levels closed" eval '! has_rect panel:Add_level'
xdotool key --window "$W" ctrl+q
if finish "Ctrl+Q" && grep -qx "section Levels 0" "$XDG_CONFIG_HOME/strata/prefs" && grep -qx "section Tool 0" "$XDG_CONFIG_HOME/strata/prefs" &&
   grep -qx "brush_tool smooth" "$XDG_CONFIG_HOME/strata/prefs"; then ok "a section closed by a click is kept in the preferences"
else bad "preferences after closing Levels: $(cat "$XDG_CONFIG_HOME/strata/prefs")"; fi
# A corrupt file: a message naming it and its line, the window starts with
# the defaults (scale 1 here: no content scale under Xvfb).
printf 'strata-prefs 1\npanel_width wide\n' > "$XDG_CONFIG_HOME/strata/prefs"
start --size 1000x700 "$ASSETS/cube.obj"
until_true "cube.obj loaded" is file cube.obj
xdotool key --window "$W" ctrl+q
finish "Ctrl+Q" || true
if grep -q "strata/prefs:2: cannot read \"panel_width wide\"; preferences ignored" "$TMP/strata.log"; then ok "corrupt preferences ignored with a message"
else bad "corrupt preferences: $(head -3 "$TMP/strata.log")"; fi
if out=$("$EXE" --ui-scale 9 "$ASSETS/cube.obj" 2>&1); then bad "--ui-scale 9 accepted"
elif grep -q -- "--ui-scale wants 0.5..4" <<< "$out"; then ok "--ui-scale 9 refused"; else bad "--ui-scale 9: $out"; fi

if [ "${STRATA_UPDATE_REFS:-0}" = 1 ]; then
    cp "$OUT"/2*_xdo_*.png "$REF"/ && echo "references updated in $REF"
fi
echo "cli_gui_xdotool: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
