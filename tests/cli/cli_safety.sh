#!/usr/bin/env bash
# The command line's safety net (issue 35):
#  - writes are atomic: with the file size limited (ulimit -f, writes fail
#    with EFBIG, no root needed) render, convert (OBJ, session, glTF with its
#    .bin) and bake fail with a message naming the output and the reason
#    ("File too large"), never a temporary; the old files stay byte for
#    byte; no temporary is left; bake's two maps stay both old when the
#    second one fails;
#  - temporaries of dead processes ("NAME.tmp-PID") are removed from the
#    folder a command writes into; a live process's, other names, symlinks
#    and other folders are left alone;
#  - glTF external buffers are confined to the glTF's folder: a FIFO, a
#    ../ escape, an absolute path, a symlink out, a file larger than its
#    byteLength, one over --mem-budget are refused within a second with the
#    glTF and the URI named; a good external buffer and data: URIs load;
#  - an input that is a FIFO or a device (a mesh, a session, a glTF, a
#    normal map) is refused within a second, not waited on.
# Usage: cli_safety.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
S=$1 D=$2 A=$3 B=$4
W=$B/cli_safety
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }
unset DISPLAY WAYLAND_DISPLAY
now_ms() { date +%s%3N; }
temps() { find "$1" -name '*.tmp*' | sort; }

# ---- atomic writes under a file-size limit ------------------------------------
# limited KB TAG PATTERN FILES... -- CMD...: CMD under `ulimit -f KB` exits
# 1 with PATTERN (the output and the reason) and no temporary's name in its
# message, every one of FILES keeps its bytes, no temporary is left.
limited() {
    local kb=$1 tag=$2 pat=$3
    shift 3
    local files=()
    while [ "$1" != "--" ]; do files+=("$1"); shift; done
    shift
    for f in "${files[@]}"; do cp "$f" "$f.before"; done
    local rc=0
    ( ulimit -f "$kb"; exec "$@" ) > "$W/$tag.out" 2> "$W/$tag.err" || rc=$?
    local kept=1
    for f in "${files[@]}"; do cmp -s "$f" "$f.before" || kept=0; rm -f "$f.before"; done
    if [ $rc -eq 1 ] && [ $kept = 1 ] && grep -q -- "$pat" "$W/$tag.err" && ! grep -q "tmp" "$W/$tag.err" \
       && [ -z "$(temps "$W")" ]; then
        ok "$tag: refused, old file(s) kept, no temporary: $(head -1 "$W/$tag.err")"
    else bad "$tag: exit $rc, kept $kept, temporaries '$(temps "$W")', message: $(cat "$W/$tag.err")"; fi
}

"$S" render "$A/cube.obj" -o "$W/r.png" > /dev/null || bad "render of the cube"
limited 8 render "r.png: write error: File too large" "$W/r.png" -- \
    "$S" render "$A/torus.obj" --levels 2 --size 800x800 -o "$W/r.png"
"$S" convert "$A/cube.obj" "$W/m.obj" > /dev/null || bad "convert to OBJ"
limited 4 convert_obj "m.obj: .*File too large" "$W/m.obj" -- "$S" convert "$A/torus.obj" "$W/m.obj" --levels 2
"$S" convert "$A/cube.obj" "$W/s.strata" > /dev/null || bad "convert to a session"
limited 8 convert_session "s.strata: .*File too large" "$W/s.strata" -- "$S" convert "$A/torus.obj" "$W/s.strata" --levels 2
mkdir -p "$W/gl"
"$S" convert "$A/cube.obj" "$W/gl/g.gltf" > /dev/null || bad "convert to glTF"
limited 16 convert_gltf "g.bin: write error: File too large" "$W/gl/g.gltf" "$W/gl/g.bin" -- \
    "$S" convert "$A/torus.obj" "$W/gl/g.gltf" --levels 2
# bake: the normal map fits the limit, the displacement map does not: both
# stay old (they appear together or not at all).
"$S" convert "$A/cube.obj" "$W/cube.strata" --levels 2 > /dev/null
"$S" bake "$W/cube.strata" --base-level 0 --normal-map "$W/n.png" --displacement-map "$W/d.exr" --size 64 --auto-uv > /dev/null \
    || bad "bake at 64"
"$S" bake "$W/cube.strata" --base-level 0 --normal-map "$W/n_big.png" --displacement-map "$W/d_big.exr" --size 256 --auto-uv > /dev/null
nkb=$(( ($(stat -c %s "$W/n_big.png") + 1023) / 1024 )) dkb=$(( ($(stat -c %s "$W/d_big.exr") + 1023) / 1024 ))
rm -f "$W/n_big.png" "$W/d_big.exr"
if [ "$dkb" -gt "$nkb" ]; then
    limited "$nkb" bake "d.exr: write error: File too large" "$W/n.png" "$W/d.exr" -- \
        "$S" bake "$W/cube.strata" --base-level 0 --normal-map "$W/n.png" --displacement-map "$W/d.exr" --size 256 --auto-uv
else bad "bake: the displacement map ($dkb KB) is not larger than the normal map ($nkb KB) at 256"; fi

# ---- temporaries of dead processes are swept ------------------------------------
sh -c 'exit 0' & dead=$!
wait $dead
if kill -0 "$dead" 2>/dev/null; then bad "pid $dead still alive"; fi
mkdir -p "$W/sw" "$W/other"
echo stale > "$W/sw/old.png.tmp-$dead"
echo stale > "$W/sw/x.strata.tmp-$dead"
echo live > "$W/sw/live.obj.tmp-$$"
echo keep > "$W/sw/notes.tmp-12ab"
echo keep > "$W/sw/plain.tmp-"
echo keep > "$W/other/y.obj.tmp-$dead"
echo target > "$W/target.txt"
ln -s "$W/target.txt" "$W/sw/link.png.tmp-$dead"
"$S" render "$A/cube.obj" -o "$W/sw/r.png" > /dev/null || bad "render into sw"
if [ ! -e "$W/sw/old.png.tmp-$dead" ] && [ ! -e "$W/sw/x.strata.tmp-$dead" ]; then ok "a dead process's temporaries removed"
else bad "dead temporaries left: $(ls "$W/sw")"; fi
if [ -e "$W/sw/live.obj.tmp-$$" ] && [ -e "$W/sw/notes.tmp-12ab" ] && [ -e "$W/sw/plain.tmp-" ] && [ -L "$W/sw/link.png.tmp-$dead" ] \
   && [ -e "$W/other/y.obj.tmp-$dead" ] && [ -e "$W/target.txt" ]; then
    ok "a live process's temporary, other names, a symlink and another folder left alone"
else bad "too much swept: sw: $(ls "$W/sw"), other: $(ls "$W/other")"; fi
# A killed writer's temporary (kill -9 while it writes a session) goes at
# the next command writing there.
"$S" convert "$D/catmull_clark/spot_quadrangulated.obj" "$W/sw/big.strata" --levels 4 > /dev/null 2>&1 & w=$!
for _ in $(seq 1 200); do ls "$W/sw" | grep -q "^big.strata.tmp-$w$" && break; sleep 0.05; done
kill -9 $w 2>/dev/null; wait $w 2>/dev/null
if [ -e "$W/sw/big.strata.tmp-$w" ]; then
    "$S" convert "$A/cube.obj" "$W/sw/c.obj" > /dev/null
    if [ ! -e "$W/sw/big.strata.tmp-$w" ]; then ok "a killed writer's temporary removed by the next write there"
    else bad "a killed writer's temporary stays"; fi
else echo "note: the writer finished before the kill; the kill case is not exercised"; fi

# ---- glTF external buffers --------------------------------------------------------
G=$W/gltf
mkdir -p "$G/in"
"$S" convert "$A/cube.obj" "$G/in/cube.gltf" > /dev/null || bad "convert cube to glTF"
len=$(stat -c %s "$G/in/cube.bin")
if "$S" info "$G/in/cube.gltf" > /dev/null 2> "$W/good.err"; then ok "a glTF with its external buffer in its folder loads"
else bad "good external buffer: $(cat "$W/good.err")"; fi
# variant NAME URI [BYTELENGTH]: cube.gltf with the buffer's uri (and
# byteLength) replaced, in $G/in.
variant() {
    sed -e "s|\"uri\": \"cube.bin\"|\"uri\": \"$2\"|" \
        -e "/\"buffers\"/,/]/s|\"byteLength\": $len|\"byteLength\": ${3:-$len}|" "$G/in/cube.gltf" > "$G/in/$1.gltf"
}
# refused_gltf NAME URI PATTERN [info options]: refused within a second,
# exit 1, the glTF and the URI named.
refused_gltf() {
    local name=$1 uri=$2 pat=$3
    shift 3
    local t0 t1 rc=0
    t0=$(now_ms)
    timeout 10 "$S" info "$G/in/$name.gltf" "$@" > /dev/null 2> "$W/$name.err" || rc=$?
    t1=$(now_ms)
    if [ $rc -eq 1 ] && grep -qF "$name.gltf: buffer '$uri': " "$W/$name.err" && grep -q -- "$pat" "$W/$name.err" \
       && [ $((t1 - t0)) -lt 1000 ]; then
        ok "$name refused in $((t1 - t0)) ms: $(head -1 "$W/$name.err")"
    else bad "$name: exit $rc after $((t1 - t0)) ms: $(cat "$W/$name.err")"; fi
}
mkfifo "$G/in/fifo.bin"
variant fifo fifo.bin
refused_gltf fifo fifo.bin "a FIFO, not a regular file"
cp "$G/in/cube.bin" "$G/outside.bin"
variant escape ../outside.bin
refused_gltf escape ../outside.bin "outside the glTF's folder"
variant deep ../../../../../../../../dev/zero
refused_gltf deep ../../../../../../../../dev/zero "outside the glTF's folder"
variant absolute /etc/passwd
refused_gltf absolute /etc/passwd "an absolute path"
ln -s ../outside.bin "$G/in/link.bin"
variant link link.bin
refused_gltf link link.bin "outside the glTF's folder"
ln -s /dev/zero "$G/in/zero.bin"
variant zero zero.bin
refused_gltf zero zero.bin "outside the glTF's folder"
mkdir "$G/in/dir.bin"
variant dir dir.bin
refused_gltf dir dir.bin "a folder, not a regular file"
head -c $((len + 100)) /dev/zero > "$G/in/long.bin"
variant long long.bin
refused_gltf long long.bin "$((len + 100)) bytes, more than the buffer's byteLength $len"
truncate -s 40M "$G/in/huge.bin"
variant huge huge.bin 41943040
refused_gltf huge huge.bin "reading it needs about 40.0 MiB more (estimate)" --mem-budget 30
variant missing nothere.bin
refused_gltf missing nothere.bin "No such file or directory"
# A symlink that stays inside the folder is followed.
ln -s cube.bin "$G/in/alias.bin"
variant alias alias.bin
if "$S" info "$G/in/alias.gltf" > /dev/null 2> "$W/alias.err"; then ok "a symlink inside the folder loads"
else bad "symlink inside: $(cat "$W/alias.err")"; fi
# A data: URI still loads.
b64=$(base64 -w0 "$G/in/cube.bin")
variant data "data:application/octet-stream;base64,$b64"
if "$S" info "$G/in/data.gltf" > /dev/null 2> "$W/data.err"; then ok "a data: URI loads"
else bad "data: URI: $(cat "$W/data.err")"; fi

# ---- inputs that are not regular files: refused at once, never waited on -------
mkdir -p "$W/fifo"
for f in in.obj in.strata in.gltf in.glb nm.png; do mkfifo "$W/fifo/$f"; done
ln -s /dev/zero "$W/fifo/zero.obj"
# at_once TAG PATTERN CMD...: exit 1 within a second with PATTERN.
at_once() {
    local tag=$1 pat=$2
    shift 2
    local t0 t1 rc=0
    t0=$(now_ms)
    timeout 10 "$@" > /dev/null 2> "$W/$tag.err" || rc=$?
    t1=$(now_ms)
    if [ $rc -eq 1 ] && grep -q -- "$pat" "$W/$tag.err" && [ $((t1 - t0)) -lt 1000 ]; then
        ok "$tag refused in $((t1 - t0)) ms: $(head -1 "$W/$tag.err")"
    else bad "$tag: exit $rc after $((t1 - t0)) ms: $(cat "$W/$tag.err")"; fi
}
at_once fifo_obj "fifo/in.obj: a FIFO, not a regular file" "$S" info "$W/fifo/in.obj"
at_once fifo_session "fifo/in.strata: a FIFO, not a regular file" "$S" info "$W/fifo/in.strata"
at_once fifo_gltf "fifo/in.gltf: cannot read: a FIFO, not a regular file" "$S" info "$W/fifo/in.gltf"
at_once fifo_glb "fifo/in.glb: cannot read: a FIFO, not a regular file" "$S" info "$W/fifo/in.glb"
at_once device_obj "fifo/zero.obj: a device, not a regular file" "$S" info "$W/fifo/zero.obj"
at_once fifo_normal_map "fifo/nm.png: a FIFO, not a regular file" "$S" render "$A/cube.obj" --normal-map "$W/fifo/nm.png" -o "$W/fifo/r.png"

echo "$((n - fail)) passed, $fail failed"
[ $fail -eq 0 ]
