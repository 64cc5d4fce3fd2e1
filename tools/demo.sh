#!/usr/bin/env bash
# Builds (running setup when needed), then audits the bundled sample model with brickcheck:
# a report, JSON, a heat map, and pictures when LeoCAD is installed. Output goes to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
[[ -x build/src/app/brickcheck ]] || bash tools/setup.sh
cmake --build build -j"$(nproc)" >/dev/null
mkdir -p out
sample=samples/tower.ldr
set +e
build/src/app/brickcheck --steps --heatmap out/tower-heatmap.ldr "$sample" | tee out/tower-report.txt
build/src/app/brickcheck --steps --json "$sample" > out/tower-report.json
status=${PIPESTATUS[0]}
set -e
if command -v leocad >/dev/null && command -v xvfb-run >/dev/null; then
  for model in "$sample" out/tower-heatmap.ldr; do
    png="out/$(basename "${model%.ldr}").png"
    xvfb-run -a leocad -l ldraw_parts -i "$png" -w 800 -h 600 "$model" >/dev/null 2>&1 && echo "picture: $png"
  done
fi
echo
echo "output in out/: tower-report.txt, tower-report.json, tower-heatmap.ldr (open it in LeoCAD or LDView)"
exit 0
