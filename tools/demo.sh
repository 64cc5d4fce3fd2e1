#!/usr/bin/env bash
# Builds (running setup when needed), then runs the main job on a bundled sample: legolize turns
# samples/table.obj (with 300 g on its top) into a stable LEGO model, writes the .mpd, a parts
# list, a BrickLink wanted list, a report, a heat map and building instructions (an HTML booklet,
# pictures by LeoCAD when installed), and brickcheck checks the result and every build step. With
# LeoCAD installed, it also renders the model, one build step and the heat map. Output in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
[[ -x build/src/app/legolize ]] || bash tools/setup.sh
cmake --build build -j"$(nproc)" >/dev/null
mkdir -p out
set +e
build/src/app/legolize samples/table.obj --scale 1 --load-top 300 -o out/table.mpd \
  --parts-list out/table-parts.csv --bricklink out/table-bricklink.xml \
  --report out/table-report.json --heatmap out/table-heatmap.ldr \
  --instructions out/table-instructions
status=$?
echo
echo "brickcheck on the result (the same 300 g on the top), and on every build step:"
build/src/app/brickcheck --load top=300 out/table.mpd | tee out/table-brickcheck.txt
build/src/app/brickcheck --steps --quiet out/table.mpd | tee -a out/table-brickcheck.txt
set -e
if command -v leocad >/dev/null && command -v xvfb-run >/dev/null; then
  render() { xvfb-run -a leocad -l ldraw_parts "$@" >/dev/null 2>&1; }
  render -i out/table.png -w 800 -h 600 out/table.mpd && echo "picture: out/table.png"
  render -i out/table-heatmap.png -w 800 -h 600 out/table-heatmap.ldr &&
    echo "picture: out/table-heatmap.png"
  # Step 6: the legs and the first bricks of the top.
  render -i out/table-step.png -w 800 -h 600 -f 6 -t 6 out/table.mpd &&
    ls out/table-step*.png 2>/dev/null | sed 's/^/picture: /'
fi
echo
echo "output in out/: table.mpd (open it in LeoCAD, LDView or Studio), table-parts.csv,"
echo "table-bricklink.xml, table-report.json, table-heatmap.ldr, table-brickcheck.txt,"
echo "table-instructions/index.html (open it in a browser)"
exit "$status"
