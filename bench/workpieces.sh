#!/usr/bin/env bash
# The workpieces side by side on a bundled job (default examples/jobs/example.json: a two-tool
# G-code program and a 5-axis CLDATA pass, with forces; examples/jobs/part.json is its program
# alone, which the B-rep workpiece runs too): the dexel workpiece at the job's resolution, the
# mesh workpiece (the polyhedral method) at FACET mm facets, the B-rep one (the solid-model
# method).
#   bench/workpieces.sh [build/cwe] [FACET] [RUNS] [THREADS] [JOB] [WORKPIECES]
# Runs `cwe simulate` on each of WORKPIECES (default "dexel mesh") RUNS times (default 3; the
# mesh and B-rep take minutes) on THREADS threads (default 2), prints each run's wall and CPU
# seconds, moves and cutter locations per CPU-second and peak resident memory, then the medians,
# and compares the last runs' outputs with the first workpiece's: removed volume, engaged
# locations, engaged area and axial depth per location.
set -euo pipefail
cwe=$(realpath "${1:-build/cwe}")
facet=${2:-1}
runs=${3:-3}
threads=${4:-2}
job=$(realpath "${5:-$(dirname "$0")/../examples/jobs/example.json}")
read -r -a workpieces <<< "${6:-dexel mesh}"
[ -x /usr/bin/time ] || { echo "needs /usr/bin/time (Debian package time)" >&2; exit 1; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
for workpiece in "${workpieces[@]}"; do
  walls=() cpus=() rsss=()
  for r in $(seq "$runs"); do
    rm -rf "$dir/$workpiece"
    /usr/bin/time -f "%e %U %S %M" -o "$dir/time" "$cwe" simulate "$job" --workpiece "$workpiece" \
      --facet "$facet" --threads "$threads" --out "$dir/$workpiece" --quiet > /dev/null
    read -r wall user sys rss < "$dir/time"
    moves=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["moves"])' \
      "$dir/$workpiece/summary.json")
    cls=$(($(wc -l < "$dir/$workpiece/engagement.csv") - 1))
    awk -v p="$workpiece" -v r="$r" -v w="$wall" -v u="$user" -v s="$sys" -v m="$rss" \
      -v n="$moves" -v c="$cls" \
      'BEGIN { printf "%s run %d: wall %.2f s, CPU %.2f s, %.1f moves and %.0f CL per CPU-second, peak RSS %d MiB\n",
                      p, r, w, u + s, n / (u + s), c / (u + s), m / 1024 }'
    walls+=("$wall") cpus+=("$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')")
    rsss+=("$rss")
  done
  awk -v p="$workpiece" -v w="$(median "${walls[@]}")" -v c="$(median "${cpus[@]}")" \
    -v m="$(median "${rsss[@]}")" -v n="$moves" -v k="$cls" -v t="$threads" \
    'BEGIN { printf "%s median (%d threads): wall %.2f s, CPU %.2f s, %.1f moves and %.0f CL per CPU-second, peak RSS %d MiB\n",
                    p, t, w, c, n / c, k / c, m / 1024 }'
done
python3 - "${workpieces[@]/#/$dir/}" <<'EOF'
import csv, json, os, statistics, sys
dirs = sys.argv[1:]
names = [os.path.basename(d) for d in dirs]
rows = [{int(r["cl"]): r for r in csv.DictReader(open(f"{d}/engagement.csv"))} for d in dirs]
volumes = [json.load(open(f"{d}/summary.json"))["removed_volume_mm3"] for d in dirs]
def spread(name, values):
    values = sorted(values)
    if values:
        print(f"{name}: median {statistics.median(values):.3f}, "
              f"90th percentile {values[int(0.9 * (len(values) - 1))]:.3f}, "
              f"largest {values[-1]:.3f}")
first = rows[0]
engaged_first = {k for k, r in first.items() if r["engaged"] == "1"}
for name, other, volume in zip(names[1:], rows[1:], volumes[1:]):
    print(f"{name} against {names[0]}:")
    print(f"removed volume: {names[0]} {volumes[0]:.1f} mm³, {name} {volume:.1f} mm³ "
          f"({100 * (volume - volumes[0]) / volumes[0]:+.2f} %)")
    engaged = {k for k, r in other.items() if r["engaged"] == "1"}
    both = engaged_first & engaged
    print(f"engaged locations: {names[0]} {len(engaged_first)}, {name} {len(engaged)}, "
          f"both {len(both)} of {len(first)}")
    spread("engaged area difference, mm²",
           [abs(float(other[k]["area_mm2"]) - float(first[k]["area_mm2"])) for k in both])
    spread("axial depth difference, mm",
           [abs(float(other[k]["axial_depth_mm"]) - float(first[k]["axial_depth_mm"]))
            for k in both])
EOF
