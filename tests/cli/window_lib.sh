# Sourced by the CLI tests that open the window (cli_window.sh,
# cli_bake_window.sh, cli_window_hd.sh): without $DISPLAY the script runs
# itself again under xvfb-run, or fails saying why.
#   . "$(dirname "$0")/window_lib.sh"; need_display "$0" "$@"
need_display() {
    [ -n "${DISPLAY:-}" ] || [ -n "${STRATA_CLI_WINDOW_XVFB:-}" ] && return 0
    if command -v xvfb-run >/dev/null 2>&1; then
        export STRATA_CLI_WINDOW_XVFB=1
        # -n: a random first display number, so that window tests started
        # at once (ctest -j2, other builds) do not race for :99 (xvfb-run -a
        # looks for a free number, then starts the server: two can pick one).
        exec xvfb-run -a -n $((100 + RANDOM % 800)) -s "-screen 0 1280x800x24" bash "$@"
    fi
    echo "FAIL: no \$DISPLAY and no xvfb-run: the window cannot be tested (install xvfb)"
    exit 1
}
