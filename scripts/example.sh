#!/usr/bin/env bash
# Builds cwe (installing what is missing) and runs it on the bundled example.
# Today the most complete pipeline is the cutter model: every cutter of examples/cutters.txt is
# described and its profile drawn into out/example/.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/build.sh
mapfile -t specs < <(grep -v '^\s*\(#\|$\)' examples/cutters.txt)
build/cwe tool "${specs[@]}" --svg-dir out/example
echo
echo "Drawings of the ${#specs[@]} cutters are in out/example/ (open the .svg files in a browser)."
