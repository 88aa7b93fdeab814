#!/usr/bin/env bash
# Builds cwe (installing what is missing) and runs the main job on the bundled example
# (examples/jobs/example.json): a block cut by one program with two tools from a tool table, a
# 10 mm flat end mill (slot, side milling up and down, ramp, helical entry, plunge, peck
# drilling) then a 6 mm ball end mill finishing pass, and a simultaneous 5-axis APT CLDATA pass, with the cutter-workpiece engagement at every cutter
# location and the cutting forces, then schedules the pocketing feeds to a force limit. On the way it also draws the example cutters, dumps the example programs' moves and
# writes the swept volumes of the first pocketing moves, all into out/example/.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/build.sh
out=out/example
mapfile -t specs < <(grep -v '^\s*\(#\|$\)' examples/cutters.txt)
build/cwe tool "${specs[@]}" --svg-dir "$out" > /dev/null
for program in examples/programs/*; do
  build/cwe path "$program" --dump > "$out/$(basename "$program").moves.jsonl"
done
build/cwe envelope --tool flat:10 --path examples/programs/pocket.ngc --moves 1-25 \
  --out "$out/envelope" > /dev/null
# The main job: engagement at every cutter location of a two-tool program and a 5-axis pass.
build/cwe simulate examples/jobs/example.json
# Feed-rate scheduling: the pocketing program rewritten so that the peak force stays at 600 N.
build/cwe schedule examples/jobs/pocket.json --forces al7075-t6-carbide --limit force=600N \
  --out "$out/pocket_scheduled.ngc" --quiet
echo
echo "Where to look:"
echo "  $out/simulate/engagement.csv    one row per cutter location: entry/exit angle, depth, area"
echo "  $out/simulate/engagement.jsonl  per cutter location, the engaged angles of every axial disc"
echo "  $out/simulate/maps/             engagement maps (PNG, SVG) and path.png along the whole job"
echo "  $out/simulate/forces.csv        cutting forces, torque, power per cutter location"
echo "  $out/simulate/force_curves/     force against spindle angle at chosen cutter locations"
echo "  $out/simulate/stock.stl         the machined block; summary.json: volumes, memory, time"
echo "  $out/pocket_scheduled.ngc       the pocketing program with feeds scheduled to 600 N"
echo "Also: cutter drawings in $out/*.svg, the programs' moves in $out/*.moves.jsonl, swept"
echo "volumes and feasible contact surfaces of the first pocketing moves in $out/envelope/."
