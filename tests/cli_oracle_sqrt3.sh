#!/usr/bin/env bash
# √3 through the CLI against CGAL 5.5 and OpenMesh 9 (tests/oracles) and the
# lagrange golden step.
#
#   bash cli_oracle_sqrt3.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# For every mesh and level, `strata subdivide --scheme sqrt3 --levels L` is
# compared with both libraries as point sets (pointset_diff: equal vertex and
# face counts, equal face-size histograms, symmetric nearest-neighbour
# distance <= 1e-6 of the bounding-box diagonal), and up to 10000 faces
# their edge sets are compared (vertices matched by position), which checks
# the flips.  Closed meshes, open meshes (boundary rule: see
# core/schemes/scheme_sqrt3.c) and generated bipyramids with valence-16 and
# valence-64 apexes (OpenMesh's weight table stops at 50; the oracle widens
# it).  Prints the measured errors.  Skips (exit 0, with a note) only when an
# oracle program is missing.
set -u
EXE=$1
MESHES=$2
BIN=$4
TOL=1e-6
. "$(dirname "$0")/oracle_lib.sh" # find_oracle

CGAL=$(find_oracle cgal_oracle) || { echo "SKIP: cgal_oracle not built (needs CGAL 5.5; see tests/oracles)"; exit 0; }
OM=$(find_oracle openmesh_oracle) || { echo "SKIP: openmesh_oracle not built (needs OpenMesh 9; see tests/oracles)"; exit 0; }
DIFF=$(find_oracle pointset_diff) || { echo "SKIP: pointset_diff not built"; exit 0; }

WORK=$(mktemp -d "${TMPDIR:-/tmp}/strata_sqrt3.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
fail=0
worst=0

# Generated bipyramid: n rim vertices on the unit circle, apexes (0,0,±1.5).
bipyramid() {
    awk -v n="$1" 'BEGIN {
        pi = atan2(0, -1)
        for (i = 0; i < n; i++) printf "v %.17g %.17g 0\n", cos(2 * pi * i / n), sin(2 * pi * i / n)
        printf "v 0 0 1.5\nv 0 0 -1.5\n"
        for (i = 0; i < n; i++) {
            a = i + 1; b = (i + 1) % n + 1
            printf "f %d %d %d\nf %d %d %d\n", a, b, n + 1, b, a, n + 2
        }
    }' > "$2"
}

# Same edges?  Every vertex of A is matched to the vertex of B within 1e-9
# (a hash grid of 1e-6 cells, 27 neighbours; meshes of unit size), then the
# edge sets are compared.  Prints "same N" or what differs.
same_edges() {
    awk '
    function cell(x) { return int(x >= 0 ? x / 1e-6 : x / 1e-6 - 1) }
    FNR == 1 { file++ }
    file == 1 && /^v / { na++; ax[na] = $2; ay[na] = $3; az[na] = $4 }
    file == 2 && /^v / { nb++; bx[nb] = $2; by[nb] = $3; bz[nb] = $4
        k = cell($2) " " cell($3) " " cell($4); grid[k] = grid[k] " " nb }
    /^f / {
        m = NF - 1
        for (i = 2; i <= NF; i++) { split($i, t, "/"); c[i - 1] = t[1] }
        for (i = 1; i <= m; i++) {
            a = c[i] + 0; b = c[i % m + 1] + 0
            if (a > b) { t0 = a; a = b; b = t0 }
            if (file == 1) ea[a " " b] = 1; else eb[a " " b] = 1
        }
    }
    END {
        if (na != nb) { print "differ: vertex counts " na " " nb; exit }
        for (i = 1; i <= na; i++) {
            cx = cell(ax[i]); cy = cell(ay[i]); cz = cell(az[i]); best = -1
            for (dx = -1; dx <= 1; dx++) for (dy = -1; dy <= 1; dy++) for (dz = -1; dz <= 1; dz++) {
                n = split(grid[(cx + dx) " " (cy + dy) " " (cz + dz)], L, " ")
                for (j = 1; j <= n; j++) {
                    q = L[j]; d = (ax[i] - bx[q]) ^ 2 + (ay[i] - by[q]) ^ 2 + (az[i] - bz[q]) ^ 2
                    if (d <= 1e-18 && (best < 0 || d < bd)) { best = q; bd = d }
                }
            }
            if (best < 0) { print "unmatched: vertex " i; exit }
            if (used[best]++) { print "differ: two vertices of A match vertex " best " of B"; exit }
            map[i] = best
        }
        ne = 0
        for (e in ea) {
            split(e, p, " "); a = map[p[1]]; b = map[p[2]]
            if (a > b) { t0 = a; a = b; b = t0 }
            if (!((a " " b) in eb)) { print "differ: edge " p[1] "-" p[2] " of A is not an edge of B"; exit }
            ne++
        }
        nbe = 0; for (e in eb) nbe++
        if (ne != nbe) { print "differ: " ne " edges vs " nbe; exit }
        print "same " ne
    }
    ' "$1" "$2"
}

# compare NAME IN LEVELS: levels 1..LEVELS against both libraries
sqrt3_compare() {
    local name=$1 in=$2 levels=$3
    "$CGAL" "$in" --scheme sqrt3 --levels "$levels" --out-prefix "$WORK/${name}_cgal" 2> "$WORK/log" ||
        { echo "FAIL: cgal_oracle on $name"; cat "$WORK/log"; fail=1; return; }
    "$OM" "$in" --scheme sqrt3 --levels "$levels" --out-prefix "$WORK/${name}_om" 2> "$WORK/log" ||
        { echo "FAIL: openmesh_oracle on $name"; cat "$WORK/log"; fail=1; return; }
    for ((L = 1; L <= levels; L++)); do
        local out="$WORK/${name}_strata_$L.obj"
        if ! "$EXE" subdivide "$in" --scheme sqrt3 --levels "$L" -o "$out" 2> "$WORK/log"; then
            echo "FAIL: strata subdivide $name --levels $L"; cat "$WORK/log"; fail=1; continue
        fi
        for lib in cgal om; do
            local line rc
            line=$("$DIFF" "$out" "$WORK/${name}_${lib}_$L.obj" --tol "$TOL"); rc=$?
            echo "$name level $L vs $lib: $line"
            [ $rc -eq 0 ] || { echo "FAIL: $name level $L differs from $lib beyond $TOL"; fail=1; }
            local rel
            rel=$(echo "$line" | sed -n 's/.*max_nn_rel=\([^ ]*\).*/\1/p')
            worst=$(awk -v a="$worst" -v b="${rel:-1}" 'BEGIN { print (b + 0 > a + 0) ? b : a }')
            # (edge sets only up to 10000 faces: awk is slow beyond)
            [ "$(grep -c '^f ' "$out")" -le 10000 ] || continue
            local same
            same=$(same_edges "$out" "$WORK/${name}_${lib}_$L.obj")
            case $same in
                same*) echo "  edges of $name level $L: same as $lib (${same#same } edges)" ;;
                *) echo "FAIL: edges of $name level $L vs $lib: $same"; fail=1 ;;
            esac
        done
    done
}

bipyramid 16 "$WORK/bipyramid16.obj"
bipyramid 64 "$WORK/bipyramid64.obj"

# Closed meshes.
sqrt3_compare sphere_ico "$MESHES/triangle/sphere_ico.obj" 4
sqrt3_compare spot "$MESHES/triangle/spot_low_resolution.obj" 3
sqrt3_compare bob "$MESHES/triangle/bob_small.ply" 4
sqrt3_compare bipyramid16 "$WORK/bipyramid16.obj" 4
sqrt3_compare bipyramid64 "$WORK/bipyramid64.obj" 3
# Open meshes: boundary refined on even levels.
sqrt3_compare cube_no_bottom "$MESHES/triangle/cube_no_bottom.obj" 4
sqrt3_compare hemisphere "$MESHES/triangle/hemisphere.obj" 3
sqrt3_compare hand "$MESHES/triangle/hand_lowres.obj" 3

# The lagrange golden step (one Kobbelt √3 step of sphere.ply).
REF="$MESHES/reference/lagrange_sqrt3"
if "$EXE" subdivide "$REF/sphere.ply" --scheme sqrt3 --levels 1 -o "$WORK/lagrange.obj" 2> "$WORK/log"; then
    line=$("$DIFF" "$WORK/lagrange.obj" "$REF/sphere_sqrt3.ply" --tol 1e-9); rc=$?
    echo "lagrange sphere_sqrt3: $line"
    [ $rc -eq 0 ] || { echo "FAIL: lagrange sphere_sqrt3 beyond 1e-9"; fail=1; }
else
    echo "FAIL: strata subdivide sphere.ply"; cat "$WORK/log"; fail=1
fi

# Quads are refused with a message, not a crash.
"$EXE" subdivide "$MESHES/catmull_clark/chamfer_cube.off" --scheme sqrt3 --levels 1 -o "$WORK/q.obj" 2> "$WORK/log"
rc=$?
if [ $rc -ne 1 ] || ! grep -q "triangle" "$WORK/log"; then
    echo "FAIL: quad input: exit $rc, message: $(cat "$WORK/log")"; fail=1
else
    echo "quad input refused: $(cat "$WORK/log")"
fi

echo "max relative point-set error over all oracle comparisons: $worst"
[ $fail -eq 0 ] && echo "cli_oracle_sqrt3: ok"
exit $fail
