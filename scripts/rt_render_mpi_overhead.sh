#!/usr/bin/env bash
# What mpirun costs rt_render on one machine (docs/distributed.md): the same frame by
# `rt_render --threads 2` (one process) and by `mpirun -np 2 rt_render --threads 1`, in
# paired rounds (both once per round, in alternating order, so a busy spell of a shared
# machine hits both alike). Prints per run: the render's wall seconds as rt_render reports
# them (scene loading and MPI start-up excluded), the whole command's wall seconds, and
# its CPU seconds (user + sys of every process, from /usr/bin/time: mpirun waits for the
# ranks it starts, so theirs are included). Then the CPU and render-wall ratios, np2/one.
# Usage: scripts/rt_render_mpi_overhead.sh <rt_render> <scene> [rounds] [WxH] [spp]
set -euo pipefail
app=$1
scene=$2
rounds=${3:-5}
size=${4:-320x200}
spp=${5:-64}
flags=(--oversubscribe)
[ "$(id -u)" -ne 0 ] || flags+=(--allow-run-as-root)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
frame=("$scene" --size "$size" --spp "$spp" --seed 1 -o "$out/frame.png")

declare -A cpu_sum render_sum
run() {  # name, command...
  local name=$1
  shift
  local t0 t1 log render cpu
  t0=$(date +%s.%N)
  log=$(/usr/bin/time -f 'cpu %U %S' "$@" 2>&1)
  t1=$(date +%s.%N)
  render=$(sed -nE 's/.*render ([0-9.]+) s.*/\1/p' <<<"$log" | head -1)
  cpu=$(sed -nE 's/^cpu ([0-9.]+) ([0-9.]+)$/\1 + \2/p' <<<"$log" | bc)
  cpu_sum[$name]=$(echo "${cpu_sum[$name]:-0} + $cpu" | bc)
  render_sum[$name]=$(echo "${render_sum[$name]:-0} + $render" | bc)
  printf '%-24s round %d  render %7.3f s  wall %7.3f s  cpu %7.3f s\n' \
    "$name" "$round" "$render" "$(echo "$t1 - $t0" | bc)" "$cpu"
}

for round in $(seq 1 "$rounds"); do
  if [ $((round % 2)) -eq 1 ]; then
    run "one process, 2 threads" "$app" "${frame[@]}" --threads 2
    run "-np 2 x 1 thread" mpirun "${flags[@]}" -np 2 "$app" "${frame[@]}" --threads 1
  else
    run "-np 2 x 1 thread" mpirun "${flags[@]}" -np 2 "$app" "${frame[@]}" --threads 1
    run "one process, 2 threads" "$app" "${frame[@]}" --threads 2
  fi
done
one="one process, 2 threads"
np2="-np 2 x 1 thread"
printf 'sums over %d rounds: cpu %s s vs %s s (np2/one %s); render wall %s s vs %s s (np2/one %s)\n' \
  "$rounds" "${cpu_sum[$one]}" "${cpu_sum[$np2]}" \
  "$(echo "scale=3; ${cpu_sum[$np2]} / ${cpu_sum[$one]}" | bc)" \
  "${render_sum[$one]}" "${render_sum[$np2]}" \
  "$(echo "scale=3; ${render_sum[$np2]} / ${render_sum[$one]}" | bc)"
