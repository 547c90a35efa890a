#!/usr/bin/env bash
# Issue 13 item 4 for every app: --version; exit 1 on a bad option (issue 37), 0 for
# --help; a repeated option takes its last value (so `scripts/render.sh -o mine.png`
# works); rt_mesh's naive-scan comparison only on request.
# Usage: app_polish_test.sh <apps build directory> <scratch directory>
set -euo pipefail
apps=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
cd "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
printf 'v -1 -1 0\nv 1 -1 0\nv 1 1 0\nf 1 2 3\n' >tri.obj
for app in rt_hard_shadows rt_indirect rt_soft_shadows rt_antialiasing rt_depth_of_field \
           rt_mesh rt_synthesis rt_render rt_materials; do
    version=$("$apps/$app" --version) || fail "$app --version failed"
    grep -q "^$app (librt [0-9]*\.[0-9]*\.[0-9]*)$" <<<"$version" || fail "$app --version: $version"
    # A bad command line exits 1 (not CLI11's own codes, e.g. 109 for an unknown option)
    # with CLI11's message; --help exits 0. rt_render gets its scene, or CLI11 would
    # report the missing scene first.
    scene=()
    [ "$app" != rt_render ] || scene=(tri.obj)
    status=0
    "$apps/$app" "${scene[@]}" --no-such-option 2>err.txt >/dev/null || status=$?
    [ "$status" -eq 1 ] || fail "$app --no-such-option: exit $status, expected 1"
    grep -q "no-such-option" err.txt || fail "$app --no-such-option: message $(cat err.txt)"
    status=0
    "$apps/$app" "${scene[@]}" --spp many 2>err.txt >/dev/null || status=$?
    [ "$status" -eq 1 ] || fail "$app --spp many: exit $status, expected 1"
    grep -q "many" err.txt || fail "$app --spp many: message $(cat err.txt)"
    "$apps/$app" --help >/dev/null || fail "$app --help: exit $?, expected 0"
    if [ "$app" = rt_render ]; then
        args=(tri.obj --size 8x8 --size 16x16 --spp 1 --threads 1 -q)
    elif [ "$app" = rt_materials ]; then
        args=(--size 8x8 --size 16x16 --spp 1 --threads 1 -q)
    else
        args=(--size 8 --size 16 --spp 1 --threads 1 -q)
    fi
    "$apps/$app" "${args[@]}" -o first.pfm -o last.pfm 2>err.txt ||
        fail "$app with repeated options: $(cat err.txt)"
    [ ! -e first.pfm ] || fail "$app: the first -o was written"
    [ -e last.pfm ] || fail "$app: the last -o was not written"
    # The last --size (16) won: a PFM header "PF\n16 16\n".
    [ "$(head -c 9 last.pfm | tail -c 6)" = "16 16" ] || fail "$app: the last --size did not win"
    rm -f last.pfm
done
out=$("$apps/rt_mesh" --size 8 --spp 1 --threads 1 -o m.png)
if grep -q "linear scan" <<<"$out"; then fail "rt_mesh compared with the naive scan unasked"; fi
out=$("$apps/rt_mesh" --size 8 --spp 1 --threads 1 --compare-naive -o m.png)
grep -q "linear scan" <<<"$out" || fail "rt_mesh --compare-naive did not compare: $out"
cd / && rm -rf "$dir"
echo "--version, bad-option exit codes, last-value options and --compare-naive checked on every app"
