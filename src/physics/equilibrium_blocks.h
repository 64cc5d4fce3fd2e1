#pragma once
// An equilibrium system whose bodies fall into groups that no force joins (a town's buildings,
// each standing on the ground alone) is one LP per group: C_M is the least of theirs, and each
// LP is far smaller than the whole, whose one scale column couples every row.
#include <vector>

#include "physics/force_model.h"

namespace lego::physics {

struct EquilibriumBlock {
  EquilibriumSystem system;  // its bodies renumbered from 0, its columns in the whole's order
  std::vector<int> columns;  // the whole system's column of each of its columns
  std::vector<int> rows;     // the whole system's row of each of its rows
  int structures = 0;        // how many independent structures it holds
};

// The system's independent structures as blocks: each of `least_bodies` bodies or more alone, so
// that its C_M is its own (a town's buildings, ranked weakest first in the report), the smaller
// ones gathered into blocks of `least_bodies` bodies or more (small LPs each cost a solve's fixed
// work: the corpus's models, with many small structures, solved 4x slower one structure at a
// time), each with the friction columns first as in the whole; none when that makes a single
// block.
std::vector<EquilibriumBlock> independent_blocks(const EquilibriumSystem& system, int least_bodies);

// The structures that hold one of `bodies`, each as a block of its own: what a diagnosis of
// those bodies needs. One simplex over all of them at once costs more than one over each (a town
// with the same unbalanced building several times: docs/scale.md).
std::vector<EquilibriumBlock> structures_holding(const EquilibriumSystem& system,
                                                 const std::vector<int>& bodies);

}  // namespace lego::physics
