#!/usr/bin/env bash
# Ctrl-C on a demo app: start a render that would take minutes, send SIGINT once it is
# under way, and expect an exit with status 130, the "interrupted" message, and no
# output file nor temporary file left in the (otherwise empty) output directory. "Under
# way" is a state of the app, not a time: its SIGINT handler is installed and it has used
# 0.5 s of CPU (a loaded machine only makes the wait longer). That it stops promptly rather
# than after the minutes of rendering is guarded by the test's ctest TIMEOUT.
# Usage: interrupt_test.sh <app> <scratch directory>
set -euo pipefail
set -m  # job control: a background job of a non-interactive shell would ignore SIGINT
app=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
out="$dir/interrupted.png"

"$app" --size 256 --spp 100000 --threads 2 -o "$out" 2>"$dir/stderr.txt" >/dev/null &
pid=$!
fail() { echo "FAIL: $*" >&2; echo "app stderr: ${stderr:-$(cat "$dir/stderr.txt")}" >&2; exit 1; }
# SigCgt (the signals the process catches, hex) has bit 1, SIGINT; CPU ticks of /proc/PID/stat.
catches_sigint() {
  local mask
  mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$1/status" 2>/dev/null) && [ -n "$mask" ] &&
    (( (16#$mask >> 1) & 1 ))
}
cpu_ticks() { awk '{print $14 + $15}' "/proc/$1/stat" 2>/dev/null || echo 0; }
running() { [ "$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null || echo X)" != X ] &&
  [ "$(awk '{print $3}' "/proc/$1/stat")" != Z ]; }
until catches_sigint "$pid" && [ "$(cpu_ticks "$pid")" -ge 50 ]; do
  running "$pid" || fail "the app ended before it was interrupted"
  sleep 0.05
done
kill -INT "$pid"
status=0
wait "$pid" || status=$?
stderr=$(cat "$dir/stderr.txt")
rm -f "$dir/stderr.txt"
[ "$status" -eq 130 ] || fail "exit status $status, expected 130"
grep -q "interrupted: nothing written" <<<"$stderr" || fail "no 'interrupted' message"
leftovers=$(ls -A "$dir")
[ -z "$leftovers" ] || fail "files left behind: $leftovers"
rmdir "$dir"
echo "stopped by SIGINT with status 130, nothing written"
