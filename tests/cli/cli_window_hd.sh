#!/usr/bin/env bash
# HD levels in the window (tests/replay/hd_sculpt.txt): spot's cage rebuilt
# from spot_quadrangulated.obj (unsubdivide) with a uniform level added,
# then sculpted at HD level 8 through the real window under Xvfb; the
# replay's expects (edit_level, box_max, hd_faces, box_on) must hold, the
# screenshots must exist, and a session saved from it must list HD levels
# and the HD sculpt layer in `strata info`.
#
#   cli_window_hd.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
. "$(dirname "$0")/window_lib.sh"
need_display "$0" "$@"
EXE=$1 MESHES=$2 ASSETS=$3
SPOT="$MESHES/catmull_clark/spot_quadrangulated.obj"
[ -f "$SPOT" ] || { echo "skipped: $SPOT is missing"; exit 77; }
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_window_hd.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
export STRATA_RECOVERY="$TMP/recovery.strata"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }
"$EXE" rebuild "$SPOT" --method unsubdivide -o "$TMP/cage.strata" >/dev/null 2>&1 || bad "rebuild spot's cage"
"$EXE" convert "$TMP/cage.strata" "$TMP/spot3.strata" --levels 3 >/dev/null || bad "spot's cage to level 3"
cp "$ASSETS/../tests/replay/hd_sculpt.txt" "$TMP/hd.txt"
printf 'menu File/Save_session_as %s\n' "$TMP/hd_saved.strata" >> "$TMP/hd.txt"
(cd "$TMP" && timeout 600 "$EXE" --size 640x480 --replay "$TMP/hd.txt" "$TMP/spot3.strata") >"$TMP/log" 2>&1
if grep -q "replay .* passed" "$TMP/log"; then ok; else bad "the HD replay: $(tail -3 "$TMP/log")"; fi
for s in hd_before hd_after hd_boxoff hd_layer; do
    if [ -s "$TMP/$s.png" ]; then ok; else bad "screenshot $s.png"; fi
done
# The window's bake of the top level reads the HD levels (st_doc_hd_bake_source).
if grep -q "baked level 8 onto level 0" "$TMP/log" && [ -s "$TMP/hd_normal.png" ]; then ok
else bad "the window's bake did not read HD level 8: $(grep -i bake "$TMP/log" | tail -2)"; fi
if [ -s "$TMP/hd_saved.strata" ] && "$EXE" info "$TMP/hd_saved.strata" 2>&1 | grep -q "HD hierarchy"; then ok
else bad "the saved session lists no HD levels: $("$EXE" info "$TMP/hd_saved.strata" 2>&1 | tail -3)"; fi
# ... and the sculpt layer of HD level 8, in the HD image.
if "$EXE" info "$TMP/hd_saved.strata" 2>&1 | grep -q "HD sculpt layer 'Layer 1': level 8, strength 0.75"; then ok
else bad "the saved session lists no HD layer: $("$EXE" info "$TMP/hd_saved.strata" 2>&1 | grep -i layer)"; fi
# The saved session opened again in the window (tests/replay/hd_reopen.txt):
# the HD layer and faces are back and take a stroke.
(cd "$TMP" && timeout 300 "$EXE" --size 640x480 --replay "$ASSETS/../tests/replay/hd_reopen.txt" "$TMP/hd_saved.strata") >"$TMP/log2" 2>&1
if grep -q "replay .* passed" "$TMP/log2"; then ok; else bad "the saved session reopened: $(tail -3 "$TMP/log2")"; fi
# HD level 8 made uniform on spot: about 3 GB; refused under a 64 MiB budget
# before anything is allocated (the estimate was 0 from the HD hierarchy).
out=$(timeout 60 "$EXE" convert "$TMP/hd_saved.strata" "$TMP/l8.obj" --level 8 --mem-budget 64 2>&1); rc=$?
if [ "$rc" = 1 ] && echo "$out" | grep -q "HD level 8 everywhere needs about" && [ ! -e "$TMP/l8.obj" ]; then ok
else bad "convert --level 8 --mem-budget 64 not refused (rc $rc): $out"; fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
