#!/usr/bin/env bash
# Self-check of the reference programs: the libraries must agree with each other (and with
# rules_reference.py, the executable form of docs/SUBDIVISION-RULES.md) where they should.
# Usage: oracle_selfcheck.sh ORACLE_DIR SHARED_MESH_DIR WORK_DIR
# Skips (exit 0 with a message) any check whose program was not built.
set -euo pipefail
O=$1 D=$2 W=$3/oracle_selfcheck
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$W"
cd "$W"
TOL=1e-12
fail=0
have() { [ -x "$O/$1" ]; }
check() { # label A B
    local out
    if out=$("$O/pointset_diff" "$2" "$3" --tol $TOL); then
        echo "ok   $1: $out"
    else
        echo "FAIL $1: $out"
        fail=1
    fi
}

if have osd_oracle && have cgal_oracle && have openmesh_oracle; then
    "$O/osd_oracle" "$D/triangle/sphere_ico.obj" --scheme loop --levels 2 --out-prefix osd_loop 2>/dev/null
    "$O/cgal_oracle" "$D/triangle/sphere_ico.obj" --scheme loop --levels 2 --out-prefix cgal_loop 2>/dev/null
    "$O/openmesh_oracle" "$D/triangle/sphere_ico.obj" --scheme loop --levels 2 --out-prefix om_loop 2>/dev/null
    check "loop closed osd/cgal" osd_loop_2.obj cgal_loop_2.obj
    check "loop closed osd/openmesh" osd_loop_2.obj om_loop_2.obj
    "$O/osd_oracle" "$D/triangle/cube_no_bottom.obj" --scheme loop --levels 2 --out-prefix osd_loopo 2>/dev/null
    "$O/cgal_oracle" "$D/triangle/cube_no_bottom.obj" --scheme loop --levels 2 --out-prefix cgal_loopo 2>/dev/null
    check "loop open osd/cgal" osd_loopo_2.obj cgal_loopo_2.obj
    "$O/osd_oracle" "$D/catmull_clark/blub_control_mesh.obj" --scheme catmark --levels 2 --out-prefix osd_cc 2>/dev/null
    "$O/openmesh_oracle" "$D/catmull_clark/blub_control_mesh.obj" --scheme catmull-clark --levels 2 --out-prefix om_cc 2>/dev/null
    check "cc closed osd/openmesh" osd_cc_2.obj om_cc_2.obj
    "$O/osd_oracle" "$D/catmull_clark/hole_capsule.off" --scheme catmark --levels 2 --out-prefix osd_cco 2>/dev/null
    "$O/cgal_oracle" "$D/catmull_clark/hole_capsule.off" --scheme catmull-clark --levels 2 --out-prefix cgal_cco 2>/dev/null
    check "cc open osd(edge-only)/cgal" osd_cco_2.obj cgal_cco_2.obj
    "$O/cgal_oracle" "$D/triangle/cube_no_bottom.obj" --scheme sqrt3 --levels 3 --out-prefix cgal_s3 2>/dev/null
    "$O/openmesh_oracle" "$D/triangle/cube_no_bottom.obj" --scheme sqrt3 --levels 3 --out-prefix om_s3 2>/dev/null
    check "sqrt3 open cgal/openmesh" cgal_s3_3.obj om_s3_3.obj
    "$O/cgal_oracle" "$D/reference/lagrange_sqrt3/sphere.ply" --scheme sqrt3 --levels 1 --out-prefix cgal_sph 2>/dev/null
    check "sqrt3 cgal/lagrange golden" cgal_sph_1.obj "$D/reference/lagrange_sqrt3/sphere_sqrt3.ply"
else
    echo "skip: not all oracles built"
fi

if have osd_oracle && command -v python3 >/dev/null; then
    cat > creased_cube.obj <<'EOF'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
t crease 2/1/0 4 5 2.5
t crease 2/1/0 5 6 1.0
t crease 2/1/0 6 7 0.5
t crease 2/1/0 7 4 3.2
t crease 2/1/0 0 1 1.7
t crease 2/1/0 1 2 0.3
t corner 1/1/0 3 1.5
t corner 1/1/0 0 0.6
EOF
    for m in uniform chaikin; do
        "$O/osd_oracle" creased_cube.obj --scheme catmark --levels 3 --creasing $m --out-prefix osd_cr_$m 2>/dev/null
        python3 "$HERE/rules_reference.py" creased_cube.obj --scheme catmark --levels 3 --creasing $m --out-prefix ref_cr_$m
        check "creases ($m) osd/rules_reference" osd_cr_${m}_3.obj ref_cr_${m}_3.obj
    done
fi
exit $fail
