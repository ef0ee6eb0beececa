#!/usr/bin/env bash
# `strata render` from the command line: headless (no $DISPLAY), from any
# directory (shaders are embedded), same bytes for the same inputs, the same
# image as the in-process renderer (compared with a reference under the
# image metric of tests/render/test_render_images.c), every mode and view, the UV
# checker against its own reference, and
# clear errors with non-zero exits on bad arguments.
#
#   cli_render.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
EXE=$1 MESHES=$2 ASSETS=$3 BIN=$4
# Absolute paths: the script works from another directory.
abs() { (cd "$(dirname "$1")" && printf '%s/%s' "$(pwd)" "$(basename "$1")"); }
EXE=$(abs "$EXE") ASSETS=$(abs "$ASSETS") BIN=$(abs "$BIN") MESHES=$(abs "$MESHES")
REF="$ASSETS/../tests/render_ref"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_render.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
unset DISPLAY WAYLAND_DISPLAY
passed=0 failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }

# run EXPECTED_EXIT PATTERN_IN_OUTPUT args... : runs strata, checks the exit
# status and that its output (stdout + stderr) matches PATTERN.
run() {
    local want=$1 pat=$2
    shift 2
    local out rc=0
    out=$("$EXE" "$@" 2>&1) || rc=$?
    if [ "$rc" -ne "$want" ]; then bad "strata $* exited $rc, expected $want: $out"; return; fi
    if [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$out"; then bad "strata $*: output lacks /$pat/: $out"; return; fi
    ok
}

is_png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ]; }

# Listed by help (scripts/run.sh looks for this line).
if "$EXE" help | grep -qE '^[[:space:]]*render[[:space:]]'; then ok; else bad "strata help does not list render"; fi

# From another directory, no display.
cd "$TMP"
run 0 "^wrote a\.png \(160x120, flat, level 2, 96 faces, iso view\)" render "$ASSETS/cube.obj" --levels 2 --mode flat --size 160x120 -o a.png
if [ -f a.png ] && is_png a.png; then ok; else bad "a.png is not a PNG"; fi
run 0 "^wrote" render "$ASSETS/cube.obj" --scheme catmull-clark --levels 2 --level 2 --mode flat --view iso --size 160x120 -o b.png
if cmp -s a.png b.png; then ok; else bad "two runs with the same inputs gave different files"; fi

# The CLI draws what the library draws: compare with the matrix reference.
if [ -z "${STRATA_UPDATE_REFS:-}" ] && [ -x "$BIN/test_render_images" ] && [ -f "$REF/cube_catmark_l2_flat.png" ]; then
    if "$BIN/test_render_images" --compare "$REF/cube_catmark_l2_flat.png" a.png; then ok; else bad "CLI image differs from tests/render_ref/cube_catmark_l2_flat.png"; fi
else
    echo "note: reference comparison skipped (updating references, or test_render_images not built)"
fi

# Every mode and view, the orbit form, a level below the top, and default size.
for m in smooth flat wire cage; do
    for v in front back left right top iso; do
        run 0 "^wrote m\.png \(48x32, $m, level 1" render "$ASSETS/octahedron.obj" --scheme loop --levels 1 --mode "$m" --view "$v" --size 48x32 -o m.png
    done
done
run 0 "orbit 30,-20,0\)" render "$ASSETS/torus.obj" --levels 1 --orbit 30,-20,0 --size 64x48 -o o1.png
run 0 "orbit 30,-20,12\)" render "$ASSETS/torus.obj" --levels 1 --orbit 30,-20,12 --size 64x48 -o o2.png
if cmp -s o1.png o2.png; then bad "--orbit distance had no effect"; else ok; fi
run 0 "level 0, 6 faces" render "$ASSETS/cube.obj" --levels 2 --level 0 --size 64x48 -o l0.png
run 0 "800x600" render "$ASSETS/tetrahedron.obj" --scheme sqrt3 --levels 2 -o big.png
for s in doo-sabin butterfly quad-triangle; do
    run 0 "^wrote" render "$ASSETS/octahedron.obj" --scheme "$s" --levels 2 --size 64x48 -o s.png
done
run 0 "^wrote" render "$ASSETS/open.obj" --levels 2 --mode wire --size 64x48 -o open.png
# Adaptive display: the top level of an interest-box refinement.  (Where a
# vertex lies on a plane of the box, which side its position falls on is a
# matter of the last bit, which depends on the face whose stencil placed it:
# on the cube's plane of symmetry 0 or -1.7e-18.  Since an update places a
# shared vertex once, by the first face that holds it, one more face touches
# the box in each case here: 129 and 425 faces, 126 and 422 before.)
run 0 "level 3, 129 faces" render "$ASSETS/cube.obj" --box 0,0,0,1,1,1 --size 64x48 -o box.png

# UV checker (--mode uv): a shared mesh with UVs against its reference (made
# by this script under STRATA_UPDATE_REFS=1: look at it before committing),
# another view and scheme, and what has no UVs refused.
UVMESH="$MESHES/catmull_clark/blub_control_mesh.obj"
run 0 "^wrote uv\.png \(160x120, uv, level 2, 1776 faces, iso view\)" render "$UVMESH" --levels 2 --mode uv --size 160x120 -o uv.png
run 0 "^wrote" render "$UVMESH" --levels 2 --mode smooth --size 160x120 -o uv_smooth.png
if cmp -s uv.png uv_smooth.png; then bad "--mode uv drew the same image as --mode smooth"; else ok; fi
if [ -n "${STRATA_UPDATE_REFS:-}" ]; then
    cp uv.png "$REF/blub_catmark_l2_uv.png" && echo "updated $REF/blub_catmark_l2_uv.png"
elif [ -x "$BIN/test_render_images" ]; then
    if "$BIN/test_render_images" --compare "$REF/blub_catmark_l2_uv.png" uv.png; then ok
    else bad "--mode uv image differs from tests/render_ref/blub_catmark_l2_uv.png"; fi
fi
run 0 "^wrote uvl\.png \(64x48, uv, level 1, 1280 faces, front view\)" render "$MESHES/triangle/sphere_ico.obj" --scheme loop --levels 1 --mode uv --view front --size 64x48 -o uvl.png
run 1 "no UVs for --mode uv" render "$ASSETS/cube.obj" --levels 1 --mode uv --size 32x24 -o nouv.png
# √3 and Doo-Sabin subdivide the UVs too (docs/SUBDIVISION-RULES.md §7b): every level drawn.
run 0 "^wrote uvs1\.png \(32x24, uv, level 1, 960 faces" render "$MESHES/triangle/sphere_ico.obj" --scheme sqrt3 --levels 1 --mode uv --size 32x24 -o uvs1.png
run 0 "^wrote uvs0\.png \(32x24, uv, level 0" render "$MESHES/triangle/sphere_ico.obj" --scheme sqrt3 --levels 1 --level 0 --mode uv --size 32x24 -o uvs0.png
run 0 "^wrote uvds\.png \(32x24, uv, level 2, 1778 faces" render "$UVMESH" --scheme doo-sabin --levels 2 --mode uv --size 32x24 -o uvds.png
# With --box: the adaptive mesh's own UVs (core/adapt/adapt_uv.c), against
# its reference (made the same way as the one above); no UVs: refused.
run 0 "^wrote uvbox\.png \(160x120, uv, level 3, 425 faces, iso view\)" render "$UVMESH" --box 0,0,0,0.5,0.5,0.5 --max-level 3 --mode uv --size 160x120 -o uvbox.png
if [ -n "${STRATA_UPDATE_REFS:-}" ]; then
    cp uvbox.png "$REF/blub_catmark_box_uv.png" && echo "updated $REF/blub_catmark_box_uv.png"
elif [ -x "$BIN/test_render_images" ]; then
    if "$BIN/test_render_images" --compare "$REF/blub_catmark_box_uv.png" uvbox.png; then ok
    else bad "--box --mode uv image differs from tests/render_ref/blub_catmark_box_uv.png"; fi
fi
run 1 "no UVs for --mode uv: the mesh has no texture coordinates" render "$ASSETS/cube.obj" --box 0,0,0,1,1,1 --mode uv -o nouv.png
if [ ! -e nouv.png ]; then ok; else bad "a refused --mode uv left an output file"; fi

# Bad arguments: exit 2 with a message naming the problem; bad input: exit 1.
run 2 "--mode wants" render "$ASSETS/cube.obj" --mode shiny -o x.png
run 2 "--view wants" render "$ASSETS/cube.obj" --view under -o x.png
run 2 "--size wants" render "$ASSETS/cube.obj" --size 0x10 -o x.png
run 2 "--size wants" render "$ASSETS/cube.obj" --size 100 -o x.png
run 2 "--size wants" render "$ASSETS/cube.obj" --size 99999x10 -o x.png
run 2 "--orbit wants" render "$ASSETS/cube.obj" --orbit 1,2 -o x.png
run 2 "--orbit wants" render "$ASSETS/cube.obj" --orbit a,b,c -o x.png
run 2 "either --view or --orbit" render "$ASSETS/cube.obj" --view top --orbit 1,2,3 -o x.png
run 2 "needs a value" render "$ASSETS/cube.obj" -o x.png --mode
run 2 "-o OUT.png is required" render "$ASSETS/cube.obj"
run 2 "must be a \.png" render "$ASSETS/cube.obj" -o x.jpg
run 2 "above --levels" render "$ASSETS/cube.obj" --levels 1 --level 3 -o x.png
run 2 "--box wants" render "$ASSETS/cube.obj" --box 0,0,0,1,1 -o x.png
run 2 "do not go with --box" render "$ASSETS/cube.obj" --box 0,0,0,1,1,1 --levels 2 -o x.png
run 2 "--base-level is above" render "$ASSETS/cube.obj" --box 0,0,0,1,1,1 --base-level 3 --max-level 1 -o x.png
run 2 "unknown or incomplete option" render "$ASSETS/cube.obj" --frobnicate -o x.png
run 2 "unknown scheme" render "$ASSETS/cube.obj" --scheme nurbs -o x.png
run 1 "cannot open|No such file" render "$TMP/missing.obj" -o x.png
run 1 "triangle" render "$ASSETS/cube.obj" --scheme loop -o x.png
run 1 "cannot write" render "$ASSETS/cube.obj" --size 32x24 -o "$TMP/no/such/dir/x.png"
if [ ! -e x.png ] && [ ! -e x.jpg ]; then ok; else bad "a failed render left an output file"; fi

echo "cli_render: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
