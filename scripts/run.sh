#!/usr/bin/env bash
# Builds Strata (release) and opens a model.
#
#   bash scripts/run.sh [MODEL]        MODEL defaults to assets/cube.obj
#
# With $DISPLAY set it opens the modeller's window on MODEL. Without a display
# it says so and shows what it can headless (see headless() below).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

MODEL="${1:-assets/cube.obj}"
BUILD="$ROOT/build/release"
STRATA="$BUILD/strata"
JOBS="$(nproc 2>/dev/null || echo 2)"

say() { printf 'run: %s\n' "$*"; }

bash "$ROOT/scripts/setup.sh"

# Same configuration as scripts/test.sh's release stage, so the two share
# build/release instead of rebuilding each other's work.
if [ -f "$BUILD/CMakeCache.txt" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$BUILD/CMakeCache.txt"; then
  say "build/release was configured with another generator; removing it"
  rm -rf "$BUILD"
fi
say "configuring and building build/release"
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSTRATA_WERROR=ON
cmake --build "$BUILD" -j"$JOBS" --target strata

if [ ! -f "$MODEL" ]; then
  say "ERROR: model '$MODEL' not found" >&2
  exit 1
fi

# ---- what to show without a display ----------------------------------------
# THE ONE PLACE TO CHANGE once headless rendering lands: if `strata help` lists
# a `render` command, it renders MODEL to a PNG; otherwise it prints the
# subdivision statistics. Adjust the render arguments here to match the CLI.
headless() {
  local out help_text
  out="$ROOT/build/run/$(basename "${MODEL%.*}").png"
  help_text="$("$STRATA" help 2>&1 || true)"
  # A help line that lists the command: "  render ...", "strata render ...".
  if grep -qiE '^[[:space:]]*(usage:[[:space:]]*)?(strata[[:space:]]+)?render([[:space:]]|$)' <<<"$help_text"; then
    mkdir -p "$(dirname "$out")"
    say "rendering $MODEL headless (OSMesa) to ${out#"$ROOT"/}"
    "$STRATA" render "$MODEL" --scheme catmull-clark --levels 3 -o "$out"
    say "wrote ${out#"$ROOT"/}"
  else
    say "showing: strata info $MODEL --scheme catmull-clark --levels 3"
    "$STRATA" info "$MODEL" --scheme catmull-clark --levels 3
  fi
}
# -----------------------------------------------------------------------------

if [ -n "${DISPLAY:-}" ]; then
  say "opening $MODEL in the modeller window (DISPLAY=$DISPLAY)"
  exec "$STRATA" "$MODEL"
else
  say "no \$DISPLAY set, so no window can open; running headless instead"
  say "(for the window: run under X, or e.g. xvfb-run -a -s '-screen 0 1280x800x24' bash scripts/run.sh)"
  headless
fi
