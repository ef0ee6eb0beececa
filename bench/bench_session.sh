#!/usr/bin/env bash
# Session size, save and load of two builds of strata, in alternating runs
# (the speed issue's "compact sessions"): for each model, each build writes
# its own session of the model (strata convert MESH OUT.strata, timed as
# "build + save"), then loads it (strata info OUT.strata, "load") and loads
# and saves it again (strata convert OUT.strata OUT2.strata, "load + save";
# "save" is that minus "load").  Prints each side's session size, the
# medians of ROUNDS runs and the ratios new / old.  Whole-process wall
# times: run it on a quiet machine.
#   bench/bench_session.sh OLD_STRATA NEW_STRATA [ROUNDS]
set -euo pipefail
old=$1 new=$2 rounds=${3:-5}
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MESHES="${STRATA_SHARED_DATA:-$ROOT/../shared/data/meshes}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# model: name, mesh, the command that makes its session (convert: the
# subdivision levels, compared with the binary PLY of the finest level;
# rebuild: a progressive hierarchy, compared with the input OBJ), options.
models=(
  "spot_cc4|$MESHES/catmull_clark/spot_quadrangulated.obj|convert|--scheme catmull-clark --levels 4"
  "blub_cc4|$MESHES/catmull_clark/blub_quadrangulated.obj|convert|--scheme catmull-clark --levels 4"
  "koala_progressive|$MESHES/large/koala.obj|rebuild|--method progressive"
)
make_session() {   # exe tool mesh out opts...
    local exe=$1 tool=$2 mesh=$3 out=$4; shift 4
    if [ "$tool" = rebuild ]; then "$exe" rebuild "$mesh" "$@" -o "$out"; else "$exe" convert "$mesh" "$out" "$@"; fi
}

secs() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N); echo "$t1 - $t0" | bc; }
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

for m in "${models[@]}"; do
    IFS='|' read -r name mesh tool opts <<<"$m"
    [ -f "$mesh" ] || { echo "$name: $mesh missing, skipped"; continue; }
    if [ "$tool" = rebuild ]; then
        ref=$(stat -c %s "$mesh") refname="input OBJ"
    else
        # shellcheck disable=SC2086
        "$new" subdivide "$mesh" $opts -o "$work/$name.ply" >/dev/null 2>&1
        ref=$(stat -c %s "$work/$name.ply") refname="binary PLY of the finest level"
    fi
    declare -A t=()
    for side in old new; do for k in build load resave; do t[$side.$k]=""; done; done
    for ((i = 1; i <= rounds; i++)); do
        for side in old new; do
            exe=${!side}
            f="$work/$name.$side.strata"
            # shellcheck disable=SC2086
            t[$side.build]+="$(secs make_session "$exe" "$tool" "$mesh" "$f" $opts) "
            t[$side.load]+="$(secs "$exe" info "$f") "
            t[$side.resave]+="$(secs "$exe" convert "$f" "$work/$name.$side.2.strata") "
        done
    done
    so=$(stat -c %s "$work/$name.old.strata") sn=$(stat -c %s "$work/$name.new.strata")
    cmp -s "$work/$name.new.strata" "$work/$name.new.2.strata" || echo "$name: new: load -> save is not byte-identical"
    echo "$name: session old $so bytes, new $sn bytes: new/old $(echo "scale=3; $sn / $so" | bc)x;" \
         "$refname $ref bytes: new/ref $(echo "scale=3; $sn / $ref" | bc)x, old/ref $(echo "scale=3; $so / $ref" | bc)x"
    for k in build load resave; do
        mo=$(tr ' ' '\n' <<<"${t[old.$k]}" | grep . | median)
        mn=$(tr ' ' '\n' <<<"${t[new.$k]}" | grep . | median)
        echo "  $k: old $mo s, new $mn s, new/old $(echo "scale=3; $mn / $mo" | bc)x  (medians of $rounds)"
    done
    ls_=$(tr ' ' '\n' <<<"${t[old.load]}" | grep . | median) rs=$(tr ' ' '\n' <<<"${t[old.resave]}" | grep . | median)
    ln=$(tr ' ' '\n' <<<"${t[new.load]}" | grep . | median) rn=$(tr ' ' '\n' <<<"${t[new.resave]}" | grep . | median)
    echo "  save (load + save - load): old $(echo "$rs - $ls_" | bc) s, new $(echo "$rn - $ln" | bc) s," \
         "new/old $(echo "scale=3; ($rn - $ln) / ($rs - $ls_)" | bc)x"
    unset t
done
