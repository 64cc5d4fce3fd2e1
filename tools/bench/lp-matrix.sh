#!/usr/bin/env bash
# Measures the stability LP under each Clp configuration tried for issue 3; the results are in
# docs/stability-lp.md. Usage: tools/bench/lp-matrix.sh [build-dir]. Takes about an hour.
set -uo pipefail
bench="${1:-build}/tools/bench/stability-bench"
run() { timeout 2400 "$bench" "$@" || echo "# timed out or failed: $*"; }
echo "# $(date -u +%F) $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
echo "# bricks rows cols nonzeros form method presolve scaling graph_s build_s solve_s status cm_gf bottleneck"
run --bricks 500 --repeat 3 --method barrier-nocross
run --bricks 500 --repeat 3 --method barrier-nocross --support-bound inf
run --bricks 500 --repeat 3 --method barrier
run --bricks 500 --repeat 3 --method dual
run --bricks 500 --repeat 1 --method dual --no-presolve
run --bricks 500 --repeat 1 --method dual --no-scaling
run --bricks 500 --repeat 1 --method primal
run --bricks 500 --repeat 1 --form maxmin --method dual
run --bricks 500 --repeat 1 --form maxmin --method primal
run --bricks 500 --repeat 1 --form maxmin --method barrier-nocross --max-seconds 600
run --bricks 2000 --repeat 1 --method barrier-nocross
run --bricks 2000 --repeat 1 --method dual --max-seconds 1800
run --bricks 8000 --repeat 1 --method barrier-nocross
