#!/usr/bin/env bash
# strata adapt: the adaptive mesh of an interest box is written, re-loads as
# a closed manifold with the same Euler characteristic, has more faces than
# the base level and fewer than the regular maximum level; bad options fail.
# Usage: cli_adapt.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 D=$2 A=$3 B=$4
W=$B/cli_adapt
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
faces_of() { "$S" info "$1" | awk '$1 == "0" { print $4 }'; }
euler_of() { "$S" info "$1" | awk '$1 == "0" { print $6 }'; }
check() { # label input scheme box max
    local out=$W/$1.obj
    if "$S" adapt "$2" --scheme "$3" --base-level 0 --max-level "$5" --box "$4" -o "$out" >/dev/null; then ok "$1 written"; else bad "$1 adapt failed"; return; fi
    local f0 fa fm
    f0=$(faces_of "$2"); fa=$(faces_of "$out")
    "$S" subdivide "$2" --scheme "$3" --levels "$5" -o "$W/$1_regular.obj"
    fm=$(faces_of "$W/$1_regular.obj")
    if [ "$fa" -gt "$f0" ] && [ "$fa" -lt "$fm" ]; then ok "$1: $f0 < $fa < $fm faces"; else bad "$1: faces $f0 / $fa / $fm"; fi
    if [ "$(euler_of "$out")" = "$(euler_of "$2")" ]; then ok "$1: euler $(euler_of "$out")"; else bad "$1: euler changed"; fi
    "$S" adapt "$2" --scheme "$3" --max-level "$5" --box "$4" --triangulate -o "$W/$1_tri.obj" >/dev/null
    if [ "$(euler_of "$W/$1_tri.obj")" = "$(euler_of "$2")" ]; then ok "$1: triangulated mesh closed, same euler"; else bad "$1: triangulation euler"; fi
}
check spot_cc "$D/catmull_clark/spot_quadrangulated.obj" catmull-clark 0.2,0,0,0.6,0.6,0.6 3
check cube_cc "$A/cube.obj" catmull-clark 0.8,0.8,0.8,1.2,1.2,1.2 4
check ico_loop "$D/triangle/sphere_ico.obj" loop 0.5,-1,-1,2,1,1 3
check ico_butterfly "$D/triangle/sphere_ico.obj" butterfly 0.5,-1,-1,2,1,1 3
check ico_sqrt3 "$D/triangle/sphere_ico.obj" sqrt3 0.5,-1,-1,2,1,1 4
check torus_ds "$A/torus.obj" doo-sabin 0,0,0,1,1,1 3
# Adaptive access (marker bits on the regular levels) shows the same mesh.
# (Boxes off the model's symmetry plane: a face exactly touching a box side
# may be decided either way by rounding, differently in the two builds.)
for c in "spot $D/catmull_clark/spot_quadrangulated.obj catmull-clark 0.013,0.011,0.017,0.5,0.5,0.5 4" \
         "ico $D/triangle/sphere_ico.obj loop 0.31,-1,-1,2,1,1 3"; do
    set -- $c
    "$S" adapt "$2" --scheme "$3" --base-level 1 --max-level "$5" --box "$4" -o "$W/$1_ad.obj" | tail -n 1 | cut -d' ' -f2- > "$W/$1_ad.txt"
    "$S" adapt "$2" --scheme "$3" --base-level 1 --max-level "$5" --box "$4" --access -o "$W/$1_ac.obj" | tail -n 1 | cut -d' ' -f2- > "$W/$1_ac.txt"
    if [ -s "$W/$1_ad.txt" ] && cmp -s "$W/$1_ad.txt" "$W/$1_ac.txt"; then ok "$1: --access gives the adaptive mesh ($(cat "$W/$1_ac.txt"))"
    else bad "$1: --access $(cat "$W/$1_ac.txt") vs adaptive $(cat "$W/$1_ad.txt")"; fi
    diff_tool="$(dirname "$S")/tests/oracles/pointset_diff"
    if [ -x "$diff_tool" ]; then
        if "$diff_tool" "$W/$1_ad.obj" "$W/$1_ac.obj" --tol 1e-9 >/dev/null; then ok "$1: same points (pointset_diff)"; else bad "$1: points differ"; fi
    fi
done
for args in "--box 1,2,3" "--box a,b,c,d,e,f" "--base-level 4 --max-level 2 --box 0,0,0,1,1,1"; do
    # shellcheck disable=SC2086
    if "$S" adapt "$A/cube.obj" $args -o "$W/bad.obj" 2>/dev/null; then bad "accepted: $args"; else ok "refused: $args"; fi
done
# Adaptive display: strata render with the same box options, deterministic.
for k in 1 2; do
    "$S" render "$D/triangle/sphere_ico.obj" --scheme loop --box 0.5,-1,-1,2,1,1 --max-level 3 --mode wire --size 160x120 -o "$W/ico_box_$k.png" >/dev/null
done
if [ -s "$W/ico_box_1.png" ] && cmp -s "$W/ico_box_1.png" "$W/ico_box_2.png"; then ok "render --box: PNG written, identical on rerun"; else bad "render --box output"; fi
for k in 1 2; do
    "$S" render "$A/torus.obj" --scheme doo-sabin --box 0.2,-2,-2,2,2,2 --max-level 3 --mode flat --size 160x120 -o "$W/torus_ds_box_$k.png" >/dev/null
done
if [ -s "$W/torus_ds_box_1.png" ] && cmp -s "$W/torus_ds_box_1.png" "$W/torus_ds_box_2.png"; then ok "render --box doo-sabin: PNG written, identical on rerun"; else bad "render --box doo-sabin output"; fi
if "$S" render "$A/cube.obj" --box 0,0,0,1,1,1 --levels 2 -o "$W/bad.png" 2>/dev/null; then bad "render --box with --levels accepted"; else ok "render: --box with --levels refused"; fi
if "$S" render "$A/cube.obj" --box 0,0,0,1,1 -o "$W/bad.png" 2>/dev/null; then bad "render: short --box accepted"; else ok "render: short --box refused"; fi
echo "$((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
