#!/usr/bin/env bash
# Strata's whole test suite, as CI runs it (bash .ci/run -> this script).
#
#   bash scripts/test.sh [extra ctest arguments, e.g. -R test_map]
#
# Stages (each in its own build folder under the repo root):
#   release  Release build, -Werror, ctest                         build/release
#            then the kernel alone (STRATA_CORE_ONLY): configure with
#            no GL/window/image package looked for, build, quick tests  build/core-only
#   asan     Debug (-O1) build with ASan+UBSan, -Werror, ctest     build/asan
#   fuzz     clang + libFuzzer (+ASan/UBSan), every tests/fuzz/fuzz_*.c
#            run for FUZZ_SECONDS each on a copy of its seed corpus, as
#            many at once as there are cores                      build/fuzz
# Every stage runs even if an earlier one failed; the exit status is non-zero
# if any stage failed. The last line is "N passed, N failed": the ctest counts
# of all stages plus one test per fuzzer (plus one failure for each stage that
# failed outside ctest's count, e.g. a compile error or a stage time-out),
# with ", N skipped" after it when tests were skipped.  A test skips (exit
# 77, ctest's SKIP_RETURN_CODE) when its data (../shared/data) or OSMesa is
# missing; a skip is not a pass.  With CI=true any skip fails the run (CI
# has the data), and the skipped tests are named.
#
# Environment knobs:
#   STRATA_STAGES   which stages, default "release asan fuzz"
#   FUZZ_SECONDS    seconds per fuzzer, default 30
#   CTEST_TIMEOUT   per-test limit in seconds, default 900
#   RELEASE_CTEST_LIMIT / ASAN_CTEST_LIMIT  whole-ctest limits, default 900 / 1500
#   STRATA_XVFB     1 (default): run ctest under xvfb-run when $DISPLAY is unset,
#                   so tests that open a GLFW window have an X server; 0: don't
# A file tests/lsan.supp, if present, is used as LeakSanitizer suppressions.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

STAGES="${STRATA_STAGES:-release asan fuzz}"
FUZZ_SECONDS="${FUZZ_SECONDS:-30}"
CTEST_TIMEOUT="${CTEST_TIMEOUT:-900}"
RELEASE_CTEST_LIMIT="${RELEASE_CTEST_LIMIT:-900}"
ASAN_CTEST_LIMIT="${ASAN_CTEST_LIMIT:-1500}"
STRATA_XVFB="${STRATA_XVFB:-1}"
JOBS="$(nproc 2>/dev/null || echo 2)"
CTEST_EXTRA=("$@")

LOGDIR="$ROOT/build/logs"

TOTAL_PASSED=0
TOTAL_FAILED=0
TOTAL_SKIPPED=0
SKIPPED_TESTS=()
FAILED_STAGES=()
STAGE_RESULTS=()

log() { printf '\n==> %s\n' "$*"; }

bash "$ROOT/scripts/setup.sh"
bash "$ROOT/scripts/setup_node.sh" || echo "setup_node.sh failed: no glTF validator, tests/cli/cli_gltf.sh will fail"
mkdir -p "$LOGDIR"

# configure BUILD_DIR [cmake args...]: Ninja build folder; a folder configured
# earlier with another generator is wiped first.
configure() {
  local dir="$1"; shift
  local cache="$dir/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then
    log "$dir was configured with another generator; removing it"
    rm -rf "$dir"
  fi
  cmake -S "$ROOT" -B "$dir" -G Ninja "$@"
}

# run_ctest NAME BUILD_DIR LIMIT_SECONDS [VAR=VALUE...]: runs ctest with those
# variables set, adds its counts to the totals; returns non-zero if ctest
# failed, timed out or printed no summary.
run_ctest() {
  local name="$1" dir="$2" limit="$3"
  shift 3
  local logf="$LOGDIR/ctest-$name.log"
  local wrap=()
  if [ "$STRATA_XVFB" = 1 ] && [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null 2>&1; then
    wrap=(xvfb-run -a -s "-screen 0 1280x800x24")
  fi
  log "[$name] ctest (limit ${limit}s in all, ${CTEST_TIMEOUT}s per test${wrap:+, under xvfb-run})"
  local rc=0
  env "$@" timeout --kill-after=30 "$limit" ${wrap[@]+"${wrap[@]}"} \
    ctest --test-dir "$dir" --output-on-failure -j2 --timeout "$CTEST_TIMEOUT" \
      ${CTEST_EXTRA[@]+"${CTEST_EXTRA[@]}"} </dev/null 2>&1 | tee "$logf" || rc=$?
  local line
  line="$(grep -E '^[0-9]+% tests passed, [0-9]+ tests? failed out of [0-9]+' "$logf" | tail -n 1 || true)"
  if [ -n "$line" ]; then
    local failed total
    failed="$(sed -E 's/^[0-9]+% tests passed, ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")"
    total="$(sed -E 's/^[0-9]+% tests passed, ([0-9]+) tests? failed out of ([0-9]+).*/\2/' <<<"$line")"
    # ctest counts a skipped test (SKIP_RETURN_CODE) among the passed ones
    # in this line and names it under "The following tests did not run".
    local skipped=() t
    while IFS= read -r t; do skipped+=("$name: $t"); done < <(sed -nE 's/^[[:space:]]*[0-9]+ - ([^ ]+) \(Skipped\)$/\1/p' "$logf")
    TOTAL_PASSED=$((TOTAL_PASSED + total - failed - ${#skipped[@]}))
    TOTAL_FAILED=$((TOTAL_FAILED + failed))
    TOTAL_SKIPPED=$((TOTAL_SKIPPED + ${#skipped[@]}))
    SKIPPED_TESTS+=(${skipped[@]+"${skipped[@]}"})
    if [ "$rc" -ne 0 ] && [ "$failed" -eq 0 ]; then
      TOTAL_FAILED=$((TOTAL_FAILED + 1))   # ctest failed without a failed test
    fi
  elif grep -q 'No tests were found' "$logf"; then
    echo "[$name] ctest found no tests"
  else
    # No summary (killed by the time limit?): count the per-test result lines.
    local p f
    p="$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* Passed ' "$logf" || true)"
    f="$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*' "$logf" || true)"
    echo "[$name] ctest printed no summary (exit $rc); counted $p passed, $f failed from its log"
    TOTAL_PASSED=$((TOTAL_PASSED + p))
    TOTAL_FAILED=$((TOTAL_FAILED + f + 1))
    [ "$rc" -ne 0 ] || rc=1
  fi
  if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
    echo "[$name] ctest ran past its ${limit}s limit"
  fi
  return "$rc"
}

# ccache for the release and core-only builds: with CCACHE_BASEDIR at the
# repo root their commands for core's sources are the same (paths relative
# to build folders of the same depth), so the core-only build gets core from
# the cache instead of compiling it a second time.
CCACHE_ARGS=()
if command -v ccache >/dev/null 2>&1; then
  CCACHE_ARGS=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}"
fi

stage_release() {
  local dir="$ROOT/build/release" rc=0
  log "[release] configure"
  configure "$dir" -DCMAKE_BUILD_TYPE=Release -DSTRATA_WERROR=ON ${CCACHE_ARGS[@]+"${CCACHE_ARGS[@]}"} ||
    { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }
  log "[release] build (-j$JOBS)"
  cmake --build "$dir" -j"$JOBS" || { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }
  run_ctest release "$dir" "$RELEASE_CTEST_LIMIT" || rc=$?
  core_only || rc=1
  return "$rc"
}

# The kernel alone, as a machine without OpenGL, GLFW, ImGui or the image
# libraries builds it (-DSTRATA_CORE_ONLY=ON): the find_package calls those
# would need are disabled, and the cache must hold none of their find
# results afterwards; core, its tests and examples/ build with -Werror; the
# tests run except the long ones, which the release build has just run on
# the same sources.  About half a minute with core from ccache.
CORE_ONLY_LONG='^(test_membudget|test_adapt_uv|test_progressive_adapt|test_progressive|test_bake|test_unsubdivide|test_analysis|test_adapt_sqrt3)$'
core_only() {
  local dir="$ROOT/build/core-only" t0=$SECONDS
  log "[release] core only: configure"
  configure "$dir" -DCMAKE_BUILD_TYPE=Release -DSTRATA_WERROR=ON -DSTRATA_CORE_ONLY=ON -DSTRATA_ORACLES=OFF \
    -DCMAKE_DISABLE_FIND_PACKAGE_OpenGL=ON -DCMAKE_DISABLE_FIND_PACKAGE_glfw3=ON \
    -DCMAKE_DISABLE_FIND_PACKAGE_PNG=ON -DCMAKE_DISABLE_FIND_PACKAGE_PkgConfig=ON \
    ${CCACHE_ARGS[@]+"${CCACHE_ARGS[@]}"} || { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }
  local found
  found="$(grep -E '^(STRATA_(GL|OSMESA|STB|TINYEXR|TINYGLTF)_[A-Z]+|PNG_[A-Z_]+|GLFW3_[A-Z_]+|IMGUI_[A-Z_]+|OPENGL_[A-Z_]+|PKG_CONFIG_[A-Z_]+)(:|=)' "$dir/CMakeCache.txt" || true)"
  if [ -n "$found" ]; then
    echo "[release] core only: the configure looked for libraries core does not need:"
    echo "$found"
    TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1
  fi
  log "[release] core only: build (-j$JOBS)"
  cmake --build "$dir" -j"$JOBS" || { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }
  local saved=(${CTEST_EXTRA[@]+"${CTEST_EXTRA[@]}"}) rc=0
  CTEST_EXTRA=(-E "$CORE_ONLY_LONG" ${saved[@]+"${saved[@]}"})
  run_ctest core-only "$dir" "$RELEASE_CTEST_LIMIT" || rc=$?
  CTEST_EXTRA=(${saved[@]+"${saved[@]}"})
  echo "[release] core only: $((SECONDS - t0))s"
  return "$rc"
}

stage_asan() {
  local dir="$ROOT/build/asan"
  log "[asan] configure"
  configure "$dir" -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_C_FLAGS_DEBUG="-g -O1" -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
    -DSTRATA_SANITIZE=ON -DSTRATA_WERROR=ON || { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }
  log "[asan] build (-j$JOBS)"
  cmake --build "$dir" -j"$JOBS" || { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }
  local env=(
    "ASAN_OPTIONS=detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
    "UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
  )
  if [ -f "$ROOT/tests/lsan.supp" ]; then
    env+=("LSAN_OPTIONS=suppressions=$ROOT/tests/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}")
  fi
  run_ctest asan "$dir" "$ASAN_CTEST_LIMIT" "${env[@]}"
}

# running_fuzzers PID...: how many of these (empty ones skipped) still run.
running_fuzzers() {
  local n=0 p
  for p in "$@"; do [ -n "$p" ] && kill -0 "$p" 2>/dev/null && n=$((n + 1)); done
  echo "$n"
}

stage_fuzz() {
  local dir="$ROOT/build/fuzz"
  local srcs=() names=() s n
  shopt -s nullglob
  srcs=("$ROOT"/tests/fuzz/fuzz_*.c)
  shopt -u nullglob
  if [ "${#srcs[@]}" -eq 0 ]; then
    echo "[fuzz] no tests/fuzz/fuzz_*.c yet; nothing to fuzz"
    return 0
  fi
  for s in "${srcs[@]}"; do
    n="$(basename "$s" .c)"
    names+=("$n")
  done
  log "[fuzz] configure (clang, libFuzzer, ASan+UBSan)"
  configure "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DSTRATA_FUZZ=ON -DSTRATA_SANITIZE=ON -DSTRATA_ORACLES=OFF || { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }
  log "[fuzz] build ${names[*]} (-j$JOBS)"
  cmake --build "$dir" -j"$JOBS" --target "${names[@]}" || { TOTAL_FAILED=$((TOTAL_FAILED + 1)); return 1; }

  local status=0 exe seed work art rc dict
  rm -rf "$dir/artifacts"
  mkdir -p "$dir/artifacts"
  # The fuzzers run $JOBS at a time (each is one process on one core), each
  # into its own log; results are printed in the order of the names.
  local pids=() works=() i
  for ((i = 0; i < ${#names[@]}; i++)); do
    n="${names[$i]}"
    exe="$(find "$dir" -type f -name "$n" -perm -u+x | head -n 1)"
    if [ -z "$exe" ]; then
      echo "[fuzz] $n: executable not found after build"
      TOTAL_FAILED=$((TOTAL_FAILED + 1)); status=1; pids+=(""); works+=(""); continue
    fi
    # Work on a copy of the seed corpus so the repo is never modified.
    work="$(mktemp -d "${TMPDIR:-/tmp}/strata-$n.XXXXXX")"
    seed="$ROOT/tests/fuzz/corpus/${n#fuzz_}"
    if [ -d "$seed" ]; then
      cp -R "$seed"/. "$work"/
    fi
    art="$dir/artifacts/$n-"
    dict=()
    if [ -f "$ROOT/tests/fuzz/$n.dict" ]; then
      dict=(-dict="$ROOT/tests/fuzz/$n.dict")
    fi
    # At most $JOBS running at once.
    while [ "$(running_fuzzers "${pids[@]}")" -ge "$JOBS" ]; do sleep 1; done
    log "[fuzz] $n for ${FUZZ_SECONDS}s ($(find "$work" -type f | wc -l) seed inputs)"
    (
      cd "$dir"
      ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
      UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}" \
      timeout --kill-after=30 "$((FUZZ_SECONDS + 300))" \
        "$exe" -max_total_time="$FUZZ_SECONDS" -timeout=20 -rss_limit_mb=4096 \
          -print_final_stats=1 -artifact_prefix="$art" ${dict[@]+"${dict[@]}"} "$work" </dev/null
    ) > "$LOGDIR/$n.log" 2>&1 &
    pids+=("$!")
    works+=("$work")
  done
  for ((i = 0; i < ${#names[@]}; i++)); do
    [ -n "${pids[$i]}" ] || continue
    n="${names[$i]}"
    rc=0
    wait "${pids[$i]}" || rc=$?
    log "[fuzz] $n"
    tail -n 20 "$LOGDIR/$n.log"
    if [ "$rc" -eq 0 ]; then
      echo "[fuzz] $n: passed"
      TOTAL_PASSED=$((TOTAL_PASSED + 1))
    else
      echo "[fuzz] $n: FAILED (exit $rc); full log $LOGDIR/$n.log, inputs in $dir/artifacts/"
      TOTAL_FAILED=$((TOTAL_FAILED + 1)); status=1
    fi
    rm -rf "${works[$i]}"
  done
  return "$status"
}

START=$SECONDS
for stage in $STAGES; do
  case "$stage" in
    release|asan|fuzz) ;;
    *) echo "unknown stage '$stage' (known: release asan fuzz)"; exit 2 ;;
  esac
  t0=$SECONDS
  rc=0
  "stage_$stage" || rc=$?
  if [ "$rc" -eq 0 ]; then
    STAGE_RESULTS+=("$stage: ok ($((SECONDS - t0))s)")
  else
    STAGE_RESULTS+=("$stage: FAILED ($((SECONDS - t0))s)")
    FAILED_STAGES+=("$stage")
  fi
done

log "summary ($((SECONDS - START))s)"
for r in "${STAGE_RESULTS[@]}"; do echo "  $r"; done
if [ "$TOTAL_SKIPPED" -ne 0 ]; then
  echo "  skipped (data or OSMesa missing):"
  for t in "${SKIPPED_TESTS[@]}"; do echo "    $t"; done
  if [ "${CI:-}" = true ]; then
    echo "  CI=true: CI has the data, so no test may skip"
    FAILED_STAGES+=("skips")
  fi
fi
if [ "${#FAILED_STAGES[@]}" -ne 0 ] && [ "$TOTAL_FAILED" -eq 0 ]; then
  TOTAL_FAILED=${#FAILED_STAGES[@]}
fi
if [ "$TOTAL_SKIPPED" -ne 0 ]; then
  echo "$TOTAL_PASSED passed, $TOTAL_FAILED failed, $TOTAL_SKIPPED skipped"
else
  echo "$TOTAL_PASSED passed, $TOTAL_FAILED failed"
fi
[ "${#FAILED_STAGES[@]}" -eq 0 ]
