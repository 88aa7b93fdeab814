#!/usr/bin/env bash
# Memory and time of `cwe path` on a 10-million-line G-code program (and a loop that executes 10
# million lines), the programs streamed through the reader: peak resident memory must stay a few
# tens of MB whatever the length. Writes the programs to a temporary folder (about 300 MB), runs
# each 3 times and prints wall and CPU seconds, lines per second and the peak RSS of each run.
#   bench/gcode_memory.sh [build/cwe]
set -euo pipefail
cwe=$(realpath "${1:-build/cwe}")
[ -x /usr/bin/time ] || { echo "needs /usr/bin/time (Debian package time)" >&2; exit 1; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
awk 'BEGIN { print "G21 G90 G17 F600"; print "G0 X0 Y0 Z5";
             for (k = 0; k < 10000000; k++)
               printf "G1 X%.4f Y%.4f Z%.4f\n", 0.01 * (k % 100000), 0.5 * (k % 100), -0.001 * (k % 7);
             print "M2" }' > "$dir/lines.ngc"
cat > "$dir/loop.ngc" <<'NGC'
G21 G90 F600
#1 = 0
o100 while [#1 LT 2500000]
  #2 = [#1 * 0.0001]
  G1 X#2 Y[SIN[#1] * 10] Z[-1 - [#1 MOD 5] * 0.1]
  #1 = [#1 + 1]
o100 endwhile
M2
NGC
for program in lines loop; do
  for run in 1 2 3; do
    /usr/bin/time -f "%e %U %S %M" -o "$dir/time" "$cwe" path "$dir/$program.ngc" > /dev/null
    read -r wall user sys rss < "$dir/time"
    awk -v p="$program" -v r="$run" -v w="$wall" -v u="$user" -v s="$sys" -v m="$rss" 'BEGIN {
      printf "%s.ngc run %d: wall %.2f s, CPU %.2f s, %.2f M lines/s, peak RSS %d MiB\n",
             p, r, w, u + s, 10 / w, m / 1024 }'
  done
done
