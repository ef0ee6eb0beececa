#!/usr/bin/env bash
# The memory guard on every command: an operation whose estimated memory is
# over the budget is refused from the counts, within a second, with the
# estimate and the limit in the message, exit status 1, and nothing written;
# under the budget the same command runs.  (The estimates themselves are
# checked against measured peaks by tests/core/test_membudget.c.)
# Usage: cli_membudget.sh STRATA SHARED_MESHES ASSETS BINDIR
set -euo pipefail
S=$1 D=$2 A=$3 B=$4
W=$B/cli_membudget
rm -rf "$W"; mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
KOALA=$D/large/koala.obj SPOT=$D/catmull_clark/spot_quadrangulated.obj BLUB=$D/catmull_clark/blub_control_mesh.obj

# refused LABEL OUTFILE CMD...: exit 1 within 1 s of processor time after
# loading (the limit allows for loading koala, about 1 s itself; processor
# time, not wall time, so that a loaded machine does not fail it), message,
# OUTFILE absent.
refused() {
    local label=$1 out=$2; shift 2
    local rc=0 cpu
    cpu=$( { TIMEFORMAT='%U %S'; time "$@" >"$W/$label.out" 2>"$W/$label.err"; } 2>&1 ) || rc=$?
    if [ "$rc" = 1 ]; then ok "$label: exit 1"; else bad "$label: exit $rc"; fi
    if grep -q "needs about .* MiB more (estimate).*memory budget is" "$W/$label.err"; then ok "$label: message"; else bad "$label: message: $(cat "$W/$label.err")"; fi
    if [ -z "$out" ] || [ ! -e "$out" ]; then ok "$label: nothing written"; else bad "$label: $out written"; fi
    if awk -v t="$cpu" 'BEGIN { split(t, a, " "); exit !(a[1] + a[2] < 3.0) }'; then ok "$label: $cpu s processor time"; else bad "$label: took $cpu s processor time"; fi
}

# Koala at Loop depth 7 is 1.6 billion faces (~120 GiB): refused on any machine here.
refused info_koala7 "" "$S" info "$KOALA" --scheme loop --levels 7
refused subdivide_koala6 "$W/k6.ply" "$S" subdivide "$KOALA" --scheme loop --levels 6 -o "$W/k6.ply"
refused convert_spot "$W/spot.strata" "$S" convert "$SPOT" "$W/spot.strata" --levels 4 --mem-budget 64
refused render_spot "$W/spot.png" "$S" render "$SPOT" --levels 5 --mem-budget 100 -o "$W/spot.png"
# render's image: framebuffers, pixels and the PNG encoder, counted before
# anything is read or allocated (8192x8192: about 1.8 GiB).
refused render_8k "$W/big.png" "$S" render "$A/cube.obj" --size 8192x8192 --mem-budget 30 -o "$W/big.png"
refused adapt_blub12 "$W/blub12.obj" "$S" adapt "$BLUB" --scheme catmull-clark --base-level 0 --max-level 12 \
    --box 0,0.5,0,0.2,0.7,0.2 --mem-budget 500 -o "$W/blub12.obj"
refused render_box "$W/box.png" "$S" render "$BLUB" --box 0,0.5,0,0.2,0.7,0.2 --base-level 0 --max-level 12 \
    --mem-budget 500 -o "$W/box.png"
refused convert_box "$W/box.obj" "$S" convert "$BLUB" "$W/box.obj" --box 0,0.5,0,0.2,0.7,0.2 --base-level 0 \
    --max-level 12 --mem-budget 500
# rebuild: the progressive hierarchy of koala, and the levels unsubdivide
# finds in spot subdivided three times
refused rebuild_koala "$W/k.strata" "$S" rebuild "$KOALA" --method progressive --mem-budget 20 -o "$W/k.strata"
"$S" subdivide "$SPOT" --scheme catmull-clark --levels 3 -o "$W/spot3.obj" >/dev/null
refused rebuild_spot "$W/s.strata" "$S" rebuild "$W/spot3.obj" --method unsubdivide --mem-budget 20 -o "$W/s.strata"
# reading: a mesh file (a bound of 7 times its bytes) and a session (4
# times), before the file is read
refused load_koala "" "$S" info "$KOALA" --mem-budget 15
"$S" rebuild "$KOALA" --target-faces 20000 -o "$W/k20.strata" >/dev/null 2>&1
refused load_session "$W/kf.obj" "$S" filter "$W/k20.strata" --gains 1,0 --mem-budget 12 -o "$W/kf.obj"
if "$S" filter "$W/k20.strata" --gains 1,0 -o "$W/kf.obj" >/dev/null 2>&1 && [ -s "$W/kf.obj" ]; then
    ok "filter under the budget"; else bad "filter under the budget"; fi

# Under the budget the same commands run.
if "$S" info "$SPOT" --levels 2 --mem-budget 500 >/dev/null; then ok "info under the budget"; else bad "info under the budget"; fi
if "$S" adapt "$BLUB" --scheme catmull-clark --base-level 0 --max-level 7 --box 0,0.5,0,0.2,0.7,0.2 --mem-budget 500 \
    -o "$W/blub7.obj" >/dev/null && [ -s "$W/blub7.obj" ]; then ok "adapt under the budget"; else bad "adapt under the budget"; fi
# A bad budget is a usage error.
rc=0; "$S" info "$SPOT" --mem-budget nope >/dev/null 2>&1 || rc=$?
if [ "$rc" = 2 ]; then ok "--mem-budget nope: exit 2"; else bad "--mem-budget nope: exit $rc"; fi

echo "$((n - fail)) passed, $fail failed"
[ "$fail" = 0 ]
