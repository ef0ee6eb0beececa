#!/usr/bin/env bash
# Issue 31: no command refuses because of the UV range.
# - Keenan Crane's spot (u from -0.052 to 1.00065) bakes at base levels 0
#   and 1, the corners outside their tile counted in a note and baked with
#   wrap-around; level 0 renders with its map (closer to the fine level than
#   plain, test_render_bake --compare's figures printed) and exports to a
#   GLB whose normal texture samples with REPEAT, validator-clean.
# - spot_udim.obj, made here: spot's faces moved whole tiles by the quadrant
#   of their 3D centroid (tiles 1001, 1002, 1011, 1012), bakes one image per
#   tile (NAME.1001.png ...), renders from NAME.<UDIM>.png like the single
#   map; --udim off wraps the four tiles back into one map; --udim on
#   refuses a layout with a face in a tile without a UDIM number.
# Needs node and gltf-validator (as cli_gltf.sh): without them it FAILS.
#   cli_bake_udim.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
EXE=$1 MESHES=$2 BIN=$4
R="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_bake_udim.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
cd "$TMP" || exit 1
unset DISPLAY WAYLAND_DISPLAY
passed=0 failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }
run() {
    local want=$1 pat=$2
    shift 2
    local out rc=0
    out=$("$EXE" "$@" 2>&1) || rc=$?
    echo "$out" | grep -E "note|UDIM|tile|texels baked|refus|UDIM number" | head -12
    if [ "$rc" -ne "$want" ]; then bad "strata $* exited $rc, expected $want: $out"; return; fi
    if [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$out"; then bad "strata $*: output lacks /$pat/: $out"; return; fi
    ok
}
SPOT="$MESHES/catmull_clark/spot_quadrangulated.obj"
T="$BIN/test_render_bake"

# Spot at base levels 0 and 1 (both refused before issue 31).
run 0 "note: 8 of 11712 corners of level 0 lie outside their face's UV tile: baked with wrap-around" \
    bake "$SPOT" --levels 3 --base-level 0 --normal-map s0.png --displacement-map s0.exr --size 512
run 0 "note: [0-9]+ of 46848 corners of level 1 lie outside their face's UV tile.*" \
    bake "$SPOT" --levels 3 --base-level 1 --normal-map s1.png --size 512
[ -f s0.png ] && [ -f s0.exr ] && [ -f s1.png ] && ok || bad "spot's maps not written"
run 0 "^wrote" render "$SPOT" --levels 3 --level 3 --size 320x320 -o fine.png
run 0 "^wrote" render "$SPOT" --levels 3 --level 0 --size 320x320 -o plain.png
run 0 "^wrote" render "$SPOT" --levels 3 --level 0 --normal-map s0.png --size 320x320 -o mapped.png
cmp -s mapped.png plain.png && bad "spot's map did not change the render" || ok
# Mean difference to the fine level: the mapped level 0 closer than plain.
cmpout=$("$T" --compare fine.png mapped.png plain.png 2>&1)
echo "spot: $cmpout"
m=$(sed -nE 's/.*vs fine\.png: mean ([0-9.]+)\/255.*/\1/p' <<<"$cmpout")
p=$(sed -nE 's/.*plain\.png: mean ([0-9.]+)\/255.*/\1/p' <<<"$cmpout")
if [ -n "$m" ] && [ -n "$p" ] && awk -v m="$m" -v p="$p" 'BEGIN { exit !(m < p) }'; then ok; else bad "spot mapped ($m) not closer to level 3 than plain ($p)"; fi

# GLB with the map: TEXCOORD_0, TANGENT, normalTexture, REPEAT sampler.
VALIDATOR="${GLTF_VALIDATOR:-$R/build/node/node_modules/gltf-validator}"
export GLTF_VALIDATOR="$VALIDATOR"
run 0 "normal map" convert "$SPOT" spot.glb --levels 3 --level 0 --normal-map s0.png
if node "$R/tests/cli/gltf_validate.js" spot.glb >val.txt 2>&1 && grep -q ': 0 errors, 0 warnings' val.txt; then ok; else bad "validator on spot.glb: $(cat val.txt)"; fi
cat val.txt
if grep -aq '"wrapS":10497' spot.glb && grep -aq '"wrapT":10497' spot.glb; then ok; else bad "spot.glb's sampler does not repeat"; fi

# The UDIM mesh: each face moved by whole tiles (the %.17g keeps shared
# corners of faces in one tile bit-equal).
awk -f "$R/tests/cli/spot_udim.awk" "$SPOT" > spot_udim.obj
for B in 0 1; do
    run 0 "UDIM: 4 tiles written" bake spot_udim.obj --levels 3 --base-level $B --normal-map u$B.png --displacement-map d$B.exr --size 256
    for n in 1001 1002 1011 1012; do [ -f u$B.$n.png ] && [ -f d$B.$n.exr ] && ok || bad "base $B: tile $n not written"; done
done
run 0 "^wrote" render spot_udim.obj --levels 3 --level 0 --normal-map 'u0.<UDIM>.png' --size 320x320 -o umapped.png
cmp -s umapped.png plain.png && bad "the UDIM maps did not change the render" || ok
cmpout=$("$T" --compare fine.png umapped.png plain.png 2>&1)
echo "spot_udim: $cmpout"
m=$(sed -nE 's/.*vs fine\.png: mean ([0-9.]+)\/255.*/\1/p' <<<"$cmpout")
if [ -n "$m" ] && awk -v m="$m" -v p="$p" 'BEGIN { exit !(m < p) }'; then ok; else bad "spot_udim mapped ($m) not closer to level 3 than plain ($p)"; fi

# UDIM glTF: one primitive and material per used tile, UVs moved into
# [0,1], each tile's image its normalTexture; GLB (embedded) and .gltf
# (URIs to the tile PNGs) validator-clean.
run 0 "normal map" convert spot_udim.obj udim.glb --levels 3 --level 0 --normal-map 'u0.<UDIM>.png'
if node "$R/tests/cli/gltf_validate.js" udim.glb >val.txt 2>&1 && grep -q ': 0 errors' val.txt; then ok; else bad "validator on udim.glb: $(cat val.txt)"; fi
cat val.txt
json=$(node -e '
const b = require("fs").readFileSync(process.argv[1]); const n = b.readUInt32LE(12);
const j = JSON.parse(b.slice(20, 20 + n).toString());
const uv = j.meshes[0].primitives.map(p => j.accessors[p.attributes.TEXCOORD_0]);
console.log(j.meshes[0].primitives.length, j.materials.length, j.images.length,
            j.materials.map(m => m.name).join(","), j.textures.map(t => t.source).join(","));' udim.glb 2>&1)
echo "udim.glb: primitives materials images: $json"
[ "$json" = "4 4 4 strata.1001,strata.1002,strata.1011,strata.1012 0,1,2,3" ] && ok || bad "udim.glb: $json"
run 0 "normal map" convert spot_udim.obj udim.gltf --levels 3 --level 0 --normal-map 'u0.<UDIM>.png'
if node "$R/tests/cli/gltf_validate.js" udim.gltf >val.txt 2>&1 && grep -q ': 0 errors' val.txt; then ok; else bad "validator on udim.gltf: $(cat val.txt)"; fi
for n in 1001 1002 1011 1012; do grep -q "\"u0.$n.png\"" udim.gltf && ok || bad "udim.gltf does not reference u0.$n.png"; done
# UVs in [0,1] give or take spot's overshoot (u down to -0.052).
uvr=$(node -e '
const b = require("fs").readFileSync(process.argv[1]); const n = b.readUInt32LE(12);
const j = JSON.parse(b.slice(20, 20 + n).toString()); const bin = b.slice(20 + n + 8);
const a = j.accessors[j.meshes[0].primitives[0].attributes.TEXCOORD_0], v = j.bufferViews[a.bufferView];
const f = new Float32Array(bin.buffer.slice(bin.byteOffset + v.byteOffset, bin.byteOffset + v.byteOffset + v.byteLength));
console.log(Math.min(...f) > -0.1 && Math.max(...f) < 1.1 ? "in" : "out " + Math.min(...f) + " " + Math.max(...f));' udim.glb 2>&1)
[ "$uvr" = in ] && ok || bad "udim.glb UVs not moved into [0,1]: $uvr"

rm u0.1012.png
run 1 "u0\.1012\.png" convert spot_udim.obj x.glb --levels 1 --level 0 --normal-map 'u0.<UDIM>.png'
run 1 "u0\.1012\.png" render spot_udim.obj --levels 1 --level 0 --normal-map 'u0.<UDIM>.png' --size 64x64 -o x.png
# --udim off: the four tiles wrapped into one map, as many texels as spot's own.
run 0 "faces at home in 4 UV tiles wrapped into one map" bake spot_udim.obj --levels 3 --base-level 0 --normal-map w.png --size 512 --udim off
a=$("$EXE" bake "$SPOT" --levels 3 --base-level 0 --normal-map s512.png --size 512 2>&1 | grep -oE '[0-9]+ texels baked')
b=$("$EXE" bake spot_udim.obj --levels 3 --base-level 0 --normal-map w.png --size 512 --udim off 2>&1 | grep -oE '[0-9]+ texels baked')
echo "texels: spot $a, spot_udim --udim off $b"
[ -n "$a" ] && [ "$a" = "$b" ] && ok || bad "--udim off baked $b, spot $a"
# --udim on: spot has faces at home in tile (-1, 0), which has no number.
run 1 "face [0-9]+ of level 0 lies in UV tile \(-1, 0\), which has no UDIM number" bake "$SPOT" --levels 1 --base-level 0 --normal-map x.png --size 64 --udim on
[ -e x.png ] && bad "--udim on refusal wrote x.png" || ok

echo "cli_bake_udim: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
