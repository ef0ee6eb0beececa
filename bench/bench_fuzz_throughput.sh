#!/usr/bin/env bash
# Throughput of two builds of one libFuzzer target, each on its own seed
# corpus, in alternating runs; prints each run's exec/s, the medians and
# their ratio (new / old).  Used for fuzz_session (the first-hour issue's
# "at least 5x"):
#   bench/bench_fuzz_throughput.sh OLD_EXE OLD_CORPUS NEW_EXE NEW_CORPUS [SECONDS] [ROUNDS]
# The corpora are copied for each run (the fuzzer writes into its folder);
# the same -seed is used on both sides.
set -euo pipefail
old=$1 oldc=$2 new=$3 newc=$4 secs=${5:-20} rounds=${6:-5}
run() {
    local exe=$1 corpus=$2 work
    work=$(mktemp -d)
    cp -R "$corpus"/. "$work"/
    "$exe" -seed=1 -max_total_time="$secs" -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 "$work" 2>&1 |
        sed -n 's/^stat::average_exec_per_sec: *//p'
    rm -rf "$work"
}
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
o=() n=()
for ((i = 1; i <= rounds; i++)); do
    o+=("$(run "$old" "$oldc")")
    n+=("$(run "$new" "$newc")")
    echo "round $i: old ${o[-1]} exec/s, new ${n[-1]} exec/s"
done
mo=$(printf '%s\n' "${o[@]}" | median)
mn=$(printf '%s\n' "${n[@]}" | median)
awk -v a="$mo" -v b="$mn" 'BEGIN { printf "median: old %d exec/s, new %d exec/s, new/old %.2fx\n", a, b, b / a }'
