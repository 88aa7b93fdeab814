#!/usr/bin/env bash
# Builds cwe (installing what is missing) and runs it on the bundled example: every cutter of
# examples/cutters.txt is described and its profile drawn into out/example/, and the example
# programs (G-code and APT CLDATA) are read, summarised and dumped as JSON lines.
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
echo "Drawings of the ${#specs[@]} cutters are in $out/ (open the .svg files in a browser);"
echo "the moves of each example program, one JSON object per line, are in $out/*.moves.jsonl."
