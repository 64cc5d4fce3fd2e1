#include "physics/equilibrium_blocks.h"

#include <algorithm>

#include "physics/disjoint_sets.h"

namespace lego::physics {

std::vector<EquilibriumBlock> independent_blocks(const EquilibriumSystem& sys, int least_bodies) {
  const int bodies = sys.rows / EquilibriumSystem::kEquations;
  if (bodies < 2) return {};
  // Bodies joined by a column (a contact's force between two bodies; the ground is no body).
  DisjointSets joined(bodies);
  for (int j = 0; j < sys.columns(); ++j) {
    const int first = sys.column_start[size_t(j)], end = sys.column_start[size_t(j) + 1];
    for (int k = first + 1; k < end; ++k)
      joined.join(EquilibriumSystem::body_of_row(sys.row_index[size_t(first)]),
                  EquilibriumSystem::body_of_row(sys.row_index[size_t(k)]));
  }
  // Structures, in the order of their first bodies, gathered into blocks of at least
  // `least_bodies` (the last one's remainder joining the one before).
  std::vector<int> structure_of(size_t(bodies), -1), size;
  for (int b = 0; b < bodies; ++b) {
    const int root = joined.find(b);
    if (structure_of[size_t(root)] < 0) {
      structure_of[size_t(root)] = int(size.size());
      size.push_back(0);
    }
    structure_of[size_t(b)] = structure_of[size_t(root)];
    ++size[size_t(structure_of[size_t(b)])];
  }
  std::vector<int> bin(size.size(), 0);
  int bins = 0, filled = 0;
  for (size_t k = 0; k < size.size(); ++k) {
    if (filled >= least_bodies) ++bins, filled = 0;
    bin[k] = bins;
    filled += size[k];
  }
  if (filled < least_bodies && bins > 0)  // the last bin is short: into the one before
    for (int& b : bin)
      if (b == bins) b = bins - 1;
  std::vector<int> block_of(size_t(bodies), -1), index_in_block(size_t(bodies), 0);
  std::vector<EquilibriumBlock> blocks(size_t(*std::max_element(bin.begin(), bin.end()) + 1));
  if (blocks.size() < 2) return {};
  for (int b = 0; b < bodies; ++b) {
    block_of[size_t(b)] = bin[size_t(structure_of[size_t(b)])];
    EquilibriumBlock& block = blocks[size_t(block_of[size_t(b)])];
    index_in_block[size_t(b)] = block.system.rows / EquilibriumSystem::kEquations;
    for (int e = 0; e < EquilibriumSystem::kEquations; ++e) {
      block.rows.push_back(EquilibriumSystem::row(b, e));
      block.system.rhs.push_back(sys.rhs[size_t(EquilibriumSystem::row(b, e))]);
    }
    block.system.rows += EquilibriumSystem::kEquations;
  }
  std::vector<int> local_column(size_t(sys.columns()), -1);
  for (int j = 0; j < sys.columns(); ++j) {
    const int first = sys.column_start[size_t(j)], end = sys.column_start[size_t(j) + 1];
    const int body = first < end ? EquilibriumSystem::body_of_row(sys.row_index[size_t(first)]) : 0;
    EquilibriumBlock& block = blocks[size_t(block_of[size_t(body)])];
    EquilibriumSystem& s = block.system;
    for (int k = first; k < end; ++k) {
      const int row = sys.row_index[size_t(k)];
      const int b = EquilibriumSystem::body_of_row(row);
      s.row_index.push_back(
          EquilibriumSystem::row(index_in_block[size_t(b)], row % EquilibriumSystem::kEquations));
      s.value.push_back(sys.value[size_t(k)]);
    }
    s.column_start.push_back(int(s.row_index.size()));
    s.kind.push_back(sys.kind[size_t(j)]);
    s.contact.push_back(sys.contact[size_t(j)]);
    if (j < sys.friction_columns) ++s.friction_columns;
    local_column[size_t(j)] = int(block.columns.size());
    block.columns.push_back(j);
  }
  for (int c : sys.turning_columns) {
    const int first = sys.column_start[size_t(c)];
    const int body = first < sys.column_start[size_t(c) + 1]
                         ? EquilibriumSystem::body_of_row(sys.row_index[size_t(first)])
                         : 0;
    blocks[size_t(block_of[size_t(body)])].system.turning_columns.push_back(
        local_column[size_t(c)]);
  }
  for (EquilibriumBlock& block : blocks) block.system.body_of.assign(sys.body_of.size(), -1);
  for (size_t brick = 0; brick < sys.body_of.size(); ++brick) {
    const int b = sys.body_of[brick];
    if (b >= 0)
      blocks[size_t(block_of[size_t(b)])].system.body_of[brick] = index_in_block[size_t(b)];
  }
  return blocks;
}

}  // namespace lego::physics
