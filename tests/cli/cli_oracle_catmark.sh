#!/usr/bin/env bash
# Catmull-Clark against OpenSubdiv 3.5 (osd_oracle: Far::TopologyRefiner +
# PrimvarRefiner): levels 1..4 as point sets (tests/cli/oracle_lib.sh) on closed
# and open meshes, both boundary conventions, creases and corners, n-gons,
# high valence; and OpenSubdiv's OBJ tags as its regression harness reads
# them (regression/common/far_utils.h): crease integers are vertex pairs,
# several pairs per tag with one sharpness or one per pair, several corners
# per tag, interpolateboundary from the file, creasemethod normal and
# smoothtriangles catmark; creasemethod chaikin (Chaikin's sharpness rule)
# on closed and open meshes; hole faces and interpolateboundary 0 (the
# boundary faces become holes), compared with OpenSubdiv's faces without
# its holes; smoothtriangles smooth (TRI_SUB_SMOOTH) on mixed and
# triangle meshes; odd crease counts, unknown tag values and faces out of
# range are refused with file:line.
#
#   cli_oracle_catmark.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
. "$(dirname "$0")/oracle_lib.sh"
oracle_init catmark "$@"
need_oracle OSD osd_oracle

# run_case MESH LEVELS BOUNDARY [LABEL]: strata levels 1..LEVELS vs
# OpenSubdiv; BOUNDARY "tag": neither side is given one (the file's
# interpolateboundary tag, else edge-only).
run_case() {
    local mesh=$1 levels=$2 boundary=$3 label=${4:-$(basename "$1")} b
    have_mesh "$mesh" || return
    b=$boundary; [ "$b" = tag ] && b=
    strata_levels catmull-clark "$mesh" "$levels" "$b" "$TMP/s" || return
    oracle_levels "$OSD" "$mesh" "$levels" "$TMP/osd" --scheme catmark ${b:+--boundary "$b"} || return
    compare_levels "$label $boundary vs OpenSubdiv" "$levels" "$TMP/s" "$TMP/osd"
}

# refused NAME TAG WHAT: the cube with the tag line TAG is refused, with a
# message naming the file, the tag's line (15) and WHAT.
refused() {
    local f=$TMP/$1.obj out
    { cube_cage; printf '%s\n' "$2"; } >"$f"
    cases=$((cases + 1))
    if out=$("$EXE" subdivide "$f" --scheme catmull-clark --levels 1 -o "$TMP/refused.obj" 2>&1); then
        fail_case "$1: accepted, should be refused ($2)"
    elif [[ $out == *"$1.obj:15: "*"$3"* ]]; then
        echo "ok    $1 refused: $out"
    else
        fail_case "$1: message lacks '$1.obj:15: ... $3': $out"
    fi
}

# cube_cage: the unit cube, 8 vertex lines then 6 face lines (a tag that
# follows is on line 15; tags number vertices from 0).
cube_cage() {
    printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n'
    printf 'f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n'
}

# A cube with a semi-sharp crease loop, a fractional crease and a corner,
# one edge per tag.
{ cube_cage; cat <<'OBJ'
t crease 2/1/0 4 5 2.5
t crease 2/1/0 5 6 2.5
t crease 2/1/0 6 7 2.5
t crease 2/1/0 7 4 2.5
t crease 2/1/0 0 1 0.5
t corner 1/1/0 2 1.7
OBJ
} >"$TMP/creased_cube.obj"
# The same kinds of tags with several pairs each: the top loop in one tag
# with one sharpness; three edges with a sharpness each; `3 7 2 3` is the
# edges 3-7 and 2-3 (read as a chain it would hold 7-2, a face diagonal);
# two corners with their own sharpness; OpenSubdiv's defaults named.
{ cube_cage; cat <<'OBJ'
t crease 8/1/0 4 5 5 6 6 7 7 4 2.5
t crease 6/3/0 0 1 1 2 2 6 0.5 1.5 3.2
t crease 4/1/0 3 7 2 3 1.2
t corner 2/2/0 0 5 1.7 0.8
t creasemethod 0/0/1 normal
t smoothtriangles 0/0/1 catmark
OBJ
} >"$TMP/pairs_cube.obj"
# A fan with one vertex of valence 16 (an open disk).
{
    echo "v 0 0 0.3"
    for i in $(seq 0 15); do
        awk -v i="$i" 'BEGIN { a = 2 * 3.14159265358979 * i / 16; printf "v %.17g %.17g %.17g\n", cos(a), sin(a), 0.1 * (i % 3) }'
    done
    for i in $(seq 0 15); do echo "f 1 $((i + 2)) $(( (i + 1) % 16 + 2 ))"; done
} >"$TMP/fan16.obj"
# The boundary convention from the file (edge-and-corner), with two spokes
# creased in one tag.
{ cat "$TMP/fan16.obj"; echo "t interpolateboundary 1/0/0 1"; echo "t crease 4/2/0 0 1 0 9 1.5 0.5"; } >"$TMP/fan16_ec.obj"

# face_loops_tags IN.obj OUT.obj METHOD: the mesh with the edges of its
# first face and of face nf/2 creased in one tag of pairs, one sharpness
# per pair (varying along each loop, so that Chaikin's averaging matters),
# and `t creasemethod METHOD`.
face_loops_tags() {
    awk -v method="$3" '
    { print }
    /^f / {
        nf++; n[nf] = NF - 1
        for (i = 2; i <= NF; i++) { split($i, c, "/"); f[nf, i - 1] = c[1] - 1 }
    }
    END {
        k[1] = 1; k[2] = int(nf / 2); np = 0; ints = ""; floats = ""
        for (j = 1; j <= 2; j++)
            for (i = 1; i <= n[k[j]]; i++) {
                ints = ints " " f[k[j], i] " " f[k[j], i % n[k[j]] + 1]
                floats = floats " " (0.4 + 0.7 * ((np * 3) % 5)); np++
            }
        printf "t crease %d/%d/0%s%s\n", 2 * np, np, ints, floats
        printf "t creasemethod 0/0/1 %s\n", method
    }' "$1" >"$2"
}

C=$MESHES/catmull_clark
run_case "$C/blub_control_mesh.obj" 4 edge-only
run_case "$C/dodecahedron_poly.obj" 3 edge-only
run_case "$C/chamfer_cube.off" 3 edge-only
run_case "$C/hole_capsule.off" 3 edge-only
run_case "$C/hole_capsule.off" 3 edge-and-corner
run_case "$C/mixed_faring.off" 2 edge-only
run_case "$C/hexa_sphere.off" 2 edge-only
run_case "$TMP/creased_cube.obj" 4 edge-only
run_case "$TMP/pairs_cube.obj" 4 edge-only
run_case "$TMP/fan16.obj" 3 edge-and-corner
run_case "$TMP/fan16.obj" 3 edge-only
run_case "$TMP/fan16_ec.obj" 3 tag
run_case "$ASSETS/open.obj" 3 edge-and-corner
run_case "$ASSETS/ngon.obj" 3 edge-only

# Chaikin creasing (Sdc::Options::CREASE_CHAIKIN): the same tags with
# `t creasemethod 0/0/1 chaikin`, closed and open meshes, both boundary
# conventions, multi-pair tags; tag_matters below shows that the method
# changes OpenSubdiv's surface on these tags.
for m in creased_cube pairs_cube fan16_ec; do
    { cat "$TMP/$m.obj"; echo "t creasemethod 0/0/1 chaikin"; } >"$TMP/${m}_chaikin.obj"
done
run_case "$TMP/creased_cube_chaikin.obj" 3 edge-only
run_case "$TMP/pairs_cube_chaikin.obj" 3 edge-only
run_case "$TMP/fan16_ec_chaikin.obj" 3 tag
for m in "$C/blub_control_mesh.obj" "$ASSETS/open.obj" "$ASSETS/ngon.obj"; do
    have_mesh "$m" || continue
    face_loops_tags "$m" "$TMP/$(basename "$m" .obj)_loops_chaikin.obj" chaikin
    face_loops_tags "$m" "$TMP/$(basename "$m" .obj)_loops_normal.obj" normal
done
run_case "$TMP/blub_control_mesh_loops_chaikin.obj" 3 edge-only
run_case "$TMP/blub_control_mesh_loops_normal.obj" 3 edge-only
run_case "$TMP/open_loops_chaikin.obj" 3 edge-and-corner
run_case "$TMP/open_loops_chaikin.obj" 3 edge-only
run_case "$TMP/ngon_loops_chaikin.obj" 3 edge-only

# The pair convention changes the surface: one tag of pairs differs from the
# chain it would be, so a reader of chains would fail the case above.
{ cube_cage; echo "t crease 4/1/0 0 1 2 3 2.0"; } >"$TMP/pair_cube.obj"
{ cube_cage; echo "t crease 6/1/0 0 1 1 2 2 3 2.0"; } >"$TMP/chain3_cube.obj"
cases=$((cases + 1))
strata_levels catmull-clark "$TMP/pair_cube.obj" 2 edge-only "$TMP/pair" &&
    strata_levels catmull-clark "$TMP/chain3_cube.obj" 2 edge-only "$TMP/chain3" &&
    if "$DIFF" "$TMP/pair_2.obj" "$TMP/chain3_2.obj" --tol "$TOL" >/dev/null 2>&1; then
        fail_case "t crease 4/1/0 0 1 2 3 gives the surface of the chain 0-1-2-3"
    else
        echo "ok    t crease 4/1/0 0 1 2 3 is the edges 0-1 and 2-3, not the chain 0-1-2-3"
    fi
run_case "$TMP/pair_cube.obj" 3 edge-only

# Refused: an odd crease count, and what Strata does not model.  Each of
# those tags changes OpenSubdiv's level 2 (so ignoring it would be wrong).
tag_matters() { # LABEL MESH TAG
    { cat "$2"; echo "$3"; } >"$TMP/tagged.obj"
    cases=$((cases + 1))
    oracle_levels "$OSD" "$2" 2 "$TMP/plain" --scheme catmark || return
    oracle_levels "$OSD" "$TMP/tagged.obj" 2 "$TMP/tagged" --scheme catmark || return
    if "$DIFF" "$TMP/plain_2.obj" "$TMP/tagged_2.obj" --tol "$TOL" >/dev/null 2>&1; then
        fail_case "$1: OpenSubdiv's level 2 is the same with '$3'"
    else
        echo "ok    $1: OpenSubdiv's level 2 changes with '$3'"
    fi
}
tag_matters "chaikin creasing" "$TMP/pairs_cube.obj" "t creasemethod 0/0/1 chaikin"
tag_matters "chaikin creasing" "$TMP/blub_control_mesh_loops_normal.obj" "t creasemethod 0/0/1 chaikin"
tag_matters "smooth triangles" "$TMP/fan16.obj" "t smoothtriangles 0/0/1 smooth"
tag_matters "hole" "$TMP/pairs_cube.obj" "t hole 1/0/0 2"
tag_matters "interpolateboundary none" "$ASSETS/open.obj" "t interpolateboundary 1/0/0 0"

# Holes (t hole: faces in the rules with no surface; OpenSubdiv's
# TopologyDescriptor::holeIndices): both sides write every level without
# its hole faces.  Closed and open meshes, with creases, several tags.
with_holes() { # IN OUT TAG-LINES...
    local in=$1 out=$2
    shift 2
    { cat "$in"; printf '%s\n' "$@"; } >"$out"
}
with_holes "$TMP/pairs_cube.obj" "$TMP/pairs_cube_holes.obj" "t hole 1/0/0 2" "t hole 1/0/0 5"
with_holes "$TMP/creased_cube_chaikin.obj" "$TMP/creased_cube_hole.obj" "t hole 1/0/0 1"
with_holes "$TMP/fan16_ec.obj" "$TMP/fan16_holes.obj" "t hole 3/0/0 0 7 8"
run_case "$TMP/pairs_cube_holes.obj" 3 edge-only
run_case "$TMP/creased_cube_hole.obj" 3 edge-only
run_case "$TMP/fan16_holes.obj" 3 tag
if have_mesh "$C/blub_control_mesh.obj"; then
    nf=$(grep -c '^f ' "$C/blub_control_mesh.obj")
    with_holes "$TMP/blub_control_mesh_loops_normal.obj" "$TMP/blub_holes.obj" \
        "t hole 4/0/0 0 1 $((nf / 2)) $((nf - 1))"
    run_case "$TMP/blub_holes.obj" 3 edge-only
fi
# interpolateboundary 0 (Sdc VTX_BOUNDARY_NONE): every face at a vertex with
# a boundary edge that is not infinitely sharp becomes a hole; a boundary
# creased to 10 keeps its faces.  --boundary overrides the tag.
{ cat "$ASSETS/open.obj"; echo "t interpolateboundary 1/0/0 0"; } >"$TMP/open_none.obj"
{ cat "$TMP/fan16.obj"; echo "t interpolateboundary 1/0/0 0"; echo "t crease 2/1/0 0 1 1.5"; } >"$TMP/fan16_none.obj"
{ cat "$TMP/fan16.obj"; echo "t interpolateboundary 1/0/0 0"
  echo "t crease 6/1/0 1 2 2 3 3 4 10"; } >"$TMP/fan16_none_sharp.obj"
run_case "$TMP/open_none.obj" 3 tag
run_case "$TMP/fan16_none.obj" 3 tag
run_case "$TMP/fan16_none_sharp.obj" 3 tag
run_case "$TMP/open_none.obj" 2 edge-and-corner "open_none (--boundary overrides the tag)"
if have_mesh "$C/blub_control_mesh.obj"; then
    # blub is closed and hole faces are no boundary: `none` adds no holes.
    with_holes "$C/blub_control_mesh.obj" "$TMP/blub_none.obj" "t hole 2/0/0 3 40" "t interpolateboundary 1/0/0 0"
    run_case "$TMP/blub_none.obj" 3 tag
fi
refused odd_crease "t crease 3/1/0 0 1 3 2.5" "crease tag has 3 integers: they are vertex pairs"
refused hole_range "t hole 1/0/0 6" "hole tag references face 6 but the file has 6 faces"
refused bad_method "t creasemethod 0/0/1 sharp" "creasemethod 'sharp' is not 'normal' or 'chaikin'"
refused bad_tri "t smoothtriangles 0/0/1 loop" "smoothtriangles 'loop' is not 'catmark' or 'smooth'"

# Smooth triangles (Sdc::Options::TRI_SUB_SMOOTH): edge points next to a
# triangle weigh its face point 0.47.  A large mixed mesh (its triangles
# changed by the option: tag_matters), with creases, a triangle fan with
# both boundary rules, and a closed all-triangle mesh.
if have_mesh "$C/mixed_faring.off"; then
    "$EXE" subdivide "$C/mixed_faring.off" --scheme catmull-clark --levels 0 -o "$TMP/mixed.obj" 2>/dev/null
    { cat "$TMP/mixed.obj"; echo "t smoothtriangles 0/0/1 smooth"; } >"$TMP/mixed_smooth.obj"
    face_loops_tags "$TMP/mixed_smooth.obj" "$TMP/mixed_smooth_creased.obj" chaikin
    run_case "$TMP/mixed_smooth.obj" 3 edge-only
    run_case "$TMP/mixed_smooth_creased.obj" 2 edge-only
    tag_matters "smooth triangles" "$TMP/mixed.obj" "t smoothtriangles 0/0/1 smooth"
fi
{ cat "$TMP/fan16.obj"; echo "t smoothtriangles 0/0/1 smooth"; } >"$TMP/fan16_smooth.obj"
run_case "$TMP/fan16_smooth.obj" 3 edge-only
run_case "$TMP/fan16_smooth.obj" 3 edge-and-corner
{ printf 'v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n'
  printf 'f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n'
  echo "t smoothtriangles 0/0/1 smooth"; echo "t crease 4/2/0 0 2 2 1 2.5 0.5"; } >"$TMP/octa_smooth.obj"
run_case "$TMP/octa_smooth.obj" 3 edge-only
oracle_done
