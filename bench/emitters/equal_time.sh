#!/usr/bin/env bash
# Emitters as lights (issue 42): equal-time error and speed of two rt_render builds on a
# ToyCar-like model (bench/emitters/toycar_like.py: a 90,000-triangle body whose material
# emits through a map that is black but for four lamps), against a long reference.
# Usage: bench/emitters/equal_time.sh <rt_render before> <rt_render after> [rounds = 4]
#        [spp = 32] [reference spp = 2048] [floor = 0] [size = 160x120] [after options...]
# floor: toycar_like.py --floor (0: a black map; 3: near-black dither as a compressed map's).
# Each round renders both builds (alternating which goes first, so that a busy spell of
# this shared machine hits both alike) at the same spp, one thread, seed = the round, and
# takes each run's user CPU seconds (load and light set-up included: both changed).
# Extra arguments go to the after build only (e.g. --all-emitters).
# Prints per build: mean CPU s, samples per CPU s, RMSE against the reference (the after
# build, its own seed) away from the lamps seen directly (pfm_rmse.py --near-above 20's
# "room"), and the equal-time RMSE ratio before / after,
# sqrt(MSE_before t_before / (MSE_after t_after)) (> 1: after is better; MSE ~ 1 / time
# for an unbiased renderer).
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 <rt_render before> <rt_render after> [rounds] [spp] [ref spp] [floor] [size]" >&2
  exit 2
fi
before=$1
after=$2
rounds=${3:-4}
spp=${4:-32}
ref_spp=${5:-2048}
floor=${6:-0}
size=${7:-160x120}
shift $(($# < 7 ? $# : 7))
extra=("$@")
here=$(cd "$(dirname "$0")" && pwd)
for app in "$before" "$after"; do
  [ -x "$app" ] || { echo "$0: $app: not an executable" >&2; exit 2; }
done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
python3 "$here/toycar_like.py" "$out/car.glb" --floor "$floor"
common=(--size "$size" --threads 1 --no-adaptive --sampler independent -q)

echo "reference: after build, $ref_spp spp"
"$after" "$out/car.glb" "${common[@]}" "${extra[@]}" --spp "$ref_spp" --seed 1000 \
  -o "$out/ref.pfm" 2>/dev/null

pixels=$(python3 -c "w, h = '$size'.split('x'); print(int(w) * int(h))")
declare -A cpu mse
cpu[before]=0; cpu[after]=0; mse[before]=0; mse[after]=0
for ((r = 1; r <= rounds; ++r)); do
  if ((r % 2 == 1)); then order=(before after); else order=(after before); fi
  for name in "${order[@]}"; do
    app=$before
    args=()
    if [ "$name" = after ]; then app=$after; args=("${extra[@]}"); fi
    /usr/bin/time -f '%U' -o "$out/time" "$app" "$out/car.glb" "${common[@]}" "${args[@]}" \
      --spp "$spp" --seed "$r" -o "$out/$name.pfm" 2>"$out/err" >/dev/null ||
      { cat "$out/err" >&2; exit 1; }
    t=$(tail -1 "$out/time")
    # The MSE away from the lamps seen directly (pixels within 2 of one whose reference
    # exceeds 20: their anti-aliased edges at radiance 1000 swamp everything else, and
    # light sampling does not change them).
    m=$(python3 "$here/../../scripts/pfm_rmse.py" --near-above 20 "$out/ref.pfm" \
        "$out/$name.pfm" | sed 's/.*room MSE \([0-9.e+-]*\).*/\1/')
    echo "round $r $name: $t s user CPU, room MSE $m"
    cpu[$name]=$(awk -v a="${cpu[$name]}" -v b="$t" 'BEGIN { print a + b }')
    mse[$name]=$(awk -v a="${mse[$name]}" -v b="$m" 'BEGIN { print a + b }')
  done
done
awk -v tb="${cpu[before]}" -v ta="${cpu[after]}" -v mb="${mse[before]}" -v ma="${mse[after]}" \
  -v n="$rounds" -v spp="$spp" -v px="$pixels" 'BEGIN {
  tb /= n; ta /= n; mb /= n; ma /= n
  printf "before: %.3f s CPU, %.3f M samples / CPU s, room RMSE %.5f\n", tb, px * spp / tb / 1e6, sqrt(mb)
  printf "after:  %.3f s CPU, %.3f M samples / CPU s, room RMSE %.5f\n", ta, px * spp / ta / 1e6, sqrt(ma)
  printf "equal-time RMSE ratio before / after: %.3f (time ratio after / before %.3f)\n",
    sqrt(mb * tb / (ma * ta)), ta / tb }'
