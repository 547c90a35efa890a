#!/usr/bin/env bash
# The denoiser's figures (docs/benchmarks.md, "Denoiser"): every shared glTF scene and the
# report's synthesis scene, noisy and denoised relMSE at 16 and 64 spp against a long
# reference, the worst 16 x 16 block mean, the most the denoiser moved a block, the blocks
# beyond 1 % + 4 standard errors, and the render's and the denoiser's time.
#   bash scripts/denoise_figures.sh [SIZE [REF_SPP [THREADS]]]   (default 320x240 512 2)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/release/bench/librt_denoise_figures"
data="${LIBRT_DATA_DIR:-$root/../shared/data}"
size="${1:-320x240}"
ref_spp="${2:-512}"
threads="${3:-2}"
[ -x "$bin" ] || { echo "build first: cmake --build --preset release --target librt_denoise_figures" >&2; exit 1; }
echo "| scene | spp | relMSE noisy | relMSE denoised | reduction | worst block noisy | worst block denoised | worst block moved | blocks off | render | denoise |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for scene in "$data"/gltf/*.glb synthesis; do
    "$bin" "$scene" --size "$size" --ref-spp "$ref_spp" --threads "$threads" --spp 16,64 |
        grep '^|' | sed "s#$data/gltf/##"
done
