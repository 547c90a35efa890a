#!/usr/bin/env bash
# rt_render under mpirun (ctest mpi.rt_render_*, registered when librt::mpi is built):
#   identical  mpirun -np 1, 2, 3, 4 give files byte-identical (cmp) to the one-process
#              rt_render: a PNG (default sampler and pixel jitter) and an EXR with every
#              layer rendered with --sampler sobol --filter mitchell, and a PFM with
#              --guiding (training passes kept), and an EXR with --adaptive, on an OBJ
#              this script writes (rt_render has no built-in scene; this mode needs no
#              data);
#   gltf       the same on the data's glTF scene gltf/textures.glb (exit 77, a skip, with a
#              message when the data is missing; a failure when LIBRT_REQUIRE_DATA=1);
#   failures   one rank whose scene file is missing, and one rank killed by SIGKILL while
#              rendering, each end the job with a non-zero exit, a message naming that rank
#              and no output file (nor temporary); Ctrl-C (SIGINT to mpirun) stops every
#              rank and writes nothing; --time-limit and --region are refused under mpirun.
#   mismatch   ranks given different jobs (MPMD: `mpirun -np 1 app args : -np 1 app other`):
#              another scene file, --integrator bdpt (whose splats once left the ranks
#              waiting for each other forever), --spp, --guiding or the output's format on
#              one rank; the same scene file text on every rank, each side in its own
#              directory, naming a .bin (a glTF) or an .mtl (an OBJ) whose bytes differ
#              there. Every rank must exit non-zero, quickly (under `timeout`, so a hang
#              fails), nothing written, with the message naming that rank and the item (a
#              named file by its path relative to the scene file's directory).
# Usage: rt_render_mpi_test.sh identical|gltf|failures|mismatch <rt_render> <mpirun>
#        <scratch dir> <data dir>
set -euo pipefail
mode=$1
app=$2
mpirun=$3
dir=$4
data=$5
rm -rf "$dir"
mkdir -p "$dir"

# Root (CI) needs --allow-run-as-root; 4 ranks on 2 cores need --oversubscribe.
flags=(--oversubscribe)
[ "$(id -u)" -ne 0 ] || flags+=(--allow-run-as-root)
fail() { echo "FAIL: $*" >&2; exit 1; }

# A floor and a tetrahedron, no MTL: the default material, camera and light.
scene="$dir/tetra.obj"
cat >"$scene" <<'EOF'
v -4 0 -4
v 4 0 -4
v 4 0 4
v -4 0 4
v -1 0 -1
v 1 0 -1
v 0 0 1
v 0 1.5 0
f 1 3 2
f 1 4 3
f 5 6 8
f 6 7 8
f 7 5 8
f 5 7 6
EOF

# Renders $1 with the rest of the arguments by one process and by -np 1..4, comparing files.
# --no-denoise: one process denoises PNG and EXR by default, ranks do not (they keep no film
# part way for its noise estimate); the frames compared are the unbiased estimates.
identical() {
  local name=$1 file=$2
  shift 2
  local ext=${name##*.}
  set -- "$@" --no-denoise
  "$app" "$file" "$@" --threads 2 --quiet -o "$dir/one.$ext"
  for n in 1 2 3 4; do
    # Tiles of 16 px: 12 of a 64 x 40 frame, so every rank of 4 has some to do.
    "$mpirun" "${flags[@]}" -np "$n" "$app" "$file" "$@" --threads 1 --mpi-tile 16 --quiet \
      -o "$dir/np$n.$ext"
    cmp "$dir/one.$ext" "$dir/np$n.$ext" || fail "$name: -np $n differs from one process"
  done
  echo "$name: -np 1, 2, 3, 4 byte-identical to the one-process rt_render"
  rm -f "$dir"/one.* "$dir"/np*.*
}

frame=(--size 64x40 --spp 4 --seed 7)
if [ "$mode" = identical ]; then
  identical obj.png "$scene" "${frame[@]}"
  identical obj-sobol-mitchell.exr "$scene" "${frame[@]}" --sampler sobol --filter mitchell \
    --filter-radius 2
  # --guiding keeps its training passes: the progressive one-process image and render_mpi's
  # both join them to the film as render() does.
  identical obj-guiding.pfm "$scene" "${frame[@]}" --guiding --guiding-passes 3
  # --adaptive: the pilots of all tiles, the counts from the whole image on rank 0, then
  # the rest; the EXR's sample_count layer holds each pixel's count.
  identical obj-adaptive.exr "$scene" --size 64x40 --spp 16 --seed 7 --adaptive
  rm -rf "$dir"
  exit 0
fi
if [ "$mode" = gltf ]; then
  gltf="$data/gltf/textures.glb"
  if [ ! -f "$gltf" ]; then
    [ "${LIBRT_REQUIRE_DATA:-0}" != 1 ] || fail "$gltf is missing and LIBRT_REQUIRE_DATA=1"
    echo "SKIPPED: $gltf is missing (set LIBRT_DATA_DIR)"
    exit 77  # ctest's SKIP_RETURN_CODE
  fi
  identical gltf.png "$gltf" "${frame[@]}"
  identical gltf-sobol-mitchell.exr "$gltf" "${frame[@]}" --sampler sobol --filter mitchell
  rm -rf "$dir"
  exit 0
fi

if [ "$mode" = mismatch ]; then
  # A different scene: the tetrahedron moved up.
  other="$dir/other.obj"
  sed 's/^v 0 1.5 0$/v 0 2 0/' "$scene" >"$other"
  cmp -s "$scene" "$other" && fail "other.obj equals tetra.obj"
  mkdir -p "$dir/out"
  out="$dir/out/frame.png"
  common=(--size 64x40 --threads 1 --mpi-tile 16 --quiet)
  # Each rank runs through this wrapper, which records its exit status in rc.<rank> and
  # exits 0: mpirun would otherwise kill the other ranks once one fails, and a rank left
  # waiting would go unseen. So every rank must end by itself, within the timeout.
  wrapper='"$0" "$@"; echo $? >"'"$dir"'/rc.$OMPI_COMM_WORLD_RANK"'
  # mismatch <what> <ranks> <pattern> <rank 0's args> -- <last rank's args>: the first
  # ranks-1 ranks run the first arguments, the last rank the others.
  mismatch() {
    local what=$1 ranks=$2 pattern=$3
    shift 3
    local first=() last=()
    while [ "$1" != -- ]; do first+=("$1"); shift; done
    shift
    last=("$@")
    rm -f "$dir"/rc.*
    local status=0
    timeout 60 "$mpirun" "${flags[@]}" \
      -np $((ranks - 1)) bash -c "$wrapper" "$app" "${first[@]}" "${common[@]}" : \
      -np 1 bash -c "$wrapper" "$app" "${last[@]}" "${common[@]}" >"$dir/log" 2>&1 || status=$?
    local log
    log=$(cat "$dir/log")
    [ "$status" -ne 124 ] || fail "$what: still running after 60 s (a hang); output: $log"
    [ "$status" -eq 0 ] || fail "$what: mpirun exit status $status; output: $log"
    grep -Eq "$pattern" <<<"$log" || fail "$what: no message matching '$pattern': $log"
    local r
    for ((r = 0; r < ranks; ++r)); do
      [ -f "$dir/rc.$r" ] || fail "$what: rank $r did not end by itself; output: $log"
      [ "$(cat "$dir/rc.$r")" -ne 0 ] || fail "$what: rank $r exited 0; output: $log"
    done
    [ -z "$(ls -A "$dir/out")" ] || fail "$what: files written: $(ls -A "$dir/out")"
    echo "$what: every rank exits $(cat "$dir"/rc.* | sort -u | tr '\n' ' ')with '$(grep -Eo "$pattern" <<<"$log" | head -1)'"
  }
  mismatch "another scene file on rank 1" 2 \
    "rank 1: scene file differs from rank 0 \(fnv1a64 [0-9a-f]{16}, 119 bytes vs fnv1a64 [0-9a-f]{16}, 121 bytes\)" \
    "$scene" --spp 4 -o "$out" -- "$other" --spp 4 -o "$out"
  mismatch "--integrator bdpt on rank 1" 2 "rank 1: --integrator differs from rank 0 \(bdpt vs path\)" \
    "$scene" --spp 4 -o "$out" -- "$scene" --spp 4 -o "$out" --integrator bdpt
  mismatch "--spp on rank 2 of 3" 3 "rank 2: --spp differs from rank 0 \(8 vs 4\)" \
    "$scene" --spp 4 -o "$out" -- "$scene" --spp 8 -o "$out"
  mismatch "--guiding on rank 1" 2 "rank 1: --guiding differs from rank 0 \(on vs off\)" \
    "$scene" --spp 4 -o "$out" -- "$scene" --spp 4 -o "$out" --guiding
  mismatch "another output format on rank 1" 2 \
    "rank 1: --output differs from rank 0 \(.*frame\.exr vs .*frame\.png\)" \
    "$scene" --spp 4 -o "$out" -- "$scene" --spp 4 -o "$dir/out/frame.exr"

  # The files a scene names. The first ranks read a/, the last b/: the same scene file
  # text (so the check before loading passes), but the bytes it names differ between the
  # two directories, as between two machines' disks.
  mkdir -p "$dir/a/maps" "$dir/b/maps"
  # One triangle whose positions lie in maps/geometry.bin, 36 bytes of little-endian
  # floats: (0 0 0) (1 0 0) (0 1 0) in a/, (0 0 0) (0.5 0 0) (0 1 0) in b/.
  cat >"$dir/a/scene.gltf" <<'GLTF'
{"asset": {"version": "2.0"},
 "buffers": [{"uri": "maps/geometry.bin", "byteLength": 36}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
GLTF
  cp "$dir/a/scene.gltf" "$dir/b/scene.gltf"
  zero='\x00\x00\x00\x00' one='\x00\x00\x80\x3f' half='\x00\x00\x00\x3f'
  printf "$zero$zero$zero$one$zero$zero$zero$one$zero" >"$dir/a/maps/geometry.bin"
  printf "$zero$zero$zero$half$zero$zero$zero$one$zero" >"$dir/b/maps/geometry.bin"
  cmp -s "$dir/a/maps/geometry.bin" "$dir/b/maps/geometry.bin" && fail "the two .bin are equal"
  # Alone, each renders: only their disagreement fails.
  for side in a b; do
    "$app" "$dir/$side/scene.gltf" --size 16x16 --spp 1 --quiet -o "$dir/$side/alone.png" \
      >"$dir/log" 2>&1 || fail "$side/scene.gltf does not render alone: $(cat "$dir/log")"
  done
  mismatch "another .bin beside the same .gltf on rank 1" 2 \
    "rank 1: file 'maps/geometry\.bin' differs from rank 0 \(fnv1a64 [0-9a-f]{16}, 36 bytes vs fnv1a64 [0-9a-f]{16}, 36 bytes\)" \
    "$dir/a/scene.gltf" --spp 4 -o "$out" -- "$dir/b/scene.gltf" --spp 4 -o "$out"
  # An OBJ: the same text naming looks.mtl, whose Kd differs in b/.
  for side in a b; do
    { echo "mtllib looks.mtl"; echo "usemtl grey"; cat "$scene"; } >"$dir/$side/tetra.obj"
  done
  printf 'newmtl grey\nKd 0.5 0.5 0.5\n' >"$dir/a/looks.mtl"
  printf 'newmtl grey\nKd 0.4 0.5 0.5\n' >"$dir/b/looks.mtl"
  mismatch "another .mtl beside the same .obj on rank 2 of 3" 3 \
    "rank 2: file 'looks\.mtl' differs from rank 0 \(fnv1a64 [0-9a-f]{16}, 27 bytes vs fnv1a64 [0-9a-f]{16}, 27 bytes\)" \
    "$dir/a/tetra.obj" --spp 4 -o "$out" -- "$dir/b/tetra.obj" --spp 4 -o "$out"
  rm -rf "$dir"
  exit 0
fi

[ "$mode" = failures ] || fail "unknown mode $mode"
# Runs mpirun with the given arguments; checks a non-zero exit, the message and no file.
expect_failure() {
  local what=$1 pattern=$2 out=$3
  shift 3
  local status=0
  "$mpirun" "${flags[@]}" "$@" >"$dir/log" 2>&1 || status=$?
  local log
  log=$(cat "$dir/log")
  [ "$status" -ne 0 ] || fail "$what: exit status 0; output: $log"
  grep -Eq "$pattern" <<<"$log" || fail "$what: no message matching '$pattern': $log"
  local leftovers
  leftovers=$(ls -A "$(dirname "$out")")
  [ -z "$leftovers" ] || fail "$what: files left behind: $leftovers"
  echo "$what: exit $status, '$(grep -Eo "$pattern" <<<"$log" | head -1)', nothing written"
}
mkdir -p "$dir/out"
out="$dir/out/frame.exr"
common=(--size 64x40 --threads 1 --mpi-tile 16 --quiet -o "$out")

# Rank 2 of 3 is given a scene file that is not there (as on a machine without the share).
expect_failure "missing scene on rank 2" "rank 2: .*no_such_scene\.obj" "$out" \
  -np 2 "$app" "$scene" --spp 4 "${common[@]}" : \
  -np 1 "$app" "$dir/no_such_scene.obj" --spp 4 "${common[@]}"

# Rank 2 of 3 is killed once it has used 0.3 s of CPU (rendering: loading this scene takes
# milliseconds); 100000 spp keep every rank busy for a minute. The wrapper then dies of
# SIGKILL too, so that mpirun sees rank 2 killed.
killer='"$0" "$@" & pid=$!
while t=$(awk "{print \$14 + \$15}" /proc/$pid/stat 2>/dev/null) && [ "$t" -lt 30 ]; do
  sleep 0.05
done
kill -9 $pid; wait $pid; kill -9 $$'
expect_failure "rank 2 killed while rendering" "process rank 2 .*signal 9" "$out" \
  -np 2 "$app" "$scene" --spp 100000 "${common[@]}" : \
  -np 1 bash -c "$killer" "$app" "$scene" --spp 100000 "${common[@]}"

# Ctrl-C: mpirun forwards SIGINT to every rank once rank 0 has used 0.3 s of CPU
# rendering; every rank stops, nothing is written, rank 0 says so.
status=0
"$mpirun" "${flags[@]}" -np 2 "$app" "$scene" --spp 100000 "${common[@]}" >"$dir/log" 2>&1 &
job=$!
# (No wall-clock cap on the wait: ctest's TIMEOUT guards it.)
rank0=""
while [ "$(awk '{print $3}' "/proc/$job/stat" 2>/dev/null || echo Z)" != Z ]; do
  rank0=$(pgrep -P "$job" -f "$(basename "$app")" | head -1 || true)
  if [ -n "$rank0" ]; then
    t=$(awk '{print $14 + $15}' "/proc/$rank0/stat" 2>/dev/null || echo 0)
    [ "$t" -lt 30 ] || break
  fi
  sleep 0.05
done
kill -INT "$job"
wait "$job" || status=$?
log=$(cat "$dir/log")
[ "$status" -ne 0 ] || fail "Ctrl-C: exit status 0; output: $log"
grep -q "interrupted: nothing written" <<<"$log" || fail "Ctrl-C: no message: $log"
[ -z "$(ls -A "$dir/out")" ] || fail "Ctrl-C: files left behind: $(ls -A "$dir/out")"
echo "Ctrl-C under mpirun: exit $status, 'interrupted: nothing written', nothing written"

# A time limit cannot stop ranks at the same pass: refused before anything is loaded.
expect_failure "--time-limit under mpirun" "time-limit = .* not available under mpirun" "$out" \
  -np 2 "$app" "$scene" --spp 4 --time-limit 5 "${common[@]}"
# Nor can ranks rendering tiles of the frame render a crop of it: --region is refused.
expect_failure "--region under mpirun" "region = 0,0,8,8: is not available under mpirun" "$out" \
  -np 2 "$app" "$scene" --spp 4 --region 0,0,8,8 "${common[@]}"
rm -rf "$dir"
