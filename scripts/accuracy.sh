#!/usr/bin/env bash
# The runs behind docs/accuracy.md: `cwe compare` on the analytic cases (examples/accuracy/: a
# slot, a side cut and a ramp, each with a flat, a ball and a bull-nose end mill of 10 mm) and
# on the bundled example (its program, and the whole job with its 5-axis pass, against the B-rep
# workpiece), each table printed as the document shows it. About 20 minutes on
# two cores (the B-rep bull-nose runs are most of it).
#   scripts/accuracy.sh [OUT]    outputs in OUT (default out/accuracy)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh > /dev/null
out="$(realpath -m "${1:-out/accuracy}")"
mkdir -p "$out"
cwe="$PWD/build/cwe"

# A row of convergence.csv's columns: setting, error over the job (%), its 95th percentile per CL
# (%), entry and exit 95th percentiles (deg), CPU seconds.
table() {
  awk -F, -v setting="$2" 'NR > 1 {
      printf "| %s | %s | %.3g | %.3g | %.3g | %.3g | %.2f |\n", $1, $(setting == "s" ? 2 : 3),
             100 * $4, 100 * $5, $6, $7, $11 }' "$1/convergence.csv"
}

echo "Analytic cases against the B-rep workpiece (reference at the finest setting):"
echo "| case | workpiece | s or facet (mm) | over the job (%) | p95 per CL (%) | entry p95 (°) | exit p95 (°) | CPU (s) |"
for program in slot side ramp; do
  for tool in flat:10,30 ball:10,30 bull:10,2,30; do
    name="${program}_${tool%%:*}"
    common=(--stock box:0,0,0,60,40,20 --tool "$tool" --path "examples/accuracy/$program.ngc"
            --quiet)
    $cwe compare "${common[@]}" --workpieces dexel,brep --sweep-resolution 0.4,0.2,0.1,0.05 \
      --out "$out/resolution_$name" > "$out/resolution_$name.txt"
    $cwe compare "${common[@]}" --workpieces mesh,brep --sweep-facet 4,2,1,0.5 \
      --out "$out/facet_$name" > "$out/facet_$name.txt"
    table "$out/resolution_$name" s | sed "s/^/| $name /"
    table "$out/facet_$name" f | sed "s/^/| $name /"
  done
done

echo
echo "The bundled example's program against the B-rep workpiece (examples/programs/part.ngc):"
part=(--stock box:0,0,-30,100,60,0 --tools examples/tool_table.json
      --path examples/programs/part.ngc --quiet)
$cwe compare "${part[@]}" --workpieces dexel,mesh,brep --out "$out/part" > "$out/part.txt"
$cwe compare "${part[@]}" --workpieces dexel,brep --sweep-resolution 0.4,0.2,0.1,0.05 \
  --out "$out/part_resolution" > "$out/part_resolution.txt"
grep -E "removed|against" "$out/part.txt"
echo "| workpiece | s (mm) | over the job (%) | p95 per CL (%) | entry p95 (°) | exit p95 (°) | CPU (s) |"
table "$out/part_resolution" s

echo
echo "The bundled example (examples/jobs/example.json):"
(cd examples/jobs &&
  $cwe compare example.json --workpieces dexel,mesh,brep --out "$out/example" --quiet \
    > "$out/example.txt" &&
  $cwe compare example.json --workpieces dexel,brep --sweep-resolution 0.4,0.2,0.1,0.05 \
    --out "$out/example_resolution" --quiet > "$out/example_resolution.txt")
grep -E "removed|against" "$out/example.txt"
echo "| workpiece | s (mm) | over the job (%) | p95 per CL (%) | entry p95 (°) | exit p95 (°) | CPU (s) |"
table "$out/example_resolution" s
