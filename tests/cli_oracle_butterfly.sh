#!/usr/bin/env bash
# Modified Butterfly through the strata CLI against OpenMesh 9's
# ModifiedButterflyT (openmesh_oracle), on closed and open meshes, plus
# generated meshes with high-valence vertices (12 to 60: OpenMesh grows its
# weight table past its initial 30 entries) and an open grid whose corners
# exercise the boundary 4-point rule at valence 2 and 3.
#
#   cli_oracle_butterfly.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Each case writes levels 1..N with `strata subdivide` and compares them as
# point sets (pointset_diff): equal vertex and face counts, equal face-size
# histograms, and max nearest-neighbour distance <= 1e-6 x the bounding-box
# diagonal.  The measured error of every case is printed.  Skips (exit 0,
# with a note) only when openmesh_oracle or pointset_diff is not built.
set -u
EXE=$1 MESHES=$2 ASSETS=$3 BIN=$4
TOL=1e-6
. "$(dirname "$0")/oracle_lib.sh"

OM=$(find_oracle openmesh_oracle) || { echo "note: openmesh_oracle not built, $0 skipped"; exit 0; }
DIFF=$(find_oracle pointset_diff) || { echo "note: pointset_diff not built, $0 skipped"; exit 0; }

TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_butterfly.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
failures=0
cases=0


# run_case MESH LEVELS [BOUNDARY]: strata levels 1..LEVELS vs OpenMesh.
run_case() {
    local mesh=$1 levels=$2 boundary=${3:-edge-only} name l
    name=$(basename "$mesh")
    if [ ! -f "$mesh" ]; then echo "note: $mesh missing, skipped"; return; fi
    for l in $(seq 1 "$levels"); do
        if ! "$EXE" subdivide "$mesh" --scheme butterfly --levels "$l" --boundary "$boundary" -o "$TMP/s_$l.obj" >"$TMP/strata.log" 2>&1; then
            echo "FAIL  strata subdivide $name level $l: $(cat "$TMP/strata.log")"
            failures=$((failures + 1))
            return
        fi
    done
    if ! "$OM" "$mesh" --scheme butterfly --levels "$levels" --out-prefix "$TMP/om" >"$TMP/om.log" 2>&1; then
        echo "FAIL  openmesh_oracle on $name: $(tail -3 "$TMP/om.log")"
        failures=$((failures + 1))
        return
    fi
    for l in $(seq 1 "$levels"); do compare "$name $boundary L$l vs OpenMesh" "$TMP/s_$l.obj" "$TMP/om_$l.obj"; done
}

# bipyramid N OUT.obj: closed, equator of N vertices (valence 4, wavy z),
# two poles of valence N.
bipyramid() {
    awk -v n="$1" 'BEGIN {
        pi = atan2(0, -1)
        for (k = 0; k < n; k++) printf "v %.17g %.17g %.17g\n", cos(2 * pi * k / n), sin(2 * pi * k / n), 0.2 * (k % 3)
        printf "v 0 0 1.5\nv 0 0 -1.5\n"
        for (k = 0; k < n; k++) {
            a = k + 1; b = (k + 1) % n + 1
            printf "f %d %d %d\nf %d %d %d\n", a, b, n + 1, b, a, n + 2
        }
    }' >"$2"
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

# tri_grid N OUT.obj: open grid of squares cut by one diagonal.
tri_grid() {
    awk -v n="$1" 'BEGIN {
        for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %d %d %.2f\n", i, j, 0.1 * ((i * 7 + j * 3) % 5)
        for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
            a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 2; d = a + n + 1
            printf "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d
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
bipyramid 14 "$TMP/bipyramid14.obj"; run_case "$TMP/bipyramid14.obj" 4
bipyramid 60 "$TMP/bipyramid60.obj"; run_case "$TMP/bipyramid60.obj" 3
disk 13 "$TMP/disk13.obj"; run_case "$TMP/disk13.obj" 4
tri_grid 5 "$TMP/tri_grid.obj"; run_case "$TMP/tri_grid.obj" 4

echo "$cases comparisons, $failures failures"
[ "$failures" -eq 0 ]
