#!/usr/bin/env bash
# Builds cwe (installing what is missing) and runs it on the bundled example: every cutter of
# examples/cutters.txt is described and its profile drawn into out/example/, the example
# programs (G-code and APT CLDATA) are read, summarised and dumped as JSON lines, and the swept
# volumes, grazing curves and feasible contact surfaces of the first pocketing moves are written;
# then the pocketing job is simulated on the tri-dexel workpiece (examples/jobs/pocket.json).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/build.sh
out=out/example
mapfile -t specs < <(grep -v '^\s*\(#\|$\)' examples/cutters.txt)
build/cwe tool "${specs[@]}" --svg-dir "$out"
for program in examples/programs/*; do
  echo
  build/cwe path "$program"
  build/cwe path "$program" --dump > "$out/$(basename "$program").moves.jsonl"
done
echo
build/cwe envelope --tool flat:10 --path examples/programs/pocket.ngc --moves 1-25 \
  --out "$out/envelope"
echo
build/cwe simulate examples/jobs/pocket.json
echo
echo "Drawings of the ${#specs[@]} cutters are in $out/ (open the .svg files in a browser);"
echo "the moves of each example program, one JSON object per line, are in $out/*.moves.jsonl;"
echo "swept volumes (STL/PLY), grazing curves (OBJ) and feasible contact surfaces (SVG) of the"
echo "first pocketing moves are in $out/envelope/; the machined stock (STL) and the simulation"
echo "summary (JSON) are in $out/simulate/."
