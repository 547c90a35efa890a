#!/usr/bin/env bash
# Equal-time error of rt_render's defaults (Sobol', adaptive sampling, paths ended by
# roulette, denoised output) against the defaults before them (independent samples,
# uniform, 5 bounces, no denoiser) on every shared glTF scene (docs/benchmarks.md,
# "rt_render's defaults at equal time").
#
#   bench/sampling/defaults_equal_time.sh [BUILD_DIR] [DATA_DIR] [SIZE] [REF_SPP] [SPP] [RUNS]
#
# Per scene: a reference (REF_SPP Sobol' samples, uniform, unbiased depth, seed 99, both
# threads); the old defaults at SPP, one thread, seed 1; the new defaults at SPP without
# and with the denoiser. CPU time (user + system, the whole process) is the least of RUNS
# runs of each, alternated (the machine is shared). Then the new defaults again at the
# spp that takes the old one's CPU time: noisy (PFM, --no-denoise) and as a user gets
# them (--denoise: the denoised image, its cost counted in the time). Error: RMSE of the
# linear PFM against the reference divided by the reference's mean (a relative error, so a
# dark scene is measured like a bright one; the ratios are those of the RMSE), by
# scripts/pfm_rmse.py; the reference's own noise is not subtracted (it flatters neither
# side). Columns: the ratio old / new at equal samples (error per sample), at equal time
# noisy (sampling only), at equal time denoised (what a user gets).
#
# Then the same error as displayed: each image written as the PNG a user gets (the default
# exposure and tone curve, sRGB, 8 bits; the old defaults and the noisy new ones with
# --no-denoise, the denoised one with rt_render's PNG default) against the reference written
# through the same look as a 16-bit PNG; by scripts/display_error.py: RMSE in 8-bit sRGB
# code values and relMSE of the display-linear values. The display columns follow the
# linear ones, with their ratios old / new. The exposure is the default (0 EV) unless the
# scene is black at it (reference mean luminance below 0.01, as dragons_instanced's 3-lux
# sun): then the reference's auto exposure (Reinhard's key, mid grey 0.18) rounded to
# whole stops, the same for every image of the scene, as a user would set it.
#
# REF_DIR=DIR keeps the references there (SCENE.pfm, SCENE.png) and reuses them when
# present, so runs of two builds share one reference.
set -euo pipefail
build=${1:-build/release}
data=${2:-../shared/data}
size=${3:-96x96}
ref_spp=${4:-2048}
spp0=${5:-16}
runs=${6:-3}
rt=$build/apps/rt_render
here=$(cd "$(dirname "$0")" && pwd)
display() {  # "RMSE-of-255 relMSE" of each PNG against the reference PNG
  python3 "$here/../../scripts/display_error.py" "$@" |
    sed -E 's/.*RMSE ([0-9.e+-]+) of 255, relMSE ([0-9.e+-]+),.*/\1 \2/'
}
display_ev() {  # 0, or for a scene black at 0 EV the reference's auto exposure in whole stops
  python3 - "$1" "$here/../../scripts" <<'PY'
import math, sys
sys.path.insert(0, sys.argv[2])
from pfm_rmse import read_pfm
w, h, c, v = read_pfm(sys.argv[1])
y = [0.2126 * v[c * i] + 0.7152 * v[c * i + 1] + 0.0722 * v[c * i + 2] for i in range(w * h)]
key = math.exp(sum(math.log(1e-4 + max(0.0, t)) for t in y) / len(y))
print(0 if sum(y) / len(y) >= 0.01 else round(math.log2(0.18 / key)))
PY
}
relerr() {  # RMSE / reference mean, full precision
  python3 "$here/../../scripts/pfm_rmse.py" "$1" "$2" |
    sed -E 's/.*relative to the mean ([0-9.e+-]+).*/\1/'
}
cpu() {  # runs the command, prints its user + system CPU seconds
  local t
  t=$(mktemp)
  /usr/bin/time -o "$t" -f "%U %S" "$@" >/dev/null 2>&1
  awk '{printf "%.3f", $1 + $2}' "$t"
  rm -f "$t"
}
least() { printf '%s\n' "$@" | sort -g | head -1; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}'; }
equal_spp() { awk -v a="$1" -v b="$2" -v n="$spp0" 'BEGIN {s = int(n * a / b + 0.5); if (s < 4) s = 4; print s}'; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
refs=${REF_DIR:-$work}
mkdir -p "$refs"
printf '| scene | old err | old CPU s | new err, same spp | new CPU s, same spp (noisy / denoised) | equal-time spp (noisy / denoised) | new err, equal time (noisy / denoised) | old / new: same spp | equal time, noisy | equal time, denoised | display EV | display RMSE of 255: old / new noisy / new denoised | old / new, display RMSE: noisy / denoised | display relMSE: old / new noisy / new denoised | old / new, display relMSE: noisy / denoised |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for scene in "$data"/gltf/*.glb; do
  name=$(basename "$scene" .glb)
  common=(--size "$size" -q --threads 1 --seed 1)
  old=(--sampler independent --no-adaptive --max-depth 5 --no-denoise)
  reference=(--size "$size" -q --no-denoise --spp "$ref_spp" --sampler sobol --no-adaptive
    --seed 99 --threads 2)
  [ -s "$refs/$name.pfm" ] || "$rt" "$scene" "${reference[@]}" -o "$refs/$name.pfm" >/dev/null 2>&1
  ev=$(display_ev "$refs/$name.pfm")
  [ -s "$refs/$name.ev$ev.png" ] ||
    "$rt" "$scene" "${reference[@]}" --exposure "$ev" --png-bits 16 -o "$refs/$name.ev$ev.png" >/dev/null 2>&1
  cp "$refs/$name.pfm" "$work/ref.pfm"
  t_old=() t_new=() t_den=()
  for _ in $(seq "$runs"); do
    t_old+=("$(cpu "$rt" "$scene" "${common[@]}" --spp "$spp0" "${old[@]}" -o "$work/old.pfm")")
    t_new+=("$(cpu "$rt" "$scene" "${common[@]}" --spp "$spp0" --no-denoise -o "$work/new0.pfm")")
    t_den+=("$(cpu "$rt" "$scene" "${common[@]}" --spp "$spp0" --denoise -o "$work/den0.pfm")")
  done
  old_cpu=$(least "${t_old[@]}") new0_cpu=$(least "${t_new[@]}") den0_cpu=$(least "${t_den[@]}")
  spp_n=$(equal_spp "$old_cpu" "$new0_cpu")
  spp_d=$(equal_spp "$old_cpu" "$den0_cpu")
  "$rt" "$scene" "${common[@]}" --spp "$spp_n" --no-denoise -o "$work/new.pfm" >/dev/null 2>&1
  "$rt" "$scene" "${common[@]}" --spp "$spp_d" --denoise -o "$work/den.pfm" >/dev/null 2>&1
  # The PNGs a user sees (same seeds and counts as the PFMs above).
  look=(--exposure "$ev")
  "$rt" "$scene" "${common[@]}" "${look[@]}" --spp "$spp0" "${old[@]}" -o "$work/old.png" >/dev/null 2>&1
  "$rt" "$scene" "${common[@]}" "${look[@]}" --spp "$spp_n" --no-denoise -o "$work/new.png" >/dev/null 2>&1
  "$rt" "$scene" "${common[@]}" "${look[@]}" --spp "$spp_d" -o "$work/den.png" >/dev/null 2>&1
  read -r -a shown <<<"$(display "$refs/$name.ev$ev.png" "$work/old.png" "$work/new.png" "$work/den.png" | tr '\n' ' ')"
  e_old=$(relerr "$work/ref.pfm" "$work/old.pfm")
  e_new0=$(relerr "$work/ref.pfm" "$work/new0.pfm")
  e_new=$(relerr "$work/ref.pfm" "$work/new.pfm")
  e_den=$(relerr "$work/ref.pfm" "$work/den.pfm")
  printf '| %s | %s | %s | %s | %s / %s | %s / %s | %s / %s | %s | %s | %s | %s | %s / %s / %s | %s / %s | %s / %s / %s | %s / %s |\n' \
    "$name" "$e_old" "$old_cpu" "$e_new0" "$new0_cpu" "$den0_cpu" "$spp_n" "$spp_d" "$e_new" \
    "$e_den" "$(ratio "$e_old" "$e_new0")" "$(ratio "$e_old" "$e_new")" "$(ratio "$e_old" "$e_den")" \
    "$ev" "${shown[0]}" "${shown[2]}" "${shown[4]}" "$(ratio "${shown[0]}" "${shown[2]}")" \
    "$(ratio "${shown[0]}" "${shown[4]}")" "${shown[1]}" "${shown[3]}" "${shown[5]}" \
    "$(ratio "${shown[1]}" "${shown[3]}")" "$(ratio "${shown[1]}" "${shown[5]}")"
done
