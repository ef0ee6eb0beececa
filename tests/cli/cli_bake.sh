#!/usr/bin/env bash
# `strata bake` and `strata render --normal-map` from the command line:
# normal maps (8- and 16-bit PNG), displacement maps (32-bit float EXR, or
# 16-bit PNG with its JSON scale and offset), same bytes for the same
# inputs, sessions and meshes as input, on the mesh's own UVs or the
# --auto-uv atlas, √3 and Doo-Sabin by rays along level B's normals (the
# rendered map close to level L: test_render_bake --compare), and refusals
# (no UVs, overlapping UVs, progressive hierarchies, levels, sizes,
# extensions, the memory budget) with a message, a non-zero exit and nothing
# written.
#
#   cli_bake.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
EXE=$1 MESHES=$2 ASSETS=$3 BIN=$4
abs() { (cd "$(dirname "$1")" && printf '%s/%s' "$(pwd)" "$(basename "$1")"); }
EXE=$(abs "$EXE") ASSETS=$(abs "$ASSETS")
: "$MESHES" "$BIN"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_bake.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
unset DISPLAY WAYLAND_DISPLAY
passed=0 failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }

# run EXPECTED_EXIT PATTERN args...: exit status and output (stdout + stderr).
run() {
    local want=$1 pat=$2
    shift 2
    local out rc=0
    out=$("$EXE" "$@" 2>&1) || rc=$?
    if [ "$rc" -ne "$want" ]; then bad "strata $* exited $rc, expected $want: $out"; return; fi
    if [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$out"; then bad "strata $*: output lacks /$pat/: $out"; return; fi
    ok
}
magic() { head -c "$2" "$1" | od -An -tx1 | tr -d ' \n'; }
is_png() { [ "$(magic "$1" 8)" = "89504e470d0a1a0a" ]; }
is_exr() { [ "$(magic "$1" 4)" = "762f3101" ]; }
# PNG IHDR: bit depth at byte 24, colour type at byte 25 (0 grey, 2 RGB).
png_depth() { od -An -tu1 -j24 -N1 "$1" | tr -d ' '; }
png_type() { od -An -tu1 -j25 -N1 "$1" | tr -d ' '; }
nothing_written() { # nothing named $1* in $TMP
    if compgen -G "$TMP/$1*" >/dev/null; then bad "files were written: $(ls "$TMP"/"$1"*)"; else ok; fi
}

cd "$TMP"
if "$EXE" help | grep -qE '^[[:space:]]*bake[[:space:]]'; then ok; else bad "strata help does not list bake"; fi
run 0 "" convert "$ASSETS/cube.obj" cube.strata --levels 3

# Normal map (8-bit) and scalar displacement (EXR).
run 0 "^wrote n\.png \(256x256, tangent-space normals, 8-bit RGB\)" \
    bake cube.strata --base-level 1 --normal-map n.png --displacement-map d.exr --size 256 --auto-uv
if is_png n.png && [ "$(png_depth n.png)" = 8 ] && [ "$(png_type n.png)" = 2 ]; then ok; else bad "n.png is not an 8-bit RGB PNG"; fi
if is_exr d.exr; then ok; else bad "d.exr is not an OpenEXR file"; fi
run 0 "level 3 onto level 1: [0-9]+ texels baked, [0-9]+ padded, displacement -" \
    bake cube.strata --base-level 1 --normal-map n2.png --displacement-map d2.exr --size 256 --auto-uv
if cmp -s n.png n2.png && cmp -s d.exr d2.exr; then ok; else bad "two bakes with the same inputs gave different files"; fi
# No temporary files left (the old name NAME.tmp.EXT and the atomic
# writer's NAME.tmp-PID).
if compgen -G "$TMP/*.tmp.*" >/dev/null || compgen -G "$TMP/*.tmp-*" >/dev/null; then
    bad "temporary files left: $(ls "$TMP" | grep '\.tmp')"; else ok; fi

# 16-bit normal map, vector displacement as 16-bit PNG + JSON.
run 0 "wrote dv\.png \(128x128, vector displacement, 16-bit PNG\), scale and offset in dv\.json" \
    bake cube.strata --base-level 0 --level 2 --normal-map n16.png --bits 16 --displacement-map dv.png --vector --size 128 --auto-uv
if [ "$(png_depth n16.png)" = 16 ] && [ "$(png_depth dv.png)" = 16 ] && [ "$(png_type dv.png)" = 2 ]; then ok; else bad "n16.png/dv.png are not 16-bit RGB"; fi
if grep -q '"scale": ' dv.json && grep -q '"offset": -' dv.json && grep -q '"image": "dv.png"' dv.json; then ok; else bad "dv.json lacks scale/offset: $(cat dv.json)"; fi
run 0 "scalar displacement, 16-bit PNG" bake cube.strata --base-level 1 --displacement-map ds.png --size 64 --auto-uv
if [ "$(png_type ds.png)" = 0 ]; then ok; else bad "a scalar displacement PNG is not grey"; fi
run 0 "object-space normals" bake cube.strata --base-level 1 --normal-map no.png --space object --size 64 --padding 0 --auto-uv

# A mesh as input, Loop and quad/triangle.
run 0 "level 2 onto level 0" bake "$ASSETS/octahedron.obj" --scheme loop --levels 2 --base-level 0 --normal-map lo.png --size 64 --auto-uv
run 0 "level 2 onto level 1" bake "$ASSETS/mixed.obj" --scheme quad-triangle --levels 2 --base-level 1 --normal-map qt.png --size 64 --auto-uv

# The mesh's own UVs (no --auto-uv): the icosphere's layout, from the OBJ
# and from a session; --auto-uv still forces the generated atlas, which
# covers other texels.
ICO="$MESHES/triangle/sphere_ico.obj"
run 0 "level 2 onto level 0: [0-9]+ texels baked" bake "$ICO" --scheme loop --levels 2 --base-level 0 --normal-map ico.png --displacement-map ico.exr --size 128
run 0 "" convert "$ICO" ico.strata --scheme loop --levels 2
run 0 "level 2 onto level 1: [0-9]+ texels baked" bake ico.strata --base-level 1 --normal-map ico1.png --size 128
run 0 "level 2 onto level 0" bake ico.strata --base-level 0 --normal-map ico_s.png --displacement-map ico_s.exr --size 128
if cmp -s ico.png ico_s.png && cmp -s ico.exr ico_s.exr; then ok; else bad "the OBJ and its session baked different maps"; fi
own=$("$EXE" bake ico.strata --base-level 0 --normal-map o.png --size 128 2>&1 | grep -oE '[0-9]+ texels baked')
auto=$("$EXE" bake ico.strata --base-level 0 --normal-map a.png --size 128 --auto-uv 2>&1 | grep -oE '[0-9]+ texels baked')
if [ -n "$own" ] && [ -n "$auto" ] && [ "$own" != "$auto" ] && ! cmp -s o.png a.png; then ok
else bad "own UVs ($own) and --auto-uv ($auto) baked the same"; fi
run 0 "^wrote ir\.png \(96x96, smooth, level 0, 320 faces" render ico.strata --level 0 --normal-map ico_s.png --size 96x96 -o ir.png
run 0 "^wrote" render ico.strata --level 0 --size 96x96 -o iplain.png
if ! cmp -s ir.png iplain.png; then ok; else bad "the normal map on the icosphere's UVs did not change the image"; fi
# A map baked with --auto-uv on a level that has UVs of its own (blub's
# level 1) is read on the same atlas with render --auto-uv: mapped level 1
# is then nearer level 3 than plain level 1 is (mean difference on the
# pixels both cover: 10.3 against 11.1/255 when written), and nearer than
# the same map read on the level's own UVs (14.9).
BLUB="$MESHES/catmull_clark/blub_control_mesh.obj"
run 0 "" convert "$BLUB" blub3.strata --levels 3
run 0 "coverage: " bake blub3.strata --base-level 1 --normal-map ba.png --size 512 --auto-uv
run 0 "^wrote" render blub3.strata --level 1 --normal-map ba.png --auto-uv --size 320x320 -o ba_mapped.png
run 0 "^wrote" render blub3.strata --level 1 --normal-map ba.png --size 320x320 -o ba_own.png
run 0 "^wrote" render blub3.strata --level 1 --size 320x320 -o ba_plain.png
run 0 "^wrote" render blub3.strata --level 3 --size 320x320 -o ba_fine.png
mean_to_fine() { "$BIN/test_render_bake" --compare ba_fine.png "$1" ba_plain.png | sed -nE 's/^compare: [^ ]+ vs [^ ]+: mean ([0-9.]+)\/255.*p?.*$/\1/p' | head -1; }
m=$(mean_to_fine ba_mapped.png) o=$(mean_to_fine ba_own.png) p=$(mean_to_fine ba_plain.png)
if [ -n "$m" ] && [ -n "$o" ] && [ -n "$p" ] && awk -v m="$m" -v o="$o" -v p="$p" 'BEGIN { exit !(m < p && m < o) }'; then
    ok; echo "auto-uv map on blub's level 1, mean difference to level 3: on its atlas $m, on the own UVs $o, plain $p (/255)"
else bad "the --auto-uv map read on its atlas is not the nearest to level 3: atlas '$m', own UVs '$o', plain '$p'"; fi
run 2 "--auto-uv applies to --mode uv or --normal-map" render blub3.strata --level 0 --auto-uv --size 64x64 -o y.png
run 2 "--auto-uv goes with --normal-map" convert blub3.strata y.glb --level 0 --auto-uv
# blub's control mesh has a quad concave in UV (face 106): split through its
# reflex corner it bakes on its own UVs (no false "UV islands overlap").
run 0 "level 3 onto level 0: [0-9]+ texels baked" bake "$MESHES/catmull_clark/blub_control_mesh.obj" --levels 3 --base-level 0 --normal-map blub.png --size 256
if [ -f blub.png ] && is_png blub.png; then ok; else bad "blub_control_mesh baked no normal map"; fi
# Overlapping islands (every face of the cube on the same unit square) are
# refused with nothing written; a corner moved outside [0,1] (issue 31: no
# longer refused for its range) leaves the islands overlapping all the same.
{ grep '^v ' "$ASSETS/cube.obj"; printf 'vt 0.1 0.1\nvt 0.9 0.1\nvt 0.9 0.9\nvt 0.1 0.9\n'
  grep '^f ' "$ASSETS/cube.obj" | awk '{ printf "f %s/1 %s/2 %s/3 %s/4\n", $2, $3, $4, $5 }'; } > stacked.obj
run 1 "stacked\.obj: UV islands overlap: faces [0-9]+ and [0-9]+ of level 0" bake stacked.obj --levels 1 --base-level 0 --normal-map xo.png --displacement-map xo.exr --size 64
nothing_written xo
sed 's/^vt 0\.9 0\.9/vt 1.5 0.9/' stacked.obj > tiled.obj
run 1 "tiled\.obj: UV islands overlap: faces [0-9]+ and [0-9]+ of level 0" bake tiled.obj --levels 1 --base-level 0 --normal-map xo.png --size 64
nothing_written xo
run 0 "level 1 onto level 0" bake stacked.obj --levels 1 --base-level 0 --normal-map so.png --size 64 --auto-uv

# Refusals: message, exit status, nothing written.
run 1 "level 1 has no UVs .*--auto-uv" bake cube.strata --base-level 1 --normal-map x.png --size 64
nothing_written x
"$EXE" rebuild "$ASSETS/torus.obj" --method progressive --target-faces 100 -o prog.strata >/dev/null 2>&1
run 1 "prog\.strata: baking needs a subdivision hierarchy; progressive levels come from edge collapses" \
    bake prog.strata --base-level 0 --normal-map x.png --auto-uv
nothing_written x
run 1 "cannot bake level 3 onto level 4: levels are 0\.\.3" bake cube.strata --base-level 4 --normal-map x.png --auto-uv
run 1 "cannot bake level 1 onto level 2" bake cube.strata --base-level 2 --level 1 --normal-map x.png --auto-uv
run 1 "baking and writing the maps needs about [0-9.]+ MiB more .*memory budget is 8\.0 MiB" \
    bake cube.strata --base-level 1 --normal-map x.png --displacement-map x.exr --size 4096 --auto-uv --mem-budget 8
nothing_written x
run 2 "--base-level B is required" bake cube.strata --normal-map x.png --auto-uv
run 2 "nothing to bake" bake cube.strata --base-level 0 --auto-uv
run 2 "--size wants 1\.\.16384" bake cube.strata --base-level 0 --normal-map x.png --size 0 --auto-uv
run 2 "--bits wants 8 or 16" bake cube.strata --base-level 0 --normal-map x.png --bits 12 --auto-uv
run 2 "--space wants tangent or object" bake cube.strata --base-level 0 --normal-map x.png --space world --auto-uv
run 2 "x\.jpg: the normal map is written as \.png" bake cube.strata --base-level 0 --normal-map x.jpg --auto-uv
run 2 "x\.tif: the displacement map is written as \.exr or \.png" bake cube.strata --base-level 0 --displacement-map x.tif --auto-uv
run 2 "--vector applies to --displacement-map" bake cube.strata --base-level 0 --normal-map x.png --vector --auto-uv
run 2 "unknown or incomplete option '--frobnicate'" bake cube.strata --base-level 0 --normal-map x.png --frobnicate --auto-uv
run 1 "missing\.strata" bake missing.strata --base-level 0 --normal-map x.png --auto-uv
mkdir ro && chmod 555 ro
if [ "$(id -u)" != 0 ]; then
    # The output is named with the reason, never the temporary.
    run 1 "ro/x\.png: cannot write: Permission denied" bake cube.strata --base-level 0 --normal-map ro/x.png --size 16 --auto-uv
fi
nothing_written x

# render --normal-map: level 1 with its baked map.
run 0 "^wrote r\.png \(96x96, smooth, level 1, 24 faces, iso view\)" render cube.strata --level 1 --normal-map n.png --size 96x96 -o r.png
if is_png r.png; then ok; else bad "r.png is not a PNG"; fi
run 0 "^wrote r2\.png" render cube.strata --level 1 --normal-map n.png --size 96x96 -o r2.png
if cmp -s r.png r2.png; then ok; else bad "two renders with the same inputs gave different files"; fi
run 0 "^wrote" render cube.strata --level 1 --normal-map no.png --normal-space object --size 96x96 -o ro.png
# The map changes the picture (the plain level differs from the mapped one).
run 0 "^wrote" render cube.strata --level 1 --size 96x96 -o plain.png
if ! cmp -s r.png plain.png; then ok; else bad "the normal map did not change the image"; fi
run 1 "missing\.png: cannot open" render cube.strata --level 1 --normal-map missing.png -o y.png
printf 'not a png\n' > fake.png
run 1 "fake\.png" render cube.strata --level 1 --normal-map fake.png -o y.png
run 2 "does not go with --box or --mode wire" render cube.strata --level 1 --normal-map n.png --mode wire -o y.png
run 2 "--normal-space wants tangent or object" render cube.strata --level 1 --normal-map n.png --normal-space up -o y.png
nothing_written y

# √3 and Doo-Sabin: the faces do not nest, so the bake casts rays along
# level B's normals (the open cube of ../shared, its own UVs); the output
# says so; level B rendered with its map is close to level L (closer than
# plain level B: test_render_bake's comparison and thresholds).
CNB="$MESHES/triangle/cube_no_bottom.obj"
for scheme in sqrt3 doo-sabin; do
    L=5; [ $scheme = doo-sabin ] && L=4
    run 0 "" convert "$CNB" $scheme.strata --scheme $scheme --levels $L
    run 0 "correspondence: by rays along level 1's normals: [0-9]+ texels, [0-9]+ misses \(filled flat\), reach 0\.17" \
        bake $scheme.strata --base-level 1 --normal-map ${scheme}_n.png --displacement-map ${scheme}_d.exr --size 1024
    if is_png ${scheme}_n.png && is_exr ${scheme}_d.exr; then ok; else bad "$scheme: no maps written"; fi
    "$EXE" bake $scheme.strata --base-level 1 --normal-map ${scheme}_n2.png --size 1024 >/dev/null 2>&1
    if cmp -s ${scheme}_n.png ${scheme}_n2.png; then ok; else bad "$scheme: two bakes by rays gave different maps"; fi
    run 0 "^wrote" render $scheme.strata --level $L --size 320x320 -o ${scheme}_fine.png
    run 0 "^wrote" render $scheme.strata --level 1 --normal-map ${scheme}_n.png --size 320x320 -o ${scheme}_mapped.png
    run 0 "^wrote" render $scheme.strata --level 1 --size 320x320 -o ${scheme}_plain.png
    if [ -x "$BIN/test_render_bake" ]; then
        if out=$("$BIN/test_render_bake" --compare ${scheme}_fine.png ${scheme}_mapped.png ${scheme}_plain.png); then ok; echo "$scheme: $out"
        else bad "$scheme: level 1 with its map is not close to level $L: $out"; fi
    fi
done
# The nesting schemes keep the exact correspondence; --ray-reach is checked.
run 0 "correspondence: exact \(the faces of level 2 nest in those of level 0\)" \
    bake "$ASSETS/octahedron.obj" --scheme loop --levels 2 --base-level 0 --normal-map lo2.png --size 64 --auto-uv
run 0 "misses \(filled flat\), reach 0\.5$" bake sqrt3.strata --base-level 1 --normal-map r5.png --size 64 --ray-reach 0.5
run 2 "--ray-reach wants a distance > 0" bake sqrt3.strata --base-level 1 --normal-map x.png --ray-reach -1
nothing_written x

# --auto-uv's atlas of charts (core/uv) uses the map: at least 55 % of a
# 1024² map's texels baked on spot's cage, blub's cage and koala's
# progressive level 0 (strata rebuild --method progressive, written out as
# a mesh: progressive hierarchies are not baked), with a note giving the
# charts and their distortion.
coverage_at_least() { # LABEL PERCENT args...: the bake's "coverage:" line at PERCENT or more
    local label=$1 want=$2 out pct
    shift 2
    if ! out=$("$EXE" "$@" 2>&1); then bad "$label: strata $* failed: $out"; return; fi
    pct=$(sed -n 's/^coverage: [0-9]* of [0-9]* texels baked (\([0-9.]*\) %)$/\1/p' <<<"$out")
    if ! grep -qE '^note: auto UVs of level 0: [0-9]+ charts .*L2 stretch [0-9.]+, angle error [0-9.]+ deg' <<<"$out"; then
        bad "$label: no auto-UV note: $out"; return; fi
    if [ -n "$pct" ] && awk -v p="$pct" -v w="$want" 'BEGIN { exit !(p >= w) }'; then ok; echo "$label: $pct % of the texels baked"
    else bad "$label: coverage '$pct' % under $want %: $out"; fi
}
skipped=0
SPOT="$MESHES/catmull_clark/spot_quadrangulated.obj" BLUB="$MESHES/catmull_clark/blub_control_mesh.obj" KOALA="$MESHES/large/koala.obj"
if [ -f "$SPOT" ] && [ -f "$BLUB" ] && [ -f "$KOALA" ]; then
    coverage_at_least "spot cage" 55 bake "$SPOT" --levels 1 --base-level 0 --normal-map cov_spot.png --size 1024 --auto-uv
    coverage_at_least "blub cage" 55 bake "$BLUB" --levels 2 --base-level 0 --normal-map cov_blub.png --size 1024 --auto-uv
    run 0 "" rebuild "$KOALA" --method progressive -o koala_p.strata
    run 0 "" convert koala_p.strata koala_p0.obj --level 0
    coverage_at_least "koala progressive level 0" 55 bake koala_p0.obj --levels 1 --base-level 0 --normal-map cov_koala.png --size 1024 --auto-uv
    # The map's own size and the default padding give render the bake's layout.
    run 0 "^wrote" render "$BLUB" --levels 2 --level 0 --normal-map cov_blub.png --size 96x96 -o cov_blub_r.png
    # The UV checker through the atlas (--mode uv --auto-uv); without
    # --auto-uv a mesh without UVs is refused and pointed to it.
    run 0 "^wrote cov_uv\.png \(96x96, uv, level 0, 112 faces" render "$BLUB" --level 0 --mode uv --auto-uv --size 96x96 -o cov_uv.png
    run 1 "no UVs for --mode uv .*--auto-uv" render koala_p0.obj --level 0 --mode uv --size 96x96 -o cov_none.png
    run 2 "--auto-uv applies to --mode uv" render "$BLUB" --level 0 --auto-uv --size 96x96 -o cov_none.png
    nothing_written cov_none
else
    echo "skipped: spot, blub or koala missing under $MESHES"; skipped=1
fi

echo "cli_bake: $passed passed, $failed failed"
[ "$failed" -eq 0 ] || exit 1
[ "$skipped" -eq 0 ] || exit 77
