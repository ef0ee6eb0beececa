#!/usr/bin/env bash
# Whole process, the progressive build against meshoptimizer (the speed
# issue's goal 2): `strata rebuild MESH --method progressive -o OUT.strata`
# (read the OBJ, every level and its details, the session written) against
# bench/meshopt_program (read the OBJ, meshopt_simplify to the same 1 % of
# the triangles, the coarse mesh written as OBJ), interleaved, RUNS times
# each; /usr/bin/time gives wall time, CPU time and peak RSS; prints
# medians and ratios Strata / meshoptimizer.
#   bash bench/progressive_process.sh [BUILD_DIR]   (RUNS=N, MESHES="a.obj b.obj",
#   OLD=path/to/an/older/strata: its rebuild too, interleaved, with its ratios)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=${1:-$ROOT/build/release}
runs=${RUNS:-5}
data="${STRATA_SHARED_DATA:-$ROOT/../shared/data/meshes}"
meshes=${MESHES:-"$data/large/koala.obj $data/large/sword_quad_dominant.obj $data/triangle/boot.obj $data/triangle/blub_open.obj"}
strata=$build/strata mo=$build/bench/meshopt_program
for exe in "$strata" "$mo" /usr/bin/time; do
  [ -x "$exe" ] || { echo "progressive_process: $exe not found (build the release tree; meshopt_program needs libmeshoptimizer-dev)" >&2; exit 2; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

run() {   # NAME CMD...: one run, appended to $tmp/NAME as "wall cpu rss_kB" (wall to the microsecond,
          # CPU to /usr/bin/time's hundredth)
  local name=$1; shift
  local t0 t1
  t0=$(date +%s%N)
  /usr/bin/time -f '%U %S %M' -o "$tmp/t" "$@" > /dev/null 2> "$tmp/err" || { echo "'$*' failed:" >&2; cat "$tmp/err" >&2; exit 1; }
  t1=$(date +%s%N)
  awk -v w="$(( (t1 - t0) / 1000 ))" '{ printf "%.6f %.3f %s\n", w / 1e6, $1 + $2, $3 }' "$tmp/t" >> "$tmp/$name"
}
median() { sort -g -k"$2","$2" "$1" | awk -v c="$2" '{ v[NR] = $c } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

echo "progressive_process: $runs runs each, interleaved; $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg)"
for mesh in $meshes; do
  [ -f "$mesh" ] || { echo "$mesh missing, skipped"; continue; }
  rm -f "$tmp"/{s,m,o}
  for ((i = 0; i < runs; i++)); do
    run s "$strata" rebuild "$mesh" --method progressive -o "$tmp/out.strata"
    run m "$mo" "$mesh" "$tmp/out.obj"
    if [ -n "${OLD:-}" ]; then run o "$OLD" rebuild "$mesh" --method progressive -o "$tmp/old.strata"; fi
  done
  printf '%s (%s bytes): session %s bytes\n' "$(basename "$mesh")" "$(stat -c %s "$mesh")" "$(stat -c %s "$tmp/out.strata")"
  printf '  %-34s %8s %8s %9s\n' "median of $runs" "wall s" "CPU s" "peak MiB"
  printf '  %-34s %8.4f %8.3f %9.1f\n' "strata rebuild --method progressive" "$(median "$tmp/s" 1)" "$(median "$tmp/s" 2)" \
    "$(awk -v k="$(median "$tmp/s" 3)" 'BEGIN { print k / 1024 }')"
  printf '  %-34s %8.4f %8.3f %9.1f\n' "meshopt_program (1 %)" "$(median "$tmp/m" 1)" "$(median "$tmp/m" 2)" \
    "$(awk -v k="$(median "$tmp/m" 3)" 'BEGIN { print k / 1024 }')"
  printf '  ratio wall %.2fx  CPU %s  peak memory %.2fx\n' \
    "$(awk -v a="$(median "$tmp/s" 1)" -v b="$(median "$tmp/m" 1)" 'BEGIN { print a / b }')" \
    "$(awk -v a="$(median "$tmp/s" 2)" -v b="$(median "$tmp/m" 2)" 'BEGIN { if (b > 0) printf "%.2fx", a / b; else print "(below the hundredth)" }')" \
    "$(awk -v a="$(median "$tmp/s" 3)" -v b="$(median "$tmp/m" 3)" 'BEGIN { print a / b }')"
  if [ -n "${OLD:-}" ]; then
    printf '  %-34s %8.4f %8.3f %9.1f  (session %s bytes)\n' "older strata rebuild" "$(median "$tmp/o" 1)" "$(median "$tmp/o" 2)" \
      "$(awk -v k="$(median "$tmp/o" 3)" 'BEGIN { print k / 1024 }')" "$(stat -c %s "$tmp/old.strata")"
    printf '  older / meshopt: wall %.2fx  peak memory %.2fx;  new / older: wall %.2fx\n' \
      "$(awk -v a="$(median "$tmp/o" 1)" -v b="$(median "$tmp/m" 1)" 'BEGIN { print a / b }')" \
      "$(awk -v a="$(median "$tmp/o" 3)" -v b="$(median "$tmp/m" 3)" 'BEGIN { print a / b }')" \
      "$(awk -v a="$(median "$tmp/s" 1)" -v b="$(median "$tmp/o" 1)" 'BEGIN { print a / b }')"
  fi
done
