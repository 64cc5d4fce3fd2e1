#pragma once
// The time one run may take (brickcheck's --max-seconds for a file), shared by every stage of it:
// reading, part knowledge, the contact graph and the solves. Each stage checks it where it
// loops and stops by throwing OutOfTime, which says where it was. With a progress sink a person
// watching sees every stage that lasts.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lego {

// A stage of a run, and what it counts.
struct Stage {
  std::string_view name, unit;
};
inline constexpr Stage kReading{"reading", "part"};
inline constexpr Stage kPartKnowledge{"part knowledge", "part"};
inline constexpr Stage kContactGraph{"contact graph", "part"};
inline constexpr Stage kSolve{"solve", "iteration"};

class OutOfTime : public std::runtime_error {
 public:
  // `total` 0: not known (reading does not know how many parts a file places until it has).
  OutOfTime(Stage stage, size_t done, size_t total, double seconds)
      : std::runtime_error(message(stage, done, total, seconds)),
        stage_(stage.name),
        done_(done),
        total_(total) {}
  const std::string& stage() const { return stage_; }
  size_t done() const { return done_; }
  size_t total() const { return total_; }

  // "out of time (1 s) in the contact graph, at part 12345 of 100000"
  static std::string message(Stage stage, size_t done, size_t total, double seconds) {
    if (done == 0) return fmt::format("out of time ({:g} s) as the {} began", seconds, stage.name);
    return fmt::format("out of time ({:g} s) in the {}, at {} {}{}", seconds, stage.name,
                       stage.unit, done, total > 0 ? fmt::format(" of {}", total) : "");
  }

 private:
  std::string stage_;
  size_t done_, total_;
};

class Budget {
 public:
  // Called with the stage, how far it is and of how much (0: not known), from any thread.
  using Progress = std::function<void(Stage stage, size_t done, size_t total)>;
  // How long the run goes before the sink hears of it (a run that ends sooner shows nothing), and
  // then how often.
  static constexpr double kQuietSeconds = 2, kShowEverySeconds = 0.25;

  Budget() = default;  // no limit, no progress
  explicit Budget(double seconds, Progress progress = {})
      : seconds_(seconds), progress_(std::move(progress)) {}

  double seconds() const { return seconds_; }
  double elapsed() const { return since(start_); }
  double seconds_left() const {
    const double left = seconds_ - elapsed();
    return left > 0 ? left : 0;
  }
  bool spent() const { return elapsed() >= seconds_; }

  // Throws OutOfTime past the budget; shows progress now and then.
  void check(Stage stage, size_t done, size_t total = 0) const {
    const double now = elapsed();
    if (now >= seconds_) throw OutOfTime(stage, done, total, seconds_);
    if (!progress_ || now < kQuietSeconds) return;
    double last = last_shown_.load(std::memory_order_relaxed);
    if (now - last >= kShowEverySeconds &&
        last_shown_.compare_exchange_strong(last, now, std::memory_order_relaxed))
      progress_(stage, done, total);
  }

 private:
  static double since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double seconds_ = std::numeric_limits<double>::infinity();
  Progress progress_;
  mutable std::atomic<double> last_shown_{0};
};

}  // namespace lego
