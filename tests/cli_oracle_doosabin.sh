#!/usr/bin/env bash
# Doo-Sabin against CGAL 5.5 Subdivision_method_3::DooSabin_subdivision
# (original weights): levels 1..4 as point sets (<= 1e-6 of the bbox
# diagonal) with equal vertex and face counts, on closed meshes (CGAL drops
# the faces along a boundary); open meshes by Strata's boundary rule.
# Usage: cli_oracle_doosabin.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 D=$2 A=$3 B=$4
O=$B/oracles
W=$B/cli_oracle_doosabin
if [ ! -x "$O/cgal_oracle" ] || [ ! -x "$O/pointset_diff" ]; then
    echo "skipped: oracles not built"; exit 0
fi
mkdir -p "$W"
fail=0 n=0
compare() { # mesh levels label
    "$O/cgal_oracle" "$1" --scheme doo-sabin --levels "$2" --out-prefix "$W/$3" >/dev/null 2>&1
    for l in $(seq 1 "$2"); do
        "$S" subdivide "$1" --scheme doo-sabin --levels "$2" --level "$l" -o "$W/${3}_st_$l.obj"
        n=$((n + 1))
        if out=$("$O/pointset_diff" "$W/${3}_$l.obj" "$W/${3}_st_$l.obj" --tol 1e-6); then echo "ok   $3 level $l: $out"
        else echo "FAIL $3 level $l: $out"; fail=$((fail + 1)); fi
    done
}
compare "$D/catmull_clark/blub_control_mesh.obj" 4 blub
compare "$D/catmull_clark/dodecahedron_poly.obj" 4 dodeca
compare "$D/catmull_clark/chamfer_cube.off" 3 chamfer
compare "$D/catmull_clark/hexa_sphere.off" 2 hexa
compare "$D/triangle/bob_small.ply" 2 bob
compare "$A/torus.obj" 3 torus
compare "$A/tetrahedron.obj" 4 tetra
# Open meshes (Strata's boundary rule, tests/test_doosabin_open.c checks the
# formulas): subdivided, with one face per face, edge and vertex below and the
# hole kept; adaptive Doo-Sabin refuses them with a message.
n=$((n + 1))
if "$S" subdivide "$A/open.obj" --scheme doo-sabin --levels 2 -o "$W/open.obj" 2>"$W/open.err" &&
   info=$("$S" info "$A/open.obj" --scheme doo-sabin --levels 2) &&
   echo "$info" | grep -Eq '^ +1 +96 +176 +81 +1 +1 ' && echo "$info" | grep -Eq '^ +2 +384 +736 +353 +1 +1 '; then
    echo "ok   open mesh: levels 1 and 2 have 81 and 353 faces around one hole"
else echo "FAIL open mesh: $(cat "$W/open.err") $info"; fail=$((fail + 1)); fi
n=$((n + 1))
if "$S" adapt "$A/open.obj" --scheme doo-sabin --base-level 0 --max-level 2 --box -0.5,-0.5,-0.5,0.5,0.5,0.5 -o "$W/open_adapt.obj" 2>"$W/open_adapt.err"; then
    echo "FAIL adaptive doo-sabin accepted an open mesh"; fail=$((fail + 1))
elif grep -q "open meshes is not supported" "$W/open_adapt.err"; then echo "ok   adaptive open mesh refused: $(cat "$W/open_adapt.err")"
else echo "FAIL adaptive open mesh message: $(cat "$W/open_adapt.err")"; fail=$((fail + 1)); fi
echo "$((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
