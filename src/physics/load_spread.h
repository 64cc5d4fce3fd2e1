#pragma once
// Loads spread as the LP spreads them: from the optimum of a build step the LP solved, the
// forces' response to a small change of load, for the steps that follow it at the cost of one
// factorization each (no ordering: that is done once per LP). Near its optimum the interior point
// method weighs each force by Θ, about (its slack to the bound it nears) / (its reduced cost):
// forces the optimum holds at a bound, or that would cost C_M, weigh next to nothing; those it is
// free to move weigh much. The least-Θ-norm forces that balance a load, Θ·Aᵀ·(A·Θ·Aᵀ)⁻¹·r, move
// the optimum along its face (docs/physics.md, "Build steps"), so the certificates made from them
// keep the LP's largest friction, where certify() body by body piles friction up near the ground
// (the duck at height 24: steps after an LP certified at 41-67 gf where the LP gives 59.5-67.3,
// and body by body at 1.3-9 gf). The response is linear: a few steps on, forces the optimum had
// held off their bounds pass them, and certify() brings them back by small LPs near each
// (certificate.h).
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "physics/force_model.h"

namespace lego::physics {

class LoadSpread {
 public:
  // The step's system, its columns' keys and its bodies' bricks in the whole model (whole
  // indexes), and the row duals of the LP's optimum there (the scaled form's, Clp's sign).
  LoadSpread(const EquilibriumSystem& system, const std::vector<uint64_t>& column_keys,
             const std::vector<int>& body_bricks, const std::vector<double>& row_duals, double cm);
  ~LoadSpread();
  LoadSpread(const LoadSpread&) = delete;
  LoadSpread& operator=(const LoadSpread&) = delete;

  bool usable() const { return usable_; }
  double solved_cm() const { return solved_cm_; }  // the LP's C_M at the solved step, g·m/s²
  // The body of the solved step that brick `whole` was, or -1.
  int body_of_brick(int whole) const;
  // Adds to `x` (per column of `system`, a later step of the same model) the forces of the solved
  // step's columns that balance what `x` leaves unbalanced on the solved step's bodies; `body_of`
  // gives each of `system`'s bodies its body here (-1: none). The rows of other bodies are left
  // as they are: no column here touches them.
  bool spread(const EquilibriumSystem& system, const std::vector<uint64_t>& column_keys,
              const std::vector<int>& body_of, std::vector<double>& x) const;

 private:
  struct Solved;  // the solved step's columns, reduced costs and normal matrix
  std::unique_ptr<Solved> solved_;
  std::unordered_map<int, int> body_of_brick_;
  mutable std::mutex factoring_;  // the matrix and its factor are formed anew for each spread
  bool usable_ = false;
  double solved_cm_ = 0;
};

}  // namespace lego::physics
