#!/usr/bin/env bash
# Runs clang-tidy (.clang-tidy's checks) over the project's own sources, in parallel, and exits 1
# on any finding. Each translation unit's result is remembered under a hash of its preprocessed
# text, the compile command and .clang-tidy, so a second run checks only what changed (CI keeps
# the cache outside the clone, as it keeps ccache's).
#
#   scripts/run-clang-tidy.sh [BUILD_DIR] [FILE...]
#     BUILD_DIR  a configured build with compile_commands.json (default: build/release)
#     FILE...    only these sources (default: every .cpp under src/, apps/ and python/)
#   CLOTHSIM_TIDY_CACHE   where results are remembered (default: ~/.cache/clothsim-tidy)
#   CLOTHSIM_TIDY_JOBS    parallel runs (default: the CPUs)
#   CLOTHSIM_TIDY_BUDGET  seconds after which no new source is started (default: none); the ones
#                         left are named and checked by the next run. CI sets it, so that a cold
#                         cache (about 7 minutes of clang-tidy on 2 cores) costs CI a bounded
#                         time, and the sources the last commit changed go first.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build/release}
[ $# -gt 0 ] && shift
database="$build/compile_commands.json"
[ -f "$database" ] || { echo "run-clang-tidy: $database is missing: configure $build first" >&2; exit 2; }
command -v clang-tidy >/dev/null || { echo "run-clang-tidy: clang-tidy is not installed (scripts/install-deps.sh)" >&2; exit 2; }
cache=${CLOTHSIM_TIDY_CACHE:-$HOME/.cache/clothsim-tidy}
jobs=${CLOTHSIM_TIDY_JOBS:-$(nproc)}
mkdir -p "$cache"

# The sources to check with the hash of each one's inputs, from the compile database.
plan=$(mktemp)
python3 - "$database" "$PWD" "$@" >"$plan" <<'PY'
import hashlib, json, os, shlex, subprocess, sys
database, root, only = sys.argv[1], sys.argv[2], {os.path.realpath(f) for f in sys.argv[3:]}
config = open(os.path.join(root, ".clang-tidy"), "rb").read()
for entry in json.load(open(database)):
    source = os.path.realpath(os.path.join(entry["directory"], entry["file"]))
    relative = os.path.relpath(source, root)
    if only and source not in only:
        continue
    if not only and not relative.startswith(("src/", "apps/", "python/")):
        continue
    words = shlex.split(entry["command"]) if "command" in entry else entry["arguments"]
    # The preprocessed text: what the compiler sees, headers included (-o and -M* dropped).
    keep, skip = [], False
    for word in words:
        if skip:
            skip = False
            continue
        if word in ("-o", "-MF", "-MT", "-MQ"):
            skip = True
            continue
        if word in ("-c", "-MD", "-MMD") or word.startswith("-Werror"):
            continue
        keep.append(word)
    text = subprocess.run(keep + ["-E", "-P", "-w"], cwd=entry["directory"], capture_output=True).stdout
    # The clone's path left out, as ccache's CCACHE_BASEDIR does, so a clone elsewhere finds the cache.
    command = " ".join(keep).replace(root, "<root>")
    digest = hashlib.sha256(config + b"\0" + command.encode() + b"\0" + text.replace(root.encode(), b"<root>")).hexdigest()
    print(digest, relative)
PY

total=$(wc -l <"$plan")
# What the last commit changed first, then the rest, each in the database's order.
changed=$(git diff --name-only HEAD~1 HEAD 2>/dev/null || true)
todo=$(while read -r digest source; do
  [ -e "$cache/$digest" ] && continue
  if grep -qxF "$source" <<<"$changed"; then echo "0 $digest $source"; else echo "1 $digest $source"; fi
done <"$plan" | sort -s -k1,1 | cut -d' ' -f2-)
count=$(printf '%s' "$todo" | grep -c . || true)
echo "run-clang-tidy: $total sources, $count to check ($((total - count)) unchanged since a clean run)"
[ "$count" -eq 0 ] && exit 0

deadline=0
[ -n "${CLOTHSIM_TIDY_BUDGET:-}" ] && deadline=$(($(date +%s) + CLOTHSIM_TIDY_BUDGET))
skipped=$(mktemp)
trap 'rm -f "$plan" "$skipped"' EXIT
export build cache deadline skipped
check_one() {
  local digest=$1 source=$2 log
  if [ "$deadline" -gt 0 ] && [ "$(date +%s)" -ge "$deadline" ]; then
    echo "$source" >>"$skipped"
    return 0
  fi
  log=$(clang-tidy -p "$build" --quiet --extra-arg=-Wno-unknown-warning-option --extra-arg=-Wno-unknown-pragmas "$source" 2>&1) && { touch "$cache/$digest"; return 0; }
  printf '%s\n' "$log" | grep -v "warnings generated\|Suppressed\|Use -header-filter\|^Error while processing" >&2
  return 1
}
export -f check_one
if printf '%s\n' "$todo" | xargs -P "$jobs" -L 1 bash -c 'check_one "$0" "$1"'; then
  left=$(wc -l <"$skipped")
  if [ "$left" -gt 0 ]; then
    echo "run-clang-tidy: clean; $left sources left for the next run (CLOTHSIM_TIDY_BUDGET):" $(sort "$skipped")
  else
    echo "run-clang-tidy: clean"
  fi
else
  echo "run-clang-tidy: findings above (.clang-tidy lists the checks)" >&2
  exit 1
fi
