#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz/) with clang, ASan and UBSan into
# build-fuzz/ and runs each for a fixed time from its committed seed corpus;
# fails on any crash, sanitizer report, uncaught exception, leak, input slower
# than 10 s or allocation above 2 GiB. Prints executions and coverage.
# Usage: bash scripts/fuzz.sh [SECONDS_PER_HARNESS] [--keep-corpus]
#   default 20 s per harness, two at a time (CI). The long run, 10 CPU-minutes
#   per harness (about 40 minutes on 2 cores), keeps what it found:
#   bash scripts/fuzz.sh 600 --keep-corpus
#   merges each harness's grown corpus into tests/fuzz/corpus/NAME (libFuzzer
#   -merge=1: only inputs that add coverage, so the committed corpus stays small).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
keep_corpus=${2:-}
harnesses=(flight_path rig sidecar manifest calibration frame_selection ply gltf)

# -O1 -gline-tables-only: libFuzzer's recommended flags, and a quicker build than -O2 -g.
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=None "-DCMAKE_CXX_FLAGS=-O1 -gline-tables-only" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DAAR_BUILD_TESTS=OFF -DAAR_BUILD_FUZZERS=ON >/dev/null
cmake --build build-fuzz --target aar_fuzzers --parallel "$(nproc)"

out=build-fuzz/fuzz-runs
rm -rf "$out"
mkdir -p "$out/artifacts"
run_one() {
  local name=$1
  local corpus="$out/corpus-$name"   # grows here; the committed seeds stay as they are
  mkdir -p "$corpus"
  if build-fuzz/tests/fuzz/fuzz_"$name" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$out/artifacts/$name-" "$corpus" "tests/fuzz/corpus/$name" \
      >"$out/$name.log" 2>&1; then
    echo ok >"$out/$name.status"
  else
    echo failed >"$out/$name.status"
  fi
}
jobs=$(nproc)
for name in "${harnesses[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  run_one "$name" &
done
wait

failed=0
printf '| harness | status | executions | coverage (edges) | features | corpus |\n|---|---|---|---|---|---|\n'
for name in "${harnesses[@]}"; do
  log="$out/$name.log"
  status=$(cat "$out/$name.status")
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | awk '{print $2}' || true)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  cov=$(echo "$last" | grep -o 'cov: [0-9]*' | awk '{print $2}' || true)
  ft=$(echo "$last" | grep -o 'ft: [0-9]*' | awk '{print $2}' || true)
  corpus=$(echo "$last" | grep -o 'corp: [0-9]*' | awk '{print $2}' || true)
  printf '| %s | %s | %s | %s | %s | %s |\n' "$name" "$status" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${corpus:-?}"
  if [ "$status" != ok ]; then
    failed=1
    echo "---- $name: last lines of $log" >&2
    tail -40 "$log" >&2
  fi
done
if [ "$keep_corpus" = --keep-corpus ] && [ "$failed" = 0 ]; then
  for name in "${harnesses[@]}"; do
    before=$(ls "tests/fuzz/corpus/$name" | wc -l)
    build-fuzz/tests/fuzz/fuzz_"$name" -merge=1 -timeout=10 -rss_limit_mb=2048 "tests/fuzz/corpus/$name" \
      "$out/corpus-$name" >"$out/$name.merge.log" 2>&1
    echo "$name: committed corpus $before -> $(ls "tests/fuzz/corpus/$name" | wc -l) inputs"
  done
fi
exit "$failed"
