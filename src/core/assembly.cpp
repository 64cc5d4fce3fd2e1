#include "core/assembly.h"

#include <algorithm>

namespace lego {

int Assembly::ground_level() const {
  if (ground_y) return *ground_y;
  if (bricks.empty()) return 0;
  int lowest = bricks.front().min.y;
  for (const auto& b : bricks) lowest = std::min(lowest, b.min.y);
  return lowest;
}

}  // namespace lego
