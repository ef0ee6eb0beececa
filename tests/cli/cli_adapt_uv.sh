#!/usr/bin/env bash
# Adaptive meshes carry UVs through the CLI (core/adapt/adapt_uv.c):
# `strata adapt` writes OBJ vt with f v/t(/n) on every corner, and the OBJ
# re-reads with the same texture coordinates per corner; glTF gets
# TEXCOORD_0 and passes the Khronos validator; PLY splits vertices along
# seams; --access carries the regular levels' UVs; `strata render --box --mode uv` draws the adaptive checker; √3
# and Doo-Sabin carry UVs too (Doo-Sabin's box over everything: the vt of
# subdivide, bit for bit; --triangulate and render --box --mode uv as well);
# meshes without vt say why nothing is carried (exit 0 / exit 1 for
# render), without crashing.
# Usage: cli_adapt_uv.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 D=$2 A=$3 B=$4
R="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
W=$B/cli_adapt_uv
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }

BLUB=$D/catmull_clark/blub_control_mesh.obj
ICO=$D/triangle/sphere_ico.obj
box() { echo --box 0,0,0,0.5,0.5,0.5; }

# corners in f lines, and corners with a texture coordinate (v/t or v/t/n)
corners() { awk '$1 == "f" { for (i = 2; i <= NF; i++) { c++; if ($i ~ /^[0-9]+\/[0-9]+/) t++ } } END { print c + 0, t + 0 }' "$1"; }
# the texture coordinate of every corner, in order (to compare two OBJs)
corner_uvs() {
    awk '$1 == "vt" { vt[++k] = $2 " " $3 } $1 == "f" { for (i = 2; i <= NF; i++) { split($i, p, "/"); print vt[p[2]] } }' "$1"
}

for scheme in catmull-clark quad-triangle loop butterfly; do
    in=$BLUB
    case $scheme in loop | butterfly) in=$ICO ;; esac
    out=$W/$scheme.obj
    if "$S" adapt "$in" --scheme "$scheme" --max-level 3 $(box) -o "$out" >"$W/$scheme.log" 2>&1; then
        read -r c t < <(corners "$out")
        nvt=$(grep -c '^vt ' "$out" || true)
        if [ "$c" -gt 0 ] && [ "$c" = "$t" ] && [ "$nvt" -gt 0 ]; then ok "$scheme: adapt wrote $nvt vt, $t of $c corners with one"
        else bad "$scheme: $t of $c corners have a vt ($nvt vt lines)"; fi
        grep -q "do not carry\|written without" "$W/$scheme.log" && bad "$scheme: a note says UVs are dropped: $(cat "$W/$scheme.log")"
        # re-read: the same UV per corner
        if "$S" convert "$out" "$W/$scheme.again.obj" >/dev/null 2>&1 &&
            cmp -s <(corner_uvs "$out") <(corner_uvs "$W/$scheme.again.obj"); then
            ok "$scheme: the OBJ re-reads with the same UV on every corner"
        else
            bad "$scheme: the re-read OBJ's UVs differ"
        fi
    else
        bad "$scheme: adapt failed: $(cat "$W/$scheme.log")"
    fi
done

# --access reads the same mesh off the regular levels, with their UVs
if "$S" adapt "$BLUB" --access --max-level 3 $(box) -o "$W/access.obj" >"$W/access.log" 2>&1; then
    read -r c t < <(corners "$W/access.obj")
    if [ "$c" -gt 0 ] && [ "$c" = "$t" ]; then ok "--access: $t of $c corners with a vt"; else bad "--access: $t of $c corners with a vt"; fi
else
    bad "--access failed: $(cat "$W/access.log")"
fi

# The box over everything gives the regular level's UVs: the same texture
# coordinates (as a sorted set of vt lines) as subdivide (quad/triangle and
# Loop are bit-exact there, test_adapt_uv.c).
for scheme in quad-triangle loop; do
    in=$BLUB
    [ $scheme = loop ] && in=$ICO
    "$S" adapt "$in" --scheme $scheme --max-level 2 --box -1e9,-1e9,-1e9,1e9,1e9,1e9 -o "$W/all_$scheme.obj" >/dev/null 2>&1
    "$S" subdivide "$in" --scheme $scheme --levels 2 -o "$W/reg_$scheme.obj" >/dev/null 2>&1
    if [ -s "$W/all_$scheme.obj" ] && cmp -s <(grep '^vt ' "$W/all_$scheme.obj" | sort) <(grep '^vt ' "$W/reg_$scheme.obj" | sort); then
        ok "$scheme: box over everything: the vt of subdivide --levels 2 ($(grep -c '^vt ' "$W/reg_$scheme.obj"))"
    else
        bad "$scheme: box over everything: vt differ from subdivide --levels 2"
    fi
done

# glTF: TEXCOORD_0, validator clean
VALIDATOR="${GLTF_VALIDATOR:-$R/build/node/node_modules/gltf-validator}"
"$S" adapt "$BLUB" --max-level 3 $(box) -o "$W/blub.gltf" >/dev/null 2>&1 || bad "adapt to .gltf failed"
"$S" adapt "$BLUB" --max-level 3 $(box) -o "$W/blub.glb" >/dev/null 2>&1 || bad "adapt to .glb failed"
if grep -q TEXCOORD_0 "$W/blub.gltf"; then ok "glTF: TEXCOORD_0 written"; else bad "glTF: no TEXCOORD_0"; fi
if ! command -v node >/dev/null 2>&1 || ! node -e 'require(process.argv[1])' "$VALIDATOR" 2>/dev/null; then
    bad "gltf-validator not found at $VALIDATOR (bash scripts/setup_node.sh)"
elif GLTF_VALIDATOR="$VALIDATOR" node "$R/tests/cli/gltf_validate.js" "$W/blub.gltf" "$W/blub.glb" >"$W/validator.txt" 2>&1; then
    ok "glTF: the validator reports no error ($(grep -c . "$W/validator.txt") lines)"
else
    bad "glTF: validator: $(cat "$W/validator.txt")"
fi

# PLY: vertices split along seams, one UV each
if "$S" adapt "$BLUB" --max-level 2 $(box) -o "$W/blub.ply" >/dev/null 2>&1 &&
    head -c 600 "$W/blub.ply" | grep -aq "property .* [us]\b\|property .*texture_u\|property .* s$"; then
    ok "PLY: per-vertex UVs (seams split)"
else
    bad "PLY: no UV properties: $(head -c 400 "$W/blub.ply" | tr -d '\0' | grep -a property | tr '\n' ' ')"
fi

# render --box --mode uv
if "$S" render "$BLUB" $(box) --max-level 3 --mode uv --view iso --size 320x240 -o "$W/uv.png" >"$W/render.log" 2>&1 && [ -s "$W/uv.png" ]; then
    ok "render --box --mode uv: $(cat "$W/render.log")"
else
    bad "render --box --mode uv failed: $(cat "$W/render.log")"
fi
set +e
"$S" render "$A/cube.obj" $(box) --mode uv -o "$W/nouv.png" >/dev/null 2>"$W/nouv.err"
rc=$?
set -e
if [ $rc = 1 ] && grep -q "no UVs" "$W/nouv.err" && [ ! -e "$W/nouv.png" ]; then ok "render --box --mode uv without vt: exit 1: $(cat "$W/nouv.err")"
else bad "render --box --mode uv without vt: exit $rc: $(cat "$W/nouv.err")"; fi

# √3 above level 0: vt on every corner, inside level 0's range [0, 1], no note, exit 0
if "$S" adapt "$ICO" --scheme sqrt3 --max-level 2 $(box) -o "$W/sqrt3.obj" >/dev/null 2>"$W/sqrt3.err" &&
    ! grep -q "note" "$W/sqrt3.err" && grep -q '^vt ' "$W/sqrt3.obj" &&
    awk '/^vt /{if($2<0||$2>1||$3<0||$3>1)bad++} /^f /{for(i=2;i<=NF;i++)if($i!~/^[0-9]+\/[0-9]+/)bad++} END{exit bad>0}' "$W/sqrt3.obj"; then
    ok "sqrt3: $(grep -c '^vt ' "$W/sqrt3.obj") vt, every corner with one, all in [0, 1]"
else
    bad "sqrt3: $(cat "$W/sqrt3.err")"
fi

# Doo-Sabin above level 0 (the dual encoding): vt on every corner, inside
# level 0's range, no note, the OBJ re-reads with the same UVs; the box over
# everything writes the vt of subdivide --levels 2 (bit for bit,
# test_adapt_uv.c); --triangulate and render --box --mode uv carry them too.
urange() { awk '$1 == "vt" { print $2; print $3 }' "$1" | sort -g | sed -n '1p;$p' | paste -sd ' '; }
read -r ulo uhi < <(urange "$BLUB")
if "$S" adapt "$BLUB" --scheme doo-sabin --max-level 3 $(box) -o "$W/ds.obj" >/dev/null 2>"$W/ds.err" &&
    ! grep -q "note" "$W/ds.err" && grep -q '^vt ' "$W/ds.obj" &&
    awk -v lo="$ulo" -v hi="$uhi" '/^vt /{if($2<lo||$2>hi||$3<lo||$3>hi)bad++} /^f /{for(i=2;i<=NF;i++)if($i!~/^[0-9]+\/[0-9]+/)bad++} END{exit bad>0}' "$W/ds.obj"; then
    read -r c t < <(corners "$W/ds.obj")
    ok "doo-sabin: $(grep -c '^vt ' "$W/ds.obj") vt, $t of $c corners with one, all in level 0's [$ulo, $uhi]"
else
    bad "doo-sabin: $(cat "$W/ds.err")"
fi
if "$S" convert "$W/ds.obj" "$W/ds.again.obj" >/dev/null 2>&1 && cmp -s <(corner_uvs "$W/ds.obj") <(corner_uvs "$W/ds.again.obj"); then
    ok "doo-sabin: the OBJ re-reads with the same UV on every corner"
else
    bad "doo-sabin: the re-read OBJ's UVs differ"
fi
"$S" adapt "$BLUB" --scheme doo-sabin --max-level 2 --box -1e9,-1e9,-1e9,1e9,1e9,1e9 -o "$W/all_ds.obj" >/dev/null 2>&1
"$S" subdivide "$BLUB" --scheme doo-sabin --levels 2 -o "$W/reg_ds.obj" >/dev/null 2>&1
if [ -s "$W/all_ds.obj" ] && grep -q '^vt ' "$W/reg_ds.obj" &&
    cmp -s <(grep '^vt ' "$W/all_ds.obj" | sort) <(grep '^vt ' "$W/reg_ds.obj" | sort); then
    ok "doo-sabin: box over everything: the vt of subdivide --levels 2 ($(grep -c '^vt ' "$W/reg_ds.obj"))"
else
    bad "doo-sabin: box over everything: vt differ from subdivide --levels 2"
fi
if "$S" adapt "$BLUB" --scheme doo-sabin --max-level 3 $(box) --triangulate -o "$W/ds_tri.obj" >/dev/null 2>"$W/ds_tri.err" &&
    ! grep -q "note" "$W/ds_tri.err"; then
    read -r c t < <(corners "$W/ds_tri.obj")
    if [ "$c" -gt 0 ] && [ "$c" = "$t" ]; then ok "doo-sabin --triangulate: $t of $c corners with a vt"
    else bad "doo-sabin --triangulate: $t of $c corners with a vt"; fi
else
    bad "doo-sabin --triangulate: $(cat "$W/ds_tri.err")"
fi
if "$S" render "$BLUB" --scheme doo-sabin $(box) --max-level 3 --mode uv --view iso --size 320x240 -o "$W/ds_uv.png" \
    >"$W/ds_render.log" 2>&1 && [ -s "$W/ds_uv.png" ]; then
    ok "doo-sabin render --box --mode uv: $(cat "$W/ds_render.log")"
else
    bad "doo-sabin render --box --mode uv failed: $(cat "$W/ds_render.log")"
fi

echo "$((n - fail)) passed, $fail failed"
[ $fail = 0 ]
