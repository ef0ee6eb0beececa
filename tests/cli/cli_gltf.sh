#!/usr/bin/env bash
# glTF through the CLI: meshes of several kinds (quads, n-gons fanned into
# triangles, triangles, an adaptive mesh, an open mesh, >65535 vertices for
# u32 indices) are exported as .gltf and .glb and every file must pass the
# Khronos glTF Validator with no errors; exports load back (same triangles,
# same Euler characteristic); broken files are refused with a message.
# Normal-mapped exports (convert --normal-map) must also have no warnings.
# Needs node and gltf-validator (bash scripts/setup_node.sh): without them
# this test FAILS, it does not skip.
# Usage: cli_gltf.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 D=$2 A=$3 B=$4
R="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
W=$B/cli_gltf
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }

VALIDATOR="${GLTF_VALIDATOR:-$R/build/node/node_modules/gltf-validator}"
if ! command -v node >/dev/null 2>&1; then
    echo "FAIL: node is not installed; the glTF Validator cannot run (bash scripts/setup.sh, then bash scripts/setup_node.sh)"
    exit 1
fi
if ! node -e 'require(process.argv[1])' "$VALIDATOR" 2>/dev/null; then
    echo "FAIL: gltf-validator not found at $VALIDATOR; run: bash scripts/setup_node.sh"
    exit 1
fi
export GLTF_VALIDATOR="$VALIDATOR"

row0() { "$S" info "$1" | awk '$1 == "0" { print $'"$2"' }'; }   # level-0 column
files=()
export_one() { # label input scheme levels ext
    local out=$W/$1.$5
    if "$S" subdivide "$2" --scheme "$3" --levels "$4" -o "$out" 2>"$W/$1.err"; then
        ok "$1: wrote $(basename "$out")"; files+=("$out")
    else
        bad "$1: export failed: $(cat "$W/$1.err")"
    fi
}
export_one cube_cc2 "$A/cube.obj" catmull-clark 2 gltf
export_one cube_cc2 "$A/cube.obj" catmull-clark 2 glb
export_one cube_cc7 "$A/cube.obj" catmull-clark 7 glb          # 98306 vertices: u32 indices
export_one spot_cc1 "$D/catmull_clark/spot_quadrangulated.obj" catmull-clark 1 glb
export_one dodeca "$D/catmull_clark/dodecahedron_poly.obj" catmull-clark 0 gltf   # pentagons
export_one cube_ds2 "$A/cube.obj" doo-sabin 2 gltf             # n-gons
export_one ico_loop2 "$D/triangle/sphere_ico.obj" loop 2 glb
export_one open_cc1 "$A/open.obj" catmull-clark 1 gltf         # with boundary
export_one ngon "$A/ngon.obj" catmull-clark 0 glb
# Hole faces (t hole) are left out; the vertices only they use stay.
{ cat "$A/cube.obj"; echo "t hole 2/0/0 0 2"; } >"$W/cube_hole.obj"
export_one cube_hole_cc2 "$W/cube_hole.obj" catmull-clark 2 glb
if "$S" adapt "$D/catmull_clark/spot_quadrangulated.obj" --max-level 3 --box 0.2,0,0,0.6,0.6,0.6 -o "$W/spot_adapt.glb" >/dev/null 2>"$W/adapt.err"; then
    ok "spot_adapt: wrote spot_adapt.glb"; files+=("$W/spot_adapt.glb")
else
    bad "spot_adapt: export failed: $(cat "$W/adapt.err")"
fi

# The validator, on every file written.
if node "$R/tests/cli/gltf_validate.js" "${files[@]}" >"$W/validator.txt" 2>&1; then
    ok "glTF Validator: ${#files[@]} files, no errors"
else
    bad "glTF Validator found errors"
fi
cat "$W/validator.txt"

# Loading back: a level-2 Catmull-Clark cube is 96 quads, 192 triangles.
for f in cube_cc2.gltf cube_cc2.glb; do
    faces=$(row0 "$W/$f" 4 || true); euler=$(row0 "$W/$f" 6 || true)
    if [ "$faces" = 192 ] && [ "$euler" = 2 ]; then ok "$f loads back: $faces triangles, euler $euler"; else bad "$f loads back as faces=$faces euler=$euler"; fi
done
e_in=$(row0 "$D/catmull_clark/spot_quadrangulated.obj" 6); e_out=$(row0 "$W/spot_adapt.glb" 6 || true)
if [ "$e_in" = "$e_out" ]; then ok "spot_adapt.glb loads back, euler $e_out"; else bad "spot_adapt.glb euler $e_out, input $e_in"; fi
if "$S" subdivide "$W/ico_loop2.glb" --scheme loop --levels 1 -o "$W/ico_again.obj" 2>"$W/again.err"; then ok "glb input subdivides again"; else bad "glb input: $(cat "$W/again.err")"; fi
# UVs (TEXCOORD_0) go out and come back: the sphere's level-2 UVs, written
# to .glb (vertices split along seams) and read back, give as many texture
# coordinates as the OBJ of the same level.
"$S" subdivide "$D/triangle/sphere_ico.obj" --scheme loop --levels 2 -o "$W/ico2.obj" 2>/dev/null
"$S" subdivide "$W/ico_loop2.glb" --scheme loop --levels 0 -o "$W/ico_back.obj" 2>/dev/null
n_obj=$(grep -c '^vt' "$W/ico2.obj" || true); n_back=$(grep -c '^vt' "$W/ico_back.obj" || true)
if [ "${n_obj:-0}" -gt 0 ] && [ "$n_obj" = "$n_back" ] && grep -q '^f [0-9]*/[0-9]' "$W/ico_back.obj"; then
    ok "TEXCOORD_0 round trip: $n_back texture coordinates, as the OBJ's $n_obj"
else
    bad "TEXCOORD_0 round trip: $n_back texture coordinates back, the OBJ has $n_obj"
fi

# Normal-mapped export (convert --normal-map): the icosphere's level 1 with
# the map baked on its own UVs, and the cube's level 1 with the --auto-uv
# atlas.  The validator must report no errors and no warnings (none about
# tangents); the JSON has TEXCOORD_0, TANGENT (w = ±1, orthogonal to NORMAL)
# and a material whose normalTexture is the PNG: embedded in the .glb,
# a relative URI that reaches the file from the .gltf.
mapped=()
mkdir -p "$W/maps" "$W/sub"
"$S" convert "$D/triangle/sphere_ico.obj" "$W/ico.strata" --scheme loop --levels 2 >/dev/null
"$S" convert "$A/cube.obj" "$W/cube.strata" --levels 3 >/dev/null
if "$S" bake "$W/ico.strata" --base-level 1 --normal-map "$W/maps/ico_n.png" --size 128 >/dev/null 2>"$W/bake.err" &&
   "$S" bake "$W/cube.strata" --base-level 1 --normal-map "$W/maps/cube_n.png" --size 64 --auto-uv >/dev/null 2>>"$W/bake.err"; then
    ok "normal maps baked"
else
    bad "bake failed: $(cat "$W/bake.err")"
fi
for spec in "ico.strata maps/ico_n.png ico_mapped.glb" "ico.strata maps/ico_n.png sub/ico_mapped.gltf" "cube.strata maps/cube_n.png cube_mapped.glb"; do
    set -- $spec
    if "$S" convert "$W/$1" "$W/$3" --level 1 --normal-map "$W/$2" >"$W/mapped.out" 2>&1 &&
       grep -q "UVs, tangents and a material with normal map" "$W/mapped.out"; then
        ok "$3: written"; mapped+=("$W/$3")
    else
        bad "$3: $(cat "$W/mapped.out")"
    fi
done
if node "$R/tests/cli/gltf_validate.js" "${mapped[@]}" >"$W/validator_mapped.txt" 2>&1 &&
   [ "$(grep -c ': 0 errors, 0 warnings' "$W/validator_mapped.txt")" = "${#mapped[@]}" ]; then
    ok "glTF Validator: ${#mapped[@]} normal-mapped files, no errors, no warnings"
else
    bad "glTF Validator on the normal-mapped files"
fi
cat "$W/validator_mapped.txt"
check_mapped() { # FILE: prints a line starting with "ok" or "bad"
    node - "$1" <<'JS'
const fs = require('fs'), path = require('path');
const file = process.argv[2], bytes = fs.readFileSync(file);
let j, bin;
if (bytes.toString('latin1', 0, 4) === 'glTF') {
  const n = bytes.readUInt32LE(12);
  j = JSON.parse(bytes.toString('utf8', 20, 20 + n));
  bin = bytes.subarray(20 + n + 8);
} else {
  j = JSON.parse(bytes.toString('utf8'));
  bin = fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(j.buffers[0].uri)));
}
const p = j.meshes[0].primitives[0], a = p.attributes;
const get = (i, k) => { const acc = j.accessors[i], v = j.bufferViews[acc.bufferView];
  const off = (v.byteOffset || 0) + (acc.byteOffset || 0);
  return Array.from({ length: acc.count * k }, (_, q) => bin.readFloatLE(off + 4 * q)); };
if (a.TANGENT === undefined || a.TEXCOORD_0 === undefined || a.NORMAL === undefined) { console.log('bad: attributes ' + Object.keys(a)); process.exit(0); }
const t = get(a.TANGENT, 4), n = get(a.NORMAL, 3);
let worst = 0, signs = 0;
for (let i = 0; i < t.length / 4; i++) {
  if (Math.abs(t[4 * i + 3]) !== 1) signs++;
  worst = Math.max(worst, Math.abs(t[4 * i] * n[3 * i] + t[4 * i + 1] * n[3 * i + 1] + t[4 * i + 2] * n[3 * i + 2]));
}
const m = j.materials && j.materials[p.material], tex = m && m.normalTexture && j.textures[m.normalTexture.index];
const img = tex && j.images[tex.source];
let where = 'none';
if (img && img.bufferView !== undefined && img.mimeType === 'image/png') {
  const v = j.bufferViews[img.bufferView];
  if (bin.toString('latin1', (v.byteOffset || 0) + 1, (v.byteOffset || 0) + 4) === 'PNG') where = 'embedded';
} else if (img && img.uri && fs.existsSync(path.join(path.dirname(file), decodeURIComponent(img.uri)))) where = 'uri ' + img.uri;
if (signs || worst > 1e-4 || where === 'none') console.log(`bad: ${signs} tangent signs not ±1, |t·n| up to ${worst}, normal map ${where}`);
else console.log(`ok: ${t.length / 4} vertices with TANGENT (|t·n| <= ${worst.toExponential(1)}), normal map ${where}`);
JS
}
for f in "${mapped[@]}"; do
    r=$(check_mapped "$f" 2>&1 || true)
    case $r in ok*) ok "$(basename "$f"): ${r#ok: }" ;; *) bad "$(basename "$f"): $r" ;; esac
done
# Refusals: glTF only, a PNG that exists, nothing written.
if "$S" convert "$W/ico.strata" "$W/x.obj" --level 1 --normal-map "$W/maps/ico_n.png" 2>"$W/x.err"; then bad "--normal-map to .obj accepted"
elif grep -q "glTF output" "$W/x.err" && [ ! -e "$W/x.obj" ]; then ok "--normal-map to .obj refused: $(cat "$W/x.err")"; else bad "--normal-map to .obj: $(cat "$W/x.err")"; fi
printf 'not a png' >"$W/fake.png"
for m in missing.png fake.png; do
    if "$S" convert "$W/ico.strata" "$W/x.glb" --level 1 --normal-map "$W/$m" 2>"$W/x.err"; then bad "$m accepted"
    elif grep -q "$m" "$W/x.err" && ! compgen -G "$W/x.glb*" >/dev/null; then ok "$m refused: $(cat "$W/x.err")"; else bad "$m: $(cat "$W/x.err")"; fi
done

# Bad files: refused with a message naming the file, non-zero exit.
head -c 100 "$W/cube_cc2.glb" >"$W/truncated.glb"
printf 'not a gltf file at all' >"$W/garbage.gltf"
sed 's/"uri": "cube_cc2.bin"/"uri": "nobin.bin"/' "$W/cube_cc2.gltf" >"$W/nobin.gltf"
for f in truncated.glb garbage.gltf nobin.gltf missing.glb; do
    if "$S" info "$W/$f" >/dev/null 2>"$W/bad.err"; then
        bad "$f accepted"
    elif grep -q "$f" "$W/bad.err"; then
        ok "$f refused: $(head -n 1 "$W/bad.err")"
    else
        bad "$f refused without naming the file: $(cat "$W/bad.err")"
    fi
done

echo "$((n - fail))/$n checks passed"
[ "$fail" -eq 0 ]
