#!/usr/bin/env bash
# RMSE against CPU time on the report's synthesis room (rt_synthesis, the bunny-free default
# teapot, 96 x 96) for each sampler and pixel filter (and adaptive sampling with the
# report's jitter), into a CSV and a log-log SVG plot
# (docs/sampling_convergence.svg). Each filter is a different image, so each gets its own
# reference (Sobol', REF_SPP samples, another seed), cached in the build directory.
#
# Usage: [REF_SPP=4096] bash bench/sampling/convergence.sh [build dir = build/release] [out.svg]
set -euo pipefail
build=${1:-build/release}
svg=${2:-docs/sampling_convergence.svg}
ref_spp=${REF_SPP:-4096}
app="$build/apps/rt_synthesis"
rmse_tool="$build/bench/librt_smallpt"
out="$build/sampling_convergence"
mkdir -p "$out"
csv="$out/convergence.csv"
echo "option,spp,cpu_seconds,rmse" > "$csv"

cpu_of() { sed -n 's/.*, \([0-9.]*\) CPU s.*/\1/p' "$1" | tail -1; }

for filter in app tent box mitchell; do
  fargs=()
  [[ "$filter" != app ]] && fargs=(--filter "$filter")
  ref="$out/ref_${filter}_${ref_spp}.pfm"
  if [[ ! -f "$ref" ]]; then
    "$app" --size 96 --threads 2 --seed 99 --sampler sobol --spp "$ref_spp" "${fargs[@]}" \
      -q -o "$ref"
  fi
  # Adaptive sampling (--adaptive) with the report's own jitter only.
  samplers=(independent sobol)
  [[ "$filter" == app ]] && samplers+=(independent+adaptive sobol+adaptive)
  for option in "${samplers[@]}"; do
    sampler=${option%+adaptive}
    aargs=()
    [[ "$option" == *+adaptive ]] && aargs=(--adaptive)
    for spp in 16 64 256; do
      img="$out/${option}_${filter}_${spp}.pfm"
      "$app" --size 96 --threads 1 --seed 1 --sampler "$sampler" --spp "$spp" "${fargs[@]}" \
        "${aargs[@]}" -o "$img" > "$out/log.txt" 2>&1
      cpu=$(cpu_of "$out/log.txt")
      rmse=$("$rmse_tool" rmse "$img" "$ref")
      label="$option / $([[ $filter == app ]] && echo "Gaussian jitter (report)" || echo "$filter filter")"
      echo "$label,$spp,$cpu,$rmse" >> "$csv"
    done
  done
done
python3 "$(dirname "$0")/plot_loglog.py" "$csv" "$svg" \
  "RMSE against CPU time, report's synthesis room, 96 x 96"
echo "wrote $csv and $svg"
