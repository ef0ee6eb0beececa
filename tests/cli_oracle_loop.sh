#!/usr/bin/env bash
# Loop subdivision through the strata CLI against OpenSubdiv 3.5 (osd_oracle),
# and against CGAL and OpenMesh on closed meshes (they have no corner rule and
# OpenMesh's Loop weight table stops at valence 50).
#
#   cli_oracle_loop.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Each case writes levels 1..N with `strata subdivide --level L` and compares
# them as point sets (pointset_diff): equal vertex and face counts, equal
# face-size histograms, and max nearest-neighbour distance <= 1e-6 x the
# bounding-box diagonal.  The measured error of every case is printed.
# Skips (exit 0, with a note) only when osd_oracle or pointset_diff is not built.
set -u
EXE=$1 MESHES=$2 ASSETS=$3 BIN=$4
TOL=1e-6
. "$(dirname "$0")/oracle_lib.sh"
SCHEME=loop

OSD=$(find_oracle osd_oracle) || { echo "note: osd_oracle not built, $0 skipped"; exit 0; }
DIFF=$(find_oracle pointset_diff) || { echo "note: pointset_diff not built, $0 skipped"; exit 0; }
CGAL=$(find_oracle cgal_oracle) || { CGAL=; echo "note: cgal_oracle not built, CGAL comparisons skipped"; }
OM=$(find_oracle openmesh_oracle) || { OM=; echo "note: openmesh_oracle not built, OpenMesh comparisons skipped"; }

TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_loop.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
failures=0
cases=0

# compare LABEL OURS THEIRS: one line with the measured error.

# ours MESH LEVELS BOUNDARY PREFIX: writes PREFIX_1.obj .. PREFIX_N.obj.
ours() {
    local l
    for l in $(seq 1 "$2"); do
        if ! "$EXE" subdivide "$1" --scheme "$SCHEME" --levels "$l" --boundary "$3" -o "$4_$l.obj" >"$TMP/strata.log" 2>&1; then
            echo "FAIL  strata subdivide $1 level $l: $(cat "$TMP/strata.log")"
            failures=$((failures + 1))
            return 1
        fi
    done
}

# run_case MESH LEVELS BOUNDARY LIB: OpenSubdiv at levels 1..LEVELS, CGAL and
# OpenMesh (closed meshes only) at levels 1..LIB (0: not compared).
run_case() {
    local mesh=$1 levels=$2 boundary=$3 lib=$4 name l
    name=$(basename "$mesh")
    if [ ! -f "$mesh" ]; then echo "note: $mesh missing, skipped"; return; fi
    ours "$mesh" "$levels" "$boundary" "$TMP/s" || return
    if "$OSD" "$mesh" --scheme loop --levels "$levels" --boundary "$boundary" --out-prefix "$TMP/osd" >"$TMP/osd.log" 2>&1; then
        for l in $(seq 1 "$levels"); do compare "$name $boundary L$l vs OpenSubdiv" "$TMP/s_$l.obj" "$TMP/osd_$l.obj"; done
    else
        echo "FAIL  osd_oracle on $name: $(tail -3 "$TMP/osd.log")"; failures=$((failures + 1))
    fi
    [ "$lib" -gt 0 ] || return
    if [ -n "$CGAL" ]; then
        if "$CGAL" "$mesh" --scheme loop --levels "$lib" --out-prefix "$TMP/cgal" >"$TMP/cgal.log" 2>&1; then
            for l in $(seq 1 "$lib"); do compare "$name L$l vs CGAL" "$TMP/s_$l.obj" "$TMP/cgal_$l.obj"; done
        else
            echo "FAIL  cgal_oracle on $name: $(tail -3 "$TMP/cgal.log")"; failures=$((failures + 1))
        fi
    fi
    if [ -n "$OM" ]; then
        if "$OM" "$mesh" --scheme loop --levels "$lib" --out-prefix "$TMP/om" >"$TMP/om.log" 2>&1; then
            for l in $(seq 1 "$lib"); do compare "$name L$l vs OpenMesh" "$TMP/s_$l.obj" "$TMP/om_$l.obj"; done
        else
            echo "FAIL  openmesh_oracle on $name: $(tail -3 "$TMP/om.log")"; failures=$((failures + 1))
        fi
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

# make_tri_grid N OUT.obj: open N x N grid of squares cut by one diagonal,
# bumpy z; corners (N,0) and (0,N) have a single face (edge-and-corner makes
# them corners), (0,0) and (N,N) two.
make_tri_grid() {
    awk -v n="$1" 'BEGIN {
        for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %d %d %.2f\n", i, j, 0.1 * ((i * 7 + j * 3) % 5)
        for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
            a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 2; d = a + n + 1
            printf "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d
        }
    }' >"$2"
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
make_tri_grid 6 "$TMP/tri_grid.obj"
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

echo "$cases comparisons, $failures failures"
[ "$failures" -eq 0 ]
