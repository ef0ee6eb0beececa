#!/usr/bin/env bash
# Sessions with an HD hierarchy (chunk 'hdlv', core/io/session.h): strata
# info lists the HD levels (faces stored at each, bytes, the uniform
# count); strata convert writes the HD adaptive mesh (closed: no holes, the
# cube's Euler characteristic), an HD level made uniform (the uniform face
# count), the model's own levels, refuses a level above the HD top and a
# refinement over the memory budget (the estimate in the message, no
# file), and re-saves the session byte for byte.  The input is made by
# test_session_hd --write (a cube: model levels 0..2, HD up to 4); with
# --write-layer, a sculpt layer at HD level 4 that info lists and that
# strata deform at level 4 keeps (its active layer takes the change).
# Usage: cli_session_hd.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 B=$4
W=$B/cli_session_hd
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
row0() { "$S" info "$1" | awk '$1 == "0" { print $4, $5, $6 }'; }   # faces holes euler of a mesh

"$B/test_session_hd" --write "$W/hd.strata"
"$S" info "$W/hd.strata" > "$W/info.txt"
cat "$W/info.txt"
hd_row() { awk -v l="$1" 'f && $1 == l { print $2, $4 } /^HD hierarchy:/ { f = 1 }' "$W/info.txt"; }
if grep -q "^HD hierarchy: 5 levels (0..4), levels 0..2 the model's" "$W/info.txt"; then ok "info: HD header"; else bad "info: HD header"; fi
read -r f3 u3 <<< "$(hd_row 3)"; read -r f4 u4 <<< "$(hd_row 4)"
if [ "$u3" = 384 ] && [ "$u4" = 1536 ]; then ok "info: uniform faces 384, 1536"; else bad "info: uniform faces '$u3' '$u4'"; fi
if [ "$f3" -gt 0 ] && [ "$f3" -lt 384 ] && [ "$f4" -gt 0 ] && [ "$f4" -lt 1536 ]; then ok "info: HD faces $f3, $f4"; else bad "info: HD faces '$f3' '$f4'"; fi

# No --level: the HD adaptive mesh, more faces than the model's top, fewer
# than uniform level 4, closed.
"$S" convert "$W/hd.strata" "$W/hd.obj" > "$W/out.txt"
grep -q "HD adaptive" "$W/out.txt" && ok "convert: HD adaptive mesh" || bad "convert: $(cat "$W/out.txt")"
read -r fa ha ea <<< "$(row0 "$W/hd.obj")"
if [ "$fa" -gt 96 ] && [ "$fa" -lt 1536 ] && [ "$ha" = 0 ] && [ "$ea" = 2 ]; then ok "HD mesh: $fa faces, closed, euler 2"; else bad "HD mesh: faces $fa holes $ha euler $ea"; fi

# --level 4 (above the model, the HD top): uniform with the HD details.
"$S" convert "$W/hd.strata" "$W/hd4.obj" --level 4 > /dev/null
read -r f h e <<< "$(row0 "$W/hd4.obj")"
if [ "$f" = 1536 ] && [ "$h" = 0 ] && [ "$e" = 2 ]; then ok "HD level 4: 1536 faces, closed"; else bad "HD level 4: $f $h $e"; fi
# Its surface is the plain subdivision of the model's level 0 except near
# the box where the details were set: some vertices moved, not all.
verts() { awk '/^v / { printf "%.5f %.5f %.5f\n", $2, $3, $4 }' "$1" | sort; }
"$S" convert "$W/hd.strata" "$W/cage.obj" --level 0 --no-normals > /dev/null
"$S" subdivide "$W/cage.obj" --levels 4 -o "$W/plain4.obj" > /dev/null
moved=$(comm -13 <(verts "$W/plain4.obj") <(verts "$W/hd4.obj") | wc -l)
if [ "$moved" -gt 0 ] && [ "$moved" -lt 1538 ]; then ok "HD level 4: $moved of 1538 vertices off the plain subdivision"; else bad "HD level 4: $moved vertices moved"; fi
# --level up to the model's top: the model's level.
"$S" convert "$W/hd.strata" "$W/m2.obj" --level 2 > /dev/null
read -r f h e <<< "$(row0 "$W/m2.obj")"
[ "$f" = 96 ] && ok "model level 2: 96 faces" || bad "model level 2: $f faces"
# Above the HD top: usage error.
set +e
"$S" convert "$W/hd.strata" "$W/l5.obj" --level 5 2> "$W/err5.txt"; rc=$?
set -e
if [ $rc = 2 ] && grep -q "HD levels up to 4" "$W/err5.txt" && [ ! -e "$W/l5.obj" ]; then ok "--level 5 refused"; else bad "--level 5: rc $rc $(cat "$W/err5.txt")"; fi
# Over the budget: refused with the estimate, nothing written.
set +e
"$S" convert "$W/hd.strata" "$W/big.obj" --level 4 --mem-budget 1 2> "$W/errb.txt"; rc=$?
set -e
if [ $rc = 1 ] && grep -q "HD level 4 everywhere needs about .* (estimate)" "$W/errb.txt" && [ ! -e "$W/big.obj" ]; then ok "budget: refused with the estimate"; else bad "budget: rc $rc $(cat "$W/errb.txt")"; fi

# Session output keeps the HD hierarchy, byte for byte.
"$S" convert "$W/hd.strata" "$W/copy.strata" > /dev/null
cmp -s "$W/hd.strata" "$W/copy.strata" && ok "session re-saved byte for byte" || bad "session re-saved differs"
set +e
"$S" convert "$W/hd.strata" "$W/more.strata" --levels 3 2> /dev/null; rc=$?
set -e
[ $rc = 2 ] && ok "--levels above the model refused" || bad "--levels: rc $rc"

# A sculpt layer at HD level 4 (test_session_hd --write-layer): info lists
# it; strata deform at level 4 edits the session (its active layer takes the
# change, app/cmd_deform.c) and writes it back with the layer.
"$B/test_session_hd" --write-layer "$W/hdl.strata"
if "$S" info "$W/hdl.strata" | grep -q "HD sculpt layer 'hd layer': level 4, strength 0.50"; then ok "info: the HD layer"
else bad "info: no HD layer: $("$S" info "$W/hdl.strata" | tail -2)"; fi
"$S" convert "$W/hdl.strata" "$W/hdl_a.obj" > /dev/null
if "$S" deform "$W/hdl.strata" --level 4 --box 0.3,0.3,0.3,1.3,1.3,1.3 --bump 0.7,0.7,0.7,0.3,0,0,0.05 -o "$W/hdl2.strata" > "$W/dl.txt" &&
   grep -q "[1-9][0-9]* vertices of HD level 4 moved" "$W/dl.txt" &&
   "$S" info "$W/hdl2.strata" | grep -q "HD sculpt layer 'hd layer': level 4" &&
   "$S" convert "$W/hdl2.strata" "$W/hdl_b.obj" > /dev/null && ! cmp -s "$W/hdl_a.obj" "$W/hdl_b.obj"; then
    ok "deform --level 4 with an HD layer: $(cat "$W/dl.txt")"
else bad "deform with an HD layer: $(cat "$W/dl.txt" 2>/dev/null)"; fi

echo "$n checks, $fail failed"
[ $fail = 0 ]
