#!/usr/bin/env bash
# Face-varying UVs against OpenSubdiv 3.5 (osd_fvar_oracle: Far::PrimvarRefiner::
# InterpolateFaceVarying): `strata subdivide --uv-interp NAME` at levels 1..3
# compared per face corner (the corner at the same vertex leading to the same
# next vertex has the same UV within TOL, absolute) on the shared meshes that
# carry vt and on generated ones with seams: a junction of three UV regions, a
# seam ending inside the mesh (a dart), a closed torus whose seams cross (four
# values at one vertex), their triangulations for Loop, an open grid with the
# edge-and-corner boundary rule; every FVarLinearInterpolation option.  The
# options must matter: on the generated meshes `none` and `all` differ.
#
#   cli_oracle_uv.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
set -u
. "$(dirname "$0")/oracle_lib.sh"
oracle_init uv "$@"
need_oracle FV osd_fvar_oracle
OPTS="none corners-only corners-plus1 corners-plus2 boundaries all"

# uv_case SCHEME MESH LEVELS INTERP [BOUNDARY]: strata vs OpenSubdiv per corner.
uv_case() {
    local scheme=$1 mesh=$2 levels=$3 interp=$4 boundary=${5:-edge-only} l out err osd=catmark
    [ "$scheme" = loop ] && osd=loop
    have_mesh "$mesh" || return
    if ! "$FV" "$mesh" --scheme "$osd" --levels "$levels" --uv-interp "$interp" --boundary "$boundary" \
         --out-prefix "$TMP/osd" >"$TMP/oracle.log" 2>&1; then
        cases=$((cases + 1)); fail_case "osd_fvar_oracle $(basename "$mesh"): $(tail -2 "$TMP/oracle.log")"; return
    fi
    for l in $(seq 1 "$levels"); do
        cases=$((cases + 1))
        if ! "$EXE" subdivide "$mesh" --scheme "$scheme" --levels "$l" --uv-interp "$interp" --boundary "$boundary" \
             -o "$TMP/s_$l.obj" >"$TMP/strata.log" 2>&1; then
            fail_case "strata subdivide $(basename "$mesh") L$l: $(cat "$TMP/strata.log")"; continue
        fi
        if out=$("$FV" --compare "$TMP/s_$l.obj" "$TMP/osd_$l.obj" --tol "$TOL"); then
            err=$(sed -n 's/.*max_uv_err=\([^ ]*\).*/\1/p' <<<"$out")
            worst=$(awk -v a="$worst" -v b="${err:-0}" 'BEGIN { print (b + 0 > a + 0) ? b : a }')
            printf 'ok    %-62s %s\n' "$(basename "$mesh") $scheme $interp $boundary L$l" "$(tail -1 <<<"$out")"
        else
            fail_case "$(basename "$mesh") $scheme $interp $boundary L$l: $out"
        fi
    done
}

# gen_grid KIND TRI: a 4 x 4 quad grid in z = 0 (TRI=1: each quad as two
# triangles) with UVs (x/4, y/4) cut by seams:
#   junction: three regions (x < 2; x >= 2 below y = 2; above) meet at (2,2);
#   dart: a cut along x = 2 from the boundary to (2,2), where it ends.
gen_grid() {
    awk -v kind="$1" -v tri="$2" 'BEGIN {
        n = 4
        for (y = 0; y <= n; y++) for (x = 0; x <= n; x++) printf "v %d %d %.3f\n", x, y, 0.05 * ((x * 7 + y * 3) % 5)
        nt = 0
        for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
            r = 0
            if (kind == "junction") r = (i < 2) ? 0 : (j < 2 ? 1 : 2)
            split(i " " (i + 1) " " (i + 1) " " i, cx, " "); split(j " " j " " (j + 1) " " (j + 1), cy, " ")
            for (k = 1; k <= 4; k++) {
                x = cx[k]; y = cy[k]; key = r ":" x ":" y
                if (kind == "dart" && i < 2 && x == 2 && y < 2) key = "cut:" x ":" y
                if (!(key in id)) {
                    id[key] = ++nt
                    u = x / n + (kind == "junction" && r > 0 ? 0.1 : 0) - (key ~ /^cut/ ? 0.05 : 0)
                    v = y / n + (r == 2 ? 0.1 : 0)
                    vt[nt] = u " " v
                }
                c[k] = (y * (n + 1) + x + 1) "/" id[key]
            }
            if (tri) face[++nf] = c[1] " " c[2] " " c[3] "\n" "f " c[1] " " c[3] " " c[4]
            else face[++nf] = c[1] " " c[2] " " c[3] " " c[4]
        }
        for (t = 1; t <= nt; t++) print "vt " vt[t]
        for (f = 1; f <= nf; f++) print "f " face[f]
    }'
}

# gen_torus TRI: a closed 6 x 4 torus, UVs (i/6, j/4) with the seams of a
# wrapped rectangle: they cross at vertex 0 (four values there).
gen_torus() {
    awk -v tri="$1" 'BEGIN {
        nu = 6; nv = 4; pi = 3.14159265358979
        for (i = 0; i < nu; i++) for (j = 0; j < nv; j++) {
            a = 2 * pi * i / nu; b = 2 * pi * j / nv
            printf "v %.17g %.17g %.17g\n", (2 + cos(b)) * cos(a), (2 + cos(b)) * sin(a), sin(b)
        }
        for (i = 0; i <= nu; i++) for (j = 0; j <= nv; j++) printf "vt %.17g %.17g\n", i / nu, j / nv
        for (i = 0; i < nu; i++) for (j = 0; j < nv; j++) {
            v1 = i * nv + j + 1; v2 = ((i + 1) % nu) * nv + j + 1
            v3 = ((i + 1) % nu) * nv + (j + 1) % nv + 1; v4 = i * nv + (j + 1) % nv + 1
            t1 = i * (nv + 1) + j + 1; t2 = (i + 1) * (nv + 1) + j + 1; t3 = t2 + 1; t4 = t1 + 1
            if (tri) { print "f " v1 "/" t1 " " v2 "/" t2 " " v3 "/" t3; print "f " v1 "/" t1 " " v3 "/" t3 " " v4 "/" t4 }
            else print "f " v1 "/" t1 " " v2 "/" t2 " " v3 "/" t3 " " v4 "/" t4
        }
    }'
}

gen_grid junction 0 >"$TMP/junction.obj"
gen_grid junction 1 >"$TMP/junction_tri.obj"
gen_grid dart 0 >"$TMP/dart.obj"
gen_grid dart 1 >"$TMP/dart_tri.obj"
gen_torus 0 >"$TMP/torus.obj"
gen_torus 1 >"$TMP/torus_tri.obj"

for o in $OPTS; do
    uv_case catmull-clark "$TMP/junction.obj" 3 "$o"
    uv_case catmull-clark "$TMP/dart.obj" 3 "$o"
    uv_case catmull-clark "$TMP/torus.obj" 3 "$o"
    uv_case catmull-clark "$TMP/junction.obj" 2 "$o" edge-and-corner
    uv_case loop "$TMP/junction_tri.obj" 3 "$o"
    uv_case loop "$TMP/dart_tri.obj" 3 "$o"
    uv_case loop "$TMP/torus_tri.obj" 3 "$o"
    uv_case catmull-clark "$MESHES/catmull_clark/blub_control_mesh.obj" 3 "$o"
    uv_case loop "$MESHES/triangle/sphere_ico.obj" 3 "$o"
    uv_case loop "$MESHES/triangle/cube_no_bottom.obj" 3 "$o"
done
uv_case catmull-clark "$MESHES/catmull_clark/spot_quadrangulated.obj" 2 corners-plus1
uv_case catmull-clark "$MESHES/catmull_clark/blub_quadrangulated.obj" 2 corners-plus1
uv_case loop "$MESHES/triangle/blub_open.obj" 2 corners-plus1
uv_case loop "$MESHES/triangle/blub_open.obj" 1 boundaries

# The options change the UVs (so the comparisons above can tell them apart).
for m in junction dart torus; do
    cases=$((cases + 1))
    "$EXE" subdivide "$TMP/$m.obj" --levels 2 --uv-interp none -o "$TMP/none.obj" &&
        "$EXE" subdivide "$TMP/$m.obj" --levels 2 --uv-interp all -o "$TMP/all.obj" || { fail_case "$m: subdivide"; continue; }
    if "$FV" --compare "$TMP/none.obj" "$TMP/all.obj" --tol "$TOL" >/dev/null; then
        fail_case "$m: --uv-interp none and all give the same UVs"
    else
        echo "ok    $m: --uv-interp none and all differ"
    fi
done
# A bad option name is refused.
cases=$((cases + 1))
if out=$("$EXE" subdivide "$TMP/dart.obj" --levels 1 --uv-interp sideways -o "$TMP/x.obj" 2>&1); then
    fail_case "--uv-interp sideways accepted"
elif [[ $out == *"--uv-interp wants none, corners-only"* ]]; then
    echo "ok    --uv-interp sideways refused: $out"
else
    fail_case "--uv-interp sideways: $out"
fi
echo "(the worst figure below is the largest UV difference per corner)"
oracle_done
