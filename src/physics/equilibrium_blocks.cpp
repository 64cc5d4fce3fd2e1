#include "physics/equilibrium_blocks.h"

#include <algorithm>

#include "physics/disjoint_sets.h"

namespace lego::physics {
namespace {

constexpr int kEquations = EquilibriumSystem::kEquations;

int body_of_column(const EquilibriumSystem& sys, int j) {
  const int first = sys.column_start[size_t(j)];
  return first < sys.column_start[size_t(j) + 1]
             ? EquilibriumSystem::body_of_row(sys.row_index[size_t(first)])
             : -1;
}

// Per body, its structure: bodies that a column (a force between two bodies; the ground is no
// body) joins, numbered in the order of their first bodies. `count` is how many there are.
std::vector<int> structure_of_bodies(const EquilibriumSystem& sys, int& count) {
  const int bodies = sys.rows / kEquations;
  DisjointSets joined(bodies);
  for (int j = 0; j < sys.columns(); ++j) {
    const int first = sys.column_start[size_t(j)], end = sys.column_start[size_t(j) + 1];
    for (int k = first + 1; k < end; ++k)
      joined.join(EquilibriumSystem::body_of_row(sys.row_index[size_t(first)]),
                  EquilibriumSystem::body_of_row(sys.row_index[size_t(k)]));
  }
  std::vector<int> structure(size_t(bodies), -1), of_root(size_t(bodies), -1);
  count = 0;
  for (int b = 0; b < bodies; ++b) {
    int& s = of_root[size_t(joined.find(b))];
    if (s < 0) s = count++;
    structure[size_t(b)] = s;
  }
  return structure;
}

// The blocks that `block_of` (per body: its block, -1 to leave it out) makes, `count` of them.
// A column lies in its first body's block: a structure is never split, so its other bodies are
// there too.
std::vector<EquilibriumBlock> split(const EquilibriumSystem& sys, const std::vector<int>& block_of,
                                    int count) {
  std::vector<EquilibriumBlock> blocks(static_cast<size_t>(count));
  std::vector<int> index_in_block(block_of.size(), 0);
  for (size_t b = 0; b < block_of.size(); ++b) {
    if (block_of[b] < 0) continue;
    EquilibriumBlock& block = blocks[size_t(block_of[b])];
    index_in_block[b] = block.system.rows / kEquations;
    block.system.brick_of_body.push_back(sys.brick_of_body[b]);
    for (int e = 0; e < kEquations; ++e) {
      block.rows.push_back(EquilibriumSystem::row(int(b), e));
      block.system.rhs.push_back(sys.rhs[size_t(EquilibriumSystem::row(int(b), e))]);
    }
    block.system.rows += kEquations;
  }
  std::vector<int> local_column(size_t(sys.columns()), -1);
  for (int j = 0; j < sys.columns(); ++j) {
    const int body = body_of_column(sys, j);
    const int in = block_of[size_t(std::max(body, 0))];
    if (in < 0) continue;
    EquilibriumBlock& block = blocks[size_t(in)];
    EquilibriumSystem& s = block.system;
    for (int k = sys.column_start[size_t(j)]; k < sys.column_start[size_t(j) + 1]; ++k) {
      const int row = sys.row_index[size_t(k)];
      const int b = EquilibriumSystem::body_of_row(row);
      s.row_index.push_back(EquilibriumSystem::row(index_in_block[size_t(b)], row % kEquations));
      s.value.push_back(sys.value[size_t(k)]);
    }
    s.column_start.push_back(int(s.row_index.size()));
    s.kind.push_back(sys.kind[size_t(j)]);
    s.contact.push_back(sys.contact[size_t(j)]);
    if (j < sys.friction_columns) ++s.friction_columns;
    local_column[size_t(j)] = int(block.columns.size());
    block.columns.push_back(j);
  }
  for (int c : sys.turning_columns)
    if (local_column[size_t(c)] >= 0)
      blocks[size_t(block_of[size_t(std::max(body_of_column(sys, c), 0))])]
          .system.turning_columns.push_back(local_column[size_t(c)]);
  return blocks;
}

}  // namespace

std::vector<EquilibriumBlock> independent_blocks(const EquilibriumSystem& sys, int least_bodies) {
  if (sys.rows / kEquations < 2) return {};
  int structures = 0;
  const std::vector<int> structure = structure_of_bodies(sys, structures);
  std::vector<int> size(size_t(structures), 0);
  for (int s : structure) ++size[size_t(s)];
  // Large structures alone; the small ones, in the order of their first bodies, gathered into
  // blocks of at least `least_bodies` (the last one's remainder joining the one before).
  std::vector<int> bin(size.size(), 0);
  int bins = 0, filling = -1, before = -1, filled = 0;  // before: the small bin filled last
  for (size_t k = 0; k < size.size(); ++k) {
    if (size[k] >= least_bodies) {
      bin[k] = bins++;
      continue;
    }
    if (filling < 0 || filled >= least_bodies) before = filling, filling = bins++, filled = 0;
    bin[k] = filling;
    filled += size[k];
  }
  if (filled < least_bodies && before >= 0) {  // the last small bin is short: into the one before
    for (int& b : bin) b = b == filling ? before : b > filling ? b - 1 : b;
    --bins;
  }
  if (bins < 2) return {};
  std::vector<int> block_of(structure.size());
  for (size_t b = 0; b < structure.size(); ++b) block_of[b] = bin[size_t(structure[b])];
  std::vector<EquilibriumBlock> blocks = split(sys, block_of, bins);
  for (size_t k = 0; k < size.size(); ++k) ++blocks[size_t(bin[k])].structures;
  return blocks;
}

std::vector<EquilibriumBlock> structures_holding(const EquilibriumSystem& sys,
                                                 const std::vector<int>& bodies) {
  int structures = 0;
  const std::vector<int> structure = structure_of_bodies(sys, structures);
  std::vector<int> kept(size_t(structures), -1);  // per structure: its block
  int count = 0;
  for (int b : bodies)
    if (int& k = kept[size_t(structure[size_t(b)])]; k < 0) k = count++;
  std::vector<int> block_of(structure.size());
  for (size_t b = 0; b < structure.size(); ++b) block_of[b] = kept[size_t(structure[b])];
  return split(sys, block_of, count);
}

}  // namespace lego::physics
