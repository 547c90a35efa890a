#!/usr/bin/env bash
# Where rt_render's new defaults' per-sample cost goes: instructions per camera sample
# (callgrind, the tile loop only: work_on_tiles; deterministic, unlike CPU time on a shared
# machine) of the old defaults and of each change on its own road to the new ones
# (docs/benchmarks.md, "rt_render's defaults at equal time").
#
#   bench/sampling/defaults_cost_callgrind.sh [BUILD_DIR] [DATA_DIR] [SIZE] [SPP]
#
# Rows: old (independent, uniform, 5 bounces), + Sobol', + roulette-ended paths (no cap),
# both, and the new defaults (adding adaptive sampling). Samples are the calls of
# PathTracer::li counted by callgrind.
set -euo pipefail
build=${1:-build/release}
data=${2:-../shared/data}
size=${3:-48x48}
spp=${4:-16}
rt=$build/apps/rt_render
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
per_sample() {  # label scene flags...: prints "Ir total, samples, Ir per sample"
  local label=$1 scene=$2
  shift 2
  valgrind --tool=callgrind --toggle-collect='*work_on_tiles*' \
    --callgrind-out-file="$work/$label.out" "$rt" "$scene" --size "$size" --spp "$spp" \
    --threads 1 --seed 1 --no-denoise -q -o "$work/$label.pfm" "$@" >/dev/null 2>&1
  python3 - "$work/$label.out" <<'PY'
import re, sys
names, cur, calls, total = {}, None, 0, 0
for line in open(sys.argv[1]):
    m = re.match(r'(c?)fn=\((\d+)\)(?: (.*))?', line)
    if m:
        if m.group(3): names[m.group(2)] = m.group(3)
        if m.group(1): cur = names.get(m.group(2), '')
        continue
    m = re.match(r'calls=(\d+)', line)
    if m and cur and 'librt::PathTracer::li(' in cur: calls += int(m.group(1))
    m = re.match(r'summary: (\d+)', line)
    if m: total = int(m.group(1))
print(f"{total / 1e6:.1f} M, {calls}, {total / calls:.0f}")
PY
}
printf '| scene | old | + Sobol'"'"' | + roulette paths | Sobol'"'"' + roulette | new (+ adaptive) |\n|---|---|---|---|---|---|\n'
for scene in "$data"/gltf/*.glb; do
  name=$(basename "$scene" .glb)
  [ "$name" = dragons_instanced ] && continue  # too dark to measure (benchmarks.md)
  row="| $name"
  base=""
  for cfg in old sobol5 indep_rr sobol_rr new; do
    case $cfg in
      old) flags=(--sampler independent --no-adaptive --max-depth 5) ;;
      sobol5) flags=(--sampler sobol --no-adaptive --max-depth 5) ;;
      indep_rr) flags=(--sampler independent --no-adaptive) ;;
      sobol_rr) flags=(--no-adaptive) ;;
      new) flags=() ;;
    esac
    ir=$(per_sample "$cfg" "$scene" "${flags[@]}" | awk -F', ' '{print $3}')
    [ -z "$base" ] && base=$ir
    row="$row | $ir ($(awk -v a="$ir" -v b="$base" 'BEGIN {printf "%+.1f %%", 100 * (a / b - 1)}'))"
  done
  echo "$row |"
done
