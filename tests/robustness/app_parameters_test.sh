#!/usr/bin/env bash
# Issue 10, defects 1, 4 and 8 on the command line: every app checks all its parameters
# before loading or allocating anything, and its messages name what the user typed (the
# option and its value, or the mesh file). Also the crash of defect 1 through the app:
# rt_synthesis on an OBJ of two triangles 1e-40 apart. Registered by apps/CMakeLists.txt.
# Usage: app_parameters_test.sh <directory of the built apps> <scratch directory>
set -euo pipefail
apps=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
cd "$dir"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# expect_error <expected text> <app> <args...>: (args with -q unless the case needs the
# app's non-quiet path) exit status 1, the text on stderr, no
# "internal error", no output file. (timeout 60 only keeps a hung app from hanging the
# test; how long a call takes is not asserted: the messages show what was checked first.)
expect_error() {
  local expected=$1 app=$2
  shift 2
  local status=0 err
  rm -f out.png
  err=$(timeout 60 "$apps/$app" "$@" -o out.png 2>&1 >/dev/null) || status=$?
  [ "$status" -eq 1 ] || fail "$app $*: exit status $status, expected 1 (stderr: $err)"
  grep -qF -- "$expected" <<<"$err" || fail "$app $*: stderr lacks '$expected': $err"
  if grep -q "internal error" <<<"$err"; then fail "$app $*: $err"; fi
  [ ! -e out.png ] || fail "$app $*: wrote out.png"
}

# Defect 4: the BVH timing (skipped by -q, so not quiet here) allocated 65536^2 rays
# (std::bad_alloc) before the film size was checked.
expect_error "image size 65536 x 65536: the film would need 48 GiB, more than the 4 GiB limit" \
  rt_mesh --size 65536
# Defect 8: --size 0 / -5 silently rendered 512 x 512.
expect_error "rt_mesh: --size = 0: must be in [1, 65536]" rt_mesh --size 0 -q
expect_error "rt_hard_shadows: --size = -5: must be in [1, 65536]" rt_hard_shadows --size -5 -q
expect_error "--width = 0: must be in [1, 65536]" rt_indirect --width 0 -q
# The typed values, not derived ones (exposure times the report's, power as radiance).
expect_error "--exposure = -1: must be finite and > 0" rt_soft_shadows --exposure -1 -q
expect_error "--power = -2: must be finite and >= 0" rt_synthesis --power -2 -q
expect_error "--bounces = -1: must be in [0, 1000]" rt_depth_of_field --bounces -1 -q
expect_error "--roulette = -2: must be -1 (off) or in [0, 1000]" rt_synthesis --roulette -2 -q
expect_error "samples_per_pixel = 0" rt_antialiasing --spp 0 -q
expect_error "--mesh-scale = 0: must be finite and > 0" rt_mesh --mesh-scale 0 -q
# Issue 15: the sampler and pixel filter options.
expect_error "--sampler = halton: must be independent or sobol" rt_indirect --sampler halton -q
expect_error "--filter = lanczos: must be box, tent" rt_synthesis --filter lanczos -q
expect_error "--filter-radius = 0: must be finite and > 0" rt_synthesis --filter tent --filter-radius 0 -q
expect_error "--filter-radius = 1: needs --filter" rt_synthesis --filter-radius 1 -q
# rt_materials (the material gallery): every option checked before the sky is built or a
# sphere placed; a sky file that is not there is named.
expect_error "rt_materials: --size = 0: each side must be in [1, 65536]" rt_materials --size 0 -q
expect_error "--size = 12x: must be WIDTHxHEIGHT or WIDTH" rt_materials --size 12x -q
expect_error "image size 65536 x 65536: the film would need 48 GiB" rt_materials --size 65536x65536 -q
expect_error "samples_per_pixel = 0" rt_materials --spp 0 -q
expect_error "--max-depth = -1: must be in [0, 1000]" rt_materials --max-depth -1 -q
expect_error "--exposure = 100: must be in [-64, 64]" rt_materials --exposure 100 -q
expect_error "--env-strength = -0.5: must be finite and >= 0" rt_materials --env-strength -0.5 -q
expect_error "--env-rotate = inf: must be finite" rt_materials --env-rotate inf -q
expect_error "--time-limit = -1: must be finite and >= 0" rt_materials --time-limit -1 -q
expect_error "no_sky.hdr" rt_materials --env no_sky.hdr --size 8 -q
# Placement overflow names the options, not an internal matrix.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > one.obj
expect_error "one.obj: --mesh-fit = 10, --mesh-scale = 1e+38: the placed mesh's coordinates overflow float" \
  rt_synthesis --mesh one.obj --mesh-fit 10 --mesh-scale 1e38 -q
# A mesh without vertices, or with all of them at one point, names the file.
printf '# no vertices\n' > empty.obj
expect_error "empty.obj: the mesh has no vertices" rt_mesh --mesh empty.obj -q
printf 'v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n' > point.obj
expect_error "point.obj: all vertices of the mesh are at one point" rt_mesh --mesh point.obj -q

# The loader's warnings are printed by the app (librt itself never prints), once each.
printf 'mtllib gone.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl a\nf 1 2 3\n' > warn.obj
err=$("$apps/rt_mesh" --mesh warn.obj --size 8 --spp 1 --threads 1 -q -o warn.png 2>&1 >/dev/null) ||
  fail "rt_mesh --mesh warn.obj failed: $err"
grep -qF "warning: warn.obj: line 1: MTL file 'gone.mtl' not found" <<<"$err" ||
  fail "the MTL warning was not printed with its line: $err"
[ "$(grep -c "usemtl 'a'" <<<"$err")" -eq 1 ] || fail "the usemtl warning is not printed once: $err"
if grep -q "librt: warning" <<<"$err"; then fail "the library printed: $err"; fi

# Defect 1 through the app: two triangles in the planes x = 0 and x = 1e-40 (SIGSEGV).
printf 'v 0 0 0\nv 0 1 0\nv 0 0 1\nv 1e-40 0 0\nv 1e-40 1 0\nv 1e-40 0 1\nf 1 2 3\nf 4 5 6\n' > tiny.obj
status=0
"$apps/rt_synthesis" --mesh tiny.obj --size 8 --spp 1 --threads 1 -q -o tiny.png || status=$?
[ "$status" -eq 0 ] || fail "rt_synthesis --mesh tiny.obj: exit status $status"

# Issue 37, defect 5, in the report apps: an -o that cannot be written (/sys takes no files,
# even from root) fails in apps::validate, before the scene is built or a pixel rendered;
# so does a size whose render (here with --guiding: the film, the half film, the kept sums,
# the image, 124 bytes per pixel) would exceed 16 GiB, while its image alone is under 4 GiB.
# Not quiet: a render would print its summary on stdout before the write failed (as it did).
for app in rt_hard_shadows rt_antialiasing rt_synthesis; do
  status=0
  "$apps/$app" --size 8 --spp 1 --threads 1 -o /sys/librt_out.png >stdout.txt 2>stderr.txt ||
    status=$?
  [ "$status" -eq 1 ] || fail "$app -o /sys/librt_out.png: exit status $status"
  grep -qF "cannot write '/sys/librt_out.png': " stderr.txt ||
    fail "$app -o /sys/...: $(cat stderr.txt)"
  [ ! -s stdout.txt ] || fail "$app -o /sys/...: rendered first: $(cat stdout.txt)"
done
expect_error "--size = 12000: the render would need 17856000000 bytes" \
  rt_synthesis --size 12000 --guiding -q
expect_error "--width = 12000, --height = 12000: the render would need 17856000000 bytes" \
  rt_indirect --width 12000 --height 12000 --guiding -q

if [ "$failures" -gt 0 ]; then
  echo "$failures failure(s)" >&2
  exit 1
fi
echo "app parameter checks: all passed"
