#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine, builds librt and its demo apps, and renders the
# report's synthesis image to synthesis.png (extra arguments go to the app).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release
cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)"
./build/release/apps/rt_synthesis -o synthesis.png "$@"
echo "wrote $(pwd)/synthesis.png"
