#!/usr/bin/env bash
# Stops at random moments, in CI's fuzz step: RUNS runs (default 200) of legolize with --jobs 2
# writing a set of four outputs over old ones, each sent SIGTERM (every fifth SIGINT) after a
# random delay within the run's usual length, then as many of brickcheck --steps
# --heatmap. Every run must end by its signal (a shell's 143 or 130) or have finished first (0);
# its outputs must be all old or all new, never mixed; no temporary may be left behind.
#   tools/stop_stress.sh [RUNS [BIN_DIR]]   (BIN_DIR defaults to build-asan/src/app)
# The seed is the date, printed: FUZZ_SEED=N repeats a day's delays.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-200}
bin=${2:-build-asan/src/app}
seed=${FUZZ_SEED:-$(date -u +%Y%m%d)}
RANDOM=$((seed % 32768))
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
legolize=("$bin/legolize" samples/crate.obj --height 8 --jobs 2 --quiet -o "$work/out.mpd"
  --report "$work/out.json" --parts-list "$work/out.csv" --heatmap "$work/heat.ldr")
brickcheck=("$bin/brickcheck" --steps --jobs 2 --quiet --heatmap "$work/tower-heat.ldr"
  samples/tower.ldr)

milliseconds() { date +%s%3N; }

# The run's usual length, in ms (the shortest of three: the first reads a cold disk): the delays
# spread over it.
length_of() {
  local start shortest=999999999
  for _ in 1 2 3; do
    start=$(milliseconds)
    "$@" >/dev/null 2>&1 || true
    local took=$(($(milliseconds) - start))
    if [ "$took" -lt "$shortest" ]; then shortest=$took; fi
  done
  echo "$shortest"
}

failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# stress NAME RUNS FILES... -- COMMAND...
stress() {
  local name=$1 count=$2
  shift 2
  local files=()
  while [ "$1" != "--" ]; do
    files+=("$1")
    shift
  done
  shift
  local length stopped=0 finished=0
  length=$(length_of "$@")
  for k in $(seq 1 "$count"); do
    for f in "${files[@]}"; do echo "old $k" >"$f"; done
    local signal=TERM expected=143
    if [ $((k % 5)) -eq 0 ]; then signal=INT expected=130; fi
    local delay=$((RANDOM % (length + 1)))
    # A background job of a script starts with SIGINT ignored: env gives it back its default.
    env --default-signal=INT "$@" >/dev/null 2>&1 &
    local pid=$!
    sleep "$(printf '%d.%03d' $((delay / 1000)) $((delay % 1000)))"
    local sent=1
    kill -s "$signal" "$pid" 2>/dev/null || sent=0
    local code=0
    wait "$pid" || code=$?
    if [ "$code" -eq "$expected" ]; then
      stopped=$((stopped + 1))
    elif [ "$code" -eq 0 ]; then
      finished=$((finished + 1))
    else
      fail "$name run $k: exit $code after SIG$signal at $delay ms (sent: $sent)"
    fi
    local old=0
    for f in "${files[@]}"; do
      if grep -q "^old $k\$" "$f" 2>/dev/null; then old=$((old + 1)); fi
    done
    if [ "$old" -ne 0 ] && [ "$old" -ne "${#files[@]}" ]; then
      fail "$name run $k: a mixed set, $old of ${#files[@]} outputs old (SIG$signal at $delay ms)"
    fi
    if [ "$old" -eq 0 ] && [ "$code" -ne 0 ] && [ "$code" -ne "$expected" ]; then
      fail "$name run $k: new outputs from a run that failed"
    fi
    if ls -A "$work" | grep -q tmp-legolization; then
      fail "$name run $k: a temporary left behind: $(ls -A "$work" | grep tmp-legolization)"
      rm -rf "$work"/.tmp-legolization-* "$work"/*.tmp-legolization-*
    fi
  done
  echo "stops: $name: $count runs of about $length ms, $stopped stopped, $finished finished first"
}

echo "stops: seed $seed"
stress legolize "$runs" "$work/out.mpd" "$work/out.json" "$work/out.csv" "$work/heat.ldr" -- \
  "${legolize[@]}"
stress brickcheck "$runs" "$work/tower-heat.ldr" -- "${brickcheck[@]}"
echo "stops: $failures failures"
[ "$failures" -eq 0 ]
