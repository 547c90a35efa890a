#!/usr/bin/env bash
# Ctrl-C on a demo app: start a render that would take minutes, send SIGINT once it is
# under way, and expect a prompt exit with status 130, the "interrupted" message, and no
# output file nor temporary file left in the (otherwise empty) output directory.
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
sleep 1.5
start=$(date +%s%N)
kill -INT "$pid"
status=0
wait "$pid" || status=$?
elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
stderr=$(cat "$dir/stderr.txt")
rm -f "$dir/stderr.txt"

fail() { echo "FAIL: $*" >&2; echo "app stderr: $stderr" >&2; exit 1; }
[ "$status" -eq 130 ] || fail "exit status $status, expected 130"
grep -q "interrupted: nothing written" <<<"$stderr" || fail "no 'interrupted' message"
# Bound on the reaction time (a correctness bound, not a benchmark).
[ "$elapsed_ms" -lt 5000 ] || fail "took ${elapsed_ms} ms to stop"
leftovers=$(ls -A "$dir")
[ -z "$leftovers" ] || fail "files left behind: $leftovers"
rmdir "$dir"
echo "stopped ${elapsed_ms} ms after SIGINT with status 130, nothing written"
