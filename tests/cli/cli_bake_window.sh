#!/usr/bin/env bash
# Baking from the window (docs/BAKING.md, docs/MODELLER.md; ui/bake_ui.c, the job in
# ui/jobs.c, formats/bake_run.h shared with strata bake), under Xvfb:
# - tests/replay/bake_window.txt on spot (2 levels): Bake > Bake maps...,
#   the bake as a job, the maps on disk, View > Show baked map, and
#   File > Export > GLB with "Attach the baked normal map"; the GLB is
#   validator-clean (0 errors) with TEXCOORD_0, TANGENT and a normalTexture
#   and the one exported without the checkbox has no material; the map
#   view differs from the surface view.
# - tests/replay/bake_udim.txt on spot_udim.obj (tests/cli/spot_udim.awk): one
#   map per UDIM tile, and a GLB with one primitive per tile, validator-clean.
# - --strict: the window refuses a non-manifold edge on open (the commands'
#   --strict), and splits it without.
# Needs node and gltf-validator (scripts/setup_node.sh) and xvfb-run.
#   cli_bake_window.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
. "$(dirname "$0")/window_lib.sh"
need_display "$0" "$@"
abs() { (cd "$(dirname "$1")" && printf '%s/%s' "$(pwd)" "$(basename "$1")"); }
EXE=$(abs "$1") MESHES=$(abs "$2") ASSETS=$(abs "$3") BIN=$(abs "$4")
R="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SPOT="$MESHES/catmull_clark/spot_quadrangulated.obj"
[ -f "$SPOT" ] || { echo "note: $SPOT not found: skipped"; exit 77; }
OUT="$BIN/bake_window_out"
rm -rf "$OUT"
mkdir -p "$OUT"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_bake_window.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export STRATA_RECOVERY="$TMP/recovery.strata"
# Leak checks off for processes that open a window (tests/cli/cli_window.sh says why).
WINDOW_ASAN="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
VALIDATOR="${GLTF_VALIDATOR:-$R/build/node/node_modules/gltf-validator}"
export GLTF_VALIDATOR="$VALIDATOR"
passed=0 failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }
# run_in DIR EXPECTED_EXIT PATTERN args...: strata in DIR, its exit and output checked.
run_in() {
    local dir=$1 want=$2 pat=$3
    shift 3
    local out rc=0
    out=$(cd "$dir" && ASAN_OPTIONS="$WINDOW_ASAN" "$@" 2>&1) || rc=$?
    if [ "$rc" -ne "$want" ]; then bad "$* exited $rc, expected $want: $(tail -20 <<<"$out")"; return 1; fi
    if [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$out"; then bad "$*: output lacks /$pat/: $(tail -20 <<<"$out")"; return 1; fi
    ok
}
validate() {
    if node "$R/tests/cli/gltf_validate.js" "$1" > "$TMP/val.txt" 2>&1 && grep -q ': 0 errors' "$TMP/val.txt"; then ok
    else bad "validator on $1: $(cat "$TMP/val.txt")"; fi
    cat "$TMP/val.txt"
}
# glb_json FILE EXPR: EXPR of the GLB's JSON chunk j, printed.
glb_json() {
    node -e 'const b = require("fs").readFileSync(process.argv[1]); const n = b.readUInt32LE(12);
             const j = JSON.parse(b.slice(20, 20 + n).toString()); console.log(eval(process.argv[2]));' "$1" "$2" 2>&1
}

# 1. Spot: bake, view, export.
mkdir -p "$TMP/spot"
run_in "$TMP/spot" 0 "replay .* passed" "$EXE" --size 800x600 --levels 2 --replay "$R/tests/replay/bake_window.txt" \
    --screenshot-dir "$OUT" "$SPOT"
for f in spot_n.png spot_d.exr spot_mapped.glb spot_plain.glb; do [ -s "$TMP/spot/$f" ] && ok || bad "$f not written"; done
[ -e "$TMP/spot/bad.jpg" ] && bad "the refused bake wrote bad.jpg" || ok
ls "$TMP/spot"/*.tmp* 2>/dev/null && bad "temporaries left behind" || ok
validate "$TMP/spot/spot_mapped.glb"
got=$(glb_json "$TMP/spot/spot_mapped.glb" \
  '[j.meshes[0].primitives.length, "TANGENT" in j.meshes[0].primitives[0].attributes, "TEXCOORD_0" in j.meshes[0].primitives[0].attributes, j.materials[0].normalTexture.index, j.images[0].mimeType].join(" ")')
echo "spot_mapped.glb: primitives, TANGENT, TEXCOORD_0, normalTexture, image: $got"
[ "$got" = "1 true true 0 image/png" ] && ok || bad "spot_mapped.glb: $got"
got=$(glb_json "$TMP/spot/spot_plain.glb" '[(j.materials || []).length, "TANGENT" in j.meshes[0].primitives[0].attributes].join(" ")')
[ "$got" = "0 false" ] && ok || bad "spot_plain.glb (no checkbox) has a material or tangents: $got"
# The mapped export is level 0 (the bake's base), the plain one the displayed level 2.
got=$(glb_json "$TMP/spot/spot_mapped.glb" 'j.accessors[j.meshes[0].primitives[0].indices].count / 3')
want=$(awk '/^f / { n += NF - 3 } END { print n }' "$SPOT")
[ "$got" = "$want" ] && ok || bad "spot_mapped.glb has $got triangles, level 0 has $want"
validate "$TMP/spot/spot_plain.glb"
# The map view is not the surface view.
for f in bake_dialog baked_view surface_view; do [ -s "$OUT/$f.png" ] && ok || bad "screenshot $f.png missing"; done
cmp -s "$OUT/baked_view.png" "$OUT/surface_view.png" && bad "Show baked map drew the same picture as the surface" || ok

# 2. UDIM: spot's faces in four tiles.
mkdir -p "$TMP/udim"
awk -f "$R/tests/cli/spot_udim.awk" "$SPOT" > "$TMP/udim/spot_udim.obj"
run_in "$TMP/udim" 0 "replay .* passed" "$EXE" --size 800x600 --levels 2 --replay "$R/tests/replay/bake_udim.txt" \
    --screenshot-dir "$OUT" "$TMP/udim/spot_udim.obj"
validate "$TMP/udim/udim_mapped.glb"
got=$(glb_json "$TMP/udim/udim_mapped.glb" '[j.meshes[0].primitives.length, j.materials.length, j.images.length, j.materials.map(m => m.name).join(",")].join(" ")')
echo "udim_mapped.glb: primitives materials images: $got"
[ "$got" = "4 4 4 strata.1001,strata.1002,strata.1011,strata.1012" ] && ok || bad "udim_mapped.glb: $got"

# 3. --strict: a non-manifold edge refused on open; split without.
NM="$MESHES/edge_cases/nonmanifold_edge.obj"
if [ -f "$NM" ]; then
    printf 'wait 1\nmenu File/Open %s\nexpect error 1\nexpect message non-manifold edge between vertices 4 and 6\nquit\n' "$NM" > "$TMP/strict.txt"
    run_in "$TMP" 0 "replay .* passed" "$EXE" --strict --size 320x240 --levels 1 --replay "$TMP/strict.txt" "$ASSETS/cube.obj"
    printf 'wait 1\nmenu File/Open %s\nexpect error 0\nexpect faces 12\nquit\n' "$NM" > "$TMP/split.txt"
    run_in "$TMP" 0 "replay .* passed" "$EXE" --size 320x240 --levels 1 --replay "$TMP/split.txt" "$ASSETS/cube.obj"
else
    bad "$NM not found: --strict cannot be tested (the shared test meshes are incomplete)"
fi

# 4. The window opens glTF: a .glb on the command line and through File >
# Open (the document reads meshes through the program's reader,
# st_any_mesh_load; glTF's cube is 12 triangles).
run_in "$TMP" 0 "" "$EXE" convert "$ASSETS/cube.obj" "$TMP/cube.glb"
printf 'wait 1\nexpect error 0\nexpect faces 12\nmenu File/Open %s\nexpect error 0\nexpect faces 12\nquit\n' "$TMP/cube.glb" > "$TMP/glb.txt"
run_in "$TMP" 0 "replay .* passed" "$EXE" --size 320x240 --levels 0 --replay "$TMP/glb.txt" "$TMP/cube.glb"

echo "cli_bake_window: $passed passed, $failed failed (screenshots in $OUT)"
[ "$failed" -eq 0 ]
