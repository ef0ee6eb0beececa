#!/usr/bin/env bash
# strata deform at HD levels (app/cmd_deform.c): a bump at level 5 of spot
# (model levels 0..2) inside --box makes the session's HD levels: strata
# info lists them with faces, strata convert writes a closed adaptive mesh
# with more faces than level 2 and the bump in it (its largest x grows by
# about the bump's x); a later bump at level 1 moves the model and keeps the
# HD levels, every vertex of the HD mesh moving by the coarse bump's formula
# (so the sculpted HD detail rides along instead of being lost); a second HD
# bump at level 6 adds a level.  Refused, with a message, a non-zero exit
# and an existing OUT left byte for byte: no --box, the sqrt3 scheme, a
# refinement over --mem-budget.
# Usage: cli_deform_hd.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
S=$1 D=$2 B=$4
SPOT=$D/catmull_clark/spot_quadrangulated.obj
LOWTRI=$D/triangle/spot_low_resolution.obj
[ -f "$SPOT" ] && [ -f "$LOWTRI" ] || { echo "note: $SPOT or $LOWTRI not found: skipped"; exit 77; }
W=$B/cli_deform_hd
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }

# The box around spot's largest-x vertex (0.471552, 0.708579, -0.199184),
# the bump centred there.
BOX=0.35,0.6,-0.3,0.6,0.8,-0.1
HDBUMP=0.47,0.7,-0.2,0.05,0.02,0.01,0

# faces holes euler of a mesh file (level 0 of strata info)
row0() { "$S" info "$1" | awk '$1 == "0" { print $4, $5, $6 }'; }
maxx() { awk '/^v / && (!n++ || $2 > m) { m = $2 } END { printf "%.9f\n", m }' "$1"; }

# ---- a bump at HD level 5 -----------------------------------------------
if "$S" deform "$SPOT" --levels 2 --level 5 --box "$BOX" --bump "$HDBUMP" -o "$W/hd.strata" > "$W/d1.txt"; then
    cat "$W/d1.txt"
    faces=$(sed -n 's/.*HD levels 3\.\.5: \([0-9]*\) faces stored.*/\1/p' "$W/d1.txt")
    moved=$(sed -n 's/.*: \([0-9]*\) vertices of HD level 5 moved.*/\1/p' "$W/d1.txt")
    if [ "${faces:-0}" -gt 0 ] && [ "${moved:-0}" -gt 0 ]; then ok "deform --level 5: $moved vertices moved, $faces HD faces"
    else bad "deform --level 5 output: $(cat "$W/d1.txt")"; fi
else
    bad "deform --level 5 failed"
fi
"$S" info "$W/hd.strata" > "$W/info.txt"
hd_faces() { awk -v l="$2" 'f && $1 == l { print $2 } /^HD hierarchy:/ { f = 1 }' "$1"; }
f3=$(hd_faces "$W/info.txt" 3) f4=$(hd_faces "$W/info.txt" 4) f5=$(hd_faces "$W/info.txt" 5)
if grep -q "^HD hierarchy: 6 levels (0..5), levels 0..2 the model's" "$W/info.txt" &&
   [ "${f3:-0}" -gt 0 ] && [ "${f4:-0}" -gt 0 ] && [ "${f5:-0}" -gt 0 ]; then ok "info: HD levels 3..5 with $f3, $f4, $f5 faces"
else bad "info: HD levels '$f3' '$f4' '$f5'"; sed -n '/^HD/,$p' "$W/info.txt"; fi

"$S" convert "$W/hd.strata" "$W/hd.obj" --no-normals > /dev/null
"$S" convert "$W/hd.strata" "$W/top.obj" --level 2 --no-normals > /dev/null
read -r hf hh he <<< "$(row0 "$W/hd.obj")"
read -r uf _ _ <<< "$(row0 "$W/top.obj")"
if [ "$hh" = 0 ] && [ "$he" = 2 ] && [ "$hf" -gt "$uf" ]; then ok "convert: closed HD mesh, $hf faces > level 2's $uf"
else bad "convert: HD mesh faces $hf holes $hh euler $he, level 2 faces $uf"; fi
# The bump's x (0.02) at its centre, the largest-x vertex: the HD mesh
# reaches that much farther than the model.
dx=$(awk -v a="$(maxx "$W/hd.obj")" -v b="$(maxx "$W/top.obj")" 'BEGIN { printf "%.6f", a - b }')
if awk -v d="$dx" 'BEGIN { exit !(d > 0.015 && d < 0.025) }'; then ok "the HD bump is in the mesh: largest x +$dx"
else bad "the HD mesh's largest x moved by $dx, not about 0.02"; fi

# ---- a coarse bump at level 1 keeps the HD levels --------------------------
C=(0.47 0.7 -0.2 0.3 0.05 0 0)
if "$S" deform "$W/hd.strata" --level 1 --bump "$(IFS=,; echo "${C[*]}")" -o "$W/hd2.strata" > "$W/d2.txt"; then
    cat "$W/d2.txt"
    "$S" info "$W/hd2.strata" > "$W/info2.txt"
    if [ "$(sed -n '/^HD hierarchy/,$p' "$W/info.txt")" = "$(sed -n '/^HD hierarchy/,$p' "$W/info2.txt")" ]; then
        ok "deform --level 1: the HD levels stay (same faces per level)"
    else bad "deform --level 1 changed the HD levels"; sed -n '/^HD/,$p' "$W/info2.txt"; fi
else
    bad "deform --level 1 of the HD session failed"
fi
"$S" convert "$W/hd2.strata" "$W/hd2.obj" --no-normals > /dev/null
# Every vertex of the HD mesh (same map, same order) moved by the coarse
# bump D*exp(-|v-C|^2/R^2) up to the subdivision's smoothing of a wide
# bump; a lost HD detail would be off by the HD bump (0.02).
emax=$(awk -v cx="${C[0]}" -v cy="${C[1]}" -v cz="${C[2]}" -v r="${C[3]}" -v dx="${C[4]}" -v dy="${C[5]}" -v dz="${C[6]}" '
    function abs(x) { return x < 0 ? -x : x }
    FNR == NR && /^v / { nb++; X[nb] = $2; Y[nb] = $3; Z[nb] = $4; next }
    /^v / { na++; w = exp(-((X[na] - cx) ^ 2 + (Y[na] - cy) ^ 2 + (Z[na] - cz) ^ 2) / (r * r))
            e = abs($2 - X[na] - dx * w) + abs($3 - Y[na] - dy * w) + abs($4 - Z[na] - dz * w); if (e > m) m = e }
    END { if (na != nb || !na) print "count", nb, na; else printf "%.6f\n", m }' "$W/hd.obj" "$W/hd2.obj")
if awk -v e="$emax" 'BEGIN { exit !(e ~ /^[0-9.]+$/ && e < 0.003) }'; then ok "the HD mesh followed the coarse bump (largest error $emax)"
else bad "the HD mesh after the coarse bump: error $emax"; fi

# ---- another HD level on the existing HD hierarchy ----------------------------
if "$S" deform "$W/hd.strata" --level 6 --box "$BOX" --bump 0.47,0.7,-0.2,0.02,0,0.01,0 -o "$W/hd3.strata" > "$W/d3.txt" &&
   grep -q "HD levels 3\.\.6: [1-9][0-9]* faces stored" "$W/d3.txt"; then ok "deform --level 6 adds HD level 6: $(cat "$W/d3.txt")"
else bad "deform --level 6: $(cat "$W/d3.txt" 2>/dev/null)"; fi

# ---- refusals -----------------------------------------------------------------
echo "an older OUT" > "$W/out.strata"
cp "$W/out.strata" "$W/out.orig"
refused() {   # name wanted-status message-pattern args...
    local name=$1 want=$2 pat=$3
    shift 3
    "$S" deform "$@" -o "$W/out.strata" > "$W/r.out" 2> "$W/r.err"
    local rc=$?
    if [ "$rc" = "$want" ] && grep -q -- "$pat" "$W/r.err" && cmp -s "$W/out.strata" "$W/out.orig"; then
        ok "refused: $name (exit $rc): $(head -1 "$W/r.err")"
    else bad "$name: exit $rc (wanted $want), stderr: $(cat "$W/r.err")"; fi
}
refused "no --box" 2 "give --box" "$W/hd.strata" --level 5 --bump "$HDBUMP"
refused "sqrt3" 2 "need a quadrisection scheme" "$LOWTRI" --scheme sqrt3 --levels 1 --level 3 --box "$BOX" --bump "$HDBUMP"
refused "over --mem-budget" 1 "needs about .* MiB more" "$W/hd.strata" --level 8 --box -1,-1,-1,1,1,1.1 --bump "$HDBUMP" --mem-budget 100

echo "$((n - fail))/$n passed"
[ "$fail" -eq 0 ]
