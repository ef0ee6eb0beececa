#!/usr/bin/env bash
# Loop subdivision through the strata CLI against OpenSubdiv 3.5 (osd_oracle),
# and against CGAL and OpenMesh on closed meshes (they have no corner rule and
# OpenMesh's Loop weight table stops at valence 50).
#
#   cli_oracle_loop.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Each case compares levels 1..N as point sets (tests/cli/oracle_lib.sh).  Skips
# (exit 0, with a note) when osd_oracle or pointset_diff is not built;
# exits 77 (skipped) when a mesh of ../shared/data is missing.
set -u
. "$(dirname "$0")/oracle_lib.sh"
oracle_init loop "$@"
need_oracle OSD osd_oracle
want_oracle CGAL cgal_oracle
want_oracle OM openmesh_oracle

# run_case MESH LEVELS BOUNDARY LIB: OpenSubdiv at levels 1..LEVELS, CGAL and
# OpenMesh (closed meshes only) at levels 1..LIB (0: not compared).
run_case() {
    local mesh=$1 levels=$2 boundary=$3 lib=$4 name
    name=$(basename "$mesh")
    have_mesh "$mesh" || return
    strata_levels loop "$mesh" "$levels" "$boundary" "$TMP/s" || return
    if oracle_levels "$OSD" "$mesh" "$levels" "$TMP/osd" --scheme loop --boundary "$boundary"; then
        compare_levels "$name $boundary vs OpenSubdiv" "$levels" "$TMP/s" "$TMP/osd"
    fi
    [ "$lib" -gt 0 ] || return
    if [ -n "$CGAL" ] && oracle_levels "$CGAL" "$mesh" "$lib" "$TMP/cgal" --scheme loop; then
        compare_levels "$name vs CGAL" "$lib" "$TMP/s" "$TMP/cgal"
    fi
    if [ -n "$OM" ] && oracle_levels "$OM" "$mesh" "$lib" "$TMP/om" --scheme loop; then
        compare_levels "$name vs OpenMesh" "$lib" "$TMP/s" "$TMP/om"
    fi
}

# add_tags IN.obj OUT.obj: copies the mesh and appends OpenSubdiv tags
# (0-based) on real edges: the three edges of face 1 (2.5, 2.5, 0.6: a
# closed semi-sharp loop with different sharpness), two more edges of a
# neighbouring face (1.0 and infinite: the shared edge's ends get 3 sharp
# edges, the corner rule), a lone edge at face nf/2 (3.3: two darts), the
# loop of face nf/3 (1.7), and corners at face 2nf/3 (1.3) and 3nf/4 (10).
add_tags() {
    awk '
    { print }
    /^f / {
        nf++; n[nf] = NF - 1
        for (i = 2; i <= NF; i++) { split($i, c, "/"); f[nf, i - 1] = c[1] - 1 }
    }
    function has(k, v,   i) { for (i = 1; i <= n[k]; i++) if (f[k, i] == v) return 1; return 0 }
    END {
        a0 = f[1, 1]; a1 = f[1, 2]; a2 = f[1, 3]
        printf "t crease 2/1/0 %d %d 2.5\nt crease 2/1/0 %d %d 2.5\nt crease 2/1/0 %d %d 0.6\n", a0, a1, a1, a2, a2, a0
        for (k = 2; k <= nf; k++) if (has(k, a0) + has(k, a1) + has(k, a2) == 2) break
        # the two edges of face k that are not edges of face 1
        for (i = 1; i <= 3; i++) {
            u = f[k, i]; w = f[k, i % 3 + 1]
            if (has(1, u) && has(1, w)) continue
            s = (++m == 1) ? "1.0" : "10"
            printf "t crease 2/1/0 %d %d %s\n", u, w, s
        }
        k = int(nf / 2); printf "t crease 2/1/0 %d %d 3.3\n", f[k, 1], f[k, 2]
        k = int(nf / 3); printf "t crease 2/1/0 %d %d 1.7\nt crease 2/1/0 %d %d 1.7\nt crease 2/1/0 %d %d 1.7\n", f[k, 1], f[k, 2], f[k, 2], f[k, 3], f[k, 3], f[k, 1]
        k = int(2 * nf / 3); printf "t corner 1/1/0 %d 1.3\n", f[k, 1]
        k = int(3 * nf / 4); printf "t corner 1/1/0 %d 10\n", f[k, 2]
    }' "$1" >"$2"
}

T=$MESHES/triangle
# Closed meshes (the boundary option changes nothing; CGAL and OpenMesh too).
run_case "$T/sphere_ico.obj" 4 edge-only 3
run_case "$T/spot_low_resolution.obj" 3 edge-only 2
run_case "$T/bob_small.ply" 3 edge-only 2
# Open meshes, both boundary conventions (levels 1..2 only with
# edge-and-corner on the larger ones, to keep the suite fast under ASan).
run_case "$T/hemisphere.obj" 3 edge-only 0
run_case "$T/hemisphere.obj" 2 edge-and-corner 0
run_case "$T/cube_no_bottom.obj" 4 edge-only 0
run_case "$T/cube_no_bottom.obj" 4 edge-and-corner 0
run_case "$T/hand_lowres.obj" 3 edge-only 0
run_case "$T/hand_lowres.obj" 2 edge-and-corner 0
tri_grid 6 "$TMP/tri_grid.obj"
run_case "$TMP/tri_grid.obj" 4 edge-only 0
run_case "$TMP/tri_grid.obj" 4 edge-and-corner 0
# Semi-sharp creases, darts and corners from `t` tags.
if [ -f "$T/sphere_ico.obj" ]; then
    add_tags "$T/sphere_ico.obj" "$TMP/sphere_creased.obj"
    run_case "$TMP/sphere_creased.obj" 3 edge-only 0
fi
if [ -f "$T/hemisphere.obj" ]; then
    add_tags "$T/hemisphere.obj" "$TMP/hemisphere_creased.obj"
    run_case "$TMP/hemisphere_creased.obj" 3 edge-only 0
    run_case "$TMP/hemisphere_creased.obj" 2 edge-and-corner 0
fi
# Chaikin creasing (t creasemethod 0/0/1 chaikin) on the same tags, and the
# crease tags merged into one tag of vertex pairs with one sharpness per
# pair (OpenSubdiv's convention), closed and open.
with_chaikin() { # IN OUT
    { cat "$1"; echo "t creasemethod 0/0/1 chaikin"; } >"$2"
}
one_pair_tag() { # IN OUT: the `t crease 2/1/0 a b s` lines as one tag
    awk '
    $1 == "t" && $2 == "crease" { ints = ints " " $4 " " $5; floats = floats " " $6; np++; next }
    { print }
    END { printf "t crease %d/%d/0%s%s\n", 2 * np, np, ints, floats }' "$1" >"$2"
}
if [ -f "$T/sphere_ico.obj" ]; then
    with_chaikin "$TMP/sphere_creased.obj" "$TMP/sphere_chaikin.obj"
    run_case "$TMP/sphere_chaikin.obj" 3 edge-only 0
    one_pair_tag "$TMP/sphere_creased.obj" "$TMP/sphere_pairs.obj"
    run_case "$TMP/sphere_pairs.obj" 3 edge-only 0
fi
if [ -f "$T/hemisphere.obj" ]; then
    with_chaikin "$TMP/hemisphere_creased.obj" "$TMP/hemisphere_chaikin.obj"
    run_case "$TMP/hemisphere_chaikin.obj" 3 edge-only 0
    run_case "$TMP/hemisphere_chaikin.obj" 2 edge-and-corner 0
    one_pair_tag "$TMP/hemisphere_chaikin.obj" "$TMP/hemisphere_pairs_chaikin.obj"
    run_case "$TMP/hemisphere_pairs_chaikin.obj" 3 edge-only 0
fi
# Hole faces (t hole) and interpolateboundary 0 (the faces at the boundary
# become holes): OpenSubdiv's levels without its hole faces.  run_case
# passes --boundary to both sides, so `none` is compared through tag_case.
tag_case() { # MESH LEVELS: the file's own tags on both sides
    local mesh=$1 levels=$2
    strata_levels loop "$mesh" "$levels" "" "$TMP/s" || return
    oracle_levels "$OSD" "$mesh" "$levels" "$TMP/osd" --scheme loop || return
    compare_levels "$(basename "$mesh") tags vs OpenSubdiv" "$levels" "$TMP/s" "$TMP/osd"
}
if [ -f "$T/sphere_ico.obj" ]; then
    { cat "$TMP/sphere_chaikin.obj"; echo "t hole 3/0/0 0 1 7"; echo "t hole 1/0/0 30"; } >"$TMP/sphere_holes.obj"
    run_case "$TMP/sphere_holes.obj" 3 edge-only 0
fi
if [ -f "$T/hemisphere.obj" ]; then
    { cat "$TMP/hemisphere_creased.obj"; echo "t hole 2/0/0 5 9"; } >"$TMP/hemisphere_holes.obj"
    run_case "$TMP/hemisphere_holes.obj" 3 edge-only 0
    run_case "$TMP/hemisphere_holes.obj" 2 edge-and-corner 0
    { cat "$TMP/hemisphere_creased.obj"; echo "t interpolateboundary 1/0/0 0"; } >"$TMP/hemisphere_none.obj"
    tag_case "$TMP/hemisphere_none.obj" 3
fi
if [ -f "$T/cube_no_bottom.obj" ]; then
    { cat "$T/cube_no_bottom.obj"; echo "t interpolateboundary 1/0/0 0"; } >"$TMP/cube_no_bottom_none.obj"
    tag_case "$TMP/cube_no_bottom_none.obj" 3
fi

oracle_done
