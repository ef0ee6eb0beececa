# Shared by the tests/cli_oracle_*.sh scripts (sourced).  Needs BIN (the test
# binary folder) and TOL; keeps the counters `cases` and `failures`.

# find_oracle NAME: path of an oracle program (built in <build>/tests/oracles).
find_oracle() {
    for d in "$BIN/oracles" "$BIN/../oracles"; do
        if [ -x "$d/$1" ]; then echo "$d/$1"; return 0; fi
    done
    return 1
}

# compare LABEL A B: point sets of two OBJ files within TOL of the bbox
# diagonal, equal counts; prints the measured error.  Needs DIFF.
compare() {
    local out rc err faces
    out=$("$DIFF" "$2" "$3" --tol "$TOL" 2>&1); rc=$?
    cases=$((cases + 1))
    err=$(sed -n 's/.*max_nn_rel=\([^ ]*\).*/\1/p' <<<"$out")
    faces=$(sed -n 's/.*faces A=\([0-9]*\) B=\([0-9]*\).*/\1\/\2/p' <<<"$out")
    if [ $rc -eq 0 ]; then
        printf 'ok    %-58s max_nn_rel=%s faces=%s\n' "$1" "$err" "$faces"
    else
        printf 'FAIL  %-58s %s\n' "$1" "$out"
        failures=$((failures + 1))
    fi
}
