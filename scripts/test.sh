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

# A short fixed-seed fuzzing run of every reader when clang and its libFuzzer runtime are
# installed (fuzz/README.md): CWE_FUZZ_SECONDS per target (0: none), two targets at a time.
if [ "$variant" = release ] && [ "${CWE_FUZZ_SECONDS:-30}" != 0 ] && command -v clang++ >/dev/null &&
  compgen -G "$(clang++ -print-runtime-dir)/libclang_rt.fuzzer-*.a" >/dev/null; then
  CWE_FUZZ_SEED="${CWE_FUZZ_SEED:-1}" CWE_FUZZ_PARALLEL="${CWE_FUZZ_PARALLEL:-2}" \
    scripts/fuzz.sh all "${CWE_FUZZ_SECONDS:-30}"
fi
