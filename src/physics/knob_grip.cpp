#include "physics/knob_grip.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace lego::physics {
namespace {

// Solves max Σ N_i over N with Σ N_i u_i = 0 and 0 <= N_i <= 1, the u_i the unit directions of
// the contacts. It is a linear program with two equations, so an optimum is a vertex with at most
// two contacts strictly between their bounds: every contact is tried at 0, at 1 or free, two free
// at most (3⁸ cases for the eight directions, once per mask).
GripShares solve(uint8_t mask) {
  std::vector<int> dirs;
  for (int d = 0; d < kGripDirections; ++d)
    if (mask & (1u << d)) dirs.push_back(d);
  std::vector<std::array<double, 2>> u;
  for (int d : dirs) {
    const double x = kGripStep[d][0], y = kGripStep[d][1], length = std::hypot(x, y);
    u.push_back({x / length, y / length});
  }
  const int n = int(dirs.size());
  constexpr double kEps = 1e-9;
  double best = 0;
  std::vector<double> best_n(static_cast<size_t>(n), 0.0), trial(static_cast<size_t>(n));
  std::vector<int> state(size_t(n), 0);  // 0: at 0, 1: at 1, 2: free
  int cases = 1;
  for (int i = 0; i < n; ++i) cases *= 3;
  for (int c = 0; c < cases; ++c) {
    int free[2], nfree = 0;
    double rx = 0, ry = 0;  // what the free contacts must balance
    bool ok = true;
    for (int i = 0, code = c; i < n; ++i, code /= 3) {
      state[size_t(i)] = code % 3;
      if (state[size_t(i)] == 2) {
        if (nfree == 2) {
          ok = false;
          break;
        }
        free[nfree++] = i;
      } else if (state[size_t(i)] == 1) {
        rx -= u[size_t(i)][0];
        ry -= u[size_t(i)][1];
      }
    }
    if (!ok) continue;
    for (int i = 0; i < n; ++i) trial[size_t(i)] = state[size_t(i)] == 1 ? 1.0 : 0.0;
    if (nfree == 0) {
      if (std::abs(rx) > kEps || std::abs(ry) > kEps) continue;
    } else if (nfree == 1) {
      const auto& a = u[size_t(free[0])];
      const double t = rx * a[0] + ry * a[1];  // |a| = 1
      if (std::abs(rx - t * a[0]) > kEps || std::abs(ry - t * a[1]) > kEps) continue;
      trial[size_t(free[0])] = t;
    } else {
      const auto &a = u[size_t(free[0])], &b = u[size_t(free[1])];
      const double det = a[0] * b[1] - a[1] * b[0];
      if (std::abs(det) < kEps) continue;
      trial[size_t(free[0])] = (rx * b[1] - ry * b[0]) / det;
      trial[size_t(free[1])] = (a[0] * ry - a[1] * rx) / det;
    }
    double sum = 0;
    for (int i = 0; i < n && ok; ++i) {
      ok = trial[size_t(i)] >= -kEps && trial[size_t(i)] <= 1 + kEps;
      sum += trial[size_t(i)];
    }
    if (ok && sum > best + kEps) {
      best = sum;
      best_n = trial;
    }
  }
  GripShares out;
  out.balanced = best > kEps;
  for (int i = 0; i < n; ++i)
    out.share[size_t(dirs[size_t(i)])] =
        out.balanced ? std::clamp(best_n[size_t(i)], 0.0, 1.0) : 1.0;
  return out;
}

}  // namespace

const GripShares& grip_shares(uint8_t mask) {
  static const std::array<GripShares, 256> table = [] {
    std::array<GripShares, 256> t;
    for (int m = 0; m < 256; ++m) t[size_t(m)] = solve(uint8_t(m));
    return t;
  }();
  return table[mask];
}

}  // namespace lego::physics
