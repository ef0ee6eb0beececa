#!/usr/bin/env bash
# The interest box on a progressive hierarchy (core/adapt/adapt.h,
# "Progressive hierarchies"): strata adapt writes a surface of the input's
# topology with more faces than the base level and fewer than the finest,
# the base level exactly for a box far away, --triangulate the same mesh;
# strata render --box draws it; strata convert --box saves the box in the
# session's adaptive state and a second save is byte-identical.
# Usage: cli_progressive_box.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 D=$2 B=$4
W=$B/cli_progressive_box
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
row() { "$S" info "$1" | awk -v l="$2" '$1 == l { print $4, $6, $5 }'; } # faces euler holes of level l
IN=$D/triangle/boot.obj
"$S" rebuild "$IN" --method progressive --target-faces 400 -o "$W/boot.strata" > /dev/null
top=$("$S" info "$W/boot.strata" | awk '$1 ~ /^[0-9]+$/ { t = $1 } END { print t }')
read -r fin ein hin <<< "$(row "$IN" 0)"
read -r f2 _ _ <<< "$(row "$W/boot.strata" 2)"
BOX=-0.2,-0.1,-0.1,-0.08,0.05,0.1
if "$S" adapt "$W/boot.strata" --base-level 2 --max-level "$top" --box "$BOX" -o "$W/box.obj" > "$W/box.out"; then
    ok "adapt: $(cat "$W/box.out")"
else bad "adapt failed"; fi
read -r fa ea ha <<< "$(row "$W/box.obj" 0)"
if [ "$fa" -gt "$f2" ] && [ "$fa" -lt "$fin" ]; then ok "$f2 < $fa < $fin faces"; else bad "faces $f2 / $fa / $fin"; fi
if [ "$ea" = "$ein" ] && [ "$ha" = "$hin" ]; then ok "Euler $ea and $ha holes as the input"; else bad "Euler $ea holes $ha, input $ein $hin"; fi
"$S" adapt "$W/boot.strata" --base-level 2 --max-level "$top" --box "$BOX" --triangulate -o "$W/tri.obj" > /dev/null
read -r ft et _ <<< "$(row "$W/tri.obj" 0)"
if [ "$ft" = "$fa" ] && [ "$et" = "$ea" ]; then ok "--triangulate: the same $ft triangles"; else bad "--triangulate: $ft faces, Euler $et"; fi
"$S" adapt "$W/boot.strata" --base-level 2 --max-level "$top" --box 10,10,10,11,11,11 -o "$W/far.obj" > /dev/null
"$S" convert "$W/boot.strata" "$W/l2.obj" --level 2 > /dev/null
if cmp -s <(grep '^f' "$W/far.obj" | wc -l) <(grep '^f' "$W/l2.obj" | wc -l) && [ "$(row "$W/far.obj" 0)" = "$(row "$W/l2.obj" 0)" ]; then
    ok "a box far away: level 2 ($(row "$W/far.obj" 0 | cut -d' ' -f1) faces)"
else bad "a box far away: $(row "$W/far.obj" 0) vs level 2 $(row "$W/l2.obj" 0)"; fi
if "$S" render "$W/boot.strata" --box "$BOX" --base-level 2 --max-level "$top" --size 160x120 -o "$W/box.png" > "$W/render.out" \
   && grep -q "$fa faces" "$W/render.out"; then ok "render: $(cat "$W/render.out")"
else bad "render: $(cat "$W/render.out" 2>/dev/null)"; fi
if "$S" convert "$W/boot.strata" "$W/boxed.strata" --box "$BOX" --base-level 2 --max-level "$top" > /dev/null \
   && "$S" convert "$W/boxed.strata" "$W/boxed2.strata" > /dev/null && cmp -s "$W/boxed.strata" "$W/boxed2.strata"; then
    ok "a session with the box: load -> save byte-identical"
else bad "a session with the box does not round-trip"; fi
if "$S" convert "$W/boxed.strata" "$W/boxed.obj" > /dev/null && [ "$(row "$W/boxed.obj" 0)" = "$(row "$W/box.obj" 0)" ]; then
    ok "the saved box shows the same mesh"
else bad "the saved box shows $(row "$W/boxed.obj" 0), adapt $(row "$W/box.obj" 0)"; fi
echo "$((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
