#!/usr/bin/env bash
# rt_mpi_render under mpirun (ctest mpi.*, registered when librt::mpi is built):
#   identical  mpirun -np 1, 2, 3, 4 give PFM files byte-identical (cmp) to the one-process
#              threaded render (--single-process), and -np 3 an EXR (every layer, float)
#              byte-identical to the one-process EXR, and -np 2 with --guiding (training
#              passes kept) a PFM byte-identical to the one-process one, and -np 3 with
#              --adaptive an EXR byte-identical to the one-process one;
#   failures   a rank that fails (bad mesh file while setting up, an exception while
#              rendering, killed by SIGKILL while rendering) ends the job with a non-zero
#              exit, a message naming that rank, and no output file (nor temporary).
# Usage: mpi_test.sh identical|failures <rt_mpi_render> <mpirun> <scratch directory>
set -euo pipefail
mode=$1
app=$2
mpirun=$3
dir=$4
rm -rf "$dir"
mkdir -p "$dir"

# Root (CI) needs --allow-run-as-root; 4 ranks on 2 cores need --oversubscribe.
flags=(--oversubscribe)
[ "$(id -u)" -ne 0 ] || flags+=(--allow-run-as-root)
fail() { echo "FAIL: $*" >&2; exit 1; }

if [ "$mode" = identical ]; then
  frame=(--width 64 --height 48 --spp 4 --seed 7 --quiet)
  "$app" "${frame[@]}" --threads 2 --single-process -o "$dir/reference.pfm"
  "$app" "${frame[@]}" --threads 2 --single-process --exr-float -o "$dir/reference.exr"
  for n in 1 2 3 4; do
    # Tiles of 16 px: 12 tiles, so every rank of 4 has some to do.
    "$mpirun" "${flags[@]}" -np "$n" "$app" "${frame[@]}" --threads 1 --tile 16 \
      -o "$dir/np$n.pfm"
    cmp "$dir/reference.pfm" "$dir/np$n.pfm" || fail "-np $n differs from the one-process render"
    echo "-np $n: byte-identical to the one-process render"
  done
  "$mpirun" "${flags[@]}" -np 3 "$app" "${frame[@]}" --threads 1 --tile 16 --exr-float \
    -o "$dir/np3.exr"
  cmp "$dir/reference.exr" "$dir/np3.exr" || fail "-np 3 EXR differs from the one-process EXR"
  echo "-np 3 EXR with AOVs: byte-identical to the one-process EXR"
  # --guiding keeps its training passes: render_block in halves joined by PassCombination
  # in one process, render_mpi's image over 2 ranks.
  "$app" "${frame[@]}" --threads 2 --single-process --guiding --guiding-passes 3 \
    -o "$dir/reference_guiding.pfm"
  "$mpirun" "${flags[@]}" -np 2 "$app" "${frame[@]}" --threads 1 --tile 16 --guiding \
    --guiding-passes 3 -o "$dir/np2_guiding.pfm"
  cmp "$dir/reference_guiding.pfm" "$dir/np2_guiding.pfm" ||
    fail "-np 2 --guiding differs from the one-process render"
  echo "-np 2 --guiding (training passes kept): byte-identical to the one-process render"
  # --adaptive: render() onto a film in one process; the pilots, the counts on rank 0 and
  # the rest over 3 ranks. The EXR's sample_count layer holds each pixel's count.
  "$app" "${frame[@]}" --threads 2 --single-process --adaptive --exr-float \
    -o "$dir/reference_adaptive.exr"
  "$mpirun" "${flags[@]}" -np 3 "$app" "${frame[@]}" --threads 1 --tile 16 --adaptive \
    --exr-float -o "$dir/np3_adaptive.exr"
  cmp "$dir/reference_adaptive.exr" "$dir/np3_adaptive.exr" ||
    fail "-np 3 --adaptive differs from the one-process render"
  echo "-np 3 --adaptive EXR: byte-identical to the one-process render"
  rm -rf "$dir"
  exit 0
fi

[ "$mode" = failures ] || fail "unknown mode $mode"
# Rank 2 of 3 fails; 64 spp so that every rank is still rendering when it does.
for how in setup render kill; do
  out="$dir/$how/out.pfm"
  mkdir -p "$dir/$how"
  status=0
  "$mpirun" "${flags[@]}" -np 3 "$app" --width 64 --height 48 --spp 64 --threads 1 \
    --tile 16 --quiet --fail-rank 2 --fail-how "$how" --fail-after 100 -o "$out" \
    >"$dir/$how.out" 2>&1 || status=$?
  log=$(cat "$dir/$how.out")
  [ "$status" -ne 0 ] || fail "--fail-how $how: exit status 0; output: $log"
  case $how in
    setup) pattern="rank 0: rank 2: /nonexistent/rt_mpi_render_fail.obj" ;;
    render) pattern="rank 0: rank 2 failed: --fail-rank: simulated failure" ;;
    kill) pattern="process rank 2 .* exited on signal 9" ;;
  esac
  grep -Eq "$pattern" <<<"$log" || fail "--fail-how $how: no message matching '$pattern': $log"
  leftovers=$(ls -A "$dir/$how")
  [ -z "$leftovers" ] || fail "--fail-how $how: files left behind: $leftovers"
  echo "--fail-how $how: exit $status, the message names rank 2, nothing written"
done
rm -rf "$dir"
