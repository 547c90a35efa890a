#!/usr/bin/env bash
# Runs a program as N ranks: mpirun_np.sh <mpirun> <N> <program> [arguments...]
# (--oversubscribe: more ranks than this machine's cores; --allow-run-as-root as root, CI).
set -euo pipefail
mpirun=$1
n=$2
shift 2
flags=(--oversubscribe)
[ "$(id -u)" -ne 0 ] || flags+=(--allow-run-as-root)
exec "$mpirun" "${flags[@]}" -np "$n" "$@"
