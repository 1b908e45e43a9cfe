#!/usr/bin/env bash
# The soak (issue 11, item 7): long runs of the paper's scenes, a tearing scene and colliding ones,
# each checked by clothsim_soak (bench/soak.cpp) for flat memory and a bounded energy balance.
# Writes bench/results/soak-<scene>.csv (one row per sample) and prints one line per scene.
#
#   bench/soak.sh [BUILD_DIR] [SECONDS]
#
# BUILD_DIR must be configured with -DCLOTHSIM_BUILD_BENCH=ON (default build/bench). SECONDS is
# the simulated time of every scene (default 3600: an hour; the tearing and colliding scenes take
# about 1.2 s of wall time per simulated second on one core, the paper's 0.1 to 0.4).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build/bench}
seconds=${2:-3600}
every=$(awk -v s="$seconds" 'BEGIN { print (s >= 600 ? 60 : s / 10) }')
cmake --build "$build" --target clothsim_soak >/dev/null
status=0
for scene in paper-fig4 paper-fig5 paper-fig6 tear-pull sphere-sweep; do
  "$build/bench/clothsim_soak" "$scene" --duration "$seconds" --every "$every" \
    --csv "bench/results/soak-$scene.csv" || status=1
done
exit $status
