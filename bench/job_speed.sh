#!/usr/bin/env bash
# Speed of the main job (removal, engagement and forces) on a pocketing program, in cutter
# locations per second, the benchmark of docs/performance.md.
#   bench/job_speed.sh [build/cwe] [RESOLUTION] [RUNS] [THREADS]
# The program: a 10 mm flat end mill clearing a 80 × 80 mm pocket in a 100 × 100 × 40 mm block
# in three 2 mm levels, zig-zag rows of 1 mm G1 segments at 5 mm stepover (4,131 feed moves,
# about 8,700 cutter locations at the default CL step of 0.5 mm). Runs `cwe simulate` with
# forces (al7075-t6-carbide), default maps, RUNS times (default 3) at RESOLUTION mm (default
# 0.1) on THREADS threads (default 2), and prints each run's wall and CPU seconds, CL per wall
# second and CL per CPU second, and its wall time by stage as summary.json gives it (set-up,
# simulation, closing: docs/simulate.md) and the rest of it (the process's start, the outputs'
# publication and its exit), then the medians. Wall and CPU time are those of the cwe process
# alone, read in the shell around it ($EPOCHREALTIME, to the microsecond; `times`, to the
# millisecond): timed through date, /usr/bin/time and taskset, each run also counted 12-19 ms of
# those programs' own starts.
# THREADS may list several counts, e.g. 1,2: each run then runs them one after the other (so
# that a shared machine's changing load falls on all alike), the medians are given per count,
# and each later count's speed-up over the first (wall time, the first over it) per run and as
# a median. A count may name the CPUs it runs on (`taskset -c`), as COUNT@CPU or COUNT@FIRST-LAST:
# 1@0,2@0,2@0-1 runs one thread on CPU 0, two threads sharing CPU 0 and two threads on CPUs 0
# and 1 (what two cores cost beyond the program's own parallel work); 1@0,1@1 compares the
# machine's two CPUs on the same one-thread job (a quiet machine gives about 1.00 in every run).
# Before and after the runs it prints how long a cache line takes to go between two CPUs and back
# (BM_HandOff of bench/host_bench, beside the cwe it runs), when the build has it: about 100 ns
# where two cores share a cache, 400-480 ns on this machine's vCPUs at most times, and two threads
# scale with it (docs/performance.md, nineteenth pass).
set -euo pipefail
export LC_ALL=C  # decimal points in what times, awk and sort read and write
cwe=$(realpath "${1:-build/cwe}")
resolution=${2:-0.1}
runs=${3:-3}
threads=${4:-2}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
awk 'BEGIN { print "G21 G90 G17 F1200 S12000 M3"; print "G0 X10 Y10 Z45";
             for (z = 38; z >= 34; z -= 2) {
               print "G0 X10 Y10"; printf "G1 Z%d\n", z;
               row = 0;
               for (y = 10; y <= 90; y += 5) {
                 if (y > 10) printf "G1 Y%d\n", y;
                 for (k = 1; k <= 80; k++) printf "G1 X%d\n", row % 2 == 0 ? 10 + k : 90 - k;
                 row++;
               }
               print "G0 Z45";
             }
             print "M2" }' > "$dir/pocket.ngc"
IFS=, read -r -a counts <<< "$threads"
for t in "${counts[@]}"; do
  [[ $t =~ ^[1-9][0-9]*(@[0-9]+(-[0-9]+)?)?$ ]] || {
    echo "THREADS: '$t' is not a count, COUNT@CPU or COUNT@FIRST-LAST (e.g. 1,2 or 1@0,2@0-1)" >&2
    exit 2
  }
  [[ $(printf '%s\n' "${counts[@]}" | grep -cx -- "$t") == 1 ]] || {
    echo "THREADS: '$t' is listed twice" >&2
    exit 2
  }
done
if [[ $threads == *@* ]] && ! command -v taskset > /dev/null; then
  echo "THREADS names CPUs: needs taskset (Debian package util-linux)" >&2
  exit 1
fi
# A count as the report names it: "2 threads", "1 threads on CPU 0", "2 threads on CPUs 0-1".
label() {
  local cpus=${1#*@}
  if [[ $1 != *@* ]]; then echo "$1 threads"
  elif [[ $cpus == *-* ]]; then echo "${1%@*} threads on CPUs $cpus"
  else echo "${1%@*} threads on CPU $cpus"; fi
}
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
# The user and system seconds a shell's children took between two outputs of `times` (whose
# second line gives them, as 1m2.345s).
children_cpu() {
  awk 'FNR == 2 { for (i = 1; i <= 2; ++i) { split($i, p, "m"); sub("s", "", p[2]);
                                           t[i] = p[1] * 60 + p[2] - t[i] } }
       END { printf "%.3f %.3f\n", t[1], t[2] }' "$1" "$2"
}
host_bench=$(dirname "$cwe")/bench/host_bench
round_trip() {
  [ -x "$host_bench" ] || return 0
  "$host_bench" --benchmark_filter=HandOff --benchmark_repetitions=3 2> /dev/null |
    awk -v when="$1" '/_median/ { for (i = 1; i <= NF; ++i) if ($i ~ /^round_trip=/) {
                         sub("round_trip=", "", $i);
                         print "a cache line between two CPUs and back " when ": " $i \
                               " (bench/host_bench BM_HandOff, median of 3)" } }'
}
round_trip "before the runs"
declare -A walls cpus set_ups simulations closings rests
# The stages of the run's wall time (summary.json's seconds_by_stage).
stages() {
  awk -F': ' '/"set_up"/ { s = $2 } /"simulation"/ { m = $2 } /"closing"/ { c = $2 }
              END { gsub(",", "", s); gsub(",", "", m); gsub(",", "", c); print s, m, c }' "$1"
}
for r in $(seq "$runs"); do
  for t in "${counts[@]}"; do
    rm -rf "$dir/out"
    # In a subshell pinned first (its child inherits the CPUs): the wall time from just before
    # cwe starts to just after it ends, and the CPU its children took meanwhile.
    (
      if [[ $t == *@* ]]; then taskset -c -p "${t#*@}" "$BASHPID" > /dev/null; fi
      times > "$dir/times.before"
      start=$EPOCHREALTIME
      "$cwe" simulate --stock box:0,0,0,100,100,40 --tool flat:10,30 --path "$dir/pocket.ngc" \
        --resolution "$resolution" --threads "${t%@*}" --forces al7075-t6-carbide \
        --out "$dir/out" --quiet > /dev/null
      end=$EPOCHREALTIME
      times > "$dir/times.after"
      echo "$start $end" > "$dir/time"
    )
    read -r start end < "$dir/time"
    wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", b - a }')
    read -r user sys < <(children_cpu "$dir/times.before" "$dir/times.after")
    cls=$(($(wc -l < "$dir/out/engagement.csv") - 1))
    read -r set_up simulation closing < <(stages "$dir/out/summary.json")
    rest=$(awk -v w="$wall" -v a="$set_up" -v b="$simulation" -v c="$closing" \
      'BEGIN { printf "%.4f", w - a - b - c }')
    awk -v r="$r" -v t="$(label "$t")" -v w="$wall" -v u="$user" -v s="$sys" -v n="$cls" \
      -v a="$set_up" -v b="$simulation" -v c="$closing" -v e="$rest" \
      'BEGIN { printf "run %d, %s: %d CLs, wall %.3f s, CPU %.2f s, %.0f CL/s, " \
                      "%.0f CL per CPU-second; set-up %.3f s, simulation %.3f s, closing " \
                      "%.3f s, rest %.3f s\n", r, t, n, w, u + s, n / w, n / (u + s), a, b, c, e }'
    walls[$t]+="$wall " cpus[$t]+="$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }') "
    set_ups[$t]+="$set_up " simulations[$t]+="$simulation " closings[$t]+="$closing "
    rests[$t]+="$rest "
  done
done
for t in "${counts[@]}"; do
  read -r -a tw <<< "${walls[$t]}"
  read -r -a tc <<< "${cpus[$t]}"
  w=$(median "${tw[@]}") c=$(median "${tc[@]}")
  read -r -a ta <<< "${set_ups[$t]}"
  read -r -a tb <<< "${simulations[$t]}"
  read -r -a td <<< "${closings[$t]}"
  read -r -a te <<< "${rests[$t]}"
  awk -v w="$w" -v c="$c" -v n="$cls" -v s="$resolution" -v t="$(label "$t")" \
    -v a="$(median "${ta[@]}")" -v b="$(median "${tb[@]}")" -v d="$(median "${td[@]}")" \
    -v e="$(median "${te[@]}")" \
    'BEGIN { printf "median (s = %s mm, %s): wall %.3f s, CPU %.2f s, %.0f CL/s, " \
                    "%.0f CL per CPU-second; set-up %.3f s, simulation %.3f s, closing %.3f s, " \
                    "rest %.3f s\n", s, t, w, c, n / w, n / c, a, b, d, e }'
done
read -r -a first <<< "${walls[${counts[0]}]}"
for t in "${counts[@]:1}"; do
  read -r -a tw <<< "${walls[$t]}"
  ratios=()
  for k in "${!first[@]}"; do
    ratios+=("$(awk -v a="${first[$k]}" -v b="${tw[$k]}" 'BEGIN { printf "%.2f", a / b }')")
  done
  echo "speed-up of $(label "$t") over $(label "${counts[0]}"): median $(median "${ratios[@]}")" \
    "(runs: ${ratios[*]})"
done
round_trip "after the runs"
