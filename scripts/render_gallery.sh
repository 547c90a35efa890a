#!/usr/bin/env bash
# Renders the images of docs/gallery.md that are not the report's figures: the material
# gallery (rt_materials, under its built-in sky and under the data's sky.hdr) and every
# glTF scene of the data directory through rt_render, into docs/gallery/ (or OUTDIR):
#
#   bash scripts/render_gallery.sh [DATA_DIR [OUTDIR [app options...]]]
#
# DATA_DIR defaults to ../shared/data (relative to the repository root). Extra options go
# last to every command and so win over the script's (e.g. `--size 64x36 --spp 2` for a
# quick look; the ctest smoke.render_gallery_script runs it so). Sizes and sample
# counts are the gallery's: each image takes under a minute on two busy cores, the
# material gallery under two. Re-run it after the glTF materials and textures change, so
# the gallery shows what main renders. Builds the apps first when they are missing.
set -euo pipefail
cd "$(dirname "$0")/.."
data=${1:-../shared/data}
out=${2:-docs/gallery}
extra=("${@:3}")
apps=${LIBRT_APPS_DIR:-build/release/apps}
if [ ! -x "$apps/rt_render" ] || [ ! -x "$apps/rt_materials" ]; then
  cmake --preset release
  cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)" --target librt_apps
fi
mkdir -p "$out"
TIMEFORMAT='   %R s wall, %U s user'
run() { echo "== $* ${extra[*]}"; time "$@" "${extra[@]}"; }

# The material gallery.
run "$apps/rt_materials" --size 800 --spp 64 -q -o "$out/materials.png"
run "$apps/rt_materials" --size 480 --spp 32 --orthographic -q -o "$out/materials_orthographic.png"
if [ -f "$data/sky.hdr" ]; then
  run "$apps/rt_materials" --size 480 --spp 48 --env "$data/sky.hdr" --exposure -2.5 -q \
    -o "$out/materials_sky_hdr.png"
else
  echo "skipped materials_sky_hdr.png: $data/sky.hdr not found"
fi

# The data's glTF scenes, each by its own camera.
gltf() {  # gltf NAME [rt_render options...]
  local name=$1
  shift
  if [ -f "$data/gltf/$name.glb" ]; then
    run "$apps/rt_render" "$data/gltf/$name.glb" -q -o "$out/gltf_$name.png" "$@"
  else
    echo "skipped gltf_$name.png: $data/gltf/$name.glb not found"
  fi
}
# Lit by its own panel, as the image below was made (no studio lighting: the file has no
# punctual light, so rt_render would add it).
gltf cornell_pbr --size 320x320 --spp 64 --max-depth 8 --no-default-light
gltf material_spheres --size 400x400 --spp 32 --max-depth 6
gltf textures --size 512x320 --spp 32
# The file's sun says 3 lux (Blender's 3 W/m^2 not multiplied by 683): by the spec's units
# it is 683 times dimmer than the other files' lights; 2^9.4 = 676 makes up for it.
gltf dragons_instanced --size 960x540 --spp 16 --max-depth 4 --exposure 9.4
# The denoiser (issue 38): the same 16 samples per pixel, written raw and denoised (the
# default for PNG), with rt_render's defaults (Sobol', adaptive sampling, roulette).
if [ -f "$data/gltf/material_spheres.glb" ]; then
  for kind in noisy denoised; do
    flag=--denoise
    [ "$kind" = noisy ] && flag=--no-denoise
    run "$apps/rt_render" "$data/gltf/material_spheres.glb" --size 400x400 --spp 16 --seed 1 \
      "$flag" -q -o "$out/denoise_${kind}_16spp.png"
  done
else
  echo "skipped denoise_*_16spp.png: $data/gltf/material_spheres.glb not found"
fi
# A model with no light (and no camera) of its own (issue 42): the studio lighting and the
# framing camera rt_render gives it, turned 30 degrees, in the default filmic look.
if [ -f "$data/stanford-bunny.obj" ]; then
  run "$apps/rt_render" "$data/stanford-bunny.obj" --size 480x360 --spp 32 --orbit 30 -q \
    -o "$out/default_lighting_bunny.png"
else
  echo "skipped default_lighting_bunny.png: $data/stanford-bunny.obj not found"
fi
echo "wrote the gallery's images to $(cd "$out" && pwd)"
