#!/usr/bin/env bash
# Doo-Sabin against CGAL 5.5 Subdivision_method_3::DooSabin_subdivision
# (original weights): levels 1..4 as point sets (<= 1e-6 of the bbox
# diagonal) with equal vertex and face counts, on closed meshes; open meshes
# are refused with a message (no boundary rule yet).
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
# Open meshes: a clear refusal, non-zero exit, no crash.
n=$((n + 1))
if "$S" subdivide "$A/open.obj" --scheme doo-sabin --levels 1 -o "$W/open.obj" 2>"$W/open.err"; then
    echo "FAIL open mesh accepted"; fail=$((fail + 1))
elif grep -q "open meshes are not supported" "$W/open.err"; then echo "ok   open mesh refused: $(cat "$W/open.err")"
else echo "FAIL open mesh message: $(cat "$W/open.err")"; fail=$((fail + 1)); fi
echo "$((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
