#!/usr/bin/env bash
# Paired timing of two rt_render builds on one render (docs/benchmarks.md): each round runs
# both, in alternating order, so a busy spell of this shared machine hits both alike.
# Prints each run's user CPU seconds, then the mean of each and the ratio after / before,
# and whether the two builds wrote the same image bits (cmp of their .pfm outputs).
# Usage: scripts/paired_timing.sh <rt_render before> <rt_render after> <rounds> <scene>
#        [rt_render options...]   (e.g. --size 96x96 --threads 1 --seed 3 --spp 128)
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 <rt_render before> <rt_render after> <rounds> <scene> [rt_render options...]" >&2
  exit 2
fi
before=$1
after=$2
rounds=$3
scene=$4
shift 4
for app in "$before" "$after"; do
  [ -x "$app" ] || { echo "$0: $app: not an executable" >&2; exit 2; }
done
case $rounds in
  '' | *[!0-9]* | 0) echo "$0: rounds = '$rounds': must be a whole number >= 1" >&2; exit 2 ;;
esac
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

sum_before=0
sum_after=0
for ((r = 1; r <= rounds; ++r)); do
  if ((r % 2 == 1)); then order=(before after); else order=(after before); fi
  for name in "${order[@]}"; do
    app=$before
    [ "$name" = after ] && app=$after
    if ! /usr/bin/time -f '%U' -o "$out/time" "$app" "$scene" "$@" -q -o "$out/$name.pfm" \
      >/dev/null 2>"$out/err"; then
      echo "$0: $app failed:" >&2
      cat "$out/err" >&2
      exit 1
    fi
    t=$(tail -1 "$out/time")
    echo "round $r $name $t s"
    if [ "$name" = before ]; then
      sum_before=$(awk -v a="$sum_before" -v b="$t" 'BEGIN { print a + b }')
    else
      sum_after=$(awk -v a="$sum_after" -v b="$t" 'BEGIN { print a + b }')
    fi
  done
done
awk -v b="$sum_before" -v a="$sum_after" -v n="$rounds" 'BEGIN {
  printf "mean user CPU: before %.2f s, after %.2f s, after / before %.3f\n", b / n, a / n, a / b }'
if cmp -s "$out/before.pfm" "$out/after.pfm"; then
  echo "images: bit-identical"
else
  echo "images: differ"
fi
