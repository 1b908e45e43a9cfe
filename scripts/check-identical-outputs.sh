#!/usr/bin/env bash
# Runs every built-in scene with two clothsim binaries and checks that every output file is the
# same, byte for byte: the arrays, energy.csv, scene.json, final.obj, every export (PC2 and its
# rest mesh, the OBJ sequence, final.glb), the checkpoints but for the wall time and command line
# they record, and summary.json but for what measures the machine (timings, the peak RSS) and the
# command line. A refactoring that claims to change no behaviour is held to this (docs/testing.md,
# "Outputs byte for byte").
#
#   scripts/check-identical-outputs.sh BEFORE AFTER [options] [-- extra run flags]
#     BEFORE, AFTER   two clothsim executables, e.g. a build of main and one of the change
#     --duration S    simulate S seconds of every scene (default: each scene's own duration)
#     --scenes LIST   comma-separated built-in scenes (default: all of `AFTER scenes`)
#     --backend B     cpu (default) or vulkan (where a device is at hand)
#     --work DIR      where the runs go (default: a temporary folder, removed at the end)
#     --new-fields    AFTER may add records: summary.json keys that only AFTER writes, and
#                     checkpoint fields that only one side writes (a new format that renames),
#                     are listed, not failed, and the checkpoints' format version may differ;
#                     every key and field both write must still be the same
#   Anything after `--` is passed to every run of both binaries.
#
# Prints one line per scene and exits 1 if any file differs (naming it), 0 if all are the same.
# summary.json is compared key by key (its keys' order aside), so a failure names the key.
# Pictures are not compared (--render none): they are drawn by OpenGL from the same positions,
# and issue 26 changes what they draw.
set -euo pipefail

usage() { sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
[ $# -ge 2 ] || usage
before=$(realpath "$1")
after=$(realpath "$2")
shift 2
duration=""
scenes=""
backend=cpu
work=""
new_fields=0
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --duration) duration=$2; shift 2 ;;
    --scenes) scenes=$2; shift 2 ;;
    --backend) backend=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --new-fields) new_fields=1; shift ;;
    --) shift; extra=("$@"); break ;;
    *) usage ;;
  esac
done
for binary in "$before" "$after"; do
  [ -x "$binary" ] || { echo "check-identical-outputs: $binary is not an executable" >&2; exit 2; }
done
if [ -z "$work" ]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"
if [ -z "$scenes" ]; then
  scenes=$("$after" scenes | awk '/^  [a-z]/ {print $1}' | paste -sd, -)
fi

# Two summary.json files hold the same values under the same keys, but for what measures the
# machine or names the binary's path; with --new-fields, keys only AFTER has are listed on stderr.
# Prints the keys that differ; exits 1 if any does.
same_summary() {
  python3 - "$1" "$2" "$new_fields" <<'EOF'
import json, sys
MEASURED = ("timings", "command_line", "peak_rss_bytes")
def flat(value, prefix=""):
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if prefix == "" and key in MEASURED:
                continue
            out.update(flat(item, f"{prefix}{key}."))
        return out
    return {prefix[:-1]: json.dumps(value)}
a, b = (flat(json.load(open(path))) for path in sys.argv[1:3])
allow_new = sys.argv[3] == "1"
added = sorted(set(b) - set(a))
wrong = [key for key in sorted(set(a) | set(b)) if a.get(key) != b.get(key) and not (allow_new and key in added)]
if allow_new and added:
    print("  summary.json: only after: " + ", ".join(added), file=sys.stderr)
print(" ".join(wrong))
sys.exit(1 if wrong else 0)
EOF
}

# Two checkpoint files hold the same fields with the same bytes, but for the run's wall time and
# command line (the output folders differ), which a checkpoint records for the resumed run's
# summary.json; the checksum then differs too. The layout is io/checkpoint.h's. With
# --new-fields, the format version may differ and fields only AFTER writes are listed on stderr.
same_checkpoint() {
  python3 - "$1" "$2" "$new_fields" <<'EOF'
import struct, sys
SIZES = {1: 8, 2: 8, 3: 1, 4: 8, 5: 24, 6: 1, 7: 4, 8: 4}  # io/checkpoint.cpp, CheckpointReader::Type
MEASURED = {b"run.wall_seconds", b"run.command_line"}
def records(path):
    data = open(path, "rb").read()
    header, (length,) = data[:16], struct.unpack_from("<Q", data, 16)
    payload, at, fields = data[24:24 + length], 0, {}
    while at < len(payload):
        (name_length,) = struct.unpack_from("<H", payload, at)
        name = payload[at + 2:at + 2 + name_length]
        kind, count = struct.unpack_from("<BQ", payload, at + 2 + name_length)
        end = at + 2 + name_length + 9 + count * SIZES[kind]
        fields[name] = kind if name in MEASURED else payload[at:end]
        at = end
    return header, fields
(header_a, a), (header_b, b) = records(sys.argv[1]), records(sys.argv[2])
allow_new = sys.argv[3] == "1"
added, removed = sorted(set(b) - set(a)), sorted(set(a) - set(b))
if allow_new:
    # A new format may add fields and rename others: the fields both write must be the same.
    if added:
        print("  checkpoint: only after: " + ", ".join(n.decode() for n in added), file=sys.stderr)
    if removed:
        print("  checkpoint: only before: " + ", ".join(n.decode() for n in removed), file=sys.stderr)
    a = {name: value for name, value in a.items() if name in b}
    b = {name: value for name, value in b.items() if name in a}
same = a == b and (allow_new or header_a == header_b)
sys.exit(0 if same else 1)
EOF
}

failures=0
IFS=, read -ra scene_list <<<"$scenes"
for scene in "${scene_list[@]}"; do
  flags=(--render none --export pc2,obj-sequence,gltf --backend "$backend" --quiet)
  [ -n "$duration" ] && flags+=(--duration "$duration")
  # One checkpoint part-way (the first frame after a quarter of the run), compared too.
  status=()
  for side in before after; do
    binary=$before
    [ $side = after ] && binary=$after
    out="$work/$side/$scene"
    rm -rf "$out"
    set +e
    "$binary" run "$scene" "${flags[@]}" --checkpoint-every 0.25 --out "$out" "${extra[@]}" >"$work/$side-$scene.log" 2>&1
    status+=($?)
    set -e
  done
  if [ "${status[0]}" != "${status[1]}" ]; then
    echo "$scene: exit status ${status[0]} before, ${status[1]} after"
    failures=$((failures + 1))
    continue
  fi
  differ=()
  a="$work/before/$scene"
  b="$work/after/$scene"
  if [ ! -d "$a" ] || [ ! -d "$b" ]; then
    if [ -d "$a" ] || [ -d "$b" ]; then differ+=("(output folder on one side only)"); fi
  else
    while IFS= read -r -d '' file; do
      rel=${file#"$a"/}
      if [ ! -e "$b/$rel" ]; then
        differ+=("$rel (only before)")
      elif [ "$rel" = summary.json ]; then
        keys=$(same_summary "$a/$rel" "$b/$rel") || differ+=("$rel ($keys)")
      elif [[ "$rel" == *.ckpt ]]; then
        same_checkpoint "$a/$rel" "$b/$rel" || differ+=("$rel")
      else
        cmp -s "$a/$rel" "$b/$rel" || differ+=("$rel")
      fi
    done < <(find "$a" -type f -print0 | sort -z)
    while IFS= read -r -d '' file; do
      rel=${file#"$b"/}
      [ -e "$a/$rel" ] || differ+=("$rel (only after)")
    done < <(find "$b" -type f -print0 | sort -z)
  fi
  files=0
  [ -d "$a" ] && files=$(find "$a" -type f | wc -l)
  if ((${#differ[@]})); then
    echo "$scene: DIFFERENT: ${differ[*]}"
    failures=$((failures + 1))
  else
    echo "$scene: same ($files files, exit ${status[0]})"
  fi
done

if ((failures)); then
  echo "check-identical-outputs: $failures scene(s) differ"
  exit 1
fi
echo "check-identical-outputs: every output of ${#scene_list[@]} scene(s) is byte-identical"
