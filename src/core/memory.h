#pragma once
// The memory a run may count on, for the budgets that refuse a model before it is worked on: a
// run that would need more is told so at once (exit 4), instead of failing an allocation an hour
// in or being ended by the kernel.
#include <fmt/format.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace lego {

// Bytes the kernel says can be had without swapping (MemAvailable), else the physical memory.
inline uint64_t available_memory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line))
    if (line.starts_with("MemAvailable:")) {
      std::istringstream in(line.substr(13));
      uint64_t kb = 0;
      if (in >> kb) return kb << 10;
    }
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : UINT64_MAX;
}

// "1.3 GB"
inline std::string gigabytes(double bytes) {
  return fmt::format("{:.1f} GB", bytes / (1 << 30));
}

// A run refused by the memory budget, or an allocation that failed: what, and how much.
class OutOfMemory : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Empty when `needed` bytes fit in what is available, else why not, naming `what` needs them.
inline std::string memory_shortfall(double needed, const std::string& what) {
  const uint64_t available = available_memory();
  if (needed <= double(available)) return {};
  return fmt::format("{} needs about {}, and {} is available", what, gigabytes(needed),
                     gigabytes(double(available)));
}

}  // namespace lego
