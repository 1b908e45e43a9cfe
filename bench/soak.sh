#!/usr/bin/env bash
# The soak (issue 11 item 7, issue 26 item 4): every built-in scene run for a long simulated time,
# each checked by clothsim_soak (bench/soak.cpp) for flat memory and a bounded energy balance.
# Writes bench/results/soak-<run>.csv (one row per sample: wall time, resident memory, steps, the
# balance) and bench/results/soak-<run>.txt (clothsim_soak's verdict), and prints the verdicts.
#
#   bench/soak.sh [BUILD_DIR] [RUN...]
#
# BUILD_DIR must be configured with -DCLOTHSIM_BUILD_BENCH=ON (default build/bench; a folder
# without a CMakeCache.txt is taken as it is, holding bench/clothsim_soak). A RUN is a
# built-in scene's name, or paper-fig5-self-collision / paper-fig6-self-collision (the scene with
# collision.self on); without any, all of them. The paper's three scenes and the two runs with
# self-collision go for an hour of simulated time, every other scene for 600 s (SOAK_SECONDS
# overrides both). SOAK_JOBS runs that many at once, on one thread each (default 1: one at a
# time on the scene's own threads). SOAK_CHECKPOINTS=DIR checkpoints each run at every sample in
# DIR/<run>.checkpoint and resumes it from there when it exists, so a soak can be stopped and
# taken up again (the runs go on bit for bit). bench/soak_table.py prints the results as the table
# of docs/performance.md, "Soak", which has the costs per simulated second and how each run ended.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build/bench}
shift || true
if [ -f "$build/CMakeCache.txt" ]; then cmake --build "$build" --target clothsim_soak >/dev/null; fi
soak="$build/bench/clothsim_soak"
runs=("$@")
if [ ${#runs[@]} -eq 0 ]; then
  mapfile -t runs < <("$soak" --list)
  runs+=(paper-fig5-self-collision paper-fig6-self-collision)
fi
jobs=${SOAK_JOBS:-1}

# One run: its scene, its duration, its sampling interval (60 s for an hour, 20 s for 600 s).
soak_one() {
  local run=$1 scene=$1 extra=() seconds=600
  case $run in
    *-self-collision) scene=${run%-self-collision}; extra=(--set collision.self=true) ;;
  esac
  case $scene in paper-fig4 | paper-fig5 | paper-fig6) seconds=3600 ;; esac
  seconds=${SOAK_SECONDS:-$seconds}
  local every
  every=$(awk -v s="$seconds" 'BEGIN { print (s >= 3600 ? 60 : s >= 600 ? 20 : s / 10) }')
  local threads=()
  if [ "$jobs" -gt 1 ]; then threads=(--threads 1); fi
  local checkpoint=()
  if [ -n "${SOAK_CHECKPOINTS:-}" ]; then checkpoint=(--checkpoint "$SOAK_CHECKPOINTS/$run.checkpoint"); fi
  local status=0
  "$soak" "$scene" --duration "$seconds" --every "$every" "${extra[@]}" "${threads[@]}" "${checkpoint[@]}" \
    --csv "bench/results/soak-$run.csv" >"bench/results/soak-$run.txt" 2>&1 || status=$?
  cat "bench/results/soak-$run.txt"
  return $status
}
export -f soak_one
export soak jobs SOAK_SECONDS SOAK_CHECKPOINTS
printf '%s\n' "${runs[@]}" | xargs -P "$jobs" -I{} bash -c 'soak_one "$@"' _ {}
