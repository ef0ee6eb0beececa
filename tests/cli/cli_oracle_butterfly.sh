#!/usr/bin/env bash
# Modified Butterfly through the strata CLI against OpenMesh 9's
# ModifiedButterflyT (openmesh_oracle), on closed and open meshes, plus
# generated meshes with high-valence vertices (12 to 60: OpenMesh grows its
# weight table past its initial 30 entries) and an open grid whose corners
# exercise the boundary 4-point rule at valence 2 and 3.
#
#   cli_oracle_butterfly.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Each case compares levels 1..N as point sets (tests/cli/oracle_lib.sh).  Skips
# (exit 0, with a note) when openmesh_oracle or pointset_diff is not built;
# exits 77 (skipped) when a mesh of ../shared/data is missing.
set -u
. "$(dirname "$0")/oracle_lib.sh"
oracle_init butterfly "$@"
need_oracle OM openmesh_oracle

# run_case MESH LEVELS [BOUNDARY]: strata levels 1..LEVELS vs OpenMesh.
run_case() {
    local mesh=$1 levels=$2 boundary=${3:-edge-only}
    have_mesh "$mesh" || return
    strata_levels butterfly "$mesh" "$levels" "$boundary" "$TMP/s" || return
    oracle_levels "$OM" "$mesh" "$levels" "$TMP/om" --scheme butterfly || return
    compare_levels "$(basename "$mesh") $boundary vs OpenMesh" "$levels" "$TMP/s" "$TMP/om"
}

# disk N OUT.obj: open two-ring disk: centre (interior, valence N), ring 1
# of N interior vertices (valence 5), ring 2 of N boundary vertices.
disk() {
    awk -v n="$1" 'BEGIN {
        pi = atan2(0, -1)
        printf "v 0 0 0.5\n"
        for (k = 0; k < n; k++) printf "v %.17g %.17g %.17g\n", cos(2 * pi * k / n), sin(2 * pi * k / n), 0.3 * cos(6 * pi * k / n)
        for (k = 0; k < n; k++) printf "v %.17g %.17g %.17g\n", 2 * cos(2 * pi * (k + 0.5) / n), 2 * sin(2 * pi * (k + 0.5) / n), 0.1 * (k % 4)
        for (k = 0; k < n; k++) {
            r1 = k + 2; r1n = (k + 1) % n + 2; r2 = n + k + 2; r2p = n + (k + n - 1) % n + 2
            printf "f 1 %d %d\nf %d %d %d\nf %d %d %d\n", r1, r1n, r1, r2, r1n, r1, r2p, r2
        }
    }' >"$2"
}

T=$MESHES/triangle
# Closed meshes.
run_case "$T/sphere_ico.obj" 4
run_case "$T/spot_low_resolution.obj" 3
run_case "$T/bob_small.ply" 3
# Open meshes (the boundary option does not apply to this scheme: one run
# with each to show it changes nothing).
run_case "$T/hemisphere.obj" 3 edge-only
run_case "$T/hemisphere.obj" 2 edge-and-corner
run_case "$T/cube_no_bottom.obj" 4
run_case "$T/hand_lowres.obj" 3
# High valence, closed and open; boundary corners of valence 2 and 3.
bipyramid 14 "$TMP/bipyramid14.obj" 0.2; run_case "$TMP/bipyramid14.obj" 4
bipyramid 60 "$TMP/bipyramid60.obj" 0.2; run_case "$TMP/bipyramid60.obj" 3
disk 13 "$TMP/disk13.obj"; run_case "$TMP/disk13.obj" 4
tri_grid 5 "$TMP/tri_grid.obj"; run_case "$TMP/tri_grid.obj" 4

oracle_done
