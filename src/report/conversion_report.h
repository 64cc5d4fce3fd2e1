#pragma once
// legolize's --report: what was converted, how it turned out, and where the time went
// (documented in docs/legolize-report.md).
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "physics/stability.h"

namespace lego::report {

struct ConversionReport {
  std::string input, output;
  std::array<int, 3> voxels{0, 0, 0};  // W, H, D
  size_t voxels_filled = 0;
  size_t bricks = 0;
  std::map<std::string, int> bricks_by_part;  // "3001": 12
  int components = 0;
  bool single_connected = false;
  double min_cm_gf = 0;
  double cm_gf_initial = 0, cm_gf_final = 0;  // -inf (JSON null) when there is no equilibrium
  std::string status_initial, status_final;
  bool stable = false;
  int iterations = 0, accepted = 0, lp_solves = 0;
  // Candidates rejected on a local upper bound, without a whole-model analysis.
  int rejected_by_bound = 0;
  std::vector<std::pair<std::string, double>> seconds;  // per stage, in order
  std::string bottleneck;                               // words, when not stable
  uint64_t seed = 0;
  std::string version;
};

nlohmann::json to_json(const ConversionReport& report);

}  // namespace lego::report
