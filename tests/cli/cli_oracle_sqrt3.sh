#!/usr/bin/env bash
# √3 through the CLI against CGAL 5.5 and OpenMesh 9 (tests/oracles) and the
# lagrange golden step.
#
#   bash cli_oracle_sqrt3.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# For every mesh and level, `strata subdivide --scheme sqrt3 --levels L` is
# compared with both libraries as point sets (tests/cli/oracle_lib.sh), and up to
# 10000 faces their edge sets are compared (vertices matched by position),
# which checks the flips.  Closed meshes, open meshes (boundary rule: see
# core/schemes/scheme_sqrt3.c) and generated bipyramids with valence-16 and
# valence-64 apexes (OpenMesh's weight table stops at 50; the oracle widens
# it).  Prints the measured errors.  Skips (exit 0, with a note) when an
# oracle program is missing; exits 77 (skipped) when a mesh of ../shared/data
# is missing.
set -u
. "$(dirname "$0")/oracle_lib.sh"
oracle_init sqrt3 "$@"
need_oracle CGAL cgal_oracle
need_oracle OM openmesh_oracle

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

# sqrt3_case NAME IN LEVELS: levels 1..LEVELS against both libraries.
sqrt3_case() {
    local name=$1 in=$2 levels=$3 lib l same
    have_mesh "$in" || return
    strata_levels sqrt3 "$in" "$levels" "" "$TMP/${name}_strata" || return
    oracle_levels "$CGAL" "$in" "$levels" "$TMP/${name}_cgal" --scheme sqrt3 || return
    oracle_levels "$OM" "$in" "$levels" "$TMP/${name}_om" --scheme sqrt3 || return
    for lib in cgal om; do
        compare_levels "$name vs $lib" "$levels" "$TMP/${name}_strata" "$TMP/${name}_$lib"
        for l in $(seq 1 "$levels"); do
            # (edge sets only up to 10000 faces: awk is slow beyond)
            [ "$(grep -c '^f ' "$TMP/${name}_strata_$l.obj")" -le 10000 ] || continue
            cases=$((cases + 1))
            same=$(same_edges "$TMP/${name}_strata_$l.obj" "$TMP/${name}_${lib}_$l.obj")
            case $same in
                same*) echo "ok    edges of $name level $l: same as $lib (${same#same } edges)" ;;
                *) fail_case "edges of $name level $l vs $lib: $same" ;;
            esac
        done
    done
}

bipyramid 16 "$TMP/bipyramid16.obj"
bipyramid 64 "$TMP/bipyramid64.obj"

# Closed meshes.
sqrt3_case sphere_ico "$MESHES/triangle/sphere_ico.obj" 4
sqrt3_case spot "$MESHES/triangle/spot_low_resolution.obj" 3
sqrt3_case bob "$MESHES/triangle/bob_small.ply" 4
sqrt3_case bipyramid16 "$TMP/bipyramid16.obj" 4
sqrt3_case bipyramid64 "$TMP/bipyramid64.obj" 3
# Open meshes: boundary refined on even levels.
sqrt3_case cube_no_bottom "$MESHES/triangle/cube_no_bottom.obj" 4
sqrt3_case hemisphere "$MESHES/triangle/hemisphere.obj" 3
sqrt3_case hand "$MESHES/triangle/hand_lowres.obj" 3

# The lagrange golden step (one Kobbelt √3 step of sphere.ply), to 1e-9.
REF="$MESHES/reference/lagrange_sqrt3"
if strata_levels sqrt3 "$REF/sphere.ply" 1 "" "$TMP/lagrange"; then
    TOL=1e-9 compare "lagrange sphere_sqrt3" "$TMP/lagrange_1.obj" "$REF/sphere_sqrt3.ply"
fi

# Quads are refused with a message, not a crash.
cases=$((cases + 1))
"$EXE" subdivide "$MESHES/catmull_clark/chamfer_cube.off" --scheme sqrt3 --levels 1 -o "$TMP/q.obj" 2>"$TMP/log"
rc=$?
if [ $rc -ne 1 ] || ! grep -q "triangle" "$TMP/log"; then
    fail_case "quad input: exit $rc, message: $(cat "$TMP/log")"
else
    echo "ok    quad input refused: $(cat "$TMP/log")"
fi
oracle_done
