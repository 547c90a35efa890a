#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine, then builds and runs the whole test suite:
#   1. release build (after a clang-format check), every ctest test (unit, statistical, app smoke tests, package tests:
#      install into a scratch prefix, then build and run examples/* against it)
#   2. AddressSanitizer + UndefinedBehaviorSanitizer (with float-cast-overflow) build, every
#      test, with librt as a shared library: so the whole suite also runs through the
#      shared library's exported API (and its visibility test), without a build of its own
#   3. ThreadSanitizer build, the multithreaded renderer, film and render_mpi tests
#   4. the OBJ, image, glTF and BVH fuzzers (libFuzzer, clang), each for a bounded time
#      (LIBRT_FUZZ_SECONDS, default 60)
# CI runs exactly this (.ci/run). `--quick` runs stage 1 only.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1

bash scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
# Each banner carries the seconds since the start, so a CI log shows what each stage costs.
stage() { printf '\n==== %s (at %d s) ====\n' "$*" "$SECONDS"; }
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
# Runs one ctest preset, keeping its output to total the counts at the end.
run_ctest() { ctest --preset "$1" -j "$jobs" 2>&1 | tee "$logs/$1.log"; }
# "N passed, N failed" over every ctest run so far (ctest prints "x tests failed out of y").
summary() {
  local total=0 failed=0 t f
  for log in "$logs"/*.log; do
    read -r f t < <(sed -nE 's/.* ([0-9]+) tests? failed out of ([0-9]+).*/\1 \2/p' "$log" | tail -n 1)
    total=$((total + ${t:-0})); failed=$((failed + ${f:-0}))
  done
  echo "ctest: $((total - failed)) passed, $failed failed"
}

stage "release build and tests"
cmake --preset release
cmake --build --preset release --target format-check  # clang-format, .clang-format
cmake --build --preset release -j "$jobs"
run_ctest release
if [ "$quick" = 1 ]; then summary; exit 0; fi

stage "AddressSanitizer + UndefinedBehaviorSanitizer (librt as a shared library)"
cmake --preset asan
cmake --build --preset asan -j "$jobs"
run_ctest asan

stage "ThreadSanitizer (renderer)"
cmake --preset tsan
cmake --build --preset tsan -j "$jobs" --target librt_all_tests
run_ctest tsan

stage "fuzzing load_obj + BVH build, the image loaders, load_gltf and the BVH builders, ${LIBRT_FUZZ_SECONDS:-60} s each"
cmake --preset fuzz
cmake --build --preset fuzz -j "$jobs"
# Each target works on a copy of its seed corpus, so new inputs stay out of the tree. A
# fuzzer is one single-threaded process: they run $jobs at a time, each for the full time,
# and each one's log is printed when it ends (a failing target fails the stage).
fuzz_one() {
  local name=$1 binary=$2 corpus="$logs/corpus_$1"
  mkdir -p "$corpus"
  cp "tests/fuzz/corpus/$name"/* "$corpus"/
  ./build/fuzz/tests/fuzz/"$binary" -max_total_time="${LIBRT_FUZZ_SECONDS:-60}" \
      -max_len=4096 -rss_limit_mb=2048 -print_final_stats=1 "$corpus" > "$logs/fuzz_$name.txt" 2>&1
}
# Waits for one target; prints its final stats, or its whole report when it failed.
fuzz_report() {
  if wait "$1"; then
    tail -n 12 "$logs/fuzz_$2.txt"
  else
    cat "$logs/fuzz_$2.txt"
    echo "fuzz target $2 failed"
    return 1
  fi
}
pids=() names=()
fuzz_failed=0
for target in obj:obj_fuzz image:image_fuzz gltf:gltf_fuzz bvh:bvh_fuzz; do
  if [ "${#pids[@]}" -ge "$jobs" ]; then
    fuzz_report "${pids[0]}" "${names[0]}" || fuzz_failed=1
    pids=("${pids[@]:1}") names=("${names[@]:1}")
  fi
  fuzz_one "${target%%:*}" "${target##*:}" &
  pids+=("$!") names+=("${target%%:*}")
done
for i in "${!pids[@]}"; do
  fuzz_report "${pids[$i]}" "${names[$i]}" || fuzz_failed=1
done
[ "$fuzz_failed" = 0 ]

stage "all stages passed"
summary
