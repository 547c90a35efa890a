#!/usr/bin/env bash
# Issue 15's efficiency target: RMSE^2 x CPU seconds on smallpt's scene (256 x 192) at 16,
# 64 and 256 spp, for librt (independent and Sobol samplers, tent filter of radius 1, the
# light sphere light-sampled with MIS by power or by bound, or only found by BSDF sampling
# as smallpt finds it; with path guiding, SAMPLER+guiding, its 5 training passes
# kept in the image) and for smallpt itself when SMALLPT names its binary (built by hand
# from Kevin Beason's public smallpt.cpp, outside the repository: it is never committed).
# Lower is better. The reference is librt at REF_SPP (default 8192) Sobol samples, cached
# in the build directory (not in git) and reused.
#
# Usage: [SMALLPT=/path/to/smallpt] [REF_SPP=8192] [THREADS=1] [RENDER_ONLY=1] [FRESH=1] \
#        bash bench/smallpt/efficiency.sh [build dir = build/release]
# Candidate images and their CPU times are cached beside the reference (FRESH=1 renders
# them again); RENDER_ONLY=1 renders the candidates without the reference or the table
# (to run them while the reference renders).
# smallpt's command line here: smallpt W H SPP SEED OUT.pfm (linear PFM, no clamp), the
# measuring form described in docs/benchmarks.md.
set -euo pipefail
build=${1:-build/release}
bin="$build/bench/librt_smallpt"
ref_spp=${REF_SPP:-8192}
threads=${THREADS:-1}
out="$build/smallpt_efficiency"
mkdir -p "$out"
ref="$out/reference_${ref_spp}.pfm"
if [[ -z "${RENDER_ONLY:-}" && ! -f "$ref" ]]; then
  echo "rendering the reference ($ref_spp spp, Sobol, 2 threads) into $ref" >&2
  "$bin" render "$ref_spp" sobol mis "$ref.tmp.pfm" 2 987654 >&2
  mv "$ref.tmp.pfm" "$ref"
fi

cpu_of() { sed -n 's/^cpu_seconds //p' "$1"; }
# Renders with COMMAND... into IMAGE unless cached; its log (CPU seconds) is IMAGE.log.
cached() {
  local img=$1; shift
  if [[ -n "${FRESH:-}" || ! -f "$img" || ! -f "$img.log" ]]; then
    "$@" > "$img.log.tmp" && mv "$img.log.tmp" "$img.log"
  fi
}

echo "| renderer | sampler | light | spp | CPU s | RMSE | RMSE² × CPU-s |"
echo "|---|---|---|---|---|---|---|"
for spp in 16 64 256; do
  for sampler in independent sobol independent+guiding sobol+guiding; do
    for light in mis bounded emitter; do
      # Guided candidates (path guiding, 5 training passes kept in the image): MIS only.
      [[ "$sampler" == *guiding* && "$light" != mis ]] && continue
      img="$out/librt_${sampler}_${light}_${spp}.pfm"
      cached "$img" "$bin" render "$spp" "$sampler" "$light" "$img" "$threads" 1
      [[ -n "${RENDER_ONLY:-}" ]] && continue
      cpu=$(cpu_of "$img.log")
      rmse=$("$bin" rmse "$img" "$ref")
      awk -v s="$sampler" -v l="$light" -v n="$spp" -v c="$cpu" -v r="$rmse" \
        'BEGIN { printf "| librt | %s | %s | %d | %.3f | %.5f | %.3e |\n", s, l, n, c, r, r*r*c }'
    done
  done
  if [[ -n "${SMALLPT:-}" ]]; then
    a="$out/smallpt_${spp}_a.pfm"; b="$out/smallpt_${spp}_b.pfm"
    cached "$a" "$SMALLPT" 256 192 "$spp" 1 "$a"
    cached "$b" "$SMALLPT" 256 192 "$spp" 2 "$b"
    [[ -n "${RENDER_ONLY:-}" ]] && continue
    cpu=$(cpu_of "$a.log")
    rmse=$("$bin" rmse "$a" "$ref")
    # Its own noise, without the difference of its image from librt's (Schlick glass, its
    # 2 x 2 sub-pixel tents): two seeds differ by sqrt(2) x the noise, so RMSE = d / sqrt 2.
    d=$("$bin" rmse "$a" "$b")
    awk -v n="$spp" -v c="$cpu" -v r="$rmse" -v d="$d" 'BEGIN {
      printf "| smallpt (vs librt reference) | erand48 | none (BSDF only) | %d | %.3f | %.5f | %.3e |\n", n, c, r, r*r*c
      s = d / sqrt(2)
      printf "| smallpt (noise only, 2 seeds) | erand48 | none (BSDF only) | %d | %.3f | %.5f | %.3e |\n", n, c, s, s*s*c }'
  fi
done
