#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine, builds librt and runs the whole test suite with
# ctest, including the package tests (install + examples). Used as-is by CI (.ci/run).
# Usage: scripts/test.sh [preset]   (default: release; e.g. release-shared, debug)
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
bash scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake --preset "$preset"
cmake --build --preset "$preset" -j "$jobs"
ctest --preset "$preset" -j "$jobs"
