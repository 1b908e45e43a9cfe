#!/usr/bin/env bash
# Real-time capacity of `clothsim view`: for square lattices of the paper's material (centre
# anchored, rkf45 at the default tolerances), the viewer's frames per second and simulated time per
# wall time, each the median of RUNS runs of --benchmark-frames FRAMES. A lattice "keeps up at 60
# fps" when both its fps >= 60 and its ratio >= 0.95. Runs under its own Xvfb when DISPLAY is unset.
#
#   bench/viewer/scan_lattices.sh build/release/apps/clothsim/clothsim [SIZES...]
#   FRAMES=300 RUNS=3 WINDOW=1280x800 EXTRA="--hide-panel" bench/viewer/scan_lattices.sh ... 7 11 15 21
set -euo pipefail

exe=${1:?usage: scan_lattices.sh CLOTHSIM [SIZES...]}
shift
sizes=("$@")
((${#sizes[@]})) || sizes=(5 7 9 11 15 21)
frames=${FRAMES:-300}
runs=${RUNS:-3}
window=${WINDOW:-1280x800}
read -r -a extra <<<"${EXTRA:-}"

if [ -z "${DISPLAY:-}" ]; then
  exec xvfb-run -a -s "-screen 0 1920x1200x24" "$0" "$exe" "${sizes[@]}"
fi

median() { sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

printf '%-8s %10s %10s   (medians of %d runs of %d frames, window %s %s, load %s)\n' lattice fps ratio "$runs" \
  "$frames" "$window" "${EXTRA:-}" "$(cut -d' ' -f1 /proc/loadavg)"
for n in "${sizes[@]}"; do
  fps=()
  ratio=()
  for ((r = 0; r < runs; ++r)); do
    line=$("$exe" view --paper-args "$n,$n,1,4,1,1400,200,80,5,1" --benchmark-frames "$frames" --size "$window" \
      ${extra[@]+"${extra[@]}"} |
      grep ' fps (')
    fps+=("$(sed -E 's/.*: ([0-9.]+) fps.*/\1/' <<<"$line")")
    ratio+=("$(sed -E 's/.*, ([0-9.]+)x real time.*/\1/' <<<"$line")")
  done
  printf '%-8s %10s %10s\n' "${n}x${n}" "$(printf '%s\n' "${fps[@]}" | median)" \
    "$(printf '%s\n' "${ratio[@]}" | median)"
done
