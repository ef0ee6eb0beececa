#!/usr/bin/env bash
# Strata installed as Debian software (cmake/install.cmake, README
# "Install"): `cpack -G DEB` builds the package; it declares the packages of
# every shared library the executable needs, and unpacked into a staging
# folder (dpkg -x) it works from there:
#   - strata info and strata render run from the staging folder, and its
#     window opens the installed default model;
#   - the man page strata(1) formats without a warning and names every
#     command `strata help` lists;
#   - the .desktop entry passes desktop-file-validate, runs strata, and its
#     icon is there (SVG and 256x256 PNG);
#   - the kernel: only public headers (no *_internal.h), each compiles on
#     its own as strict C11; strata.pc gives the staging folder's paths
#     (its prefix is found from its own place);
#   - examples/strata_example.c builds against the unpacked package through
#     pkg-config alone, runs on a shared mesh, writes level 3 with the
#     expected faces, and its one-vertex edit moved some vertices of level 3
#     and left the rest bit for bit as `strata subdivide` writes them.
# Usage: cli_install.sh BUILD_DIR SOURCE_DIR SHARED_MESHES WORK_PARENT CPACK
set -uo pipefail
BUILD=$1 SRC=$2 MESHES=$3 PARENT=$4 CPACK=$5
W=$PARENT/cli_install
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }

MESH=$MESHES/catmull_clark/spot_quadrangulated.obj
if [ ! -f "$MESH" ]; then echo "skip: $MESH missing"; exit 77; fi
# Tools, all from scripts/setup.sh: not having one is a failure, not a skip.
for t in dpkg-deb dpkg-shlibdeps pkg-config desktop-file-validate groff cc; do
    command -v "$t" > /dev/null || { echo "FAIL $t not found: run scripts/setup.sh"; exit 1; }
done

# ---- the package --------------------------------------------------------------
if ! "$CPACK" -G DEB --config "$BUILD/CPackConfig.cmake" -B "$W/pkg" > "$W/cpack.log" 2>&1; then
    cat "$W/cpack.log"; echo "FAIL cpack -G DEB"; exit 1
fi
DEB=$(ls "$W"/pkg/*.deb 2>/dev/null | head -n 1)
[ -n "$DEB" ] || { echo "FAIL cpack wrote no .deb"; exit 1; }
ok "cpack -G DEB: $(basename "$DEB") ($(stat -c %s "$DEB") bytes)"
depends=$(dpkg-deb -f "$DEB" Depends)
echo "     Depends: $depends"
ST=$W/stage
dpkg-deb -x "$DEB" "$ST" || { echo "FAIL dpkg-deb -x"; exit 1; }
EXE=$ST/usr/bin/strata
[ -x "$EXE" ] && ok "usr/bin/strata unpacked" || { echo "FAIL no usr/bin/strata in the package"; exit 1; }

# Every library strata links (NEEDED), and the two it opens at run time
# (libOSMesa.so.8, libGL.so.1), belongs to a package that Depends names.
# (dpkg -S knows a library by the path its package ships, /lib or /usr/lib.)
owner() {
    local p
    for p in "$1" "$(readlink -f "$1")" "${1#/usr}" "/usr$1"; do
        dpkg -S "$p" 2>/dev/null | head -n 1 | cut -d: -f1 | grep . && return 0
    done
    return 1
}
dep_names=$(tr ',' '\n' <<< "$depends" | awk '{ print $1 }')
sonames=$(objdump -p "$EXE" | awk '$1 == "NEEDED" { print $2 }')
for so in $sonames libOSMesa.so.8 libGL.so.1; do
    path=$(ldconfig -p | awk -v so="$so" '$1 == so && /x86-64/ { print $NF; exit }')
    pkg=$([ -n "$path" ] && owner "$path")
    if [ -z "$pkg" ]; then bad "$so: no package owns it here"; continue; fi
    if grep -Fxq "$pkg" <<< "$dep_names"; then ok "$so: $pkg in Depends"
    else bad "$so: its package $pkg is not in Depends"; fi
done

# ---- the executable, from the staging folder --------------------------------
out=$("$EXE" info "$MESH" --scheme catmull-clark --levels 2 2>&1)
if grep -Eq '^ +2 +46850 +93696 +46848 ' <<< "$out"; then ok "staged strata info: level 2 has 46848 faces"
else echo "$out"; bad "staged strata info"; fi
if "$EXE" render "$ST/usr/share/strata/assets/torus.obj" --levels 1 --size 64x64 -o "$W/torus.png" > /dev/null 2>&1 &&
   [ "$(head -c 8 "$W/torus.png" | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ]; then
    ok "staged strata render of the installed torus.obj"
else bad "staged strata render"; fi

# The window with no FILE opens the installed torus.obj, found from the
# executable's place (ui/window.c): a cube put in its stead shows 96 faces.
cp "$SRC/assets/cube.obj" "$ST/usr/share/strata/assets/torus.obj"
printf 'wait 2\nexpect error 0\nexpect faces 96\n' > "$W/default.txt"
xvfb=()
[ -n "${DISPLAY:-}" ] || xvfb=(xvfb-run -a -n $((100 + RANDOM % 800)) -s "-screen 0 1280x800x24")
if env -u STRATA_ASSETS -u XDG_CONFIG_HOME -u XDG_STATE_HOME HOME="$W/home" timeout 120 \
       ${xvfb[@]+"${xvfb[@]}"} "$EXE" --replay "$W/default.txt" > "$W/window.log" 2>&1; then
    ok "staged window opens the installed default model"
else cat "$W/window.log"; bad "staged window's default model"; fi

# ---- man page -----------------------------------------------------------------
MAN=$ST/usr/share/man/man1/strata.1.gz
if [ -f "$MAN" ]; then
    warn=$(zcat "$MAN" | groff -man -Tutf8 -ww -z 2>&1)
    [ -z "$warn" ] && ok "strata.1.gz formats without a warning" || bad "groff warns: $warn"
    text=$(zcat "$MAN" | groff -man -Tascii -P-cbou 2>/dev/null)
    grep -q '^NAME' <<< "$text" && grep -q 'strata - multiresolution subdivision modeller' <<< "$text" &&
        ok "man page: NAME" || bad "man page: no NAME line"
    missing=""
    for c in $("$EXE" help | sed -nE 's/^  ([a-z]+) .*/\1/p'); do
        grep -q "strata $c" <<< "$text" || missing="$missing $c"
    done
    [ -z "$missing" ] && ok "man page names every command of strata help" || bad "man page lacks:$missing"
else bad "no usr/share/man/man1/strata.1.gz"; fi

# ---- desktop entry and icon ---------------------------------------------------
DESK=$ST/usr/share/applications/strata.desktop
if [ -f "$DESK" ]; then
    v=$(desktop-file-validate "$DESK" 2>&1)
    [ -z "$v" ] && ok "desktop-file-validate strata.desktop" || bad "desktop-file-validate: $v"
    exec_cmd=$(sed -n 's/^Exec=\([^ ]*\).*/\1/p' "$DESK")
    [ -x "$ST/usr/bin/$exec_cmd" ] && ok "Exec=$exec_cmd is usr/bin/$exec_cmd" || bad "Exec=$exec_cmd not in usr/bin"
    icon=$(sed -n 's/^Icon=//p' "$DESK")
else bad "no usr/share/applications/strata.desktop"; icon=strata; fi
SVG=$ST/usr/share/icons/hicolor/scalable/apps/$icon.svg
PNG=$ST/usr/share/icons/hicolor/256x256/apps/$icon.png
if [ -f "$SVG" ] && head -n 1 "$SVG" | grep -q '^<?xml' && grep -q '<svg xmlns="http://www.w3.org/2000/svg"' "$SVG" &&
   tail -n 1 "$SVG" | grep -q '</svg>'; then ok "icon $icon.svg"; else bad "icon $SVG"; fi
# PNG signature, then IHDR's width and height (bytes 16..23, big-endian).
if [ -f "$PNG" ] && [ "$(od -An -tx1 -j0 -N8 "$PNG" | tr -d ' \n')" = 89504e470d0a1a0a ] &&
   [ "$(od -An -tx1 -j16 -N8 "$PNG" | tr -d ' \n')" = 0000010000000100 ]; then ok "icon $icon.png, 256x256"
else bad "icon $PNG is not a 256x256 PNG"; fi

# ---- the kernel: headers, strata.pc -------------------------------------------
INC=$ST/usr/include/strata
internal=$(find "$INC" -name '*_internal.h' | wc -l)
nh=$(find "$INC/core" -name '*.h' | wc -l)
[ "$internal" -eq 0 ] && [ "$nh" -gt 10 ] && ok "$nh public headers, no *_internal.h" ||
    bad "headers: $nh public, $internal internal"
hfail=""
for h in $(cd "$INC" && find core -name '*.h' | sort); do
    printf '#include "%s"\n#include "%s"\nint main(void) { return 0; }\n' "$h" "$h" > "$W/h.c"
    cc -std=c11 -pedantic -Wall -Wextra -Werror -fsyntax-only -I"$INC" "$W/h.c" 2> "$W/h.err" || hfail="$hfail $h"
done
[ -z "$hfail" ] && ok "each header compiles alone, twice, as strict C11" || { cat "$W/h.err"; bad "headers:$hfail"; }

PC=$(dirname "$(find "$ST" -name strata.pc | head -n 1)")
export PKG_CONFIG_PATH=$PC
flags=$(pkg-config --cflags --libs strata 2>&1)
echo "     pkg-config --cflags --libs strata: $flags"
idir=$(sed -nE 's/.*-I([^ ]+).*/\1/p' <<< "$flags")
ldir=$(sed -nE 's/.*-L([^ ]+).*/\1/p' <<< "$flags")
[ "$(readlink -f "$idir")" = "$(readlink -f "$INC")" ] && ok "Cflags: -I the staged include/strata" || bad "Cflags $idir"
[ -f "$ldir/libstrata_core.a" ] && ok "Libs: -L the staged libstrata_core.a" || bad "Libs -L$ldir"
for l in -lstrata_core -lm -lpthread; do
    grep -q -- "$l" <<< "$flags" || bad "Libs lacks $l"
done

# ---- the example, built against the package -----------------------------------
EX=$W/strata_example
# shellcheck disable=SC2086  # pkg-config's words
if cc -std=c11 -Wall -Wextra -Werror "$SRC/examples/strata_example.c" $(pkg-config --cflags --libs strata) -o "$EX" 2> "$W/cc.err"; then
    ok "examples/strata_example.c built with pkg-config alone"
    out=$("$EX" "$MESH" "$W/example.obj" 2>&1); rc=$?
    echo "$out" | sed 's/^/     /'
    # spot: 2928 quads, 2928 * 4^3 at level 3.
    if [ "$rc" -eq 0 ] && grep -Eq '^level 3: [0-9]+ vertices, 187392 faces written' <<< "$out" &&
       [ "$(grep -c '^f ' "$W/example.obj")" -eq 187392 ]; then ok "example wrote level 3: 187392 faces"
    else bad "example (exit $rc)"; fi
    before=$(sed -nE 's/^vertex [0-9]+ at level 3: ([^>]+) -> .*/\1/p' <<< "$out")
    after=$(sed -nE 's/^vertex [0-9]+ at level 3: [^>]+ -> (.*)/\1/p' <<< "$out")
    [ -n "$after" ] && [ "$before" != "$after" ] &&
        ok "the edited vertex moved at level 3" || bad "edited vertex: '$before' -> '$after'"
    # Against the same levels unedited: same faces, some vertices moved, the
    # others bit for bit.
    "$EXE" subdivide "$MESH" --scheme catmull-clark --levels 3 -o "$W/plain.obj" > /dev/null 2>&1
    read -r nv moved < <(awk 'FNR == NR && /^v / { p[++a] = $0; next } /^v / { b++; if ($0 != p[b]) m++ }
                              END { print (a == b ? a : -1), m + 0 }' "$W/plain.obj" "$W/example.obj")
    if cmp -s <(grep '^f ' "$W/plain.obj") <(grep '^f ' "$W/example.obj") && [ "$nv" -gt 0 ] &&
       [ "$moved" -gt 0 ] && [ "$moved" -lt $((nv / 10)) ]; then
        ok "the edit is local: $moved of $nv vertices of level 3 moved, faces unchanged"
    else bad "edit against strata subdivide: $moved of $nv vertices moved"; fi
else
    cat "$W/cc.err"; bad "examples/strata_example.c does not build against the package"
fi

echo "$((n - fail)) of $n checks passed"
[ "$fail" -eq 0 ] && rm -rf "$W"
[ "$fail" -eq 0 ]
