# What the tests/cli/cli_oracle_*.sh scripts share (sourced).  A script says
# only what differs: its meshes, levels, boundary rules and oracles.
#
#   . "$(dirname "$0")/oracle_lib.sh"
#   oracle_init NAME "$@"           EXE MESHES ASSETS BIN from the arguments
#                                   (STRATA_EXE SHARED_MESH_DIR ASSETS_DIR
#                                   BINARY_TEST_DIR), TOL (default 1e-6), TMP
#   need_oracle OSD osd_oracle      the program's path in OSD, or the script
#                                   is skipped (exit 0 with a note)
#   strata_levels SCHEME MESH N BOUNDARY PREFIX   strata's levels 1..N
#   oracle_levels "$OSD" MESH N PREFIX ARGS...    the oracle's levels 1..N
#   compare_levels LABEL N PREFIX_A PREFIX_B      one comparison per level
#   oracle_done                     totals; the exit status of the script
#
# A comparison (pointset_diff): equal vertex and face counts, equal face-size
# histograms, max nearest-neighbour distance <= TOL x the bounding-box
# diagonal; every case prints its measured error.

# find_oracle NAME: path of an oracle program (built in <build>/tests/oracles).
find_oracle() {
    for d in "$BIN/oracles" "$BIN/../oracles"; do
        if [ -x "$d/$1" ]; then echo "$d/$1"; return 0; fi
    done
    return 1
}

# oracle_init NAME EXE MESHES ASSETS BIN: the arguments, a temporary folder
# removed on exit, the counters, and pointset_diff (needed by every script).
oracle_init() {
    local name=$1
    EXE=$2 MESHES=$3 ASSETS=$4 BIN=$5
    TOL=${TOL:-1e-6}
    failures=0 cases=0 worst=0 skipped=0
    need_oracle DIFF pointset_diff
    TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_$name.XXXXXX")
    trap 'rm -rf "$TMP"' EXIT
}

# need_oracle VAR NAME: the path of oracle NAME into VAR, or skip the script.
need_oracle() {
    local path
    path=$(find_oracle "$2") || { echo "note: $2 not built, $0 skipped"; exit 0; }
    printf -v "$1" '%s' "$path"
}

# want_oracle VAR NAME: the same, but VAR is left empty (with a note) and the
# script goes on without the comparisons that need it.
want_oracle() {
    local path
    path=$(find_oracle "$2") || { echo "note: $2 not built, its comparisons skipped"; path=; }
    printf -v "$1" '%s' "$path"
}

# fail_case MESSAGE: one failed case.
fail_case() {
    echo "FAIL  $*"
    failures=$((failures + 1))
}

# have_mesh MESH: whether it exists (when not: counted as skipped, with a
# note; the script goes on and oracle_done exits 77 unless a case failed).
have_mesh() {
    [ -f "$1" ] && return 0
    echo "skipped: $1 missing"
    skipped=$((skipped + 1))
    return 1
}

# strata_levels SCHEME MESH N BOUNDARY PREFIX: `strata subdivide` at levels
# 1..N into PREFIX_1.obj .. PREFIX_N.obj (BOUNDARY may be empty: the
# scheme's own rule); fails the case and returns 1 at the first error.
strata_levels() {
    local scheme=$1 mesh=$2 levels=$3 boundary=$4 prefix=$5 l
    for l in $(seq 1 "$levels"); do
        if ! "$EXE" subdivide "$mesh" --scheme "$scheme" --levels "$l" ${boundary:+--boundary "$boundary"} \
             -o "${prefix}_$l.obj" >"$TMP/strata.log" 2>&1; then
            fail_case "strata subdivide $(basename "$mesh") --scheme $scheme level $l: $(cat "$TMP/strata.log")"
            return 1
        fi
    done
}

# oracle_levels PROGRAM MESH N PREFIX [ARGS...]: the oracle's levels 1..N
# into PREFIX_1.obj .. PREFIX_N.obj; fails the case and returns 1 on error.
oracle_levels() {
    local prog=$1 mesh=$2 levels=$3 prefix=$4
    shift 4
    if ! "$prog" "$mesh" --levels "$levels" --out-prefix "$prefix" "$@" >"$TMP/oracle.log" 2>&1; then
        fail_case "$(basename "$prog") on $(basename "$mesh"): $(tail -3 "$TMP/oracle.log")"
        return 1
    fi
}

# compare LABEL A B: point sets of two OBJ files within TOL of the bbox
# diagonal, equal counts; prints the measured error and keeps the worst.
compare() {
    local out rc err faces
    out=$("$DIFF" "$2" "$3" --tol "$TOL" 2>&1); rc=$?
    cases=$((cases + 1))
    err=$(sed -n 's/.*max_nn_rel=\([^ ]*\).*/\1/p' <<<"$out")
    faces=$(sed -n 's/.*faces A=\([0-9]*\) B=\([0-9]*\).*/\1\/\2/p' <<<"$out")
    worst=$(awk -v a="$worst" -v b="${err:-0}" 'BEGIN { print (b + 0 > a + 0) ? b : a }')
    if [ $rc -eq 0 ]; then
        printf 'ok    %-58s max_nn_rel=%s faces=%s\n' "$1" "$err" "$faces"
    else
        printf 'FAIL  %-58s %s\n' "$1" "$out"
        failures=$((failures + 1))
    fi
}

# compare_levels LABEL N PREFIX_A PREFIX_B: compare at levels 1..N.
compare_levels() {
    local l
    for l in $(seq 1 "$2"); do compare "$1 L$l" "$3_$l.obj" "$4_$l.obj"; done
}

# oracle_done: the totals; returns 1 when a case failed, else 77 (ctest's
# SKIP_RETURN_CODE) when a mesh was missing.
oracle_done() {
    echo "$cases comparisons, $failures failures, $skipped skipped; worst max_nn_rel $worst (tolerance $TOL)"
    [ "$failures" -eq 0 ] || return 1
    [ "$skipped" -eq 0 ] || return 77
}

# ---- generated meshes --------------------------------------------------------

# tri_grid N OUT.obj: open N x N grid of squares cut by one diagonal, bumpy
# z; corners (N,0) and (0,N) have a single face (edge-and-corner makes them
# corners), (0,0) and (N,N) two.
tri_grid() {
    awk -v n="$1" 'BEGIN {
        for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %d %d %.2f\n", i, j, 0.1 * ((i * 7 + j * 3) % 5)
        for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
            a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 2; d = a + n + 1
            printf "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d
        }
    }' >"$2"
}

# bipyramid N OUT.obj [WAVE]: closed; an equator of N vertices on the unit
# circle (valence 4, z = WAVE x (k mod 3)) and two poles (0, 0, +-1.5) of
# valence N.
bipyramid() {
    awk -v n="$1" -v wave="${3:-0}" 'BEGIN {
        pi = atan2(0, -1)
        for (k = 0; k < n; k++) printf "v %.17g %.17g %.17g\n", cos(2 * pi * k / n), sin(2 * pi * k / n), wave * (k % 3)
        printf "v 0 0 1.5\nv 0 0 -1.5\n"
        for (k = 0; k < n; k++) {
            a = k + 1; b = (k + 1) % n + 1
            printf "f %d %d %d\nf %d %d %d\n", a, b, n + 1, b, a, n + 2
        }
    }' >"$2"
}
