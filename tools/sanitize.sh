#!/usr/bin/env bash
# The test suite built with AddressSanitizer and UndefinedBehaviorSanitizer, in build-asan/ (issue
# 19). Any sanitizer report stops the program it happens in, so the test that ran it fails and its
# output holds the report. Leak checks are off: the target is memory errors and undefined
# behaviour, and the libraries we link (Assimp, Clp, OpenBLAS) keep allocations for the process.
# Tests that only drive outside programs (LeoCAD, Chromium) are left to tools/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh >/dev/null  # the packages (and the Release build, which this does not use)
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLEGOLIZATION_SANITIZE=ON >/dev/null
cmake --build build-asan -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=0:halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cd build-asan
ctest --output-on-failure -j"$(nproc)" --timeout 900 -E "^(LeoCad|Booklet)\."
