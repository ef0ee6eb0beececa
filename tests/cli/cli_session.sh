#!/usr/bin/env bash
# strata convert and session files: mesh -> session -> mesh round trips,
# session -> session byte-identical, adaptive sessions, normals in OBJ/PLY,
# crash-safe saving (a save killed with SIGKILL in the middle leaves the
# previous file intact), refusal of bad input with a message and exit 1/2.
# Usage: cli_session.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
S=$1 D=$2 A=$3 B=$4
W=$B/cli_session
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
size_of() { wc -c < "$1" | tr -d ' '; }
faces_of() { "$S" info "$1" | awk '$1 == "0" { print $4 }'; }

CAGE=$D/catmull_clark/blub_control_mesh.obj
ICO=$D/triangle/sphere_ico.obj

# ---- round trips -------------------------------------------------------------
for spec in "cc:$CAGE:catmull-clark:3" "loop:$ICO:loop:2" "ds:$A/cube.obj:doo-sabin:3" \
            "sqrt3:$ICO:sqrt3:2" "bf:$ICO:butterfly:2"; do
    IFS=: read -r tag mesh scheme levels <<< "$spec"
    if "$S" convert "$mesh" "$W/$tag.strata" --scheme "$scheme" --levels "$levels" > "$W/$tag.out"; then
        ok "$tag: $(cat "$W/$tag.out")"
    else bad "$tag: convert to a session failed"; continue; fi
    "$S" convert "$W/$tag.strata" "$W/${tag}_2.strata" > /dev/null
    if cmp -s "$W/$tag.strata" "$W/${tag}_2.strata"; then ok "$tag: session -> session byte-identical ($(size_of "$W/$tag.strata") bytes)"
    else bad "$tag: session -> session differs"; fi
    # The top level from the session equals `strata subdivide` of the mesh.
    "$S" convert "$W/$tag.strata" "$W/${tag}_s.obj" --no-normals > /dev/null
    "$S" subdivide "$mesh" --scheme "$scheme" --levels "$levels" -o "$W/${tag}_d.obj" > /dev/null
    if cmp -s "$W/${tag}_s.obj" "$W/${tag}_d.obj"; then ok "$tag: level $levels from the session = strata subdivide"
    else bad "$tag: level $levels from the session differs from strata subdivide"; fi
done

# ---- exports with normals ---------------------------------------------------------
"$S" convert "$W/cc.strata" "$W/cc1.obj" --level 1 > /dev/null
# blub_control_mesh has UVs: its corners are v/vt/vn (v//vn without UVs).
if grep -q '^vn ' "$W/cc1.obj" && grep -q '^vt ' "$W/cc1.obj" && grep -q '^f [0-9]*/[0-9][0-9]*/[0-9]*' "$W/cc1.obj"; then ok "OBJ export has vn, vt and f v/vt/vn"; else bad "OBJ normals or UVs missing"; fi
"$S" convert "$A/cube.obj" "$W/cube1.obj" --levels 1 > /dev/null
if grep -q '^vn ' "$W/cube1.obj" && grep -q '^f [0-9]*//[0-9]*' "$W/cube1.obj"; then ok "OBJ export without UVs has vn and f v//vn"; else bad "OBJ normals missing"; fi
if [ "$(faces_of "$W/cc1.obj")" = "$(faces_of "$W/cc1.obj")" ] && "$S" info "$W/cc1.obj" > /dev/null; then ok "OBJ with normals reads back"; else bad "OBJ with normals does not read back"; fi
"$S" convert "$W/cc.strata" "$W/cc1.ply" --level 1 > /dev/null
if head -c 400 "$W/cc1.ply" | grep -q 'property double nx' && "$S" info "$W/cc1.ply" > /dev/null; then ok "PLY export has nx ny nz and reads back"; else bad "PLY normals"; fi
"$S" convert "$W/cc.strata" "$W/cc1n.obj" --level 1 --no-normals > /dev/null
if ! grep -q '^vn ' "$W/cc1n.obj"; then ok "--no-normals"; else bad "--no-normals still writes vn"; fi
"$S" convert "$CAGE" "$W/direct.ply" --levels 2 > /dev/null && ok "mesh -> mesh (PLY, level 2)" || bad "mesh -> mesh"
# glTF through formats/mesh_any.h, when the build has it.
if "$S" convert "$W/cc.strata" "$W/cc1.glb" --level 1 > /dev/null 2> "$W/gltf_err.txt"; then
    if "$S" convert "$W/cc1.glb" "$W/from_glb.strata" --levels 1 > /dev/null; then ok "session -> .glb -> session"; else bad "a .glb export does not convert back"; fi
else echo "skip glTF: $(head -1 "$W/gltf_err.txt")"; fi

# ---- adaptive sessions -----------------------------------------------------------------
BOX=0,0,0,0.4,0.4,0.4
if "$S" convert "$CAGE" "$W/ad.strata" --box $BOX --max-level 4 > "$W/ad.out"; then ok "adaptive: $(cat "$W/ad.out")"; else bad "adaptive session"; fi
"$S" convert "$W/ad.strata" "$W/ad_2.strata" > /dev/null
cmp -s "$W/ad.strata" "$W/ad_2.strata" && ok "adaptive session -> session byte-identical" || bad "adaptive session re-save differs"
"$S" convert "$W/ad.strata" "$W/ad_s.obj" --no-normals > /dev/null
"$S" adapt "$CAGE" --box $BOX --max-level 4 -o "$W/ad_d.obj" > /dev/null
cmp -s "$W/ad_s.obj" "$W/ad_d.obj" && ok "adaptive mesh from the session = strata adapt" || bad "adaptive mesh from the session differs from strata adapt"
# Moving the box of a loaded session = the same move in one go.
"$S" convert "$W/ad.strata" "$W/ad_m.obj" --box -0.4,-0.4,-0.4,0,0,0 --max-level 4 --no-normals > /dev/null &&
    ok "box moved on a loaded session: $(faces_of "$W/ad_m.obj") faces" || bad "box move on a loaded session"

# ---- crash-safe saving: kill a save in the middle ------------------------------------------
"$S" convert "$CAGE" "$W/keep.strata" --levels 1 > /dev/null
cp "$W/keep.strata" "$W/keep.orig"
# (a) deterministic: slowed down (50 ms per 64 KiB), killed while the temporary grows.
STRATA_SAVE_SLOWDOWN=50000 "$S" convert "$CAGE" "$W/keep.strata" --levels 5 > /dev/null 2>&1 &
pid=$!
tmp="$W/keep.strata.tmp-$pid"
for _ in $(seq 1 600); do
    [ -f "$tmp" ] && [ "$(size_of "$tmp")" -gt 1000000 ] && break
    sleep 0.1
done
partial=$( [ -f "$tmp" ] && size_of "$tmp" || echo 0)
kill -KILL $pid 2>/dev/null
wait $pid 2>/dev/null
if [ "$partial" -gt 0 ] && cmp -s "$W/keep.strata" "$W/keep.orig"; then
    ok "save killed with SIGKILL after $partial bytes of the temporary: previous file intact ($(size_of "$W/keep.strata") bytes, same bytes)"
else bad "killed save: partial=$partial, previous file changed or no temporary seen"; fi
# The partial temporary is kept aside first: the next command writing into
# this folder removes the temporaries of dead processes (atomic_file.h).
[ -f "$tmp" ] && cp "$tmp" "$W/partial.strata"
if "$S" convert "$W/keep.strata" "$W/keep.obj" > /dev/null; then ok "previous file still loads"; else bad "previous file no longer loads"; fi
if [ ! -e "$tmp" ]; then ok "the killed save's temporary removed by the next command writing there"
else bad "the killed save's temporary $tmp stays after another write into its folder"; fi
if [ ! -f "$W/partial.strata" ]; then bad "no partial temporary to check"
elif "$S" convert "$W/partial.strata" "$W/x.obj" > /dev/null 2> "$W/tmp_err.txt"; then bad "the partial temporary loads?"
else ok "the partial temporary is refused: $(head -1 "$W/tmp_err.txt")"; fi
rm -f "$tmp"
# (b) a real, full-speed save of a large session (Catmull-Clark depth 6), killed
#     as soon as its temporary appears: the file is the old one or the complete
#     new one, never anything else.
"$S" convert "$CAGE" "$W/big.strata" --levels 1 > /dev/null
cp "$W/big.strata" "$W/big.orig"
"$S" convert "$CAGE" "$W/big.strata" --levels 6 > /dev/null 2>&1 &
pid=$!
tmp="$W/big.strata.tmp-$pid"
for _ in $(seq 1 3000); do
    [ -f "$tmp" ] && [ "$(size_of "$tmp")" -gt 0 ] && break
    sleep 0.01
done
partial=$( [ -f "$tmp" ] && size_of "$tmp" || echo 0)
kill -KILL $pid 2>/dev/null
wait $pid 2>/dev/null
if cmp -s "$W/big.strata" "$W/big.orig"; then ok "full-speed save killed (temporary at $partial bytes): previous file intact"
elif "$S" convert "$W/big.strata" "$W/big2.strata" > /dev/null 2>&1 && cmp -s "$W/big.strata" "$W/big2.strata"; then
    ok "full-speed save finished before the kill: the new file is complete ($(size_of "$W/big.strata") bytes)"
else bad "killed full-speed save left a damaged file"; fi
rm -f "$tmp"
# A complete large session: load -> save byte-identical.
if "$S" convert "$CAGE" "$W/big.strata" --levels 5 > "$W/big.out"; then ok "large session: $(cat "$W/big.out")"; else bad "large session save"; fi
"$S" convert "$W/big.strata" "$W/big_2.strata" > /dev/null
cmp -s "$W/big.strata" "$W/big_2.strata" && ok "large session -> session byte-identical" || bad "large session re-save differs"
ls "$W"/*.tmp-* > /dev/null 2>&1 && bad "stray temporaries: $(ls "$W"/*.tmp-*)" || ok "no stray temporary files"

# ---- bad input ------------------------------------------------------------------------------
expect() { # label status command...
    local want=$1 label=$2; shift 2
    "$@" > /dev/null 2> "$W/err.txt"
    local got=$?
    if [ "$got" = "$want" ] && [ -s "$W/err.txt" ]; then ok "$label: exit $got: $(head -1 "$W/err.txt")"
    else bad "$label: exit $got (wanted $want), message '$(head -1 "$W/err.txt")'"; fi
}
head -c 5000 "$W/cc.strata" > "$W/cut.strata"
expect 1 "truncated session" "$S" convert "$W/cut.strata" "$W/x.obj"
cp "$W/cc.strata" "$W/flip.strata"
printf '\x55' | dd of="$W/flip.strata" bs=1 seek=4000 conv=notrunc status=none
expect 1 "bit-flipped session" "$S" convert "$W/flip.strata" "$W/x.obj"
grep -q "flip.strata" "$W/err.txt" && ok "the message names the file" || bad "message does not name the file"
printf 'STRATASN' > "$W/short.strata"
expect 1 "8-byte session" "$S" convert "$W/short.strata" "$W/x.obj"
cp "$CAGE" "$W/notasession.strata"
expect 1 "an OBJ named .strata" "$S" convert "$W/notasession.strata" "$W/x.obj"
expect 1 "missing input" "$S" convert "$W/none.obj" "$W/x.strata"
expect 2 "unknown output format" "$S" convert "$CAGE" "$W/x.stl"
expect 2 "unknown scheme" "$S" convert "$CAGE" "$W/x.strata" --scheme nope
expect 2 "--box with --levels" "$S" convert "$CAGE" "$W/x.strata" --levels 2 --box 0,0,0,1,1,1
expect 2 "bad box" "$S" convert "$CAGE" "$W/x.strata" --box 1,2,3
expect 2 "--level above the top" "$S" convert "$W/cc.strata" "$W/x.obj" --level 9
expect 1 "loop on a quad mesh" "$S" convert "$A/cube.obj" "$W/x.strata" --scheme loop
expect 1 "unwritable output" "$S" convert "$W/cc.strata" "/nonexistent/dir/x.strata"
expect 2 "no output" "$S" convert "$W/cc.strata"

# ---- sessions as input to the other commands ------------------------------------
if "$S" info "$W/cc.strata" > "$W/info.txt" && grep -q '^    3 ' "$W/info.txt"; then ok "strata info reads a session (levels 0..3)"
else bad "strata info on a session"; fi
"$S" subdivide "$W/cc.strata" -o "$W/cc_top.obj" > /dev/null
if cmp -s "$W/cc_top.obj" "$W/cc_d.obj"; then ok "strata subdivide of a session writes its top level"; else bad "subdivide of a session"; fi
"$S" subdivide "$W/cc.strata" --levels 4 -o "$W/cc_4.obj" > /dev/null
"$S" subdivide "$CAGE" --levels 4 -o "$W/cc_4d.obj" > /dev/null
if [ "$(faces_of "$W/cc_4.obj")" = "$(faces_of "$W/cc_4d.obj")" ]; then ok "a session refined one level further ($(faces_of "$W/cc_4.obj") faces)"
else bad "session --levels 4"; fi
if "$S" render "$W/cc.strata" --size 80x60 -o "$W/cc.png" | grep -q 'level 3'; then ok "strata render draws a session's top level"; else bad "render of a session"; fi
expect 2 "a session with another --scheme" "$S" info "$W/cc.strata" --scheme loop
expect 2 "a session's missing level" "$S" subdivide "$W/cc.strata" --level 7 -o "$W/x.obj"

echo "$((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
