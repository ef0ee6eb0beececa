#!/usr/bin/env bash
# strata deform: a Gaussian bump at level L moves every vertex v of level L
# by D*exp(-|v-C|^2/R^2) (checked vertex by vertex against the formula on
# the OBJ of level L before and after), the vertex at C by D, far vertices
# not at all, the levels below L not at all, and the finest level follows;
# a mesh input is built with --scheme/--levels first.  Bad arguments are
# refused with the argument named, a non-zero exit, nothing written and an
# existing OUT left byte for byte as it was.
# Usage: cli_deform.sh STRATA SHARED_MESHES ASSETS BINDIR
set -uo pipefail
S=$1 D=$2 A=$3 B=$4
W=$B/cli_deform
rm -rf "$W"
mkdir -p "$W"
fail=0 n=0
ok() { n=$((n + 1)); echo "ok   $*"; }
bad() { n=$((n + 1)); fail=$((fail + 1)); echo "FAIL $*"; }

level_obj() { "$S" convert "$1" "$2" --level "$3" --no-normals > /dev/null; }

# Compares two OBJs of the same level (same vertex order) against the bump
# C,R,D: prints the largest error against the formula, the move of the
# vertex nearest C over |D|, the largest move of a vertex farther than 6R.
check_bump() {   # before.obj after.obj cx cy cz r dx dy dz
    awk -v cx="$3" -v cy="$4" -v cz="$5" -v r="$6" -v dx="$7" -v dy="$8" -v dz="$9" '
        function abs(x) { return x < 0 ? -x : x }
        FNR == NR && /^v / { nb++; X[nb] = $2; Y[nb] = $3; Z[nb] = $4; next }
        /^v / {
            na++
            q2 = (X[na] - cx) ^ 2 + (Y[na] - cy) ^ 2 + (Z[na] - cz) ^ 2; w = exp(-q2 / (r * r))
            e = abs($2 - X[na] - dx * w) + abs($3 - Y[na] - dy * w) + abs($4 - Z[na] - dz * w)
            if (e > emax) emax = e
            m = sqrt(($2 - X[na]) ^ 2 + ($3 - Y[na]) ^ 2 + ($4 - Z[na]) ^ 2)
            if (na == 1 || q2 < qbest) { qbest = q2; mnear = m }
            if (q2 > 36 * r * r && m > mfar) mfar = m
        }
        END { if (na != nb || na == 0) print "count", nb, na
              else printf "%.3g %.9f %.3g\n", emax, mnear / sqrt(dx * dx + dy * dy + dz * dz), mfar }' "$1" "$2"
}

# Largest move between two OBJs of the same level, over |D|, and the largest
# move of a vertex farther than FAR from C (the count of those follows).
moves() {   # before.obj after.obj cx cy cz far dnorm
    awk -v cx="$3" -v cy="$4" -v cz="$5" -v far="$6" -v dn="$7" '
        FNR == NR && /^v / { nb++; X[nb] = $2; Y[nb] = $3; Z[nb] = $4; next }
        /^v / { na++; m = sqrt(($2 - X[na]) ^ 2 + ($3 - Y[na]) ^ 2 + ($4 - Z[na]) ^ 2)
                if (m > mmax) mmax = m
                if ((X[na] - cx) ^ 2 + (Y[na] - cy) ^ 2 + (Z[na] - cz) ^ 2 > far * far) { nfar++; if (m > mfar) mfar = m } }
        END { if (na != nb || na == 0) print "count", nb, na; else printf "%.6f %.3g %d\n", mmax / dn, mfar, nfar }' "$1" "$2"
}

# A vertex of level L of f as "x,y,z" (the bump's centre).
vertex_of() { awk -v k="$2" '/^v / { i++; if (i == k) { print $2 "," $3 "," $4; exit } }' "$1"; }

# ---- a session: blub's cage with three Catmull-Clark levels, a bump at 1 ----
"$S" convert "$D/catmull_clark/blub_control_mesh.obj" "$W/in.strata" --levels 3 > /dev/null || bad "convert to a session failed"
level_obj "$W/in.strata" "$W/in1.obj" 1
level_obj "$W/in.strata" "$W/in0.obj" 0
level_obj "$W/in.strata" "$W/in3.obj" 3
C=$(vertex_of "$W/in1.obj" 40)
R=0.2 DX=0 DY=0.1 DZ=0.05
if "$S" deform "$W/in.strata" --level 1 --bump "$C,$R,$DX,$DY,$DZ" -o "$W/out.strata" > "$W/out.txt" 2> "$W/out.err"; then
    ok "deform at level 1: $(cat "$W/out.txt")"
else bad "deform at level 1 failed: $(cat "$W/out.err")"; fi
level_obj "$W/out.strata" "$W/out1.obj" 1
level_obj "$W/out.strata" "$W/out0.obj" 0
level_obj "$W/out.strata" "$W/out3.obj" 3
read -r emax near far <<< "$(check_bump "$W/in1.obj" "$W/out1.obj" ${C//,/ } $R $DX $DY $DZ)"
if awk -v e="$emax" 'BEGIN { exit !(e < 1e-9) }'; then ok "level 1 moved as the formula says (largest error $emax)"
else bad "level 1 against the formula: largest error $emax"; fi
if awk -v m="$near" 'BEGIN { exit !(m > 0.999999 && m < 1.000001) }'; then ok "the vertex at C moved by D ($near |D|)"
else bad "the vertex at C moved by $near |D|"; fi
if awk -v m="$far" 'BEGIN { exit !(m < 1e-12) }'; then ok "level-1 vertices farther than 6R did not move ($far)"
else bad "level-1 vertices farther than 6R moved by $far"; fi
if cmp -s "$W/in0.obj" "$W/out0.obj"; then ok "level 0 unchanged"; else bad "level 0 changed by an edit at level 1"; fi
read -r top fartop nfar <<< "$(moves "$W/in3.obj" "$W/out3.obj" ${C//,/ } 1.6 "$(awk -v a=$DX -v b=$DY -v c=$DZ 'BEGIN { print sqrt(a*a + b*b + c*c) }')")"
if awk -v m="$top" -v f="$fartop" -v k="$nfar" 'BEGIN { exit !(m > 0.5 && m < 1.5 && f < 1e-12 && k > 100) }'; then
    ok "the finest level (3) followed: largest move $top |D|, none of the $nfar vertices farther than 8R moved ($fartop)"
else bad "the finest level: largest move $top |D|, $fartop for the $nfar farther than 8R"; fi
"$S" convert "$W/out.strata" "$W/out2.strata" > /dev/null
if cmp -s "$W/out.strata" "$W/out2.strata"; then ok "the deformed session re-saves byte-identically"
else bad "the deformed session re-saves differently"; fi

# A radius whose square underflows: the vertex at C moves by D, no other.
"$S" deform "$W/in.strata" --level 1 --bump "$C,1e-200,$DX,$DY,$DZ" -o "$W/tiny.strata" > "$W/tiny.txt" 2> "$W/tiny.err" \
    || bad "deform with R = 1e-200 failed: $(cat "$W/tiny.err")"
level_obj "$W/tiny.strata" "$W/tiny1.obj" 1
read -r emax near far <<< "$(check_bump "$W/in1.obj" "$W/tiny1.obj" ${C//,/ } 1e-200 $DX $DY $DZ)"
if grep -q ": 1 vertex of level 1 moved" "$W/tiny.txt" && awk -v m="$near" 'BEGIN { exit !(m > 0.999999 && m < 1.000001) }'; then
    ok "R = 1e-200: only the vertex at C moved, by D ($(cat "$W/tiny.txt"))"
else bad "R = 1e-200: $(cat "$W/tiny.txt"), the vertex at C by $near |D|"; fi

# ---- a mesh input: built with --scheme/--levels, a bump at level 0 ----------
C0=$(vertex_of "$W/in0.obj" 7)
if "$S" deform "$D/catmull_clark/blub_control_mesh.obj" --scheme catmull-clark --levels 2 --level 0 \
        --bump "$C0,0.3,0.05,-0.1,0" -o "$W/mesh.strata" > "$W/mesh.txt" 2> "$W/mesh.err"; then
    ok "deform of a mesh: $(cat "$W/mesh.txt")"
else bad "deform of a mesh failed: $(cat "$W/mesh.err")"; fi
level_obj "$W/mesh.strata" "$W/mesh0.obj" 0
read -r emax near far <<< "$(check_bump "$W/in0.obj" "$W/mesh0.obj" ${C0//,/ } 0.3 0.05 -0.1 0)"
if awk -v e="$emax" -v m="$near" 'BEGIN { exit !(e < 1e-9 && m > 0.999999 && m < 1.000001) }'; then
    ok "mesh input: level 0 moved as the formula says (error $emax, the vertex at C by $near |D|)"
else bad "mesh input: error $emax, the vertex at C by $near |D|"; fi
if "$S" info "$W/mesh.strata" | grep -q "scheme catmull-clark, 3 levels (0..2)"; then ok "mesh input built to --levels 2"
else bad "mesh input: $("$S" info "$W/mesh.strata" | head -1)"; fi

# ---- refusals: argument named, non-zero exit, nothing written, OUT kept ------
cp "$W/out.strata" "$W/keep.strata"
refuse() {   # tag pattern args...
    local tag=$1 pat=$2
    shift 2
    rm -f "$W/new.strata"
    cp "$W/out.strata" "$W/existing.strata"
    local rc=0 rc2=0
    "$S" deform "$@" -o "$W/new.strata" > /dev/null 2> "$W/ref.err" || rc=$?
    "$S" deform "$@" -o "$W/existing.strata" > /dev/null 2> /dev/null || rc2=$?
    if [ $rc -ne 0 ] && [ $rc2 -ne 0 ] && grep -q -e "$pat" "$W/ref.err" && [ ! -e "$W/new.strata" ] \
       && cmp -s "$W/existing.strata" "$W/keep.strata"; then
        ok "$tag refused (exit $rc): $(head -1 "$W/ref.err")"
    else bad "$tag: exit $rc/$rc2, $(cat "$W/ref.err"), new written: $([ -e "$W/new.strata" ] && echo yes || echo no)"; fi
}
refuse "unknown level" "--level 4 does not exist" "$W/in.strata" --level 4 --bump "0,0,0,1,0,0,1"
refuse "level not a number" "--level wants" "$W/in.strata" --level x --bump "0,0,0,1,0,0,1"
refuse "no level" "--level L is required" "$W/in.strata" --bump "0,0,0,1,0,0,1"
refuse "NaN centre" "--bump: number 1 .* not finite" "$W/in.strata" --level 1 --bump "nan,0,0,1,0,0,1"
refuse "infinite move" "--bump: number 7 .* not finite" "$W/in.strata" --level 1 --bump "0,0,0,1,0,0,inf"
refuse "zero radius" "--bump: the radius R .* must be > 0" "$W/in.strata" --level 1 --bump "0,0,0,0,0,0,1"
refuse "negative radius" "--bump: the radius R .* must be > 0" "$W/in.strata" --level 1 --bump "0,0,0,-1,0,0,1"
refuse "six numbers" "--bump wants 7 numbers .* got 6" "$W/in.strata" --level 1 --bump "0,0,0,1,0,0"
refuse "eight numbers" "--bump wants 7 numbers .* got 8" "$W/in.strata" --level 1 --bump "0,0,0,1,0,0,1,2"
refuse "not a number" "--bump wants 7 numbers .*number 3 is not a number" "$W/in.strata" --level 1 --bump "0,0,z,1,0,0,1"
refuse "an edit past the double range" "a number in the positions is not finite" "$W/in.strata" --level 1 --bump "0,0,0,10,1e308,1e308,1e308"
refuse "no bump" "--bump CX,CY,CZ,R,DX,DY,DZ is required" "$W/in.strata" --level 1
refuse "unknown scheme" "unknown scheme 'nope'" "$D/catmull_clark/blub_control_mesh.obj" --scheme nope --level 0 --bump "0,0,0,1,0,0,1"
refuse "missing input" "missing.obj" "$W/missing.obj" --level 0 --bump "0,0,0,1,0,0,1"
# Over the memory budget: refused from the estimate, exit 1, nothing written.
rc=0; "$S" deform "$D/catmull_clark/spot_quadrangulated.obj" --levels 5 --level 0 --bump "0,0,0,1,0,0,1" --mem-budget 50 \
    -o "$W/budget.strata" > /dev/null 2> "$W/budget.err" || rc=$?
if [ $rc -eq 1 ] && grep -q "needs about .* MiB more (estimate).*memory budget is 50.0 MiB" "$W/budget.err" && [ ! -e "$W/budget.strata" ]; then
    ok "over --mem-budget refused: $(head -c 160 "$W/budget.err")"
else bad "over --mem-budget: exit $rc, $(cat "$W/budget.err")"; fi
rc=0; "$S" deform "$W/in.strata" --level 1 --bump "0,0,0,1,0,0,1" > /dev/null 2> "$W/noout.err" || rc=$?
if [ $rc -ne 0 ] && grep -q -e "-o OUT.strata is required" "$W/noout.err"; then ok "missing -o refused (exit $rc): $(head -1 "$W/noout.err")"
else bad "missing -o: exit $rc, $(cat "$W/noout.err")"; fi
rc=0; "$S" deform "$W/in.strata" --level 1 --bump "0,0,0,1,0,0,1" -o "$W/out.obj" > /dev/null 2> "$W/obj.err" || rc=$?
if [ $rc -ne 0 ] && grep -q -e "-o .*out.obj: the output is a session" "$W/obj.err" && [ ! -e "$W/out.obj" ]; then
    ok "a mesh output refused (exit $rc): $(head -1 "$W/obj.err")"
else bad "a mesh output: exit $rc, $(cat "$W/obj.err")"; fi
if ls "$W" | grep -q "\.tmp-"; then bad "temporaries left: $(ls "$W" | grep "\.tmp-")"; else ok "no temporary left"; fi

if "$S" help | grep -qE '^[[:space:]]*deform[[:space:]]'; then ok "help lists deform"; else bad "help does not list deform"; fi

echo "$((n - fail)) passed, $fail failed"
[ $fail -eq 0 ]
