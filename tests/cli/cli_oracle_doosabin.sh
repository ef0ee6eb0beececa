#!/usr/bin/env bash
# Doo-Sabin against CGAL 5.5 Subdivision_method_3::DooSabin_subdivision
# (original weights): levels 1..4 as point sets (tests/cli/oracle_lib.sh) on
# closed meshes (CGAL drops the faces along a boundary); open meshes by
# Strata's boundary rule.
#
#   cli_oracle_doosabin.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
. "$(dirname "$0")/oracle_lib.sh"
oracle_init doosabin "$@"
need_oracle CGAL cgal_oracle

# run_case MESH LEVELS: strata levels 1..LEVELS vs CGAL.
run_case() {
    local mesh=$1 levels=$2
    have_mesh "$mesh" || return
    strata_levels doo-sabin "$mesh" "$levels" "" "$TMP/s" || return
    oracle_levels "$CGAL" "$mesh" "$levels" "$TMP/cgal" --scheme doo-sabin || return
    compare_levels "$(basename "$mesh") vs CGAL" "$levels" "$TMP/s" "$TMP/cgal"
}

run_case "$MESHES/catmull_clark/blub_control_mesh.obj" 4
run_case "$MESHES/catmull_clark/dodecahedron_poly.obj" 4
run_case "$MESHES/catmull_clark/chamfer_cube.off" 3
run_case "$MESHES/catmull_clark/hexa_sphere.off" 2
run_case "$MESHES/triangle/bob_small.ply" 2
run_case "$ASSETS/torus.obj" 3
run_case "$ASSETS/tetrahedron.obj" 4
# Open meshes (Strata's boundary rule, tests/core/test_doosabin_open.c checks the
# formulas): subdivided, with one face per face, edge and vertex below and the
# hole kept; adaptive Doo-Sabin refuses them with a message.
cases=$((cases + 1))
if "$EXE" subdivide "$ASSETS/open.obj" --scheme doo-sabin --levels 2 -o "$TMP/open.obj" 2>"$TMP/open.err" &&
   info=$("$EXE" info "$ASSETS/open.obj" --scheme doo-sabin --levels 2) &&
   echo "$info" | grep -Eq '^ +1 +96 +176 +81 +1 +1 ' && echo "$info" | grep -Eq '^ +2 +384 +736 +353 +1 +1 '; then
    echo "ok    open mesh: levels 1 and 2 have 81 and 353 faces around one hole"
else fail_case "open mesh: $(cat "$TMP/open.err") ${info:-}"; fi
cases=$((cases + 1))
if "$EXE" adapt "$ASSETS/open.obj" --scheme doo-sabin --base-level 0 --max-level 2 --box -0.5,-0.5,-0.5,0.5,0.5,0.5 \
       -o "$TMP/open_adapt.obj" 2>"$TMP/open_adapt.err"; then
    fail_case "adaptive doo-sabin accepted an open mesh"
elif grep -q "open meshes is not supported" "$TMP/open_adapt.err"; then
    echo "ok    adaptive open mesh refused: $(cat "$TMP/open_adapt.err")"
else fail_case "adaptive open mesh message: $(cat "$TMP/open_adapt.err")"; fi
oracle_done
