#!/usr/bin/env bash
# OpenSubdiv's scheme tags through the commands (positions against
# OpenSubdiv: cli_oracle_catmark.sh, cli_oracle_loop.sh): hole faces are
# not drawn (render), not written (subdivide, adapt, adapt --access),
# sessions keep them and re-save byte for byte, as they keep creasemethod
# chaikin and smoothtriangles smooth; schemes that cannot have holes refuse
# them with a message and exit 1.
# Usage: cli_tags.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
S=$1 A=$3 B=$4
W=$B/cli_tags
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
faces_in() { grep -c '^f ' "$1"; }

# The cube with three of its six faces as holes (in two tags).
{ cat "$A/cube.obj"; echo "t hole 2/0/0 0 2"; echo "t hole 1/0/0 4"; } >"$W/cube_holes.obj"

# subdivide: level 2 has 96 faces, 48 of them children of holes.
"$S" subdivide "$W/cube_holes.obj" --scheme catmull-clark --levels 2 -o "$W/l2.obj" >/dev/null 2>&1
"$S" subdivide "$A/cube.obj" --scheme catmull-clark --levels 2 -o "$W/l2_plain.obj" >/dev/null 2>&1
if [ "$(faces_in "$W/l2.obj")" = 48 ] && [ "$(faces_in "$W/l2_plain.obj")" = 96 ] &&
   [ "$(grep -c '^v ' "$W/l2.obj")" = "$(grep -c '^v ' "$W/l2_plain.obj")" ]; then
    ok "subdivide: 48 of 96 faces written, every vertex"
else bad "subdivide: $(faces_in "$W/l2.obj") faces written, expected 48 (and all vertices)"; fi
# The vertices both write are the same: holes stay in the rules.
if cmp -s <(grep '^v ' "$W/l2.obj") <(grep '^v ' "$W/l2_plain.obj"); then ok "subdivide: positions as without holes"
else bad "subdivide: holes moved vertices"; fi

# render: the faces drawn, and the image differs from the cube without holes.
out=$("$S" render "$W/cube_holes.obj" --scheme catmull-clark --levels 3 --view back -o "$W/holes.png" 2>&1)
"$S" render "$A/cube.obj" --scheme catmull-clark --levels 3 --view back -o "$W/plain.png" >/dev/null 2>&1
if [[ $out == *"192 faces"* ]] && ! cmp -s "$W/holes.png" "$W/plain.png"; then ok "render: $out"
else bad "render: '$out' (expected 192 faces drawn and a different image)"; fi

# adapt, both extractions: the faces of holes are left out.
for mode in "" --access; do
    "$S" adapt "$W/cube_holes.obj" --scheme catmull-clark --base-level 1 --max-level 3 \
        --box -1,-1,-1,0,0,0 $mode -o "$W/a.obj" >/dev/null 2>&1
    "$S" adapt "$A/cube.obj" --scheme catmull-clark --base-level 1 --max-level 3 \
        --box -1,-1,-1,0,0,0 $mode -o "$W/a_plain.obj" >/dev/null 2>&1
    h=$(faces_in "$W/a.obj") p=$(faces_in "$W/a_plain.obj")
    if [ "$h" -gt 0 ] && [ "$h" -lt "$p" ]; then ok "adapt ${mode:-(levels)}: $h faces written of $p without holes"
    else bad "adapt ${mode:-(levels)}: $h faces with holes, $p without"; fi
done

# Sessions: holes, Chaikin creasing and smooth triangles survive; a re-save
# is byte-identical; the level written from the session is the same file.
{ cat "$A/cube.obj"; echo "t hole 1/0/0 1"; echo "t crease 6/3/0 0 1 1 2 2 3 0.5 2.5 1.5"
  echo "t creasemethod 0/0/1 chaikin"; echo "t smoothtriangles 0/0/1 smooth"; } >"$W/tagged.obj"
if "$S" convert "$W/tagged.obj" "$W/t.strata" --scheme catmull-clark --levels 3 >/dev/null 2>&1 &&
   "$S" convert "$W/t.strata" "$W/t2.strata" >/dev/null 2>&1 && cmp -s "$W/t.strata" "$W/t2.strata"; then
    ok "session: re-save byte-identical"
else bad "session: round trip failed or differs"; fi
"$S" subdivide "$W/tagged.obj" --scheme catmull-clark --levels 3 -o "$W/direct.obj" >/dev/null 2>&1
"$S" convert "$W/t.strata" "$W/from_session.obj" --level 3 --no-normals >/dev/null 2>&1
if cmp -s <(grep -v '^#' "$W/direct.obj") <(grep -v '^#' "$W/from_session.obj"); then
    ok "session: level 3 from the session = level 3 from the file ($(faces_in "$W/direct.obj") faces)"
else bad "session: level 3 from the session differs from the file's"; fi

# Refusals: message with the file and the reason, exit 1, nothing written.
for scheme in sqrt3 doo-sabin; do
    mesh=$W/cube_holes.obj
    [ "$scheme" = sqrt3 ] && { { printf 'v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n'
        printf 'f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\nt hole 1/0/0 3\n'; } >"$W/octa_hole.obj"
        mesh=$W/octa_hole.obj; }
    out=$("$S" subdivide "$mesh" --scheme "$scheme" --levels 1 -o "$W/refused.obj" 2>&1); rc=$?
    if [ $rc = 1 ] && [[ $out == *"$(basename "$mesh")"*"holes need a face-splitting scheme"* ]] && [ ! -e "$W/refused.obj" ]; then
        ok "$scheme refuses holes: $out"
    else bad "$scheme with holes: rc $rc, '$out'"; fi
done

# A glTF of nothing but holes is refused (a primitive needs triangles).
{ cat "$A/cube.obj"; echo "t hole 6/0/0 0 1 2 3 4 5"; } >"$W/all_holes.obj"
out=$("$S" convert "$W/all_holes.obj" "$W/all_holes.glb" --levels 1 2>&1); rc=$?
if [ $rc = 1 ] && [[ $out == *"all_holes.glb: every face is a hole"* ]] && [ ! -e "$W/all_holes.glb" ]; then
    ok "glTF of holes only refused: $out"
else bad "glTF of holes only: rc $rc, '$out'"; fi

echo "$((n - fail)) passed, $fail failed"
[ "$fail" = 0 ]
