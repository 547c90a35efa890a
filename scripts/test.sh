#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine, builds librt (release preset) and runs the whole
# test suite with ctest. Used as-is by CI (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake --preset release
cmake --build --preset release -j "$jobs"
ctest --preset release -j "$jobs"
