#pragma once
// Blocks of equilibrium systems solved before, found again by their equations
// (equilibrium_blocks.h): a model analysed again after a few of its parts are carried (a town
// whose one lamp rests where it cannot stay, report/audit.cpp) solves only the structures that
// changed; an analysis solves a structure placed several times (a town's copies of one house)
// once. Kept for one sequence of analyses with the same options; shared by no threads.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>

#include "physics/force_model.h"

namespace lego::physics {

struct StabilityResult;

class SolvedBlocks {
 public:
  // What identifies a block: a 128-bit hash of its equations (every coefficient and right-hand
  // side to a millionth, every bound kind), not of which parts and contacts they belong to.
  using Key = std::array<uint64_t, 2>;
  static Key key_of(const EquilibriumSystem& block);

  // The outcome stored for equations with this key, expressed for `block` and `graph` (its
  // weakest contacts and unbalanced bricks are theirs); nothing when none is stored.
  std::optional<StabilityResult> find(const Key& key, const EquilibriumSystem& block,
                                      const ContactGraph& graph) const;
  // Keeps a decided outcome of `block` (solved, or no equilibrium), in the block's own terms.
  void store(const Key& key, const EquilibriumSystem& block, const StabilityResult& outcome);

  int reused() const { return reused_; }

 private:
  struct Outcome;
  std::map<Key, std::shared_ptr<const Outcome>> solved_;
  mutable int reused_ = 0;
};

}  // namespace lego::physics
