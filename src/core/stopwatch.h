#pragma once
// Elapsed wall time, measured one way everywhere: the reports' timings, the time limits of the
// analysis and the build order, the benchmarks and the fuzzer.
#include <chrono>

namespace lego {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace lego
