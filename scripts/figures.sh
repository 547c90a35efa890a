#!/usr/bin/env bash
# Renders every figure of the report, each by its app at the report's own settings
# (512x512, the report's samples and bounces), into figures/ or the folder given first:
#
#   bash scripts/figures.sh [OUTDIR] [app options...]
#
# Extra options go to every app (e.g. `--size 128 --spp 4` for a quick look). Builds the
# apps first when they are missing (setting up the machine as scripts/render.sh does).
# About 40 s on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-figures}
[ $# -gt 0 ] && shift
apps=${LIBRT_APPS_DIR:-build/release/apps}  # the ctest smoke.figures_script points it elsewhere
if [ ! -x "$apps/rt_synthesis" ]; then
  bash scripts/setup.sh
  cmake --preset release
  cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)"
fi
mkdir -p "$out"
run() { echo "== $*"; "$@"; }
run "$apps/rt_hard_shadows" -o "$out/hard_shadows.png" "$@"
run "$apps/rt_indirect" -o "$out/indirect.png" "$@"
run "$apps/rt_soft_shadows" -o "$out/soft_shadows.png" "$@"
run "$apps/rt_antialiasing" --zoom 8 -o "$out/antialiasing.png" "$@"
run "$apps/rt_antialiasing" --zoom 8 --no-jitter -o "$out/antialiasing_no_jitter.png" "$@"
run "$apps/rt_depth_of_field" -o "$out/depth_of_field.png" "$@"
run "$apps/rt_depth_of_field" --pinhole -o "$out/depth_of_field_pinhole.png" "$@"
run "$apps/rt_mesh" -o "$out/mesh.png" "$@"
run "$apps/rt_synthesis" -o "$out/synthesis.png" "$@"
echo "wrote the report's figures to $(cd "$out" && pwd)"
