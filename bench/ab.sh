#!/bin/bash
# Two clothsim binaries on one command, alternating, ROUNDS rounds: the wall time and chosen rows
# of `--profile` for each run, and their medians. Alternating spreads a shared machine's drift
# over both; quote the medians and their ratio (docs/performance.md).
#
#   bench/ab.sh ROUNDS BINARY_A BINARY_B -- run SCENE [flags...]
#   ROWS="linear solve,preconditioner setup" bench/ab.sh 7 old/clothsim new/clothsim -- \
#       run cotton-drape --duration 1 --render none
#
# ROWS: profile rows to show besides the total, comma-separated, by their names in the profile
# (default: "collisions,integration"). Each run writes to a scratch folder, removed at the end.
set -euo pipefail
if [[ $# -lt 5 || $4 != "--" ]]; then
  sed -n '2,11p' "$0" >&2
  exit 2
fi
rounds=$1
binaries=("$2" "$3")
shift 4
IFS=',' read -r -a rows <<<"${ROWS:-collisions,integration}"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

median() { sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
# The seconds of profile row $1 in the text on standard input (the row's name, then its seconds).
row_seconds() { awk -v name="$1" '{ line = $0; sub(/^ +/, "", line) } index(line, name " ") == 1 {
  rest = substr(line, length(name) + 1); split(rest, f, " "); print f[1]; exit }'; }

declare -A values
for ((round = 1; round <= rounds; ++round)); do
  for k in 0 1; do
    text=$("${binaries[$k]}" "$@" --profile --out "$out/run" 2>&1)
    values[$k,total]+="$(row_seconds total <<<"$text") "
    for row in "${rows[@]}"; do values[$k,$row]+="$(row_seconds "$row" <<<"$text") "; done
  done
done
for k in 0 1; do
  echo "${binaries[$k]}"
  for row in total "${rows[@]}"; do
    runs=${values[$k,$row]}
    printf "  %-22s median %8s   runs %s\n" "$row" "$(tr ' ' '\n' <<<"$runs" | grep . | median)" "$runs"
  done
done
