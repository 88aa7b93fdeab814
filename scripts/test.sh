#!/usr/bin/env bash
# Builds cwe (installing what is missing) and runs the whole test suite with CTest.
#   scripts/test.sh         the release build (assertions on)
#   scripts/test.sh asan    the same tests under AddressSanitizer + UndefinedBehaviorSanitizer
set -euo pipefail
cd "$(dirname "$0")/.."

variant="${1:-release}"
scripts/build.sh "$variant"
dir=build; [ "$variant" = asan ] && dir=build-asan
ctest --test-dir "$dir" --output-on-failure -j "${CWE_JOBS:-$(nproc)}"
