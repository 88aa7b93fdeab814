#!/usr/bin/env bash
# Fuzzes cwe's readers with the libFuzzer targets in fuzz/ (fuzz/README.md).
#   scripts/fuzz.sh TARGET SECONDS
# TARGET: gcode, cldata, stl, job, tool_spec, tool_file, coefficients, tool_table, machine (or
# with the fuzz_ prefix), or all. Builds build-fuzz/ with clang first (installing clang and its
# sanitizer runtimes when they are missing, as scripts/bootstrap.sh does). Each target starts
# from a copy of its seed corpus (fuzz/corpus/TARGET and the malformed inputs of its kind in
# tests/malformed/, never written to) with its dictionary, and
# runs SECONDS seconds. Prints executions and coverage per target; exits 1 on a finding, naming
# the saved input.
# Environment:
#   CWE_FUZZ_SEED=N      libFuzzer's -seed (the same mutations again; default: random)
#   CWE_FUZZ_PARALLEL=N  with `all`, N targets at a time (default 1); each uses one core
#   CWE_FUZZ_OUT=DIR     work corpora, logs and findings (default build-fuzz/runs/DATE-PID)
#   CWE_FUZZ_NO_BUILD=1  use build-fuzz/ as it is
#   CWE_JOBS=N           build jobs (default: the number of cores)
set -euo pipefail
# The whole script is one function, read before it runs, and the line that calls it exits:
# editing the file does not disturb a run.
main() {
  cd "$(dirname "$0")/.."
  root="$PWD"

  all_targets=(gcode cldata stl job tool_spec tool_file coefficients tool_table machine)
  usage() {
    echo "usage: scripts/fuzz.sh TARGET SECONDS  (TARGET: all or one of ${all_targets[*]})" >&2
    exit 2
  }
  [ $# -eq 2 ] || usage
  case "$2" in '' | *[!0-9]*) usage ;; esac
  seconds=$((10#$2))
  [ "$seconds" -gt 0 ] || usage  # libFuzzer's -max_total_time=0 would run without end
  if [ "$1" = all ]; then
    targets=("${all_targets[@]}")
  else
    name="${1#fuzz_}"
    [[ " ${all_targets[*]} " == *" $name "* ]] || usage
    targets=("$name")
  fi

  # Inputs longer than this are not tried: long inputs only run into the readers' resource limits.
  max_len() {
    case "$1" in
      gcode | cldata | stl | job) echo 4096 ;;
      *) echo 2048 ;;
    esac
  }

  dir=build-fuzz
  if [ "${CWE_FUZZ_NO_BUILD:-0}" != 1 ]; then
    "scripts/bootstrap.sh"
    # clang, and libFuzzer with the sanitizer runtimes (libclang-rt-14-dev carries libFuzzer's
    # library for -fsanitize=fuzzer).
    "scripts/bootstrap.sh" clang libclang-rt-14-dev
    export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/ccache}"
    if [ ! -f "$dir/CMakeCache.txt" ]; then
      # -O1 as the ASan build: exact reports, a fast enough fuzzer. Only the libraries the targets
      # link are built (no tests, benchmarks or Python module).
      CC=clang CXX=clang++ cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" -DCWE_FUZZ=ON -DCWE_BUILD_TESTS=OFF \
        -DCWE_BUILD_BENCHMARKS=OFF -DCWE_BUILD_PYTHON=OFF >/dev/null
    fi
    cmake --build "$dir" --target fuzz -j "${CWE_JOBS:-$(nproc)}"
  fi

  out="${CWE_FUZZ_OUT:-$dir/runs/$(date +%Y%m%d-%H%M%S)-$$}"
  mkdir -p "$out"
  out="$(cd "$out" && pwd)"

  # One target: a scratch folder with the work corpus, the findings (artifacts/) and the log; the
  # fuzzer runs in that folder, so relative paths in its inputs find nothing of the tree.
  run_target() {
    local t="$1" work="$out/$1"
    rm -rf "$work"
    mkdir -p "$work/corpus" "$work/artifacts"
    cp "$root/fuzz/corpus/fuzz_$t/." "$work/corpus/" -R
    # The malformed-input corpus of the same kind seeds it too (tests/malformed/README.md).
    local kind="$t"
    case "$t" in tool_file) kind=tool ;; tool_spec) kind= ;; esac
    if [ -n "$kind" ] && [ -d "$root/tests/malformed/$kind" ]; then
      find "$root/tests/malformed/$kind" -type f ! -name README.md \
        -exec cp -t "$work/corpus/" {} +
    fi
    local args=("$work/corpus" "-dict=$root/fuzz/dict/fuzz_$t.dict" "-max_total_time=$seconds"
                "-max_len=$(max_len "$t")" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
                "-artifact_prefix=$work/artifacts/")
    [ -n "${CWE_FUZZ_SEED:-}" ] && args+=("-seed=$CWE_FUZZ_SEED")
    local status=0
    (cd "$work" && "$root/$dir/fuzz/fuzz_$t" "${args[@]}") >"$work/log.txt" 2>&1 || status=$?
    echo "$status" >"$work/status"
  }

  summary() {
    local t="$1" work="$out/$1" log="$out/$1/log.txt"
    local status execs rate last cov ft corpus findings
    status="$(cat "$work/status")"
    execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)"
    rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)"
    last="$(grep -E '^#[0-9]+.*cov: ' "$log" | tail -n 1 || true)"
    cov="$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")"
    ft="$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")"
    corpus="$(find "$work/corpus" -type f | wc -l)"
    printf '%-17s %11s %8s %7s %7s %7s  ' "fuzz_$t" "${execs:-?}" "${rate:-?}" "${cov:-?}" \
      "${ft:-?}" "$corpus"
    findings="$(find "$work/artifacts" -type f)"
    if [ "$status" = 0 ] && [ -z "$findings" ]; then
      echo "no finding"
      return 0
    fi
    echo "FINDING (exit $status): ${findings:-see $log}"
    return 1
  }

  parallel="${CWE_FUZZ_PARALLEL:-1}"
  echo "fuzz: ${targets[*]}, ${seconds} s each${CWE_FUZZ_SEED:+, seed $CWE_FUZZ_SEED}," \
    "$parallel at a time; work in $out" >&2
  for t in "${targets[@]}"; do
    while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do wait -n || true; done
    run_target "$t" &
  done
  wait

  printf '%-17s %11s %8s %7s %7s %7s  %s\n' target executions exec/s cov ft corpus result
  found=0
  for t in "${targets[@]}"; do summary "$t" || found=1; done
  if [ "$found" != 0 ]; then
    echo "fuzz: a finding; reproduce with $dir/fuzz/fuzz_TARGET FILE, minimise with" \
      "-minimize_crash=1 -runs=10000 (fuzz/README.md)" >&2
    exit 1
  fi
}

main "$@"; exit $?
