#!/usr/bin/env bash
# The layers as the build enforces them (docs/ARCHITECTURE.md):
#   - every core/**/*_internal.h refuses to compile without
#     STRATA_CORE_INTERNAL, and compiles with it;
#   - every public core header compiles on its own from the include root
#     that render/, ui/ and app/ get (which holds core/ alone);
#   - render/, ui/ and app/ include no internal core header, core/ includes
#     nothing from render/, ui/ or app/, and render/ nothing from ui/;
#   - render's private headers (the GL plumbing, the case tables) refuse to
#     compile without STRATA_RENDER_INTERNAL and compile with it; its public
#     ones compile on their own from render's and core's include roots.
# Usage: cli_layering.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
B=$4
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
INC=$B/../include
CC=${CC:-cc}
fail=0 n=0
ok() { n=$((n + 1)); }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
compiles() { echo "#include \"$1\"" | "$CC" -std=c11 -D_XOPEN_SOURCE=700 -fsyntax-only -I"$INC" $2 -x c - 2>/dev/null; }

[ "$(ls "$INC")" = core ] && ok || bad "the include root $INC holds more than core/: $(ls "$INC")"
cd "$ROOT"
for h in core/*/*_internal.h; do
    if compiles "$h" ""; then bad "$h compiles without STRATA_CORE_INTERNAL"; else ok; fi
    if compiles "$h" "-DSTRATA_CORE_INTERNAL=1"; then ok; else bad "$h does not compile with STRATA_CORE_INTERNAL"; fi
done
for h in core/*/*.h; do
    case $h in *_internal.h) continue ;; esac
    if compiles "$h" ""; then ok; else bad "public header $h does not compile on its own from the include root"; fi
done
hits=$(grep -rn '#include "core/[a-z]*/[a-z_0-9]*_internal\.h"' render ui app || true)
[ -z "$hits" ] && ok || bad "outside core, internal headers included: $hits"
hits=$(grep -rln '#include "\(render\|ui\|app\)/\|#include "\(renderer\|window\|editor\|geom\|cli\)\.h"' core || true)
[ -z "$hits" ] && ok || bad "core includes render/ui/app headers: $hits"
hits=$(grep -ln '#include "\(editor\|window\|actions\|hud\|pick\|replay\|camera_ctl\)[a-z_]*\.h"' render/*.c render/*.h || true)
[ -z "$hits" ] && ok || bad "render includes ui headers: $hits"
RINC=$B/../include-render
if [ -d "$RINC" ]; then
    [ "$(ls "$RINC")" = render ] && ok || bad "render's include root $RINC holds more than render/: $(ls "$RINC")"
    for h in render/*.h; do
        if grep -q '^#ifndef STRATA_RENDER_INTERNAL' "$h"; then
            if compiles "$h" "-I$RINC"; then bad "$h compiles without STRATA_RENDER_INTERNAL"; else ok; fi
            if compiles "$h" "-I$RINC -DSTRATA_RENDER_INTERNAL=1"; then ok; else bad "$h does not compile with STRATA_RENDER_INTERNAL"; fi
        elif compiles "$h" "-I$RINC"; then ok
        else bad "public header $h does not compile on its own from the include roots"; fi
    done
fi
echo "$((n - fail)) passed, $fail failed"
[ "$fail" = 0 ]
