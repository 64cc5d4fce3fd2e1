#!/usr/bin/env bash
# Builds everything (running setup first when needed) and runs the whole test suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 300
