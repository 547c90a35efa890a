#!/usr/bin/env bash
# Equal-time error of rt_render's defaults (Sobol', adaptive sampling, paths ended by
# roulette) against the defaults before them (independent samples, uniform, 5 bounces) on
# every shared glTF scene (docs/benchmarks.md, "rt_render's defaults at equal time").
#
#   bench/sampling/defaults_equal_time.sh [BUILD_DIR] [DATA_DIR] [SIZE] [REF_SPP] [SPP]
#
# Per scene: a reference (REF_SPP Sobol' samples, uniform, unbiased depth, seed 99, both
# threads); the old defaults at SPP (16), one thread, timed (user + system CPU seconds);
# the new defaults at SPP, timed, then again at the spp that takes the old one's CPU time.
# PFM output: not denoised (the denoiser's figures are its own section).
# RMSE against the reference by scripts/pfm_rmse.py (the reference's own noise is not
# subtracted: it flatters neither side).
set -euo pipefail
build=${1:-build/release}
data=${2:-../shared/data}
size=${3:-96x96}
ref_spp=${4:-2048}
spp0=${5:-16}
rt=$build/apps/rt_render
here=$(cd "$(dirname "$0")" && pwd)
rmse() { python3 "$here/../../scripts/pfm_rmse.py" "$1" "$2" | awk '/RMSE/ {print $0; exit}' | sed -E 's/.*RMSE ([0-9.e+-]+).*/\1/'; }
cpu() {  # runs the command, prints its user + system CPU seconds
  local t
  t=$(mktemp)
  /usr/bin/time -o "$t" -f "%U %S" "$@" >/dev/null
  awk '{printf "%.2f", $1 + $2}' "$t"
  rm -f "$t"
}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '| scene | old RMSE | old CPU s | new spp | new RMSE | new CPU s | RMSE old / new |\n'
printf '|---|---|---|---|---|---|---|\n'
for scene in "$data"/gltf/*.glb; do
  name=$(basename "$scene" .glb)
  common=(--size "$size" -q --no-denoise)
  "$rt" "$scene" "${common[@]}" --spp "$ref_spp" --sampler sobol --no-adaptive --seed 99 \
    --threads 2 -o "$work/ref.pfm" >/dev/null
  old_cpu=$(cpu "$rt" "$scene" "${common[@]}" --threads 1 --seed 1 --spp "$spp0" \
    --sampler independent --no-adaptive --max-depth 5 -o "$work/old.pfm")
  new0_cpu=$(cpu "$rt" "$scene" "${common[@]}" --threads 1 --seed 1 --spp "$spp0" -o "$work/new.pfm")
  spp=$(awk -v a="$old_cpu" -v b="$new0_cpu" -v n="$spp0" 'BEGIN {s = int(n * a / b + 0.5); if (s < 4) s = 4; print s}')
  new_cpu=$(cpu "$rt" "$scene" "${common[@]}" --threads 1 --seed 1 --spp "$spp" -o "$work/new.pfm")
  old_rmse=$(rmse "$work/ref.pfm" "$work/old.pfm")
  new_rmse=$(rmse "$work/ref.pfm" "$work/new.pfm")
  ratio=$(awk -v a="$old_rmse" -v b="$new_rmse" 'BEGIN {printf "%.2f", a / b}')
  printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$old_rmse" "$old_cpu" "$spp" \
    "$new_rmse" "$new_cpu" "$ratio"
done
