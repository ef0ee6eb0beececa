#!/usr/bin/env bash
# Whole process, Strata against OpenSubdiv: `strata info` and
# `strata subdivide -o OUT.ply` against bench/osd_program.cpp doing
# OpenSubdiv's factory + RefineUniform + Interpolate (double) on the same
# file, then printing the per-level counts or writing the same binary PLY.
# Each command runs RUNS times (default 5), the four commands interleaved
# so that a change in the machine's load falls on all alike; /usr/bin/time
# measures wall time, CPU time (user + system) and peak resident memory.
# Prints the medians and the ratios Strata / OpenSubdiv.  OBJ=1 adds a
# third pair: `strata subdivide -o OUT.obj` against `osd_program obj` (the
# same lines, numbers as %.17g).
#
#   bash bench/whole_process.sh [BUILD_DIR]      (default build/release)
#   RUNS=9 CASES="spot koala" bash bench/whole_process.sh
#   OBJ=1 CASES=spot bash bench/whole_process.sh
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build/release}
data=${STRATA_SHARED_DATA:-/work/shared/data/meshes}
runs=${RUNS:-5}
cases=${CASES:-spot koala}
obj=${OBJ:-0}
strata=$build/strata
osd=$build/bench/osd_program
for exe in "$strata" "$osd" /usr/bin/time; do
  [ -x "$exe" ] || { echo "whole_process: $exe not found (build the release tree; osd_program needs libosd-dev; time: apt-get install time)" >&2; exit 2; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# run NAME CMD...: one measured run, appended to $tmp/NAME as "wall cpu rss_kB".
run() {
  local name=$1; shift
  /usr/bin/time -f '%e %U %S %M' -o "$tmp/t" "$@" > "$tmp/out.$name" 2> "$tmp/err.$name" || {
    echo "whole_process: '$*' failed:" >&2; cat "$tmp/err.$name" >&2; exit 1; }
  awk '{ printf "%s %.3f %s\n", $1, $2 + $3, $4 }' "$tmp/t" >> "$tmp/$name"
}

# median FILE COLUMN
median() { sort -g -k"$2","$2" "$1" | awk -v c="$2" '{ v[NR] = $c } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

echo "whole_process: $runs runs each, interleaved; $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "STRATA_THREADS=${STRATA_THREADS:-(unset: all cores)}; OpenSubdiv on one thread"
for c in $cases; do
  case $c in
    spot)  mesh=$data/catmull_clark/spot_quadrangulated.obj; scheme=catmull-clark; osd_scheme=catmark; depth=4 ;;
    koala) mesh=$data/large/koala.obj; scheme=loop; osd_scheme=loop; depth=3 ;;
    *) echo "whole_process: unknown case $c (spot, koala)" >&2; exit 2 ;;
  esac
  rm -f "$tmp"/{s_info,s_sub,o_info,o_ply,s_obj,o_obj}
  for ((i = 0; i < runs; i++)); do
    run s_info "$strata" info "$mesh" --scheme "$scheme" --levels "$depth"
    run o_info "$osd" info "$mesh" "$osd_scheme" "$depth"
    run s_sub "$strata" subdivide "$mesh" --scheme "$scheme" --levels "$depth" -o "$tmp/strata.ply"
    run o_ply "$osd" ply "$mesh" "$osd_scheme" "$depth" "$tmp/osd.ply"
    if [ "$obj" = 1 ]; then
      run s_obj "$strata" subdivide "$mesh" --scheme "$scheme" --levels "$depth" -o "$tmp/strata.obj"
      run o_obj "$osd" obj "$mesh" "$osd_scheme" "$depth" "$tmp/osd.obj"
      rm -f "$tmp/strata.obj" "$tmp/osd.obj"
    fi
  done
  s_bytes=$(stat -c %s "$tmp/strata.ply"); o_bytes=$(stat -c %s "$tmp/osd.ply")
  echo
  echo "$c: $(basename "$mesh"), $scheme depth $depth; PLY $s_bytes bytes (Strata), $o_bytes (OpenSubdiv)"
  printf '  %-28s %9s %9s %10s\n' "median of $runs" "wall s" "CPU s" "peak MiB"
  names="s_info o_info s_sub o_ply"
  [ "$obj" = 1 ] && names="$names s_obj o_obj"
  for n in $names; do
    case $n in
      s_info) label="strata info" ;; o_info) label="osd_program info" ;;
      s_sub) label="strata subdivide -o .ply" ;; o_ply) label="osd_program ply" ;;
      s_obj) label="strata subdivide -o .obj" ;; o_obj) label="osd_program obj" ;;
    esac
    printf '  %-28s %9.3f %9.3f %10.1f\n' "$label" "$(median "$tmp/$n" 1)" "$(median "$tmp/$n" 2)" \
      "$(awk -v k="$(median "$tmp/$n" 3)" 'BEGIN { print k / 1024 }')"
  done
  pairs=("info s_info o_info" "subdivide s_sub o_ply")
  [ "$obj" = 1 ] && pairs+=("obj s_obj o_obj")
  for pair in "${pairs[@]}"; do
    set -- $pair
    printf '  ratio %-10s wall %.2fx  CPU %.2fx  peak memory %.2fx\n' "$1" \
      "$(awk -v a="$(median "$tmp/$2" 1)" -v b="$(median "$tmp/$3" 1)" 'BEGIN { print a / b }')" \
      "$(awk -v a="$(median "$tmp/$2" 2)" -v b="$(median "$tmp/$3" 2)" 'BEGIN { print a / b }')" \
      "$(awk -v a="$(median "$tmp/$2" 3)" -v b="$(median "$tmp/$3" 3)" 'BEGIN { print a / b }')"
  done
done
