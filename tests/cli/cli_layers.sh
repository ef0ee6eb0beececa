#!/usr/bin/env bash
# The layer order of docs/ARCHITECTURE.md, read from the #include lines:
#   - core/ includes nothing outside core; render/ only core; formats/ only
#     core; nothing below ui/ and app/ includes them; ui/ includes no file
#     of app/;
#   - inside core, each folder includes only itself and folders below it,
#     in this order (bottom first):
#       base map schemes fvar multires progressive adapt uv bake sculpt io rebuild
#     with no exception: any include upward fails (the schemes' rules take
#     a view of the surface, core/schemes/view.h, not the hierarchy);
#   - no code in core/schemes or core/fvar uses st_hier, the type of the
#     layer above them, even without including its header.
#   bash tests/cli/cli_layers.sh [ignored arguments of the cli_*.sh tests]
set -u
R="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$R"
n=0 fail=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }

# includes FILES...: "file included" per quoted #include, relative forms kept
includes() { grep -H -oE '^[[:space:]]*#[[:space:]]*include[[:space:]]+"[^"]+"' "$@" 2>/dev/null | sed -E 's/:[[:space:]]*#[[:space:]]*include[[:space:]]+"/ /; s/"$//'; }

# Top-level layers.
check_top() {  # DIR ALLOWED-REGEX (of included paths with a folder)
    local dir=$1 allow=$2 out
    out=$(includes $(find "$dir" -name '*.[ch]' -o -name '*.cc' -o -name '*.cpp' | sort) | awk '{print $2}' | grep / | grep -vE "$allow" | sort -u)
    if [ -z "$out" ]; then ok "$dir/ includes only $allow"; else bad "$dir/ includes $(tr '\n' ' ' <<<"$out")"; fi
}
check_top core '^core/'
check_top render '^(core/|render/)'
check_top formats '^(core/|formats/)'
for d in core render formats; do
    out=$(includes $(find $d -name '*.[ch]' -o -name '*.cc' | sort) | awk '{print $2}' | grep -E '^(ui|app)/|^(window|actions|gui|editor|cli)\.h$' | sort -u)
    if [ -z "$out" ]; then ok "$d/ includes nothing of ui/ or app/"; else bad "$d/ includes $out"; fi
done
# ui/ includes no header that lives in app/ (bare names included).
app_headers=$(cd app && ls *.h | tr '\n' '|' | sed 's/|$//')
out=$(includes $(find ui -name '*.[ch]' -o -name '*.cc' | sort) | awk -v re="^(app/)?($app_headers)\$" '$2 ~ re' | sort -u)
if [ -z "$out" ]; then ok "ui/ includes no header of app/"; else bad "ui/ includes app/'s: $out"; fi

# Render's API: ui/, app/, bench/ and examples/ include render's headers as
# "render/<header>.h" (the include root holds render/ alone: a bare name is
# not found) and only its public ones; a private header (one that refuses
# to compile without STRATA_RENDER_INTERNAL) is included outside render/
# only by a test built with that definition (test_render_*.c:
# tests/CMakeLists.txt) or one that defines it itself.
render_private=$(grep -l '^#ifndef STRATA_RENDER_INTERNAL' render/*.h | xargs -n1 basename | sort)
render_all=$(cd render && ls *.h | sort)
[ -n "$render_private" ] && ok "render's private headers: $(tr '\n' ' ' <<<"$render_private")" ||
    bad "render/ has no private header (none refuses to compile without STRATA_RENDER_INTERNAL)"
render_re="($(tr '\n' '|' <<<"$render_all" | sed 's/|$//; s/\./\\./g'))"
private_re="^render/($(tr '\n' '|' <<<"$render_private" | sed 's/|$//; s/\./\\./g'))\$"
for d in ui app bench examples; do
    [ -d "$d" ] || continue
    files=$(find "$d" -name '*.[ch]' -o -name '*.cc' -o -name '*.cpp' | sort)
    bare=$(includes $files | awk -v re="^$render_re\$" '$2 ~ re' | sort -u)
    priv=$(includes $files | awk -v re="$private_re" '$2 ~ re' | sort -u)
    if [ -z "$bare$priv" ]; then ok "$d/ includes render's public headers only, as render/<header>.h"
    else bad "$d/ includes render headers bare or private: $(tr '\n' ' ' <<<"$bare$priv")"; fi
done
out=$(includes $(find tests -name '*.[ch]' | sort) | awk -v re="$private_re" '$2 ~ re' | while read -r file inc; do
    case ${file##*/} in test_render_*.c) continue ;; esac
    grep -q '^#define STRATA_RENDER_INTERNAL' "$file" || echo "$file: $inc"
done | sort -u)
if [ -z "$out" ]; then ok "tests/ include render's private headers only where STRATA_RENDER_INTERNAL is defined"
else bad "tests/ include render's private headers without STRATA_RENDER_INTERNAL: $(tr '\n' ' ' <<<"$out")"; fi

# Core's folders, bottom first.
order=(base map schemes fvar multires progressive adapt uv bake sculpt io rebuild)
declare -A rank
for i in "${!order[@]}"; do rank[${order[$i]}]=$i; done
for d in core/*/; do
    d=${d%/}; d=${d#core/}
    [ -n "${rank[$d]:-}" ] || bad "core/$d is not in the order (add it to tests/cli/cli_layers.sh and docs/ARCHITECTURE.md)"
done
upward=$(for d in "${order[@]}"; do
    [ -d "core/$d" ] || continue
    includes core/$d/*.[ch] | while read -r file inc; do
        case $inc in core/*/*) ;; *) continue ;; esac
        t=${inc#core/}; t=${t%%/*}
        [ -n "${rank[$t]:-}" ] || continue
        if [ "${rank[$t]}" -gt "${rank[$d]}" ]; then echo "$d -> $t ($file: $inc)"; fi
    done
done)
if [ -z "$upward" ]; then ok "core's folders include only folders below them"
else bad "includes upward in core: $upward"; fi
# A forward declaration or a call would hide an upward dependency from the
# includes (comments may name the hierarchy: lines opening with /* or *).
out=$(grep -nE 'struct st_hier\b|\bst_hier \*|\bst_hier_[a-z_]+\(' core/schemes/*.[ch] core/fvar/*.[ch] 2>/dev/null |
      grep -vE '^[^:]+:[0-9]+:[[:space:]]*(/\*|\*)' || true)
if [ -z "$out" ]; then ok "core/schemes and core/fvar use no st_hier"
else bad "st_hier used below core/multires: $out"; fi

echo "cli_layers: $((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
