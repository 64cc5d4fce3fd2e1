#!/usr/bin/env bash
# Builds everything (running setup first when needed) and runs the whole test suite with ctest.
# Ends with one line saying how many tests were skipped and what they need.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cd build
log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
ctest --output-on-failure -j"$(nproc)" --timeout 300 | tee "$log" || status=$?
skipped=$(grep -c '(Skipped)$' "$log" || true)
if [ "$skipped" -gt 0 ]; then
  echo "$skipped tests skipped: they need ../shared beside the project (its models and corpus)," \
    "an LDraw library (LDRAWDIR, or ../shared/ldraw-library), or leocad, xvfb-run, chromium and" \
    "assimp-testmodels (tools/setup.sh installs them); 'ctest -V -R NAME' shows why one skipped"
fi
exit "$status"
