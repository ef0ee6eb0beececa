#!/usr/bin/env bash
# Installs the Khronos glTF Validator (npm package gltf-validator, pinned) into
# build/node/ for tests/cli/gltf_validate.js and tests/cli/cli_gltf.sh.
#
#   bash scripts/setup_node.sh      (safe to run again: does nothing when the
#                                    pinned version is already there)
# Needs node and npm (scripts/setup.sh installs them) and, the first time,
# the npm registry.  GLTF_VALIDATOR_DIR overrides the folder.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DIR="${GLTF_VALIDATOR_DIR:-$ROOT/build/node}"
VERSION="2.0.0-dev.3.10"

say() { printf 'setup_node: %s\n' "$*"; }

installed_version() {
  local pkg="$DIR/node_modules/gltf-validator/package.json"
  [ -f "$pkg" ] || return 0
  node -e 'process.stdout.write(require(process.argv[1]).version)' "$pkg" 2>/dev/null || true
}

for cmd in node npm; do
  if ! command -v "$cmd" >/dev/null 2>&1; then
    say "ERROR: '$cmd' not found; run scripts/setup.sh (Debian packages nodejs npm)" >&2
    exit 1
  fi
done

if [ "$(installed_version)" = "$VERSION" ]; then
  say "gltf-validator $VERSION already in $DIR; nothing to do"
  exit 0
fi

mkdir -p "$DIR"
# A package.json of our own so npm installs here and not in a parent folder.
if [ ! -f "$DIR/package.json" ]; then
  printf '{ "name": "strata-node-tools", "private": true }\n' > "$DIR/package.json"
fi
say "running: npm install gltf-validator@$VERSION in $DIR"
(cd "$DIR" && npm install --no-audit --no-fund --save-exact "gltf-validator@$VERSION")

if [ "$(installed_version)" != "$VERSION" ]; then
  say "ERROR: gltf-validator $VERSION is still not in $DIR after npm install" >&2
  exit 1
fi
say "installed gltf-validator $VERSION in $DIR"
