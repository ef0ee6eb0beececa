#!/usr/bin/env bash
# Installs everything Strata needs to build, test and run, on Debian 12.
#
#   bash scripts/setup.sh        (as root; safe to run again and again)
#
# When every package is already installed it touches nothing (no apt-get at
# all), so scripts/test.sh and scripts/run.sh can call it every time.
# Not root: works only when everything is already installed; otherwise it says
# what is missing and stops.
set -euo pipefail

# Debian 12 package names (all checked with apt-cache policy on bookworm).
PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  libxxhash-dev                       # the session files' checksum (XXH3, core/io/map_io.c)
  ccache                              # the release stage's kernel, compiled once for its core-only build too
  # packaging (cpack -G DEB, tests/cli/cli_install.sh): dpkg-shlibdeps, the .desktop
  # validator, groff to format the man page
  dpkg-dev desktop-file-utils groff-base
  clang libclang-rt-14-dev            # libFuzzer + LeakSanitizer runtime for clang
  # rendering: GLFW window, OSMesa headless, GL headers, cglm maths, Dear ImGui (the GUI)
  libglfw3-dev libosmesa6-dev libgl-dev libcglm-dev libimgui-dev
  # glTF / images
  libtinygltf-dev nlohmann-json3-dev libstb-dev
  # baked maps (strata bake): 16-bit PNG, 32-bit float OpenEXR
  libpng-dev libtinyexr-dev
  # reference implementations used by tests/oracles and benchmarks
  libosd-dev libcgal-dev libgmp-dev libmpfr-dev libopenmesh-dev libmeshoptimizer-dev
  # testing the window as a person would, screenshots
  xvfb xauth xdotool imagemagick
  # glTF validator (npm package gltf-validator)
  nodejs npm
  # instruction counts for benchmarks
  valgrind
  # wall time, CPU time and peak memory of whole processes (bench/whole_process.sh)
  time
)

say() { printf 'setup: %s\n' "$*"; }

is_installed() {
  [ "$(dpkg-query -W -f='${Status}' "$1" 2>/dev/null || true)" = "install ok installed" ]
}

missing=()
for pkg in "${PACKAGES[@]}"; do
  if is_installed "$pkg"; then
    continue
  fi
  # A node.js from elsewhere (e.g. NodeSource) ships its own npm and conflicts
  # with Debian's npm package: accept working commands in that case.
  case "$pkg" in
    nodejs) command -v node >/dev/null 2>&1 && continue ;;
    npm)    command -v npm  >/dev/null 2>&1 && continue ;;
  esac
  missing+=("$pkg")
done

if [ "${#missing[@]}" -eq 0 ]; then
  say "all ${#PACKAGES[@]} packages already installed; nothing to do"
  exit 0
fi

say "missing packages: ${missing[*]}"

if [ "$(id -u)" -ne 0 ]; then
  say "ERROR: installing packages needs root. Run as root:  bash scripts/setup.sh" >&2
  say "       (or install by hand: apt-get install ${missing[*]})" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
say "running: apt-get update"
apt-get update
say "running: apt-get install -y --no-install-recommends ${missing[*]}"
apt-get install -y --no-install-recommends "${missing[@]}"

# Check that it all landed.
still=()
for pkg in "${missing[@]}"; do
  is_installed "$pkg" || still+=("$pkg")
done
if [ "${#still[@]}" -ne 0 ]; then
  say "ERROR: still not installed after apt-get: ${still[*]}" >&2
  exit 1
fi
say "installed ${#missing[@]} package(s); done"
