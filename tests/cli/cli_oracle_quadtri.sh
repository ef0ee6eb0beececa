#!/usr/bin/env bash
# Quad/triangle subdivision through the strata CLI.  No library implements
# Stam & Loop's scheme, so it is checked through its reductions, against
# OpenSubdiv 3.5 (osd_oracle):
#   - meshes without triangles (quads and n-gons) == Catmull-Clark,
#   - meshes of triangles == Loop,
# with both boundary conventions on open meshes; and on mixed meshes (no
# oracle) every level is written and has the expected face counts.
#
#   cli_oracle_quadtri.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Comparisons as point sets (tests/cli/oracle_lib.sh).  Skips (exit 0, with a
# note) when osd_oracle or pointset_diff is not built; exits 77 (skipped)
# when a mesh of ../shared/data is missing.
set -u
. "$(dirname "$0")/oracle_lib.sh"
oracle_init quadtri "$@"
need_oracle OSD osd_oracle

# run_case MESH LEVELS BOUNDARY OSD_SCHEME
run_case() {
    local mesh=$1 levels=$2 boundary=$3 ref=$4
    have_mesh "$mesh" || return
    strata_levels quad-triangle "$mesh" "$levels" "$boundary" "$TMP/s" || return
    oracle_levels "$OSD" "$mesh" "$levels" "$TMP/osd" --scheme "$ref" --boundary "$boundary" || return
    compare_levels "$(basename "$mesh") $boundary vs OpenSubdiv $ref" "$levels" "$TMP/s" "$TMP/osd"
}

# face_sizes MESH: "tris quads others" of an OBJ or OFF file.
face_sizes() {
    case "$1" in
    *.off) awk 'NR == 1 && $1 ~ /OFF/ { next } !h && NF >= 2 { nv = $1; nf = $2; h = 1; next }
               h && /^[^#]/ && NF > 0 { if (nv > 0) { nv--; next } if (nf > 0) { nf--; k[$1 == 3 ? 3 : $1 == 4 ? 4 : 5]++ } }
               END { printf "%d %d %d\n", k[3], k[4], k[5] }' "$1" ;;
    *) awk '/^f / { n = NF - 1; k[n == 3 ? 3 : n == 4 ? 4 : 5]++ } END { printf "%d %d %d\n", k[3], k[4], k[5] }' "$1" ;;
    esac
}

# mixed_case MESH LEVELS: levels 1..LEVELS written; level 1 has 4 triangles
# per triangle and quads only otherwise (n per n-gon), each next level 4x.
mixed_case() {
    local mesh=$1 levels=$2 name l t q o et eq got
    name=$(basename "$mesh")
    have_mesh "$mesh" || return
    read -r t q o <<<"$(face_sizes "$mesh")"
    # Σ n over the n-gons (n > 4) from the file.
    case "$mesh" in
    *.off) o=$(awk 'NR == 1 && $1 ~ /OFF/ { next } !h && NF >= 2 { nv = $1; nf = $2; h = 1; next }
                   h && /^[^#]/ && NF > 0 { if (nv > 0) { nv--; next } if (nf > 0) { nf--; if ($1 > 4) s += $1 } }
                   END { print s + 0 }' "$mesh") ;;
    *) o=$(awk '/^f / && NF - 1 > 4 { s += NF - 1 } END { print s + 0 }' "$mesh") ;;
    esac
    et=$((4 * t)); eq=$((4 * q + o))
    strata_levels quad-triangle "$mesh" "$levels" edge-only "$TMP/m" || return
    for l in $(seq 1 "$levels"); do
        got=$(face_sizes "$TMP/m_$l.obj")
        cases=$((cases + 1))
        if [ "$got" = "$et $eq 0" ]; then
            printf 'ok    %-62s tris quads = %s %s\n' "$name L$l mixed (face counts only)" "$et" "$eq"
        else
            fail_case "$(printf '%-62s got %s, want %s %s 0' "$name L$l mixed" "$got" "$et" "$eq")"
        fi
        et=$((4 * et)); eq=$((4 * eq))
    done
}

C=$MESHES/catmull_clark
T=$MESHES/triangle
# No triangles: Catmull-Clark (n-gons included).
run_case "$ASSETS/cube.obj" 3 edge-only catmark
run_case "$ASSETS/ngon.obj" 3 edge-only catmark
run_case "$C/dodecahedron_poly.obj" 3 edge-only catmark
run_case "$C/hexa_sphere.off" 2 edge-only catmark
for b in edge-only edge-and-corner; do
    run_case "$ASSETS/open.obj" 3 "$b" catmark
    run_case "$C/hole_capsule.off" 3 "$b" catmark
done
# Triangles only: Loop.
run_case "$T/sphere_ico.obj" 3 edge-only loop
tri_grid 5 "$TMP/tri_grid.obj"
for b in edge-only edge-and-corner; do
    run_case "$T/cube_no_bottom.obj" 3 "$b" loop
    run_case "$TMP/tri_grid.obj" 3 "$b" loop
done
# Mixed meshes: no oracle (tests/core/test_scheme_quadtri.c checks values).
mixed_case "$ASSETS/mixed.obj" 3
mixed_case "$C/chamfer_cube.off" 3
mixed_case "$C/blub_control_mesh.obj" 2
mixed_case "$C/newell_teapot_cage.obj" 2
mixed_case "$C/mixed_faring.off" 1

oracle_done
