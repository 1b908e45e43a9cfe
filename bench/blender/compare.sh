#!/bin/bash
# clothsim against Blender's own cloth on the same sheet (issue 25: "ten times faster than
# Blender's cloth on the same sheet"), medians of REPEATS runs, wall seconds.
#
#   bench/blender/compare.sh [CLOTHSIM] [SIZES] [REPEATS]
#   bench/blender/compare.sh build/release/apps/clothsim/clothsim "64 128" 3
#
# Blender (Debian's `blender` package): bench/blender/blender_cloth.py, N x N vertices hung by
# two corners, its Cotton preset at quality 5, 120 frames. Its cloth takes a frame as
# seconds_per_frame simulated seconds (0.0316 s, measured by the script), so those 120 frames are
# 3.79 s of simulated time. clothsim: `cotton-drape` on the same N x N sheet (spacing 1/127 m,
# anchors edge-corners) for the same simulated time, with its defaults (implicit Euler at the
# frame step 1/60 s, the machine's cores), output files written as usual. The two materials
# differ (Blender's preset against clothsim's measured cotton shirting), the sheet, its pins and
# the simulated time do not.
set -euo pipefail
clothsim=${1:-build/release/apps/clothsim/clothsim}
sizes=${2:-"64 128"}
repeats=${3:-3}
frames=121  # frame 1 is the start: 120 simulated
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

median() { sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }

printf "%-6s %-14s %-12s %-16s %-14s %-8s\n" "N" "simulated, s" "blender, s" "clothsim, s" "clothsim, x rt" "ratio"
for n in $sizes; do
  blender_times=()
  seconds_per_frame=""
  for ((k = 0; k < repeats; ++k)); do
    line=$(blender -b --factory-startup --python "$here/blender_cloth.py" -- "$n" "$frames" 60 5 2>/dev/null | grep '^{')
    blender_times+=("$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["wall_seconds"])' "$line")")
    seconds_per_frame=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["seconds_per_frame"])' "$line")
  done
  simulated=$(python3 -c "print(round(($frames - 1) * $seconds_per_frame, 4))")
  clothsim_times=()
  for ((k = 0; k < repeats; ++k)); do
    start=$(date +%s.%N)
    "$clothsim" run cotton-drape --set lattice.rows="$n" --set lattice.cols="$n" --set anchors=edge-corners \
      --duration "$simulated" --render none --quiet --out "$out/run" >/dev/null
    clothsim_times+=("$(python3 -c "print($(date +%s.%N) - $start)")")
  done
  b=$(printf "%s\n" "${blender_times[@]}" | median)
  c=$(printf "%s\n" "${clothsim_times[@]}" | median)
  printf "%-6s %-14s %-12.2f %-16.2f %-14.2f %-8.1f\n" "$n" "$simulated" "$b" "$c" \
    "$(python3 -c "print($simulated / $c)")" "$(python3 -c "print($b / $c)")"
done
