#!/usr/bin/env bash
# Measures the stability LP under each Clp configuration tried for issue 3 (docs/stability-lp.md).
# Usage: tools/bench/lp-matrix.sh [build-dir]   (takes about 20 minutes on 2 cores)
set -uo pipefail
bench="${1:-build}/tools/bench/stability-bench"
run() { timeout 1200 "$bench" "$@" || echo "# timed out or failed: $*"; }
echo "# bricks rows cols nonzeros form method presolve scaling graph_s build_s solve_s status cm_gf bottleneck"
run --bricks 500 2000 --repeat 3 --form scaled --method dual
run --bricks 500 2000 --repeat 1 --form scaled --method dual --no-presolve
run --bricks 500 2000 --repeat 1 --form scaled --method dual --no-scaling
run --bricks 500 2000 --repeat 1 --form scaled --method primal
run --bricks 500 --repeat 1 --form scaled --method barrier --max-seconds 300
run --bricks 500 --repeat 1 --form scaled --method barrier-nocross --max-seconds 300
run --bricks 500 2000 --repeat 1 --form maxmin --method dual
run --bricks 500 --repeat 1 --form maxmin --method primal
run --bricks 500 --repeat 1 --form maxmin --method barrier --max-seconds 300
run --bricks 8000 --repeat 1 --form scaled --method dual
