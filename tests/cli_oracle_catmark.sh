#!/usr/bin/env bash
# Catmull-Clark against OpenSubdiv 3.5 (Far::TopologyRefiner + PrimvarRefiner):
# levels 1..4 as point sets (max nearest-neighbour distance <= 1e-6 of the
# bounding-box diagonal) with equal face counts; closed and open meshes, both
# boundary conventions, creases and corners, n-gons, high valence.
# Usage: cli_oracle_catmark.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 D=$2 A=$3 B=$4
O=$B/oracles
W=$B/cli_oracle_catmark
if [ ! -x "$O/osd_oracle" ] || [ ! -x "$O/pointset_diff" ]; then
    echo "skipped: oracles not built"; exit 0
fi
mkdir -p "$W"
fail=0 n=0
compare() { # mesh levels boundary label
    local mesh=$1 levels=$2 bnd=$3 label=$4
    "$O/osd_oracle" "$mesh" --scheme catmark --levels "$levels" --boundary "$bnd" --out-prefix "$W/$label" >/dev/null
    for l in $(seq 1 "$levels"); do
        "$S" subdivide "$mesh" --scheme catmull-clark --levels "$levels" --level "$l" --boundary "$bnd" -o "$W/${label}_st_$l.obj"
        n=$((n + 1))
        if out=$("$O/pointset_diff" "$W/${label}_$l.obj" "$W/${label}_st_$l.obj" --tol 1e-6); then
            echo "ok   $label level $l: $out"
        else
            echo "FAIL $label level $l: $out"; fail=$((fail + 1))
        fi
    done
}
# A cube with a semi-sharp crease loop, a fractional crease and a corner.
cat > "$W/creased_cube.obj" <<'OBJ'
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
t crease 2/1/0 4 5 2.5
t crease 2/1/0 5 6 2.5
t crease 2/1/0 6 7 2.5
t crease 2/1/0 7 4 2.5
t crease 2/1/0 0 1 0.5
t corner 1/1/0 2 1.7
OBJ
# A fan with one vertex of valence 16 (an open disk).
{
    echo "v 0 0 0.3"
    for i in $(seq 0 15); do
        awk -v i="$i" 'BEGIN { a = 2 * 3.14159265358979 * i / 16; printf "v %.17g %.17g %.17g\n", cos(a), sin(a), 0.1 * (i % 3) }'
    done
    for i in $(seq 0 15); do echo "f 1 $((i + 2)) $(( (i + 1) % 16 + 2 ))"; done
} > "$W/fan16.obj"
compare "$D/catmull_clark/blub_control_mesh.obj" 4 edge-only blub
compare "$D/catmull_clark/dodecahedron_poly.obj" 3 edge-only dodeca
compare "$D/catmull_clark/chamfer_cube.off" 3 edge-only chamfer
compare "$D/catmull_clark/hole_capsule.off" 3 edge-only capsule_eo
compare "$D/catmull_clark/hole_capsule.off" 3 edge-and-corner capsule_ec
compare "$D/catmull_clark/mixed_faring.off" 2 edge-only faring
compare "$D/catmull_clark/hexa_sphere.off" 2 edge-only hexa
compare "$W/creased_cube.obj" 4 edge-only creased
compare "$W/fan16.obj" 3 edge-and-corner fan16_ec
compare "$W/fan16.obj" 3 edge-only fan16_eo
compare "$A/open.obj" 3 edge-and-corner open_ec
compare "$A/ngon.obj" 3 edge-only ngon
echo "$((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
