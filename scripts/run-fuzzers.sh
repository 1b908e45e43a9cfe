#!/usr/bin/env bash
# Runs every libFuzzer target of the fuzz preset (tests/fuzz, docs/testing.md "Fuzzing") for a
# bounded time, as many at once as there are cores, and fails if any finds a bug.
#
#   scripts/run-fuzzers.sh [SECONDS_PER_TARGET] [TARGET...]    (default 60 s, every target)
#
# Needs `cmake --preset fuzz && cmake --build build/fuzz`. Each target starts from its kept inputs
# (tests/fuzz/<name>/seeds and crashes, read only) and grows a working corpus in
# build/fuzz/corpus/<name>, kept between runs. A finding is written to
# build/fuzz/artifacts/<name>/ and the target's log printed; keep the input as a regression test by
# copying it to tests/fuzz/<name>/crashes/ under a name that says what it found.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

seconds=${1:-60}
shift || true
build=build/fuzz/tests/fuzz
if [ ! -d "$build" ]; then
  echo "run-fuzzers: no $build; run: cmake --preset fuzz && cmake --build build/fuzz" >&2
  exit 2
fi
targets=("$@")
if ((${#targets[@]} == 0)); then
  for binary in "$build"/fuzz_*; do
    name=${binary##*/fuzz_}
    [[ $name == *_replay ]] && continue
    targets+=("$name")
  done
fi

parallel=$(nproc)
failed=()
pids=()
names=()

finish() {  # waits for the oldest running target
  local pid=${pids[0]} name=${names[0]}
  pids=("${pids[@]:1}")
  names=("${names[@]:1}")
  if wait "$pid"; then
    echo "run-fuzzers: $name: no finding ($(grep -o 'stat::number_of_executed_units: *[0-9]*' "build/fuzz/logs/$name.log" | grep -o '[0-9]*$') inputs in ${seconds} s)"
  else
    echo "run-fuzzers: $name: FINDING; its log:" >&2
    tail -n 80 "build/fuzz/logs/$name.log" >&2
    echo "run-fuzzers: $name: the input is in build/fuzz/artifacts/$name/; keep it in tests/fuzz/$name/crashes/" >&2
    failed+=("$name")
  fi
}

mkdir -p build/fuzz/logs
for name in "${targets[@]}"; do
  binary=$build/fuzz_$name
  [ -x "$binary" ] || { echo "run-fuzzers: no fuzz target $binary" >&2; exit 2; }
  mkdir -p "build/fuzz/corpus/$name" "build/fuzz/artifacts/$name"
  inputs=("build/fuzz/corpus/$name")  # the first folder is the one libFuzzer adds to
  for kept in "tests/fuzz/$name/seeds" "tests/fuzz/$name/crashes"; do
    [ -d "$kept" ] && inputs+=("$kept")
  done
  echo "run-fuzzers: $name for ${seconds} s"
  # -timeout: one input running longer than 10 s is a finding (a hang); -rss_limit_mb: so is
  # growing past 2 GiB. -print_final_stats for the count above.
  "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="build/fuzz/artifacts/$name/" "${inputs[@]}" > "build/fuzz/logs/$name.log" 2>&1 &
  pids+=($!)
  names+=("$name")
  ((${#pids[@]} < parallel)) || finish
done
while ((${#pids[@]} > 0)); do finish; done

if ((${#failed[@]})); then
  echo "run-fuzzers: findings in: ${failed[*]}" >&2
  exit 1
fi
echo "run-fuzzers: ${#targets[@]} target(s), no finding"
