#!/usr/bin/env bash
# time_render.sh — the whole `softpbr render MODEL -o out.png --width 1920 --height 1080`
# process, start to PNG, as issue 14's targets count it: the median wall time of RUNS runs
# per binary and model. With several binaries (e.g. before and after a change) the runs
# alternate between them, so that both sides see the same machine load.
#
#   benchmarks/time_render.sh [-n RUNS] [-a "EXTRA ARGS"] SOFTPBR... -- MODEL...
#
#   benchmarks/time_render.sh -n 7 build/cli/softpbr -- ../shared/gltf/WaterBottle/glTF/WaterBottle.gltf
#
# Prints one line per binary and model: median, min and max wall seconds, and the median
# process CPU seconds (user + system, from bash's `times` of the child).
set -euo pipefail
runs=5
extra=""
while [ $# -gt 0 ]; do
  case "$1" in
    -n) runs=$2; shift 2 ;;
    -a) extra=$2; shift 2 ;;
    --) shift; break ;;
    *) break ;;
  esac
done
bins=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do bins+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
models=("$@")
if [ ${#bins[@]} -eq 0 ] || [ ${#models[@]} -eq 0 ]; then
  echo "usage: $0 [-n RUNS] [-a \"EXTRA ARGS\"] SOFTPBR... -- MODEL..." >&2
  exit 2
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

median() { sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else printf "%.4f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
for model in "${models[@]}"; do
  declare -A wall=() cpu=()
  for ((r = 0; r < runs; ++r)); do
    for ((b = 0; b < ${#bins[@]}; ++b)); do
      start=$(date +%s%N)
      # shellcheck disable=SC2086
      /usr/bin/time -f "%U %S" -o "$out/cpu" "${bins[$b]}" render "$model" -o "$out/out.png" --width 1920 --height 1080 \
        $extra >/dev/null
      end=$(date +%s%N)
      wall[$b]+="$(awk -v s="$start" -v e="$end" 'BEGIN { printf "%.4f", (e - s) / 1e9 }') "
      cpu[$b]+="$(awk '{ printf "%.4f", $1 + $2 }' "$out/cpu") "
      cp "$out/out.png" "$out/out-$b.png"
    done
  done
  for ((b = 0; b < ${#bins[@]}; ++b)); do
    w=$(tr ' ' '\n' <<<"${wall[$b]}" | grep . | median)
    lo=$(tr ' ' '\n' <<<"${wall[$b]}" | grep . | sort -g | head -1)
    hi=$(tr ' ' '\n' <<<"${wall[$b]}" | grep . | sort -g | tail -1)
    c=$(tr ' ' '\n' <<<"${cpu[$b]}" | grep . | median)
    same=""
    if [ "$b" -gt 0 ]; then
      if cmp -s "$out/out-0.png" "$out/out-$b.png"; then same=" (PNG identical to the first binary's)"; else same=" (PNG DIFFERS from the first binary's)"; fi
    fi
    printf "%-40s %-32s wall median %.3f s (min %.3f, max %.3f), CPU median %.3f s%s\n" "${bins[$b]}" \
      "$(basename "$model")" "$w" "$lo" "$hi" "$c" "$same"
  done
  unset wall cpu
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
