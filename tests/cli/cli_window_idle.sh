#!/usr/bin/env bash
# The window sleeps when nothing happens: after it has loaded the default
# model and drawn, an idle window uses (almost) no processor time, as it
# draws only after input or a change (ui/window.c, the main loop); pointer
# motion over it makes it draw again.  Measured as the process's own CPU
# time (/proc/PID/stat), which a loaded machine does not inflate much:
# before, the window redrew every 0.25 s, about 0.12 s of CPU per second
# at 1024x768 under llvmpipe (Release), more under the sanitizers.
#
#   cli_window_idle.sh STRATA_EXE SHARED_MESH_DIR ASSETS_DIR BINARY_TEST_DIR
#
# Runs itself under its own xvfb-run: the pointer is the X server's.
set -u
if [ -z "${STRATA_CLI_IDLE_XVFB:-}" ]; then
    if command -v xvfb-run > /dev/null 2>&1; then
        export STRATA_CLI_IDLE_XVFB=1
        exec xvfb-run -a -n $((100 + RANDOM % 800)) -s "-screen 0 1280x800x24" bash "$0" "$@"
    fi
    echo "FAIL: no xvfb-run: the window cannot be tested (install xvfb)"
    exit 1
fi
command -v xdotool > /dev/null 2>&1 || { echo "FAIL: xdotool is not installed (bash scripts/setup.sh installs it)"; exit 1; }
EXE=$1
TMP=$(mktemp -d "${TMPDIR:-/tmp}/strata_cli_idle.XXXXXX")
pid=
cleanup() { [ -n "$pid" ] && kill "$pid" 2> /dev/null; rm -rf "$TMP"; }
trap cleanup EXIT
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"   # Mesa's GLX leaks (cli_window.sh)
export XDG_CONFIG_HOME="$TMP/config" STRATA_RECOVERY="$TMP/recovery.strata"
unset STRATA_GUI_PROBE
mkdir -p "$XDG_CONFIG_HOME"
"$EXE" --size 1024x768 > "$TMP/log" 2>&1 &
pid=$!
# ticks: user + system CPU time of the window so far, in clock ticks.
ticks() { awk '{ print $14 + $15 }' "/proc/$pid/stat" 2> /dev/null; }
hz=$(getconf CLK_TCK)
alive() { kill -0 "$pid" 2> /dev/null || { echo "FAIL: the window exited:"; tail -5 "$TMP/log"; exit 1; }; }

# Settled: a whole second in which it used at most 3 % of a core.  Loading
# and the first frames take a few seconds (more under the sanitizers).
settled=0
for _ in $(seq 1 120); do
    alive
    t0=$(ticks); sleep 1; t1=$(ticks)
    if [ $((t1 - t0)) -le $((hz * 3 / 100)) ]; then settled=1; break; fi
done
[ "$settled" = 1 ] || { echo "FAIL: the window never went idle: $((t1 - t0)) ticks (of $hz per second) in its last second, after 120 s"; exit 1; }

t0=$(ticks); sleep 3; t1=$(ticks)
idle=$((t1 - t0))
[ "$idle" -le $((hz * 10 / 100)) ] || { echo "FAIL: idle for 3 s, the window used $idle ticks (of $hz per second; at most $((hz * 10 / 100)))"; exit 1; }
echo "ok   idle: $idle ticks of CPU in 3 s (clock $hz Hz)"

# Pointer motion over the window: the GUI's hover needs frames, so it draws.
t0=$(ticks)
for xy in "200 200" "400 300" "600 400" "300 500" "500 250"; do xdotool mousemove $xy; sleep 0.2; done
sleep 1
t1=$(ticks)
woke=$((t1 - t0))
[ "$woke" -gt "$idle" ] && [ "$woke" -ge 2 ] || { echo "FAIL: pointer motion over the window drew nothing: $woke ticks (idle: $idle)"; exit 1; }
echo "ok   input: $woke ticks of CPU while the pointer moved"
alive
echo "cli_window_idle: passed"
