// The run's time budget: what a spent one says, and that an unlimited one never stops a run.
#include "core/budget.h"
#include "core/memory.h"

#include <gtest/gtest.h>

namespace lego {
namespace {

std::string stop_message(const Budget& budget, Stage stage, size_t done, size_t total) {
  try {
    budget.check(stage, done, total);
  } catch (const OutOfTime& e) {
    EXPECT_EQ(e.stage(), stage.name);
    EXPECT_EQ(e.done(), done);
    EXPECT_EQ(e.total(), total);
    return e.what();
  }
  return "not stopped";
}

TEST(Budget, ASpentBudgetStopsSayingWhere) {
  const Budget spent(0);
  EXPECT_TRUE(spent.spent());
  EXPECT_EQ(spent.seconds_left(), 0);
  EXPECT_EQ(stop_message(spent, kContactGraph, 12288, 40000),
            "out of time (0 s) in the contact graph, at part 12288 of 40000");
  // Reading does not know how many parts the file places until it has read them.
  EXPECT_EQ(stop_message(spent, kReading, 1024, 0),
            "out of time (0 s) in the reading, at part 1024");
  EXPECT_EQ(stop_message(spent, kSolve, 0, 400), "out of time (0 s) as the solve began");
  EXPECT_EQ(stop_message(Budget(60), kSolve, 3, 400), "not stopped");
}

TEST(Budget, WithoutALimitARunNeverStops) {
  const Budget unlimited;
  EXPECT_FALSE(unlimited.spent());
  EXPECT_GT(unlimited.seconds_left(), 1e300);
  EXPECT_EQ(stop_message(unlimited, kPartKnowledge, 1, 2), "not stopped");
}

// The memory budget says what needs how much, and what there is; what fits passes.
TEST(Budget, MemoryShortfallSaysWhatNeedsHowMuch) {
  EXPECT_EQ(memory_shortfall(1 << 20, "a small model"), "");
  const std::string why = memory_shortfall(1e18, "a model of 10^18 bytes");
  EXPECT_TRUE(why.starts_with("a model of 10^18 bytes needs about 931322574.6 GB, and ")) << why;
  EXPECT_TRUE(why.ends_with(" GB is available")) << why;
}

}  // namespace
}  // namespace lego
