#include "core/in_order.h"

#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <string>

namespace lego {
namespace {

using namespace std::chrono_literals;

std::vector<size_t> delivered_order(size_t n, int jobs, const std::function<size_t(size_t)>& work) {
  std::vector<size_t> order;
  run_in_order<size_t>(n, jobs, work, [&](size_t i, size_t&& r) {
    EXPECT_EQ(r, i * 10);
    order.push_back(i);
  });
  return order;
}

TEST(RunInOrder, DeliversInTheOrderAskedWhenLaterWorkFinishesFirst) {
  const std::vector<size_t> expected{0, 1, 2, 3, 4, 5, 6, 7};
  for (int jobs : {1, 2, 3, 8})
    EXPECT_EQ(delivered_order(8, jobs,
                              [](size_t i) {
                                std::this_thread::sleep_for((8 - i) * 3ms);
                                return i * 10;
                              }),
              expected)
        << jobs << " jobs";
  EXPECT_TRUE(delivered_order(0, 2, [](size_t i) { return i; }).empty());
}

TEST(RunInOrder, RunsItemsAtOnceWithTwoJobs) {
  // Item 0 finishes only once item 1 has started: with one thread at a time it would wait out
  // its whole patience.
  std::atomic<bool> second_started{false};
  std::atomic<bool> first_saw_second{false};
  run_in_order<int>(
      2, 2,
      [&](size_t i) {
        if (i == 1) {
          second_started = true;
          return 1;
        }
        for (int k = 0; k < 2000 && !second_started; ++k) std::this_thread::sleep_for(1ms);
        first_saw_second = second_started.load();
        return 0;
      },
      [](size_t, int&&) {});
  EXPECT_TRUE(first_saw_second);
}

TEST(RunInOrder, AFailureComesWhereItsResultWouldHave) {
  for (int jobs : {1, 2}) {
    std::vector<size_t> order;
    EXPECT_THROW(run_in_order<size_t>(
                     6, jobs,
                     [](size_t i) -> size_t {
                       if (i == 3) throw std::runtime_error("item 3");
                       return i;
                     },
                     [&](size_t i, size_t&&) { order.push_back(i); }),
                 std::runtime_error);
    EXPECT_EQ(order, (std::vector<size_t>{0, 1, 2})) << jobs << " jobs";
  }
}

}  // namespace
}  // namespace lego
