#!/usr/bin/env bash
# The scaling table of docs/distributed.md: the same frame rendered by one process
# (threaded, --single-process) and by mpirun -np 1, 2, 4 (1 thread per rank), in paired
# rounds (every configuration once per round, so a busy spell of a shared machine hits all
# of them alike). Prints one line per run: configuration, round, render seconds (as the
# app reports: render_mpi or render_block, MPI start-up excluded), wall seconds of the
# whole command, CPU seconds (user + sys of every process of the job, from /usr/bin/time),
# the render's own CPU seconds summed over the ranks (getrusage around the render call),
# gather bytes and seconds, tiles per rank. On a shared machine the wall times measure the
# CPU share the scheduler grants as much as the renderer; CPU seconds are the overhead.
# Usage: scripts/mpi_scaling.sh <rt_mpi_render> [rounds] [size] [spp] [more options...]
# (the more options, e.g. --adaptive, go to every run)
set -euo pipefail
app=$1
rounds=${2:-3}
size=${3:-256}
spp=${4:-32}
flags=(--oversubscribe)
[ "$(id -u)" -ne 0 ] || flags+=(--allow-run-as-root)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
frame=(--size "$size" --spp "$spp" --seed 1 -o "$out/frame.pfm" "${@:5}")

run() {  # name, command...
  local name=$1
  shift
  local t0 t1 log
  t0=$(date +%s.%N)
  log=$(/usr/bin/time -f 'cpu %U %S' "$@" 2>&1)
  t1=$(date +%s.%N)
  local render gather_b gather_s cpu rcpu
  render=$(sed -nE 's/.*threads: ([0-9.]+) s$/\1/p' <<<"$log")
  gather_b=$(sed -nE 's/^gather: ([0-9]+) bytes.*/\1/p' <<<"$log")
  gather_s=$(sed -nE 's/.*bytes received, ([0-9.]+) s.*/\1/p' <<<"$log")
  rcpu=$(sed -nE 's/^render cpu: ([0-9.]+) s.*/\1/p' <<<"$log")
  cpu=$(sed -nE 's/^cpu ([0-9.]+) ([0-9.]+)$/\1 + \2/p' <<<"$log" | bc)
  printf '%-22s round %d  render %7.3f s  wall %7.3f s  cpu %7.3f s (render %7.3f s)  gather %9s B %7s s  %s\n' \
    "$name" "$round" "$render" "$(echo "$t1 - $t0" | bc)" "$cpu" "$rcpu" "${gather_b:--}" "${gather_s:--}" \
    "$(grep -o 'per rank:.*' <<<"$log" || true)"
}

for round in $(seq 1 "$rounds"); do
  run "1 process, 2 threads" "$app" "${frame[@]}" --threads 2 --single-process
  run "-np 2 x 1 thread" mpirun "${flags[@]}" -np 2 "$app" "${frame[@]}" --threads 1
  run "1 process, 1 thread" "$app" "${frame[@]}" --threads 1 --single-process
  run "-np 1 x 1 thread" mpirun "${flags[@]}" -np 1 "$app" "${frame[@]}" --threads 1
  run "-np 4 x 1 thread" mpirun "${flags[@]}" -np 4 "$app" "${frame[@]}" --threads 1
done
