#!/usr/bin/env bash
# strata rebuild: subdivided cages (by Strata and, when built, by OpenSubdiv
# through tests/oracles/osd_oracle, which numbers vertices differently),
# shuffled (vertex order, face order, starting corners), rebuilt by
# unsubdivide; `info` lists k+1 levels, level k written back equals the
# input up to vertex order, the session re-saves byte-identically.
# Re-meshed input is refused by --method unsubdivide with the place named;
# auto falls back to the progressive method; the progressive method and
# strata filter on an open triangle mesh; bad
# input is refused with the file named and nothing written; an edge with
# three faces opens split, and is refused with --strict.
# Usage: cli_rebuild.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
S=$1 D=$2 A=$3 B=$4
W=$B/cli_rebuild
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
levels_of() { "$S" info "$1" | awk '$1 ~ /^[0-9]+$/ { n++ } END { print n + 0 }'; }
faces_at() { "$S" info "$1" | awk -v l="$2" '$1 == l { print $4 }'; }

# Vertices, faces and starting corners shuffled (awk's rand, fixed seed).
shuffle() {
    awk -v seed="$3" 'BEGIN { srand(seed) }
        /^v / { nv++; V[nv] = $2 " " $3 " " $4 }
        /^f / { nf++; F[nf] = ""; for (i = 2; i <= NF; i++) { split($i, t, "/"); F[nf] = F[nf] " " t[1] } }
        END {
            for (i = 1; i <= nv; i++) P[i] = i
            for (i = nv; i > 1; i--) { j = int(rand() * i) + 1; tmp = P[i]; P[i] = P[j]; P[j] = tmp }
            for (i = 1; i <= nv; i++) { NEW[P[i]] = i; print "v " V[P[i]] }
            for (i = 1; i <= nf; i++) Q[i] = i
            for (i = nf; i > 1; i--) { j = int(rand() * i) + 1; tmp = Q[i]; Q[i] = Q[j]; Q[j] = tmp }
            for (i = 1; i <= nf; i++) {
                k = split(substr(F[Q[i]], 2), c, " "); r = int(rand() * k); line = "f"
                for (j = 0; j < k; j++) line = line " " NEW[c[(j + r) % k + 1]]
                print line
            }
        }' "$1" > "$2"
}

# Faces as lists of vertex coordinates (as written: %.17g), each rotated to
# its smallest coordinate string, sorted: equal for equal meshes up to order.
canon() {
    awk '/^v / { nv++; V[nv] = $2 " " $3 " " $4 }
         /^f / { k = 0; for (i = 2; i <= NF; i++) { split($i, t, "/"); k++; c[k] = V[t[1]] }
                 s = 1; for (i = 2; i <= k; i++) if (c[i] < c[s]) s = i
                 line = ""; for (i = 0; i < k; i++) line = line "|" c[(s - 1 + i) % k + 1]
                 print line }' "$1" | LC_ALL=C sort
}

check_rebuild() {   # tag fine.obj k cage_faces [rebuild options]
    local tag=$1 fine=$2 k=$3 cf=$4
    shift 4
    if "$S" rebuild "$fine" "$@" -o "$W/$tag.strata" > "$W/$tag.out" 2> "$W/$tag.err"; then
        ok "$tag: $(head -1 "$W/$tag.out")"
    else bad "$tag: rebuild failed: $(cat "$W/$tag.err")"; return; fi
    local lv
    lv=$(levels_of "$W/$tag.strata")
    if [ "$lv" = $((k + 1)) ]; then ok "$tag: info lists $lv levels"; else bad "$tag: info lists $lv levels, expected $((k + 1))"; fi
    local f0
    f0=$(faces_at "$W/$tag.strata" 0)
    if [ "$f0" = "$cf" ]; then ok "$tag: cage of $f0 faces"; else bad "$tag: cage of $f0 faces, expected $cf"; fi
    "$S" convert "$W/$tag.strata" "$W/${tag}_fine.obj" --level "$k" --no-normals > /dev/null
    if [ -n "$(canon "$fine")" ] && cmp -s <(canon "$fine") <(canon "$W/${tag}_fine.obj"); then
        ok "$tag: level $k = the input up to vertex order"
    else bad "$tag: level $k differs from the input"; fi
    "$S" convert "$W/$tag.strata" "$W/${tag}_2.strata" > /dev/null
    if cmp -s "$W/$tag.strata" "$W/${tag}_2.strata"; then ok "$tag: load -> save byte-identical"
    else bad "$tag: load -> save differs"; fi
}

CC=$D/catmull_clark
TRI=$D/triangle
# ---- subdivided by Strata, shuffled -------------------------------------------
for spec in "blub:$CC/blub_control_mesh.obj:catmull-clark:3:112" "dodeca:$CC/dodecahedron_poly.obj:catmull-clark:4:12" \
            "cube:$A/cube.obj:catmull-clark:2:6" "hemi:$TRI/hemisphere.obj:loop:3:640" \
            "cnb:$TRI/cube_no_bottom.obj:loop:2:40" "qt:$A/cube.obj:quad-triangle:2:6"; do
    IFS=: read -r tag mesh scheme k cf <<< "$spec"
    "$S" subdivide "$mesh" --scheme "$scheme" --levels "$k" -o "$W/${tag}_in.obj" > /dev/null
    shuffle "$W/${tag}_in.obj" "$W/${tag}_sh.obj" 11
    extra=()
    [ "$scheme" = quad-triangle ] && extra=(--scheme quad-triangle)
    check_rebuild "$tag" "$W/${tag}_sh.obj" "$k" "$cf" --max-levels "$k" "${extra[@]}"
done
# The icosphere is itself two quadrisections of the icosahedron: with no
# limit, Loop x1 of it comes back to 20 faces in 3 levels.
"$S" subdivide "$TRI/sphere_ico.obj" --scheme loop --levels 1 -o "$W/ico_in.obj" > /dev/null
check_rebuild ico "$W/ico_in.obj" 3 20
# --target-faces: the coarsest level with at least N faces (960 -> 240 -> 60).
"$S" subdivide "$CC/dodecahedron_poly.obj" --scheme catmull-clark --levels 3 -o "$W/d3.obj" > /dev/null
check_rebuild target "$W/d3.obj" 2 60 --target-faces 50

# ---- subdivided by OpenSubdiv (its own vertex order) ---------------------------
OSD=$B/oracles/osd_oracle
if [ -x "$OSD" ]; then
    "$OSD" "$CC/blub_control_mesh.obj" --scheme catmark --levels 3 --out-prefix "$W/osd_blub" 2> /dev/null
    check_rebuild osd_blub "$W/osd_blub_3.obj" 3 112 --max-levels 3
    "$OSD" "$TRI/hemisphere.obj" --scheme loop --levels 2 --out-prefix "$W/osd_hemi" 2> /dev/null
    shuffle "$W/osd_hemi_2.obj" "$W/osd_hemi_sh.obj" 5
    check_rebuild osd_hemi "$W/osd_hemi_sh.obj" 2 640 --max-levels 2
else
    echo "skip OpenSubdiv inputs: $OSD not built"
fi

# ---- refusals --------------------------------------------------------------------
# One quad of a Catmull-Clark level split into two triangles (face 100).
awk '/^f / { nf++; if (nf == 100) { print "f " $2 " " $3 " " $4; print "f " $2 " " $4 " " $5; next } } { print }' \
    "$W/blub_in.obj" > "$W/split.obj"
"$S" rebuild "$W/split.obj" --method unsubdivide -o "$W/split.strata" > /dev/null 2> "$W/split.err"
rc=$?
if [ $rc -ne 0 ] && grep -q "split.obj" "$W/split.err" && grep -q "face 100 has 3 sides" "$W/split.err" && [ ! -e "$W/split.strata" ]; then
    ok "re-meshed input refused (exit $rc): $(cat "$W/split.err")"
else bad "re-meshed input: exit $rc, $(cat "$W/split.err")"; fi
"$S" rebuild "$W/split.obj" -o "$W/split.strata" > "$W/auto.out" 2> "$W/auto.err"
rc=$?
if [ $rc -eq 0 ] && grep -q "unsubdivide refused" "$W/auto.err" && grep -q "using the progressive method" "$W/auto.err" \
   && grep -q "progressive, [0-9]* levels" "$W/auto.out" && grep -q "split into triangles" "$W/auto.out" \
   && [ "$(levels_of "$W/split.strata")" -ge 3 ]; then
    ok "auto falls back to progressive and says why: $(head -1 "$W/auto.out" | cut -c1-100)"
else bad "auto: exit $rc, $(cat "$W/auto.err" "$W/auto.out")"; fi

# ---- progressive: a triangle mesh (open) -------------------------------------------
HEMI=$D/triangle/hemisphere.obj
"$S" convert "$HEMI" "$W/hemi_in.obj" --no-normals > /dev/null
if "$S" rebuild "$HEMI" --method progressive --target-faces 100 -o "$W/p.strata" > "$W/p.out" 2> "$W/p.err"; then
    ok "progressive: $(head -1 "$W/p.out" | cut -c1-120)"
else bad "progressive rebuild failed: $(cat "$W/p.err")"; fi
plv=$(levels_of "$W/p.strata")
ptop=$((plv - 1))
if [ "$plv" -ge 4 ] && [ "$(faces_at "$W/p.strata" 0)" -le 130 ]; then ok "progressive: $plv levels, $(faces_at "$W/p.strata" 0) faces at level 0"
else bad "progressive: $plv levels, $(faces_at "$W/p.strata" 0) faces at level 0"; fi
if [ "$(faces_at "$W/p.strata" "$ptop")" = "$(faces_at "$HEMI" 0)" ]; then ok "progressive: finest level has the input's faces"; else bad "progressive: finest faces"; fi
"$S" convert "$W/p.strata" "$W/p_top.obj" --level "$ptop" --no-normals > /dev/null
if cmp -s <(canon "$W/p_top.obj") <(canon "$W/hemi_in.obj"); then ok "progressive: finest level == input up to vertex order"
else bad "progressive: finest level differs from the input"; fi
"$S" convert "$W/p.strata" "$W/p2.strata" > /dev/null
if cmp -s "$W/p.strata" "$W/p2.strata"; then ok "progressive: load -> save byte-identical"; else bad "progressive: re-save differs"; fi
# Stored as its recipe (level 0 and the vertex splits, docs/SESSION-FORMAT.md
# PMRC), not as every level's relations (MAP).
if grep -qa "PMRC" "$W/p.strata" && ! grep -qa "MAP " "$W/p.strata"; then ok "progressive: the session holds the recipe ($(stat -c %s "$W/p.strata") bytes)"
else bad "progressive: the session holds no recipe"; fi
ones=$(printf '1,%.0s' $(seq 1 "$ptop")); ones=${ones%,}
"$S" filter "$W/p.strata" --gains "$ones" -o "$W/f1.obj" > /dev/null
"$S" convert "$W/f1.obj" "$W/f1c.obj" --no-normals > /dev/null
if cmp -s <(canon "$W/f1c.obj") <(canon "$W/hemi_in.obj"); then ok "filter: gains 1 change nothing"; else bad "filter: gains 1 changed the surface"; fi
zeros=$(printf '1,%.0s' $(seq 1 $((ptop - 2)))); zeros="${zeros}0,0"
"$S" filter "$W/p.strata" --gains "$zeros" -o "$W/f0.strata" > /dev/null
"$S" convert "$W/f0.strata" "$W/f0.obj" --level "$ptop" --no-normals > /dev/null
if ! cmp -s <(canon "$W/f0.obj") <(canon "$W/hemi_in.obj") && [ "$(faces_at "$W/f0.strata" "$ptop")" = "$(faces_at "$HEMI" 0)" ]; then
    ok "filter: gain 0 on the two finest bands changes the finest level, same faces"
else bad "filter: gain 0 had no effect"; fi
rc=0; "$S" filter "$W/p.strata" --gains 1,x -o "$W/bad.obj" > /dev/null 2>&1 || rc=$?
if [ $rc -eq 2 ] && [ ! -e "$W/bad.obj" ]; then ok "filter: bad gains refused"; else bad "filter: bad gains exit $rc"; fi
"$S" rebuild "$W/blub_in.obj" --scheme loop -o "$W/l.strata" > /dev/null 2> "$W/l.err"
rc=$?
if [ $rc -eq 2 ] && grep -q "polygon split" "$W/l.err" && [ ! -e "$W/l.strata" ]; then ok "incompatible scheme refused: $(cat "$W/l.err")"
else bad "incompatible scheme: exit $rc, $(cat "$W/l.err")"; fi
"$S" rebuild "$W/blub_in.obj" -o "$W/x.obj" > /dev/null 2>&1
rc=$?
if [ $rc -eq 2 ] && [ ! -e "$W/x.obj" ]; then ok "non-session output refused"; else bad "non-session output: exit $rc"; fi

# ---- tags and UVs ------------------------------------------------------------------
# A 2x2 grid cage (open) with a crease of
# sharpness 2.5 down its middle column and UVs (not a linear map: the
# middle one moved), subdivided once with linear UVs; the fine mesh gets its tags back by position: the crease chain (the
# vertices at x = 1, sharpness 1.5) and the four children of the first
# coarse face (around the face point at 0.5 0.5 0) as holes.
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 0 2 0.5\nv 1 2 0.5\nv 2 2 0.5\n' > "$W/tcage.obj"
printf 'vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 0.5\nvt 0.6 0.4\nvt 1 0.5\nvt 0 1\nvt 0.5 1\nvt 1 1\n' >> "$W/tcage.obj"
printf 'f 1/1 2/2 5/5 4/4\nf 2/2 3/3 6/6 5/5\nf 4/4 5/5 8/8 7/7\nf 5/5 6/6 9/9 8/8\nt crease 4/1/0 1 4 4 7 2.5\n' >> "$W/tcage.obj"
"$S" subdivide "$W/tcage.obj" --scheme catmull-clark --levels 1 --uv-interp all -o "$W/tfine.obj" > /dev/null
# tag_fine HOLES [CREASE_PAIRS [FILE [SHARPNESS]]]: FILE (tfine.obj) plus a crease tag along x = 1 (the
# first CREASE_PAIRS of its edges) and a hole tag on the first HOLES
# children of the first coarse face.
tag_fine() {
    awk -v holes="$1" -v pairs="${2:-99}" -v sharp="${4:-1.5}" '
        /^v / { nv++; if ($2 == 1) { X[++nx] = nv - 1; Y[nx] = $3 } if ($2 == 0.5 && $3 == 0.5 && $4 == 0) fp = nv }
        /^f / { nf++; for (i = 2; i <= NF; i++) { split($i, t, "/"); if (t[1] == fp) H[++nh] = nf - 1 } }
        { print }
        END {
            for (i = 1; i <= nx; i++) for (j = i + 1; j <= nx; j++) if (Y[j] < Y[i]) { tmp = Y[i]; Y[i] = Y[j]; Y[j] = tmp; tmp = X[i]; X[i] = X[j]; X[j] = tmp }
            np = nx - 1 < pairs ? nx - 1 : pairs
            line = "t crease " 2 * np "/1/0"; for (i = 1; i <= np; i++) line = line " " X[i] " " X[i + 1]; print line " " sharp
            if (holes > 0) { line = "t hole " holes "/0/0"; for (i = 1; i <= holes; i++) line = line " " H[i]; print line }
        }' "${3:-$W/tfine.obj}"
}
tag_fine 4 > "$W/tags.obj"
if "$S" rebuild "$W/tags.obj" --method unsubdivide --uv-interp all -o "$W/tags.strata" > "$W/tags.out" 2> "$W/tags.err" \
   && grep -q "tags kept: cage 2 crease edges, 0 corners, 1 hole face" "$W/tags.out" \
   && grep -q "UVs: .*--uv-interp all.* by at most 0 " "$W/tags.out" \
   && [ "$(faces_at "$W/tags.strata" 0)" = 4 ]; then
    ok "unsubdivide keeps creases, holes and UVs: $(grep -h "tags kept\|UVs" "$W/tags.out" | tr '\n' ' ' | cut -c1-220)"
else bad "unsubdivide with tags: $(cat "$W/tags.out" "$W/tags.err")"; fi
"$S" rebuild "$W/tags.obj" --method unsubdivide -o "$W/tags2.strata" > "$W/tags2.out" 2>&1
if grep -Eq "UVs: .*--uv-interp corners-plus1.* by at most (0\.[0-9]*[1-9]|[1-9])" "$W/tags2.out"; then
    ok "smooth face-varying UVs: the refined UVs differ and it says by how much: $(grep -h "UVs" "$W/tags2.out" | cut -c1-160)"
else bad "UVs under corners-plus1: $(cat "$W/tags2.out")"; fi
# The same cage refined twice by OpenSubdiv (its rules for the crease, its
# vertex order), the chain tagged 0.5: unsubdivide finds the cage (positions
# within 1e-9 of the diagonal, details zero) with the crease at 2.5.
if [ -x "$OSD" ]; then
    "$OSD" "$W/tcage.obj" --scheme catmark --levels 2 --out-prefix "$W/osd_tags" 2> /dev/null
    tag_fine 0 99 "$W/osd_tags_2.obj" 0.5 > "$W/osd_tags.obj"
    "$S" rebuild "$W/osd_tags.obj" --method unsubdivide -o "$W/osd_tags.strata" > "$W/osd_tags.out" 2>&1
    "$S" convert "$W/osd_tags.strata" "$W/osd_tags_cage.obj" --level 0 --no-normals > /dev/null 2>&1
    dev=$(awk '/^v / { if (FILENAME == ARGV[1]) P[++n] = $2 " " $3 " " $4; else Q[++m] = $2 " " $3 " " $4 }
        END { worst = (n == m && n == 9) ? 0 : 1e9
              for (i = 1; i <= m; i++) { best = 1e9; split(Q[i], q, " ")
                  for (j = 1; j <= n; j++) { split(P[j], p, " "); d = (p[1]-q[1])^2 + (p[2]-q[2])^2 + (p[3]-q[3])^2; if (d < best) best = d }
                  if (sqrt(best) > worst) worst = sqrt(best) }
              printf "%.3g", worst }' "$W/tcage.obj" "$W/osd_tags_cage.obj")
    if grep -q "3 levels (0..2), cage 4 faces and 9 vertices" "$W/osd_tags.out" && grep -q "tags kept: cage 2 crease edges" "$W/osd_tags.out" \
       && grep -Eq "longest detail ([0-9.]+e-(1[0-9]|[2-9][0-9])|0)$" "$W/osd_tags.out" && awk -v d="$dev" 'BEGIN { exit !(d <= 3e-9) }'; then
        ok "OpenSubdiv-refined creased cage: cage back within $dev (diagonal ~3), $(grep -o "longest detail.*" "$W/osd_tags.out")"
    else bad "OpenSubdiv-refined creased cage: off by $dev, $(cat "$W/osd_tags.out")"; fi
fi
{ cat "$W/tfine.obj"; echo "t interpolateboundary 1/0/0 0"; } > "$W/ibnone.obj"
rc=0; "$S" rebuild "$W/ibnone.obj" --method unsubdivide -o "$W/ibnone.strata" > /dev/null 2> "$W/ibnone.err" || rc=$?
if [ $rc -eq 1 ] && grep -q "interpolateboundary 0. with a boundary" "$W/ibnone.err" && [ ! -e "$W/ibnone.strata" ]; then ok "interpolateboundary 0 with a boundary refused: $(cat "$W/ibnone.err")"
else bad "interpolateboundary 0: exit $rc, $(cat "$W/ibnone.err")"; fi
rc=0; "$S" rebuild "$W/tags.obj" --uv-interp smooth -o "$W/uvbad.strata" > /dev/null 2> "$W/uvbad.err" || rc=$?
if [ $rc -eq 2 ] && grep -q "uv-interp wants" "$W/uvbad.err" && [ ! -e "$W/uvbad.strata" ]; then ok "bad --uv-interp refused (exit 2)"
else bad "bad --uv-interp: exit $rc, $(cat "$W/uvbad.err")"; fi
# Tags no coarser mesh refines into: refused by unsubdivide, naming what;
# auto falls back to progressive, which says what it drops.
tag_fine 3 > "$W/mixhole.obj"
tag_fine 0 1 > "$W/halfcrease.obj"
for c in "mixhole hole: face" "halfcrease crease: edge"; do
    set -- $c
    rc=0; "$S" rebuild "$W/$1.obj" --method unsubdivide -o "$W/$1.strata" > /dev/null 2> "$W/$1.err" || rc=$?
    if [ $rc -eq 1 ] && grep -q "$1.obj: .*$2 $3" "$W/$1.err" && [ ! -e "$W/$1.strata" ]; then ok "$1 refused: $(cat "$W/$1.err")"
    else bad "$1: exit $rc, $(cat "$W/$1.err")"; fi
done
rc=0; "$S" rebuild "$W/mixhole.obj" -o "$W/mix_auto.strata" > "$W/mix_auto.out" 2> "$W/mix_auto.err" || rc=$?
if [ $rc -eq 0 ] && grep -q "unsubdivide refused: .*hole: face" "$W/mix_auto.err" \
   && grep -q "note: the progressive method keeps no tags or UVs; dropped 4 crease tags, 3 hole faces (they are ordinary faces now), the UVs" "$W/mix_auto.out"; then
    ok "auto falls back to progressive, which names what it drops: $(grep note "$W/mix_auto.out")"
else bad "auto with mixed holes: exit $rc, $(cat "$W/mix_auto.out" "$W/mix_auto.err")"; fi

# ---- bad input ---------------------------------------------------------------------
: > "$W/empty.obj"
for f in "$D/edge_cases/moebius_quad.obj" "$W/empty.obj" "$W/missing.obj"; do
    "$S" rebuild "$f" --method unsubdivide -o "$W/bad.strata" > /dev/null 2> "$W/bad.err"
    rc=$?
    if [ $rc -ne 0 ] && grep -q "$(basename "$f")" "$W/bad.err" && [ ! -e "$W/bad.strata" ]; then
        ok "bad input $(basename "$f") refused (exit $rc): $(head -1 "$W/bad.err")"
    else bad "bad input $(basename "$f"): exit $rc, $(cat "$W/bad.err")"; fi
done

# An edge shared by three faces: rebuild reads through the same reader, so
# the mesh opens split (the note on stderr) and the progressive method
# rebuilds it; unsubdivide refuses it for what it is (no polygon split), not
# for the edge; --strict refuses it at the line, nothing written.
NM=$D/edge_cases/nonmanifold_edge.obj
rc=0; "$S" rebuild "$NM" -o "$W/nm.strata" > "$W/nm.out" 2> "$W/nm.err" || rc=$?
if [ $rc -eq 0 ] && [ -s "$W/nm.strata" ] && grep -q "nonmanifold_edge.obj: repaired: split 1 non-manifold edge" "$W/nm.err" \
   && grep -q "using the progressive method" "$W/nm.err"; then
    ok "nonmanifold_edge.obj opens split and rebuilds (progressive): $(grep 'split 1' "$W/nm.err")"
else bad "nonmanifold_edge.obj: exit $rc, $(cat "$W/nm.out" "$W/nm.err")"; fi
rc=0; "$S" rebuild "$NM" --method unsubdivide -o "$W/nm_u.strata" > /dev/null 2> "$W/nm_u.err" || rc=$?
if [ $rc -eq 1 ] && grep -q "not a polygon split" "$W/nm_u.err" && ! grep -q "faces share it" "$W/nm_u.err" && [ ! -e "$W/nm_u.strata" ]; then
    ok "nonmanifold_edge.obj: unsubdivide refuses it as no polygon split: $(tail -1 "$W/nm_u.err")"
else bad "nonmanifold_edge.obj unsubdivide: exit $rc, $(cat "$W/nm_u.err")"; fi
rc=0; "$S" rebuild "$NM" --strict -o "$W/nm_s.strata" > /dev/null 2> "$W/nm_s.err" || rc=$?
if [ $rc -eq 1 ] && grep -q "nonmanifold_edge.obj:22: non-manifold edge between vertices 4 and 6: 3 faces share it (lines 20, 21, 22)" "$W/nm_s.err" \
   && [ ! -e "$W/nm_s.strata" ]; then
    ok "nonmanifold_edge.obj refused with --strict: $(cat "$W/nm_s.err")"
else bad "nonmanifold_edge.obj --strict: exit $rc, $(cat "$W/nm_s.err")"; fi

if "$S" help | grep -qE '^[[:space:]]*rebuild[[:space:]]'; then ok "help lists rebuild"; else bad "help does not list rebuild"; fi

echo "$((n - fail)) passed, $fail failed"
[ $fail -eq 0 ]
