#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine, builds librt and its demo apps (not the tests nor the
# benchmarks), and renders the report's synthesis image to synthesis.png (extra arguments go
# to the app; a repeated option such as -o takes its last value).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release
# librt_apps: the library and every app, not the test suite nor the benchmarks.
cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)" --target librt_apps
./build/release/apps/rt_synthesis -o synthesis.png "$@"
echo "wrote $(pwd)/synthesis.png"
