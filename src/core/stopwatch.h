#pragma once
// Elapsed wall time, measured one way everywhere: the reports' timings, the time limits of the
// analysis and the build order, the benchmarks and the fuzzer.
#include <chrono>

namespace lego {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// What is left of `budget` seconds counted from `start` (0 once spent).
inline double seconds_left(std::chrono::steady_clock::time_point start, double budget) {
  const double left = budget - seconds_since(start);
  return left > 0 ? left : 0;
}

}  // namespace lego
