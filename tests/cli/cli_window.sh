#!/usr/bin/env bash
# The modeller window for real: under Xvfb (Mesa llvmpipe), a
# scripted replay drives the real GLFW window and its callbacks through
# loading, a level change, a vertex drag at level 2, a brush stroke, a box
# move and an undo; screenshots read from the framebuffer are compared with
# tests/window_ref/ (the metric of render/image.h: a channel off by more
# than 4 counts a pixel as differing, at most 0.3 % of the pixels may
# differ; on a mismatch NAME.png, NAME.expected.png and NAME.diff.png are
# left in BINARY_TEST_DIR/window_out).  Also: a failing expect exits
# non-zero; without a display strata fails with a clear message, not a
# crash; a file that does not load keeps the current model.
#
#   cli_window.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Runs itself under xvfb-run when $DISPLAY is unset.  To accept new
# references: STRATA_UPDATE_REFS=1 bash tests/cli/cli_window.sh ... (copies the
# screenshots into tests/window_ref/).
set -u
. "$(dirname "$0")/window_lib.sh"
need_display "$0" "$@"
EXE=$1 MESHES=$2 ASSETS=$3 BIN=$4
abs() { (cd "$(dirname "$1")" && printf '%s/%s' "$(pwd)" "$(basename "$1")"); }
EXE=$(abs "$EXE") ASSETS=$(abs "$ASSETS") BIN=$(abs "$BIN") MESHES=$(abs "$MESHES")
SRC="$ASSETS/../tests"
REF="$SRC/window_ref"
OUT="$BIN/window_out"
rm -rf "$OUT"
mkdir -p "$OUT"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_window.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
# Sanitizer builds (scripts/test.sh's asan stage): leak checking is off for
# the processes that open a window.  Mesa's GLX/DRI driver leaks a few
# hundred bytes per process (a bare glfwInit/CreateWindow/Terminate program
# shows the same 128 + 56 + 56 bytes) and is unloaded before LeakSanitizer
# reports, so its frames are "<unknown module>" and no suppression can name
# them.  Address and UB checks stay on; the no-display run keeps leak checks.
WINDOW_ASAN="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
# No recovery file from an earlier run.
export STRATA_RECOVERY="$TMP/recovery.strata"
passed=0 failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }

# win args...: strata with a window (leak checks off, see above).
win() { ASAN_OPTIONS="$WINDOW_ASAN" "$@"; }

# run EXPECTED_EXIT PATTERN args... (exit status and output pattern)
run() {
    local want=$1 pat=$2
    shift 2
    local out rc=0
    out=$("$@" 2>&1) || rc=$?
    if [ "$rc" -ne "$want" ]; then bad "$* exited $rc, expected $want: $(tail -20 <<<"$out")"; return; fi
    if [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$out"; then bad "$*: output lacks /$pat/: $(tail -20 <<<"$out")"; return; fi
    ok
}

# 1. The scripted session, screenshots compared with the references.
if [ "${STRATA_UPDATE_REFS:-0}" = 1 ]; then
    win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/session.txt" --screenshot-dir "$OUT" "$ASSETS/torus.obj"
    cp "$OUT"/[0-9]*.png "$REF"/ && rm -f "$REF"/*.expected.png "$REF"/*.diff.png
    echo "references updated in $REF"
fi
run 0 "replay .* passed" win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/session.txt" \
    --screenshot-dir "$OUT" --compare-dir "$REF" "$ASSETS/torus.obj"
# Masks and sculpt layers (ui/editor_mask.c, ui/editor_layers.c) by their
# keys; the mask's darkening compared with its reference.
if [ "${STRATA_UPDATE_REFS:-0}" = 1 ]; then
    win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/masks_layers.txt" --screenshot-dir "$OUT" "$ASSETS/torus.obj"
    cp "$OUT"/08_mask*.png "$REF"/
fi
run 0 "replay .* passed" win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/masks_layers.txt" \
    --screenshot-dir "$OUT" --compare-dir "$REF" "$ASSETS/torus.obj"
# The GUI (ui/gui.cc): menu bar and side panel, the File menu opened with
# the pointer, a panel checkbox clicked, actions through the menus (exports,
# a failed open, save as, a scheme change), F10; files land in a scratch
# directory.
mkdir -p "$TMP/gui"
if [ "${STRATA_UPDATE_REFS:-0}" = 1 ]; then
    (cd "$TMP/gui" && win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/gui.txt" --screenshot-dir "$OUT" "$ASSETS/torus.obj")
    cp "$OUT"/0[67]_gui*.png "$REF"/
fi
run 0 "replay .* passed" bash -c 'cd "$1" && shift && ASAN_OPTIONS="$0" "$@"' "$WINDOW_ASAN" "$TMP/gui" "$EXE" --size 640x480 --levels 2 \
    --replay "$SRC/replay/gui.txt" --screenshot-dir "$OUT" --compare-dir "$REF" "$ASSETS/torus.obj"
# A stroke with every brush (ui/brush_tools.c), each compared with its
# reference, and the brush settings by keys and replay events (falloff,
# X/Y/Z symmetry, spacing, stabiliser, front faces only).
if [ "${STRATA_UPDATE_REFS:-0}" = 1 ]; then
    win "$EXE" --size 480x360 --levels 2 --replay "$SRC/replay/brushes.txt" --screenshot-dir "$OUT" "$ASSETS/torus.obj"
    cp "$OUT"/1[0-9]_brush*.png "$REF"/
fi
run 0 "replay .* passed" win "$EXE" --size 480x360 --levels 2 --replay "$SRC/replay/brushes.txt" \
    --screenshot-dir "$OUT" --compare-dir "$REF" "$ASSETS/torus.obj"
# The UV checker (U, View menu) on a shared mesh with UVs: on, through level
# changes, a stroke, undo and the interest box (its adaptive mesh's UVs);
# its pictures compared with their references.  On a mesh without UVs the key does nothing.
UVMESH="$MESHES/catmull_clark/blub_control_mesh.obj"
if [ "${STRATA_UPDATE_REFS:-0}" = 1 ]; then
    win "$EXE" --size 480x360 --levels 2 --replay "$SRC/replay/uv_checker.txt" --screenshot-dir "$OUT" "$UVMESH"
    cp "$OUT"/09_uv_checker*.png "$REF"/
fi
run 0 "replay .* passed" win "$EXE" --size 480x360 --levels 2 --replay "$SRC/replay/uv_checker.txt" \
    --screenshot-dir "$OUT" --compare-dir "$REF" "$UVMESH"
# Doo-Sabin's interest box draws the checker through its own UVs too.
run 0 "replay .* passed" win "$EXE" --size 480x360 --scheme doo-sabin --levels 2 --replay "$SRC/replay/uv_checker_ds.txt" \
    --screenshot-dir "$OUT" "$UVMESH"
printf 'wait 1\nkey u\nexpect checker 0\nquit\n' > "$TMP/nouv.txt"
run 0 "replay .* passed" win "$EXE" --size 320x240 --levels 1 --replay "$TMP/nouv.txt" "$ASSETS/cube.obj"
# A bad brush setting is refused before a window opens, naming the line.
printf 'brush falloff wobbly\n' > "$TMP/badbrush.txt"
run 2 "badbrush.txt:1: brush falloff wobbly: not one of smooth" "$EXE" --replay "$TMP/badbrush.txt" "$ASSETS/cube.obj"
# A menu path that names no item fails the replay, naming the line.
printf 'gui on\nwait 1\nmenu File/No_such_item\n' > "$TMP/badmenu.txt"
run 1 "badmenu.txt:3: menu File/No_such_item: no such menu item" win "$EXE" --size 320x240 --replay "$TMP/badmenu.txt" "$ASSETS/cube.obj"
# (Its own references: 0*.png; 2*_xdo_*.png are tests/cli/cli_gui_xdotool.sh's.)
for f in "$REF"/0*.png; do
    [ -f "$OUT/$(basename "$f")" ] && ok || bad "screenshot $(basename "$f") was not taken"
done

# More bindings, by expectations: rectangle/all/none selection, G grab and
# its cancel, drag along the normal, every brush, undo/redo, displayed
# level, level deletion and rebase, the scheme change and its confirmation,
# views, zoom, orbit and pan.
run 0 "replay .* passed" win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/features.txt" "$ASSETS/torus.obj"

# No FILE: the default asset; --scheme picks the scheme at open.
printf 'wait 1\nexpect scheme catmull-clark\nexpect faces 1536\nquit\n' > "$TMP/default.txt"
run 0 "opened torus.obj" win "$EXE" --size 320x240 --levels 2 --replay "$TMP/default.txt"
printf 'wait 1\nexpect scheme loop\nexpect top 3\nexpect faces 512\nquit\n' > "$TMP/loop.txt"
run 0 "opened octahedron.obj \(loop, 4 levels \(0..3\)\)" win "$EXE" --size 320x240 --scheme loop --levels 3 --replay "$TMP/loop.txt" "$ASSETS/octahedron.obj"

# An operation over the memory budget is refused with the bytes it needs,
# and the model stays as it was.
printf 'wait 1\nkey ctrl+d\nkey ctrl+d\nexpect error 1\nexpect message refused\nexpect top 3\nquit\n' > "$TMP/mem.txt"
run 0 "level 4 refused: it needs about [0-9]+ bytes" win "$EXE" --size 320x240 --levels 2 --mem-budget 1 --replay "$TMP/mem.txt" "$ASSETS/torus.obj"

# Incremental buffer updates equal a fresh build after every kind of edit,
# with the box off and on.
run 0 "replay .* passed" win "$EXE" --size 640x480 --levels 3 --replay "$SRC/replay/sync.txt" "$ASSETS/torus.obj"

# Box moves over a finer display patch only the touched faces, and the
# patched buffers stay equal to a fresh build.
run 0 "replay .* passed" win "$EXE" --size 480x360 --levels 4 --replay "$SRC/replay/box_patch.txt" "$ASSETS/torus.obj"

# Every scheme through the same interactions (it must survive; the interest
# box works for every scheme).
for spec in "catmull-clark open.obj" "loop octahedron.obj" "butterfly octahedron.obj" \
            "quad-triangle mixed.obj" "sqrt3 tetrahedron.obj" "doo-sabin cube.obj"; do
    set -- $spec
    run 0 "replay .* passed" win "$EXE" --size 480x360 --scheme "$1" --levels 2 --replay "$SRC/replay/smoke.txt" "$ASSETS/$2"
done
# The interest box on sqrt3 and Doo-Sabin: on, moved, edits with the box on,
# undo, off and on; the buffers stay equal to a fresh build.
for spec in "sqrt3 octahedron.obj" "sqrt3 tetrahedron.obj" "doo-sabin torus.obj" "doo-sabin cube.obj"; do
    set -- $spec
    run 0 "replay .* passed" win "$EXE" --size 480x360 --scheme "$1" --levels 2 --replay "$SRC/replay/box_schemes.txt" "$ASSETS/$2"
done

# Rebuild levels (Ctrl+U, Mesh menu) on meshes opened with no levels: a
# twice subdivided cube (unsubdivide) and a triangle mesh without
# subdivision connectivity (the progressive method); undo and redo.
if "$EXE" subdivide "$ASSETS/cube.obj" --scheme catmull-clark --levels 2 -o "$TMP/cube_cc2.obj" > /dev/null; then
    run 0 "replay .* passed" win "$EXE" --size 480x360 --levels 0 --replay "$SRC/replay/rebuild.txt" "$TMP/cube_cc2.obj"
else
    bad "strata subdivide cube.obj failed"
fi
run 0 "replay .* passed" win "$EXE" --size 480x360 --scheme loop --levels 0 --replay "$SRC/replay/rebuild_progressive.txt" \
    "$MESHES/triangle/bob_small.ply"

# The memory budget before an edit (ui/editor.c, ed_edit_budget): refused
# over it, done within it.
if "$EXE" rebuild "$MESHES/triangle/bob_small.ply" --method progressive -o "$TMP/bob_p.strata" > /dev/null; then
    run 0 "replay .* passed" win "$EXE" --size 480x360 --mem-budget 1 --replay "$SRC/replay/edit_budget.txt" "$TMP/bob_p.strata"
    printf 'wait 2\nkey d\nsnapshot\ndrag left 200 200 260 220 6\nexpect moved\nexpect undo_depth 1\nquit\n' > "$TMP/edit_budget_ok.txt"
    run 0 "replay .* passed" win "$EXE" --size 480x360 --mem-budget 3 --replay "$TMP/edit_budget_ok.txt" "$TMP/bob_p.strata"
    # Multiresolution filtering in the window (the Filter panel), undoable.
    run 0 "replay .* passed" win "$EXE" --size 640x480 --replay "$SRC/replay/filter.txt" "$TMP/bob_p.strata"
    printf 'wait 2\nfilter 1,0\nexpect error 1\nexpect message progressive\nexpect undo_depth 0\nquit\n' > "$TMP/filter_loop.txt"
    run 0 "replay .* passed" win "$EXE" --size 480x360 --levels 2 --replay "$TMP/filter_loop.txt" "$ASSETS/torus.obj"
else
    bad "strata rebuild bob_small.ply failed"
fi

# Esc cancels a rebuild and keeps the model: real key presses (xdotool,
# every 50 ms while the replay runs; STRATA_REPLAY_LIVE=1 lets them through)
# on a 40k-face mesh whose progressive rebuild takes longer than that.
if command -v xdotool > /dev/null 2>&1; then
    printf 'wait 1\nexpect top 0\nkey ctrl+u\nwait 1\nexpect message cancelled\nexpect top 0\nexpect undo_depth 0\nquit\n' > "$TMP/cancel.txt"
    # STRATA_JOB_HOLD_S: the rebuild's reports wait up to 20 s for the Esc,
    # so that the slower search below cannot come too late.
    STRATA_JOB_HOLD_S=20 STRATA_REPLAY_LIVE=1 ASAN_OPTIONS="$WINDOW_ASAN" timeout 300 "$EXE" --size 320x240 --scheme loop --levels 0 \
        --replay "$TMP/cancel.txt" "$MESHES/triangle/boot.obj" > "$TMP/cancel.log" 2>&1 &
    pid=$!
    # Until a window exists, look every 0.5 s only: a search every 50 ms
    # opens 20 X connections a second while strata opens its own, and strata
    # twice failed to open the display then (CI's ASan stage).
    while kill -0 "$pid" 2> /dev/null; do
        w=$(xdotool search --name '^Strata' 2> /dev/null | head -1)
        if [ -n "$w" ]; then xdotool key --window "$w" Escape 2> /dev/null; sleep 0.05; else sleep 0.5; fi
    done
    rc=0; wait "$pid" || rc=$?
    if [ "$rc" -eq 0 ] && grep -q "rebuild cancelled: the model is unchanged" "$TMP/cancel.log"; then ok
    else bad "Esc during a rebuild: exit $rc, output: $(tail -5 "$TMP/cancel.log")"; fi
else
    echo "cli_window: no xdotool: Esc cancelling a rebuild not checked"
fi

# 1b. Quitting with unsaved changes asks (ui/session_io.c): Esc cancels, D
# quits without saving, S saves STEM.strata then quits; the recovery file
# holds the stroke as soon as it ends (expect recovery 1) and after D.
rm -f "$STRATA_RECOVERY"
out=$(win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/quit.txt" "$ASSETS/torus.obj" 2>&1); rc=$?
if [ "$rc" -eq 0 ] && grep -q "replay .* passed" <<<"$out" && ! grep -q NOT_QUIT <<<"$out" && [ -s "$STRATA_RECOVERY" ] &&
   "$EXE" convert "$STRATA_RECOVERY" "$TMP/rec2.obj" --level 2 > /dev/null &&
   "$EXE" convert "$ASSETS/torus.obj" "$TMP/orig2.obj" --levels 2 --level 2 > /dev/null &&
   ! cmp -s "$TMP/rec2.obj" "$TMP/orig2.obj"; then ok
else bad "quit question (quit.txt): exit $rc, recovery $(ls -l "$STRATA_RECOVERY" 2>&1): $(tail -5 <<<"$out")"; fi
mkdir -p "$TMP/quitsave" && cp "$ASSETS/torus.obj" "$TMP/quitsave/"
out=$(cd "$TMP/quitsave" && win "$EXE" --size 640x480 --levels 1 --replay "$SRC/replay/quit_save.txt" torus.obj 2>&1); rc=$?
if [ "$rc" -eq 0 ] && ! grep -q NOT_QUIT <<<"$out" && [ -s "$TMP/quitsave/torus.strata" ] && [ ! -e "$STRATA_RECOVERY" ]; then ok
else bad "quit question, Save (quit_save.txt): exit $rc, $(ls "$TMP/quitsave"): $(tail -5 <<<"$out")"; fi

# 1c. A stroke pressed off the surface starts where the pointer reaches it.
run 0 "replay .* passed" win "$EXE" --size 640x480 --levels 2 --replay "$SRC/replay/stroke_offsurface.txt" "$ASSETS/torus.obj"

# 1d. A click right after a wheel turn opens the folder drawn under the pointer.
mkdir -p "$TMP/dirs" && for i in $(seq -w 0 39); do mkdir -p "$TMP/dirs/d$i"; done && cp "$ASSETS/cube.obj" "$TMP/dirs/"
run 0 "replay .* passed" win bash -c 'cd "$1" && "$2" --size 640x480 --replay "$3" cube.obj' _ "$TMP/dirs" "$EXE" "$SRC/replay/dialog_scroll.txt"

# 1e. A dense mesh (koala, 125k faces) opens as it is, at level 0, with the
# note that points at Mesh > Rebuild levels; --levels still wins.
printf 'wait 1\nexpect top 0\nexpect message Rebuild levels\nquit\n' > "$TMP/dense.txt"
run 0 "replay .* passed" win "$EXE" --size 320x240 --replay "$TMP/dense.txt" "$MESHES/large/koala.obj"
printf 'wait 1\nexpect top 1\nquit\n' > "$TMP/dense1.txt"
run 0 "replay .* passed" win "$EXE" --size 320x240 --levels 1 --replay "$TMP/dense1.txt" "$MESHES/large/koala.obj"
# 1f. With the default model (no file given), File > Open starts in the
# working directory, not in assets/.
printf 'gui on\nwait 2\nkey ctrl+o\nwait 2\nexpect dialog_dir dirs\nquit\n' > "$TMP/dlgcwd.txt"
run 0 "replay .* passed" win bash -c 'cd "$1" && "$2" --size 640x480 --replay "$3"' _ "$TMP/dirs" "$EXE" "$TMP/dlgcwd.txt"

# 1g. The box's max level slider shows its new value before the display is computed.
run 0 "replay .* passed" win "$EXE" --size 640x700 --levels 2 --replay "$SRC/replay/box_slider.txt" "$ASSETS/torus.obj"

# 2. A failing expectation exits non-zero and says which line.
printf 'wait 2\nexpect top 99\nquit\n' > "$TMP/fail.txt"
run 1 "fail.txt:2: expect top 99 failed: actual 2" win "$EXE" --size 320x240 --levels 2 --replay "$TMP/fail.txt" "$ASSETS/cube.obj"
# A bad event file is refused before a window opens.
printf 'wiggle 3\n' > "$TMP/bad.txt"
run 2 "bad.txt:1: unknown event 'wiggle'" "$EXE" --replay "$TMP/bad.txt" "$ASSETS/cube.obj"

# 3. No display: a clear message and a non-zero exit, no crash (signals
# give 128+).
out=$(env -u DISPLAY -u WAYLAND_DISPLAY "$EXE" "$ASSETS/cube.obj" 2>&1); rc=$?
if [ "$rc" -ne 0 ] && [ "$rc" -lt 128 ] && grep -q "cannot open a window" <<<"$out"; then ok
else bad "without a display: exit $rc, output: $out"; fi

# 4. Bad options.
run 2 "unknown option" "$EXE" --frobnicate "$ASSETS/cube.obj"
run 2 "--size wants" "$EXE" --size 12 "$ASSETS/cube.obj"

# 5. Sessions: Ctrl+S saves NAME.strata in the current directory, which
# opens again with its levels; edits left unsaved at exit are in the
# recovery file, which Ctrl+R restores at the next start.
(
    cd "$TMP" || exit 1
    # The session keeps the tool, its strength and falloff, the mirror
    # axes, the display toggles (wireframe on, cage off) and the box (on), and
    # opens with an empty undo history (the box is not a step to undo).
    printf 'wait 1\nkey ctrl+d\nlevel edit 1\nkey shift+c\nbrush strength 0.3\nbrush falloff sharp\nbrush symmetry xz\nkey alt+shift+z\nkey alt+c\nexpect wire 1\nexpect cage 0\nkey i\nexpect box_on 1\nkey ctrl+s\nexpect message saved\nquit\n' > save.txt
    printf 'wait 1\nexpect top 2\nexpect edit_level 1\nexpect tool crease\nexpect brush_strength 30\nexpect falloff sharp\nexpect symmetry xz\nexpect wire 1\nexpect cage 0\nexpect box_on 1\nexpect undo_depth 0\nexpect undo_name -\nquit\n' > load.txt
    printf 'wait 1\nkey ctrl+d\nkey ctrl+d\nquit\n' > edit.txt
    printf 'wait 1\nexpect top 1\nkey ctrl+r\nexpect top 3\nexpect message opened\nquit\n' > recover.txt
) || bad "cannot write the session scripts"
run 0 "saved cube.strata" win bash -c 'cd "$1" && "$2" --size 320x240 --levels 1 --replay save.txt "$3/cube.obj"' _ "$TMP" "$EXE" "$ASSETS"
run 0 "opened session" win bash -c 'cd "$1" && "$2" --size 320x240 --replay load.txt cube.strata' _ "$TMP" "$EXE"
rm -f "$STRATA_RECOVERY"
printf 'wait 2\nquit\n' > "$TMP/noedit.txt"
run 0 "passed" win "$EXE" --size 320x240 --levels 1 --replay "$TMP/noedit.txt" "$ASSETS/cube.obj"
[ ! -e "$STRATA_RECOVERY" ] && ok || bad "a recovery file was written without any edit"
run 0 "passed" win "$EXE" --size 320x240 --levels 1 --replay "$TMP/edit.txt" "$ASSETS/cube.obj"
[ -s "$STRATA_RECOVERY" ] && ok || bad "no recovery file after unsaved edits"
run 0 "opened session .*recovery.strata" win "$EXE" --size 320x240 --levels 1 --replay "$TMP/recover.txt" "$ASSETS/cube.obj"

echo "cli_window: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
