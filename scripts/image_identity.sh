#!/usr/bin/env bash
# Renders a fixed set of small images as linear PFM, one per integrator and feature a
# reshape could disturb: the report's figures, the material gallery, every glTF scene of
# the data directory through each integrator, guiding, caustic paths, Sobol' with a
# filter, adaptive sampling and the environment light. Run it before and after a change
# that must not change a pixel, then compare the two folders:
#
#   bash scripts/image_identity.sh OUTDIR [DATA_DIR]
#   bash scripts/image_identity.sh --compare BEFORE AFTER
#
# The apps come from LIBRT_APPS_DIR (default build/release/apps); every render uses one
# fixed seed, so the same code writes the same bits for any thread count. About 2 min on
# two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--compare" ]; then
  before=$2 after=$3 differ=0 count=0
  for f in "$before"/*.pfm; do
    count=$((count + 1))
    name=$(basename "$f")
    if ! cmp -s "$f" "$after/$name"; then
      echo "DIFFERS: $name"
      differ=$((differ + 1))
    fi
  done
  [ "$count" -gt 0 ] || { echo "no images in $before"; exit 1; }
  echo "$((count - differ)) of $count images bit-identical"
  [ "$differ" -eq 0 ]
  exit
fi
out=${1:?usage: image_identity.sh OUTDIR [DATA_DIR] | --compare BEFORE AFTER}
data=${2:-../shared/data}
apps=${LIBRT_APPS_DIR:-build/release/apps}
mkdir -p "$out"
run() { local name=$1; shift; "$@" -o "$out/$name.pfm" > /dev/null; }

# The report's figures, small.
small=(--size 96 --spp 4)
run hard_shadows "$apps/rt_hard_shadows" "${small[@]}"
run indirect "$apps/rt_indirect" "${small[@]}"
run soft_shadows "$apps/rt_soft_shadows" "${small[@]}"
run antialiasing "$apps/rt_antialiasing" --size 32 --spp 4
run depth_of_field "$apps/rt_depth_of_field" "${small[@]}"
run mesh "$apps/rt_mesh" "${small[@]}"
run synthesis "$apps/rt_synthesis" --size 128 --spp 8
# The material gallery (every BSDF kind), with and without the data's sky.
run materials "$apps/rt_materials" --size 160 --spp 8 -q
if [ -f "$data/sky.hdr" ]; then
  run materials_sky "$apps/rt_materials" --size 120 --spp 8 --env "$data/sky.hdr" -q
fi
# The data's glTF scenes through each integrator and feature.
for scene in "$data"/gltf/*.glb "$data"/gltf/*.gltf; do
  [ -f "$scene" ] || continue
  name=$(basename "${scene%.*}")
  base=("$apps/rt_render" "$scene" --size 96x64 --spp 4 --max-depth 6 --seed 7 -q)
  run "${name}_path" "${base[@]}"
  run "${name}_bdpt" "${base[@]}" --integrator bdpt
  run "${name}_brute" "${base[@]}" --integrator brute
  run "${name}_caustics" "${base[@]}" --caustic-paths
  run "${name}_sobol_mitchell" "${base[@]}" --sampler sobol --filter mitchell
  run "${name}_bounded" "${base[@]}" --light-choice bounded
  run "${name}_adaptive" "${base[@]}" --spp 8 --adaptive
  run "${name}_guiding" "${base[@]}" --guiding --guiding-passes 3
  if [ -f "$data/sky.hdr" ]; then
    run "${name}_env" "${base[@]}" --env "$data/sky.hdr" --env-strength 0.5
  fi
done
echo "wrote $(ls "$out"/*.pfm | wc -l) images to $out"
