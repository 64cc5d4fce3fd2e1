#include "physics/solved_blocks.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <unordered_map>

#include "physics/stability.h"

namespace lego::physics {

struct SolvedBlocks::Outcome {
  StabilityResult result;              // its weakest and unbalanced cleared: kept below
  std::vector<int> weakest_columns;    // per weakest contact: a friction column of it
  std::vector<double> weakest_shares;  // and its share
  std::vector<int> unbalanced_bodies;  // the block's bodies no forces hold
};

namespace {

// Two 64-bit lanes, each a multiply-xorshift chain (splitmix64's finalizer) over the words.
struct Hasher {
  uint64_t lane[2] = {0x243F6A8885A308D3ull, 0x13198A2E03707344ull};
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  void add(uint64_t word) {
    lane[0] = mix(lane[0] ^ word);
    lane[1] = mix(lane[1] + word * 0x9E3779B97F4A7C15ull);
  }
  // To a millionth of its unit (studs for lever arms, g·m/s² for weights): copies of a structure
  // placed apart (a town's houses) have equations that differ only in the last bits their
  // positions left, and are the same structure. A coefficient on a millionth's boundary may still
  // round apart: such copies are solved each, as before.
  void add(double v) {
    add(std::abs(v) < 1e12 ? uint64_t(std::llround(v * 1e6)) : std::bit_cast<uint64_t>(v));
  }
  template <class T>
  void add_all(const std::vector<T>& values) {
    add(uint64_t(values.size()));
    for (const T& v : values) {
      if constexpr (std::is_floating_point_v<T>)
        add(double(v));
      else
        add(uint64_t(int64_t(v)));
    }
  }
};

}  // namespace

SolvedBlocks::Key SolvedBlocks::key_of(const EquilibriumSystem& s) {
  Hasher h;
  h.add(uint64_t(s.rows));
  h.add(uint64_t(s.friction_columns));
  h.add_all(s.column_start);
  h.add_all(s.row_index);
  h.add_all(s.value);
  h.add(uint64_t(s.kind.size()));
  for (ForceKind kind : s.kind) h.add(uint64_t(kind));
  h.add_all(s.rhs);
  h.add_all(s.turning_columns);
  return {h.lane[0], h.lane[1]};
}

std::optional<StabilityResult> SolvedBlocks::find(const Key& key, const EquilibriumSystem& block,
                                                  const ContactGraph& graph) const {
  const auto it = solved_.find(key);
  if (it == solved_.end()) return std::nullopt;
  const Outcome& o = *it->second;
  StabilityResult r = o.result;
  for (size_t k = 0; k < o.weakest_columns.size(); ++k) {
    const int contact = block.contact[size_t(o.weakest_columns[k])];
    r.weakest.push_back({contact, graph.contacts[size_t(contact)].lower,
                         graph.contacts[size_t(contact)].upper, o.weakest_shares[k]});
  }
  for (int body : o.unbalanced_bodies) r.unbalanced.push_back(block.brick_of_body[size_t(body)]);
  r.stats.iterations = 0;  // nothing solved
  ++reused_;
  return r;
}

void SolvedBlocks::store(const Key& key, const EquilibriumSystem& block,
                         const StabilityResult& outcome) {
  if (outcome.status != StabilityStatus::Solved && outcome.status != StabilityStatus::NoEquilibrium)
    return;
  auto o = std::make_shared<Outcome>();
  o->result = outcome;
  o->result.weakest.clear();
  o->result.unbalanced.clear();
  std::unordered_map<int, int> column_of;  // contact -> its first friction column
  for (int j = block.friction_columns - 1; j >= 0; --j) column_of[block.contact[size_t(j)]] = j;
  for (const WeakContact& w : outcome.weakest) {
    const auto column = column_of.find(w.contact);
    if (column == column_of.end()) return;  // not the block's own: not kept
    o->weakest_columns.push_back(column->second);
    o->weakest_shares.push_back(w.share);
  }
  const auto& bricks = block.brick_of_body;
  for (int brick : outcome.unbalanced)
    o->unbalanced_bodies.push_back(
        int(std::lower_bound(bricks.begin(), bricks.end(), brick) - bricks.begin()));
  std::sort(o->unbalanced_bodies.begin(), o->unbalanced_bodies.end());
  solved_[key] = std::move(o);
}

}  // namespace lego::physics
