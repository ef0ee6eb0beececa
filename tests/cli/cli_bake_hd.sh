#!/usr/bin/env bash
# strata bake with HD levels (app/cmd_bake.c, core/bake/bake_walk.c): a
# session whose HD levels hold a bump (strata deform --level 5 --box on
# spot, model levels 0..2) bakes from its HD hierarchy's top by default,
# each texel from the finest face there.  Against the same model without
# HD levels (strata deform with a zero bump: the same bits, no hdlv chunk)
# the normal maps differ in the bump's region and are equal elsewhere (the
# figures are printed); --level 2 of the HD session bakes the model's level
# 2, byte for byte the map without HD; an HD level below the top bakes; a
# level above the HD top is refused, the old map left as it was.
# Usage: cli_bake_hd.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
S=$1 D=$2 B=$4
SPOT=$D/catmull_clark/spot_quadrangulated.obj
[ -f "$SPOT" ] || { echo "note: $SPOT not found: skipped"; exit 77; }
W=$B/cli_bake_hd
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }

# Texels of two 8-bit RGB PNGs of one size: "differing used total" (used:
# not the background normal (128,128,255) in one of them).  The standard
# library's zlib and the five PNG row filters; nothing to install.
cat > "$W/pngdiff.py" <<'PY'
import sys, zlib, struct
def load(path):
    b = open(path, 'rb').read()
    assert b[:8] == b'\x89PNG\r\n\x1a\n', path
    off, idat, w = 8, b'', 0
    while off < len(b):
        n, t = struct.unpack('>I4s', b[off:off + 8])
        d = b[off + 8:off + 8 + n]
        if t == b'IHDR': w, h, depth, ctype = struct.unpack('>IIBB', d[:10])
        if t == b'IDAT': idat += d
        off += 12 + n
    assert depth == 8 and ctype == 2, (path, depth, ctype)
    raw, bpp, stride, rows, prev = zlib.decompress(idat), 3, 3 * w, [], bytearray(3 * w)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + prev[i]) & 255
            elif f == 3: line[i] = (line[i] + (a + prev[i]) // 2) & 255
            elif f == 4:
                p = a + prev[i] - c; pa, pb, pc = abs(p - a), abs(p - prev[i]), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else prev[i] if pb <= pc else c)) & 255
        rows.append(bytes(line)); prev = line
    return w, h, b''.join(rows)
wa, ha, a = load(sys.argv[1]); wb, hb, b = load(sys.argv[2])
assert (wa, ha) == (wb, hb)
bg = bytes((128, 128, 255))
n = wa * ha
diff = sum(1 for i in range(n) if a[3 * i:3 * i + 3] != b[3 * i:3 * i + 3])
used = sum(1 for i in range(n) if a[3 * i:3 * i + 3] != bg or b[3 * i:3 * i + 3] != bg)
print(diff, used, n)
PY
pngdiff() { python3 "$W/pngdiff.py" "$1" "$2"; }

"$S" deform "$SPOT" --levels 2 --level 5 --box 0.35,0.6,-0.3,0.6,0.8,-0.1 --bump 0.47,0.7,-0.2,0.05,0.02,0.01,0 \
    -o "$W/hd.strata" > /dev/null || bad "deform --level 5"
"$S" deform "$SPOT" --levels 2 --level 2 --bump 0,0,0,1,0,0,0 -o "$W/plain.strata" > /dev/null || bad "deform without HD"
if "$S" info "$W/plain.strata" | grep -q "^HD"; then bad "plain.strata has HD levels"; fi

bake() { "$S" bake "$1" --base-level 0 --size 256 --normal-map "$2" --displacement-map "${2%.png}.exr" "${@:3}"; }
if bake "$W/hd.strata" "$W/hd.png" > "$W/hd.txt"; then
    cat "$W/hd.txt"
    if grep -q "baking from the HD levels (3\.\.5 above the model's 0\.\.2): level 5" "$W/hd.txt" &&
       grep -q "^level 5 onto level 0: " "$W/hd.txt" && grep -q "correspondence: exact" "$W/hd.txt"; then
        ok "the HD session bakes from HD level 5, exactly"
    else bad "the HD bake's report"; fi
else bad "bake of the HD session failed"; fi
bake "$W/plain.strata" "$W/plain.png" > "$W/plain.txt" || bad "bake of the session without HD failed"
bake "$W/hd.strata" "$W/model2.png" --level 2 > /dev/null || bad "bake --level 2 of the HD session failed"
if cmp -s "$W/model2.png" "$W/plain.png" && cmp -s "$W/model2.exr" "$W/plain.exr"; then
    ok "--level 2 of the HD session: the model's maps, byte for byte"
else bad "--level 2 of the HD session differs from the bake without HD"; fi

read -r diff used total <<< "$(pngdiff "$W/hd.png" "$W/plain.png")"
echo "normal maps, HD against no HD: $diff texels differ, $((used - diff)) of $used used texels equal ($total in the map)"
if [ "${diff:-0}" -gt 0 ]; then ok "the HD detail is in the normal map ($diff texels differ)"
else bad "the HD bake's normal map equals the one without HD"; fi
# The bump (radius 0.05 on a 1.7-unit cow) covers well under 2 % of the
# map; every other texel is baked from the same faces of level 2.
if [ "${used:-0}" -gt 0 ] && [ $((diff * 50)) -lt "$used" ]; then ok "elsewhere the maps are equal ($((used - diff)) of $used texels)"
else bad "$diff of $used texels differ: more than the HD region"; fi
# The leaves of the adaptive map tile every face of level 0: no texel lost.
cov() { sed -n 's/^coverage: \([0-9]*\) of.*/\1/p' "$1"; }
if [ -n "$(cov "$W/hd.txt")" ] && [ "$(cov "$W/hd.txt")" = "$(cov "$W/plain.txt")" ]; then ok "same coverage: $(cov "$W/hd.txt") texels"
else bad "coverage $(cov "$W/hd.txt") with HD, $(cov "$W/plain.txt") without"; fi
dmax() { sed -n 's/.*displacement .* \.\. \([-0-9.e]*\)$/\1/p' "$1"; }
dh=$(dmax "$W/hd.txt") dp=$(dmax "$W/plain.txt")
if awk -v a="$dh" -v b="$dp" 'BEGIN { exit !(a > b + 0.005) }'; then ok "the displacement map holds the bump: max $dh against $dp"
else bad "displacement max $dh (HD) against $dp"; fi

bake "$W/hd.strata" "$W/hd4.png" --level 4 > "$W/hd4.txt" && grep -q "^level 4 onto level 0" "$W/hd4.txt" &&
    ok "HD level 4 bakes" || bad "HD level 4: $(cat "$W/hd4.txt")"
cp "$W/hd.png" "$W/keep.png"
if "$S" bake "$W/hd.strata" --base-level 0 --level 6 --size 256 --normal-map "$W/hd.png" 2> "$W/r.err"; then
    bad "--level 6 above the HD top was baked"
elif grep -q "HD levels go up to 5" "$W/r.err" && cmp -s "$W/hd.png" "$W/keep.png"; then ok "refused: $(cat "$W/r.err")"
else bad "--level 6: $(cat "$W/r.err")"; fi

echo "$((n - fail))/$n passed"
[ "$fail" -eq 0 ]
