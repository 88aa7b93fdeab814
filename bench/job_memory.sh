#!/usr/bin/env bash
# Memory and time of the main job on a 10-million-line G-code program: the program is read move
# by move each time the job needs its moves (docs/simulate.md, "Long programs"), so peak resident
# memory is the stock's and the outputs', whatever the program's length.
#   bench/job_memory.sh [build/cwe] [LINES]
# Writes a raster of LINES G1 lines (default 10,000,000; about 310 MB) over a 1000 × 50 mm block
# to a temporary folder, then runs 3 times each:
#   removal    cwe simulate --stock-only at s = 0.2 mm (every move removed from the stock);
#   engagement cwe simulate with the engagement at every 5 mm of path (--cl-step 5, no maps) on
#              the program's first tenth, for the memory of the engagement outputs' path.
# Prints wall and CPU seconds, moves per wall second and the peak RSS of each run.
set -euo pipefail
cwe=$(realpath "${1:-build/cwe}")
lines=${2:-10000000}
[ -x /usr/bin/time ] || { echo "needs /usr/bin/time (Debian package time)" >&2; exit 1; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# A raster of 0.5 mm steps across Y at depths of 0 to 0.3 mm, advancing 0.01 mm in X per line.
raster() {
  awk -v n="$1" 'BEGIN { print "G21 G90 G17 F600 S10000 M3"; print "G0 X0 Y0 Z5";
                         for (k = 0; k < n; k++)
                           printf "G1 X%.4f Y%.4f Z%.4f\n", 0.01 * (k % 100000),
                                  0.5 * (k % 100), -0.05 * (k % 7);
                         print "M2" }'
}
raster "$lines" > "$dir/raster.ngc"
raster $((lines / 10)) > "$dir/tenth.ngc"
stock=box:0,0,-5,1000,50,0
run() {
  local name="$1" moves="$2"
  shift 2
  for r in 1 2 3; do
    rm -rf "$dir/out"
    /usr/bin/time -f "%e %U %S %M" -o "$dir/time" "$cwe" simulate --stock "$stock" --tool flat:2 \
      --resolution 0.2 --out "$dir/out" --quiet "$@" > /dev/null
    read -r wall user sys rss < "$dir/time"
    awk -v p="$name" -v r="$r" -v w="$wall" -v u="$user" -v s="$sys" -v m="$rss" -v n="$moves" \
      'BEGIN { printf "%s run %d: %d moves, wall %.1f s, CPU %.1f s, %.0f moves/s, peak RSS %d MiB\n",
                      p, r, n, w, u + s, n / w, m / 1024 }'
  done
}
run removal "$lines" --path "$dir/raster.ngc" --stock-only
run engagement $((lines / 10)) --path "$dir/tenth.ngc" --cl-step 5 --maps none
